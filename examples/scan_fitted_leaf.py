"""The comparison loop of issue 24: fit a leaf to a measured scan, scan the fitted leaf the way the leaf was scanned,
and compare the simulated cloud with the measured one.

    pvbatch examples/scan_fitted_leaf.py [--plugin build/.../PlantMorph.so] [--scan data/leaf-clouds/soybean_..txt]

1. Leaf Cloud Reader reads a shipped soybean scan (millimetres); a B-spline LeafOutlineSource leaf (centimetres) is
   fitted through control points picked from the scan, as examples/compare_scanned_leaf.py does (LeafFitFilter will
   replace this when it lands).
2. The fit residual: CloudComparisonFilter, scan against the fitted leaf (Scale 0.1: mm to cm).
3. VirtualScanner scans the fitted leaf with a set-up like the real one's: a depth camera on the leaf's normal, 3
   leaf lengths away, its pixel footprint on the leaf equal to the scan's mean point spacing, range noise equal to
   the residual's RMS (so the simulated cloud scatters about the model as the measured one does).
4. Cloud to cloud: CloudComparisonFilter of the measured scan against the simulated cloud (nearest neighbour), and
   of the simulated cloud against the fitted leaf, printed beside the fit residual: a simulated scan that samples
   like the real one gives cloud-to-cloud distances of the order of the residual and the spacing.
"""
import argparse
import glob
import math
import os

import numpy

from paraview.simple import *  # noqa: F401,F403 (the pvpython way)
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser()
parser.add_argument("--plugin", default=os.path.join(HERE, "..", "build", "lib", "paraview-5.11", "plugins",
                                                     "PlantMorph", "PlantMorph.so"))
parser.add_argument("--scan", default=sorted(glob.glob(os.path.join(HERE, "..", "data", "leaf-clouds",
                                                                     "soybean_*_pot1_1.txt")))[0])
arguments = parser.parse_args()
LoadPlugin(os.path.abspath(arguments.plugin), remote=False, ns=globals())

scan = LeafCloudReader(FileName=os.path.abspath(arguments.scan))
xyz = vtk_to_numpy(servermanager.Fetch(scan).GetPoints().GetData()) * 0.1  # mm -> cm

# 1. The fit (examples/compare_scanned_leaf.py's control points: principal frame, base and apex, five stations).
centre = xyz.mean(axis=0)
_, _, axes = numpy.linalg.svd(xyz - centre, full_matrices=False)
e_length, e_width = axes[0], axes[1]
s = (xyz - centre) @ e_length
t = (xyz - centre) @ e_width
if ((s > s.max() - 0.15 * (s.max() - s.min())).sum() > (s < s.min() + 0.15 * (s.max() - s.min())).sum()):
    s, e_length = -s, -e_length
base, apex = xyz[numpy.argmin(s)], xyz[numpy.argmax(s)]
stations = numpy.linspace(s.min(), s.max(), 7)[1:-1]
half = 0.5 * (stations[1] - stations[0])
midvein, left, right = [base], [base], [base]
for station in stations:
    ids = numpy.nonzero(numpy.abs(s - station) < half)[0]
    if len(ids) < 3:
        continue
    middle = numpy.median(t[ids])
    midvein.append(xyz[ids[numpy.argmin(numpy.abs(t[ids] - middle))]])
    left.append(xyz[ids[numpy.argmin(t[ids])]])
    right.append(xyz[ids[numpy.argmax(t[ids])]])
for points in (midvein, left, right):
    points.append(apex)
normal = numpy.cross(e_length, e_width)
if normal[2] < 0:
    left, right = right, left


def flat(points):
    return [float(x) for p in points for x in p]


leaf = LeafOutlineSource(Model="B-spline", BSplinePreset="Custom", Resolution=80,
                         MidveinPoints=flat(midvein), LeftMarginPoints=flat(left), RightMarginPoints=flat(right))
blade = servermanager.Fetch(leaf)
if blade.GetNumberOfPolys() == 0:
    leaf.LeftMarginPoints, leaf.RightMarginPoints = flat(right), flat(left)
    blade = servermanager.Fetch(leaf)


def statistics(comparison):
    table = servermanager.Fetch(comparison, idx=2)
    return {name: table.GetValueByName(0, name).ToDouble() for name in ("Count", "Mean", "RMS", "Percentile95")}


# 2. The fit residual.
residual = statistics(CloudComparisonFilter(Input=scan, Reference=leaf, Scale=0.1))

# 3. The simulated scan: spacing from the blade's area and the scan's point count.
points = vtk_to_numpy(blade.GetPoints().GetData())
polys = vtk_to_numpy(blade.GetPolys().GetConnectivityArray()).reshape(-1, 3)
area = 0.5 * numpy.linalg.norm(numpy.cross(points[polys[:, 1]] - points[polys[:, 0]],
                                           points[polys[:, 2]] - points[polys[:, 0]]), axis=1).sum()
spacing = math.sqrt(area / len(xyz))
length = s.max() - s.min()
distance = 3.0 * length
field = 2.0 * math.degrees(math.atan(0.65 * length / distance))
resolution = int(math.ceil(2.0 * distance * math.tan(math.radians(field / 2)) / spacing))
camera = list(centre + distance * normal / numpy.linalg.norm(normal))
scanner = VirtualScanner(Input=leaf, ScannerType="Depth camera", Positions=camera, LookAt=list(centre),
                         Up=list(e_length), HorizontalFieldOfView=field, VerticalFieldOfView=field,
                         Resolution=[resolution, resolution], RangeNoise=residual["RMS"], Seed=1)
simulated = servermanager.Fetch(scanner)

# 4. Cloud to cloud, and the simulated cloud against the model.
cloud_to_cloud = statistics(CloudComparisonFilter(Input=scan, Reference=OutputPort(scanner, 0), Scale=0.1))
simulated_to_model = statistics(CloudComparisonFilter(Input=OutputPort(scanner, 0), Reference=leaf))
print("leaf %.2f cm long, blade area %.2f cm^2; scan %d points, spacing %.3f cm; simulated %d points "
      "(depth camera %d x %d, %.1f degrees, range noise %.4f cm)"
      % (length, area, len(xyz), spacing, simulated.GetNumberOfPoints(), resolution, resolution, field,
         residual["RMS"]))
print("%-38s %8s %8s %8s %8s" % ("cm", "count", "mean", "RMS", "p95"))
for name, row in (("measured scan to fitted leaf (residual)", residual),
                  ("simulated scan to fitted leaf", simulated_to_model),
                  ("measured scan to simulated scan", cloud_to_cloud)):
    print("%-38s %8d %8.4f %8.4f %8.4f" % (name, row["Count"], row["Mean"], row["RMS"], row["Percentile95"]))
