# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: LeafFitFilter on inputs of several leaves, as a plant scan gives them.

- Two flat 10 x 4 ellipses 3 units apart, no LeafIdArray: two rows of area 10 pi (not one invented leaf), a warning
  saying how many blades were found; the Plant port counts them.
- LeafId as the integer it is: ids 0 and 2^32 (int64 array) stay two leaves on every port; a fraction or NaN in a
  floating-point LeafId array is an error naming the array and the value, with empty outputs.
- One leaf that cannot be fitted (10 points) gets a row with Status 2 and the reason, a warning, and the other
  leaves' rows are what they are alone.
- Negative ids are points on no leaf: no row, the other leaves as alone, the Scan port keeps them (FitDistance NaN);
  an input whose ids are all negative is an error with empty outputs.
- The Plant table: three leaves tilted by known angles give the inclination classes and the beta distribution the
  method of moments gives on the Traits' own Inclination column (computed here independently).
- Units: LengthUnit mm, cm with Scale 0.1; PlantMorph.ColumnUnits in field data.
- EstimatedArea: two leaves give no plant shape, so each keeps its Area (AreaRule 3) and the Plant's
  TotalEstimatedLeafArea is TotalLeafArea (WholeLeaves 0).
- Leaf points on no leaf (LeafId -1, Organ 1): half an ellipse's points counted (UnassignedLeafPoints) and their area
  at the fitted leaves' points per area (UnassignedLeafArea, the half's within 5 %) added to TotalEstimatedLeafArea;
  without an Organ array, or with Organ 0 (wood), nothing is counted.
- LeafIdArray is a menu of the input's point arrays (None first); SurfaceSmoothing below 0.1 is refused.
- One leaf scanned by VirtualScanner along lines (its points much closer along a line than the lines are) is one
  leaf, not one per group of lines.
- Threads: pvpython starts vtkSMPTools on its Sequential backend; the filter's loops run on threads all the same,
  leave the process-wide backend as it was, and give the outputs of one thread (vtkSMPTools.Initialize(1)) bit for
  bit on three dense blades.

    pvpython test_leaf_fit_plant.py --plugin PlantMorph.so --work DIR
