// SPDX-License-Identifier: GPL-3.0-or-later
#include "LeafFit.h"
#include "LeafFitInternal.h"
#include "PointGrid.h"

#include "BSplineLeaf.h"
#include "BladeMesher.h"
#include "LeafGeometry.h"

#include <plantmorph/statistics/Median.h>
#include <plantmorph/DataContract.h>
#include <plantmorph/RangeError.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace plantmorph
{
namespace
{
using fit::Frame;
using fit::Outline;

struct Fitted
{
  Frame frame;
  fit::CrossSections sections;
  Outline outline;
  TensorSurface surface;
  std::vector<int> kept;              // ids of the points the cleaning kept
  std::vector<Eigen::Vector3d> local; // their local coordinates
  std::vector<Eigen::Vector2d> ts;    // their (t, s)
  std::vector<double> residual;       // their distances to the surface
  double sigma = 0.0;                 // robust scale of the final residuals
};

/// The largest distance to the surface an inlier may have.
double InlierLimit(const Fitted& f, double spacing)
{
  return std::max(5.0 * f.sigma, spacing);
}

/// Moves (t, s) towards the foot of the local point q on the surface: two Gauss-Newton steps, a step longer than
/// 10 spacings refused.
void Project(const TensorSurface& surface, const Eigen::Vector3d& q, double spacing, Eigen::Vector2d& ts)
{
  for (int step = 0; step < 2; ++step)
  {
    Eigen::Vector3d x, dt, ds;
    surface.Evaluate(ts.x(), ts.y(), x, dt, ds);
    Eigen::Matrix<double, 3, 2> J;
    J << dt, ds;
    const Eigen::Vector3d r = q - x;
    const Eigen::Vector2d delta = (J.transpose() * J).ldlt().solve(J.transpose() * r);
    if (delta.allFinite() && delta.norm() < 10.0 * spacing)
      ts += delta;
  }
}

/// Every point's distance to the surface (f.residual) and their robust scale (returned).
double Scatter(const ParallelFor& parallel, Fitted& f)
{
  ForEachIndex(parallel, f.ts.size(),
    [&](std::size_t i) { f.residual[i] = (f.local[i] - f.surface(f.ts[i].x(), f.ts[i].y())).norm(); });
  return RobustScale(f.residual, 0.0, 0.0);
}

/// The factor on the bending penalty `lambda` for the scan's noise (MaxNoiseTilt, MaxNoiseScatterGrowth), from the
/// first fit at `lambda` whose robust scatter is f.sigma: 1 when the noise tilts the surface little; otherwise the
/// surface is refitted at the raised penalty, f.sigma and f.residual are those of the factor returned (at 1, of a
/// fit at `lambda` again, as before the raise). `perCell`: points per knot cell the points occupy; `knot`: the knot
/// spacing.
double NoisePenalty(const Eigen::Vector2d& tRange, const Eigen::Vector2d& sRange, int nt, int ns, double perCell,
  double knot, double lambda, const std::vector<double>& w, const ParallelFor& parallel, Fitted& f, bool& fitted)
{
  fitted = true;
  const double tilt = f.sigma / (std::sqrt(std::max(perCell, 1.0)) * knot) / MaxNoiseTilt;
  double factor = tilt * tilt;
  if (!(factor > 1.0))
    return 1.0;
  const double scatter = f.sigma;
  for (;;)
  {
    const double penalty = lambda * std::max(factor, 1.0);
    fitted = f.surface.Fit(tRange, sRange, nt, ns, f.ts, f.local, w, penalty, parallel);
    if (!fitted)
      return 1.0;
    f.sigma = Scatter(parallel, f);
    if (!(factor > 1.0) || f.sigma <= MaxNoiseScatterGrowth * scatter)
      return std::max(factor, 1.0);
    factor = factor < 1.5 ? 1.0 : std::sqrt(factor);
  }
}

/// The penalised, Huber-reweighted surface through the kept points.
std::string FitSurface(const LeafFitParameters& options, double spacing, const ParallelFor& parallel, Fitted& f)
{
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& p : f.ts)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // The domain reaches beyond the points by more than the outline's tips may be extrapolated (4 spacings).
  const double pad = 6.0 * spacing;
  const Eigen::Vector2d tRange(lo.x() - pad, hi.x() + pad), sRange(lo.y() - pad, hi.y() + pad);
  const double length = sRange[1] - sRange[0], width = tRange[1] - tRange[0];
  const double n = static_cast<double>(f.ts.size());
  const int ns = std::clamp(static_cast<int>(std::lround(std::sqrt(n / 5.0 * length / width))), 6, 40);
  const int nt = std::clamp(static_cast<int>(std::lround(ns * width / length)), 4, 30);
  double lambda = 0.01 * options.surfaceSmoothing;
  std::vector<double> w(f.ts.size(), 1.0);
  // The points per knot cell they occupy, for the noise's tilt (NoisePenalty).
  double perCell = 0.0;
  {
    std::vector<unsigned char> used(static_cast<std::size_t>(nt) * ns, 0);
    for (const auto& p : f.ts)
    {
      const int i = std::clamp(static_cast<int>((p.x() - tRange[0]) / width * nt), 0, nt - 1);
      const int j = std::clamp(static_cast<int>((p.y() - sRange[0]) / length * ns), 0, ns - 1);
      used[static_cast<std::size_t>(i) + static_cast<std::size_t>(nt) * j] = 1;
    }
    perCell = n / std::max(1.0, static_cast<double>(std::count(used.begin(), used.end(), 1)));
  }
  std::vector<double>& residual = f.residual;
  residual.resize(f.ts.size());
  for (int pass = 0; pass < 2; ++pass)
  {
    if (pass > 0)
    {
      // Project every point onto the surface (two Gauss-Newton steps on its (t, s)): a point's noise along a
      // tilted normal must not move it along the leaf, or the outermost samples reach beyond the margin and tips.
      ForEachIndex(parallel, f.ts.size(), [&](std::size_t i) { Project(f.surface, f.local[i], spacing, f.ts[i]); });
    }
    for (int iteration = 0; iteration < 3; ++iteration)
    {
      if (!f.surface.Fit(tRange, sRange, nt, ns, f.ts, f.local, w, lambda, parallel))
        return "no leaf shape: the surface could not be fitted";
      f.sigma = Scatter(parallel, f);
      if (pass == 0 && iteration == 0)
      {
        bool fitted = true;
        lambda *= NoisePenalty(
          tRange, sRange, nt, ns, perCell, std::min(length / ns, width / nt), lambda, w, parallel, f, fitted);
        if (!fitted)
          return "no leaf shape: the surface could not be fitted";
      }
      const double k = 2.0 * std::max(f.sigma, 1e-6 * spacing);
      for (std::size_t i = 0; i < f.ts.size(); ++i)
        w[i] = residual[i] <= k ? 1.0 : k / residual[i];
    }
  }
  if (f.sigma > 0.05 * width)
  {
    std::ostringstream message;
    message << "no leaf shape: the points scatter " << f.sigma << " around the best smooth surface, more than 5 % of "
            << "the leaf's width " << width;
    return message.str();
  }
  return {};
}

/// Samples (x = t, y = s - s0) of one margin at about `spacing` from the base to the apex, ends included.
std::vector<Eigen::Vector2d> SampleMargin(const Outline& outline, bool right, double spacing)
{
  const int dense = 4000;
  const double L = outline.s1 - outline.s0;
  std::vector<Eigen::Vector2d> curve(dense + 1);
  std::vector<double> arc(dense + 1, 0.0);
  for (int i = 0; i <= dense; ++i)
  {
    const double y = L * i / dense;
    const double s = outline.s0 + y;
    curve[i] = { i == 0 || i == dense ? 0.0 : (right ? outline.Right(s) : outline.Left(s)), y };
    if (i > 0)
      arc[i] = arc[i - 1] + (curve[i] - curve[i - 1]).norm();
  }
  const int pieces = std::max(2, static_cast<int>(std::lround(arc.back() / spacing)));
  std::vector<Eigen::Vector2d> samples;
  int j = 0;
  for (int k = 0; k <= pieces; ++k)
  {
    const double target = arc.back() * k / pieces;
    while (j + 1 < dense && arc[j + 1] < target)
      ++j;
    const double f = arc[j + 1] > arc[j] ? std::clamp((target - arc[j]) / (arc[j + 1] - arc[j]), 0.0, 1.0) : 0.0;
    samples.push_back((1.0 - f) * curve[j] + f * curve[j + 1]);
  }
  samples.front() = curve.front();
  samples.back() = curve.back();
  return samples;
}

/// A polyline resampled at about `step` along its arc length, its ends kept.
std::vector<Eigen::Vector2d> Resample(const std::vector<Eigen::Vector2d>& line, double step)
{
  std::vector<double> arc(line.size(), 0.0);
  for (std::size_t i = 1; i < line.size(); ++i)
    arc[i] = arc[i - 1] + (line[i] - line[i - 1]).norm();
  const int pieces = std::max(2, static_cast<int>(std::lround(arc.back() / step)));
  std::vector<Eigen::Vector2d> samples{ line.front() };
  std::size_t j = 0;
  for (int k = 1; k < pieces; ++k)
  {
    const double target = arc.back() * k / pieces;
    while (j + 2 < line.size() && arc[j + 1] < target)
      ++j;
    const double f = arc[j + 1] > arc[j] ? std::clamp((target - arc[j]) / (arc[j + 1] - arc[j]), 0.0, 1.0) : 0.0;
    samples.push_back((1.0 - f) * line[j] + f * line[j + 1]);
  }
  samples.push_back(line.back());
  return samples;
}

/// The blade: the outline in (t, s) (the points' contour when there is one, else the smooth margins) meshed by
/// LeafOutlineSource's mesher, laid out with its base at the origin, mapped to 3-D.
std::string MeshFittedBlade(
  const LeafFitParameters& options, const Fitted& f, const fit::Contour& contour, LeafFitResult& result)
{
  const Outline& o = f.outline;
  const double L = o.apex - o.base;
  // The mesh's step from the blade's extent (the points' own, never from the midvein alone, which a wrong apex
  // could make short), and the mesh's size bounded before it is built.
  const double h = std::max(L, o.s1 - o.s0) / options.resolution;
  result.midvein.clear();
  result.leftMargin.clear();
  result.rightMargin.clear();
  BladeOutline outline;
  auto add = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& uv, int region) {
    outline.points.push_back(p);
    outline.uv.push_back(uv);
    outline.region.push_back(region);
    return static_cast<int>(outline.points.size() - 1);
  };
  for (int k = 0; k <= options.resolution; ++k)
    result.midvein.push_back(
      add({ 0.0, L * k / options.resolution }, { 0.0, static_cast<double>(k) / options.resolution }, RegionMidvein));
  for (int side = 0; side < 2; ++side)
  {
    std::vector<Eigen::Vector2d> samples;
    if (contour.right.empty())
      samples = SampleMargin(o, side == 1, h);
    else
      for (Eigen::Vector2d p : Resample(side == 1 ? contour.right : contour.left, h))
        samples.push_back(p - Eigen::Vector2d(0.0, o.base));
    std::vector<int>& margin = side == 0 ? result.leftMargin : result.rightMargin;
    margin.push_back(result.midvein.front());
    for (std::size_t i = 1; i + 1 < samples.size(); ++i)
      margin.push_back(
        add(samples[i], { side == 0 ? -0.5 : 0.5, std::clamp(samples[i].y() / L, 0.0, 1.0) }, RegionMargin));
    margin.push_back(result.midvein.back());
  }
  outline.boundary.assign(result.rightMargin.begin(), result.rightMargin.end() - 1);
  outline.boundary.insert(outline.boundary.end(), result.leftMargin.rbegin(), result.leftMargin.rend() - 1);
  outline.midvein = result.midvein;
  auto solveUV = [&](const Eigen::Vector2d& p, const Eigen::Vector2d&) {
    const double s = o.base + p.y();
    const double u = p.x() >= 0.0 ? 0.5 * p.x() / o.Right(s) : -0.5 * p.x() / o.Left(s);
    return Eigen::Vector2d(std::clamp(u, -0.5, 0.5), std::clamp(p.y() / L, 0.0, 1.0));
  };
  // About 1.2 vertices per h^2 of blade in quality mode (edges near h, angles above 20 degrees), plus the outline's.
  const double expected = 1.2 * std::abs(PolygonArea(outline.points, outline.boundary)) / (h * h) +
    static_cast<double>(outline.points.size());
  if (!(expected <= static_cast<double>(MaxBladeVertices)))
  {
    std::ostringstream message;
    message << "Resolution " << options.resolution << ": the blade's mesh would need about " << std::lround(expected)
            << " vertices, more than " << MaxBladeVertices << "; lower Resolution";
    return message.str();
  }
  BladeMeshParameters meshOptions;
  meshOptions.quality = true;
  meshOptions.maxEdgeLength = h;
  meshOptions.maxVertices = MaxBladeVertices;
  BladeMesh mesh;
  const std::string error = MeshBlade(outline, meshOptions, solveUV, mesh);
  if (!error.empty())
    return "meshing the fitted outline: " + error;
  result.flat = mesh.points;
  result.leafUV = mesh.uv;
  result.region = mesh.region;
  result.triangles = mesh.triangles;
  result.tcoords = BoundingBoxTextureCoordinates(mesh.points);
  result.points.resize(mesh.points.size());
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    result.points[i] = f.frame.World(f.surface(mesh.points[i].x(), o.base + mesh.points[i].y()));
  result.normals = VertexNormals(result.points, result.triangles);
  return {};
}

