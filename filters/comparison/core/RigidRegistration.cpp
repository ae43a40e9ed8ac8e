// SPDX-License-Identifier: GPL-3.0-or-later
#include "RigidRegistration.h"

#include <plantmorph/RandomStream.h>
#include <plantmorph/RangeError.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <vector>

namespace plantmorph
{

//------------------------------------------------------------------------------
std::string ValidateRegistrationParameters(const RegistrationParameters& settings)
{
  std::ostringstream message;
  if (settings.maximumIterations < 1 || settings.maximumIterations > 10000)
  {
    message << plantmorph::OutOfRange("RegistrationIterations", settings.maximumIterations, "[1, 10000]");
  }
  else if (!(settings.tolerance > 0.0 && settings.tolerance < 1.0))
  {
    message << plantmorph::OutOfRange("RegistrationTolerance", settings.tolerance, "(0, 1)");
  }
  else if (settings.maximumLandmarks < 3)
  {
    message << plantmorph::OutOfRange("RegistrationLandmarks", settings.maximumLandmarks, "[3, inf)");
  }
  else if (std::isnan(settings.rejectDistance))
  {
    message << "the registration's rejection distance is NaN";
  }
  return message.str();
}

//------------------------------------------------------------------------------
bool FitSimilarity(const double* source, const double* target, std::size_t count, bool withScale, double matrix[16])
{
  if (count < 3)
  {
    return false;
  }
  const Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>> src(source, 3, static_cast<Eigen::Index>(count));
  const Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>> dst(target, 3, static_cast<Eigen::Index>(count));
  const Eigen::Vector3d mean = src.rowwise().mean();
  if ((src.colwise() - mean).squaredNorm() <= 0.0)
  {
    return false;
  }
  const Eigen::Matrix4d m = Eigen::umeyama(src, dst, withScale);
  if (!m.allFinite())
  {
    return false;
  }
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      matrix[4 * r + c] = m(r, c);
    }
  }
  return true;
}

//------------------------------------------------------------------------------
void ApplyTransform(const double m[16], const double* in, double* out, std::size_t count)
{
  for (std::size_t i = 0; i < count; ++i)
  {
    const double x = in[3 * i];
    const double y = in[3 * i + 1];
    const double z = in[3 * i + 2];
    out[3 * i] = m[0] * x + m[1] * y + m[2] * z + m[3];
    out[3 * i + 1] = m[4] * x + m[5] * y + m[6] * z + m[7];
    out[3 * i + 2] = m[8] * x + m[9] * y + m[10] * z + m[11];
  }
}

