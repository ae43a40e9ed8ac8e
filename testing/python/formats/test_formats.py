# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: the MTG and QSM readers and writers as users run them.

A TreeFromSketchSource skeleton saved as MTG (SaveData picks the MTG writer for .mtg) reads back with the same
polylines and radii bit for bit (Connect Branches off) and, connected, feeds TreeFromSketchSource's Strokes input; the
OpenAlea-shaped fixtures (testing/fuzz/corpus/mtg) load with their axes and features, the one without coordinates
with a warning; the skeleton saved as a QSM table reads back as one cylinder per segment, and that table written
again is the same file byte for byte; TreeQSM text reads, tubes are closed; malformed files give an error naming the
line and an empty output; File > Save Data offers both writers.

    pvpython test_formats.py --plugin PlantMorph.so --work DIR
"""
import os

from plantmorph_testing import Checks, Messages, load_plugin, parse_arguments

arguments = parse_arguments([("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()
CORPUS = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "fuzz", "corpus"))
work = arguments.work


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, idx=port)


def polylines(data):
    """Each line cell's points, as arrays."""
    lines = data.GetLines()
    ids = vtk_to_numpy(lines.GetConnectivityArray())
    offsets = vtk_to_numpy(lines.GetOffsetsArray())
    points = vtk_to_numpy(data.GetPoints().GetData())
    return [points[ids[offsets[k]:offsets[k + 1]]] for k in range(len(offsets) - 1)]


# A skeleton saved as MTG and read back.
tree = TreeFromSketchSource(Preset="Custom", Depth=2, ChildCount=3, Leaves=0)
skeleton = fetch(tree, 1)
mtg_file = os.path.join(work, "formats_tree.mtg")
SaveData(mtg_file, proxy=OutputPort(tree, 1))
checks.check(os.path.exists(mtg_file), "SaveData wrote no MTG file")
reader = MTGReader(FileName=mtg_file, ConnectBranches=0)
back = fetch(reader)
original, read = polylines(skeleton), polylines(back)
checks.check(len(read) == len(original), "MTG round trip: %d axes for %d branches" % (len(read), len(original)))
# The writer orders branches parent before child; match them by their first point.
by_start = {tuple(line[0]): line for line in read}
for line in original:
    match = by_start.get(tuple(line[0]))
    checks.check(match is not None and numpy.array_equal(match, line), "a branch's points did not read back exactly")
radius = vtk_to_numpy(skeleton.GetPointData().GetArray("Radius"))
radius_back = vtk_to_numpy(back.GetPointData().GetArray("Radius"))
checks.check(sorted(radius.tolist()) == sorted(radius_back.tolist()), "radii did not read back exactly")
checks.check(back.GetFieldData().GetArray("PlantMorph.ExplicitCoordinates").GetValue(0) == 1, "not explicit")

# The connected reading feeds the Strokes input: one stroke per axis, the tree grows without error.
connected = MTGReader(FileName=os.path.join(CORPUS, "mtg", "implicit.mtg"))
sketched = TreeFromSketchSource(Strokes=connected, Mode="Strokes", StrokesOnly=1, Leaves=0)
with Messages(connected, sketched) as messages:
    strokes = fetch(connected)
    grown = fetch(sketched, 1)
checks.check(not messages.errors, "MTG strokes: errors %s" % messages.errors)
checks.check(any("no entity has XX, YY, ZZ" in w for w in messages.warnings), "no default-layout warning")
checks.check(grown.GetNumberOfCells() == strokes.GetNumberOfCells() == 2,
             "MTG strokes: %d branches from %d axes" % (grown.GetNumberOfCells(), strokes.GetNumberOfCells()))
first_branch = polylines(strokes)[1]
checks.check(numpy.allclose(first_branch[0], [0, 5, 0]), "the branch stroke does not start on its bearer")

