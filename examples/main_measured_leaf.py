# SPDX-License-Identifier: GPL-3.0-or-later
"""A measured leaf becomes a PlantMorph leaf: a shipped soybean leaflet scan fitted, measured, veined and compared.

1. Leaf Cloud Reader reads data/leaf-clouds/soybean_11_20190508T043118_pot1_36.txt (a close-range scan of one
   soybean leaflet: x, y, z in mm, normals, colours).
2. LeafFitFilter (Scale 0.1: mm -> cm) fits a blade to it; its traits are printed (Length, Width, Area, FitRMS).
3. VenationFilter grows pinnate veins (a midvein, brochidodromous secondaries looping below the margin, as on a
   soybean leaflet) on the fitted blade, which carries LeafUV like a LeafOutlineSource blade.
4. CloudComparisonFilter (Scale 0.1, symmetric) measures every scan point's signed distance to the fitted blade.

measured_leaf.png, seen along the leaf's normal, apex up: on the left the fitted leaf with its veins, on the right
the scan's points coloured by their signed distance to the fit (cm, positive on the scanner's side) inside the
fitted outline; the stray points outside it are the ones the fit left out as outliers (the comparison's RMS
counts them, the fit's FitRMS does not). Writes measured_leaf_blade.vtp, measured_leaf_outline.vtp, measured_leaf_veins.vtp,
measured_leaf_distances.vtp (the scan with Distance and SignedDistance) and measured_leaf_traits.csv.

    xvfb-run -a pvbatch examples/main_measured_leaf.py --plugin build/.../PlantMorph.so --output output/
"""
import os

import numpy

from plantmorph_example import ROOT, save_framed_png, save_state, save_vtp, show_solid, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

SCAN = os.path.join(ROOT, "data", "leaf-clouds", "soybean_11_20190508T043118_pot1_36.txt")
BLADE = [0.62, 0.80, 0.42]
VEIN = [0.16, 0.34, 0.08]
OUTLINE = [0.15, 0.15, 0.15]
TRAITS = [("Length", "cm"), ("Width", "cm"), ("Area", "cm^2"), ("Perimeter", "cm"), ("FitRMS", "cm")]

scan = LeafCloudReader(registrationName="SoybeanScan", FileName=SCAN)
fit = LeafFitFilter(registrationName="FittedLeaf", Input=scan, Scale=0.1)  # the scan is in mm; the fitted leaf in cm
traits = servermanager.Fetch(fit, idx=2)
if traits.GetNumberOfRows() != 1:
    raise SystemExit("LeafFitFilter gave no leaf (see the error above)")
print("traits of the fitted soybean leaflet (%s):" % os.path.basename(SCAN))
for name, unit in TRAITS:
    print("  %-10s %9.3f %s" % (name, traits.GetValueByName(0, name).ToDouble(), unit))
with open(os.path.join(arguments.output, "measured_leaf_traits.csv"), "w") as out:
    out.write(",".join("%s_%s" % (name, unit.replace("^", "")) for name, unit in TRAITS) + "\n")
    out.write(",".join("%.6g" % traits.GetValueByName(0, name).ToDouble() for name, _ in TRAITS) + "\n")

veins = VenationFilter(registrationName="Veins", Input=OutputPort(fit, 0), Preset="Custom", Pattern="Brochidodromous",
                       DivergenceAngle=40.0, DivergenceAngleApex=30.0, SecondarySpacing=0.12, Seed=1)
comparison = CloudComparisonFilter(registrationName="ScanToFit", Input=scan, Reference=OutputPort(fit, 0), Scale=0.1,
                                   Symmetric=1)
statistics = servermanager.Fetch(comparison, idx=2)
print("scan against the fitted blade (cm):")
for name in ("Count", "Mean", "RMS", "Percentile95", "Hausdorff"):
    print("  %-12s %9.4f" % (name, statistics.GetValueByName(0, name).ToDouble()))
for port, name in ((0, "blade"), (1, "outline")):
    save_vtp(fit, os.path.join(arguments.output, "measured_leaf_%s.vtp" % name), port=port)
