# SPDX-License-Identifier: GPL-3.0-or-later
"""VenationFilter and WiltingSimulator on several leaves: each leaf is processed alone, on one MPI rank, and the
results are the serial run's, bit for bit.

Four LeafOutlineSource blades (three models, side by side) appended on rank 0, without a LeafId: the leaves are the
connected blades, numbered 0-3 in the order they were appended. VenationFilter grows the veins of each; its Blade and
Veins (which carry LeafId) feed WiltingSimulator (Resolution 14, the coarsest the Cucumber preset accepts, 0.5 s: quick).
Serially (--write-reference, pvpython), besides writing the reference: every leaf's veins, statistics row, histogram
rows, wilted points and frame rows are those of the leaf run alone, bit for bit.
On 1, 2 and 4 ranks (`mpirun -np N pvbatch test_mpi_leaf_filters.py ... --ranks N`):
- the Statistics, Areole histogram and frame tables (gathered on rank 0, once) equal the serial ones bit for bit, rows
  in LeafId order;
- every leaf's veins, blade and wilted leaf lie on one rank only, the leaves spread over min(ranks, leaves) ranks,
  and each is the serial one bit for bit (points and every point array).
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
MODELS = ("Deformed rectangle", "B-spline", "Space curve", "B-spline")
WILTING = dict(Resolution=14, Duration=0.5, FrameInterval=0.1)
END = WILTING["Duration"]


def make_leaf(k):
    source = LeafOutlineSource(Model=MODELS[k], Length=8.0 + 2.0 * k)
    if k == 0:
        return source
    moved = Transform(Input=source)
    moved.Transform.Translate = [40.0 * k, 0.0, 0.0]
    return moved


LEAVES = [make_leaf(k) for k in range(len(MODELS))]
venation = VenationFilter(Input=AppendGeometry(Input=LEAVES), Preset="Custom", Tertiary=1, Veinlets=1)
wilting = WiltingSimulator(Input=OutputPort(venation, 1), Veins=OutputPort(venation, 0), **WILTING)


def fetch(proxy, port, time=None):
    """The port's data from every rank, with a ProcessId point array."""
    ids = ProcessIdScalars(Input=OutputPort(proxy, port))
    if time is not None:
        ids.UpdatePipeline(time)
    return servermanager.Fetch(ids)


def point_arrays(data):
    """Points and every point array of a dataset, by name, as float64 columns."""
    result = {"Points": vtk_to_numpy(data.GetPoints().GetData()).astype(numpy.float64)}
    for a in range(data.GetPointData().GetNumberOfArrays()):
        array = data.GetPointData().GetArray(a)
        if array is not None and array.GetName() != "ProcessId":
            result[array.GetName()] = vtk_to_numpy(array).astype(numpy.float64)
    return result


def per_leaf(data):
    """Per LeafId: every point array of the leaf's points (in order) and the set of ranks holding them."""
    arrays = point_arrays(data)
    ids, ranks = arrays["LeafId"], vtk_to_numpy(data.GetPointData().GetArray("ProcessId"))
    return {int(i): ({k: v[ids == i] for k, v in arrays.items()}, set(ranks[ids == i].tolist()))
            for i in numpy.unique(ids)}


def table_columns(proxy, port, time=None):
    if time is not None:
        proxy.UpdatePipeline(time)
    table = servermanager.Fetch(proxy, idx=port)
    return {table.GetColumnName(c): vtk_to_numpy(table.GetColumn(c)).astype(numpy.float64)
            for c in range(table.GetNumberOfColumns())}


OUTPUTS = (("veins", venation, 0, None), ("blade", venation, 1, None), ("wilted", wilting, 0, END),
           ("moved_veins", wilting, 3, END))
TABLES = (("statistics", venation, 2, None), ("histogram", venation, 3, None), ("frames", wilting, 2, END))


def equal_columns(a, b):
    return set(a) == set(b) and all(numpy.array_equal(a[k], b[k]) for k in a)


