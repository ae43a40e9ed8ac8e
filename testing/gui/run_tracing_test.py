# SPDX-License-Identifier: GPL-3.0-or-later
"""The tracing GUI test: docs/tracing-a-tree-photo.md clicked through in the real ParaView GUI (under Xvfb).

A drawing of a tree (three strokes: a trunk and two branches) is written as a PNG "photograph". ParaView opens it
(macro PlantMorphTracingPhoto: File > Open and a Transform to centimetres, the recipe's step 2) and looks at it from
+Z in 2-D mode (macro PlantMorphTracingView, a fixed parallel camera so that the clicks below land where computed).
Then, as a user does it, with events this script writes into the work folder (tracing_events.xml):
  - per stroke: Sources > Alphabetical > Poly Line, Apply; in the render view drag the new line's two end handles
    to the stroke's first two points and Alt+click each further point (the Poly Line widget appends it); Apply;
  - click the three Poly Lines in the pipeline browser in drawing order (Ctrl+click) and apply Filters >
    Alphabetical > Append Geometry;
  - Sources > PlantMorph > Tree From Sketch Source, Apply (a template tree), Edit > Change Input: the dialog's
    Strokes port (the first) gets the Append Geometry, OK; Mode = Strokes in the Properties panel; Apply.
Macro PlantMorphTracingCheck writes what was built; this script checks it: the traced points are the drawn ones (to
the click's pixel), the Append Geometry has the lines in drawing order, the tree's Strokes input is it, and the tree
covers the strokes (each stroke's last point is a branch's end in x and y, the trunk stays in the photo's plane, the
branches are lifted out of it).

    python3 run_tracing_test.py --paraview paraview --plugin-dir build/lib/paraview-5.11/plugins/PlantMorph \
        --work build/testing/gui-tracing"""
import argparse
import os
import struct
import sys
import zlib

import gui_playback

HERE = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser()
parser.add_argument("--paraview", required=True)
parser.add_argument("--plugin-dir", required=True, help="folder holding PlantMorph.so")
parser.add_argument("--work", required=True)
arguments = parser.parse_args()
os.makedirs(arguments.work, exist_ok=True)

# The drawn tree, in cm (0.05 cm per pixel of the photograph, the trunk's foot at pixel (160, 30)).
STROKES = [
    [(0.0, 0.0), (0.3, 4.0), (-0.2, 8.0), (0.2, 12.0), (0.0, 16.0)],
    [(0.2, 7.0), (2.0, 8.5), (4.0, 9.5), (6.5, 11.5)],
    [(-0.1, 6.0), (-2.0, 7.0), (-4.5, 8.0), (-6.0, 10.0)],
]
CM_PER_PIXEL, ORIGIN_PIXEL, PHOTO_SIZE = 0.05, (160, 30), (320, 400)
# The camera PlantMorphTracingView sets, and the render view's size in pixels under gui_playback's screen.
VIEW_CENTRE, VIEW_HALF_HEIGHT, VIEW_SIZE = (0.0, 8.0), 10.0, (844, 527)
PIXEL_CM = 2 * VIEW_HALF_HEIGHT / VIEW_SIZE[1]  # one screen pixel in cm


def write_photograph(path):
    """An RGB PNG: the strokes drawn 7 pixels wide in bark brown on a pale background."""
    width, height = PHOTO_SIZE
    rows = [bytearray(b"\xeb\xf0\xe1" * width) for _ in range(height)]
    for stroke in STROKES:
        pixels = [(ORIGIN_PIXEL[0] + x / CM_PER_PIXEL, ORIGIN_PIXEL[1] + y / CM_PER_PIXEL) for x, y in stroke]
        for (x0, y0), (x1, y1) in zip(pixels, pixels[1:]):
            steps = 2 * int(max(abs(x1 - x0), abs(y1 - y0))) + 1
            for step in range(steps + 1):
                x, y = x0 + (x1 - x0) * step / steps, y0 + (y1 - y0) * step / steps
                for dy in range(-3, 4):
                    for dx in range(-3, 4):
                        column, row = int(x) + dx, int(y) + dy
                        if 0 <= column < width and 0 <= row < height:
                            rows[height - 1 - row][3 * column:3 * column + 3] = b"\x6e\x4b\x28"

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(b"".join(b"\x00" + bytes(row) for row in rows), 9)) +
                chunk(b"IEND", b""))


