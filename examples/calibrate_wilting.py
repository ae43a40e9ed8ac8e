# SPDX-License-Identifier: GPL-3.0-or-later
"""Fits WiltingSimulator's load and material parameters to a measured leaf-tip trajectory (paper 001 Table 1).

    pvpython examples/calibrate_wilting.py --plugin build/lib/paraview-5.11/plugins/PlantMorph/PlantMorph.so \
        [--csv data/cucumber-wilting-tip.csv] [--fit NAME,NAME,...] [--evaluations 120] [--yaw] \
        [--leave-one-out] [--evaluate-preset] [--set NAME=VALUE,...] [--step 0.7] [--beat-paper W]
        [--curl-direction Radial] [--frame-interval S] [--ensemble N [--seed S]] [--resolution R] [--duration S]
        [--result FILE]
    mpirun -np N pvbatch --symmetric examples/calibrate_wilting.py --plugin ... (the same options)

The CSV has columns sample, measured_x, measured_y, measured_z (cm, origin at the petiole-blade junction, samples in
time order, no time stamps); optional paper_sim_x/y/z columns are reported for comparison.

The leaf: LeafOutlineSource's cucumber B-spline blade of the measured size (BladeLength 20.1 cm, BladeWidth 22.1 cm:
the Length/Width properties belong to the other models and do not size it) -> VenationFilter (palmate, the
cucumber's five primaries) -> WiltingSimulator with the blade on Input and the veins on Veins, at the settings the
Cucumber preset was fitted at (SETTINGS below: Resolution 14, AnchorRadius 3, TimeStep 1/60 s, one Newton
iteration, 10 s). The properties are in physical units (Units Physical: Young's moduli and pressures in dyn/cm^2,
strains), so a fit carries over to other Resolutions (14-30 verified) and leaf sizes; `--resolution`
fits at another one. `--max-rise F` penalises a tip that rises back more than F leaf lengths after falling;
`--swing W` adds W times the tip's swing: the sum over the frames of every increase of its horizontal distance from
the base and of its height, in cm (beyond `--swing-allowance` cm), as a wilting tip only comes in and goes down.

The parameters (PARAMETERS below, each a physical property of the filter): DroopForce, ContractionForce (towards the
base on the voxels' bottom nodes: the margins and apex curl down), blade, vein and margin stiffness, LoadTime (the
droop's sigmoid), ContractionTime (the contraction's: the margins may curl before the leaf droops, as the paper
observed), RayleighAlpha (how quasi-static the fall is), DroopAsymmetry and ContractionAsymmetry (how much more
the +x half of the leaf droops or contracts than the -x half: a real leaf is not symmetric, and a symmetric model
keeps its tip at x = 0 while the measured tip wanders sideways), and ShrinkageStrain and ShrinkageAsymmetry (the
lamina shortening in its own plane as it dehydrates, on the contraction's time profile: it brings the tip closer to
the petiole without curling the leaf; ShrinkageTime, its own sigmoid), and the curl: CurlStrain, CurlDirection
(`--curl-direction`), CurlTime, CurlRelaxation, CurlRelaxationTime and CurlAsymmetry (the lower face shrinking
before the upper: an intrinsic bend that rises and then partly relaxes), and the stand: AnchorRadius, PetioleLength
(0: none, the blade held at its base; above 0 a petiole of that many cm, in whole voxels, held at its far end) and
PetioleStiffness. `--fit` picks which are fitted (the others keep their START value, the
Cucumber preset's); log-parameters for the positive ones, the asymmetries and the shrinkage as they are.
Nelder-Mead, then restarted from the best point with a smaller simplex. The objective is the mean time-monotone
tip error: each measurement matched to one simulated frame, frames increasing (dynamic programming), plus, with
`--beat-paper W`, W times each sample's excess over the paper's error. With `--yaw` the simulated track is also
turned about the vertical axis through the petiole-blade junction by the angle in [-10, 10] deg that minimises that
objective: the leaf's azimuth on its stand, which the CSV does not give (its origin is the junction; its axes are
the digitiser's). Gravity is vertical and every other load is defined relative to the leaf, so the model has no
preferred horizontal direction: a turned track is the same leaf wilting at another azimuth, and the yaw is a
registration of the two frames, not a force. Off by default; `--yaw-angle` gives it instead of searching it.

`--leave-one-out` then refits the fitted parameters five times, each time without one sample (from the best point,
a quarter of the budget each), and reports the left-out sample's error: how well the model predicts a measurement
it was not fitted to, the overfitting check of a fit of several parameters to five points.

On several MPI ranks, `mpirun -np N pvbatch --symmetric examples/calibrate_wilting.py ...` (every rank runs this
script), the candidate parameter sets that do not depend on each other are evaluated on all ranks, round-robin
(candidate i on rank i mod N), each rank simulating on its own (its pipeline serial: the leaf whole on every rank),
and the objectives are gathered in candidate order on every rank (mpi4py), so every rank takes the same next step:
Nelder-Mead's first simplex and its shrinks, the leave-one-out folds' first simplices, and `--ensemble N` (N
candidates: START and N - 1 points drawn about it, seeded, `--step` wide; the best reported). The steps that need
the one before (reflect, expand, contract) run on every rank at once. The result is the serial run's, candidate
for candidate and bit for bit (`--result FILE` writes it as JSON). Only rank 0 prints.

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
parser.add_argument("--csv", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data",
                                                  "cucumber-wilting-tip.csv"))
parser.add_argument("--evaluations", type=int, default=120, help="simulations the fit may run")
parser.add_argument("--curl-direction", default="Radial", choices=("Isotropic", "Radial"),
                    help="CurlDirection of the simulated leaf (default: the Cucumber preset's)")
parser.add_argument("--step", type=float, default=0.7,
                    help="the first Nelder-Mead simplex's size (log-parameters; the restart uses 0.3 times it)")
parser.add_argument("--fit", default=None, help="comma-separated names of the parameters to fit (default: all)")
parser.add_argument("--set", default="", help="NAME=VALUE,...: start values other than START")
parser.add_argument("--length", type=float, default=20.1, help="leaf length (cm), BladeLength")
parser.add_argument("--width", type=float, default=22.1, help="leaf width (cm), BladeWidth")
parser.add_argument("--yaw", action="store_true", help="also turn the simulated track about the vertical")
parser.add_argument("--yaw-angle", type=float, default=None,
                    help="turn the simulated track by this yaw (deg) instead of searching it (implies --yaw; the "
                         "Cucumber preset's: 3.02)")
parser.add_argument("--frame-interval", type=float, default=None,
                    help="seconds between the simulated tip samples compared with the measurements (default: "
                         "SETTINGS' FrameInterval)")
parser.add_argument("--beat-paper", type=float, default=0.0,
                    help="W > 0: add W times each sample's excess over the paper's error (the CSV's paper_sim_* "
                         "columns) to the objective, so the fit also aims at every sample below the paper's")
parser.add_argument("--margin", type=float, default=0.02,
                    help="with --beat-paper: a sample's excess is counted over the paper's error less this (cm), "
                         "so a fit aims strictly below the paper's")
parser.add_argument("--max-rise", type=float, default=None,
                    help="F: add 100 cm times the amount (in leaf lengths) by which the tip rises back after its "
                         "lowest point so far beyond F (the measured tip never rises)")
parser.add_argument("--swing", type=float, default=0.0,
                    help="W > 0: add W times the tip's swing (cm): the sum over the frames of every increase of the "
                         "tip's horizontal distance from the base and of its height (a wilting tip only comes in "
                         "and down)")
parser.add_argument("--swing-allowance", type=float, default=0.0,
                    help="with --swing: the swing (cm) counted only beyond this")
parser.add_argument("--max-angle", type=float, default=None,
                    help="with --beat-paper: also add W times 0.1 cm per degree the direction difference exceeds this")
parser.add_argument("--leave-one-out", action="store_true",
                    help="after the fit (or from START with --evaluate), refit without each sample")
parser.add_argument("--loo-evaluations", type=int, default=None,
                    help="simulations per leave-one-out refit (default: a quarter of --evaluations)")
parser.add_argument("--evaluate-preset", action="store_true",
                    help="no fit: run the Cucumber preset at SETTINGS and print its table")
parser.add_argument("--evaluate", action="store_true", help="no fit: run START (with --set) and print its table")
parser.add_argument("--ensemble", type=int, default=0,
                    help="N > 0: no fit: evaluate START and N - 1 seeded candidates about it (on all MPI ranks)")
parser.add_argument("--seed", type=int, default=1, help="the --ensemble candidates' random seed")
parser.add_argument("--resolution", type=int, default=None,
                    help="Resolution instead of SETTINGS' 14 (quicker runs; the preset was fitted at 14)")
parser.add_argument("--duration", type=float, default=None,
                    help="Duration (s) instead of SETTINGS' 10 (quicker runs)")
parser.add_argument("--result", default=None, help="write the candidates' objectives and the best (JSON) here")
arguments = parser.parse_args()
if arguments.yaw_angle is not None:
    arguments.yaw = True

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.vtkParallelCore import vtkDummyController, vtkMultiProcessController  # noqa: E402

LoadPlugin(arguments.plugin, remote=False, ns=globals())

# MPI (pvbatch --symmetric on several ranks): every rank runs this script; mpi4py shares the objectives.
RANKS = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
if RANKS > 1:
    import sys
    from mpi4py import MPI
    COMM = MPI.COMM_WORLD
    RANK = COMM.Get_rank()
    if RANK != 0:
        sys.stdout = open(os.devnull, "w")
else:
    COMM, RANK = None, 0

# The settings the Cucumber preset was fitted at (everything the preset does not set).
SETTINGS = dict(Resolution=14, Duration=10.0, FrameInterval=0.1, TimeStep=1.0 / 60.0,
                NewtonIterations=1, Threads=1)
if arguments.frame_interval:
    SETTINGS["FrameInterval"] = arguments.frame_interval
if arguments.resolution:
    SETTINGS["Resolution"] = arguments.resolution
if arguments.duration:
    SETTINGS["Duration"] = arguments.duration

# name, start value (the Cucumber preset's, filters/wilting/core/WiltingPresets.cpp), positive (fitted as a logarithm),
# Nelder-Mead step relative to the --step of the log-parameters.
PARAMETERS = (
    ("DroopForce", 10179.0, True, 1.0),  # dyn/cm^2 of leaf (Units Physical, as every property below)
    ("ContractionForce", 2500.0, True, 1.0),  # dyn/cm^2 on the lower face
    ("BladeStiffness", 1034750.0, True, 1.0),  # Young's modulus, dyn/cm^2, of a blade of BladeThickness
    ("VeinStiffness", 4507280.0, True, 1.0),
    ("MarginStiffness", 1118350.0, True, 1.0),
    ("LoadTime", 9.6427, True, 1.0),
    ("ContractionTime", 11.546, True, 1.0),
    ("RayleighAlpha", 1.16, True, 1.0),
    ("DroopAsymmetry", -0.00744, False, 0.5),
    ("ContractionAsymmetry", -0.0404, False, 0.5),
    ("ShrinkageStrain", 0.050521, False, 0.03),
    ("ShrinkageAsymmetry", 0.1916, False, 0.5),
    ("CurlStrain", 0.22276, False, 0.1),  # strain difference across BladeThickness
    ("CurlAsymmetry", -0.00975, False, 0.5),
    ("CurlRelaxation", 0.80755, False, 0.3),
    ("CurlRelaxationTime", 6.7684, True, 1.0),
    ("CurlTime", 4.0657, True, 1.0),
    ("ShrinkageTime", 1.06, True, 1.0),
    ("PetioleLength", 0.0, False, 2.0),
    ("PetioleStiffness", 22536400.0, True, 1.0),
    ("AnchorRadius", 3.0, True, 1.0),
)
NAMES = [p[0] for p in PARAMETERS]
START = {p[0]: p[1] for p in PARAMETERS}
POSITIVE = {p[0]: p[2] for p in PARAMETERS}
STEP = {p[0]: p[3] for p in PARAMETERS}


def require_known(name, option):
    if name not in START:
        parser.error("%s: unknown parameter %s (known: %s)" % (option, name, ", ".join(NAMES)))


for item in filter(None, arguments.set.split(",")):
    name, value = item.split("=")
    require_known(name, "--set")
    START[name] = float(value)
FITTED = NAMES if arguments.fit is None else arguments.fit.split(",")
for name in FITTED:
    require_known(name, "--fit")

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


def closest(track, targets):
    """The paper's choice: each measurement's nearest simulated sample, at any time."""
    return [min(range(len(track)), key=lambda i: distance(track[i], m)) for m in targets]


def monotone(track, targets):
    """Frames i_1 <= ... <= i_n minimising the summed distance (dynamic programming)."""
    n = len(track)
    cost = [distance(track[i], targets[0]) for i in range(n)]
    back = []
    for m in targets[1:]:
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


def rises_back(track):
    """The largest rise of the tip's height after its lowest point so far, in leaf lengths (--length)."""
    lowest, rise = track[0][2], 0.0
    for point in track:
        lowest = min(lowest, point[2])
        rise = max(rise, point[2] - lowest)
    return rise / arguments.length


