"""Fits WiltingSimulator's load and material parameters to a measured leaf-tip trajectory (paper 001 Table 1).

    pvpython examples/calibrate_wilting.py --plugin build/lib/paraview-5.11/plugins/PlantMorph/PlantMorph.so \
        [--csv ../shared/data/cucumber-wilting-tip.csv] [--evaluations 60]

The CSV has columns sample, measured_x, measured_y, measured_z (cm, origin at the petiole-blade junction, samples in
time order, no time stamps); optional paper_sim_x/y/z columns are reported for comparison. The leaf is
LeafOutlineSource's cucumber B-spline blade of the measured size; the fit (Nelder-Mead, log-parameters) minimises
the mean time-monotone tip error: each measurement matched to one simulated frame, frames increasing. Reported:
that error, the paper's closest-sample error (each measurement to its nearest frame at any time), and the angle
between the (sample 5 - sample 1) directions of measurement and simulation."""
import argparse
import csv
import math
import os
import sys

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--csv", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared", "data",
                                                  "cucumber-wilting-tip.csv"))
parser.add_argument("--evaluations", type=int, default=60)
parser.add_argument("--length", type=float, default=20.1)
parser.add_argument("--width", type=float, default=22.1)
arguments = parser.parse_args()

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

LoadPlugin(arguments.plugin, remote=False, ns=globals())

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
    picks = [min(range(len(track)), key=lambda i: distance(track[i], m)) for m in measured]
    return picks


def monotone(track):
    """Frames i_1 <= ... <= i_5 minimising the summed distance (dynamic programming)."""
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


leaf = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", Length=arguments.length, Width=arguments.width,
                         Resolution=30)
wilt = WiltingSimulator(Input=leaf, Preset="Custom", Resolution=14, Duration=12.0, FrameInterval=0.05,
                        TimeStep=1.0 / 60.0, NewtonIterations=2, LoadProfile="Sigmoid")
NAMES = ("DroopForce", "ContractionForce", "BladeStiffness", "VeinStiffness", "LoadTime")


def run(x):
    droop, contraction, blade, vein, load_time = (math.exp(v) for v in x)
    wilt.DroopForce = droop
    wilt.ContractionForce = contraction
    wilt.BladeMaterial = [0.02, blade, 0.0]
    wilt.MarginMaterial = [0.03, 0.8 * blade, 0.0]
    wilt.VeinMaterial = [0.04, vein, 0.0]
    wilt.PetioleMaterial = [0.05, 5 * vein, 0.0]
    wilt.LoadTime = load_time
    table = servermanager.Fetch(wilt, idx=2)
    if table is None or table.GetNumberOfRows() == 0:
        return None
    cols = [table.GetColumnByName(n) for n in ("TipX", "TipY", "TipZ")]
    return [tuple(c.GetValue(i) for c in cols) for i in range(table.GetNumberOfRows())]


def objective(x):
    track = run(x)
    if not track:
        return 1e9
    picks = monotone(track)
    return sum(distance(track[i], m) for i, m in zip(picks, measured)) / len(measured)


def nelder_mead(f, x0, step, budget):
    simplex = [list(x0)] + [[x0[j] + (step if j == i else 0.0) for j in range(len(x0))] for i in range(len(x0))]
    values = [f(x) for x in simplex]
    evaluations = len(simplex)
    while evaluations < budget:
        order = sorted(range(len(simplex)), key=lambda i: values[i])
        simplex, values = [simplex[i] for i in order], [values[i] for i in order]
        print("  best %.3f cm after %d runs" % (values[0], evaluations), flush=True)
        centre = [sum(p[j] for p in simplex[:-1]) / (len(simplex) - 1) for j in range(len(x0))]
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
            contract = [c + 0.5 * (w - c) for c, w in zip(centre, worst)]
            fc = f(contract)
            evaluations += 1
            if fc < values[-1]:
                simplex[-1], values[-1] = contract, fc
            else:
                best = simplex[0]
                simplex = [best] + [[b + 0.5 * (p - b) for b, p in zip(best, q)] for q in simplex[1:]]
                values = [values[0]] + [f(x) for x in simplex[1:]]
                evaluations += len(simplex) - 1
    i = min(range(len(simplex)), key=lambda k: values[k])
    return simplex[i], values[i]


x0 = [math.log(v) for v in (3.0, 1.0, 1000.0, 2000.0, 8.0)]
best, value = nelder_mead(objective, x0, 0.5, arguments.evaluations)
track = run(best)
print("fitted:", ", ".join("%s %.4g" % (n, math.exp(v)) for n, v in zip(NAMES, best)))
print("%-8s %-22s %-22s %-10s %-10s %-10s" % ("sample", "measured", "ours (monotone)", "monotone", "closest", "paper"))
mono, near = monotone(track), closest(track)
for k, m in enumerate(measured):
    print("%-8d %-22s %-22s %-10.2f %-10.2f %-10s" % (
        k + 1, "(%.2f, %.2f, %.2f)" % m, "(%.2f, %.2f, %.2f)" % track[mono[k]], distance(track[mono[k]], m),
        distance(track[near[k]], m), "%.2f" % distance(paper[k], m) if paper else "-"))
print("mean: monotone %.2f cm, closest %.2f cm, paper %s" % (
    sum(distance(track[i], m) for i, m in zip(mono, measured)) / 5,
    sum(distance(track[i], m) for i, m in zip(near, measured)) / 5,
    "%.2f cm" % (sum(distance(p, m) for p, m in zip(paper, measured)) / 5) if paper else "-"))
print("direction difference: monotone %.2f deg, closest %.2f deg, paper %s" % (
    angle(measured[0], measured[-1], track[mono[0]], track[mono[-1]]),
    angle(measured[0], measured[-1], track[near[0]], track[near[-1]]),
    "%.2f deg" % angle(measured[0], measured[-1], paper[0], paper[-1]) if paper else "-"))
