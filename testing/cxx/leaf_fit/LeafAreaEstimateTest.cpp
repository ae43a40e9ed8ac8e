// SPDX-License-Identifier: GPL-3.0-or-later
// LeafAreaEstimate (filters/leaf_fit/plant/): the area of a leaf seen in part from the plant's leaves seen whole, on
// plants of ellipse leaves of one shape and several sizes, some cut by a line across the tip or along one side:
// exact cut ellipses (their extents and areas in closed form) and scanned ones fitted by FitLeaf (whose blade of a part
// runs past its straight cut edge: there the estimate is over, but nearer the whole than the fitted area).
#include "LeafAreaEstimate.h"
#include "LeafFit.h"
#include "LeafPlant.h"
#include "ScannerView.h"

#include <plantmorph/MathConstants.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace plantmorph
{
namespace
{
/// Area of the part x <= u a of the ellipse x^2 / a^2 + y^2 / b^2 <= 1 (u in [-1, 1]).
double EllipsePartArea(double a, double b, double u)
{
  return a * b * (0.5 * Pi + std::asin(u) + u * std::sqrt(1.0 - u * u));
}

/// The traits LeafAreaEstimate reads of an ellipse (semi-axes a along X, b < a along Y) cut to x <= u a and
/// y <= v b: its extents along X and Y and its area (cut along one axis at a time).
LeafTraits CutEllipse(double a, double b, double u, double v)
{
  LeafTraits t;
  t.coverage = 1.0;
  if (u < 1.0) // across the tip: the length shortens; the width too once the cut passes the middle
  {
    t.projectedLength = a * (1.0 + u);
    t.projectedWidth = 2.0 * b * (u >= 0.0 ? 1.0 : std::sqrt(1.0 - u * u));
    t.area = EllipsePartArea(a, b, u);
  }
  else // along one side
  {
    t.projectedLength = 2.0 * a * (v >= 0.0 ? 1.0 : std::sqrt(1.0 - v * v));
    t.projectedWidth = b * (1.0 + v);
    t.area = EllipsePartArea(b, a, v);
  }
  t.length = t.projectedLength; // a flat leaf: its arc lengths are its extents
  t.width = t.projectedWidth;
  return t;
}

/// Six whole ellipse leaves of one size (semi-axes a, b), their sizes within 1 %, as fitted areas are.
std::vector<LeafTraits> SixWholeLeaves(double a, double b)
{
  std::vector<LeafTraits> traits;
  for (double stretch : { 1.0, 1.005, 0.995, 1.01, 0.99, 1.0 })
    traits.push_back(CutEllipse(a * stretch, b * stretch, 1, 1));
  return traits;
}

TEST(LeafAreaEstimate, CutEllipsesOfThePlantsShapeGetTheirWholeArea)
{
  // Five whole leaves of length over width 1.5 (within 1 %, as measured extents are), four sizes; then cut ones.
  const double ratio = 1.5;
  const std::vector<double> sizes = { 1.0, 1.4, 2.0, 2.5, 3.0, 1.2, 1.8, 2.2, 2.6 };
  const std::vector<double> stretch = { 1.0, 0.995, 1.01, 1.0, 0.99, 1.0, 1.0, 1.0, 1.0 };
  const std::vector<double> u = { 1, 1, 1, 1, 1, 0.4, 0.2, 1, 1 };  // across the tip at u a
  const std::vector<double> v = { 1, 1, 1, 1, 1, 1, 1, 0.2, -0.2 }; // along a side at v b
  std::vector<LeafTraits> traits;
  std::vector<double> whole;
  for (std::size_t i = 0; i < sizes.size(); ++i)
  {
    const double a = sizes[i], b = a / (ratio * stretch[i]);
    traits.push_back(CutEllipse(a, b, u[i], v[i]));
    whole.push_back(Pi * a * b);
  }
  const LeafAreaEstimates out = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  ASSERT_TRUE(out.shape.valid);
  EXPECT_EQ(out.shape.wholeLeaves, 5);
  EXPECT_NEAR(out.shape.ratio, ratio, 0.01 * ratio);
  EXPECT_NEAR(out.shape.fill, Pi / (4.0 * ratio), 0.01);
  for (std::size_t i = 0; i < 5; ++i) // seen whole: unchanged
  {
    EXPECT_EQ(out.area[i], traits[i].area) << i;
    EXPECT_EQ(out.rule[i], static_cast<int>(AreaRule::Fitted)) << i;
  }
  // Across the tip, the width still whole: the length from it (exact but for the plant's ratio's 1 %).
  EXPECT_EQ(out.rule[5], static_cast<int>(AreaRule::LongFromShort));
  EXPECT_NEAR(out.area[5] / whole[5], 1.0, 0.03);
  EXPECT_LT(traits[5].area / whole[5], 0.8);
  // Across the tip past a third of the length: the cut length is now the short extent, the width the long one,
  // and the width's extent is taken for the length's: more than its own area, less than the whole.
  EXPECT_GT(out.area[6], 1.1 * traits[6].area);
  EXPECT_LT(out.area[6], whole[6]);
  // Along one side: the length still whole (exact), or a little short when the cut passes the midvein.
  EXPECT_EQ(out.rule[7], static_cast<int>(AreaRule::ShortFromLong));
  EXPECT_NEAR(out.area[7] / whole[7], 1.0, 0.03);
  EXPECT_LT(traits[7].area / whole[7], 0.8);
  EXPECT_EQ(out.rule[8], static_cast<int>(AreaRule::ShortFromLong));
  EXPECT_NEAR(out.area[8] / whole[8], 1.0, 0.06);
  EXPECT_LT(traits[8].area / whole[8], 0.5);
}

/// The traits LeafAreaEstimate reads of the corner x <= u a, y <= v b of an ellipse (semi-axes a along X, b along Y):
/// a leaf cut on two sides, both extents short. Integrated on a grid of a 400th of the axes (area within 0.5 %).
LeafTraits CornerOfEllipse(double a, double b, double u, double v)
{
  LeafTraits t;
  t.coverage = 1.0;
  const int n = 400;
  const double hx = 2.0 * a / n, hy = 2.0 * b / n;
  double lowX = a, highX = -a, lowY = b, highY = -b;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
    {
      const double x = -a + (i + 0.5) * hx, y = -b + (j + 0.5) * hy;
      if (x * x / (a * a) + y * y / (b * b) > 1.0 || x > u * a || y > v * b)
        continue;
      t.area += hx * hy;
      lowX = std::min(lowX, x), highX = std::max(highX, x), lowY = std::min(lowY, y), highY = std::max(highY, y);
    }
  t.projectedLength = t.length = highX - lowX;
  t.projectedWidth = t.width = highY - lowY;
  return t;
}

TEST(LeafAreaEstimate, ACutLeafOfAPlantOfOneLeafSizeIsThatSize)
{
  // Six whole leaves of one size (within 1 %, as fitted areas are) and length over width 1.5; a corner of one cut
  // across the tip and along the midvein (both extents short: the shape alone gives it a quarter of the whole) and
  // one cut along a side only. Both are taken to be of the plant's size.
  const double a = 2.0, b = a / 1.5, whole = Pi * a * b;
  std::vector<LeafTraits> traits = SixWholeLeaves(a, b);
  traits.push_back(CornerOfEllipse(a, b, -0.2, 0.0));
  traits.push_back(CutEllipse(a, b, 1, -0.2));
  const LeafAreaEstimates out = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  ASSERT_TRUE(out.shape.valid);
  EXPECT_EQ(out.shape.wholeLeaves, 6);
  EXPECT_TRUE(out.shape.oneSize);
  EXPECT_LT(out.shape.areaSpread, 0.03);
  EXPECT_LT(traits[6].area / whole, 0.2);
  for (std::size_t i = 6; i < 8; ++i)
  {
    EXPECT_EQ(out.rule[i], static_cast<int>(AreaRule::PlantSize)) << i;
    EXPECT_NEAR(out.area[i] / whole, 1.0, 0.03) << i;
  }
  for (std::size_t i = 0; i < 6; ++i)
    EXPECT_EQ(out.area[i], traits[i].area) << i;

  // The same cut leaves on a plant whose whole leaves differ in size (0.7 to 1.4 times): the size of a cut leaf is
  // not known from them, and the corner keeps the shape's estimate (more than its Area, well under the whole).
  std::vector<LeafTraits> varied;
  for (double scale : { 0.7, 0.85, 1.0, 1.2, 1.4, 1.1 })
    varied.push_back(CutEllipse(a * scale, b * scale, 1, 1));
  varied.push_back(traits[6]);
  const LeafAreaEstimates shapeOnly = EstimateLeafAreas(varied, std::vector<bool>(varied.size(), true));
  ASSERT_TRUE(shapeOnly.shape.valid);
  EXPECT_FALSE(shapeOnly.shape.oneSize);
  EXPECT_GT(shapeOnly.shape.areaSpread, 0.3);
  EXPECT_EQ(shapeOnly.rule[6], static_cast<int>(AreaRule::LongFromShort));
  EXPECT_GT(shapeOnly.area[6], traits[6].area);
  EXPECT_LT(shapeOnly.area[6] / whole, 0.3);
}

TEST(LeafAreaEstimate, AnEstimatePastEveryLeafOfAPlantOfOneSizeIsThatSize)
{
  // Six whole leaves of one size and length over width 1.5 (within 1 %), and one seen whole whose width was measured
  // 10 % wide (its ratio rounder than every whole leaf's): the shape stretches its long extent from that width to
  // 21 % over the whole leaves' area. On a plant of one size the estimate stays the plant's size.
  const double a = 2.0, b = a / 1.5, whole = Pi * a * b;
  std::vector<LeafTraits> traits = SixWholeLeaves(a, b);
  LeafTraits wide = CutEllipse(a, b, 1, 1);
  wide.width *= 1.1;
  traits.push_back(wide);
  const LeafAreaEstimates out = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  ASSERT_TRUE(out.shape.valid);
  ASSERT_TRUE(out.shape.oneSize);
  EXPECT_GT(out.shape.lowRatio, 1.5 / 1.1); // the wide leaf is rounder than every whole leaf
  EXPECT_EQ(out.rule[6], static_cast<int>(AreaRule::PlantSize));
  EXPECT_NEAR(out.area[6] / whole, 1.0, 0.01);
  // Its own Area more than every whole leaf's: never less than that.
  traits[6].area = 1.05 * whole;
  const LeafAreaEstimates large = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  EXPECT_EQ(large.area[6], traits[6].area);

  // On a plant whose whole leaves differ in size the plant's size is not known: the shape's estimate stands.
  std::vector<LeafTraits> varied;
  for (double scale : { 0.7, 0.85, 1.0, 1.2, 1.4, 1.1 })
    varied.push_back(CutEllipse(a * scale, b * scale, 1, 1));
  varied.push_back(wide);
  const LeafAreaEstimates shapeOnly = EstimateLeafAreas(varied, std::vector<bool>(varied.size(), true));
  ASSERT_TRUE(shapeOnly.shape.valid);
  ASSERT_FALSE(shapeOnly.shape.oneSize);
  EXPECT_EQ(shapeOnly.rule[6], static_cast<int>(AreaRule::LongFromShort));
  EXPECT_NEAR(shapeOnly.area[6] / whole, 1.1 * 1.1, 0.03);
}

TEST(LeafAreaEstimate, PiecesTakenWholeByTheirShapeLeaveAPlantOfOneSizeOneSizeAndGetItsSize)
{
  // A plant of one lobed blade size: six blades seen whole (within 1 %, as fitted areas are) and seven pieces of
  // blades that keep the blade's ratio and fill (a lobe of a lobed blade, a blade hidden on both sides alike: a
  // smaller copy of the shape, 0.3-0.85 of its length), so the shape takes them as whole too; they are more than half
  // of the leaves it takes whole. A corner of a blade (both extents short) is cut and is of the plant's size.
  const double a = 2.0, b = a / 1.5, whole = Pi * a * b;
  std::vector<LeafTraits> traits = SixWholeLeaves(a, b);
  for (double piece : { 0.3, 0.5, 0.6, 0.7, 0.75, 0.8, 0.85 })
    traits.push_back(CutEllipse(a * piece, b * piece, 1, 1));
  traits.push_back(CornerOfEllipse(a, b, -0.2, 0.0));
  const std::size_t corner = traits.size() - 1;
  const LeafAreaEstimates out = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  ASSERT_TRUE(out.shape.valid);
  EXPECT_EQ(out.shape.wholeLeaves, 13);
  // The larger half holds the six blades and the largest piece: its spread is the blades' (1 %), the size theirs.
  EXPECT_TRUE(out.shape.oneSize);
  EXPECT_LT(out.shape.areaSpread, 0.05);
  EXPECT_NEAR(std::exp(out.shape.logSize) / whole, 1.0, 0.02);
  EXPECT_EQ(out.rule[corner], static_cast<int>(AreaRule::PlantSize));
  // The plant's size from the blades alone: the pieces (the largest 0.72 of a blade's area) stay out of it.
  EXPECT_NEAR(out.area[corner] / whole, 1.0, 0.02);
  // The pieces under the plant's size are more than its size leaves: they are taken for leaves of another size and
  // every leaf keeps its Area.
  EXPECT_EQ(out.shape.sizeLeaves, 6);
  EXPECT_EQ(out.shape.smallerLeaves, 7);
  for (std::size_t i = 0; i < corner; ++i)
  {
    EXPECT_EQ(out.area[i], traits[i].area) << i;
    EXPECT_EQ(out.rule[i], static_cast<int>(AreaRule::Fitted)) << i;
  }

  // Three of the pieces (0.3, 0.6, 0.8 of the length), fewer than the blades: each is a piece of a blade of the
  // plant's size and gets the blades' median Area (AreaRule 5); the blades keep theirs.
  std::vector<LeafTraits> fewer(traits.begin(), traits.begin() + 6);
  for (double piece : { 0.3, 0.6, 0.8 })
    fewer.push_back(CutEllipse(a * piece, b * piece, 1, 1));
  const LeafAreaEstimates pieces = EstimateLeafAreas(fewer, std::vector<bool>(fewer.size(), true));
  ASSERT_TRUE(pieces.shape.oneSize);
  EXPECT_EQ(pieces.shape.sizeLeaves, 6);
  EXPECT_EQ(pieces.shape.smallerLeaves, 3);
  for (std::size_t i = 0; i < fewer.size(); ++i)
  {
    const bool piece = i >= 6;
    EXPECT_EQ(pieces.rule[i], static_cast<int>(piece ? AreaRule::Piece : AreaRule::Fitted)) << i;
    if (piece)
      EXPECT_NEAR(pieces.area[i] / whole, 1.0, 0.01) << i;
    else
      EXPECT_EQ(pieces.area[i], fewer[i].area) << i;
  }
  // A leaf just under the blades (0.97 of the length, 6 % of area: within the floor) is of the plant's size.
  fewer.push_back(CutEllipse(0.97 * a, 0.97 * b, 1, 1));
  const LeafAreaEstimates near = EstimateLeafAreas(fewer, std::vector<bool>(fewer.size(), true));
  EXPECT_EQ(near.rule.back(), static_cast<int>(AreaRule::Fitted));
  EXPECT_EQ(near.area.back(), fewer.back().area);

  // Leaves that differ in size (0.55 to 1.4 times a length) spread the larger half as they spread the whole sample,
  // with or without the same pieces: the plant is not taken for one of one size and the corner keeps the shape's
  // estimate.
  for (const bool withPieces : { false, true })
  {
    std::vector<LeafTraits> varied;
    for (double scale : { 0.55, 0.7, 0.85, 1.0, 1.1, 1.2, 1.4 })
      varied.push_back(CutEllipse(a * scale, b * scale, 1, 1));
    if (withPieces)
      for (double piece : { 0.3, 0.4, 0.5 })
        varied.push_back(CutEllipse(a * piece, b * piece, 1, 1));
    varied.push_back(traits[corner]);
    const LeafAreaEstimates shapeOnly = EstimateLeafAreas(varied, std::vector<bool>(varied.size(), true));
    ASSERT_TRUE(shapeOnly.shape.valid) << withPieces;
    EXPECT_FALSE(shapeOnly.shape.oneSize) << withPieces;
    EXPECT_GT(shapeOnly.shape.areaSpread, 0.3) << withPieces;
    EXPECT_EQ(shapeOnly.rule.back(), static_cast<int>(AreaRule::LongFromShort)) << withPieces;
    EXPECT_LT(shapeOnly.area.back() / whole, 0.3) << withPieces;
    // No plant size, no pieces: every leaf of the plant's shape keeps its Area.
    for (std::size_t i = 0; i + 1 < varied.size(); ++i)
    {
      EXPECT_EQ(shapeOnly.rule[i], static_cast<int>(AreaRule::Fitted)) << withPieces << " " << i;
      EXPECT_EQ(shapeOnly.area[i], varied[i].area) << withPieces << " " << i;
    }
  }

  // Two leaf sizes seen whole, as many small leaves (0.6 of the length) as large ones: the larger half is the large
  // leaves, so the plant is taken for one of their size, but the small leaves are as many as they: a second leaf
  // size (young leaves), not pieces, and every leaf keeps its Area.
  std::vector<LeafTraits> twoSizes;
  for (double stretch : { 1.0, 1.005, 0.995, 1.01, 0.99 })
  {
    twoSizes.push_back(CutEllipse(a * stretch, b * stretch, 1, 1));
    twoSizes.push_back(CutEllipse(0.6 * a * stretch, 0.6 * b * stretch, 1, 1));
  }
  const LeafAreaEstimates two = EstimateLeafAreas(twoSizes, std::vector<bool>(twoSizes.size(), true));
  ASSERT_TRUE(two.shape.valid);
  EXPECT_EQ(two.shape.sizeLeaves, 5);
  EXPECT_EQ(two.shape.smallerLeaves, 5);
  for (std::size_t i = 0; i < twoSizes.size(); ++i)
  {
    EXPECT_EQ(two.rule[i], static_cast<int>(AreaRule::Fitted)) << i;
    EXPECT_EQ(two.area[i], twoSizes[i].area) << i;
  }
}

TEST(LeafAreaEstimate, PiecesWhoseMarginTheScannerSawHiddenAreNotTakenWholeAndGetThePlantsSize)
{
  // The plant of the test above: six blades seen whole and seven smaller copies of the shape, which the shape alone
  // takes for leaves of another size (they are more than the blades). With the scanners' view known, the copies'
  // margins are hidden over 0.6 of them and the blades' over 0.05: the shape is the blades', and every copy is a
  // piece of a blade of the plant's one size.
  const double a = 2.0, b = a / 1.5, whole = Pi * a * b;
  std::vector<LeafTraits> traits = SixWholeLeaves(a, b);
  for (LeafTraits& blade : traits)
    blade.hiddenMargin = 0.05;
  for (double piece : { 0.3, 0.5, 0.6, 0.7, 0.75, 0.8, 0.85 })
  {
    traits.push_back(CutEllipse(a * piece, b * piece, 1, 1));
    traits.back().hiddenMargin = 0.6;
  }
  const LeafAreaEstimates out = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  ASSERT_TRUE(out.shape.valid);
  EXPECT_EQ(out.shape.wholeLeaves, 6);
  EXPECT_TRUE(out.shape.oneSize);
  EXPECT_EQ(out.shape.smallerLeaves, 0);
  for (std::size_t i = 0; i < traits.size(); ++i)
    if (i < 6)
    {
      EXPECT_EQ(out.rule[i], static_cast<int>(AreaRule::Fitted)) << i;
      EXPECT_EQ(out.area[i], traits[i].area) << i;
    }
    else
    {
      EXPECT_EQ(out.rule[i], static_cast<int>(AreaRule::Piece)) << i;
      EXPECT_NEAR(out.area[i] / whole, 1.0, 0.01) << i;
    }
  // A margin hidden up to MaxHiddenMarginOfWhole still counts as seen whole; past it, not.
  for (std::size_t i = 6; i < traits.size(); ++i)
    traits[i].hiddenMargin = MaxHiddenMarginOfWhole;
  EXPECT_EQ(EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true)).shape.wholeLeaves, 13);
}

