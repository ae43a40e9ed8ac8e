// SPDX-License-Identifier: GPL-3.0-or-later
// A leaf's base at the end of its midvein nearer its plant's wood (LeafPlant.h, OrientByWood).
#include "LeafPlant.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph
{
namespace
{
/// The smallest wood distance among the points within `reach` of `end` (infinity when none has one).
double WoodNear(const Eigen::Vector3d& end, const std::vector<Eigen::Vector3d>& points,
  const std::vector<double>& woodDistance, double reach)
{
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i)
    if (std::isfinite(woodDistance[i]) && (points[i] - end).squaredNorm() <= reach * reach)
      nearest = std::min(nearest, woodDistance[i]);
  return nearest;
}
} // namespace

WoodEnd EndNearerTheWood(
  const LeafFitResult& fit, const std::vector<Eigen::Vector3d>& points, const std::vector<double>& woodDistance)
{
  if (!fit.error.empty() || fit.midvein.size() < 2 || woodDistance.size() != points.size())
    return WoodEnd::Unknown;
  const double reach = WoodEndReach * fit.traits.length;
  const double base = WoodNear(fit.points[static_cast<std::size_t>(fit.midvein.front())], points, woodDistance, reach);
  const double apex = WoodNear(fit.points[static_cast<std::size_t>(fit.midvein.back())], points, woodDistance, reach);
  if (!std::isfinite(base) || !std::isfinite(apex))
    return WoodEnd::Unknown;
  const double margin = WoodEndMargin * fit.traits.length;
  if (base - apex > margin)
    return WoodEnd::Apex;
  if (apex - base > margin)
    return WoodEnd::Base;
  return WoodEnd::Unknown;
}

int OrientByWood(const std::vector<std::vector<Eigen::Vector3d>>& leaves,
  const std::vector<std::vector<double>>& woodDistance, const LeafFitParameters& options,
  std::vector<LeafFitResult>& fits, const ParallelFor& parallel)
{
  if (options.basePoint || options.apexPoint || woodDistance.size() != leaves.size())
    return 0;
  std::vector<std::size_t> turn;
  for (std::size_t k = 0; k < fits.size(); ++k)
  {
    if (!fits[k].error.empty() || fits[k].traits.baseFrom == BaseFromPoint)
      continue;
    const WoodEnd end = EndNearerTheWood(fits[k], leaves[k], woodDistance[k]);
    if (end == WoodEnd::Apex)
      turn.push_back(k);
    else if (end == WoodEnd::Base && fits[k].traits.baseFrom == BaseFromGuess)
    {
      fits[k].traits.baseFrom = BaseFromWood; // the guess is the wood's end
      fits[k].baseGuess = BaseGuess::None;
    }
  }
  std::vector<LeafFitResult> again(turn.size());
  parallel(turn.size(), [&](std::size_t begin, std::size_t stop) {
    for (std::size_t j = begin; j < stop; ++j)
    {
      const LeafFitResult& fit = fits[turn[j]];
      LeafFitParameters turned = options;
      turned.basePoint = fit.points[static_cast<std::size_t>(fit.midvein.back())];
      again[j] = FitLeaf(leaves[turn[j]], turned);
    }
  });
  int turnedCount = 0;
  for (std::size_t j = 0; j < turn.size(); ++j)
    if (again[j].error.empty()) // else the first fit stays
    {
      fits[turn[j]] = std::move(again[j]);
      fits[turn[j]].traits.baseFrom = BaseFromWood;
      ++turnedCount;
    }
  return turnedCount;
}

} // namespace plantmorph
