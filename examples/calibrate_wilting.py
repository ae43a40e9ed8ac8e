"""Fits WiltingSimulator's load and material parameters to a measured leaf-tip trajectory (paper 001 Table 1).

    pvpython examples/calibrate_wilting.py --plugin build/lib/paraview-5.11/plugins/PlantMorph/PlantMorph.so \
        [--csv ../shared/data/cucumber-wilting-tip.csv] [--evaluations 120] [--no-yaw] [--evaluate-preset]

The CSV has columns sample, measured_x, measured_y, measured_z (cm, origin at the petiole-blade junction, samples in
time order, no time stamps); optional paper_sim_x/y/z columns are reported for comparison.

The leaf: LeafOutlineSource's cucumber B-spline blade of the measured size (BladeLength 20.1 cm, BladeWidth 22.1 cm:
the Length/Width properties belong to the other models and do not size it) -> VenationFilter (palmate, the
cucumber's five primaries) -> WiltingSimulator with the blade on Input and the veins on Veins, at the settings the
Cucumber preset was fitted at (SETTINGS below: Resolution 14, AnchorRadius 3, TimeStep 1/60 s, one Newton
iteration, 10 s). A mass-spring model depends on its voxel size: at another Resolution the same preset droops
differently, so rerun this script there.

Fitted (log-parameters; Nelder-Mead, restarted from the best point with a smaller simplex): DroopForce,
ContractionForce (towards the base on the voxels' bottom nodes: the margins and apex curl down), blade stiffness,
vein stiffness, margin stiffness, LoadTime (the droop's sigmoid) and ContractionTime (the contraction's: the
margins may curl before the leaf droops, as the paper observed) and the Rayleigh mass damping alpha (how
quasi-static the fall is). The objective is the mean time-monotone tip error: each measurement matched to one
simulated frame, frames increasing (dynamic programming). With yaw on (the default) the simulated track is also
turned about the vertical axis through the petiole by the angle that fits best (searched in [-10, 10] deg): the
digitiser's y axis and the leaf's midvein need not be parallel, and a symmetric model cannot move its tip sideways
(measured x wanders from -1.3 to 0.6 cm). Both the raw (yaw 0) and the turned results are printed.

Reported: per sample the time-monotone error and the paper's closest-sample error (each measurement to its nearest
frame at any time), their means, and the angle between the (sample 5 - sample 1) directions of measurement and
simulation, next to the paper's own numbers."""
import argparse
import csv
import math
import os
import time

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--csv", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared",
                                                  "data", "cucumber-wilting-tip.csv"))
parser.add_argument("--evaluations", type=int, default=120, help="simulations the fit may run")
parser.add_argument("--length", type=float, default=20.1, help="leaf length (cm), BladeLength")
parser.add_argument("--width", type=float, default=22.1, help="leaf width (cm), BladeWidth")
parser.add_argument("--no-yaw", action="store_true", help="do not turn the simulated track about the vertical")
parser.add_argument("--evaluate-preset", action="store_true",
                    help="no fit: run the Cucumber preset at SETTINGS and print its table")
arguments = parser.parse_args()

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

LoadPlugin(arguments.plugin, remote=False, ns=globals())

# The settings the Cucumber preset was fitted at (everything the preset does not set).
SETTINGS = dict(Resolution=14, AnchorRadius=3.0, Duration=10.0, FrameInterval=0.1, TimeStep=1.0 / 60.0,
                NewtonIterations=1, Threads=1)

measured, paper = [], []
with open(arguments.csv) as f:
    rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
header = rows[0]
for row in rows[1:]:
    values = dict(zip(header, row))
    measured.append(tuple(float(values["measured_" + c]) for c in "xyz"))
    if "paper_sim_x" in values:
        paper.append(tuple(float(values["paper_sim_" + c]) for c in "xyz"))


def distance(a, b):
    return math.sqrt(sum((p - q) ** 2 for p, q in zip(a, b)))


def angle(a0, a1, b0, b1):
    u = [q - p for p, q in zip(a0, a1)]
    v = [q - p for p, q in zip(b0, b1)]
    c = sum(p * q for p, q in zip(u, v)) / math.sqrt(sum(p * p for p in u) * sum(q * q for q in v))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def closest(track):
    """The paper's choice: each measurement's nearest simulated sample, at any time."""
    return [min(range(len(track)), key=lambda i: distance(track[i], m)) for m in measured]


