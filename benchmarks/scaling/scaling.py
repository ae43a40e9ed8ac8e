# SPDX-License-Identifier: GPL-3.0-or-later
"""Scaling on ParaView's MPI (what a cluster user gains from more ranks): wall time and every rank's peak memory of the main steps.

    mpirun -np N pvbatch benchmarks/scaling/scaling.py --plugin PlantMorph.so --work DIR --steps read,compare

Steps (each timed alone, inside this script: a barrier, UpdatePipeline, a barrier, so pvbatch's start-up and the
plugin loading are not counted; run_scaling.sh times the whole pvbatch too):
- read: Leaf Cloud Reader of a generated text scan (--points, default 2*10^6 points on and near a cucumber blade,
  written once into DIR as x y z lines);
- compare: Cloud Comparison Filter of that scan against the cucumber blade (LeafOutlineSource B-spline "Cucumber"),
  after read (the reader is up to date then);
- fit: Leaf Fit Filter on a multi-leaf scan: the shipped scans (data/leaf-clouds), --fit-copies copies each, every
  copy its own LeafId, moved apart;
- tree: TreeFromSketchSource, Custom template, Depth 5, ChildCount 8, no leaves (about 2.85*10^6 triangles);
- prepare: only writes the scan (run_scaling.sh runs it in a pvbatch of its own, so that no measured process has
  held the generated points).
--size large: a 6*10^6-point scan (about 200 MB of text) and ChildCount 10 (about 8.5*10^6 triangles), where the
data outweighs what pvbatch holds before any step, so rank 0's whole-process peak can be compared at 1 and 2 ranks.
Memory: before each step every rank's VmHWM is reset to its current resident set (writing 5 to /proc/self/clear_refs)
and read after it, so `peak_mb` is that rank's peak during the step, `rss_before_mb` what it held before (pvbatch,
Python, ParaView and the plugin: about 300 MB) and `step_mb` the difference, the step's own memory. `cpu_s`: each
rank's CPU time (user + system) over the step, which a loaded machine stretches less than wall time. A
ProgrammableSource that runs on every rank reads /proc/self/status; gathering it is also the barrier.
Prints one JSON line per step ("RESULT {...}") and appends it to DIR/scaling.jsonl. Use VTK_SMP_MAX_THREADS=1 to
measure the MPI dimension alone.
"""
import argparse
import glob
import json
import os
import time

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--work", required=True)
parser.add_argument("--steps", default="read,compare,fit,tree")
parser.add_argument("--size", choices=("normal", "large"), default="normal",
                    help="large: a 6*10^6-point scan and a ChildCount 10 tree (about 8.5*10^6 triangles), where the data "
                         "outweighs pvbatch's own ~330 MB a rank (rank 0's whole peak at 1 vs 2 ranks)")
parser.add_argument("--points", type=int, default=None, help="default 2*10^6, 6*10^6 at --size large")
parser.add_argument("--fit-copies", type=int, default=4)
parser.add_argument("--tree-depth", type=int, default=5)
parser.add_argument("--tree-children", type=int, default=None, help="default 8, 10 at --size large")
parser.add_argument("--label", default="")
parser.add_argument("--again", type=int, default=0,
                    help="re-run the tree this many more times in the same process (Seed changed, which leaves a template "
                         "tree as it is): step tree_again, warm")
arguments = parser.parse_args()
large = arguments.size == "large"
if arguments.points is None:
    arguments.points = 6000000 if large else 2000000
if arguments.tree_children is None:
    arguments.tree_children = 10 if large else 8

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

LoadPlugin(arguments.plugin, ns=globals())
HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.normpath(os.path.join(HERE, "..", "..", "data"))
ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()

PROBE = """
from vtkmodules.vtkParallelCore import vtkMultiProcessController
from vtkmodules.vtkCommonCore import vtkPoints, vtkDoubleArray
from vtkmodules.vtkCommonDataModel import vtkCellArray
controller = vtkMultiProcessController.GetGlobalController()
rank = controller.GetLocalProcessId() if controller else 0
if %(reset)d:
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")
status = {}
with open("/proc/self/status") as f:
    for line in f:
        key, _, value = line.partition(":")
        if key in ("VmHWM", "VmRSS"):
            status[key] = float(value.split()[0]) / 1024.0
import os
with open("/proc/self/stat") as f:
    fields = f.read().rsplit(")", 1)[1].split()
cpu = (float(fields[11]) + float(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime + stime
out = self.GetPolyDataOutput()
points = vtkPoints()
points.InsertNextPoint(rank, 0, 0)
out.SetPoints(points)
verts = vtkCellArray()
verts.InsertNextCell(1)
verts.InsertCellPoint(0)
out.SetVerts(verts)
for name, value in (("Rank", rank), ("VmHWM", status.get("VmHWM", -1)), ("VmRSS", status.get("VmRSS", -1)),
                    ("Cpu", cpu), ("Call", %(call)d)):
    a = vtkDoubleArray()
    a.SetName(name)
    a.InsertNextValue(value)
    out.GetPointData().AddArray(a)
"""
probe = ProgrammableSource(OutputDataSetType="vtkPolyData")
calls = [0]