def swing(track):
    """The tip's swing back (cm): the sum of every frame-to-frame increase of its horizontal distance from the base
    (sqrt(x^2 + y^2), the base at the origin) and of its height. 0 for a tip that only comes in and goes down; the yaw
    does not change it."""
    out, up = 0.0, 0.0
    for a, b in zip(track, track[1:]):
        out += max(0.0, math.hypot(b[0], b[1]) - math.hypot(a[0], a[1]))
        up += max(0.0, b[2] - a[2])
    return out, up


def swings_out(track, least=0.1):
    """The tip's moves back out: each run of frames over which its horizontal distance from the base grows, as
    (start s, end s, from cm, to cm), those of at least `least` cm."""
    r = [math.hypot(p[0], p[1]) for p in track]
    runs, i = [], 0
    while i + 1 < len(r):
        if r[i + 1] > r[i]:
            j = i + 1
            while j + 1 < len(r) and r[j + 1] > r[j]:
                j += 1
            if r[j] - r[i] >= least:
                runs.append((i * SETTINGS["FrameInterval"], j * SETTINGS["FrameInterval"], r[i], r[j]))
            i = j
        else:
            i += 1
    return runs


def turned(track, degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return [(c * x - s * y, s * x + c * y, z) for x, y, z in track]


def best_yaw(track, score):
    """The yaw in [-10, 10] deg minimising `score(turned track)`, --yaw-angle, or 0 without --yaw."""
    if not arguments.yaw:
        return 0.0
    if arguments.yaw_angle is not None:
        return arguments.yaw_angle
    lo, hi = -10.0, 10.0  # golden-section search over the yaw angle
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = hi - g * (hi - lo), lo + g * (hi - lo)
    fa, fb = score(turned(track, a)), score(turned(track, b))
    for _ in range(30):
        if fa < fb:
            hi, b, fb = b, a, fa
            a = hi - g * (hi - lo)
            fa = score(turned(track, a))
        else:
            lo, a, fa = a, b, fb
            b = lo + g * (hi - lo)
            fb = score(turned(track, b))
    return 0.5 * (lo + hi)


leaf = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", BladeLength=arguments.length,
                         BladeWidth=arguments.width, Resolution=30)
