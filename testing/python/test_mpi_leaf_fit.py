# SPDX-License-Identifier: GPL-3.0-or-later
"""LeafFitFilter under MPI: each rank fits its own leaves, and the results are the serial run's, bit for bit.

The shipped scans appended with a LeafId (read by pieces, each rank its byte range of each file), once as they come and once split
over the ranks by D3 (each leaf's points then start on several ranks). On 1, 2 and 4 ranks:
- the Traits table (gathered on rank 0, once) equals the serial one bit for bit, in LeafId order, HiddenMargin
  among it (each scan given the Range and ScanPosition of a scanner 1 m above it: the scanner's position and depth
  map are made from every rank's points);
- every leaf's blade lies on one rank only, the leaves are spread over min(ranks, leaves) ranks, and each blade is
  the serial blade bit for bit (points, normals, support);
- Scan stays where its points are (rank 0 for the unsplit input, several ranks for the split one) and every point's
  FitDistance and Inlier equal the serial run's;
- without LeafIdArray (the scans moved 300 mm apart, split over the ranks by D3) the separate blades are found
  whatever the ranks: six rows, the serial table bit for bit, and every Scan point's LeafId the serial one.
Run once serially with --write-reference (pvpython), then as `mpirun -np N pvbatch test_mpi_leaf_fit.py ... --ranks N`.
"""
import glob
import os

from plantmorph_testing import (check_rank_count, Checks, load_plugin, load_reference, MPI_EQUALITY_ARGUMENTS,
                               parse_arguments, save_reference)

arguments = parse_arguments(MPI_EQUALITY_ARGUMENTS)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
DATA = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data"))
SCANS = sorted(glob.glob(os.path.join(DATA, "leaf-clouds", "*.txt")))
LEAF_IDS = [7 + 3 * k for k in range(len(SCANS))]  # not 0..n-1, so LeafId order is tested, not the position

parts = []
for leaf_id, scan in zip(LEAF_IDS, SCANS):
    parts.append(Calculator(Input=LeafCloudReader(FileName=scan), ResultArrayName="LeafId", Function="%d" % leaf_id,
                            ResultArrayType="Int"))
# Each scan as if seen from a scanner 1 m above (its Range, ScanPosition 0): HiddenMargin is then measured, from the
# scanner's position and depth map made of every rank's points.
for k, part in enumerate(parts):
    seen = Calculator(Input=part, ResultArrayName="Range", Function="mag(coords - 1000*kHat)")
    parts[k] = Calculator(Input=seen, ResultArrayName="ScanPosition", Function="0", ResultArrayType="Int")
appended = AppendDatasets(Input=parts)
FITS = {"whole": LeafFitFilter(Input=appended, LeafIdArray="LeafId"),
        "split": LeafFitFilter(Input=D3(Input=appended, BoundaryMode="Assign cells uniquely"), LeafIdArray="LeafId")}
moved = []
for k, part in enumerate(parts):
    move = Transform(Input=part)
    move.Transform.Translate = [300.0 * k, 0.0, 0.0]
    moved.append(move)
BLADES = LeafFitFilter(Input=D3(Input=AppendDatasets(Input=moved), BoundaryMode="Assign cells uniquely"))


def array(data, name):
    return vtk_to_numpy(data.GetPointData().GetArray(name))


def same(a, b):
    """Bit for bit, NaN equal to NaN (HiddenMargin is NaN where no scanner saw the leaf)."""
    if a is None or b is None:
        return False
    a, b = numpy.asarray(a), numpy.asarray(b)
    return numpy.array_equal(a, b, equal_nan=a.dtype.kind == "f" and b.dtype.kind == "f")


def column_values(column):
    """A column's values: floats, or strings for the text columns (Message, LengthUnit)."""
    if column.IsA("vtkStringArray"):
        return numpy.array([column.GetValue(i) for i in range(column.GetNumberOfValues())], dtype=str)
    return vtk_to_numpy(column).astype(numpy.float64)


def table_columns(table):
    return {table.GetColumnName(c): column_values(table.GetColumn(c)) for c in range(table.GetNumberOfColumns())}


def blades(fit):
    """Per LeafId: the blade's points, normals and support, and the ranks its points came from."""
    data = servermanager.Fetch(ProcessIdScalars(Input=OutputPort(fit, 0)))
    ids, ranks = array(data, "LeafId"), array(data, "ProcessId")
    points = vtk_to_numpy(data.GetPoints().GetData())
    normals, support = array(data, "Normals"), array(data, "Support")
    return {int(i): (points[ids == i], normals[ids == i], support[ids == i], set(ranks[ids == i].tolist()))
            for i in numpy.unique(ids)}


