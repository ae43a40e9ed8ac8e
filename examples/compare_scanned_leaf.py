"""Compare a scanned soybean leaf with a B-spline leaf (LeafOutlineSource, Model C) fitted to it.

    xvfb-run -a pvbatch examples/compare_scanned_leaf.py [--plugin build/.../PlantMorph.so] [--output output]

1. Leaf Cloud Reader reads the scan (data/leaf-clouds/soybean_*_1.txt: x, y, z in mm, normals, colours).
2. Control points are picked from the scan: in the scan's principal frame (numpy PCA: length, width, normal), the
   base and apex are the extreme points along the length; at 5 stations along it the midvein point is the scan point
   nearest the middle of the slice and the margin points are the slice's widest scan points on each side. Picked
   points are scan points, in cm (x 0.1), so the B-spline leaf passes through the scan's own margin.
3. LeafOutlineSource(Model="B-spline", BSplinePreset="Custom") builds the leaf through them (a curved blade: the
   points are 3-D).
4. Cloud Comparison Filter (Scale 0.1: the scan is in mm) gives the distances, the histogram and the statistics; they
   are printed, the distance colour map and the histogram are rendered to PNG.
"""
import argparse
import glob
import os

import numpy

from paraview.simple import *  # noqa: F401,F403 (the pvpython way)
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser()
parser.add_argument("--plugin", default=os.path.join(HERE, "..", "build", "lib", "paraview-5.11", "plugins",
                                                     "PlantMorph", "PlantMorph.so"))
parser.add_argument("--output", default=os.path.join(HERE, "..", "output"))
parser.add_argument("--scan", default=sorted(glob.glob(os.path.join(HERE, "..", "data", "leaf-clouds",
                                                                     "soybean_*_pot1_1.txt")))[0])
arguments = parser.parse_args()
os.makedirs(arguments.output, exist_ok=True)
LoadPlugin(os.path.abspath(arguments.plugin), remote=False, ns=globals())

scan = LeafCloudReader(FileName=os.path.abspath(arguments.scan))
cloud = servermanager.Fetch(scan)
xyz = vtk_to_numpy(cloud.GetPoints().GetData()) * 0.1  # mm -> cm

# Principal frame: e_length (largest spread), e_width, e_normal.
centre = xyz.mean(axis=0)
_, _, axes = numpy.linalg.svd(xyz - centre, full_matrices=False)
e_length, e_width = axes[0], axes[1]
s = (xyz - centre) @ e_length
t = (xyz - centre) @ e_width
# The base is the narrower end (the petiole side of a soybean leaflet is narrower than its apex half? not always):
# take the end whose last 15 % of length holds fewer points as the apex (the tip tapers).
if ((s > s.max() - 0.15 * (s.max() - s.min())).sum() > (s < s.min() + 0.15 * (s.max() - s.min())).sum()):
    s, e_length = -s, -e_length
base = xyz[numpy.argmin(s)]
apex = xyz[numpy.argmax(s)]
stations = numpy.linspace(s.min(), s.max(), 7)[1:-1]
width = 0.5 * (stations[1] - stations[0])
midvein, left, right = [base], [base], [base]
for station in stations:
    in_slice = numpy.abs(s - station) < width
    if in_slice.sum() < 3:
        continue
    ids = numpy.nonzero(in_slice)[0]
    middle = numpy.median(t[ids])
    midvein.append(xyz[ids[numpy.argmin(numpy.abs(t[ids] - middle))]])
    left.append(xyz[ids[numpy.argmin(t[ids])]])
    right.append(xyz[ids[numpy.argmax(t[ids])]])
midvein.append(apex)
left.append(apex)
right.append(apex)
# Which side is "left" depends on the normal's orientation: the leaf is meshed with its normal towards +Z.
normal = numpy.cross(e_length, e_width)
if normal[2] < 0:
    left, right = right, left


def flat(points):
    return [float(x) for p in points for x in p]


leaf = LeafOutlineSource(Model="B-spline", BSplinePreset="Custom", Resolution=80,
                         MidveinPoints=flat(midvein), LeftMarginPoints=flat(left), RightMarginPoints=flat(right))
blade = servermanager.Fetch(leaf)
if blade.GetNumberOfPolys() == 0:
    # The least-squares plane's normal came out the other way: the margins swap sides.
    left, right = right, left
    leaf.LeftMarginPoints = flat(left)
    leaf.RightMarginPoints = flat(right)
    blade = servermanager.Fetch(leaf)
print("fitted B-spline leaf: %d triangles through %d + %d + %d control points picked from the scan"
      % (blade.GetNumberOfPolys(), len(midvein), len(left), len(right)))

comparison = CloudComparisonFilter(Input=scan, Reference=leaf, Scale=0.1, Symmetric=1, HistogramBins=30)
statistics = servermanager.Fetch(comparison, idx=2)
for i in range(statistics.GetNumberOfColumns()):
    print("  %-20s %.4f" % (statistics.GetColumnName(i), statistics.GetValue(0, i).ToDouble()))

# Render: the scan coloured by signed distance over the fitted leaf, and the histogram as a bar chart.
view = CreateView("RenderView")
view.ViewSize = [1000, 800]
view.Background = [1, 1, 1]
view.OrientationAxesVisibility = 0
leaf_display = Show(leaf, view)
leaf_display.DiffuseColor = [0.55, 0.75, 0.5]
leaf_display.Opacity = 0.6
points_display = Show(OutputPort(comparison, 0), view)
points_display.SetRepresentationType("Points")
points_display.PointSize = 4
ColorBy(points_display, ("POINTS", "SignedDistance"))
lut = GetColorTransferFunction("SignedDistance")
lut.ApplyPreset("Cool to Warm", True)
bound = max(abs(statistics.GetValueByName(0, "Percentile99").ToDouble()), 1e-6)
lut.RescaleTransferFunction(-bound, bound)
points_display.SetScalarBarVisibility(view, True)
view.CameraPosition = list(centre + 40 * normal)
view.CameraFocalPoint = list(centre)
view.CameraViewUp = list(e_length)
view.ResetCamera()
SaveScreenshot(os.path.join(arguments.output, "compare_scanned_leaf.png"), view)

chart = CreateView("XYBarChartView")
chart.ViewSize = [800, 500]
bars = Show(OutputPort(comparison, 1), chart)
bars.XArrayName = "bin_extents"
bars.SeriesVisibility = ["bin_values"]
chart.ChartTitle = "Scan to fitted leaf: distance (cm)"
SaveScreenshot(os.path.join(arguments.output, "compare_scanned_leaf_histogram.png"), chart)
print("wrote", os.path.join(arguments.output, "compare_scanned_leaf.png"), "and compare_scanned_leaf_histogram.png")
