// SPDX-License-Identifier: GPL-3.0-or-later
// Steps 5-6 of the tree fit (TreeFit.h): which fitted radii the points support, the growth-length (pipe model)
// radius everywhere else, and the branches.
#include "TreeFitInternal.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph
{
namespace treefit
{
namespace
{
constexpr int MinMeasuredPoints = 12;
constexpr double MinCoverage = 150.0;   // degrees
constexpr double MinArcSpacings = 5.0;  // the arc seen, in spacings
constexpr double MinRadiusNoise = 3.0;  // noise deviations
constexpr double MaxScaleRadius = 0.35; // residual scale / radius
constexpr double ModelFactor = 2.0;     // a measured radius this far from the model is not trusted...
constexpr double StrongCoverage = 240.0, StrongRadiusNoise = 10.0; // ...unless the fit is this good
constexpr int MinStrongPoints = 50;
constexpr double ContinueShare = 0.25; // of the heaviest child's carried volume
constexpr double ContinueAngle = 20.0; // degrees: no child turning more continues its parent's branch
constexpr double SameDirection = 0.02; // cosines this close: the heavier child continues

double Median(std::vector<double> values)
{
  if (values.empty())
    return std::numeric_limits<double>::quiet_NaN();
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  return values[mid];
}

/// log r = a + b log GL fitted (Huber IRLS, weights sqrt(points)) to the measured cylinders; b = 1/2 (the pipe model:
/// area proportional to what is carried) when they do not span a factor 3 of growth length or are fewer than 5.
void FitModel(const std::vector<TreeCylinder>& cylinders, double& a, double& b)
{
  std::vector<double> x, y, w;
  for (const auto& c : cylinders)
    if (c.measured)
    {
      x.push_back(std::log(c.growthLength));
      y.push_back(std::log(c.fittedRadius));
      w.push_back(std::sqrt(static_cast<double>(c.points)));
    }
  b = 0.5;
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  const bool spans = x.size() >= 5 && *hi - *lo >= std::log(3.0);
  std::vector<double> weight = w;
  for (int iteration = 0; iteration < 20; ++iteration)
  {
    if (spans)
    {
      double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (std::size_t i = 0; i < x.size(); ++i)
      {
        sw += weight[i], sx += weight[i] * x[i], sy += weight[i] * y[i];
        sxx += weight[i] * x[i] * x[i], sxy += weight[i] * x[i] * y[i];
      }
      const double det = sw * sxx - sx * sx;
      b = det > 0 ? std::clamp((sw * sxy - sx * sy) / det, 0.25, 1.0) : 0.5;
    }
    double sw = 0, sr = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      sw += weight[i], sr += weight[i] * (y[i] - b * x[i]);
    a = sr / sw;
    std::vector<double> absolute;
    for (std::size_t i = 0; i < x.size(); ++i)
      absolute.push_back(std::abs(y[i] - a - b * x[i]));
    const double k = 1.345 * std::max(1.4826 * Median(absolute), 0.05);
    for (std::size_t i = 0; i < x.size(); ++i)
      weight[i] = w[i] * std::min(1.0, k / std::max(absolute[i], 1e-12));
  }
}

/// Branches: the trunk from the base, at every fork the child carrying the most volume continues its parent's branch.
void AssignBranches(TreeFitResult& result, const std::vector<double>& radius)
{
  auto& cylinders = result.cylinders;
  const std::size_t n = cylinders.size();
  std::vector<double> carried(n, 0.0);
  for (std::size_t k = n; k-- > 0;)
  {
    carried[k] += M_PI * radius[k] * radius[k] * cylinders[k].length;
    if (cylinders[k].parent >= 0)
      carried[cylinders[k].parent] += carried[k];
  }
  // At a fork the branch goes on into the straightest child among those carrying at least ContinueShare of what the
  // heaviest carries (a leader goes on past a heavy lateral) and turning less than ContinueAngle (children that all
  // diverge, a sympodial fork, end the branch); within a few degrees, the heavier. Directions are
  // chords over about four parent radii: the parent's from below the fork (the cylinders at a fork hold both branches
  // and lean towards the child), each child's forward along its straightest path.
  std::vector<int> heavy(n, -1), straight(n, -1), forks(n, 0);
  std::vector<double> straightCosine(n, -2.0);
  for (std::size_t k = 0; k < n; ++k)
  {
    const int p = cylinders[k].parent;
    if (p < 0)
      continue;
    ++forks[p];
    if (heavy[p] < 0 || carried[k] > carried[heavy[p]])
      heavy[p] = static_cast<int>(k);
    const double cosine =
      (cylinders[p].end - cylinders[p].start).normalized().dot((cylinders[k].end - cylinders[k].start).normalized());
    if (cosine > straightCosine[p])
    {
      straightCosine[p] = cosine;
      straight[p] = static_cast<int>(k);
    }
  }
  std::vector<int> continuing(n, -1);
  std::vector<double> bestCosine(n, -2.0);
  for (std::size_t k = 0; k < n; ++k)
  {
    const int p = cylinders[k].parent;
    if (p < 0 || carried[k] < ContinueShare * carried[heavy[p]])
      continue;
    const double reach = std::max(4.0 * radius[p], 2.0 * cylinders[p].length);
    // The parent's direction from below the junction: between half a reach and two reaches back from the fork.
    int near = cylinders[p].parent >= 0 ? cylinders[p].parent : p, far = p, ahead = static_cast<int>(k);
    for (double along = cylinders[p].length; cylinders[near].parent >= 0 && along < 0.5 * reach;)
      along += cylinders[near = cylinders[near].parent].length;
    far = near;
    for (double along = 0; cylinders[far].parent >= 0 && along < 1.5 * reach;)
      along += cylinders[far = cylinders[far].parent].length;
    for (double along = cylinders[k].length; straight[ahead] >= 0 && along < reach;)
      along += cylinders[ahead = straight[ahead]].length;
    Eigen::Vector3d dp = cylinders[near].end - cylinders[far].start;
    dp = dp.norm() > 0 ? dp.normalized() : (cylinders[p].end - cylinders[p].start).normalized().eval();
    const double cosine = dp.dot((cylinders[ahead].end - cylinders[k].start).normalized());
    if (forks[p] > 1 && cosine < std::cos(ContinueAngle * M_PI / 180.0))
      continue; // a fork into diverging children (sympodial): the branch ends here
    const int best = continuing[p];
    if (best < 0 || cosine > bestCosine[p] + SameDirection ||
      (cosine > bestCosine[p] - SameDirection && carried[k] > carried[best]))
    {
      bestCosine[p] = best >= 0 && cosine <= bestCosine[p] + SameDirection ? std::max(cosine, bestCosine[p]) : cosine;
      continuing[p] = static_cast<int>(k);
    }
  }
  result.branches.clear();
  for (std::size_t k = 0; k < n; ++k)
  {
    TreeCylinder& c = cylinders[k];
    if (c.parent >= 0 && continuing[c.parent] == static_cast<int>(k))
    {
      c.branch = cylinders[c.parent].branch;
      c.order = cylinders[c.parent].order;
    }
    else
    {
      TreeBranchRow row;
      row.id = static_cast<int>(result.branches.size());
      row.parent = c.parent >= 0 ? cylinders[c.parent].branch : -1;
      row.order = c.parent >= 0 ? cylinders[c.parent].order + 1 : 0;
      result.branches.push_back(row);
      c.branch = row.id;
      c.order = row.order;
    }
    result.branches[c.branch].cylinders.push_back(static_cast<int>(k));
  }
}

double SegmentDistance(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((x - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return (x - a - t * ab).norm();
}

/// A child branch leaves the level sets only where its surface parts from its parent's, some way past the fork: its
/// first cylinder is extended back along its axis to the parent's surface (the parent's cylinders near the fork).
void SeatBranches(TreeFitResult& result)
{
  auto& cylinders = result.cylinders;
  std::vector<std::vector<int>> children(cylinders.size());
  for (std::size_t k = 0; k < cylinders.size(); ++k)
    if (cylinders[k].parent >= 0)
      children[cylinders[k].parent].push_back(static_cast<int>(k));
  for (const TreeBranchRow& branch : result.branches)
  {
    TreeCylinder& first = cylinders[branch.cylinders.front()];
    if (first.parent < 0)
      continue;
    std::vector<int> near;
    for (int q = first.parent, back = 0; q >= 0 && back < 4; q = cylinders[q].parent, ++back)
      near.push_back(q);
    for (int q = first.parent, ahead = 0; ahead < 3;)
    {
      int next = -1;
      for (int c : children[q])
        if (cylinders[c].branch == cylinders[first.parent].branch)
          next = c;
      if (next < 0)
        break;
      near.push_back(next);
      q = next;
      ++ahead;
    }
    const Eigen::Vector3d d = (first.end - first.start).normalized();
    const double reach = 2.0 * std::max(first.length, 3.0 * cylinders[first.parent].radius);
    const double step = std::max(reach / 200.0, 1e-9);
    for (double t = 0; t <= reach; t += step)
    {
      const Eigen::Vector3d x = first.start - t * d;
      const bool inside = std::any_of(near.begin(), near.end(),
        [&](int q) { return SegmentDistance(x, cylinders[q].start, cylinders[q].end) <= cylinders[q].radius; });
      if (inside)
      {
        first.start = x;
        first.length += t;
        break;
      }
    }
  }
}
} // namespace

std::string ModelRadii(double spacing, TreeFitResult& result)
{
  auto& cylinders = result.cylinders;
  const std::size_t n = cylinders.size();
  // The scan's noise: the residual scale of the well-covered fits.
  std::vector<double> scales, all;
  for (const auto& c : cylinders)
    if (std::isfinite(c.fittedRadius))
    {
      all.push_back(c.fitRMS);
      if (c.points >= 30 && c.coverage >= 180.0)
        scales.push_back(c.fitRMS);
    }
  double noise = !scales.empty() ? Median(scales) : !all.empty() ? Median(all) : 0.5 * spacing;
  noise = std::max(noise, 1e-3 * spacing);
  result.traits.noise = noise;
  for (auto& c : cylinders)
  {
    const double r = c.fittedRadius;
    c.measured = std::isfinite(r) && c.points >= MinMeasuredPoints && c.coverage >= MinCoverage &&
      r * c.coverage * M_PI / 180.0 >= MinArcSpacings * spacing && r >= MinRadiusNoise * noise &&
      c.fitRMS <= MaxScaleRadius * r;
  }
  for (std::size_t k = n; k-- > 0;)
  {
    cylinders[k].growthLength += std::max(cylinders[k].length, 1e-12);
    if (cylinders[k].parent >= 0)
      cylinders[cylinders[k].parent].growthLength += cylinders[k].growthLength;
  }
  double a = 0, b = 0.5;
  for (int round = 0; round < 3; ++round)
  {
    if (std::none_of(cylinders.begin(), cylinders.end(), [](const TreeCylinder& c) { return c.measured; }))
      return "no part of the cloud has points enough to measure a radius: too sparse, too noisy, or not a tree";
    FitModel(cylinders, a, b);
    for (auto& c : cylinders)
    {
      if (!c.measured)
        continue;
      const double model = std::exp(a + b * std::log(c.growthLength));
      const double ratio = c.fittedRadius / model;
      const bool strong =
        c.coverage >= StrongCoverage && c.points >= MinStrongPoints && c.fittedRadius >= StrongRadiusNoise * noise;
      if (!strong && (ratio > ModelFactor || ratio < 1.0 / ModelFactor))
        c.measured = false;
    }
  }
  std::vector<double> model(n), first(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    model[k] = std::exp(a + b * std::log(cylinders[k].growthLength));
    first[k] = cylinders[k].measured ? cylinders[k].fittedRadius : model[k];
  }
  AssignBranches(result, first);
  // Each branch's level: the geometric mean of its measured / model ratios, else its parent branch's.
  std::vector<double> level(result.branches.size(), 1.0);
  for (const auto& branch : result.branches)
  {
    double sum = 0, count = 0;
    for (int k : branch.cylinders)
      if (cylinders[k].measured)
      {
        sum += std::log(cylinders[k].fittedRadius / model[k]);
        count += 1;
      }
    level[branch.id] = count > 0 ? std::exp(std::clamp(sum / count, -std::log(ModelFactor), std::log(ModelFactor)))
                                 : (branch.parent >= 0 ? level[branch.parent] : 1.0);
  }
  for (std::size_t k = 0; k < n; ++k)
  {
    TreeCylinder& c = cylinders[k];
    if (c.measured)
      c.radius = c.fittedRadius;
    else
    {
      c.radius = level[c.branch] * model[k];
      if (c.parent >= 0)
        c.radius = std::min(c.radius, cylinders[c.parent].radius); // no modelled cylinder wider than what carries it
    }
  }
  SeatBranches(result);
  return {};
}

} // namespace treefit
} // namespace plantmorph
