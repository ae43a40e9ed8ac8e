# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs a benchmark's Open3D side in a process of its own and reads its answer.

Debian's python3-open3d links VTK 9.1, which cannot load beside ParaView's VTK, so each benchmark that measures
Open3D hands it a script (run by the system's python3 with an empty PYTHONPATH) and its arguments. The script prints
its answer as one JSON line last. `run_open3d` returns that answer as a dictionary, or None after printing why
Open3D did not run (for instance, not installed).
"""
import json
import os
import subprocess


def run_open3d(script, *arguments, label="Open3D"):
    run = subprocess.run(["/usr/bin/python3", "-c", script] + [str(argument) for argument in arguments],
                         capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=""))
    if run.returncode != 0:
        print("%s: not run (%s); apt-get install python3-open3d" % (label, run.stderr.strip().splitlines()[-1:]))
        return None
    return json.loads(run.stdout.strip().splitlines()[-1])
