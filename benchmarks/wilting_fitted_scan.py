# SPDX-License-Identifier: GPL-3.0-or-later
"""The Cucumber wilting preset on fitted scans of the cucumber blade, as users chain them.

    pvbatch benchmarks/wilting_fitted_scan.py [--plugin build/.../PlantMorph.so] [--sizes 5,20.1,40]
                                              [--widths 1.0,0.8] [--resolutions 14,18]

LeafOutlineSource (B-spline, Cucumber, BladeLength L, BladeWidth w * 22.1 / 20.1 * L, Resolution 30) ->
VirtualScanner (depth camera 200 x 200 pixels, 45 degrees, 2 L above the blade's middle looking down, Seed 1) ->
LeafFitFilter (InputUnit cm, its defaults) -> WiltingSimulator (Preset Cucumber, Resolution R, its 10 s), and the
same preset on the source's blade. Printed per case: the run's end (10 s, or the blow-up's time and message), the
tip's lowest height and its largest rise after its lowest point so far, over the blade length L, and the wall time.
"""
import argparse
import os
import time

import numpy

from paraview.simple import *  # noqa: F401,F403 (the pvpython way)
from vtkmodules.util.numpy_support import vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))
parser = argparse.ArgumentParser()
parser.add_argument("--plugin", default=os.path.join(HERE, "..", "build", "lib", "paraview-5.11", "plugins",
                                                      "PlantMorph", "PlantMorph.so"))
parser.add_argument("--sizes", default="5,20.1,40")
parser.add_argument("--widths", default="1.0,0.8")
parser.add_argument("--resolutions", default="14,18")
arguments = parser.parse_args()
LoadPlugin(os.path.abspath(arguments.plugin), remote=False, ns=globals())


def run(blade, resolution, length):
    wilting = WiltingSimulator(Input=blade, Preset="Cucumber", Resolution=resolution)
    start = time.time()
    wilting.UpdatePipeline(0.0)
    wall = time.time() - start
    table = wilting.GetClientSideObject().GetOutputDataObject(2)
    t = vtk_to_numpy(table.GetColumn(0))
    z = vtk_to_numpy(table.GetColumnByName("TipZ"))
    lowest = numpy.minimum.accumulate(z)
    Delete(wilting)
    return t[-1], (z.min() - z[0]) / length, (z - lowest).max() / length, wall


print("| maker | L (cm) | width | R | ran to (s) | lowest / L | rises back / L | wall s |")
print("|---|---|---|---|---|---|---|---|")
for length in [float(s) for s in arguments.sizes.split(",")]:
    for width in [float(w) for w in arguments.widths.split(",")]:
        leaf = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", BladeLength=length,
                                 BladeWidth=width * 22.1 / 20.1 * length, Resolution=30)
        scan = VirtualScanner(Input=leaf, ScannerType="Depth camera", Positions=[0, 0.5 * length, 2.0 * length],
                              LookAt=[0, 0.5 * length, 0], Up=[0, 1, 0], Resolution=[200, 200],
                              HorizontalFieldOfView=45, VerticalFieldOfView=45, Seed=1)
        fit = LeafFitFilter(Input=scan, InputUnit="cm")
        for maker, blade in (("source", leaf), ("fitted scan", fit)):
            for resolution in [int(r) for r in arguments.resolutions.split(",")]:
                end, lowest, rise, wall = run(blade, resolution, length)
                print("| %s | %g | %g | %d | %.2f | %.3f | %.4f | %.1f |"
                      % (maker, length, width, resolution, end, lowest, rise, wall), flush=True)
        for proxy in (fit, scan, leaf):
            Delete(proxy)