TEST(LeafAreaEstimate, LeavesSeenWholeByTheViewOfSeveralSizesAreNotTakenForOneSize)
{
  // A plant of three leaf sizes (0.5, 0.75 and 1 of a length) seen from one position: its whole leaves by the view
  // are four of each size, its five largest alike. Their larger half is of one size; all of them are not, and the
  // plant is not taken for one of one size. A leaf narrower than the plant's shape is cut along a side and keeps its
  // long extent (AreaRule 2, not raised to a size); a corner of a leaf (its view blocked) gets the shape's estimate.
  const double a = 2.0, b = a / 1.5;
  std::vector<LeafTraits> traits;
  for (double size : { 0.5, 0.75, 1.0 })
    for (double stretch : { 1.0, 1.005, 0.995, 1.01 })
    {
      traits.push_back(CutEllipse(a * size * stretch, b * size * stretch, 1, 1));
      traits.back().hiddenMargin = 0.1;
    }
  traits.push_back(CutEllipse(a, 0.6 * b, 1, 1)); // a side cut off by the segmentation: its margin seen free
  traits.back().hiddenMargin = 0.05;
  const std::size_t odd = traits.size() - 1;
  traits.push_back(CornerOfEllipse(a, b, -0.2, 0.0));
  traits.back().hiddenMargin = 0.7;
  const std::size_t corner = traits.size() - 1;
  const LeafAreaEstimates out = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  ASSERT_TRUE(out.shape.valid);
  EXPECT_TRUE(out.shape.fromView);
  EXPECT_FALSE(out.shape.oneSize);
  EXPECT_GT(out.shape.areaSpread, 0.3);
  EXPECT_EQ(out.rule[odd], static_cast<int>(AreaRule::ShortFromLong));
  EXPECT_NEAR(out.area[odd] / (Pi * a * b), 1.0, 0.03);
  EXPECT_EQ(out.rule[corner], static_cast<int>(AreaRule::LongFromShort));
  EXPECT_GT(out.area[corner], traits[corner].area);
  // Without the view the same leaves are judged by their shape alone, and the spread of the larger half (kept for
  // the pieces the shape takes whole) calls the plant one of one size: the odd leaf is cut and raised to that size.
  for (LeafTraits& t : traits)
    t.hiddenMargin = std::numeric_limits<double>::quiet_NaN();
  const LeafAreaEstimates shapeOnly = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  EXPECT_FALSE(shapeOnly.shape.fromView);
  EXPECT_TRUE(shapeOnly.shape.oneSize);
  EXPECT_EQ(shapeOnly.rule[odd], static_cast<int>(AreaRule::PlantSize));
}

