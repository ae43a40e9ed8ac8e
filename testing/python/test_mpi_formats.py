# SPDX-License-Identifier: GPL-3.0-or-later
"""pvbatch under MPI: the MTG and QSM writers write, on 1, 2 or 4 ranks, the file a serial run writes, byte for byte,
and the readers give the serial output once. A writer has no output port to carry a piece request, so each asks its
input for its own rank's piece and the pieces are gathered on the first rank (without that, every rank would hand the
whole tree over and the first rank would write it as many times as there are ranks). Run once serially with
--write-reference (pvpython), then as `mpirun -np N pvbatch test_mpi_formats.py ... --ranks N`."""
import hashlib
import os

from plantmorph_testing import (check_rank_count, Checks, fingerprint, load_plugin, load_reference,
                               MPI_EQUALITY_ARGUMENTS, parse_arguments, save_reference)

arguments = parse_arguments(MPI_EQUALITY_ARGUMENTS)

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

load_plugin(arguments.plugin, globals())
CORPUS = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fuzz", "corpus"))
run = "serial" if arguments.write_reference else "np%d" % arguments.ranks
mtg_file = os.path.join(arguments.work, "mpi_formats_%s.mtg" % run)
csv_file = os.path.join(arguments.work, "mpi_formats_%s.csv" % run)

tree = TreeFromSketchSource(Preset="Custom", Depth=2, ChildCount=3, Leaves=0)
servermanager.writers.MTGWriter(Input=OutputPort(tree, 1), FileName=mtg_file).UpdatePipeline()
servermanager.writers.QSMWriter(Input=OutputPort(tree, 1), FileName=csv_file).UpdatePipeline()
results = {}
for name in (mtg_file, csv_file):
    with open(name, "rb") as f:
        results[os.path.splitext(name)[1]] = hashlib.sha256(f.read()).hexdigest()
readers = {"mtg_read": MTGReader(FileName=mtg_file), "qsm_read": QSMReader(FileName=csv_file, Tubes=1),
           "mtg_fixture": MTGReader(FileName=os.path.join(CORPUS, "mtg", "monopodial.mtg")),
           "treeqsm_fixture": QSMReader(FileName=os.path.join(CORPUS, "qsm", "treeqsm.txt"))}
for name, reader in readers.items():
    data = servermanager.Fetch(reader)
    results[name] = [data.GetNumberOfPoints(), data.GetNumberOfCells(), fingerprint(data)]

reference_file = os.path.join(arguments.work, "mpi_formats_reference.json")
if arguments.write_reference:
    save_reference(reference_file, results)
    raise SystemExit(0)
checks = Checks()
check_rank_count(checks, arguments)
reference = load_reference(reference_file)
for name, value in results.items():
    checks.check(value == reference[name], "%s on %d ranks: %s, serially %s" % (name, arguments.ranks, value,
                                                                                reference[name]))
checks.finish()
