# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: an example's shipped state file (examples/states/<name>.pvsm) loads in a fresh pvpython and gives the
same data as the example script.

First process (pvbatch): runs examples/main_<name>.py without rendering and fingerprints the output of every pipeline
object it made, by registration name and port. Second process (a fresh pvpython): loads the plugin, then the shipped
state file, and fingerprints every object again; each must be there and bit-identical. A failure after an example
changed means its state file is stale: rerun scripts/update_example_states.sh."""
import json
import os
import runpy
import subprocess
import sys

from plantmorph_testing import Checks, fingerprint, load_plugin, parse_arguments

arguments = parse_arguments([("--example", dict(required=True)), ("--pvpython", dict(required=True)),
                             ("--load", dict(default=None))])
name = os.path.splitext(os.path.basename(arguments.example))[0][len("main_"):]
states = os.path.join(os.path.dirname(os.path.abspath(arguments.example)), "states")
shipped = os.path.join(states, name + ".pvsm")
expected_file = os.path.join(arguments.work, "example_state_%s.json" % name)


def fingerprints():
    """{registration name/port: fingerprint} of every pipeline object, at the animation scene's time."""
    from paraview.simple import GetAnimationScene, GetSources
    from paraview import servermanager
    time = GetAnimationScene().AnimationTime
    result = {}
    for (registration, _), proxy in GetSources().items():
        for port in range(proxy.SMProxy.GetNumberOfOutputPorts()):
            proxy.UpdatePipeline(time)
            data = servermanager.Fetch(proxy, idx=port)
            if data is not None:
                result["%s/%d" % (registration, port)] = fingerprint(data)
    return result


if arguments.load is None:
    # First process: the example itself, without rendering (no X server needed).
    if not os.path.exists(shipped):
        sys.exit("FAIL: %s has no shipped state file %s (run scripts/update_example_states.sh)" % (
            arguments.example, shipped))
    sys.path.insert(0, os.path.dirname(os.path.abspath(arguments.example)))
    sys.argv = [arguments.example, "--plugin", arguments.plugin, "--output", os.path.join(arguments.work, "examples"),
                "--no-render"]
    runpy.run_path(arguments.example, run_name="__main__")
    expected = fingerprints()
    with open(expected_file, "w") as f:
        json.dump(expected, f)
    print("%d outputs fingerprinted" % len(expected))
    result = subprocess.run([arguments.pvpython, os.path.abspath(__file__), "--plugin", arguments.plugin, "--work",
                             arguments.work, "--example", arguments.example, "--pvpython", arguments.pvpython,
                             "--load", shipped])
    sys.exit(result.returncode)

# Second process: a fresh pvpython loads the shipped state file.
from paraview.simple import LoadState  # noqa: E402

checks = Checks()
load_plugin(arguments.plugin, globals())
# Data files are named relative to the repository in a shipped state (examples/plantmorph_example.py save_state):
# ParaView finds them under the repository's folder.
LoadState(arguments.load, data_directory=os.path.dirname(os.path.dirname(os.path.abspath(arguments.example))))
with open(expected_file) as f:
    expected = json.load(f)
actual = fingerprints()
checks.check(len(expected) > 0, "the example made pipeline objects")
for key, value in sorted(expected.items()):
    checks.check(key in actual, "%s: in the state file %s" % (key, os.path.basename(arguments.load)))
    checks.check(actual.get(key) == value, "%s: the state file's output is bit-identical to the script's" % key)
checks.check(set(actual) == set(expected), "no object in the state file that the script does not make: %s" % sorted(
    set(actual) - set(expected)))
checks.finish()
