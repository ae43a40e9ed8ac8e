# SPDX-License-Identifier: GPL-3.0-or-later
"""Wall time of VenationFilter on many leaves and WiltingSimulator on a few, by rank count (each leaf processed on one rank).

    VTK_SMP_MAX_THREADS=1 mpirun -np N pvbatch benchmarks/scaling/leaf_filters_scaling.py --plugin PlantMorph.so \
        [--venation-leaves 16] [--wilting-leaves 4] [--repeat 2]

The leaves: LeafOutlineSource blades (B-spline, Deformed rectangle, Space curve in turn, lengths 8-14), side by
side, appended on rank 0 (as sources make them); VenationFilter (Preset Custom, tertiaries and veinlets) grows the
veins of each on the rank that owns it; WiltingSimulator (Resolution 10, 2 s) wilts the first --wilting-leaves of
them with their veins. Each step is timed on rank 0 around an UpdatePipeline that runs on every rank (the other
ranks' share included); the faster of --repeat runs (the filters' inputs re-made each time so nothing is cached).
Prints one line per step: name, ranks, leaves, seconds.
"""
import argparse
import time

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--venation-leaves", type=int, default=16)
parser.add_argument("--wilting-leaves", type=int, default=4)
parser.add_argument("--repeat", type=int, default=2)
arguments = parser.parse_args()

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

LoadPlugin(arguments.plugin, remote=False, ns=globals())
RANKS = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
MODELS = ("B-spline", "Deformed rectangle", "Space curve")


def leaves(count, seed):
    parts = []
    for k in range(count):
        # Length differs per repeat (seed) so the sources and everything after them run again.
        source = LeafOutlineSource(Model=MODELS[k % 3], Length=8.0 + (k % 4) * 2.0 + 1e-6 * seed)
        moved = Transform(Input=source)
        moved.Transform.Translate = [40.0 * k, 0.0, 0.0]
        parts.append(moved)
    return AppendGeometry(Input=parts)


def timed(proxy):
    start = time.perf_counter()
    proxy.UpdatePipeline()
    return time.perf_counter() - start


best = {}
for repeat in range(arguments.repeat):
    blades = leaves(arguments.venation_leaves, repeat)
    blades.UpdatePipeline()
    venation = VenationFilter(Input=blades, Preset="Custom", Tertiary=1, Veinlets=1)
    seconds = timed(venation)
    best["venation"] = min(best.get("venation", seconds), seconds)
    few = leaves(arguments.wilting_leaves, repeat + 100)
    few_veins = VenationFilter(Input=few, Preset="Custom", Tertiary=1, Veinlets=1)
    few_veins.UpdatePipeline()
    wilting = WiltingSimulator(Input=OutputPort(few_veins, 1), Veins=OutputPort(few_veins, 0), Resolution=10,
                               Duration=2.0, Threads=1)
    seconds = timed(wilting)
    best["wilting"] = min(best.get("wilting", seconds), seconds)
for name, count in (("venation", arguments.venation_leaves), ("wilting", arguments.wilting_leaves)):
    print("%-9s ranks %d leaves %2d  %.3f s" % (name, RANKS, count, best[name]), flush=True)
