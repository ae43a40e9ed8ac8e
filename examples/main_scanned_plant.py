# SPDX-License-Identifier: GPL-3.0-or-later
"""A plant as a terrestrial laser scanner sees it: a template tree with leaves scanned from three tripods around it.

1. TreeFromSketchSource makes paper 004's Table 1 left template (monopodial 3/8) with leaves; its wood (port 0) and
   its leaves (port 2) are labelled Leaf 0 and 1 (a Calculator's constant) and appended: every cell carries BranchId
   and Leaf.
2. VirtualScanner (Terrestrial) scans it from three tripods 120 degrees apart, each at a tripod's height (a tenth of
   the tree's), 1.6 tree heights from the trunk, looking at the tree's middle, with range noise (0.1 % of the tree's
   height) and 5 % dropout. The crown hides the wood and leaves behind it, as in a real scan, and every point carries
   its hit cell's labels: the training data of wood-leaf segmentation.

scanned_plant.png shows the cloud from the side, coloured by organ (the Leaf label: brown wood, green leaf); the
cloud is written as scanned_plant_cloud.vtp (points with Normals, Range, Intensity, ScanPosition, BranchId, Leaf).

    xvfb-run -a pvbatch examples/main_scanned_plant.py --plugin build/.../PlantMorph.so --output output/
"""
import math
import os

from plantmorph_example import save_framed_png, save_state, save_vtp, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

WOOD = [0.45, 0.28, 0.12]
LEAF = [0.25, 0.62, 0.18]

tree = TreeFromSketchSource(registrationName="Tree", Preset="Table 1 left: monopodial 3/8", LeafScale=0.9,
                            LeafCount=3)
wood = Calculator(registrationName="WoodLabel", Input=OutputPort(tree, 0), AttributeType="Cell Data",
                  ResultArrayName="Leaf", Function="0", ResultArrayType="Int")
leaves = Calculator(registrationName="LeafLabel", Input=OutputPort(tree, 2), AttributeType="Cell Data",
                    ResultArrayName="Leaf", Function="1", ResultArrayType="Int")
plant = AppendGeometry(registrationName="Plant", Input=[wood, leaves])
plant.UpdatePipeline()
xmin, xmax, ymin, ymax, zmin, zmax = plant.GetDataInformation().GetBounds()
height = ymax - ymin  # the tree grows along +y from y = 0
middle = [0.5 * (xmin + xmax), 0.5 * (ymin + ymax), 0.5 * (zmin + zmax)]
distance = 1.6 * height
tripods = []
for k in range(3):
    angle = 2.0 * math.pi * (k + 0.25) / 3.0
    tripods += [middle[0] + distance * math.cos(angle), ymin + 0.1 * height, middle[2] + distance * math.sin(angle)]
# Each tripod's field of view holds the whole tree with a margin; 0.12 degrees between beams, about a tenth of the
# leaves' size at that range.
half_width = 0.5 * max(xmax - xmin, zmax - zmin)
horizontal = 2.4 * math.degrees(math.atan(half_width / distance))
vertical = 2.4 * math.degrees(math.atan(0.5 * height / distance))
scanner = VirtualScanner(registrationName="TerrestrialScan", Input=plant, ScannerType="Terrestrial",
                         Positions=tripods, LookAt=middle, Up=[0.0, 1.0, 0.0], HorizontalFieldOfView=horizontal,
                         VerticalFieldOfView=vertical, AngularStep=0.12, RangeNoise=0.001 * height,
                         DropoutProbability=0.05, Seed=1, MaximumRange=3.0 * distance)
cloud = servermanager.Fetch(scanner)
labels = cloud.GetPointData().GetArray("Leaf")
leaf_points = sum(labels.GetValue(i) for i in range(labels.GetNumberOfTuples()))
print("%d beams from %d tripods, %d points: %d wood, %d leaf" % (
    cloud.GetFieldData().GetArray("PlantMorph.Beams").GetValue(0), len(tripods) // 3, cloud.GetNumberOfPoints(),
    cloud.GetNumberOfPoints() - leaf_points, leaf_points))
save_vtp(scanner, os.path.join(arguments.output, "scanned_plant_cloud.vtp"))

view = white_view(800, 600)
points = Show(OutputPort(scanner, 0), view)
points.SetRepresentationType("Points")
points.PointSize = 2.0
points.RenderPointsAsSpheres = 1
ColorBy(points, ("POINTS", "Leaf"))
lut = GetColorTransferFunction("Leaf")
lut.InterpretValuesAsCategories = 1
lut.Annotations = ["0", "wood", "1", "leaf"]
lut.IndexedColors = WOOD + LEAF
bar = GetScalarBar(lut, view)
bar.Title = "organ (Leaf label)"
bar.ComponentTitle = ""
bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
bar.TitleFontSize = 15
bar.LabelFontSize = 15
bar.WindowLocation = "Upper Right Corner"
points.SetScalarBarVisibility(view, True)
# From the side, level with the tree's middle, a little off the first tripod's line so the trunk shows.
side = 2.0 * math.pi * 0.25 / 3.0 + 0.5
save_framed_png(view, os.path.join(arguments.output, "scanned_plant.png"), middle,
                [middle[0] + 4.0 * distance * math.cos(side), middle[1], middle[2] + 4.0 * distance * math.sin(side)],
                [0.0, 1.0, 0.0], 0.56 * height)
save_state(arguments, "scanned_plant")
