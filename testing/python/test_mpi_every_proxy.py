# SPDX-License-Identifier: GPL-3.0-or-later
"""pvbatch under MPI: every PlantMorph source and filter gives, on 1, 2 or 4 ranks, the result of a serial run, once.

Sources make their data on rank 0 (piece 0), except TreeFromSketchSource's branches and leaves, made by pieces and
checked as triangle sets by test_mpi_tree_pieces.py (its skeleton stays on rank 0, here); the reader reads its file
by pieces, each rank its byte range, and CloudComparisonFilter compares each rank's points there
(test_mpi_cloud_comparison.py checks that in detail); filters that need the whole leaf run where it is, and gather it
onto rank 0 when it arrives split over ranks (here by D3). For every output port:
the totals over all ranks equal the serial counts (nothing duplicated, nothing lost) and the data gathered from all
ranks is bit-identical to the serial output. Run once serially with --write-reference (pvpython), then as
`mpirun -np N pvbatch test_mpi_every_proxy.py ... --ranks N`."""
import glob
import math
import os

from plantmorph_testing import (check_rank_count, Checks, fingerprint, load_plugin, load_reference,
                               MPI_EQUALITY_ARGUMENTS, parse_arguments, save_reference)

arguments = parse_arguments(MPI_EQUALITY_ARGUMENTS)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
DATA = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data"))
soybean_file = sorted(glob.glob(os.path.join(DATA, "leaf-clouds", "soybean_*.txt")))[0]
tip_file = os.path.join(DATA, "cucumber-wilting-tip.csv")
WILT_TIME = 0.5

# Every source and filter, each on small data.
rectangle = LeafOutlineSource(Preset=4, Resolution=45)
space = LeafOutlineSource(Model="Space curve", SpaceCurvePreset="Paper 002 Fig. 5", Resolution=40)
spline = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", Resolution=30)
palmate = LeafOutlineSource(Model="Space curve", SpaceCurvePreset="Paper 002 Fig. 8, 3 lobes", Resolution=24)
veins = VenationFilter(Input=rectangle, Preset="Poplar (paper 000 Fig. 12)", Seed=4)
loop = AdaptiveLoopFilter(Input=spline, MaximumLevel=1)
curl = LeafCurlFilter(Input=loop, LongitudinalAngle=60.0, TransverseAngle=40.0)
spline_veins = VenationFilter(Input=spline, Preset="Custom", Pattern="Palmate (actinodromous)")
wilt = WiltingSimulator(Input=OutputPort(spline_veins, 1), Veins=OutputPort(spline_veins, 0), Preset="Cucumber",
                        Resolution=14, Duration=WILT_TIME, FrameInterval=0.25)
tree = TreeFromSketchSource()
cloud = LeafCloudReader(FileName=soybean_file)
comparison = CloudComparisonFilter(Input=cloud, Reference=spline, Scale=0.1)
leaf_fit = LeafFitFilter(Input=cloud)
tip = LeafCloudReader(FileName=tip_file)
trajectory = TrajectoryComparisonFilter(Input=OutputPort(tip, 1), Simulated=OutputPort(tip, 1),
                                        MeasuredColumns=["measured_x", "measured_y", "measured_z"],
                                        SimulatedColumns=["paper_sim_x", "paper_sim_y", "paper_sim_z"])
# A leaf split over the ranks (D3 partitions it, each cell on one rank; ExtractSurface makes it polygons again): the whole-leaf filters
# gather it on rank 0. Serially D3 passes the leaf through, so the references are the unsplit leaf's.
split = ExtractSurface(Input=D3(Input=rectangle, BoundaryMode="Assign cells uniquely"))
split_curl = LeafCurlFilter(Input=split, LongitudinalAngle=60.0, TransverseAngle=40.0)
split_loop = AdaptiveLoopFilter(Input=split, MaximumLevel=1)
split_comparison = CloudComparisonFilter(Input=D3(Input=cloud, BoundaryMode="Assign cells uniquely"), Reference=spline,
                                         Scale=0.1)
# The leaf fit of a scan split over the ranks: its points are sent to the leaf's one owner (rank 0, one leaf).
split_fit = LeafFitFilter(Input=D3(Input=cloud, BoundaryMode="Assign cells uniquely"))
# VirtualScanner: a noisy scan of the tree (made on rank 0, its beams shared over the ranks), and a scan of the split leaf from above (gathered whole).
scan = VirtualScanner(Input=tree, Positions=[0.0, -40.0, 5.0, 30.0, 10.0, 8.0], LookAt=[0.0, 0.0, 5.0], AngularStep=0.5,
                      RangeNoise=0.01, DropoutProbability=0.1, Seed=3)
