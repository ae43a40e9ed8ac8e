# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: PlantSegmentationFilter as users build it. The proxy is in the PlantMorph menu with its documented
defaults; a simulated plant (TreeFromSketchSource's wood and leaves, scanned by VirtualScanner from two sides, the
scan carrying the true Organ and LeafId) comes out with Organ, LeafId and SegmentationConfidence on every point,
close to the truth, a Leaves row per leaf and a Plants row; two plants told apart by PlantIdArray are segmented each
on its own; and bad input (a PlantIdArray the input lacks, one point, a NaN point, a bare stem, a leaf alone) gives an
error naming the problem and empty outputs on all three ports.

    pvpython test_plant_segmentation.py --plugin PlantMorph.so --work DIR
"""
from plantmorph_testing import Checks, Messages, load_plugin, parse_arguments, scan_around

arguments = parse_arguments([("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()


def outputs(proxy):
    proxy.UpdatePipeline()
    return [servermanager.Fetch(proxy, idx=port) for port in range(3)]


def scanned(tree_proxy):
    plant = AppendGeometry(Input=[OutputPort(tree_proxy, 0), OutputPort(tree_proxy, 2)])
    return scan_around(VirtualScanner, plant, 2, 0.15, 0.0015, 2)


# The menu and the defaults.
segmentation = PlantSegmentationFilter(Input=LeafOutlineSource())
for name, value in (("PlantIdArray", "None"), ("UpAxis", "Z"), ("FeatureScale", 4.0), ("LinkScale", 2.5),
                    ("NormalAngle", 25.0), ("CreaseVariation", 0.02), ("SheetCoherence", 0.8),
                    ("MaximumLeafElongation", 12.0), ("MinimumLeafPoints", 50)):
    checks.check(segmentation.GetPropertyValue(name) == value, "default %s = %r (is %r)" % (
        name, value, segmentation.GetPropertyValue(name)))
Delete(segmentation)

# A herb: a stem, three shoots, nine leaves, scanned from two sides.
tree = TreeFromSketchSource(Preset="Custom", Depth=1, ChildCount=3, Ratio=0.6, Length=4.0, Radius=0.08,
                            LeafCount=3, LeafScale=1.5, LeafAngle=50.0, Sides=12)
scan = scanned(tree)
segmentation = PlantSegmentationFilter(Input=scan, UpAxis="Y")
points, leaves, plants = outputs(segmentation)
truth = servermanager.Fetch(scan).GetPointData()
n = points.GetNumberOfPoints()
checks.check(n == servermanager.Fetch(scan).GetNumberOfPoints() and n > 10000, "every scanned point out (%d)" % n)
organ = vtk_to_numpy(points.GetPointData().GetArray("Organ"))
leaf = vtk_to_numpy(points.GetPointData().GetArray("LeafId"))
confidence = vtk_to_numpy(points.GetPointData().GetArray("SegmentationConfidence"))
true_organ = vtk_to_numpy(truth.GetArray("Organ"))
true_leaf = vtk_to_numpy(truth.GetArray("LeafId"))
leaf_iou = numpy.count_nonzero((organ == 1) & (true_organ == 1)) / numpy.count_nonzero((organ == 1) | (true_organ == 1))
checks.check(leaf_iou > 0.95, "leaf IoU against the scan's truth %.3f > 0.95" % leaf_iou)
checks.check(bool(numpy.all((confidence >= 0) & (confidence <= 1))), "confidences in [0, 1]")
checks.check(bool(numpy.all((leaf >= 0) <= (organ == 1))), "LeafId only on leaf points")
found = sorted(set(leaf[leaf >= 0].tolist()))
checks.check(found == list(range(leaves.GetNumberOfRows())), "one Leaves row per LeafId (%d)" % len(found))
matched = 0
for k in found:
    ids, counts = numpy.unique(true_leaf[leaf == k], return_counts=True)
    best = counts.argmax()
    inter = counts[best]
    union = numpy.count_nonzero(leaf == k) + numpy.count_nonzero(true_leaf == ids[best]) - inter
    matched += ids[best] >= 0 and inter / union > 0.5
checks.check(matched >= 7, "%d of the 9 leaves found at IoU > 0.5 (%d instances)" % (matched, len(found)))
rows = {leaves.GetColumnName(c) for c in range(leaves.GetNumberOfColumns())}
checks.check({"LeafId", "PlantId", "Points", "Area", "Base", "Branch", "PetioleLength"} <= rows,
             "Leaves columns: %s" % sorted(rows))
column = lambda table, name: vtk_to_numpy(table.GetColumnByName(name))  # noqa: E731
checks.check(bool(numpy.all(column(leaves, "Points") == [numpy.count_nonzero(leaf == k) for k in found])),
             "each row's Points is its LeafId's point count")
area = column(leaves, "Area")
checks.check(bool(numpy.all(area < 1.5 * 1.5 * 1.1)), "first areas at most a 1.5-wide quad's: %s" % area.round(2))
checks.check(plants.GetNumberOfRows() == 1 and column(plants, "LeafCount")[0] == len(found),
             "one Plants row with the leaf count")
counted = sum(column(plants, name)[0] for name in ("WoodPoints", "LeafPoints", "PetiolePoints"))
checks.check(counted == n, "wood + leaf + petiole points = all")
# the herb's leaves have no petiole (its truth has no Organ 2): any petiole point would be wood or leaf called petiole
checks.check(numpy.count_nonzero(true_organ == 2) == 0 and numpy.count_nonzero(organ == 2) == 0,
             "no petiole on a plant without petioles (%d called)" % numpy.count_nonzero(organ == 2))
checks.check(bool(numpy.all(column(leaves, "PetioleLength") == 0)), "no PetioleLength without petioles")
b = points.GetBounds()
checks.check(abs(column(plants, "Height")[0] - (b[3] - b[2])) < 1e-9, "Height is the extent along Y")

# Two plants side by side, told apart by a point array.
calculator = Calculator(Input=scan, ResultArrayName="Plant", ResultArrayType="Int", Function="0")
second = Transform(Input=calculator)
second.Transform.Translate = [20, 0, 0]
other = Calculator(Input=second, ResultArrayName="Plant", ResultArrayType="Int", Function="1")
both = AppendGeometry(Input=[calculator, other])
pair = PlantSegmentationFilter(Input=both, PlantIdArray="Plant", UpAxis="Y")
pair_points, pair_leaves, pair_plants = outputs(pair)
checks.check(pair_plants.GetNumberOfRows() == 2 and list(column(pair_plants, "PlantId")) == [0, 1],
             "two Plants rows")
checks.check(pair_leaves.GetNumberOfRows() == 2 * leaves.GetNumberOfRows(), "each plant its own leaves")
pair_leaf = vtk_to_numpy(pair_points.GetPointData().GetArray("LeafId"))
checks.check(len(set(pair_leaf[pair_leaf >= 0].tolist())) == 2 * len(found), "LeafIds unique over both plants")


def refused(proxy, words, what):
    with Messages(proxy) as messages:
        data = outputs(proxy)
    empty = all(d.GetNumberOfPoints() == 0 if d.IsA("vtkPolyData") else d.GetNumberOfRows() == 0 for d in data)
    checks.check(messages.said(*words, kind="error") and empty,
                 "%s: an error with %s and empty outputs (%s)" % (what, words, messages.errors))


refused(PlantSegmentationFilter(Input=scan, PlantIdArray="NoSuchArray"), ["PlantIdArray", "NoSuchArray"],
        "a missing PlantIdArray")
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkPolyData  # noqa: E402


def cloud_source(coordinates):
    data = vtkPolyData()
    p = vtkPoints()
    p.SetData(numpy_to_vtk(numpy.ascontiguousarray(coordinates, dtype=numpy.float64), deep=1))
    data.SetPoints(p)
    source = PVTrivialProducer()
    source.GetClientSideObject().SetOutput(data)
    return source


refused(PlantSegmentationFilter(Input=cloud_source([[0.0, 0.0, 0.0]])), ["1 points"], "one point")
coordinates = vtk_to_numpy(servermanager.Fetch(scan).GetPoints().GetData()).copy()
coordinates[5, 1] = numpy.nan
refused(PlantSegmentationFilter(Input=cloud_source(coordinates)), ["point 5", "non-finite"], "a NaN point")
stem = Cylinder(Resolution=64, Capping=0, Height=4.0, Radius=0.1)
stem_scan = VirtualScanner(Input=stem, Positions=[3, 0, 0, -3, 0, 0], LookAt=[0, 0, 0], Up=[0, 1, 0],
                           HorizontalFieldOfView=20, VerticalFieldOfView=80, AngularStep=0.1)
refused(PlantSegmentationFilter(Input=stem_scan, UpAxis="Y"), ["no leaf found"], "wood only (a stem)")
leaf_scan = VirtualScanner(Input=LeafOutlineSource(), Positions=[0, 2.5, 8], LookAt=[0, 2.5, 0], Up=[0, 1, 0],
                           HorizontalFieldOfView=60, VerticalFieldOfView=60, AngularStep=0.2)
refused(PlantSegmentationFilter(Input=leaf_scan), ["no wood found"], "a leaf only")
checks.finish()
