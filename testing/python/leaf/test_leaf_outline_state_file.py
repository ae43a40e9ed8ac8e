# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: a LeafOutlineSource pipeline saved as a state file loads in a fresh pvpython with the same properties
and bit-identical output."""
import os
import sys

from plantmorph_testing import (check_same_properties, Checks, fingerprint, load_plugin, loaded_state, parse_arguments,
                                reload_in_fresh_pvpython)

arguments = parse_arguments([("--pvpython", dict(required=True)), ("--load", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

load_plugin(arguments.plugin, globals())
state = os.path.join(arguments.work, "leaf_outline.pvsm")
expected_file = os.path.join(arguments.work, "leaf_outline_state_expected.json")


def property_value(source, name):
    """A property's value as plain JSON data (enumerations as their label, vectors as lists)."""
    value = source.GetPropertyValue(name)
    if hasattr(value, "GetData"):
        value = value.GetData()
    return list(value) if isinstance(value, (list, tuple)) or hasattr(value, "__len__") and not isinstance(
        value, str) else value


SPACE_PROPERTIES = ("Model", "SpaceCurvePreset", "CurveLength", "CurvatureFunction", "CurvatureMu",
                    "CurvatureLambda", "CurvatureN1", "TorsionEta", "Opening", "MidveinStretchZ", "Resolution",
                    "StripColumns")
SPLINE_PROPERTIES = ("Model", "BSplinePreset", "MidveinPoints", "LeftMarginPoints", "RightMarginPoints", "Resolution",
                     "MeshQuality")
PALMATE_PROPERTIES = ("Model", "SpaceCurvePreset", "CurvatureMu", "CurvatureLambda", "Lobes", "LobeStart", "LobeAngle",
                      "LobeScale", "MeshQuality", "Resolution")
DEFORMED_RECTANGLE_PROPERTIES = ("Preset", "Length", "Width", "Terms", "Resolution", "MeshQuality", "Asymmetry",
                                 "Bending")


def describe(source, properties=DEFORMED_RECTANGLE_PROPERTIES, time=None):
    source.UpdatePipeline() if time is None else source.UpdatePipeline(time)
    if time is None:
        blade = servermanager.Fetch(source)
    else:
        # Fetch at the time: through a filter that asks for it (Fetch itself uses the pipeline's current time).
        blade = servermanager.Fetch(ForceTime(Input=source, ForcedTime=time, IgnorePipelineTime=1))
    outline = servermanager.Fetch(PassArrays(Input=OutputPort(source, 1)))
    return {
        "properties": {name: property_value(source, name) for name in properties},
        "blade": fingerprint(blade),
        "outline": fingerprint(outline),
        "points": blade.GetNumberOfPoints(),
    }


if arguments.load is None:
    # First process: a custom leaf with every kind of property changed, saved as a state file.
    leaf = LeafOutlineSource(registrationName="Leaf", Preset="Custom", Length=4.0, Width=3.0, Resolution=33,
                             MeshQuality="Quality", Asymmetry=0.2, Bending=0.15,
                             Terms=[0, 0, -1, 1, 0, 1, 1.5707963267948966, 0, 0, 1, 1, 1, 1, 0,
                                    1, 1, 0.1, 2, 1, 1, 0])
    space = LeafOutlineSource(registrationName="SpaceLeaf", Model="Space curve", SpaceCurvePreset="Custom",
                              CurveLength=4.5, CurvatureFunction="Power", CurvatureMu=3.0, CurvatureLambda=0.6,
                              CurvatureN1=2.0, TorsionEta=2.5, Opening=0.2, MidveinStretchZ=0.5, Resolution=25,
                              StripColumns=3)
    growing = LeafOutlineSource(registrationName="GrowingLeaf", Model="Space curve",
                                SpaceCurvePreset="Paper 002 Fig. 5", Growth=1, GrowthTimeSteps=9, Resolution=20)
    spline = LeafOutlineSource(registrationName="SplineLeaf", Model="B-spline", BSplinePreset="Custom",
                               MidveinPoints=[0, 0, 0, 0.3, 3, 0, 0, 6, 0], LeftMarginPoints=[-2, 2, 0, -1.5, 4.5, 0],
                               RightMarginPoints=[2.2, 2.5, 0], Resolution=28, MeshQuality="Quality")
    palmate = LeafOutlineSource(registrationName="PalmateLeaf", Model="Space curve", SpaceCurvePreset="Custom",
                                CurvatureMu=3.0, CurvatureLambda=0.5, Lobes=5, LobeStart=0.25, LobeAngle=38.0,
                                LobeScale=0.8, MeshQuality="Paper", Resolution=24)
    expected = describe(leaf)
    expected["palmate"] = describe(palmate, PALMATE_PROPERTIES)
    expected["space"] = describe(space, SPACE_PROPERTIES)
    expected["spline"] = describe(spline, SPLINE_PROPERTIES)
    # A growing leaf saved at a non-zero animation time comes back at that time. Nothing is shown: with a view,
    # setting the scene's time renders, and pvpython aborts at a render without an X server.
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = 0.625
    expected["growing"] = describe(growing, ("Growth", "GrowthTimeSteps", "GrowthInitialScale"), time=0.625)
    sys.exit(reload_in_fresh_pvpython(state, expected, expected_file, arguments, __file__))

