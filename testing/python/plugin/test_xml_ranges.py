# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: every range in the proxy XML is the range the filter accepts.

For each IntRangeDomain / DoubleRangeDomain bound in xml/*.xml (each element a bound is given for; a single bound
on a vector property applies to every element), the proxy runs on a small valid input with the property at the
bound, then just outside it (an int's next value, a double's bound moved by 1e-6 of its size, at least 1e-6),
every other property at its base value:
  * at the bound: no error (VALUE_AT_BOUND lists those refused there, with the reason: an open interval, or a
    value that fails with the other properties at their defaults);
  * just outside: a range error naming the property ("<Property> = <value> is outside the accepted range ...";
    OTHER_NAMES lists the properties whose error uses another name). A bound with no value beyond it (a 32-bit
    int's limit) is not tried. A bound the filter does not enforce is a hint for the panel's slider only: those
    are listed in GUI_HINTS with the reason, and the test fails when one of them starts being enforced, or when a
    bound not listed is not enforced. COSTLY lists the three bounds whose run takes minutes (not run).
The property's panel decorators give the settings under which it is used (its Model, ScannerType, Lobes..., and
Custom for a property a preset overrides); CONTEXT adds what the XML cannot say (a file, a second input). Each run
prints one row of the table: proxy, property[element], bound, value, result at the bound, result outside.

    pvpython test_xml_ranges.py --plugin PlantMorph.so --work DIR [--xml-dir xml/] [--only PROXY]
"""
import glob
import os
import re
import time
import xml.etree.ElementTree as ElementTree

from plantmorph_testing import Checks, Messages, load_plugin, parse_arguments

root = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
arguments = parse_arguments([("--xml-dir", dict(default=os.path.join(root, "xml"))),
                             ("--only", dict(default=None, help="check this proxy only"))])

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager

load_plugin(arguments.plugin, globals())
checks = Checks()

INT32 = (-2 ** 31, 2 ** 31 - 1)
# Two rows of the deformed rectangle's terms, so the Custom leaf is a leaf.
TERMS = [0, 0, 0.2, 0, 1, 1, 0, 1, 1, 0.05, 1, 2, 0, 0]
STROKES_CSV = os.path.join(arguments.work, "xml_ranges_strokes.csv")
with open(STROKES_CSV, "w") as f:
    f.write("stroke_id,x,y\n0,0,0\n0,0,5\n0,0,10\n1,0,6\n1,3,9\n")
QSM_CSV = os.path.join(arguments.work, "xml_ranges_cylinders.csv")
with open(QSM_CSV, "w") as f:
    f.write("ID,parentID,startX,startY,startZ,endX,endY,endZ,radius\n1,0,0,0,0,0,0,1,0.1\n")
SetActiveSource(None)
leaf = LeafOutlineSource(Resolution=12)
leaf_cloud = VirtualScanner(Input=leaf, Resolution=[60, 40])
other_cloud = VirtualScanner(Input=leaf, Resolution=[50, 30], Positions=[1, -5, 1])
second_tree = TreeFromSketchSource(Preset="Custom", Depth=1, ChildCount=2, Leaves=0)
strokes_tree = {"Mode": "Strokes", "StrokeFile": STROKES_CSV}
tree_cloud = VirtualScanner(Input=TreeFromSketchSource(Preset="Custom", Depth=1, ChildCount=3, Length=4, Radius=0.12,
                                                       Leaves=0, Sides=16),
                            Positions=[6, 1.5, 0, -3, 1.5, 5, -3, 1.5, -5], LookAt=[0, 2.5, 0], Up=[0, 1, 0],
                            HorizontalFieldOfView=50, VerticalFieldOfView=60, AngularStep=0.1, RangeNoise=0.002)
plant = TreeFromSketchSource(Preset="Custom", Depth=1, ChildCount=3, Length=4.0, Radius=0.08, LeafCount=3,
                             LeafScale=1.5)
plant_cloud = VirtualScanner(Input=AppendGeometry(Input=[OutputPort(plant, 0), OutputPort(plant, 2)]),
                             Positions=[8, 3, 0, -8, 3, 0], LookAt=[0, 3, 0], Up=[0, 1, 0], AngularStep=0.25,
                             HorizontalFieldOfView=60, VerticalFieldOfView=60)

# How each proxy is made for the runs: a small valid input, settings that keep a run short.
BASES = {
    "LeafOutlineSource": lambda: LeafOutlineSource(Resolution=12, Terms=TERMS),
    "TreeFromSketchSource": lambda: TreeFromSketchSource(Depth=2, ChildCount=2, Leaves=0),
    "VenationFilter": lambda: VenationFilter(Input=leaf),
    "AdaptiveLoopFilter": lambda: AdaptiveLoopFilter(Input=leaf, MaximumLevel=1),
    "LeafCurlFilter": lambda: LeafCurlFilter(Input=leaf),
    "WiltingSimulator": lambda: WiltingSimulator(Input=leaf, Resolution=14, Duration=0.05, FrameInterval=0.05),
    "CloudComparisonFilter": lambda: CloudComparisonFilter(Input=leaf_cloud, Reference=other_cloud),
    "TrajectoryComparisonFilter": None,  # no range
    "LeafCloudReader": None,  # no range
    "LeafFitFilter": lambda: LeafFitFilter(Input=leaf_cloud),
    "VirtualScanner": lambda: VirtualScanner(Input=leaf, Resolution=[40, 30]),
    "TreeFitFilter": lambda: TreeFitFilter(Input=tree_cloud, UpAxis="Y"),

    "QsmReader": lambda: QSMReader(FileName=QSM_CSV, Tubes=1),
    "PlantSegmentationFilter": lambda: PlantSegmentationFilter(Input=plant_cloud, UpAxis=1),
}
# (proxy, property): settings the property needs besides its panel decorators, for every run of it (values by
# property name; a bound may also name its own: (proxy, property, "min"/"max")).
CONTEXT = {
    ("TreeFromSketchSource", "StrokeControlPoints"): strokes_tree,
    ("TreeFromSketchSource", "StrokeLengthRatio"): strokes_tree,
    ("TreeFromSketchSource", "StrokeSubtreeDepth"): strokes_tree,
    ("TreeFromSketchSource", "MergeParentBranch"): {"MergeTree": OutputPort(second_tree, 1)},
    ("TreeFromSketchSource", "MergeU"): {"MergeTree": OutputPort(second_tree, 1)},
    ("TreeFromSketchSource", "MergeAngle"): {"MergeTree": OutputPort(second_tree, 1)},
    ("TreeFromSketchSource", "MergeRotation"): {"MergeTree": OutputPort(second_tree, 1)},
    ("TreeFromSketchSource", "MergeScale"): {"MergeTree": OutputPort(second_tree, 1)},
    ("TreeFromSketchSource", "MergeOffset"): {"MergeTree": OutputPort(second_tree, 1)},
    ("TreeFromSketchSource", "LeafCount"): {"Leaves": 1},
    ("TreeFromSketchSource", "LeafRatio"): {"Leaves": 1},
    ("TreeFromSketchSource", "LeafScale"): {"Leaves": 1},
    ("TreeFromSketchSource", "LeafAngle"): {"Leaves": 1},
    ("TreeFromSketchSource", "LeafTipScale"): {"Leaves": 1},
    ("TreeFromSketchSource", "LeafScaleSpread"): {"Leaves": 1},
    # Each curvature family's own parameters are read only under that family (CurvatureFunction / TorsionFunction
    # 2 piecewise power, 3 piecewise exponential, 4 notched apex).
    **{("LeafOutlineSource", family + name): {family + "Function": function}
       for family in ("Curvature", "Torsion")
       for function, names in ((2, ("N1", "N2")), (3, ("B1", "U3")), (4, ("Beta", "Alpha4", "Lambda2")))
       for name in names},
    # The exponential torsion needs a positive peak (TorsionEta).
    ("LeafOutlineSource", "TorsionB1"): {"TorsionFunction": 3, "TorsionEta": 1.0},
    ("LeafOutlineSource", "TorsionU3"): {"TorsionFunction": 3, "TorsionEta": 1.0},
    ("CloudComparisonFilter", "RegistrationIterations"): {"Registration": 1},
    ("CloudComparisonFilter", "RegistrationTolerance"): {"Registration": 1},
    ("CloudComparisonFilter", "RegistrationLandmarks"): {"Registration": 1},
    ("CloudComparisonFilter", "MaximumDistance"): {"UseMaximumDistance": 1},
    ("VirtualScanner", "TurntableSteps"): {"LineMotion": 1},
    ("VirtualScanner", "Seed"): {"RangeNoise": 0.01},
    ("VenationFilter", "EmbossDepth"): {"PrimaryWidth": 0.015},
    # Wilting: the longest Duration in steps of 10 s; a curl at the default Resolution (14), where the voxel edge is
    # the default BladeThickness.
    ("WiltingSimulator", "Duration", "max"): {"TimeStep": 10.0, "FrameInterval": 1000.0},
    ("WiltingSimulator", "CurlStrain"): {"Resolution": 14},
    # Lobes: the curvature of the 3-lobed preset (Paper 002 Fig. 8), as the Custom defaults fold a lobed leaf.
    **{("LeafOutlineSource", name): {"CurvatureMu": 3.0, "CurvatureLambda": 0.5}
       for name in ("LobeStart", "LobeAngle", "LobeScale", "SubLobes", "SubLobeDepth", "SinusDepth")},
}
# (proxy, property, "min"/"max"): why that bound is not run at all (its run takes minutes).
COSTLY = {
    ("LeafOutlineSource", "Resolution", "max"): "1000 segments of the deformed rectangle: over 3 minutes",
    ("LeafFitFilter", "Resolution", "max"): "1000 segments along the midvein: 45 s",
    ("WiltingSimulator", "Resolution", "max"): "1000 voxels along the leaf: minutes before MaximumVoxels refuses it",
}
# Keys of the three lists below: (proxy, property, "min"/"max") for one bound, (proxy, property) for both.
CLASS_WIDER = "the class accepts values beyond it"
SHAPE_ONLY = "no range check; only the outline's geometry check refuses a leaf it folds"
# Bounds the filter does not enforce: a hint for the panel's slider only, with the reason.
GUI_HINTS = {
    ("CloudComparisonFilter", "RegistrationTolerance", "max"): CLASS_WIDER,
    ("LeafOutlineSource", "Length"): CLASS_WIDER + " (any length > 0)",
    ("LeafOutlineSource", "Width", "max"): CLASS_WIDER + " (its documentation says 0 to 1e6)",
    ("LeafOutlineSource", "CurveLength"): CLASS_WIDER + " (any length > 0)",
    ("LeafOutlineSource", "CurvatureN1"): CLASS_WIDER + " ((0, 100], CurvatureFamily)",
    ("LeafOutlineSource", "CurvatureN2"): CLASS_WIDER + " ((0, 100], CurvatureFamily)",
    ("LeafOutlineSource", "CurvatureB1"): CLASS_WIDER + " ((0, inf), CurvatureFamily)",
    ("LeafOutlineSource", "CurvatureU3"): CLASS_WIDER + " ((0, inf), CurvatureFamily)",
    ("LeafOutlineSource", "CurvatureBeta"): CLASS_WIDER + " (|beta| > 1, CurvatureFamily)",
    ("LeafOutlineSource", "CurvatureAlpha4"): CLASS_WIDER + " ((0, 1), CurvatureFamily)",
    ("LeafOutlineSource", "TorsionEta"): CLASS_WIDER + " ([-1e4, 1e4], CurvatureFamily)",
    ("LeafOutlineSource", "TorsionN1"): CLASS_WIDER + " ((0, 100], CurvatureFamily)",
    ("LeafOutlineSource", "TorsionN2"): CLASS_WIDER + " ((0, 100], CurvatureFamily)",
    ("LeafOutlineSource", "TorsionB1"): CLASS_WIDER + " ((0, inf), CurvatureFamily)",
    ("LeafOutlineSource", "TorsionU3"): CLASS_WIDER + " ((0, inf), CurvatureFamily)",
    ("LeafOutlineSource", "TorsionBeta"): CLASS_WIDER + " (|beta| > 1, CurvatureFamily)",
    ("LeafOutlineSource", "TorsionAlpha4"): CLASS_WIDER + " ((0, 1), CurvatureFamily)",
    ("LeafOutlineSource", "MidveinStretchZ"): CLASS_WIDER,
    ("LeafOutlineSource", "MidveinStretchXY"): CLASS_WIDER,
    ("LeafOutlineSource", "Opening"): CLASS_WIDER,
    ("LeafOutlineSource", "InitialAngle"): CLASS_WIDER,
    ("LeafOutlineSource", "LobeAngle", "min"): CLASS_WIDER,
    ("LeafOutlineSource", "LobeScale", "min"): CLASS_WIDER,
    ("LeafOutlineSource", "SubLobeDepth", "min"): CLASS_WIDER,
    ("LeafOutlineSource", "CurvatureMu"): CLASS_WIDER + " ([-1e4, 1e4], CurvatureFamily); here the geometry check "
                                                        "refuses it",
    ("LeafOutlineSource", "LobeStart"): SHAPE_ONLY,
    ("LeafOutlineSource", "BladeLength"): SHAPE_ONLY,
    ("LeafOutlineSource", "BladeWidth"): SHAPE_ONLY,
    ("LeafOutlineSource", "ControlPointCount", "max"): CLASS_WIDER,
    ("LeafOutlineSource", "Bending"): CLASS_WIDER,
    ("LeafOutlineSource", "Asymmetry"): SHAPE_ONLY,
    ("LeafOutlineSource", "MaxVertices", "max"): CLASS_WIDER + " ([3, inf))",
    ("LeafOutlineSource", "GrowthTimeSteps", "max"): CLASS_WIDER + " ([2, 10000])",
    ("LeafOutlineSource", "GrowthInitialScale", "min"): CLASS_WIDER + " ((0, 1])",
    ("TreeFromSketchSource", "Length", "max"): CLASS_WIDER + " ((0, 1e6])",
    ("TreeFromSketchSource", "Radius", "max"): CLASS_WIDER + " ((0, 1e5])",
    ("TreeFromSketchSource", "Depth", "max"): CLASS_WIDER + " (MaxSegments bounds the tree)",
    ("TreeFromSketchSource", "PhyllotaxisA", "max"): CLASS_WIDER,
    ("TreeFromSketchSource", "PhyllotaxisB", "max"): CLASS_WIDER,
    ("TreeFromSketchSource", "ChildCount", "max"): CLASS_WIDER + " (MaxSegments bounds the tree)",
    ("TreeFromSketchSource", "LengthScale"): CLASS_WIDER,
    ("TreeFromSketchSource", "SegmentsPerBranch", "max"): CLASS_WIDER,
    ("TreeFromSketchSource", "TwigScale"): CLASS_WIDER,
    ("TreeFromSketchSource", "Sides", "max"): CLASS_WIDER,
    ("TreeFromSketchSource", "StrokeControlPoints", "max"): CLASS_WIDER,
    ("TreeFromSketchSource", "StrokeLengthRatio"): CLASS_WIDER + " (<= 0: the rule's own ratio)",
    ("TreeFromSketchSource", "StrokeSubtreeDepth", "max"): CLASS_WIDER,
    ("TreeFromSketchSource", "LeafCount", "max"): CLASS_WIDER,
    ("TreeFromSketchSource", "LeafScale"): CLASS_WIDER,
    ("TreeFromSketchSource", "LeafTipScale"): CLASS_WIDER + " ((0, 10])",
    ("TreeFromSketchSource", "Seed"): "any integer seeds the generator",
    ("TreeFromSketchSource", "MergeRotation"): "an angle in degrees, any value turns",
    ("TreeFromSketchSource", "MergeScale"): CLASS_WIDER,
    ("TreeFromSketchSource", "MergeParentBranch", "max"): "checked against the tree's branch ids, not a range",
    ("VenationFilter", "Seed"): "any integer seeds the generator",
    ("VenationFilter", "EmbossDepth"): CLASS_WIDER,
    ("PlantSegmentationFilter", "NormalAngle"): CLASS_WIDER + " ((0, 90))",
    ("PlantSegmentationFilter", "CreaseVariation"): CLASS_WIDER + " ((0, 1))",
    ("PlantSegmentationFilter", "SheetCoherence"): CLASS_WIDER + " ((0, 1))",
    ("VirtualScanner", "HorizontalFieldOfView", "min"): CLASS_WIDER + " (any angle > 0)",
    ("VirtualScanner", "VerticalFieldOfView", "min"): CLASS_WIDER + " (any angle > 0)",
    ("WiltingSimulator", "MaximumVoxels", "max"): CLASS_WIDER,
}
# Bounds refused at the bound itself, with the reason.
EXCLUSIVE = "the class needs a value above it (an open interval the XML's inclusive range cannot say)"
VALUE_AT_BOUND = {
    ("LeafOutlineSource", "Width", "min"): "a rectangle of width 0 folds the Custom outline",
    ("LeafOutlineSource", "CurvatureMu"): "at the default CurvatureLambda (0.7) the margin hooks back across the "
                                          "blade from |mu| about 12",
    ("LeafOutlineSource", "CurvatureB1", "max"): "the exponential margin hooks back across the blade",
    ("LeafOutlineSource", "LobeStart"): "a lobe starting at the very base or apex leaves the blade",
    ("LeafOutlineSource", "LobeAngle", "max"): "a lobe at 90 degrees meets the previous one",
    ("LeafOutlineSource", "BladeLength", "max"): "the default control points fold a blade this long and narrow",
    ("LeafOutlineSource", "BladeWidth", "min"): "the default control points fold a blade this narrow",
    ("LeafOutlineSource", "Asymmetry"): "the Custom outline folds at +-0.9",
    ("WiltingSimulator", "Resolution", "min"): "Physical units refuse voxels coarser than the blade is thick: "
                                               "below 14 with the default thickness",
    ("TreeFromSketchSource", "Length", "min"): EXCLUSIVE,
    ("TreeFromSketchSource", "Radius", "min"): EXCLUSIVE,
    ("TreeFromSketchSource", "MergeParentBranch", "max"): "a branch id the tree has (this one has 7)",
    ("VenationFilter", "AreoleSize", "min"): "needs more vein segments than the default MaxSegments",
    ("VenationFilter", "MaxSegments", "min"): "the default AreoleSize needs more vein segments",
    ("VenationFilter", "KillDistance", "max"): "AttractionDistance (default 0.1) must be at least KillDistance",
    ("VenationFilter", "AttractionDistance", "min"): "must be at least KillDistance (default 0.01)",
    ("PlantSegmentationFilter", "FeatureScale", "max"): "features 50 spacings wide blur the test plant's leaves "
                                                        "into its stem: no leaf found",
    ("VirtualScanner", "AngularStep", "min"): "the scan casts more beams than the default MaximumBeams",
    ("VirtualScanner", "MaximumBeams", "min"): "any scan casts more than one beam",
    ("VirtualScanner", "TurntableSteps", "max"): "the scan casts more beams than the default MaximumBeams",
    ("WiltingSimulator", "MaximumVoxels", "min"): "any leaf has more than one voxel",
    ("WiltingSimulator", "BladeMaterial", "min"): EXCLUSIVE + " (density and Young's modulus; damping may be 0)",
    ("WiltingSimulator", "VeinMaterial", "min"): EXCLUSIVE + " (density and Young's modulus; damping may be 0)",
    ("WiltingSimulator", "MarginMaterial", "min"): EXCLUSIVE + " (density and Young's modulus; damping may be 0)",
    ("WiltingSimulator", "PetioleMaterial", "min"): EXCLUSIVE + " (density and Young's modulus; damping may be 0)",
    ("WiltingSimulator", "DroopForce"): "a load of 1e9 makes the simulation blow up (reported as an error)",
    ("WiltingSimulator", "ContractionForce"): "a load of 1e9 makes the simulation blow up (reported as an error)",
    ("WiltingSimulator", "LoadTime", "min"): EXCLUSIVE,
    ("WiltingSimulator", "Duration", "min"): EXCLUSIVE,
    ("WiltingSimulator", "TimeStep", "min"): EXCLUSIVE,
    ("WiltingSimulator", "FrameInterval", "min"): EXCLUSIVE,
}
# Properties whose range error names something other than the property (the core's name): the names it uses.
# The error should name the property; listed so the test still checks the value is refused.
OTHER_NAMES = {
    ("VenationFilter", "SecondaryCurvatureBase"): ["SecondaryCurvature"],
    ("VenationFilter", "SecondaryCurvatureApex"): ["SecondaryCurvature"],
    ("VenationFilter", "SecondaryWidthRatio"): ["VeinWidthRatio"],
    ("VenationFilter", "TertiaryWidthRatio"): ["VeinWidthRatio"],
    ("VenationFilter", "VeinletWidthRatio"): ["VeinWidthRatio"],
    **{("WiltingSimulator", region + "Material"): [region + "Density", region + "YoungsModulus",
                                                   region + "DampingTime"]
       for region in ("Blade", "Vein", "Margin", "Petiole")},
    ("WiltingSimulator", "RayleighAlpha"): ["RayleighMass (alpha)"],
    ("WiltingSimulator", "RayleighBeta"): ["RayleighStiffness (beta)"],
}


def MAY_BE_ACCEPTED(key, element):
    """The materials' third element (a damping time) is accepted at 0, their first two are not."""
    return key[1].endswith("Material") and element == 2


def numbers(text):
    return [float(v) for v in text.split()] if text else []


def decorator_settings(element, proxy_element):
    """{property: value} the panel decorators of `element` (a property's XML) ask for: a GenericDecorator's
    value, or for an inverse one the controlling property's first enumeration value that is not it."""
    settings = {}
    for decorator in element.iter("PropertyWidgetDecorator"):
        if decorator.get("type") != "GenericDecorator":
            continue
        controller, value = decorator.get("property"), decorator.get("value")
        if decorator.get("inverse") == "1":
            entries = [e.get("value") for c in proxy_element if c.get("name") == controller
                       for e in c.iter("Entry")]
            value = next(e for e in entries if e != value)
        settings.setdefault(controller, int(value) if value.lstrip("-").isdigit() else value)
    return settings


def bounds(prop):
    """[(element, "min"/"max", value)] of a property's range domain."""
    domain = next((c for c in prop if c.tag in ("IntRangeDomain", "DoubleRangeDomain")), None)
    if domain is None:
        return []
    count = int(prop.get("number_of_elements", "1"))
    result = []
    for side in ("min", "max"):
        values = numbers(domain.get(side))
        if len(values) == 1 and count > 1:
            values = values * count
        result += [(i, side, v) for i, v in enumerate(values)]
    return result


def outside(prop, side, bound):
    """The value just outside `bound`, or None when there is none to try."""
    if prop.tag in ("IntVectorProperty", "IdTypeVectorProperty"):
        value = int(bound) - 1 if side == "min" else int(bound) + 1
        limits = INT32 if prop.tag == "IntVectorProperty" else (-2 ** 63, 2 ** 63 - 1)
        return value if limits[0] <= value <= limits[1] else None
    step = 1e-6 * max(1.0, abs(bound))
    return bound - step if side == "min" else bound + step


def set_values(proxy, settings):
    """Sets {property: value}; returns the old values to restore."""
    old = {}
    for name, value in settings.items():
        prop = proxy.GetProperty(name)
        old[name] = prop.GetData()
        prop.SetData(value)
    proxy.UpdateVTKObjects()
    return old


def run(proxy, names):
    """Runs the proxy; returns (errors, the range errors naming one of `names` ("<name> = <value> is outside the
    accepted range ...", plantmorph::OutOfRange's phrasing, the name possibly followed by a note in parentheses:
    "Resolution (width) = 0"), first output's size)."""
    with Messages(proxy) as messages:
        proxy.UpdatePipeline()
    data = servermanager.Fetch(proxy)
    size = data.GetNumberOfRows() if data.IsA("vtkTable") else data.GetNumberOfPoints()
    patterns = [re.compile(r"\b%s( \([^)]*\))? = " % re.escape(n)) for n in names]
    named = [e for e in messages.errors if "outside" in e and any(p.search(e) for p in patterns)]
    return messages.errors, named, size


def describe(errors):
    """The first error without VTK's "ERROR: In file, line N / vtkClass (0x...): " header."""
    if not errors:
        return "no error"
    return errors[0].split("): ", 1)[-1].strip().replace("\n", " ")[:150]


def listed(table, key):
    """The reason `table` gives for the bound `key` (proxy, property, side), or for the property, or None."""
    return table.get(key, table.get(key[:2]))


def check_bound(proxy_name, proxy, prop, element, side, bound, settings):
    name = prop.get("name")
    is_int = prop.tag in ("IntVectorProperty", "IdTypeVectorProperty")
    values = list(proxy.GetProperty(name).GetData()) if int(prop.get("number_of_elements", "1")) > 1 else None
    label = "%s.%s%s" % (proxy_name, name, "[%d]" % element if values is not None else "")

    def with_value(value):
        if values is None:
            setting = {name: int(value) if is_int else value}
        else:
            changed = list(values)
            changed[element] = int(value) if is_int else value
            setting = {name: changed}
        old = set_values(proxy, setting)
        result = run(proxy, [name] + OTHER_NAMES.get((proxy_name, name), []))
        set_values(proxy, old)
        return result

    key = (proxy_name, name, side)
    if key in COSTLY:
        print("| %-22s | %-24s | %s | %-12g | not run (%s)" % (proxy_name, label.split(".", 1)[1], side, bound,
                                                           COSTLY[key]))
        return
    old = set_values(proxy, settings)
    start = time.time()
    errors, _, _ = with_value(bound)
    if listed(VALUE_AT_BOUND, key) and (errors or not MAY_BE_ACCEPTED(key, element)):
        at_bound = "refused (listed: %s)" % describe(errors) if errors else "ACCEPTED, listed as refused"
        checks.check(bool(errors), "%s = %r (%s): listed as refused at the bound (%s) but accepted" % (
            label, bound, side, listed(VALUE_AT_BOUND, key)))
    else:
        at_bound = "accepted" if not errors else "REFUSED: " + describe(errors)
        checks.check(not errors, "%s = %r, the XML's %s: refused: %s" % (label, bound, side, describe(errors)))
    beyond = outside(prop, side, bound)
    if beyond is None:
        outcome = "n/a (no value beyond)"
    else:
        errors, named, size = with_value(beyond)
        if listed(GUI_HINTS, key):
            outcome = "not enforced (GUI hint, listed)" if not named else "ENFORCED, listed as a hint"
            checks.check(not named, "%s = %r: listed as a GUI hint (%s) but refused: %s" % (
                label, beyond, listed(GUI_HINTS, key), describe(named)))
        elif named:
            other = [n for n in OTHER_NAMES.get(key[:2], []) if n + " = " in named[0] and name + " = " not in named[0]]
            outcome = "refused, names %s%s" % ("it" if not other else other[0] + " (listed)",
                                              "" if size == 0 else ", OUTPUT NOT EMPTY")
            checks.check(size == 0, "%s = %r: refused but the output has %d points" % (label, beyond, size))
        else:
            outcome = "NOT REFUSED (%s)" % describe(errors)
            checks.check(False, "%s = %r, just outside the XML's %s %r: no error naming %s (%s)" % (
                label, beyond, side, bound, name, describe(errors)))
    set_values(proxy, old)
    print("| %-22s | %-24s | %s | %-12g | %s | %s | %.1fs" % (
        proxy_name, label.split(".", 1)[1], side, bound, at_bound, outcome, time.time() - start))


files = sorted(glob.glob(os.path.join(arguments.xml_dir, "*.xml")))
checks.check(len(files) >= 11, "the proxy XML found in %s (%d files)" % (arguments.xml_dir, len(files)))
tried = 0
seen = set()
print("| proxy | property | bound | value | at the bound | just outside | time")
for path in files:
    for proxy_element in ElementTree.parse(path).getroot().iter():
        if not proxy_element.get("class") or not proxy_element.tag.endswith("Proxy"):
            continue
        proxy_name = proxy_element.get("name")
        if arguments.only and proxy_name != arguments.only:
            continue
        ranged = [p for p in proxy_element if bounds(p) and p.get("information_only") != "1"]
        checks.check(not ranged or BASES.get(proxy_name) is not None,
                     "%s has ranges: give it a base in BASES" % proxy_name)
        if not ranged or BASES.get(proxy_name) is None:
            continue
        SetActiveSource(None)
        proxy = BASES[proxy_name]()
        # A proxy with presets: Custom, so every property is used.
        custom = {"Preset": 0} if proxy_element.find("IntVectorProperty[@name='Preset']") is not None else {}
        errors, _, _ = run(proxy, [])
        checks.check(not errors, "%s: the base run has no error (%s)" % (proxy_name, describe(errors)))
        for prop in ranged:
            name = prop.get("name")
            seen.add((proxy_name, name))
            settings = dict(custom)
            settings.update(decorator_settings(prop, proxy_element))
            settings.update(CONTEXT.get((proxy_name, name), {}))
            for element, side, bound in bounds(prop):
                full = dict(settings)
                full.update(CONTEXT.get((proxy_name, name, side), {}))
                check_bound(proxy_name, proxy, prop, element, side, bound, full)
                tried += 1
        Delete(proxy)
checks.check(tried > 0, "%d bounds tried" % tried)
if not arguments.only:
    stale = sorted({key[:2] for table in (GUI_HINTS, VALUE_AT_BOUND, OTHER_NAMES, CONTEXT, COSTLY) for key in table}
                   - seen)
    checks.check(not stale, "every listed property has a range in the XML: %s" % stale)
checks.finish()
