# SPDX-License-Identifier: GPL-3.0-or-later
"""What every PlantMorph example script shares: its arguments, loading the plugin, a white render view, writing .vtp
files that this ParaView can read back, and saving the pipeline as a ParaView state file (.pvsm) next to them."""
import argparse
import os

from paraview.simple import (CreateRenderView, LoadPlugin, Render, ResetCamera, SaveData, SaveScreenshot)


def start(description):
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--plugin", required=True, help="path to PlantMorph.so")
    parser.add_argument("--output", required=True, help="folder for the .vtp files, PNG renders and the state file")
    parser.add_argument("--no-render", action="store_true",
                        help="build the pipeline, write the .vtp files and the state file, but render nothing (no X "
                             "server needed: the state-file tests use this)")
    arguments = parser.parse_args()
    os.makedirs(arguments.output, exist_ok=True)
    global RENDER
    RENDER = not arguments.no_render
    import __main__
    LoadPlugin(arguments.plugin, remote=False, ns=vars(__main__))
    return arguments


RENDER = True


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def save_state(arguments, name):
    """Saves the whole pipeline, views included, as <output>/<name>.pvsm: File > Load State in ParaView (after loading
    the plugin) rebuilds the figure. examples/states/ holds these files as shipped (scripts/update_example_states.sh
    writes them; the ctest example_state.* tests check they still give the scripts' data).

    A data file the pipeline reads from the repository (data/...) is named relative to the repository's folder, so
    the state is the same wherever the repository is: load it with the repository's folder as the current one, or
    say where it is (pvpython: LoadState(path, data_directory=REPOSITORY); the GUI's Load State dialog: "Search
    files under specified directory")."""
    from paraview.simple import SaveState
    path = os.path.join(arguments.output, name + ".pvsm")
    SaveState(path)
    with open(path) as f:
        text = f.read()
    relative = text.replace('value="%s/' % ROOT, 'value="')
    if relative != text:
        with open(path, "w") as f:
            f.write(relative)
    print("wrote", path)


def white_view(width, height):
    view = CreateRenderView()
    view.ViewSize = [width, height]
    view.OrientationAxesVisibility = 0
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    view.Background = [1.0, 1.0, 1.0]
    return view


def show_solid(proxy, view, color, **properties):
    """Shows a proxy in one solid colour (no array colouring), with extra representation properties."""
    from paraview.simple import Show
    display = Show(proxy, view)
    display.ColorArrayName = ["POINTS", ""]
    display.DiffuseColor = color
    display.AmbientColor = color
    for name, value in properties.items():
        setattr(display, name, value)
    return display


def caption(view, text, position, scale):
    """Dark 3-D text in the XY plane at `position` (world coordinates), so a caption stays with its leaf."""
    from paraview.simple import Transform, a3DText
    placed = Transform(Input=a3DText(Text=text))
    placed.Transform.Translate = position
    placed.Transform.Scale = [scale, scale, 1.0]
    return show_solid(placed, view, [0.1, 0.1, 0.1])


def save_vtp(proxy, path, port=0):
    """Inline binary: Debian's ParaView 5.11 cannot read back appended-mode XML files (see README)."""
    from paraview.simple import OutputPort
    SaveData(path, proxy=OutputPort(proxy, port), DataMode="Binary")
    print("wrote", path)


def save_png(view, path, top_down=True):
    if not RENDER:
        return
    if top_down:
        view.CameraPosition = [0, 0, 1]
        view.CameraFocalPoint = [0, 0, 0]
        view.CameraViewUp = [0, 1, 0]
        view.CameraParallelProjection = 1
    ResetCamera(view)
    Render(view)
    SaveScreenshot(path, view, ImageResolution=list(view.ViewSize), CompressionLevel="9")
    print("wrote", path)


def save_framed_png(view, path, focal, position, view_up, half_height):
    """A parallel projection of the given half-height, looking from `position` at `focal` (ResetCamera would fit the
    bounding sphere and leave wide margins). Nothing under --no-render."""
    from paraview.simple import Render, SaveScreenshot
    if not RENDER:
        return
    Render(view)  # the first render resets the camera: set ours after it
    view.CameraFocalPoint = focal
    view.CameraPosition = position
    view.CameraViewUp = view_up
    view.CameraParallelProjection = 1
    view.CameraParallelScale = half_height
    Render(view)
    SaveScreenshot(path, view, ImageResolution=list(view.ViewSize), CompressionLevel="9")
    print("wrote", path)