def monotone(track):
    """Frames i_1 <= ... <= i_n minimising the summed distance (dynamic programming)."""
    n = len(track)
    cost = [distance(track[i], measured[0]) for i in range(n)]
    back = []
    for m in measured[1:]:
        best, arg, new, choice = float("inf"), 0, [], []
        for i in range(n):
            if cost[i] < best:
                best, arg = cost[i], i
            new.append(best + distance(track[i], m))
            choice.append(arg)
        cost = new
        back.append(choice)
    i = min(range(n), key=lambda k: cost[k])
    picks = [i]
    for choice in reversed(back):
        i = choice[i]
        picks.append(i)
    return list(reversed(picks))


def turned(track, degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return [(c * x - s * y, s * x + c * y, z) for x, y, z in track]


def monotone_error(track):
    picks = monotone(track)
    return sum(distance(track[i], m) for i, m in zip(picks, measured)) / len(measured)


def best_yaw(track):
    if arguments.no_yaw:
        return 0.0
    lo, hi = -10.0, 10.0  # golden-section search of the monotone error over the yaw angle
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = hi - g * (hi - lo), lo + g * (hi - lo)
    fa, fb = monotone_error(turned(track, a)), monotone_error(turned(track, b))
    for _ in range(30):
        if fa < fb:
            hi, b, fb = b, a, fa
            a = hi - g * (hi - lo)
            fa = monotone_error(turned(track, a))
        else:
            lo, a, fa = a, b, fb
            b = lo + g * (hi - lo)
            fb = monotone_error(turned(track, b))
    return 0.5 * (lo + hi)


leaf = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", BladeLength=arguments.length,
                         BladeWidth=arguments.width, Resolution=30)
veins = VenationFilter(Input=leaf, Preset="Custom", Pattern="Palmate (actinodromous)")
wilt = WiltingSimulator(Input=OutputPort(veins, 1), Veins=OutputPort(veins, 0), Preset="Custom",
                        LoadProfile="Sigmoid", ContractionSide="Bottom", ContractionTarget="Base",
                        RayleighBeta=0.01, **SETTINGS)
NAMES = ("DroopForce", "ContractionForce", "BladeStiffness", "VeinStiffness", "MarginStiffness", "LoadTime",
         "ContractionTime", "RayleighAlpha")
# Starting point: the loads are tens of times the leaf's weight per voxel (0.02 g/cm^3 * (1.6 cm)^3 * 981 = 80 dyn)
# and the springs stiff enough that gravity alone sags the tip about 1 cm, as the first measurement shows.
START = (9.4e3, 3.4e3, 7.4e4, 2.9e5, 9.9e4, 10.6, 3.6, 2.0)


def configure(x):
    droop, contraction, blade, vein, margin, load_time, contraction_time, alpha = (math.exp(v) for v in x)
    wilt.RayleighAlpha = alpha
    wilt.LoadTime = load_time
    wilt.ContractionTime = contraction_time
    wilt.DroopForce = droop
    wilt.ContractionForce = contraction
    wilt.BladeMaterial = [0.02, blade, 0.0]
    wilt.MarginMaterial = [0.02, margin, 0.0]
    wilt.VeinMaterial = [0.02, vein, 0.0]
    wilt.PetioleMaterial = [0.02, 5.0 * vein, 0.0]


def track_of(proxy):
    table = servermanager.Fetch(proxy, idx=2)
    if table is None or table.GetNumberOfRows() < 2:
        return None
    cols = [table.GetColumnByName(n) for n in ("TipX", "TipY", "TipZ")]
    track = [tuple(c.GetValue(i) for c in cols) for i in range(table.GetNumberOfRows())]
    frames = 1 + int(round(SETTINGS["Duration"] / SETTINGS["FrameInterval"]))
    return track if len(track) == frames else None  # a blow-up keeps fewer frames: reject it


runs = [0]


def objective(x):
    configure(x)
    runs[0] += 1
    track = track_of(wilt)
    if not track:
        return 1e9
    return monotone_error(turned(track, best_yaw(track)))


