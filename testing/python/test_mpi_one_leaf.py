"""pvbatch under MPI: LeafOutlineSource yields one leaf, not one per rank, equal to the serial one, and
VenationFilter grows its veins once on it, equal to the serial veins.

Run once serially with --write-reference (pvpython), then as `mpirun -np 2 pvbatch ... --ranks 2`."""
import os

from plantmorph_testing import Checks, fingerprint, load_plugin, parse_arguments

arguments = parse_arguments([("--write-reference", dict(action="store_true")), ("--ranks", dict(type=int, default=1))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
# One leaf per model: each must appear once, not once per rank, and equal its serial self.
LEAVES = {
    "deformed_rectangle": dict(Preset=4, Resolution=45),
    "space_curve": dict(Model="Space curve", SpaceCurvePreset="Paper 002 Fig. 5", Resolution=40),
    "b_spline": dict(Model="B-spline", BSplinePreset="Pin oak", Resolution=40),
}
leaves = {name: LeafOutlineSource(**properties) for name, properties in LEAVES.items()}
# Filters downstream of a source: they run where the leaf is and nowhere else.
leaves["venation"] = VenationFilter(Input=leaves["deformed_rectangle"], Preset="Poplar (paper 000 Fig. 12)", Seed=4)


def reference(name):
    return os.path.join(arguments.work, "mpi_reference_%s.vtp" % name)


if arguments.write_reference:
    for name, leaf in leaves.items():
        # Inline binary: Debian's ParaView 5.11 cannot read back appended-mode .vtp files (see README).
        SaveData(reference(name), proxy=leaf, DataMode="Binary")
        print("reference leaf written to", reference(name))
    raise SystemExit(0)

checks = Checks()
ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
checks.check(ranks == arguments.ranks, "running on %d ranks (expected %d)" % (ranks, arguments.ranks))
for name, leaf in leaves.items():
    leaf.UpdatePipeline()
    serial = servermanager.Fetch(XMLPolyDataReader(FileName=[reference(name)]))
    info = leaf.GetDataInformation()
    checks.check(info.GetNumberOfPoints() == serial.GetNumberOfPoints(),
                 "%s: points over all ranks %d, serial %d" % (name, info.GetNumberOfPoints(),
                                                              serial.GetNumberOfPoints()))
    checks.check(info.GetNumberOfCells() == serial.GetNumberOfCells(),
                 "%s: cells over all ranks %d, serial %d" % (name, info.GetNumberOfCells(), serial.GetNumberOfCells()))
    gathered = servermanager.Fetch(leaf)
    points = vtk_to_numpy(gathered.GetPoints().GetData())
    checks.check(len(numpy.unique(points, axis=0)) == len(points), "%s: no point appears twice" % name)
    checks.check(fingerprint(gathered) == fingerprint(serial), "%s: gathered leaf bit-identical to the serial one" % name)
checks.finish()
