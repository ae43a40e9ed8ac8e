# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: TreeFitFilter on the tree cloud shipped in data/tree-clouds (generated: data/README.md says how), read by
LeafCloudReader and fitted with the defaults, as a user opens a scan. The cylinders lie on the points (median
|FitDistance| about the scan's 5 mm range noise), and the table is plausible against the tree the cloud was made
from (its skeleton, rebuilt here with the generator's parameters): height, DBH, volume, first-order branches.

    pvpython test_tree_fit_data.py --plugin PlantMorph.so --work DIR
"""
import os

from plantmorph_testing import Checks, load_plugin, parse_arguments, skeleton_truth

arguments = parse_arguments([("--pvpython", dict(default=None))])

from paraview.simple import *  # noqa: E402,F401,F403
from paraview import servermanager  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
import numpy  # noqa: E402

load_plugin(arguments.plugin, globals())
checks = Checks()
DATA = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "data"))
NOISE = 0.005
# The generator's tree (data/tree-clouds/make_generated_tree.py).
TREE = dict(Preset="Custom", TreeType="Monopodial", Length=12.0, Radius=0.25, Depth=2, ChildCount=8, PhyllotaxisA=3,
            PhyllotaxisB=8, Ratio=0.7, Sides=24, Joints="Seated tubes", Leaves=0)

cloud = LeafCloudReader(FileName=os.path.join(DATA, "tree-clouds", "generated_tree.xyz"))
fit = TreeFitFilter(Input=cloud, UpAxis="Y")
fit.UpdatePipeline()
table = servermanager.Fetch(fit, idx=2)
row = {table.GetColumnName(c): table.GetValue(0, c).ToString() for c in range(table.GetNumberOfColumns())}
checks.check(table.GetNumberOfRows() == 1 and row.get("Status") == "ok", "one tree, fitted: %s" % row.get("Status"))
value = {k: float(v) for k, v in row.items() if k not in ("Status",)}

scan = servermanager.Fetch(fit, idx=4)
distance = vtk_to_numpy(scan.GetPointData().GetArray("FitDistance"))
median = float(numpy.nanmedian(numpy.abs(distance)))
checks.check(median < 2.0 * NOISE, "the cylinders lie on the points: median |FitDistance| %.4f m (noise %.3f)" % (
    median, NOISE))
checks.check(numpy.mean(numpy.isfinite(distance)) > 0.9, "over 90 %% of the points are on a cylinder (%.3f)" % (
    numpy.mean(numpy.isfinite(distance))))

# The truth: the generating tree's skeleton (frusta, its trunk's radius at breast height, its surface's height).
tree = TreeFromSketchSource(**TREE)
truth = skeleton_truth(servermanager.Fetch(tree, idx=1), servermanager.Fetch(tree).GetBounds())
volume, dbh, height, first_order = truth["volume"], truth["dbh"], truth["height"], truth["first_order"]
# At this beam spacing (2.8 cm at the tree) the top twigs' thin tips are hardly hit: the height comes out 3 % short.
checks.check(abs(value["Height"] / height - 1) < 0.05, "height %.2f m within 5 %% of %.2f" % (value["Height"], height))
checks.check(abs(value["DBH"] / dbh - 1) < 0.03, "DBH %.3f m within 3 %% of %.3f" % (value["DBH"], dbh))
checks.check(abs(value["TotalVolume"] / volume - 1) < 0.15, "total volume %.3f m3 within 15 %% of %.3f" % (
    value["TotalVolume"], volume))
# A known shortfall at this spacing: the trunk is split at a junction high up, and the laterals above it come out as
# branches of order 2 (4 of the 8 first-order branches are found as such; docs/methods/tree-fit.md).
checks.check(first_order // 2 <= value["BranchesOrder1"] <= first_order, "first-order branches %d, %d in the tree" % (
    value["BranchesOrder1"], first_order))
checks.check(0 < value["CrownBaseHeight"] < value["Height"], "crown base %.2f m below the top" % value["CrownBaseHeight"])
print("fitted:", {k: row[k] for k in ("Height", "DBH", "TotalVolume", "TrunkVolume", "BranchesOrder1", "BranchCount",
                                      "FitRMS", "Noise")}, "truth: height %.3f DBH %.4f volume %.4f first order %d" % (
    height, dbh, volume, first_order))
checks.finish()
