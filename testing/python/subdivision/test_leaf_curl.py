# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: LeafOutlineSource -> LeafCurlFilter as users run it. The proxy is in the PlantMorph menu with its
documented defaults; the curl keeps the mesh and every array (TCoords still active), keeps the midvein, keeps edge
lengths (longitudinal curl alone), puts the margin 2W/pi above the midvein at 180 degrees; bad values give an empty
output; and a pipeline with curl angles set, saved as a state file, loads in a fresh pvpython with the same
properties and bit-identical output.

    pvpython test_leaf_curl.py --plugin PlantMorph.so --work DIR
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
state = os.path.join(arguments.work, "leaf_curl.pvsm")
expected_file = os.path.join(arguments.work, "leaf_curl_state_expected.json")
CURL_PROPERTIES = ("LongitudinalAngle", "TransverseAngle", "TransverseCenter")


def fetch(proxy):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy)


def describe(curl):
    data = fetch(curl)
    return {"properties": {name: curl.GetPropertyValue(name) for name in CURL_PROPERTIES},
            "fingerprint": fingerprint(data), "points": data.GetNumberOfPoints()}


checks = Checks()

if arguments.load is not None:
    # Second process: a fresh pvpython loads the state saved by the first and compares.
    curl, expected = loaded_state(checks, arguments, expected_file, "CurledLeaf")
    actual = describe(curl)
    check_same_properties(checks, actual, expected)
    checks.check(actual["points"] == expected["points"] and actual["points"] > 0, "same number of points")
    checks.check(actual["fingerprint"] == expected["fingerprint"], "curled leaf bit-identical after the round trip")
    checks.finish()
    sys.exit(0)

# The proxy: pvpython name, menu, defaults.
leaf = LeafOutlineSource(registrationName="Leaf", Preset="Ginkgo", Length=5.0, Resolution=60, MeshQuality="Quality")
curl = LeafCurlFilter(registrationName="CurledLeaf", Input=leaf)
hints = curl.SMProxy.GetHints()
menu = hints.FindNestedElementByName("ShowInMenu") if hints else None
checks.check(menu is not None and menu.GetAttribute("category") == "PlantMorph", "Leaf Curl Filter in the PlantMorph menu")
checks.check(curl.SMProxy.GetXMLLabel() == "Leaf Curl Filter", "label 'Leaf Curl Filter'")
checks.check((curl.LongitudinalAngle, curl.TransverseAngle, curl.TransverseCenter) == (90.0, 0.0, 0.5),
             "defaults 90, 0, 0.5: %r" % ((curl.LongitudinalAngle, curl.TransverseAngle, curl.TransverseCenter),))

flat = fetch(leaf)
flat_points = vtk_to_numpy(flat.GetPoints().GetData()).astype(float)
flat_uv = vtk_to_numpy(flat.GetPointData().GetArray("LeafUV"))
midvein = numpy.abs(flat_uv[:, 0]) <= 1e-9
triangles = vtk_to_numpy(flat.GetPolys().GetConnectivityArray()).reshape(-1, 3)
edges = numpy.unique(numpy.sort(numpy.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]),
                                axis=1), axis=0)


def edge_lengths(points):
    return numpy.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1)


# Longitudinal curl at 180 degrees: isometric, midvein fixed, margins 2W/pi above the midvein.
curl.LongitudinalAngle = 180.0
curled = fetch(curl)
points = vtk_to_numpy(curled.GetPoints().GetData()).astype(float)
checks.check(curled.GetNumberOfPoints() == flat.GetNumberOfPoints() and curled.GetNumberOfPolys() == flat.GetNumberOfPolys(),
             "same mesh: %d points, %d triangles" % (curled.GetNumberOfPoints(), curled.GetNumberOfPolys()))
change = numpy.max(numpy.abs(edge_lengths(points) / edge_lengths(flat_points) - 1.0))
print("longitudinal 180 deg: largest relative edge-length change %.2e" % change)
checks.check(change < 0.01, "edge lengths within 1%% under longitudinal curl: %.3e" % change)
checks.check(numpy.array_equal(points[midvein], flat_points[midvein]), "midvein points did not move")
for side, name in ((flat_points[:, 0] < 0, "left"), (flat_points[:, 0] > 0, "right")):
    half_width = numpy.max(numpy.abs(flat_points[side, 0]))
    top = numpy.max(points[side, 2])
    checks.check(abs(top - 2.0 * half_width / math.pi) < 1e-6 * half_width,
                 "%s margin at 2W/pi = %.6f above the midvein: %.6f" % (name, 2 * half_width / math.pi, top))
    checks.check(numpy.min(points[side, 2]) >= -1e-12, "%s half rolled up (+Z)" % name)