namespace
{
/// Every k-th of `count` triples so that at most `limit` remain (all when count <= limit), in order.
std::vector<double> Strided(const double* xyz, std::size_t count, std::size_t limit)
{
  const std::size_t stride = std::max<std::size_t>(1, (count + limit - 1) / std::max<std::size_t>(limit, 1));
  std::vector<double> out;
  for (std::size_t i = 0; i < count; i += stride)
    out.insert(out.end(), xyz + 3 * i, xyz + 3 * i + 3);
  return out;
}

/// Pulls `referencePoints` back through `matrix` (a similarity) into `pulled`; returns its scale (the cube root of
/// the determinant), or 0 when the matrix cannot be inverted. A similarity keeps nearest neighbours, so the nearest
/// moved landmark of a reference point r is the nearest original landmark of M^-1 r, at s times that one's distance:
/// the landmarks' search structure is built once, not once per transform.
double PullBack(const double matrix[16], const std::vector<double>& referencePoints, std::vector<double>& pulled)
{
  const Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> current(matrix);
  const double determinant = current.topLeftCorner<3, 3>().determinant();
  double inverse[16];
  Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> back(inverse);
  back = current.inverse();
  if (!(determinant > 0.0) || !back.allFinite())
    return 0.0;
  pulled.resize(referencePoints.size());
  ApplyTransform(inverse, referencePoints.data(), pulled.data(), referencePoints.size() / 3);
  return std::cbrt(determinant);
}

/// The symmetric mean distance of the landmarks moved by `matrix` and the reference (see RegistrationResult);
/// `cloud` is the landmarks' own search structure (see PullBack).
double SymmetricDistance(const double matrix[16], const std::vector<double>& landmarks,
  const std::vector<double>& referencePoints, const PointSurfaceDistance& reference, const PointSurfaceDistance& cloud,
  const ParallelFor& parallelFor)
{
  const std::size_t n = landmarks.size() / 3, m = referencePoints.size() / 3;
  std::vector<double> moved(landmarks.size()), pulled, forward(n), backward(m);
  const double scale = PullBack(matrix, referencePoints, pulled);
  if (!(scale > 0.0))
    return std::numeric_limits<double>::infinity();
  ApplyTransform(matrix, landmarks.data(), moved.data(), n);
  reference.QueryMany(moved.data(), n, forward.data(), nullptr, nullptr, nullptr, parallelFor);
  cloud.QueryMany(pulled.data(), m, backward.data(), nullptr, nullptr, nullptr, parallelFor);
  const double f = std::accumulate(forward.begin(), forward.end(), 0.0) / static_cast<double>(n);
  const double b = scale * std::accumulate(backward.begin(), backward.end(), 0.0) / static_cast<double>(m);
  return 0.5 * (f + b);
}

/// The pairs of one symmetric iteration: each landmark's closest point on the reference (and its triangle on a
/// surface), each reference point's nearest moved landmark, with their distances.
struct SymmetricPairs
{
  std::vector<double> moved, closest, forward, backward, pulled;
  std::vector<std::int64_t> primitive, nearest;
  std::vector<double> referenceNormal; ///< the surface's normal at each reference point
  double rounding = 0.0; ///< distances below this (1e-12 of the landmarks' extent) are rounding, not a direction
  double covered = 0.0;  ///< a reference point nearer its landmark than this lies within the landmarks' cover
  double scale = 1.0;    ///< the transform's scale (0: not invertible)
};

/// Adds one linearised residual u . (x' - target) = r of a landmark at x (relative to the centroid) to the normal
/// equations of the motion x' = x + w x x + t + s x: its row is (x x u, u, u . x).
Eigen::Matrix<double, 7, 1> Row(const Eigen::Vector3d& x, const Eigen::Vector3d& u, bool withScale)
{
  Eigen::Matrix<double, 7, 1> j;
  j << x.cross(u), u, withScale ? u.dot(x) : 0.0;
  return j;
}

void AddRow(const Eigen::Vector3d& x, const Eigen::Vector3d& u, double r, bool withScale,
  Eigen::Matrix<double, 7, 7>& a, Eigen::Matrix<double, 7, 1>& b)
{
  const Eigen::Matrix<double, 7, 1> j = Row(x, u, withScale);
  a.selfadjointView<Eigen::Upper>().rankUpdate(j);
  b -= j * r;
}

/// Solves the normal equations (a tiny ridge keeps directions nothing constrains, e.g. sliding on a plane, at
/// zero), applies the step, times `damping`, as an exact rotation and scale about the centroid g and composes it with `matrix` into
/// `fitted`. False when the step is not usable.
bool SolveStep(Eigen::Matrix<double, 7, 7> a, const Eigen::Matrix<double, 7, 1>& b, const Eigen::Vector3d& g,
  bool withScale, double damping, const double matrix[16], double fitted[16])
{
  a.triangularView<Eigen::StrictlyLower>() = a.transpose();
  const double ridge = 1e-12 * std::max(a.trace(), 1e-300);
  for (int k = 0; k < 7; ++k)
    a(k, k) += ridge;
  const Eigen::Matrix<double, 7, 1> step = damping * a.ldlt().solve(b);
  if (!step.allFinite())
    return false;
  const Eigen::Vector3d w = step.head<3>();
  const double angle = w.norm();
  const Eigen::Matrix3d rotation =
    angle > 0.0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
  const double s = withScale ? 1.0 + step(6) : 1.0;
  Eigen::Matrix4d delta = Eigen::Matrix4d::Identity();
  delta.topLeftCorner<3, 3>() = s * rotation;
  delta.topRightCorner<3, 1>() = g - s * rotation * g + step.segment<3>(3);
  const Eigen::Matrix4d current = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(matrix);
  Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> composed(fitted);
  composed = delta * current;
  return s > 0.0;
}

/// One Gauss-Newton step of the symmetric objective on a surface reference: each landmark's distance to the surface
/// (residual along u = (x - c) / |x - c|, the surface's normal where the closest point is inside a triangle, the
/// direction to an edge or corner beyond the outline: the tangent plane, so that landmarks slide freely along the
/// surface instead of being held at their closest points as point-to-point pairs hold them) and each reference
/// point's offset to its nearest moved landmark (three rows), all of equal weight as in the point-to-point stage.
bool SymmetricPlaneStep(const SymmetricPairs& p, const std::vector<double>& referencePoints,
  const PointSurfaceDistance& reference, const RegistrationParameters& settings, double damping,
  const double matrix[16], double fitted[16], std::size_t& pairs)
{
  const std::size_t n = p.forward.size(), m = p.nearest.size();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i)
    g += Eigen::Vector3d(p.moved[3 * i], p.moved[3 * i + 1], p.moved[3 * i + 2]);
  g /= static_cast<double>(n);
  Eigen::Matrix<double, 7, 7> a = Eigen::Matrix<double, 7, 7>::Zero();
  Eigen::Matrix<double, 7, 1> b = Eigen::Matrix<double, 7, 1>::Zero();
  for (std::size_t i = 0; i < n; ++i)
  {
    if (settings.rejectDistance >= 0.0 && p.forward[i] > settings.rejectDistance)
      continue;
    const Eigen::Vector3d x = Eigen::Vector3d(p.moved[3 * i], p.moved[3 * i + 1], p.moved[3 * i + 2]) - g;
    const Eigen::Vector3d d = Eigen::Vector3d(p.moved[3 * i], p.moved[3 * i + 1], p.moved[3 * i + 2]) -
      Eigen::Vector3d(p.closest[3 * i], p.closest[3 * i + 1], p.closest[3 * i + 2]);
    double normal[3];
    reference.GetTriangleNormal(p.primitive[i], normal);
    Eigen::Vector3d u(normal[0], normal[1], normal[2]);
    // Closest to an edge or corner (off the triangle's normal by more than rounding): the distance's own direction.
    if (p.forward[i] > p.rounding && std::abs(u.dot(d)) < (1.0 - 1e-9) * p.forward[i])
      u = d / p.forward[i];
    AddRow(x, u, u.dot(d), settings.withScale, a, b);
    ++pairs;
  }
  for (std::size_t j = 0; j < m; ++j)
  {
    if (settings.rejectDistance >= 0.0 && p.backward[j] > settings.rejectDistance)
      continue;
    const auto k = static_cast<std::size_t>(p.nearest[j]);
    const Eigen::Vector3d y(p.moved[3 * k], p.moved[3 * k + 1], p.moved[3 * k + 2]);
    const Eigen::Vector3d d =
      y - Eigen::Vector3d(referencePoints[3 * j], referencePoints[3 * j + 1], referencePoints[3 * j + 2]);
    if (p.backward[j] > p.covered)
    {
      for (int e = 0; e < 3; ++e)
        AddRow(y - g, Eigen::Vector3d::Unit(e), d(e), settings.withScale, a, b);
    }
    else
    {
      // Within the landmarks' cover the nearest landmark changes as the motion slides them along the surface, so
      // the offset along the surface has no curvature to speak of: it enters the gradient, not the Hessian (the
      // fixed point is the same; Gauss-Newton's Hessian would hold the landmarks in place there and crawl).
      const Eigen::Vector3d nr(p.referenceNormal[3 * j], p.referenceNormal[3 * j + 1], p.referenceNormal[3 * j + 2]);
      AddRow(y - g, nr, nr.dot(d), settings.withScale, a, b);
      b -= Row(y - g, d - nr.dot(d) * nr, settings.withScale);
    }
    ++pairs;
  }
  return pairs >= 3 && SolveStep(a, b, g, settings.withScale, damping, matrix, fitted);
}