/// The points the fit did not run on (a cloud above MaxFitPoints is fitted on a sample, `sampled`): each takes the
/// part of a cleaned sample point (`cleanPoints`, input ids `cleanIds`) within `reach` (PointGrid::Near), blade or petiole,
/// and is dropped as a stray when there is none; a blade point gets its (t, s) on the surface (the cross-sections'
/// coordinates, then projected as the fitted points are), FitDistance and Inlier. `kept` marks every point the
/// cleaning would keep (blade and petiole).
void ScanUnsampled(const std::vector<Eigen::Vector3d>& points, const std::vector<unsigned char>& sampled,
  const std::vector<Eigen::Vector3d>& cleanPoints, const std::vector<int>& cleanIds, const Fitted& f, double spacing,
  double reach, const ParallelFor& parallel, LeafFitResult& result, std::vector<unsigned char>& kept)
{
  const double limit = InlierLimit(f, spacing);
  const PointGrid grid(cleanPoints, reach, parallel); // cells of the reach: a point's own cell nearly always holds one
  ForEachIndex(parallel, points.size(), [&](std::size_t i) {
    if (sampled[i])
      return;
    const int near = grid.Near(points[i], reach);
    if (near < 0)
      return;
    kept[i] = 1;
    if (result.petiole[cleanIds[near]])
    {
      result.petiole[i] = 1;
      return;
    }
    const Eigen::Vector3d q = f.frame.Local(points[i]);
    Eigen::Vector2d ts = f.sections.Intrinsic(q);
    Project(f.surface, q, spacing, ts);
    Eigen::Vector3d x, normal;
    f.surface.PointAndNormal(ts.x(), ts.y(), x, normal);
    const Eigen::Vector3d d = q - x;
    result.fitDistance[i] = d.dot(normal);
    result.intrinsic[i] = { ts.x(), ts.y() - f.outline.base };
    result.inlier[i] = d.norm() <= limit ? 1 : 0;
  });
}

