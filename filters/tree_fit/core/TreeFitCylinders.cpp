// SPDX-License-Identifier: GPL-3.0-or-later
// Step 4 of the tree fit (TreeFit.h): robust cylinders along the skeleton's segments.
#include "TreeFitInternal.h"

#include <plantmorph/PlaneFit.h>

#include <plantmorph/statistics/Median.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace plantmorph
{
namespace treefit
{
void Frame(const Eigen::Vector3d& axis, Eigen::Vector3d& u, Eigen::Vector3d& v)
{
  const Eigen::Vector3d reference =
    std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX().eval() : Eigen::Vector3d::UnitY().eval();
  u = axis.cross(reference).normalized();
  v = axis.cross(u);
}

bool CircleFit(const std::vector<Eigen::Vector3d>& q, const Eigen::Vector3d& c, const Eigen::Vector3d& u,
  const Eigen::Vector3d& v, Eigen::Vector3d& circle)
{
  std::vector<Eigen::Vector2d> plane(q.size());
  for (std::size_t i = 0; i < q.size(); ++i)
    plane[i] = Eigen::Vector2d((q[i] - c).dot(u), (q[i] - c).dot(v));
  return FitCircle(plane, circle);
}

namespace
{
constexpr double PathTilt = 20.0; // degrees a piece's fitted axis may turn from the skeleton's path (PathDirection)
constexpr double PathLean = 10.0; // degrees a piece's start direction may lean from that path and be trusted
constexpr int PieceMinNodes = 2, PieceMaxNodes = 8;
constexpr int PathNodes = 9; // centroids the skeleton's direction through a piece is fitted to (PathDirection)
// A fit from the chord that lies off its points (residual scale above FarScale of its radius and above a spacing) where
// the centroids give no path is fitted again from its segment's line when that differs by over SecondStart degrees;
// the second fit is kept when its residual scale is below BetterScale times the first's (a wrong axis leaves
// residuals of a sizeable share of the radius, many noise deviations; a tie keeps the chord's).
constexpr double SecondStart = 3.0;
constexpr double BetterScale = 0.5;
constexpr double FarScale = 0.1; // share of its radius beyond which a fit's residual scale says it is off its points
// The refinement has converged when a step moves the axis and radius by less than StepLength of the residual floor
// (a twentieth of a spacing) and turns the axis by less than StepTurn radians: far below what the points resolve.
// Reweighting moves the minimum a little at every iteration, so a relative step of 1e-10 alone was seldom reached:
// two fits in three ran to the iteration limit or to eight failed damping attempts.
constexpr double StepLength = 1e-3;
constexpr double StepTurn = 1e-6;

/// Residuals (distance to the axis minus radius) for parameters (a, b, alpha, beta, r) about (c, u, v, axis0).
void Residuals(const std::vector<Eigen::Vector3d>& q, const Eigen::Vector3d& c, const Eigen::Vector3d& u,
  const Eigen::Vector3d& v, const Eigen::Vector3d& axis0, const Eigen::Matrix<double, 5, 1>& x, Eigen::VectorXd& res)
{
  const Eigen::Vector3d p = c + x[0] * u + x[1] * v;
  const Eigen::Vector3d d = (axis0 + x[2] * u + x[3] * v).normalized();
  res.resize(static_cast<Eigen::Index>(q.size()));
  for (std::size_t i = 0; i < q.size(); ++i)
    res[static_cast<Eigen::Index>(i)] = (q[i] - p).cross(d).norm() - x[4];
}

/// The residuals' derivatives by (a, b, alpha, beta, r) at x, in closed form. With w = q - p, e its part across the
/// axis d and e^ = e / |e|: d|e|/da = -e^.u, d|e|/db = -e^.v; d = n / |n| with n = axis0 + alpha u + beta v gives
/// d|e|/dalpha = -(w.d)(e^.u) / |n| and d|e|/dbeta = -(w.d)(e^.v) / |n|; the radius enters as -1.
Eigen::Matrix<double, 5, 1> ResidualGradient(const Eigen::Vector3d& q, const Eigen::Vector3d& p,
  const Eigen::Vector3d& d, double nNorm, const Eigen::Vector3d& u, const Eigen::Vector3d& v)
{
  const Eigen::Vector3d w = q - p;
  const double along = w.dot(d);
  const Eigen::Vector3d e = w - along * d;
  const double rho = e.norm();
  Eigen::Matrix<double, 5, 1> g;
  if (!(rho > 0.0)) // a point on the axis: the distance has no direction there; it moves the radius alone
  {
    g << 0.0, 0.0, 0.0, 0.0, -1.0;
    return g;
  }
  const double eu = e.dot(u) / rho, ev = e.dot(v) / rho;
  g << -eu, -ev, -along * eu / nNorm, -along * ev / nNorm, -1.0;
  return g;
}

/// Robustly weighted Gauss-Newton (Levenberg-Marquardt) on the 5 (or, with fixed direction, 3) parameters: Huber
/// weights, or with `redescending` Tukey's biweight (points far off the surface, such as a child branch's start in a
/// junction piece, get no weight at all; started from the Huber fit). The normal equations are summed point by point
/// from the closed-form derivatives (ResidualGradient), with no matrix of one row per point.
Eigen::Matrix<double, 5, 1> Refine(const std::vector<Eigen::Vector3d>& q, const Eigen::Vector3d& c,
  const Eigen::Vector3d& u, const Eigen::Vector3d& v, const Eigen::Vector3d& axis0, Eigen::Matrix<double, 5, 1> x,
  bool fixDirection, double floor, bool redescending = false)
{
  Eigen::VectorXd res, trial, w;
  std::vector<double> scratch;
  double lambda = 1e-3;
  for (int iteration = 0; iteration < 30; ++iteration)
  {
    Residuals(q, c, u, v, axis0, x, res);
    scratch.assign(res.data(), res.data() + res.size());
    const double sigma = std::max(RobustScale(scratch), floor);
    const double k = (redescending ? 4.685 : 1.345) * sigma;
    w.resize(res.size());
    for (Eigen::Index i = 0; i < res.size(); ++i)
    {
      const double t = std::abs(res[i]) / k;
      w[i] = redescending ? (t < 1.0 ? (1 - t * t) * (1 - t * t) : 0.0) : (t <= 1.0 ? 1.0 : 1.0 / t);
    }
    const Eigen::Vector3d p = c + x[0] * u + x[1] * v;
    const Eigen::Vector3d n = axis0 + x[2] * u + x[3] * v;
    const double nNorm = n.norm();
    const Eigen::Vector3d d = n / nNorm;
    Eigen::Matrix<double, 5, 5> a = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 1> g = Eigen::Matrix<double, 5, 1>::Zero();
    double cost = 0.0;
    for (std::size_t i = 0; i < q.size(); ++i)
    {
      const auto index = static_cast<Eigen::Index>(i);
      if (w[index] == 0.0)
        continue;
      Eigen::Matrix<double, 5, 1> j = ResidualGradient(q[i], p, d, nNorm, u, v);
      if (fixDirection)
        j[2] = j[3] = 0.0;
      a.noalias() += (w[index] * j) * j.transpose();
      g += w[index] * res[index] * j;
      cost += w[index] * res[index] * res[index];
    }
    bool improved = false;
    for (int attempt = 0; attempt < 8 && !improved; ++attempt)
    {
      Eigen::Matrix<double, 5, 5> damped = a;
      for (int m = 0; m < 5; ++m)
        damped(m, m) += lambda * (a(m, m) + 1e-12);
      if (fixDirection)
        damped(2, 2) = damped(3, 3) = 1.0;
      const Eigen::Matrix<double, 5, 1> step = damped.ldlt().solve(-g);
      if (!step.allFinite())
        break;
      Residuals(q, c, u, v, axis0, x + step, trial);
      if (trial.dot(w.asDiagonal() * trial) < cost)
      {
        x += step;
        lambda = std::max(lambda / 4, 1e-9);
        improved = true;
        const bool small = std::abs(step[0]) + std::abs(step[1]) + std::abs(step[4]) < StepLength * floor &&
          std::abs(step[2]) + std::abs(step[3]) < StepTurn;
        if (small || step.norm() < 1e-10 * (1.0 + x.norm()))
          return x;
      }
      else
        lambda *= 8;
    }
    if (!improved)
      break;
  }
  return x;
}
} // namespace

CylinderFit FitCylinder(
  const std::vector<Eigen::Vector3d>& q, const Eigen::Vector3d& axis0In, double spacing, double maxTilt)
{
  CylinderFit fit;
  if (q.size() < 6 || !(axis0In.norm() > 0.0))
    return fit;
  const Eigen::Vector3d axis0 = axis0In.normalized();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : q)
    c += p;
  c /= static_cast<double>(q.size());
  Eigen::Vector3d u, v;
  Frame(axis0, u, v);
  Eigen::Vector3d circle;
  if (!CircleFit(q, c, u, v, circle))
    return fit;
  Eigen::Matrix<double, 5, 1> x0;
  x0 << circle[0], circle[1], 0.0, 0.0, circle[2];
  const double floor = 0.05 * spacing;
  Eigen::Matrix<double, 5, 1> x = Refine(q, c, u, v, axis0, x0, false, floor);
  x = Refine(q, c, u, v, axis0, x, false, floor, true);
  Eigen::Vector3d d = (axis0 + x[2] * u + x[3] * v).normalized();
  if (!x.allFinite() || std::acos(std::min(1.0, std::abs(d.dot(axis0)))) > maxTilt * M_PI / 180.0 || !(x[4] > 0.0))
  {
    x = Refine(q, c, u, v, axis0, x0, true, floor);
    d = axis0;
  }
  if (!x.allFinite() || !(x[4] > 0.0))
    return fit;
  // A circle far wider than the points (a few points on a nearly flat patch) has its axis metres away: neither a
  // radius nor a position for a cylinder of the tree.
  double extent = 0;
  for (const auto& p : q)
    extent = std::max(extent, (p - c).cross(axis0).norm());
  if (Eigen::Vector2d(x[0], x[1]).norm() > 2.0 * extent)
    return fit;
  fit.point = c + x[0] * u + x[1] * v;
  fit.axis = d.dot(axis0) < 0 ? (-d).eval() : d;
  fit.radius = x[4];
  Eigen::VectorXd res;
  Residuals(q, c, u, v, axis0, x, res);
  fit.rms = std::sqrt(res.squaredNorm() / static_cast<double>(res.size()));
  fit.scale = RobustScale(std::vector<double>(res.data(), res.data() + res.size()));
  // Coverage: 10-degree sectors around the axis holding an inlier.
  Eigen::Vector3d fu, fv;
  Frame(fit.axis, fu, fv);
  std::array<bool, 36> seen{};
  const double band = std::max(3.0 * fit.scale, 0.5 * spacing);
  for (std::size_t i = 0; i < q.size(); ++i)
    if (std::abs(res[static_cast<Eigen::Index>(i)]) <= band)
    {
      const Eigen::Vector3d r = q[i] - fit.point;
      const double angle = std::atan2(r.dot(fv), r.dot(fu)) + M_PI;
      seen[static_cast<std::size_t>(std::min(35.0, std::floor(angle / (2 * M_PI) * 36.0)))] = true;
    }
  fit.coverage = 10.0 * static_cast<double>(std::count(seen.begin(), seen.end(), true));
  fit.ok = true;
  return fit;
}

namespace
{
/// One piece of a segment: its nodes (consecutive) and the direction to start its fit from.
struct Piece
{
  int segment = 0;
  std::vector<int> nodes;
  Eigen::Vector3d axis0 = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d path = Eigen::Vector3d::UnitZ(); ///< PathDirection
  bool pathFound = false; ///< whether the path is the centroids' line (else it is axis0: they do not line up)
  Eigen::Vector3d stem = Eigen::Vector3d::UnitZ(); ///< PathDirection over the piece's whole segment
};

/// The direction of a run of nodes: last centroid minus first (the run widened by one node each side if short).
Eigen::Vector3d ChainDirection(const Skeleton& s, const std::vector<int>& chain, std::size_t first, std::size_t last)
{
  for (int widen = 0; widen < 3; ++widen)
  {
    const std::size_t a = first >= static_cast<std::size_t>(widen) ? first - widen : 0;
    const std::size_t b = std::min(chain.size() - 1, last + widen);
    const Eigen::Vector3d d = s.nodes[chain[b]].centroid - s.nodes[chain[a]].centroid;
    if (d.norm() > 0.75 * s.binWidth * static_cast<double>(b - a))
      return d.normalized();
  }
  return Eigen::Vector3d::Zero();
}

/// The skeleton's direction through a run of nodes: the principal direction of their centroids, the run widened
/// along the chain to PathNodes nodes (a stem's level sets can swing from side to side bin by bin, where strips of it
/// were joined: a line through many centroids follows the stem, a chord between two does not); `fallback` when the
/// chain is too short or its centroids do not line up.
Eigen::Vector3d PathDirection(const Skeleton& s, const std::vector<int>& chain, std::size_t first, std::size_t last,
  const Eigen::Vector3d& fallback)
{
  std::size_t a = first, b = last;
  while (b - a + 1 < static_cast<std::size_t>(PathNodes) && (a > 0 || b + 1 < chain.size()))
  {
    if (a > 0)
      --a;
    if (b + 1 < chain.size() && b - a + 1 < static_cast<std::size_t>(PathNodes))
      ++b;
  }
  if (b - a + 1 < 3)
    return fallback;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t m = a; m <= b; ++m)
    mean += s.nodes[chain[m]].centroid;
  mean /= static_cast<double>(b - a + 1);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (std::size_t m = a; m <= b; ++m)
  {
    const Eigen::Vector3d r = s.nodes[chain[m]].centroid - mean;
    scatter += r * r.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  Eigen::Vector3d d = eigen.eigenvectors().col(2);
  const Eigen::Vector3d chord = s.nodes[chain[b]].centroid - s.nodes[chain[a]].centroid;
  if (!d.allFinite() || !(eigen.eigenvalues()[2] > 4.0 * eigen.eigenvalues()[1]) || !(std::abs(d.dot(chord)) > 0.0))
    return fallback;
  return d.dot(chord) < 0 ? (-d).eval() : d;
}

/// The pieces: each segment cut into runs about two radii long (PieceMinNodes to PieceMaxNodes nodes).
std::vector<Piece> CutSegments(const Wood& wood, const Skeleton& s, const Eigen::Vector3d& up)
{
  std::vector<Piece> pieces;
  std::vector<Eigen::Vector3d> segmentAxis(s.segments.size(), up);
  for (std::size_t g = 0; g < s.segments.size(); ++g)
  {
    const auto& chain = s.segments[g];
    Eigen::Vector3d axis = ChainDirection(s, chain, 0, chain.size() - 1);
    if (axis.isZero())
      axis = s.segmentParent[g] >= 0 ? segmentAxis[s.segmentParent[g]] : up;
    if (axis.isZero() || !axis.allFinite())
      axis = up;
    segmentAxis[g] = axis;
    const Eigen::Vector3d stem = PathDirection(s, chain, 0, chain.size() - 1, axis);
    std::vector<double> radii;
    for (int node : chain)
    {
      std::vector<double> distance;
      for (int i : s.nodes[node].points)
        if (s.fitted[i])
          distance.push_back((wood.points[i] - s.nodes[node].centroid).cross(axis).norm());
      if (!distance.empty())
        radii.push_back(Median(distance));
    }
    const double radius = radii.empty() ? s.binWidth : Median(radii);
    const int per = std::clamp(static_cast<int>(std::lround(2.0 * radius / s.binWidth)), PieceMinNodes, PieceMaxNodes);
    const int count = std::max(1, static_cast<int>(std::lround(static_cast<double>(chain.size()) / per)));
    for (int k = 0; k < count; ++k)
    {
      Piece piece;
      piece.segment = static_cast<int>(g);
      const std::size_t first = chain.size() * k / count, last = chain.size() * (k + 1) / count - 1;
      piece.nodes.assign(
        chain.begin() + static_cast<std::ptrdiff_t>(first), chain.begin() + static_cast<std::ptrdiff_t>(last) + 1);
      piece.axis0 = ChainDirection(s, chain, first, last);
      if (piece.axis0.isZero())
        piece.axis0 = axis;
      piece.path = PathDirection(s, chain, first, last, Eigen::Vector3d::Zero());
      piece.pathFound = !piece.path.isZero();
      if (!piece.pathFound)
        piece.path = piece.axis0;
      piece.stem = stem;
      pieces.push_back(piece);
    }
  }
  return pieces;
}
} // namespace

std::string FitCylinders(const Wood& wood, const Skeleton& s, const TreeFitParameters& options,
  const ParallelFor& parallel, TreeFitResult& result, std::vector<int>& woodCylinder, std::vector<TreeCylinder>* fitted)
{
  const std::vector<Piece> pieces = CutSegments(wood, s, options.up);
  std::vector<CylinderFit> fits(pieces.size());
  std::vector<int> counts(pieces.size(), 0);
  parallel(pieces.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
    {
      std::vector<Eigen::Vector3d> q;
      for (int node : pieces[k].nodes)
        for (int i : s.nodes[node].points)
          if (s.fitted[i])
            q.push_back(wood.points[i]);
      counts[k] = static_cast<int>(q.size());
      fits[k] = FitCylinder(q, pieces[k].axis0, wood.spacing);
      // Started from a chord that leans off the path and fitted across the path (the junction of a strip joined to
      // a stem, its centroids swinging): fitted again from the path, turning from it by at most PathTilt. Where the
      // chord follows the path, a fit turning from it follows the branch's own bend. Without a path, a fit off its
      // points is started again from the segment's line (SecondStart): a trunk whose wood label leaves its surface
      // in strips (a segmentation calling part of it leaf) has level sets that swing from strip to strip, chords
      // that lean 40 degrees and centroids too scattered for a path, and the fit from such a chord settles on a
      // tilted, narrower cylinder tens of noise deviations off the points; the one from the segment's line lies on
      // them.
      const double leanCos = std::cos(PathLean * M_PI / 180.0), tiltCos = std::cos(PathTilt * M_PI / 180.0);
      const double startCos = std::cos(SecondStart * M_PI / 180.0);
      const double lean = std::abs(pieces[k].axis0.dot(pieces[k].path));
      if (fits[k].ok && lean < leanCos && std::abs(fits[k].axis.dot(pieces[k].path)) < tiltCos)
        fits[k] = FitCylinder(q, pieces[k].path, wood.spacing, PathTilt);
      else if (!pieces[k].pathFound &&
        (!fits[k].ok || fits[k].scale > std::max(FarScale * fits[k].radius, wood.spacing)) &&
        std::abs(pieces[k].stem.dot(pieces[k].axis0)) < startCos &&
        !(fits[k].ok && std::abs(pieces[k].stem.dot(fits[k].axis)) >= startCos))
      {
        const CylinderFit again = FitCylinder(q, pieces[k].stem, wood.spacing, PathTilt);
        if (again.ok && (!fits[k].ok || again.scale < BetterScale * fits[k].scale))
          fits[k] = again;
      }
    }
  });
  std::vector<int> nodeCylinder(s.nodes.size(), -1), lastOfSegment(s.segments.size(), -1);
  result.cylinders.resize(pieces.size());
  for (std::size_t k = 0; k < pieces.size(); ++k)
  {
    const Piece& piece = pieces[k];
    TreeCylinder& cyl = result.cylinders[k];
    const Eigen::Vector3d& first = s.nodes[piece.nodes.front()].centroid;
    const Eigen::Vector3d& last = s.nodes[piece.nodes.back()].centroid;
    Eigen::Vector3d point = 0.5 * (first + last), axis = piece.axis0;
    if (fits[k].ok)
    {
      point = fits[k].point;
      axis = fits[k].axis;
    }
    const double t0 = (first - point).dot(axis) - 0.5 * s.binWidth, t1 = (last - point).dot(axis) + 0.5 * s.binWidth;
    cyl.start = point + t0 * axis;
    cyl.end = point + t1 * axis;
    cyl.length = t1 - t0;
    cyl.fittedRadius = fits[k].ok ? fits[k].radius : std::numeric_limits<double>::quiet_NaN();
    cyl.coverage = fits[k].ok ? fits[k].coverage : 0.0;
    cyl.fitRMS = fits[k].ok ? fits[k].scale : std::numeric_limits<double>::quiet_NaN(); // robust; replaced later
    cyl.points = counts[k];
    cyl.support = cyl.length > 0 ? counts[k] / cyl.length : 0.0;
    cyl.segment = piece.segment;
    cyl.path = piece.path;
    const int previous = lastOfSegment[piece.segment];
    cyl.parent = previous >= 0
      ? previous
      : (s.segmentParent[piece.segment] >= 0 ? lastOfSegment[s.segmentParent[piece.segment]] : -1);
    lastOfSegment[piece.segment] = static_cast<int>(k);
    for (int node : piece.nodes)
      nodeCylinder[node] = static_cast<int>(k);
  }
  woodCylinder.assign(wood.points.size(), -1);
  for (std::size_t i = 0; i < wood.points.size(); ++i)
    if (s.nodeOf[i] >= 0)
      woodCylinder[i] = nodeCylinder[s.nodeOf[i]];
  if (fitted != nullptr)
    *fitted = result.cylinders;
  return ModelRadii(wood.spacing, result, wood.leafLabelled);
}

} // namespace treefit
} // namespace plantmorph
