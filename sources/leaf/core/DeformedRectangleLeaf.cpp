// SPDX-License-Identifier: GPL-3.0-or-later
#include "DeformedRectangleLeaf.h"

#include <plantmorph/DataContract.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace plantmorph
{
namespace
{
/// Most samples one edge of the rectangle may get: beyond it the terms make a margin too long to mesh.
constexpr double MaxMarginPieces = 1e6;

/// The samples (as LeafUV) of one half-margin: from the base (0, 0) along v = 0 to u = side, up the side to v = 1,
/// and along v = 1 back to the apex (0, 1). Consecutive samples closer than `tolerance` are merged (a fan's base
/// edge collapses to the petiole point).
std::vector<Eigen::Vector2d> HalfMarginUV(
  const DeformedRectangleModel& model, double side, double spacing, double tolerance)
{
  const std::array<Eigen::Vector2d, 4> corners = { Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(side, 0.0),
    Eigen::Vector2d(side, 1.0), Eigen::Vector2d(0.0, 1.0) };
  std::vector<Eigen::Vector2d> uv = { corners[0] };
  Eigen::Vector2d last = model.Evaluate(0.0, 0.0);
  for (int edge = 0; edge < 3; ++edge)
  {
    const Eigen::Vector2d from = corners[edge], to = corners[edge + 1];
    auto at = [&](double t) { return Eigen::Vector2d(from + t * (to - from)); };
    auto curve = [&](double t) {
      const Eigen::Vector2d q = at(t);
      return model.Evaluate(q.x(), q.y());
    };
    const double pieces = std::ceil(CurveLength(curve, 0.0, 1.0) / spacing);
    if (!(pieces <= MaxMarginPieces))
      return {}; // the margin is absurdly long for this spacing: the caller reports it
    const std::vector<double> parameters =
      SampleByArcLength(curve, 0.0, 1.0, std::isfinite(pieces) ? static_cast<int>(pieces) : 0);
    for (std::size_t k = 1; k < parameters.size(); ++k)
    {
      const Eigen::Vector2d q = at(parameters[k]);
      const Eigen::Vector2d p = model.Evaluate(q.x(), q.y());
      if ((p - last).norm() > tolerance)
      {
        uv.push_back(q);
        last = p;
      }
    }
  }
  if (uv.back() != corners[3])
    uv.push_back(corners[3]); // the apex coincides with the last sample only if the top edge collapsed
  return uv;
}
std::string BuildLeaf(
  const DeformedRectangleParameters& parameters, const LeafMeshParameters& settings, LeafGeometry& leaf)
{
  std::string error = Validate(parameters);
  if (!error.empty())
    return error;
  error = ValidateResolution(settings.resolution);
  if (!error.empty())
    return error;
  const DeformedRectangleModel model(parameters);
  const double tolerance = 1e-9 * model.Size();

  // Midvein u = 0: Resolution pieces of equal arc length; the margins use the same spacing.
  auto midveinCurve = [&](double v) { return model.Evaluate(0.0, v); };
  const Eigen::Vector2d apexPoint = model.Evaluate(0.0, 1.0);
  if (!(apexPoint.norm() > tolerance))
    return "Terms: the midvein (u = 0) has no length; the apex falls onto the base";
  const double midveinLength = CurveLength(midveinCurve, 0.0, 1.0);
  const std::vector<double> midveinV = SampleByArcLength(midveinCurve, 0.0, 1.0, settings.resolution);
  if (midveinV.size() < 2)
    return "Terms: the midvein (u = 0) has no length";
  const double spacing = midveinLength / settings.resolution;
  if (settings.progress && !settings.progress(0.02))
    return "aborted";

  BladeOutline outline;
  auto add = [&](const Eigen::Vector2d& uv, int region) {
    outline.points.push_back(model.Evaluate(uv.x(), uv.y()));
    outline.uv.push_back(uv);
    outline.region.push_back(region);
    return static_cast<int>(outline.points.size() - 1);
  };
  for (double v : midveinV)
    leaf.midvein.push_back(add(Eigen::Vector2d(0.0, v), RegionMidvein));
  const int base = leaf.midvein.front(), apex = leaf.midvein.back();

  for (double side : { 0.5, -0.5 })
  {
    std::vector<int>& margin = side > 0 ? leaf.rightMargin : leaf.leftMargin;
    const std::vector<Eigen::Vector2d> uv = HalfMarginUV(model, side, spacing, tolerance);
    if (uv.empty())
      return "Terms: the margin is more than a million Resolution spacings long; lower the amplitudes or "
             "frequencies, or the Resolution";
    const Eigen::Vector2d apexXY = outline.points[apex];
    margin.push_back(base);
    for (std::size_t k = 1; k + 1 < uv.size(); ++k)
    {
      const Eigen::Vector2d p = model.Evaluate(uv[k].x(), uv[k].y());
      if ((p - apexXY).norm() > tolerance && p.norm() > tolerance)
        margin.push_back(add(uv[k], RegionMargin));
    }
    margin.push_back(apex);
  }
  // Counter-clockwise: up the right margin, down the left one.
  outline.boundary = leaf.rightMargin;
  outline.boundary.pop_back();
  outline.boundary.insert(outline.boundary.end(), leaf.leftMargin.rbegin(), leaf.leftMargin.rend() - 1);
  outline.midvein = leaf.midvein;

  const BladeMeshParameters options = MeshParametersFor(settings, spacing);
  std::size_t failures = 0;
  auto solveUV = [&](const Eigen::Vector2d& xy, const Eigen::Vector2d& guess) {
    Eigen::Vector2d uv;
    if (model.Invert(xy, guess, uv))
      return uv;
    ++failures;
    return Eigen::Vector2d(std::clamp(guess.x(), -0.5, 0.5), std::clamp(guess.y(), 0.0, 1.0));
  };
  error = MeshBlade(outline, options, solveUV, leaf.blade);
  if (!error.empty())
    return error.rfind("outline:", 0) == 0 ? "Terms/Width/Length: " + error : error;
  leaf.uvInversionFailures = failures;
  leaf.tcoords = BoundingBoxTextureCoordinates(leaf.blade.points);
  return {};
}
} // namespace

std::string BuildDeformedRectangleLeaf(
  const DeformedRectangleParameters& parameters, const LeafMeshParameters& settings, LeafGeometry& leaf)
{
  return BuildAllOrNothing(leaf, [&] { return BuildLeaf(parameters, settings, leaf); });
}

} // namespace plantmorph
