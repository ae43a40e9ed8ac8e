# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: the chain LeafOutlineSource -> AdaptiveLoopFilter -> LeafCurlFilter, as a user builds it.
Each filter has its own test; this one checks what only the chain shows:

- AdaptiveLoopFilter on the flat blade, every edge split (EdgeAngleThreshold 180, FlatnessThreshold 1, FeatureRule
  Refine): exactly 4x the triangles per level and V + E new points per level in its field data, a conforming mesh,
  margin and midvein points kept in place, the new ones on the input's margin and midvein polylines, LeafUV u = 0 on
  the new midvein points, and TCoords still the bounding-box map of x, y (the paper's eq. (6) texture: an affine
  function of the flat blade, which the affine Loop stencils must preserve);
- LeafCurlFilter on the subdivided blade: isometric (edge lengths within 1%), the refined midvein does not move
  under longitudinal curl, LeafUV, TCoords, Region (points and cells) and the loop's field data pass through;
- AdaptiveLoopFilter with its defaults leaves a flat blade alone, so the chain curls it exactly as the curl alone;
- the chain saved as a state file loads in a fresh pvpython with the same properties, the same per-level counts and
  bit-identical output of both filters.

Nothing is rendered.

    pvpython test_outline_loop_curl_chain.py --plugin PlantMorph.so --work DIR