def scan_rows(fit):
    """The Scan output: rows (x, y, z, LeafId, FitDistance, Inlier) sorted, and the ranks holding them."""
    data = servermanager.Fetch(ProcessIdScalars(Input=OutputPort(fit, 3)))
    rows = numpy.column_stack([vtk_to_numpy(data.GetPoints().GetData()), array(data, "LeafId"),
                               array(data, "FitDistance"), array(data, "Inlier")]).astype(numpy.float64)
    return rows[numpy.lexsort(rows.T[::-1])], set(array(data, "ProcessId").tolist())


reference_file = os.path.join(arguments.work, "mpi_leaf_fit_reference.npz")
if arguments.write_reference:
    fit = FITS["whole"]
    saved = {"traits_" + k: v for k, v in table_columns(servermanager.Fetch(fit, idx=2)).items()}
    for leaf_id, (points, normals, support, _) in blades(fit).items():
        saved.update({"blade_points_%d" % leaf_id: points, "blade_normals_%d" % leaf_id: normals,
                      "blade_support_%d" % leaf_id: support})
    saved["scan"] = scan_rows(fit)[0]
    saved.update({"blades_traits_" + k: v for k, v in table_columns(servermanager.Fetch(BLADES, idx=2)).items()})
    saved["blades_scan"] = scan_rows(BLADES)[0]
    save_reference(reference_file, saved)
    raise SystemExit(0)

checks = Checks()
ranks = check_rank_count(checks, arguments)
reference = load_reference(reference_file)
for name, fit in FITS.items():
    traits = table_columns(servermanager.Fetch(fit, idx=2))
    expected = {k[len("traits_"):]: reference[k] for k in reference.files if k.startswith("traits_")}
    checks.check(list(traits["LeafId"]) == LEAF_IDS, "%s: one row per leaf in LeafId order: %s" % (
        name, list(traits["LeafId"])))
    checks.check(bool(numpy.all(numpy.isfinite(traits["HiddenMargin"]))), "%s: HiddenMargin measured on every leaf: %s"
                 % (name, traits["HiddenMargin"]))
    checks.check(set(traits) == set(expected) and all(same(traits[k], v) for k, v in expected.items()),
                 "%s: the Traits table on %d ranks is the serial one bit for bit (differing: %s)" % (
                     name, ranks, [k for k, v in expected.items() if not same(traits.get(k), v)]))
    checks.check(OutputPort(fit, 2).GetDataInformation().GetNumberOfRows() == len(LEAF_IDS),
                 "%s: the table's rows once over all ranks" % name)
    per_leaf = blades(fit)
    checks.check(sorted(per_leaf) == LEAF_IDS, "%s: a blade per leaf" % name)
    checks.check(all(len(r) == 1 for (_, _, _, r) in per_leaf.values()), "%s: each blade on one rank: %s" % (
        name, {k: r for k, (_, _, _, r) in per_leaf.items()}))
    owners = set().union(*(r for (_, _, _, r) in per_leaf.values()))
    checks.check(len(owners) == min(ranks, len(LEAF_IDS)), "%s: the leaves are fitted on %d ranks (%s)" % (
        name, min(ranks, len(LEAF_IDS)), sorted(owners)))
    for leaf_id, (points, normals, support, _) in per_leaf.items():
        checks.check(numpy.array_equal(points, reference["blade_points_%d" % leaf_id]) and
                     numpy.array_equal(normals, reference["blade_normals_%d" % leaf_id]) and
                     numpy.array_equal(support, reference["blade_support_%d" % leaf_id]),
                     "%s: leaf %d's blade is the serial one bit for bit" % (name, leaf_id))
    rows, holders = scan_rows(fit)
    checks.check(numpy.array_equal(rows, reference["scan"]),
                 "%s: every scan point's LeafId, FitDistance and Inlier as in the serial run" % name)
    if name == "whole":
        # The reader reads each scan by pieces (each rank its byte range of every file): the points are on every
        # rank, and the Scan output stays there.
        checks.check(holders == set(range(ranks)), "whole: Scan stays on the ranks holding the points (every rank "
                     "reads a piece of each scan): %s" % sorted(holders))
    elif ranks > 1:
        checks.check(len(holders) > 1, "split: Scan stays on the ranks holding the points: %s" % sorted(holders))
traits = table_columns(servermanager.Fetch(BLADES, idx=2))
expected = {k[len("blades_traits_"):]: reference[k] for k in reference.files if k.startswith("blades_traits_")}
checks.check(list(traits["LeafId"]) == list(range(len(SCANS))), "blades: one row per scan, LeafId 0 to %d: %s" % (
    len(SCANS) - 1, list(traits["LeafId"])))
checks.check(set(traits) == set(expected) and all(same(traits[k], v) for k, v in expected.items()),
             "blades: the Traits table on %d ranks is the serial one bit for bit (differing: %s)" % (
                 ranks, [k for k, v in expected.items() if not same(traits.get(k), v)]))
checks.check(numpy.array_equal(scan_rows(BLADES)[0], reference["blades_scan"]),
             "blades: every scan point's LeafId, FitDistance and Inlier as in the serial run")
checks.finish()
