# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: LeafOutlineSource -> VenationFilter -> Tube as users build it. The proxy is in the PlantMorph menu with
its documented defaults; every preset and pattern grows veins with the data contract's arrays and statistics; Tube
turns them into vein tubes of their width; bad values give empty outputs; and a pipeline with custom venation
properties, saved as a state file, loads in a fresh pvpython with bit-identical veins and embossed blade.

    pvpython test_venation_filter.py --plugin PlantMorph.so --work DIR
"""
import os
import sys

from plantmorph_testing import (check_same_properties, Checks, fingerprint, load_plugin, loaded_state, parse_arguments,
                                reload_in_fresh_pvpython)

arguments = parse_arguments([("--load", dict(default=None)), ("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
state = os.path.join(arguments.work, "venation.pvsm")
expected_file = os.path.join(arguments.work, "venation_state_expected.json")
PROPERTIES = ("Preset", "Pattern", "Seed", "SecondarySpacing", "DivergenceAngle", "AreoleSize", "Veinlets",
              "EmbossDepth", "ForkFraction")


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy if port == 0 else PassArrays(Input=OutputPort(proxy, port)))


def value(proxy, name):
    v = proxy.GetPropertyValue(name)
    return v.GetData() if hasattr(v, "GetData") else v


def describe(venation):
    veins = fetch(venation)
    blade = fetch(venation, 1)
    return {"properties": {name: value(venation, name) for name in PROPERTIES},
            "veins": fingerprint(veins), "blade": fingerprint(blade), "points": veins.GetNumberOfPoints()}


checks = Checks()

if arguments.load is not None:
    # Second process: a fresh pvpython loads the state saved by the first and compares.
    venation, expected = loaded_state(checks, arguments, expected_file, "Veins")
    actual = describe(venation)
    check_same_properties(checks, actual, expected)
    checks.check(actual["points"] == expected["points"] and actual["points"] > 0, "same number of vein points")
    checks.check(actual["veins"] == expected["veins"], "veins bit-identical after the round trip")
    checks.check(actual["blade"] == expected["blade"], "embossed blade bit-identical after the round trip")
    checks.finish()
    sys.exit(0)

leaf = LeafOutlineSource(Preset="Entire", Resolution=80)
venation = VenationFilter(Input=leaf)
checks.check(venation.Preset == "Paper mulberry (paper 000 Fig. 10)" and venation.Seed == 0
             and venation.EmbossDepth == 0.0, "defaults: paper mulberry, seed 0, no relief")

veins = fetch(venation)
checks.check(veins.GetNumberOfLines() > 50, "paper mulberry: %d vein polylines" % veins.GetNumberOfLines())
order = vtk_to_numpy(veins.GetCellData().GetArray("VeinOrder"))
checks.check(set(order.tolist()) == {1, 2, 3, 4},
             "primary, secondary, tertiary and quaternary veins: %s" % sorted(set(order.tolist())))
checks.check(veins.GetPointData().GetScalars().GetName() == "VeinWidth", "VeinWidth is the active scalar")
for name in ("Region", "LeafUV"):
    checks.check(veins.GetPointData().GetArray(name) is not None, "vein points carry %s" % name)
checks.check(veins.GetPointData().GetTCoords() is not None, "vein points carry the blade's TCoords")
field = veins.GetFieldData()
checks.check(field.GetArray("PlantMorph.AreoleCount").GetValue(0) > 20, "areoles counted in field data")
checks.check(abs(field.GetArray("PlantMorph.VeinLength").GetComponent(0, 0) - 5.0) < 1e-6,
             "primary vein length = the 5 cm midvein")
blade = fetch(venation, 1)
checks.check(blade.GetNumberOfPoints() == fetch(leaf).GetNumberOfPoints(), "port 1 passes the blade through")

# Tube, as the docs say: vein tubes as thick as the veins.
tube = Tube(Input=OutputPort(venation, 0))
tube.Scalars = ["POINTS", "VeinWidth"]
tube.VaryRadius = "By Scalar"
tube.Radius = 0.01
tubes = fetch(tube)
checks.check(tubes.GetNumberOfPolys() + tubes.GetNumberOfStrips() > 100, "Tube makes vein tubes")
Delete(tube)

# Every preset and every pattern.
PRESETS = ["Paper mulberry (paper 000 Fig. 10)", "Ginkgo (paper 000 Fig. 11)", "Poplar (paper 000 Fig. 12)",
           "Cucumber (palmate)", "Tomato (pinnate leaflet)", "Watermelon (palmate, lobed)"]
for preset in PRESETS:
    venation.Preset = preset
    veins = fetch(venation)
    checks.check(veins.GetNumberOfLines() > 10, "%s: %d veins" % (preset, veins.GetNumberOfLines()))
venation.Preset = "Custom"
PATTERNS = ["Craspedodromous", "Semicraspedodromous", "Brochidodromous", "Eucamptodromous", "Reticulodromous",
            "Cladodromous", "Arcuate (acrodromous)", "Parallel", "Palmate (actinodromous)",
            "Space colonization (Runions 2005)"]
for pattern in PATTERNS:
    venation.Pattern = pattern
    veins = fetch(venation)
    checks.check(veins.GetNumberOfLines() > 10, "%s: %d veins" % (pattern, veins.GetNumberOfLines()))
venation.ClosedVenation = 1
veins = fetch(venation)
checks.check(veins.GetNumberOfLines() > 10, "closed space colonization: %d veins" % veins.GetNumberOfLines())
venation.ClosedVenation = 0
venation.MarginalGrowth = 1
veins = fetch(venation)
checks.check(veins.GetNumberOfLines() > 10, "space colonization, marginal growth: %d veins" % veins.GetNumberOfLines())
venation.MarginalGrowth = 0
# Palmate secondaries through the proxy: none by default, secondaries off the primaries when asked for, whose
# VeinOrder-2 cells start on a primary; the field data tells the choice.
venation.Pattern = "Palmate (actinodromous)"
venation.ForkLevels = 0
bare = fetch(venation)
bare_orders = set(vtk_to_numpy(bare.GetCellData().GetArray("VeinOrder")).tolist())
for kind in ("Craspedodromous", "Brochidodromous"):
    venation.PalmateSecondaries = kind
    veins = fetch(venation)
    order = vtk_to_numpy(veins.GetCellData().GetArray("VeinOrder"))
    chosen = veins.GetFieldData().GetArray("PlantMorph.Venation.PalmateSecondaries").GetValue(0)
    expected = 1 if kind == "Craspedodromous" else 2
    checks.check(2 not in bare_orders and (order == 2).sum() >= 8 and chosen == expected,
                 "PalmateSecondaries %s: %d secondary veins (none without), field data %s" % (
                     kind, (order == 2).sum(), chosen))
venation.PalmateSecondaries = "None"
venation.AreoleGradient = 0.9
checks.check(fetch(venation).GetNumberOfPoints() == 0, "AreoleGradient 0.9 (above 0.8): empty output")
venation.AreoleGradient = 0.0
venation.ForkLevels = 1
venation.Pattern = "Space colonization (Runions 2005)"
venation.KillDistance = 0.0
checks.check(fetch(venation).GetNumberOfPoints() == 0, "KillDistance 0: empty output")
venation.KillDistance = 0.01

# Bad values: an error and empty outputs.
venation.Pattern = "Brochidodromous"
venation.AreoleSize = 0.0
checks.check(fetch(venation).GetNumberOfPoints() == 0 and fetch(venation, 1).GetNumberOfPoints() == 0,
             "AreoleSize 0: empty outputs")
venation.AreoleSize = 0.05

# State file: save with custom venation properties, load in a fresh pvpython, compare.
RenameSource("Veins", venation)
venation.Pattern = "Cladodromous"
venation.Seed = 7
venation.SecondarySpacing = 0.08
venation.DivergenceAngle = 48.0
venation.Veinlets = 1
venation.EmbossDepth = 0.02
venation.ForkFraction = 0.7
returncode = reload_in_fresh_pvpython(state, describe(venation), expected_file, arguments, __file__)
checks.check(returncode == 0, "the state file loads in a fresh pvpython with the same output")
checks.finish()
