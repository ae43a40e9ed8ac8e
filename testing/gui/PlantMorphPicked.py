# SPDX-License-Identifier: GPL-3.0-or-later
"""ParaView macro for the GUI test: records the filters just made from the PlantMorph menu that are not part of the
flagship pipeline (Leaf Curl), removes them before they are applied, and makes the tree the active source again so
the next menu item is enabled (an unapplied active source disables the Filters menu)."""
import json
import os

from paraview.simple import Delete, FindSource, GetSources, SetActiveSource

record = os.environ.get("PLANTMORPH_GUI_CHECK", "plantmorph_gui_check.json") + ".picked"
picked = json.load(open(record)) if os.path.exists(record) else []
for (name, _), proxy in list(GetSources().items()):
    if name.split("1")[0] in ("LeafCurlFilter", "CloudComparisonFilter", "TrajectoryComparisonFilter"):
        picked.append(name)
        Delete(proxy)
with open(record, "w") as f:
    json.dump(picked, f)
SetActiveSource(FindSource("TreeFromSketchSource1"))
