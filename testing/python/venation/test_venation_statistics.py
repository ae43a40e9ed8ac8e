# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: VenationFilter's Statistics port (one row of network measures) and Areole histogram port, as users
read them, against numbers derived without the filter's measuring code:

- a W x L rectangular blade with N Parallel veins and no tertiaries: every primary leaves the base (0, 0) for its
  line x = u W, reaching it after the first of its L / step pieces (step L / 40 on this mesh, whose mean edge is
  longer: the growth's step is the mean edge clamped to [L / 400, L / 40]), and runs straight up to the apex edge.
  So by hand the total length is L + sum over the others of (sqrt((u W)^2 + step^2) + L - step), VLA that over W L,
  no areoles and no free ends, one branch point (the base, where all N meet), loopiness 1 (a tree), and the
  primaries' mean width PrimaryWidth L (1 + PrimaryTaper) / 2 (the width falls linearly along each vein);
- a paper mulberry leaf: VLA = the polylines' length (IntegrateAttributes) over the blade's area (MassProperties),
  the areole count from Euler's formula for the planar vein graph (faces = E - V + components), branch points and
  free ends (ends off the margin) counted on the output graph, loopiness from a minimum spanning forest (Kruskal)
  computed here, the histogram's counts summing to AreoleCount over AreoleHistogramBins contiguous bins, and the
  veins' field data telling the same numbers;
- a bad AreoleHistogramBins: an error naming it and every port empty.

    pvpython test_venation_statistics.py --plugin PlantMorph.so --work DIR
"""
import math
import os

from plantmorph_testing import Checks, Messages, load_plugin, parse_arguments

arguments = parse_arguments()

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints, VTK_DOUBLE  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData  # noqa: E402
from vtkmodules.vtkFiltersCore import vtkFeatureEdges, vtkMassProperties  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()


def close(a, b, tolerance=1e-9):
    return abs(a - b) <= tolerance * max(1.0, abs(a), abs(b))


def table(proxy, port):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, idx=port)


def row(statistics):
    return {statistics.GetColumnName(c): statistics.GetColumn(c).GetTuple1(0)
            for c in range(statistics.GetNumberOfColumns())}


def network(veins):
    """Unique segments (a, b) and each point's degree in them."""
    segments = set()
    lines = veins.GetLines()
    ids = vtk_to_numpy(lines.GetConnectivityArray())
    offsets = vtk_to_numpy(lines.GetOffsetsArray())
    for c in range(len(offsets) - 1):
        chain = ids[offsets[c]:offsets[c + 1]]
        for a, b in zip(chain[:-1], chain[1:]):
            if a != b:
                segments.add((min(a, b), max(a, b)))
    degree = numpy.zeros(veins.GetNumberOfPoints(), dtype=int)
    for a, b in segments:
        degree[a] += 1
        degree[b] += 1
    return sorted(segments), degree


def spanning_forest(points, segments):
    """Kruskal: the minimum spanning forest's length and the number of connected components of the used nodes."""
    parent = list(range(len(points)))

    def root(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x
    length = 0.0
    for a, b in sorted(segments, key=lambda s: numpy.linalg.norm(points[s[0]] - points[s[1]])):
        ra, rb = root(a), root(b)
        if ra != rb:
            parent[ra] = rb
            length += numpy.linalg.norm(points[a] - points[b])
    used = {a for s in segments for a in s}
    return length, len({root(a) for a in used})


# 1. By hand: a W x L rectangle, LeafUV = (x / W, y / L), Parallel veins straight from edge to edge.
W, L, N = 4.0, 10.0, 5
rectangle = vtkPolyData()
points = vtkPoints()
points.SetDataType(VTK_DOUBLE)
uv = vtkDoubleArray()
uv.SetName("LeafUV")
uv.SetNumberOfComponents(2)
NX, NY = 16, 20
for j in range(NY + 1):
    for i in range(NX + 1):
        u, v = -0.5 + i / NX, j / NY
        points.InsertNextPoint(u * W, v * L, 0.0)
        uv.InsertNextTuple2(u, v)
triangles = vtkCellArray()
for j in range(NY):
    for i in range(NX):
        a = j * (NX + 1) + i
        triangles.InsertNextCell(3, [a, a + 1, a + NX + 2])
        triangles.InsertNextCell(3, [a, a + NX + 2, a + NX + 1])
rectangle.SetPoints(points)
rectangle.SetPolys(triangles)
rectangle.GetPointData().AddArray(uv)
rectangle_file = os.path.join(arguments.work, "venation_statistics_rectangle.vtp")
writer = vtkXMLPolyDataWriter()
writer.SetInputData(rectangle)
writer.SetFileName(rectangle_file)
writer.Write()
blade = XMLPolyDataReader(FileName=[rectangle_file])
WIDTH, TAPER = 0.02, 0.4
parallel = VenationFilter(Input=blade, Preset="Custom", Pattern="Parallel", ParallelVeins=N, ParallelSpread=0.4,
                          Tertiary=0, PrimaryWidth=WIDTH, PrimaryTaper=TAPER)
s = row(table(parallel, 2))
checks.check(table(parallel, 2).GetNumberOfRows() == 1, "Statistics: one row per leaf")
STEP = L / 40
expected = L + sum(math.hypot(u * W, STEP) + L - STEP
                   for u in (0.4 * (2.0 * i / (N - 1) - 1.0) for i in range(N)) if u != 0.0)
checks.check(close(s["TotalLength"], expected) and close(s["LengthPrimary"], expected),
             "rectangle: total length %.12g = %.12g by hand" % (s["TotalLength"], expected))
checks.check(close(s["BladeArea"], W * L), "rectangle: blade area %.12g = W L" % s["BladeArea"])
checks.check(close(s["VLA"], expected / (W * L)), "rectangle: VLA %.12g = %.12g by hand"
             % (s["VLA"], expected / (W * L)))
checks.check(s["AreoleCount"] == 0 and s["BranchPoints"] == 1 and s["FreeEnds"] == 0,
             "rectangle: no areoles, one branch point, no free ends (%d, %d, %d)"
             % (s["AreoleCount"], s["BranchPoints"], s["FreeEnds"]))
checks.check(close(s["Loopiness"], 1.0), "rectangle: loopiness 1 (a forest)")
checks.check(close(s["MeanWidthPrimary"], WIDTH * L * (1 + TAPER) / 2, 1e-6),
             "rectangle: primaries' mean width %.9g = PrimaryWidth L (1 + taper) / 2 = %.9g"
             % (s["MeanWidthPrimary"], WIDTH * L * (1 + TAPER) / 2))
checks.check(s["LengthSecondary"] == 0 and s["MeanWidthSecondary"] == 0, "rectangle: no secondaries")
checks.check(table(parallel, 3).GetNumberOfRows() == 0, "rectangle: no areoles, an empty histogram")

# 2. Paper mulberry: the measures against the output graph, measured here.
leaf = LeafOutlineSource(Preset="Entire", Length=9.0, Resolution=60)
BINS = 12
mulberry = VenationFilter(Input=OutputPort(leaf, 0), Preset="Paper mulberry (paper 000 Fig. 10)", Seed=3,
                          AreoleHistogramBins=BINS)
mulberry.UpdatePipeline()
veins = servermanager.Fetch(mulberry, idx=0)
blade_data = servermanager.Fetch(mulberry, idx=1)
s = row(table(mulberry, 2))
xyz = vtk_to_numpy(veins.GetPoints().GetData()).astype(float)
segments, degree = network(veins)
length = IntegrateVariables(Input=OutputPort(mulberry, 0))
integrated = servermanager.Fetch(length)
total = integrated.GetCellData().GetArray("Length").GetValue(0)
mass = vtkMassProperties()
mass.SetInputData(blade_data)
mass.Update()
area = mass.GetSurfaceArea()
checks.check(close(s["BladeArea"], area, 1e-9), "mulberry: blade area %.12g = MassProperties' %.12g"
             % (s["BladeArea"], area))
checks.check(close(s["TotalLength"], total, 1e-9), "mulberry: total length %.12g = IntegrateVariables' %.12g"
             % (s["TotalLength"], total))
checks.check(close(s["VLA"], total / area, 1e-9), "mulberry: VLA %.12g = length / area %.12g"
             % (s["VLA"], total / area))
spanning, components = spanning_forest(xyz, segments)
used = int((degree > 0).sum())
euler = len(segments) - used + components
checks.check(s["AreoleCount"] == euler and euler > 50,
             "mulberry: %d areoles = E - V + C = %d - %d + %d" % (s["AreoleCount"], len(segments), used, components))
checks.check(close(s["Loopiness"], spanning / total, 1e-9) and s["Loopiness"] < 0.95,
             "mulberry: loopiness %.9g = spanning forest / total %.9g" % (s["Loopiness"], spanning / total))
checks.check(s["BranchPoints"] == int((degree >= 3).sum()), "mulberry: %d branch points = nodes of degree >= 3 (%d)"
             % (s["BranchPoints"], int((degree >= 3).sum())))
edges = vtkFeatureEdges()
edges.SetInputData(blade_data)
edges.BoundaryEdgesOn()
edges.FeatureEdgesOff()
edges.NonManifoldEdgesOff()
edges.ManifoldEdgesOff()
edges.Update()
margin = edges.GetOutput()
margin_points = vtk_to_numpy(margin.GetPoints().GetData()).astype(float)
margin_lines = vtk_to_numpy(margin.GetLines().GetConnectivityArray()).reshape(-1, 2)


def distance_to_margin(x):
    a, b = margin_points[margin_lines[:, 0]], margin_points[margin_lines[:, 1]]
    d = b - a
    t = numpy.clip(((x - a) * d).sum(axis=1) / numpy.maximum((d * d).sum(axis=1), 1e-300), 0.0, 1.0)
    return numpy.linalg.norm(a + t[:, None] * d - x, axis=1).min()


free = sum(1 for p in numpy.nonzero(degree == 1)[0] if distance_to_margin(xyz[p]) > 1e-6 * 9.0)
checks.check(s["FreeEnds"] == free, "mulberry: %d free ends = ends off the margin (%d)" % (s["FreeEnds"], free))
checks.check(close(s["BranchPointsPerArea"], s["BranchPoints"] / area, 1e-9)
             and close(s["FreeEndsPerArea"], s["FreeEnds"] / area, 1e-9), "mulberry: counts per area")
checks.check(close(s["LengthPrimary"] + s["LengthSecondary"] + s["LengthTertiary"] + s["LengthQuaternary"]
                   + s["LengthVeinlet"], s["TotalLength"], 1e-12), "mulberry: lengths per order sum to the total")
checks.check(s["LengthTertiary"] > 0 and s["LengthQuaternary"] > 0
             and s["MeanWidthTertiary"] >= s["MeanWidthQuaternary"] > 0,
             "mulberry: tertiaries (%.3g long, %.3g wide) and the finer quaternary reticulum (%.3g, %.3g)"
             % (s["LengthTertiary"], s["MeanWidthTertiary"], s["LengthQuaternary"], s["MeanWidthQuaternary"]))
checks.check(0 < s["AreoleAreaMedian"] and 0 < s["AreoleAreaMean"] and s["AreoleAreaCV"] > 0,
             "mulberry: areole mean %.4g, median %.4g, CV %.3g" % (s["AreoleAreaMean"], s["AreoleAreaMedian"],
                                                                  s["AreoleAreaCV"]))
histogram = table(mulberry, 3)
lower = vtk_to_numpy(histogram.GetColumnByName("BinLower"))
upper = vtk_to_numpy(histogram.GetColumnByName("BinUpper"))
count = vtk_to_numpy(histogram.GetColumnByName("Count"))
checks.check(histogram.GetNumberOfRows() == BINS, "histogram: AreoleHistogramBins = %d rows" % BINS)
checks.check(int(count.sum()) == s["AreoleCount"], "histogram: counts sum to AreoleCount (%d)" % int(count.sum()))
checks.check(numpy.all(lower[1:] == upper[:-1]) and numpy.all(upper > lower), "histogram: contiguous bins")
checks.check(count[0] > 0 and count[-1] > 0, "histogram: the smallest and the largest areole in the end bins")
checks.check(lower[0] <= s["AreoleAreaMedian"] <= upper[-1], "histogram: the median inside its range")
field = veins.GetFieldData()
checks.check(field.GetArray("PlantMorph.AreoleCount").GetValue(0) == s["AreoleCount"]
             and close(field.GetArray("PlantMorph.VeinDensity").GetValue(0), s["VLA"], 1e-15)
             and field.GetArray("PlantMorph.BranchPoints").GetValue(0) == s["BranchPoints"]
             and field.GetArray("PlantMorph.FreeEnds").GetValue(0) == s["FreeEnds"]
             and close(field.GetArray("PlantMorph.AreoleAreaStd").GetValue(0), s["AreoleAreaCV"] * s["AreoleAreaMean"]),
             "the veins' field data tells the Statistics port's numbers")

# 3. A bad bin count: an error naming it, every port empty.
mulberry.AreoleHistogramBins = 0
with Messages(mulberry) as messages:
    mulberry.UpdatePipeline()
checks.check(any("AreoleHistogramBins = 0 is outside the accepted range" in e for e in messages.errors),
             "AreoleHistogramBins 0: %s" % messages.errors)
checks.check(servermanager.Fetch(mulberry, idx=0).GetNumberOfPoints() == 0
             and table(mulberry, 2).GetNumberOfRows() == 0 and table(mulberry, 3).GetNumberOfRows() == 0,
             "AreoleHistogramBins 0: empty outputs")
checks.finish()
