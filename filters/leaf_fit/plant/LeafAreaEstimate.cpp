// SPDX-License-Identifier: GPL-3.0-or-later
#include "LeafAreaEstimate.h"

#include "LeafPlant.h"   // MinCoverage
#include "ScannerView.h" // LengthSeen, WidthSeen

#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph
{
namespace
{
double Median(std::vector<double> values)
{
  const std::size_t half = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + half, values.end());
  const double upper = values[half];
  if (values.size() % 2 == 1)
    return upper;
  return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + half));
}

/// The median absolute deviation of `values` from `centre`.
double MedianDeviation(const std::vector<double>& values, double centre)
{
  std::vector<double> deviation(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    deviation[i] = std::abs(values[i] - centre);
  return Median(deviation);
}

/// The robust spread of `values` about `centre`: 1.4826 x their median absolute deviation from it.
double RobustSpread(const std::vector<double>& values, double centre)
{
  return 1.4826 * MedianDeviation(values, centre);
}

/// A leaf's long extent: the longer of its Length and Width (arc lengths on the blade, along the midvein and across).
double LongExtent(const LeafTraits& t)
{
  return std::max(t.length, t.width);
}

/// A leaf's short extent: the shorter of its Length and Width.
double ShortExtent(const LeafTraits& t)
{
  return std::min(t.length, t.width);
}

/// A fitted leaf's log ratio (long over short extent) and log fill (Area over the long extent squared); false when
/// its extents or area do not give them.
bool LeafShape(const LeafTraits& t, double& logRatio, double& logFill)
{
  const double high = LongExtent(t);
  const double low = ShortExtent(t);
  if (!(low > 0.0) || !std::isfinite(high) || !(t.area > 0.0) || !std::isfinite(t.area))
    return false;
  logRatio = std::log(high / low);
  logFill = std::log(t.area / (high * high));
  return true;
}

/// The plant's shape from the leaves `usable` (their log ratios and fills in `ratio`, `fill`); `whole` gets the
/// leaves it was taken from.
PlantShape ShapeOfWholeLeaves(const std::vector<double>& ratio, const std::vector<double>& fill,
  const std::vector<bool>& usable, std::vector<bool>& whole)
{
  PlantShape shape;
  whole = usable;
  double centreRatio = 0.0, centreFill = 0.0;
  for (int round = 0; round < 5; ++round)
  {
    std::vector<double> r, f;
    for (std::size_t i = 0; i < ratio.size(); ++i)
      if (whole[i])
      {
        r.push_back(ratio[i]);
        f.push_back(fill[i]);
      }
    if (static_cast<int>(r.size()) < MinWholeLeaves)
      return shape;
    centreRatio = Median(r);
    centreFill = Median(f);
    const double spreadRatio = std::max(RobustSpread(r, centreRatio), MinShapeSpread);
    const double spreadFill = std::max(RobustSpread(f, centreFill), MinShapeSpread);
    for (std::size_t i = 0; i < ratio.size(); ++i)
      whole[i] = usable[i] && std::abs(ratio[i] - centreRatio) <= SpreadsOfWhole * spreadRatio &&
        std::abs(fill[i] - centreFill) <= SpreadsOfWhole * spreadFill;
  }
  shape.lowRatio = std::numeric_limits<double>::infinity();
  shape.highRatio = -shape.lowRatio;
  for (std::size_t i = 0; i < ratio.size(); ++i)
    if (whole[i])
    {
      ++shape.wholeLeaves;
      shape.lowRatio = std::min(shape.lowRatio, std::exp(ratio[i]));
      shape.highRatio = std::max(shape.highRatio, std::exp(ratio[i]));
    }
  shape.valid = shape.wholeLeaves >= MinWholeLeaves;
  shape.ratio = std::exp(centreRatio);
  shape.fill = std::exp(centreFill);
  return shape;
}

/// The plant's size from the log Area of the leaves `whole`: the median of their larger half and its robust spread
/// about it, scaled to the spread of the whole leaves' log Area under a normal spread (LargerHalfSpreadScale).
/// Pieces of blades taken whole by their shape are smaller than the blade and fall in the smaller half.
void SizeOfWholeLeaves(const std::vector<LeafTraits>& traits, const std::vector<bool>& whole, PlantShape& shape)
{
  std::vector<double> logArea;
  for (std::size_t i = 0; i < whole.size(); ++i)
    if (whole[i])
      logArea.push_back(std::log(traits[i].area));
  if (logArea.empty())
  {
    shape.areaSpread = std::numeric_limits<double>::infinity();
    return;
  }
  std::sort(logArea.begin(), logArea.end());
  const std::vector<double> larger(logArea.begin() + static_cast<std::ptrdiff_t>(logArea.size() / 2), logArea.end());
  shape.logSize = Median(larger);
  shape.areaSpread = LargerHalfSpreadScale * MedianDeviation(larger, shape.logSize);
  // Leaves seen whole by the view hold no pieces: a larger half of a few leaves of near sizes must not hide the
  // spread of the others (a plant of three leaf sizes seen from one position, its largest leaves alike).
  if (shape.fromView)
    shape.areaSpread = std::max(shape.areaSpread, RobustSpread(logArea, Median(logArea)));
}

/// The least log Area of a leaf of the plant's size: SpreadsOfWhole spreads (no less than MinShapeSpread) under the
/// larger half's median.
double SizeFloor(const PlantShape& shape)
{
  return shape.logSize - SpreadsOfWhole * std::max(shape.areaSpread, MinShapeSpread);
}

/// The Areas of the leaves `whole` of the plant's size (log Area at least SpreadsOfWhole spreads under the larger
/// half's median) whose long extent is at least `longExtent`.
std::vector<double> SizeLeafAreas(
  const std::vector<LeafTraits>& traits, const std::vector<bool>& whole, const PlantShape& shape, double longExtent)
{
  const double least = SizeFloor(shape);
  std::vector<double> areas;
  for (std::size_t i = 0; i < whole.size(); ++i)
    if (whole[i] && std::log(traits[i].area) >= least && LongExtent(traits[i]) >= longExtent)
      areas.push_back(traits[i].area);
  return areas;
}

/// A cut leaf's estimate on a plant of one size (AreaRule 4, or `area` unchanged): the median Area of the size
/// leaves whose long extent is at least `longExtent` when that is more than `area`; the median Area of all the size
/// leaves when `area` is more than the largest of them (a cut leaf's shape estimate past every leaf of the plant's
/// one size: a leaf seen nearly whole whose ratio fell just outside the whole leaves' range, its long extent
/// stretched by the ratio), but never less than the leaf's own Area `own`.
double PlantSizeArea(const std::vector<LeafTraits>& traits, const std::vector<bool>& whole, const PlantShape& shape,
  double longExtent, double own, double area)
{
  const std::vector<double> atLeast = SizeLeafAreas(traits, whole, shape, longExtent);
  const double atLeastMedian = atLeast.empty() ? 0.0 : Median(atLeast);
  if (atLeastMedian > area)
    return atLeastMedian;
  if (shape.sizeLeaves > 0 && area > shape.sizeLargestArea)
    return std::max(own, shape.sizeArea);
  return area;
}

/// On a plant of one size, a cut leaf's estimate `out.area[i]` (long extent `longExtent`) to the plant's size when
/// PlantSizeArea says so (AreaRule 4).
void ToPlantSize(const std::vector<LeafTraits>& traits, LeafAreaEstimates& out, std::size_t i, double longExtent)
{
  const double plantSize = out.shape.oneSize
    ? PlantSizeArea(traits, out.whole, out.shape, longExtent, traits[i].area, out.area[i])
    : out.area[i];
  if (plantSize != out.area[i])
  {
    out.area[i] = plantSize;
    out.rule[i] = static_cast<int>(AreaRule::PlantSize);
  }
}

/// A leaf not seen whole (`out.whole[i]` false) whose ratio lies outside the whole leaves' range: AreaRule 1 or 2
/// and the shape's estimate, or AreaRule 4 on a plant of one size (PlantSizeArea). Inside the range it keeps its Area.
void EstimateCutLeaf(const std::vector<LeafTraits>& traits, LeafAreaEstimates& out, std::size_t i)
{
  const double high = LongExtent(traits[i]);
  const double low = ShortExtent(traits[i]);
  const double ratioHere = high / low;
  double longExtent = high;
  if (ratioHere < out.shape.lowRatio) // rounder than every whole leaf: its long extent is short
  {
    longExtent = out.shape.ratio * low;
    out.rule[i] = static_cast<int>(AreaRule::LongFromShort);
  }
  else if (ratioHere > out.shape.highRatio) // narrower: its short extent is short, the long one is whole
    out.rule[i] = static_cast<int>(AreaRule::ShortFromLong);
  else
    return;
  out.area[i] = std::max(traits[i].area, out.shape.fill * longExtent * longExtent);
  ToPlantSize(traits, out, i, longExtent);
}

/// A leaf whose margin was hidden past more than MaxHiddenMarginOfWhole of it, one of whose extents the scanners saw
/// whole (ExtentsSeen): its area from the extents seen and the plant's Length over Width and fill of Length x Width
/// (AreaRule 6, never less than its Area; on a plant of one size, ToPlantSize). False, the leaf unchanged, when the
/// view did not see an extent whole or the plant's whole leaves do not agree on which way their Length runs.
bool EstimateFromSeenExtents(const std::vector<LeafTraits>& traits, LeafAreaEstimates& out, std::size_t i)
{
  const LeafTraits& t = traits[i];
  if (!out.shape.extentsAgree || !(t.hiddenMargin > MaxHiddenMarginOfWhole) || !std::isfinite(t.extentsSeen))
    return false;
  const int seen = static_cast<int>(t.extentsSeen);
  const bool length = (seen & LengthSeen) != 0 && t.length > 0.0;
  const bool width = (seen & WidthSeen) != 0 && t.width > 0.0;
  if (!length && !width)
    return false;
  const double l = length ? t.length : out.shape.lengthOverWidth * t.width;
  const double w = width ? t.width : t.length / out.shape.lengthOverWidth;
  out.area[i] = std::max(t.area, out.shape.fillOfExtents * l * w);
  out.rule[i] = static_cast<int>(AreaRule::FromSeenExtents);
  ToPlantSize(traits, out, i, std::max(l, w));
  return true;
}

/// The plant's Length over Width and fill of Length x Width, from the whole leaves, when the view says which leaves
/// are whole (PlantShape::fromView) and their log Length over Width spreads by at most MaxAxisSpread.
void ExtentsOfWholeLeaves(const std::vector<LeafTraits>& traits, const std::vector<bool>& whole, PlantShape& shape)
{
  if (!shape.fromView)
    return;
  std::vector<double> ratio, fill;
  for (std::size_t i = 0; i < whole.size(); ++i)
    if (whole[i] && traits[i].length > 0.0 && traits[i].width > 0.0)
    {
      ratio.push_back(std::log(traits[i].length / traits[i].width));
      fill.push_back(std::log(traits[i].area / (traits[i].length * traits[i].width)));
    }
  if (static_cast<int>(ratio.size()) < MinWholeLeaves)
    return;
  const double centre = Median(ratio);
  shape.lengthOverWidth = std::exp(centre);
  shape.fillOfExtents = std::exp(Median(fill));
  shape.extentsAgree = RobustSpread(ratio, centre) <= MaxAxisSpread;
}

/// The plant's size leaves (SizeLeafAreas) and the leaves taken whole under them: their counts, and the size leaves'
/// median and largest Area. Once per plant: PlantSizeArea and EstimatePiece read them for every cut leaf or piece.
void CountSizeLeaves(const std::vector<LeafTraits>& traits, const std::vector<bool>& whole, PlantShape& shape)
{
  const std::vector<double> size = SizeLeafAreas(traits, whole, shape, 0.0);
  shape.sizeLeaves = static_cast<int>(size.size());
  shape.sizeArea = size.empty() ? 0.0 : Median(size);
  shape.sizeLargestArea = size.empty() ? 0.0 : *std::max_element(size.begin(), size.end());
  const double least = SizeFloor(shape);
  shape.smallerLeaves = 0;
  for (std::size_t i = 0; i < whole.size(); ++i)
    if (whole[i] && std::log(traits[i].area) < least)
      ++shape.smallerLeaves;
}

/// A leaf of the plant's shape (AreaRule 0) on a plant of one size whose Area is under the plant's size leaves (log
/// Area more than SpreadsOfWhole spreads under the larger half's median), when the leaves taken whole under the size
/// are fewer than the size leaves: a piece of a leaf of that size, given the size leaves' median Area (AreaRule 5).
void EstimatePiece(const std::vector<LeafTraits>& traits, LeafAreaEstimates& out, std::size_t i)
{
  const PlantShape& shape = out.shape;
  if (shape.smallerLeaves >= shape.sizeLeaves || !(std::log(traits[i].area) < SizeFloor(shape)) ||
    !(shape.sizeArea > traits[i].area))
    return;
  out.area[i] = shape.sizeArea;
  out.rule[i] = static_cast<int>(AreaRule::Piece);
}

} // namespace

