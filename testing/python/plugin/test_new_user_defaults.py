# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: what a new user trips over, each check one that failed before its fix.

1. A source's optional inputs stay empty when another source is active (paraview.simple connects the active source
   to a new proxy's input property of port_index 0), and setting one to None disconnects it.
2. (and 9, in part) A property a named preset overrides is reported; what the preset chose is in the field data: a warning naming it and Custom, the same in a fresh pvpython
   loading the saved state (whose outputs are the same).
3. LeafOutlineSource's Length is the blade's length from base to apex for every deformed-rectangle preset.
4. Trajectory Comparison's default columns chain: WiltingSimulator's Trajectory table with itself and with the tip
   CSV, the tip CSV with itself (measured_* against paper_sim_*, paper 001's 1.76 ... 2.92 cm).
10. Bad input is an error naming the property or input, and empty output: TimeStep longer than Duration, a
   one-sample trajectory, a table whose header names no x, y, z read as points; the tip CSV's points are its
   measured_x, measured_y, measured_z.
11. An empty input gives a warning naming it, and empty output: Venation, Adaptive Loop, Curl, Wilting, Cloud and
   Trajectory Comparison.

    pvpython test_new_user_defaults.py --plugin PlantMorph.so --work DIR
"""
import json
import math
import os

from plantmorph_testing import Checks, Messages, fingerprint, load_plugin, parse_arguments, reload_in_fresh_pvpython

arguments = parse_arguments([("--load", dict(default=None)), ("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager

load_plugin(arguments.plugin, globals())
checks = Checks()
root = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
tip_csv = os.path.join(root, "data", "cucumber-wilting-tip.csv")
state = os.path.join(arguments.work, "new_user_defaults.pvsm")
expected_file = os.path.join(arguments.work, "new_user_defaults_expected.json")


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, idx=port)


def size(data):
    return data.GetNumberOfRows() if data.IsA("vtkTable") else data.GetNumberOfPoints()


def value(table, name, row=0):
    """A table cell, or None when the column or row is missing (so a failing check reports instead of raising)."""
    array = table.GetRowData().GetArray(name)
    return array.GetValue(row) if array is not None and row < array.GetNumberOfTuples() else None


def connections(proxy, port):
    return proxy.GetClientSideObject().GetNumberOfInputConnections(port)


if arguments.load is not None:
    # 2, state path: the saved pipeline loads in a fresh pvpython, the same warning, the same outputs.
    LoadState(arguments.load)
    with open(expected_file) as f:
        expected = json.load(f)
    tree = FindSource("DepthTree")
    leaf = FindSource("LobedLeaf")
    with Messages(tree, leaf) as messages:
        tree.UpdatePipeline()
        leaf.UpdatePipeline()
    checks.check(messages.said("Depth = 2", "Custom", kind="warning"), "state: the tree's ignored Depth is reported")
    checks.check(messages.said("Lobes", "SpaceCurvePreset", kind="warning"), "state: the ignored Lobes is reported")
    checks.check(fingerprint(fetch(tree)) == expected["tree"], "state: the same tree")
    checks.check(fingerprint(fetch(leaf)) == expected["leaf"], "state: the same leaf")
    checks.check(connections(tree, 0) == 0 and connections(leaf, 0) == 0, "state: the optional inputs still empty")
    checks.finish()
    raise SystemExit(0)

# 1. Optional inputs are not the active source.
strokes_csv = os.path.join(arguments.work, "new_user_strokes.csv")
with open(strokes_csv, "w") as f:
    f.write("stroke_id,x,y\n0,0,0\n0,0,5\n0,0,10\n1,0,6\n1,3,9\n")
sphere = Sphere()
SetActiveSource(sphere)
tree = TreeFromSketchSource(Mode="Strokes", StrokeFile=strokes_csv)
checks.check(tree.Strokes is None and tree.Leaf is None and tree.MergeTree is None,
             "tree made after a Sphere: Strokes, Leaf and MergeTree empty (%s)" % (tree.Strokes,))
checks.check(all(connections(tree, port) == 0 for port in (0, 1, 2)), "tree: no input connected on the server")
with Messages(tree) as messages:
    branches = fetch(tree)
checks.check(not messages.errors and branches.GetNumberOfPoints() > 0,
             "tree from the StrokeFile, not from the Sphere: %d points, %s" % (branches.GetNumberOfPoints(),
                                                                               messages.errors[:1]))
tree.Strokes = sphere
checks.check(connections(tree, 0) == 1, "Strokes set by the user: connected")
tree.Strokes = None
checks.check(connections(tree, 0) == 0, "Strokes = None: disconnected on the server too")
SetActiveSource(sphere)
leaf = LeafOutlineSource(Model="B-spline")
checks.check(leaf.ControlPoints is None and connections(leaf, 0) == 0,
             "leaf made after a Sphere: ControlPoints empty (%s)" % (leaf.ControlPoints,))
checks.check(leaf.SMProxy.GetXMLLabel() == "Leaf Outline Source", "6: spaced label '%s'" % leaf.SMProxy.GetXMLLabel())
Delete(tree)
Delete(leaf)

# 2. A property a preset overrides is reported, with the property and the way out (Custom).
tree = TreeFromSketchSource(registrationName="DepthTree", Depth=2)
with Messages(tree) as messages:
    tree.UpdatePipeline()
checks.check(messages.said("Depth = 2", "Custom", kind="warning"), "Depth=2 under a preset: a warning %s" %
             messages.warnings)
checks.check(not messages.said("Length =", kind="warning"), "Length (unchanged) is not named")
custom = TreeFromSketchSource(Depth=2, Preset="Custom")
with Messages(custom) as messages:
    custom_tree = fetch(custom, 1)
checks.check(not messages.warnings, "Custom: no warning")
preset_tree = fetch(tree, 1)
checks.check(custom_tree.GetNumberOfCells() < preset_tree.GetNumberOfCells(),
             "Custom uses Depth 2: %d < %d skeleton branches" % (custom_tree.GetNumberOfCells(),
                                                                  preset_tree.GetNumberOfCells()))
Delete(custom)
leaf = LeafOutlineSource(registrationName="LobedLeaf", Model="Space curve", Lobes=3)
with Messages(leaf) as messages:
    leaf.UpdatePipeline()
checks.check(messages.said("Lobes", "SpaceCurvePreset", "Custom", kind="warning"), "Lobes=3 under a space-curve "
             "preset: a warning %s" % messages.warnings)
ginkgo = LeafOutlineSource(Preset="Ginkgo", Length=5)
with Messages(ginkgo) as messages:
    ginkgo.UpdatePipeline()
checks.check(not messages.warnings, "a preset's own properties (Length) changed: no warning %s" % messages.warnings)
Delete(ginkgo)
SetActiveSource(None)

# 3. Length is the blade's length, base to apex (the Outline port's midvein: its first and last points), for every
# deformed-rectangle preset, Custom included; the rectangle's a_x, b_y are in the field data.
sizer = LeafOutlineSource(Length=5.0, Resolution=30)
presets = sizer.GetProperty("Preset").Available
for preset in presets:
    sizer.Preset = preset
    if preset == "Custom":
        sizer.Width = 2.0
        sizer.Terms = [1, 1, 0.3, 2, 1, 0, 0]
    outline = fetch(sizer, 1)
    lines = outline.GetLines()
    ids = []
    if lines is not None and lines.GetNumberOfCells() == 3:
        lines.InitTraversal()
        from vtkmodules.vtkCommonCore import vtkIdList
        cell = vtkIdList()
        for _ in range(3):
            lines.GetNextCell(cell)
        ids = [cell.GetId(0), cell.GetId(cell.GetNumberOfIds() - 1)]
    length = math.dist(outline.GetPoint(ids[0]), outline.GetPoint(ids[1])) if ids else None
    checks.check(length is not None and abs(length - 5.0) < 1e-9,
                 "3: %s with Length 5 is %s long from base to apex" % (preset, length))
rectangle = fetch(sizer).GetFieldData()
checks.check(rectangle.GetArray("PlantMorph.RectangleWidth") is not None and
             rectangle.GetArray("PlantMorph.RectangleHeight") is not None, "3: a_x and b_y reachable by name")
Delete(sizer)

# 4. The trajectory filters chain with their defaults.
tip = LeafCloudReader(FileName=tip_csv)
paper = TrajectoryComparisonFilter(Input=OutputPort(tip, 1), Simulated=OutputPort(tip, 1))
with Messages(paper) as messages:
    samples = fetch(paper)
distances = [value(samples, "ClosestDistance", i) for i in range(samples.GetNumberOfRows())]
checks.check(not messages.errors and [round(d, 2) for d in distances] == [1.76, 0.69, 2.52, 1.89, 2.92],
             "tip CSV with itself, no column typed: paper 001's distances %s %s" % (distances, messages.errors))
checks.check(value(samples, "MeasuredX") == 0.46, "measured_x read as the measured x")
blade = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", BladeLength=20.1, BladeWidth=22.1,
                          Resolution=12)
wilt = WiltingSimulator(Input=blade, Duration=0.5, Resolution=14, Gravity=500)
with Messages(wilt) as messages:
    wilt.UpdatePipeline()
checks.check(messages.said("Gravity", "Preset", "Custom", kind="warning") and
             not messages.said("Duration", kind="warning"),
             "2: Gravity under the Cucumber preset: a warning naming it (not Duration) %s" % messages.warnings)
# 2, the other way: a proxy left at its defaults names no property as changed (the class's own defaults equal the
# XML's; WiltingSimulator's materials did not, and every default wilting run warned about them).
for name, make in (("WiltingSimulator", lambda: WiltingSimulator(Input=blade, Duration=0.5, Resolution=14)),
                   ("VenationFilter", lambda: VenationFilter(Input=blade)),
                   ("LeafOutlineSource", lambda: LeafOutlineSource()),
                   ("TreeFromSketchSource", lambda: TreeFromSketchSource())):
    proxy = make()
    with Messages(proxy) as messages:
        proxy.UpdatePipeline()
    checks.check(not messages.said("not used", kind="warning"),
                 "2: %s at its defaults names no ignored property %s" % (name, messages.warnings))
    Delete(proxy)
veins = VenationFilter(Input=blade, PrimaryCount=5)
with Messages(veins) as messages:
    veins.UpdatePipeline()
checks.check(messages.said("PrimaryCount", "Custom", kind="warning"), "2: PrimaryCount under a venation preset: "
             "a warning %s" % messages.warnings)


def chosen(proxy, name):
    array = fetch(proxy).GetFieldData().GetArray("PlantMorph.Venation." + name)
    return array.GetValue(0) if array is not None else None


# 9 (in part): what the preset chose is in the veins' field data, for the Information panel.
checks.check(chosen(veins, "DivergenceAngleApex") == 70.0 and chosen(veins, "PrimaryCount") == 3,
             "9: the paper mulberry preset's own values in the field data (%s, %s)" % (
                 chosen(veins, "DivergenceAngleApex"), chosen(veins, "PrimaryCount")))
veins.Preset = "Custom"
checks.check(chosen(veins, "PrimaryCount") == 5, "9: Custom: the property's value in the field data")
Delete(veins)
itself = TrajectoryComparisonFilter(Input=OutputPort(wilt, 2), Simulated=OutputPort(wilt, 2))
with Messages(itself) as messages:
    summary = fetch(itself, 1)
trajectory = fetch(wilt, 2)
checks.check(trajectory.GetColumnByName("TipX") is not None, "WiltingSimulator's Trajectory is a table with TipX")
checks.check(not messages.errors and summary.GetNumberOfRows() == 1 and value(summary, "ClosestMaxDistance") == 0.0,
             "the simulated trajectory with itself, no column typed: distance 0 (%s)" % messages.errors[:1])
against = TrajectoryComparisonFilter(Input=OutputPort(tip, 1), Simulated=OutputPort(wilt, 2))
with Messages(against) as messages:
    samples = fetch(against)
checks.check(not messages.errors and samples.GetNumberOfRows() == 5 and
             samples.GetRowData().GetArray("ClosestTime") is not None,
             "the tip CSV against the simulation, no column typed: 5 rows with the simulated Time (%s)" %
             messages.errors[:1])
Delete(against)
Delete(itself)

# 10. Bad input: an error naming the property or input, and empty output.
wilt.TimeStep = 0.75
with Messages(wilt) as messages:
    leaf_out = fetch(wilt)
    table_out = fetch(wilt, 2)
checks.check(messages.said("TimeStep = 0.75", "Duration = 0.5", kind="error"),
             "TimeStep longer than Duration: an error naming both %s" % messages.errors)
checks.check(leaf_out.GetNumberOfPoints() == 0 and table_out.GetNumberOfRows() == 0, "... and empty outputs")
Delete(wilt)
# A surface without LeafUV and Region, and a non-manifold one (three triangles on one edge): what is assumed is said.
# Three quads on one edge (x = z = 0, y in [0, 1]), their coincident points merged.
wings = [Plane(Origin=[0, 0, 0], Point1=list(p1), Point2=[0, 4, 0]) for p1 in ((3, 0, 0), (-3, 0, 0), (0, 0, 3))]
fin = Clean(Input=AppendGeometry(Input=wings))
bare = WiltingSimulator(Input=fin, Duration=0.1, Resolution=14)
with Messages(bare) as messages:
    bare.UpdatePipeline()
checks.check(messages.said("no LeafUV", "lowest point", kind="warning") and messages.said("no Region", kind="warning"),
             "10: Wilting without LeafUV and Region says what it assumes %s" % messages.warnings)
checks.check(messages.said("not a manifold surface", "1 edge(s)", kind="warning"),
             "10: Wilting on a non-manifold surface says so %s" % messages.warnings)
Delete(bare)
for proxy in [fin, fin.Input] + wings:
    Delete(proxy)
one_csv = os.path.join(arguments.work, "new_user_one_sample.csv")
with open(one_csv, "w") as f:
    f.write("x,y,z\n1,2,3\n")
one = LeafCloudReader(FileName=one_csv)
# Columns named, so the check holds without the default-column recognition of item 4.
short = TrajectoryComparisonFilter(Input=OutputPort(one, 1), Simulated=OutputPort(tip, 1),
                                   MeasuredColumns=["x", "y", "z"],
                                   SimulatedColumns=["paper_sim_x", "paper_sim_y", "paper_sim_z"])
with Messages(short) as messages:
    out = fetch(short)
    out_summary = fetch(short, 1)
checks.check(messages.said("1 sample", "at least 2", kind="error"), "one sample: an error %s" % messages.errors)
checks.check(out.GetNumberOfRows() == 0 and out_summary.GetNumberOfRows() == 0,
             "one sample: empty outputs, not a NaN angle")
Delete(short)
points = fetch(tip)
first = points.GetPoint(0) if points.GetNumberOfPoints() else None
checks.check(points.GetNumberOfPoints() == 5 and first == (0.46, 19.58, -2.13),
             "the tip CSV's points are measured_x/y/z, not (sample, measured_x, measured_y): %s" % (first,))
checks.check(points.GetPointData().GetArray("paper_sim_x") is not None, "the other columns kept as point arrays")
unnamed_csv = os.path.join(arguments.work, "new_user_unnamed.csv")
with open(unnamed_csv, "w") as f:
    f.write("a,b,c\n1,2,3\n4,5,6\n")
unnamed = LeafCloudReader(FileName=unnamed_csv)
with Messages(unnamed) as messages:
    out = fetch(unnamed)
    out_table = fetch(unnamed, 1)
checks.check(messages.said("'a', 'b', 'c'", "x, y, z", kind="error") and out.GetNumberOfPoints() == 0,
             "a header naming no x, y, z: refused with an error %s" % messages.errors)
checks.check(out_table.GetNumberOfRows() == 2, "... the Table port still has the file")

# 11. Empty inputs: a warning naming the input, and empty output.
# An empty blade (a LeafOutlineSource refusing Resolution 1) and an empty table (Leaf Cloud Reader's Table port for a
# file that does not exist): their own errors are not the filters' messages.
empty = LeafOutlineSource(Resolution=1)
missing = LeafCloudReader(FileName=os.path.join(arguments.work, "no-such-file.csv"))
empty_table = OutputPort(missing, 1)
checks.check(size(fetch(empty)) == 0 and size(fetch(missing, 1)) == 0, "the empty inputs are empty")
cases = [
    ("Venation Filter", VenationFilter(Input=empty)),
    ("Adaptive Loop Filter", AdaptiveLoopFilter(Input=empty)),
    ("Leaf Curl Filter", LeafCurlFilter(Input=empty)),
    ("Wilting Simulator", WiltingSimulator(Input=empty)),
    ("Cloud Comparison Filter", CloudComparisonFilter(Input=empty, Reference=sphere)),
    ("Trajectory Comparison Filter", TrajectoryComparisonFilter(Input=empty_table, Simulated=empty_table)),
]
for name, proxy in cases:
    with Messages(proxy) as messages:
        out = fetch(proxy)
    checks.check(messages.said("Input", "empty", kind="warning") and not messages.errors,
                 "%s on an empty input: a warning naming it %s %s" % (name, messages.warnings, messages.errors))
    checks.check(size(out) == 0, "%s on an empty input: empty output (%d)" % (name, size(out)))

# 2, the state round trip: the tree and the lobed leaf, saved and loaded in a fresh pvpython.
for proxy in [p for _, p in cases] + [empty, missing, unnamed, one, paper, tip, blade, sphere]:
    Delete(proxy)
expected = {"tree": fingerprint(fetch(tree)), "leaf": fingerprint(fetch(leaf))}
checks.check(reload_in_fresh_pvpython(state, expected, expected_file, arguments, __file__) == 0,
             "the state file loads in a fresh pvpython with the same warnings and outputs")
checks.finish()
