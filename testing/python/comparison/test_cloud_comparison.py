# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: the comparison filters as users build them, on the real data in data/. Leaf Cloud Reader reads a
soybean scan (x, y, z, normals, colours, scalar) exactly as numpy reads the file, and a sugar-beet scan (x, y, z
only); Cloud Comparison Filter on the real scan: distances to a subsampled, moved copy equal numpy's brute-force
nearest neighbours, the scan against itself is at 0, the histogram adds up, Symmetric Hausdorff is symmetric; the
scan in mm against a leaf in cm with Scale 0.1; the cucumber tip file read through the reader's table port gives
paper 001's 1.76, 0.69, 2.52, 1.89, 2.92 cm and 6.1 degrees; bad properties give empty outputs. Nothing is
rendered."""
import glob
import os

import numpy

from plantmorph_testing import Checks, load_plugin, Messages, parse_arguments

from paraview.simple import *  # noqa: F401,F403 (the pvpython way)
from paraview import servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy

arguments = parse_arguments()
load_plugin(arguments.plugin, globals())
checks = Checks()

DATA = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "data"))
soybean_file = sorted(glob.glob(os.path.join(DATA, "leaf-clouds", "soybean_*.txt")))[0]
sugarbeet_file = sorted(glob.glob(os.path.join(DATA, "leaf-clouds", "sugarbeet_*.txt")))[0]
tip_file = os.path.join(DATA, "cucumber-wilting-tip.csv")


def stat(proxy, name):
    table = servermanager.Fetch(proxy, idx=2)
    array = table.GetColumnByName(name)
    return array.GetValue(0) if array is not None else None


# --- Leaf Cloud Reader on the real files.
expected = numpy.loadtxt(soybean_file, delimiter=",")
reader = LeafCloudReader(FileName=soybean_file)
cloud = servermanager.Fetch(reader)
n = cloud.GetNumberOfPoints()
checks.check(n == expected.shape[0], "soybean: %d points, %d lines" % (n, expected.shape[0]))
points = vtk_to_numpy(cloud.GetPoints().GetData())
checks.check(cloud.GetPoints().GetDataType() == 11 and numpy.array_equal(points, expected[:, 0:3]),
             "soybean: double points equal to the file's x, y, z")
normals = cloud.GetPointData().GetNormals()
checks.check(normals is not None and numpy.array_equal(vtk_to_numpy(normals), expected[:, 3:6]),
             "soybean: the file's normals are the active normals")
colors = cloud.GetPointData().GetScalars()
checks.check(colors is not None and colors.GetName() == "Colors" and colors.GetDataType() == 3
             and numpy.array_equal(vtk_to_numpy(colors), numpy.rint(expected[:, 6:9] * 255)),
             "soybean: colours as unsigned char, the active scalars")
checks.check(numpy.array_equal(vtk_to_numpy(cloud.GetPointData().GetArray("Scalar")), expected[:, 9]),
             "soybean: the tenth column as Scalar")
checks.check(cloud.GetNumberOfVerts() == n, "soybean: one vertex per point")
beet = servermanager.Fetch(LeafCloudReader(FileName=sugarbeet_file))
beet_expected = numpy.loadtxt(sugarbeet_file, delimiter=",")
checks.check(beet.GetNumberOfPoints() == beet_expected.shape[0] and beet.GetPointData().GetNormals() is None,
             "sugar beet: x, y, z only (%d points)" % beet.GetNumberOfPoints())

# The documented CSV recipe (CSV Reader + Table To Points) gives the same points, which the filter accepts.
recipe = TableToPoints(Input=CSVReader(FileName=soybean_file, HaveHeaders=0), XColumn="Field 0", YColumn="Field 1",
                       ZColumn="Field 2")
recipe_points = vtk_to_numpy(servermanager.Fetch(recipe).GetPoints().GetData())
checks.check(numpy.array_equal(recipe_points, points), "CSV recipe: the same points as the reader")
checks.check(stat(CloudComparisonFilter(Input=recipe, Reference=reader), "Maximum") == 0.0,
             "CSV recipe: at distance 0 from the reader's cloud")

# --- Cloud Comparison Filter on the real scan: against a subsampled, moved copy (point-cloud reference).
subset = MaskPoints(Input=reader, OnRatio=3, GenerateVertices=1, SingleVertexPerCell=1, RandomSampling=0,
                    MaximumNumberofPoints=10 ** 6)
moved = Transform(Input=subset)
moved.Transform.Translate = [0.7, -0.4, 1.1]
comparison = CloudComparisonFilter(Input=reader, Reference=moved, Symmetric=1, HistogramBins=20)
checks.check(comparison.GetXMLLabel() == "Cloud Comparison Filter", "label 'Cloud Comparison Filter'")
checks.check(comparison.Scale == 1 and comparison.Registration == "None" and comparison.HistogramBins == 20
             and comparison.UseMaximumDistance == 0, "properties and defaults")
result = servermanager.Fetch(comparison)
distance = vtk_to_numpy(result.GetPointData().GetArray("Distance"))
reference_points = vtk_to_numpy(servermanager.Fetch(moved).GetPoints().GetData()).astype(float)
brute = numpy.sqrt(((points[:, None, :] - reference_points[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
checks.check(numpy.abs(distance - brute).max() < 1e-9,
             "real scan: distances equal numpy's brute-force nearest neighbours (max error %g)"
             % numpy.abs(distance - brute).max())
checks.check(result.GetPointData().GetArray("SignedDistance") is None, "no signed distance against a cloud")
checks.check(abs(stat(comparison, "Hausdorff") - brute.max()) < 1e-9, "one-sided Hausdorff = max distance")
checks.check(abs(stat(comparison, "Mean") - brute.mean()) < 1e-9, "mean distance")
checks.check(abs(stat(comparison, "Percentile95") - numpy.percentile(brute, 95)) < 1e-9, "95th percentile (numpy)")
histogram = servermanager.Fetch(comparison, idx=1)
checks.check(histogram.GetNumberOfRows() == 20
             and vtk_to_numpy(histogram.GetColumnByName("bin_values")).sum() == n, "histogram: 20 bins adding up to n")
swapped = CloudComparisonFilter(Input=moved, Reference=reader, Symmetric=1)
checks.check(abs(stat(swapped, "SymmetricHausdorff") - stat(comparison, "SymmetricHausdorff")) < 1e-12
             and abs(stat(swapped, "Chamfer") - stat(comparison, "Chamfer")) < 1e-12,
             "symmetric Hausdorff and Chamfer unchanged by swapping the inputs")
itself = CloudComparisonFilter(Input=reader, Reference=reader)
checks.check(stat(itself, "Maximum") == 0.0, "the scan against itself: distance 0")

# The scan (mm) against a leaf surface in cm: Scale 0.1 puts it in cm; signed distances exist against a surface.
leaf = LeafOutlineSource(Preset="Ginkgo", Resolution=30)
scaled = CloudComparisonFilter(Input=reader, Reference=leaf, Scale=0.1)
scaled_points = vtk_to_numpy(servermanager.Fetch(scaled).GetPoints().GetData())
checks.check(numpy.allclose(scaled_points, 0.1 * expected[:, 0:3], rtol=0, atol=1e-12), "Scale 0.1: points in cm")
checks.check(servermanager.Fetch(scaled).GetPointData().GetArray("SignedDistance") is not None,
             "signed distance against a surface")
# A unit mismatch: the same scan without Scale (mm against cm) is about 10 times the leaf's size, and a warning says
# so with both sizes; with Scale 0.1 (same size) no such warning.
mismatched = CloudComparisonFilter(Input=reader, Reference=leaf)
with Messages(mismatched) as said:
    mismatched.UpdatePipeline()
checks.check(said.said("unit mismatch", "Scale", kind="warning"), "mm against cm without Scale: a unit-mismatch warning "
             "(%s)" % said.warnings)
with Messages(scaled) as said:
    scaled.Scale = 0.1000001
    scaled.UpdatePipeline()
checks.check(not said.said("unit mismatch"), "Scale 0.1: no unit-mismatch warning (%s)" % said.warnings)
scaled.Scale = 0.1
Delete(mismatched)

# --- Trajectory Comparison Filter on the cucumber tip file, read through the reader's table port.
tip = LeafCloudReader(FileName=tip_file)
tip_table = servermanager.Fetch(tip, idx=1)
checks.check(tip_table.GetNumberOfRows() == 5 and tip_table.GetColumnByName("paper_sim_z") is not None,
             "tip file: 5 rows, header names kept, '#' lines skipped")
trajectory = TrajectoryComparisonFilter(Input=OutputPort(tip, 1), Simulated=OutputPort(tip, 1),
                                        MeasuredColumns=["measured_x", "measured_y", "measured_z"],
                                        SimulatedColumns=["paper_sim_x", "paper_sim_y", "paper_sim_z"])
checks.check(trajectory.GetXMLLabel() == "Trajectory Comparison Filter", "label 'Trajectory Comparison Filter'")
samples = servermanager.Fetch(trajectory)
distances = [round(samples.GetValueByName(i, "ClosestDistance").ToDouble(), 2) for i in range(5)]
checks.check(distances == [1.76, 0.69, 2.52, 1.89, 2.92], "paper 001 distances: %s" % distances)
summary = servermanager.Fetch(trajectory, idx=1)
angle = summary.GetValueByName(0, "ClosestDirectionAngle").ToDouble()
checks.check(round(angle, 1) == 6.1, "paper 001 direction angle 6.1 deg: %.3f" % angle)

# --- Bad properties: an error and empty outputs (ParaView prints the error; the script carries on).
comparison.Scale = -1
bad = servermanager.Fetch(comparison)
checks.check(bad.GetNumberOfPoints() == 0 and servermanager.Fetch(comparison, idx=2).GetNumberOfColumns() == 0,
             "Scale -1: empty outputs")
comparison.Scale = 1
trajectory.MeasuredColumns = ["x", "y", "nope"]
checks.check(servermanager.Fetch(trajectory).GetNumberOfRows() == 0, "unknown column: empty output")

# Seed is ignored (registration subsamples by stride) and hidden, but kept so that old state files set it: two seeds
# give the same registered result on a cloud larger than RegistrationLandmarks.
seeded = [CloudComparisonFilter(Input=reader, Reference=LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber"),
                                Scale=0.1, Registration="Rigid + scale ICP", RegistrationLandmarks=500, Seed=seed)
          for seed in (0, 12345)]
matrices = [vtk_to_numpy(servermanager.Fetch(f).GetFieldData().GetArray("PlantMorph.MeasuredTransform")) for f in seeded]
checks.check(numpy.array_equal(matrices[0], matrices[1]) and seeded[1].Seed == 12345,
             "Seed is accepted and ignored: the same transform with two seeds")

checks.finish()
