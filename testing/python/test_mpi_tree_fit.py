# SPDX-License-Identifier: GPL-3.0-or-later
"""TreeFitFilter under MPI: many trees, each fitted whole on one owner rank, and the results are the serial run's.

A small stand of four scanned trees told apart by a TreeId point array (three copies of a leafless tree's scan moved
apart and turned, and a fourth "tree" that cannot be fitted: 501 points on a line). The trees' owners are spread
over the ranks (largest first, each to the least loaded rank), so on 2 and 4 ranks most trees are fitted on a rank
that does not hold their points, which are sent there and whose values come back. On 1, 2 and 4 ranks:
- Cylinders, Skeleton, Trees and Branches (gathered on rank 0, once) are the serial outputs bit for bit, in TreeId
  order; the tree that fails has its Trees row with the reason in Status and NaN traits, the three others are fitted;
- Scan stays where its points are (every point once over the ranks) and every point's TreeId, CylinderId, BranchId,
  Wood and FitDistance equal the serial run's (compared as a sorted set of rows), also when Scan is the first and
  only port asked of a filter.
Run once serially with --write-reference (pvpython), then as `mpirun -np N pvbatch test_mpi_tree_fit.py ... --ranks N`.
"""
import math
import os

from plantmorph_testing import (check_rank_count, Checks, fingerprint, load_plugin, load_reference,
                               moved_copies, MPI_EQUALITY_ARGUMENTS, parse_arguments, save_reference,
                               sorted_point_rows)

arguments = parse_arguments(MPI_EQUALITY_ARGUMENTS)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())

wood = TreeFromSketchSource(Preset="Custom", TreeType="Monopodial", Length=4.0, Radius=0.12, Depth=1, ChildCount=4,
                            Sides=24, Joints="Seated tubes", Leaves=0)
tripods = [coordinate for k in range(3) for coordinate in (7 * math.cos(2 * math.pi * (k + 0.1) / 3), 1.5,
                                                           7 * math.sin(2 * math.pi * (k + 0.1) / 3))]
scan = VirtualScanner(Input=wood, Positions=tripods, LookAt=[0, 2.0, 0], Up=[0, 1, 0], HorizontalFieldOfView=50,
                      VerticalFieldOfView=60, AngularStep=0.2, RangeNoise=0.003, Seed=3)
parts = moved_copies(scan, 3, "Tree", 10, 6.0)
line = Line(Point1=[-5.0, 0.0, 0.0], Point2=[-5.0, 3.0, 0.0], Resolution=500)
parts.append(Calculator(Input=line, ResultArrayName="Tree", Function="3", ResultArrayType="Int"))
stand = AppendDatasets(Input=parts)
fit = TreeFitFilter(Input=stand, TreeIdArray="Tree", UpAxis="Y")
PORTS = {"cylinders": 0, "skeleton": 1, "trees": 2, "branches": 3}
SCAN_ARRAYS = ["TreeId", "CylinderId", "BranchId", "Wood", "FitDistance"]


def scan_rows(data):
    return sorted_point_rows(data, SCAN_ARRAYS)


def table_rows(table):
    return [{table.GetColumnName(c): table.GetValue(r, c).ToString() for c in range(table.GetNumberOfColumns())}
            for r in range(table.GetNumberOfRows())]


reference_file = os.path.join(arguments.work, "mpi_tree_fit_reference.npz")
if arguments.write_reference:
    reference = {name: numpy.array(fingerprint(servermanager.Fetch(fit, idx=port))) for name, port in PORTS.items()}
    reference["scan"] = scan_rows(servermanager.Fetch(fit, idx=4))
    save_reference(reference_file, reference)
    raise SystemExit(0)

checks = Checks()
ranks = check_rank_count(checks, arguments)
reference = load_reference(reference_file)
# A filter asked for its Scan port alone before any other port: the ranks still exchange their trees (the pieces are
# read from the port the request comes through, not from port 0, which has none yet).
scan_first = TreeFitFilter(Input=stand, TreeIdArray="Tree", UpAxis="Y")
rows = scan_rows(servermanager.Fetch(scan_first, idx=4))
checks.check(rows.shape == reference["scan"].shape and rows.tobytes() == reference["scan"].tobytes(),
             "Scan asked first and alone: every point's values are the serial run's")
Delete(scan_first)
for name, port in PORTS.items():
    data = servermanager.Fetch(fit, idx=port)
    checks.check(fingerprint(data) == str(reference[name]), "%s on %d ranks: bit-identical to the serial output" % (
        name, ranks))
trees = table_rows(servermanager.Fetch(fit, idx=2))
checks.check([row["TreeId"] for row in trees] == ["3", "10", "11", "12"], "one Trees row per tree, in TreeId order")
checks.check(trees and "line" in trees[0]["Status"] and trees[0]["Height"] == "nan",
             "the line: its row says why, NaN traits (%s)" % (trees[0] if trees else None))
checks.check(all(row["Status"] == "ok" for row in trees[1:]), "the three other trees are fitted")
fit.UpdatePipeline()
scan_points = OutputPort(fit, 4).GetDataInformation().GetNumberOfPoints()
checks.check(scan_points == len(reference["scan"]), "Scan: %d points over all ranks, %d serially" % (
    scan_points, len(reference["scan"])))
rows = scan_rows(servermanager.Fetch(fit, idx=4))
checks.check(rows.shape == reference["scan"].shape and rows.tobytes() == reference["scan"].tobytes(),
             "Scan: every point's values are the serial run's")
checks.finish()