veins = VenationFilter(Input=leaf, Preset="Custom", Pattern="Palmate (actinodromous)",
                       PalmateEnds="Along the far edge (paper 000)", ForkLevels=1)  # the veins the Cucumber preset was fitted on
wilt = WiltingSimulator(Input=OutputPort(veins, 1), Veins=OutputPort(veins, 0), Preset="Custom", Units="Physical",
                        LoadProfile="Sigmoid", ContractionSide="Bottom", ContractionTarget="Base",
                        RayleighBeta=0.01, **SETTINGS)


def values_of(x):
    """The full parameter set: START with the fitted ones from the optimiser's vector x."""
    values = dict(START)
    for name, v in zip(FITTED, x):
        values[name] = math.exp(v) if POSITIVE[name] else v
    return values


def vector_of(values):
    return [math.log(values[n]) if POSITIVE[n] else values[n] for n in FITTED]


def configure(values):
    wilt.RayleighAlpha = values["RayleighAlpha"]
    wilt.LoadTime = values["LoadTime"]
    wilt.ContractionTime = values["ContractionTime"]
    wilt.DroopForce = values["DroopForce"]
    wilt.ContractionForce = values["ContractionForce"]
    wilt.DroopAsymmetry = values["DroopAsymmetry"]
    wilt.ContractionAsymmetry = values["ContractionAsymmetry"]
    wilt.ShrinkageStrain = values["ShrinkageStrain"]
    wilt.ShrinkageAsymmetry = values["ShrinkageAsymmetry"]
    wilt.CurlStrain = values["CurlStrain"]
    wilt.CurlAsymmetry = values["CurlAsymmetry"]
    wilt.CurlRelaxation = values["CurlRelaxation"]
    wilt.CurlRelaxationTime = values["CurlRelaxationTime"]
    wilt.CurlTime = values["CurlTime"]
    wilt.ShrinkageTime = values["ShrinkageTime"]
    wilt.CurlDirection = arguments.curl_direction
    wilt.BladeMaterial = [0.02, values["BladeStiffness"], 0.0]
    wilt.MarginMaterial = [0.02, values["MarginStiffness"], 0.0]
    wilt.VeinMaterial = [0.02, values["VeinStiffness"], 0.0]
    wilt.PetioleMaterial = [0.02, values["PetioleStiffness"], 0.0]
    wilt.PetioleLength = values["PetioleLength"]
    wilt.AnchorRadius = values["AnchorRadius"]