/// One symmetric point-to-point step on a point-cloud reference: Umeyama's similarity between the original
/// landmarks and their pairs in both directions.
bool SymmetricPointStep(const std::vector<double>& landmarks, const SymmetricPairs& p,
  const std::vector<double>& referencePoints, const RegistrationParameters& settings, double fitted[16],
  std::size_t& pairs)
{
  std::vector<double> source, target;
  for (std::size_t i = 0; i < p.forward.size(); ++i)
    if (settings.rejectDistance < 0.0 || p.forward[i] <= settings.rejectDistance)
    {
      source.insert(source.end(), landmarks.begin() + 3 * i, landmarks.begin() + 3 * i + 3);
      target.insert(target.end(), p.closest.begin() + 3 * i, p.closest.begin() + 3 * i + 3);
    }
  for (std::size_t j = 0; j < p.nearest.size(); ++j)
    if (settings.rejectDistance < 0.0 || p.backward[j] <= settings.rejectDistance)
    {
      const auto k = static_cast<std::size_t>(p.nearest[j]);
      source.insert(source.end(), landmarks.begin() + 3 * k, landmarks.begin() + 3 * k + 3);
      target.insert(target.end(), referencePoints.begin() + 3 * j, referencePoints.begin() + 3 * j + 3);
    }
  pairs = source.size() / 3;
  return FitSimilarity(source.data(), target.data(), pairs, settings.withScale, fitted);
}

