# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: LeafOutlineSource -> WiltingSimulator as users build it: the proxy and its defaults, time steps
advertised, frames served from the cache (scrubbing does not re-simulate), the leaf equal to the input at t = 0
with every array kept, drooping later with the anchored voxel nodes fixed, the voxel grid and the trajectory table,
bad properties giving empty outputs, and a state file round trip at a non-zero time in a fresh pvpython. Nothing
is rendered."""
import json
import os
import sys

from plantmorph_testing import Checks, fingerprint, load_plugin, parse_arguments, reload_in_fresh_pvpython

arguments = parse_arguments([("--load", dict(default=None))])

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy

load_plugin(arguments.plugin, globals())
checks = Checks()
state = os.path.join(arguments.work, "wilting.pvsm")
expected_file = os.path.join(arguments.work, "wilting_expected.json")


def at(proxy, time, port=0):
    proxy.UpdatePipeline(time)
    return servermanager.Fetch(ForceTime(Input=OutputPort(proxy, port), ForcedTime=time, IgnorePipelineTime=1))


if arguments.load is None:
    # The cucumber leaf of paper 001's size, which the Cucumber preset was fitted on.
    leaf = LeafOutlineSource(registrationName="Leaf", Model="B-spline", BSplinePreset="Cucumber", BladeLength=20.1,
                             BladeWidth=22.1, Resolution=24)
    wilt = WiltingSimulator(registrationName="Wilt", Input=leaf)
    checks.check(wilt.GetXMLLabel() == "Wilting Simulator", "label: %s" % wilt.GetXMLLabel())
    checks.check(wilt.Preset == "Cucumber" and wilt.Resolution == 14 and wilt.CompressionClamp == 1 and
                 wilt.AnchorRadius == 3.0 and wilt.NewtonIterations == 1 and abs(wilt.TimeStep - 1.0 / 60.0) < 1e-15,
                 "defaults: the Cucumber preset at the settings it was fitted at, clamp on")
    wilt.Duration = 3.0
    wilt.Resolution = 14
    wilt.UpdatePipelineInformation()
    times = list(wilt.TimestepValues)
    checks.check(len(times) == 31 and abs(times[-1] - 3.0) < 1e-9, "31 frames advertised up to 3 s: %d" % len(times))

    blade = servermanager.Fetch(leaf)
    first = at(wilt, 0.0)
    same = (vtk_to_numpy(first.GetPoints().GetData()) == vtk_to_numpy(blade.GetPoints().GetData())).all()
    checks.check(bool(same), "t = 0: the input's points exactly")
    for name in ("LeafUV", "TCoords", "Region", "Displacement"):
        checks.check(first.GetPointData().GetArray(name) is not None, "array %s on the leaf" % name)
    checks.check(first.GetPointData().GetTCoords() is not None, "TCoords still the active texture coordinates")
    def runs(data):
        return data.GetFieldData().GetArray("WiltingSimulator.SimulationCount").GetValue(0)

    count = runs(first)
    last = at(wilt, 3.0)
    middle = [at(wilt, t) for t in (1.0, 2.0, 1.05)]
    again = at(wilt, 3.0)
    checks.check(runs(again) == count == 1, "scrubbing served from the cache (%d simulations)" % runs(again))
    checks.check(abs(middle[2].GetFieldData().GetArray("WiltingSimulator.FrameTime").GetValue(0) - 1.05) < 1e-9,
                 "a time between frames is interpolated")
    checks.check(fingerprint(again) == fingerprint(last), "the same frame twice, bit-identical")
    zmin = last.GetBounds()[4]
    checks.check(zmin < blade.GetBounds()[4] - 0.5, "the leaf droops: z min %.3f" % zmin)
    voxels = at(wilt, 3.0, 1)
    checks.check(voxels.GetNumberOfCells() > 20 and voxels.GetCellType(0) == 12, "hexahedra: %d" % voxels.GetNumberOfCells())
    fixed = vtk_to_numpy(voxels.GetPointData().GetArray("Fixed"))
    disp = vtk_to_numpy(voxels.GetPointData().GetArray("Displacement"))
    checks.check(fixed.sum() > 0 and abs(disp[fixed == 1]).max() == 0.0, "anchored nodes do not move")
    table = servermanager.Fetch(wilt, idx=2)
    checks.check(table.GetNumberOfRows() == 31 and table.GetColumnByName("TipZ") is not None,
                 "trajectory table: %d rows" % table.GetNumberOfRows())
    tipz = vtk_to_numpy(table.GetColumnByName("TipZ"))
    checks.check(tipz[-1] < tipz[0] - 0.5, "the tip went down: %.3f -> %.3f" % (tipz[0], tipz[-1]))

    # Bad input: an empty output, not a crash.
    bad = WiltingSimulator(Input=leaf, Duration=-1.0)
    checks.check(servermanager.Fetch(bad).GetNumberOfPoints() == 0, "Duration -1: empty output")
    Delete(bad)

    # State file at a non-zero time: set the time without a view (a view would render).
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = 2.0
    expected = {"fingerprint": fingerprint(at(wilt, 2.0)), "duration": wilt.Duration, "resolution": wilt.Resolution}
    checks.finish()
    sys.exit(reload_in_fresh_pvpython(state, expected, expected_file, arguments, __file__))

LoadState(arguments.load)
wilt = FindSource("Wilt")
checks.check(wilt is not None, "the state holds the filter")
with open(expected_file) as f:
    expected = json.load(f)
time = GetAnimationScene().AnimationTime
checks.check(abs(time - 2.0) < 1e-12, "animation time restored: %r" % time)
checks.check(wilt.Duration == expected["duration"] and wilt.Resolution == expected["resolution"], "properties restored")
checks.check(fingerprint(at(wilt, time)) == expected["fingerprint"], "the leaf at t = 2 bit-identical after the round trip")
checks.finish()