def track_of(proxy):
    """The simulated tip track. On one rank the pipeline runs as usual; on several each rank runs its own copy of it
    alone (a one-process controller while it runs, so no filter waits for the other ranks), whole, as serially."""
    algorithm = proxy.GetClientSideObject()
    if RANKS > 1:
        everyone = vtkMultiProcessController.GetGlobalController()
        vtkMultiProcessController.SetGlobalController(vtkDummyController())
        try:
            algorithm.Update()
        finally:
            vtkMultiProcessController.SetGlobalController(everyone)
    else:
        proxy.UpdatePipeline()
    table = algorithm.GetOutputDataObject(2)
    if table is None or table.GetNumberOfRows() < 2:
        return None
    cols = [table.GetColumnByName(n) for n in ("TipX", "TipY", "TipZ")]
    track = [tuple(c.GetValue(i) for c in cols) for i in range(table.GetNumberOfRows())]
    frames = 1 + int(round(SETTINGS["Duration"] / SETTINGS["FrameInterval"]))
    return track if len(track) == frames else None  # a blow-up keeps fewer frames: reject it


runs = [0]
tracks = {}


def simulate(x):
    values = values_of(x)
    if any(abs(values[n]) > 1.0 for n in ("DroopAsymmetry", "ContractionAsymmetry", "ShrinkageAsymmetry",
                                          "CurlAsymmetry")):
        return None  # outside the properties' range [-1, 1]
    if values["PetioleLength"] < 0.0:
        return None
    if abs(values["CurlStrain"]) > 0.4 or abs(values["ShrinkageStrain"]) > 0.4 or not (
            0.0 <= values["CurlRelaxation"] <= 1.0):
        return None  # outside [-0.4, 0.4] and [0, 1]
    key = tuple(round(v, 12) for v in x)
    if key not in tracks:
        configure(values)
        runs[0] += 1
        tracks[key] = track_of(wilt)
    return tracks[key]