/// The pairs at `matrix` (moved landmarks to the reference, reference points to the moved landmarks, and on a
/// surface the cover distance); returns the symmetric mean distance (see RegistrationResult) of `matrix`.
double FindPairs(const double matrix[16], const std::vector<double>& landmarks,
  const std::vector<double>& referencePoints, const PointSurfaceDistance& reference, const PointSurfaceDistance& cloud,
  const ParallelFor& parallelFor, SymmetricPairs& p)
{
  const std::size_t n = landmarks.size() / 3, m = referencePoints.size() / 3;
  ApplyTransform(matrix, landmarks.data(), p.moved.data(), n);
  reference.QueryMany(p.moved.data(), n, p.forward.data(), nullptr, p.closest.data(),
    p.primitive.empty() ? nullptr : p.primitive.data(), parallelFor);
  p.scale = PullBack(matrix, referencePoints, p.pulled);
  if (!(p.scale > 0.0))
    return std::numeric_limits<double>::infinity();
  cloud.QueryMany(p.pulled.data(), m, p.backward.data(), nullptr, nullptr, p.nearest.data(), parallelFor);
  for (double& d : p.backward)
    d *= p.scale;
  if (!p.primitive.empty())
  {
    // Twice the median distance of a reference point to its nearest landmark: about the landmarks' spacing.
    std::vector<double> sorted = p.backward;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(m / 2), sorted.end());
    p.covered = 2.0 * sorted[m / 2];
  }
  return 0.5 *
    (std::accumulate(p.forward.begin(), p.forward.end(), 0.0) / static_cast<double>(n) +
      std::accumulate(p.backward.begin(), p.backward.end(), 0.0) / static_cast<double>(m));
}

/// Symmetric ICP (RegisterPoints' symmetric mode) from the identity; fills matrix, iterations, converged (the
/// caller guards and finishes the result). On a surface each iteration is a Gauss-Newton step with the surface's
/// tangent planes (SymmetricPlaneStep: a few iterations), on a point cloud Umeyama's closed form on the pairs.
void SymmetricICP(const std::vector<double>& landmarks, const std::vector<double>& referencePoints,
  const PointSurfaceDistance& reference, const PointSurfaceDistance& cloud, const RegistrationParameters& settings,
  const ParallelFor& parallelFor, RegistrationResult& result)
{
  const std::size_t n = landmarks.size() / 3, m = referencePoints.size() / 3;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (std::size_t i = 0; i < n; ++i)
  {
    lo = lo.cwiseMin(Eigen::Vector3d(landmarks[3 * i], landmarks[3 * i + 1], landmarks[3 * i + 2]));
    hi = hi.cwiseMax(Eigen::Vector3d(landmarks[3 * i], landmarks[3 * i + 1], landmarks[3 * i + 2]));
  }
  const double stepLimit = settings.tolerance * std::max((hi - lo).norm(), 1e-300);
  const bool planes = reference.IsSurface();
  SymmetricPairs p;
  p.rounding = 1e-12 * (hi - lo).norm();
  if (planes)
  {
    std::vector<double> unused(m);
    std::vector<std::int64_t> triangle(m);
    reference.QueryMany(referencePoints.data(), m, unused.data(), nullptr, nullptr, triangle.data(), parallelFor);
    p.referenceNormal.resize(3 * m);
    for (std::size_t j = 0; j < m; ++j)
      reference.GetTriangleNormal(triangle[j], p.referenceNormal.data() + 3 * j);
  }
  p.moved.resize(3 * n);
  p.closest.resize(3 * n);
  p.forward.resize(n);
  p.backward.resize(m);
  p.primitive.resize(planes ? n : 0);
  p.nearest.resize(m);
  std::vector<double> next(3 * n);
  double matrix[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 }, bestMatrix[16];
  double best = std::numeric_limits<double>::infinity(), damping = 1.0;
  SymmetricPairs bestPairs;
  int stale = 0, refused = 0;
  for (int iteration = 1; iteration <= settings.maximumIterations; ++iteration)
  {
    const double mean = FindPairs(matrix, landmarks, referencePoints, reference, cloud, parallelFor, p);
    result.iterations = iteration;
    // A transform that does not lower the symmetric mean distance is taken back (the Hessian left out along the
    // surface can overshoot). Near the minimum the pairs' own jitter keeps
    // the steps from shrinking below the tolerance: three transforms in a row that do not lower it by 0.1 % end the
    // stage with the best transform seen.
    if (mean < best || iteration == 1)
    {
      refused = 0;
      const bool progress = mean < (1.0 - 1e-3) * best;
      best = mean;
      std::copy(matrix, matrix + 16, bestMatrix);
      bestPairs = p;
      stale = progress ? 0 : stale + 1;
      damping = progress ? std::min(1.0, 2.0 * damping) : damping;
    }
    else
    {
      // Back to the best transform; the step from there counts every reference point's pairs in the Hessian (the
      // Gauss-Newton step of the whole objective), halved after a second refusal.
      ++stale;
      std::copy(bestMatrix, bestMatrix + 16, matrix);
      p = bestPairs;
      p.covered = 0.0;
      damping = refused++ ? 0.5 * damping : 1.0;
    }
    if (stale == 3)
    {
      std::copy(bestMatrix, bestMatrix + 16, matrix);
      result.converged = true;
      break;
    }
    double fitted[16];
    std::size_t pairs = 0;
    bool solved = p.scale > 0.0 &&
      (planes ? SymmetricPlaneStep(p, referencePoints, reference, settings, damping, matrix, fitted, pairs)
              : SymmetricPointStep(landmarks, p, referencePoints, settings, fitted, pairs));
    for (int shorter = 0; planes && !solved && pairs >= 3 && shorter < 4; ++shorter)
    {
      damping *= 0.5; // an unusable step (a scale at or below zero): a shorter one
      pairs = 0;
      solved = SymmetricPlaneStep(p, referencePoints, reference, settings, damping, matrix, fitted, pairs);
    }
    if (!solved)
    {
      std::ostringstream message;
      message << "registration failed at iteration " << iteration << ": " << pairs
              << " landmark pairs within the rejection distance (at least 3 distinct points are needed)";
      result.error = message.str();
      return;
    }
    ApplyTransform(fitted, landmarks.data(), next.data(), n);
    double step2 = 0.0;
    for (std::size_t i = 0; i < 3 * n; i += 3)
      step2 = std::max(step2,
        (Eigen::Vector3d(next[i], next[i + 1], next[i + 2]) -
          Eigen::Vector3d(p.moved[i], p.moved[i + 1], p.moved[i + 2]))
          .squaredNorm());
    std::copy(fitted, fitted + 16, matrix);
    if (std::sqrt(step2) <= stepLimit)
    {
      result.converged = true;
      break;
    }
  }
  std::copy(matrix, matrix + 16, result.matrix);
}

