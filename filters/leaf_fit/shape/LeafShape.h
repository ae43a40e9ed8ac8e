// SPDX-License-Identifier: GPL-3.0-or-later
// The leaf's shape before the surface fit (docs/methods/leaf-fit.md): where the petiole leaves the blade, and the
// blade's midvein axis from its base and its symmetry. Plain C++17 (Eigen), no VTK.
//
// Petiole: the blade is what a ball of a few point spacings rolled inside the cloud covers (a morphological opening:
// the points whose ball holds most of the points a ball inside the sheet holds, not spread along a line and round
// across it like a stalk seen from two sides, in that ball or, for a stalk thicker than half its radius, in one twice
// as large; and every point within such a ball).
// What the opening leaves out are thin parts: a petiole (a trail one to a few points wide, or sparser and wider
// where a stalk is seen from the side), acute tips and teeth (wedges). A left-out part touching the blade is a
// petiole when it keeps its width (measured across the trail, in bins of distance from the blade) over at least 6
// spacings, is narrow, and does not narrow away from the blade like a wedge (a winged petiole may taper first); the
// longest such part is the petiole. A part within 20 spacings of the blade touches it across that gap (the unseen
// end of a base narrowing into the stalk, narrower than the scan's lines are apart): the blade runs on to it. Its junction is its first points at the blade, or where the stalk's axis (from its
// cross-section: a scanner sees one side of it; its direction through its points where two of its stretches'
// centroids tilt it) meets the blade's plane; its length is measured along the trail's
// centre line (bins' centroids two stalk widths apart), on across gaps to the pieces of the stalk beyond them that
// lie on the line of its last stretch within its width.
//
// Axis: the blade's points, seen in their best plane, mirrored across a line through the base: the line whose
// mirror image leaves the blade least (the fewest mirrored points off it) is the midvein axis (a symmetric blade of
// any outline, wide fans and cordate and lobed blades included, maps onto itself across its midvein, and across no
// other line through its base).
// Without a known base, lines through the blade's centroid are tried, and among equally symmetric lines (an
// ellipse has two) the one nearest the blade's longest principal axis is taken.
#pragma once

#include <Eigen/Core>
#include <plantmorph/ParallelFor.h>

#include <optional>
#include <vector>

namespace plantmorph
{
namespace fit
{

struct Petiole
{
  bool found = false;
  std::vector<unsigned char> member;                  ///< per input point: 1 for the petiole's points
  Eigen::Vector3d junction = Eigen::Vector3d::Zero(); ///< where the petiole meets the blade
  std::vector<Eigen::Vector3d> line;                  ///< the petiole's centre line, from the junction to its far end
  double length = 0.0;                                ///< arc length of `line`
  /// The junction is where the stalk's axis meets the blade's plane (a stalk leaving the blade at 15 degrees or
  /// more), not only where the thin trail ends.
  bool meetsPlane = false;
  /// The stalk begins a gap away from the blade's samples (a base narrowing into it, narrower than the scan's lines
  /// are apart over its last stretch, which the scan misses): the blade runs on, unseen, to the junction.
  bool acrossGap = false;
  double halfWidth = 0.0;                 ///< the stalk's half-width about its axis (zero when it has no axis)
  std::vector<unsigned char> looseMember; ///< per point of FindPetiole's `loose`: 1 for the petiole's points
  /// The share of the points the blade's opening covers (a ball of 4 spacings holding most of what a ball inside
  /// the sheet holds): 0.96 or more on scans that sample the blade evenly, under 0.8 where a scanner's lines lie
  /// far apart over much of it. Under MinSheetShareForPetiole no petiole is looked for.
  double sheetShare = 1.0;
};

/// The least share of the points in the blade's sheet (Petiole::sheetShare) with which a thin trail is told from
/// sparse blade. The six real leaf scans shipped have 0.61-0.93 (0.88 on the sugar beet with the shortest petiole);
/// a simulated leaf scanned at a grazing angle, its lines ten times farther apart than its samples along them,
/// 0.35-0.77.
inline constexpr double MinSheetShareForPetiole = 0.75;

/// Finds the petiole of a leaf's points (outliers already removed; `spacing` their median nearest-neighbour
/// distance). `found` is false when no thin trail leaves the blade. `loose`: the points the cleaning removed as
/// strays; those that continue the stalk's line beyond a gap join it (`looseMember`).
Petiole FindPetiole(const std::vector<Eigen::Vector3d>& points, double spacing, const ParallelFor& parallel = SerialFor,
  const std::vector<Eigen::Vector3d>& loose = {});

/// The unit direction, in the blade's best plane (unit normal `normal`), of the line through `through` across
/// which the blade's points are most nearly mirror images of each other. `hint`: the direction to prefer among
/// equally symmetric lines; the result points the same way as `hint` (positive dot product). The lines tried are
/// scored through `parallel`, each on its own (the result does not depend on the threads).
Eigen::Vector3d SymmetryAxis(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& through,
  const Eigen::Vector3d& normal, const Eigen::Vector3d& hint, double spacing, const ParallelFor& parallel = SerialFor);

} // namespace fit
} // namespace plantmorph
