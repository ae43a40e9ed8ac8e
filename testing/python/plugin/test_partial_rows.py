# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: a row-list property whose numbers do not fill whole rows is refused, with an error naming the property.

ParaView pushes a repeat_command property row by row and drops a partial last row before the filter sees it, so
`Terms` of 9 numbers used to give a leaf from the first 7 and `BranchOverrides = [1, 2, 3]` was ignored. Now the
filter hears the raw count (vtkSICountedDoubleVectorProperty) and reports an error naming the property, with empty
outputs; whole rows still work, and a state file keeps the refusal (it stores all the numbers) and loads the good
rows as before.

    pvpython test_partial_rows.py --plugin PlantMorph.so --work DIR
"""
import os

from plantmorph_testing import Checks, Messages, fingerprint, load_plugin, parse_arguments

arguments = parse_arguments()

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager

load_plugin(arguments.plugin, globals())
checks = Checks()
# Two whole rows of the deformed rectangle's terms: a y bulge and an x wave (Target, Scale, Amplitude, Multiplier,
# Frequency, Variable, Phase).
TWO_ROWS = [0, 0, 0.2, 0, 1, 1, 0, 1, 1, 0.05, 1, 2, 0, 0]


def fetch(proxy, port=0):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy, idx=port)


def sizes(proxy, ports):
    return [fetch(proxy, port).GetNumberOfPoints() for port in ports]


SetActiveSource(None)
leaf = LeafOutlineSource(Preset="Custom", Terms=TWO_ROWS)
with Messages(leaf) as messages:
    good = fetch(leaf)
checks.check(not messages.errors and good.GetNumberOfPoints() > 0, "14 Terms numbers (two rows): a leaf %s" %
             messages.errors)
good_print = fingerprint(good)

leaf.Terms = TWO_ROWS[:9]
with Messages(leaf) as messages:
    counts = sizes(leaf, (0, 1))
checks.check(messages.said("Terms = 9 numbers", "{0, 7, 14, ...}", "last row has 2", kind="error"),
             "9 Terms numbers: an error naming Terms and the partial row %s" % messages.errors)
checks.check(counts == [0, 0], "9 Terms numbers: empty Blade and Outline %s" % counts)

leaf.Terms = TWO_ROWS
with Messages(leaf) as messages:
    again = fetch(leaf)
checks.check(not messages.errors and fingerprint(again) == good_print, "whole rows again: the same leaf")

leaf.Terms = []
with Messages(leaf) as messages:
    plain = fetch(leaf)
checks.check(not messages.errors and plain.GetNumberOfPoints() > 0, "no Terms: the plain rectangle, no error")

SetActiveSource(None)
tree = TreeFromSketchSource(Preset="Custom", Depth=2, BranchOverrides=[1, 2, 3])
with Messages(tree) as messages:
    counts = sizes(tree, (0, 1, 2))
checks.check(messages.said("BranchOverrides = 3 numbers", "{0, 6, 12, ...}", "last row has 3", kind="error"),
             "a BranchOverrides row of 3 numbers: an error naming BranchOverrides %s" % messages.errors)
checks.check(counts == [0, 0, 0], "... and empty outputs %s" % counts)
tree.BranchOverrides = [1, 2, -1000, -1000, -1000, -1000]
with Messages(tree) as messages:
    counts = sizes(tree, (0, 1))
checks.check(not messages.errors and counts[0] > 0 and counts[1] > 0, "a whole row: a tree %s" % messages.errors)

# The scanner's Positions: a partial row was a silent single position.
SetActiveSource(None)
scan_leaf = Sphere(Radius=1.0)
scanner = VirtualScanner(Input=scan_leaf, ScannerType="Depth camera", Resolution=[40, 30], Positions=[0, -5, 1, 2])
with Messages(scanner) as messages:
    counts = sizes(scanner, (0, 1))
checks.check(messages.said("Positions = 4 numbers", "{3, 6, 9, ...}", "last row has 1", kind="error"),
             "Positions of 4 numbers: an error naming Positions %s" % messages.errors)
checks.check(counts == [0, 0], "... and empty outputs %s" % counts)
scanner.Positions = [0, -5, 1, 1, -5, 1]
with Messages(scanner) as messages:
    counts = sizes(scanner, (0,))
checks.check(not messages.errors and counts[0] > 0, "two whole rows: a cloud %s" % messages.errors)
for seed in (-1, -5, 1000001):
    scanner.Seed = seed
    with Messages(scanner) as messages:
        counts = sizes(scanner, (0, 1))
    checks.check(messages.said("Seed = %d" % seed, "[0, 1000000]", kind="error") and counts == [0, 0],
                 "Seed %d: refused, naming Seed, empty outputs %s %s" % (seed, messages.errors, counts))
scanner.Seed = 1000000
with Messages(scanner) as messages:
    counts = sizes(scanner, (0,))
checks.check(not messages.errors and counts[0] > 0, "Seed 1000000: accepted %s" % messages.errors)
scanner.Positions = [0, -5, 1, 2]

# A state file stores every number: the partial row is refused after loading too, the whole rows give the same leaf.
leaf.Terms = TWO_ROWS[:9]
state = os.path.join(arguments.work, "partial_rows.pvsm")
SaveState(state)
ResetSession()
load_plugin(arguments.plugin, globals())
LoadState(state)
loaded = [p for p in GetSources().values() if p.GetXMLName() == "LeafOutlineSource"]
checks.check(len(loaded) == 1, "the state holds the leaf")
if loaded:
    with Messages(loaded[0]) as messages:
        counts = sizes(loaded[0], (0,))
    checks.check(messages.said("Terms = 9 numbers", kind="error") and counts == [0],
                 "the loaded state refuses the partial row too %s" % messages.errors)
    loaded[0].Terms = TWO_ROWS
    with Messages(loaded[0]) as messages:
        reloaded = fetch(loaded[0])
    checks.check(not messages.errors and fingerprint(reloaded) == good_print, "... and gives the same leaf once whole")
scanners = [p for p in GetSources().values() if p.GetXMLName() == "VirtualScanner"]
checks.check(len(scanners) == 1, "the state holds the scanner")
if scanners:
    with Messages(scanners[0]) as messages:
        counts = sizes(scanners[0], (0,))
    checks.check(messages.said("Positions = 4 numbers", kind="error") and counts == [0],
                 "the loaded state refuses the partial Positions row too %s" % messages.errors)
checks.finish()
