# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs the real ParaView GUI under Xvfb with PlantMorph loaded and plays a QtTesting XML event file: what both GUI
tests (run_gui_test.py, run_tracing_test.py) share.

ParaView gets a home of its own (no user settings; the given macros in its Macros folder, where the XML events can
pick them from the Macros menu). On this kind of machine an X connection to Xvfb now and then fails at once ("bad X
server connection"); such a run says nothing about PlantMorph, so it is run again on a new server, up to six times."""
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
from virtual_display import VirtualDisplay  # noqa: E402

SCREEN = "1600x1000x24"  # the main window's layout, and so the render view's size, follow from it


def play(paraview, plugin_dir, events, work, macros, environment=None, extra_arguments=(), fresh_files=()):
    """Plays `events` (an XML file) in `paraview`; returns (exit code, log). `macros`: Python files to install as
    ParaView macros; `environment`: extra variables for the macros; `fresh_files`: files removed before every
    attempt (what the macros write)."""
    home = os.path.join(work, "home")
    shutil.rmtree(home, ignore_errors=True)
    macro_dir = os.path.join(home, ".config", "ParaView", "Macros")
    os.makedirs(macro_dir)
    os.chmod(home, 0o700)  # it is also XDG_RUNTIME_DIR, which Qt wants private
    for macro in macros:
        shutil.copy(macro, macro_dir)
    env = dict(os.environ, HOME=home, XDG_RUNTIME_DIR=home, **(environment or {}))
    # the macros import this folder's pipeline_description
    here = os.path.dirname(os.path.abspath(__file__))
    env["PYTHONPATH"] = here + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    command = [paraview, "--dr", "--plugin-search-paths=" + plugin_dir,
               "--plugins=PlantMorph", "--test-script=" + events, "--test-directory=" + work]
    command += list(extra_arguments) + ["--exit"]
    print(" ".join(command))
    for attempt in range(6):
        for stale in fresh_files:
            if os.path.exists(stale):
                os.remove(stale)
        with VirtualDisplay(SCREEN) as server:  # a server of its own each time: xvfb-run -a races (virtual_display.py)
            run = subprocess.run(command, env=server.environment(env), stdout=subprocess.PIPE,
                                 stderr=subprocess.STDOUT, timeout=600)
        log = run.stdout.decode(errors="replace")
        if "X server" not in log and "cannot open display" not in log.lower():
            break
        print("attempt %d: X connection failed, running again" % (attempt + 1))
    return run.returncode, log


class Checks:
    """Collects ok/FAIL lines; `failed` says whether any check failed."""

    def __init__(self):
        self.failures = []

    def __call__(self, condition, message):
        print(("ok: " if condition else "FAIL: ") + message)
        if not condition:
            self.failures.append(message)

    @property
    def failed(self):
        return bool(self.failures)

    def playback(self, returncode, log, check_file):
        """The checks every GUI test starts with: ParaView exited with 0 (playback and, if asked, the image
        comparison passed), the playback reported success, and the check macro wrote `check_file`. Returns what
        that file holds (JSON), or None."""
        self(returncode == 0, "ParaView exited with 0: %d" % returncode)
        self("Success =  true" in log or "Success = true" in log, "the playback succeeded")
        self(os.path.exists(check_file), "the check macro ran and wrote %s" % check_file)
        if not os.path.exists(check_file):
            return None
        with open(check_file) as f:
            return json.load(f)
