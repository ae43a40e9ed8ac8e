# SPDX-License-Identifier: GPL-3.0-or-later
"""PlantSegmentationFilter's accuracy on exact truth: simulated plants (TreeFromSketchSource with leaves, LeafId and
Organ on every cell), scanned by VirtualScanner from 1, 2 and 4 positions with range noise of 0.1 % and 1 % of a
leaf's length, segmented with the filter's defaults, scored point by point against the labels each beam carried.

    pvpython benchmarks/segmentation/segmentation_accuracy.py [--plugin build/.../PlantMorph.so] [--quick]
        [--plants herb,shrub,tree] [--positions 1,2,4] [--noise 0.001,0.01] [--scans DIR] [--fit]

The plant kind *petioled* (not in the default set) is the shrub whose blades each sit on a petiole: a tube of
radius 1.2 % of the blade's length, 30 % of it long, leaving the blade's base 30 degrees below the blade in line with
its midrib (cells Region 5, so the tree gives them Organ 2). `--plants petioled` scores it.

Plants of other species and leaf sizes (not in the default set either; `--plants
shrub-entire,shrub-lobed,shrub-watermelon,shrub-sizes`): the shrub with the LeafOutlineSource blade of preset Entire
(elliptic), of preset Lobed (five lobes), of the Space curve model's Watermelon (palmate, five sub-lobed lobes), and
the shrub of the default blade whose leaves taper to half their length at the twig's tip (LeafTipScale 0.5) and
spread at random (LeafScaleSpread 0.15, Seed 1). The other species' blades are scaled to the default blade's area
(LeafScale 1.448, 1.281 and 0.852); the scans' noise is that of the shrub. The kind *sympodial* (`--plants
sympodial`) is a sympodial tree (TreeType 1, Depth 3, ChildCount 3, the shrub's other properties) about 20 long with
Entire blades of length 1: its thinnest twigs are only 2-3 point spacings across.

Scores per run: leaf IoU and wood IoU (points), petiole IoU (Organ 2; on a plant without petioles, the points called
petiole, every one an error), leaf instance precision and recall matched at IoU 0.5 (recall over
the true leaves with at least 100 scanned points; precision over every predicted leaf), the points, the true and
found leaves, the merged true leaves (unmatched although one instance holds over half of them) and the fragments
(unmatched instances mostly of one leaf, holding no quarter of another), and the segmentation's wall and CPU time (the
process's, all threads). Prints a Markdown table (benchmarks/README.md keeps it).
Then the leaves table's Base against the truth: over the matched leaves whose base was scanned (a scanned blade point
within 5 % of the leaf's length of its true base, the blade's points of the smallest TCoords v), how many have their
Base within 5 % and within 25 % of the length of the true base. On plants with petioles, the leaves table's
PetioleLength against each matched leaf's true petiole (the extent of its Organ 2 points along their main axis): how
many leaves got one, and how many of those within 5 % and within 20 % of the truth.

With `--fit`, each scan's leaf points (LeafId >= 0; the cloud goes whole, LeafId -1 is on no leaf) also go to
LeafFitFilter (LeafIdArray LeafId, UpAxis Y, its other defaults, as examples/main_segment_plant.py), and a second
table gives the leaf areas against the truth: each true leaf's area is the sum of its blade cells (Organ 1) on the
simulated plant, rebuilt from its parameters. Per scan: the matched leaves (IoU > 0.5) fitted (Status 0 or 1) and
their median |area error| and fraction within 3 %; the plant's leaf area (the fitted areas of every fitted row,
matched or not) against the true area of every leaf and of the leaves with at least 100 scanned points; the rows not
fitted (Status 2) and their reasons. Beside them, to tell the segmentation's share from the fit's and the scan's:
the same true leaves fitted on their true labels (each true blade's scanned points alone), and pooled, the matched
leaves seen whole (0.99 of the blade's area or more within 2-4 % of a leaf's length of the leaf's own scanned
points; a leaf seen in part fits small). A third table sets the Traits' EstimatedArea (a leaf seen in part estimated
from the plant's leaves seen whole) beside Area: the matched leaves' median error, the share within 3 % and the
plant's sum; a fourth adds the Plant table's UnassignedLeafArea (the segmentation's leaf points it gave no leaf,
LeafId -1 and Organ 1: LeafFitFilter gets the whole segmented cloud and counts them) to that sum. `--fit-csv FILE`
writes one line per matched leaf (the found and true LeafId, points, areas, the area on the true labels, the share
seen, EstimatedArea and AreaRule, HiddenMargin, ExtentsSeen, Length and Width, Status and Message). With `--fit` it
also counts the matched leaves whose fitted base (the Outline's midvein end, LeafUV (0, 0)) lies more than a quarter
of the leaf's length from the true base (the blade's points of the smallest TCoords v): turned end to end, or based
at a cut edge; and, over the matched leaves whose base was scanned, those whose fitted base lies within 5 % and
within 25 % of the length of the true base (as for the leaves table's Base); `--orient-by-wood 0` fits without the
wood's help (LeafFitFilter's OrientByWood) to compare.
"""
import argparse
import math
import os
import time

HERE = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser()
parser.add_argument("--plugin", default=os.path.join(HERE, "..", "..", "build", "lib", "paraview-5.11", "plugins",
                                                     "PlantMorph", "PlantMorph.so"))
parser.add_argument("--plants", default="herb,shrub,tree")
parser.add_argument("--positions", default="1,2,4")
parser.add_argument("--noise", default="0.001,0.01", help="range noise as fractions of the leaf length")
parser.add_argument("--quick", action="store_true", help="coarser scans (a smoke run)")
parser.add_argument("--fit", action="store_true", help="also fit each found leaf (LeafFitFilter) and score its area")
parser.add_argument("--orient-by-wood", type=int, default=1, help="with --fit: LeafFitFilter's OrientByWood (0 to "
                    "compare: each leaf's base from its shape alone)")