TEST(LeafAreaEstimate, ALeafHiddenInPartGetsItsAreaFromTheExtentTheScannerSawWhole)
{
  // A plant of three leaf sizes whose whole leaves' Length over Width spreads by +-10 % (as fitted leaves do), so
  // the whole leaves' range of the ratio is wide: a leaf whose tip is hidden at 0.85 of its semi-axis (0.966 of its
  // area) is still inside it, and by its shape keeps its Area. The view says its Width was seen whole: from it and
  // the plant's Length over Width its Length, and so its area (AreaRule 6). A leaf with a side hidden likewise,
  // from its Length.
  const double a = 2.0, b = a / 1.5;
  std::vector<LeafTraits> traits;
  const std::vector<double> stretch = { 0.9, 0.95, 1.0, 1.05, 1.1 };
  for (double size : { 0.5, 0.75, 1.0 })
    for (double s : stretch)
    {
      traits.push_back(CutEllipse(a * size, b * size * s, 1, 1));
      traits.back().hiddenMargin = 0.1;
      traits.back().extentsSeen = LengthSeen + WidthSeen;
    }
  const std::size_t tip = traits.size(), side = tip + 1, free = tip + 2;
  traits.push_back(CutEllipse(0.8 * a, 0.8 * b, 0.85, 1));
  traits.back().hiddenMargin = 0.3;
  traits.back().extentsSeen = WidthSeen;
  traits.push_back(CutEllipse(0.8 * a, 0.8 * b, 1, 0.85));
  traits.back().hiddenMargin = 0.3;
  traits.back().extentsSeen = LengthSeen;
  traits.push_back(CutEllipse(0.8 * a, 0.8 * b, 0.85, 1)); // its margin seen free: whole, or cut by the segmentation
  traits.back().hiddenMargin = 0.2;
  traits.back().extentsSeen = WidthSeen;
  const double truth = Pi * 0.64 * a * b;
  const LeafAreaEstimates out = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  ASSERT_TRUE(out.shape.valid);
  EXPECT_FALSE(out.shape.oneSize);
  EXPECT_TRUE(out.shape.extentsAgree);
  EXPECT_NEAR(out.shape.lengthOverWidth, 1.5, 1e-9);
  EXPECT_NEAR(out.shape.fillOfExtents, Pi / 4.0, 1e-9);
  EXPECT_LT(traits[tip].area / truth, 0.97);
  for (const std::size_t i : { tip, side })
  {
    EXPECT_EQ(out.rule[i], static_cast<int>(AreaRule::FromSeenExtents)) << i;
    EXPECT_NEAR(out.area[i] / truth, 1.0, 1e-9) << i;
  }
  EXPECT_EQ(out.rule[free], static_cast<int>(AreaRule::Fitted));
  EXPECT_EQ(out.area[free], traits[free].area);
  // By its shape alone (no extent seen) the tip-cut leaf is inside the whole leaves' range and keeps its Area.
  traits[tip].extentsSeen = 0;
  const LeafAreaEstimates unseen = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  EXPECT_EQ(unseen.rule[tip], static_cast<int>(AreaRule::Fitted));
  EXPECT_EQ(unseen.area[tip], traits[tip].area);
  // Whole leaves whose Length runs one way on some and the other way on others (a blade nearly as wide as long whose
  // midvein the fit may lay either way) say nothing of a leaf's other extent: no AreaRule 6.
  for (std::size_t i = 0; i < tip; i += 2)
    std::swap(traits[i].length, traits[i].width);
  traits[tip].extentsSeen = WidthSeen;
  const LeafAreaEstimates crossed = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  EXPECT_FALSE(crossed.shape.extentsAgree);
  EXPECT_NE(crossed.rule[tip], static_cast<int>(AreaRule::FromSeenExtents));
  EXPECT_NE(crossed.rule[side], static_cast<int>(AreaRule::FromSeenExtents));
}

