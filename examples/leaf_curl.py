# SPDX-License-Identifier: GPL-3.0-or-later
"""Paper 003, Fig. 7: curling a leaf. An elliptic B-spline leaf (LeafOutlineSource, Model "B-spline") flat and curled
by LeafCurlFilter: two longitudinal curls (the halves rolling about the midvein) and a transverse one (apex and base
bending about the mid-line), plus both together. A checkerboard texture mapped through TCoords, computed on the flat
blade, follows the curl as in the paper.

    xvfb-run -a pvbatch examples/leaf_curl.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import caption, save_vtp, show_solid, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403


def checkerboard(path, squares=8, size=256):
    """A green checkerboard PNG for the leaf's texture (vein-coloured and blade-coloured squares)."""
    import numpy
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOImage import vtkPNGWriter
    j, i = numpy.mgrid[0:size, 0:size]
    dark = ((i * squares // size) + (j * squares // size)) % 2 == 0
    rgb = numpy.where(dark[..., None], [70, 130, 40], [170, 215, 110]).astype(numpy.uint8).reshape(-1, 3)
    image = vtkImageData()
    image.SetDimensions(size, size, 1)
    image.GetPointData().SetScalars(numpy_to_vtk(rgb, deep=True))
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()
    return path


texture = CreateTexture(checkerboard(os.path.join(arguments.output, "leaf_curl_checkerboard.png")))
CURLS = [
    ("flat", dict(LongitudinalAngle=0.0)),
    ("longitudinal 90", dict(LongitudinalAngle=90.0)),
    ("longitudinal 230", dict(LongitudinalAngle=230.0)),
    ("transverse 120", dict(LongitudinalAngle=0.0, TransverseAngle=120.0)),
    ("both 70, 60", dict(LongitudinalAngle=70.0, TransverseAngle=60.0, TransverseCenter=0.5)),
]
leaf = LeafOutlineSource(registrationName="EllipticLeaf", Model="B-spline", BSplinePreset="Elliptic", Resolution=80,
                         MeshQuality="Quality")
view = white_view(1800, 650)
spacing = 8.0
for column, (name, properties) in enumerate(CURLS):
    curl = LeafCurlFilter(registrationName="Curl_" + name.replace(" ", "_").replace(",", ""), Input=leaf, **properties)
    save_vtp(curl, os.path.join(arguments.output, "leaf_curl_%s.vtp" % name.replace(" ", "_").replace(",", "")))
    placed = Transform(Input=curl)
    placed.Transform.Translate = [column * spacing, 0.0, 0.0]
    display = show_solid(placed, view, [1.0, 1.0, 1.0])
    display.Texture = texture
    display.Specular = 0.2
    caption(view, name, [column * spacing - 2.2, -2.2, 0.0], 0.55)

# An oblique view from the front, above the leaves, so the rolls show; then closer than ResetCamera's framing.
view.CameraPosition = [2.0 * spacing, -26.0, 20.0]
view.CameraFocalPoint = [2.0 * spacing, 3.5, 1.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
view.CameraParallelProjection = 0
ResetCamera(view)
SetActiveView(view)
GetActiveCamera().Dolly(1.9)
Render(view)
png = os.path.join(arguments.output, "leaf_curl.png")
SaveScreenshot(png, view, ImageResolution=list(view.ViewSize))  # not save_png: it resets the camera
print("wrote", png)
