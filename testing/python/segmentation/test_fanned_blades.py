# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: elliptic blades fanned around a twig are leaves, not a tube. The accuracy benchmark's shrub (16 twigs,
64 blades) with LeafOutlineSource's Entire blade (elliptic, 0.61 as wide as long, 1.448 long) scanned from one
position at 1 % of a leaf's length in range noise (the benchmark's scan of shrub-entire, point for point). A twig
carries its four blades like vanes, each blade's plane holding the twig's axis, their normals 45 degrees apart; the
features' radius r, widened to 12 times the noise, is thicker than the twig, so the twig's surface takes the blades'
normals and the four blades grow into one region through it. That region's normals turn about the twig's axis as a
tube's do (a cylinder's axis, spread and kurtosis) and all four blades (12,701 points) were wood. A tube's normals
fill the arc they turn over; the blades' sit in one tight group per blade with empty arcs between, so the region is
several sheets, grown again apart, and each blade is a leaf instance.

    pvpython test_fanned_blades.py --plugin PlantMorph.so --work DIR
"""
import math

from plantmorph_testing import Checks, leaf_instances_against_truth, load_plugin, parse_arguments, scan_around

arguments = parse_arguments([("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()

# the blade's LeafScale gives it the default blade's area (0.7339 at length 1; the Entire blade fills 0.3501 of its
# length squared)
tree = TreeFromSketchSource(Preset=0, TreeType=0, Depth=2, ChildCount=4, Ratio=0.7, Length=6.0, Radius=0.15,
                            LeafCount=4, LeafScale=round(math.sqrt(0.7339 / 0.3501), 3), Sides=12)
tree.Leaf = OutputPort(LeafOutlineSource(Preset="Entire"), 0)
plant = AppendGeometry(Input=[OutputPort(tree, 0), OutputPort(tree, 2)])
scan = scan_around(VirtualScanner, plant, 1, 0.08, 0.01, 1, maximum_range=5)
segmentation = PlantSegmentationFilter(Input=scan, UpAxis="Y")
segmentation.UpdatePipeline()
labels = servermanager.Fetch(segmentation).GetPointData()
truth = servermanager.Fetch(scan).GetPointData()
organ = vtk_to_numpy(labels.GetArray("Organ"))
true_organ = vtk_to_numpy(truth.GetArray("Organ"))
true_leaf = numpy.where(true_organ == 1, vtk_to_numpy(truth.GetArray("LeafId")), -1)
for leaf in range(4):  # the first twig's four blades, 861-5,022 points each
    mine = true_leaf == leaf
    share = numpy.count_nonzero(organ[mine] == 1) / max(1, numpy.count_nonzero(mine))
    checks.check(numpy.count_nonzero(mine) >= 500 and share > 0.9,
                 "blade %d (%d points) is leaf: %.3f of its points (0.05 at most before)" % (leaf, numpy.count_nonzero(mine), share))
both = numpy.count_nonzero((organ == 0) & (true_organ == 0))
either = numpy.count_nonzero((organ == 0) | (true_organ == 0))
checks.check(both / either > 0.8, "wood IoU %.3f above 0.8 (0.427 before)" % (both / either))
found, wood_instances, matched = leaf_instances_against_truth(labels, truth)
checks.check(matched >= 44, "at least 44 leaves matched at IoU > 0.5 (%d; 40 before)" % matched)
checks.finish()
