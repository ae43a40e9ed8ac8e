# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: writes generated_tree.xyz, the tree cloud shipped in data/tree-clouds (no public tree scan with a
licence that allows shipping it could be fetched where this was made, so the cloud is generated, as the data README
says). A TreeFromSketchSource tree (Table 1's left template, monopodial 3/8, depth 2, 12 m, radius 0.25 m, seated
tubes of 24 sides, no leaves) scanned by VirtualScanner from three terrestrial tripods 14 m away at 1.5 m height,
beams about 2.8 cm apart at the tree, 5 mm range noise, 10 % dropout, seed 7; x, y, z in metres (y up), rounded to
the millimetre. The truth (from the same source) is in the data README.

    pvpython make_generated_tree.py --plugin PlantMorph.so [--out generated_tree.xyz]
"""
import argparse
import math

parser = argparse.ArgumentParser()
parser.add_argument("--plugin", required=True)
parser.add_argument("--out", default="generated_tree.xyz")
arguments = parser.parse_args()

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

LoadPlugin(arguments.plugin, ns=globals())
TREE = dict(Preset="Custom", TreeType="Monopodial", Length=12.0, Radius=0.25, Depth=2, ChildCount=8, PhyllotaxisA=3,
            PhyllotaxisB=8, Ratio=0.7, Sides=24, Joints="Seated tubes", Leaves=0)
tree = TreeFromSketchSource(**TREE)
positions = [c for k in range(3) for c in (14 * math.cos(2 * math.pi * (k + 0.2) / 3), 1.5,
                                           14 * math.sin(2 * math.pi * (k + 0.2) / 3))]
scan = VirtualScanner(Input=tree, ScannerType="Terrestrial", Positions=positions, LookAt=[0, 7.0, 0], Up=[0, 1, 0],
                      HorizontalFieldOfView=70, VerticalFieldOfView=70, AngularStep=math.degrees(0.028 / 14),
                      RangeNoise=0.005, DropoutProbability=0.1, Seed=7, MaximumBeams=4e8)
points = vtk_to_numpy(servermanager.Fetch(scan).GetPoints().GetData())
numpy.savetxt(arguments.out, numpy.round(points, 3), fmt="%.3f", delimiter=",")
print("%s: %d points" % (arguments.out, len(points)))
