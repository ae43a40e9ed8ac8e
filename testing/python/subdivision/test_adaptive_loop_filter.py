# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: AdaptiveLoopFilter as users build it. LeafOutlineSource -> (Calculator bend) -> AdaptiveLoopFilter:
the proxy's label and defaults, a flat blade left alone, uniform Loop counts (4^L), adaptive counts between, the
data contract's arrays interpolated (LeafUV, TCoords active, Region codes, unit Normals, cell Region), the Fixed rule
keeping margin and midvein points, triangle counts per level in field data, a conforming mesh, and bad properties
giving an empty output. Nothing is rendered."""
import collections
import math

from plantmorph_testing import Checks, load_plugin, parse_arguments

from paraview.simple import *  # noqa: F401,F403 (the pvpython way)
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy

arguments = parse_arguments()
load_plugin(arguments.plugin, globals())
checks = Checks()


def edge_use(data):
    """Undirected edge -> number of triangles using it."""
    cells = vtk_to_numpy(data.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    use = collections.Counter()
    for a, b, c in cells.tolist():
        for p, q in ((a, b), (b, c), (c, a)):
            use[(min(p, q), max(p, q))] += 1
    return use


def per_level(data, name):
    array = data.GetFieldData().GetArray(name)
    return [int(array.GetValue(i)) for i in range(array.GetNumberOfTuples())] if array else None


# The ginkgo of paper 000's b_y = 5: its blade is 5 (1.6 + 0.05 sin(-1.5)) = 7.75 long from base to apex (Length is
# the blade's length); the bend below is sized for it.
leaf = LeafOutlineSource(Preset="Ginkgo", Length=5.0 * (1.6 + 0.05 * math.sin(-1.5)), Resolution=30)
flat_blade = servermanager.Fetch(leaf)
n_in = flat_blade.GetNumberOfCells()

# The proxy: label, menu name, defaults.
loop = AdaptiveLoopFilter(Input=leaf)
checks.check(loop.GetXMLLabel() == "Adaptive Loop Filter", "label is 'Adaptive Loop Filter': %s" % loop.GetXMLLabel())
checks.check(loop.MaximumLevel == 2 and loop.EdgeAngleThreshold == 170 and abs(loop.FlatnessThreshold - 0.999) < 1e-12
             and loop.FeatureRule == "Fixed" and loop.MidveinFeatures == 1
             and loop.RefinementRule == "Dihedral angle" and abs(loop.ErrorTolerance - 0.001) < 1e-15,
             "defaults: MaximumLevel 2, EdgeAngleThreshold 170, FlatnessThreshold 0.999, Fixed, midvein features, "
             "Dihedral angle rule, ErrorTolerance 0.001")

# A flat blade has nothing to smooth: output = input, one entry per level list.
out = servermanager.Fetch(loop)
checks.check(out.GetNumberOfCells() == n_in and out.GetNumberOfPoints() == flat_blade.GetNumberOfPoints(),
             "flat blade left alone (%d -> %d triangles)" % (n_in, out.GetNumberOfCells()))
checks.check(per_level(out, "AdaptiveLoop.TrianglesPerLevel") == [n_in], "flat blade: no level applied")
same_points = (vtk_to_numpy(out.GetPoints().GetData()) == vtk_to_numpy(flat_blade.GetPoints().GetData())).all()
checks.check(bool(same_points), "flat blade: points bit-identical")

# Bend the blade (Calculator keeps every array) so the adaptive rules have something to do.
bent = Calculator(Input=leaf, CoordinateResults=1,
                  Function="coordsX*iHat + coordsY*jHat + (0.6*sin(0.8*coordsX)*cos(0.5*coordsY) + 0.05*coordsX^2)*kHat")
bent_blade = servermanager.Fetch(bent)
checks.check(bent_blade.GetNumberOfCells() == n_in and bent_blade.GetBounds()[5] - bent_blade.GetBounds()[4] > 0.3,
             "the Calculator bends the blade")
loop.Input = bent

# Uniform Loop: 4^L triangles per level.
loop.EdgeAngleThreshold = 180
loop.FlatnessThreshold = 1
loop.FeatureRule = "Loop"
loop.MaximumLevel = 3
uniform = servermanager.Fetch(loop)
checks.check(per_level(uniform, "AdaptiveLoop.TrianglesPerLevel") == [n_in, 4 * n_in, 16 * n_in, 64 * n_in],
             "uniform: 4^L triangles per level %s" % per_level(uniform, "AdaptiveLoop.TrianglesPerLevel"))
checks.check(uniform.GetNumberOfCells() == 64 * n_in, "uniform: 64x triangles after 3 levels")

# Adaptive (defaults but three levels): between the input and uniform, with the data contract's arrays.
loop.EdgeAngleThreshold = 176
loop.FlatnessThreshold = 0.998
loop.FeatureRule = "Fixed"
adaptive = servermanager.Fetch(loop)
counts = per_level(adaptive, "AdaptiveLoop.TrianglesPerLevel")
checks.check(counts is not None and counts[0] == n_in and counts[-1] == adaptive.GetNumberOfCells(),
             "adaptive: counts per level in field data %s" % counts)
checks.check(n_in < adaptive.GetNumberOfCells() < 64 * n_in,
             "adaptive: %d triangles, between %d and %d" % (adaptive.GetNumberOfCells(), n_in, 64 * n_in))
points_per_level = per_level(adaptive, "AdaptiveLoop.PointsPerLevel")
checks.check(points_per_level[-1] == adaptive.GetNumberOfPoints(), "adaptive: points per level in field data")
pd = adaptive.GetPointData()
n = adaptive.GetNumberOfPoints()
uv = vtk_to_numpy(pd.GetArray("LeafUV"))
checks.check(uv.shape == (n, 2) and pd.GetArray("LeafUV").GetDataType() == 11, "LeafUV: double x2 on every point")
checks.check(uv[:, 0].min() >= -0.5 - 1e-9 and uv[:, 0].max() <= 0.5 + 1e-9 and uv[:, 1].min() >= -1e-9
             and uv[:, 1].max() <= 1 + 1e-9, "LeafUV stays in the canonical leaf")
tcoords = pd.GetTCoords()
checks.check(tcoords is not None and tcoords.GetName() == "TCoords" and tcoords.GetDataType() == 10,
             "TCoords: float, still the active texture coordinates")
region = vtk_to_numpy(pd.GetArray("Region"))
checks.check(set(region.tolist()) == {0, 1, 4}, "Region codes %s" % sorted(set(region.tolist())))
normals = vtk_to_numpy(pd.GetNormals())
checks.check(abs((normals ** 2).sum(axis=1) - 1).max() < 1e-5, "Normals: active and unit length")
cell_region = adaptive.GetCellData().GetArray("Region")
checks.check(cell_region is not None and cell_region.GetNumberOfTuples() == adaptive.GetNumberOfCells(),
             "cell Region inherited by every triangle")
checks.check(adaptive.GetPoints().GetDataType() == bent_blade.GetPoints().GetDataType(), "points keep their precision")
use = edge_use(adaptive)
checks.check(set(use.values()) <= {1, 2}, "conforming: every edge in one or two triangles")
boundary_edges = sum(1 for count in use.values() if count == 1)
checks.check(boundary_edges == sum(1 for count in edge_use(bent_blade).values() if count == 1),
             "Fixed: the margin keeps its edges (%d boundary edges)" % boundary_edges)

# Fixed rule: margin and midvein points (Region 4 and 1) are bit-identical, and there are no new ones.
in_points = vtk_to_numpy(bent_blade.GetPoints().GetData())
in_region = vtk_to_numpy(bent_blade.GetPointData().GetArray("Region"))
out_points = vtk_to_numpy(adaptive.GetPoints().GetData())
feature = (in_region == 1) | (in_region == 4)
checks.check(bool((out_points[:len(in_points)][feature] == in_points[feature]).all()),
             "Fixed: margin and midvein points bit-identical")
checks.check(int(((region == 1) | (region == 4)).sum()) == int(feature.sum()), "Fixed: no new margin or midvein point")

# The Surface error rule (not in the paper): between the input and uniform mode, conforming, margin kept; tolerance 0
# is uniform mode with the same feature rule.
loop.RefinementRule = "Surface error"
loop.ErrorTolerance = 0.002
by_error = servermanager.Fetch(loop)
n_uniform_fixed = 64 * n_in  # three levels; an upper bound: Fixed never splits the margin
checks.check(n_in < by_error.GetNumberOfCells() < n_uniform_fixed,
             "Surface error: %d triangles, between %d and %d" % (by_error.GetNumberOfCells(), n_in, n_uniform_fixed))
checks.check(set(edge_use(by_error).values()) <= {1, 2}, "Surface error: conforming")
by_error_points = vtk_to_numpy(by_error.GetPoints().GetData())
checks.check(bool((by_error_points[:len(in_points)][feature] == in_points[feature]).all()),
             "Surface error, Fixed: margin and midvein points bit-identical")
loop.ErrorTolerance = 0
zero = servermanager.Fetch(loop)
loop.RefinementRule = "Dihedral angle"
loop.EdgeAngleThreshold = 180
loop.FlatnessThreshold = 1
uniform_fixed = servermanager.Fetch(loop)
checks.check(zero.GetNumberOfCells() == uniform_fixed.GetNumberOfCells() and bool(
    (vtk_to_numpy(zero.GetPoints().GetData()) == vtk_to_numpy(uniform_fixed.GetPoints().GetData())).all()),
             "Surface error, tolerance 0: uniform mode's points")
loop.FlatnessThreshold = 0.998

# The Chord error rule (not in the paper, anisotropic): the same guarantees through the proxy.
loop.RefinementRule = "Chord error"
loop.ErrorTolerance = 0.002
by_chord = servermanager.Fetch(loop)
checks.check(n_in < by_chord.GetNumberOfCells() < n_uniform_fixed,
             "Chord error: %d triangles, between %d and %d" % (by_chord.GetNumberOfCells(), n_in, n_uniform_fixed))
checks.check(set(edge_use(by_chord).values()) <= {1, 2}, "Chord error: conforming")
by_chord_points = vtk_to_numpy(by_chord.GetPoints().GetData())
checks.check(bool((by_chord_points[:len(in_points)][feature] == in_points[feature]).all()),
             "Chord error, Fixed: margin and midvein points bit-identical")
loop.RefinementRule = "Dihedral angle"

# Bad properties: an error and an empty output (ParaView prints the error; the script carries on).
loop.EdgeAngleThreshold = 200
bad = servermanager.Fetch(loop)
checks.check(bad.GetNumberOfPoints() == 0 and bad.GetNumberOfCells() == 0, "EdgeAngleThreshold 200: empty output")
loop.EdgeAngleThreshold = 176
loop.MaximumLevel = 11
bad = servermanager.Fetch(loop)
checks.check(bad.GetNumberOfPoints() == 0, "MaximumLevel 11: empty output")
loop.MaximumLevel = 2
loop.RefinementRule = "Surface error"
loop.ErrorTolerance = -1
bad = servermanager.Fetch(loop)
checks.check(bad.GetNumberOfPoints() == 0, "ErrorTolerance -1: empty output")
loop.RefinementRule = "Dihedral angle"
loop.ErrorTolerance = 0.001
good = servermanager.Fetch(loop)
checks.check(good.GetNumberOfCells() > n_in, "valid again after the error")

checks.finish()
