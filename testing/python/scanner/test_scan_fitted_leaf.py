# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: examples/scan_fitted_leaf.py, the comparison loop, runs as users run it (a fresh pvbatch) and its numbers
are sane. LeafFitFilter fits the shipped soybean scan, VirtualScanner's line scanner scans the fitted blade at the
scan's spacing with the fit residual as range noise, CloudComparisonFilter compares the clouds. Checked: the outputs
exist; the simulated cloud has about as many points as the measured one (the scanner samples at its spacing; the
blade's area divided by spacing^2 is the scan's point count); every simulated point lies on the fitted blade within
the range noise (RMS to the blade about the noise, 95th percentile within 3 noise sigmas); the measured scan's
cloud-to-cloud distances to the simulated cloud are of the order of the fit residual and the spacing (RMS below
residual RMS + spacing, not below half the residual's).

    pvpython test_scan_fitted_leaf.py --plugin PlantMorph.so --work DIR [--pvbatch pvbatch]
"""
import json
import os
import shutil
import subprocess
import sys

from plantmorph_testing import Checks, parse_arguments

arguments = parse_arguments([("--pvbatch", dict(default=None))])
HERE = os.path.dirname(os.path.abspath(__file__))
example = os.path.normpath(os.path.join(HERE, "..", "..", "..", "examples", "scan_fitted_leaf.py"))
output = os.path.join(arguments.work, "scan_fitted_leaf")
shutil.rmtree(output, ignore_errors=True)
pvbatch = arguments.pvbatch or shutil.which("pvbatch") or shutil.which("pvpython")
run = subprocess.run([pvbatch, example, "--plugin", arguments.plugin, "--output", output],
                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=600)
print(run.stdout)
checks = Checks()
checks.check(run.returncode == 0, "the example ran (exit %d)" % run.returncode)
for name in ("scan_fitted_leaf_simulated.vtp", "scan_fitted_leaf_blade.vtp", "scan_fitted_leaf.json"):
    path = os.path.join(output, name)
    checks.check(os.path.isfile(path) and os.path.getsize(path) > 0, "%s written" % name)
if run.returncode != 0 or not os.path.isfile(os.path.join(output, "scan_fitted_leaf.json")):
    checks.finish()
    sys.exit(1)
with open(os.path.join(output, "scan_fitted_leaf.json")) as f:
    result = json.load(f)
residual, simulated, c2c = result["residual"], result["simulated_to_model"], result["cloud_to_cloud"]
spacing, noise = result["spacing_cm"], residual["RMS"]
ratio = result["simulated_points"] / float(result["scan_points"])
checks.check(0.8 < ratio < 1.25, "simulated points %d vs scan points %d (ratio %.2f, expected about 1)"
             % (result["simulated_points"], result["scan_points"], ratio))
checks.check(0.0 < noise < 0.2 * result["length_cm"], "fit residual RMS %.4f cm is positive and small" % noise)
checks.check(simulated["Count"] == result["simulated_points"], "every simulated point compared to the blade")
checks.check(0.5 * noise < simulated["RMS"] < 1.5 * noise,
             "simulated cloud RMS to the blade %.4f cm is about the range noise %.4f cm" % (simulated["RMS"], noise))
checks.check(simulated["Percentile95"] < 3.0 * noise,
             "simulated cloud p95 to the blade %.4f cm within 3 noise sigmas" % simulated["Percentile95"])
checks.check(c2c["Count"] == result["scan_points"], "every measured point compared to the simulated cloud")
checks.check(0.5 * noise < c2c["RMS"] < noise + spacing,
             "cloud to cloud RMS %.4f cm between half the residual (%.4f) and residual + spacing (%.4f)"
             % (c2c["RMS"], 0.5 * noise, noise + spacing))
checks.finish()
