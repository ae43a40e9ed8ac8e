// SPDX-License-Identifier: GPL-3.0-or-later
// WiltingSimulator's algorithm layer: voxeliser (exact triangle-box test), embedding exactness, a drooping leaf
// with its anchors fixed, loads, determinism and bad input (docs/methods/wilting.md).
#include "WiltingEmbedding.h"
#include "WiltingPresets.h"
#include "WiltingSimulation.h"
#include "WiltingTestBlades.h"
#include "WiltingVoxelizer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace
{
using namespace plantmorph;

/// A flat rectangular blade [-w/2, w/2] x [0, l] in z = 0, triangulated on an nx x ny grid, with LeafUV and a
/// midvein Region along x = 0 and margin Region on the sides.
WiltingInput Rectangle(double w, double l, int nx, int ny)
{
  return GridBlade(w, l, nx, ny, [nx](int i, int) { return i == nx / 2 ? 1 : (i == 0 || i == nx ? 4 : 0); });
}

TEST(WiltingVoxelizer, TriangleBoxOverlapAgreesWithSampling)
{
  // Random triangles against the unit box: an overlap found by sampling points of the triangle must be reported.
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 2.0);
  const Eigen::Vector3d low(0, 0, 0);
  const Eigen::Vector3d high(1, 1, 1);
  int overlaps = 0;
  for (int trial = 0; trial < 2000; ++trial)
  {
    const Eigen::Vector3d a(coordinate(random), coordinate(random), coordinate(random));
    const Eigen::Vector3d b(coordinate(random), coordinate(random), coordinate(random));
    const Eigen::Vector3d c(coordinate(random), coordinate(random), coordinate(random));
    bool sampled = false;
    const int n = 60;
    for (int i = 0; i <= n && !sampled; ++i)
    {
      for (int j = 0; i + j <= n && !sampled; ++j)
      {
        const Eigen::Vector3d p = a + (b - a) * i / n + (c - a) * j / n;
        sampled = (p.array() >= low.array()).all() && (p.array() <= high.array()).all();
      }
    }
    const bool exact = TriangleBoxOverlap(a, b, c, low, high);
    if (sampled)
    {
      EXPECT_TRUE(exact) << "trial " << trial;
    }
    overlaps += exact ? 1 : 0;
  }
  EXPECT_GT(overlaps, 100);
  // Separated only by the triangle's plane (the 13th axis), and only by an edge axis.
  EXPECT_FALSE(
    TriangleBoxOverlap(Eigen::Vector3d(3.1, 0, 0), Eigen::Vector3d(0, 3.1, 0), Eigen::Vector3d(0, 0, 3.1), low, high));
  EXPECT_TRUE(
    TriangleBoxOverlap(Eigen::Vector3d(2.9, 0, 0), Eigen::Vector3d(0, 2.9, 0), Eigen::Vector3d(0, 0, 2.9), low, high));
  EXPECT_TRUE(
    TriangleBoxOverlap(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(3, 0, 0), Eigen::Vector3d(3, 3, 0), low, high))
    << "touching an edge counts";
}

TEST(WiltingVoxelizer, FlatLeafIsOneLayerWithSharedNodes)
{
  const WiltingInput in = Rectangle(4.0, 10.0, 8, 20);
  VoxelGrid grid;
  VoxelizeParameters options;
  options.resolution = 10;
  ASSERT_EQ(Voxelize(in.points, in.triangles, in.regions, options, grid), "");
  EXPECT_EQ(grid.dims[2], 1);
  EXPECT_EQ(grid.voxels.size(), 4u * 10u) << "4 x 10 cells of edge 1 cover the 4 x 10 rectangle";
  EXPECT_EQ(grid.nodes.size(), 2u * 5u * 11u) << "shared corners are shared nodes";
  // The midvein column's voxels carry the vein Region, the side columns the margin.
  int veins = 0;
  int margins = 0;
  for (int r : grid.regions)
  {
    veins += r == 1 ? 1 : 0;
    margins += r == 4 ? 1 : 0;
  }
  EXPECT_EQ(veins, 20) << "the midvein x = 0 lies on the face between two columns: both are vein voxels";
  EXPECT_EQ(margins, 20);
}

TEST(WiltingVoxelizer, AlignedGridPutsANodePlaneThroughThePointAndCoversTheLeaf)
{
  // The 4 x 10 rectangle (x in [-2, 2]) at Resolution 11: centred on the box, x = 0 is the middle of a cell column
  // (11 columns of 10/11); aligned across (x) on the base (0, 0), a node plane passes through x = 0, one column is
  // added, and the grid still covers the rectangle.
  const WiltingInput in = Rectangle(4.0, 10.0, 8, 20);
  VoxelizeParameters options;
  options.resolution = 11;
  VoxelGrid centred;
  ASSERT_EQ(Voxelize(in.points, in.triangles, in.regions, options, centred), "");
  const double h = 10.0 / 11.0;
  const auto nodePlaneOffset = [&](const VoxelGrid& grid) {
    const double local = (0.0 - grid.origin[0]) / h;
    return std::abs(local - std::round(local));
  };
  EXPECT_NEAR(nodePlaneOffset(centred), 0.5, 1e-9) << "odd columns across: x = 0 mid-cell";
  options.align = { true, false, false };
  VoxelGrid aligned;
  ASSERT_EQ(Voxelize(in.points, in.triangles, in.regions, options, aligned), "");
  EXPECT_NEAR(nodePlaneOffset(aligned), 0.0, 1e-9);
  EXPECT_EQ(aligned.dims[0], centred.dims[0] + 1);
  EXPECT_EQ(aligned.dims[1], centred.dims[1]);
  EXPECT_DOUBLE_EQ(aligned.origin[1], centred.origin[1]) << "only the aligned axis moves";
  EXPECT_LE(aligned.origin[0], -2.0);
  EXPECT_GE(aligned.origin[0] + h * aligned.dims[0], 2.0);
  // Already on a node plane (Resolution 10: 1 cm cells, x = 0 a face): nothing moves.
  options.resolution = 10;
  VoxelGrid even;
  ASSERT_EQ(Voxelize(in.points, in.triangles, in.regions, options, even), "");
  EXPECT_EQ(even.dims[0], 4);
  EXPECT_DOUBLE_EQ(even.origin[0], -2.0);
}