save_vtp(veins, os.path.join(arguments.output, "measured_leaf_veins.vtp"))
save_vtp(comparison, os.path.join(arguments.output, "measured_leaf_distances.vtp"))

# The leaf's frame from the fitted blade: its normal (towards the scanner, +z) and its midvein from base (LeafUV v = 0)
# to apex (v = 1), so the picture shows the leaf apex up, as a botanical plate does.
blade = servermanager.Fetch(fit, idx=0)
points = vtk_to_numpy(blade.GetPoints().GetData())
v = vtk_to_numpy(blade.GetPointData().GetArray("LeafUV"))[:, 1]
centre = points.mean(axis=0)
normal = numpy.linalg.svd(points - centre, full_matrices=False)[2][2]
if normal[2] < 0:
    normal = -normal
up = points[v.argmax()] - points[v.argmin()]
up -= (up @ normal) * normal
up /= numpy.linalg.norm(up)
right = numpy.cross(up, normal)  # the screen's right, seen from the normal's side
length = numpy.ptp((points - centre) @ up)
width = numpy.ptp((points - centre) @ right)
shift = 1.25 * width * right  # the scan panel beside the leaf


def moved(proxy, port, name, offset):
    placed = Transform(registrationName=name, Input=OutputPort(proxy, port))
    placed.Transform.Translate = list(offset)
    return placed


view = white_view(800, 540)
show_solid(OutputPort(fit, 0), view, BLADE, Ambient=0.3, Diffuse=0.7)
show_solid(moved(veins, 0, "VeinsAbove", 0.02 * normal), view, VEIN, LineWidth=2.0)
show_solid(moved(fit, 1, "OutlineAbove", 0.02 * normal), view, OUTLINE, LineWidth=2.5)
show_solid(moved(fit, 1, "OutlineBesideScan", shift), view, OUTLINE, LineWidth=1.5)
distances = Show(moved(comparison, 0, "ScanBeside", shift), view)
distances.SetRepresentationType("Points")
distances.PointSize = 3.0
distances.RenderPointsAsSpheres = 1
ColorBy(distances, ("POINTS", "SignedDistance"))
lut = GetColorTransferFunction("SignedDistance")
lut.ApplyPreset("Cool to Warm", True)
lut.AutomaticRescaleRangeMode = "Never"
lut.RescaleTransferFunction(-0.1, 0.1)  # cm: about three fit RMS either side
bar = GetScalarBar(lut, view)
bar.Title = "scan to fitted leaf (cm)"
bar.ComponentTitle = ""
bar.TitleColor = bar.LabelColor = [0.1, 0.1, 0.1]
bar.TitleFontSize = 14
bar.LabelFontSize = 13
bar.RangeLabelFormat = "%.2f"
bar.WindowLocation = "Any Location"
bar.Position = [0.88, 0.15]
bar.ScalarBarLength = 0.6
distances.SetScalarBarVisibility(view, True)
value = {name: traits.GetValueByName(0, name).ToDouble() for name, _ in TRAITS}
label = Text(registrationName="Traits", Text="Soybean leaflet scan, fitted: length %.2f cm, width %.2f cm, area %.1f cm2,"
             " fit RMS %.2f mm" % (value["Length"], value["Width"], value["Area"], 10.0 * value["FitRMS"]))
text = Show(label, view)
text.WindowLocation = "Upper Center"
text.FontSize = 15
text.Color = [0.1, 0.1, 0.1]
# Framed on the two panels' bounds in the picture's plane, with room for the title and the colour legend.
low = numpy.array([((points - centre) @ right).min(), ((points - centre) @ up).min()])
high = numpy.array([((points - centre) @ right).max() + 1.25 * width, ((points - centre) @ up).max()])
middle = centre + (0.5 * (low[0] + high[0]) + 0.16 * width) * right + (0.5 * (low[1] + high[1]) + 0.05 * length) * up
save_framed_png(view, os.path.join(arguments.output, "measured_leaf.png"), list(middle),
                list(middle + 10.0 * length * normal), list(up), 0.66 * (high[1] - low[1]))
save_state(arguments, "measured_leaf")
