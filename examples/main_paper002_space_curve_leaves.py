# SPDX-License-Identifier: GPL-3.0-or-later
"""Paper 002, Figs. 1-6: space-curve leaves (LeafOutlineSource, Model "Space curve"), each preset at three
half-margin lengths S = 2, 3.5, 5 to show growth: Figs. 1, 2, 4, 5 and 6 grow as exact similar copies (their mu
and eta are held fixed), Fig. 3's exponential curvature with fixed u3 turns as it grows.

    xvfb-run -a pvbatch examples/main_paper002_space_curve_leaves.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import caption, save_png, save_state, save_vtp, show_solid, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403

LENGTHS = [2.0, 3.5, 5.0]
view = white_view(1800, 1100)
for figure in range(1, 7):
    row, column = divmod(figure - 1, 3)
    for k, length in enumerate(LENGTHS):
        leaf = LeafOutlineSource(Model="Space curve", SpaceCurvePreset="Paper 002 Fig. %d" % figure,
                                 CurveLength=length, Resolution=60, StripColumns=6)
        if length == LENGTHS[-1]:
            save_vtp(leaf, os.path.join(arguments.output, "paper002_figure%d.vtp" % figure))
        offset = [column * 16.0 + k * 4.2, -row * 11.0]
        placed = Transform(Input=leaf)
        placed.Transform.Translate = offset + [0.0]
        show_solid(placed, view, [0.45, 0.7, 0.25])
        outline = Transform(Input=OutputPort(leaf, 1))
        outline.Transform.Translate = offset + [0.05]
        show_solid(outline, view, [0.15, 0.3, 0.1], LineWidth=2.0)
    caption(view, "Paper 002 Fig. %d   S = 2, 3.5, 5" % figure, [column * 16.0 - 1.5, -row * 11.0 - 1.8, 0.0], 0.45)
save_png(view, os.path.join(arguments.output, "paper002_space_curve_leaves.png"))
save_state(arguments, "paper002_space_curve_leaves")
