# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: TreeFitFilter against exact truth. TreeFromSketchSource trees (templates of both types and two sizes) are
scanned by VirtualScanner from four terrestrial positions with range noise and fitted with the filter's defaults;
the fit is compared with the tree's own skeleton (radius at every skeleton point, branch ids, parents, depth).

Truth and how it is compared (benchmarks/README.md, "tree_fit_accuracy"):
  * volumes: the skeleton's frusta (pi/3 (r0^2 + r0 r1 + r1^2) L per skeleton segment); the welded surface the scanner
    sees (MeshVolume, vtkMassProperties of the Branches output) is printed too: junctions make it smaller;
  * trunk: the branch with ParentId -1; DBH at BreastHeight above the lowest point; height: the surface's extent
    along the up axis (+Y for TreeFromSketchSource);
  * first-order branches found: a true child of the trunk is found when a fitted branch (any order >= 1) passes
    within max(3 base radii, 5 % of its length) of the true branch's point at a quarter of its length and of its
    point at three quarters; its angle (the chord over the first third against the parent's axis, as the filter
    measures it) is compared with the true one.

  * stroke trees: TreeFromSketchSource in Strokes mode on strokes traced in its XY plane (the example's seven
    strokes at two sizes, and the same strokes alone), lifted to 3-D by its phyllotaxis rule;
  * with --leaves the trees carry their leaves and the scan the surfaces' Organ label (0 wood, 1 leaf, 2 petiole);
    each scan is fitted twice: with WoodArray the scanner's Organ ("label": the exact wood) and behind
    PlantSegmentationFilter with WoodArray its Organ ("segmented": what a user without labels runs). Height is then
    compared with the top of the tree, leaves included (foresters' height), WoodHeight with the wood's.

  * --physical: leaves of a broadleaf's size (0.15 m, 267 a twig: the 1-m leaves' area, so the crown keeps its leaf
    area index, printed per tree) scanned from stations one tree height away, as a terrestrial scan of one tree is
    set up; without it the leaves are the source's default, 1 m long on trees of 7-19 m: the stress case.

    pvpython tree_fit_accuracy.py --plugin build/lib/paraview-5.11/plugins/PlantMorph/PlantMorph.so [--quick]
                                  [--leaves | --physical] [--json out.json] [--top-probe] [--cache DIR]