RegistrationResult RegisterOneSided(const double* points, std::size_t count, const PointSurfaceDistance& reference,
  const RegistrationParameters& settings, const ParallelFor& parallelFor);
} // namespace

//------------------------------------------------------------------------------
std::string UndeterminedRegistration(const double* points, std::size_t count, bool withScale)
{
  // Distinct points, up to the number of unknowns (6 rigid, 7 with scale): fewer leave the motion free.
  const std::size_t unknowns = withScale ? 7 : 6;
  std::vector<Eigen::Vector3d> distinct;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < count; ++i)
  {
    const Eigen::Vector3d x(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
    mean += x;
    if (distinct.size() < unknowns && std::find(distinct.begin(), distinct.end(), x) == distinct.end())
      distinct.push_back(x);
  }
  mean /= static_cast<double>(std::max<std::size_t>(count, 1));
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < count; ++i)
  {
    const Eigen::Vector3d d = Eigen::Vector3d(points[3 * i], points[3 * i + 1], points[3 * i + 2]) - mean;
    covariance += d * d.transpose();
  }
  const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues();
  std::ostringstream message;
  message << "registration is not determined by the measured points: ";
  if (distinct.size() <= 1 || !(spread(2) > 0.0))
    message << "all " << count << " are the same point (a rotation about it moves none of them)";
  else if (spread(1) <= 1e-12 * spread(2))
    message << "all " << count << " lie on one line (a rotation about the line moves none of them)";
  else if (distinct.size() < unknowns)
    message << "only " << distinct.size() << " distinct points for the " << unknowns
            << " unknowns of the transform (at least " << unknowns << " are needed)";
  else
    return {};
  message << "; the measured points are left unregistered (identity transform, RegistrationConverged = 0)";
  return message.str();
}

