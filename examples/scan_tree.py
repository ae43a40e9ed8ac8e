# SPDX-License-Identifier: GPL-3.0-or-later
"""Scan a tree with leaves from three positions and write a labelled point cloud for segmentation training.

    xvfb-run -a pvbatch examples/scan_tree.py [--plugin build/.../PlantMorph.so] [--output output] [--step 0.15]

1. TreeFromSketchSource makes a template tree with leaves; its wood (port 0) and its leaves (port 2) are appended,
   each cell labelled with BranchId (from the source) and Leaf (0 wood, 1 leaf, a Calculator's constant).
2. VirtualScanner (Terrestrial) scans it from three positions 120 degrees apart around the trunk, at the tree's
   mid-height (the tree grows along y), with 1 mm-like range noise (0.1 % of the tree's height) and 5 % dropout: leaves hide the leaves and
   branches behind them, as in a real terrestrial scan, and every point carries its hit cell's labels.
3. The cloud is written as scan_tree.vtp (every array), scan_tree.las (LAS 1.4 for lidar tools: every array, the
   labels among them, as a described extra-bytes dimension; docs/formats/las.md) and scan_tree.csv (x, y, z, normal,
   range, intensity, scan position and every label: the plain table point-cloud segmentation tools read), and rendered to
   scan_tree.png from the side, the whole tree in frame, each point coloured by the scan position that saw it.
"""
import argparse
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
parser.add_argument("--output", default=os.path.join(HERE, "..", "output"))
parser.add_argument("--step", type=float, default=0.15, help="the scanner's angular step, degrees")
arguments = parser.parse_args()
os.makedirs(arguments.output, exist_ok=True)
LoadPlugin(os.path.abspath(arguments.plugin), remote=False, ns=globals())

tree = TreeFromSketchSource()
wood = Calculator(Input=OutputPort(tree, 0), AttributeType="Cell Data", ResultArrayName="Leaf", Function="0",
                  ResultArrayType="Int")
leaves = Calculator(Input=OutputPort(tree, 2), AttributeType="Cell Data", ResultArrayName="Leaf", Function="1",
                    ResultArrayType="Int")
plant = AppendGeometry(Input=[wood, leaves])
surface = servermanager.Fetch(plant)
b = surface.GetBounds()
centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
height = b[3] - b[2]  # the tree grows along +y from y = 0
distance = 1.5 * max(b[1] - b[0], height, b[5] - b[4])
positions = []
for k in range(3):
    angle = 2 * math.pi * k / 3
    positions += [centre[0] + distance * math.cos(angle), centre[1], centre[2] + distance * math.sin(angle)]

scanner = VirtualScanner(Input=plant, ScannerType="Terrestrial", Positions=positions, LookAt=centre, Up=[0, 1, 0],
                         HorizontalFieldOfView=60, VerticalFieldOfView=60, AngularStep=arguments.step,
                         RangeNoise=0.001 * height, DropoutProbability=0.05, Seed=1, MaximumRange=3 * distance)
scanner.UpdatePipeline()
cloud = servermanager.Fetch(scanner)
print("%d beams, %d points" % (cloud.GetFieldData().GetArray("PlantMorph.Beams").GetValue(0),
                               cloud.GetNumberOfPoints()))

vtp = os.path.join(arguments.output, "scan_tree.vtp")
SaveData(vtp, proxy=OutputPort(scanner, 0))
las = os.path.join(arguments.output, "scan_tree.las")
SaveData(las, proxy=OutputPort(scanner, 0))

# The CSV: one row per point, every point array (vectors split into _x, _y, _z columns).
pd = cloud.GetPointData()
columns = [("x", "y", "z")]
values = [vtk_to_numpy(cloud.GetPoints().GetData())]
for i in range(pd.GetNumberOfArrays()):
    a = pd.GetArray(i)
    if a is None:
        continue
    data = vtk_to_numpy(a).reshape(cloud.GetNumberOfPoints(), -1)
    name = a.GetName()
    columns.append(tuple(name + ("_%s" % "xyz"[c] if data.shape[1] == 3 else ("_%d" % c if data.shape[1] > 1 else ""))
                         for c in range(data.shape[1])))
    values.append(data.astype(numpy.float64))
table = numpy.hstack(values)
header = ",".join(name for group in columns for name in group)
csv = os.path.join(arguments.output, "scan_tree.csv")
numpy.savetxt(csv, table, delimiter=",", header=header, comments="", fmt="%.9g")
print("wrote", vtp, las, "and", csv, "columns:", header)

# The picture: the cloud seen from the side (the tree grows along +y), between two scan positions, the whole tree
# in frame, each point coloured by the position that saw it.
view = CreateView("RenderView")
view.ViewSize = [800, 600]
view.OrientationAxesVisibility = 0
view.Background = [1, 1, 1]
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass
display = Show(OutputPort(scanner, 0), view)
display.SetRepresentationType("Points")
display.PointSize = 2
ColorBy(display, ("POINTS", "ScanPosition"))
lut = GetColorTransferFunction("ScanPosition")
lut.InterpretValuesAsCategories = 1
lut.Annotations = ["0", "position 1", "1", "position 2", "2", "position 3"]
lut.IndexedColors = [0.85, 0.37, 0.01, 0.46, 0.44, 0.70, 0.11, 0.62, 0.47]  # colour-blind safe (Dark2)
bar = GetScalarBar(lut, view)
bar.Title = "seen from"
bar.ComponentTitle = ""
bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
bar.TitleFontSize = 15
bar.LabelFontSize = 15
bar.WindowLocation = "Upper Right Corner"
display.SetScalarBarVisibility(view, True)
Render(view)  # the first render resets the camera: set ours after it
side = math.pi / 3  # halfway between the first two positions
view.CameraFocalPoint = centre
view.CameraPosition = [centre[0] + 4 * distance * math.cos(side), centre[1], centre[2] + 4 * distance * math.sin(side)]
view.CameraViewUp = [0, 1, 0]
view.CameraParallelProjection = 1
view.CameraParallelScale = 0.56 * height
picture = os.path.join(arguments.output, "scan_tree.png")
SaveScreenshot(picture, view, ImageResolution=[800, 600], CompressionLevel="9")
print("wrote", picture)
