# SPDX-License-Identifier: GPL-3.0-or-later
"""Paper 002, Fig. 8: growing palmate leaves (LeafOutlineSource, Model "Space curve", the Fig. 8 presets), 3 and 5
lobes, each at half-margin lengths S = 1.5, 2.5, 3.5: with mu held fixed every lobe grows as a similar copy, so the
whole leaf does. Each lobe's midvein is drawn in dark green.

    xvfb-run -a pvbatch examples/main_paper002_palmate_leaves.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import caption, save_png, save_state, save_vtp, show_solid, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403

LENGTHS = [1.5, 2.5, 3.5]
view = white_view(1800, 1000)
for row, lobes in enumerate((3, 5)):
    x = 0.0
    for k, length in enumerate(LENGTHS):
        leaf = LeafOutlineSource(Model="Space curve", SpaceCurvePreset="Paper 002 Fig. 8, %d lobes" % lobes,
                                 CurveLength=length, Resolution=60, MeshQuality="Quality")
        if length == LENGTHS[-1]:
            save_vtp(leaf, os.path.join(arguments.output, "paper002_figure8_%d_lobes.vtp" % lobes))
        leaf.UpdatePipeline()
        bounds = leaf.GetDataInformation().GetBounds()
        half_width = 0.5 * (bounds[1] - bounds[0])
        x += half_width
        offset = [x, -row * 6.5]
        x += half_width + 0.8
        placed = Transform(Input=leaf)
        placed.Transform.Translate = offset + [0.0]
        show_solid(placed, view, [0.45, 0.7, 0.25])
        outline = Transform(Input=OutputPort(leaf, 1))
        outline.Transform.Translate = offset + [0.05]
        show_solid(outline, view, [0.1, 0.3, 0.05], LineWidth=2.0)
    caption(view, "Paper 002 Fig. 8, %d lobes   S = 1.5, 2.5, 3.5" % lobes, [0.0, -row * 6.5 - 1.0, 0.0], 0.35)
save_png(view, os.path.join(arguments.output, "paper002_palmate_leaves.png"))
save_state(arguments, "paper002_palmate_leaves")
