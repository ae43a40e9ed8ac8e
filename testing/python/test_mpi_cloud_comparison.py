# SPDX-License-Identifier: GPL-3.0-or-later
"""A text scan read by pieces and compared on every rank: 1, 2 and 4 ranks give the serial results.

The scan (a cucumber blade's points moved off the leaf and perturbed, with comment lines, a header, blank lines and
CRLF endings, written by the serial run) is read by Leaf Cloud Reader, each rank parsing its own byte range, and
compared with the blade (a surface: distances, Symmetric, an outlier cut-off; a rigid + scale registration) and with
a point-cloud reference read by the reader too (so split over the ranks and gathered back for every rank). Checks:
- the reader: the same points in file order (gathered in rank order), the same table, split over every rank; a file
  with one bad line (in the last rank's piece) gives no point on any rank; a file whose colours are fractions except
  one 0-255 value near its end is scaled 0-255 on every rank, as serially;
- per point: Distance, SignedDistance, ClosestPoint and the points (moved by the registration) bit for bit;
- the statistics: counts, minimum, maximum and the percentiles exactly (a distributed selection), the sums (mean,
  deviation, RMS, Chamfer) to 1e-12 relative; the histogram's bins and counts exactly; the registration's
  transform to 1e-12 relative.
Run once serially with --write-reference (pvpython), then as `mpirun -np N pvbatch ... --ranks N`.
"""
import os

from plantmorph_testing import (check_rank_count, Checks, load_plugin, load_reference, MPI_EQUALITY_ARGUMENTS,
                               parse_arguments, save_reference)

arguments = parse_arguments(MPI_EQUALITY_ARGUMENTS)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
scan_file = os.path.join(arguments.work, "mpi_cloud_scan.txt")
cloud_file = os.path.join(arguments.work, "mpi_cloud_reference.txt")
colour_file = os.path.join(arguments.work, "mpi_cloud_colours.txt")
bad_file = os.path.join(arguments.work, "mpi_cloud_bad.txt")
reference_file = os.path.join(arguments.work, "mpi_cloud_comparison_reference.npz")
blade = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", Resolution=30)

if arguments.write_reference:
    # The files: written once by the serial run, read by every rank later.
    leaf = servermanager.Fetch(blade)
    points = vtk_to_numpy(leaf.GetPoints().GetData())
    rng = numpy.random.default_rng(21)
    rows = []
    for k in range(20):
        moved = points * 1.02 + numpy.array([0.05, -0.03, 0.02]) + rng.normal(0.0, 0.02, points.shape)
        rows.append(numpy.column_stack([moved, rng.uniform(0.0, 1.0, (len(points), 3))]))
    rows = numpy.concatenate(rows)
    with open(scan_file, "w", newline="") as f:
        f.write("# a synthetic scan\r\n\r\nx,y,z,nx,ny,nz\r\n")
        for i, row in enumerate(rows):
            f.write(",".join(repr(float(v)) for v in row) + ("\r\n" if i % 7 else "\r\n// a comment\n\n"))
    with open(colour_file, "w") as f:  # colours as fractions but one 0-255 value near the end: 0-255 for all
        for i in range(4000):
            f.write("%d 1 2 0 0 1 %s 0.5 1\n" % (i, "200" if i == 3900 else "0.25"))
    with open(bad_file, "w") as f:  # an error on line 3901, in the last rank's piece
        f.write("".join("%d 1 2\n" % i for i in range(3900)) + "1 two 3\n" + "".join("%d 1 2\n" % i for i in range(99)))
    with open(cloud_file, "w") as f:
        for row in points[::2] + rng.normal(0.0, 0.01, points[::2].shape):
            f.write("%r %r %r\n" % tuple(float(v) for v in row))

scan = LeafCloudReader(FileName=scan_file)
colours = LeafCloudReader(FileName=colour_file)
bad = LeafCloudReader(FileName=bad_file)
point_reference = LeafCloudReader(FileName=cloud_file)
COMPARISONS = {
    "surface": CloudComparisonFilter(Input=scan, Reference=blade, Symmetric=1, UseMaximumDistance=1,
                                     MaximumDistance=0.08, HistogramBins=17),
    "registered": CloudComparisonFilter(Input=scan, Reference=blade, Registration="Rigid + scale ICP",
                                        RegistrationLandmarks=997),
    "cloud": CloudComparisonFilter(Input=scan, Reference=point_reference, Symmetric=1),
}
EXACT = {"Count", "Outliers", "Minimum", "Maximum", "Percentile50", "Percentile68", "Percentile75", "Percentile95",
         "Percentile99", "Hausdorff", "ReferenceIsSurface", "ReverseCount", "ReverseHausdorff", "SymmetricHausdorff"}


