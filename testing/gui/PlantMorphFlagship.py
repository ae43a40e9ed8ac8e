# SPDX-License-Identifier: GPL-3.0-or-later
"""ParaView macro for the GUI test (testing/gui/run_gui_test.py installs it in the test's own Macros folder).

The menus have built LeafOutlineSource1 -> AdaptiveLoopFilter1 -> VenationFilter1, TreeFromSketchSource1 and
WiltingSimulator1 (on the tree, the active source then). This does what a user does in the pipeline browser, the
Change Input dialog and the Properties panel: WiltingSimulator1 on the venation's blade (port 1) with its veins
(port 0) on the Veins input, the subdivided blade as the tree's leaf, the animation at the end of the wilting, a
fixed camera. Then it writes what it found to $PLANTMORPH_GUI_CHECK (JSON) for the test."""
import json
import os

from paraview.simple import (FindSource, GetActiveViewOrCreate, GetAnimationScene, GetSources, Hide, OutputPort,
                             Render, SetActiveSource, Show, Transform, Tube)

from pipeline_description import describe

view = GetActiveViewOrCreate("RenderView")
leaf = FindSource("LeafOutlineSource1")
loop = FindSource("AdaptiveLoopFilter1")
venation = FindSource("VenationFilter1")
tree = FindSource("TreeFromSketchSource1")
# What a user sets in the Properties panel: a coarse 3-D leaf (paper 002's space curve; a flat blade is left as it
# is by the adaptive rules), two Loop levels, a small custom tree with two leaves per twig.
leaf.Model = "Space curve"
leaf.SpaceCurvePreset = "Paper 002 Fig. 5"
leaf.Resolution = 16
loop.MaximumLevel = 2
tree.Preset = "Custom"
tree.Depth = 3
tree.ChildCount = 3
tree.LeafCount = 2
# The menu made WiltingSimulator1 on the active source (the tree): its inputs are the venation's blade and veins.
wilt = FindSource("WiltingSimulator1")
wilt.Input = OutputPort(venation, 1)
wilt.Veins = OutputPort(venation, 0)
wilt.Resolution = 14  # the smallest the presets accept at the default blade thickness
wilt.Duration = 1.0
wilt.FrameInterval = 0.25
tree.Leaf = OutputPort(loop, 0)
tree.LeafScale = 1.0
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()
scene.AnimationTime = 1.0

for proxy in (leaf, loop, venation, tree):
    for port in range(proxy.SMProxy.GetNumberOfOutputPorts()):
        Hide(OutputPort(proxy, port), view)


def solid(proxy, color, port=0):
    display = Show(OutputPort(proxy, port), view)
    display.ColorArrayName = ["POINTS", ""]
    display.DiffuseColor = color
    display.AmbientColor = color
    return display


solid(wilt, [0.55, 0.75, 0.25])
solid(Tube(Input=OutputPort(wilt, 3), Radius=0.03, NumberofSides=6), [0.2, 0.35, 0.1])
bounds = wilt.GetDataInformation().GetBounds()
placed = {}
for port, color in ((0, [0.45, 0.32, 0.2]), (2, [0.35, 0.62, 0.22])):
    moved = Transform(Input=OutputPort(tree, port))
    moved.Transform.Translate = [bounds[1] + 2.0, 0.0, 0.0]
    moved.Transform.Scale = [0.25, 0.25, 0.25]
    moved.Transform.Rotate = [90.0, 0.0, 0.0]  # the tree grows along +y; wilting hangs along -z: stand it up
    placed[port] = moved
    solid(moved, color)
view.OrientationAxesVisibility = 0
if hasattr(view, "UseColorPaletteForBackground"):
    view.UseColorPaletteForBackground = 0
view.Background = [1.0, 1.0, 1.0]
view.CameraPosition = [-20.0, -30.0, 15.0]
view.CameraFocalPoint = [0.0, 0.0, 0.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
view.ResetCamera()
SetActiveSource(wilt)
Render(view)


check = {
    "sources": sorted(name for name, _ in GetSources().keys()),
    "pipeline": {name: describe(proxy) for name, proxy in (("leaf", leaf), ("loop", loop), ("venation", venation),
                                                           ("wilt", wilt), ("tree", tree))},
    "time": scene.AnimationTime,
    "wilt_times": list(wilt.TimestepValues),
}
with open(os.environ.get("PLANTMORPH_GUI_CHECK", "plantmorph_gui_check.json"), "w") as f:
    json.dump(check, f, indent=1)
