# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: LeafFitFilter's petiole, base and axis, as users meet them.

The shipped sugar-beet scans (data/leaf-clouds/, millimetres) hold a petiole, a thin trail of points leaving the
blade: with the defaults it is found (PetioleLength in Traits, Region 5 on the Scan port, a Region 5 polyline on the
Outline port), the base (the midvein's first point) is at its junction with the blade, and the blade's Length
excludes it. A synthetic leaf (LeafOutlineSource's elliptic blade, 100 long, with a petiole of 30 leaving its base
downwards) gives the true junction, Length and PetioleLength; ApexPoint turns a blade without a petiole around.

    pvpython test_leaf_fit_petiole.py --plugin PlantMorph.so --work DIR
"""
import glob
import math
import os

from plantmorph_testing import Checks, load_plugin, parse_arguments

arguments = parse_arguments([])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonCore import vtkIdList, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkPolyData  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
HERE = os.path.dirname(os.path.abspath(__file__))
BEETS = sorted(glob.glob(os.path.join(HERE, "..", "..", "..", "data", "leaf-clouds", "sugarbeet_*.txt")))


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, idx=port)


def row(fit):
    table = fetch(fit, 2)
    names = [table.GetColumnName(c) for c in range(table.GetNumberOfColumns())]
    return {n: table.GetValueByName(0, n).ToDouble() for n in names} if table.GetNumberOfRows() else {}


def lines(outline, region):
    """The polylines of the Outline port with the given Region, as arrays of points."""
    regions = vtk_to_numpy(outline.GetCellData().GetArray("Region"))
    points = vtk_to_numpy(outline.GetPoints().GetData())
    found = []
    cells = outline.GetLines()
    cells.InitTraversal()
    ids = vtkIdList()
    for k in range(outline.GetNumberOfLines()):
        cells.GetNextCell(ids)
        if regions[k] == region:
            found.append(points[[ids.GetId(i) for i in range(ids.GetNumberOfIds())]])
    return found


def midvein_start(outline):
    midveins = lines(outline, 1)
    return midveins[0][0] if midveins else numpy.array([numpy.nan] * 3)


checks = Checks()
checks.check(len(BEETS) == 3, "the three sugar-beet scans are found")
for path in BEETS:
    name = os.path.basename(path)[:31]
    reader = LeafCloudReader(FileName=path)
    fit = LeafFitFilter(Input=reader)
    r = row(fit)
    outline, scan = fetch(fit, 1), fetch(fit, 3)
    checks.check(r.get("BaseFrom") == 2, name + ": the base comes from the petiole (BaseFrom 2)")
    checks.check(r.get("PetioleLength", 0) > 10, "%s: PetioleLength %.1f mm" % (name, r.get("PetioleLength", -1)))
    region = scan.GetPointData().GetArray("Region")
    checks.check(region is not None, name + ": Scan has Region")
    if region is not None:
        petiole = int((vtk_to_numpy(region) == 5).sum())
        checks.check(10 < petiole < 0.1 * scan.GetNumberOfPoints(), "%s: %d petiole points on Scan" % (name, petiole))
    stalks = lines(outline, 5)
    checks.check(len(stalks) == 1, name + ": one petiole polyline (Region 5) on Outline")
    if stalks:
        stalk = stalks[0]
        length = float(numpy.linalg.norm(numpy.diff(stalk, axis=0), axis=1).sum())
        checks.check(abs(length - r.get("PetioleLength", 0)) < 1e-6 * max(1.0, length),
                     name + ": the polyline is PetioleLength long")
        # The base is at the junction (within about a tenth of the blade's length: the sugar beet of 30 August 6.4 mm
        # from it, 0.12 of its 53 mm), the far end of the stalk is not.
        base = midvein_start(outline)
        gap = float(numpy.linalg.norm(base - stalk[0]))
        checks.check(gap < 0.125 * r.get("Length", 0), "%s: base %.1f mm from the junction (Length %.1f)"
                     % (name, gap, r.get("Length", 0)))
        checks.check(float(numpy.linalg.norm(base - stalk[-1])) > gap, name + ": the base is not the petiole's far end")
    Delete(fit)
    Delete(reader)


def synthetic(petiole):
    """Points of the elliptic blade (100 x 45, base at the origin, midvein along +Y) and a petiole 2 points wide
    leaving the base at 30 degrees below the blade's plane."""
    source = LeafOutlineSource(Model=2, BSplinePreset=1, BladeLength=50, BladeWidth=22.5, Resolution=100)
    blade = fetch(source)
    Delete(source)
    # Every blade triangle sampled uniformly by area (deterministic), the leaf scaled to 100 long.
    rng = numpy.random.default_rng(5)
    pts = 2.0 * vtk_to_numpy(blade.GetPoints().GetData())
    tri = vtk_to_numpy(blade.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    areas = 0.5 * numpy.linalg.norm(numpy.cross(b - a, c - a), axis=1)
    n = 6000
    pick = rng.choice(len(tri), size=n, p=areas / areas.sum())
    u, v = rng.random(n), rng.random(n)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    cloud = a[pick] + u[:, None] * (b[pick] - a[pick]) + v[:, None] * (c[pick] - a[pick])
    cloud[:, 2] += rng.normal(0.0, 0.1, n)
    length = float(pts[:, 1].max() - pts[:, 1].min())
    h = math.sqrt(areas.sum() / n)
    if petiole > 0:
        s = numpy.arange(0.5 * h, petiole, h)
        angle = math.radians(30.0)
        for offset in (-0.5 * h, 0.5 * h):
            stalk = numpy.stack([numpy.full_like(s, offset), -s * math.cos(angle), -s * math.sin(angle)], axis=1)
            cloud = numpy.vstack([cloud, stalk])
    polydata = vtkPolyData()
    points = vtkPoints()
    for p in cloud:
        points.InsertNextPoint(*p)
    polydata.SetPoints(points)
    producer = TrivialProducer()
    producer.GetClientSideObject().SetOutput(polydata)
    return producer, length


producer, length = synthetic(30.0)
fit = LeafFitFilter(Input=producer)
r = row(fit)
base = midvein_start(fetch(fit, 1))
checks.check(r.get("BaseFrom") == 2, "synthetic: base from the petiole")
checks.check(float(numpy.linalg.norm(base)) < 0.02 * length, "synthetic: base %s within 2 %% of the length of the "
             "junction (the origin)" % numpy.round(base, 2))
checks.check(abs(r.get("Length", 0) - length) < 0.01 * length, "synthetic: Length %.2f within 1 %% of %.2f"
             % (r.get("Length", 0), length))
checks.check(abs(r.get("PetioleLength", 0) - 30.0) < 1.5, "synthetic: PetioleLength %.2f within 5 %% of 30"
             % r.get("PetioleLength", 0))
Delete(fit)
Delete(producer)

# No petiole: the ellipse is symmetric end to end; ApexPoint says which end is the apex.
producer, length = synthetic(0.0)
fit = LeafFitFilter(Input=producer)
for apex_y in (length, 0.0):
    fit.UseApexPoint = 1
    fit.ApexPoint = [0.0, apex_y, 0.0]
    r = row(fit)
    base = midvein_start(fetch(fit, 1))
    checks.check(r.get("PetioleLength") == 0.0, "no petiole: PetioleLength 0")
    checks.check(abs(base[1] - (length - apex_y)) < 2.0, "ApexPoint at y=%g: the base at the other end (y=%.2f)"
                 % (apex_y, base[1]))
Delete(fit)
Delete(producer)
checks.finish()