"""
import argparse
import json
import math
import os
import time

import numpy

PHYSICAL_LEAF_LENGTH = 0.15  # m: a broadleaf's leaf (beech 5-10 cm, oak 7-14, lime 6-12, maple 8-15, plane 12-25)

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--quick", action="store_true", help="two trees only")
parser.add_argument("--leaves", action="store_true", help="scan the trees with their leaves; fit with the scan's "
                    "Organ label and behind PlantSegmentationFilter")
parser.add_argument("--noise", type=float, default=0.003, help="range noise deviation (m)")
parser.add_argument("--json", default=None)
parser.add_argument("--trees", default=None, help="comma-separated names: only these trees")
parser.add_argument("--top-probe", action="store_true", help="no fits: per tree, the highest return of scans of "
                    "its top by the benchmark's stations, a finer step, more stations, farther ones and a raised one "
                    "(why the scans' tops lie below the tree's; with --leaves)")
parser.add_argument("--leaf-length", type=float, default=None, help="with --leaves: LeafScale, the leaves' length in "
                    "metres (default the source's, 1 m: the stress case)")
parser.add_argument("--leaf-count", type=int, default=None, help="with --leaves: LeafCount, leaves per twig (default "
                    "the source's, 6)")
parser.add_argument("--stations", choices=["benchmark", "forester"], default="benchmark", help="benchmark: four "
                    "stations 1.2 H away (at least 8 m); forester: four stations H away, as a terrestrial scan of one "
                    "tree is set up (beams 1.2 cm apart at the tree in both)")
parser.add_argument("--physical", action="store_true", help="leaves of a broadleaf's size: --leaves --leaf-length "
                    "0.15 --leaf-count 267 (the 1-m leaves' area per twig) --stations forester")
parser.add_argument("--cache", default=None, help="folder: each scan (and its segmentation) is written there once "
                    "and read back on later runs, so that two versions of the fit see the same points")
arguments = parser.parse_args()
if arguments.physical:
    arguments.leaves, arguments.stations = True, "forester"
    arguments.leaf_length = arguments.leaf_length or PHYSICAL_LEAF_LENGTH
    arguments.leaf_count = arguments.leaf_count or round(6 * (1.0 / arguments.leaf_length) ** 2)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkFiltersCore import vtkMassProperties, vtkTriangleFilter  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter  # noqa: E402

LoadPlugin(arguments.plugin, ns=globals())

# (name, TreeFromSketchSource properties): the templates, two sizes each, and variations of angle and phyllotaxis.
TREES = [
    ("mono-small", dict(TreeType="Monopodial", Length=6.0, Radius=0.15, Depth=2, ChildCount=6)),
    ("mono-large", dict(TreeType="Monopodial", Length=12.0, Radius=0.3, Depth=2, ChildCount=8)),
    ("sym-small", dict(TreeType="Sympodial", Length=3.0, Radius=0.12, Depth=3, ChildCount=2, Ratio=0.0)),
    ("sym-large", dict(TreeType="Sympodial", Length=5.0, Radius=0.3, Depth=3, ChildCount=3, Ratio=0.0)),
    ("mono-wide", dict(TreeType="Monopodial", Length=8.0, Radius=0.2, Depth=2, ChildCount=7, MonopodialAngle=50.0)),
    ("mono-58", dict(TreeType="Monopodial", Length=10.0, Radius=0.25, Depth=2, ChildCount=10, PhyllotaxisA=5,
                     PhyllotaxisB=8, Ratio=0.6)),
    ("sym-narrow", dict(TreeType="Sympodial", Length=4.0, Radius=0.2, Depth=3, ChildCount=2, Ratio=0.0,
                        SympodialAngle=35.0)),
    ("mono-deep", dict(TreeType="Monopodial", Length=8.0, Radius=0.25, Depth=3, ChildCount=5)),
    ("sym-wide", dict(TreeType="Sympodial", Length=4.0, Radius=0.25, Depth=3, ChildCount=3, Ratio=0.0,
                      SympodialAngle=65.0)),
    ("mono-short", dict(TreeType="Monopodial", Length=4.0, Radius=0.1, Depth=2, ChildCount=6)),
]
# Strokes traced in the XY plane, trunk first, 16 m tall; scaled for the sizes. A copy of the example's
# (examples/main_tree_from_sketch.py) on purpose: the benchmark's trees must not change when the example does.
STROKES = [
    [0, 0, 0, 0.3, 4, 0, -0.2, 8, 0, 0.2, 12, 0, 0, 16, 0],
    [0.2, 7, 0, 2, 8.5, 0, 4, 9.5, 0, 6.5, 11.5, 0],
    [-0.1, 6, 0, -2, 7, 0, -4.5, 8, 0, -6, 10, 0],
    [0.1, 11, 0, 1.5, 12.5, 0, 3, 14.5, 0],
    [0, 10, 0, -1.5, 11.5, 0, -3.5, 13.5, 0, -4, 15, 0],
    [4, 9.5, 0, 5, 8.5, 0, 6.5, 8.2, 0],
    [-4.5, 8, 0, -5.5, 7, 0, -7, 6.8, 0],
]
STROKE_TREES = [
    ("stroke-small", 0.4, dict(Radius=0.12, StrokeSubtreeDepth=1, ChildCount=4)),
    ("stroke-large", 0.75, dict(Radius=0.25, StrokeSubtreeDepth=1, ChildCount=4)),
    ("stroke-only", 0.5, dict(Radius=0.15, StrokesOnly=1)),
]
TREES += [(name, dict(properties, Mode="Strokes", TreeType="Monopodial", PhyllotaxisA=2, PhyllotaxisB=5,
                      SegmentsPerBranch=16, Ratio=0.6, _strokes=[[scale * v for v in stroke] for stroke in STROKES]))
          for name, scale, properties in STROKE_TREES]
if arguments.quick:
    TREES = TREES[:2] + TREES[-1:]
if arguments.trees:
    TREES = [t for t in TREES if t[0] in arguments.trees.split(",")]
UP = numpy.array([0.0, 1.0, 0.0])
BREAST = 1.3


def polylines(data):
    """Each line cell's point coordinates and point ids."""
    points = vtk_to_numpy(data.GetPoints().GetData())
    lines = []
    ids = data.GetLines()
    ids.InitTraversal()
    import vtk
    cell = vtk.vtkIdList()
    while ids.GetNextCell(cell):
        lines.append([cell.GetId(k) for k in range(cell.GetNumberOfIds())])
    return points, lines


