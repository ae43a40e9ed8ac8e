# SPDX-License-Identifier: GPL-3.0-or-later
"""Paper 003: adaptive Loop subdivision of a curled leaf. A coarse cucumber blade (LeafOutlineSource, Model
"B-spline") curled by LeafCurlFilter, then AdaptiveLoopFilter two levels deep: uniformly (every triangle split
each level, as VTK's Loop filter), with the paper's dihedral and flatness rules, and with the Surface error rule
(a tolerance in cm). The margin keeps its vertices (FeatureRule Fixed). Each blade is labelled with its triangle
count.

    xvfb-run -a pvbatch examples/adaptive_loop_leaf.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import caption, save_png, show_solid, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403

leaf = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", Resolution=8)
curled = LeafCurlFilter(Input=leaf, LongitudinalAngle=120.0, TransverseAngle=60.0)
SETTINGS = [
    ("uniform", dict(EdgeAngleThreshold=180.0, FlatnessThreshold=1.0)),
    ("paper rules", dict()),
    ("Surface error 0.01", dict(RefinementRule="Surface error", ErrorTolerance=0.01)),
]
curled.UpdatePipeline()
xmin, xmax, ymin, ymax, _, _ = curled.GetDataInformation().GetBounds()
step, size = 1.6 * (xmax - xmin), ymax - ymin
view = white_view(1500, 600)
for k, (name, properties) in enumerate(SETTINGS):
    subdivided = AdaptiveLoopFilter(Input=curled, MaximumLevel=2, FeatureRule="Fixed", **properties)
    subdivided.UpdatePipeline()
    placed = Transform(Input=subdivided)
    placed.Transform.Translate = [k * step, 0.0, 0.0]
    show_solid(placed, view, [0.55, 0.75, 0.25], Representation="Surface With Edges", EdgeColor=[0.2, 0.35, 0.1])
    triangles = subdivided.GetDataInformation().GetNumberOfCells()
    caption(view, "%s" % name, [k * step - 0.4 * step, ymin - 0.12 * size, 0.0], 0.05 * size)
    caption(view, "%d triangles" % triangles, [k * step - 0.4 * step, ymin - 0.22 * size, 0.0], 0.05 * size)
view.CameraPosition = [0.0, -3.0, 2.0]  # from the front and above: the curl shows
view.CameraFocalPoint = [0.0, 0.0, 0.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
save_png(view, os.path.join(arguments.output, "adaptive_loop_leaf.png"), top_down=False)