TEST(LeafAreaEstimate, ACurledOrTurnedLeafSeenWholeIsWhole)
{
  // The shape is read from the arc lengths on the blade (Length, Width), not from the projected extents: a leaf
  // rolled about its midvein projects 30 % narrower, and a round blade's plane's major axis can turn anywhere (its
  // projected extents then measured across a diagonal), but seen whole it keeps its Area.
  const double a = 2.0, b = a / 1.5;
  std::vector<LeafTraits> traits = SixWholeLeaves(a, b);
  LeafTraits curled = CutEllipse(a, b, 1, 1);
  curled.projectedWidth *= 0.7;
  traits.push_back(curled);
  LeafTraits turned = CutEllipse(a, b, 1, 1);
  turned.projectedLength = turned.projectedWidth = 0.5 * (turned.length + turned.width);
  traits.push_back(turned);
  const LeafAreaEstimates out = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  ASSERT_TRUE(out.shape.valid);
  EXPECT_EQ(out.shape.wholeLeaves, 8);
  for (std::size_t i = 0; i < traits.size(); ++i)
  {
    EXPECT_EQ(out.rule[i], static_cast<int>(AreaRule::Fitted)) << i;
    EXPECT_EQ(out.area[i], traits[i].area) << i;
  }
}

TEST(LeafAreaEstimate, WithoutThreeWholeLeavesEveryLeafKeepsItsArea)
{
  // Two whole leaves and one with a side hidden.
  const std::vector<LeafTraits> traits = { CutEllipse(2.0, 1.0, 1, 1), CutEllipse(3.0, 1.5, 1, 1),
    CutEllipse(2.0, 1.0, 1, 0.0) };
  const LeafAreaEstimates out = EstimateLeafAreas(traits, { true, true, true });
  EXPECT_FALSE(out.shape.valid);
  for (std::size_t i = 0; i < traits.size(); ++i)
  {
    EXPECT_EQ(out.area[i], traits[i].area) << i;
    EXPECT_EQ(out.rule[i], static_cast<int>(AreaRule::NoPlantShape)) << i;
  }
  // A leaf not fitted has no estimate and takes no part.
  std::vector<LeafTraits> more(3, CutEllipse(2.0, 1.0, 1, 1));
  more.push_back(CutEllipse(2.0, 1.0, 1, 0.0));
  const LeafAreaEstimates some = EstimateLeafAreas(more, { true, true, false, true });
  EXPECT_FALSE(some.shape.valid);
  EXPECT_TRUE(std::isnan(some.area[2]));
  EXPECT_EQ(some.rule[2], -1);
}

