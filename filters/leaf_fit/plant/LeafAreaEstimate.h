// SPDX-License-Identifier: GPL-3.0-or-later
// The area of a leaf seen in part, estimated from the plant's leaves seen whole (docs/methods/leaf-fit.md, "Trait
// reference": EstimatedArea and AreaRule). Plain C++17, no VTK.
//
// The assumption: the leaves of one plant share a shape, so the ratio of a blade's long extent to its short one
// (Length and Width, whichever is longer) and its fill (Area over the long extent squared) are the plant's, whatever
// the leaf's size. Plant scientists estimate a partly hidden leaf so (area ~ c Length Width, with c and the ratio
// from the whole leaves). Length and Width are arc lengths on the blade, along the midvein and across it: a leaf's
// own, whatever its curl and whichever way it faces. The projected extents (ProjectedLength and ProjectedWidth,
// along the major axis of the blade's plane) were used before: a rolled leaf projects narrower, and the major axis
// of a blade nearly as wide as long (a fan, a palmate or lobed blade) turns anywhere, so leaves seen whole were
// called cut (benchmarks/README.md, "the leaf's own Length and Width").
//
// - The plant's shape: from the fitted leaves with Coverage at least MinCoverage (and, when the scanners' positions
//   are known, HiddenMargin at most MaxHiddenMarginOfWhole: a leaf the view was blocked past is not taken, unless
//   fewer than MinWholeLeaves remain: then the view does not say which leaves are whole, and every leaf is judged by
//   its shape alone), the median of the log ratio and of the log fill, and the leaves within SpreadsOfWhole robust
//   spreads of both (1.4826 x the median absolute deviation, no less than MinShapeSpread) are the whole leaves, five
//   rounds from all of them. With fewer than MinWholeLeaves whole leaves there is no shape: every leaf keeps its Area
//   (AreaRule 3). Three spreads, not two: at two, leaves seen whole with a ratio a little off (measured then on the
//   projected extents, above) fell outside and were changed.
// - A leaf is cut when its ratio lies outside the whole leaves' range (their largest deviation from the median ratio,
//   the ratio's own spread among whole leaves): rounder than every whole leaf, its long extent is short (a hidden
//   tip or base: the long extent from the short one, AreaRule 1); narrower, its short extent is short (a hidden
//   side: AreaRule 2). Its estimate is the fill times the long extent squared, never less than its own Area.
// - Every other leaf, the whole ones among them, keeps its Area (AreaRule 0): a leaf seen whole is not changed. A
//   leaf whose margin the scanners saw free is judged by its shape like any other: the segmentation may have cut
//   it (its rest seen, under another label), which the view does not tell.
// - A leaf hidden on both sides alike (a scaled-down copy of the shape) is not told from a small leaf by its shape: it
//   keeps its Area, unless the plant is of one size (below).
// - The plant's size: when its whole leaves are of one size, a cut leaf (rule 1 or 2) is taken to be of that size
//   too: its estimate is the median Area of the whole leaves of the plant's size whose long extent is at least its
//   own (estimated) one, when that is more (AreaRule 4). An estimate past the largest of those leaves comes down to
//   their median (AreaRule 4, never under the leaf's own Area): a leaf seen nearly whole whose ratio falls just
//   outside the whole leaves' narrow range (a plant of nine leaves) had its long extent stretched by the plant's
//   ratio to 20 % over the plant's size. The assumption: which leaf the scanner sees whole does not
//   depend on its size, so a cut leaf of a plant of one leaf size is that size. It completes a leaf cut on two sides
//   (a corner seen: both extents short), which the shape alone leaves short. A plant whose whole leaves differ in
//   size keeps the shape's estimate: a cut leaf's size is then not known from the others.
// - One size is judged on the larger half of the whole leaves' log Area: its robust spread about its own median,
//   scaled to the spread of the whole sample under a normal spread (LargerHalfSpreadScale), at most OneSizeSpread.
//   The larger half, because the leaves taken whole by their shape include pieces of blades whose parts keep the
//   blade's ratio and fill (a lobe of a lobed or palmate blade, a blade hidden on both sides alike): such a piece is
//   smaller than its blade, so it falls in the smaller half and leaves the larger one to the blades seen whole.
//   Leaves that differ in size spread the larger half as they spread the whole sample. When pieces are more than
//   half of the leaves taken whole, the larger half holds some of them, spreads, and the plant is not taken for one
//   of one size (the safe side: the shape's estimates). The plant's size leaves are the whole leaves whose log Area
//   is at least SpreadsOfWhole spreads (no less than MinShapeSpread) under the larger half's median: the pieces stay
//   out of the size too.
// - Pieces: on a plant of one size, a leaf of the plant's shape (AreaRule 0: seen whole by its shape, or its ratio in
//   the whole leaves' range) whose Area is under the size leaves' (log Area more than SpreadsOfWhole spreads under
//   the larger half's median) is a piece of a leaf of that size: its estimate is the size leaves' median Area
//   (AreaRule 5). The same assumption as AreaRule 4's, applied to the pieces that keep the blade's ratio and fill,
//   which the shape cannot tell from a leaf seen whole and the size can. Pieces are the exception: when the leaves
//   taken whole under the size are as many as the size leaves or more, they are taken for leaves of another size
//   (young leaves) and every leaf keeps its Area. Where it fails: a plant of one leaf size with a few smaller leaves
//   seen whole (young leaves at the shoot's tip, fewer than the leaves of the plant's size): those are raised to the
//   plant's size. AreaRule 5 tells them apart in the table; Area keeps what was measured.
//
// The leaf points on no leaf (a segmentation's leaf points it gave no LeafId: pieces of leaves seen in small parts,
// edges of leaves it cut off) are leaf surface the fitted leaves leave out. Their area is taken at the fitted leaves'
// own density: their count times the fitted leaves' summed Area over their summed Points (UnassignedLeafArea). The
// assumption: the scanner saw them as densely as it saw the plant's fitted leaves, on average. It gives the area the
// points cover, not the leaves' hidden rest.
#pragma once