def truth_of(tree):
    skeleton = servermanager.Fetch(tree, idx=1)
    points, lines = polylines(skeleton)
    radius = vtk_to_numpy(skeleton.GetPointData().GetArray("Radius"))
    branch_id = vtk_to_numpy(skeleton.GetCellData().GetArray("BranchId"))
    parent_id = vtk_to_numpy(skeleton.GetCellData().GetArray("ParentId"))
    branches = {}
    for c, line in enumerate(lines):
        p, r = points[line], radius[line]
        seg = numpy.linalg.norm(numpy.diff(p, axis=0), axis=1)
        volume = float(numpy.sum(math.pi / 3 * seg * (r[:-1] ** 2 + r[:-1] * r[1:] + r[1:] ** 2)))
        branches[int(branch_id[c])] = dict(points=p, radii=r, parent=int(parent_id[c]), length=float(seg.sum()),
                                           volume=volume)
    trunk = [b for b in branches.values() if b["parent"] < 0][0]
    surface = servermanager.Fetch(tree, idx=0)
    triangles = vtkTriangleFilter()
    triangles.SetInputData(surface)
    mass = vtkMassProperties()
    mass.SetInputConnection(triangles.GetOutputPort())
    mass.Update()
    bounds = surface.GetBounds()
    low = bounds[2]
    heights = trunk["points"] @ UP - low
    dbh = 2 * float(numpy.interp(BREAST, heights, trunk["radii"])) if heights[-1] > BREAST else float("nan")
    trunk_id = [k for k, b in branches.items() if b["parent"] < 0][0]
    for b in branches.values():  # orders: steps up the parents to the trunk
        b["order"], q = 0, b
        while q["parent"] >= 0:
            b["order"], q = b["order"] + 1, branches[q["parent"]]
    return dict(branches=branches, trunk=trunk_id, total=sum(b["volume"] for b in branches.values()),
                trunk_volume=trunk["volume"], mesh=mass.GetVolume(), height=bounds[3] - bounds[2], dbh=dbh,
                branch_length=sum(b["length"] for k, b in branches.items() if k != trunk_id), low=low)


def at_fraction(p, f):
    seg = numpy.linalg.norm(numpy.diff(p, axis=0), axis=1)
    s = numpy.concatenate([[0], numpy.cumsum(seg)])
    t = f * s[-1]
    return numpy.array([numpy.interp(t, s, p[:, k]) for k in range(3)])


def distance_to_polyline(q, p):
    best = float("inf")
    for a, b in zip(p[:-1], p[1:]):
        ab = b - a
        t = numpy.clip(numpy.dot(q - a, ab) / max(numpy.dot(ab, ab), 1e-300), 0, 1)
        best = min(best, numpy.linalg.norm(q - a - t * ab))
    return best