double UnassignedLeafArea(const std::vector<LeafTraits>& traits, const std::vector<bool>& fitted, double points)
{
  if (!(points > 0.0))
    return 0.0;
  double area = 0.0, count = 0.0;
  for (std::size_t i = 0; i < traits.size(); ++i)
    if (!(i < fitted.size() && !fitted[i]) && traits[i].points > 0.0 && traits[i].area > 0.0 &&
      std::isfinite(traits[i].area))
    {
      area += traits[i].area;
      count += traits[i].points;
    }
  return count > 0.0 ? points * area / count : std::numeric_limits<double>::quiet_NaN();
}

LeafAreaEstimates EstimateLeafAreas(const std::vector<LeafTraits>& traits, const std::vector<bool>& fitted)
{
  const std::size_t n = traits.size();
  LeafAreaEstimates out;
  out.area.assign(n, std::numeric_limits<double>::quiet_NaN());
  out.rule.assign(n, -1);
  std::vector<double> ratio(n, 0.0), fill(n, 0.0);
  std::vector<bool> usable(n, false), seenFree(n, false);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (i < fitted.size() && !fitted[i])
      continue;
    out.area[i] = traits[i].area;
    usable[i] = LeafShape(traits[i], ratio[i], fill[i]) && traits[i].coverage >= MinCoverage;
    seenFree[i] = usable[i] && !(traits[i].hiddenMargin > MaxHiddenMarginOfWhole); // NaN (no view): not judged
  }
  // The leaves whose margin the scanners saw free; with fewer than MinWholeLeaves of them the view does not say
  // which leaves are whole, and the shape is taken from every usable leaf, as without it.
  out.shape = ShapeOfWholeLeaves(ratio, fill, seenFree, out.whole);
  out.shape.fromView = out.shape.valid &&
    std::any_of(traits.begin(), traits.end(), [](const LeafTraits& t) { return std::isfinite(t.hiddenMargin); });
  if (!out.shape.valid && seenFree != usable)
    out.shape = ShapeOfWholeLeaves(ratio, fill, usable, out.whole);
  if (out.shape.valid)
  {
    SizeOfWholeLeaves(traits, out.whole, out.shape);
    out.shape.oneSize = out.shape.areaSpread <= OneSizeSpread;
    CountSizeLeaves(traits, out.whole, out.shape);
    ExtentsOfWholeLeaves(traits, out.whole, out.shape);
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    if (i < fitted.size() && !fitted[i])
      continue;
    out.rule[i] = static_cast<int>(out.shape.valid ? AreaRule::Fitted : AreaRule::NoPlantShape);
    double r = 0.0, f = 0.0;
    if (!out.shape.valid || !LeafShape(traits[i], r, f))
      continue;
    if (!out.whole[i] && !EstimateFromSeenExtents(traits, out, i))
      EstimateCutLeaf(traits, out, i);
    if (out.rule[i] == static_cast<int>(AreaRule::Fitted) && out.shape.oneSize)
      EstimatePiece(traits, out, i);
  }
  return out;
}

} // namespace plantmorph