/// FitDistance, Inlier and (t, s) of every input point; Support of every blade point.
void ScanArrays(const std::vector<Eigen::Vector3d>& points, const Fitted& f, double spacing,
  const ParallelFor& parallel, LeafFitResult& result)
{
  const double limit = InlierLimit(f, spacing);
  std::vector<Eigen::Vector3d> inliers;
  for (std::size_t k = 0; k < f.kept.size(); ++k)
  {
    const int i = f.kept[k];
    const Eigen::Vector2d& ts = f.ts[k];
    Eigen::Vector3d x, normal;
    f.surface.PointAndNormal(ts.x(), ts.y(), x, normal);
    const Eigen::Vector3d d = f.local[k] - x;
    result.fitDistance[i] = d.dot(normal);
    result.intrinsic[i] = { ts.x(), ts.y() - f.outline.base };
    result.inlier[i] = f.residual[k] <= limit ? 1 : 0;
    if (result.inlier[i])
      inliers.push_back(points[i]);
  }
  // Dropped points: the distance to the nearest blade vertex, signed by the side of the blade's normal there.
  // A far stray's search on the fine grid visits the cube of the cells it is away: beyond 8 cells the nearest
  // vertex is found on a grid 16 times coarser (the same vertex: both searches are exact).
  const double cell = PointGrid::CellFor(result.points, 4.0);
  const PointGrid blade(result.points, cell), coarse(result.points, 16.0 * cell);
  ForEachIndex(parallel, points.size(), [&](std::size_t i) {
    if (std::isnan(result.fitDistance[i]))
    {
      auto nb = blade.Nearest(points[i], 1, -1, 8.0 * cell);
      if (nb.empty())
        nb = coarse.Nearest(points[i], 1);
      const Eigen::Vector3d d = points[i] - result.points[nb.front().second];
      result.fitDistance[i] = std::copysign(d.norm(), d.dot(result.normals[nb.front().second]));
    }
  });
  const PointGrid scan(inliers, PointGrid::CellFor(inliers, 4.0), parallel);
  result.support.resize(result.points.size());
  ForEachIndex(parallel, result.points.size(),
    [&](std::size_t i) { result.support[i] = std::sqrt(scan.Nearest(result.points[i], 1).front().first); });
}

