# SPDX-License-Identifier: GPL-3.0-or-later
"""Tracing a leaf: three Poly Line sources (left margin, right margin, midvein) combined with Append Geometry drive
LeafOutlineSource's B-spline model through its ControlPoints input. In the GUI the three polylines are drawn over a
photograph with the Poly Line widget (docs/tracing-a-leaf-photo.md); here their points are typed in.

    xvfb-run -a pvbatch examples/trace_leaf_outline.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import save_png, save_vtp, show_solid, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403

# Points in cm as traced over a photograph: base at the origin, apex at (0.4, 9.0).
left = PolyLineSource(registrationName="LeftMargin",
                      Points=[0, 0, 0, -2.2, 1.5, 0, -3.3, 3.8, 0, -3.0, 6.0, 0, -1.6, 8.0, 0, 0.4, 9.0, 0])
right = PolyLineSource(registrationName="RightMargin",
                       Points=[0, 0, 0, 1.8, 1.2, 0, 3.1, 3.5, 0, 3.2, 5.8, 0, 2.0, 7.9, 0, 0.4, 9.0, 0])
midvein = PolyLineSource(registrationName="Midvein", Points=[0, 0, 0, 0.1, 4.5, 0, 0.4, 9.0, 0])
traced = AppendGeometry(registrationName="TracedOutline", Input=[left, right, midvein])  # this order matters
leaf = LeafOutlineSource(registrationName="TracedLeaf", ControlPoints=traced, Model="B-spline",
                         BSplinePreset="ControlPoints input", Resolution=60)
save_vtp(leaf, os.path.join(arguments.output, "traced_leaf.vtp"))

view = white_view(800, 900)
show_solid(OutputPort(leaf, 0), view, [0.45, 0.7, 0.25], Representation="Surface With Edges",
           EdgeColor=[0.3, 0.5, 0.15])
for line in (left, right, midvein):
    show_solid(line, view, [0.8, 0.2, 0.1], LineWidth=2.0, Representation="Points", PointSize=8.0)
save_png(view, os.path.join(arguments.output, "traced_leaf.png"))
