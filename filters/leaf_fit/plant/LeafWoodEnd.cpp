// SPDX-License-Identifier: GPL-3.0-or-later
// A leaf's base from its plant's wood: the end of its midvein nearer the wood, or where the leaf meets it (LeafPlant.h,
// OrientByWood).
#include "LeafPlant.h"

#include <algorithm>
#include <array>
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

/// The blade's two ends across its midvein: its points of the least and the greatest flat `t` (Width's ends).
std::array<Eigen::Vector3d, 2> WidthEnds(const LeafFitResult& fit)
{
  std::size_t low = 0, high = 0;
  for (std::size_t i = 1; i < fit.flat.size(); ++i)
  {
    if (fit.flat[i].x() < fit.flat[low].x())
      low = i;
    if (fit.flat[i].x() > fit.flat[high].x())
      high = i;
  }
  return { fit.points[low], fit.points[high] };
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

WoodAxis AxisNearerTheWood(const LeafFitResult& fit, const std::vector<Eigen::Vector3d>& points,
  const std::vector<double>& woodDistance, Eigen::Vector3d* widthEnd)
{
  if (!fit.error.empty() || fit.midvein.size() < 2 || fit.flat.size() != fit.points.size() || fit.points.empty() ||
    woodDistance.size() != points.size() || !(fit.traits.length > 0.0) || !(fit.traits.width > 0.0))
    return WoodAxis::Unknown;
  const double reach = WoodEndReach * std::min(fit.traits.length, fit.traits.width);
  const auto near = [&](const Eigen::Vector3d& end) { return WoodNear(end, points, woodDistance, reach); };
  const std::array<Eigen::Vector3d, 2> sides = WidthEnds(fit);
  const double along = std::min(near(fit.points[static_cast<std::size_t>(fit.midvein.front())]),
    near(fit.points[static_cast<std::size_t>(fit.midvein.back())]));
  const double side0 = near(sides[0]), side1 = near(sides[1]);
  const double across = std::min(side0, side1);
  if (widthEnd)
    *widthEnd = side0 <= side1 ? sides[0] : sides[1];
  const double margin = WoodEndMargin * std::max(fit.traits.length, fit.traits.width);
  if (along + margin < across)
    return WoodAxis::Along;
  if (across + margin < along)
    return WoodAxis::Across;
  return WoodAxis::Unknown;
}

std::vector<double> AxisShapes(const std::vector<LeafFitResult>& fits,
  const std::vector<std::vector<Eigen::Vector3d>>& leaves, const std::vector<std::vector<double>>& woodDistance)
{
  std::vector<double> shapes;
  if (woodDistance.size() != leaves.size() || fits.size() != leaves.size())
    return shapes;
  for (std::size_t k = 0; k < fits.size(); ++k)
  {
    const LeafFitResult& fit = fits[k];
    if (fit.traits.baseFrom == BaseFromPoint)
      continue;
    const WoodAxis axis = AxisNearerTheWood(fit, leaves[k], woodDistance[k]);
    if (axis != WoodAxis::Unknown) // across: the leaf's own Width over Length is the fit's turned over
      shapes.push_back((axis == WoodAxis::Along ? 1.0 : -1.0) * std::log(fit.traits.width / fit.traits.length));
  }
  return shapes;
}

std::optional<double> PlantAxisShape(std::vector<double> shapes)
{
  if (static_cast<int>(shapes.size()) < MinAxisShapeLeaves)
    return std::nullopt;
  std::sort(shapes.begin(), shapes.end());
  const std::size_t half = shapes.size() / 2;
  const double median = shapes.size() % 2 ? shapes[half] : 0.5 * (shapes[half - 1] + shapes[half]);
  if (std::abs(median) < WoodShapeMargin)
    return std::nullopt;
  return median;
}

namespace
{
/// Where a leaf is fitted again from, by its wood, and whether that is the wood's base point (WoodBasePoint).
struct WoodBase
{
  std::optional<Eigen::Vector3d> at;
  bool woodPoint = false;
  WoodEnd end = WoodEnd::Unknown; ///< EndNearerTheWood of the fit
};

/// The midvein's end the wood says is the base (`end`, EndNearerTheWood of `fit`): its apex end when that lies nearer
/// the wood (fitted again from there); a guessed base the base end confirms is marked so. Nothing when the fit stands.
std::optional<Eigen::Vector3d> EndByWood(LeafFitResult& fit, WoodEnd end)
{
  if (end == WoodEnd::Apex)
    return fit.points[static_cast<std::size_t>(fit.midvein.back())];
  if (end == WoodEnd::Base && fit.traits.baseFrom == BaseFromGuess)
  {
    fit.traits.baseFrom = BaseFromWood; // the guess is the wood's end
    fit.baseGuess = BaseGuess::None;
  }
  return std::nullopt;
}

/// Where a leaf is fitted again from, by its wood (OrientByWood): a base the shape guessed, or put at a petiole's
/// junction, moves to the leaf's point near the wood at an end of the leaf (WoodBasePoint), unless the wood tells the
/// midvein's ends apart and that point lies by one of them; else the ends decide (EndByWood).
WoodBase BaseByWood(
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
      return { points[*wood], true, end };
  }
  return { EndByWood(fit, end), false, end };
}

/// How far a fit's log Width over Length lies from the plant's (log `plant`), and from it turned over (the fit's
/// Length taken as its Width).
double OffThePlant(const LeafFitResult& fit, double plant, bool turned = false)
{
  const double ratio = std::log(fit.traits.width / fit.traits.length);
  return std::abs((turned ? -ratio : ratio) - plant);
}

/// Whether `again`'s Width over Length lies farther from the plant's (log `plant`) than `first`'s, by more than
/// WoodShapeMargin.
bool LeavesThePlantsShape(const LeafFitResult& again, const LeafFitResult& first, double plant)
{
  return again.traits.length > 0 && again.traits.width > 0 && first.traits.length > 0 && first.traits.width > 0 &&
    OffThePlant(again, plant) > OffThePlant(first, plant) + WoodShapeMargin;
}

/// Each of `turn` fitted again from its base in `from` (as BasePoint puts it), in parallel.
std::vector<LeafFitResult> FitAgain(const std::vector<std::vector<Eigen::Vector3d>>& leaves,
  const std::vector<std::size_t>& turn, const std::vector<Eigen::Vector3d>& from, const LeafFitParameters& options,
  const ParallelFor& parallel)
{
  std::vector<LeafFitResult> again(turn.size());
  parallel(turn.size(), [&](std::size_t begin, std::size_t stop) {
    for (std::size_t j = begin; j < stop; ++j)
    {
      LeafFitParameters turned = options;
      turned.basePoint = from[j];
      again[j] = FitLeaf(leaves[turn[j]], turned);
    }
  });
  return again;
}

/// Leaves fitted across their width (OrientByWood in LeafPlant.h): each fitted again from the end of its width
/// nearer the wood, kept when that brings its Width over Length nearer the plant's by WoodShapeMargin and its
/// Coverage falls by no more than MaxTurnCoverageLoss.
int FitAlongThePlantsAxis(const std::vector<std::vector<Eigen::Vector3d>>& leaves,
  const std::vector<std::vector<double>>& woodDistance, const LeafFitParameters& options,
  std::vector<LeafFitResult>& fits, const ParallelFor& parallel, double plant)
{
  std::vector<std::size_t> turn;
  std::vector<Eigen::Vector3d> from;
  for (std::size_t k = 0; k < fits.size(); ++k)
  {
    const LeafFitResult& fit = fits[k];
    Eigen::Vector3d end;
    if (fit.error.empty() && fit.traits.baseFrom != BaseFromPoint && fit.traits.length > 0.0 &&
      fit.traits.width > 0.0 && OffThePlant(fit, plant, true) + WoodShapeMargin < OffThePlant(fit, plant) &&
      AxisNearerTheWood(fit, leaves[k], woodDistance[k], &end) == WoodAxis::Across)
    {
      turn.push_back(k);
      from.push_back(end);
    }
  }
  std::vector<LeafFitResult> again = FitAgain(leaves, turn, from, options, parallel);
  int count = 0;
  for (std::size_t j = 0; j < turn.size(); ++j)
    if (again[j].error.empty() && again[j].traits.length > 0.0 && again[j].traits.width > 0.0 &&
      OffThePlant(again[j], plant) + WoodShapeMargin < OffThePlant(fits[turn[j]], plant) &&
      again[j].traits.coverage + MaxTurnCoverageLoss >= fits[turn[j]].traits.coverage)
    {
      fits[turn[j]] = std::move(again[j]);
      fits[turn[j]].traits.baseFrom = BaseFromWood;
      ++count;
    }
  return count;
}
} // namespace

