# SPDX-License-Identifier: GPL-3.0-or-later
"""CloudCompare's command-line C2M (cloud-to-mesh distance) next to CloudComparisonFilter on the same data:
a sphere of about 2*10^5 triangles and 10^6 points on it with 1% noise in random order (the "scan-like" case of
cloud_comparison_benchmark.cpp). Writes both inputs, runs `CloudCompare -SILENT ... -C2M_DIST` (under
QT_QPA_PLATFORM=offscreen), then the filter in this pvpython, and prints wall times and the largest difference
between the two distance fields.

    pvpython benchmarks/cloudcompare_c2m.py --plugin build/.../PlantMorph.so --work /tmp/c2m [--points 1000000]
CloudCompare is not a dependency: `apt-get install cloudcompare` (Debian 12: 2.11.3) to run this.
"""
import argparse
import os
import shutil
import subprocess
import time

import numpy

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--work", required=True)
parser.add_argument("--points", type=int, default=1000000)
arguments = parser.parse_args()
os.makedirs(arguments.work, exist_ok=True)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy, numpy_to_vtk  # noqa: E402
from vtkmodules.vtkIOPLY import vtkPLYWriter  # noqa: E402

LoadPlugin(arguments.plugin, remote=False, ns=globals())
sphere = Sphere(ThetaResolution=317, PhiResolution=317, Radius=1.0)
mesh = servermanager.Fetch(Triangulate(Input=sphere))
print("reference triangles:", mesh.GetNumberOfPolys())
rng = numpy.random.default_rng(7)
directions = rng.normal(size=(arguments.points, 3))
directions /= numpy.linalg.norm(directions, axis=1)[:, None]
cloud = directions * (1.0 + 0.01 * rng.normal(size=(arguments.points, 1)))

mesh_file = os.path.join(arguments.work, "sphere.ply")
cloud_file = os.path.join(arguments.work, "cloud.xyz")
writer = vtkPLYWriter()
writer.SetFileName(mesh_file)
writer.SetInputData(mesh)
writer.SetFileTypeToBinary()
writer.Write()
numpy.savetxt(cloud_file, cloud, fmt="%.9f")

# CloudCompare C2M.
executable = shutil.which("CloudCompare")
cc_distances = None
if executable:
    environment = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    for old in os.listdir(arguments.work):
        if old.startswith("cloud_C2M"):
            os.remove(os.path.join(arguments.work, old))
    start = time.time()
    run = subprocess.run([executable, "-SILENT", "-AUTO_SAVE", "OFF", "-C_EXPORT_FMT", "ASC", "-O", cloud_file, "-O",
                          mesh_file, "-C2M_DIST", "-SAVE_CLOUDS"], env=environment, capture_output=True, text=True,
                         cwd=arguments.work)
    cc_seconds = time.time() - start
    print("CloudCompare C2M: %.2f s wall (exit %d)" % (cc_seconds, run.returncode))
    outputs = [f for f in os.listdir(arguments.work) if f.startswith("cloud_C2M") and f.endswith(".asc")]
    if outputs:
        cc_distances = numpy.abs(numpy.loadtxt(os.path.join(arguments.work, outputs[0]))[:, 3])
else:
    print("CloudCompare not installed: only the filter is timed")

# CloudComparisonFilter on the same data.
points = vtk_to_numpy  # noqa: F841 (kept for readers of this script)
from vtkmodules.vtkCommonDataModel import vtkPolyData  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
measured = vtkPolyData()
pts = vtkPoints()
pts.SetData(numpy_to_vtk(cloud, deep=True))
measured.SetPoints(pts)
source = PVTrivialProducer()
source.GetClientSideObject().SetOutput(measured)
reference = PVTrivialProducer()
reference.GetClientSideObject().SetOutput(mesh)
comparison = CloudComparisonFilter(Input=source, Reference=reference)
start = time.time()
comparison.UpdatePipeline()
ours_seconds = time.time() - start
ours = vtk_to_numpy(servermanager.Fetch(comparison).GetPointData().GetArray("Distance"))
print("CloudComparisonFilter: %.2f s wall, %.0f points/s" % (ours_seconds, arguments.points / ours_seconds))
if cc_distances is not None and len(cc_distances) == len(ours):
    print("largest |CloudCompare - ours|: %.3g (CloudCompare stores float distances)" % numpy.abs(cc_distances - ours).max())
    print("ratio CloudCompare / ours: %.1fx" % (cc_seconds / ours_seconds))