def check_alone(checks):
    """Serial: each leaf among the others gives what it gives alone."""
    stats, histogram = table_columns(venation, 2), table_columns(venation, 3)
    frames = table_columns(wilting, 2, END)
    veins, wilted = per_leaf(fetch(venation, 0)), per_leaf(fetch(wilting, 0, END))
    for k, leaf in enumerate(LEAVES):
        alone = VenationFilter(Input=leaf, Preset="Custom", Tertiary=1, Veinlets=1)
        alone_wilt = WiltingSimulator(Input=OutputPort(alone, 1), Veins=OutputPort(alone, 0), **WILTING)
        alone_veins = point_arrays(fetch(alone, 0))
        checks.check(all(numpy.array_equal(veins[k][0][n], v) for n, v in alone_veins.items()),
                     "leaf %d: its veins among the others are its veins alone (points and arrays)" % k)
        for name, table, mine in (("statistics", stats, table_columns(alone, 2)),
                                  ("histogram", histogram, table_columns(alone, 3)),
                                  ("frames", frames, table_columns(alone_wilt, 2, END))):
            rows = table["LeafId"] == k
            checks.check(rows.any() and all(numpy.array_equal(table[n][rows], v) for n, v in mine.items()),
                         "leaf %d: its %s rows are the leaf's alone" % (k, name))
        alone_wilted = point_arrays(fetch(alone_wilt, 0, END))
        checks.check(all(numpy.array_equal(wilted[k][0][n], v) for n, v in alone_wilted.items()),
                     "leaf %d: wilted among the others as alone (points, Displacement, every array)" % k)


reference_file = os.path.join(arguments.work, "mpi_leaf_filters_reference.npz")
checks = Checks()
if arguments.write_reference:
    check_alone(checks)
    saved = {}
    for name, proxy, port, time in TABLES:
        saved.update({"%s:%s" % (name, k): v for k, v in table_columns(proxy, port, time).items()})
    for name, proxy, port, time in OUTPUTS:
        for leaf_id, (arrays, _) in per_leaf(fetch(proxy, port, time)).items():
            saved.update({"%s:%d:%s" % (name, leaf_id, k): v for k, v in arrays.items()})
    save_reference(reference_file, saved)
    checks.finish()
    raise SystemExit(0)

ranks = check_rank_count(checks, arguments)
reference = load_reference(reference_file)
for name, proxy, port, time in TABLES:
    columns = table_columns(proxy, port, time)
    expected = {k.split(":", 1)[1]: reference[k] for k in reference.files if k.startswith(name + ":")}
    checks.check(equal_columns(columns, expected), "%s: the table on %d ranks is the serial one bit for bit" % (
        name, ranks))
    checks.check(list(columns["LeafId"]) == sorted(columns["LeafId"]), "%s: rows in LeafId order" % name)
for name, proxy, port, time in OUTPUTS:
    leaves = per_leaf(fetch(proxy, port, time))
    checks.check(sorted(leaves) == list(range(len(MODELS))), "%s: every leaf: %s" % (name, sorted(leaves)))
    checks.check(all(len(r) == 1 for _, r in leaves.values()), "%s: each leaf on one rank: %s" % (
        name, {k: r for k, (_, r) in leaves.items()}))
    owners = set().union(*(r for _, r in leaves.values()))
    checks.check(len(owners) == min(ranks, len(MODELS)), "%s: the leaves on %d ranks (%s)" % (
        name, min(ranks, len(MODELS)), sorted(owners)))
    for leaf_id, (arrays, _) in leaves.items():
        prefix = "%s:%d:" % (name, leaf_id)
        expected = {k[len(prefix):]: reference[k] for k in reference.files if k.startswith(prefix)}
        checks.check(equal_columns(arrays, expected), "%s: leaf %d is the serial one bit for bit (differing: %s)" % (
            name, leaf_id, [k for k in expected if not numpy.array_equal(arrays.get(k), expected[k])]))
checks.finish()
