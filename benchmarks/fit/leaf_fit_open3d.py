# SPDX-License-Identifier: GPL-3.0-or-later
"""LeafFitFilter next to Open3D's Poisson surface reconstruction on the same dense leaf cloud, in one run.

A curled cucumber blade (LeafOutlineSource + LeafCurlFilter, in cm) is sampled uniformly by area with POINTS points
(default 10^6) and isotropic Gaussian noise of 0.1 % of its length (numpy, seed 1). Both turn the cloud into a surface:

  * ours: LeafFitFilter with its defaults on the points, first update and the mean of the next updates (a property
    nudged by 1e-9 makes it run again), whole filter (outliers, petiole search, surface, outline, traits, outputs),
    wall, process CPU time (every thread) and the calling thread's CPU time (under load, about the wall time two
    idle cores would take when the other thread keeps up);
  * Open3D 0.16 (Debian's python3-open3d), in a process of its own (it links another VTK): normals estimated from
    30 neighbours within 2 % of the length and turned to +z, then create_from_point_cloud_poisson at DEPTH
    (default 8); its time is those two calls. Poisson gives a closed surface round the cloud, not a leaf: it has no
    outline, midvein or traits, so it is the nearest general tool, not an equal; its area is printed beside ours.

The truth is the blade the points were drawn from: its area, against the Area trait and Poisson's mesh area.
Peak resident memory of each process is printed beside its times. Open3D is skipped when it is not installed
(`apt-get install python3-open3d`).

    pvpython benchmarks/fit/leaf_fit_open3d.py --plugin build/.../PlantMorph.so [--points 1000000] [--repeat 1] [--depth 8]
"""
import argparse
import os
import sys
import tempfile
import time

import numpy

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--points", type=int, default=1000000)
parser.add_argument("--repeat", type=int, default=1)
parser.add_argument("--depth", type=int, default=8)
arguments = parser.parse_args()

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from open3d_peer import run_open3d  # noqa: E402
from speed_runs import peak_mb  # noqa: E402
from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkPolyData  # noqa: E402
from vtkmodules.vtkFiltersCore import vtkTriangleFilter  # noqa: E402

LoadPlugin(arguments.plugin, remote=False, ns=globals())


# The blade, its true area and a uniform sample of it.
leaf = LeafOutlineSource(Model=2, BSplinePreset=2)  # the B-spline cucumber blade
curled = LeafCurlFilter(Input=leaf, LongitudinalAngle=40, TransverseAngle=30)
triangulate = vtkTriangleFilter()
triangulate.SetInputData(servermanager.Fetch(curled))
triangulate.Update()
blade = triangulate.GetOutput()
vertices = vtk_to_numpy(blade.GetPoints().GetData()).astype(float)
triangles = vtk_to_numpy(blade.GetPolys().GetConnectivityArray()).reshape(-1, 3)
a, b, c = vertices[triangles[:, 0]], vertices[triangles[:, 1]], vertices[triangles[:, 2]]
areas = 0.5 * numpy.linalg.norm(numpy.cross(b - a, c - a), axis=1)
true_area = float(areas.sum())
length = float(numpy.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0)))
rng = numpy.random.default_rng(1)
pick = rng.choice(len(areas), size=arguments.points, p=areas / true_area)
u, v = rng.random(arguments.points), rng.random(arguments.points)
flip = u + v > 1
u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
cloud_points = a[pick] + u[:, None] * (b[pick] - a[pick]) + v[:, None] * (c[pick] - a[pick])
cloud_points += rng.normal(scale=0.001 * length, size=cloud_points.shape)

# Ours.
cloud = vtkPolyData()
points = vtkPoints()
points.SetData(numpy_to_vtk(numpy.ascontiguousarray(cloud_points), deep=True))
cloud.SetPoints(points)
producer = PVTrivialProducer()
producer.GetClientSideObject().SetOutput(cloud)
fit = LeafFitFilter(Input=producer, InputUnit="cm")
sigma = fit.OutlierSigma
times, cpu, calling = [], [], []
for k in range(arguments.repeat + 1):
    fit.OutlierSigma = sigma * (1 + 1e-9 * k)  # a changed property: the filter runs again
    start, start_cpu, start_thread = time.perf_counter(), time.process_time(), time.thread_time()
    fit.UpdatePipeline()
    times.append(time.perf_counter() - start)
    cpu.append(time.process_time() - start_cpu)
    calling.append(time.thread_time() - start_thread)
traits = servermanager.Fetch(fit, idx=2)
area = traits.GetColumnByName("Area").GetValue(0)
ours_peak = peak_mb()
print("points %d, blade length %.3f cm, true area %.3f cm^2" % (arguments.points, length, true_area))
print("ours   : first %.3f s, warm %.3f s (CPU %.3f / %.3f s, the calling thread's %.3f / %.3f s), Area %.3f cm^2 "
      "(%+.2f %%), peak %.0f MB (the whole pvpython process, the cloud's making included)"
      % (times[0], numpy.mean(times[1:]), cpu[0], numpy.mean(cpu[1:]), calling[0], numpy.mean(calling[1:]), area,
         100 * (area / true_area - 1), ours_peak))

OPEN3D = r"""
import json, sys, time
import numpy
import open3d as o3d
points = numpy.load(sys.argv[1])
length, repeat, depth = float(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
times, cpu = [], []
for k in range(repeat + 1):
    start, start_cpu = time.perf_counter(), time.process_time()
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=0.02 * length, max_nn=30))
    cloud.orient_normals_to_align_with_direction([0.0, 0.0, 1.0])
    mesh, _ = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(cloud, depth=depth)
    times.append(time.perf_counter() - start)
    cpu.append(time.process_time() - start_cpu)
peak = [int(line.split()[1]) for line in open("/proc/self/status") if line.startswith("VmHWM")][0] / 1024.0
print(json.dumps({"times": times, "cpu": cpu, "area": mesh.get_surface_area(), "peak": peak}))
"""

with tempfile.TemporaryDirectory() as work:
    inputs = os.path.join(work, "points.npy")
    numpy.save(inputs, cloud_points)
    reply = run_open3d(OPEN3D, inputs, repr(length), arguments.repeat, arguments.depth, label="open3d")
if reply is not None:
    o3d_times, o3d_cpu = reply["times"], reply["cpu"]
    print("open3d : first %.3f s, warm %.3f s (CPU %.3f / %.3f s), Poisson depth %d, mesh area %.3f cm^2 (closed "
          "round the cloud: about twice the blade's), peak %.0f MB" % (o3d_times[0], numpy.mean(o3d_times[1:]),
                                                                      o3d_cpu[0], numpy.mean(o3d_cpu[1:]),
                                                                      arguments.depth, reply["area"], reply["peak"]))
    print("ours / open3d: first run %.2fx, warm %.2fx; CPU time: first run %.2fx, warm %.2fx"
          % (times[0] / o3d_times[0], numpy.mean(times[1:]) / numpy.mean(o3d_times[1:]), cpu[0] / o3d_cpu[0],
             numpy.mean(cpu[1:]) / numpy.mean(o3d_cpu[1:])))