TEST(WiltingVoxelizer, PetioleGrowsTheGridBelowTheBaseAndKeepsTheBlade)
{
  const WiltingInput in = Rectangle(4.0, 10.0, 8, 20);
  VoxelizeParameters options;
  options.resolution = 10;
  VoxelGrid blade;
  ASSERT_EQ(Voxelize(in.points, in.triangles, in.regions, options, blade), "");
  // The base (0, 0, 0) lies on the face between two columns, at the grid's -y end: the petiole is two columns
  // wide, one layer thick, 3 rows long, and the grid grows by 3 rows.
  VoxelGrid grid = blade;
  PetiolePlacement petiole;
  ASSERT_EQ(AddPetiole(grid, Eigen::Vector3d::Zero(), 2.6, options.maxVoxels, petiole), "");
  EXPECT_EQ(petiole.voxels, 6);
  EXPECT_EQ(petiole.shift, 3);
  EXPECT_EQ(grid.dims[1], blade.dims[1] + 3);
  EXPECT_NEAR(petiole.length, 3.0, 1e-12) << "2.6 rounds to 3 whole voxels";
  EXPECT_LT((petiole.end - Eigen::Vector3d(0.0, -3.0, 0.0)).norm(), 1e-12);
  ASSERT_EQ(grid.voxels.size(), blade.voxels.size() + 6);
  int petioleCells = 0;
  for (std::size_t v = 0; v < grid.voxels.size(); ++v)
  {
    const Eigen::Vector3d low =
      grid.origin + grid.h * Eigen::Vector3d(grid.voxels[v][0], grid.voxels[v][1], grid.voxels[v][2]);
    if (grid.regions[v] == 5)
    {
      ++petioleCells;
      EXPECT_LT(low[1], -0.5) << "petiole cells lie below the base";
      EXPECT_NEAR(std::abs(low[0] + 0.5), 0.5, 1e-12) << "in the two columns x in [-1, 0] and [0, 1]";
    }
    else
    {
      // Every blade cell is where it was, with its Region.
      const int i = static_cast<int>(std::lround((low[0] - blade.origin[0]) / blade.h));
      const int j = static_cast<int>(std::lround((low[1] - blade.origin[1]) / blade.h));
      const int k = static_cast<int>(std::lround((low[2] - blade.origin[2]) / blade.h));
      const int old = blade.VoxelAt(i, j, k);
      ASSERT_GE(old, 0);
      EXPECT_LT((blade.origin + blade.h * Eigen::Vector3d(i, j, k) - low).norm(), 1e-12);
      EXPECT_EQ(grid.regions[v], blade.regions[static_cast<std::size_t>(old)]);
    }
    for (int corner : grid.corners[v])
    {
      ASSERT_GE(corner, 0) << "every corner is a node";
    }
  }
  EXPECT_EQ(petioleCells, 6);
  EXPECT_EQ(grid.nodes.size(), blade.nodes.size() + 3u * 2u * 3u) << "3 new node rows of 3 x 2";
  ASSERT_EQ(petiole.endNodes.size(), 6u) << "the end face: 3 x 2 nodes";
  for (int node : petiole.endNodes)
  {
    EXPECT_NEAR(grid.nodes[static_cast<std::size_t>(node)][1], -3.0, 1e-12);
  }
  // A base inside the blade: the cells on the petiole's path become petiole, the grid keeps its size; a base in a
  // column's middle gives a one-column petiole.
  grid = blade;
  ASSERT_EQ(AddPetiole(grid, Eigen::Vector3d(0.5, 2.5, 0.0), 2.0, options.maxVoxels, petiole), "");
  EXPECT_EQ(petiole.shift, 0);
  EXPECT_EQ(petiole.voxels, 2);
  EXPECT_EQ(grid.voxels.size(), blade.voxels.size());
  EXPECT_EQ(std::count(grid.regions.begin(), grid.regions.end(), 5), 2);
  ASSERT_GE(grid.VoxelAt(2, 0, 0), 0);
  ASSERT_GE(grid.VoxelAt(2, 1, 0), 0);
  EXPECT_EQ(grid.regions[static_cast<std::size_t>(grid.VoxelAt(2, 0, 0))], 5);
  EXPECT_EQ(grid.regions[static_cast<std::size_t>(grid.VoxelAt(2, 1, 0))], 5);
  EXPECT_EQ(grid.regions[static_cast<std::size_t>(grid.VoxelAt(2, 2, 0))],
    blade.regions[static_cast<std::size_t>(blade.VoxelAt(2, 2, 0))]);
  EXPECT_EQ(petiole.endNodes.size(), 4u);
  EXPECT_NE(AddPetiole(grid, Eigen::Vector3d::Zero(), std::nan(""), options.maxVoxels, petiole).find("PetioleLength"),
    std::string::npos);
  EXPECT_NE(AddPetiole(grid, Eigen::Vector3d::Zero(), 1e9, options.maxVoxels, petiole).find("PetioleLength"),
    std::string::npos);
}