parser.add_argument("--fit-csv", default="", help="with --fit: a CSV file for every fitted row matched to a true leaf")
parser.add_argument("--scans", default="",
                    help="a folder for the scans: each is read from it when there, else scanned and written to it, so "
                         "two versions of the filter are compared on the same points without scanning again")
arguments = parser.parse_args()

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

LoadPlugin(os.path.abspath(arguments.plugin), remote=False, ns=globals())

# name: (tree properties, leaf length, the scanner's distance in plant sizes, angular step in degrees)
PLANTS = {
    # a small herbaceous plant: a stem, three shoots, nine large leaves
    "herb": (dict(Preset=0, TreeType=0, Depth=1, ChildCount=3, Ratio=0.6, Length=4.0, Radius=0.08, LeafCount=3,
                  LeafScale=1.5, LeafAngle=50.0, Sides=12), 1.5, 1.5, 0.12),
    # a shrub: 64 leaves on 16 twigs
    "shrub": (dict(Preset=0, TreeType=0, Depth=2, ChildCount=4, Ratio=0.7, Length=6.0, Radius=0.15, LeafCount=4,
                   LeafScale=1.0, Sides=12), 1.0, 1.5, 0.08),
    # a small tree: 500 leaves on 125 twigs
    "tree": (dict(Preset=0, TreeType=0, Depth=3, ChildCount=5, Ratio=0.7, Length=10.0, Radius=0.3, LeafCount=4,
                  LeafScale=1.0, Sides=12), 1.0, 1.5, 0.05),
    # the shrub with a petiole on every blade (the tree scales blade and petiole together to LeafScale along +Y:
    # 1.26 makes the blade about 1.0 long)
    "petioled": (dict(Preset=0, TreeType=0, Depth=2, ChildCount=4, Ratio=0.7, Length=6.0, Radius=0.15, LeafCount=4,
                      LeafScale=1.26, Sides=12), 1.0, 1.5, 0.08),
}
# Plants of other species and of leaf sizes that vary (not in the default set): the shrub with the blade of another
# LeafOutlineSource preset, or with the default blade at sizes that taper towards the twigs' tips and spread at random.
# Each blade's LeafScale gives it the default blade's area (0.734 at length 1), so the plants differ in the blades'
# shape, not in how much of the shrub they cover; the scans' noise stays that of the shrub (of length 1).
SHRUB = PLANTS["shrub"]
SPECIES_BLADES = {  # name: (LeafOutlineSource properties, the blade's area over its length squared)
    "shrub-entire": (dict(Preset="Entire"), 0.3501),  # entire, elliptic, 0.61 as wide as long
    "shrub-lobed": (dict(Preset="Lobed"), 0.4471),  # five lobes (paper 000 Fig. 1)
    "shrub-watermelon": (dict(Model="Space curve", SpaceCurvePreset="Watermelon (5 lobes, sub-lobed)"), 1.0106),
}
for kind, (blade, fill) in SPECIES_BLADES.items():
    PLANTS[kind] = (dict(SHRUB[0], LeafScale=round(math.sqrt(0.7339 / fill), 3)),) + SHRUB[1:]
# leaf j of a twig's four LeafTipScale 0.5 at the tip, and a log-normal spread of 0.15 (Seed 1)
PLANTS["shrub-sizes"] = (dict(SHRUB[0], LeafTipScale=0.5, LeafScaleSpread=0.15, Seed=1),) + SHRUB[1:]
# A sympodial tree about 20 long (not in the default set): its thinnest leafy twigs, of radius 0.02-0.03 (2-3 point spacings
# across at the shrub's angular step) carrying blades of preset Entire of length 1 (LeafScale 1: the blade, not its
# area, matches the default blade's).
PLANTS["sympodial"] = (dict(SHRUB[0], TreeType=1, Depth=3, ChildCount=3),) + SHRUB[1:]
SPECIES_BLADES["sympodial"] = (dict(Preset="Entire"), 0.3501)
PETIOLE_LENGTH, PETIOLE_RADIUS, PETIOLE_DROP = 0.3, 0.012, 30.0  # of the blade's length; degrees below the blade


def leaf_with_petiole():
    """The default blade (XY plane, base at the origin, midrib along +Y) with a petiole: a triangulated tube leaving
    the base backwards and PETIOLE_DROP degrees below the blade, cells Region 5 (the blade's 0), its end at z = 0."""
    blade = LeafOutlineSource()
    b = servermanager.Fetch(blade).GetBounds()
    length = b[3] - b[2]
    drop = math.radians(PETIOLE_DROP)
    end = [0.0, -PETIOLE_LENGTH * length * math.cos(drop), -PETIOLE_LENGTH * length * math.sin(drop)]
    tube = Tube(Input=Line(Point1=[0.0, 0.0, 0.0], Point2=end, Resolution=20), Radius=PETIOLE_RADIUS * length,
                NumberofSides=12, Capping=0)
    parts = []
    for source, region in ((ExtractSurface(Input=blade), 0), (tube, 5)):
        parts.append(Calculator(Input=Triangulate(Input=source), AttributeType="Cell Data", ResultArrayName="Region",
                                ResultArrayType="Int", Function=str(region)))
    # the tree puts the leaf's lowest y at the twig's surface, its z unchanged: the petiole's end goes to z = 0
    lifted = Transform(Input=AppendGeometry(Input=parts))
    lifted.Transform.Translate = [0.0, 0.0, -end[2]]
    return lifted


def plant_surface(name, properties):
    # the default blade (with a petiole for the petioled plant), instanced at every leaf
    blade = leaf_with_petiole() if name == "petioled" else LeafOutlineSource(**SPECIES_BLADES.get(name, ({},))[0])
    tree = TreeFromSketchSource(**properties)
    tree.Leaf = OutputPort(blade, 0)
    plant = AppendGeometry(Input=[OutputPort(tree, 0), OutputPort(tree, 2)])
    plant.UpdatePipeline()
    return plant