TEST(LeafAreaEstimate, TraitsReadBackFromATraitsRowAreTheTraits)
{
  // The Traits table's rows are what the estimate reads (gathered from every rank): each value back in its field.
  LeafTraits t;
  std::vector<double> values = TraitValues(t);
  for (std::size_t k = 0; k < values.size(); ++k)
    values[k] = 1.0 + static_cast<double>(k);
  const LeafTraits back = TraitsFromValues(values);
  EXPECT_EQ(TraitValues(back), values);
  EXPECT_EQ(back.projectedWidth, values[3]);
  EXPECT_EQ(back.coverage, values[20]);
  EXPECT_EQ(back.hiddenMargin, values[24]);
  // Not a row: default traits (HiddenMargin NaN, not known, in both).
  const std::vector<double> fallback = TraitValues(TraitsFromValues({ 1.0, 2.0 })), plain = TraitValues(LeafTraits());
  ASSERT_EQ(fallback.size(), plain.size());
  for (std::size_t k = 0; k < plain.size(); ++k)
    EXPECT_TRUE(fallback[k] == plain[k] || (std::isnan(fallback[k]) && std::isnan(plain[k]))) << k;
}

/// Points on a flat ellipse (semi-axes a along X, b along Y) on a jittered grid of step h, kept where x <= u a and
/// y <= v b.
std::vector<Eigen::Vector3d> ScannedCutEllipse(double a, double b, double u, double v, double h, unsigned seed)
{
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> jitter(-0.3 * h, 0.3 * h);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::vector<Eigen::Vector3d> points;
  for (double x = -a; x <= a; x += h)
    for (double y = -b; y <= b; y += h)
    {
      const Eigen::Vector3d p(x + jitter(random), y + jitter(random), noise(random));
      if ((p.x() / a) * (p.x() / a) + (p.y() / b) * (p.y() / b) <= 1.0 && p.x() <= u * a && p.y() <= v * b)
        points.push_back(p);
    }
  return points;
}