TEST(WiltingEmbedding, ExactAtRestAndForAffineMotion)
{
  WiltingInput in = Rectangle(4.0, 10.0, 7, 19);
  in.points.emplace_back(0.3, 5.1, 0.4); // a point off the surface, inside a voxel
  in.points.emplace_back(0.3, 5.1, 3.0); // outside every voxel: extrapolated
  VoxelGrid grid;
  VoxelizeParameters options;
  options.resolution = 10;
  std::vector<int> regions = in.regions;
  regions.resize(in.points.size(), 0);
  ASSERT_EQ(Voxelize(in.points, in.triangles, regions, options, grid), "");
  for (bool tricubic : { false, true })
  {
    WiltingEmbedding embedding;
    ASSERT_EQ(embedding.Bind(grid, in.points, tricubic), "");
    std::vector<double> rest(3 * grid.nodes.size());
    for (std::size_t n = 0; n < grid.nodes.size(); ++n)
    {
      for (int c = 0; c < 3; ++c)
      {
        rest[3 * n + static_cast<std::size_t>(c)] = grid.nodes[n][c];
      }
    }
    std::vector<double> x(3 * in.points.size());
    embedding.InterpolateField(rest.data(), 3, x.data());
    for (std::size_t p = 0; p < in.points.size(); ++p)
    {
      EXPECT_LT((Eigen::Vector3d(x[3 * p], x[3 * p + 1], x[3 * p + 2]) - in.points[p]).norm(), 1e-12)
        << "point " << p << (tricubic ? " tricubic" : " trilinear");
    }
    // An affine motion of the nodes moves every point by the same affine map.
    Eigen::Matrix3d a;
    a << 0.9, 0.1, 0.0, -0.2, 1.1, 0.3, 0.05, 0.0, 0.8;
    const Eigen::Vector3d shift(0.5, -1.0, 2.0);
    std::vector<double> moved(rest.size());
    for (std::size_t n = 0; n < grid.nodes.size(); ++n)
    {
      const Eigen::Vector3d y = a * grid.nodes[n] + shift - grid.nodes[n];
      for (int c = 0; c < 3; ++c)
      {
        moved[3 * n + static_cast<std::size_t>(c)] = y[c];
      }
    }
    embedding.Interpolate(moved.data(), x.data());
    for (std::size_t p = 0; p < in.points.size(); ++p)
    {
      const Eigen::Vector3d expected = a * in.points[p] + shift - in.points[p];
      EXPECT_LT((Eigen::Vector3d(x[3 * p], x[3 * p + 1], x[3 * p + 2]) - expected).norm(), 1e-12);
    }
  }
}

WiltingParameters DroopOnly()
{
  WiltingParameters p;
  p.resolution = 10;
  p.gravity = 0.0;
  p.droopForce = 3.0;
  p.contractionForce = 0.0;
  p.loadProfile = WiltingLoadProfile::Ramp;
  p.loadTime = 2.0;
  p.duration = 2.0;
  p.frameInterval = 0.05;
  p.anchorRadius = 1.5;
  p.newmark.timeStep = 1.0 / 120.0;
  p.newmark.rayleighMass = 20.0; // overdamped: a monotone droop
  p.newmark.maxIterations = 3;
  p.newmark.newtonTolerance = 1e-10;
  p.newmark.cgTolerance = 1e-10;
  return p;
}

TEST(WiltingSimulation, DroopIsMonotoneAndAnchorsStayFixed)
{
  const WiltingInput in = Rectangle(4.0, 10.0, 8, 20);
  WiltingSimulation simulation;
  ASSERT_EQ(simulation.Setup(in, DroopOnly()), "");
  ASSERT_EQ(simulation.Run(), "");
  const std::vector<WiltingFrame>& frames = simulation.Frames();
  ASSERT_EQ(frames.size(), 41u);
  EXPECT_EQ(simulation.TipPoint(), 20 * 9 + 4) << "the tip is the apex of the midvein";
  std::size_t fixed = 0;
  for (std::size_t n = 0; n < simulation.System().NodeCount(); ++n)
  {
    fixed += simulation.System().IsFixed(n) ? 1 : 0;
  }
  EXPECT_GT(fixed, 0u);
  for (std::size_t f = 1; f < frames.size(); ++f)
  {
    EXPECT_LT(frames[f].tip[2], frames[f - 1].tip[2]) << "frame " << f;
    for (std::size_t n = 0; n < simulation.System().NodeCount(); ++n)
    {
      if (simulation.System().IsFixed(n))
      {
        ASSERT_EQ(frames[f].q[3 * n], 0.0);
        ASSERT_EQ(frames[f].q[3 * n + 1], 0.0);
        ASSERT_EQ(frames[f].q[3 * n + 2], 0.0);
      }
    }
  }
  EXPECT_LT(frames.back().tip[2], -0.5) << "it drooped";
  // At t = 0 the embedded leaf is the input, exactly.
  const std::vector<Eigen::Vector3d> x0 = simulation.PointPositions(0);
  for (std::size_t p = 0; p < in.points.size(); ++p)
  {
    EXPECT_LT((x0[p] - in.points[p]).norm(), 1e-12);
  }
}

TEST(WiltingSimulation, ContractionSideChoosesTheCurl)
{
  // Contraction on the bottom nodes curls the margins down relative to the midvein; on the top nodes, up.
  const WiltingInput in = Rectangle(6.0, 6.0, 12, 12);
  double marginMinusMid[2] = { 0.0, 0.0 };
  for (int side = 0; side < 2; ++side)
  {
    WiltingParameters p = DroopOnly();
    p.resolution = 12;
    p.droopForce = 0.0;
    p.contractionForce = 4.0;
    p.contractionSide = side == 0 ? WiltingContractionSide::Bottom : WiltingContractionSide::Top;
    p.voxelSize = 0.5;
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, p), "");
    ASSERT_EQ(simulation.Run(), "");
    const std::vector<Eigen::Vector3d> x = simulation.PointPositions(simulation.Frames().size() - 1);
    const std::size_t apexMargin = 12 * 13 + 0;
    const std::size_t apexMid = 12 * 13 + 6;
    marginMinusMid[side] = x[apexMargin][2] - x[apexMid][2];
  }
  EXPECT_LT(marginMinusMid[0], -1e-3) << "bottom: margin down";
  EXPECT_GT(marginMinusMid[1], 1e-3) << "top: margin up";
}

