# SPDX-License-Identifier: GPL-3.0-or-later
"""The LAS writer and LASReader under MPI: VirtualScanner's cloud (each rank scans its share of the beams) saved as LAS
through File > Save Data's writer, which gathers the pieces on the first rank and writes one file, is the serial
run's file byte for byte (the creation date aside); LASReader reads it by pieces, each rank its share of the point
records, every point once, in file order.

Serially (--write-reference, pvpython) the file's bytes are the reference. On 1, 2 and 4 ranks
(`mpirun -np N pvbatch test_mpi_las.py ... --ranks N`) the file written must equal them, and LASReader's output
gathered from every rank must have the scan's points once, with its BeamId in the serial order, rank r holding
records [R r / N, R (r + 1) / N) of the file's R; a refused file leaves every rank's output empty.
"""
import hashlib
import os

from plantmorph_testing import (check_rank_count, Checks, load_plugin, load_reference, MPI_EQUALITY_ARGUMENTS,
                               parse_arguments, save_reference)

arguments = parse_arguments(MPI_EQUALITY_ARGUMENTS)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()
reference_file = os.path.join(arguments.work, "mpi_las_reference.json")
path = os.path.join(arguments.work, "mpi_las_%s.las" % ("serial" if arguments.write_reference else arguments.ranks))
if os.path.exists(path):
    os.remove(path)

leaf = LeafOutlineSource(Resolution=16)
scan = VirtualScanner(Input=leaf, Resolution=[60, 40])
SaveData(path, proxy=OutputPort(scan, 0))
with open(path, "rb") as f:
    content = f.read()
# Bytes 90-93 are the file's creation day and year (the day it is written).
digest = hashlib.sha256(content[:90] + content[94:]).hexdigest()
reader = LASReader(FileName=path)
ids = ProcessIdScalars(Input=reader)
ids.UpdatePipeline()
cloud = servermanager.Fetch(ids)
beams = vtk_to_numpy(cloud.GetPointData().GetArray("BeamId")).tolist() if cloud.GetNumberOfPoints() else []
ranks = vtk_to_numpy(cloud.GetPointData().GetArray("ProcessId")).tolist() if cloud.GetNumberOfPoints() else []
checks.check(len(content) > 375 and content[:4] == b"LASF", "%s written (%d bytes)" % (path, len(content)))
if arguments.write_reference:
    checks.check(len(beams) > 500, "the serial scan has points (%d)" % len(beams))
    save_reference(reference_file, {"digest": digest, "beams": beams})
else:
    check_rank_count(checks, arguments)
    reference = load_reference(reference_file)
    checks.check(digest == reference["digest"], "the file on %d ranks is the serial run's, byte for byte" % arguments.ranks)
    checks.check(beams == reference["beams"], "LASReader on %d ranks gives the scan's %d points once, in the serial "
                 "order (%d points)" % (arguments.ranks, len(reference["beams"]), len(beams)))
    total, n = len(reference["beams"]), arguments.ranks
    shares = [total * (r + 1) // n - total * r // n for r in range(n)]
    checks.check([ranks.count(r) for r in range(n)] == shares,
                 "rank r reads records [R r / N, R (r + 1) / N): %s, expected %s" % ([ranks.count(r) for r in range(n)],
                                                                                      shares))
# A refused file: every rank finds the header's error, it is said once, and the output is empty (no rank hangs).
bad = os.path.join(arguments.work, "mpi_las_bad_%s.las" % ("serial" if arguments.write_reference else arguments.ranks))
with open(bad, "wb") as f:
    f.write(b"LASX" + content[4:])
refused = servermanager.Fetch(LASReader(FileName=bad))
checks.check(refused.GetNumberOfPoints() == 0, "a file with a wrong signature gives an empty output")
checks.finish()
