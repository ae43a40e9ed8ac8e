# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: LeafFitFilter's HiddenMargin, where the scanner's view past a leaf's margin was blocked, on a simulated
herb (TreeFromSketchSource, nine LeafOutlineSource blades of one size) scanned by VirtualScanner from one position,
its leaves fitted on the scan's own LeafId (the truth, so what is measured is the view, not a segmentation).

- HiddenMargin lies in [0, 1] on every fitted leaf (the scan has Range and ScanPosition).
- The leaves whose margin was seen free (HiddenMargin at most 0.25) were seen whole: their Area within 5 % of the
  true blade's; those hidden over 0.4 of their margin were seen in part: Area under 0.9 of the true blade's.
- EstimatedArea, with the plant's shape and size taken from the leaves seen free, gives every leaf within 10 % of its
  true area and their median within 3 %.
- ExtentsSeen is a code 0-3; 3 (Length and Width seen whole) on every leaf whose margin was seen free all round, and
  0 only on leaves whose margin was hidden somewhere; EstimatedArea by AreaRule 6 (from an extent seen whole) is never
  under Area.
- The same scan without its Range array: HiddenMargin and ExtentsSeen are NaN on every row (not known). With a
  Range that is no distance from one place (the range plus half the x coordinate): NaN on every row, and a warning
  naming Range and ScanPosition; with 25 such positions it names ten and counts the other 15.

    pvpython test_leaf_fit_hidden_margin.py --plugin PlantMorph.so --work DIR
"""
from plantmorph_testing import (Checks, load_plugin, Messages, nine_leaf_herb, parse_arguments, scan_around,
                                true_leaf_areas)

arguments = parse_arguments()

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()

tree, plant = nine_leaf_herb(LeafOutlineSource, TreeFromSketchSource)
scan = scan_around(VirtualScanner, plant, 1, 0.12, 0.0015, 1, maximum_range=5)
fit = LeafFitFilter(Input=scan, LeafIdArray="LeafId", UpAxis="Y")
fit.UpdatePipeline()
traits = servermanager.Fetch(fit, idx=2)


def column(table, name):
    return vtk_to_numpy(table.GetColumnByName(name))


true_area = true_leaf_areas(servermanager.Fetch(tree, idx=2))
ids = column(traits, "LeafId").astype(int)
hidden = column(traits, "HiddenMargin")
area = column(traits, "Area") / true_area[ids]
estimated = column(traits, "EstimatedArea") / true_area[ids]
checks.check(len(ids) == 9, "a row per leaf the scanner saw (%d)" % len(ids))
checks.check(bool(numpy.all((hidden >= 0) & (hidden <= 1))), "HiddenMargin in [0, 1]: %s" % hidden.round(2))
free, blocked = hidden <= 0.25, hidden > 0.4
checks.check(free.sum() >= 2 and blocked.sum() >= 2, "leaves seen free (%d) and leaves hidden (%d) both" % (
    free.sum(), blocked.sum()))
checks.check(bool(numpy.all(numpy.abs(area[free] - 1) < 0.05)),
             "the leaves seen free were seen whole: Area / true %s" % area[free].round(3))
checks.check(bool(numpy.all(area[blocked] < 0.9)), "the leaves hidden were seen in part: Area / true %s" %
             area[blocked].round(3))
# ExtentsSeen: which of Length and Width the margin about both their ends shows whole. A margin seen free all round
# shows both; a leaf with neither seen was hidden somewhere. A leaf seen whole (free) with its Length seen has its
# true Length: its Area is its whole area.
extents = column(traits, "ExtentsSeen")
checks.check(bool(numpy.all(numpy.isin(extents, [0, 1, 2, 3]))), "ExtentsSeen a code 0-3: %s" % extents)
checks.check(bool(numpy.all(extents[hidden == 0] == 3)) and bool(numpy.all(hidden[extents == 0] > 0)),
             "a margin seen free all round shows both extents, and a leaf showing neither was hidden: %s / %s" % (
                 hidden.round(2), extents))
rule = column(traits, "AreaRule")
checks.check(bool(numpy.all(estimated[rule == 6] >= area[rule == 6])),
             "AreaRule 6 (from the extents seen) never under Area")
errors = numpy.abs(estimated - 1)
checks.check(bool(numpy.all(errors < 0.10)) and numpy.median(errors) < 0.03,
             "EstimatedArea within 10 %%, median %.2f %% (%s)" % (100 * numpy.median(errors), (100 * errors).round(1)))

# Without Range the scanner's position is not known.
no_range = PassArrays(Input=scan, PointDataArrays=["LeafId", "Organ", "ScanPosition"])
blind = servermanager.Fetch(LeafFitFilter(Input=no_range, LeafIdArray="LeafId", UpAxis="Y"), idx=2)
checks.check(blind.GetNumberOfRows() == len(ids) and bool(numpy.all(numpy.isnan(column(blind, "HiddenMargin")))) and
             bool(numpy.all(numpy.isnan(column(blind, "ExtentsSeen")))),
             "without Range: HiddenMargin and ExtentsSeen NaN on every row")
# A Range of another meaning: no position, and the filter says so.
bent = Calculator(Input=scan, ResultArrayName="Range", Function="Range + 0.5 * coordsX")
bent_fit = LeafFitFilter(Input=bent, LeafIdArray="LeafId", UpAxis="Y")
with Messages(bent_fit) as said:
    bent_fit.UpdatePipeline()
bent_traits = servermanager.Fetch(bent_fit, idx=2)
checks.check(bent_traits.GetNumberOfRows() == len(ids) and
             bool(numpy.all(numpy.isnan(column(bent_traits, "HiddenMargin")))),
             "a Range that is no distance from one place: HiddenMargin NaN on every row")
checks.check(any("Range and ScanPosition: no scanner position" in w and "no distances from one place" in w
                 for w in said.warnings),
             "a warning says the ranges gave no scanner position: %s" % [w[:80] for w in said.warnings][:3])
# Many positions that give none (as a line scanner's lines, each in a plane): the warning names ten and counts the
# rest, not hundreds of numbers.
many = PythonCalculator(Input=bent, ArrayName="ScanPosition", Expression="numpy.arange(len(Range)) % 25")
many_fit = LeafFitFilter(Input=many, LeafIdArray="LeafId", UpAxis="Y")
with Messages(many_fit) as said:
    many_fit.UpdatePipeline()
named = [w for w in said.warnings if "no scanner position was solved" in w]
checks.check(len(named) == 1 and "ScanPosition 0, 1, 2, 3, 4, 5, 6, 7, 8, 9 and 15 more" in named[0],
             "25 unsolved positions: ten named, the rest counted: %s" % [w[:160] for w in named])
checks.finish()