TEST(WiltingSimulation, ContractionHasItsOwnTimeAndTarget)
{
  // Ramp profile, LoadTime 8 s: the droop is at 1/8 at t = 1 s. With ContractionTime 2 s the contraction is at 1/2
  // then, exactly what it is at t = 4 s when it shares LoadTime (ContractionTime 0).
  const WiltingInput in = Rectangle(4.0, 10.0, 8, 20);
  WiltingParameters p = DroopOnly();
  p.voxelSize = 1.0;
  p.gravity = 0.0;
  p.loadProfile = WiltingLoadProfile::Ramp;
  p.loadTime = 8.0;
  p.droopForce = 0.0;
  p.contractionForce = 3.0;
  p.contractionTarget = WiltingContractionTarget::Base;
  std::vector<double> own, shared, droop;
  {
    p.contractionTime = 2.0;
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, p), "");
    simulation.ExternalForce(1.0, own);
  }
  {
    p.contractionTime = 0.0;
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, p), "");
    simulation.ExternalForce(4.0, shared);
  }
  ASSERT_EQ(own.size(), shared.size());
  double towardsBase = 0.0, vertical = 0.0;
  for (std::size_t k = 0; k < own.size(); ++k)
  {
    EXPECT_EQ(own[k], shared[k]);
    towardsBase += k % 3 == 1 ? own[k] : 0.0; // every voxel pulls towards the base at y = 0: -y
    vertical += k % 3 == 2 ? std::abs(own[k]) : 0.0;
  }
  EXPECT_LT(towardsBase, -1.0);
  EXPECT_EQ(vertical, 0.0);
  // The droop is unaffected by ContractionTime: at t = 1 s it is 1/8 of DroopForce per voxel whatever it is.
  p.contractionForce = 0.0;
  p.droopForce = 8.0;
  for (double contractionTime : { 0.0, 2.0 })
  {
    p.contractionTime = contractionTime;
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, p), "");
    simulation.ExternalForce(1.0, droop);
    double total = 0.0;
    for (std::size_t k = 2; k < droop.size(); k += 3)
    {
      total += droop[k];
    }
    // 40 voxels of 1 cm, their anchored nodes' share removed: between 30 and 40 voxels' worth of 1 dyn each.
    EXPECT_LT(total, -30.0 * 1.0);
    EXPECT_GT(total, -40.0 * 1.0 - 1e-9);
  }
  p.contractionTime = -1.0;
  EXPECT_NE(ValidateWilting(p).find("ContractionTime"), std::string::npos);
}

/// The symmetric loads of the model's definition, recomputed from the grid: per voxel a quarter of DroopForce
/// (-z) and of ContractionForce (towards the midvein plane x = 0) on each of its four bottom nodes, in voxel order.
std::vector<double> SymmetricLoads(const WiltingSimulation& simulation, const WiltingParameters& p)
{
  const VoxelGrid& grid = simulation.Grid();
  std::vector<double> f(3 * grid.nodes.size(), 0.0);
  for (std::size_t v = 0; v < grid.voxels.size(); ++v)
  {
    const double x = grid.origin[0] + grid.h * (grid.voxels[v][0] + 0.5);
    const double towards = std::abs(x) <= 0.5 * grid.h ? 0.0 : (x > 0.0 ? -1.0 : 1.0);
    for (int corner = 0; corner < 4; ++corner)
    {
      const std::size_t node = static_cast<std::size_t>(grid.corners[v][static_cast<std::size_t>(corner)]);
      f[3 * node + 0] += 0.25 * p.contractionForce * towards;
      f[3 * node + 1] += 0.25 * p.contractionForce * 0.0;
      f[3 * node + 2] -= 0.25 * p.droopForce;
    }
  }
  for (std::size_t n = 0; n < grid.nodes.size(); ++n)
  {
    if (simulation.System().IsFixed(n))
    {
      f[3 * n] = f[3 * n + 1] = f[3 * n + 2] = 0.0;
    }
  }
  return f;
}

/// The symmetric rectangle of Rectangle(4.5, 10, 8, 20) in 1 cm voxels: five columns centred on x = 0, the middle
/// one on the midvein, so the voxel model is mirror-symmetric too.
WiltingParameters AsymmetryCase()
{
  WiltingParameters p = DroopOnly();
  p.voxelSize = 1.0;
  p.gravity = 0.0;
  p.loadProfile = WiltingLoadProfile::Constant;
  p.droopForce = 2.0;
  p.contractionForce = 1.5;
  p.contractionTarget = WiltingContractionTarget::Midvein;
  p.duration = 1.0;
  p.frameInterval = 0.25;
  return p;
}

/// The system's own rest lengths, one per spring (what WiltingSimulation::RestLengths gives without shrinkage or
/// curl).
std::vector<double> SystemRestLengths(const WiltingSimulation& simulation)
{
  std::vector<double> lengths;
  for (const MassSpringSpring& spring : simulation.System().Springs())
  {
    lengths.push_back(spring.restLength);
  }
  return lengths;
}

/// The tip's displacement from `rest` at the end of a run; `tip` is the input point expected to be the tip.
Eigen::Vector3d TipDisplacementAfter(const WiltingInput& in, const WiltingParameters& parameters, int tip)
{
  WiltingSimulation simulation;
  EXPECT_EQ(simulation.Setup(in, parameters), "");
  EXPECT_EQ(simulation.Run(), "");
  EXPECT_EQ(simulation.TipPoint(), tip);
  return simulation.Frames().back().tip - in.points[static_cast<std::size_t>(tip)];
}

TEST(WiltingSimulation, ZeroAsymmetryGivesExactlyTheSymmetricLoads)
{
  const WiltingInput in = Rectangle(4.5, 10.0, 8, 20);
  WiltingParameters p = AsymmetryCase();
  WiltingSimulation simulation;
  ASSERT_EQ(simulation.Setup(in, p), "");
  std::vector<double> force;
  simulation.ExternalForce(0.5, force);
  EXPECT_EQ(force, SymmetricLoads(simulation, p)) << "bit for bit: asymmetry 0 is the model without it";
  // A nonzero asymmetry keeps the total (the leaf is symmetric) and moves (1 + a) : (1 - a) to the +x side.
  p.droopAsymmetry = 0.5;
  p.contractionAsymmetry = -0.25;
  ASSERT_EQ(simulation.Setup(in, p), "");
  simulation.ExternalForce(0.5, force);
  double plus = 0.0, minus = 0.0, total = 0.0, pullPlus = 0.0, pullMinus = 0.0;
  for (std::size_t n = 0; n < simulation.Grid().nodes.size(); ++n)
  {
    const double x = simulation.Grid().nodes[n][0];
    total += force[3 * n + 2];
    // Nodes on the middle column's faces (x = -0.5, 0.5) share loads with the middle voxel; count the outer ones.
    plus += x > 0.75 ? force[3 * n + 2] : 0.0;
    minus += x < -0.75 ? force[3 * n + 2] : 0.0;
    pullPlus += x > 0.75 ? force[3 * n] : 0.0;
    pullMinus += x < -0.75 ? force[3 * n] : 0.0;
  }
  const std::vector<double> symmetric = SymmetricLoads(simulation, AsymmetryCase());
  double symmetricTotal = 0.0;
  for (std::size_t k = 2; k < symmetric.size(); k += 3)
  {
    symmetricTotal += symmetric[k];
  }
  EXPECT_NEAR(total, symmetricTotal, 1e-9 * std::abs(symmetricTotal));
  EXPECT_LT(plus, 0.0);
  EXPECT_NEAR(plus / minus, 1.5 / 0.5, 1e-12) << "droop: (1 + a) / (1 - a) on the outer columns";
  EXPECT_NEAR(-pullPlus / pullMinus, 0.75 / 1.25, 1e-12) << "contraction: (1 + a) / (1 - a)";
  p.droopAsymmetry = 1.01;
  EXPECT_NE(ValidateWilting(p).find("DroopAsymmetry = 1.01 is outside the accepted range [-1, 1]"), std::string::npos);
  p.droopAsymmetry = 0.0;
  p.contractionAsymmetry = std::nan("");
  EXPECT_NE(simulation.Setup(in, p).find("ContractionAsymmetry"), std::string::npos);
}