def base_angle(p, parent_points):
    """The chord over the first third against the parent's axis nearest the base, degrees (as the filter)."""
    d = at_fraction(p, 1 / 3) - p[0]
    d /= numpy.linalg.norm(d)
    k = numpy.argmin([distance_to_polyline(p[0], parent_points[i:i + 2]) for i in range(len(parent_points) - 1)])
    dp = parent_points[k + 1] - parent_points[k]
    dp /= numpy.linalg.norm(dp)
    return math.degrees(math.acos(max(-1.0, min(1.0, float(numpy.dot(d, dp))))))


def fitted_branches(fit):
    skeleton = servermanager.Fetch(fit, idx=1)
    points, lines = polylines(skeleton)
    ids = vtk_to_numpy(skeleton.GetCellData().GetArray("BranchId"))
    table = servermanager.Fetch(fit, idx=3)
    column = {table.GetColumnName(c): vtk_to_numpy(table.GetColumn(c)) for c in range(table.GetNumberOfColumns())}
    rows = {int(column["BranchId"][k]): k for k in range(table.GetNumberOfRows())}
    out = {}
    for c, line in enumerate(lines):
        k = rows[int(ids[c])]
        out[int(ids[c])] = dict(points=points[line], order=int(column["Order"][k]), angle=float(column["Angle"][k]))
    return out


def passes_along(b, f):
    """Whether fitted branch f passes within max(3 base radii, 5 % of its length) of true branch b at a quarter and at
    three quarters of its length; the sum of both distances."""
    tolerance = max(3 * b["radii"][0], 0.05 * b["length"])
    d1 = distance_to_polyline(at_fraction(b["points"], 0.25), f["points"])
    d3 = distance_to_polyline(at_fraction(b["points"], 0.75), f["points"])
    return d1 + d3 if d1 < tolerance and d3 < tolerance else None


def match_orders(truth, fitted):
    """Per order: (true branches, fitted branches, true branches matched by a fitted branch of the same order)."""
    top = max([b["order"] for b in truth["branches"].values()] + [f["order"] for f in fitted.values()])
    out = []
    for order in range(top + 1):
        true = [b for b in truth["branches"].values() if b["order"] == order]
        same = [f for f in fitted.values() if f["order"] == order]
        found = sum(1 for b in true if any(passes_along(b, f) is not None for f in same))
        out.append((len(true), len(same), found))
    return out


def match_first_order(truth, fitted):
    """True first-order branches, those found, their angle errors, and per branch (in the JSON, "first"): the height
    of its base, its true angle, the angle of the fitted branch found for it (None when none is) and the orders of
    the fitted branches that pass along it (of any order: a branch found at the wrong order, or not at all)."""
    found, errors, detail = 0, [], []
    first = [b for b in truth["branches"].values() if b["parent"] == truth["trunk"]]
    trunk_points = truth["branches"][truth["trunk"]]["points"]
    for b in first:
        best = None
        for f in fitted.values():
            if f["order"] < 1:
                continue
            d = passes_along(b, f)
            if d is not None and (best is None or d < best[0]):
                best = (d, f)
        true_angle = base_angle(b["points"], trunk_points)
        if best is not None:
            found += 1
            errors.append(best[1]["angle"] - true_angle)
        detail.append(dict(height=float(b["points"][0] @ UP - truth["low"]), length=b["length"], angle=true_angle,
                           fitted_angle=best[1]["angle"] if best is not None else None,
                           orders=sorted(f["order"] for f in fitted.values() if passes_along(b, f) is not None)))
    return len(first), found, errors, detail