def memory(reset):
    """Every rank's (VmHWM, VmRSS) in MB and CPU seconds so far, by rank; reset: VmHWM set to the current RSS first.
    A barrier too."""
    calls[0] += 1
    probe.Script = PROBE % {"reset": 1 if reset else 0, "call": calls[0]}
    data = servermanager.Fetch(probe)
    rank = vtk_to_numpy(data.GetPointData().GetArray("Rank")).astype(int)
    hwm = vtk_to_numpy(data.GetPointData().GetArray("VmHWM"))
    rss = vtk_to_numpy(data.GetPointData().GetArray("VmRSS"))
    cpu = vtk_to_numpy(data.GetPointData().GetArray("Cpu"))
    order = numpy.argsort(rank)
    return hwm[order].round(1).tolist(), rss[order].round(1).tolist(), cpu[order]


def timed(step, proxy, port=0, extra=None, again=arguments.again, touch=None):
    _, before, cpu_before = memory(reset=True)
    start = time.perf_counter()
    proxy.UpdatePipeline()
    peak, _, cpu_after = memory(reset=False)  # the barrier: every rank has finished the update
    seconds = time.perf_counter() - start
    info = proxy.GetDataInformation(port)
    result = {"step": step, "ranks": ranks, "size": arguments.size, "seconds": round(seconds, 3), "peak_mb": peak,
              "rss_before_mb": before,
              "step_mb": [round(p - b, 1) for p, b in zip(peak, before)],
              "cpu_s": (cpu_after - cpu_before).round(2).tolist(), "points": info.GetNumberOfPoints(), "cells": info.GetNumberOfCells(),
              "rows": info.GetNumberOfRows(),
              "threads": os.environ.get("VTK_SMP_MAX_THREADS", ""), "label": arguments.label}
    result.update(extra or {})
    line = json.dumps(result)
    print("RESULT " + line, flush=True)
    with open(os.path.join(arguments.work, "scaling.jsonl"), "a") as f:
        f.write(line + "\n")
    if again > 0 and touch:
        touch()  # a property change that makes every rank execute again
        timed(step + "_again", proxy, port, extra, again - 1, touch)


def cucumber_blade():
    return LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", Resolution=60)


def generated_scan(points):
    """A text scan of `points` points on the cucumber blade (uniform by area) with 0.3 % noise; written once."""
    path = os.path.join(arguments.work, "scan_%d.txt" % points)
    if os.path.exists(path):
        return path
    blade = servermanager.Fetch(cucumber_blade())
    xyz = vtk_to_numpy(blade.GetPoints().GetData()).astype(numpy.float64)
    ids = vtk_to_numpy(blade.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    a, b, c = xyz[ids[:, 0]], xyz[ids[:, 1]], xyz[ids[:, 2]]
    area = 0.5 * numpy.linalg.norm(numpy.cross(b - a, c - a), axis=1)
    random = numpy.random.default_rng(21)
    pick = random.choice(len(ids), size=points, p=area / area.sum())
    u, v = random.random(points), random.random(points)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    sample = a[pick] + u[:, None] * (b[pick] - a[pick]) + v[:, None] * (c[pick] - a[pick])
    size = numpy.ptp(xyz, axis=0).max()
    sample += random.normal(scale=0.003 * size, size=sample.shape)
    numpy.savetxt(path + ".part", sample, fmt="%.6f", delimiter=" ")
    os.replace(path + ".part", path)
    return path


# The first Fetch of the probe costs rank 0 (pvbatch's client) alone about 0.2 s of CPU (proxy definitions, the
# reduction's first use, imports): paid once here, before any step, so that no step's time or CPU split counts it.
memory(reset=False)
steps = arguments.steps.split(",")
if "prepare" in steps:  # the scan written by its own pvbatch (run_scaling.sh), so no measured process ever held it
    generated_scan(arguments.points)
if "read" in steps or "compare" in steps:
    reader = LeafCloudReader(FileName=generated_scan(arguments.points))
    if "read" in steps:
        timed("read", reader, extra={"file_mb": round(os.path.getsize(reader.FileName) / 2**20, 1)})
    if "compare" in steps:
        reader.UpdatePipeline()
        blade = cucumber_blade()
        blade.UpdatePipeline()
        timed("compare", CloudComparisonFilter(Input=reader, Reference=blade))
if "fit" in steps:
    parts = []
    scans = sorted(glob.glob(os.path.join(DATA, "leaf-clouds", "*.txt")))
    for copy in range(arguments.fit_copies):
        for k, scan in enumerate(scans):
            leaf = len(parts)
            moved = Transform(Input=LeafCloudReader(FileName=scan))
            moved.Transform.Translate = [500.0 * copy, 500.0 * k, 0.0]
            parts.append(Calculator(Input=moved, ResultArrayName="LeafId", Function="%d" % leaf,
                                    ResultArrayType="Int"))
    scan = AppendDatasets(Input=parts)
    scan.UpdatePipeline()
    timed("fit", LeafFitFilter(Input=scan, LeafIdArray="LeafId"), port=2, extra={"leaves": len(parts)})
if "tree" in steps:
    tree = TreeFromSketchSource(Preset=0, Depth=arguments.tree_depth, ChildCount=arguments.tree_children, Leaves=0)

    def touch():
        tree.Seed = tree.Seed + 1

    timed("tree", tree, extra={"depth": arguments.tree_depth, "child_count": arguments.tree_children}, touch=touch)
