// SPDX-License-Identifier: GPL-3.0-or-later
#include "BSplineLeaf.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/CubicBSpline.h>
#include <plantmorph/DataContract.h>
#include <plantmorph/PlaneFit.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace plantmorph
{
namespace
{
/// Right-margin control points of a preset, as (x / width, y / length), base and apex excluded.
std::vector<Eigen::Vector2d> RightMarginShape(BSplinePreset preset, int count)
{
  switch (preset)
  {
    case BSplinePreset::Cucumber:
      // Cordate base with a basal lobe below the petiole, an angular lateral lobe, shallow upper lobes.
      return { { 0.15, -0.10 }, { 0.33, -0.09 }, { 0.46, 0.02 }, { 0.50, 0.20 }, { 0.44, 0.36 }, { 0.36, 0.46 },
        { 0.33, 0.62 }, { 0.22, 0.78 }, { 0.10, 0.91 } };
    case BSplinePreset::PinOak:
      // Deep sinuses (x ~ 0.1 of the width) between lobes reaching 0.4-0.5 of it. Every tip and sinus has a
      // shoulder point on each side: an interpolating spline through a bare zigzag makes small loops there.
      return { { 0.08, 0.06 }, { 0.25, 0.08 }, { 0.40, 0.14 }, { 0.30, 0.20 }, { 0.12, 0.26 }, { 0.20, 0.32 },
        { 0.40, 0.36 }, { 0.50, 0.40 }, { 0.36, 0.47 }, { 0.13, 0.52 }, { 0.22, 0.58 }, { 0.42, 0.66 }, { 0.30, 0.71 },
        { 0.10, 0.76 }, { 0.16, 0.84 }, { 0.12, 0.92 } };
    case BSplinePreset::Custom:
    case BSplinePreset::Elliptic:
      break;
  }
  std::vector<Eigen::Vector2d> shape;
  for (int k = 1; k <= count; ++k)
  {
    const double t = static_cast<double>(k) / (count + 1);
    shape.emplace_back(0.5 * std::pow(std::sin(Pi * t), 0.9), t);
  }
  return shape;
}

/// Samples of a curve at (about) `spacing`, with their LeafUV (u fixed, v = arc-length fraction).
std::string SampleCurve(const CubicBSpline3d& curve, double spacing, double u, std::vector<Eigen::Vector3d>& points,
  std::vector<Eigen::Vector2d>& uv)
{
  CubicBSpline3d::PointList samples;
  std::vector<double> parameters;
  const std::string error = curve.SampleAtSpacing(spacing, samples, &parameters);
  if (!error.empty())
    return error;
  points.assign(samples.begin(), samples.end());
  uv.clear();
  for (double t : parameters)
    uv.emplace_back(u, std::clamp(curve.ArcLength(t) / curve.Length(), 0.0, 1.0));
  uv.front().y() = 0.0;
  uv.back().y() = 1.0;
  return {};
}

/// The plane the blade is meshed in: origin, axes e1, e2 and normal n (right-handed).
struct MeshPlane
{
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX(), e2 = Eigen::Vector3d::UnitY(), n = Eigen::Vector3d::UnitZ();
  Eigen::Vector2d Flat(const Eigen::Vector3d& x) const { return { (x - origin).dot(e1), (x - origin).dot(e2) }; }
  double Height(const Eigen::Vector3d& x) const { return (x - origin).dot(n); }
};

/// Exactly XY when every point has the same z; otherwise the least-squares plane, normal towards +Z, e2 along the
/// base-to-apex direction.
MeshPlane PlaneOf(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& base, const Eigen::Vector3d& apex)
{
  MeshPlane plane;
  if (AllAtSameHeight(points))
    return plane;
  const FittedPlane fitted = FitPlane(points);
  const Eigen::Vector3d& n = fitted.normal;
  const Eigen::Vector3d& centroid = fitted.centroid;
  Eigen::Vector3d e2 = (apex - base) - (apex - base).dot(n) * n;
  if (!(e2.norm() > 0.0))
    return plane;
  plane.origin = centroid;
  plane.n = n;
  plane.e2 = e2.normalized();
  plane.e1 = plane.e2.cross(n);
  return plane;
}

std::string BuildLeaf(const BSplineLeafParameters& p, const LeafMeshParameters& settings, LeafGeometry& leaf)
{
  std::string error = ValidateResolution(settings.resolution);
  if (!error.empty())
    return error;
  CubicBSpline3d midvein;
  error = CubicBSpline3d::Interpolate(p.midvein, midvein);
  if (!error.empty())
    return "MidveinPoints: " + error;
  const Eigen::Vector3d base = p.midvein.front(), apex = p.midvein.back();

  // Margins run from the base to the apex: add them where the user's points stop short.
  CubicBSpline3d margins[2];
  const std::vector<Eigen::Vector3d>* given[2] = { &p.leftMargin, &p.rightMargin };
  const char* names[2] = { "LeftMarginPoints", "RightMarginPoints" };
  const double tolerance = 1e-9 * std::max(1.0, (apex - base).norm());
  for (int side = 0; side < 2; ++side)
  {
    std::vector<Eigen::Vector3d> points = *given[side];
    if (points.empty() || (points.front() - base).norm() > tolerance)
      points.insert(points.begin(), base);
    else
      points.front() = base;
    if ((points.back() - apex).norm() > tolerance)
      points.push_back(apex);
    else
      points.back() = apex;
    if (points.size() < 3)
      return std::string(names[side]) + ": needs at least one control point besides the base and the apex";
    error = CubicBSpline3d::Interpolate(points, margins[side]);
    if (!error.empty())
      return std::string(names[side]) + ": " + error;
  }

  // Samples: the midvein in exactly Resolution pieces, the margins at the same spacing.
  const double spacing = midvein.Length() / settings.resolution;
  std::vector<Eigen::Vector3d> midveinPoints, sidePoints[2];
  std::vector<Eigen::Vector2d> midveinUV, sideUV[2];
  {
    const std::vector<double> t = midvein.EqualArcLengthParameters(settings.resolution + 1);
    for (std::size_t i = 0; i < t.size(); ++i)
    {
      midveinPoints.push_back(midvein.Evaluate(t[i]));
      midveinUV.emplace_back(0.0, static_cast<double>(i) / settings.resolution);
    }
    midveinPoints.front() = base;
    midveinPoints.back() = apex;
  }
  for (int side = 0; side < 2; ++side)
  {
    error = SampleCurve(margins[side], spacing, side == 0 ? -0.5 : 0.5, sidePoints[side], sideUV[side]);
    if (!error.empty())
      return std::string(names[side]) + ": " + error;
  }
  if (settings.progress && !settings.progress(0.05))
    return "aborted";

  std::vector<Eigen::Vector3d> samples = midveinPoints;
  samples.insert(samples.end(), sidePoints[0].begin(), sidePoints[0].end());
  samples.insert(samples.end(), sidePoints[1].begin(), sidePoints[1].end());
  const MeshPlane plane = PlaneOf(samples, base, apex);
  std::vector<Eigen::Vector3d> outline3d; // the outline's exact 3-D samples, by outline point id

  BladeOutline outline;
  auto add = [&](const Eigen::Vector3d& x, const Eigen::Vector2d& uv, int region) {
    outline3d.push_back(x);
    outline.points.push_back(plane.Flat(x));
    outline.uv.push_back(uv);
    outline.region.push_back(region);
    return static_cast<int>(outline.points.size() - 1);
  };
  for (std::size_t i = 0; i < midveinPoints.size(); ++i)
    leaf.midvein.push_back(add(midveinPoints[i], midveinUV[i], RegionMidvein));
  const int baseId = leaf.midvein.front(), apexId = leaf.midvein.back();
  for (int side = 1; side >= 0; --side)
  {
    std::vector<int>& margin = side == 0 ? leaf.leftMargin : leaf.rightMargin;
    margin.push_back(baseId);
    for (std::size_t i = 1; i + 1 < sidePoints[side].size(); ++i)
      margin.push_back(add(sidePoints[side][i], sideUV[side][i], RegionMargin));
    margin.push_back(apexId);
  }
  outline.boundary.assign(leaf.rightMargin.begin(), leaf.rightMargin.end() - 1);
  outline.boundary.insert(outline.boundary.end(), leaf.leftMargin.rbegin(), leaf.leftMargin.rend() - 1);
  outline.midvein = leaf.midvein;

  // LeafUV of interior points: mean-value coordinates over the half blade that holds them.
  std::vector<Eigen::Vector2d> halfPolygon[2], halfUV[2], halfHeightValues[2];
  for (int side = 0; side < 2; ++side)
  {
    // Left half: up the midvein, down the left margin; right half: up the right margin, down the midvein.
    std::vector<int> loop;
    if (side == 0)
    {
      loop.assign(leaf.midvein.begin(), leaf.midvein.end() - 1);
      loop.insert(loop.end(), leaf.leftMargin.rbegin(), leaf.leftMargin.rend() - 1);
    }
    else
    {
      loop.assign(leaf.rightMargin.begin(), leaf.rightMargin.end() - 1);
      loop.insert(loop.end(), leaf.midvein.rbegin(), leaf.midvein.rend() - 1);
    }
    for (int id : loop)
    {
      halfPolygon[side].push_back(outline.points[id]);
      halfUV[side].push_back(outline.uv[id]);
      halfHeightValues[side].emplace_back(plane.Height(outline3d[id]), 0.0);
    }
  }
  auto solveUV = [&](const Eigen::Vector2d& x, const Eigen::Vector2d&) {
    const int side = InsidePolygon(halfPolygon[0], x) ? 0 : 1;
    Eigen::Vector2d uv = MeanValueInterpolate(halfPolygon[side], halfUV[side], x);
    uv.x() = side == 0 ? std::clamp(uv.x(), -0.5, 0.0) : std::clamp(uv.x(), 0.0, 0.5);
    uv.y() = std::clamp(uv.y(), 0.0, 1.0);
    return uv;
  };

  const BladeMeshParameters options = MeshParametersFor(settings, spacing);
  error = MeshBlade(outline, options, solveUV, leaf.blade);
  if (!error.empty())
    return error.rfind("outline:", 0) == 0 ? "MidveinPoints/LeftMarginPoints/RightMarginPoints: " + error : error;
  // Eq. (6) on the flat blade, then back to 3-D: outline vertices are their samples, interior ones are lifted off
  // the plane by the mean-value interpolation of the outline's heights.
  leaf.tcoords = BoundingBoxTextureCoordinates(leaf.blade.points);
  std::vector<Eigen::Vector3d> world(leaf.blade.points.size());
  const std::size_t outlineCount = outline3d.size();
  bool flat = true;
  for (std::size_t i = 0; i < world.size(); ++i)
  {
    if (i < outlineCount)
      world[i] = outline3d[i];
    else
    {
      const Eigen::Vector2d& q = leaf.blade.points[i];
      const int side = InsidePolygon(halfPolygon[0], q) ? 0 : 1;
      const double h = MeanValueInterpolate(halfPolygon[side], halfHeightValues[side], q).x();
      world[i] = plane.origin + q.x() * plane.e1 + q.y() * plane.e2 + h * plane.n;
    }
    flat = flat && world[i].z() == 0.0;
  }
  if (!flat)
  {
    for (std::size_t i = 0; i < world.size(); ++i)
    {
      leaf.blade.points[i] = world[i].head<2>();
      leaf.z.push_back(world[i].z());
    }
    leaf.normals = VertexNormals(world, leaf.blade.triangles);
  }
  return {};
}
} // namespace

BSplineLeafParameters MakeBSplinePreset(BSplinePreset preset, double length, double width, int count)
{
  BSplineLeafParameters p;
  const int midveinPoints = std::max(2, count);
  for (int k = 0; k < midveinPoints; ++k)
    p.midvein.emplace_back(0.0, length * k / (midveinPoints - 1), 0.0);
  for (const Eigen::Vector2d& s : RightMarginShape(preset, std::max(1, count)))
  {
    p.rightMargin.emplace_back(width * s.x(), length * s.y(), 0.0);
    p.leftMargin.emplace_back(-width * s.x(), length * s.y(), 0.0);
  }
  return p;
}

std::string BSplinePresetName(BSplinePreset preset)
{
  static const char* const names[BSplinePresetCount] = { "Custom", "Elliptic", "Cucumber", "PinOak" };
  const int index = static_cast<int>(preset);
  return index >= 0 && index < BSplinePresetCount ? names[index] : "Unknown";
}

std::string BuildBSplineLeaf(
  const BSplineLeafParameters& parameters, const LeafMeshParameters& settings, LeafGeometry& leaf)
{
  return BuildAllOrNothing(leaf, [&] { return BuildLeaf(parameters, settings, leaf); });
}

namespace
{
/// The margin on the left of the base-to-apex direction seen from +Z first (the larger summed cross product).
void OrderMargins(const Eigen::Vector3d& base, const Eigen::Vector3d& apex, std::vector<Eigen::Vector3d> margins[2])
{
  const auto side = [&](const std::vector<Eigen::Vector3d>& margin) {
    double sum = 0.0;
    const Eigen::Vector3d d = apex - base;
    for (const Eigen::Vector3d& x : margin)
      sum += d.x() * (x.y() - base.y()) - d.y() * (x.x() - base.x());
    return sum;
  };
  if (side(margins[0]) < side(margins[1]))
    std::swap(margins[0], margins[1]);
}

/// The midvein and the two margins of the lines, by Region or by position; "" or the message.
std::string PickLines(const std::vector<std::vector<Eigen::Vector3d>>& lines, const std::vector<int>* regions,
  std::vector<Eigen::Vector3d>& midvein, std::vector<Eigen::Vector3d> margins[2])
{
  if (!regions)
  {
    if (lines.size() != 3)
    {
      std::ostringstream message;
      message << "without a Region cell array it needs exactly 3 polylines (left margin, right margin, midvein), got "
              << lines.size();
      return message.str();
    }
    margins[0] = lines[0];
    margins[1] = lines[1];
    midvein = lines[2];
    return {};
  }
  int found = 0;
  for (std::size_t k = 0; k < lines.size() && k < regions->size(); ++k)
  {
    if ((*regions)[k] == RegionMidvein && midvein.empty())
      midvein = lines[k];
    else if ((*regions)[k] == RegionMargin && found < 2)
      margins[found++] = lines[k];
  }
  if (midvein.empty() || found < 2)
    return "needs one polyline with Region 1 (midvein) and two with Region 4 (margins)";
  return {};
}
} // namespace

std::string ControlPointsFromLines(const std::vector<std::vector<Eigen::Vector3d>>& lines,
  const std::vector<int>* regions, double scale, BSplineLeafParameters& parameters)
{
  std::vector<Eigen::Vector3d> margins[2];
  const std::string error = PickLines(lines, regions, parameters.midvein, margins);
  if (!error.empty())
    return error;
  if (parameters.midvein.size() < 2)
    return "the midvein polyline needs at least 2 points";
  const Eigen::Vector3d base = parameters.midvein.front(), apex = parameters.midvein.back();
  for (std::vector<Eigen::Vector3d>& margin : margins)
  {
    if (!margin.empty() && (margin.front() - base).norm() > (margin.back() - base).norm())
      std::reverse(margin.begin(), margin.end());
  }
  if (regions)
    OrderMargins(base, apex, margins);
  const auto scaled = [&](std::vector<Eigen::Vector3d> points) {
    for (Eigen::Vector3d& x : points)
      x = base + scale * (x - base);
    return points;
  };
  parameters.midvein = scaled(parameters.midvein);
  parameters.leftMargin = scaled(margins[0]);
  parameters.rightMargin = scaled(margins[1]);
  return {};
}

} // namespace plantmorph
