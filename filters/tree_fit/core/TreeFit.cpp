// SPDX-License-Identifier: GPL-3.0-or-later
// TreeFitFilter's algorithm, the steps put together (TreeFit.h describes the method).
#include "TreeFitInternal.h"

#include <plantmorph/RangeError.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <sstream>
#include <tuple>

namespace plantmorph
{

std::string ValidateTreeFitParameters(const TreeFitParameters& o)
{
  if (!o.up.allFinite() || std::abs(o.up.norm() - 1.0) > 1e-9)
    return "Up must be a unit vector";
  std::string error = CheckRange(std::isfinite(o.outlierSigma) && o.outlierSigma >= 1.0 && o.outlierSigma <= 100.0,
    "OutlierSigma", o.outlierSigma, "[1, 100]");
  if (error.empty())
    error = CheckRange(std::isfinite(o.breastHeight) && o.breastHeight > 0.0 && o.breastHeight <= 1e6, "BreastHeight",
      o.breastHeight, "(0, 1e6]");
  return error;
}

std::vector<std::string> TreeTraitNames()
{
  return { "Height", "DBH", "TrunkVolume", "BranchVolume", "TotalVolume", "TrunkLength", "TotalBranchLength",
    "BranchCount", "BranchesOrder1", "BranchesOrder2", "BranchesOrder3", "BranchesOrder4Plus", "CrownProjectedArea",
    "CrownBaseHeight", "Points", "WoodPoints", "Cylinders", "FitRMS", "Spacing", "Noise", "MeasuredVolumeFraction",
    "WoodHeight" };
}

std::vector<double> TreeTraitValues(const TreeTraits& t)
{
  return { t.height, t.dbh, t.trunkVolume, t.branchVolume, t.totalVolume, t.trunkLength, t.totalBranchLength,
    t.branchCount, t.order1, t.order2, t.order3, t.order4Plus, t.crownProjectedArea, t.crownBaseHeight, t.points,
    t.woodPoints, t.cylinders, t.fitRMS, t.spacing, t.noise, t.measuredVolumeFraction, t.woodHeight };
}

namespace
{
constexpr double MaxRelativeDistance = 0.3; // median |distance| / radius beyond which the points are no wood surface
constexpr int MergePasses = 2; // chains inside other branches merged, the cylinders fitted again, at most this often

/// "" or why the input cannot be a tree before any fitting (sizes, too few points; FitTree checks for NaN).
std::string CheckInput(
  const std::vector<Eigen::Vector3d>& points, const std::vector<int>& woodLabel, std::vector<int>& candidates)
{
  if (!woodLabel.empty() && woodLabel.size() != points.size())
    return "the wood labels do not match the points in number";
  for (std::size_t i = 0; i < points.size(); ++i)
    if (woodLabel.empty() || woodLabel[i] != 0)
      candidates.push_back(static_cast<int>(i));
  if (candidates.size() < static_cast<std::size_t>(MinTreePoints))
  {
    std::ostringstream message;
    message << (woodLabel.empty() ? "" : "wood ") << "points: " << candidates.size() << ", at least " << MinTreePoints
            << " needed";
    return message.str();
  }
  return {};
}

/// Per input point: its cylinder, branch, wood flag and distance to its cylinder's surface; each cylinder's FitRMS.
/// "" or why the points do not lie on the cylinders (a volume of noise).
std::string PointValues(const std::vector<Eigen::Vector3d>& points, const treefit::Wood& wood,
  const std::vector<int>& woodCylinder, TreeFitResult& result)
{
  const std::size_t n = points.size();
  result.pointCylinder.assign(n, -1);
  result.pointBranch.assign(n, -1);
  result.wood.assign(n, 0);
  result.fitDistance.assign(n, std::numeric_limits<double>::quiet_NaN());
  std::vector<double> sum(result.cylinders.size(), 0.0), relative;
  std::vector<int> count(result.cylinders.size(), 0);
  for (std::size_t i = 0; i < wood.points.size(); ++i)
  {
    const int c = woodCylinder[i], id = wood.input[i];
    result.wood[id] = 1;
    if (c < 0)
      continue;
    const TreeCylinder& cyl = result.cylinders[c];
    const Eigen::Vector3d axis = (cyl.end - cyl.start).normalized();
    const double d = (wood.points[i] - cyl.start).cross(axis).norm() - cyl.radius;
    result.pointCylinder[id] = c;
    result.pointBranch[id] = cyl.branch;
    result.fitDistance[id] = d;
    sum[c] += d * d;
    ++count[c];
    relative.push_back(std::abs(d) / cyl.radius);
  }
  for (std::size_t c = 0; c < result.cylinders.size(); ++c)
    result.cylinders[c].fitRMS = count[c] > 0 ? std::sqrt(sum[c] / count[c]) : 0.0;
  const std::size_t mid = relative.size() / 2;
  std::nth_element(relative.begin(), relative.begin() + static_cast<std::ptrdiff_t>(mid), relative.end());
  if (relative.empty() || relative[mid] > MaxRelativeDistance)
  {
    std::ostringstream message;
    message << "the points do not lie on cylinder surfaces (median distance "
            << (relative.empty() ? 0.0 : relative[mid]) << " radii): a volume of scattered points, not a tree";
    return message.str();
  }
  return {};
}
} // namespace

namespace
{
/// The skeleton's leaf sheets (points without a node) are no wood: out of the cleaned wood (whose graph is no longer
/// used), its points' cylinders, and the candidates the tip's height is strung from.
void ReturnToLeaves(
  const std::vector<int>& nodeOf, treefit::Wood& wood, std::vector<int>& woodCylinder, std::vector<int>& candidates)
{
  if (std::find(nodeOf.begin(), nodeOf.end(), -1) == nodeOf.end())
    return;
  std::vector<unsigned char> leaf(*std::max_element(candidates.begin(), candidates.end()) + 1, 0);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < wood.points.size(); ++i)
    if (nodeOf[i] < 0)
      leaf[wood.input[i]] = 1;
    else
    {
      wood.points[kept] = wood.points[i];
      woodCylinder[kept] = woodCylinder[i];
      wood.input[kept++] = wood.input[i];
    }
  wood.points.resize(kept);
  woodCylinder.resize(kept);
  wood.input.resize(kept);
  wood.graph = {};
  wood.geodesic.clear();
  wood.previous.clear();
  candidates.erase(
    std::remove_if(candidates.begin(), candidates.end(), [&](int i) { return leaf[i] != 0; }), candidates.end());
}

/// Step 7 where the scan has leaf points (label 0): the wood points labelled wood that the fit could not connect to
/// the tree (further from it than the gaps it bridges: the leaves hide the twigs between) draw the twigs grown from
/// the cylinders as step 4 left them (`fitted`); step 5 runs again on both for the branches. Without leaf points
/// (a bare scan, or no labels) nothing changes.
std::string GrowTwigs(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& woodLabel,
  const treefit::Wood& wood, const std::vector<TreeCylinder>& fitted, TreeFitResult& result)
{
  if (std::find(woodLabel.begin(), woodLabel.end(), 0) == woodLabel.end())
    return {};
  std::vector<unsigned char> used(woodLabel.size(), 0);
  for (int i : wood.input)
    used[i] = 1;
  std::vector<Eigen::Vector3d> apart;
  for (std::size_t i = 0; i < woodLabel.size(); ++i)
    if (woodLabel[i] != 0 && !used[i])
      apart.push_back(points[i]);
  std::vector<TreeCylinder> cylinders = fitted;
  const double spacing = wood.spacing;
  if (apart.empty() || treefit::GrowHiddenTwigs(apart, spacing, result.cylinders, cylinders) == 0)
    return {};
  TreeFitResult grown;
  grown.cylinders = std::move(cylinders);
  const std::string error = treefit::ModelRadii(spacing, grown, true);
  result.cylinders = std::move(grown.cylinders);
  result.branches = std::move(grown.branches);
  result.traits.noise = grown.traits.noise;
  return error;
}

/// The fit on the points in their canonical order (FitTree sorts them first).
TreeFitResult FitSorted(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& woodLabel,
  const TreeFitParameters& options, const ParallelFor& parallel)
{
  TreeFitResult result;
  std::vector<int> candidates;
  result.error = ValidateTreeFitParameters(options);
  if (result.error.empty())
    result.error = CheckInput(points, woodLabel, candidates);
  treefit::Wood wood;
  std::vector<int> others; // the points labelled leaf
  for (std::size_t i = 0; i < woodLabel.size(); ++i)
    if (woodLabel[i] == 0)
      others.push_back(static_cast<int>(i));
  if (result.error.empty())
    result.error = treefit::CleanAndConnect(points, candidates, others, options, parallel, wood);
  wood.leafLabelled = !others.empty();
  std::vector<int> woodCylinder;
  std::vector<TreeCylinder> fitted; // the last fit's cylinders before step 5
  if (result.error.empty())
  {
    treefit::Skeleton skeleton = treefit::BuildSkeleton(wood);
    result.error = treefit::FitCylinders(wood, skeleton, options, parallel, result, woodCylinder, &fitted);
    for (int pass = 0; pass < MergePasses && result.error.empty() && treefit::MergeInsideChains(wood, result, skeleton);
         ++pass)
    {
      result = TreeFitResult();
      result.error = treefit::FitCylinders(wood, skeleton, options, parallel, result, woodCylinder, &fitted);
    }
    if (result.error.empty() && treefit::ReturnOffSurfaceChains(wood, result, woodCylinder, skeleton))
    {
      result = TreeFitResult();
      result.error = treefit::FitCylinders(wood, skeleton, options, parallel, result, woodCylinder, &fitted);
    }
    if (result.error.empty())
      ReturnToLeaves(skeleton.nodeOf, wood, woodCylinder, candidates);
  }
  if (result.error.empty())
    result.error = GrowTwigs(points, woodLabel, wood, fitted, result);
  if (result.error.empty() && wood.leafLabelled)
    treefit::NarrowLeafFilledCylinders(points, woodLabel, wood.spacing, result);
  if (result.error.empty())
    result.error = PointValues(points, wood, woodCylinder, result);
  if (!result.error.empty())
  {
    TreeFitResult failed;
    failed.error = result.error;
    return failed;
  }
  treefit::ComputeTraits(points, candidates, wood, options, result);
  return result;
}

/// Per point, the Morton code of its cell in a grid of 1024 cells a side over the points' bounding box (which does not
/// depend on their order): sorting by it first keeps points near each other in space near each other in memory, so
/// that the neighbour searches, the graph and the geodesic distances of 10^6 points do not miss the cache at every
/// step (in the coordinates' order, a point's neighbours lay a whole slab of the cloud away).
std::vector<std::uint32_t> MortonCells(const std::vector<Eigen::Vector3d>& points)
{
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& p : points)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double side = std::max((hi - lo).maxCoeff(), 1e-300) / 1023.0;
  std::vector<std::uint32_t> code(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    std::uint32_t c = 0;
    for (int a = 0; a < 3; ++a)
    {
      const auto v = static_cast<std::uint32_t>(std::clamp((points[i][a] - lo[a]) / side, 0.0, 1023.0));
      for (int bit = 0; bit < 10; ++bit)
        c |= ((v >> bit) & 1u) << (3 * bit + a);
    }
    code[i] = c;
  }
  return code;
}

