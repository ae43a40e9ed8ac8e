# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: the wood's surface grown into a leaf-shaped sheet gets no leaf instance. The herb of the accuracy
benchmark (a stem, three shoots, nine blades 1.5 long, tubes of 12 sides) scanned from four positions at 0.1 % of a
leaf's length in range noise: a piece of a shoot's surface, bent around the shoot and lying along it, passes as a leaf
region; as an instance it held wood points only. Every leaf instance now holds mostly leaf points (the scan's
truth), and the nine leaves are still found.

    pvpython test_wood_surface_sheets.py --plugin PlantMorph.so --work DIR
"""
from plantmorph_testing import Checks, leaf_instances_against_truth, load_plugin, parse_arguments, scan_around

arguments = parse_arguments([("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()

tree = TreeFromSketchSource(Preset=0, TreeType=0, Depth=1, ChildCount=3, Ratio=0.6, Length=4.0, Radius=0.08,
                            LeafCount=3, LeafScale=1.5, LeafAngle=50.0, Sides=12)
tree.Leaf = OutputPort(LeafOutlineSource(), 0)
plant = AppendGeometry(Input=[OutputPort(tree, 0), OutputPort(tree, 2)])
scan = scan_around(VirtualScanner, plant, 4, 0.12, 0.001 * 1.5, 1, maximum_range=5)
segmentation = PlantSegmentationFilter(Input=scan, UpAxis="Y")
segmentation.UpdatePipeline()
found, wood_instances, matched = leaf_instances_against_truth(servermanager.Fetch(segmentation).GetPointData(),
                                                             servermanager.Fetch(scan).GetPointData())
checks.check(not wood_instances, "no leaf instance is mostly wood (%d of %d are)" % (len(wood_instances), len(found)))
checks.check(matched == 9, "the 9 leaves found at IoU > 0.5 (%d)" % matched)
checks.finish()
