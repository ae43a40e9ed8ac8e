# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs one script of examples/ as its users run it and checks it wrote its files (plain python3).

    python3 run_example.py --example examples/NAME.py --plugin PlantMorph.so --work DIR --pvbatch PVBATCH
                           --pvpython PVPYTHON
    python3 run_example.py --labels NAME.py      (prints the ctest labels of the example, for testing/CMakeLists.txt)

EXAMPLES below says, for every script in examples/, how it is run and what it must write. testing/CMakeLists.txt
registers a test for every examples/*.py (a glob): example.NAME runs this script for the scripts that are not main_
examples; the main_ ones run in their python.example_state.NAME tests (examples/states). A new example without an
entry here fails its test, and repo.examples_registered fails until every example has an entry and a test.

The example runs in a fresh folder DIR/NAME (its --output, and the current folder), under its interpreter: pvbatch
for the scripts that render (on a private Xvfb server when there is no X server, virtual_display.py; a run that
still aborts on "bad X server connection" is run again on a new server, up to six times), pvpython for the
others. The test fails if the script exits non-zero or any file it must write is missing or empty."""
import argparse
import contextlib
import json
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from virtual_display import VirtualDisplay  # noqa: E402

# name: (interpreter, arguments after --plugin ({output}: its output folder), files it must write there, ctest method
# labels). Interpreter "state": a main_ example, run by its example_state test. The arguments keep each test short.
OUTPUT = ["--output", "{output}"]
EXAMPLES = {
    "adaptive_loop_leaf.py": ("pvbatch", OUTPUT, ["adaptive_loop_leaf.png"], ["subdivision"]),
    "calibrate_wilting.py": ("pvpython", ["--fit", "DroopForce", "--evaluations", "4", "--resolution", "14",
                                          "--duration", "3", "--result", "{output}/calibrate_wilting.json"],
                             ["calibrate_wilting.json"], ["wilting"]),
    "compare_scanned_leaf.py": ("pvbatch", OUTPUT, ["compare_scanned_leaf.png"], ["leaf_fit", "comparison"]),
    "leaf_curl.py": ("pvbatch", OUTPUT, ["leaf_curl.png", "leaf_curl_flat.vtp", "leaf_curl_both_70_60.vtp"],
                     ["subdivision"]),
    "scan_fitted_leaf.py": ("pvpython", OUTPUT, ["scan_fitted_leaf_simulated.vtp", "scan_fitted_leaf_blade.vtp",
                                                 "scan_fitted_leaf.json"], ["scanner", "leaf_fit"]),
    "scan_tree.py": ("pvbatch", OUTPUT, ["scan_tree.vtp", "scan_tree.las", "scan_tree.csv", "scan_tree.png"],
                     ["scanner", "tree", "las"]),
    "trace_leaf_outline.py": ("pvbatch", OUTPUT, ["traced_leaf.vtp", "traced_leaf.png"], ["leaf"]),
    "tree_formats.py": ("pvbatch", OUTPUT, ["tree_formats.mtg", "tree_formats.csv", "tree_formats.png"],
                        ["formats", "tree"]),
    "main_ginkgo_leaf.py": ("state", [], [], ["leaf"]),
    "main_measured_leaf.py": ("state", [], [], ["leaf_fit", "comparison"]),
    "main_paper000_leaf_shapes.py": ("state", [], [], ["leaf"]),
    "main_paper000_venation.py": ("state", [], [], ["venation"]),
    "main_paper002_palmate_leaves.py": ("state", [], [], ["leaf"]),
    "main_paper002_space_curve_leaves.py": ("state", [], [], ["leaf"]),
    "main_paper003_bspline_leaves.py": ("state", [], [], ["leaf"]),
    "main_scanned_plant.py": ("state", [], [], ["scanner", "tree"]),
    "main_segment_plant.py": ("state", [], [], ["segmentation", "leaf_fit", "scanner"]),
    "main_tree_from_sketch.py": ("state", [], [], ["tree"]),
    "main_wilting_cucumber.py": ("state", [], [], ["wilting"]),
}
HELPER = "plantmorph_example.py"  # the module the examples share, not an example


def run(command, cwd, render):
    """Runs the command (on a private Xvfb server if it renders and there is no X server), again after an X abort."""
    for attempt in range(1, 7):
        print("run (attempt %d): %s" % (attempt, " ".join(command)), flush=True)
        with contextlib.ExitStack() as stack:
            environment = None
            if render and not os.environ.get("DISPLAY"):
                environment = stack.enter_context(VirtualDisplay()).environment()
            result = subprocess.run(command, cwd=cwd, env=environment, stdin=subprocess.DEVNULL,
                                    stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                                    timeout=900)
        print(result.stdout, flush=True)
        if result.returncode == 0 or "bad X server connection" not in result.stdout:
            return result.returncode
    return result.returncode


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--labels", help="print the ctest labels of this example and exit")
    parser.add_argument("--example")
    parser.add_argument("--plugin")
    parser.add_argument("--work")
    parser.add_argument("--pvbatch", default="pvbatch")
    parser.add_argument("--pvpython", default="pvpython")
    arguments = parser.parse_args()
    if arguments.labels is not None:
        entry = EXAMPLES.get(os.path.basename(arguments.labels))
        print(";".join(entry[3] if entry else ["leaf"]), end="")
        return 0
    name = os.path.basename(arguments.example)
    if name not in EXAMPLES:
        print("FAIL: examples/%s has no entry in %s's EXAMPLES: say how it runs and what it writes" % (
            name, os.path.abspath(__file__)))
        return 1
    interpreter, extra, outputs, _ = EXAMPLES[name]
    if interpreter == "state":
        print("FAIL: examples/%s is a main_ example: its python.example_state test runs it" % name)
        return 1
    output = os.path.join(os.path.abspath(arguments.work), os.path.splitext(name)[0])
    shutil.rmtree(output, ignore_errors=True)
    os.makedirs(output)
    executable = arguments.pvbatch if interpreter == "pvbatch" else arguments.pvpython
    command = [executable, os.path.abspath(arguments.example), "--plugin", arguments.plugin]
    command += [argument.replace("{output}", output) for argument in extra]
    started = time.time()
    returncode = run(command, output, render=interpreter == "pvbatch")
    failures = [] if returncode == 0 else ["examples/%s exited with %d" % (name, returncode)]
    for file in outputs:
        path = os.path.join(output, file)
        size = os.path.getsize(path) if os.path.isfile(path) else 0
        print("%s: %d bytes" % (file, size))
        if size == 0:
            failures.append("examples/%s wrote no %s (or an empty one) into %s" % (name, file, output))
        elif file.endswith(".json"):
            # A calibration whose every simulation failed scores 1e9 (its penalty): a result, but not a calibration.
            with open(path) as f:
                best = json.load(f).get("best_objective")
            if best is not None and not best < 1e9:
                failures.append("examples/%s: every simulation failed (best objective %s)" % (name, best))
    print("examples/%s: %.1f s" % (name, time.time() - started))
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