def scan(plant, surface, positions, noise, step):
    b = surface.GetBounds()
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
    places = []
    for k in range(positions):
        angle = 2 * math.pi * k / positions + 0.3
        places += [centre[0] + size * math.cos(angle), centre[1] + 0.3 * size, centre[2] + size * math.sin(angle)]
    scanner = VirtualScanner(Input=plant, Positions=places, LookAt=centre, Up=[0, 1, 0], HorizontalFieldOfView=80,
                             VerticalFieldOfView=80, AngularStep=step, RangeNoise=noise, Seed=1,
                             MaximumRange=5 * size)
    scanner.UpdatePipeline()
    return scanner


surfaces = {}  # name: (the plant's pipeline, its surface), made when a scan needs it


def stored_scan(name, positions, noise, step):
    """The scan from arguments.scans when it holds it (written by an earlier run), else a new one (written there)."""
    path = os.path.join(arguments.scans, "%s_%d_%g%s.vtp" % (name, positions, noise, "_quick" if arguments.quick else ""))
    if arguments.scans and os.path.exists(path):
        reader = XMLPolyDataReader(FileName=[path])
        reader.UpdatePipeline()
        return reader
    if name not in surfaces:
        plant = plant_surface(name, PLANTS[name][0])
        surfaces[name] = (plant, servermanager.Fetch(plant))
    scanner = scan(*surfaces[name], positions, noise * PLANTS[name][1], step)
    if not arguments.scans:
        return scanner
    os.makedirs(arguments.scans, exist_ok=True)
    SaveData(path, proxy=scanner)
    Delete(scanner)
    reader = XMLPolyDataReader(FileName=[path])
    reader.UpdatePipeline()
    return reader


def scores(true_organ, true_leaf, organ, leaf):
    result = {}
    for name, code in (("leaf", 1), ("wood", 0), ("petiole", 2)):
        t, p = true_organ == code, organ == code
        union = numpy.count_nonzero(t | p)
        result[name + "_iou"] = numpy.count_nonzero(t & p) / union if union else float("nan")
    result["petiole_true"] = numpy.count_nonzero(true_organ == 2)
    result["petiole_called"] = numpy.count_nonzero(organ == 2)
    true_leaf = numpy.where(true_organ == 1, true_leaf, -1)  # a leaf instance is its blade: its petiole is Organ 2
    true_ids, true_counts = numpy.unique(true_leaf[true_leaf >= 0], return_counts=True)
    big = set(true_ids[true_counts >= 100].tolist())
    sizes = dict(zip(true_ids.tolist(), true_counts.tolist()))
    pred_ids = numpy.unique(leaf[leaf >= 0])
    matched_pred, matched_true, fragments, holder, match = 0, set(), 0, {}, {}
    for pid in pred_ids:
        mine = leaf == pid
        overlap_ids, overlaps = numpy.unique(true_leaf[mine & (true_leaf >= 0)], return_counts=True)
        for tid, inter in zip(overlap_ids.tolist(), overlaps.tolist()):
            if 2 * inter > sizes[tid]:
                holder[tid] = int(pid)  # this instance holds over half of that leaf
        if len(overlaps) == 0:
            continue
        best = int(numpy.argmax(overlaps))
        tid, inter = int(overlap_ids[best]), int(overlaps[best])
        if inter / (numpy.count_nonzero(mine) + sizes[tid] - inter) > 0.5:
            matched_pred += 1
            matched_true.add(tid)
            match[int(pid)] = tid
        elif 2 * inter > numpy.count_nonzero(mine) and all(
                4 * o < sizes[t] for t, o in zip(overlap_ids.tolist(), overlaps.tolist()) if t != tid):
            fragments += 1  # mostly one leaf's points and no quarter of another leaf: a piece of a leaf
    result["precision"] = matched_pred / len(pred_ids) if len(pred_ids) else float("nan")
    result["recall"] = len(matched_true & big) / len(big) if big else float("nan")
    result["true_leaves"] = len(big)
    result["found_leaves"] = len(pred_ids)
    result["matched_found"], result["matched_true"] = matched_pred, len(matched_true & big)
    # a true leaf missed although one instance holds over half of it: merged with another leaf or with wood
    result["merged"] = sum(1 for t in big - matched_true if t in holder)
    result["fragments"] = fragments
    result["match"], result["big"], result["sizes"] = match, big, sizes
    return result


def true_leaf_areas(name):
    """Each true leaf's blade area (its Organ 1 cells summed per LeafId) on the simulated plant."""
    if name not in surfaces:
        plant = plant_surface(name, PLANTS[name][0])
        surfaces[name] = (plant, servermanager.Fetch(plant))
    sizes = CellSize(Input=surfaces[name][0], ComputeVertexCount=0, ComputeLength=0, ComputeArea=1, ComputeVolume=0,
                     ComputeSum=0)
    cells = servermanager.Fetch(sizes).GetCellData()
    area, organ, leaf = (vtk_to_numpy(cells.GetArray(a)) for a in ("Area", "Organ", "LeafId"))
    Delete(sizes)
    blade = (organ == 1) & (leaf >= 0)
    areas[name] = numpy.bincount(leaf[blade].astype(numpy.int64), weights=area[blade])
    centres = CellCenters(Input=surfaces[name][0])
    centre = vtk_to_numpy(servermanager.Fetch(centres).GetPoints().GetData())
    Delete(centres)
    cell_areas[name] = centre[blade], area[blade], leaf[blade].astype(numpy.int64)
    return areas[name]


def voxel_keys(points, leaf, size):
    """One integer per (leaf, voxel of `size`) of each point."""
    cell = numpy.floor(points / size).astype(numpy.int64) + (1 << 20)
    return ((leaf * (1 << 21) + cell[:, 0]) * (1 << 21) + cell[:, 1]) * (1 << 21) + cell[:, 2]