//------------------------------------------------------------------------------
RegistrationResult RegisterPoints(const double* points, std::size_t count, const PointSurfaceDistance& reference,
  const RegistrationParameters& settings, const ParallelFor& parallelFor)
{
  RegistrationResult result;
  result.error = ValidateRegistrationParameters(settings);
  if (result.error.empty() && reference.IsEmpty())
    result.error = "registration: the reference is empty";
  if (result.error.empty() && count < 3)
    result.error = "registration needs at least 3 measured points";
  for (std::size_t i = 0; result.error.empty() && i < 3 * count; ++i)
    if (!std::isfinite(points[i]))
      result.error = "registration: a measured point has a non-finite coordinate";
  if (!result.error.empty())
    return result;
  result.warning = UndeterminedRegistration(points, count, settings.withScale);
  if (!result.warning.empty())
  {
    // The identity, as no registration: the distances are those of the points as they are.
    result.landmarks = count;
    std::vector<double> distance(count);
    reference.QueryMany(points, count, distance.data(), nullptr, nullptr, nullptr, parallelFor);
    double sum = 0.0;
    for (double d : distance)
      sum += d * d;
    result.rms = std::sqrt(sum / static_cast<double>(count));
    return result;
  }
  if (!settings.referencePoints || settings.referenceCount == 0)
    return RegisterOneSided(points, count, reference, settings, parallelFor);
  const std::vector<double> landmarks = Strided(points, count, settings.maximumLandmarks);
  const std::vector<double> referencePoints =
    Strided(settings.referencePoints, settings.referenceCount, settings.maximumLandmarks);
  result.landmarks = landmarks.size() / 3;
  PointSurfaceDistance cloud; // the landmarks' search structure, built once (see PullBack)
  result.error = cloud.BuildCloud(landmarks.data(), result.landmarks, parallelFor);
  if (!result.error.empty())
    return result;
  SymmetricICP(landmarks, referencePoints, reference, cloud, settings, parallelFor, result);
  if (!result.error.empty())
    return result;
  // Polish, on a point-cloud reference: rigid point-to-point ICP from there (the scale stays), kept only if the
  // symmetric distance does not grow (one-sided ICP may slide a mismatched leaf along itself). It shares the
  // RegistrationIterations budget (none left: no polish), and when it is kept its own convergence is the result's:
  // the transform is then the polish's. A surface's symmetric stage already fits its tangent planes, and the
  // one-sided point-to-plane polish only slid a partial scan along the leaf until the budget ran out.
  if (!reference.IsSurface() && result.iterations < settings.maximumIterations)
  {
    std::vector<double> moved(landmarks.size());
    ApplyTransform(result.matrix, landmarks.data(), moved.data(), result.landmarks);
    RegistrationParameters rigid = settings;
    rigid.withScale = false;
    rigid.maximumIterations = settings.maximumIterations - result.iterations;
    const RegistrationResult polish = RegisterOneSided(moved.data(), result.landmarks, reference, rigid, parallelFor);
    if (polish.error.empty())
    {
      const Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> a(result.matrix), b(polish.matrix);
      double composed[16];
      Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> product(composed);
      product = b * a;
      if (SymmetricDistance(composed, landmarks, referencePoints, reference, cloud, parallelFor) <=
        SymmetricDistance(result.matrix, landmarks, referencePoints, reference, cloud, parallelFor))
      {
        std::copy(composed, composed + 16, result.matrix);
        result.iterations += polish.iterations;
        result.converged = polish.converged;
      }
    }
  }
  const double identity[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  result.symmetricBefore = SymmetricDistance(identity, landmarks, referencePoints, reference, cloud, parallelFor);
  result.symmetricAfter = SymmetricDistance(result.matrix, landmarks, referencePoints, reference, cloud, parallelFor);
  if (!(result.symmetricAfter <= result.symmetricBefore))
  {
    std::ostringstream message;
    message << "registration made the fit worse (symmetric mean distance " << result.symmetricAfter << " instead of "
            << result.symmetricBefore << " without it): the measured points are left unregistered";
    result.warning = message.str();
    result.worse = true;
    std::copy(identity, identity + 16, result.matrix);
  }
  Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> m(result.matrix);
  if (!settings.withScale && !result.worse)
  {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m.topLeftCorner<3, 3>(), Eigen::ComputeFullU | Eigen::ComputeFullV);
    m.topLeftCorner<3, 3>() = svd.matrixU() * svd.matrixV().transpose();
  }
  result.scale = std::cbrt(m.topLeftCorner<3, 3>().determinant());
  std::vector<double> moved(landmarks.size()), distance(result.landmarks);
  ApplyTransform(result.matrix, landmarks.data(), moved.data(), result.landmarks);
  reference.QueryMany(moved.data(), result.landmarks, distance.data(), nullptr, nullptr, nullptr, parallelFor);
  double sum = 0.0;
  std::size_t kept = 0;
  for (double d : distance)
    if (settings.rejectDistance < 0.0 || d <= settings.rejectDistance)
    {
      sum += d * d;
      ++kept;
    }
  result.rms = kept ? std::sqrt(sum / static_cast<double>(kept)) : 0.0;
  return result;
}