leaf_bounds = servermanager.Fetch(rectangle).GetBounds()
leaf_centre = [(leaf_bounds[2 * k] + leaf_bounds[2 * k + 1]) / 2 for k in range(3)]
leaf_size = max(leaf_bounds[1] - leaf_bounds[0], leaf_bounds[3] - leaf_bounds[2])
split_scan = VirtualScanner(Input=split, ScannerType="Depth camera", Resolution=[64, 64], LookAt=leaf_centre,
                            Positions=[leaf_centre[0], leaf_centre[1], leaf_centre[2] + 2 * leaf_size])
# TreeFitFilter on a distributed scan of a leafless tree from three tripods: the tree's points sent to its owner rank,
# which fits it; the Scan stays where its points are, with the owner's values.
wood = TreeFromSketchSource(Preset="Custom", TreeType="Monopodial", Length=4.0, Radius=0.12, Depth=1, ChildCount=4,
                            Sides=24, Joints="Seated tubes", Leaves=0)
tripods = [coordinate for k in range(3) for coordinate in (7 * math.cos(2 * math.pi * (k + 0.1) / 3), 1.5,
                                                           7 * math.sin(2 * math.pi * (k + 0.1) / 3))]
wood_scan = VirtualScanner(Input=wood, Positions=tripods, LookAt=[0, 2.0, 0], Up=[0, 1, 0], HorizontalFieldOfView=50,
                           VerticalFieldOfView=60, AngularStep=0.15, RangeNoise=0.003, Seed=3)
tree_fit = TreeFitFilter(Input=wood_scan, UpAxis="Y")
SPLIT = {"split_curl": split_curl, "split_loop": split_loop, "split_scan": split_scan}

OUTPUTS = {
    "outline_rectangle_blade": (rectangle, 0), "outline_rectangle_outline": (rectangle, 1),
    "outline_space_blade": (space, 0), "outline_space_outline": (space, 1),
    "outline_spline_blade": (spline, 0), "outline_palmate_blade": (palmate, 0), "outline_palmate_outline": (palmate, 1),
    "venation_veins": (veins, 0), "venation_blade": (veins, 1), "venation_statistics": (veins, 2),
    "venation_areole_histogram": (veins, 3),
    "adaptive_loop": (loop, 0), "leaf_curl": (curl, 0),
    "wilting_leaf": (wilt, 0), "wilting_voxels": (wilt, 1), "wilting_table": (wilt, 2), "wilting_veins": (wilt, 3),
    "tree_skeleton": (tree, 1),
    "cloud_reader": (cloud, 0), "cloud_distances": (comparison, 0), "cloud_histogram": (comparison, 1),
    "cloud_statistics": (comparison, 2),
    "fit_blade": (leaf_fit, 0), "fit_outline": (leaf_fit, 1), "fit_traits": (leaf_fit, 2), "fit_scan": (leaf_fit, 3),
    "trajectory_samples": (trajectory, 0), "trajectory_summary": (trajectory, 1),
    "scanner_cloud": (scan, 0), "scanner_setup": (scan, 1),
    "tree_fit_cylinders": (tree_fit, 0), "tree_fit_skeleton": (tree_fit, 1), "tree_fit_trees": (tree_fit, 2),
    "tree_fit_branches": (tree_fit, 3),
}
TIMED = {"wilting_leaf", "wilting_voxels", "wilting_veins"}


def fetch(proxy, port, name):
    if name in TIMED:
        # At the time: through a filter that asks for it (Fetch itself uses the pipeline's current time).
        return servermanager.Fetch(ForceTime(Input=OutputPort(proxy, port), ForcedTime=WILT_TIME,
                                             IgnorePipelineTime=1))
    return servermanager.Fetch(proxy, idx=port)


def counts(data):
    if data.IsA("vtkTable"):
        return [data.GetNumberOfRows(), data.GetNumberOfColumns()]
    return [data.GetNumberOfPoints(), data.GetNumberOfCells()]


def statistics(table):
    return {table.GetColumnName(c): table.GetValue(0, c).ToDouble() for c in range(table.GetNumberOfColumns())
            if table.GetColumn(c).IsA("vtkDataArray")}


TREE_FIT_SCAN_ARRAYS = ["TreeId", "CylinderId", "BranchId", "Wood", "FitDistance", "TCoords"]


def tree_fit_scan(data):
    """TreeFitFilter's Scan with the filter's own point arrays and VirtualScanner's TCoords, which it passes through:
    the scanner's replica of the tree made by pieces keeps both points of each texture seam (0 and 1 around the
    tube), so the points hitting next to a seam get the serial run's TCoords."""
    import vtk
    own = vtk.vtkPolyData()
    own.SetPoints(data.GetPoints())
    own.SetVerts(data.GetVerts())
    for name in TREE_FIT_SCAN_ARRAYS:
        own.GetPointData().AddArray(data.GetPointData().GetArray(name))
    return own


def sorted_points(data):
    """The distinct points, rounded to 1e-9 first so that rounding noise cannot change their sorted order."""
    points = vtk_to_numpy(data.GetPoints().GetData())
    return numpy.unique(numpy.round(points, 9), axis=0)


