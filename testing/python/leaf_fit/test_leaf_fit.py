# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: LeafCloudReader -> LeafFitFilter on the shipped leaf scans (data/leaf-clouds/, millimetres), as users run
it with the defaults. Every scan gives a blade with the data contract's arrays, one Traits row and the Scan port;
the fit lies on the scan (FitRMS and FitP95 within about twice the scans' noise; no blade triangle more than 3
point spacings from it on four of the six, no margin vertex more than 6.5 on all six); several scans appended with a LeafId array give
one row each, equal to the single fits; LeafOutlineSource rebuilds a leaf from the fitted Model C control points in
field data (the documented recipe); bad input (an empty cloud too) gives an error and empty outputs; a state file
round-trips.

    pvpython test_leaf_fit.py --plugin PlantMorph.so --work DIR
"""
import glob
import os
import sys

from plantmorph_testing import (Checks, fingerprint, load_plugin, loaded_state, Messages, parse_arguments,
                                reload_in_fresh_pvpython)

arguments = parse_arguments([("--load", dict(default=None)), ("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkPolyData  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
HERE = os.path.dirname(os.path.abspath(__file__))
SCANS = sorted(glob.glob(os.path.join(HERE, "..", "..", "..", "data", "leaf-clouds", "*.txt")))
state = os.path.join(arguments.work, "leaf_fit.pvsm")
expected_file = os.path.join(arguments.work, "leaf_fit_state_expected.json")
TRAITS = ["LeafId", "Length", "Width", "Area", "ProjectedArea", "Perimeter", "AspectRatio", "Bending", "Rolling",
          "Inclination", "Azimuth", "Points", "Inliers", "FitRMS", "FitP95", "FitMax", "Coverage"]


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, idx=port)


def rows(fit):
    table = fetch(fit, 2)
    names = [table.GetColumnName(c) for c in range(table.GetNumberOfColumns())]
    return [{n: table.GetValueByName(r, n).ToDouble() for n in names} for r in range(table.GetNumberOfRows())]


def describe(fit):
    return {"properties": {n: fit.GetPropertyValue(n) for n in ("Scale", "Resolution", "SurfaceSmoothing")},
            "fingerprints": [fingerprint(fetch(fit, port)) for port in range(4)]}


checks = Checks()
if arguments.load is not None:
    fit, expected = loaded_state(checks, arguments, expected_file, "FittedLeaf")
    actual = describe(fit)
    checks.check(actual["properties"] == expected["properties"], "properties survive the round trip")
    checks.check(actual["fingerprints"] == expected["fingerprints"], "all four outputs bit-identical after loading")
    checks.finish()
    sys.exit(0)

checks.check(len(SCANS) == 6, "the six shipped scans are found")
# Every shipped scan with the defaults.
single = []
for path in SCANS:
    name = os.path.basename(path)[:24]
    reader = LeafCloudReader(FileName=path)
    fit = LeafFitFilter(Input=reader)
    blade, outline, scan = fetch(fit, 0), fetch(fit, 1), fetch(fit, 3)
    table = rows(fit)
    checks.check(len(table) == 1, name + ": one Traits row")
    row = table[0] if table else {}
    single.append(row)
    checks.check(all(t in row for t in TRAITS), name + ": every trait column")
    for array in ("LeafUV", "TCoords", "Region", "Normals", "LeafId", "Support"):
        checks.check(blade.GetPointData().GetArray(array) is not None, name + ": blade has " + array)
    checks.check(blade.GetNumberOfPolys() > 500, name + ": blade is a mesh")
    lines = 4 if row.get("PetioleLength", 0) > 0 else 3
    checks.check(outline.GetNumberOfLines() == lines, name + ": left, right margin, midvein (and the petiole)")
    n = fetch(reader).GetNumberOfPoints()
    checks.check(scan.GetNumberOfPoints() == n and row.get("Points") == n, name + ": Scan has every input point")
    for array in ("FitDistance", "Inlier", "LeafId"):
        checks.check(scan.GetPointData().GetArray(array) is not None, name + ": Scan has " + array)
    # The scans' own noise (local-plane residual) is 0.17-0.33 mm; the fit stays within about twice that, except
    # the first soybean leaflet (0.72 mm), whose scan holds two sheets 1.1-2.1 mm apart over much of the blade (its
    # lines alternate between them): a quadratic fitted to each disc of 6 spacings leaves 0.61 mm there (median),
    # so no surface smooth at that scale comes nearer.
    limit = 0.8 if "pot1_1." in path and "soybean" in path else 0.45
    checks.check(row.get("FitRMS", 1e9) < limit, "%s: FitRMS %.3f mm < %.2f" % (name, row.get("FitRMS", -1), limit))
    checks.check(row.get("FitP95", 1e9) < 2.2 * limit, "%s: FitP95 %.3f mm" % (name, row.get("FitP95", -1)))
    region = scan.GetPointData().GetArray("Region")
    petiole = int((vtk_to_numpy(region) == 5).sum()) if region is not None else 0
    checks.check(row.get("Inliers", 0) > 0.95 * (n - petiole), name + ": over 95 % of the blade's points inliers")
    checks.check(row.get("Area", 0) > 300 and row.get("Length", 0) > 30, name + ": a leaf-sized blade")
    # No blade triangle (its vertices' mean Support) more than 3 point spacings from the scan. Holds on four scans
    # (none has a hole the blade bridges); not on the two whose scans leave gaps inside the outline the points draw,
    # which the blade bridges (printed): the first soybean leaflet (141 of 6967 triangles, up to 5.7 spacings: a
    # stripe with no points across its folded half, points on both sides, and bays beside the margin) and the sugar
    # beet of 30 August (53 of 5541, up to 4.7: between the strip of points along the midrib and the blade beside it).
    support = vtk_to_numpy(blade.GetPointData().GetArray("Support"))
    triangles = vtk_to_numpy(blade.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    # The margins keep to the scan on all six: the outline the points draw lies within the closing's discs (2.5
    # spacings) and the gap to the margin (at most 3) of them, and the margins within a spacing of it, also where
    # that outline gives no contour (the sugar beet of 30 August: its smooth margins' base wedge reached 8.45).
    region = blade.GetPointData().GetArray("Region")
    margin = support[vtk_to_numpy(region) == 4] if region is not None else numpy.array([1e9])
    checks.check(margin.max() <= 6.5 * row.get("Spacing", 0.0), "%s: margin within 6.5 spacings of the scan (%.2f)" % (
        name, margin.max() / max(row.get("Spacing", 1e-9), 1e-9)))
    far = int((support[triangles].mean(axis=1) > 3.0 * row.get("Spacing", 0.0)).sum())
    known = ("soybean" in path and "pot1_1." in path) or "20170830" in path
    if known:
        print("%s: %d of %d triangles more than 3 spacings from the scan (known gap)" % (name, far, len(triangles)))
    else:
        checks.check(far == 0, "%s: %d of %d triangles more than 3 spacings from the scan" % (
            name, far, len(triangles)))
    Delete(fit)
    Delete(reader)

# Multi-leaf input: three scans appended, told apart by a LeafId array: one row each, equal to the single fits.
parts = []
for k in (0, 3, 5):
    reader = LeafCloudReader(FileName=SCANS[k])
    parts.append(Calculator(Input=reader, ResultArrayName="LeafId", Function="%d" % (10 + k),
                            ResultArrayType="Int"))
appended = AppendDatasets(Input=parts)
multi = LeafFitFilter(Input=appended, LeafIdArray="LeafId")
table = rows(multi)
checks.check([int(r["LeafId"]) for r in table] == [10, 13, 15], "one row per LeafId, in order")
for r, k in zip(table, (0, 3, 5)):
    checks.check(all(abs(r[t] - single[k][t]) <= 1e-9 * max(1.0, abs(single[k][t])) for t in TRAITS[1:]),
                 "leaf %d: the same traits as fitted alone" % (10 + k))
scan_ids = vtk_to_numpy(fetch(multi, 3).GetPointData().GetArray("LeafId"))
checks.check(sorted(set(scan_ids.tolist())) == [10, 13, 15], "Scan's LeafId holds the three leaves")
multi.LeafIdArray = "NoSuchArray"
checks.check(fetch(multi, 0).GetNumberOfPoints() == 0 and fetch(multi, 2).GetNumberOfRows() == 0,
             "a LeafIdArray the input does not have: empty outputs")
Delete(multi)

# The recipe: LeafOutlineSource (B-spline, Custom) from the fitted Model C control points in field data. The 3-D
# points rebuild a leaf that curves gently enough to be meshed in one plane (the second soybean leaflet); the flat
# ones (intrinsic layout) rebuild every leaf.
def one_sided(a, b):
    return max(numpy.min(numpy.linalg.norm(b - p, axis=1)) for p in a)


def rebuild(blade, prefix):
    fd = blade.GetFieldData()
    model = {k: vtk_to_numpy(fd.GetArray("PlantMorph.FitModel.0." + prefix + k)).ravel().tolist()
             for k in ("MidveinPoints", "LeftMarginPoints", "RightMarginPoints")}
    source = LeafOutlineSource(Model="B-spline", BSplinePreset="Custom", Resolution=60, **model)
    return source, fetch(source, 0), fetch(source, 1)


def area(polydata):
    points = vtk_to_numpy(polydata.GetPoints().GetData()).astype(float)
    cells = vtk_to_numpy(polydata.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return 0.5 * numpy.linalg.norm(numpy.cross(points[cells[:, 1]] - points[cells[:, 0]],
                                               points[cells[:, 2]] - points[cells[:, 0]]), axis=1).sum()


reader = LeafCloudReader(FileName=SCANS[1])
fit = LeafFitFilter(Input=reader)
source, rebuilt, rebuilt_outline = rebuild(fetch(fit), "")
fitted_outline = vtk_to_numpy(fetch(fit, 1).GetPoints().GetData()).astype(float)
rebuilt_points = vtk_to_numpy(rebuilt_outline.GetPoints().GetData()).astype(float)
length = rows(fit)[0]["Length"]
hausdorff = max(one_sided(rebuilt_points, fitted_outline), one_sided(fitted_outline, rebuilt_points))
checks.check(hausdorff < 0.02 * length, "3-D recipe: outline within 2%% of the length: %.3f mm" % hausdorff)
# LeafOutlineSource meshes 3-D control points in their least-squares plane and lifts the interior by interpolating
# the outline's heights: the curved interior comes out flatter, so the area is lower (7 % here).
checks.check(abs(area(rebuilt) / rows(fit)[0]["Area"] - 1.0) < 0.1,
             "3-D recipe: area within 10%%: %.1f vs %.1f" % (area(rebuilt), rows(fit)[0]["Area"]))
Delete(source)
Delete(fit)
Delete(reader)
for path, row in zip(SCANS, single):
    reader = LeafCloudReader(FileName=path)
    fit = LeafFitFilter(Input=reader)
    blade = fetch(fit)
    source, rebuilt, _ = rebuild(blade, "Flat")
    checks.check(rebuilt.GetNumberOfPolys() > 100, os.path.basename(path)[:24] + ": flat recipe rebuilds the leaf")
    # With the petiole set apart, every blade rebuilds with the 20 control points asked for (the sugar-beet leaf of 30
    # August folded with them while its petiole was fitted as blade: a margin along the midvein for a third of it),
    # but that one with 18: its blade keeps to its points, whose base is a strip about 2 mm wide along the midrib
    # for 8 mm below the lamina, margins close to the midvein where 20 interpolating points fold (two fewer per
    # curve until the model rebuilds, as documented).
    used = blade.GetFieldData().GetArray("PlantMorph.FitModel.0.ControlPoints").GetValue(0)
    checks.check(used == (18 if "20170830" in path else 20),
                 os.path.basename(path)[:24] + ": %d control points in the model" % used)
    Delete(source)
    Delete(fit)
    Delete(reader)
reader = LeafCloudReader(registrationName="Scan", FileName=SCANS[5])
fit = LeafFitFilter(registrationName="FittedLeaf", Input=reader)
length = rows(fit)[0]["Length"]

# Bad input: errors and empty outputs, never a crash.
bad = {
    "too few points": PointSource(NumberOfPoints=20, Radius=5.0),
    "a line of points": Line(Resolution=500),
    "no leaf shape": PointSource(NumberOfPoints=3000, Radius=30.0),
    "NaN coordinates": Calculator(Input=reader, CoordinateResults=1, Function="coords*ln(-1)"),
}
for what, source in bad.items():
    f = LeafFitFilter(Input=source)
    checks.check(all(fetch(f, p).GetNumberOfPoints() == 0 for p in (0, 1, 3)) and fetch(f, 2).GetNumberOfRows() == 0,
                 what + ": empty outputs")
    Delete(f)
# An empty input (a cloud with no points): an error naming the input, every output empty.
empty_cloud = TrivialProducer()
empty_cloud.GetClientSideObject().SetOutput(vtkPolyData())
nothing = LeafFitFilter(Input=empty_cloud)
with Messages(nothing) as said:
    nothing.UpdatePipeline()
checks.check(said.said("Input", "no points", kind="error"), "an empty input: an error naming it (%s)" % said.errors)
checks.check(all(fetch(nothing, p).GetNumberOfPoints() == 0 for p in (0, 1, 3))
             and fetch(nothing, 2).GetNumberOfRows() == 0 and fetch(nothing, 4).GetNumberOfRows() == 0,
             "an empty input: empty outputs")
fit.Scale = -1.0
checks.check(fetch(fit, 0).GetNumberOfPoints() == 0, "Scale -1: empty output")

# State file: Scale 0.1 (mm to cm) and a finer mesh, saved, loaded in a fresh pvpython, compared.
fit.Scale = 0.1
fit.Resolution = 80
cm = rows(fit)[0]
checks.check(abs(cm["Length"] - 0.1 * length) < 0.01 * 0.1 * length, "Scale 0.1: the length in cm")
returncode = reload_in_fresh_pvpython(state, describe(fit), expected_file, arguments, __file__)
checks.check(returncode == 0, "the state file loads in a fresh pvpython with the same outputs")
checks.finish()