TEST(WiltingSimulation, AsymmetryMovesTheTipSidewaysAndItsMirrorMirrors)
{
  // More droop on the +x half rolls the leaf about its midvein, +x side down; once the leaf hangs (its tip below
  // the base) that roll swings the tip to -x, away from the side that wilts more (here -0.028 cm at a tip 2 cm
  // down; the mirror run agrees to 1e-15). -a gives the mirror-image run.
  const WiltingInput in = Rectangle(4.5, 10.0, 8, 20);
  WiltingParameters p = AsymmetryCase();
  p.contractionForce = 0.0;
  p.droopForce = 6.0;
  Eigen::Vector3d tip[3];
  double rightMinusLeft = 0.0;
  const double asymmetry[3] = { 0.0, 0.5, -0.5 };
  for (int k = 0; k < 3; ++k)
  {
    p.droopAsymmetry = asymmetry[k];
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, p), "");
    ASSERT_EQ(simulation.Run(), "");
    tip[k] = simulation.Frames().back().tip;
    if (k == 1)
    {
      const std::vector<Eigen::Vector3d> x = simulation.PointPositions(simulation.Frames().size() - 1);
      rightMinusLeft = x[20 * 9 + 8][2] - x[20 * 9 + 0][2]; // the apex row's +x and -x corners
    }
  }
  EXPECT_NEAR(tip[0][0], 0.0, 1e-9) << "symmetric loads keep the tip on the midvein";
  EXPECT_LT(tip[1][2], -1.0) << "the leaf droops";
  EXPECT_LT(rightMinusLeft, -0.05) << "a > 0: the +x side is lower";
  EXPECT_LT(tip[1][0], -0.01) << "a > 0: the tip swings to -x";
  EXPECT_NEAR(tip[2][0], -tip[1][0], 1e-9) << "-a: the mirror image";
  EXPECT_NEAR(tip[2][1], tip[1][1], 1e-9);
  EXPECT_NEAR(tip[2][2], tip[1][2], 1e-9);
}

TEST(WiltingSimulation, PetioleHoldsTheBladeAtItsEndAndLetsItRoll)
{
  // The symmetric rectangle on a 2 cm petiole one voxel wide (the base x = 0 is the middle column's centre), held
  // by its end face only (AnchorRadius 0). Uneven droop (DroopAsymmetry 0.5) twists the petiole: the blade rolls
  // +x side down while it is still nearly flat, which a blade held at its base cannot do.
  const WiltingInput in = Rectangle(4.5, 10.0, 8, 20);
  WiltingParameters p = AsymmetryCase();
  p.contractionForce = 0.0;
  p.droopForce = 6.0;
  p.loadProfile = WiltingLoadProfile::Ramp;
  p.loadTime = 1.0;
  p.materials[WiltingPetiole] = { 0.05, 5000.0, 0.0 };
  p.petioleLength = 2.0;
  p.anchorRadius = 0.0;
  const int rowAt = 5 * 9; // the input points' row v = 0.25: its -x and +x corners are rowAt and rowAt + 8
  double roll[2] = { 0.0, 0.0 };
  Eigen::Vector3d tip[3];
  const double asymmetry[3] = { 0.0, 0.5, -0.5 };
  for (int k = 0; k < 3; ++k)
  {
    p.droopAsymmetry = asymmetry[k];
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, p), "");
    EXPECT_EQ(simulation.Petiole().voxels, 2);
    std::size_t fixed = 0;
    for (std::size_t n = 0; n < simulation.System().NodeCount(); ++n)
    {
      fixed += simulation.System().IsFixed(n) ? 1 : 0;
    }
    EXPECT_EQ(fixed, 4u) << "only the end face is held";
    ASSERT_EQ(simulation.Run(), "");
    const std::vector<WiltingFrame>& frames = simulation.Frames();
    for (int node : simulation.Petiole().endNodes)
    {
      EXPECT_EQ(frames.back().q[3 * static_cast<std::size_t>(node) + 2], 0.0);
    }
    const std::vector<Eigen::Vector3d> x = simulation.PointPositions(1);
    if (k == 0)
    {
      EXPECT_LT(x[4][2], -1e-3) << "the base itself drops: the petiole bends";
      EXPECT_NEAR(frames.back().tip[0], 0.0, 1e-9) << "symmetric loads keep the tip on the midvein";
    }
    if (k == 1)
    {
      roll[0] = x[rowAt + 8][2] - x[rowAt][2];
    }
    tip[k] = frames.back().tip;
  }
  EXPECT_NEAR(tip[2][0], -tip[1][0], 1e-9) << "-a: the mirror image";
  EXPECT_NEAR(tip[2][2], tip[1][2], 1e-9);
  // The same leaf held at its base (no petiole, AnchorRadius 1.5 as the other tests).
  p.petioleLength = 0.0;
  p.anchorRadius = 1.5;
  p.droopAsymmetry = 0.5;
  WiltingSimulation held;
  ASSERT_EQ(held.Setup(in, p), "");
  ASSERT_EQ(held.Run(), "");
  const std::vector<Eigen::Vector3d> x = held.PointPositions(1);
  roll[1] = x[rowAt + 8][2] - x[rowAt][2];
  EXPECT_LT(roll[0], -0.05) << "on a petiole the +x side drops";
  EXPECT_LT(roll[0], 3.0 * roll[1]) << "three times more than held at the base (" << roll[0] << " vs " << roll[1]
                                    << ")";
  p.petioleLength = -1.0;
  EXPECT_NE(ValidateWilting(p).find("PetioleLength = -1 is outside the accepted range [0, 10000]"), std::string::npos);
}

