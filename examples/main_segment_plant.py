# SPDX-License-Identifier: GPL-3.0-or-later
"""The whole-plant pipeline: a plant scan becomes one trait row per leaf. Simulated here, so every number can be
checked against the truth the scanner carried.

1. A small herbaceous plant: TreeFromSketchSource (a stem, three shoots, three leaves each) with LeafOutlineSource's
   default blade instanced at every leaf site; its wood and leaves appended (every cell carries Organ and LeafId).
2. VirtualScanner (Terrestrial) scans it from four tripods around it, range noise 0.1 % of a leaf's length: each
   point knows the organ and leaf it hit (kept as TrueOrgan and TrueLeafId).
3. PlantSegmentationFilter with its defaults (UpAxis Y: the plant grows along +y) gives every point Organ and LeafId
   and tables per leaf and per plant.
4. The segmented cloud goes whole to LeafFitFilter with LeafIdArray = LeafId: one fitted blade and one row of
   traits per leaf (points with LeafId -1 are on no leaf and are not fitted); its Plant table sums the leaf area,
   counting the leaf points the segmentation left on no leaf (UnassignedLeafArea).

Prints, per found leaf, the true leaf it matches, its points, the segmentation's first area, LeafFitFilter's Area
and the true leaf's area (segment_plant.csv), then the plant's row. segment_plant.png shows the cloud coloured by
the LeafId found (wood brown); segment_plant.pvsm is the pipeline as a state file (File > Load State).

    xvfb-run -a pvbatch examples/main_segment_plant.py --plugin build/.../PlantMorph.so --output output/
"""
import math
import os

import plantmorph_example
from plantmorph_example import save_framed_png, save_state, save_vtp, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

LEAF_LENGTH = 1.5
blade = LeafOutlineSource(registrationName="Blade")
tree = TreeFromSketchSource(registrationName="Herb", Preset="Custom", Depth=1, ChildCount=3, Ratio=0.6, Length=4.0,
                            Radius=0.08, LeafCount=3, LeafScale=LEAF_LENGTH, LeafAngle=50.0, Sides=12)
tree.Leaf = OutputPort(blade, 0)
plant = AppendGeometry(registrationName="Plant", Input=[OutputPort(tree, 0), OutputPort(tree, 2)])
plant.UpdatePipeline()
xmin, xmax, ymin, ymax, zmin, zmax = plant.GetDataInformation().GetBounds()
middle = [0.5 * (xmin + xmax), 0.5 * (ymin + ymax), 0.5 * (zmin + zmax)]
size = max(xmax - xmin, ymax - ymin, zmax - zmin)
tripods = []
for k in range(4):
    angle = 0.5 * math.pi * k + 0.3
    tripods += [middle[0] + size * math.cos(angle), middle[1] + 0.3 * size, middle[2] + size * math.sin(angle)]
scan = VirtualScanner(registrationName="Scan", Input=plant, Positions=tripods, LookAt=middle, Up=[0, 1, 0],
                      HorizontalFieldOfView=80, VerticalFieldOfView=80, AngularStep=0.12,
                      RangeNoise=0.001 * LEAF_LENGTH, Seed=1, MaximumRange=5 * size)
# The scanner's truth under other names: the segmentation writes its own Organ and LeafId.
true_organ = Calculator(registrationName="TrueOrgan", Input=scan, ResultArrayName="TrueOrgan",
                        ResultArrayType="Int", Function="Organ")
truth = Calculator(registrationName="TrueLeafId", Input=true_organ, ResultArrayName="TrueLeafId",
                   ResultArrayType="Int", Function="LeafId")
segmentation = PlantSegmentationFilter(registrationName="Segmentation", Input=truth, UpAxis="Y")
fit = LeafFitFilter(registrationName="Fit", Input=OutputPort(segmentation, 0), LeafIdArray="LeafId", UpAxis="Y")
fit.UpdatePipeline()

cloud = servermanager.Fetch(segmentation, idx=0)
found = vtk_to_numpy(cloud.GetPointData().GetArray("LeafId"))
true_leaf = vtk_to_numpy(cloud.GetPointData().GetArray("TrueLeafId"))
organ = vtk_to_numpy(cloud.GetPointData().GetArray("Organ"))
true_organ_values = vtk_to_numpy(cloud.GetPointData().GetArray("TrueOrgan"))

