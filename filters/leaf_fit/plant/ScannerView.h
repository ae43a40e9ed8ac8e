// SPDX-License-Identifier: GPL-3.0-or-later
// What a terrestrial scanner saw around a leaf (docs/methods/leaf-fit.md, "HiddenMargin: where the scanner's view
// was blocked"). Plain C++17 (Eigen), no VTK.
//
// A leaf seen in part ends where something nearer to the scanner hides it; a leaf seen whole ends at its margin, and
// past its margin the scanner saw through: to what lies behind, or to nothing. So the scan itself tells the two
// apart, once the scanner's position is known:
//
// - The scanner's position: a scanner's points all lie at their measured range from it, |p - s| = r. With
//   c = |s|^2 that is -2 p.s + c = r^2 - |p|^2, linear in (s, c): least squares over its points (RangeEquations).
//   A scan whose ranges are not distances from one place (a moving scanner, a Range array of another meaning) leaves
//   a residual and is not used (MaxRangeResidual).
// - The scanner's depth map: the nearest range it measured in each direction cell (DepthMap). The cells are rings of
//   one elevation about the up axis, each cut into cells as wide as they are high, so there is no pole: a cell is
//   DepthCellSpacings of the scanner's angular spacing across.
// - The margin: past each vertex of the fitted blade's margin, MarginProbeSpacings point spacings out in the blade's
//   tangent plane, a probe. The probe is hidden from a scanner when one of the 3 x 3 cells about its direction holds
//   a point of something else than the leaf nearer to the scanner than the probe by more than BlockerSpacings
//   spacings: the scanner's beam there
//   stopped in front of where the leaf would go on. HiddenMargin is the share of the probes hidden from every scanner
//   that saw the leaf (at least ScannerSawShare of its points). A leaf seen whole has a margin that is free almost
//   everywhere (on the benchmark's tree scanned from one position, 21 of the 23 leaves with at most 0.2 of their
//   margin hidden were seen whole, and 1 of the 132 with over 0.4).
//
// What it cannot tell: a margin under another leaf that lies just past it, in front (the view there is blocked, and
// the leaf may or may not go on: counted hidden), and a leaf cut by the segmentation rather than by the view (its
// rest was seen: the margin is free).
#pragma once

#include "LeafFit.h"

#include <Eigen/Core>
#include <Eigen/Dense>