def scan(tree, truth):
    """Four stations around the tree, 1.5 above its base, looking at its middle: 1.2 H away (at least 8 m; the
    benchmark's), or H away (--stations forester: a terrestrial scan of one tree, the stations about a tree height
    out so that the scanner sees from the base to the top); beams about 1.2 cm apart at the tree in both."""
    height = truth["tree_height"]
    distance = max(8.0, 1.2 * height) if arguments.stations == "benchmark" else height
    centre = [0.0, truth["low"] + 0.5 * height, 0.0]
    positions = []
    for k in range(4):
        a = 2 * math.pi * (k + 0.125) / 4
        positions += [distance * math.cos(a), truth["low"] + 1.5, distance * math.sin(a)]
    field = 2 * math.degrees(math.atan(0.6 * height / distance)) + 10
    horizontal = vertical = field
    if arguments.stations == "forester":  # near stations: the crown's near side and top need a wider field
        bounds = tree.GetDataInformation().GetBounds()
        crown = max(abs(v) for v in (bounds[0], bounds[1], bounds[4], bounds[5]))
        near = max(distance - crown, 0.3 * distance)
        horizontal = min(170.0, 2 * math.degrees(math.atan((crown + 0.5) / near)) + 4)
        look = math.atan2(centre[1] - truth["low"] - 1.5, distance)
        corners = [math.atan2(y - 1.5, x) for y in (0.0, height) for x in (near, distance + crown)]
        vertical = min(170.0, 2 * math.degrees(max(abs(c - look) for c in corners)) + 6)
    step = math.degrees(0.012 / distance)  # about 1.2 cm between beams at the tree
    return VirtualScanner(Input=tree, ScannerType="Terrestrial", Positions=positions, LookAt=centre, Up=[0, 1, 0],
                          HorizontalFieldOfView=horizontal, VerticalFieldOfView=vertical, AngularStep=step,
                          RangeNoise=arguments.noise, Seed=1, MaximumBeams=4e8)


def top_probe(name, surface, truth):
    """The highest return, against the tree's height, of scans through a window about the top fifth of the tree (no
    noise), from stations around it at distance * height (at least 8 for the benchmark's own), raised by `lift`,
    beams `mm` apart at 10 m; per set-up the best station and each station's."""
    height, low = truth["tree_height"], truth["low"]
    bounds = surface.GetDataInformation().GetBounds()
    crown = max(abs(v) for v in (bounds[0], bounds[1], bounds[4], bounds[5]))
    look = [0.0, low + 0.9 * height, 0.0]
    benchmark_mm = 10000 * 0.012 / max(8.0, 1.2 * height)
    probe = VirtualScanner(Input=surface, ScannerType="Terrestrial", Up=[0, 1, 0], LookAt=look, Seed=1,
                           MaximumBeams=4e8)
    setups = [("the benchmark's", 1.2, 4, benchmark_mm, 1.5, True), ("step / 4", 1.2, 4, benchmark_mm / 4, 1.5, True),
              ("at 1.0 H, 6 mm", 1.0, 4, 6.0, 1.5, False), ("8 stations", 1.2, 8, benchmark_mm, 1.5, True),
              ("24 stations", 1.2, 24, benchmark_mm, 1.5, True), ("at 2 H", 2.0, 4, benchmark_mm, 1.5, False),
              ("at 3 H", 3.0, 4, benchmark_mm, 1.5, False), ("raised 10 m", 1.2, 4, benchmark_mm, 10.0, True)]
    for label, factor, count, mm, lift, floor in setups:
        distance = max(8.0, factor * height) if floor else factor * height
        tops = []
        for k in range(count):
            a = 2 * math.pi * (k + 0.125) / count
            probe.Positions = [distance * math.cos(a), low + lift, distance * math.sin(a)]
            probe.HorizontalFieldOfView = 2 * math.degrees(math.atan((crown + 0.5) / distance)) + 2
            probe.VerticalFieldOfView = 2 * math.degrees(math.atan(0.2 * height / math.hypot(distance, look[1] - low
                                                                                              - lift))) + 4
            probe.AngularStep = math.degrees(mm / 10000)
            probe.UpdatePipeline()
            points = vtk_to_numpy(servermanager.Fetch(probe).GetPoints().GetData())
            tops.append(100 * ((points @ UP).max() - low) / height - 100 if len(points) else float("nan"))
        print(f"{name:12s} top probe {label:15s} ({distance:5.1f} m, {mm:4.1f} mm at 10 m): highest return "
              f"{max(tops):+6.2f} % of the height; per station " + " ".join(f"{t:+.1f}" for t in tops), flush=True)
    Delete(probe)


