# SPDX-License-Identifier: GPL-3.0-or-later
"""A scanned soybean leaf becomes a PlantMorph leaf: fit, traits, venation on the fitted leaf, distances coloured.

    xvfb-run -a pvbatch examples/compare_scanned_leaf.py [--plugin build/.../PlantMorph.so] [--output output]

1. Leaf Cloud Reader reads the scan (data/leaf-clouds/soybean_*_pot1_15.txt: x, y, z in mm, normals, colours).
2. LeafFitFilter, defaults, Scale 0.1 (mm -> cm): the fitted blade (port 0), its outline (1), the traits (2) and the
   scan with each point's distance to the fit (3). The traits are printed.
3. VenationFilter grows veins on the fitted blade (it carries LeafUV like a LeafOutlineSource blade).
4. Cloud Comparison Filter (Scale 0.1, symmetric) measures the scan against the fitted blade; its statistics are
   printed, and the scan coloured by signed distance is rendered with the blade, its outline and veins.
"""
import argparse
import glob
import os

from paraview.simple import *  # noqa: F401,F403 (the pvpython way)
from paraview import servermanager

HERE = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser()
parser.add_argument("--plugin", default=os.path.join(HERE, "..", "build", "lib", "paraview-5.11", "plugins",
                                                     "PlantMorph", "PlantMorph.so"))
parser.add_argument("--output", default=os.path.join(HERE, "..", "output"))
parser.add_argument("--scan", default=sorted(glob.glob(os.path.join(HERE, "..", "data", "leaf-clouds",
                                                                     "soybean_*_pot1_15.txt")))[0])
arguments = parser.parse_args()
os.makedirs(arguments.output, exist_ok=True)
LoadPlugin(os.path.abspath(arguments.plugin), remote=False, ns=globals())

scan = LeafCloudReader(FileName=os.path.abspath(arguments.scan))
fit = LeafFitFilter(Input=scan, Scale=0.1)  # the scan is in mm; the fitted leaf in cm
traits = servermanager.Fetch(fit, idx=2)
if traits.GetNumberOfRows() != 1:
    raise SystemExit("LeafFitFilter gave no leaf (see the error above)")
print("traits of the scanned leaf (cm, cm^2, degrees):")
for c in range(traits.GetNumberOfColumns()):
    print("  %-20s %.4f" % (traits.GetColumnName(c), traits.GetValue(0, c).ToDouble()))

veins = VenationFilter(Input=fit)
comparison = CloudComparisonFilter(Input=scan, Reference=fit, Scale=0.1, Symmetric=1)
statistics = servermanager.Fetch(comparison, idx=2)
print("scan against the fitted blade (cm):")
for name in ("Count", "Mean", "RMS", "Percentile95", "Hausdorff", "SymmetricHausdorff"):
    column = statistics.GetColumnByName(name)
    if column is not None:
        print("  %-20s %.4f" % (name, column.GetValue(0)))

view = CreateView("RenderView")
view.ViewSize = [900, 700]
view.OrientationAxesVisibility = 0
blade = Show(OutputPort(fit, 0), view)
blade.ColorArrayName = ["POINTS", ""]
blade.DiffuseColor = [0.55, 0.75, 0.45]
blade.Opacity = 0.5
outline = Show(OutputPort(fit, 1), view)
outline.ColorArrayName = ["POINTS", ""]
outline.DiffuseColor = outline.AmbientColor = [0.0, 0.0, 0.0]
outline.LineWidth = 3
vein_display = Show(OutputPort(veins, 0), view)
vein_display.ColorArrayName = ["POINTS", ""]
vein_display.DiffuseColor = vein_display.AmbientColor = [0.25, 0.35, 0.15]
vein_display.LineWidth = 2
points = Show(OutputPort(comparison, 0), view)
ColorBy(points, ("POINTS", "SignedDistance"))
points.PointSize = 3
lut = GetColorTransferFunction("SignedDistance")
lut.ApplyPreset("Cool to Warm")
lut.RescaleTransferFunction(-0.1, 0.1)
bar = GetScalarBar(lut, view)
bar.Title = "SignedDistance (cm)"
bar.ComponentTitle = ""
points.SetScalarBarVisibility(view, True)
view.CameraPosition = [1.0, -1.2, 1.6]
view.CameraFocalPoint = [0.0, 0.0, 0.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
view.ResetCamera()
SaveScreenshot(os.path.join(arguments.output, "compare_scanned_leaf.png"), view)
print("wrote", os.path.join(arguments.output, "compare_scanned_leaf.png"))