def arrays(data, names):
    return {name: vtk_to_numpy(data.GetPointData().GetArray(name)).copy() for name in names
            if data.GetPointData().GetArray(name) is not None}


def columns(table):
    return {table.GetColumnName(c): vtk_to_numpy(table.GetColumn(c)).astype(numpy.float64)
            for c in range(table.GetNumberOfColumns())}


def results():
    # The table first: ParaView 5.11's Fetch of a table port (no append helper for tables) after a Fetch of the
    # same reader's port 0 returns rank 0's rows only; fetched first, it has every rank's in rank order.
    out = {"table_" + k: v for k, v in columns(servermanager.Fetch(scan, idx=1)).items()}
    out["table_rows_over_ranks"] = numpy.array([OutputPort(scan, 1).GetDataInformation().GetNumberOfRows()])
    data = servermanager.Fetch(scan)
    out["scan_points"] = vtk_to_numpy(data.GetPoints().GetData()).copy()
    out["colours"] = vtk_to_numpy(servermanager.Fetch(colours).GetPointData().GetArray("Colors")).copy()
    bad.UpdatePipeline()
    out["bad_points_over_ranks"] = numpy.array([bad.GetDataInformation().GetNumberOfPoints()])
    out.update({"scan_" + k: v for k, v in arrays(data, ["Normals"]).items()})
    for name, comparison in COMPARISONS.items():
        data = servermanager.Fetch(comparison)
        out[name + "_points"] = vtk_to_numpy(data.GetPoints().GetData()).copy()
        out.update({name + "_" + k: v for k, v in arrays(data, ["Distance", "SignedDistance", "ClosestPoint"]).items()})
        out[name + "_transform"] = vtk_to_numpy(data.GetFieldData().GetArray("PlantMorph.MeasuredTransform")).copy()
        out.update({name + "_stat_" + k: v for k, v in columns(servermanager.Fetch(comparison, idx=2)).items()})
        out.update({name + "_hist_" + k: v for k, v in columns(servermanager.Fetch(comparison, idx=1)).items()})
    return out


if arguments.write_reference:
    save_reference(reference_file, results())
    raise SystemExit(0)

checks = Checks()
ranks = check_rank_count(checks, arguments)
expected = load_reference(reference_file)
now = results()
checks.check(set(now) == set(expected.files), "the same outputs and arrays as serially: %s" % sorted(
    set(now) ^ set(expected.files)))
checks.check(len(expected["scan_points"]) == 20 * len(vtk_to_numpy(servermanager.Fetch(blade).GetPoints().GetData())),
             "the serial read has every data line")
holders = set(vtk_to_numpy(servermanager.Fetch(ProcessIdScalars(Input=scan)).GetPointData().GetArray(
    "ProcessId")).tolist())
checks.check(holders == set(range(ranks)), "the scan is read by every rank: %s" % sorted(holders))
for key in sorted(set(now) & set(expected.files)):
    a, b = now[key], expected[key]
    if "_stat_" in key and key.split("_stat_")[1] not in EXACT or key.endswith("_transform"):
        same = a.shape == b.shape and numpy.allclose(a, b, rtol=1e-12, atol=1e-300)
        checks.check(same, "%s equal to the serial one to 1e-12 relative on %d ranks: %s, %s" % (key, ranks, a, b))
    else:
        checks.check(a.shape == b.shape and numpy.array_equal(a, b),
                     "%s bit for bit the serial one on %d ranks" % (key, ranks))
checks.check(expected["bad_points_over_ranks"][0] == 0 and expected["colours"][0, 0] == 0,
             "serially: the bad file gives no point, the colours are taken as 0-255 values (0.25 -> 0, not 64)")
checks.check(expected["registered_stat_Count"][0] > 0 and not numpy.allclose(
    expected["registered_transform"], numpy.eye(4).ravel()), "the registration moved the scan (not the identity)")
checks.finish()
