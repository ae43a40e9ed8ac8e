# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: LeafOutlineSource as users build it. Every preset yields a blade and an outline with the data contract's
arrays; bad properties give an error and empty outputs."""
from plantmorph_testing import Checks, load_plugin, parse_arguments

from paraview.simple import *  # noqa: F401,F403 (the pvpython way)
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy

arguments = parse_arguments()
load_plugin(arguments.plugin, globals())
checks = Checks()

PRESETS = ["Custom", "Ginkgo", "Entire", "Serrate", "Lobed", "Parted", "AcuteBaseAcuteApex",
           "RoundedBaseAcuminateApex", "CordateBaseRoundedApex", "AcuminateBaseEmarginateApex"]

leaf = LeafOutlineSource()
checks.check(leaf.Preset == "Ginkgo" and leaf.Model == "Deformed rectangle" and leaf.Length == 5.0 and leaf.Resolution == 60 and leaf.MeshQuality == "Quality",
             "defaults: Ginkgo, Length 5, Resolution 60, quality mesh")
LABELS = ["Custom", "Ginkgo", "Entire", "Serrate", "Lobed", "Parted", "Acute base, acute apex",
          "Rounded base, acuminate apex", "Cordate base, rounded apex", "Acuminate base, emarginate apex"]
for preset in range(1, 10):
    for quality in (0, 1):
        # The drop-down's labels, as a pvpython user types them.
        leaf.Preset = LABELS[preset]
        leaf.MeshQuality = ["Paper", "Quality"][quality]
        leaf.Resolution = 30
        leaf.UpdatePipeline()
        blade = servermanager.Fetch(leaf)
        name = "%s/%s" % (PRESETS[preset], "quality" if quality else "paper")
        checks.check(blade.GetNumberOfPolys() > 50 and blade.GetNumberOfPolys() == blade.GetNumberOfCells(),
                     name + ": blade is triangles")
        pd = blade.GetPointData()
        uv = vtk_to_numpy(pd.GetArray("LeafUV"))
        checks.check(uv.shape == (blade.GetNumberOfPoints(), 2), name + ": LeafUV on every point")
        checks.check(uv[:, 0].min() >= -0.5 and uv[:, 0].max() <= 0.5 and uv[:, 1].min() >= 0
                     and uv[:, 1].max() <= 1, name + ": LeafUV in range")
        tcoords = pd.GetTCoords()
        checks.check(tcoords is not None and tcoords.GetName() == "TCoords", name + ": TCoords active")
        checks.check(tcoords.GetRange(0) == (0.0, 1.0) and tcoords.GetRange(1) == (0.0, 1.0),
                     name + ": TCoords span [0, 1]")
        region = vtk_to_numpy(pd.GetArray("Region"))
        # Paper mode has no interior points: only midvein (1) and margin (4).
        expected = {0, 1, 4} if quality else {1, 4}
        checks.check(set(region.tolist()) == expected,
                     name + ": Region codes %s, expected %s" % (sorted(set(region.tolist())), sorted(expected)))
        checks.check(pd.GetNormals() is not None, name + ": normals")
        checks.check(blade.GetFieldData().GetAbstractArray("PlantMorph.Preset").GetValue(0) == PRESETS[preset],
                     name + ": preset in field data")

        # Port 1 through a pass-through filter, as a user would connect it.
        pass_through = PassArrays(Input=OutputPort(leaf, 1))
        outline = servermanager.Fetch(pass_through)
        checks.check(outline.GetNumberOfLines() == 3, name + ": outline has 3 polylines")
        regions = vtk_to_numpy(outline.GetCellData().GetArray("Region")).tolist()
        checks.check(regions == [4, 4, 1], name + ": outline regions %s" % regions)
        Delete(pass_through)

# Space-curve model (paper 002): every figure preset yields a blade and an outline; Figs. 5 and 6 are 3-D.
space = LeafOutlineSource(Model="Space curve", Resolution=30)
for figure in range(1, 7):
    space.SpaceCurvePreset = "Paper 002 Fig. %d" % figure
    space.UpdatePipeline()
    blade = servermanager.Fetch(space)
    name = "paper 002 Fig. %d" % figure
    checks.check(blade.GetNumberOfPolys() > 100, name + ": blade has triangles")
    checks.check(blade.GetFieldData().GetAbstractArray("PlantMorph.Model").GetValue(0) == "SpaceCurve",
                 name + ": model in field data")
    uv = vtk_to_numpy(blade.GetPointData().GetArray("LeafUV"))
    checks.check(uv[:, 0].min() == -0.5 and uv[:, 0].max() == 0.5 and uv[:, 1].min() == 0 and uv[:, 1].max() == 1,
                 name + ": LeafUV spans the canonical leaf")
    depth = blade.GetBounds()[5] - blade.GetBounds()[4]
    checks.check((depth > 0.1) == (figure >= 5), name + ": 3-D exactly when it has torsion (depth %g)" % depth)
    outline = servermanager.Fetch(PassArrays(Input=OutputPort(space, 1)))
    checks.check(outline.GetNumberOfLines() == 3, name + ": outline has 3 polylines")

# Palmate leaves (paper 002 Fig. 8): the presets, and custom lobes from the properties. The Outline port carries every
# lobe's midvein after the margins and lobe 1's midvein.
for lobes in (3, 5):
    space.SpaceCurvePreset = "Paper 002 Fig. 8, %d lobes" % lobes
    space.MeshQuality = "Quality"
    space.UpdatePipeline()
    blade = servermanager.Fetch(space)
    name = "paper 002 Fig. 8, %d lobes" % lobes
    checks.check(blade.GetNumberOfPolys() > 500, name + ": blade has triangles")
    checks.check(blade.GetFieldData().GetArray("PlantMorph.Lobes").GetValue(0) == lobes, name + ": lobes in field data")
    uv = vtk_to_numpy(blade.GetPointData().GetArray("LeafUV"))
    checks.check(uv[:, 0].min() >= -0.5 and uv[:, 0].max() <= 0.5 and uv[:, 1].min() == 0 and uv[:, 1].max() == 1,
                 name + ": LeafUV in range")
    bounds = blade.GetBounds()
    checks.check(abs(bounds[0] + bounds[1]) < 1e-9 and bounds[1] - bounds[0] > bounds[3] - bounds[2],
                 name + ": symmetric and broader than long")
    outline = servermanager.Fetch(PassArrays(Input=OutputPort(space, 1)))
    regions = vtk_to_numpy(outline.GetCellData().GetArray("Region")).tolist()
    checks.check(regions == [4, 4] + [1] * lobes, name + ": outline regions %s" % regions)
space.SpaceCurvePreset = "Custom"
space.CurvatureFunction = "Triangular"
space.CurvatureMu = 3.0
space.CurvatureLambda = 0.5
space.Lobes = 3
space.LobeStart = 0.3
space.LobeAngle = 35.0
space.LobeScale = 0.7
space.UpdatePipeline()
blade = servermanager.Fetch(space)
checks.check(blade.GetNumberOfPolys() > 500 and blade.GetFieldData().GetArray("PlantMorph.LobeAngle").GetValue(0) == 35.0,
             "custom palmate leaf from the Lobe properties")
space.LobeAngle = 95.0
space.UpdatePipeline()
checks.check(servermanager.Fetch(space).GetNumberOfPoints() == 0, "LobeAngle 95: error, empty blade")
space.LobeAngle = 35.0
space.TorsionEta = 2.0
space.UpdatePipeline()
checks.check(servermanager.Fetch(space).GetNumberOfPoints() == 0, "palmate with torsion: error, empty blade")
Delete(space)

# B-spline model (paper 003): every preset, and control points typed in.
spline = LeafOutlineSource(Model="B-spline", Resolution=30)
for preset in ("Elliptic", "Cucumber", "Pin oak"):
    spline.BSplinePreset = preset
    spline.UpdatePipeline()
    blade = servermanager.Fetch(spline)
    checks.check(blade.GetNumberOfPolys() > 100, "B-spline %s: blade has triangles" % preset)
    checks.check(blade.GetFieldData().GetAbstractArray("PlantMorph.Model").GetValue(0) == "BSpline",
                 "B-spline %s: model in field data" % preset)
spline.BSplinePreset = "Custom"
spline.MidveinPoints = [0, 0, 0, 0, 5, 0]
spline.LeftMarginPoints = [-2, 2.5, 0]
spline.RightMarginPoints = [2, 2, 0, 1.5, 4, 0]
spline.UpdatePipeline()
blade = servermanager.Fetch(spline)
checks.check(blade.GetNumberOfPolys() > 50 and abs(blade.GetBounds()[3] - 5.0) < 1e-12,
             "B-spline custom control points: blade up to the apex")

# The tracing recipe (docs/tracing-a-leaf-photo.md): three Poly Line sources appended in the order left margin,
# right margin, midvein drive the B-spline model through the ControlPoints input (BSplinePreset "ControlPoints input").
left = PolyLineSource(Points=[0, 0, 0, -2, 2, 0, -1.5, 4.5, 0, 0, 6, 0])
right = PolyLineSource(Points=[0, 0, 0, 2.2, 2.5, 0, 0, 6, 0])
midvein = PolyLineSource(Points=[0, 0, 0, 0.3, 3, 0, 0, 6, 0])
traced = LeafOutlineSource(ControlPoints=AppendGeometry(Input=[left, right, midvein]), Model="B-spline",
                           BSplinePreset="ControlPoints input", Resolution=30)
traced.UpdatePipeline()
blade = servermanager.Fetch(traced)
checks.check(blade.GetFieldData().GetAbstractArray("PlantMorph.Preset").GetValue(0) == "ControlPointsInput",
             "traced polylines drive the leaf")
bounds = blade.GetBounds()
checks.check(abs(bounds[3] - 6.0) < 1e-6 and bounds[0] < -1.9 and bounds[1] > 2.1,
             "traced leaf spans the traced points: bounds %s" % (bounds,))

# Custom terms through the property, as in the GUI's table: eq. (1) rows give the ginkgo leaf bit for bit.
leaf.Preset = "Ginkgo"
leaf.MeshQuality = "Quality"
leaf.Resolution = 40
leaf.UpdatePipeline()
ginkgo = servermanager.Fetch(leaf)
custom = LeafOutlineSource(Preset="Custom", Width=5.5, Length=5.0, Resolution=40,
                           Terms=[0, 1, 1.1, 1, 1, 1, -1.5707963267948966,
                                  1, 1, 0.05, 2, 11, 0, -1.5,
                                  1, 1, -0.6, 2, 1, 0, -1.5707963267948966])
custom.UpdatePipeline()
custom_data = servermanager.Fetch(custom)
checks.check(custom_data.GetNumberOfPoints() == ginkgo.GetNumberOfPoints(), "custom eq. (1) = ginkgo preset")
difference = abs(vtk_to_numpy(custom_data.GetPoints().GetData()) - vtk_to_numpy(ginkgo.GetPoints().GetData())).max()
checks.check(difference < 1e-12, "custom eq. (1) points = ginkgo preset points (max difference %g)" % difference)

# Bad input: an error and empty outputs, never a crash.
bad = LeafOutlineSource(Resolution=1)
bad.UpdatePipeline()
checks.check(servermanager.Fetch(bad).GetNumberOfPoints() == 0, "Resolution 1: empty blade")
bad.Resolution = 30
bad.Preset = "Custom"
bad.Terms = [0, 0, -3, 1, 1, 1, 0]  # folds the leaf
bad.UpdatePipeline()
checks.check(servermanager.Fetch(bad).GetNumberOfPoints() == 0, "folding terms: empty blade")
bad.Terms = [0, 0, 0.1, 1, 1, 1, 0]
bad.UpdatePipeline()
checks.check(servermanager.Fetch(bad).GetNumberOfPoints() > 0, "recovers once the terms are fixed")
checks.finish()