VIEWPORT = ("pqClientMainWindow/centralwidget/MultiViewWidget/CoreWidget/qt_tabwidget_stackedwidget/"
            "MultiViewWidget1/Container/Frame.0/CentralWidgetFrame/Viewport")
BROWSER = "pqClientMainWindow/pipelineBrowserDock/pipelineBrowser"
PANEL = ("pqClientMainWindow/propertiesDock/propertiesPanel/scrollArea/qt_scrollarea_viewport/"
         "scrollAreaWidgetContents/PropertiesFrame/ProxyPanel")
LEFT, CTRL, ALT = 1, 67108864, 134217728  # Qt::LeftButton, Qt::ControlModifier, Qt::AltModifier


def write_events(path):
    events = []

    def event(widget, command, argument=""):
        events.append('  <pqevent object="%s" command="%s" arguments="%s" />' % (widget, command, argument))

    def menu(bar_menu, *path_items):
        event("pqClientMainWindow/menubar", "activate", bar_menu)
        parent = "pqClientMainWindow/menubar/" + bar_menu
        for item in path_items[:-1]:
            if item != "Alphabetical":  # the Alphabetical submenu has no action to activate: it is found by name
                event(parent, "activate", item)
            parent += "/" + item
        event(parent, "activate", path_items[-1])

    def apply():
        event("pqClientMainWindow/propertiesDock/propertiesPanel/Accept", "activate")

    def mouse(command, point, button, buttons, modifiers):
        # the viewport player takes the position as a fraction of the widget, from its top-left corner
        x = 0.5 + (point[0] - VIEW_CENTRE[0]) / (PIXEL_CM * VIEW_SIZE[0])
        y = 0.5 - (point[1] - VIEW_CENTRE[1]) / (2 * VIEW_HALF_HEIGHT)
        event(VIEWPORT, command, "(%.6f,%.6f,%d,%d,%d)" % (x, y, button, buttons, modifiers))

    def drag(start, end):
        mouse("mouseMove", start, 0, 0, 0)
        mouse("mousePress", start, LEFT, LEFT, 0)
        for t in (0.25, 0.5, 0.75, 1.0):
            mouse("mouseMove", (start[0] + t * (end[0] - start[0]), start[1] + t * (end[1] - start[1])), 0, LEFT, 0)
        mouse("mouseRelease", end, LEFT, 0, 0)

    def alt_click(point):
        mouse("mouseMove", point, 0, 0, 0)
        mouse("mousePress", point, LEFT, LEFT, ALT)
        mouse("mouseRelease", point, LEFT, 0, ALT)

    def browser_click(row, modifiers):
        # button, buttons, modifiers, x and y inside the item, item path (the server's row 0, then the source's row)
        for command, buttons in (("mousePress", LEFT), ("mouseRelease", 0)):
            event(BROWSER, command, "%d,%d,%d,30,8,/0:0/%d:0" % (LEFT, buttons, modifiers, row))

    menu("menu_Macros", "PlantMorphTracingPhoto")
    menu("menu_Macros", "PlantMorphTracingView")
    for stroke in STROKES:
        menu("menuSources", "Alphabetical", "PolyLineSource")
        apply()
        menu("menu_Macros", "PlantMorphTracingView")
        default_ends = [(0.0, 0.0), (1.0, 0.0)]  # a new Poly Line runs from (0, 0, 0) to (1, 0, 0)
        for handle, target in zip(default_ends, stroke[:2]):
            if handle != target:
                drag(handle, target)
        for point in stroke[2:]:
            alt_click(point)  # the last handle moved is the end one: the point is appended
        apply()
    # The photograph's reader is the browser's row 0 (its Transform is under it), the Poly Lines rows 1, 2, 3.
    for row in range(1, len(STROKES) + 1):
        browser_click(row, 0 if row == 1 else CTRL)
    menu("menuFilters", "Alphabetical", "AppendPolyData")
    apply()
    menu("menuSources", "PlantMorph", "TreeFromSketchSource")
    apply()
    menu("menu_Edit", "actionChangeInput")
    dialog = "pqClientMainWindow/ChangeInputDialog"
    # Strokes is the dialog's first (selected) port; Append Geometry sits under the first Poly Line (row 1).
    for command, buttons in (("mousePress", LEFT), ("mouseRelease", 0)):
        event(dialog + "/pipelineView", command, "%d,%d,0,30,8,/0:0/1:0/0:0" % (LEFT, buttons))
    event(dialog + "/buttonBox/1QPushButton0", "activate")
    event(PANEL + "/Mode/ComboBox", "activated", "Strokes")
    apply()
    menu("menu_Macros", "PlantMorphTracingCheck")
    with open(path, "w") as f:
        f.write('<?xml version="1.0" ?>\n<pqevents>\n' + "\n".join(events) + "\n</pqevents>\n")