TEST(WiltingSimulation, ShrinkageShortensTheLeafInPlaneAndItsAsymmetryBendsItSideways)
{
  // Shrinkage shortens every lamina spring: a flat leaf, its two faces shrinking alike, shortens towards its
  // anchored base and stays in its plane (a contraction on the bottom nodes curls it down instead); without other
  // loads the free leaf takes the shrunk rest shape, its tip e times its distance from the anchor closer. 5 % is
  // far beyond what explicit pulls along the springs would survive at this time step: the rest lengths are implicit.
  // More shrinkage on the +x half makes that half the concave side of a bend in the plane: the tip moves to +x,
  // still flat; -a is the mirror image.
  const WiltingInput in = Rectangle(4.5, 10.0, 8, 20);
  WiltingParameters p = AsymmetryCase();
  p.droopForce = 0.0;
  p.contractionForce = 0.0;
  p.contractionTarget = WiltingContractionTarget::Base;
  const auto tipAfter = [&](const WiltingParameters& parameters) {
    return TipDisplacementAfter(in, parameters, 20 * 9 + 4);
  };
  {
    // Without shrinkage the integrator keeps the system's rest lengths (the model without it, bit for bit); with
    // it, at full load (Constant profile), every spring is (1 - e) times as long (no petiole voxels here, and every
    // voxel shrinks alike, so a shared spring's stiffness-weighted strain is e too).
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, p), "");
    const std::vector<double> own = SystemRestLengths(simulation);
    EXPECT_EQ(simulation.RestLengths(0.5), own);
    WiltingParameters shrinking = p;
    shrinking.shrinkageStrain = 0.05;
    ASSERT_EQ(simulation.Setup(in, shrinking), "");
    const std::vector<double> shrunkLengths = simulation.RestLengths(0.5);
    ASSERT_EQ(shrunkLengths.size(), own.size());
    for (std::size_t e = 0; e < own.size(); ++e)
    {
      EXPECT_NEAR(shrunkLengths[e], 0.95 * own[e], 1e-12 * own[e]) << "spring " << e;
    }
    // ShrinkageTime: its own profile (Ramp over 4 s: a quarter at 1 s, while the contraction's 1 s is complete).
    shrinking.loadProfile = WiltingLoadProfile::Ramp;
    shrinking.contractionTime = 1.0;
    shrinking.shrinkageTime = 4.0;
    ASSERT_EQ(simulation.Setup(in, shrinking), "");
    const std::vector<double> quarter = simulation.RestLengths(1.0);
    for (std::size_t e = 0; e < own.size(); ++e)
    {
      EXPECT_NEAR(quarter[e], (1.0 - 0.25 * 0.05) * own[e], 1e-12 * own[e]) << "spring " << e;
    }
    shrinking.shrinkageTime = -1.0;
    EXPECT_NE(
      ValidateWilting(shrinking).find("ShrinkageTime = -1 is outside the accepted range [0, inf)"), std::string::npos);
  }
  p.shrinkageStrain = 0.05;
  const Eigen::Vector3d shrunk = tipAfter(p);
  // The free part, from the held voxels (whole voxels whose centre is within 1.5 cm of the base: up to y = 2 on the
  // midvein) to the tip at y = 10, is 8 to 10 cm long (7.9: a margin for the discretisation); the tip comes e times
  // that closer (-0.429 cm).
  EXPECT_LT(shrunk[1], -0.05 * 7.9) << "towards the base, by e times the free length";
  EXPECT_GT(shrunk[1], -0.05 * 10.0);
  EXPECT_NEAR(shrunk[0], 0.0, 1e-9) << "a symmetric leaf shrinks symmetrically";
  EXPECT_NEAR(shrunk[2], 0.0, 1e-8) << "in the plane: both faces are pulled alike";
  WiltingParameters curl = p;
  curl.shrinkageStrain = 0.0;
  curl.contractionForce = 40.0;
  EXPECT_LT(tipAfter(curl)[2], -0.02) << "the contraction on the bottom nodes curls the tip down";
  p.shrinkageAsymmetry = 0.5;
  const Eigen::Vector3d plus = tipAfter(p);
  p.shrinkageAsymmetry = -0.5;
  const Eigen::Vector3d minus = tipAfter(p);
  EXPECT_GT(plus[0], 0.01) << "towards the half that shrinks more";
  EXPECT_NEAR(plus[2], 0.0, 1e-8) << "still in the plane";
  EXPECT_NEAR(minus[0], -plus[0], 1e-9) << "-a: the mirror image";
  EXPECT_NEAR(minus[1], plus[1], 1e-9);
  p.shrinkageAsymmetry = -1.5;
  EXPECT_NE(
    ValidateWilting(p).find("ShrinkageAsymmetry = -1.5 is outside the accepted range [-1, 1]"), std::string::npos);
  p.shrinkageAsymmetry = 0.0;
  p.shrinkageStrain = 0.45;
  EXPECT_NE(
    ValidateWilting(p).find("ShrinkageStrain = 0.45 is outside the accepted range [-0.4, 0.4]"), std::string::npos);
}

