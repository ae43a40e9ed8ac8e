# SPDX-License-Identifier: GPL-3.0-or-later
"""examples/calibrate_wilting.py on two MPI ranks gives the serial result, bit for bit, with the candidates split.

A tiny calibration (Resolution 14, the coarsest the presets accept; 3 s; two fitted parameters): once serially
(pvpython) and once as
`mpirun -np 2 pvbatch --symmetric`, each writing its result (--result, JSON):
- an ensemble of 5 candidates: the same candidates and objectives (floats compared exactly), the same best; the
  two ranks ran 3 and 2 of the 5 simulations (round-robin), which add up to the serial run's 5;
- a Nelder-Mead fit of 6 evaluations (its first simplex evaluated on both ranks): the same fitted parameters and
  objective.

    pvpython test_mpi_calibration.py --plugin PlantMorph.so --work DIR [--mpiexec mpirun] [--pvbatch pvbatch]
"""
import json
import os
import shutil
import subprocess
import sys

from plantmorph_testing import Checks, parse_arguments

arguments = parse_arguments([("--mpiexec", dict(default=shutil.which("mpirun") or "mpirun")),
                             ("--pvbatch", dict(default=shutil.which("pvbatch") or "pvbatch"))])
SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "calibrate_wilting.py")
COMMON = ["--plugin", arguments.plugin, "--fit", "DroopForce,LoadTime", "--resolution", "14", "--duration", "3"]
RUNS = {"ensemble": ["--ensemble", "5", "--seed", "3"], "fit": ["--evaluations", "6"]}
checks = Checks()
# pvpython has initialised MPI itself: its OMPI_/PMIX_ variables would make a nested mpirun think it is part of this
# process's job (as in test_client_server.py). The runs get a clean MPI environment.
ENVIRONMENT = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PMI_"))}
ENVIRONMENT["OMPI_MCA_rmaps_base_oversubscribe"] = "1"


def run(name, ranks):
    result = os.path.join(arguments.work, "calibration_%s_np%d.json" % (name, ranks))
    if os.path.exists(result):
        os.remove(result)
    if ranks == 1:
        command = [arguments.pvpython or shutil.which("pvpython") or "pvpython", SCRIPT]
    else:
        command = [arguments.mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", str(ranks), arguments.pvbatch,
                   "--symmetric", SCRIPT]
    sys.stdout.flush()
    done = subprocess.run(command + COMMON + RUNS[name] + ["--result", result], timeout=600,
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=ENVIRONMENT)
    checks.check(done.returncode == 0 and os.path.exists(result), "%s on %d rank(s) runs (exit %d)%s" % (
        name, ranks, done.returncode, "" if done.returncode == 0 else ":\n" + done.stdout[-3000:]))
    if not os.path.exists(result):
        return {}
    with open(result) as f:
        return json.load(f)


serial, parallel = run("ensemble", 1), run("ensemble", 2)
checks.check(serial.get("ranks") == 1 and parallel.get("ranks") == 2, "ranks: %s, %s" % (
    serial.get("ranks"), parallel.get("ranks")))
checks.check(len(serial.get("objectives", [])) == 5 and len(set(serial["objectives"])) == 5,
             "ensemble: 5 candidates with 5 different objectives: %s" % serial.get("objectives"))
for key in ("candidates", "objectives", "best", "best_objective"):
    checks.check(serial.get(key) == parallel.get(key), "ensemble: %s on 2 ranks is the serial one bit for bit: %s vs %s"
                 % (key, serial.get(key), parallel.get(key)))
# The 5 candidates alone (the best one's report run, on every rank, comes after the count).
checks.check(serial.get("runs_per_rank") == [5] and parallel.get("runs_per_rank") == [3, 2],
             "ensemble: the candidates split round-robin (simulations per rank: serial %s, 2 ranks %s)" % (
                 serial.get("runs_per_rank"), parallel.get("runs_per_rank")))
serial, parallel = run("fit", 1), run("fit", 2)
for key in ("fitted", "best", "best_objective"):
    checks.check(key in serial and serial.get(key) == parallel.get(key),
                 "fit: %s on 2 ranks is the serial one bit for bit: %s vs %s" % (key, serial.get(key),
                                                                                 parallel.get(key)))
checks.finish()
