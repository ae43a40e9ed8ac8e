# SPDX-License-Identifier: GPL-3.0-or-later
"""CloudComparisonFilter's registration next to Open3D's point-to-plane ICP on the same leaf, in one run.

A curled ginkgo blade (LeafOutlineSource + LeafCurlFilter) is scanned from above by VirtualScanner (a depth camera,
about 6,000-7,000 points, range noise 0.2 % of the blade's length); the scan is moved by a known rigid motion
(rotation ANGLE degrees about a fixed oblique axis through the blade's centre, and a shift of 2 % of its length).
Both registrations start from the moved scan, at the identity:

  * ours: CloudComparisonFilter(Registration="Rigid ICP") against the blade surface, first update and the mean of
    the next updates (each update re-registers), whole filter (the distances included), wall and process CPU time
    (every thread; what to compare on a loaded machine);
  * Open3D 0.16 (Debian's python3-open3d): o3d.pipelines.registration.registration_icp with
    TransformationEstimationPointToPlane, the target the blade's vertices with their normals, correspondence distance
    10 % of the blade's length, at most 100 iterations, relative fitness and RMSE 1e-7 (our tolerance); its time is
    the ICP call alone.

Accuracy: the rotation angle and the translation left between the recovered motion and the true one (the residual
motion at the blade's centre), and the RMS distance of the registered scan to the blade. Open3D is skipped when it
is not installed (`apt-get install python3-open3d`).

    pvpython benchmarks/registration_open3d.py --plugin build/.../PlantMorph.so [--angle 5] [--repeat 3]
"""
import argparse
import math
import time

import numpy

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--angle", type=float, default=5.0)
parser.add_argument("--repeat", type=int, default=3)
arguments = parser.parse_args()

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

LoadPlugin(arguments.plugin, remote=False, ns=globals())

# The blade and its scan.
leaf = LeafOutlineSource(Preset="Ginkgo")
curled = LeafCurlFilter(Input=leaf, LongitudinalAngle=50, TransverseAngle=40)
blade = servermanager.Fetch(curled)
vertices = vtk_to_numpy(blade.GetPoints().GetData()).astype(float)
low, high = vertices.min(axis=0), vertices.max(axis=0)
centre = 0.5 * (low + high)
length = float(numpy.linalg.norm(high - low))
scanner = VirtualScanner(Input=curled, ScannerType="Depth camera", Positions=list(centre + [0, 0, 2 * length]),
                         LookAt=list(centre), Up=[0, 1, 0], Resolution=[200, 200], HorizontalFieldOfView=40,
                         VerticalFieldOfView=40, RangeNoise=0.002 * length, Seed=3)
scan = vtk_to_numpy(servermanager.Fetch(scanner).GetPoints().GetData()).astype(float)

# The known motion: rotation about an oblique axis through the centre, then a shift.
axis = numpy.array([1.0, 2.0, 0.5])
axis /= numpy.linalg.norm(axis)
theta = math.radians(arguments.angle)
K = numpy.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
R = numpy.eye(3) + math.sin(theta) * K + (1 - math.cos(theta)) * K @ K
shift = 0.02 * length * numpy.array([0.6, -0.8, 0.0])
moved = (scan - centre) @ R.T + centre + shift  # truth: moved -> scan is the inverse motion


def motion_error(matrix):
    """Angle (degrees) and shift at the centre left after `matrix` (4x4, moved -> registered) is applied."""
    residual_rotation = matrix[:3, :3] @ R  # should be the identity
    u, _, vt = numpy.linalg.svd(residual_rotation)
    residual_rotation = u @ vt
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (numpy.trace(residual_rotation) - 1) / 2))))
    # Where the moved scan's image of the centre lands, against the centre.
    moved_centre = R @ numpy.zeros(3) + centre + shift
    landed = matrix[:3, :3] @ moved_centre + matrix[:3, 3]
    return angle, float(numpy.linalg.norm(landed - centre))


# Ours.
from vtkmodules.vtkCommonDataModel import vtkPolyData  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk  # noqa: E402

cloud = vtkPolyData()
points = vtkPoints()
points.SetData(numpy_to_vtk(numpy.ascontiguousarray(moved), deep=True))
cloud.SetPoints(points)
source = PVTrivialProducer()
source.GetClientSideObject().SetOutput(cloud)
comparison = CloudComparisonFilter(Input=source, Reference=curled, Registration="Rigid ICP")
times, cpu = [], []
for k in range(arguments.repeat + 1):
    comparison.RegistrationTolerance = 1e-7 * (1 + 1e-9 * k)  # a changed property: the filter runs again
    start, start_cpu = time.perf_counter(), time.process_time()
    comparison.UpdatePipeline()
    times.append(time.perf_counter() - start)
    cpu.append(time.process_time() - start_cpu)
