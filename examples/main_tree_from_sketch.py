# SPDX-License-Identifier: GPL-3.0-or-later
"""Paper 004's trees: Table 1's three template trees with leaves, and a tree sketched from strokes.

tree_templates.png: the left (monopodial 3/8, 8 children), middle (sympodial 1/3, 3 children) and right (monopodial
5/8, 10 children) templates of Table 1, with textured-quad leaves (the middle one with willow twigs and ginkgo
blades from LeafOutlineSource instead). tree_sketched.png: seven strokes as a user would trace them over a
photograph (red), the tree TreeFromSketchSource lifts from them seen from the front (it covers its strokes
exactly: every branch projects onto its stroke) and, next to it, the same tree turned 90 degrees, which shows the
depth the phyllotaxis rule gave each stroke branch, each with a two-level template subtree and leaves.
In the GUI the strokes are drawn over a photograph with the Poly Line widget (docs/tracing-a-tree-photo.md).
tree_merged.png: merging (paper 004 Fig. 11): a small sympodial tree's skeleton on the MergeTree input of a
monopodial template, once grafted onto a branch (MergeParentBranch, MergeU, MergeAngle, MergeScale) and once as a
second trunk beside it (MergeParentBranch -1, MergeOffset).

    xvfb-run -a pvbatch examples/main_tree_from_sketch.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import save_framed_png, save_state, save_vtp, show_solid, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403

BARK = [0.45, 0.32, 0.2]
LEAF = [0.35, 0.62, 0.22]


def save_framed(view, path, center, half_height):
    """Front view, framed on the trees."""
    save_framed_png(view, path, [center[0], center[1], 0], [center[0], center[1], 200], [0, 1, 0], half_height)


def placed(source, port, dx, rotate_y=0.0):
    moved = Transform(Input=OutputPort(source, port))
    moved.Transform.Translate = [dx, 0, 0]
    moved.Transform.Rotate = [0, rotate_y, 0]
    return moved


# Table 1's templates side by side.
view = white_view(1500, 700)
SetActiveSource(None)
left = TreeFromSketchSource(registrationName="Table1Left", Preset="Table 1 left: monopodial 3/8", LeafScale=0.9,
                            LeafCount=3)
SetActiveSource(None)
blade = LeafOutlineSource(registrationName="GinkgoBlade", Preset="Ginkgo", Length=5.0, Resolution=16,
                          MeshQuality="Paper")
SetActiveSource(None)
middle = TreeFromSketchSource(registrationName="Table1Middle", Preset="Table 1 middle: sympodial 1/3", Leaf=blade,
                              LeafType="Willow", LeafCount=4, LeafScale=0.5)
SetActiveSource(None)
right = TreeFromSketchSource(registrationName="Table1Right", Preset="Table 1 right: monopodial 5/8", LeafScale=0.7,
                             LeafCount=2)
for tree, dx in ((left, -24.0), (middle, 0.0), (right, 25.0)):
    show_solid(placed(tree, 0, dx), view, BARK)
    show_solid(placed(tree, 2, dx), view, LEAF)
save_vtp(left, os.path.join(arguments.output, "tree_table1_left_branches.vtp"))
save_framed(view, os.path.join(arguments.output, "tree_templates.png"), [1.5, 12], 18.5)

# A sketched tree: strokes as traced over a photograph, trunk first.
strokes = [
    [0, 0, 0, 0.3, 4, 0, -0.2, 8, 0, 0.2, 12, 0, 0, 16, 0],
    [0.2, 7, 0, 2, 8.5, 0, 4, 9.5, 0, 6.5, 11.5, 0],
    [-0.1, 6, 0, -2, 7, 0, -4.5, 8, 0, -6, 10, 0],
    [0.1, 11, 0, 1.5, 12.5, 0, 3, 14.5, 0],
    [0, 10, 0, -1.5, 11.5, 0, -3.5, 13.5, 0, -4, 15, 0],
    [4, 9.5, 0, 5, 8.5, 0, 6.5, 8.2, 0],
    [-4.5, 8, 0, -5.5, 7, 0, -7, 6.8, 0],
]
lines = [PolyLineSource(registrationName="Stroke%d" % k, Points=points) for k, points in enumerate(strokes)]
traced = AppendGeometry(registrationName="TracedStrokes", Input=lines)  # drawing order matters: the trunk first
SetActiveSource(None)
sketched = TreeFromSketchSource(registrationName="SketchedTree", Strokes=traced, Mode="Strokes",
                                SegmentsPerBranch=16, StrokeSubtreeDepth=2, ChildCount=4, Ratio=0.6,
                                Preset="Custom", TreeType="Monopodial", PhyllotaxisA=2, PhyllotaxisB=5,
                                LeafCount=3, LeafScale=0.6, Sides=8)
save_vtp(sketched, os.path.join(arguments.output, "tree_sketched_branches.vtp"))
save_vtp(sketched, os.path.join(arguments.output, "tree_sketched_skeleton.vtp"), port=1)
view2 = white_view(1400, 800)
show_solid(placed(sketched, 0, 0.0), view2, BARK)
show_solid(placed(sketched, 2, 0.0), view2, LEAF, Opacity=0.6)
strokes_shown = Transform(Input=traced)
strokes_shown.Transform.Translate = [0, 0, 30]  # in front of the tree, so the strokes are never hidden
show_solid(strokes_shown, view2, [0.85, 0.1, 0.1], LineWidth=3.0)
show_solid(placed(sketched, 0, 18.0, rotate_y=90.0), view2, BARK)
show_solid(placed(sketched, 2, 18.0, rotate_y=90.0), view2, LEAF, Opacity=0.6)
save_framed(view2, os.path.join(arguments.output, "tree_sketched.png"), [9, 12], 15)

# Merged trees: a sympodial tree's skeleton grafted onto branch 1 of a monopodial template, and stood beside it.
SetActiveSource(None)
graft = TreeFromSketchSource(registrationName="GraftedTree", Preset="Custom", TreeType="Sympodial", Depth=3,
                             ChildCount=3, Ratio=0.0, Length=4.0, Radius=0.25, PhyllotaxisA=1, PhyllotaxisB=3,
                             Leaves=0)
SetActiveSource(None)
host = TreeFromSketchSource(registrationName="HostTree", Preset="Custom", Depth=2, LeafCount=3, LeafScale=0.8,
                            MergeTree=OutputPort(graft, 1), MergeParentBranch=1, MergeU=0.5, MergeAngle=40.0,
                            MergeScale=0.8)
SetActiveSource(None)
pair = TreeFromSketchSource(registrationName="SecondTrunk", Preset="Custom", Depth=2, LeafCount=3, LeafScale=0.8,
                            MergeTree=OutputPort(graft, 1), MergeParentBranch=-1, MergeOffset=[7, 0, 0],
                            MergeAngle=0.0, MergeScale=1.0)
save_vtp(host, os.path.join(arguments.output, "tree_merged_branches.vtp"))
view3 = white_view(1400, 700)
for tree, dx in ((host, -7.0), (pair, 10.0)):
    show_solid(placed(tree, 0, dx), view3, BARK)
    show_solid(placed(tree, 2, dx), view3, LEAF)
save_framed(view3, os.path.join(arguments.output, "tree_merged.png"), [6, 8], 10)
save_state(arguments, "tree_from_sketch")