def objective_for(targets):
    bounds = [distance(p, m) for p, m in zip(paper, measured) if m in targets] if paper else []

    def score(t):
        """The mean time-monotone error, plus --beat-paper times each sample's excess over the paper's."""
        picks = monotone(t, targets)
        errors = [distance(t[i], m) for i, m in zip(picks, targets)]
        value = sum(errors) / len(targets)
        if arguments.beat_paper > 0.0 and bounds:
            value += arguments.beat_paper * sum(max(0.0, e - b + arguments.margin) for e, b in zip(errors, bounds))
            if arguments.max_angle is not None and len(targets) == len(measured):
                excess = angle(targets[0], targets[-1], t[picks[0]], t[picks[-1]]) - arguments.max_angle
                value += arguments.beat_paper * 0.1 * max(0.0, excess)
        return value

    def objective(x):
        track = simulate(x)
        if not track:
            return 1e9
        value = score(turned(track, best_yaw(track, score)))
        if arguments.max_rise is not None:
            value += 100.0 * max(0.0, rises_back(track) - arguments.max_rise)
        if arguments.swing > 0.0:
            value += arguments.swing * max(0.0, sum(swing(track)) - arguments.swing_allowance)
        if os.environ.get("CALIBRATE_WILTING_TRACK"):
            print("    run %d: %.4f %s" % (runs[0], value, describe(values_of(x))), flush=True)
        return value
    objective.score = score
    return objective


