# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: a scan of a tree with leaves is labelled training and test data. TreeFromSketchSource's wood and leaves,
appended, scanned by VirtualScanner from two positions: every point carries `LeafId` and `Organ`, each its hit
cell's; wood points have Organ 0 and LeafId -1, leaf points Organ 1 and the LeafId of the leaf they hit (one of the
tree's own, each leaf's points on that leaf's quad); and the same seed gives the same labels.

    pvpython test_scan_truth.py --plugin PlantMorph.so --work DIR
"""
import math

from plantmorph_testing import Checks, load_plugin, parse_arguments

arguments = parse_arguments([("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()

tree = TreeFromSketchSource(Preset=0, TreeType=0, Depth=2, ChildCount=4, Ratio=0.7, Length=6.0, Radius=0.2,
                            LeafCount=3, LeafScale=1.0)
plant = AppendGeometry(Input=[OutputPort(tree, 0), OutputPort(tree, 2)])
plant.UpdatePipeline()
surface = servermanager.Fetch(plant)
leaves = servermanager.Fetch(tree, idx=2)
leaf_count = leaves.GetNumberOfCells()  # one quad per leaf
checks.check(leaf_count == 16 * 3, "the tree has %d leaves" % leaf_count)
cell_leaf = vtk_to_numpy(surface.GetCellData().GetArray("LeafId"))
cell_organ = vtk_to_numpy(surface.GetCellData().GetArray("Organ"))
b = surface.GetBounds()
centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
positions = []
for angle in (0.0, math.pi):
    positions += [centre[0] + 2 * size * math.cos(angle), centre[1], centre[2] + 2 * size * math.sin(angle)]
scan = VirtualScanner(Input=plant, Positions=positions, LookAt=centre, Up=[0, 1, 0], HorizontalFieldOfView=50,
                      VerticalFieldOfView=50, AngularStep=0.1, RangeNoise=0.002, Seed=3)
scan.UpdatePipeline()
cloud = servermanager.Fetch(scan)
n = cloud.GetNumberOfPoints()
checks.check(n > 5000, "the scan has %d points" % n)
pd = cloud.GetPointData()
leaf_id = vtk_to_numpy(pd.GetArray("LeafId")) if pd.GetArray("LeafId") else None
organ = vtk_to_numpy(pd.GetArray("Organ")) if pd.GetArray("Organ") else None
checks.check(leaf_id is not None and organ is not None, "every point carries LeafId and Organ")
if leaf_id is not None and organ is not None:
    hit = vtk_to_numpy(pd.GetArray("HitCellId"))
    checks.check(numpy.array_equal(leaf_id, cell_leaf[hit]), "each point's LeafId is its hit cell's")
    checks.check(numpy.array_equal(organ, cell_organ[hit]), "each point's Organ is its hit cell's")
    checks.check(set(organ.tolist()) == {0, 1}, "wood and leaf points both seen: %s" % sorted(set(organ.tolist())))
    checks.check(bool(numpy.all((organ == 1) == (leaf_id >= 0))), "LeafId >= 0 exactly on the leaf points")
    seen = set(leaf_id[leaf_id >= 0].tolist())
    checks.check(seen <= set(range(leaf_count)) and len(seen) > leaf_count // 2,
                 "%d of the %d leaves hit, every id one of the tree's" % (len(seen), leaf_count))
    # Each leaf's points lie on that leaf's own quad (its plane, within the range noise and a little).
    points = vtk_to_numpy(cloud.GetPoints().GetData())
    worst = 0.0
    for leaf in sorted(seen)[:10]:
        quad = vtk_to_numpy(leaves.GetPoints().GetData())[4 * leaf:4 * leaf + 4]
        normal = numpy.cross(quad[1] - quad[0], quad[3] - quad[0])
        normal /= numpy.linalg.norm(normal)
        worst = max(worst, float(numpy.max(numpy.abs((points[leaf_id == leaf] - quad[0]) @ normal))))
    checks.check(worst < 0.02, "each leaf's points on its own quad (worst %.4g)" % worst)
    again = servermanager.Fetch(VirtualScanner(Input=plant, Positions=positions, LookAt=centre, Up=[0, 1, 0],
                                               HorizontalFieldOfView=50, VerticalFieldOfView=50, AngularStep=0.1,
                                               RangeNoise=0.002, Seed=3))
    checks.check(numpy.array_equal(vtk_to_numpy(again.GetPointData().GetArray("LeafId")), leaf_id),
                 "the same seed gives the same labels")
checks.finish()