/// Model C control points: the midvein at `count` stations base to apex (half-way between the margins), each margin at `count` inner stations
/// equally spaced along its arc length in (t, s) (so the rounded ends, where a margin turns fast, get their share).
void ModelControlPoints(int m, const Fitted& f, LeafFitResult& result)
{
  const Outline& o = f.outline;
  for (auto* points : { &result.modelMidvein, &result.modelLeftMargin, &result.modelRightMargin, &result.flatMidvein,
         &result.flatLeftMargin, &result.flatRightMargin })
    points->clear();
  for (int k = 0; k < m; ++k)
  {
    // The model's midvein runs half-way between the margins (the fitted one, t = 0, may run close to a margin
    // where a narrow petiole meets the blade, and an interpolating spline through it would cross that margin).
    const double s = o.base + (o.apex - o.base) * k / (m - 1);
    const double t = k == 0 || k == m - 1 ? 0.0 : 0.5 * (o.Left(s) + o.Right(s));
    result.modelMidvein.push_back(f.frame.World(f.surface(t, s)));
    result.flatMidvein.emplace_back(t, s - o.base, 0.0);
  }
  for (int side = 0; side < 2; ++side)
  {
    // The blade's own margins (laid flat, base at the origin), so the model has its lobes and sinuses.
    std::vector<Eigen::Vector2d> samples;
    for (int id : side == 0 ? result.leftMargin : result.rightMargin)
      samples.push_back(result.flat[id]);
    std::vector<double> arc(samples.size(), 0.0);
    for (std::size_t i = 1; i < samples.size(); ++i)
      arc[i] = arc[i - 1] + (samples[i] - samples[i - 1]).norm();
    std::size_t j = 0;
    for (int k = 1; k <= m; ++k)
    {
      const double target = arc.back() * k / (m + 1);
      while (j + 1 < samples.size() && arc[j + 1] < target)
        ++j;
      const double along = arc[j + 1] > arc[j] ? std::clamp((target - arc[j]) / (arc[j + 1] - arc[j]), 0.0, 1.0) : 0.0;
      const Eigen::Vector2d p = (1.0 - along) * samples[j] + along * samples[std::min(j + 1, samples.size() - 1)];
      (side == 0 ? result.modelLeftMargin : result.modelRightMargin)
        .push_back(f.frame.World(f.surface(p.x(), o.base + p.y())));
      (side == 0 ? result.flatLeftMargin : result.flatRightMargin).emplace_back(p.x(), p.y(), 0.0);
    }
  }
}

