# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: the Cucumber preset's calibration against paper 001's measured tip (Table 1,
data/cucumber-wilting-tip.csv), the table of docs/wilting-calibration.md and README.md.

The pipeline of examples/calibrate_wilting.py --evaluate-preset: the cucumber blade of the measured size (20.1 x
22.1 cm) -> palmate veins -> WiltingSimulator, Cucumber preset, at the settings it was fitted at (Resolution 14,
AnchorRadius 3, TimeStep 1/60 s, one Newton iteration, 10 s in frames of 0.1 s), the simulated track compared as
it is and turned about the vertical through the petiole-blade junction by the documented yaw (3.02 deg, the refit's
against the tip swinging back out) (the leaf's azimuth
in the digitiser's frame, which the CSV does not give; calibrate_wilting.py --yaw fits it). Checked: the
per-sample time-monotone and closest-sample errors and the direction difference are the documented ones (to 0.02
cm and 0.2 deg: the solver may change the last digits), and the goals the preset meets stay met: mean below the
paper's 1.96 cm, direction below 3 deg, and the samples documented as better than the paper's stay better; with
the yaw: every sample below the paper's, mean below 1 cm. 10-50 s (load)."""
import csv
import math
import os

from plantmorph_testing import Checks, load_plugin, parse_arguments

arguments = parse_arguments()

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager

load_plugin(arguments.plugin, globals())
checks = Checks()

DATA = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "data"))
# The preset's documented numbers (docs/wilting-calibration.md, examples/calibrate_wilting.py --evaluate-preset).
# (yaw in degrees, monotone errors, closest errors, direction difference in degrees) as it is and turned by the yaw.
EXPECTED = ((0.0, (0.62, 1.63, 1.93, 0.25, 1.04), (0.62, 1.63, 1.93, 0.25, 1.04), 0.25),
            (3.02, (1.27, 0.67, 1.35, 0.22, 1.11), (1.27, 0.67, 1.35, 0.22, 1.11), 1.84))

with open(os.path.join(DATA, "cucumber-wilting-tip.csv")) as f:
    rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
measured = [tuple(float(r["measured_" + c]) for c in "xyz") for r in rows]
paper = [tuple(float(r["paper_sim_" + c]) for c in "xyz") for r in rows]


def distance(a, b):
    return math.sqrt(sum((p - q) ** 2 for p, q in zip(a, b)))


def monotone(track):
    """Frames i_1 <= ... <= i_n minimising the summed distance (dynamic programming)."""
    cost = [distance(t, measured[0]) for t in track]
    back = []
    for m in measured[1:]:
        best, arg, new, choice = float("inf"), 0, [], []
        for i, t in enumerate(track):
            if cost[i] < best:
                best, arg = cost[i], i
            new.append(best + distance(t, m))
            choice.append(arg)
        cost = new
        back.append(choice)
    i = min(range(len(track)), key=lambda k: cost[k])
    picks = [i]
    for choice in reversed(back):
        i = choice[i]
        picks.append(i)
    return list(reversed(picks))


# The paper's per-sample errors (cm) from its own simulated tips: 1.7649, 0.6888, 2.5221, 1.8918, 2.9155.
PAPER = [distance(p, m) for p, m in zip(paper, measured)]


def angle(a0, a1, b0, b1):
    u = [q - p for p, q in zip(a0, a1)]
    v = [q - p for p, q in zip(b0, b1)]
    c = sum(p * q for p, q in zip(u, v)) / math.sqrt(sum(p * p for p in u) * sum(q * q for q in v))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


leaf = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", BladeLength=20.1, BladeWidth=22.1, Resolution=30)
veins = VenationFilter(Input=leaf, Preset="Custom", Pattern="Palmate (actinodromous)",
                       PalmateEnds="Along the far edge (paper 000)", ForkLevels=1)  # as calibrate_wilting.py
wilt = WiltingSimulator(Input=OutputPort(veins, 1), Veins=OutputPort(veins, 0), Preset="Cucumber", Resolution=14,
                        AnchorRadius=3.0, Duration=10.0, FrameInterval=0.1, TimeStep=1.0 / 60.0, NewtonIterations=1,
                        Threads=1)
table = servermanager.Fetch(wilt, idx=2)
checks.check(table is not None and table.GetNumberOfRows() == 101, "101 frames to 10 s (no blow-up)")
if table is not None and table.GetNumberOfRows() == 101:
    columns = [table.GetColumnByName(n) for n in ("TipX", "TipY", "TipZ")]
    raw = [tuple(c.GetValue(i) for c in columns) for i in range(table.GetNumberOfRows())]
    for yaw, expected_monotone, expected_closest, expected_angle in EXPECTED:
        c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
        track = [(c * x - s * y, s * x + c * y, z) for x, y, z in raw]
        picks = monotone(track)
        mono = [distance(track[i], m) for i, m in zip(picks, measured)]
        near = [min(distance(t, m) for t in track) for m in measured]
        label = "yaw %.2f deg" % yaw
        checks.check(picks == sorted(picks), "%s: monotone frames in time order: %s" % (label, picks))
        for k in range(len(measured)):
            checks.check(abs(mono[k] - expected_monotone[k]) < 0.02, "%s, sample %d: monotone %.3f cm, documented "
                         "%.2f" % (label, k + 1, mono[k], expected_monotone[k]))
            checks.check(abs(near[k] - expected_closest[k]) < 0.02, "%s, sample %d: closest %.3f cm, documented %.2f"
                         % (label, k + 1, near[k], expected_closest[k]))
            checks.check(near[k] <= mono[k] + 1e-12, "%s, sample %d: the closest frame is at least as close" % (
                label, k + 1))
            if expected_monotone[k] < PAPER[k]:
                checks.check(mono[k] < PAPER[k], "%s, sample %d: %.3f cm, better than the paper's %.4f cm" % (
                    label, k + 1, mono[k], PAPER[k]))
        mean = sum(mono) / len(mono)
        checks.check(mean < 1.96, "%s: mean monotone error %.3f cm below the paper's 1.96 cm" % (label, mean))
        checks.check(abs(mean - sum(expected_monotone) / 5.0) < 0.02, "%s: mean %.4f cm as documented" % (label, mean))
        if sum(expected_monotone) / 5.0 < 1.0:
            checks.check(mean < 1.0, "%s: mean %.3f cm below 1 cm" % (label, mean))
        lowest, rise = raw[0][2], 0.0
        for point in raw:
            lowest = min(lowest, point[2])
            rise = max(rise, point[2] - lowest)
        checks.check(rise < 0.05 * 20.1, "%s: the tip rises back %.3f cm after its lowest point (< 5 %% of 20.1 cm)" % (
            label, rise))
        direction = angle(measured[0], measured[-1], track[picks[0]], track[picks[-1]])
        checks.check(direction < 3.0 and abs(direction - expected_angle) < 0.2,
                     "%s: direction difference %.2f deg (documented %.2f, goal < 3)" % (label, direction,
                                                                                        expected_angle))
checks.finish()
