// SPDX-License-Identifier: GPL-3.0-or-later
// The checks that say when a fitted leaf is not to be trusted (LeafPlant.h: CheckFittedLeaf).
#include "LeafPlant.h"

#include "BSplineLeaf.h"
#include "LeafGeometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace plantmorph
{
namespace
{
double Area2D(const std::vector<Eigen::Vector2d>& points, const std::vector<std::array<int, 3>>& triangles)
{
  double area = 0.0;
  for (const auto& t : triangles)
  {
    const Eigen::Vector2d a = points[t[1]] - points[t[0]], b = points[t[2]] - points[t[0]];
    area += 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
  }
  return area;
}
} // namespace

double FlatModelArea(const LeafFitResult& fit, int resolution)
{
  if (fit.flatMidvein.size() < 2 || fit.flatLeftMargin.empty() || fit.flatRightMargin.empty())
    return std::numeric_limits<double>::quiet_NaN();
  LeafMeshParameters settings;
  settings.resolution = std::max(resolution, 4);
  settings.quality = false;
  LeafGeometry rebuilt;
  if (!BuildBSplineLeaf({ fit.flatMidvein, fit.flatLeftMargin, fit.flatRightMargin }, settings, rebuilt).empty())
    return std::numeric_limits<double>::quiet_NaN();
  return Area2D(rebuilt.blade.points, rebuilt.blade.triangles);
}

double FlatBladeArea(const LeafFitResult& fit)
{
  return Area2D(fit.flat, fit.triangles);
}

std::vector<std::string> CheckFittedLeaf(const LeafFitResult& fit, int resolution)
{
  std::vector<std::string> warnings;
  if (!fit.modelWarning.empty())
    warnings.push_back(fit.modelWarning);
  if (fit.traits.baseFrom == BaseFromGuess && fit.baseGuess == BaseGuess::WiderHalf)
    warnings.push_back("base and apex are a guess (BaseFrom 3): the base was taken at the blade's wider half, as on "
                       "an ovate leaf, so on an obovate leaf Azimuth, MidveinInclination and LeafUV's v are turned "
                       "end to end (give BasePoint or ApexPoint)");
  else if (fit.traits.baseFrom == BaseFromGuess)
    warnings.push_back("base and apex are a guess (BaseFrom 3): the blade is the same at both ends, so Azimuth, "
                       "MidveinInclination and LeafUV's v may be turned end to end (give BasePoint or ApexPoint)");
  if (fit.sheetShare < MinSheetShare)
  {
    std::ostringstream message;
    message.precision(2);
    message << "the scan samples the blade unevenly: only " << 100.0 * fit.sheetShare
            << " % of the points lie where a ball of 4 point spacings holds most of what one inside the blade holds"
            << " (the scanner's lines far apart over part of it, as at a grazing angle?), so Length and Area may be"
            << " short where the points are sparse" << (fit.petioleLookedFor ? "" : ", and no petiole was looked for")
            << (fit.petioleLookedFor || fit.traits.baseFrom == BaseFromPoint || fit.traits.baseFrom == BaseFromWood
                   ? ""
                   : " (give BasePoint)");
    warnings.push_back(message.str());
  }
  if (fit.apexTrail > MaxApexTrail * fit.traits.coverageSpacing)
  {
    std::ostringstream message;
    message.precision(3);
    message << "the apex is drawn out: its last " << fit.apexTrail << " (" << fit.apexTrail / fit.traits.coverageSpacing
            << " spacings) are a trail of points one across, a tip narrower than the scan's spacing ("
            << fit.traits.coverageSpacing << "), which may run on unseen beyond them: Length may be short (a denser"
            << " scan of the tip measures it)";
    // Told from the base by the shape alone, the trail may as well be a thin petiole the fit did not find (a stalk
    // a point across and a few spacings long): the leaf is then turned end to end.
    if (fit.orientedByShape)
      message << "; the base and apex were told apart by the blade's shape alone, and a thin petiole the fit did not"
              << " find is such a trail too: if the petiole is there, the base and apex are turned end to end (give"
              << " BasePoint or ApexPoint)";
    warnings.push_back(message.str());
  }
  // The base told from the shape by a narrow end's constant width alone: a stalk's, but no petiole was found there.
  if (fit.orientedByShape && fit.baseAtStalkWidth)
    warnings.push_back("the base was put at the blade's narrow end because its last slices keep one width, as a "
                       "stalk's do, but no petiole was found there: if it is a stalk, PetioleLength is 0 and Length "
                       "includes it; if it is a drawn-out tip (widened by the noise or a coarse scan), the base and "
                       "apex are turned end to end (give BasePoint or ApexPoint)");
  if (fit.traits.baseFrom == BaseFromPetiole && fit.traits.petioleLength < MinPetioleShare * fit.traits.length &&
    fit.petioleHalfWidth < MaxNarrowPetiole * fit.traits.spacing + 2.0 * fit.traits.fitRMS)
  {
    std::ostringstream message;
    message.precision(3);
    message << "the petiole found is short (PetioleLength " << fit.traits.petioleLength << ", "
            << 100.0 * fit.traits.petioleLength / fit.traits.length
            << " % of Length) and a point or two across, as the blade's own attenuate base or drawn-out tip is: if"
            << " the leaf has no petiole there, Length is short by it, or the base was put at the apex (give"
            << " BasePoint at the blade's base, or ApexPoint)";
    warnings.push_back(message.str());
  }
  if (fit.traits.coverage < MinCoverage)
  {
    double support = 0.0;
    for (double s : fit.support)
      support = std::max(support, s);
    std::ostringstream message;
    message.precision(3);
    message << "Coverage " << fit.traits.coverage << ": only " << 100.0 * fit.traits.coverage
            << " % of the blade lies within two point spacings ("
            << 2.0 * std::max(fit.traits.spacing, fit.traits.coverageSpacing) << ") of the scan (Support up to "
            << support << "): the blade spreads over empty space (a hole, a petiole or several leaves fitted as one?)";
    warnings.push_back(message.str());
  }
  // The flat model against the fitted blade's area (the Area trait): laying a curved blade flat in its intrinsic
  // coordinates changes its area, and a user who rebuilds and curls the model expects the leaf measured.
  const double model = FlatModelArea(fit, resolution), area = fit.traits.area;
  if (std::isfinite(model) && area > 0.0 && std::abs(model / area - 1.0) > MaxModelAreaError)
  {
    std::ostringstream message;
    message.precision(4);
    message << "the rebuildable flat model (Model C, " << fit.modelControlPoints
            << " control points per curve) has area " << model << " against the fitted blade's " << area << " ("
            << std::showpos << 100.0 * (model / area - 1.0) << std::noshowpos << " %; the blade laid flat has "
            << FlatBladeArea(fit) << "): LeafOutlineSource rebuilds a leaf of another size than the one measured";
    warnings.push_back(message.str());
  }
  return warnings;
}

} // namespace plantmorph
