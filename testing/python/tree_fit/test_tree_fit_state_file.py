# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: a TreeFitFilter pipeline saved as a state file loads in a fresh pvpython with the same properties and
bit-identical outputs on all five ports. The shipped tree cloud (data/tree-clouds) read by LeafCloudReader, fitted
with every property away from its default that keeps the fit meaningful (Scale, UpAxis, BreastHeight, OutlierSigma,
Tubes, TubeSides).

    pvpython test_tree_fit_state_file.py --plugin PlantMorph.so --work DIR
"""
import os
import sys

from plantmorph_testing import (check_same_properties, Checks, fingerprint, load_plugin, loaded_state, parse_arguments,
                                reload_in_fresh_pvpython)

arguments = parse_arguments([("--load", dict(default=None)), ("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

load_plugin(arguments.plugin, globals())
state = os.path.join(arguments.work, "tree_fit.pvsm")
expected_file = os.path.join(arguments.work, "tree_fit_state_expected.json")
DATA = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "data"))
PROPERTIES = {"Scale": 100.0, "UpAxis": "Y", "BreastHeight": 150.0, "OutlierSigma": 4.0, "Tubes": 1, "TubeSides": 6}
PORTS = ("Cylinders", "Skeleton", "Trees", "Branches", "Scan")


def describe(fit):
    fit.UpdatePipeline()
    outputs = [servermanager.Fetch(fit, idx=port) for port in range(len(PORTS))]
    values = {name: fit.GetPropertyValue(name) for name in PROPERTIES}
    return {"properties": {k: v if isinstance(v, (int, float)) else str(v) for k, v in values.items()},
            "fingerprints": [fingerprint(data) for data in outputs],
            "sizes": [data.GetNumberOfRows() if data.IsA("vtkTable") else data.GetNumberOfCells() for data in outputs]}


checks = Checks()

if arguments.load is not None:
    # Second process: a fresh pvpython loads the state saved by the first and compares.
    fit, expected = loaded_state(checks, arguments, expected_file, "FittedTree")
    actual = describe(fit)
    check_same_properties(checks, actual, expected)
    for port, name in enumerate(PORTS):
        checks.check(actual["sizes"][port] == expected["sizes"][port] and actual["sizes"][port] > 0,
                     "%s: %d rows or cells after loading, %d before" % (name, actual["sizes"][port],
                                                                      expected["sizes"][port]))
        checks.check(actual["fingerprints"][port] == expected["fingerprints"][port],
                     "%s bit-identical after the round trip" % name)
    checks.finish()
    sys.exit(0)

cloud = LeafCloudReader(registrationName="TreeCloud",
                        FileName=os.path.join(DATA, "tree-clouds", "generated_tree.xyz"))
fit = TreeFitFilter(registrationName="FittedTree", Input=cloud, **PROPERTIES)
before = describe(fit)
table = servermanager.Fetch(fit, idx=2)
checks.check(table.GetNumberOfRows() == 1 and table.GetValueByName(0, "Status").ToString() == "ok",
             "the cloud is fitted with these properties")
# Scale 100 (metres to centimetres): the breast height of 150 cm lies on the trunk, so DBH is a number.
dbh = table.GetValueByName(0, "DBH").ToDouble() if table.GetNumberOfRows() else float("nan")
checks.check(dbh == dbh and 10.0 < dbh < 100.0, "DBH %.1f cm at Scale 100" % dbh)
checks.check(before["sizes"][0] > 0 and before["sizes"][0] % 8 == 0, "Tubes with 6 sides: 8 cells per cylinder")
returncode = reload_in_fresh_pvpython(state, before, expected_file, arguments, __file__)
checks.check(returncode == 0, "the fresh pvpython found the same pipeline and outputs (exit code %d)" % returncode)
checks.finish()