/// Per-point results put back in the input's order: sorted[k] is input point order[k].
template <typename T>
void Unsort(std::vector<T>& values, const std::vector<std::size_t>& order)
{
  if (values.empty())
    return;
  std::vector<T> input(values.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    input[order[k]] = values[k];
  values = std::move(input);
}
} // namespace

TreeFitResult FitTree(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& woodLabel,
  const TreeFitParameters& options, const ParallelFor& parallel)
{
  // The canonical order (Morton cell, coordinates, then label, then input position for exact duplicates, which give
  // the same result either way): the fit does not depend on the order the points come in (a cloud gathered from MPI
  // ranks, a file written in another order), and points near each other are near each other in memory.
  for (std::size_t i = 0; i < points.size(); ++i) // before sorting: the message names the input's point
    if (!points[i].allFinite())
    {
      TreeFitResult failed;
      std::ostringstream message;
      message << "point " << i << " has a coordinate that is not a finite number (NaN or infinite)";
      failed.error = message.str();
      return failed;
    }
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{ 0 });
  const bool labelled = woodLabel.size() == points.size();
  const std::vector<std::uint32_t> cell = MortonCells(points);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const auto key = [&](std::size_t i) {
      return std::make_tuple(cell[i], points[i].x(), points[i].y(), points[i].z(), labelled ? woodLabel[i] : 0, i);
    };
    return key(a) < key(b);
  });
  std::vector<Eigen::Vector3d> sorted(points.size());
  std::vector<int> labels(labelled ? points.size() : 0);
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    sorted[k] = points[order[k]];
    if (labelled)
      labels[k] = woodLabel[order[k]];
  }
  TreeFitResult result = FitSorted(sorted, labelled ? labels : woodLabel, options, parallel);
  Unsort(result.pointCylinder, order);
  Unsort(result.pointBranch, order);
  Unsort(result.wood, order);
  Unsort(result.fitDistance, order);
  return result;
}

} // namespace plantmorph
