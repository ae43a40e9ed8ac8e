# SPDX-License-Identifier: GPL-3.0-or-later
"""CloudComparisonFilter's unsigned point-to-surface distances next to the two peers a user would reach for, on the
same data in one run: Open3D's RaycastingScene.compute_distance (Debian's python3-open3d, Embree inside) and
CloudCompare's command-line C2M. The data is the "scan-like" case of cloud_comparison_benchmark.cpp: a sphere of
317 x 317 (199,710 triangles) and 10^6 points on it with 1 % noise, in random order.

    pvpython benchmarks/distance_peers.py --plugin build/lib/paraview-5.11/plugins/PlantMorph/PlantMorph.so \
        --work /tmp/distances [--points 1000000] [--repeat 3]

Times are wall seconds of the distance work itself, first call and the mean of the warm calls after it:
  * ours: the filter's update (search structure built, every distance, output arrays), first in this process, then
    that of a new filter on the same inputs;
  * Open3D: a new RaycastingScene, add_triangles and compute_distance, in a Python process of its own (Debian's
    Open3D links VTK 9.1, which must not meet ParaView's VTK in one process), first and repeated;
  * CloudCompare: the whole program (it cannot be timed inside), reading the two files and writing the distances,
    so its figure includes its file input and output; run once.
A peer that is not installed is skipped with a message (`apt-get install python3-open3d cloudcompare`). The largest
difference from our distances is printed for each (CloudCompare stores float distances).
"""
import argparse
import os
import shutil
import subprocess
import sys
import time

import numpy

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--work", required=True)
parser.add_argument("--points", type=int, default=1000000)
parser.add_argument("--repeat", type=int, default=3, help="warm calls after the first, for ours and Open3D")
arguments = parser.parse_args()
os.makedirs(arguments.work, exist_ok=True)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from open3d_peer import run_open3d  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy, numpy_to_vtk  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkPolyData  # noqa: E402
from vtkmodules.vtkIOPLY import vtkPLYWriter  # noqa: E402

LoadPlugin(arguments.plugin, remote=False, ns=globals())
mesh = servermanager.Fetch(Triangulate(Input=Sphere(ThetaResolution=317, PhiResolution=317, Radius=1.0)))
rng = numpy.random.default_rng(7)
directions = rng.normal(size=(arguments.points, 3))
directions /= numpy.linalg.norm(directions, axis=1)[:, None]
cloud = directions * (1.0 + 0.01 * rng.normal(size=(arguments.points, 1)))
print("reference triangles: %d, points: %d" % (mesh.GetNumberOfPolys(), arguments.points))


def report(name, first, warm, cpu):
    print("%-13s first %.3f s (%.2f M points/s), warm %.3f s; CPU (every thread) first %.3f s, warm %.3f s"
          % (name, first, arguments.points / first / 1e6, warm, cpu[0], numpy.mean(cpu[1:])))


# Ours, first update in this process, then warm updates.
measured = vtkPolyData()
points = vtkPoints()
points.SetData(numpy_to_vtk(cloud, deep=True))
measured.SetPoints(points)
source = PVTrivialProducer()
source.GetClientSideObject().SetOutput(measured)
reference = PVTrivialProducer()
reference.GetClientSideObject().SetOutput(mesh)
source.UpdatePipeline()
reference.UpdatePipeline()
ours_times, ours_cpu = [], []
for call in range(arguments.repeat + 1):
    comparison = CloudComparisonFilter(Input=source, Reference=reference)
    start, start_cpu = time.perf_counter(), time.process_time()
    comparison.UpdatePipeline()
    ours_times.append(time.perf_counter() - start)
    ours_cpu.append(time.process_time() - start_cpu)
    ours = numpy.abs(vtk_to_numpy(servermanager.Fetch(comparison).GetPointData().GetArray("Distance")))
    Delete(comparison)
report("ours", ours_times[0], numpy.mean(ours_times[1:]), ours_cpu)