result = servermanager.Fetch(comparison)
field = result.GetFieldData()
matrix = vtk_to_numpy(field.GetArray("PlantMorph.MeasuredTransform")).reshape(4, 4)
iterations = int(field.GetArray("PlantMorph.RegistrationIterations").GetValue(0))
registered = vtk_to_numpy(result.GetPoints().GetData()).astype(float)
distance = vtk_to_numpy(result.GetPointData().GetArray("Distance"))
angle, offset = motion_error(matrix)
print("points %d, blade length %.3f, true motion %.1f degrees + %.4f" % (len(scan), length, arguments.angle,
                                                                          numpy.linalg.norm(shift)))
print("ours   : first %.3f s, warm %.3f s (CPU %.3f / %.3f s), %d iterations, angle left %.4f deg, shift left %.5f, "
      "RMS %.5f" % (times[0], numpy.mean(times[1:]), cpu[0], numpy.mean(cpu[1:]), iterations, angle, offset,
                    math.sqrt(numpy.mean(distance ** 2))))

# Open3D, in a process of its own: Debian's Open3D links VTK 9.1, which must not meet ParaView's VTK in one process.
OPEN3D = r"""
import json, sys, time
import numpy
import open3d as o3d
data = numpy.load(sys.argv[1])
length, repeat = float(sys.argv[2]), int(sys.argv[3])
mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(data["vertices"]),
                                 o3d.utility.Vector3iVector(data["triangles"]))
mesh.compute_vertex_normals()
target = o3d.geometry.PointCloud(mesh.vertices)
target.normals = mesh.vertex_normals
moving = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(data["moved"]))
criteria = o3d.pipelines.registration.ICPConvergenceCriteria(relative_fitness=1e-7, relative_rmse=1e-7,
                                                             max_iteration=100)
times, cpu = [], []
for k in range(repeat + 1):
    start, start_cpu = time.perf_counter(), time.process_time()
    fit = o3d.pipelines.registration.registration_icp(
        moving, target, 0.1 * length, numpy.eye(4),
        o3d.pipelines.registration.TransformationEstimationPointToPlane(), criteria)
    times.append(time.perf_counter() - start)
    cpu.append(time.process_time() - start_cpu)
print(json.dumps({"times": times, "cpu": cpu, "matrix": numpy.asarray(fit.transformation).tolist(),
                  "fitness": fit.fitness}))
"""
import os  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from open3d_peer import run_open3d  # noqa: E402

with tempfile.TemporaryDirectory() as work:
    inputs = os.path.join(work, "inputs.npz")
    numpy.savez(inputs, vertices=vertices, moved=moved,
                triangles=vtk_to_numpy(blade.GetPolys().GetConnectivityArray()).reshape(-1, 3).astype(numpy.int32))
    reply = run_open3d(OPEN3D, inputs, repr(length), arguments.repeat, label="open3d")
if reply is not None:
    o3d_times = reply["times"]
    transformation = numpy.array(reply["matrix"])
    angle, offset = motion_error(transformation)
    aligned = moved @ transformation[:3, :3].T + transformation[:3, 3]
    out = vtkPolyData()
    out_points = vtkPoints()
    out_points.SetData(numpy_to_vtk(numpy.ascontiguousarray(aligned), deep=True))
    out.SetPoints(out_points)
    producer = PVTrivialProducer()
    producer.GetClientSideObject().SetOutput(out)
    check = CloudComparisonFilter(Input=producer, Reference=curled)
    rms = math.sqrt(numpy.mean(vtk_to_numpy(servermanager.Fetch(check).GetPointData().GetArray("Distance")) ** 2))
    o3d_cpu = reply["cpu"]
    print("open3d : first %.3f s, warm %.3f s (CPU %.3f / %.3f s), angle left %.4f deg, shift left %.5f, RMS %.5f "
          "(fitness %.3f)" % (o3d_times[0], numpy.mean(o3d_times[1:]), o3d_cpu[0], numpy.mean(o3d_cpu[1:]), angle,
                              offset, rms, reply["fitness"]))
    print("ours / open3d: first run %.1fx, warm %.1fx; CPU time: first run %.1fx, warm %.1fx"
          % (times[0] / o3d_times[0], numpy.mean(times[1:]) / numpy.mean(o3d_times[1:]), cpu[0] / o3d_cpu[0],
             numpy.mean(cpu[1:]) / numpy.mean(o3d_cpu[1:])))