# The OpenAlea-shaped fixtures.
explicit = fetch(MTGReader(FileName=os.path.join(CORPUS, "mtg", "explicit.mtg")))
checks.check(explicit.GetNumberOfCells() == 2 and explicit.GetNumberOfPoints() == 7, "explicit fixture shape")
checks.check(vtk_to_numpy(explicit.GetCellData().GetArray("BranchOrder")).tolist() == [0, 1], "branch orders")
checks.check(vtk_to_numpy(explicit.GetCellData().GetArray("ParentId")).tolist() == [-1, 0], "parent ids")
note = explicit.GetPointData().GetAbstractArray("note")
checks.check(note is not None and note.GetValue(0) == "trunk", "the ALPHA feature is not a string array")
checks.check(explicit.GetPointData().GetAbstractArray("Scale2Label").GetValue(3) == "U2", "coarser scale labels")
diam = vtk_to_numpy(explicit.GetPointData().GetArray("diam"))
checks.check(numpy.isnan(diam[-1]) and diam[0] == 2, "missing diam is not NaN")
mono = fetch(MTGReader(FileName=os.path.join(CORPUS, "mtg", "monopodial.mtg")))
checks.check([len(line) for line in polylines(mono)] == [7, 4, 3], "monopodial fixture axes")

# The skeleton saved as a QSM table, read back, and written again byte for byte.
qsm_file, qsm_again = os.path.join(work, "formats_tree.csv"), os.path.join(work, "formats_tree_again.csv")
writer = servermanager.writers.QSMWriter(Input=OutputPort(tree, 1), FileName=qsm_file)
writer.UpdatePipeline()
cylinders = QSMReader(FileName=qsm_file)
table = fetch(cylinders)
segments = sum(len(line) - 1 for line in original)
checks.check(table.GetNumberOfCells() == segments, "QSM: %d cylinders for %d segments" % (table.GetNumberOfCells(),
                                                                                         segments))
again = servermanager.writers.QSMWriter(Input=cylinders, FileName=qsm_again)
again.UpdatePipeline()
with open(qsm_file) as a, open(qsm_again) as b:
    checks.check(a.read() == b.read(), "the QSM table written again differs")
tubes = fetch(QSMReader(FileName=qsm_file, Tubes=1, Sides=6))
checks.check(tubes.GetNumberOfPolys() == segments * 8, "tubes: %d faces" % tubes.GetNumberOfPolys())
treeqsm = fetch(QSMReader(FileName=os.path.join(CORPUS, "qsm", "treeqsm.txt")))
checks.check(treeqsm.GetNumberOfCells() == 3 and treeqsm.GetCellData().GetArray("branch_order") is not None,
             "TreeQSM text")

# Malformed files: an error naming the line, an empty output.
for name, text, words in [
        ("bad.mtg", open(os.path.join(CORPUS, "mtg", "explicit.mtg")).read().replace("^<E4", "^<X4"),
         "line 34: symbol 'X' is not declared"),
        ("bad.csv", "ID,parentID,startX,startY,startZ,endX,endY,endZ,radius\n1,0,0,0,0,0,0,1,oops\n",
         "line 2: column 9 is not a number")]:
    path = os.path.join(work, "formats_" + name)
    with open(path, "w") as f:
        f.write(text)
    bad = (MTGReader if name.endswith(".mtg") else QSMReader)(FileName=path)
    with Messages(bad) as messages:
        output = fetch(bad)
    checks.check(any(words in e and path in e for e in messages.errors), "%s: errors %s" % (name, messages.errors))
    checks.check(output.GetNumberOfPoints() == 0, "%s: output not empty" % name)

# File > Save Data offers both writers for a polydata.
factory = servermanager.vtkSMProxyManager.GetProxyManager().GetWriterFactory()
types = factory.GetSupportedFileTypes(tree.SMProxy, 1)
checks.check("MTG" in types and "QSM" in types, "Save Data does not offer the writers: %s" % types)
checks.finish()
