# SPDX-License-Identifier: GPL-3.0-or-later
"""Paper 000, Figs. 1 and 2: the margin types (entire, serrate, lobed, parted) and base/apex shapes (acute/acute,
rounded/acuminate, cordate/rounded, acuminate/emarginate) of the deformed-rectangle model, side by side.

    xvfb-run -a pvbatch examples/main_paper000_leaf_shapes.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import caption, save_png, save_state, save_vtp, show_solid, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403

ROWS = [
    ("Fig. 1", ["Entire", "Serrate", "Lobed", "Parted"]),
    ("Fig. 2", ["Acute base, acute apex", "Rounded base, acuminate apex", "Cordate base, rounded apex",
                "Acuminate base, emarginate apex"]),
]
view = white_view(1600, 1200)
for row, (figure, presets) in enumerate(ROWS):
    for column, preset in enumerate(presets):
        leaf = LeafOutlineSource(Preset=preset, Length=5.0, Resolution=80)
        name = preset.lower().replace(",", "").replace(" ", "_")
        save_vtp(leaf, os.path.join(arguments.output, "shape_%s.vtp" % name))
        placed = Transform(Input=leaf)
        placed.Transform.Translate = [column * 5.0, -row * 8.5, 0.0]
        show_solid(placed, view, [0.45, 0.7, 0.25])
        outline = Transform(Input=OutputPort(leaf, 1))
        outline.Transform.Translate = [column * 5.0, -row * 8.5, 0.01]
        show_solid(outline, view, [0.15, 0.3, 0.1], LineWidth=2.0)
        caption(view, "%s%s  %s" % (figure, "abcd"[column], preset), [column * 5.0 - 2.0, -row * 8.5 - 1.6, 0.0],
                0.16)
save_png(view, os.path.join(arguments.output, "paper000_leaf_shapes.png"))
save_state(arguments, "paper000_leaf_shapes")