/// The model control points, checked: LeafOutlineSource interpolates them, and where a margin runs close to the
/// midvein (a narrow petiole, a margin the scan barely reaches) an interpolating spline through many points may
/// cross it, and the outline folds. The flat model is built (LeafOutlineSource's own B-spline leaf, unrefined);
/// while it folds, two control points fewer per curve are tried (smoother splines), down to 3. If none builds, the
/// requested count is kept and `modelWarning` says why the model will not rebuild.
void RebuildableModel(const LeafFitParameters& options, const Fitted& f, LeafFitResult& result)
{
  std::string first;
  for (int m = options.modelControlPoints; m >= 3; m -= 2)
  {
    ModelControlPoints(m, f, result);
    // At the fit's own resolution (the recipe's) and a fine one: whether the sampled outline folds depends on it.
    std::string error;
    for (int resolution : { options.resolution, 240 })
    {
      LeafMeshParameters check;
      check.resolution = resolution;
      check.quality = false;
      LeafGeometry rebuilt;
      if (error.empty())
        error = BuildBSplineLeaf({ result.flatMidvein, result.flatLeftMargin, result.flatRightMargin }, check, rebuilt);
    }
    if (error.empty())
    {
      result.modelControlPoints = m;
      return;
    }
    if (first.empty())
      first = error;
  }
  ModelControlPoints(options.modelControlPoints, f, result);
  result.modelControlPoints = options.modelControlPoints;
  result.modelWarning = "the fitted model does not rebuild in LeafOutlineSource with " +
    std::to_string(options.modelControlPoints) + " or fewer control points (" + first + ")";
}