#include "LeafFit.h"

#include <vector>

namespace plantmorph
{

/// How a leaf's EstimatedArea was made (the Traits column AreaRule).
enum class AreaRule
{
  Fitted = 0,         ///< its own Area: its shape is the plant's (seen whole, or cut where the shape cannot tell)
  LongFromShort = 1,  ///< rounder than the plant's leaves: its long extent from its short one (a tip or base hidden)
  ShortFromLong = 2,  ///< narrower than the plant's leaves: its short extent from its long one (a side hidden)
  NoPlantShape = 3,   ///< its own Area: fewer than MinWholeLeaves leaves seen whole give no plant shape
  PlantSize = 4,      ///< cut (rule 1, 2 or 6) on a plant of one leaf size: the size leaves' median Area (see above)
  Piece = 5,          ///< the plant's shape but under the plant's one leaf size: a piece, the size leaves' median Area
  FromSeenExtents = 6 ///< its margin hidden in part: from the extents the scanners saw whole (ExtentsSeen)
};

/// Leaves seen whole needed for the plant's shape.
inline constexpr int MinWholeLeaves = 3;
/// The largest HiddenMargin (ScannerView.h) of a leaf the plant's shape is taken from, when the scanners' positions
/// are known: a leaf whose margin is hidden over more than a quarter of it may go on there. On the benchmark's tree
/// scanned from one, two and four positions, 86-91 % of the leaves with at most 0.2 hidden were seen whole (at least
/// 97 % of their true area), 0-2 % of those with over 0.4; between, about half.
inline constexpr double MaxHiddenMarginOfWhole = 0.25;
/// The largest robust spread of the log Length over Width of the leaves seen whole for AreaRule 6: above it the
/// plant's leaves do not agree on which way their Length runs (a fan or round blade whose midvein the fit may lay
/// either way), and a leaf's seen Length says nothing of its Width.
inline constexpr double MaxAxisSpread = 0.1;
/// Robust spreads (1.4826 x the median absolute deviation) about the plant's median within which a leaf is whole.
inline constexpr double SpreadsOfWhole = 3.0;
/// The least spread of the log ratio and log fill taken for the whole leaves: an extent is measured to about a point
/// spacing, and a leaf has some fifty spacings across or more, so 2 % is the measurement's own spread.
inline constexpr double MinShapeSpread = 0.02;
/// The largest spread of the whole leaves' log Area (from their larger half, below) for which the plant's leaves are
/// of one size. The fitted Area of a leaf seen whole is within 1.5 % of the truth (median) and 6 % at worst on the
/// benchmark's plants, so leaves of one size spread by a few percent; 0.1 (10 % of area, 5 % of length) is above that
/// and below the spread of a plant whose leaves differ in length by a quarter or more (log area spread 0.3 and up).
inline constexpr double OneSizeSpread = 0.1;
/// The spread of a sample from the median absolute deviation of its larger half about that half's median: for a
/// normal spread sigma that deviation is 0.3991 sigma (the 75th percentile 0.6745 sigma, and the half-width m with
/// Phi(0.6745 + m) - Phi(0.6745 - m) = 1/4), so sigma = 2.5057 times it.
inline constexpr double LargerHalfSpreadScale = 2.5057;

/// The plant's shape from its leaves seen whole.
struct PlantShape
{
  int wholeLeaves = 0;                ///< leaves taken as seen whole
  double ratio = 0;                   ///< median long over short extent of the whole leaves
  double fill = 0;                    ///< median Area over the long extent squared of the whole leaves
  double lowRatio = 0, highRatio = 0; ///< the whole leaves' range of the ratio
  double areaSpread = 0;              ///< spread of the whole leaves' log Area, from their larger half
  double logSize = 0;                 ///< median log Area of the larger half of the whole leaves
  int sizeLeaves = 0;                 ///< whole leaves of the plant's size (log Area at least its floor, below)
  int smallerLeaves = 0;              ///< whole leaves under the plant's size
  double sizeArea = 0;                ///< median Area of the size leaves
  double sizeLargestArea = 0;         ///< largest Area of the size leaves
  bool valid = false;                 ///< at least MinWholeLeaves whole leaves
  bool oneSize = false;               ///< valid, and areaSpread at most OneSizeSpread
  /// The whole leaves are those whose margin the scanners saw free (HiddenMargin): no pieces hidden by the view
  /// among them, so the spread of their log Area is the larger of their larger half's and that of all of them (a
  /// robust spread: a few leaves the segmentation cut do not widen it).
  bool fromView = false;
  double lengthOverWidth = 0; ///< median Length over Width of the whole leaves (with fromView)
  double fillOfExtents = 0;   ///< median Area over Length x Width of the whole leaves (with fromView)
  bool extentsAgree = false;  ///< fromView, and the whole leaves' log Length over Width spread at most MaxAxisSpread
};

struct LeafAreaEstimates
{
  PlantShape shape;
  std::vector<double> area; ///< every leaf's EstimatedArea (NaN when not fitted)
  std::vector<int> rule;    ///< every leaf's AreaRule (-1 when not fitted)
  std::vector<bool> whole;  ///< the leaves the shape was taken from
};

/// The leaf area of `points` leaf points on no fitted leaf, at the fitted leaves' own points per area: `points` x the
/// sum of Area over the sum of Points of the fitted leaves (`fitted[i]` false for leaves that were not fitted). 0 when
/// `points` is 0; NaN when no fitted leaf has points and area.
double UnassignedLeafArea(const std::vector<LeafTraits>& traits, const std::vector<bool>& fitted, double points);

/// The estimated areas of a plant's leaves (rules above); `fitted[i]` false for leaves that were not fitted.
LeafAreaEstimates EstimateLeafAreas(const std::vector<LeafTraits>& traits, const std::vector<bool>& fitted);

} // namespace plantmorph
