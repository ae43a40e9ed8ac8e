// SPDX-License-Identifier: GPL-3.0-or-later
// ScannerView (filters/leaf_fit/plant/): a scanner's position solved from its points' ranges, its depth map's
// direction cells, and the share of a blade's margin past which the view was blocked, on a flat square blade seen
// from above with a plate in front of one side, behind it, or nowhere (the share in closed form: 0, 1/2 or 0), and
// which of a lens-shaped blade's extents the view shows whole with a plate over its apex, its side or both.
#include "LeafAreaEstimate.h"
#include "ScannerView.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace plantmorph
{
namespace
{
/// Points of the rectangle [x0, x1] x [y0, y1] at height z, `step` apart.
std::vector<Eigen::Vector3d> Plate(double x0, double x1, double y0, double y1, double z, double step)
{
  std::vector<Eigen::Vector3d> points;
  for (double x = x0; x <= x1 + 1e-9; x += step)
    for (double y = y0; y <= y1 + 1e-9; y += step)
      points.emplace_back(x, y, z);
  return points;
}

/// A fitted blade as FitLeaf gives it: the square [-1, 1]^2 at z = 0, normals +Z, its left margin along x = -1 and
/// its right one along x = 1 (base to apex: y from -1 to 1).
LeafFitResult SquareBlade(double step)
{
  LeafFitResult fit;
  const int n = static_cast<int>(std::lround(2.0 / step)) + 1;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
    {
      fit.points.emplace_back(-1.0 + i * step, -1.0 + j * step, 0.0);
      fit.normals.emplace_back(0.0, 0.0, 1.0);
    }
  for (int j = 0; j < n; ++j)
  {
    fit.leftMargin.push_back(j);
    fit.rightMargin.push_back((n - 1) * n + j);
  }
  return fit;
}

/// A fitted lens-shaped blade as FitLeaf gives it, laid flat as it lies: at z = 0, normals +Z, its midvein along
/// x = 0 from the base y = -1 to the apex y = 1, its margins x = -+0.5 (1 - y^2), `step` apart along y; widest at
/// y = 0.
LeafFitResult LensBlade(double step)
{
  LeafFitResult fit;
  const int n = static_cast<int>(std::lround(2.0 / step)) + 1;
  for (int side = -1; side <= 1; ++side)
    for (int j = 0; j < n; ++j)
    {
      const double y = -1.0 + j * step;
      fit.points.emplace_back(side * 0.5 * (1.0 - y * y), y, 0.0);
      fit.normals.emplace_back(0.0, 0.0, 1.0);
      fit.flat.emplace_back(fit.points.back().x(), y + 1.0);
      std::vector<int>& line = side < 0 ? fit.leftMargin : side == 0 ? fit.midvein : fit.rightMargin;
      line.push_back(static_cast<int>(fit.points.size()) - 1);
    }
  return fit;
}

/// The depth map of `points` (on leaves `leaves`) seen from `position`, cells `cell` radians wide about +Z.
DepthMap MapOf(const std::vector<Eigen::Vector3d>& points, const std::vector<std::int64_t>& leaves,
  const Eigen::Vector3d& position, double cell)
{
  DepthMap map;
  map.position = position;
  map.cells = DirectionCells(Eigen::Vector3d::UnitZ(), cell);
  map.Merge(map.CellRanges(points, leaves));
  return map;
}
} // namespace

TEST(ScannerView, TheScannersPositionComesBackFromItsPointsRanges)
{
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  const Eigen::Vector3d scanner(12.0, -4.0, 2.5), other(-9.0, 6.0, 1.0);
  RangeEquations one, mixed;
  for (int i = 0; i < 500; ++i)
  {
    const Eigen::Vector3d p(uniform(random), uniform(random), uniform(random) + 3.0);
    one.Add(p, (p - scanner).norm());
    mixed.Add(p, (p - (i % 2 ? scanner : other)).norm()); // two scanners' points under one ScanPosition
  }
  const std::optional<Eigen::Vector3d> position = ScannerPosition(one);
  ASSERT_TRUE(position.has_value());
  EXPECT_LT((*position - scanner).norm(), 1e-8);
  // The equations add over ranks: two halves give the whole.
  RangeEquations half1, half2;
  const std::vector<double> values = one.Values();
  half1.Add(values.data());
  EXPECT_LT((*ScannerPosition(half1) - scanner).norm(), 1e-8);
  // Ranges that are no distances from one place do not give a position.
  EXPECT_FALSE(ScannerPosition(mixed).has_value());
  EXPECT_FALSE(ScannerPosition(half2).has_value()); // no points
}

TEST(ScannerView, ADirectionsCellIsAmongTheCellsAroundItAndNearDirectionsShareThem)
{
  const double cell = 0.01;
  const DirectionCells cells(Eigen::Vector3d::UnitZ(), cell);
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  for (int k = 0; k < 2000; ++k)
  {
    const Eigen::Vector3d d = Eigen::Vector3d(normal(random), normal(random), normal(random)).normalized();
    const std::vector<std::int64_t> around = cells.Around(d);
    EXPECT_TRUE(std::count(around.begin(), around.end(), cells.Key(d)) == 1) << k;
    // A direction half a cell away lies in one of the cells around: the 3 x 3 cells cover a cell's width about it.
    const Eigen::Vector3d side = d.cross(Eigen::Vector3d(normal(random), normal(random), normal(random))).normalized();
    const Eigen::Vector3d near = (d + 0.5 * cell * side).normalized();
    EXPECT_TRUE(std::count(around.begin(), around.end(), cells.Key(near)) == 1) << k;
    // One ten cells away does not.
    const Eigen::Vector3d far = (d + 10.0 * cell * side).normalized();
    EXPECT_TRUE(std::count(around.begin(), around.end(), cells.Key(far)) == 0) << k;
  }
  // Straight up and straight down are cells too (no pole left out).
  EXPECT_FALSE(cells.Around(Eigen::Vector3d::UnitZ()).empty());
  EXPECT_FALSE(cells.Around(-Eigen::Vector3d::UnitZ()).empty());
}

TEST(ScannerView, TheMarginPastWhichAPlateInFrontHidesTheViewIsHidden)
{
  const double step = 0.02;
  const Eigen::Vector3d scanner(0.0, 0.0, 10.0);
  const double angular = step / 10.0; // the scan's spacing seen from 10 units
  const LeafFitResult fit = SquareBlade(step);
  const std::vector<Eigen::Vector3d> blade = Plate(-1.0, 1.0, -1.0, 1.0, 0.0, step);
  // The blade is leaf 0; the plate is leaf `plateLeaf` at height z (none when z is NaN). A plate above the blade
  // starts at x = 0.93: seen from the scanner, past the margin's x = 1 (0.9 at that height) and over the probes'
  // x = 1.06 (0.954).
  const auto withPlate = [&](double z, std::int64_t plateLeaf = 1) {
    std::vector<Eigen::Vector3d> points = blade;
    std::vector<std::int64_t> leaves(points.size(), 0);
    if (std::isfinite(z))
    {
      const std::vector<Eigen::Vector3d> plate = Plate(z > 0.0 ? 0.93 : 1.0, 1.6, -1.2, 1.2, z, step);
      points.insert(points.end(), plate.begin(), plate.end());
      leaves.resize(points.size(), plateLeaf);
    }
    return MapOf(points, leaves, scanner, DepthCellSpacings * angular);
  };
  // Nothing past the margin: the view is free all round.
  const DepthMap free = withPlate(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(HiddenMargin(fit, step, { &free }, 0), 0.0);
  // A plate 1 unit above the blade, past the right margin: the right margin (half the probes) is hidden.
  const DepthMap front = withPlate(1.0);
  EXPECT_NEAR(HiddenMargin(fit, step, { &front }, 0), 0.5, 0.02);
  // The same plate under the blade is seen past the margin: nothing is hidden.
  const DepthMap behind = withPlate(-1.0);
  EXPECT_EQ(HiddenMargin(fit, step, { &behind }, 0), 0.0);
  // A second scanner that sees past the right margin (the plate is not in its way there) frees it: hidden is what
  // every scanner that saw the leaf had blocked.
  const DepthMap low = withPlate(1.0);
  const DepthMap side = MapOf(blade, std::vector<std::int64_t>(blade.size(), 0), Eigen::Vector3d(12.0, 0.0, 0.3),
    DepthCellSpacings * step / 12.0);
  EXPECT_NEAR(HiddenMargin(fit, step, { &low, &side }, 0), 0.0, 0.02);
  // The plate in front as a part of the leaf itself (a leaf curled over, or seen edge on): its own points never
  // block the view past its margin. Points on no leaf (-1) do.
  const DepthMap own = withPlate(1.0, 0);
  EXPECT_EQ(HiddenMargin(fit, step, { &own }, 0), 0.0);
  const DepthMap wood = withPlate(1.0, -1);
  EXPECT_NEAR(HiddenMargin(fit, step, { &wood }, 0), 0.5, 0.02);
  // No scanner, or no margin: not known.
  EXPECT_TRUE(std::isnan(HiddenMargin(fit, step, {}, 0)));
  EXPECT_TRUE(std::isnan(HiddenMargin(LeafFitResult(), step, { &free }, 0)));
}

TEST(ScannerView, AnExtentIsSeenWholeWhereTheMarginAboutItsTwoEndsIsSeenFree)
{
  // A lens blade seen from 10 units above, with a plate 1 unit above it (on another leaf) over a part of it: the
  // Length is seen whole when the margin about the base and the apex is free, the Width when the margin about the
  // widest point of both sides is.
  const double step = 0.02;
  const Eigen::Vector3d scanner(0.0, 0.0, 10.0);
  const LeafFitResult fit = LensBlade(step);
  const std::vector<Eigen::Vector3d> blade = Plate(-0.5, 0.5, -1.0, 1.0, 0.0, step);
  const auto withPlate = [&](double x0, double x1, double y0, double y1) {
    std::vector<Eigen::Vector3d> points = blade;
    std::vector<std::int64_t> leaves(points.size(), 0);
    if (x1 > x0)
    {
      const std::vector<Eigen::Vector3d> plate = Plate(x0, x1, y0, y1, 1.0, step);
      points.insert(points.end(), plate.begin(), plate.end());
      leaves.resize(points.size(), 1);
    }
    return MapOf(points, leaves, scanner, DepthCellSpacings * step / 10.0);
  };
  const auto seen = [&](const DepthMap& map) { return ViewOfMargin(fit, step, { &map }, 0).extentsSeen; };
  // Seen from 10 units, the plate's edges lie on the blade's plane at 10/9 of their own x and y.
  const DepthMap free = withPlate(0, 0, 0, 0);
  EXPECT_EQ(seen(free), LengthSeen + WidthSeen);
  EXPECT_EQ(ViewOfMargin(fit, step, { &free }, 0).hidden, 0.0);
  // Over the apex end (y from 0.67 on the blade): the Width is still seen whole, the Length not.
  EXPECT_EQ(seen(withPlate(-1.0, 1.0, 0.6, 1.5)), WidthSeen);
  // Over the right side's widest part (x from 0.33, |y| under 0.56): the Length is seen whole, the Width not.
  EXPECT_EQ(seen(withPlate(0.3, 1.0, -0.5, 0.5)), LengthSeen);
  // Over the apex and both sides' widest parts: neither.
  EXPECT_EQ(seen(withPlate(-1.0, 1.0, -0.5, 1.5)), 0.0);
  // A fit without its flat layout and midvein: the share hidden, but no extents.
  const MarginView square = ViewOfMargin(SquareBlade(step), step, { &free }, 0);
  EXPECT_EQ(square.hidden, 0.0);
  EXPECT_TRUE(std::isnan(square.extentsSeen));
  EXPECT_TRUE(std::isnan(ViewOfMargin(fit, step, {}, 0).extentsSeen));
}

} // namespace plantmorph