reference_file = os.path.join(arguments.work, "mpi_every_proxy_reference.json")
if arguments.write_reference:
    reference = {}
    for name, (proxy, port) in OUTPUTS.items():
        data = fetch(proxy, port, name)
        reference[name] = {"counts": counts(data), "fingerprint": fingerprint(data)}
    for name, proxy in SPLIT.items():
        data = servermanager.Fetch(proxy)
        reference[name + "_points"] = sorted_points(data).tolist()
        reference[name + "_count"] = [data.GetNumberOfPoints(), data.GetNumberOfCells()]
    scan_of_fit = tree_fit_scan(servermanager.Fetch(tree_fit, idx=4))
    reference["tree_fit_scan"] = {"counts": counts(scan_of_fit), "fingerprint": fingerprint(scan_of_fit)}
    reference["split_comparison"] = statistics(servermanager.Fetch(split_comparison, idx=2))
    reference["split_fit"] = statistics(servermanager.Fetch(split_fit, idx=2))
    save_reference(reference_file, reference)
    raise SystemExit(0)

checks = Checks()
ranks = check_rank_count(checks, arguments)
reference = load_reference(reference_file)
for name, (proxy, port) in OUTPUTS.items():
    data = fetch(proxy, port, name)
    serial = reference[name]
    checks.check(counts(data)[0] > 0, "%s: not empty" % name)
    checks.check(counts(data) == serial["counts"], "%s: %s gathered from %d ranks, %s serially" % (
        name, counts(data), ranks, serial["counts"]))
    if name not in TIMED:
        # The totals over the ranks, without gathering: each rank's share counted once.
        info = OutputPort(proxy, port).GetDataInformation()
        total = info.GetNumberOfRows() if data.IsA("vtkTable") else info.GetNumberOfPoints()
        checks.check(total == serial["counts"][0], "%s: %d over all ranks, %d serially" % (name, total,
                                                                                         serial["counts"][0]))
    checks.check(fingerprint(data) == serial["fingerprint"], "%s: bit-identical to the serial output" % name)

# The split leaf: it really is split, and curling gathers it whole (point order is the gathered one).
if ranks > 1:
    split.UpdatePipeline()
    holders = split.GetDataInformation().GetNumberOfPoints()
    checks.check(holders >= len(reference["split_curl_points"]),
                 "D3 split the leaf (%d points with the shared ones counted per rank)" % holders)
for name, proxy in SPLIT.items():
    data = servermanager.Fetch(proxy)
    counts_now = [data.GetNumberOfPoints(), data.GetNumberOfCells()] if data is not None else [0, 0]
    checks.check(counts_now == reference[name + "_count"], "%s: the leaf split over %d ranks is processed once: %s, "
                 "%s serially" % (name, ranks, counts_now, reference[name + "_count"]))
    # Gathered pieces come in another point order, so sums may round differently: equal to 1e-9, as sets.
    expected_points = numpy.array(reference[name + "_points"])
    points_now = sorted_points(data) if counts_now[0] else numpy.zeros((0, 3))
    checks.check(points_now.shape == expected_points.shape and numpy.allclose(points_now, expected_points, rtol=0,
                                                                               atol=2e-9),
                 "%s: the same points as the serial run on the unsplit leaf" % name)
# TreeFitFilter's Scan: each rank keeps its points, the tree's owner sends their values back.
scan_of_fit = tree_fit_scan(servermanager.Fetch(tree_fit, idx=4))
checks.check(counts(scan_of_fit) == reference["tree_fit_scan"]["counts"] and
             OutputPort(tree_fit, 4).GetDataInformation().GetNumberOfPoints() == reference["tree_fit_scan"]["counts"][0],
             "tree_fit_scan: every point once over %d ranks" % ranks)
checks.check(fingerprint(scan_of_fit) == reference["tree_fit_scan"]["fingerprint"],
             "tree_fit_scan: points, TreeId, CylinderId, BranchId, Wood, FitDistance and TCoords bit-identical to the "
             "serial run")
measured = statistics(servermanager.Fetch(split_comparison, idx=2))
checks.check(set(measured) == set(reference["split_comparison"]) and all(
    abs(measured[k] - v) <= 1e-9 * max(1.0, abs(v)) for k, v in reference["split_comparison"].items()),
    "a cloud split over %d ranks gives the serial statistics: %s" % (ranks, {
        k: (measured.get(k), v) for k, v in reference["split_comparison"].items() if measured.get(k) != v}))
measured = statistics(servermanager.Fetch(split_fit, idx=2))
# NaN is NaN: HiddenMargin (one flat leaf seen from one place gives no scanner position) is NaN in both runs.
differing = {k: (measured.get(k), v) for k, v in reference["split_fit"].items()
             if not (measured.get(k) == v or (k in measured and math.isnan(measured[k]) and math.isnan(v)))}
checks.check(set(measured) == set(reference["split_fit"]) and not differing,
             "a scan split over %d ranks gives the serial traits bit for bit: %s" % (ranks, differing))
checks.finish()
