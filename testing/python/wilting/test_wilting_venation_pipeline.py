# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: LeafOutlineSource -> VenationFilter -> WiltingSimulator, the way the README's pipeline builds it: the
blade (VenationFilter's port 1) on Input, the veins (port 0) on Veins. Checked: the proxy has the optional Veins
input and a Veins output; at t = 0 both outputs are their inputs exactly; later the veins droop with the blade and
stay on it (every moved vein point within a small fraction of the tip's travel of the moved blade), keep their
arrays (VeinWidth, VeinOrder, Region) and cells; the veins' primaries and secondaries make vein voxels; without
the veins the same filter still runs. Nothing is rendered."""
from plantmorph_testing import Checks, load_plugin, parse_arguments

arguments = parse_arguments()

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import reference
from vtkmodules.vtkCommonDataModel import vtkGenericCell, vtkStaticCellLocator
import numpy as np

load_plugin(arguments.plugin, globals())
checks = Checks()


def at(proxy, time, port=0):
    proxy.UpdatePipeline(time)
    return servermanager.Fetch(ForceTime(Input=OutputPort(proxy, port), ForcedTime=time, IgnorePipelineTime=1))


def points(data):
    return vtk_to_numpy(data.GetPoints().GetData()).astype(float)


leaf = LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", BladeLength=20.1, BladeWidth=22.1,
                         Resolution=24)
veins = VenationFilter(Input=leaf, Preset="Custom", Pattern="Palmate (actinodromous)", ForkLevels=1)
wilt = WiltingSimulator(Input=OutputPort(veins, 1), Veins=OutputPort(veins, 0), Preset="Cucumber", Resolution=14,
                        AnchorRadius=3.0, Duration=2.0, FrameInterval=0.1, TimeStep=1.0 / 60.0, NewtonIterations=1)
checks.check(wilt.GetProperty("Veins") is not None, "the proxy has a Veins input")
checks.check(wilt.SMProxy.GetNumberOfOutputPorts() == 4,
             "four output ports: %d" % wilt.SMProxy.GetNumberOfOutputPorts())

blade_in = servermanager.Fetch(veins, idx=1)  # Fetch ignores an OutputPort's index
veins_in = servermanager.Fetch(veins, idx=0)
checks.check(veins_in.GetNumberOfLines() > 5, "VenationFilter made veins: %d lines" % veins_in.GetNumberOfLines())

blade0, veins0 = at(wilt, 0.0, 0), at(wilt, 0.0, 3)
checks.check(np.array_equal(points(blade0), points(blade_in)), "t = 0: the blade is its input")
checks.check(np.array_equal(points(veins0), points(veins_in)), "t = 0: the veins are their input")

end = 2.0
blade1, veins1 = at(wilt, end, 0), at(wilt, end, 3)
tip_drop = points(blade_in)[:, 2].max() - points(blade1)[:, 2].min()
checks.check(tip_drop > 1.0, "the blade droops: lowest point %.2f cm down" % tip_drop)
vein_drop = points(veins_in)[:, 2].max() - points(veins1)[:, 2].min()
checks.check(vein_drop > 0.5 * tip_drop, "the veins droop with it: %.2f cm" % vein_drop)
checks.check(veins1.GetNumberOfPoints() == veins_in.GetNumberOfPoints() and
             veins1.GetNumberOfLines() == veins_in.GetNumberOfLines(), "same vein points and lines")
for name in ("VeinWidth", "Region", "LeafUV", "Displacement"):
    checks.check(veins1.GetPointData().GetArray(name) is not None, "vein point array %s kept" % name)
checks.check(veins1.GetCellData().GetArray("VeinOrder") is not None, "vein cell array VeinOrder kept")
width_in = vtk_to_numpy(veins_in.GetPointData().GetArray("VeinWidth"))
width_out = vtk_to_numpy(veins1.GetPointData().GetArray("VeinWidth"))
checks.check(np.array_equal(width_in, width_out), "VeinWidth values unchanged")

# The veins stay on the moved blade: trilinear embedding of points that were on the blade.
locator = vtkStaticCellLocator()
locator.SetDataSet(blade1)
locator.BuildLocator()
cell = vtkGenericCell()
gap = 0.0
for p in points(veins1):
    closest, cid, sub, d2 = [0.0, 0.0, 0.0], reference(0), reference(0), reference(0.0)
    locator.FindClosestPoint(list(p), closest, cell, cid, sub, d2)
    gap = max(gap, float(d2) ** 0.5)
checks.check(gap < 0.05 * tip_drop, "veins on the moved blade: largest gap %.3f cm (tip travel %.2f cm)" % (
    gap, tip_drop))

voxels = at(wilt, end, 1)
regions = np.bincount(vtk_to_numpy(voxels.GetCellData().GetArray("Region")), minlength=6)
checks.check(regions[1] + regions[2] > regions[1] and regions[1] > 0,
             "primary and secondary veins make vein voxels: %s" % list(regions))

# Without the veins: the blade alone still wilts, the Veins output is empty, and fewer voxels are veins.
alone = WiltingSimulator(Input=OutputPort(veins, 1), Preset="Cucumber", Resolution=14, AnchorRadius=3.0,
                         Duration=2.0, FrameInterval=0.1, TimeStep=1.0 / 60.0, NewtonIterations=1)
checks.check(at(alone, end, 3).GetNumberOfPoints() == 0, "no veins in, no veins out")
regions_alone = np.bincount(vtk_to_numpy(at(alone, end, 1).GetCellData().GetArray("Region")), minlength=6)
checks.check(regions_alone[1] + regions_alone[2] < regions[1] + regions[2],
             "the blade's own midvein marks fewer vein voxels: %s" % list(regions_alone))
checks.finish()