TEST(WiltingSimulation, CurlBendsTheLeafIntoItsArcAndRelaxes)
{
  // CurlStrain d: the lower face's springs (1 - d/2) L, the upper face's (1 + d/2) L, the springs joining the faces
  // unchanged, on the contraction's profile minus r times the relaxation's. Without other loads a narrow free
  // strip takes the rest shape those lengths describe: a circular arc of curvature d / h (h the voxel edge, the
  // plate's thickness) from its anchored part, apex down for d > 0, up for -d; no net force, so nothing else moves.
  const WiltingInput in = Rectangle(1.0, 10.0, 2, 20);
  WiltingParameters p = AsymmetryCase();
  p.droopForce = 0.0;
  p.contractionForce = 0.0;
  p.newmark.rayleighMass = 40.0;
  p.duration = 3.0;
  p.frameInterval = 0.5;
  {
    // Rest lengths: d = 0 keeps the system's exactly; d = 0.08 at full curl moves the bottom and top faces by
    // -+ d/2 and leaves the others; with the Ramp profile, ContractionTime 1 s and the relaxation r = 0.5 over
    // 4 s, the curl factor is 1 - 0.5 (t / 4) once the contraction is complete: 0.875 at 1 s, 0.5 from 4 s.
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, p), "");
    const std::vector<double> own = SystemRestLengths(simulation);
    EXPECT_EQ(simulation.RestLengths(0.5), own);
    WiltingParameters ramp = p;
    ramp.curlStrain = 0.08;
    ramp.loadProfile = WiltingLoadProfile::Ramp;
    ramp.contractionTime = 1.0;
    ramp.curlRelaxation = 0.5;
    ramp.curlRelaxationTime = 4.0;
    ASSERT_EQ(simulation.Setup(in, ramp), "");
    const double z0 = simulation.Grid().origin[2];
    for (const double t : { 1.0, 4.0, 6.0 })
    {
      const double factor = t < 4.0 ? 1.0 - 0.5 * t / 4.0 : 0.5;
      const std::vector<double> lengths = simulation.RestLengths(t);
      int bottom = 0, top = 0;
      for (std::size_t e = 0; e < own.size(); ++e)
      {
        const MassSpringSpring& spring = simulation.System().Springs()[e];
        const double za = simulation.Grid().nodes[static_cast<std::size_t>(spring.a)][2] - z0;
        const double zb = simulation.Grid().nodes[static_cast<std::size_t>(spring.b)][2] - z0;
        const double h = simulation.Grid().h;
        const double face = (za < 0.5 * h && zb < 0.5 * h) ? 0.5 : ((za > 0.5 * h && zb > 0.5 * h) ? -0.5 : 0.0);
        bottom += face > 0.0 ? 1 : 0;
        top += face < 0.0 ? 1 : 0;
        ASSERT_NEAR(lengths[e], own[e] * (1.0 - face * 0.08 * factor), 1e-12 * own[e]) << "spring " << e;
      }
      EXPECT_GT(bottom, 0);
      EXPECT_EQ(top, bottom);
    }
  }
  const auto tipAfter = [&](const WiltingParameters& parameters) {
    return TipDisplacementAfter(in, parameters, 20 * 3 + 1);
  };
  p.curlStrain = 0.1;
  const Eigen::Vector3d down = tipAfter(p);
  // The arc of curvature k = d / h = 0.1 / cm over the free length s (the held voxels are those whose centre lies
  // within 1.5 cm of the base, reaching y = 2, so s is 8 to 10 cm; 7.9: a margin for the discretisation): the tip
  // drops (1 - cos k s) / k, 3.0 to 4.6 cm, and comes s - sin(k s) / k, 0.8 to 1.6 cm, closer to the base.
  const auto drop = [](double s) { return (1.0 - std::cos(0.1 * s)) / 0.1; };
  const auto shortening = [](double s) { return s - std::sin(0.1 * s) / 0.1; };
  EXPECT_LT(down[2], -drop(7.9)) << down.transpose();
  EXPECT_GT(down[2], -drop(10.0)) << down.transpose();
  EXPECT_LT(down[1], -shortening(7.9)) << down.transpose();
  EXPECT_GT(down[1], -shortening(10.0)) << down.transpose();
  EXPECT_NEAR(down[0], 0.0, 1e-9) << "a symmetric strip curls symmetrically";
  p.curlStrain = -0.1;
  const Eigen::Vector3d up = tipAfter(p);
  EXPECT_NEAR(up[2], -down[2], 1e-6 * std::abs(down[2])) << "-d: the mirror image through the leaf's plane";
  EXPECT_NEAR(up[1], down[1], 1e-6 * std::abs(down[1]));
  // Half of it relaxing (r = 0.5 within the run) leaves the arc of half the curvature: a smaller drop.
  p.curlStrain = 0.1;
  p.curlRelaxation = 0.5;
  p.curlRelaxationTime = 0.5;
  const Eigen::Vector3d relaxed = tipAfter(p);
  EXPECT_LT(relaxed[2], -0.4 * drop(7.9)) << relaxed.transpose();
  EXPECT_GT(relaxed[2], -0.6 * drop(10.0)) << relaxed.transpose();
  {
    // CurlTime: the curl rises on its own profile (Ramp over 2 s: half at 1 s, when the contraction's 1 s is done).
    WiltingParameters own = p;
    own.curlRelaxation = 0.0;
    own.loadProfile = WiltingLoadProfile::Ramp;
    own.contractionTime = 1.0;
    own.curlTime = 2.0;
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, own), "");
    const std::vector<double> lengths = simulation.RestLengths(1.0);
    const double z0 = simulation.Grid().origin[2];
    for (std::size_t e = 0; e < lengths.size(); ++e)
    {
      const MassSpringSpring& spring = simulation.System().Springs()[e];
      const bool bottom = simulation.Grid().nodes[static_cast<std::size_t>(spring.a)][2] == z0 &&
        simulation.Grid().nodes[static_cast<std::size_t>(spring.b)][2] == z0;
      if (bottom)
      {
        ASSERT_NEAR(lengths[e], spring.restLength * (1.0 - 0.5 * 0.1 * 0.5), 1e-12) << "spring " << e;
      }
    }
  }
  {
    // Radial: only along the lines from the base. This strip is one voxel column on the midvein, so beyond the
    // base voxel that line is +y: a bottom-face spring along y gets all of d/2, one along x none of it.
    WiltingParameters radial = p;
    radial.curlRelaxation = 0.0;
    radial.curlDirection = WiltingCurlDirection::Radial;
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, radial), "");
    const std::vector<double> lengths = simulation.RestLengths(1.0);
    const VoxelGrid& grid = simulation.Grid();
    int alongX = 0, alongY = 0;
    for (std::size_t e = 0; e < lengths.size(); ++e)
    {
      const MassSpringSpring& spring = simulation.System().Springs()[e];
      const Eigen::Vector3d a = grid.nodes[static_cast<std::size_t>(spring.a)];
      const Eigen::Vector3d b = grid.nodes[static_cast<std::size_t>(spring.b)];
      if (a[2] != grid.origin[2] || b[2] != grid.origin[2] || std::min(a[1], b[1]) < grid.origin[1] + 2.0 * grid.h)
      {
        continue;
      }
      if (a[1] == b[1])
      {
        ++alongX;
        ASSERT_EQ(lengths[e], spring.restLength) << "spring " << e;
      }
      else if (a[0] == b[0])
      {
        ++alongY;
        ASSERT_NEAR(lengths[e], spring.restLength * (1.0 - 0.05), 1e-12) << "spring " << e;
      }
    }
    EXPECT_GT(alongX, 0);
    EXPECT_GT(alongY, 0);
    // Along a strip the radial curl is the isotropic one's arc.
    const Eigen::Vector3d arc = tipAfter(radial);
    EXPECT_LT(arc[2], -drop(7.9)) << arc.transpose();
    EXPECT_GT(arc[2], -drop(10.0)) << arc.transpose();
  }
  p.curlStrain = 0.41;
  EXPECT_NE(ValidateWilting(p).find("CurlStrain = 0.41 is outside the accepted range [-0.4, 0.4]"), std::string::npos);
  p.curlStrain = 0.1;
  p.curlRelaxation = 1.5;
  EXPECT_NE(ValidateWilting(p).find("CurlRelaxation = 1.5 is outside the accepted range [0, 1]"), std::string::npos);
  p.curlRelaxation = 0.0;
  p.curlAsymmetry = -2.0;
  EXPECT_NE(ValidateWilting(p).find("CurlAsymmetry = -2 is outside the accepted range [-1, 1]"), std::string::npos);
  p.curlAsymmetry = 0.0;
  p.curlTime = -1.0;
  EXPECT_NE(ValidateWilting(p).find("CurlTime = -1 is outside the accepted range [0, inf)"), std::string::npos);
}

