# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: VirtualScanner as users build it. The proxy is in the PlantMorph menu with its documented defaults; a
leaf scanned from above and from below gives points on the blade carrying the hit cell's Region, normals facing the
scanner and ranges equal to the distances; a tree with leaves scanned from three positions carries every cell label
of the tree; the three scanner types run; bad values (zero step, a field of view over 360, a NaN position, a beam
count over MaximumBeams) give empty outputs; and a pipeline with several positions and noise, saved as a state
file, loads in a fresh pvpython with a bit-identical cloud.

    pvpython test_virtual_scanner.py --plugin PlantMorph.so --work DIR
"""
import math
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
state = os.path.join(arguments.work, "virtual_scanner.pvsm")
expected_file = os.path.join(arguments.work, "virtual_scanner_state_expected.json")
PROPERTIES = ("ScannerType", "Positions", "LookAt", "HorizontalFieldOfView", "VerticalFieldOfView", "AngularStep",
              "RangeNoise", "DropoutProbability", "Seed", "MaximumRange")


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, idx=port)


def value(proxy, name):
    v = proxy.GetPropertyValue(name)
    return v.GetData() if hasattr(v, "GetData") else v


def describe(scanner):
    cloud = fetch(scanner)
    return {"properties": {name: value(scanner, name) for name in PROPERTIES},
            "cloud": fingerprint(cloud), "setup": fingerprint(fetch(scanner, 1)), "points": cloud.GetNumberOfPoints()}


def array(data, name, cells=False):
    values = (data.GetCellData() if cells else data.GetPointData()).GetArray(name)
    return None if values is None else vtk_to_numpy(values)


checks = Checks()

if arguments.load is not None:
    scanner, expected = loaded_state(checks, arguments, expected_file, "Scan")
    actual = describe(scanner)
    check_same_properties(checks, actual, expected,
                          lambda after, before: numpy.allclose(after, before) if isinstance(before, list) else
                          after == before)
    checks.check(actual["points"] == expected["points"] and actual["points"] > 0, "same number of points")
    checks.check(actual["cloud"] == expected["cloud"], "cloud bit-identical after the round trip")
    checks.check(actual["setup"] == expected["setup"], "set-up lines identical after the round trip")
    checks.finish()
    sys.exit(0)

# The leaf, from above: a depth camera over its centre.
leaf = LeafOutlineSource(Resolution=60)
blade = fetch(leaf)
bounds = blade.GetBounds()
centre = [(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2, (bounds[4] + bounds[5]) / 2]
size = max(bounds[1] - bounds[0], bounds[3] - bounds[2], 1e-3)
scanner = VirtualScanner(Input=leaf)
checks.check(scanner.ScannerType == "Terrestrial" and scanner.Seed == 0 and scanner.RangeNoise == 0.0
             and list(scanner.Positions) == [0.0, -5.0, 1.0], "defaults: Terrestrial, seed 0, no noise, one position")
scanner.ScannerType = "Depth camera"
scanner.Positions = [centre[0], centre[1], centre[2] + 2 * size]
scanner.LookAt = centre
scanner.Up = [0, 1, 0]
scanner.HorizontalFieldOfView = 40
scanner.VerticalFieldOfView = 40
scanner.Resolution = [120, 120]
cloud = fetch(scanner)
n = cloud.GetNumberOfPoints()
checks.check(n > 500, "the leaf from above: %d points" % n)
checks.check(cloud.GetNumberOfVerts() == n, "one vertex per point")
hit = array(cloud, "HitCellId")
region = array(cloud, "Region")
leaf_region = array(blade, "Region", cells=True)
checks.check(region is not None and leaf_region is not None and numpy.array_equal(region, leaf_region[hit]),
             "every point carries its hit cell's Region")
points = vtk_to_numpy(cloud.GetPoints().GetData())
normals = array(cloud, "Normals")
origin = numpy.array(scanner.Positions[0:3])
to_scanner = origin - points
checks.check(numpy.all(numpy.einsum("ij,ij->i", normals, to_scanner) > 0), "normals face the scanner")
checks.check(numpy.allclose(array(cloud, "Range"), numpy.linalg.norm(to_scanner, axis=1), atol=1e-9),
             "Range is the distance to the scanner")
setup = fetch(scanner, 1)
checks.check(setup.GetNumberOfLines() == 5, "the set-up: the central beam and four corners (%d lines)"
             % setup.GetNumberOfLines())

# Three scanner types run; a line scanner on a path across the leaf gives one fan per LineSpacing.
scanner.ScannerType = "Line"
scanner.Positions = [bounds[0], centre[1], centre[2] + 2 * size, bounds[1], centre[1], centre[2] + 2 * size]
scanner.LookAt = [0.5 * (bounds[0] + bounds[1]), centre[1], centre[2]]  # below the middle of the path
scanner.LineSpacing = (bounds[1] - bounds[0]) / 50
scanner.AngularStep = 0.5
line = fetch(scanner)
poses = array(line, "ScanPosition")
checks.check(line.GetNumberOfPoints() > 100 and poses is not None and poses.max() <= 50,
             "line scanner: %d points over %s fans" % (line.GetNumberOfPoints(), None if poses is None else poses.max() + 1))
scanner.ScannerType = "Terrestrial"
scanner.Positions = [centre[0], centre[1] - 2 * size, centre[2] + 2 * size]
scanner.LookAt = centre
scanner.HorizontalFieldOfView = 60
scanner.VerticalFieldOfView = 60
terrestrial = fetch(scanner)
checks.check(terrestrial.GetNumberOfPoints() > 100, "terrestrial: %d points" % terrestrial.GetNumberOfPoints())

# A tree with leaves from three positions: every cell array of the tree carried, each point's the hit cell's.
tree = TreeFromSketchSource()
tree_surface = fetch(tree)
tb = tree_surface.GetBounds()
tc = [(tb[0] + tb[1]) / 2, (tb[2] + tb[3]) / 2, (tb[4] + tb[5]) / 2]
extent = max(tb[1] - tb[0], tb[3] - tb[2], tb[5] - tb[4])
tree_scan = VirtualScanner(Input=tree, LookAt=tc, HorizontalFieldOfView=60, VerticalFieldOfView=60, AngularStep=0.4)
tree_scan.Positions = sum(([tc[0] + 2 * extent * math.cos(a), tc[1] + 2 * extent * math.sin(a), tc[2]]
                           for a in (0.0, 2.0944, 4.1888)), [])
tree_cloud = fetch(tree_scan)
checks.check(tree_cloud.GetNumberOfPoints() > 1000, "tree: %d points" % tree_cloud.GetNumberOfPoints())
checks.check(set(array(tree_cloud, "ScanPosition").tolist()) == {0, 1, 2}, "tree: points from all three positions")
tree_hit = array(tree_cloud, "HitCellId")
names = [tree_surface.GetCellData().GetArrayName(i) for i in range(tree_surface.GetCellData().GetNumberOfArrays())]
checks.check(len(names) > 0, "the tree has cell labels: %s" % names)
for name in names:
    if name in ("Normals", "Range", "Intensity", "ScanPosition", "HitCellId", "BeamId"):
        continue
    carried = array(tree_cloud, name)
    source = array(tree_surface, name, cells=True)
    checks.check(carried is not None and numpy.array_equal(carried, source[tree_hit]),
                 "tree: every point carries its hit cell's %s" % name)

# Bad values: empty outputs.
for prop, bad in (("AngularStep", 0.0), ("HorizontalFieldOfView", 400.0), ("Positions", [float("nan"), 0.0, 1.0]),
                  ("MaximumBeams", 10.0)):
    good = value(tree_scan, prop)
    setattr(tree_scan, prop, bad)
    checks.check(fetch(tree_scan).GetNumberOfPoints() == 0 and fetch(tree_scan, 1).GetNumberOfPoints() == 0,
                 "%s = %r: empty outputs" % (prop, bad))
    setattr(tree_scan, prop, good)
checks.check(fetch(tree_scan).GetNumberOfPoints() == tree_cloud.GetNumberOfPoints(), "good values scan again")

# State file: several positions and noise, saved, loaded in a fresh pvpython, compared.
RenameSource("Scan", tree_scan)
tree_scan.RangeNoise = 0.002 * extent
tree_scan.DropoutProbability = 0.1
tree_scan.Seed = 11
tree_scan.MaximumRange = 3 * extent
returncode = reload_in_fresh_pvpython(state, describe(tree_scan), expected_file, arguments, __file__)
checks.check(returncode == 0, "the state file loads in a fresh pvpython with the same output")
checks.finish()