# The true leaf areas: the leaves' triangles summed per LeafId.
leaves = servermanager.Fetch(tree, idx=2)
points = vtk_to_numpy(leaves.GetPoints().GetData())
cells = vtk_to_numpy(leaves.GetPolys().GetConnectivityArray()).reshape(-1, 3)
cell_leaf = vtk_to_numpy(leaves.GetCellData().GetArray("LeafId"))
a, b, c = points[cells[:, 0]], points[cells[:, 1]], points[cells[:, 2]]
true_area = numpy.bincount(cell_leaf, weights=0.5 * numpy.linalg.norm(numpy.cross(b - a, c - a), axis=1))

leaf_table = servermanager.Fetch(segmentation, idx=1)
traits = servermanager.Fetch(fit, idx=2)
fitted = dict(zip(vtk_to_numpy(traits.GetColumnByName("LeafId")).tolist(),
                  vtk_to_numpy(traits.GetColumnByName("Area")).tolist())) if traits.GetNumberOfRows() else {}
first = vtk_to_numpy(leaf_table.GetColumnByName("Area"))
rows = ["LeafId,TrueLeafId,Points,FirstArea,FittedArea,TrueArea"]
print("leaf  true  points  first area  fitted area  true area")
for k in range(leaf_table.GetNumberOfRows()):
    ids, counts = numpy.unique(true_leaf[found == k], return_counts=True)
    match = int(ids[counts.argmax()])
    area = fitted.get(k, float("nan"))
    truth_area = true_area[match] if match >= 0 else float("nan")
    print("%4d  %4d  %6d  %10.3f  %11.3f  %9.3f" % (k, match, counts.sum(), first[k], area, truth_area))
    rows.append("%d,%d,%d,%.6g,%.6g,%.6g" % (k, match, counts.sum(), first[k], area, truth_area))
with open(os.path.join(arguments.output, "segment_plant.csv"), "w") as f:
    f.write("\n".join(rows) + "\n")
plants = servermanager.Fetch(segmentation, idx=2)
print("plant: %s" % ", ".join("%s %s" % (plants.GetColumnName(c), plants.GetValue(0, c))
                              for c in range(plants.GetNumberOfColumns())))
leaf_plant = servermanager.Fetch(fit, idx=4)
if leaf_plant.GetNumberOfRows():
    print("leaf area: fitted %.4g, estimated with leaves seen in part and unassigned leaf points %.4g (of which %.4g "
          "unassigned), true %.4g" % (leaf_plant.GetValueByName(0, "TotalLeafArea").ToDouble(),
                                       leaf_plant.GetValueByName(0, "TotalEstimatedLeafArea").ToDouble(),
                                       leaf_plant.GetValueByName(0, "UnassignedLeafArea").ToDouble(), true_area.sum()))
for name, code in (("leaf", 1), ("wood", 0)):
    union = numpy.count_nonzero((organ == code) | (true_organ_values == code))
    print("%s IoU %.3f" % (name, numpy.count_nonzero((organ == code) & (true_organ_values == code)) / union))
save_vtp(segmentation, os.path.join(arguments.output, "segment_plant.vtp"))

if plantmorph_example.RENDER:
    view = white_view(800, 600)
    shown = Show(OutputPort(segmentation, 0), view)
    shown.SetRepresentationType("Points")
    shown.PointSize = 2.0
    ColorBy(shown, ("POINTS", "LeafId"))
    lut = GetColorTransferFunction("LeafId")
    count = leaf_table.GetNumberOfRows()
    lut.InterpretValuesAsCategories = 1
    palette = [[0.11, 0.62, 0.47], [0.85, 0.37, 0.01], [0.46, 0.44, 0.70], [0.91, 0.16, 0.54], [0.40, 0.65, 0.12],
               [0.90, 0.67, 0.01], [0.65, 0.46, 0.11], [0.40, 0.40, 0.40], [0.12, 0.47, 0.71], [0.70, 0.87, 0.54]]
    lut.Annotations = sum(([str(k), "leaf %d" % k] for k in range(count)), ["-1", "wood"])
    lut.IndexedColors = [0.45, 0.28, 0.12] + sum((palette[k % len(palette)] for k in range(count)), [])
    side = 0.3 + 0.25 * math.pi
    save_framed_png(view, os.path.join(arguments.output, "segment_plant.png"), middle,
                    [middle[0] + 4 * size * math.cos(side), middle[1], middle[2] + 4 * size * math.sin(side)],
                    [0.0, 1.0, 0.0], 0.56 * (ymax - ymin))
save_state(arguments, "segment_plant")