# Every array passes through; TCoords stay the active texture coordinates.
for a in range(flat.GetPointData().GetNumberOfArrays()):
    name = flat.GetPointData().GetArrayName(a)
    if name == "Normals":
        continue
    before = vtk_to_numpy(flat.GetPointData().GetArray(name))
    after = curled.GetPointData().GetArray(name)
    checks.check(after is not None and numpy.array_equal(vtk_to_numpy(after), before), "point array %s unchanged" % name)
tcoords = curled.GetPointData().GetTCoords()
checks.check(tcoords is not None and tcoords.GetName() == "TCoords", "TCoords still the active texture coordinates")
normals = vtk_to_numpy(curled.GetPointData().GetNormals()).astype(float)
checks.check(numpy.allclose(numpy.linalg.norm(normals, axis=1), 1.0, atol=1e-6), "normals unit length")
checks.check(numpy.min(normals[~midvein][:, 2]) < -0.5, "normals turned with the rolled halves")
checks.check(numpy.array_equal(vtk_to_numpy(curled.GetCellData().GetArray("Region")),
                               vtk_to_numpy(flat.GetCellData().GetArray("Region"))), "cell Region unchanged")
field = curled.GetFieldData()
checks.check(field.GetAbstractArray("PlantMorph.Model") is not None, "the source's field data passes through")
checks.check(field.GetArray("PlantMorph.LongitudinalAngle") is not None and
             field.GetArray("PlantMorph.LongitudinalAngle").GetValue(0) == 180.0, "the curl's angles in field data")

# Angle 0 is the identity, bit for bit.
curl.LongitudinalAngle = 0.0
curl.TransverseAngle = 0.0
identity = fetch(curl)
checks.check(fingerprint(identity) == fingerprint(flat), "both angles 0: the input's points bit for bit")

# Transverse curl alone: isometric, apex and base bent up.
curl.TransverseAngle = 120.0
curl.TransverseCenter = 0.5
bent = vtk_to_numpy(fetch(curl).GetPoints().GetData()).astype(float)
change = numpy.max(numpy.abs(edge_lengths(bent) / edge_lengths(flat_points) - 1.0))
print("transverse 120 deg: largest relative edge-length change %.2e" % change)
checks.check(change < 0.01, "edge lengths within 1%% under transverse curl: %.3e" % change)
checks.check(numpy.array_equal(bent[:, 0], flat_points[:, 0]), "transverse curl moves nothing across the blade")
checks.check(numpy.min(bent[:, 2]) >= -1e-12 and numpy.max(bent[:, 2]) > 1.0, "apex and base bent up")

# Bad values: an error and an empty output (never a crash); a good value brings the leaf back.
for name, value in (("LongitudinalAngle", 400.0), ("TransverseAngle", float("nan")), ("TransverseCenter", 1.5)):
    good = curl.GetPropertyValue(name)
    curl.SetPropertyWithName(name, value)
    checks.check(fetch(curl).GetNumberOfPoints() == 0, "%s = %r gives an empty output" % (name, value))
    curl.SetPropertyWithName(name, good)
checks.check(fetch(curl).GetNumberOfPoints() == flat.GetNumberOfPoints(), "the filter recovers")
no_uv = LeafCurlFilter(Input=PassArrays(Input=leaf, PointDataArrays=["TCoords"], CellDataArrays=[]))
checks.check(fetch(no_uv).GetNumberOfPoints() == 0, "input without LeafUV gives an empty output")
Delete(no_uv)

# The outline port curls with the same midvein and half-widths: its points land on the curled blade's.
curl.LongitudinalAngle = 130.0
curl.TransverseAngle = 45.0
curl.TransverseCenter = 0.4
outline_curl = LeafCurlFilter(Input=OutputPort(leaf, 1), LongitudinalAngle=130.0, TransverseAngle=45.0,
                              TransverseCenter=0.4)
blade_points = vtk_to_numpy(fetch(curl).GetPoints().GetData()).astype(float)
outline_points = vtk_to_numpy(fetch(outline_curl).GetPoints().GetData()).astype(float)
checks.check(numpy.allclose(outline_points, blade_points[:len(outline_points)], atol=1e-6),
             "curled outline lies on the curled blade")
Delete(outline_curl)

# State file: save with the curl angles set, load in a fresh pvpython, compare.
returncode = reload_in_fresh_pvpython(state, describe(curl), expected_file, arguments, __file__)
checks.check(returncode == 0, "the state file loads in a fresh pvpython with the same output")
checks.finish()
