# SPDX-License-Identifier: GPL-3.0-or-later
"""Wall time and per-rank peak memory of Leaf Cloud Reader + CloudComparisonFilter by rank count (both data-parallel: each rank reads and compares its own share).

    pvpython benchmarks/scaling/cloud_scaling.py --plugin PlantMorph.so --generate /tmp/scan.txt [--points 2000000]
    VTK_SMP_MAX_THREADS=1 mpirun -np N pvbatch --symmetric benchmarks/scaling/cloud_scaling.py \
        --plugin PlantMorph.so --scan /tmp/scan.txt [--repeat 2]

--generate writes the scan (not kept in the repository): a cucumber blade (LeafOutlineSource, B-spline preset
Cucumber) sampled uniformly by area, moved 2 % larger and 0.5 mm off, Gaussian noise of 0.02 (the model's units),
"x y z" per line with 17 significant digits. The timed run reads it with Leaf Cloud Reader (each rank its byte range)
and compares it with the same blade (each rank its own points, the reference replicated): time.perf_counter()
around the UpdatePipeline of the reader, then of the comparison, each between two barriers, on every rank (pvbatch --symmetric), the faster
of --repeat runs (the file name changes each run, through a symlink, so the reader reads again). Then each rank's
VmHWM (/proc/self/status) at the end. Prints "ranks N read S s compare S s read+compare S s" (the read timed
alone first, then the comparison of what was read) and "rank r VmHWM M MB, CPU read S s compare S s" (the rank's
own CPU time in the fastest run: what a loaded machine cannot hide).
"""
import argparse
import os
import time

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--scan")
parser.add_argument("--generate")
parser.add_argument("--points", type=int, default=2000000)
parser.add_argument("--repeat", type=int, default=2)
parser.add_argument("--tag", default="", help="distinguishes the symlinks of runs made at the same time")
arguments = parser.parse_args()

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.vtkParallelCore import vtkMultiProcessController  # noqa: E402

LoadPlugin(arguments.plugin, remote=False, ns=globals())
blade = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber")

if arguments.generate:
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    leaf = servermanager.Fetch(Triangulate(Input=blade))
    points = vtk_to_numpy(leaf.GetPoints().GetData())
    cells = vtk_to_numpy(leaf.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    a, b, c = points[cells[:, 0]], points[cells[:, 1]], points[cells[:, 2]]
    area = 0.5 * numpy.linalg.norm(numpy.cross(b - a, c - a), axis=1)
    rng = numpy.random.default_rng(2026)
    pick = rng.choice(len(cells), size=arguments.points, p=area / area.sum())
    u, v = rng.uniform(size=(2, arguments.points))
    flip = u + v > 1.0
    u[flip], v[flip] = 1.0 - u[flip], 1.0 - v[flip]
    sample = a[pick] + u[:, None] * (b[pick] - a[pick]) + v[:, None] * (c[pick] - a[pick])
    sample = sample * 1.02 + numpy.array([0.0, 0.0, 0.05]) + rng.normal(0.0, 0.02, sample.shape)
    numpy.savetxt(arguments.generate, sample, fmt="%.17g")
    print("wrote", arguments.points, "points to", arguments.generate)
    raise SystemExit(0)

controller = vtkMultiProcessController.GetGlobalController()
rank, ranks = controller.GetLocalProcessId(), controller.GetNumberOfProcesses()
best = None


cpu = [0.0, 0.0]


def timed(proxy, step):
    """Wall seconds of proxy.UpdatePipeline() on every rank, between barriers; this rank's CPU seconds in cpu[step]."""
    controller.Barrier()
    start, start_cpu = time.perf_counter(), time.process_time()
    proxy.UpdatePipeline()
    cpu[step] = time.process_time() - start_cpu
    controller.Barrier()
    return time.perf_counter() - start


for run in range(arguments.repeat):
    name = "%s.%srun%d" % (arguments.scan, arguments.tag, run)
    if rank == 0:
        if os.path.lexists(name):
            os.remove(name)
        os.symlink(os.path.abspath(arguments.scan), name)
    controller.Barrier()
    reader = LeafCloudReader(FileName=name)
    comparison = CloudComparisonFilter(Input=reader, Reference=blade)
    blade.UpdatePipeline()  # the reference (tiny) outside the timing
    read = timed(reader, 0)
    compare = timed(comparison, 1)
    if best is None or read + compare < sum(best):
        best = (read, compare)
        best_cpu = list(cpu)
    Delete(comparison)
    Delete(reader)
    if rank == 0:
        os.remove(name)
if rank == 0:
    print("ranks %d read %.3f s compare %.3f s read+compare %.3f s" % (ranks, best[0], best[1], sum(best)),
          flush=True)
with open("/proc/self/status") as f:
    hwm = [line.split()[1] for line in f if line.startswith("VmHWM")][0]
controller.Barrier()
for r in range(ranks):
    if r == rank:
        print("rank %d VmHWM %.0f MB, CPU read %.3f s compare %.3f s" % (rank, int(hwm) / 1024.0, best_cpu[0],
                                                                       best_cpu[1]), flush=True)
    controller.Barrier()
