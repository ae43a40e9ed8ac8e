// SPDX-License-Identifier: GPL-3.0-or-later
// FitLeaf's traits: what plant scientists measure on a leaf, from the fitted surface and blade.
#include "LeafFitInternal.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/PlaneFit.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace plantmorph
{
namespace fit
{
namespace
{
constexpr double Degrees = 180.0 / Pi;

double AngleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  return std::atan2(a.cross(b).norm(), a.dot(b)) * Degrees;
}

/// Arc length of S(t, s) over t in [a, b] at fixed s.
double CrossLength(const TensorSurface& S, double s, double a, double b, int samples)
{
  double length = 0.0;
  Eigen::Vector3d previous = S(a, s);
  for (int i = 1; i <= samples; ++i)
  {
    const Eigen::Vector3d x = S(a + (b - a) * i / samples, s);
    length += (x - previous).norm();
    previous = x;
  }
  return length;
}

void ShapeTraits(const TensorSurface& S, const Outline& o, LeafTraits& traits)
{
  // Length along the midvein from the base (a cordate blade's sinus) to the apex; the width over the whole blade.
  const double L = o.s1 - o.s0, midvein = o.apex - o.base;
  double length = 0.0;
  Eigen::Vector3d previous = S(0.0, o.base);
  for (int i = 1; i <= 2000; ++i)
  {
    const Eigen::Vector3d x = S(0.0, o.base + midvein * i / 2000);
    length += (x - previous).norm();
    previous = x;
  }
  traits.length = length;
  double width = 0.0, rolling = 0.0, curvature = 0.0;
  int stations = 0;
  for (int k = 1; k < 400; ++k)
  {
    const double s = o.s0 + L * k / 400;
    const double across = CrossLength(S, s, o.Left(s), o.Right(s), 100);
    width = std::max(width, across);
    const double xi = static_cast<double>(k) / 400;
    if (xi < 0.2 || xi > 0.8 || !(across > 0.0))
      continue;
    // Rolling: the turn of the normal from the left margin to the right one, about the midvein's tangent;
    // positive when the halves roll up (towards the upper side).
    Eigen::Vector3d dt, ds;
    S.Derivatives(0.0, s, dt, ds);
    const Eigen::Vector3d nL = S.Normal(o.Left(s), s), nR = S.Normal(o.Right(s), s);
    const double angle = -std::atan2(nL.cross(nR).dot(ds.normalized()), nL.dot(nR));
    rolling += angle;
    curvature += angle / across;
    ++stations;
  }
  traits.width = width;
  traits.aspectRatio = width > 0.0 ? length / width : 0.0;
  traits.rolling = stations > 0 ? rolling / stations * Degrees : 0.0;
  traits.rollingCurvature = stations > 0 ? curvature / stations : 0.0;
}

/// Bending: the turn of the midvein's tangent about the blade's own across direction, summed from base to apex
/// (the integral of the midvein's normal curvature), in degrees, its magnitude. The turn about the blade's normal
/// (a midvein curved within a flat blade) is not bending: a flat leaf gives 0 whatever its shape.
double OutOfPlaneBending(const TensorSurface& S, const Outline& o)
{
  const int steps = 400;
  double turn = 0.0;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (int i = 0; i <= steps; ++i)
  {
    Eigen::Vector3d dt, ds;
    const double s = o.base + (o.apex - o.base) * i / steps;
    S.Derivatives(0.0, s, dt, ds);
    const Eigen::Vector3d tangent = ds.normalized();
    if (i > 0 && tangent.allFinite() && previous.allFinite())
    {
      const Eigen::Vector3d across = S.Normal(0.0, s).cross(tangent).normalized();
      turn += std::atan2(previous.cross(tangent).dot(across), previous.dot(tangent));
    }
    previous = tangent;
  }
  return std::abs(turn) * Degrees;
}

void BladeTraits(const LeafFitParameters& options, LeafFitResult& r)
{
  LeafTraits& traits = r.traits;
  const FittedPlane plane = FitPlane(r.points);
  Eigen::Vector3d meanNormal = Eigen::Vector3d::Zero();
  double area = 0.0, projected = 0.0, horizontal = 0.0, covered = 0.0;
  for (const auto& tri : r.triangles)
  {
    const Eigen::Vector3d a = 0.5 * (r.points[tri[1]] - r.points[tri[0]]).cross(r.points[tri[2]] - r.points[tri[0]]);
    area += a.norm();
    projected += std::abs(a.dot(plane.normal));
    horizontal += std::abs(a.dot(options.up));
    meanNormal += a;
    const double support = (r.support[tri[0]] + r.support[tri[1]] + r.support[tri[2]]) / 3.0;
    if (support < 2.0 * std::max(traits.spacing, traits.coverageSpacing))
      covered += a.norm();
  }
  traits.area = area;
  traits.projectedArea = projected;
  traits.horizontalArea = horizontal;
  traits.coverage = area > 0.0 ? covered / area : 0.0;
  traits.inclination = AngleBetween(meanNormal, options.up);
  traits.inclination = std::min(traits.inclination, 180.0 - traits.inclination);
  double lo[2] = { 1e300, 1e300 }, hi[2] = { -1e300, -1e300 };
  const Eigen::Vector3d minor = plane.normal.cross(plane.major);
  for (const auto& p : r.points)
  {
    const double c[2] = { (p - plane.centroid).dot(plane.major), (p - plane.centroid).dot(minor) };
    for (int a = 0; a < 2; ++a)
    {
      lo[a] = std::min(lo[a], c[a]);
      hi[a] = std::max(hi[a], c[a]);
    }
  }
  traits.projectedLength = hi[0] - lo[0];
  traits.projectedWidth = hi[1] - lo[1];
  double perimeter = 0.0;
  for (const std::vector<int>* margin : { &r.leftMargin, &r.rightMargin })
    for (std::size_t i = 1; i < margin->size(); ++i)
      perimeter += (r.points[(*margin)[i]] - r.points[(*margin)[i - 1]]).norm();
  traits.perimeter = perimeter;
  // Fit statistics over the inliers.
  std::vector<double> distances;
  for (std::size_t i = 0; i < r.inlier.size(); ++i)
    if (r.inlier[i])
      distances.push_back(std::abs(r.fitDistance[i]));
  traits.inliers = static_cast<double>(distances.size());
  double sum = 0.0;
  for (double d : distances)
    sum += d * d;
  traits.fitRMS = distances.empty() ? 0.0 : std::sqrt(sum / distances.size());
  traits.fitP95 = traits.fitMax = 0.0;
  if (!distances.empty())
  {
    // The 95th percentile's order statistic placed, not the whole list sorted (10^6 inliers on one thread).
    const auto p95 = distances.begin() +
      static_cast<std::ptrdiff_t>(std::min(distances.size() - 1, static_cast<std::size_t>(0.95 * distances.size())));
    std::nth_element(distances.begin(), p95, distances.end());
    traits.fitP95 = *p95;
    traits.fitMax = *std::max_element(p95, distances.end());
  }
}
} // namespace

void ComputeTraits(const TensorSurface& surface, const Outline& outline, const LeafFitParameters& options,
  const Eigen::Matrix3d& axes, LeafFitResult& result)
{
  LeafTraits& traits = result.traits;
  ShapeTraits(surface, outline, traits);
  BladeTraits(options, result);
  // Angles of the midvein: its out-of-plane bending; its direction and base tangent against `up`.
  const double L = outline.apex - outline.base, d = 0.02 * L;
  const Eigen::Vector3d t0 = axes * (surface(0.0, outline.base + d) - surface(0.0, outline.base));
  traits.bending = OutOfPlaneBending(surface, outline);
  traits.midveinInclination = 90.0 - AngleBetween(t0, options.up);
  const Eigen::Vector3d direction = axes * (surface(0.0, outline.apex) - surface(0.0, outline.base));
  Eigen::Vector3d h1 = Eigen::Vector3d::UnitX() - options.up.x() * options.up;
  if (h1.norm() < 1e-6)
    h1 = Eigen::Vector3d::UnitY() - options.up.y() * options.up;
  h1.normalize();
  const Eigen::Vector3d h2 = options.up.cross(h1);
  traits.azimuth = std::atan2(direction.dot(h2), direction.dot(h1)) * Degrees;
  if (traits.azimuth < 0.0)
    traits.azimuth += 360.0;
}

} // namespace fit