photo = os.path.join(arguments.work, "tree_photo.png")
events_file = os.path.join(arguments.work, "tracing_events.xml")
check_file = os.path.join(arguments.work, "tracing_check.json")
write_photograph(photo)
write_events(events_file)
returncode, log = gui_playback.play(
    arguments.paraview, arguments.plugin_dir, events_file, arguments.work,
    [os.path.join(HERE, name + ".py") for name in ("PlantMorphTracingPhoto", "PlantMorphTracingView",
                                                    "PlantMorphTracingCheck")],
    environment={"PLANTMORPH_GUI_CHECK": check_file, "PLANTMORPH_TRACING_PHOTO": photo,
                 "PLANTMORPH_TRACING_VIEW": "%g,%g,%g" % (VIEW_CENTRE + (VIEW_HALF_HEIGHT,))},
    fresh_files=[check_file])
print(log[-4000:])

check = gui_playback.Checks()
found = check.playback(returncode, log, check_file)
if found is not None:
    sources = found["sources"]
    check(tuple(found["view_size"]) == VIEW_SIZE, "the render view is %s pixels, as the clicks assume (%s)" % (
        found["view_size"], VIEW_SIZE))
    lines = ["PolyLineSource%d" % (k + 1) for k in range(len(STROKES))]
    for name, stroke in zip(lines, STROKES):
        points = sources.get(name, {}).get("points", [])
        traced = [tuple(points[i:i + 3]) for i in range(0, len(points), 3)]
        error = max((max(abs(p[0] - q[0]), abs(p[1] - q[1]), abs(p[2])) for p, q in zip(traced, stroke)),
                    default=float("inf"))
        check(len(traced) == len(stroke) and error <= 1.5 * PIXEL_CM,
              "%s traced with the widget: %d points, at most %.4f cm from the drawing (a screen pixel is %.4f cm)"
              % (name, len(traced), error, PIXEL_CM))
    append = sources.get("AppendGeometry1", {})
    check(append.get("inputs") == ["Input=%s:0" % name for name in lines],
          "Append Geometry has the strokes in drawing order: %s" % append.get("inputs"))
    tree = sources.get("TreeFromSketchSource1", {})
    check(tree.get("inputs") == ["Strokes=AppendGeometry1:0"], "the tree's Strokes input: %s" % tree.get("inputs"))
    check(tree.get("mode") == "Strokes", "the tree's Mode: %s" % tree.get("mode"))
    check(len(tree.get("ports", [])) == 3 and all(p[0] > 0 and p[1] > 0 for p in tree["ports"]),
          "branches, skeleton and leaves are not empty: %s" % tree.get("ports"))
    skeleton = found.get("skeleton", [])
    for k, name in enumerate(lines):
        points = sources.get(name, {}).get("points", [0.0, 0.0, 0.0])
        last = points[-3:]
        ends = [b for b in skeleton if abs(b["ends"][1][0] - last[0]) < 1e-6 and abs(b["ends"][1][1] - last[1]) < 1e-6]
        check(len(ends) == 1, "stroke %d's last point (%.3f, %.3f) is one branch's end in x and y: %s" % (
            k, last[0], last[1], [b["id"] for b in ends]))
        if k == 0 and ends:
            check(ends[0]["parent"] == -1 and ends[0]["max_abs_z"] < 1e-9,
                  "the first stroke is the trunk, in the photograph's plane (|z| <= %.2g)" % ends[0]["max_abs_z"])
        elif ends:
            check(ends[0]["parent"] != -1 and ends[0]["max_abs_z"] > 0.1,
                  "stroke %d is a branch lifted out of the photograph (|z| up to %.2f cm)" % (k, ends[0]["max_abs_z"]))
sys.exit(1 if check.failed else 0)