TEST(LeafAreaEstimate, ScannedCutLeavesOfAPlantFitAndGetTheirWholeArea)
{
  // Four whole ellipses of length over width 1.6 and four sizes, one cut across the tip at 0.4 of its half length,
  // one along a side at 0.3 of its half width; each fitted by FitLeaf.
  struct Leaf
  {
    double a, u, v;
  };
  const std::vector<Leaf> leaves = { { 4.0, 1, 1 }, { 5.0, 1, 1 }, { 3.5, 1, 1 }, { 4.5, 1, 1 }, { 4.0, 0.4, 1 },
    { 5.0, 1, 0.3 } };
  std::vector<LeafTraits> traits;
  for (std::size_t i = 0; i < leaves.size(); ++i)
  {
    const double a = leaves[i].a, b = a / 1.6;
    const LeafFitResult fit =
      FitLeaf(ScannedCutEllipse(a, b, leaves[i].u, leaves[i].v, 0.1, 10u + static_cast<unsigned>(i)), {});
    ASSERT_EQ(fit.error, "") << i;
    traits.push_back(fit.traits);
  }
  const LeafAreaEstimates out = EstimateLeafAreas(traits, std::vector<bool>(traits.size(), true));
  ASSERT_TRUE(out.shape.valid);
  EXPECT_EQ(out.shape.wholeLeaves, 4);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_EQ(out.area[i], traits[i].area) << i; // seen whole: the fitted Area itself
  // The fitted blade of a part runs past the ends of its straight cut edge (the smoothing outline rounds the corners
  // outwards): the tip-cut leaf's width comes out 5 % wide, the side-cut leaf's length 8 % long, and the estimate
  // takes them for the whole leaf's: 10 % and 18 % over, where the fitted areas are 25 % and 32 % under.
  for (std::size_t i = 4; i < leaves.size(); ++i)
  {
    const double whole = Pi * leaves[i].a * leaves[i].a / 1.6;
    EXPECT_LT(traits[i].area / whole, 0.8) << i;
    EXPECT_LT(std::abs(out.area[i] / whole - 1.0), 0.6 * std::abs(traits[i].area / whole - 1.0)) << i;
    EXPECT_NEAR(out.area[i] / whole, 1.0, 0.2) << i;
  }
  EXPECT_EQ(out.rule[4], static_cast<int>(AreaRule::LongFromShort));
  EXPECT_EQ(out.rule[5], static_cast<int>(AreaRule::ShortFromLong));
}