def evaluate_all(f, xs):
    """f at every candidate of xs, in order: on several ranks candidate i on rank i mod N, the values gathered on
    every rank (each value is the serial one: the same simulation, wherever it runs)."""
    if RANKS == 1:
        return [f(x) for x in xs]
    mine = {i: f(x) for i, x in enumerate(xs) if i % RANKS == RANK}
    everyone = {}
    for part in COMM.allgather(mine):
        everyone.update(part)
    return [everyone[i] for i in range(len(xs))]


def nelder_mead(f, x0, step, budget):
    n = len(x0)
    simplex = [list(x0)] + [[x0[j] + (step * STEP[FITTED[j]] if j == i else 0.0) for j in range(n)]
                            for i in range(n)]
    values = evaluate_all(f, simplex)
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
                values = [values[0]] + evaluate_all(f, simplex[1:])
                evaluations += n
        print("  best %.3f cm after %d runs" % (min(values), evaluations), flush=True)
    i = min(range(len(simplex)), key=lambda k: values[k])
    return simplex[i], values[i]


def report(track, title):
    if not track:
        print("\n%s: the simulation blew up before Duration (see the error above); nothing to compare" % title)
        return
    if os.environ.get("CALIBRATE_WILTING_TRACK"):
        for i in range(0, len(track), 2):
            print("  track t=%.1f (%.2f, %.2f, %.2f) |tip| %.2f" % ((i * SETTINGS["FrameInterval"],) + tuple(track[i]) +
                                                               (distance(track[i], (0, 0, 0)),)))
    yaw = best_yaw(track, objective_for(measured).score)
    print("\n%s" % title)
    print("  the tip rises back %.3f leaf lengths after its lowest point so far" % rises_back(track))
    print("  swing: the tip moves back out %.2f cm and up %.2f cm in all (frame-to-frame increases)" % swing(track))
    for start, end, a, b in swings_out(track):
        print("    out from %.2f to %.2f cm (+%.2f) between %.1f and %.1f s" % (a, b, b - a, start, end))
    variants = [("raw (yaw 0)", track)]
    if arguments.yaw:
        variants.append(("turned by the best yaw %.2f deg" % yaw, turned(track, yaw)))
    for label, t in variants:
        mono, near = monotone(t, measured), closest(t, measured)
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


def describe(values):
    return ", ".join("%s %.5g" % (n, values[n]) for n in NAMES)


