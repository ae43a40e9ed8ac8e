# SPDX-License-Identifier: GPL-3.0-or-later
"""The GUI test: the real ParaView GUI (under Xvfb) loads PlantMorph, flagship_pipeline.xml clicks the flagship
pipeline together through the PlantMorph menus and the Properties panel's Apply, the PlantMorphFlagship macro wires
the second inputs and frames the scene, and ParaView's test utility compares the render view with
testing/baselines/gui_flagship.png. Then the pipeline the macro found is checked: every proxy made from its menu,
connected as built, with data on every port, the wilting leaf at the end of its time steps.

    python3 run_gui_test.py --paraview paraview --plugin-dir build/lib/paraview-5.11/plugins/PlantMorph \
        --baseline testing/baselines/gui_flagship.png --work build/testing/gui-work

A missing baseline makes the test fail and ParaView writes the image it got into --work (same name): look at it,
copy it to the baseline and commit it if it is right. On failure ParaView writes the difference image there too."""
import argparse
import json
import os
import sys

import gui_playback

HERE = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser()
parser.add_argument("--paraview", required=True)
parser.add_argument("--plugin-dir", required=True, help="folder holding PlantMorph.so")
parser.add_argument("--baseline", required=True)
parser.add_argument("--work", required=True)
parser.add_argument("--threshold", default="15", help="ParaView's image-difference threshold")
arguments = parser.parse_args()

check_file = os.path.join(arguments.work, "gui_check.json")
returncode, log = gui_playback.play(
    arguments.paraview, arguments.plugin_dir, os.path.join(HERE, "flagship_pipeline.xml"), arguments.work,
    [os.path.join(HERE, "PlantMorphFlagship.py"), os.path.join(HERE, "PlantMorphPicked.py")],
    environment={"PLANTMORPH_GUI_CHECK": check_file},
    extra_arguments=["--test-baseline=" + arguments.baseline, "--test-threshold=" + arguments.threshold],
    fresh_files=[check_file, check_file + ".picked"])
print(log[-6000:])

check = gui_playback.Checks()
found = check.playback(returncode, log, check_file)
if found is not None:
    pipeline = found["pipeline"]
    picked = json.load(open(check_file + ".picked")) if os.path.exists(check_file + ".picked") else []
    check(picked == ["LeafCurlFilter1"], "Leaf Curl Filter made from the PlantMorph menu: %s" % picked)
    for name in ("LeafOutlineSource1", "AdaptiveLoopFilter1", "VenationFilter1", "TreeFromSketchSource1",
                 "WiltingSimulator1"):
        check(name in found["sources"], "%s in the pipeline browser" % name)
    check(pipeline["loop"]["inputs"] == ["Input=LeafOutlineSource1:0"], "Adaptive Loop on the leaf: %s" %
          pipeline["loop"]["inputs"])
    check(pipeline["venation"]["inputs"] == ["Input=AdaptiveLoopFilter1:0"], "Venation on the subdivided leaf: %s" %
          pipeline["venation"]["inputs"])
    check(pipeline["wilt"]["inputs"] == ["Input=VenationFilter1:1", "Veins=VenationFilter1:0"],
          "Wilting on the venation's blade and veins: %s" % pipeline["wilt"]["inputs"])
    check(pipeline["tree"]["inputs"] == ["Leaf=AdaptiveLoopFilter1:0"], "the tree's leaf is the subdivided leaf: %s"
          % pipeline["tree"]["inputs"])
    for name, description in pipeline.items():
        check(all(points > 0 for points, _ in description["ports"]), "%s (%s): data on every port %s" % (
            name, description["label"], description["ports"]))
    leaf_cells = pipeline["leaf"]["ports"][0][1]
    check(pipeline["loop"]["ports"][0][1] > leaf_cells, "the Loop filter subdivided the blade: %d -> %d triangles" % (
        leaf_cells, pipeline["loop"]["ports"][0][1]))
    check(len(found["wilt_times"]) > 1 and found["time"] == found["wilt_times"][-1],
          "the animation is at the wilting's last time step %s of %s" % (found["time"], found["wilt_times"]))
sys.exit(1 if check.failed else 0)