def hull_area(xy):
    """Area of the convex hull of 2-D points (monotone chain)."""
    pts = sorted(set(map(tuple, numpy.round(xy, 4))))

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    h = lower[:-1] + upper[:-1]
    return 0.5 * abs(sum(h[i][0] * h[(i + 1) % len(h)][1] - h[(i + 1) % len(h)][0] * h[i][1] for i in range(len(h))))


def leaf_area_index(tree):
    """The crown's LAI: the leaves' one-sided area over the area of the tree's outline seen from above (the convex
    hull of its wood and leaves projected on the ground)."""
    leaves = servermanager.Fetch(tree, idx=2)
    triangles = vtkTriangleFilter()
    triangles.SetInputData(leaves)
    mass = vtkMassProperties()
    mass.SetInputConnection(triangles.GetOutputPort())
    mass.Update()
    points = numpy.vstack([vtk_to_numpy(leaves.GetPoints().GetData()),
                           vtk_to_numpy(servermanager.Fetch(tree, idx=0).GetPoints().GetData())])
    ground = numpy.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # the plane normal to UP (+Y)
    return mass.GetSurfaceArea() / hull_area(points @ ground.T)


def build_tree(properties):
    """TreeFromSketchSource from the template properties, or from strokes (key _strokes) in Strokes mode."""
    properties = dict(properties)
    strokes = properties.pop("_strokes", None)
    if strokes is not None:
        lines = [PolyLineSource(Points=points) for points in strokes]
        properties["Strokes"] = AppendGeometry(Input=lines)  # the trunk first
    if arguments.leaves and arguments.leaf_length is not None:
        properties["LeafScale"] = arguments.leaf_length
    if arguments.leaves and arguments.leaf_count is not None:
        properties["LeafCount"] = arguments.leaf_count
    return TreeFromSketchSource(Preset="Custom", Leaves=1 if arguments.leaves else 0, Sides=32,
                                Joints="Seated tubes", **properties)


def wood_scores(cloud, labelled):
    """Of the scan's truly wood points, the share the fit took as wood; of its leaf points, the share taken as wood."""
    organ = vtk_to_numpy(cloud.GetPointData().GetArray("Organ"))
    wood = vtk_to_numpy(labelled.GetPointData().GetArray("Wood"))
    true_wood = organ == 0
    return (float(numpy.mean(wood[true_wood] != 0)) if true_wood.any() else float("nan"),
            float(numpy.mean(wood[~true_wood] != 0)) if (~true_wood).any() else float("nan"))


