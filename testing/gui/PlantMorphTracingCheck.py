# SPDX-License-Identifier: GPL-3.0-or-later
"""ParaView macro for the tracing GUI test: writes what the clicks built to $PLANTMORPH_GUI_CHECK (JSON): every
source's label, inputs (in order), Poly Line points and output sizes, the tree's Mode, the render view's size, and
per skeleton branch its BranchId, ParentId and end points. Then it shows the tree in front of the photograph and
saves the view beside the JSON file (tracing_view.png), the photograph half transparent: the branches lifted behind
its plane show through it."""
import json
import os

from paraview import servermanager
from paraview.simple import (FindSource, GetActiveViewOrCreate, GetDisplayProperties, GetSources, Hide, OutputPort,
                             Render, SaveScreenshot, SetActiveSource, Show)
from pipeline_description import describe

found = {"sources": {}}
for (name, _), proxy in GetSources().items():
    description = describe(proxy)
    if description["label"] == "Poly Line Source":
        description["points"] = list(proxy.Points)
    if proxy.GetProperty("Mode") is not None:
        description["mode"] = proxy.GetProperty("Mode").GetData()
    found["sources"][name] = description

view = GetActiveViewOrCreate("RenderView")
found["view_size"] = list(view.ViewSize)
tree = FindSource("TreeFromSketchSource1")
if tree is not None:
    skeleton = servermanager.Fetch(tree, idx=1)  # port 1, the skeleton
    ids = skeleton.GetCellData().GetArray("BranchId")
    parents = skeleton.GetCellData().GetArray("ParentId")
    branches = []
    for cell in range(skeleton.GetNumberOfCells()):
        point_ids = skeleton.GetCell(cell).GetPointIds()
        ends = [list(skeleton.GetPoint(point_ids.GetId(i))) for i in (0, point_ids.GetNumberOfIds() - 1)]
        branches.append({"id": int(ids.GetValue(cell)), "parent": int(parents.GetValue(cell)), "ends": ends,
                         "max_abs_z": max(abs(skeleton.GetPoint(point_ids.GetId(i))[2])
                                          for i in range(point_ids.GetNumberOfIds()))})
    found["skeleton"] = branches
    for port, color in ((0, [0.45, 0.32, 0.2]), (2, [0.35, 0.62, 0.22])):
        display = Show(OutputPort(tree, port), view)
        display.ColorArrayName = ["POINTS", ""]
        display.DiffuseColor = color
        display.AmbientColor = color
    Hide(OutputPort(tree, 1), view)
    GetDisplayProperties(FindSource("PhotoInCm"), view).Opacity = 0.5
    SetActiveSource(None)
    Render(view)
    SaveScreenshot(os.path.join(os.path.dirname(os.environ["PLANTMORPH_GUI_CHECK"]), "tracing_view.png"), view,
                   ImageResolution=[800, 500])
with open(os.environ["PLANTMORPH_GUI_CHECK"], "w") as f:
    json.dump(found, f, indent=1)
