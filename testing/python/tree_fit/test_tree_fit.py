# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: TreeFromSketchSource -> VirtualScanner -> TreeFitFilter, as users run it with the defaults. A small tree
of exact tubes (seated, 24 sides) scanned from three positions with 2 mm noise: the five ports and their arrays,
volume, DBH and height against the tree's own skeleton, the cylinders on the points (median |FitDistance| about the
noise), the CSV writer's cylinder table, tubes; several trees told apart by TreeIdArray (one too small to fit: its
row says why, the others are fitted as alone); WoodArray, an Organ array (0 wood) and WoodValues; the Skeleton rebuilt
by TreeFromSketchSource as its merged tree (the documented recipe), with leaves, scanned again, compared with the scan
by CloudComparisonFilter, and edited (a measured branch deleted, one's length halved); bad
input (noise, a plane, a line, a few points, NaN, a missing array) gives an error and empty outputs.

    pvpython test_tree_fit.py --plugin PlantMorph.so --work DIR
"""
import math
import os

from plantmorph_testing import Checks, Messages, load_plugin, parse_arguments, skeleton_truth

arguments = parse_arguments([("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()
NOISE = 0.002


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, idx=port)


def rows(fit, port=2):
    table = fetch(fit, port)
    names = [table.GetColumnName(c) for c in range(table.GetNumberOfColumns())]
    return [{n: table.GetValueByName(r, n).ToString() if n == "Status" else table.GetValueByName(r, n).ToDouble()
             for n in names} for r in range(table.GetNumberOfRows())]


def scanned(tree, centre_height, distance=7.0):
    positions = []
    for k in range(3):
        a = 2 * math.pi * (k + 0.1) / 3
        positions += [distance * math.cos(a), 1.5, distance * math.sin(a)]
    return VirtualScanner(Input=tree, Positions=positions, LookAt=[0, centre_height, 0], Up=[0, 1, 0],
                          HorizontalFieldOfView=50, VerticalFieldOfView=60, AngularStep=0.07, RangeNoise=NOISE,
                          Seed=3)


def outputs_empty(fit):
    return (fetch(fit, 0).GetNumberOfCells() == 0 and fetch(fit, 1).GetNumberOfCells() == 0
            and fetch(fit, 2).GetNumberOfRows() == 0 and fetch(fit, 3).GetNumberOfRows() == 0
            and fetch(fit, 4).GetNumberOfPoints() == 0)


TREE = dict(Preset="Custom", TreeType="Monopodial", Length=4.0, Radius=0.12, Depth=1, ChildCount=4, Sides=24,
            Joints="Seated tubes", Leaves=0)
tree = TreeFromSketchSource(**TREE)
truth = skeleton_truth(fetch(tree, 1), fetch(tree, 0).GetBounds())
volume, dbh, height = truth["volume"], truth["dbh"], truth["height"]
scan = scanned(tree, 2.5)
fit = TreeFitFilter(Input=scan, UpAxis="Y")
cylinders, skeleton, scan_out = fetch(fit, 0), fetch(fit, 1), fetch(fit, 4)
trees, branches = rows(fit, 2), rows(fit, 3)
checks.check(len(trees) == 1 and trees[0]["Status"] == "ok", "one Trees row, status ok")
row = trees[0] if trees else {}
for name in ("Height", "DBH", "TrunkVolume", "BranchVolume", "TotalVolume", "TrunkLength", "TotalBranchLength",
             "BranchCount", "BranchesOrder1", "CrownProjectedArea", "CrownBaseHeight", "Points", "WoodPoints",
             "FitRMS", "MeasuredVolumeFraction", "WoodHeight"):
    checks.check(name in row, "Trees has " + name)
checks.check(row.get("WoodHeight") == row.get("Height"), "without leaf points the tree's height is its wood's")
checks.check(abs(row.get("TotalVolume", 0) / volume - 1) < 0.15,
             "total volume %.4f within 15 %% of the skeleton's %.4f" % (row.get("TotalVolume", 0), volume))
checks.check(abs(row.get("DBH", 0) / dbh - 1) < 0.05, "DBH %.4f within 5 %% of %.4f" % (row.get("DBH", 0), dbh))
checks.check(abs(row.get("Height", 0) / height - 1) < 0.02, "height %.3f within 2 %% of %.3f" % (row.get("Height", 0), height))
checks.check(row.get("BranchesOrder1", 0) >= 3, "at least 3 of the 4 first-order branches")
checks.check(len(branches) == int(row.get("BranchCount", -1)) + 1, "one Branches row per branch and the trunk")
for name in ("TreeId", "BranchId", "ParentId", "Order", "Length", "Volume", "BaseDiameter", "Angle", "Azimuth",
             "Inclination", "Height"):
    checks.check(all(name in b for b in branches), "Branches has " + name)
checks.check(abs(sum(b.get("Volume", 0) for b in branches) / row.get("TotalVolume", 1) - 1) < 1e-9,
             "the branch volumes add up to the tree's")
checks.check(all(b.get("ParentId") == -1 for b in branches if b.get("Order") == 0)
             and all(0 <= b.get("Height", -1) <= row.get("Height", 0) for b in branches),
             "the trunk has no parent, every branch's base lies within the tree's height")
checks.check(all(b["Order"] == 0 or 15 < b["Angle"] < 60 for b in branches), "first-order angles near the 34.4 degrees")
n = cylinders.GetNumberOfCells()
checks.check(n > 10 and cylinders.GetNumberOfLines() == n, "Cylinders: one line cell per cylinder")
for name in ("Radius", "Length", "CylinderId", "ParentId", "BranchId", "BranchOrder", "SegmentId", "TreeId", "FitRMS",
             "Support", "Measured", "StartX", "EndZ"):
    checks.check(cylinders.GetCellData().GetArray(name) is not None, "Cylinders has " + name)
checks.check(skeleton.GetNumberOfLines() == len(branches), "Skeleton: one polyline per branch")
for name in ("BranchId", "BranchOrder", "ParentId", "Radius"):
    checks.check(skeleton.GetPointData().GetArray(name) is not None, "Skeleton has point array " + name)
distance = vtk_to_numpy(scan_out.GetPointData().GetArray("FitDistance"))
checks.check(scan_out.GetNumberOfPoints() == fetch(scan).GetNumberOfPoints(), "Scan has every input point")
median = float(numpy.nanmedian(numpy.abs(distance)))
checks.check(median < 2.5 * NOISE, "the cylinders lie on the points: median |FitDistance| %.4f" % median)
for name in ("TreeId", "CylinderId", "BranchId", "Wood", "FitDistance"):
    checks.check(scan_out.GetPointData().GetArray(name) is not None, "Scan has " + name)

# The cylinder table QSM tools read: ParaView's CSV writer on the Cylinders' cell data.
csv = os.path.join(arguments.work, "tree_fit_cylinders.csv")
SaveData(csv, proxy=OutputPort(fit, 0), FieldAssociation="Cell Data")
with open(csv) as f:
    header = f.readline().strip().replace('"', "").split(",")
for column in ("StartX", "StartY", "StartZ", "EndX", "EndY", "EndZ", "Radius", "Length", "ParentId",
               "BranchOrder", "BranchId"):
    checks.check(column in header, "the CSV has " + column)

# Tubes: a capped tube of TubeSides sides per cylinder (sides quads + 2 caps).
fit.Tubes, fit.TubeSides = 1, 8
checks.check(fetch(fit, 0).GetNumberOfPolys() == 10 * n, "Tubes: 10 cells per cylinder with 8 sides")
fit.Tubes = 0

# The documented recipe: the Skeleton becomes a PlantMorph tree (TreeFromSketchSource's merged tree, the template's
# own trunk deleted), with leaves, and scans again.
RECIPE = dict(Preset="Custom", Depth=0, MergeParentBranch=-1, MergeAngle=0, MergeRotation=0, DeletedBranches=[0],
              Sides=24)
rebuilt = TreeFromSketchSource(MergeTree=OutputPort(fit, 1), Leaves=1, **RECIPE)
rebuilt_skeleton = fetch(rebuilt, 1)
checks.check(rebuilt_skeleton.GetNumberOfLines() == skeleton.GetNumberOfLines(), "the rebuilt tree has every branch")
extent = numpy.diff(numpy.reshape(skeleton.GetBounds(), (3, 2)), axis=1)
rebuilt_extent = numpy.diff(numpy.reshape(rebuilt_skeleton.GetBounds(), (3, 2)), axis=1)
checks.check(numpy.allclose(extent, rebuilt_extent, atol=1e-6), "the rebuilt skeleton has the fitted one's shape")
checks.check(fetch(rebuilt, 2).GetNumberOfCells() > 0, "the rebuilt tree has leaves")
rescan = scanned(rebuilt, 2.5)
checks.check(fetch(rescan).GetNumberOfPoints() > 1000, "the rebuilt tree scans")
bare = TreeFromSketchSource(MergeTree=OutputPort(fit, 1), Leaves=0, Joints="Seated tubes", **RECIPE)
refit = TreeFitFilter(Input=scanned(bare, 2.5), UpAxis="Y")
# CloudComparisonFilter on the measured tree: the original scan against the rebuilt tree's surface lies about the noise.
comparison = CloudComparisonFilter(Input=scan, Reference=bare)
statistics = fetch(comparison, 2)
p50 = statistics.GetValueByName(0, "Percentile50").ToDouble() if statistics.GetNumberOfRows() else float("inf")
checks.check(p50 < 3 * NOISE, "CloudComparisonFilter: the scan lies on the rebuilt tree, median %.4f" % p50)
again = rows(refit)
checks.check(len(again) == 1 and abs(again[0]["TotalVolume"] / row.get("TotalVolume", 1) - 1) < 0.15,
             "the rebuilt tree fits to the same volume within 15 %")

# Edits on the measured tree (TreeFromSketchSource's DeletedBranches and BranchOverrides address a merged branch as
# PlantMorph.MergeIdBase + its fitted BranchId): the heaviest first-order branch deleted takes its subtree with it,
# and a refit finds one first-order branch fewer and about that subtree's volume less; its length halved gives a
# branch half as long.
base = int(fetch(bare, 1).GetFieldData().GetArray("PlantMorph.MergeIdBase").GetValue(0))
first = max((b for b in branches if b["Order"] == 1), key=lambda b: b["Volume"])
subtree, grown = {int(first["BranchId"])}, True
while grown:
    more = {int(b["BranchId"]) for b in branches if int(b["ParentId"]) in subtree}
    grown, subtree = not more <= subtree, subtree | more
removed = sum(b["Volume"] for b in branches if int(b["BranchId"]) in subtree)
pruned = TreeFromSketchSource(MergeTree=OutputPort(fit, 1), Leaves=0, Joints="Seated tubes",
                              **dict(RECIPE, DeletedBranches=[0, base + int(first["BranchId"])]))
pruned_ids = set(vtk_to_numpy(fetch(pruned, 1).GetCellData().GetArray("BranchId")).tolist())
checks.check(len(pruned_ids) == skeleton.GetNumberOfLines() - len(subtree)
             and not {base + k for k in subtree} & pruned_ids,
             "a deleted measured branch takes its %d-branch subtree with it" % len(subtree))
before, after = rows(refit)[0], rows(TreeFitFilter(Input=scanned(pruned, 2.5), UpAxis="Y"))[0]
checks.check(after["BranchesOrder1"] == before["BranchesOrder1"] - 1,
             "the pruned tree refits with one first-order branch fewer (%d, %d)"
             % (after["BranchesOrder1"], before["BranchesOrder1"]))
lost = before["TotalVolume"] - after["TotalVolume"]
checks.check(abs(lost / removed - 1) < 0.3, "the pruned tree's volume falls by the subtree's: %.5f for %.5f"
             % (lost, removed))


def branch_length(skeleton_data, branch_id):
    points = vtk_to_numpy(skeleton_data.GetPoints().GetData())
    ids = vtk_to_numpy(skeleton_data.GetCellData().GetArray("BranchId"))
    cell = skeleton_data.GetCell(int(numpy.nonzero(ids == branch_id)[0][0]))
    line = points[[cell.GetPointId(k) for k in range(cell.GetNumberOfPoints())]]
    return float(numpy.linalg.norm(numpy.diff(line, axis=0), axis=1).sum())


merged_id = base + int(first["BranchId"])
shorter = TreeFromSketchSource(MergeTree=OutputPort(fit, 1), Leaves=0, Joints="Seated tubes",
                               BranchOverrides=[merged_id, 0.5 * first["Length"], -1000, -1000, -1000, -1000],
                               **RECIPE)
was, now = branch_length(fetch(bare, 1), merged_id), branch_length(fetch(shorter, 1), merged_id)
checks.check(abs(now / was - 0.5) < 0.02 and abs(was / first["Length"] - 1) < 0.02,
             "BranchOverrides halves a measured branch's length: %.3f from %.3f" % (now, was))

# Several trees: the same scan twice, the second moved, and a third of a few points; TreeId tells them apart.
moved = Transform(Input=scan)
moved.Transform.Translate = [20, 0, 0]
parts = [Calculator(Input=scan, ResultArrayName="Tree", Function="1", ResultArrayType="Int"),
         Calculator(Input=moved, ResultArrayName="Tree", Function="2",
                    ResultArrayType="Int"),
         Calculator(Input=MaskPoints(Input=scan, OnRatio=1, MaximumNumberofPoints=40, GenerateVertices=1),
                    ResultArrayName="Tree", Function="3", ResultArrayType="Int")]
multi = TreeFitFilter(Input=AppendDatasets(Input=parts), TreeIdArray="Tree", UpAxis="Y")
with Messages(multi) as messages:
    table = rows(multi)
checks.check([int(r["TreeId"]) for r in table] == [1, 2, 3], "one Trees row per TreeId")
checks.check([r["Status"] == "ok" for r in table] == [True, True, False] and "points" in table[-1]["Status"],
             "the tree of 40 points gets a status saying why, the others are fitted")
checks.check(messages.said("tree 3", kind="warning"), "a warning names the tree that failed")
checks.check(all(abs(r["TotalVolume"] / row.get("TotalVolume", 1) - 1) < 1e-9 for r in table[:2]),
             "each tree as fitted alone")
ids = vtk_to_numpy(fetch(multi, 1).GetCellData().GetArray("BranchId"))
checks.check(len(set(ids.tolist())) == len(ids), "BranchId unique over the trees")

# WoodArray: a label that marks every point wood gives the same fit; one marking none, an error.
labelled = Calculator(Input=scan, ResultArrayName="IsWood", Function="1", ResultArrayType="Int")
wood = TreeFitFilter(Input=labelled, UpAxis="Y", WoodArray="IsWood")
checks.check(abs(rows(wood)[0]["TotalVolume"] / row.get("TotalVolume", 1) - 1) < 1e-9, "all wood: the same fit")
none = TreeFitFilter(Input=Calculator(Input=scan, ResultArrayName="IsWood", Function="0", ResultArrayType="Int"),
                     UpAxis="Y", WoodArray="IsWood")
with Messages(none) as messages:
    checks.check(outputs_empty(none), "no wood: empty outputs")
checks.check(messages.said("wood points", kind="error"), "no wood: an error says so")


# WoodArray named Organ (PlantMorph's label, VirtualScanner's truth, PlantSegmentationFilter's output: 0 wood):
# 0 is wood by default; WoodValues turns any array's meaning.
organ = Calculator(Input=scan, ResultArrayName="Organ", Function="0", ResultArrayType="Int")
checks.check(abs(rows(TreeFitFilter(Input=organ, UpAxis="Y", WoodArray="Organ"))[0]["TotalVolume"]
                 / row.get("TotalVolume", 1) - 1) < 1e-9, "Organ 0 everywhere: all wood, the same fit")
flag = TreeFitFilter(Input=organ, UpAxis="Y", WoodArray="Organ", WoodValues="Nonzero is wood")
with Messages(flag) as messages:
    checks.check(outputs_empty(flag), "Organ 0 read as a wood flag (Nonzero is wood): no wood, empty outputs")
zero = TreeFitFilter(Input=Calculator(Input=scan, ResultArrayName="Leafy", Function="0", ResultArrayType="Int"),
                     UpAxis="Y", WoodArray="Leafy", WoodValues="Zero is wood")
checks.check(abs(rows(zero)[0]["TotalVolume"] / row.get("TotalVolume", 1) - 1) < 1e-9,
             "Zero is wood on any array: all wood, the same fit")


# Bad input: an error naming the problem, every output empty, no crash.
def bad(source, words, **properties):
    fit = TreeFitFilter(Input=source, **properties)
    with Messages(fit) as messages:
        is_empty = outputs_empty(fit)
    checks.check(is_empty, "%s: empty outputs" % words[0])
    checks.check(messages.said(*words, kind="error"), "%s: the error says so (%s)" % (words[0], messages.errors))
    Delete(fit)


noise_ball = PointSource(NumberOfPoints=20000, Radius=1.0, Center=[0, 0, 0])
bad(noise_ball, ["not a tree"])
bad(MaskPoints(Input=Plane(XResolution=150, YResolution=150), OnRatio=1, GenerateVertices=1,
               MaximumNumberofPoints=100000), ["plane"])
bad(MaskPoints(Input=Line(Resolution=5000), OnRatio=1, GenerateVertices=1, MaximumNumberofPoints=100000), ["line"])
bad(MaskPoints(Input=scan, OnRatio=1, MaximumNumberofPoints=30, GenerateVertices=1), ["at least 100"])
nan = ProgrammableFilter(Input=scan, Script="""import vtk
source = inputs[0].VTKObject
target = self.GetOutput()
target.ShallowCopy(source)
points = vtk.vtkPoints()
points.DeepCopy(source.GetPoints())
points.SetPoint(5, float("nan"), 0.0, 0.0)
target.SetPoints(points)""")
bad(nan, ["not a finite number"])
bad(scan, ["TreeIdArray", "NoSuchArray"], TreeIdArray="NoSuchArray")
bad(scan, ["Scale"], Scale=-1.0)
checks.finish()