/// Whether a petiole found leaves the blade at its given base `basePoint`: its junction lies nearer the base than
/// the blade's centroid does. A thin trail at the blade's other end is its drawn-out (acuminate) tip, a point or
/// two across and as straight as a stalk, and stays in the blade (its Length ran to where the trail began).
bool StalkAtTheBase(
  const std::vector<Eigen::Vector3d>& points, const fit::Petiole& petiole, const Eigen::Vector3d& basePoint)
{
  if (!petiole.found || points.empty())
    return true;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points)
    centroid += p;
  centroid /= static_cast<double>(points.size());
  return (petiole.junction - basePoint).norm() < (centroid - basePoint).norm();
}

fit::Petiole NoPetiole(std::size_t points, std::size_t loose)
{
  fit::Petiole none;
  none.member.assign(points, 0);
  none.looseMember.assign(loose, 0);
  return none;
}

std::string Fit(const std::vector<Eigen::Vector3d>& points, const LeafFitParameters& options,
  const ParallelFor& parallel, LeafFitResult& result)
{
  std::string error = ValidateLeafFitParameters(options);
  if (error.empty())
    error = fit::ValidateCloud(points);
  if (!error.empty())
    return error;
  // A dense cloud is fitted on a sample of MaxFitPoints (the surface's knots, the outline and the traits need no
  // more; the cost of the fit's searches and sums then stops growing), and its other points follow the fit.
  const std::vector<int> sampleIds = SampleIds(points, MaxFitPoints);
  const bool thinned = sampleIds.size() < points.size();
  std::vector<Eigen::Vector3d> sample;
  if (thinned)
    for (int id : sampleIds)
      sample.push_back(points[id]);
  const std::vector<Eigen::Vector3d>& fitted = thinned ? sample : points;
  std::vector<unsigned char> keep;
  double spacing = 0.0;
  error = fit::CleanCloud(fitted, options.outlierSigma, keep, spacing, parallel);
  if (!error.empty())
    return error;
  // The petiole is set apart: the blade alone is fitted, and every blade trait is the blade's.
  std::vector<int> cleaned, removed; // input ids
  std::vector<Eigen::Vector3d> cleanPoints, strays;
  for (std::size_t i = 0; i < fitted.size(); ++i)
  {
    (keep[i] ? cleaned : removed).push_back(thinned ? sampleIds[i] : static_cast<int>(i));
    (keep[i] ? cleanPoints : strays).push_back(fitted[i]);
  }
  fit::Petiole petiole = fit::FindPetiole(cleanPoints, spacing, parallel, strays);
  // A thin trail at the blade's far end from a given base, or without a base given a short one at an end that reads
  // as a drawn-out tip, is the blade's tip, not a petiole.
  if (options.basePoint ? !StalkAtTheBase(cleanPoints, petiole, *options.basePoint)
                        : fit::StalkIsTheBladesTip(cleanPoints, petiole, spacing))
    petiole = NoPetiole(cleanPoints.size(), strays.size());
  result.petiole.assign(points.size(), 0);
  for (std::size_t k = 0; k < removed.size(); ++k)
    if (petiole.looseMember[k])
      result.petiole[removed[k]] = 1;
  Fitted f;
  std::vector<Eigen::Vector3d> kept;
  for (std::size_t k = 0; k < cleaned.size(); ++k)
    if (petiole.member[k])
      result.petiole[cleaned[k]] = 1;
    else
    {
      f.kept.push_back(cleaned[k]);
      kept.push_back(cleanPoints[k]);
    }
  if (kept.size() < static_cast<std::size_t>(MinLeafPoints))
    return "too few blade points beside the petiole: " + std::to_string(kept.size()) + " (a leaf needs at least " +
      std::to_string(MinLeafPoints) + ")";
  f.frame = fit::LeafFrame(
    kept, options, spacing, petiole, result.traits.baseFrom, result.baseGuess, result.baseAtStalkWidth, parallel);
  result.orientedByShape = result.traits.baseFrom == BaseFromShape && !options.apexPoint;
  for (const auto& p : kept)
    f.local.push_back(f.frame.Local(p));
  error = f.sections.Build(f.local, spacing);
  if (!error.empty())
    return error;
  for (const auto& q : f.local)
    f.ts.push_back(f.sections.Intrinsic(q));
  error = FitSurface(options, spacing, parallel, f);
  if (!error.empty())
    return error;
  // The outline from the points on the surface only (an outlier beside the leaf must not widen it).
  std::vector<Eigen::Vector2d> onSurface;
  for (std::size_t k = 0; k < f.ts.size(); ++k)
    if (f.residual[k] <= InlierLimit(f, spacing))
      onSurface.push_back(f.ts[k]);
  // The outline's spacing: the gaps the points leave on the blade, which on a line scan (points much closer along
  // a line than the lines are) is the distance between the lines, not the nearest-neighbour spacing.
  std::vector<Eigen::Vector3d> flat;
  for (const auto& p : onSurface)
    flat.emplace_back(p.x(), p.y(), 0.0);
  const double outlineSpacing =
    std::max(spacing, 0.5 * CrossSpacing(flat, PointGrid(flat, PointGrid::CellFor(flat, 4.0), parallel), parallel));
  error = fit::FitOutline(onSurface, options, outlineSpacing, f.outline);
  if (!error.empty())
    return error;
  if (petiole.found && result.traits.baseFrom == BaseFromPetiole)
  {
    const Eigen::Vector2d junction = f.sections.Intrinsic(f.frame.Local(petiole.junction));
    if (std::abs(junction.x()) < 2.0 * outlineSpacing)
    {
      f.outline.junction = junction.y();
      f.outline.junctionMeetsPlane = petiole.meetsPlane;
      f.outline.junctionAcrossGap = petiole.acrossGap;
      f.outline.stalkHalfWidth = petiole.halfWidth;
    }
  }
  // The blade's outline as its points draw it (lobes and sinuses kept); where that loop does not mesh (a sinus
  // narrower than the mesh's edges), the smooth margins.
  // Snapped to the smooth margins where it follows them, else as traced when it has sinuses, notches or lobes the
  // smooth margins do not follow, else the smooth margins alone.
  error = "no contour";
  for (int attempt = 0; attempt < 2 && !error.empty(); ++attempt)
  {
    const fit::Contour contour = fit::TraceContour(onSurface, outlineSpacing, attempt == 0, f.outline, parallel);
    if (!contour.right.empty() && (attempt == 0 || contour.features))
      error = MeshFittedBlade(options, f, contour, result);
  }
  if (!error.empty())
  {
    f.outline.base = f.outline.s0;
    f.outline.apex = f.outline.s1;
    error = MeshFittedBlade(options, f, fit::Contour(), result);
  }
  if (!error.empty())
    return error;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  result.fitDistance.assign(points.size(), nan);
  result.inlier.assign(points.size(), 0);
  result.intrinsic.assign(points.size(), Eigen::Vector2d(nan, nan));
  result.traits.spacing = spacing;
  if (thinned)
  {
    // The points beside the sample: within 4 of its spacings of a kept one (a stray farther than that is dropped).
    std::vector<unsigned char> sampled(points.size(), 0), kept(points.size(), 0);
    for (int id : sampleIds)
      sampled[id] = 1;
    for (int id : cleaned)
      kept[id] = 1;
    ScanUnsampled(points, sampled, cleanPoints, cleaned, f, spacing, 4.0 * outlineSpacing, parallel, result, kept);
    // The Spacing trait is the scan's own (the kept points'), not the sample's.
    std::vector<Eigen::Vector3d> keptPoints;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (kept[i])
        keptPoints.push_back(points[i]);
    result.traits.spacing =
      MedianSpacing(keptPoints, PointGrid(keptPoints, PointGrid::CellFor(keptPoints, 4.0), parallel), parallel);
  }
  ScanArrays(points, f, spacing, parallel, result);
  RebuildableModel(options, f, result);
  result.traits.coverageSpacing = outlineSpacing;
  result.traits.points = static_cast<double>(points.size());
  fit::ComputeTraits(f.surface, f.outline, options, f.frame.axes, result);
  result.petioleLine = petiole.line;
  result.sheetShare = petiole.sheetShare;
  result.petioleLookedFor = !(petiole.sheetShare < fit::MinSheetShareForPetiole);
  result.apexTrail = fit::ApexTrail(onSurface, outlineSpacing);
  result.petioleHalfWidth = petiole.found ? petiole.halfWidth : 0.0;
  result.traits.petioleLength = petiole.length;
  return {};
}
} // namespace