/// Points of a square grid of spacing h (offset by (ox, oy)) in the part x <= u a of the ellipse x^2 / a^2 + y^2 / b^2
/// <= 1: what a scan at one density holds of it.
double GridPointsInEllipse(double a, double b, double u, double h, double ox, double oy)
{
  double count = 0.0;
  for (double x = -a + ox; x <= u * a; x += h)
    for (double y = -b + oy; y <= b; y += h)
      if (x * x / (a * a) + y * y / (b * b) <= 1.0)
        count += 1.0;
  return count;
}

TEST(LeafAreaEstimate, LeafPointsOnNoLeafAddTheAreaTheyCover)
{
  // Four fitted leaves of several sizes scanned at one spacing h (their Area exact, their Points the grid's), and
  // the leaf points of a fifth leaf seen only in part (x <= 0.3 a) that a segmentation gave no leaf: their area is
  // the piece's, within the grid's counting error (under 1 % at 50 spacings across).
  const double h = 0.02;
  const std::vector<double> sizes = { 1.0, 1.3, 1.6, 2.0 };
  std::vector<LeafTraits> traits;
  double fittedArea = 0.0;
  for (std::size_t i = 0; i < sizes.size(); ++i)
  {
    LeafTraits t;
    const double a = sizes[i], b = 0.6 * a;
    t.area = Pi * a * b;
    t.points = GridPointsInEllipse(a, b, 1.0, h, 0.3 * h * static_cast<double>(i), 0.7 * h);
    t.projectedLength = 2.0 * a;
    t.projectedWidth = 2.0 * b;
    t.coverage = 1.0;
    traits.push_back(t);
    fittedArea += t.area;
  }
  const std::vector<bool> fitted(traits.size(), true);
  const double a = 1.5, b = 0.9, u = 0.3;
  const double piecePoints = GridPointsInEllipse(a, b, u, h, 0.5 * h, 0.2 * h);
  const double pieceArea = EllipsePartArea(a, b, u);
  EXPECT_NEAR(UnassignedLeafArea(traits, fitted, piecePoints) / pieceArea, 1.0, 0.01);
  EXPECT_EQ(UnassignedLeafArea(traits, fitted, 0.0), 0.0);
  // A leaf not fitted (its traits NaN) and a fitted leaf without points take no part in the density.
  std::vector<LeafTraits> more = traits;
  more.push_back(LeafTraits{});
  more.back().area = std::numeric_limits<double>::quiet_NaN();
  more.push_back(traits.front());
  more.back().points = 0.0;
  EXPECT_DOUBLE_EQ(UnassignedLeafArea(more, { true, true, true, true, false, true }, piecePoints),
    UnassignedLeafArea(traits, fitted, piecePoints));
  EXPECT_TRUE(std::isnan(UnassignedLeafArea(std::vector<LeafTraits>(2), { true, true }, piecePoints)));

  // The Plant table: the points and their area in their own columns, the area in TotalEstimatedLeafArea (the
  // leaves here are whole, so their EstimatedArea is their Area), TotalLeafArea unchanged.
  const PlantSummary without = SummarizePlant(traits, fitted);
  const PlantSummary with = SummarizePlant(traits, fitted, piecePoints);
  EXPECT_DOUBLE_EQ(without.totalEstimatedArea, fittedArea);
  EXPECT_DOUBLE_EQ(without.unassignedLeafArea, 0.0);
  EXPECT_DOUBLE_EQ(with.totalArea, fittedArea);
  EXPECT_EQ(with.unassignedLeafPoints, piecePoints);
  EXPECT_NEAR(with.totalEstimatedArea, fittedArea + pieceArea, 0.01 * pieceArea);
  EXPECT_DOUBLE_EQ(with.totalEstimatedArea, fittedArea + with.unassignedLeafArea);
  const std::vector<std::string> names = PlantColumnNames();
  const std::vector<double> values = PlantColumnValues(with);
  ASSERT_EQ(names.size(), values.size());
  const auto at = std::find(names.begin(), names.end(), "UnassignedLeafArea") - names.begin();
  ASSERT_LT(static_cast<std::size_t>(at), names.size());
  EXPECT_EQ(values[at], with.unassignedLeafArea);
  EXPECT_EQ(ColumnUnit("UnassignedLeafArea", "mm"), "mm^2");
}

} // namespace
} // namespace plantmorph
