# SPDX-License-Identifier: GPL-3.0-or-later
"""The Cucumber wilting preset on cucumber blades of any size, made three ways, at any Resolution.

    pvbatch benchmarks/wilting_fitted_scan.py [--plugin build/.../PlantMorph.so] [--sizes 5,20.1,40]
                                              [--widths 1.0,0.8] [--resolutions 14,18]
                                              [--makers source,transform,fitted]

Makers: "source", LeafOutlineSource (B-spline, Cucumber, BladeLength L, BladeWidth w * 22.1 / 20.1 * L,
Resolution 30); "transform", the 20.1 cm blade of that width through ParaView's Transform (scaled by L / 20.1 and
moved); "fitted", the source's blade scanned (VirtualScanner, depth camera 200 x 200 pixels, 45 degrees, 2 L above
the blade's middle looking down, Seed 1) and fitted (LeafFitFilter, InputUnit cm, its defaults). Each goes into
WiltingSimulator (Preset Cucumber, Resolution R, its 10 s). Printed per case: the run's end (10 s, or the blow-up's
time), the tip's lowest height and its largest rise after its lowest point so far, over the blade length L, the
largest distance of the tip path (from its start, / L) from the finest Resolution's path of the same blade
(its last), and the wall time; the filter's warnings and errors go to the console.
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
parser.add_argument("--makers", default="source,fitted")
arguments = parser.parse_args()
LoadPlugin(os.path.abspath(arguments.plugin), remote=False, ns=globals())


def run(blade, resolution, length):
    wilting = WiltingSimulator(Input=blade, Preset="Cucumber", Resolution=resolution)
    start = time.time()
    wilting.UpdatePipeline(0.0)
    wall = time.time() - start
    table = wilting.GetClientSideObject().GetOutputDataObject(2)
    t = vtk_to_numpy(table.GetColumn(0))
    tip = numpy.stack([vtk_to_numpy(table.GetColumnByName(n)) for n in ("TipX", "TipY", "TipZ")], axis=1)
    z = tip[:, 2]
    lowest = numpy.minimum.accumulate(z)
    Delete(wilting)
    return dict(end=t[-1], lowest=(z.min() - z[0]) / length, rise=(z - lowest).max() / length,
                path=(tip - tip[0]) / length, wall=wall)


print("| maker | L (cm) | width | R | ran to (s) | lowest / L | rises back / L | path vs finest R / L | wall s |")
print("|---|---|---|---|---|---|---|---|---|")
resolutions = [int(r) for r in arguments.resolutions.split(",")]
makers = arguments.makers.split(",")
for length in [float(s) for s in arguments.sizes.split(",")]:
    for width in [float(w) for w in arguments.widths.split(",")]:
        leaf = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", BladeLength=length,
                                 BladeWidth=width * 22.1 / 20.1 * length, Resolution=30)
        reference = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", BladeLength=20.1,
                                      BladeWidth=width * 22.1, Resolution=30)
        moved = Transform(Input=reference)
        moved.Transform.Scale = [length / 20.1] * 3
        moved.Transform.Translate = [37.0, -12.5, 4.0]
        scan = VirtualScanner(Input=leaf, ScannerType="Depth camera", Positions=[0, 0.5 * length, 2.0 * length],
                              LookAt=[0, 0.5 * length, 0], Up=[0, 1, 0], Resolution=[200, 200],
                              HorizontalFieldOfView=45, VerticalFieldOfView=45, Seed=1)
        fit = LeafFitFilter(Input=scan, InputUnit="cm")
        blades = dict(source=leaf, transform=moved, fitted=fit)
        for maker in makers:
            runs = [(r, run(blades[maker], r, length)) for r in resolutions]
            finest = runs[-1][1]
            for resolution, result in runs:
                complete = len(result["path"]) == len(finest["path"]) and finest["end"] >= 10.0 - 1e-9
                path = "%.3f" % numpy.linalg.norm(result["path"] - finest["path"], axis=1).max() if complete else "-"
                print("| %s | %g | %g | %d | %.2f | %.3f | %.4f | %s | %.1f |"
                      % (maker, length, width, resolution, result["end"], result["lowest"], result["rise"], path,
                         result["wall"]), flush=True)
        for proxy in (fit, scan, moved, reference, leaf):
            Delete(proxy)