vertices = vtk_to_numpy(mesh.GetPoints().GetData()).astype(numpy.float32)
triangles = vtk_to_numpy(mesh.GetPolys().GetConnectivityArray()).reshape(-1, 3).astype(numpy.uint32)

# Open3D, in a process of its own.
OPEN3D = r"""
import json, sys, time
import numpy
import open3d as o3d
data = numpy.load(sys.argv[1])
queries = o3d.core.Tensor(data["cloud"].astype(numpy.float32))
times, cpu = [], []
for call in range(int(sys.argv[2]) + 1):
    start, start_cpu = time.perf_counter(), time.process_time()
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.core.Tensor(data["vertices"]), o3d.core.Tensor(data["triangles"]))
    distance = scene.compute_distance(queries).numpy()
    times.append(time.perf_counter() - start)
    cpu.append(time.process_time() - start_cpu)
numpy.save(sys.argv[3], distance)
print(json.dumps({"times": times, "cpu": cpu}))
"""
inputs = os.path.join(arguments.work, "inputs.npz")
numpy.savez(inputs, vertices=vertices, triangles=triangles, cloud=cloud)
o3d_output = os.path.join(arguments.work, "open3d_distance.npy")
reply = run_open3d(OPEN3D, inputs, arguments.repeat, o3d_output)
if reply is not None:
    o3d_times = reply["times"]
    report("Open3D", o3d_times[0], numpy.mean(o3d_times[1:]), reply["cpu"])
    print("  largest |Open3D - ours|: %.3g (Open3D computes in float)" % numpy.abs(numpy.load(o3d_output) - ours).max())
    print("  Open3D / ours: first run %.2fx, warm %.2fx; CPU time: first run %.2fx, warm %.2fx"
          % (o3d_times[0] / ours_times[0], numpy.mean(o3d_times[1:]) / numpy.mean(ours_times[1:]),
             reply["cpu"][0] / ours_cpu[0], numpy.mean(reply["cpu"][1:]) / numpy.mean(ours_cpu[1:])))

# CloudCompare's C2M, the whole program.
executable = shutil.which("CloudCompare")
if not executable:
    print("CloudCompare: not run (not installed); apt-get install cloudcompare")
else:
    mesh_file = os.path.join(arguments.work, "sphere.ply")
    cloud_file = os.path.join(arguments.work, "cloud.xyz")
    writer = vtkPLYWriter()
    writer.SetFileName(mesh_file)
    writer.SetInputData(mesh)
    writer.SetFileTypeToBinary()
    writer.Write()
    numpy.savetxt(cloud_file, cloud, fmt="%.9f")
    for old in os.listdir(arguments.work):
        if old.startswith("cloud_C2M"):
            os.remove(os.path.join(arguments.work, old))
    start = time.perf_counter()
    run = subprocess.run([executable, "-SILENT", "-AUTO_SAVE", "OFF", "-C_EXPORT_FMT", "ASC", "-O", cloud_file, "-O",
                          mesh_file, "-C2M_DIST", "-SAVE_CLOUDS"], env=dict(os.environ, QT_QPA_PLATFORM="offscreen"),
                         capture_output=True, text=True, cwd=arguments.work)
    cc_seconds = time.perf_counter() - start
    outputs = [f for f in os.listdir(arguments.work) if f.startswith("cloud_C2M") and f.endswith(".asc")]
    if run.returncode != 0 or not outputs:
        print("CloudCompare: failed (exit %d)" % run.returncode)
    else:
        print("%-13s %.3f s, the whole program with its file input and output (exit %d)"
              % ("CloudCompare", cc_seconds, run.returncode))
        cc = numpy.abs(numpy.loadtxt(os.path.join(arguments.work, outputs[0]))[:, 3])
        print("  largest |CloudCompare - ours|: %.3g (CloudCompare stores float distances)" % numpy.abs(cc - ours).max())
        print("  CloudCompare / ours (first run): %.1fx" % (cc_seconds / ours_times[0]))