# Second process: a fresh pvpython loads the state and compares.
checks = Checks()
leaf, expected = loaded_state(checks, arguments, expected_file, "Leaf", "source")
actual = describe(leaf)
check_same_properties(checks, actual, expected)
checks.check(actual["points"] == expected["points"] and actual["points"] > 0, "same number of points")
checks.check(actual["blade"] == expected["blade"], "blade bit-identical after the round trip")
checks.check(actual["outline"] == expected["outline"], "outline bit-identical after the round trip")
space = FindSource("SpaceLeaf")
checks.check(space is not None, "the state file holds the source 'SpaceLeaf'")
actual_space = describe(space, SPACE_PROPERTIES)
for name, value in expected["space"]["properties"].items():
    checks.check(actual_space["properties"][name] == value,
                 "space-curve property %s: %r after loading, %r before" % (name, actual_space["properties"][name],
                                                                           value))
checks.check(actual_space["points"] == expected["space"]["points"] and actual_space["points"] > 0,
             "space-curve leaf: same number of points")
checks.check(actual_space["blade"] == expected["space"]["blade"], "space-curve blade bit-identical after the round trip")
spline = FindSource("SplineLeaf")
actual_spline = describe(spline, SPLINE_PROPERTIES)
for name, value in expected["spline"]["properties"].items():
    checks.check(actual_spline["properties"][name] == value,
                 "B-spline property %s: %r after loading, %r before" % (name, actual_spline["properties"][name], value))
checks.check(actual_spline["blade"] == expected["spline"]["blade"] and actual_spline["points"] > 0,
             "B-spline blade bit-identical after the round trip")
palmate = FindSource("PalmateLeaf")
actual_palmate = describe(palmate, PALMATE_PROPERTIES)
for name, value in expected["palmate"]["properties"].items():
    checks.check(actual_palmate["properties"][name] == value,
                 "palmate property %s: %r after loading, %r before" % (name, actual_palmate["properties"][name], value))
checks.check(actual_palmate["blade"] == expected["palmate"]["blade"] and actual_palmate["points"] > 0
             and actual_palmate["outline"] == expected["palmate"]["outline"],
             "palmate blade and outline bit-identical after the round trip")
growing = FindSource("GrowingLeaf")
time = GetAnimationScene().AnimationTime
checks.check(abs(time - 0.625) < 1e-12, "animation time restored from the state file: %r" % time)
checks.check(list(growing.TimestepValues) == [k / 8.0 for k in range(9)], "growth time steps advertised")
actual_growing = describe(growing, ("Growth", "GrowthTimeSteps", "GrowthInitialScale"), time=time)
checks.check(actual_growing["blade"] == expected["growing"]["blade"], "growing leaf at t = 0.625 bit-identical")
full = describe(growing, ("Growth",), time=1.0)
checks.check(full["blade"] != actual_growing["blade"], "the leaf at t = 1 differs from t = 0.625")
checks.finish()