int OrientByWood(const std::vector<std::vector<Eigen::Vector3d>>& leaves,
  const std::vector<std::vector<double>>& woodDistance, const LeafFitParameters& options,
  std::vector<LeafFitResult>& fits, const ParallelFor& parallel, std::optional<double> plantAxisShape)
{
  if (options.basePoint || options.apexPoint || woodDistance.size() != leaves.size())
    return 0;
  std::vector<std::size_t> turn;
  std::vector<Eigen::Vector3d> turnBase;
  std::vector<WoodBase> moves;
  for (std::size_t k = 0; k < fits.size(); ++k)
  {
    if (!fits[k].error.empty() || fits[k].traits.baseFrom == BaseFromPoint)
      continue;
    const WoodBase base = BaseByWood(fits[k], leaves[k], woodDistance[k]);
    if (base.at)
    {
      turn.push_back(k);
      turnBase.push_back(*base.at);
      moves.push_back(base);
    }
  }
  std::vector<LeafFitResult> again = FitAgain(leaves, turn, turnBase, options, parallel);
  std::vector<char> taken(turn.size(), 1);
  // A move to the wood's base point that turns the leaf away from the plant's shape is dropped: the first fit's
  // axis stands, and its ends are compared by the wood (fitted again from its apex end when that is the nearer).
  std::vector<std::size_t> second;
  std::vector<Eigen::Vector3d> secondBase;
  for (std::size_t j = 0; j < turn.size(); ++j)
    if (plantAxisShape && moves[j].woodPoint && again[j].error.empty() &&
      LeavesThePlantsShape(again[j], fits[turn[j]], *plantAxisShape))
    {
      taken[j] = 0;
      if (const std::optional<Eigen::Vector3d> end = EndByWood(fits[turn[j]], moves[j].end))
      {
        second.push_back(turn[j]);
        secondBase.push_back(*end);
      }
    }
  std::vector<LeafFitResult> ends = FitAgain(leaves, second, secondBase, options, parallel);
  for (std::size_t j = 0; j < second.size(); ++j)
  {
    turn.push_back(second[j]);
    again.push_back(std::move(ends[j]));
    taken.push_back(1);
  }
  int turnedCount = 0;
  for (std::size_t j = 0; j < turn.size(); ++j)
    if (taken[j] && again[j].error.empty()) // else the first fit stays
    {
      fits[turn[j]] = std::move(again[j]);
      fits[turn[j]].traits.baseFrom = BaseFromWood;
      ++turnedCount;
    }
  if (plantAxisShape)
    turnedCount += FitAlongThePlantsAxis(leaves, woodDistance, options, fits, parallel, *plantAxisShape);
  return turnedCount;
}

} // namespace plantmorph
