# SPDX-License-Identifier: GPL-3.0-or-later
"""Paper 003: B-spline leaves (LeafOutlineSource, Model "B-spline"): the elliptic, cucumber and pin oak presets, and
a custom leaf from control points typed in (as a user would trace them over a photograph), each meshed with CGAL
(quality mode) and drawn with its margins and midvein.

    xvfb-run -a pvbatch examples/main_paper003_bspline_leaves.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import caption, save_png, save_state, save_vtp, show_solid, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403

LEAVES = [
    ("elliptic", dict(BSplinePreset="Elliptic")),
    ("cucumber", dict(BSplinePreset="Cucumber")),
    ("pin_oak", dict(BSplinePreset="Pin oak")),
    # An asymmetric leaf from traced points (cm): base at the origin, apex at (0.6, 7.5).
    ("traced", dict(BSplinePreset="Custom", MidveinPoints=[0, 0, 0, 0.2, 3.0, 0, 0.6, 7.5, 0],
                    LeftMarginPoints=[-1.8, 1.2, 0, -2.9, 3.2, 0, -2.4, 5.4, 0, -1.0, 6.9, 0],
                    RightMarginPoints=[1.4, 0.8, 0, 2.6, 2.6, 0, 2.8, 4.6, 0, 1.9, 6.4, 0])),
]
view = white_view(1600, 700)
for column, (name, properties) in enumerate(LEAVES):
    leaf = LeafOutlineSource(Model="B-spline", Resolution=60, **properties)
    save_vtp(leaf, os.path.join(arguments.output, "paper003_%s.vtp" % name))
    placed = Transform(Input=leaf)
    placed.Transform.Translate = [column * 9.0, 0.0, 0.0]
    show_solid(placed, view, [0.45, 0.7, 0.25], Representation="Surface With Edges", EdgeColor=[0.3, 0.5, 0.15])
    outline = Transform(Input=OutputPort(leaf, 1))
    outline.Transform.Translate = [column * 9.0, 0.0, 0.02]
    show_solid(outline, view, [0.1, 0.25, 0.05], LineWidth=2.0)
    caption(view, name.replace("_", " "), [column * 9.0 - 1.5, -1.8, 0.0], 0.6)
save_png(view, os.path.join(arguments.output, "paper003_bspline_leaves.png"))
save_state(arguments, "paper003_bspline_leaves")