def nelder_mead(f, x0, step, budget):
    n = len(x0)
    simplex = [list(x0)] + [[x0[j] + (step if j == i else 0.0) for j in range(n)] for i in range(n)]
    values = [f(x) for x in simplex]
    evaluations = len(simplex)
    while evaluations < budget:
        order = sorted(range(len(simplex)), key=lambda i: values[i])
        simplex, values = [simplex[i] for i in order], [values[i] for i in order]
        centre = [sum(p[j] for p in simplex[:-1]) / n for j in range(n)]
        worst = simplex[-1]
        reflect = [c + (c - w) for c, w in zip(centre, worst)]
        fr = f(reflect)
        evaluations += 1
        if fr < values[0]:
            expand = [c + 2 * (c - w) for c, w in zip(centre, worst)]
            fe = f(expand)
            evaluations += 1
            simplex[-1], values[-1] = (expand, fe) if fe < fr else (reflect, fr)
        elif fr < values[-2]:
            simplex[-1], values[-1] = reflect, fr
        else:
            inside = fr >= values[-1]
            contract = [c + 0.5 * ((w if inside else r) - c) for c, w, r in zip(centre, worst, reflect)]
            fc = f(contract)
            evaluations += 1
            if fc < min(values[-1], fr):
                simplex[-1], values[-1] = contract, fc
            else:
                best = simplex[0]
                simplex = [best] + [[b + 0.5 * (p - b) for b, p in zip(best, q)] for q in simplex[1:]]
                values = [values[0]] + [f(x) for x in simplex[1:]]
                evaluations += n
        print("  best %.3f cm after %d runs" % (min(values), evaluations), flush=True)
    i = min(range(len(simplex)), key=lambda k: values[k])
    return simplex[i], values[i]


def report(track, title):
    if not track:
        print("\n%s: the simulation blew up before Duration (see the error above); nothing to compare" % title)
        return
    yaw = best_yaw(track)
    print("\n%s" % title)
    for label, t in (("raw (yaw 0)", track), ("turned by the best yaw %.2f deg" % yaw, turned(track, yaw))):
        mono, near = monotone(t), closest(t)
        print("  %s: frames (monotone) %s, times %s s" % (label, mono, [round(i * SETTINGS["FrameInterval"], 2)
                                                                      for i in mono]))
        print("  %-6s %-22s %-22s %-9s %-9s %-6s" % ("sample", "measured", "simulated (monotone)", "monotone",
                                                   "closest", "paper"))
        for k, m in enumerate(measured):
            print("  %-6d %-22s %-22s %-9.2f %-9.2f %-6s" % (
                k + 1, "(%.2f, %.2f, %.2f)" % m, "(%.2f, %.2f, %.2f)" % t[mono[k]], distance(t[mono[k]], m),
                distance(t[near[k]], m), "%.2f" % distance(paper[k], m) if paper else "-"))
        print("  mean: monotone %.2f cm, closest %.2f cm, paper %s" % (
            sum(distance(t[i], m) for i, m in zip(mono, measured)) / len(measured),
            sum(distance(t[i], m) for i, m in zip(near, measured)) / len(measured),
            "%.2f cm" % (sum(distance(p, m) for p, m in zip(paper, measured)) / len(measured)) if paper else "-"))
        print("  direction difference: monotone %.2f deg, closest %.2f deg, paper %s" % (
            angle(measured[0], measured[-1], t[mono[0]], t[mono[-1]]),
            angle(measured[0], measured[-1], t[near[0]], t[near[-1]]),
            "%.2f deg" % angle(measured[0], measured[-1], paper[0], paper[-1]) if paper else "-"))


started = time.time()
if arguments.evaluate_preset:
    wilt.Preset = "Cucumber"
    track = track_of(wilt)
    report(track, "Cucumber preset at %s" % SETTINGS)
else:
    x0 = [math.log(v) for v in START]
    best, value = nelder_mead(objective, x0, 0.7, arguments.evaluations // 2)
    best, value = nelder_mead(objective, best, 0.2, arguments.evaluations - arguments.evaluations // 2)
    configure(best)
    fitted = ", ".join("%s %.5g" % (n, math.exp(v)) for n, v in zip(NAMES, best))
    print("fitted (%d simulations, %.0f s): %s" % (runs[0], time.time() - started, fitted))
    report(track_of(wilt), "fitted parameters at %s" % SETTINGS)