"""
import json
import os
import sys

from plantmorph_testing import Checks, fingerprint, load_plugin, parse_arguments, reload_in_fresh_pvpython

arguments = parse_arguments([("--load", dict(default=None)), ("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
state = os.path.join(arguments.work, "outline_loop_curl_chain.pvsm")
expected_file = os.path.join(arguments.work, "outline_loop_curl_chain_expected.json")
LOOP_PROPERTIES = ("MaximumLevel", "EdgeAngleThreshold", "FlatnessThreshold", "FeatureRule", "MidveinFeatures")
CURL_PROPERTIES = ("LongitudinalAngle", "TransverseAngle", "TransverseCenter")
MIDVEIN_U = 1e-9  # LeafCurl's MidveinTolerance


def fetch(proxy):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy)


def per_level(data, name):
    array = data.GetFieldData().GetArray(name)
    return [int(array.GetValue(i)) for i in range(array.GetNumberOfTuples())] if array else None


def plain(value):
    """A property value as JSON can hold it (enumerations as their text)."""
    if hasattr(value, "GetData"):
        value = value.GetData()
    return value if isinstance(value, (int, float)) else str(value)


def describe(loop, curl):
    subdivided = fetch(loop)
    curled = fetch(curl)
    return {"loop": {name: plain(getattr(loop, name)) for name in LOOP_PROPERTIES},
            "curl": {name: plain(getattr(curl, name)) for name in CURL_PROPERTIES},
            "triangles_per_level": per_level(subdivided, "AdaptiveLoop.TrianglesPerLevel"),
            "points_per_level": per_level(subdivided, "AdaptiveLoop.PointsPerLevel"),
            "loop_fingerprint": fingerprint(subdivided), "curl_fingerprint": fingerprint(curled),
            "points": curled.GetNumberOfPoints()}


checks = Checks()

if arguments.load is not None:
    # Second process: a fresh pvpython loads the state saved by the first and compares.
    LoadState(arguments.load)
    loop = FindSource("SubdividedLeaf")
    curl = FindSource("CurledLeaf")
    checks.check(loop is not None and curl is not None, "the state file holds 'SubdividedLeaf' and 'CurledLeaf'")
    if loop is None or curl is None:
        checks.finish()
    with open(expected_file) as f:
        expected = json.load(f)
    actual = describe(loop, curl)
    for group in ("loop", "curl"):
        for name, value in expected[group].items():
            checks.check(actual[group][name] == value,
                         "%s property %s: %r after loading, %r before" % (group, name, actual[group][name], value))
    for key in ("triangles_per_level", "points_per_level"):
        checks.check(actual[key] == expected[key], "%s: %r after loading, %r before" % (key, actual[key], expected[key]))
    checks.check(actual["points"] == expected["points"] and actual["points"] > 0, "same number of points")
    checks.check(actual["loop_fingerprint"] == expected["loop_fingerprint"],
                 "subdivided leaf bit-identical after the round trip")
    checks.check(actual["curl_fingerprint"] == expected["curl_fingerprint"],
                 "curled leaf bit-identical after the round trip")
    checks.finish()
    sys.exit(0)


def numpy_points(data):
    return vtk_to_numpy(data.GetPoints().GetData()).astype(float)


def edges_of(data):
    triangles = vtk_to_numpy(data.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    all_edges = numpy.sort(numpy.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]),
                           axis=1)
    return numpy.unique(all_edges, axis=0, return_counts=True)


def distance_to_segments(points, a, b):
    """Distance of every point to the nearest of the segments (a[i], b[i])."""
    ab = b - a
    ap = points[:, None, :] - a[None, :, :]
    t = numpy.clip((ap * ab[None]).sum(axis=2) / (ab * ab).sum(axis=1)[None], 0.0, 1.0)
    closest = a[None] + t[:, :, None] * ab[None]
    return numpy.linalg.norm(points[:, None, :] - closest, axis=2).min(axis=1)


# The chain, as a user builds it in the Filters > PlantMorph menu.
leaf = LeafOutlineSource(registrationName="Leaf", Preset="Ginkgo", Length=5.0, Resolution=30, MeshQuality="Quality")
loop = AdaptiveLoopFilter(registrationName="SubdividedLeaf", Input=leaf)
curl = LeafCurlFilter(registrationName="CurledLeaf", Input=loop)
direct = LeafCurlFilter(registrationName="DirectCurl", Input=leaf)

flat = fetch(leaf)
flat_points = numpy_points(flat)
flat_uv = vtk_to_numpy(flat.GetPointData().GetArray("LeafUV")).astype(float)
flat_region = vtk_to_numpy(flat.GetPointData().GetArray("Region"))
n_points, n_triangles = flat.GetNumberOfPoints(), flat.GetNumberOfPolys()
flat_edges, flat_use = edges_of(flat)
checks.check(n_triangles > 500 and flat.GetNumberOfPolys() == flat.GetNumberOfCells(), "a triangle blade to subdivide")
checks.check(numpy.all(flat_points[:, 2] == 0.0), "LeafOutlineSource's Ginkgo blade is flat (z = 0)")

# Defaults: a flat blade has nothing to refine, so the chain is the curl alone, bit for bit.
subdivided = fetch(loop)
checks.check(per_level(subdivided, "AdaptiveLoop.TrianglesPerLevel") == [n_triangles],
             "defaults on a flat blade: no level applied %r" % per_level(subdivided, "AdaptiveLoop.TrianglesPerLevel"))
# (Compared by value: AdaptiveLoopFilter stores connectivity as 32-bit ids, the source as 64-bit.)
chained, alone = fetch(curl), fetch(direct)
same = numpy.array_equal(numpy_points(chained), numpy_points(alone)) and numpy.array_equal(
    vtk_to_numpy(chained.GetPolys().GetConnectivityArray()), vtk_to_numpy(alone.GetPolys().GetConnectivityArray()))
for name in ("LeafUV", "TCoords", "Region", "Normals"):
    same = same and numpy.array_equal(vtk_to_numpy(chained.GetPointData().GetArray(name)),
                                      vtk_to_numpy(alone.GetPointData().GetArray(name)))
checks.check(same and numpy.abs(numpy_points(chained)[:, 2]).max() > 0.5,
             "defaults: LeafOutlineSource -> AdaptiveLoopFilter -> LeafCurlFilter = LeafOutlineSource -> LeafCurlFilter")
Delete(direct)

# Every edge split, margin and midvein refined in place, interior points Loop-smoothed in the plane.
LEVELS = 2
loop.MaximumLevel = LEVELS
loop.EdgeAngleThreshold = 180.0
loop.FlatnessThreshold = 1.0
loop.FeatureRule = "Refine"
subdivided = fetch(loop)
sub_points = numpy_points(subdivided)
n_sub = subdivided.GetNumberOfPoints()

# Counts per level: 4x triangles; V' = V + E; on a refined-everywhere level E' = 2E + 3T.
triangles_per_level = per_level(subdivided, "AdaptiveLoop.TrianglesPerLevel")
points_per_level = per_level(subdivided, "AdaptiveLoop.PointsPerLevel")
expected_triangles = [n_triangles * 4 ** level for level in range(LEVELS + 1)]
expected_points, v, e, t = [n_points], n_points, len(flat_edges), n_triangles
for level in range(LEVELS):
    v, e, t = v + e, 2 * e + 3 * t, 4 * t
    expected_points.append(v)
print("triangles per level %r, points per level %r" % (triangles_per_level, points_per_level))
checks.check(triangles_per_level == expected_triangles,
             "TrianglesPerLevel %r == %r (4x per level)" % (triangles_per_level, expected_triangles))
checks.check(points_per_level == expected_points,
             "PointsPerLevel %r == %r (V + E per level)" % (points_per_level, expected_points))
checks.check(subdivided.GetNumberOfPolys() == expected_triangles[-1] and n_sub == expected_points[-1],
             "output holds the last level's %d triangles and %d points" % (expected_triangles[-1], expected_points[-1]))
sub_edges, sub_use = edges_of(subdivided)
checks.check(set(sub_use.tolist()) <= {1, 2}, "conforming: every edge in one or two triangles")
checks.check(int((sub_use == 1).sum()) == 4 * int((flat_use == 1).sum()),
             "margin edges split twice: %d boundary edges, input %d" % ((sub_use == 1).sum(), (flat_use == 1).sum()))
checks.check(numpy.all(sub_points[:, 2] == 0.0), "the subdivided flat blade stays flat")

# The arrays of the data contract, through AdaptiveLoopFilter.
pd = subdivided.GetPointData()
uv_array, tcoords_array, region_array = pd.GetArray("LeafUV"), pd.GetTCoords(), pd.GetArray("Region")
checks.check(uv_array is not None and uv_array.GetNumberOfComponents() == 2 and uv_array.GetDataType() == 11,
             "loop: LeafUV double x2")
checks.check(tcoords_array is not None and tcoords_array.GetName() == "TCoords" and
             tcoords_array.GetNumberOfComponents() == 2, "loop: TCoords still the active texture coordinates")
checks.check(region_array is not None and region_array.GetNumberOfComponents() == 1, "loop: point Region")
cell_region = subdivided.GetCellData().GetArray("Region")
checks.check(cell_region is not None and cell_region.GetNumberOfTuples() == subdivided.GetNumberOfCells(),
             "loop: cell Region on every triangle")
sub_uv = vtk_to_numpy(uv_array).astype(float)
sub_region = vtk_to_numpy(region_array)
checks.check(sub_uv[:, 0].min() >= -0.5 - 1e-9 and sub_uv[:, 0].max() <= 0.5 + 1e-9 and sub_uv[:, 1].min() >= -1e-9
             and sub_uv[:, 1].max() <= 1.0 + 1e-9, "LeafUV stays in the canonical leaf")

# TCoords: the same affine map of x, y as on the input (fitted there), because every stencil is affine.
flat_tc = vtk_to_numpy(flat.GetPointData().GetTCoords()).astype(float)
design = numpy.column_stack([flat_points[:, 0], flat_points[:, 1], numpy.ones(n_points)])
affine, _, _, _ = numpy.linalg.lstsq(design, flat_tc, rcond=None)
fit_error = numpy.abs(design @ affine - flat_tc).max()
checks.check(fit_error < 1e-6, "input TCoords are an affine map of x, y (eq. (6)): residual %.2e" % fit_error)
sub_tc = vtk_to_numpy(tcoords_array).astype(float)
sub_design = numpy.column_stack([sub_points[:, 0], sub_points[:, 1], numpy.ones(n_sub)])
tc_error = numpy.abs(sub_design @ affine - sub_tc).max()
print("TCoords against the affine map of the subdivided points: %.2e" % tc_error)
checks.check(tc_error < 1e-5, "TCoords interpolated with the positions' stencils: %.2e from the map" % tc_error)
checks.check(float(numpy.abs(sub_points[:n_points] - flat_points).max()) > 1e-3,
             "interior points were Loop-smoothed (FlatnessThreshold 1), so that check has teeth")

# Refine: margin (4) and midvein (1) points keep their place; the new ones lie on the input's polylines.
feature = (flat_region == 1) | (flat_region == 4)
checks.check(numpy.array_equal(sub_points[:n_points][feature], flat_points[feature]),
             "margin and midvein points bit-identical (Refine)")
checks.check(numpy.array_equal(sub_uv[:n_points][feature], flat_uv[feature]), "their LeafUV bit-identical")
boundary = flat_edges[flat_use == 1]
new_margin = numpy.nonzero(sub_region[n_points:] == 4)[0] + n_points
checks.check(len(new_margin) == 3 * len(boundary), "3 new margin points per margin edge: %d for %d edges"
             % (len(new_margin), len(boundary)))
margin_gap = distance_to_segments(sub_points[new_margin], flat_points[boundary[:, 0]], flat_points[boundary[:, 1]])
checks.check(margin_gap.max() < 1e-12, "new margin points on the input margin: %.2e away" % margin_gap.max())
vein = flat_edges[(flat_region[flat_edges[:, 0]] == 1) & (flat_region[flat_edges[:, 1]] == 1)]
new_vein = numpy.nonzero(sub_region[n_points:] == 1)[0] + n_points
checks.check(len(vein) > 10 and len(new_vein) == 3 * len(vein),
             "3 new midvein points per midvein edge: %d for %d edges" % (len(new_vein), len(vein)))
vein_gap = distance_to_segments(sub_points[new_vein], flat_points[vein[:, 0]], flat_points[vein[:, 1]])
checks.check(vein_gap.max() < 1e-12, "new midvein points on the input midvein: %.2e away" % vein_gap.max())
checks.check(numpy.abs(sub_uv[new_vein, 0]).max() <= MIDVEIN_U, "new midvein points have LeafUV u = 0")
midvein = numpy.abs(sub_uv[:, 0]) <= MIDVEIN_U
flat_midvein = int((numpy.abs(flat_uv[:, 0]) <= MIDVEIN_U).sum())
checks.check(int(midvein.sum()) >= flat_midvein + len(new_vein),
             "the refined midvein LeafCurlFilter rolls about: %d points (input %d)" % (midvein.sum(), flat_midvein))

# LeafCurlFilter on the subdivided blade: longitudinal curl.
curl.LongitudinalAngle = 150.0
curl.TransverseAngle = 0.0
curled = fetch(curl)
curled_points = numpy_points(curled)
checks.check(curled.GetNumberOfPoints() == n_sub and curled.GetNumberOfPolys() == subdivided.GetNumberOfPolys() and
             numpy.array_equal(vtk_to_numpy(curled.GetPolys().GetConnectivityArray()),
                               vtk_to_numpy(subdivided.GetPolys().GetConnectivityArray())),
             "curl keeps the subdivided mesh's %d points and triangles" % n_sub)


def length_change(points):
    before = numpy.linalg.norm(sub_points[sub_edges[:, 0]] - sub_points[sub_edges[:, 1]], axis=1)
    after = numpy.linalg.norm(points[sub_edges[:, 0]] - points[sub_edges[:, 1]], axis=1)
    return numpy.abs(after / before - 1.0).max()


change = length_change(curled_points)
print("longitudinal 150 deg on the subdivided blade: largest relative edge-length change %.2e" % change)
checks.check(change < 0.01, "isometric: edge lengths within 1%% (%.2e)" % change)
half_width = numpy.abs(sub_points[:, 0]).max()
checks.check(curled_points[:, 2].max() > 0.5 * half_width, "the halves rolled up: top %.3f, half-width %.3f"
             % (curled_points[:, 2].max(), half_width))
checks.check(numpy.array_equal(curled_points[midvein], sub_points[midvein]),
             "the %d midvein points did not move under longitudinal curl" % midvein.sum())

# Arrays and field data through the curl: unchanged, bit for bit.
for name in ("LeafUV", "TCoords", "Region"):
    after = curled.GetPointData().GetArray(name)
    checks.check(after is not None and numpy.array_equal(vtk_to_numpy(after), vtk_to_numpy(pd.GetArray(name))),
                 "curl: point array %s carried through unchanged" % name)
checks.check(curled.GetPointData().GetTCoords() is not None and
             curled.GetPointData().GetTCoords().GetName() == "TCoords", "curl: TCoords still active")
checks.check(numpy.array_equal(vtk_to_numpy(curled.GetCellData().GetArray("Region")), vtk_to_numpy(cell_region)),
             "curl: cell Region carried through unchanged")
checks.check(per_level(curled, "AdaptiveLoop.TrianglesPerLevel") == expected_triangles,
             "curl: AdaptiveLoop.TrianglesPerLevel field data passed on")

# Both curls (transverse after longitudinal, the state file below saves this setting): the transverse bend moves
# midvein points only along the blade's length (y, z), never across it.
curl.TransverseAngle = 40.0
curl.TransverseCenter = 0.45
both = numpy_points(fetch(curl))
checks.check(numpy.array_equal(both[midvein, 0], sub_points[midvein, 0]),
             "transverse curl moves midvein points only in y and z")
checks.check(numpy.abs(both - curled_points).max() > 0.1, "transverse curl changed the leaf")

# State file: save the chain, load it in a fresh pvpython, compare.
returncode = reload_in_fresh_pvpython(state, describe(loop, curl), expected_file, arguments, __file__)
checks.check(returncode == 0, "the chain's state file loads in a fresh pvpython with the same output")
checks.finish()
