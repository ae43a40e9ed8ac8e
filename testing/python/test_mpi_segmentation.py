# SPDX-License-Identifier: GPL-3.0-or-later
"""PlantSegmentationFilter under MPI: several plants, each segmented whole on one owner rank, and the results are the
serial run's.

Three scans of a herb (TreeFromSketchSource's stem, three shoots and nine blades, scanned by VirtualScanner), moved
apart and turned, told apart by a Plant point array (ids 10, 11, 12). The plants' owners are spread over the ranks
(largest first, each to the least loaded rank), so on 2 and 4 ranks most plants are segmented on a rank that does not
hold all their points, which are sent there and whose labels come back. On 1, 2 and 4 ranks:
- Leaves and Plants (gathered on rank 0, once) are the serial tables bit for bit: one Plants row per plant in
  ascending id, LeafIds numbered per plant and on over the plants in that order;
- Points stays where its points are (every point once over the ranks) and every point's Organ, LeafId and
  SegmentationConfidence equal the serial run's (compared as a sorted set of rows); every rank holds some of them;
- LeafFitFilter on the segmented points (LeafIdArray LeafId, the whole-plant pipeline) gives the serial Traits table
  bit for bit: each leaf is fitted on its owner rank, and the plants' axis shape that checks a leaf's base by its
  wood (every rank's leaves' Width over Length, gathered) is the same on any number of ranks.
Run once serially with --write-reference (pvpython), then as `mpirun -np N pvbatch test_mpi_segmentation.py ...
--ranks N`.
"""
import math
import os

from plantmorph_testing import (check_rank_count, Checks, fingerprint, load_plugin, load_reference,
                               moved_copies, MPI_EQUALITY_ARGUMENTS, parse_arguments, save_reference,
                               sorted_point_rows)

arguments = parse_arguments(MPI_EQUALITY_ARGUMENTS)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())

tree = TreeFromSketchSource(Preset="Custom", Depth=1, ChildCount=3, Ratio=0.6, Length=4.0, Radius=0.08, LeafCount=3,
                            LeafScale=1.5, LeafAngle=50.0, Sides=12)
plant = AppendGeometry(Input=[OutputPort(tree, 0), OutputPort(tree, 2)])
positions = []
for angle in (0.3, 0.3 + math.pi):
    positions += [6.0 * math.cos(angle), 3.0, 6.0 * math.sin(angle)]
scan = VirtualScanner(Input=plant, Positions=positions, LookAt=[0, 2.5, 0], Up=[0, 1, 0], HorizontalFieldOfView=80,
                      VerticalFieldOfView=80, AngularStep=0.25, RangeNoise=0.0015, Seed=2)
stand = AppendDatasets(Input=moved_copies(scan, 3, "Plant", 10, 8.0))
segmentation = PlantSegmentationFilter(Input=stand, PlantIdArray="Plant", UpAxis="Y")
fit = LeafFitFilter(Input=segmentation, LeafIdArray="LeafId", UpAxis="Y")
TABLES = {"leaves": 1, "plants": 2}
FIT_TABLES = {"traits": 2}
POINT_ARRAYS = ["Plant", "Organ", "LeafId", "SegmentationConfidence"]


def point_rows(data):
    return sorted_point_rows(data, POINT_ARRAYS)


reference_file = os.path.join(arguments.work, "mpi_segmentation_reference.npz")
if arguments.write_reference:
    reference = {name: numpy.array(fingerprint(servermanager.Fetch(segmentation, idx=port)))
                 for name, port in TABLES.items()}
    reference.update({name: numpy.array(fingerprint(servermanager.Fetch(fit, idx=port)))
                      for name, port in FIT_TABLES.items()})
    reference["points"] = point_rows(servermanager.Fetch(segmentation, idx=0))
    plants = servermanager.Fetch(segmentation, idx=2)
    counts = vtk_to_numpy(plants.GetColumnByName("LeafCount")) if plants.GetNumberOfRows() else []
    if plants.GetNumberOfRows() != 3 or min(counts) < 6:
        raise SystemExit("the serial reference is not three plants of six leaves or more: %s" % list(counts))
    save_reference(reference_file, reference)
    raise SystemExit(0)

checks = Checks()
ranks = check_rank_count(checks, arguments)
reference = load_reference(reference_file)
for name, port in TABLES.items():
    checks.check(fingerprint(servermanager.Fetch(segmentation, idx=port)) == str(reference[name]),
                 "%s on %d ranks: bit-identical to the serial table" % (name, ranks))
for name, port in FIT_TABLES.items():
    checks.check(fingerprint(servermanager.Fetch(fit, idx=port)) == str(reference[name]),
                 "LeafFitFilter's %s on %d ranks: bit-identical to the serial table" % (name, ranks))
plants = servermanager.Fetch(segmentation, idx=2)
checks.check(plants.GetNumberOfRows() == 3 and list(vtk_to_numpy(plants.GetColumnByName("PlantId"))) == [10, 11, 12],
             "one Plants row per plant, in PlantId order")
segmentation.UpdatePipeline()
count = OutputPort(segmentation, 0).GetDataInformation().GetNumberOfPoints()
checks.check(count == len(reference["points"]), "Points: %d over all ranks, %d serially" % (
    count, len(reference["points"])))
rows = point_rows(servermanager.Fetch(segmentation, idx=0))
checks.check(rows.shape == reference["points"].shape and rows.tobytes() == reference["points"].tobytes(),
             "Points: every point's Organ, LeafId and confidence are the serial run's")
# The points stay on the ranks that hold them (the plants' labels come back to them): on several ranks, the Points
# output is spread over the ranks, not gathered on rank 0 (as when the whole input was segmented there).
ranks_of_points = vtk_to_numpy(servermanager.Fetch(ProcessIdScalars(Input=OutputPort(segmentation, 0)))
                               .GetPointData().GetArray("ProcessId"))
checks.check(len(numpy.unique(ranks_of_points)) == ranks, "Points on %d ranks: held by ranks %s" % (
    ranks, numpy.unique(ranks_of_points).tolist()))
checks.finish()
