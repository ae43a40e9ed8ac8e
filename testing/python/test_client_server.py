# SPDX-License-Identifier: GPL-3.0-or-later
"""Client-server: pvpython connected to `mpirun -np 2 pvserver` on localhost runs PlantMorph's pipelines on the
server (the plugin loaded on both sides) and gets the same data as the built-in session, once, not once per rank.

    pvpython test_client_server.py --plugin PlantMorph.so --work DIR --pvserver pvserver --mpiexec mpirun
"""
import os
import socket
import subprocess
import time

from plantmorph_testing import Checks, fingerprint, load_plugin, parse_arguments

arguments = parse_arguments([("--pvserver", dict(default="pvserver")), ("--mpiexec", dict(default="mpirun")),
                             ("--ranks", dict(type=int, default=2))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402


def pipelines():
    """The pipelines compared: a leaf of each outline model, veins grown on one, a scan of it, and a leaf refused for
    a partial Terms row."""
    leaf = LeafOutlineSource(Preset="Lobed", Resolution=40)
    return {
        "deformed_rectangle": leaf,
        "space_curve": LeafOutlineSource(Model="Space curve", SpaceCurvePreset="Paper 002 Fig. 8, 3 lobes", Resolution=30),
        "venation": VenationFilter(Input=leaf, Preset="Poplar (paper 000 Fig. 12)", Seed=3),
        # The leaf lies in z = 0, 5 long along y: scanned from above, with noise, its beams shared over the ranks.
        # A partial row of Terms: the server-side property helper (vtkSICountedDoubleVectorProperty) runs on the
        # server's ranks too, so the leaf is refused there as in the built-in session (empty, checked below).
        "partial_terms": LeafOutlineSource(Preset="Custom", Terms=[0, 0, 0.2, 0, 1, 1, 0, 1, 1]),
        "scan": VirtualScanner(Input=leaf, Positions=[0, 2.5, 15], LookAt=[0, 2.5, 0], Up=[0, 1, 0], AngularStep=0.5,
                               RangeNoise=0.01, Seed=2),
    }


def describe(proxies):
    result = {}
    for name, proxy in proxies.items():
        proxy.UpdatePipeline()
        data = servermanager.Fetch(proxy)
        result[name] = (fingerprint(data), data.GetNumberOfPoints(), proxy.GetDataInformation().GetNumberOfPoints())
    return result


checks = Checks()

# Built-in session first: the reference.
load_plugin(arguments.plugin, globals())
expected = describe(pipelines())
ResetSession()

# A free port, then the server on two ranks.
with socket.socket() as probe:
    probe.bind(("localhost", 0))
    port = probe.getsockname()[1]
command = [arguments.mpiexec, "--allow-run-as-root", "--oversubscribe", "-np", str(arguments.ranks), arguments.pvserver,
           "--server-port=%d" % port]
# pvpython has initialised MPI itself: its OMPI_/PMIX_ variables would make the nested mpirun think it is part of
# this process's job (its output pipe then closes at once). The server gets a clean MPI environment.
environment = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "OPAL_", "PMI_"))}
environment["OMPI_MCA_rmaps_base_oversubscribe"] = "1"
server = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=environment)
try:
    # Wait until it listens.
    deadline = time.time() + 60
    listening = False
    while time.time() < deadline and not listening and server.poll() is None:
        line = server.stdout.readline()
        listening = "Accepting connection" in line
    checks.check(listening, "pvserver listens on port %d" % port)
    if listening:
        Connect("localhost", port)
        ranks = servermanager.ActiveConnection.GetNumberOfDataPartitions()
        checks.check(ranks == arguments.ranks, "the server runs %d ranks (expected %d)" % (ranks, arguments.ranks))
        LoadPlugin(arguments.plugin, remote=True, ns=globals())
        LoadPlugin(arguments.plugin, remote=False, ns=globals())
        actual = describe(pipelines())
        for name, (digest, points, total) in expected.items():
            got = actual[name]
            checks.check(got[2] == total, "%s: %d points over the server's ranks, %d in the built-in session"
                         % (name, got[2], total))
            checks.check(got[0] == digest, "%s: the server's data is bit-identical to the built-in session's" % name)
        checks.check(expected["partial_terms"][2] == 0 and actual["partial_terms"][2] == 0,
                     "a partial Terms row is refused on the server as in the built-in session (empty outputs)")
        Disconnect()
finally:
    server.terminate()
    try:
        server.wait(timeout=20)
    except subprocess.TimeoutExpired:
        server.kill()
checks.finish()