def seen_areas(name, points, leaf, size):
    """Each true leaf's area seen: its blade cells with a point of that leaf within about `size` (their voxel or a
    neighbour of it), summed; a leaf seen in part has less."""
    centre, area, cell_leaf = cell_areas[name]
    keys = numpy.unique(voxel_keys(points[leaf >= 0], leaf[leaf >= 0], size))
    seen = numpy.zeros(len(centre), bool)
    for offset in ((i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)):
        probe = voxel_keys(centre + size * numpy.array(offset), cell_leaf, size)
        at = numpy.minimum(numpy.searchsorted(keys, probe), len(keys) - 1)
        seen |= keys[at] == probe
    return numpy.bincount(cell_leaf[seen], weights=area[seen], minlength=len(areas[name]))


areas, cell_areas = {}, {}  # name: each true leaf's area; each cell's blade area and LeafId (-1 off the blades)
bases = {}  # name: per true leaf, its base and its length (None: the plant's leaves carry no TCoords)
petioles = {}  # name: per true leaf, its petiole's length (empty: the plant's leaves have none)


def true_leaf_bases(name):
    """Each true leaf's base (its blade points of the smallest TCoords v: the blade's base, where LeafOutlineSource
    puts v = 0) and its length (to the points of the largest v), from the simulated plant."""
    if name not in surfaces:
        plant = plant_surface(name, PLANTS[name][0])
        surfaces[name] = (plant, servermanager.Fetch(plant))
    data = surfaces[name][1].GetPointData()
    if data.GetArray("TCoords") is None:
        bases[name] = None
        return None
    points = vtk_to_numpy(surfaces[name][1].GetPoints().GetData())
    v = vtk_to_numpy(data.GetArray("TCoords"))[:, 1]
    leaf, organ = vtk_to_numpy(data.GetArray("LeafId")), vtk_to_numpy(data.GetArray("Organ"))
    bases[name] = {}
    for k in numpy.unique(leaf[(organ == 1) & (leaf >= 0)]):
        mine = (leaf == k) & (organ == 1)
        low = points[mine][v[mine] <= v[mine].min() + 1e-9].mean(axis=0)
        high = points[mine][v[mine] >= v[mine].max() - 1e-9].mean(axis=0)
        bases[name][int(k)] = (low, float(numpy.linalg.norm(high - low)))
    return bases[name]


def bases_scanned(truth_bases, scanned, truth):
    """The true leaves whose base was scanned: a scanned blade point of the leaf within 5 % of its length of the true
    base."""
    points = vtk_to_numpy(scanned.GetPoints().GetData())
    leaf, organ = vtk_to_numpy(truth.GetArray("LeafId")), vtk_to_numpy(truth.GetArray("Organ"))
    blade = organ == 1
    seen = set()
    for t in numpy.unique(leaf[blade & (leaf >= 0)]).tolist():
        if t in truth_bases:
            low, length = truth_bases[t]
            if numpy.linalg.norm(points[blade & (leaf == t)] - low, axis=1).min() <= 0.05 * length:
                seen.add(t)
    return seen


def table_bases(segmentation, match, truth_bases, seen_bases):
    """The leaves table's Base against each matched leaf's true base, over the leaves whose base was scanned
    (`seen_bases`): how many, and how many of their Base within 5 % and within 25 % of the length of the true base."""
    table = servermanager.Fetch(segmentation, idx=1)
    ids, base = vtk_to_numpy(table.GetColumnByName("LeafId")), vtk_to_numpy(table.GetColumnByName("Base"))
    seen = near = close = 0
    for row, k in enumerate(ids.tolist()):
        t = match.get(int(k))
        if t is None or t not in seen_bases:
            continue
        low, length = truth_bases[t]
        off = numpy.linalg.norm(base[row] - low) / length
        seen, near, close = seen + 1, near + int(off <= 0.05), close + int(off <= 0.25)
    return seen, near, close


def true_petiole_lengths(name):
    """Each true leaf's petiole length (the extent of its petiole points, Organ 2, along their main axis), from the
    simulated plant; empty for a plant without petioles."""
    if name not in surfaces:
        plant = plant_surface(name, PLANTS[name][0])
        surfaces[name] = (plant, servermanager.Fetch(plant))
    data = surfaces[name][1].GetPointData()
    points = vtk_to_numpy(surfaces[name][1].GetPoints().GetData())
    leaf, organ = vtk_to_numpy(data.GetArray("LeafId")), vtk_to_numpy(data.GetArray("Organ"))
    lengths = {}
    for k in numpy.unique(leaf[(organ == 2) & (leaf >= 0)]):
        mine = points[(leaf == k) & (organ == 2)]
        centred = mine - mine.mean(axis=0)
        axis = numpy.linalg.svd(centred, full_matrices=False)[2][0]
        lengths[int(k)] = float(numpy.ptp(centred @ axis))
    petioles[name] = lengths
    return lengths


def table_petioles(segmentation, match, true_lengths):
    """The leaves table's PetioleLength against the true petiole's length, over the matched leaves: how many have a
    petiole (PetioleLength > 0), and of those how many within 5 % and within 20 % of the true length."""
    table = servermanager.Fetch(segmentation, idx=1)
    ids, length = vtk_to_numpy(table.GetColumnByName("LeafId")), vtk_to_numpy(table.GetColumnByName("PetioleLength"))
    found = near = close = 0
    for row, k in enumerate(ids.tolist()):
        t = match.get(int(k))
        if t is None or t not in true_lengths or length[row] <= 0.0:
            continue
        off = abs(length[row] - true_lengths[t]) / true_lengths[t]
        found, near, close = found + 1, near + int(off <= 0.05), close + int(off <= 0.2)
    return found, near, close