namespace
{
//------------------------------------------------------------------------------
/// RegisterOneSided's landmarks: all points, or a seeded random subset (partial Fisher-Yates), kept in input order,
/// copied to `original`; `stepLimit` is the tolerance times their bounding-box diagonal. The error or "".
std::string ChooseLandmarks(const double* points, std::size_t count, const RegistrationParameters& settings,
  std::vector<double>& original, double& stepLimit)
{
  std::vector<std::size_t> chosen;
  if (count <= settings.maximumLandmarks)
  {
    chosen.resize(count);
    std::iota(chosen.begin(), chosen.end(), std::size_t{ 0 });
  }
  else
  {
    std::vector<std::size_t> all(count);
    std::iota(all.begin(), all.end(), std::size_t{ 0 });
    RandomStream random(settings.seed, 0x1C9);
    for (std::size_t i = 0; i < settings.maximumLandmarks; ++i)
    {
      const auto j =
        static_cast<std::size_t>(random.Integer(static_cast<std::int64_t>(i), static_cast<std::int64_t>(count - 1)));
      std::swap(all[i], all[j]);
    }
    chosen.assign(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(settings.maximumLandmarks));
    std::sort(chosen.begin(), chosen.end());
  }
  const std::size_t n = chosen.size();
  original.assign(3 * n, 0.0);
  double lo[3] = { points[3 * chosen[0]], points[3 * chosen[0] + 1], points[3 * chosen[0] + 2] };
  double hi[3] = { lo[0], lo[1], lo[2] };
  for (std::size_t i = 0; i < n; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      const double x = points[3 * chosen[i] + k];
      if (!std::isfinite(x))
      {
        return "registration: a measured point has a non-finite coordinate";
      }
      original[3 * i + k] = x;
      lo[k] = std::min(lo[k], x);
      hi[k] = std::max(hi[k], x);
    }
  }
  const double diagonal = std::sqrt(
    (hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
  stepLimit = settings.tolerance * std::max(diagonal, 1e-300);
  return {};
}

/// One point-to-plane ICP step: the linearised motion about the moved landmarks' centroid g,
///   x' = g + (1 + s) R(w) (x - g) + t,  residual n . (x' - c), unknowns (w, t[, s]),
/// composed with `matrix` into `fitted`. False when fewer than 3 pairs are kept or the step is not usable.
bool PointToPlaneStep(const std::vector<double>& moved, const std::vector<double>& closest,
  const std::vector<double>& distance, const std::vector<std::int64_t>& primitive,
  const PointSurfaceDistance& reference, const RegistrationParameters& settings, const double matrix[16],
  double fitted[16], std::size_t& pairs)
{
  const std::size_t n = distance.size();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i)
  {
    g += Eigen::Vector3d(moved[3 * i], moved[3 * i + 1], moved[3 * i + 2]);
  }
  g /= static_cast<double>(n);
  Eigen::Matrix<double, 7, 7> a = Eigen::Matrix<double, 7, 7>::Zero();
  Eigen::Matrix<double, 7, 1> b = Eigen::Matrix<double, 7, 1>::Zero();
  for (std::size_t i = 0; i < n; ++i)
  {
    if (settings.rejectDistance >= 0.0 && distance[i] > settings.rejectDistance)
    {
      continue;
    }
    double normal[3];
    reference.GetTriangleNormal(primitive[i], normal);
    const Eigen::Vector3d nn(normal[0], normal[1], normal[2]);
    const Eigen::Vector3d x = Eigen::Vector3d(moved[3 * i], moved[3 * i + 1], moved[3 * i + 2]) - g;
    const Eigen::Vector3d c = Eigen::Vector3d(closest[3 * i], closest[3 * i + 1], closest[3 * i + 2]) - g;
    AddRow(x, nn, nn.dot(x - c), settings.withScale, a, b);
    ++pairs;
  }
  return pairs >= 3 && SolveStep(a, b, g, settings.withScale, 1.0, matrix, fitted);
}

/// One point-to-point ICP step: the closed-form similarity between the original landmarks and their closest
/// reference points (pairs beyond the rejection distance left out), into `fitted`.
bool PointToPointStep(const std::vector<double>& original, const std::vector<double>& closest,
  const std::vector<double>& distance, const RegistrationParameters& settings, double fitted[16], std::size_t& pairs)
{
  std::vector<double> fitSource, fitTarget;
  for (std::size_t i = 0; i < distance.size(); ++i)
  {
    if (settings.rejectDistance >= 0.0 && distance[i] > settings.rejectDistance)
    {
      continue;
    }
    fitSource.insert(fitSource.end(), original.begin() + 3 * i, original.begin() + 3 * i + 3);
    fitTarget.insert(fitTarget.end(), closest.begin() + 3 * i, closest.begin() + 3 * i + 3);
  }
  pairs = fitSource.size() / 3;
  return FitSimilarity(fitSource.data(), fitTarget.data(), pairs, settings.withScale, fitted);
}

/// The end of RegisterOneSided: the rotation re-orthonormalised in rigid mode, the scale, and the RMS of the kept
/// pairs under the final transform.
void FinishOneSided(const std::vector<double>& original, const PointSurfaceDistance& reference,
  const RegistrationParameters& settings, const ParallelFor& parallelFor, double matrix[16], RegistrationResult& result)
{
  const std::size_t n = original.size() / 3;
  if (!settings.withScale)
  {
    // Re-orthonormalise the composed rotation (rounding of many compositions), keeping the translation.
    Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> m(matrix);
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m.topLeftCorner<3, 3>(), Eigen::ComputeFullU | Eigen::ComputeFullV);
    m.topLeftCorner<3, 3>() = svd.matrixU() * svd.matrixV().transpose();
  }
  std::copy(matrix, matrix + 16, result.matrix);
  result.scale = std::cbrt(
    Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(matrix).topLeftCorner<3, 3>().determinant());
  std::vector<double> moved(3 * n), distance(n);
  ApplyTransform(matrix, original.data(), moved.data(), n);
  reference.QueryMany(moved.data(), n, distance.data(), nullptr, nullptr, nullptr, parallelFor);
  double sum = 0.0;
  std::size_t kept = 0;
  for (double d : distance)
  {
    if (settings.rejectDistance < 0.0 || d <= settings.rejectDistance)
    {
      sum += d * d;
      ++kept;
    }
  }
  result.rms = kept ? std::sqrt(sum / static_cast<double>(kept)) : 0.0;
}

