# SPDX-License-Identifier: GPL-3.0-or-later
"""A PlantMorph tree leaves ParaView as the plant and forestry tools' files and comes back: TreeFromSketchSource's
skeleton saved as an MTG (OpenAlea's multiscale tree graph, docs/formats/mtg.md) and as a QSM cylinder table
(SimpleForest / rTwig CSV, docs/formats/qsm.md), each read back by MTG Reader and QSM Reader: on the left the MTG's
axes as tubes of their diameter, coloured by branch order; on the right the QSM's cylinders as closed tubes, coloured
by the table's branchOrder column.

    xvfb-run -a pvbatch examples/tree_formats.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import caption, save_png, start, white_view

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402

tree = TreeFromSketchSource(registrationName="Tree", Preset="Custom", Depth=3, ChildCount=4, Ratio=0.6, Leaves=0)
mtg = os.path.join(arguments.output, "tree_formats.mtg")
qsm = os.path.join(arguments.output, "tree_formats.csv")
SaveData(mtg, proxy=OutputPort(tree, 1))  # File > Save Data picks MTG Writer for .mtg
print("wrote", mtg)
# A .csv has several writers (ParaView's own CSV writer too): name the QSM one.
writer = servermanager.writers.QSMWriter(Input=OutputPort(tree, 1), FileName=qsm)
writer.UpdatePipeline()
print("wrote", qsm)

view = white_view(1000, 700)
axes = Tube(registrationName="MtgAxes", Input=MTGReader(registrationName="MtgFile", FileName=mtg), Scalars=["POINTS", "Radius"],
            VaryRadius="By Absolute Scalar", NumberofSides=12, Capping=1)
cylinders = Transform(registrationName="QsmPlaced",
                      Input=QSMReader(registrationName="QsmFile", FileName=qsm, Tubes=1, Sides=12))
bounds = servermanager.Fetch(OutputPort(tree, 1)).GetBounds()
width = bounds[1] - bounds[0]
cylinders.Transform.Translate = [1.3 * width, 0.0, 0.0]
for proxy, array, where in ((axes, "BranchOrder", "CELLS"), (cylinders, "branchOrder", "CELLS")):
    display = Show(proxy, view)
    ColorBy(display, (where, array))
    display.LookupTable = GetColorTransferFunction(array)
    display.LookupTable.ApplyPreset("Viridis (matplotlib)", True)
    display.LookupTable.RescaleTransferFunction(0.0, 3.0)
height = bounds[3] - bounds[2]
caption(view, "MTG (OpenAlea)", [bounds[0], bounds[2] - 0.12 * height, 0.0], 0.06 * height)
caption(view, "QSM table (rTwig)", [bounds[0] + 1.3 * width, bounds[2] - 0.12 * height, 0.0], 0.06 * height)
save_png(view, os.path.join(arguments.output, "tree_formats.png"))