#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace plantmorph
{

/// How far past the fitted margin the probes lie, in the leaf's point spacings.
inline constexpr double MarginProbeSpacings = 3.0;
/// How much nearer to the scanner than a probe a point must be to block the view there, in the leaf's spacings: the
/// blade's own points beside the margin, seen obliquely, are nearer by less than the probe's distance out.
inline constexpr double BlockerSpacings = 3.0;
/// A depth cell's width, in the scanner's angular spacing: most cells then hold a point (no holes read as free).
inline constexpr double DepthCellSpacings = 1.5;
/// The share of a leaf's points from one scanner for that scanner to have seen the leaf.
inline constexpr double ScannerSawShare = 0.05;
/// The largest RMS of |p - s| - r, over the scanner's mean range, for a solved position to be used.
inline constexpr double MaxRangeResidual = 0.01;

/// The least-squares equations of a scanner's position from its points and ranges; they add over points and ranks.
struct RangeEquations
{
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::Vector4d right = Eigen::Vector4d::Zero();
  double count = 0.0, rangeSum = 0.0;

  void Add(const Eigen::Vector3d& point, double range);
  /// The 22 numbers (normal, right, count, rangeSum) that Add(values) adds back: to add them over ranks.
  std::vector<double> Values() const;
  void Add(const double* values);
};

/// The scanner's position, when the equations hold enough points and are well posed.
std::optional<Eigen::Vector3d> ScannerPosition(const RangeEquations& equations);

/// Direction cells about a scanner: rings of one elevation about `up`, each cut into cells about `cell` radians wide.
class DirectionCells
{
public:
  DirectionCells() = default;
  DirectionCells(const Eigen::Vector3d& up, double cell);
  bool Valid() const { return this->Cell > 0.0; }
  /// The cell of unit direction `d`.
  std::int64_t Key(const Eigen::Vector3d& d) const;
  /// The 3 x 3 cells about unit direction `d` (its ring and the two beside it, three cells each).
  std::vector<std::int64_t> Around(const Eigen::Vector3d& d) const;

private:
  void RingAndAngle(const Eigen::Vector3d& d, long long& ring, double& angle) const;
  long long CellsInRing(long long ring) const;
  Eigen::Vector3d Up = Eigen::Vector3d::UnitZ(), East = Eigen::Vector3d::UnitX(), North = Eigen::Vector3d::UnitY();
  double Cell = 0.0;
};

/// One point as a depth map takes it: its direction cell, its range and its leaf (-1: on no leaf).
struct CellRange
{
  std::int64_t key = 0;
  double range = 0.0;
  std::int64_t leaf = -1;
  bool operator<(const CellRange& other) const
  {
    return key != other.key ? key < other.key : range != other.range ? range < other.range : leaf < other.leaf;
  }
};

/// The nearest range a scanner measured in each direction cell, and the nearest of another leaf than that point's:
/// a leaf's own points never block the view past its margin (a leaf seen edge on, or curled, lies across the view
/// past its own margin; what it hides of itself is not told).
struct DepthMap
{
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  DirectionCells cells;
  std::vector<std::int64_t> keys;            ///< sorted, distinct
  std::vector<double> nearest, otherNearest; ///< per key; otherNearest: of a point on another leaf (or none)
  std::vector<std::int64_t> nearestLeaf;     ///< per key, the leaf of the nearest point

  /// Each of `points` (on leaves `leaves`) seen from `position` (to send over ranks before Merge).
  std::vector<CellRange> CellRanges(
    const std::vector<Eigen::Vector3d>& points, const std::vector<std::int64_t>& leaves) const;
  /// Sets the map from the points' cells and ranges, in any order.
  void Merge(std::vector<CellRange> points);
  /// The least range, over the points not on leaf `own`, in the 3 x 3 cells about the direction of `point`;
  /// infinity where the scanner saw nothing there.
  double NearestAround(const Eigen::Vector3d& point, std::int64_t own) const;
};

/// The centre of the fitted blade: the mean of its mesh points (zero for a blade of none).
Eigen::Vector3d BladeCentre(const LeafFitResult& fit);

/// The share of a window's probes (about an end of the midvein, or about the widest cross-section on one side) that
/// may be hidden for the margin there to count as seen: as for a whole leaf (MaxHiddenMarginOfWhole).
inline constexpr double MaxHiddenOfSeenWindow = 0.25;
/// A window's half-size along the midvein, as a share of the blade's length laid flat.
inline constexpr double ExtentWindowShare = 0.1;

/// Which of a blade's extents the scanners saw whole (the Traits column ExtentsSeen): its Length when the margin
/// about both ends of the midvein (the blade's points within ExtentWindowShare of its flat length of the base and of
/// the apex) was seen free, its Width when the margin about the widest point of each side was (the points of that
/// margin within ExtentWindowShare of the length of it along the midvein). Seen free: at most MaxHiddenOfSeenWindow
/// of the window's probes hidden, and at least one probe.
inline constexpr int LengthSeen = 1, WidthSeen = 2;

/// Where past a fitted blade's margin the view was blocked.
struct MarginView
{
  double hidden = std::numeric_limits<double>::quiet_NaN(); ///< HiddenMargin
  /// LengthSeen + WidthSeen; NaN with `hidden`, or when the fit has no flat layout and midvein
  double extentsSeen = std::numeric_limits<double>::quiet_NaN();
};

/// The share of the fitted blade's margin past which every scanner of `sawIt` had its view blocked by a point not on
/// leaf `own` (the header's probes, `spacing` the leaf's point spacing), and which extents the probes show whole;
/// NaN when `sawIt` is empty or the fit has no margin.
MarginView ViewOfMargin(
  const LeafFitResult& fit, double spacing, const std::vector<const DepthMap*>& sawIt, std::int64_t own);

/// ViewOfMargin's share hidden.
double HiddenMargin(
  const LeafFitResult& fit, double spacing, const std::vector<const DepthMap*>& sawIt, std::int64_t own);

} // namespace plantmorph