def fitted_rows(cloud, true_blades=False):
    """LeafFitFilter on `cloud` by its LeafId (the found leaves', LeafId >= 0), or with `true_blades` on the scan's
    points of Organ 1 alone (the true blades'): (LeafId, Area, Status, Message, EstimatedArea, AreaRule, HiddenMargin,
    ExtentsSeen, Length, Width) per Traits row (a plugin without EstimatedArea: Area and NaN; without the view's
    columns, NaN), the CPU time and the Plant table's UnassignedLeafArea (0
    without it). The found leaves' fit gets the whole segmented cloud: its points of LeafId -1 are on no leaf, and
    those of them with Organ 1 (leaf points the segmentation gave no leaf) are the Plant table's
    UnassignedLeafPoints."""
    leaf_points = None
    if true_blades:
        leaf_points = Threshold(Input=cloud, Scalars=["POINTS", "Organ"])
        # set after the proxy exists: on an input already updated, its domain resets the range to the data's
        leaf_points.LowerThreshold, leaf_points.UpperThreshold = 1, 1
    fit = LeafFitFilter(Input=leaf_points or cloud, LeafIdArray="LeafId", UpAxis="Y")
    if fit.GetProperty("OrientByWood") is not None:
        fit.OrientByWood = arguments.orient_by_wood
    cpu_start = time.process_time()
    fit.UpdatePipeline()
    cpu = time.process_time() - cpu_start
    outline = servermanager.Fetch(fit, idx=1)
    fitted_bases = {}  # LeafId: the midvein's base (LeafUV (0, 0) on the Outline)
    if outline.GetNumberOfPoints():
        uv = vtk_to_numpy(outline.GetPointData().GetArray("LeafUV"))
        ids = vtk_to_numpy(outline.GetPointData().GetArray("LeafId"))
        xyz = vtk_to_numpy(outline.GetPoints().GetData())
        order = numpy.abs(uv).sum(axis=1)
        for k in numpy.unique(ids):
            mine = numpy.where(ids == k)[0]
            fitted_bases[int(k)] = xyz[mine[numpy.argmin(order[mine])]]
    plant = servermanager.Fetch(fit, idx=4)
    unassigned = plant.GetColumnByName("UnassignedLeafArea")
    unassigned = unassigned.GetValue(0) if unassigned else 0.0
    traits = servermanager.Fetch(fit, idx=2)
    column = lambda c: [traits.GetColumnByName(c).GetValue(k) for k in range(traits.GetNumberOfRows())]  # noqa: E731
    names = ["LeafId", "Area", "Status", "Message"]
    names += ["EstimatedArea", "AreaRule"] if traits.GetColumnByName("EstimatedArea") else ["Area", "Area"]
    rows = list(zip(*(column(c) for c in names))) if traits.GetNumberOfRows() else []
    if names[-1] == "Area":
        rows = [r[:5] + (float("nan"),) for r in rows]
    # the view's columns and the extents, for the CSV (NaN from a build without them)
    view = [column(c) if traits.GetColumnByName(c) else [float("nan")] * len(rows)
            for c in ("HiddenMargin", "ExtentsSeen", "Length", "Width")]
    rows = [r + tuple(v[k] for v in view) for k, r in enumerate(rows)]
    Delete(fit)
    if leaf_points:
        Delete(leaf_points)
    return rows, cpu, unassigned, fitted_bases


def fit_scores(fits, s, true_area, label):
    """Areas of the fitted rows against the truth: the matched leaves' errors, the plant's sum, the failures."""
    fitted = [r for r in fits if int(r[2]) != 2]
    errors, seen, estimated = [], [], []
    for leaf_id, area, status, message, estimate, rule, hidden, extents, length, width in fitted:
        tid = s["match"].get(int(leaf_id))
        if tid is not None:
            truth = true_area[tid]
            errors.append((area - truth) / truth)
            estimated.append((estimate - truth) / truth)
            seen.append(s["seen"][tid] / truth)
            fit_csv.append("%s,%d,%d,%d,%d,%.6g,%.6g,%.5f,%d,%.6g,%.4f,%.6g,%g,%.4g,%g,%.6g,%.6g,%s" % (
                label, leaf_id, tid, s["found_points"][int(leaf_id)], s["sizes"][tid], area, truth, errors[-1],
                int(status), s["true_fits"].get(tid, float("nan")), s["seen"][tid] / truth, estimate, rule, hidden,
                extents, length, width, message.replace(",", ";")))
    errors, estimated = numpy.abs(numpy.array(errors)), numpy.abs(numpy.array(estimated))
    # the fit alone on the true labels, over the same true leaves: the error the segmentation did not add
    alone = numpy.array([abs(s["true_fits"][t] / true_area[t] - 1) for t in s["match"].values() if t in s["true_fits"]])
    reasons = {}
    for r in fits:
        if int(r[2]) == 2:
            reasons[r[3]] = reasons.get(r[3], 0) + 1
    big_area = sum(true_area[t] for t in s["big"])
    return dict(fit_matched=len(errors), fit_within=int(numpy.count_nonzero(errors <= 0.03)),
                fit_median=float(numpy.median(errors)) if len(errors) else float("nan"), fit_rows=len(fits),
                fit_ok=len(fitted), fit_warned=sum(1 for r in fitted if int(r[2]) == 1),
                fit_failed=len(fits) - len(fitted), fit_reasons=reasons, fit_errors=errors, alone_errors=alone,
                fit_seen=numpy.array(seen), est_errors=estimated,
                est_within=int(numpy.count_nonzero(estimated <= 0.03)),
                est_median=float(numpy.median(estimated)) if len(estimated) else float("nan"),
                est_plant=sum(r[4] for r in fitted),
                alone_median=float(numpy.median(alone)) if len(alone) else float("nan"),
                fit_plant=sum(r[1] for r in fitted), true_plant=float(true_area.sum()), true_big=big_area)


