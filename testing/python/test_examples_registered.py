# SPDX-License-Identifier: GPL-3.0-or-later
"""Every script in examples/ runs in a ctest (plain python3).

    python3 test_examples_registered.py --source-dir SOURCE --build-dir BUILD --ctest CTEST

Checked: every examples/*.py but the shared helper module has an entry in testing/python/run_example.py's EXAMPLES
(how it runs, what it writes) and every entry names a script that exists; the main_ examples, and only they, are run
by their state test and have a shipped state file examples/states/NAME.pvsm; and `ctest -N` in the build tree lists
the test of every script: example.NAME for the others, python.example_state.NAME (main_ dropped) for the main ones."""
import argparse
import glob
import os
import re
import subprocess
import sys

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--source-dir", required=True)
parser.add_argument("--build-dir", required=True)
parser.add_argument("--ctest", default="ctest")
arguments = parser.parse_args()
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_example import EXAMPLES, HELPER  # noqa: E402

examples = os.path.join(arguments.source_dir, "examples")
scripts = sorted(os.path.basename(p) for p in glob.glob(os.path.join(examples, "*.py")) if not p.endswith(HELPER))
listed = subprocess.run([arguments.ctest, "-N"], cwd=arguments.build_dir, stdout=subprocess.PIPE,
                        universal_newlines=True, check=True).stdout
tests = set(re.findall(r"^\s*Test\s+#\d+: (\S+)$", listed, re.MULTILINE))
failures = []
for script in scripts:
    stem = os.path.splitext(script)[0]
    main = stem.startswith("main_")
    entry = EXAMPLES.get(script)
    if entry is None:
        failures.append("examples/%s has no entry in testing/python/run_example.py's EXAMPLES" % script)
    elif (entry[0] == "state") != main:
        failures.append("examples/%s: only main_ examples are run by their state test" % script)
    test = "python.example_state.%s" % stem[len("main_"):] if main else "example.%s" % stem
    if test not in tests:
        failures.append("examples/%s has no ctest %s (testing/CMakeLists.txt)" % (script, test))
    if main and not os.path.isfile(os.path.join(examples, "states", stem[len("main_"):] + ".pvsm")):
        failures.append("examples/%s has no state file examples/states/%s.pvsm" % (script, stem[len("main_"):]))
for script in sorted(set(EXAMPLES) - set(scripts)):
    failures.append("run_example.py's EXAMPLES names examples/%s, which does not exist" % script)
print("%d example scripts, %d tests listed" % (len(scripts), len(tests)))
for failure in failures:
    print("FAIL:", failure)
sys.exit(1 if failures else 0)