def evaluate(name, variant, fit, truth, cloud):
    """One fit against the truth: its row (printed), or a failed row."""
    start, cpu = time.perf_counter(), time.process_time()
    fit.UpdatePipeline()
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    table = servermanager.Fetch(fit, idx=2)
    if table.GetNumberOfRows() == 0:
        print(f"{name} ({variant}): the fit failed")
        return dict(tree=name, variant=variant, failed=True)
    traits = {table.GetColumnName(c): table.GetValue(0, c).ToDouble() for c in range(2, table.GetNumberOfColumns())}
    fitted = fitted_branches(fit)
    total_first, found, angle_errors, first_detail = match_first_order(truth, fitted)
    orders = match_orders(truth, fitted)
    wood_kept, leaf_taken = wood_scores(cloud, servermanager.Fetch(fit, idx=4)) if arguments.leaves else (1.0, 0.0)
    row = dict(tree=name, variant=variant, points=cloud.GetNumberOfPoints(), seconds=seconds, cpu=cpu,
               total=100 * (traits["TotalVolume"] / truth["total"] - 1),
               trunk=100 * (traits["TrunkVolume"] / truth["trunk_volume"] - 1),
               branch=100 * (traits["BranchVolume"] / (truth["total"] - truth["trunk_volume"]) - 1),
               mesh_total=100 * (traits["TotalVolume"] / truth["mesh"] - 1),
               dbh=100 * (traits["DBH"] / truth["dbh"] - 1),
               height=100 * (traits["Height"] / truth["tree_height"] - 1),
               wood_height=100 * (traits["WoodHeight"] / truth["height"] - 1),
               scan_top=100 * ((vtk_to_numpy(cloud.GetPoints().GetData()) @ UP).max() - truth["low"])
               / truth["tree_height"] - 100,
               branch_length=100 * (traits["TotalBranchLength"] / truth["branch_length"] - 1),
               first_true=total_first, first_found=found,
               angle_rms=math.sqrt(sum(e * e for e in angle_errors) / len(angle_errors)) if angle_errors else float("nan"),
               measured=traits["MeasuredVolumeFraction"], true_branches=len(truth["branches"]) - 1,
               fitted_branches=traits["BranchCount"], orders=orders, wood_kept=wood_kept, leaf_taken=leaf_taken,
               first=first_detail)
    print(f"{name:12s} {variant:9s} pts {row['points']:8d} t {seconds:6.2f}s cpu {cpu:6.2f}s total {row['total']:+6.1f}% "
          f"trunk {row['trunk']:+6.1f}% branch {row['branch']:+7.1f}% (mesh {row['mesh_total']:+6.1f}%) "
          f"DBH {row['dbh']:+5.1f}% H {row['height']:+5.1f}% (scan top {row['scan_top']:+5.1f}%) "
          f"woodH {row['wood_height']:+5.1f}% BL {row['branch_length']:+6.1f}% 1st {found}/{total_first} "
          f"angle {row['angle_rms']:5.1f} branches {int(row['fitted_branches'])}/{row['true_branches']} "
          f"measured {row['measured']:.2f} wood kept {wood_kept:.3f} leaf as wood {leaf_taken:.4f}", flush=True)
    print("  per order, found/true (fitted): " + ", ".join(
        f"{k}: {found}/{true} ({count})" for k, (true, count, found) in enumerate(orders)), flush=True)
    return row


def cached_scan(scanner, path):
    """The scan read from `path`, written there first (with PlantSegmentationFilter's Organ as SegmentedOrgan when
    the trees have leaves) if it is not there yet."""
    if not os.path.exists(path):
        data = scanner
        if arguments.leaves:
            segmentation = PlantSegmentationFilter(Input=scanner, UpAxis="Y")
            labels = servermanager.Fetch(segmentation).GetPointData().GetArray("Organ")
            data = servermanager.Fetch(scanner)
            labels.SetName("SegmentedOrgan")
            data.GetPointData().AddArray(labels)
            Delete(segmentation)
        else:
            data = servermanager.Fetch(scanner)
        writer = vtkXMLPolyDataWriter()
        writer.SetFileName(path)
        writer.SetInputData(data)
        writer.Write()
    Delete(scanner)
    return XMLPolyDataReader(FileName=[path])


