"""pvbatch under MPI: LeafOutlineSource yields one leaf, not one per rank, equal to the serial one.

Run once serially with --write-reference (pvpython), then as `mpirun -np 2 pvbatch ... --ranks 2`."""
import os

from plantmorph_testing import Checks, fingerprint, load_plugin, parse_arguments

arguments = parse_arguments([("--write-reference", dict(action="store_true")), ("--ranks", dict(type=int, default=1))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
reference = os.path.join(arguments.work, "mpi_reference_leaf.vtp")
leaf = LeafOutlineSource(Preset=4, Resolution=45)
leaf.UpdatePipeline()

if arguments.write_reference:
    # Inline binary: Debian's ParaView 5.11 cannot read back appended-mode .vtp files (see README).
    SaveData(reference, proxy=leaf, DataMode="Binary")
    print("reference leaf written to", reference)
    raise SystemExit(0)

checks = Checks()
ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
checks.check(ranks == arguments.ranks, "running on %d ranks (expected %d)" % (ranks, arguments.ranks))
serial = servermanager.Fetch(XMLPolyDataReader(FileName=[reference]))
info = leaf.GetDataInformation()
checks.check(info.GetNumberOfPoints() == serial.GetNumberOfPoints(),
             "points over all ranks: %d, serial: %d" % (info.GetNumberOfPoints(), serial.GetNumberOfPoints()))
checks.check(info.GetNumberOfCells() == serial.GetNumberOfCells(),
             "cells over all ranks: %d, serial: %d" % (info.GetNumberOfCells(), serial.GetNumberOfCells()))
gathered = servermanager.Fetch(leaf)
points = vtk_to_numpy(gathered.GetPoints().GetData())
checks.check(len(numpy.unique(points, axis=0)) == len(points), "no point appears twice (no duplicated leaf)")
checks.check(fingerprint(gathered) == fingerprint(serial), "gathered leaf bit-identical to the serial one")
checks.finish()