//------------------------------------------------------------------------------
RegistrationResult RegisterOneSided(const double* points, std::size_t count, const PointSurfaceDistance& reference,
  const RegistrationParameters& settings, const ParallelFor& parallelFor)
{
  RegistrationResult result;
  result.error = ValidateRegistrationParameters(settings);
  if (!result.error.empty())
  {
    return result;
  }
  if (reference.IsEmpty())
  {
    result.error = "registration: the reference is empty";
    return result;
  }
  if (count < 3)
  {
    result.error = "registration needs at least 3 measured points";
    return result;
  }
  std::vector<double> original;
  double stepLimit = 0.0;
  result.landmarks = std::min(count, settings.maximumLandmarks);
  result.error = ChooseLandmarks(points, count, settings, original, stepLimit);
  if (!result.error.empty())
  {
    return result;
  }
  const std::size_t n = original.size() / 3;
  std::vector<double> moved(3 * n), closest(3 * n), distance(n), next(3 * n);
  std::vector<std::int64_t> primitive(n);
  double matrix[16];
  std::copy(result.matrix, result.matrix + 16, matrix);
  const bool pointToPlane = reference.IsSurface();
  for (int iteration = 1; iteration <= settings.maximumIterations; ++iteration)
  {
    ApplyTransform(matrix, original.data(), moved.data(), n);
    reference.QueryMany(moved.data(), n, distance.data(), nullptr, closest.data(), primitive.data(), parallelFor);
    double fitted[16];
    std::size_t pairs = 0;
    const bool solved = pointToPlane
      ? PointToPlaneStep(moved, closest, distance, primitive, reference, settings, matrix, fitted, pairs)
      : PointToPointStep(original, closest, distance, settings, fitted, pairs);
    if (!solved)
    {
      std::ostringstream message;
      message << "registration failed at iteration " << iteration << ": " << pairs
              << " landmark pairs within the rejection distance (at least 3 distinct points are needed)";
      result.error = message.str();
      return result;
    }
    result.iterations = iteration;
    ApplyTransform(fitted, original.data(), next.data(), n);
    double step2 = 0.0;
    for (std::size_t i = 0; i < 3 * n; i += 3)
    {
      const double dx = next[i] - moved[i];
      const double dy = next[i + 1] - moved[i + 1];
      const double dz = next[i + 2] - moved[i + 2];
      step2 = std::max(step2, dx * dx + dy * dy + dz * dz);
    }
    std::copy(fitted, fitted + 16, matrix);
    if (std::sqrt(step2) <= stepLimit)
    {
      result.converged = true;
      break;
    }
  }
  FinishOneSided(original, reference, settings, parallelFor, matrix, result);
  return result;
}
} // namespace

} // namespace plantmorph