def ensemble(objective, count):
    """START and count - 1 candidates about it (each fitted log-parameter offset by a seeded normal times --step
    times its STEP), evaluated on all ranks; returns (candidates, their objectives)."""
    import random
    generator = random.Random(arguments.seed)
    x0 = vector_of(START)
    candidates = [x0] + [[v + generator.gauss(0.0, 1.0) * arguments.step * STEP[name] for v, name in zip(x0, FITTED)]
                         for _ in range(count - 1)]
    return candidates, evaluate_all(objective, candidates)


def write_result(result):
    result["runs_per_rank"] = COMM.allgather(runs[0]) if COMM else [runs[0]]  # collective: every rank writes
    if arguments.result and RANK == 0:
        import json
        with open(arguments.result, "w") as f:
            json.dump(result, f, indent=1)


started = time.time()
if arguments.ensemble > 0:
    objective = objective_for(measured)
    candidates, values = ensemble(objective, arguments.ensemble)
    best = min(range(len(values)), key=lambda i: values[i])
    for i, (x, v) in enumerate(zip(candidates, values)):
        print("  candidate %d: %.6f cm  %s" % (i, v, describe(values_of(x))))
    print("best candidate %d: %r cm (%d ranks, %.0f s)" % (best, values[best], RANKS, time.time() - started))
    write_result(dict(ranks=RANKS, candidates=[values_of(x) for x in candidates], objectives=values, best=best,
                      best_objective=values[best]))
    configure(values_of(candidates[best]))
    report(track_of(wilt), "best candidate at %s" % SETTINGS)
    best = candidates[best]
elif arguments.evaluate_preset:
    wilt.Preset = "Cucumber"
    report(track_of(wilt), "Cucumber preset at %s" % SETTINGS)
elif arguments.evaluate:
    configure(START)
    report(track_of(wilt), "START (%s) at %s" % (describe(START), SETTINGS))
    best = vector_of(START)
else:
    print("fitting %d parameters (%s) to %d samples (%d coordinates)" % (
        len(FITTED), ", ".join(FITTED), len(measured), 3 * len(measured)), flush=True)
    objective = objective_for(measured)
    best, value = nelder_mead(objective, vector_of(START), arguments.step, arguments.evaluations // 2)
    best, value = nelder_mead(objective, best, 0.3 * arguments.step, arguments.evaluations - arguments.evaluations // 2)
    fitted = values_of(best)
    print("fitted (%d simulations, %.0f s): %s" % (runs[0], time.time() - started, describe(fitted)), flush=True)
    write_result(dict(ranks=RANKS, fitted=fitted, best=best, best_objective=value))
    configure(fitted)
    report(track_of(wilt), "fitted parameters at %s" % SETTINGS)
if arguments.leave_one_out and not arguments.evaluate_preset and not arguments.ensemble:
    budget = arguments.loo_evaluations or arguments.evaluations // 4
    print("\nleave-one-out: refit %s without each sample (from the fit, %d simulations each)" % (
        ", ".join(FITTED), budget))
    left_out = []
    for k in range(len(measured)):
        targets = measured[:k] + measured[k + 1:]
        fold = objective_for(targets)
        x, _ = nelder_mead(fold, best, 0.2, budget)
        track = simulate(x)
        if not track:
            print("  without sample %d: the refit blew up" % (k + 1))
            continue
        yaw = best_yaw(track, fold.score)  # the fold's own yaw (0 without --yaw)
        track = turned(track, yaw)
        mono = monotone(track, measured)
        error = distance(track[mono[k]], measured[k])
        near = distance(track[closest(track, measured)[k]], measured[k])
        left_out.append((error, near))
        print("  without sample %d: its error %.2f cm (monotone), %.2f cm (closest); yaw %.2f deg; refit %s" % (
            k + 1, error, near, yaw, describe(values_of(x))), flush=True)
    if left_out:
        print("  leave-one-out mean: %.2f cm (monotone), %.2f cm (closest)" % (
            sum(e for e, _ in left_out) / len(left_out), sum(n for _, n in left_out) / len(left_out)))
print("\n%d simulations, %.0f s" % (runs[0], time.time() - started))