"""
import math

from plantmorph_testing import Checks, load_plugin, Messages, parse_arguments

arguments = parse_arguments()

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkPolyData  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()
random = numpy.random.default_rng(7)


def ellipse(centre, tilt=0.0, a=2.0, b=5.0, h=0.1):
    """A flat ellipse of semi-axes a (x) and b (y) sampled on a jittered grid, tilted by `tilt` degrees about x."""
    x, y = numpy.meshgrid(numpy.arange(-a, a + h, h), numpy.arange(-b, b + h, h))
    p = numpy.c_[x.ravel(), y.ravel()] + random.uniform(-0.03, 0.03, (x.size, 2))
    p = p[(p[:, 0] / a) ** 2 + (p[:, 1] / b) ** 2 <= 1.0]
    z = random.normal(0.0, 0.005, len(p))
    c, s = math.cos(math.radians(tilt)), math.sin(math.radians(tilt))
    return numpy.c_[p[:, 0], c * p[:, 1] - s * z, s * p[:, 1] + c * z] + numpy.asarray(centre)


def source(points, ids=None, dtype=None, organ=None):
    data = vtkPolyData()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(numpy.ascontiguousarray(points), deep=1))
    data.SetPoints(vtk_points)
    for name, values, kind in (("Leaf", ids, dtype), ("Organ", organ, numpy.int32)):
        if values is not None:
            array = numpy_to_vtk(numpy.ascontiguousarray(values, dtype=kind), deep=1)
            array.SetName(name)
            data.GetPointData().AddArray(array)
    producer = TrivialProducer()
    producer.GetClientSideObject().SetOutput(data)
    return producer


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, idx=port)


def rows(fit, port=2):
    table = fetch(fit, port)
    names = [table.GetColumnName(c) for c in range(table.GetNumberOfColumns())]
    return [{n: (table.GetColumnByName(n).GetValue(r) if table.GetColumnByName(n).IsA("vtkStringArray")
                 else table.GetValueByName(r, n).ToDouble()) for n in names} for r in range(table.GetNumberOfRows())]


def run(fit):
    with Messages(fit) as said:
        fit.UpdatePipeline()
    return said


AREA = 10.0 * math.pi
first, second = ellipse((0.0, 0.0, 0.0)), ellipse((7.0, 0.0, 0.0))
both = numpy.r_[first, second]

# Two blades, no LeafIdArray: two leaves.
fit = LeafFitFilter(Input=source(both))
said = run(fit)
traits = rows(fit)
checks.check(len(traits) == 2, "two blades without LeafIdArray: two rows (%d)" % len(traits))
checks.check(all(abs(r["Area"] / AREA - 1.0) < 0.02 for r in traits),
             "each of area 10 pi within 2 %%: %s" % [round(r["Area"], 2) for r in traits])
# An ellipse is the same at both ends: each row says its base is a guess (BaseFrom 3, Status 1), nothing else.
checks.check([r["LeafId"] for r in traits] == [0, 1] and all(
    r["Status"] == 1 and r["BaseFrom"] == 3 and "same at both ends" in r["Message"] and ";" not in r["Message"]
    for r in traits), "LeafId 0 and 1, Status 1 for the base's guess alone (%s)" % [r["Message"] for r in traits])
checks.check(said.said("2 separate blades", kind="warning"), "a warning says how many blades (%s)" % said.warnings)
scan_ids = vtk_to_numpy(fetch(fit, 3).GetPointData().GetArray("LeafId"))
checks.check(numpy.array_equal(scan_ids, numpy.r_[numpy.zeros(len(first)), numpy.ones(len(second))]),
             "Scan: each point's LeafId is its blade's")
plant = rows(fit, 4)
checks.check(len(plant) == 1 and plant[0]["LeafCount"] == 2 and plant[0]["FailedLeaves"] == 0,
             "Plant: one row, two leaves")
checks.check(abs(plant[0]["TotalLeafArea"] - sum(r["Area"] for r in traits)) < 1e-9
             and abs(plant[0]["MeanLeafArea"] - 0.5 * plant[0]["TotalLeafArea"]) < 1e-9, "Plant: total and mean area")
checks.check(traits[0]["LengthUnit"] == "mm" and plant[0]["LengthUnit"] == "mm", "LengthUnit mm by default")
# Two leaves give no plant shape (3 leaves seen whole are needed): each EstimatedArea is its Area, AreaRule 3.
checks.check(all(r["EstimatedArea"] == r["Area"] and r["AreaRule"] == 3 for r in traits)
             and plant[0]["TotalEstimatedLeafArea"] == plant[0]["TotalLeafArea"] and plant[0]["WholeLeaves"] == 0,
             "EstimatedArea: Area itself without a plant shape (%s)"
             % [(r["EstimatedArea"], r["AreaRule"]) for r in traits])
units = fetch(fit, 2).GetFieldData().GetAbstractArray("PlantMorph.ColumnUnits")
table = fetch(fit, 2)
unit_of = {table.GetColumnName(c): units.GetValue(c) for c in range(table.GetNumberOfColumns())}
checks.check(unit_of.get("Area") == "mm^2" and unit_of.get("Length") == "mm" and unit_of.get("Bending") == "degrees",
             "PlantMorph.ColumnUnits: %s" % {k: unit_of.get(k) for k in ("Area", "Length", "Bending")})
fit.Scale = 0.1
checks.check(rows(fit)[0]["LengthUnit"] == "cm", "Scale 0.1 on mm: LengthUnit cm")
Delete(fit)

# The LeafIdArray menu lists the input's point arrays.
ids = numpy.r_[numpy.zeros(len(first)), numpy.full(len(second), 2.0 ** 32)]
fit = LeafFitFilter(Input=source(both, ids, numpy.int64))
domain = fit.GetProperty("LeafIdArray").SMProperty.GetDomain("array_list")
menu = [domain.GetString(i) for i in range(domain.GetNumberOfStrings())]
checks.check(fit.LeafIdArray == "None" and "Leaf" in menu, "LeafIdArray: default None, menu %s" % menu)

# Ids 0 and 2^32 stay apart.
fit.LeafIdArray = "Leaf"
traits = rows(fit)
checks.check([r["LeafId"] for r in traits] == [0, 2 ** 32], "ids 0 and 2^32: two rows %s" % [
    r["LeafId"] for r in traits])
blade_ids = set(vtk_to_numpy(fetch(fit, 0).GetPointData().GetArray("LeafId")).tolist())
checks.check(blade_ids == {0, 2 ** 32}, "Blade LeafId 0 and 2^32: %s" % blade_ids)
alone = [rows(LeafFitFilter(Input=source(leaf)))[0] for leaf in (first, second)]
checks.check(all(abs(r["Area"] - a["Area"]) < 1e-9 for r, a in zip(traits, alone)),
             "each leaf's row is the leaf's alone")

# Fractions and NaN: errors naming the array and a value, empty outputs.
for value, word in ((0.4, "0.4"), (float("nan"), "nan")):
    bad_ids = ids.copy()
    bad_ids[5] = value
    bad = LeafFitFilter(Input=source(both, bad_ids, numpy.float64), LeafIdArray="Leaf")
    said = run(bad)
    checks.check(said.said("'Leaf'", word, kind="error") and fetch(bad, 2).GetNumberOfRows() == 0
                 and fetch(bad, 0).GetNumberOfPoints() == 0, "LeafId %s: an error naming the array and the value, "
                 "empty outputs (%s)" % (word, said.errors))
    Delete(bad)

# One leaf that cannot be fitted: its row says why, the others are fitted.
few = random.uniform(40.0, 41.0, (10, 3))
with_bad = LeafFitFilter(Input=source(numpy.r_[both, few], numpy.r_[ids, numpy.full(10, 5)], numpy.int64),
                         LeafIdArray="Leaf")
said = run(with_bad)
traits = rows(with_bad)
checks.check([r["LeafId"] for r in traits] == [0, 5, 2 ** 32], "three rows in LeafId order: %s" % [
    r["LeafId"] for r in traits])
checks.check(traits[1]["Status"] == 2 and "too few points" in traits[1]["Message"]
             and math.isnan(traits[1]["Area"]), "the bad leaf: Status 2, the reason, NaN traits")
checks.check(traits[0]["Area"] == alone[0]["Area"] and traits[2]["Area"] == alone[1]["Area"],
             "the other leaves fitted as alone")
checks.check(said.said("leaf 5", "too few points", kind="warning") and not said.errors,
             "a warning names the bad leaf, no error (%s %s)" % (said.warnings, said.errors))
checks.check(rows(with_bad, 4)[0]["LeafCount"] == 2 and rows(with_bad, 4)[0]["FailedLeaves"] == 1,
             "Plant: two leaves fitted, one failed")

# Negative ids are points on no leaf (PlantSegmentationFilter's LeafId -1): a stick of points between the blades
# with id -1 (and one with -7) is fitted with no leaf, the two leaves as alone; the Scan port keeps every point.
stick = numpy.c_[numpy.linspace(2.5, 4.5, 400), numpy.zeros(400), numpy.zeros(400)] + random.normal(0, 0.01, (400, 3))
off_ids = numpy.r_[ids, numpy.full(399, -1), -7]
off = LeafFitFilter(Input=source(numpy.r_[both, stick], off_ids, numpy.int64), LeafIdArray="Leaf")
said = run(off)
traits = rows(off)
checks.check([r["LeafId"] for r in traits] == [0, 2 ** 32] and not said.errors
             and all(abs(r["Area"] - a["Area"]) < 1e-9 for r, a in zip(traits, alone)),
             "negative ids: no row, the two leaves as alone (%s, %s)" % ([r["LeafId"] for r in traits], said.errors))
scan = fetch(off, 3)
scan_ids = vtk_to_numpy(scan.GetPointData().GetArray("LeafId"))
distance = vtk_to_numpy(scan.GetPointData().GetArray("FitDistance"))
checks.check(numpy.array_equal(scan_ids, off_ids) and bool(numpy.all(numpy.isnan(distance[len(both):])))
             and bool(numpy.all(numpy.isfinite(distance[:len(both)]))),
             "Scan: every point, its id kept, FitDistance NaN on no leaf")
checks.check(rows(off, 4)[0]["LeafCount"] == 2 and rows(off, 4)[0]["UnassignedLeafPoints"] == 0
             and rows(off, 4)[0]["UnassignedLeafArea"] == 0, "Plant: two leaves; no Organ array, no point on no leaf "
             "counted as leaf (it may be wood)")
Delete(off)
# With PlantMorph's Organ array: the stick is wood (Organ 0), and half of a third ellipse (2 x 5, on the same grid)
# is leaf points with LeafId -1 (Organ 1), a leaf the segmentation gave no LeafId. Their area at the two fitted
# leaves' points per area is the half ellipse's (5 pi) within the grid's jitter, and the estimated total holds it.
half = ellipse((0.0, 0.0, 20.0))
half = half[half[:, 0] <= 0.0]
organ = numpy.r_[numpy.ones(len(both)), numpy.zeros(len(stick)), numpy.ones(len(half))]
with_organ = LeafFitFilter(Input=source(numpy.r_[both, stick, half], numpy.r_[off_ids, numpy.full(len(half), -1)],
                                        numpy.int64, organ), LeafIdArray="Leaf")
plant = rows(with_organ, 4)[0]
traits = rows(with_organ)
density = sum(r["Points"] for r in traits) / plant["TotalLeafArea"]
checks.check(plant["UnassignedLeafPoints"] == len(half)
             and abs(plant["UnassignedLeafArea"] - len(half) / density) < 1e-9 * plant["UnassignedLeafArea"]
             and abs(plant["UnassignedLeafArea"] / (5.0 * math.pi) - 1.0) < 0.05
             and abs(plant["TotalEstimatedLeafArea"] - sum(r["EstimatedArea"] for r in traits)
                     - plant["UnassignedLeafArea"]) < 1e-9 * plant["TotalEstimatedLeafArea"]
             and [r["LeafId"] for r in traits] == [0, 2 ** 32],
             "Organ 1 on no leaf: UnassignedLeafPoints %d of %d, UnassignedLeafArea %.3f against 5 pi, in the "
             "estimated total" % (plant["UnassignedLeafPoints"], len(half), plant["UnassignedLeafArea"]))
Delete(with_organ)
none = LeafFitFilter(Input=source(stick, numpy.full(400, -1), numpy.int64), LeafIdArray="Leaf")
said = run(none)
checks.check(said.said("LeafIdArray", "no point has a LeafId of 0 or more", kind="error")
             and fetch(none, 2).GetNumberOfRows() == 0 and fetch(none, 3).GetNumberOfPoints() == 0,
             "every id negative: an error, empty outputs (%s)" % said.errors)
Delete(none)
Delete(with_bad)

# A plant of three leaves tilted by 15, 35 and 65 degrees: the inclination distribution.
tilts = [15.0, 35.0, 65.0]
plant_points = numpy.r_[tuple(ellipse((20.0 * k, 0.0, 0.0), tilt) for k, tilt in enumerate(tilts))]
fit = LeafFitFilter(Input=source(plant_points))
traits = rows(fit)
angles = numpy.array([r["Inclination"] for r in traits])
checks.check(len(traits) == 3 and numpy.allclose(angles, tilts, atol=1.0), "inclinations %s" % angles)
plant = rows(fit, 4)[0]
t = angles / 90.0
common = t.mean() * (1.0 - t.mean()) / t.var() - 1.0
checks.check(abs(plant["InclinationBetaNu"] - t.mean() * common) < 1e-9
             and abs(plant["InclinationBetaMu"] - (1.0 - t.mean()) * common) < 1e-9,
             "beta by the method of moments: mu %.4f nu %.4f" % (plant["InclinationBetaMu"], plant["InclinationBetaNu"]))
classes = [plant["Inclination%d_%d" % (10 * k, 10 * k + 10)] for k in range(9)]
checks.check(numpy.allclose(classes, [0, 1 / 3, 0, 1 / 3, 0, 0, 1 / 3, 0, 0]), "inclination classes %s" % classes)
checks.check(abs(plant["MeanLeafInclination"] - angles.mean()) < 1e-9, "mean inclination")
# One leaf scanned by VirtualScanner (a line pattern: points much closer along a line than the lines are) is one
# leaf: one row, no separation warning, a blade of a few thousand vertices (it was cut into its 14 groups of lines,
# 1.05 million blade points), its Area within 10 % of the scanned leaf's (the scan misses the narrow tip).
leaf = LeafOutlineSource(Resolution=12)
scanned = LeafFitFilter(Input=VirtualScanner(Input=leaf, Resolution=[60, 40]))
said = run(scanned)
traits = rows(scanned)
blade_points = fetch(scanned).GetNumberOfPoints()
truth = IntegrateVariables(Input=leaf)
truth_area = fetch(truth).GetCellData().GetArray("Area").GetValue(0)
checks.check(len(traits) == 1 and not said.said("separate blades"), "a line-scanned leaf: one row (%d), %s" % (
    len(traits), said.warnings))
checks.check(1000 < blade_points < 50000, "a line-scanned leaf: %d blade points" % blade_points)
checks.check(abs(traits[0]["Area"] / truth_area - 1.0) < 0.1, "a line-scanned leaf: Area %g, the leaf's %g" % (
    traits[0]["Area"], truth_area))
# Coverage in the spacing across the lines (the blade between two lines is covered), so no Coverage warning. The
# scanner, 1 above the leaf's plane and 5 away, sees it at a grazing angle: its lines lie far apart at the far end,
# and the one warning says the scan samples the blade unevenly.
checks.check(traits[0]["Coverage"] > 0.95 and traits[0]["Status"] == 1 and "unevenly" in traits[0]["Message"]
             and "Coverage" not in traits[0]["Message"], "a line-scanned leaf: Coverage %g, %s" % (
    traits[0]["Coverage"], traits[0]["Message"]))
# SurfaceSmoothing below 0.1 lets the surface leave the points: refused.
fit.SurfaceSmoothing = 0.0
said = run(fit)
checks.check(said.said("SurfaceSmoothing", kind="error") and fetch(fit, 2).GetNumberOfRows() == 0,
             "SurfaceSmoothing 0: an error naming it (%s)" % said.errors)

# Threads against one thread, bit for bit: three dense blades (1.5 x 10^5 points, so that the sorts, the grids and
# the joins of the cut into blades run in many pieces), no LeafIdArray.
from vtkmodules.vtkCommonCore import vtkSMPTools  # noqa: E402

dense = numpy.r_[ellipse((0.0, 0.0, 0.0), h=0.025), ellipse((7.0, 0.0, 0.0), tilt=30.0, h=0.025),
                 ellipse((0.0, 14.0, 0.0), h=0.025)]


def every_output():
    """Every port's points, point arrays and table columns of LeafFitFilter on `dense`, as numpy arrays."""
    fit = LeafFitFilter(Input=source(dense))
    fit.UpdatePipeline()
    found = {}
    for port in range(5):
        data = fetch(fit, port)
        if data.IsA("vtkTable"):
            for c in range(data.GetNumberOfColumns()):
                column = data.GetColumn(c)
                found[(port, data.GetColumnName(c))] = (
                    [column.GetValue(r) for r in range(column.GetNumberOfTuples())] if column.IsA("vtkStringArray")
                    else vtk_to_numpy(column).copy())
            continue
        found[(port, "points")] = vtk_to_numpy(data.GetPoints().GetData()).copy()
        arrays = data.GetPointData()
        for a in range(arrays.GetNumberOfArrays()):
            found[(port, arrays.GetArrayName(a))] = vtk_to_numpy(arrays.GetArray(a)).copy()
    Delete(fit)
    return found


backend = vtkSMPTools.GetBackend()
threaded = every_output()
vtkSMPTools.Initialize(1)
one = every_output()
vtkSMPTools.Initialize(0)
checks.check(vtkSMPTools.GetBackend() == backend, "the process-wide backend stays %s" % backend)
checks.check(len(threaded[(2, "LeafId")]) == 3, "three dense blades: three rows (%d)" % len(threaded[(2, "LeafId")]))


def same(a, b):
    """Equal bit for bit (NaN included): the same text, or the same type, shape and bytes."""
    if isinstance(a, list):
        return a == b
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


differ = [key for key in threaded if key not in one or not same(threaded[key], one[key])]
checks.check(threaded.keys() == one.keys() and not differ and len(threaded) > 10,
             "threads and one thread: every output equal bit for bit (%d arrays; differ: %s)" % (len(threaded), differ))
checks.finish()