std::string ValidateLeafFitParameters(const LeafFitParameters& o)
{
  std::ostringstream m;
  if (!o.up.allFinite() || !(o.up.norm() > 0.0))
    m << "UpAxis: must be a non-zero direction";
  else if (o.basePoint && !o.basePoint->allFinite())
    m << "BasePoint: must be finite";
  else if (o.apexPoint && !o.apexPoint->allFinite())
    m << "ApexPoint: must be finite";
  else if (!(o.surfaceSmoothing >= MinSurfaceSmoothing && o.surfaceSmoothing <= 1e6))
    m << OutOfRange("SurfaceSmoothing", o.surfaceSmoothing, "[0.1, 1e6]",
      "below 0.1 the surface leaves the points where they are sparse (at 0 the traits grow 20-160 fold)");
  else if (!(o.outlineSmoothing >= 0.0 && o.outlineSmoothing <= 1e6))
    m << OutOfRange("OutlineSmoothing", o.outlineSmoothing, "[0, 1e6]");
  else if (o.outlineControlPoints < 4 || o.outlineControlPoints > 200)
    m << OutOfRange("OutlineControlPoints", o.outlineControlPoints, "[4, 200]");
  else if (!(o.outlierSigma >= 1.0 && o.outlierSigma <= 100.0))
    m << OutOfRange("OutlierSigma", o.outlierSigma, "[1, 100]");
  else if (o.resolution < 4 || o.resolution > 1000)
    m << OutOfRange("Resolution", o.resolution, "[4, 1000]");
  else if (o.modelControlPoints < 3 || o.modelControlPoints > 100)
    m << OutOfRange("ModelControlPoints", o.modelControlPoints, "[3, 100]");
  return m.str();
}

LeafFitResult FitLeaf(
  const std::vector<Eigen::Vector3d>& points, const LeafFitParameters& options, const ParallelFor& parallel)
{
  LeafFitResult result;
  LeafFitParameters normalized = options;
  if (normalized.up.allFinite() && normalized.up.norm() > 0.0)
    normalized.up.normalize();
  const std::string error = Fit(points, normalized, parallel, result);
  if (!error.empty())
  {
    result = LeafFitResult();
    result.error = error;
  }
  return result;
}

std::vector<LeafFitResult> FitLeaves(const std::vector<std::vector<Eigen::Vector3d>>& leaves,
  const LeafFitParameters& options, const ParallelFor& parallel)
{
  std::vector<LeafFitResult> results(leaves.size());
  if (leaves.size() == 1)
  {
    results[0] = FitLeaf(leaves[0], options, parallel);
    return results;
  }
  parallel(leaves.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      results[i] = FitLeaf(leaves[i], options);
  });
  return results;
}

} // namespace plantmorph
