// SPDX-License-Identifier: GPL-3.0-or-later
// A leaf's base from its plant's wood: the end of its midvein nearer the wood, or where the leaf meets it (LeafPlant.h,
// OrientByWood).
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

std::optional<std::size_t> WoodBasePoint(
  const std::vector<Eigen::Vector3d>& points, const std::vector<double>& woodDistance)
{
  if (points.empty() || woodDistance.size() != points.size())
    return std::nullopt;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points)
    centre += p;
  centre /= static_cast<double>(points.size());
  std::optional<std::size_t> best;
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const double here = LeafBaseScore(woodDistance[i], (points[i] - centre).norm());
    if (std::isfinite(here) && here < least)
    {
      least = here;
      best = i;
    }
  }
  return best;
}

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

namespace
{
/// Where a leaf is fitted again from, by its wood (OrientByWood): a base the shape guessed, or put at a petiole's
/// junction, moves to the leaf's point near the wood at an end of the leaf (WoodBasePoint), unless the wood tells the
/// midvein's ends apart and that point lies by one of them; else an apex end nearer the wood than the base end
/// becomes the base. Nothing when the fit stands; a guessed base the wood's end confirms is then marked so.
std::optional<Eigen::Vector3d> BaseByWood(
  LeafFitResult& fit, const std::vector<Eigen::Vector3d>& points, const std::vector<double>& woodDistance)
{
  const WoodEnd end = EndNearerTheWood(fit, points, woodDistance);
  if (fit.traits.baseFrom == BaseFromGuess || fit.traits.baseFrom == BaseFromPetiole)
  {
    const std::optional<std::size_t> wood = WoodBasePoint(points, woodDistance);
    const auto byAnEnd = [&](const Eigen::Vector3d& at) {
      const double reach = WoodBaseEndReach * fit.traits.length;
      return (fit.points[static_cast<std::size_t>(fit.midvein.front())] - at).norm() <= reach ||
        (fit.points[static_cast<std::size_t>(fit.midvein.back())] - at).norm() <= reach;
    };
    if (wood && (end == WoodEnd::Unknown || !byAnEnd(points[*wood])))
      return points[*wood];
  }
  if (end == WoodEnd::Apex)
    return fit.points[static_cast<std::size_t>(fit.midvein.back())];
  if (end == WoodEnd::Base && fit.traits.baseFrom == BaseFromGuess)
  {
    fit.traits.baseFrom = BaseFromWood; // the guess is the wood's end
    fit.baseGuess = BaseGuess::None;
  }
  return std::nullopt;
}
} // namespace

int OrientByWood(const std::vector<std::vector<Eigen::Vector3d>>& leaves,
  const std::vector<std::vector<double>>& woodDistance, const LeafFitParameters& options,
  std::vector<LeafFitResult>& fits, const ParallelFor& parallel)
{
  if (options.basePoint || options.apexPoint || woodDistance.size() != leaves.size())
    return 0;
  std::vector<std::size_t> turn;
  std::vector<Eigen::Vector3d> turnBase;
  for (std::size_t k = 0; k < fits.size(); ++k)
  {
    if (!fits[k].error.empty() || fits[k].traits.baseFrom == BaseFromPoint)
      continue;
    if (const std::optional<Eigen::Vector3d> base = BaseByWood(fits[k], leaves[k], woodDistance[k]))
    {
      turn.push_back(k);
      turnBase.push_back(*base);
    }
  }
  std::vector<LeafFitResult> again(turn.size());
  parallel(turn.size(), [&](std::size_t begin, std::size_t stop) {
    for (std::size_t j = begin; j < stop; ++j)
    {
      LeafFitParameters turned = options;
      turned.basePoint = turnBase[j];
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
