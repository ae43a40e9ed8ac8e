# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: with a named preset the panel shows what the preset chose.

VenationFilter, TreeFromSketchSource, LeafOutlineSource and WiltingSimulator grey out (not hide) the properties a named preset overrides, and show a
read-only PresetValues box (an information_only property, which ParaView 5.11's panel shows disabled and refreshes
after each update). Checked here: the box lists exactly the values the output was made with (the veins' field data
PlantMorph.Venation.<property>; the tree's branch count from paper 004 Table 1; the leaf's field data; a Custom
wilting run with the box's values gives the named preset's trajectory bit for bit), it follows
the Preset, and Custom says the properties are used. (The greying itself is checked on the XML by test_property_panels.py.)

    pvpython test_preset_values.py --plugin PlantMorph.so --work DIR
"""
import re

from plantmorph_testing import Checks, load_plugin, parse_arguments

arguments = parse_arguments()

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager

load_plugin(arguments.plugin, globals())
checks = Checks()


def shown(proxy):
    """The PresetValues box as the panel shows it after an update: {property: text}, and its first line."""
    proxy.UpdatePipeline()
    proxy.UpdatePipelineInformation()
    lines = str(proxy.PresetValues).split("\n")
    return dict(line.split(" = ", 1) for line in lines[1:] if " = " in line), lines[0]


SetActiveSource(None)
leaf = LeafOutlineSource()
veins = VenationFilter(Input=leaf)
for preset in ("Paper mulberry (paper 000 Fig. 10)", "Ginkgo (paper 000 Fig. 11)", "Poplar (paper 000 Fig. 12)"):
    veins.Preset = preset
    values, title = shown(veins)
    field = servermanager.Fetch(veins).GetFieldData()
    names = [field.GetArrayName(i) for i in range(field.GetNumberOfArrays())]
    grown = {n[len("PlantMorph.Venation."):]: field.GetArray(n).GetValue(0) for n in names
             if n.startswith("PlantMorph.Venation.")}
    checks.check(len(values) == len(grown) and len(values) > 20,
                 "%s: the box lists every value the preset sets (%d, grown with %d)" % (preset, len(values), len(grown)))
    mismatched = [n for n, v in grown.items() if n != "Pattern" and (n not in values or float(values[n]) != v)]
    checks.check(not mismatched, "%s: the box shows the values the veins grew with (differ: %s)" % (preset, mismatched))
    checks.check("greyed" in title, "%s: the box says the greyed properties are not used: %r" % (preset, title))
mulberry = None
veins.Preset = "Paper mulberry (paper 000 Fig. 10)"
mulberry, _ = shown(veins)
checks.check(mulberry.get("DivergenceAngleApex") == "70" and mulberry.get("Pattern") == "Brochidodromous",
             "paper mulberry: DivergenceAngleApex 70, brochidodromous (paper 000 Fig. 10) %s" % mulberry)
veins.Preset = "Custom"
values, title = shown(veins)
checks.check(not values and title.startswith("Custom"), "Custom: the box says the properties are used: %r" % title)

SetActiveSource(None)
tree = TreeFromSketchSource(Leaves=0)
for preset, depth, children, branches in ((1, 4, 8, 4681), (2, 6, 3, 1093)):
    tree.Preset = preset
    values, title = shown(tree)
    skeleton = servermanager.Fetch(tree, idx=1)
    checks.check(values.get("Depth") == str(depth) and values.get("ChildCount") == str(children),
                 "tree preset %d: Depth %d, ChildCount %d as paper 004 Table 1 (%s)" % (preset, depth, children, values))
    checks.check(skeleton.GetNumberOfLines() == branches,
                 "tree preset %d: the output has the %d branches those values give (%d)" % (
                     preset, branches, skeleton.GetNumberOfLines()))
tree.Preset = 0
values, title = shown(tree)
checks.check(not values and title.startswith("Custom"), "tree Custom: the box says the properties are used")

SetActiveSource(None)
leaf = LeafOutlineSource(Model="Space curve", SpaceCurvePreset=3)
values, title = shown(leaf)
curvature = servermanager.Fetch(leaf).GetFieldData().GetArray("PlantMorph.Curvature")
checks.check(curvature is not None and float(values.get("CurvatureMu", "nan")) == curvature.GetComponent(0, 1),
             "leaf space-curve preset: the box's CurvatureMu is the one the leaf was made with (%s)" %
             values.get("CurvatureMu"))
checks.check("greyed" in title and values.get("Model") == "SpaceCurve", "leaf: the box names the model %r" % title)
leaf.Model = "Deformed rectangle"
leaf.Preset = "Ginkgo"
values, title = shown(leaf)
checks.check(values.get("Preset") == "Ginkgo" and values.get("Terms", "").count("(") == 3,
             "leaf Ginkgo: the box lists its three terms (%s)" % values.get("Terms"))
leaf.Preset = "Custom"
values, title = shown(leaf)
checks.check(not values and title.startswith("Custom"), "leaf Custom: the box says the properties are used")

SetActiveSource(None)
blade = LeafOutlineSource()
named = WiltingSimulator(Input=blade, Preset="Cucumber", Duration=0.5, Resolution=14)
values, title = shown(named)
checks.check("greyed" in title and len(values) == 26, "wilting Cucumber: the box lists 26 values (%d) %r" % (len(values), title))
# The Cucumber's values are physical (Units Physical: per area and per thickness), so a Custom run with the
# box's numbers at the same Resolution is the same model whatever the voxel size, once it holds the leaf and scales
# the moduli and pressures to the leaf's size as the box's last line says the preset does.
checks.check(values.get("Units") == "0", "wilting Cucumber: the box says its units are Physical (0): %r" % values.get("Units"))
custom = WiltingSimulator(Input=blade, Preset="Custom", Duration=0.5, Resolution=14)
note = re.search(r"held within (\S+) of its longest side.* longest side is (\S+), scaled", str(named.PresetValues))
checks.check(note is not None, "wilting Cucumber: the box says how the preset holds and scales the leaf")
fraction, reference = float(note.group(1)), float(note.group(2))
bounds = servermanager.Fetch(blade).GetBounds()
longest = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])
SCALED = ("BladeMaterial", "VeinMaterial", "MarginMaterial", "PetioleMaterial", "DroopForce", "ContractionForce")
custom.AnchorRadius = fraction * longest
for name, text in values.items():
    numbers = [float(v) for v in text.split(",")]
    if name in SCALED:  # the Young's modulus (a material's second value) and the pressures
        numbers[1 if len(numbers) > 1 else 0] *= longest / reference
    current = custom.GetPropertyValue(name)
    if name in ("CurlDirection", "ContractionSide", "ContractionTarget", "LoadProfile", "Units"):
        custom.GetProperty(name).SetData(int(numbers[0]))
    else:
        custom.GetProperty(name).SetData(numbers if len(numbers) > 1 else numbers[0])
custom.UpdatePipeline(0.5)
named.UpdatePipeline(0.5)


def tip_path(proxy):
    table = servermanager.Fetch(proxy, idx=2)
    return [[table.GetColumnByName(c).GetValue(r) for c in ("TipX", "TipY", "TipZ")]
            for r in range(table.GetNumberOfRows())]


named_path, custom_path = tip_path(named), tip_path(custom)
checks.check(len(named_path) > 3 and named_path == custom_path,
             "wilting: Custom with the box's values moves the tip exactly as Cucumber (%d rows; last %s vs %s)" % (
                 len(named_path), named_path[-1:] if named_path else None, custom_path[-1:] if custom_path else None))
checks.check(named_path[-1][2] < named_path[0][2], "wilting: the tip droops (z %s -> %s)" % (
    named_path[0][2], named_path[-1][2]))
named.Preset = "Custom"
values, title = shown(named)
checks.check(not values and title.startswith("Custom"), "wilting Custom: the box says the properties are used")
checks.finish()
