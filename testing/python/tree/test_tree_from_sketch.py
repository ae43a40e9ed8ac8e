# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: TreeFromSketchSource as users run it. The proxy is in the PlantMorph menu with its documented defaults;
Table 1's presets give the closed-form branch counts with the contract arrays; strokes drawn as Poly Line sources
and appended in order become lifted branches that project back onto them; a CSV stroke file gives the same tree;
a LeafOutlineSource blade is instanced at every leaf; leaf sizes taper and spread as set, the same for the same
Seed; bad values give empty outputs; a second tree's skeleton on the MergeTree input is merged with ids after this
tree's own (a surface there is refused); and a tree with deleted branches, overrides, leaf sizes and a merged tree,
saved as a state file, loads in a fresh pvpython with the same properties, BranchIds and bit-identical outputs.

    pvpython test_tree_from_sketch.py --plugin PlantMorph.so --work DIR
"""
import json
import os
import sys

from plantmorph_testing import (check_same_properties, Checks, fingerprint, load_plugin, loaded_state, parse_arguments,
                                reload_in_fresh_pvpython)

arguments = parse_arguments([("--load", dict(default=None)), ("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
state = os.path.join(arguments.work, "tree_from_sketch.pvsm")
expected_file = os.path.join(arguments.work, "tree_from_sketch_state_expected.json")
EDIT_PROPERTIES = ("Preset", "Depth", "DeletedBranches", "BranchOverrides", "Seed", "LeafType", "MergeParentBranch",
                   "MergeU", "MergeAngle", "MergeRotation", "MergeScale", "LeafTipScale", "LeafScaleSpread")


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, None, None, port)




def describe(tree):
    return {"properties": {name: list(tree.GetPropertyValue(name)) if hasattr(tree.GetPropertyValue(name), "__len__")
                           else tree.GetPropertyValue(name) for name in EDIT_PROPERTIES},
            "fingerprints": [fingerprint(fetch(tree, port)) for port in range(3)],
            "cells": fetch(tree, 0).GetNumberOfCells(),
            "branch_ids": sorted(int(i) for i in vtk_to_numpy(fetch(tree, 1).GetCellData().GetArray("BranchId")))}


checks = Checks()

if arguments.load is not None:
    tree, expected = loaded_state(checks, arguments, expected_file, "EditedTree", "source")
    actual = json.loads(json.dumps(describe(tree)))
    check_same_properties(checks, actual, expected)
    checks.check(actual["cells"] == expected["cells"] and actual["cells"] > 0, "same number of cells")
    checks.check(actual["branch_ids"] == expected["branch_ids"], "the same BranchIds (merged ones too) after loading")
    checks.check(actual["fingerprints"] == expected["fingerprints"], "all three outputs bit-identical after loading")
    checks.finish()
    sys.exit(0)

# The proxy: pvpython name, menu, label, defaults.
SetActiveSource(None)
tree = TreeFromSketchSource(registrationName="Tree")
hints = tree.SMProxy.GetHints()
menu = hints.FindNestedElementByName("ShowInMenu") if hints else None
checks.check(menu is not None and menu.GetAttribute("category") == "PlantMorph", "in the PlantMorph menu")
checks.check(tree.SMProxy.GetXMLLabel() == "Tree From Sketch Source", "label 'Tree From Sketch Source'")
checks.check((tree.Mode, tree.Preset, tree.SegmentsPerBranch, tree.Sides) ==
             ("Template", "Table 1 left: monopodial 3/8", 4, 6), "defaults: %r" %
             ((tree.Mode, tree.Preset, tree.SegmentsPerBranch, tree.Sides),))

# Table 1: closed-form branch counts, arrays on every output.
for preset, count in (("Table 1 left: monopodial 3/8", 4681), ("Table 1 middle: sympodial 1/3", 1093),
                      ("Table 1 right: monopodial 5/8", 11111)):
    tree.Preset = preset
    branches, skeleton = fetch(tree, 0), fetch(tree, 1)
    ids = vtk_to_numpy(branches.GetCellData().GetArray("BranchId"))
    checks.check(len(numpy.unique(ids)) == count, "%s: %d branches, got %d" % (preset, count, len(numpy.unique(ids))))
    checks.check(skeleton.GetNumberOfLines() == count, "%s: one skeleton polyline a branch" % preset)
    checks.check(branches.GetPointData().GetTCoords() is not None and
                 branches.GetPointData().GetTCoords().GetName() == "TCoords", "%s: active TCoords" % preset)
    depth = vtk_to_numpy(branches.GetCellData().GetArray("Depth"))
    checks.check(depth.min() == 0 and depth.max() == (6 if "sympodial" in preset else 4), "%s: Depth 0..depth" % preset)
    checks.check(skeleton.GetPointData().GetArray("Radius") is not None, "%s: skeleton Radius" % preset)
    model = branches.GetFieldData().GetAbstractArray("PlantMorph.Model")
    checks.check(model is not None and model.GetValue(0) == "TreeFromSketch", "%s: field data" % preset)
Delete(tree)

# Strokes: three Poly Line sources appended in drawing order.
lines = [[0, 0, 0, 0.2, 3, 0, -0.1, 6, 0, 0.1, 9, 0, 0, 12, 0],
         [0.3, 6, 0, 1.5, 7.5, 0, 3, 8.2, 0, 4, 10, 0],
         [-0.2, 4, 0, -1, 5, 0, -2.5, 5.5, 0, -3.5, 7, 0, -4, 8, 0]]
polylines = [PolyLineSource(registrationName="Stroke%d" % k, Points=points) for k, points in enumerate(lines)]
strokes = AppendGeometry(registrationName="Strokes", Input=polylines)
SetActiveSource(None)
sketched = TreeFromSketchSource(registrationName="Sketched", Strokes=strokes, Mode="Strokes", StrokesOnly=1,
                                SegmentsPerBranch=12)
skeleton = fetch(sketched, 1)
checks.check(skeleton.GetNumberOfLines() == 3, "three strokes, three branches: %d" % skeleton.GetNumberOfLines())
points = vtk_to_numpy(skeleton.GetPoints().GetData())
offsets = vtk_to_numpy(skeleton.GetLines().GetOffsetsArray())
connectivity = vtk_to_numpy(skeleton.GetLines().GetConnectivityArray())
for k in range(3):
    last = points[connectivity[offsets[k + 1] - 1]]
    checks.check(numpy.allclose(last[:2], lines[k][-3:-1], atol=1e-6),
                 "branch %d ends above its stroke's end: %r" % (k, last))
checks.check(numpy.ptp(points[:, 2]) > 0.1, "strokes 1 and 2 are lifted out of the image plane")
csv = os.path.join(arguments.work, "tree_strokes.csv")
with open(csv, "w") as f:
    f.write("stroke_id,x,y\n")
    for k, line in enumerate(lines):
        for i in range(0, len(line), 3):
            f.write("%d,%r,%r\n" % (k, line[i], line[i + 1]))
SetActiveSource(None)
from_file = TreeFromSketchSource(registrationName="FromFile", Mode="Strokes", StrokesOnly=1, SegmentsPerBranch=12,
                                 StrokeFile=csv)
file_points = vtk_to_numpy(fetch(from_file, 1).GetPoints().GetData())
checks.check(file_points.shape == points.shape and numpy.allclose(file_points, points, atol=1e-5),
             "the CSV stroke file gives the same skeleton as the drawn strokes (float Poly Line points)")

# Leaf instances of a LeafOutlineSource blade.
SetActiveSource(None)
blade = LeafOutlineSource(registrationName="Blade", Preset="Ginkgo", Length=5.0, Resolution=20)
SetActiveSource(None)
leafy = TreeFromSketchSource(registrationName="Leafy", Leaf=blade, Preset="Table 1 middle: sympodial 1/3",
                             LeafCount=2)
leaves = fetch(leafy, 2)
blade_data = fetch(blade, 0)
checks.check(leaves.GetNumberOfPolys() == 729 * 2 * blade_data.GetNumberOfPolys(),
             "one blade per leaf: %d polys" % leaves.GetNumberOfPolys())



def polygon_area(polydata):
    """The summed area of the polygons (triangulated by their fan; the leaves here are triangles)."""
    from vtkmodules.vtkCommonCore import vtkIdList
    points = vtk_to_numpy(polydata.GetPoints().GetData()).astype(float)
    ids, total = vtkIdList(), 0.0
    polys = polydata.GetPolys()
    polys.InitTraversal()
    while polys.GetNextCell(ids):
        corner = [points[ids.GetId(k)] for k in range(ids.GetNumberOfIds())]
        for k in range(1, len(corner) - 1):
            total += 0.5 * numpy.linalg.norm(numpy.cross(corner[k] - corner[0], corner[k + 1] - corner[0]))
    return total


# A Leaf input of triangle strips (as the Triangle Strips and Tube filters give) is instanced whole.
SetActiveSource(None)
strips = TriangleStrips(registrationName="BladeStrips", Input=blade)
strips_data = fetch(strips, 0)
SetActiveSource(None)
leafy_strips = TreeFromSketchSource(registrationName="LeafyStrips", Leaf=strips,
                                    Preset="Table 1 middle: sympodial 1/3", LeafCount=2)
strip_leaves = fetch(leafy_strips, 2)
area, strip_area = polygon_area(leaves), polygon_area(strip_leaves)
checks.check(strips_data.GetNumberOfStrips() > 0 and strips_data.GetNumberOfPolys() == 0
             and abs(strip_area - area) <= 1e-6 * area,
             "a blade of %d triangle strips gives the leaves' area of its triangles: %.6g against %.6g"
             % (strips_data.GetNumberOfStrips(), strip_area, area))
Delete(leafy_strips)
Delete(strips)

# Leaf sizes: quads (no Leaf input) whose side is each leaf's length, the taper's exactly without a spread; with a
# spread of 0.2 the logs of the lengths over the taper's spread by about 0.2, the same for the same Seed.
SetActiveSource(None)
sized = TreeFromSketchSource(registrationName="Sized", Preset="Table 1 middle: sympodial 1/3", LeafCount=4,
                             LeafScale=0.8, LeafTipScale=0.5)
quads = fetch(sized, 2)
corners = vtk_to_numpy(quads.GetPoints().GetData()).reshape(-1, 4, 3)
sides = numpy.linalg.norm(corners[:, 1] - corners[:, 0], axis=1)
leaf_ids = vtk_to_numpy(quads.GetCellData().GetArray("LeafId"))
taper = 0.8 * (1 + ((leaf_ids % 4 + 1) / 4.0) * (0.5 - 1))
checks.check(len(sides) == 729 * 4 and numpy.allclose(sides, taper, rtol=1e-6, atol=0),
             "LeafTipScale 0.5: leaf j of 4 is 0.8 (1 - j / 8) long, %.4g to %.4g" % (sides.min(), sides.max()))
sized.LeafScaleSpread, sized.Seed = 0.2, 11
corners = vtk_to_numpy(fetch(sized, 2).GetPoints().GetData()).reshape(-1, 4, 3)
spread = numpy.log(numpy.linalg.norm(corners[:, 1] - corners[:, 0], axis=1) / taper)
sized_print = fingerprint(fetch(sized, 2))
checks.check(abs(spread.std(ddof=1) - 0.2) < 4 * 0.2 / numpy.sqrt(2 * len(spread)) and abs(spread.mean()) <
             4 * 0.2 / numpy.sqrt(len(spread)), "LeafScaleSpread 0.2: the log lengths' mean %.4f, deviation %.4f"
             % (spread.mean(), spread.std(ddof=1)))
sized.Seed = 12
other_print = fingerprint(fetch(sized, 2))
sized.Seed = 11
checks.check(fingerprint(fetch(sized, 2)) == sized_print and other_print != sized_print,
             "the same Seed gives the same leaf sizes, another Seed others")
Delete(sized)

# Bad values: empty outputs.
SetActiveSource(None)
bad = TreeFromSketchSource(registrationName="Bad", Preset="Custom", Length=-1.0)
checks.check(fetch(bad, 0).GetNumberOfPoints() == 0 and fetch(bad, 2).GetNumberOfPoints() == 0,
             "Length = -1 gives empty outputs")
Delete(bad)

# Merging a second tree: another source's Skeleton port on the MergeTree input.
SetActiveSource(None)
second = TreeFromSketchSource(registrationName="SecondTree", Preset="Custom", Depth=2, ChildCount=3)
second_skeleton = fetch(second, 1)
checks.check(second_skeleton.GetNumberOfLines() == 13, "second tree: 1 + 3 + 9 branches")
SetActiveSource(None)
host = TreeFromSketchSource(registrationName="Host", Preset="Custom", Depth=1)
merged = TreeFromSketchSource(registrationName="Merged", Preset="Custom", Depth=1,
                              MergeTree=OutputPort(second, 1), MergeParentBranch=-1, MergeOffset=[6, 0, 0],
                              MergeAngle=0.0)
merged_skeleton, host_skeleton = fetch(merged, 1), fetch(host, 1)
checks.check(merged_skeleton.GetNumberOfLines() == host_skeleton.GetNumberOfLines() + 13,
             "merged: branch count is the sum (%d)" % merged_skeleton.GetNumberOfLines())
base = merged_skeleton.GetFieldData().GetArray("PlantMorph.MergeIdBase").GetValue(0)
merged_ids = vtk_to_numpy(merged_skeleton.GetCellData().GetArray("BranchId"))
checks.check(base == 9 and sorted(merged_ids[9:]) == [9 + i for i in range(13)],
             "merged ids are 9 + the second tree's ids: base %r" % base)
moved = vtk_to_numpy(merged_skeleton.GetPoints().GetData())[host_skeleton.GetNumberOfPoints():]
checks.check(numpy.allclose(moved, vtk_to_numpy(second_skeleton.GetPoints().GetData()) + [6, 0, 0], atol=1e-12),
             "a second trunk at offset (6, 0, 0): the second tree's skeleton moved by it")
SetActiveSource(None)
not_a_tree = TreeFromSketchSource(registrationName="NotATree", MergeTree=OutputPort(second, 0))
checks.check(fetch(not_a_tree, 0).GetNumberOfPoints() == 0,
             "the Branches surface (no lines) on MergeTree is refused: empty outputs")
Delete(not_a_tree)

# State file: deletions and overrides (of template and merged branches) survive a save and a load in a fresh
# pvpython, with the same BranchIds.
SetActiveSource(None)
edited = TreeFromSketchSource(registrationName="EditedTree", Preset="Table 1 middle: sympodial 1/3", Depth=4,
                              DeletedBranches=[2, 700, 1093 + 1], Seed=5, LeafType="Willow", LeafTipScale=0.6,
                              LeafScaleSpread=0.2,
                              MergeTree=OutputPort(second, 1), MergeParentBranch=1, MergeU=0.6, MergeAngle=50.0,
                              MergeRotation=30.0, MergeScale=0.3,
                              BranchOverrides=[1, 3.5, -1000, -1000, 70.0, -1000,
                                               364, -1000, 0.2, 0.5, -1000, 100.0,
                                               1093, 2.0, 0.1, -1000, -1000, 200.0,
                                               1093 + 5, -1000, 0.05, -1000, -1000, -1000])
before = describe(edited)
checks.check(1093 in before["branch_ids"] and 1093 + 1 not in before["branch_ids"] and
             1093 + 5 in before["branch_ids"], "merged ids 1093.. present, the deleted one gone")
checks.check(before["cells"] > 0, "edited tree is not empty")
plain = describe(TreeFromSketchSource(registrationName="Plain", Preset="Table 1 middle: sympodial 1/3"))
checks.check(plain["fingerprints"][0] != before["fingerprints"][0], "the edits change the tree")
returncode = reload_in_fresh_pvpython(state, before, expected_file, arguments, __file__)
checks.check(returncode == 0, "the fresh pvpython found the same tree after loading the state")
checks.finish()