fit_csv = ["scan,LeafId,TrueLeafId,Points,TruePoints,FittedArea,TrueArea,Error,Status,AreaOnTrueLabels,SeenFraction,"
           "EstimatedArea,AreaRule,HiddenMargin,ExtentsSeen,Length,Width,Message"]
rows = []
for name in arguments.plants.split(","):
    step = PLANTS[name][3]
    if arguments.quick:
        step *= 2
    for positions in [int(p) for p in arguments.positions.split(",")]:
        for noise in [float(v) for v in arguments.noise.split(",")]:
            scanner = stored_scan(name, positions, noise, step)
            segmentation = PlantSegmentationFilter(Input=scanner, UpAxis=1)
            start, cpu_start = time.time(), time.process_time()
            segmentation.UpdatePipeline()
            seconds, cpu = time.time() - start, time.process_time() - cpu_start
            cloud = servermanager.Fetch(segmentation)
            pd = cloud.GetPointData()
            if pd.GetArray("Organ") is None:
                print("%s, %d positions, noise %g: the filter gave no output" % (name, positions, noise))
                continue
            get = lambda array: vtk_to_numpy(pd.GetArray(array))  # noqa: E731
            # The scanner's labels (the hit cells') were passed through; the filter's own replace them by name, so
            # read the truth from the scan itself.
            scanned = servermanager.Fetch(scanner)
            truth = scanned.GetPointData()
            s = scores(vtk_to_numpy(truth.GetArray("Organ")), vtk_to_numpy(truth.GetArray("LeafId")), get("Organ"),
                       get("LeafId"))
            s.update(plant=name, positions=positions, noise=noise, points=cloud.GetNumberOfPoints(), seconds=seconds,
                     cpu=cpu)
            truth_bases = bases[name] if name in bases else true_leaf_bases(name)
            seen_bases = bases_scanned(truth_bases, scanned, truth) if truth_bases else set()
            s["base_seen"], s["base_near"], s["base_close"] = (
                table_bases(segmentation, s["match"], truth_bases, seen_bases) if truth_bases else (0, 0, 0))
            true_petioles = petioles[name] if name in petioles else true_petiole_lengths(name)
            s["petiole_leaves"] = len(true_petioles)
            s["petiole_found"], s["petiole_near"], s["petiole_close"] = (
                table_petioles(segmentation, s["match"], true_petioles) if true_petioles else (0, 0, 0))
            if arguments.fit:
                found_ids, found_counts = numpy.unique(get("LeafId"), return_counts=True)
                s["found_points"] = dict(zip(found_ids.tolist(), found_counts.tolist()))
                fits, s["fit_cpu"], s["unassigned_area"], fitted_bases = fitted_rows(segmentation)
                # turned: a matched leaf whose fitted base lies over a quarter of its length from its true base
                if truth_bases is not None:
                    off = {t: numpy.linalg.norm(fitted_bases[k] - truth_bases[t][0]) / truth_bases[t][1]
                           for k, t in s["match"].items() if k in fitted_bases and t in truth_bases}
                    s["based"], s["turned"] = len(off), sum(1 for d in off.values() if d > 0.25)
                    # the same over the leaves whose base was scanned, and those within 5 % of the length
                    seen = [d for t, d in off.items() if t in seen_bases]
                    s["fit_base_seen"] = (len(seen), sum(1 for d in seen if d <= 0.05),
                                          sum(1 for d in seen if d <= 0.25))
                # the fit alone: each true blade's scanned points
                true_fits, _, _, _ = fitted_rows(scanner, true_blades=True)
                s["true_fits"] = {int(r[0]): r[1] for r in true_fits if int(r[2]) != 2}
                true_area = areas[name] if name in areas else true_leaf_areas(name)
                # seen: blade within 2-4 % of a leaf's length (1-5 point spacings) of the leaf's scanned points
                blade_leaf = numpy.where(vtk_to_numpy(truth.GetArray("Organ")) == 1,
                                         vtk_to_numpy(truth.GetArray("LeafId")), -1).astype(numpy.int64)
                s["seen"] = seen_areas(name, vtk_to_numpy(scanned.GetPoints().GetData()), blade_leaf,
                                       0.02 * PLANTS[name][1])
                s.update(fit_scores(fits, s, true_area, "%s %d %g" % (name, positions, noise)))
            rows.append(s)
            print("%(plant)s positions %(positions)d noise %(noise)g: %(points)d points, leaf IoU %(leaf_iou).3f, "
                  "wood IoU %(wood_iou).3f, petiole IoU %(petiole_iou).3f "
                  "(%(petiole_called)d called, %(petiole_true)d true), "
                  "precision %(precision).3f, recall %(recall).3f "
                  "(%(found_leaves)d found, %(true_leaves)d true with >= 100 points), %(seconds).1f s wall, %(cpu).1f s CPU"
                  % s, flush=True)
            Delete(segmentation)
            Delete(scanner)

