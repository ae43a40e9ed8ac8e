// SPDX-License-Identifier: GPL-3.0-or-later
// Where palmate (actinodromous) primaries end on a blade (docs/methods/venation.md, "Palmate veins by leaf growth", turn 2): on the
// blade's real margin, spread over its angular extent as seen from the base, one into each lobe of a lobed blade and
// into each basal lobe of a cordate one. Found on the boundary itself, so it works for any blade carrying LeafUV.
//
// Seen from the base B along the leaf axis (B to the apex), every vertex of the outer boundary loop has a distance
// d and a signed angle phi (positive to the left). Walking the loop from the base:
// - Lobes: local maxima of d whose prominence (d minus the higher of the two lowest points before a higher one is
//   met on either side, the base counting as d = 0) is at least `lobeProminence` leaf lengths and whose lobe (the
//   margin from one of those sinuses to the other, closed by their chord) covers at least `lobeArea` squared leaf
//   lengths. A blade with three or more lobes is lobed: one primary ends at each lobe tip (serrations, scan noise,
//   a fitted margin's thin flap beside the petiole and a ginkgo's notch are too shallow, too small or too few).
// - Basal lobes: on each side, the boundary vertex farthest behind the base (the lowest, seen along the axis), if
//   it lies more than `basalDepth` leaf lengths behind it. A blade with one on each side is cordate (or sagittate,
//   hastate); if it is not lobed, its two outermost primaries end at their tips (on a lobed blade a basal lobe
//   is a primary's only when it is one of the lobes above), and the other primaries spread evenly in angle between them.
// - Otherwise (an entire blade) the m primaries' angles spread evenly over the angular extent [low, high] of the
//   boundary vertices at least `extentDistance` leaf lengths from the base, low + (high - low)*(i + 1/4)/(m - 1/2)
//   (the outermost a quarter of a gap inside the extent), each ending where the ray from the base at its angle
//   leaves the blade for the last time.
// A dichotomous vein's 2^levels end points spread evenly in angle over its primary's share of the extent, with
// the same ray rule; with levels = 0 a lobe's or basal lobe's primary ends exactly at its tip.
//
// Plain C++17 + Eigen, no VTK.
#pragma once

#include "VenationBlade.h"

#include <vector>

namespace plantmorph
{

struct PalmateFanParameters
{
  int primaries = 4;            ///< primaries on a blade without lobes (a lobed blade has one per lobe)
  int levels = 0;               ///< dichotomous fork levels: 2^levels end points per primary
  double lobeProminence = 0.08; ///< in leaf lengths
  double lobeArea = 0.03;       ///< a lobe's area beyond its sinuses, in squared leaf lengths
  double basalDepth = 0.04;     ///< in leaf lengths
  double extentDistance = 0.15; ///< in leaf lengths
};

struct PalmateFan
{
  /// Per primary, in order of angle (right to left), the working-plane end points of its 2^levels branches.
  std::vector<std::vector<Eigen::Vector2d>> ends;
  std::vector<Eigen::Vector2d> lobeTips;  ///< the lobes found (empty unless three or more)
  std::vector<Eigen::Vector2d> basalTips; ///< the basal lobes found (right, left), empty unless cordate
};

/// The end points of the palmate primaries of `blade` seen from `base` along the unit `axis`; `length` is the leaf
/// length the settings' distances are fractions of.
PalmateFan FindPalmateFan(const VenationBlade& blade, const BladeLocator& locator, const Eigen::Vector2d& base,
  const Eigen::Vector2d& axis, double length, const PalmateFanParameters& settings);

} // namespace plantmorph
