# SPDX-License-Identifier: GPL-3.0-or-later
"""The comparison loop of measured and simulated plants: fit a leaf to a measured scan, scan the fitted leaf the way a close-range scanner
scans a leaf, and compare the simulated cloud with the measured one.

    pvbatch examples/scan_fitted_leaf.py [--plugin build/.../PlantMorph.so] [--scan data/leaf-clouds/soybean_..txt]
                                         [--output output]

1. Leaf Cloud Reader reads a shipped soybean scan (millimetres); LeafFitFilter fits a leaf to it with its defaults
   (Scale 0.1: the fitted Blade in centimetres).
2. The fit residual: CloudComparisonFilter, scan against the fitted Blade (Scale 0.1: mm to cm).
3. VirtualScanner scans the fitted Blade with a line (profile) scanner passing over the leaf along its length, looking
   down the leaf's normal from two leaf lengths away, its fan across the leaf: the angular step and the line spacing
   give the measured scan's mean point spacing (the fitted blade's area seen along the normal over the scan's point
   count), the range noise is the residual's RMS (so the simulated
   cloud scatters about the model as the measured one does about it).
4. Cloud to cloud: CloudComparisonFilter of the measured scan against the simulated cloud (nearest neighbour), and
   of the simulated cloud against the fitted Blade, printed beside the fit residual: a simulated scan that samples
   like the real one gives cloud-to-cloud distances of the order of the residual and the spacing.

Writes into --output: scan_fitted_leaf_simulated.vtp (the simulated cloud, labelled), scan_fitted_leaf_blade.vtp (the
fitted leaf) and scan_fitted_leaf.json (the numbers printed).
"""
import argparse
import glob
import json
import math
import os

import numpy

from paraview.simple import *  # noqa: F401,F403 (the pvpython way)
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser()
parser.add_argument("--plugin", default=os.path.join(HERE, "..", "build", "lib", "paraview-5.11", "plugins",
                                                     "PlantMorph", "PlantMorph.so"))
parser.add_argument("--scan", default=sorted(glob.glob(os.path.join(HERE, "..", "data", "leaf-clouds",
                                                                     "soybean_*_pot1_1.txt")))[0])
parser.add_argument("--output", default=os.path.join(HERE, "..", "output"))
arguments = parser.parse_args()
os.makedirs(arguments.output, exist_ok=True)
LoadPlugin(os.path.abspath(arguments.plugin), remote=False, ns=globals())

scan = LeafCloudReader(FileName=os.path.abspath(arguments.scan))
xyz = vtk_to_numpy(servermanager.Fetch(scan).GetPoints().GetData()) * 0.1  # mm -> cm

# 1. The fit: LeafFitFilter's defaults, output in cm.
fit = LeafFitFilter(Input=scan, Scale=0.1)
blade = servermanager.Fetch(fit, idx=0)
if blade.GetNumberOfPolys() == 0:
    raise SystemExit("LeafFitFilter gave no leaf (see the error above)")


def statistics(comparison):
    table = servermanager.Fetch(comparison, idx=2)
    return {name: table.GetValueByName(0, name).ToDouble() for name in ("Count", "Mean", "RMS", "Percentile95")}


# 2. The fit residual.
residual = statistics(CloudComparisonFilter(Input=scan, Reference=OutputPort(fit, 0), Scale=0.1))

# 3. The simulated scan. The leaf's frame from the scan (principal axes: length, width, normal towards +z, where the
# scanner looked from), the scan's spacing from the fitted blade's area seen along the normal and its point count.
centre = xyz.mean(axis=0)
_, _, axes = numpy.linalg.svd(xyz - centre, full_matrices=False)
e_length, e_width, normal = axes[0], axes[1], numpy.cross(axes[0], axes[1])
if normal[2] < 0:
    normal, e_width = -normal, -e_width
s = (xyz - centre) @ e_length
w = (xyz - centre) @ e_width
length, width = s.max() - s.min(), w.max() - w.min()
points = vtk_to_numpy(blade.GetPoints().GetData())
polys = vtk_to_numpy(blade.GetPolys().GetConnectivityArray()).reshape(-1, 3)
cross = numpy.cross(points[polys[:, 1]] - points[polys[:, 0]], points[polys[:, 2]] - points[polys[:, 0]])
area = 0.5 * numpy.linalg.norm(cross, axis=1).sum()
# The scanner looks down the normal: its points are spread over the blade's area projected on the leaf's plane.
projected = 0.5 * numpy.abs(cross @ normal).sum()
spacing = math.sqrt(projected / len(xyz))
height = 2.0 * length
# The path: over the leaf from 10 % before its base to 10 % beyond its tip, along its length, `height` above it.
start = centre + (s.min() - 0.1 * length) * e_length + height * normal
end = centre + (s.max() + 0.1 * length) * e_length + height * normal
fan = 2.0 * math.degrees(math.atan(0.6 * width / height))
scanner = VirtualScanner(Input=OutputPort(fit, 0), ScannerType="Line", LineMotion="Path",
                         Positions=list(start) + list(end), LookAt=list(0.5 * (start + end) - height * normal),
                         Up=list(e_width),
                         VerticalFieldOfView=fan, AngularStep=math.degrees(spacing / height), LineSpacing=spacing,
                         RangeNoise=residual["RMS"], Seed=1)
simulated = servermanager.Fetch(scanner)

# 4. Cloud to cloud, and the simulated cloud against the model.
cloud_to_cloud = statistics(CloudComparisonFilter(Input=scan, Reference=OutputPort(scanner, 0), Scale=0.1))
simulated_to_model = statistics(CloudComparisonFilter(Input=OutputPort(scanner, 0), Reference=OutputPort(fit, 0)))
print("leaf %.2f x %.2f cm, fitted blade area %.2f cm^2; scan %d points, spacing %.3f cm; simulated %d points "
      "(line scanner %.1f cm above, fan %.1f degrees, step %.4f degrees, lines %.3f cm apart, range noise %.4f cm)"
      % (length, width, area, len(xyz), spacing, simulated.GetNumberOfPoints(), height, fan,
         math.degrees(spacing / height), spacing, residual["RMS"]))
print("%-38s %8s %8s %8s %8s" % ("cm", "count", "mean", "RMS", "p95"))
rows = (("measured scan to fitted leaf (residual)", residual),
        ("simulated scan to fitted leaf", simulated_to_model),
        ("measured scan to simulated scan", cloud_to_cloud))
for name, row in rows:
    print("%-38s %8d %8.4f %8.4f %8.4f" % (name, row["Count"], row["Mean"], row["RMS"], row["Percentile95"]))

SaveData(os.path.join(arguments.output, "scan_fitted_leaf_simulated.vtp"), proxy=OutputPort(scanner, 0))
SaveData(os.path.join(arguments.output, "scan_fitted_leaf_blade.vtp"), proxy=OutputPort(fit, 0))
with open(os.path.join(arguments.output, "scan_fitted_leaf.json"), "w") as out:
    json.dump({"scan_points": len(xyz), "simulated_points": simulated.GetNumberOfPoints(), "spacing_cm": spacing,
               "length_cm": length, "blade_area_cm2": area, "projected_area_cm2": projected, "residual": residual,
               "simulated_to_model": simulated_to_model, "cloud_to_cloud": cloud_to_cloud}, out, indent=1)
print("wrote %s" % os.path.join(arguments.output, "scan_fitted_leaf.json"))