rows = []
for name, properties in TREES:
    tree = build_tree(properties)
    tree.UpdatePipeline()
    truth = truth_of(tree)
    surface = tree
    if arguments.leaves:  # wood and leaves in one surface; the scanner carries each cell's Organ (0 wood)
        surface = AppendGeometry(Input=[tree, OutputPort(tree, 2)])
        top = max(tree.GetDataInformation().GetBounds()[3], OutputPort(tree, 2).GetDataInformation().GetBounds()[3])
        truth["tree_height"] = top - truth["low"]
        truth["lai"] = leaf_area_index(tree)
        print(f"{name:12s} leaves {arguments.leaf_length or 1.0:.2f} m x {arguments.leaf_count or 6} per twig: crown "
              f"LAI {truth['lai']:.2f} (one-sided leaf area over the crown's projected area)", flush=True)
    else:
        truth["tree_height"] = truth["height"]
    if arguments.top_probe:
        top_probe(name, surface, truth)
        continue
    scanner = scan(surface, truth)
    if arguments.cache:
        scanner = cached_scan(scanner, f"{arguments.cache}/{name}{'-leaves' if arguments.leaves else ''}.vtp")
    scanner.UpdatePipeline()
    cloud = servermanager.Fetch(scanner)
    if arguments.leaves:
        fits = [("label", TreeFitFilter(Input=scanner, UpAxis="Y", WoodArray="Organ"))]
        if arguments.cache:  # the cached scan holds the segmentation's label as SegmentedOrgan (0 wood)
            segmentation = None
            fits.append(("segmented", TreeFitFilter(Input=scanner, UpAxis="Y", WoodArray="SegmentedOrgan",
                                                    WoodValues="Zero is wood")))
        else:
            segmentation = PlantSegmentationFilter(Input=scanner, UpAxis="Y")
            fits.append(("segmented", TreeFitFilter(Input=segmentation, UpAxis="Y", WoodArray="Organ")))
    else:
        fits = [("bare", TreeFitFilter(Input=scanner, UpAxis="Y"))]
    for variant, fit in fits:
        if variant == "segmented" and segmentation is not None:  # the segmentation's time is its own, not the fit's
            start, cpu = time.perf_counter(), time.process_time()
            segmentation.UpdatePipeline()
            print(f"  segmentation {time.perf_counter() - start:.2f} s wall, {time.process_time() - cpu:.2f} s CPU",
                  flush=True)
        rows.append(evaluate(name, variant, fit, truth, cloud))
        rows[-1]["lai"] = truth.get("lai")
        Delete(fit)
    if arguments.leaves and segmentation is not None:
        Delete(segmentation)
    Delete(scanner)

for variant in sorted({r["variant"] for r in rows}):
    ok = [r for r in rows if not r.get("failed") and r["variant"] == variant]
    if not ok:
        continue

    def rms(key):
        return math.sqrt(sum(r[key] ** 2 for r in ok) / len(ok))

    def mean(key):
        return sum(r[key] for r in ok) / len(ok)

    failed = sum(1 for r in rows if r.get("failed") and r["variant"] == variant)
    print(f"{variant}: over {len(ok)} trees ({failed} failed): total volume mean {mean('total'):+.1f}% "
          f"rRMSE {rms('total'):.1f}%; trunk rRMSE {rms('trunk'):.1f}%; branch mean {mean('branch'):+.1f}% "
          f"rRMSE {rms('branch'):.1f}%; DBH rRMSE {rms('dbh'):.1f}%; height rRMSE {rms('height'):.1f}% "
          f"(mean {mean('height'):+.1f}%); wood height rRMSE {rms('wood_height'):.1f}%; "
          f"branch length mean {mean('branch_length'):+.1f}%; first-order found "
          f"{sum(r['first_found'] for r in ok)}/{sum(r['first_true'] for r in ok)}; same order found "
          f"{sum(o[2] for r in ok for o in r['orders'])}/{sum(o[0] for r in ok for o in r['orders'])}, fitted "
          f"{sum(o[1] for r in ok for o in r['orders'])}; angle RMS "
          f"{math.sqrt(numpy.nanmean([r['angle_rms'] ** 2 for r in ok])):.1f} deg; wood kept {mean('wood_kept'):.3f}, "
          f"leaf as wood {mean('leaf_taken'):.4f}; time {sum(r['seconds'] for r in ok):.1f} s wall, "
          f"{sum(r['cpu'] for r in ok):.1f} s CPU for {sum(r['points'] for r in ok)} points")
if arguments.json:
    with open(arguments.json, "w") as f:
        json.dump(rows, f, indent=1)