TEST(WiltingSimulation, DeterministicAcrossRunsAndThreads)
{
  const WiltingInput in = Rectangle(4.0, 10.0, 8, 20);
  WiltingParameters p = DroopOnly();
  ApplyWiltingPreset(WiltingPreset::Cucumber, p);
  p.resolution = 14; // the voxels as thin as the default blade thickness (coarser ones are refused)
  p.duration = 0.5;
  std::vector<double> reference;
  for (int threads : { 1, 2, 1 })
  {
    p.newmark.threads = threads;
    WiltingSimulation simulation;
    ASSERT_EQ(simulation.Setup(in, p), "");
    ASSERT_EQ(simulation.Run(), "");
    if (reference.empty())
    {
      reference = simulation.Frames().back().q;
      EXPECT_GT(std::abs(simulation.Frames().back().tip[2]), 1e-3);
    }
    else
    {
      EXPECT_EQ(simulation.Frames().back().q, reference) << threads << " threads";
    }
  }
}

TEST(WiltingSimulation, LoadProfiles)
{
  EXPECT_EQ(WiltingLoadFactor(WiltingLoadProfile::Constant, 0.0, 4.0), 1.0);
  EXPECT_EQ(WiltingLoadFactor(WiltingLoadProfile::Ramp, 1.0, 4.0), 0.25);
  EXPECT_EQ(WiltingLoadFactor(WiltingLoadProfile::Ramp, 9.0, 4.0), 1.0);
  EXPECT_NEAR(WiltingLoadFactor(WiltingLoadProfile::Sigmoid, 0.0, 4.0), 0.0, 1e-15);
  EXPECT_NEAR(WiltingLoadFactor(WiltingLoadProfile::Sigmoid, 2.0, 4.0), 0.5, 1e-12);
  EXPECT_NEAR(WiltingLoadFactor(WiltingLoadProfile::Sigmoid, 4.0, 4.0), 1.0, 1e-15);
  EXPECT_LT(WiltingLoadFactor(WiltingLoadProfile::Sigmoid, 1.0, 4.0), 0.25) << "slow start";
}

TEST(WiltingSimulation, BadInputAndBlowUp)
{
  const WiltingInput in = Rectangle(4.0, 10.0, 8, 20);
  WiltingSimulation simulation;
  WiltingParameters p = DroopOnly();
  p.resolution = 0;
  EXPECT_NE(simulation.Setup(in, p).find("Resolution"), std::string::npos);
  p = DroopOnly();
  p.newmark.timeStep = std::nan("");
  EXPECT_NE(simulation.Setup(in, p).find("TimeStep"), std::string::npos);
  // A step longer than the run used to give a one-row trajectory and a leaf that never moves.
  p = DroopOnly();
  p.duration = 0.5;
  p.newmark.timeStep = 0.75;
  EXPECT_NE(ValidateWilting(p).find("TimeStep = 0.75 s is longer than Duration = 0.5 s"), std::string::npos);
  p.newmark.timeStep = 0.5;
  EXPECT_EQ(ValidateWilting(p), "");
  p = DroopOnly();
  p.materials[WiltingVein].stiffness = -1.0;
  EXPECT_NE(simulation.Setup(in, p).find("VeinStiffness"), std::string::npos);
  WiltingInput empty = in;
  empty.triangles.clear();
  EXPECT_NE(simulation.Setup(empty, DroopOnly()).find("triangles"), std::string::npos);
  WiltingInput nan = in;
  nan.points[3][0] = std::nan("");
  EXPECT_NE(simulation.Setup(nan, DroopOnly()).find("non-finite"), std::string::npos);
  // A huge load on soft springs with a large step: the guard stops the run and keeps the frames before it.
  p = DroopOnly();
  p.droopForce = 1e7;
  p.loadProfile = WiltingLoadProfile::Constant;
  p.newmark.rayleighMass = 0.0;
  p.newmark.maxIterations = 1;
  ASSERT_EQ(simulation.Setup(in, p), "");
  const std::string error = simulation.Run();
  EXPECT_NE(error.find("blew up at step"), std::string::npos) << error;
  EXPECT_GE(simulation.Frames().size(), 1u);
}

} // namespace
