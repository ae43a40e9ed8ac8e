# SPDX-License-Identifier: GPL-3.0-or-later
"""The ginkgo leaf of paper 000, eq. (1): LeafOutlineSource's blade and outline, written as .vtp files and rendered.

    xvfb-run -a pvbatch examples/main_ginkgo_leaf.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import save_png, save_state, save_vtp, show_solid, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403

leaf = LeafOutlineSource(registrationName="GinkgoLeaf", Preset="Ginkgo", Length=5.0, Resolution=60,
                         MeshQuality="Quality")
save_vtp(leaf, os.path.join(arguments.output, "ginkgo_blade.vtp"), port=0)
save_vtp(leaf, os.path.join(arguments.output, "ginkgo_outline.vtp"), port=1)

view = white_view(1000, 800)
show_solid(OutputPort(leaf, 0), view, [0.55, 0.75, 0.25], Representation="Surface With Edges",
           EdgeColor=[0.35, 0.5, 0.15])
show_solid(Tube(Input=OutputPort(leaf, 1), Radius=0.02), view, [0.2, 0.35, 0.1])
save_png(view, os.path.join(arguments.output, "ginkgo_leaf.png"))
save_state(arguments, "ginkgo_leaf")