print()
print("| plant | positions | noise (of leaf length) | points | leaf IoU | wood IoU | petiole IoU | petiole "
      "called / true | precision | recall | leaves found / true | merged | fragments | wall (s) | CPU (s) |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for s in rows:
    print("| %(plant)s | %(positions)d | %(noise)g | %(points)d | %(leaf_iou).3f | %(wood_iou).3f | "
          "%(petiole_iou).3f | %(petiole_called)d / %(petiole_true)d | %(precision).3f | %(recall).3f | "
          "%(found_leaves)d / %(true_leaves)d | %(merged)d | %(fragments)d | %(seconds).1f | %(cpu).1f |" % s)
if rows:
    total = lambda key: sum(s[key] for s in rows)  # noqa: E731
    print("\nPooled over the %d runs: precision %.3f (%d of %d), recall %.3f (%d of %d), mean leaf IoU %.3f, mean wood "
          "IoU %.3f, %d merged leaves, %d fragments, CPU %.1f s"
          % (len(rows), total("matched_found") / max(1, total("found_leaves")), total("matched_found"),
             total("found_leaves"), total("matched_true") / max(1, total("true_leaves")), total("matched_true"),
             total("true_leaves"), total("leaf_iou") / len(rows), total("wood_iou") / len(rows), total("merged"),
             total("fragments"), total("cpu")))
    print("\nThe leaves table's Base, over the matched leaves whose base was scanned (a blade point within 5 %% of the "
          "length of the true base; plants whose leaves carry TCoords): %d leaves, Base within 5 %% of the length of "
          "the true base %d (%.2f), within 25 %% %d (%.2f); per scan: %s"
          % (total("base_seen"), total("base_near"), total("base_near") / max(1, total("base_seen")),
             total("base_close"), total("base_close") / max(1, total("base_seen")),
             ", ".join("%s %d %g: %d / %d / %d" % (s["plant"], s["positions"], s["noise"], s["base_near"],
                                                   s["base_close"], s["base_seen"]) for s in rows)))
    with_petioles = [s for s in rows if s["petiole_leaves"]]
    if with_petioles:
        print("\nThe leaves table's PetioleLength, over the matched leaves of plants with petioles: leaves given a "
              "petiole / true leaves, and of those within 5 %% and 20 %% of the true petiole's length; per scan: %s"
              % ", ".join("%s %d %g: %d of %d, %d / %d" % (s["plant"], s["positions"], s["noise"], s["petiole_found"],
                                                           s["petiole_leaves"], s["petiole_near"], s["petiole_close"])
                          for s in with_petioles))

if arguments.fit and rows:
    print("\nLeaf areas after LeafFitFilter (the matched leaves fitted: median |area error| and the share within 3 %; "
          "the plant: the fitted rows' areas summed against every true leaf and the leaves of >= 100 points):\n")
    print("| plant | positions | noise | matched leaves fitted | median area error | within 3 % | rows fitted / all "
          "(warned) | plant area: fitted / true all / true >= 100 points | error against all / >= 100 points | "
          "median error, true labels | fit CPU (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for s in rows:
        print("| %s | %d | %g | %d | %.1f %% | %d (%.0f %%) | %d / %d (%d) | %.2f / %.2f / %.2f | "
              "%+.1f %% / %+.1f %% | "
              "%.1f %% | %.1f |" % (s["plant"], s["positions"], s["noise"], s["fit_matched"], 100 * s["fit_median"],
                          s["fit_within"], 100 * s["fit_within"] / max(1, s["fit_matched"]), s["fit_ok"],
                          s["fit_rows"], s["fit_warned"], s["fit_plant"], s["true_plant"], s["true_big"],
                          100 * (s["fit_plant"] / s["true_plant"] - 1), 100 * (s["fit_plant"] / s["true_big"] - 1),
                          100 * s["alone_median"], s["fit_cpu"]))
    pooled = numpy.concatenate([s["fit_errors"] for s in rows])
    reasons = {}
    for s in rows:
        for reason, count in s["fit_reasons"].items():
            reasons[reason] = reasons.get(reason, 0) + count
    total = lambda key: sum(s[key] for s in rows)  # noqa: E731
    print("\nPooled: %d matched leaves fitted, median |area error| %.2f %%, %d (%.1f %%) within 3 %%; plant leaf area "
          "per scan within 3 %% of every leaf's on %d of %d scans, of the leaves of >= 100 points on %d; %d of %d rows "
          "fitted (%d warned), %d not fitted"
          % (len(pooled), 100 * numpy.median(pooled) if len(pooled) else float("nan"),
             numpy.count_nonzero(pooled <= 0.03), 100 * numpy.count_nonzero(pooled <= 0.03) / max(1, len(pooled)),
             sum(1 for s in rows if abs(s["fit_plant"] / s["true_plant"] - 1) <= 0.03), len(rows),
             sum(1 for s in rows if abs(s["fit_plant"] / s["true_big"] - 1) <= 0.03),
             total("fit_rows") - total("fit_failed"), total("fit_rows"), total("fit_warned"), total("fit_failed")))
    print("Plant leaf area summed over the scans: fitted %.2f against %.2f of every leaf (%+.1f %%), %.2f of the "
          "leaves of >= 100 points (%+.1f %%)" % (total("fit_plant"), total("true_plant"),
                                           100 * (total("fit_plant") / total("true_plant") - 1), total("true_big"),
                                           100 * (total("fit_plant") / total("true_big") - 1)))
    whole = pooled[numpy.concatenate([s["fit_seen"] for s in rows]) >= 0.99]
    print("Of them seen whole (0.99 of the blade or more near its scanned points): %d, median |area error| %.2f %%, "
          "%.1f %% within 3 %%" % (len(whole), 100 * numpy.median(whole) if len(whole) else float("nan"),
                                   100 * numpy.count_nonzero(whole <= 0.03) / max(1, len(whole))))
    estimated_whole = numpy.concatenate([s["est_errors"] for s in rows])[
        numpy.concatenate([s["fit_seen"] for s in rows]) >= 0.99]
    print("EstimatedArea of the same: median |area error| %.2f %%, %.1f %% within 3 %%; %d of them more than 1 %% "
          "further from the truth than Area" % (
              100 * numpy.median(estimated_whole) if len(estimated_whole) else float("nan"),
              100 * numpy.count_nonzero(estimated_whole <= 0.03) / max(1, len(estimated_whole)),
              numpy.count_nonzero(estimated_whole > whole + 0.01)))
    print("\nEstimatedArea (a leaf seen in part from the plant's leaves seen whole) beside Area:\n")
    print("| plant | positions | noise | median area error: fitted / estimated | within 3 %: fitted / estimated | "
          "plant area: fitted / estimated / true all | error against all: fitted / estimated | against >= 100 "
          "points: fitted / estimated |")
    print("|---|---|---|---|---|---|---|---|")
    for s in rows:
        print("| %s | %d | %g | %.1f %% / %.1f %% | %d / %d | %.2f / %.2f / %.2f | %+.1f %% / %+.1f %% | "
              "%+.1f %% / %+.1f %% |" % (
                  s["plant"], s["positions"], s["noise"], 100 * s["fit_median"], 100 * s["est_median"],
                  s["fit_within"], s["est_within"], s["fit_plant"], s["est_plant"], s["true_plant"],
                  100 * (s["fit_plant"] / s["true_plant"] - 1), 100 * (s["est_plant"] / s["true_plant"] - 1),
                  100 * (s["fit_plant"] / s["true_big"] - 1), 100 * (s["est_plant"] / s["true_big"] - 1)))
    estimated = numpy.concatenate([s["est_errors"] for s in rows])
    print("\nPooled, estimated: median |area error| %.2f %% (fitted %.2f %%), %d (%.1f %%) within 3 %% (fitted %d); "
          "plant leaf area summed %.2f (fitted %.2f) against %.2f of every leaf (%+.1f %%, fitted %+.1f %%), of the "
          "leaves of >= 100 points %+.1f %% (fitted %+.1f %%); per scan within 3 %% of every leaf's on %d of %d" % (
              100 * numpy.median(estimated) if len(estimated) else float("nan"),
              100 * numpy.median(pooled) if len(pooled) else float("nan"), numpy.count_nonzero(estimated <= 0.03),
              100 * numpy.count_nonzero(estimated <= 0.03) / max(1, len(estimated)),
              numpy.count_nonzero(pooled <= 0.03), total("est_plant"), total("fit_plant"), total("true_plant"),
              100 * (total("est_plant") / total("true_plant") - 1), 100 * (total("fit_plant") / total("true_plant") - 1),
              100 * (total("est_plant") / total("true_big") - 1), 100 * (total("fit_plant") / total("true_big") - 1),
              sum(1 for s in rows if abs(s["est_plant"] / s["true_plant"] - 1) <= 0.03), len(rows)))
    print("\nThe Plant table's UnassignedLeafArea (the leaf points on no leaf, at the fitted leaves' points per area) "
          "added to the estimated area:\n")
    print("| plant | positions | noise | unassigned leaf area | plant area: estimated / with unassigned / true all | "
          "error against all: estimated / with unassigned | against >= 100 points: estimated / with unassigned |")
    print("|---|---|---|---|---|---|---|")
    for s in rows:
        total_area = s["est_plant"] + s["unassigned_area"]
        print("| %s | %d | %g | %.3f | %.2f / %.2f / %.2f | %+.1f %% / %+.1f %% | %+.1f %% / %+.1f %% |" % (
            s["plant"], s["positions"], s["noise"], s["unassigned_area"], s["est_plant"], total_area,
            s["true_plant"], 100 * (s["est_plant"] / s["true_plant"] - 1), 100 * (total_area / s["true_plant"] - 1),
            100 * (s["est_plant"] / s["true_big"] - 1), 100 * (total_area / s["true_big"] - 1)))
    with_unassigned = total("est_plant") + total("unassigned_area")
    print("\nPooled, with unassigned: plant leaf area summed %.2f (estimated %.2f) against %.2f of every leaf "
          "(%+.1f %%, estimated %+.1f %%), of the leaves of >= 100 points %+.1f %% (estimated %+.1f %%); per scan "
          "within 3 %% of every leaf's on %d of %d, nearer the truth than estimated on %d" % (
              with_unassigned, total("est_plant"), total("true_plant"),
              100 * (with_unassigned / total("true_plant") - 1),
              100 * (total("est_plant") / total("true_plant") - 1), 100 * (with_unassigned / total("true_big") - 1),
              100 * (total("est_plant") / total("true_big") - 1),
              sum(1 for s in rows if abs((s["est_plant"] + s["unassigned_area"]) / s["true_plant"] - 1) <= 0.03),
              len(rows), sum(1 for s in rows if abs(s["est_plant"] + s["unassigned_area"] - s["true_plant"])
                             < abs(s["est_plant"] - s["true_plant"]))))
    based = [s for s in rows if "based" in s]
    if based:
        print("\nBase and apex (OrientByWood %d): matched leaves whose fitted base lies over a quarter of the leaf's "
              "length from its true base, per scan: %s; pooled %d of %d"
              % (arguments.orient_by_wood, ", ".join("%s %d %g: %d of %d" % (s["plant"], s["positions"], s["noise"],
                                                                             s["turned"], s["based"]) for s in based),
                 sum(s["turned"] for s in based), sum(s["based"] for s in based)))
        print("The fitted base over the matched leaves whose base was scanned (as for the leaves table's Base above): "
              "within 5 %% / 25 %% of the length of the true base, per scan: %s; pooled %d / %d of %d"
              % (", ".join("%s %d %g: %d / %d of %d" % (s["plant"], s["positions"], s["noise"], s["fit_base_seen"][1],
                                                       s["fit_base_seen"][2], s["fit_base_seen"][0]) for s in based),
                 sum(s["fit_base_seen"][1] for s in based), sum(s["fit_base_seen"][2] for s in based),
                 sum(s["fit_base_seen"][0] for s in based)))
    alone = numpy.concatenate([s["alone_errors"] for s in rows])
    print("The fit alone on the true labels of the same leaves: median |area error| %.2f %%, %.1f %% within 3 %%"
          % (100 * numpy.median(alone) if len(alone) else float("nan"),
             100 * numpy.count_nonzero(alone <= 0.03) / max(1, len(alone))))
    for reason, count in sorted(reasons.items(), key=lambda item: -item[1]):
        print("  not fitted, %d rows: %s" % (count, reason))
    if arguments.fit_csv:
        with open(arguments.fit_csv, "w") as f:
            f.write("\n".join(fit_csv) + "\n")