std::vector<std::string> TraitNames()
{
  return { "Length", "Width", "ProjectedLength", "ProjectedWidth", "Area", "ProjectedArea", "HorizontalArea",
    "Perimeter", "AspectRatio", "Bending", "Rolling", "RollingCurvature", "Inclination", "Azimuth",
    "MidveinInclination", "Points", "Inliers", "FitRMS", "FitP95", "FitMax", "Coverage", "Spacing", "BaseFrom",
    "PetioleLength", "HiddenMargin", "ExtentsSeen" };
}

namespace
{
/// The members of a LeafTraits in TraitNames() order, for TraitValues and TraitsFromValues alike; BaseFrom, the one
/// integer, is the null entry.
constexpr std::array<double LeafTraits::*, 26> TraitFields = { &LeafTraits::length, &LeafTraits::width,
  &LeafTraits::projectedLength, &LeafTraits::projectedWidth, &LeafTraits::area, &LeafTraits::projectedArea,
  &LeafTraits::horizontalArea, &LeafTraits::perimeter, &LeafTraits::aspectRatio, &LeafTraits::bending,
  &LeafTraits::rolling, &LeafTraits::rollingCurvature, &LeafTraits::inclination, &LeafTraits::azimuth,
  &LeafTraits::midveinInclination, &LeafTraits::points, &LeafTraits::inliers, &LeafTraits::fitRMS, &LeafTraits::fitP95,
  &LeafTraits::fitMax, &LeafTraits::coverage, &LeafTraits::spacing, nullptr, &LeafTraits::petioleLength,
  &LeafTraits::hiddenMargin, &LeafTraits::extentsSeen };
} // namespace

std::vector<double> TraitValues(const LeafTraits& t)
{
  std::vector<double> values;
  values.reserve(TraitFields.size());
  for (double LeafTraits::*field : TraitFields)
    values.push_back(field ? t.*field : static_cast<double>(t.baseFrom));
  return values;
}

LeafTraits TraitsFromValues(const std::vector<double>& v)
{
  LeafTraits t;
  if (v.size() != TraitFields.size())
    return t;
  for (std::size_t k = 0; k < v.size(); ++k)
    if (TraitFields[k])
      t.*TraitFields[k] = v[k];
    else
      t.baseFrom = std::isfinite(v[k]) ? static_cast<int>(v[k]) : 0;
  return t;
}

} // namespace plantmorph
