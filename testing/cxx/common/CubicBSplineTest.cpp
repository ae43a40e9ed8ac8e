// SPDX-License-Identifier: GPL-3.0-or-later
// Interpolating cubic B-splines (docs/methods/leaf-outline.md): interpolation, C2, not-a-knot ends, exact lines and
// cubics, fourth-order convergence on a circle, derivatives, arc-length sampling, bad input, and size.
#include <plantmorph/CubicBSpline.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace plantmorph
{
namespace
{
constexpr double Pi = 3.14159265358979323846;
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

template <int Dim>
using PointList = typename CubicBSpline<Dim>::PointList;

bool Contains(const std::string& text, const std::string& part)
{
  return text.find(part) != std::string::npos;
}

/// A random walk with steps of length 0.5..1.5 in random directions: random, yet parameter spans stay comparable.
template <int Dim>
PointList<Dim> RandomWalk(int n, unsigned seed)
{
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> step(0.5, 1.5);
  PointList<Dim> points(n);
  points[0] = CubicBSpline<Dim>::Point::Zero();
  for (int i = 1; i < n; ++i)
  {
    typename CubicBSpline<Dim>::Point direction;
    for (int d = 0; d < Dim; ++d)
      direction[d] = normal(random);
    points[i] = points[i - 1] + step(random) * direction.normalized();
  }
  return points;
}

/// Points uniformly random in [-1, 1]^Dim: consecutive points anywhere, chords of very different lengths.
template <int Dim>
PointList<Dim> RandomCloud(int n, unsigned seed)
{
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  PointList<Dim> points(n);
  for (auto& p : points)
  {
    for (int d = 0; d < Dim; ++d)
      p[d] = uniform(random);
  }
  return points;
}

/// One half margin of a leaf 10 long from base (0, 0) to apex (0, 10), with `lobes` lobes (0: an entire margin),
/// curled out of the plane in 3-D.
template <int Dim>
PointList<Dim> LeafMargin(int n, int lobes)
{
  PointList<Dim> points(n);
  for (int i = 0; i < n; ++i)
  {
    const double v = static_cast<double>(i) / (n - 1);
    const double x = 3.0 * std::sin(Pi * v) * std::pow(1.0 - v, 0.3) * (1.0 + 0.35 * std::sin(2.0 * Pi * lobes * v));
    typename CubicBSpline<Dim>::Point p = CubicBSpline<Dim>::Point::Zero();
    p[0] = x;
    p[1] = 10.0 * v + 0.5 * std::sin(Pi * v);
    if constexpr (Dim == 3)
      p[2] = 0.8 * v * v + 0.15 * x * x;
    points[i] = p;
  }
  return points;
}

template <int Dim>
double Size(const PointList<Dim>& points)
{
  typename CubicBSpline<Dim>::Point low = points[0], high = points[0];
  for (const auto& p : points)
  {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  return (high - low).norm();
}

template <int Dim>
CubicBSpline<Dim> Build(const PointList<Dim>& points)
{
  CubicBSpline<Dim> curve;
  const std::string message = CubicBSpline<Dim>::Interpolate(points, curve);
  EXPECT_EQ(message, "");
  return curve;
}

/// Max |C(t_k) - Q_k| over the control points, and the first and last point must be hit exactly.
template <int Dim>
double MaxInterpolationError(const CubicBSpline<Dim>& curve)
{
  const auto& q = curve.ControlPoints();
  const auto& t = curve.Parameters();
  EXPECT_EQ(q.size(), t.size());
  double error = 0.0;
  for (std::size_t k = 0; k < q.size(); ++k)
    error = std::max(error, (curve.Evaluate(t[k]) - q[k]).norm());
  EXPECT_EQ(curve.Evaluate(0.0), q.front());
  EXPECT_EQ(curve.Evaluate(1.0), q.back());
  return error;
}

/// The distinct interior knots (where the cubic pieces meet).
std::vector<double> InteriorKnots(const std::vector<double>& knots)
{
  std::vector<double> interior;
  for (double k : knots)
  {
    if (k > 0.0 && k < 1.0)
      interior.push_back(k);
  }
  return interior;
}

/// B-spline basis N_{i,p}(t) by the Cox-de Boor recursion (0/0 = 0), independent of the code under test; t < 1.
double CoxDeBoor(int i, int p, double t, const std::vector<double>& u)
{
  if (p == 0)
    return u[i] <= t && t < u[i + 1] ? 1.0 : 0.0;
  double value = 0.0;
  if (u[i + p] > u[i])
    value += (t - u[i]) / (u[i + p] - u[i]) * CoxDeBoor(i, p - 1, t, u);
  if (u[i + p + 1] > u[i + 1])
    value += (u[i + p + 1] - t) / (u[i + p + 1] - u[i + 1]) * CoxDeBoor(i + 1, p - 1, t, u);
  return value;
}

template <int Dim>
void ExpectPassesThroughControlPoints(const PointList<Dim>& points, const char* what)
{
  const CubicBSpline<Dim> curve = Build<Dim>(points);
  ASSERT_FALSE(curve.Empty()) << what;
  EXPECT_LE(MaxInterpolationError(curve), 1e-9 * std::max(1.0, Size<Dim>(points))) << what << ", n = " << points.size();
}

TEST(CubicBSpline, PassesThroughRandomPoints)
{
  for (int n : { 2, 3, 4, 5, 6, 7, 10, 33, 200, 1000 })
  {
    for (unsigned seed : { 1u, 2u, 3u })
    {
      ExpectPassesThroughControlPoints<2>(RandomWalk<2>(n, seed), "2-D random walk");
      ExpectPassesThroughControlPoints<3>(RandomWalk<3>(n, seed), "3-D random walk");
      ExpectPassesThroughControlPoints<2>(RandomCloud<2>(n, seed), "2-D random cloud");
      ExpectPassesThroughControlPoints<3>(RandomCloud<3>(n, seed), "3-D random cloud");
    }
  }
}

TEST(CubicBSpline, PassesThroughLeafLikePoints)
{
  for (int n : { 4, 5, 9, 17, 40, 300 })
  {
    for (int lobes : { 0, 3, 7 })
    {
      ExpectPassesThroughControlPoints<2>(LeafMargin<2>(n, lobes), "2-D leaf margin");
      ExpectPassesThroughControlPoints<3>(LeafMargin<3>(n, lobes), "3-D leaf margin");
    }
  }
}

/// Left and right limits at every interior knot: position, C' and C'' agree to a relative 1e-5 (of the largest value
/// of each at the knots). The change over 2e-9 of parameter is ~1e-7 of that for these point counts; a C1 curve would
/// jump by a sizeable fraction.
template <int Dim>
void ExpectC2(const PointList<Dim>& points, const char* what)
{
  const CubicBSpline<Dim> curve = Build<Dim>(points);
  const std::vector<double> knots = InteriorKnots(curve.Knots());
  ASSERT_EQ(knots.size(), points.size() >= 4 ? points.size() - 4 : 0) << what;
  constexpr double Delta = 1e-9;
  struct Side
  {
    typename CubicBSpline<Dim>::Point p, d1, d2;
  };
  std::vector<Side> left(knots.size()), right(knots.size());
  double scale[3] = { 0.0, 0.0, 0.0 };
  for (std::size_t i = 0; i < knots.size(); ++i)
  {
    curve.Derivatives(knots[i] - Delta, left[i].p, left[i].d1, left[i].d2);
    curve.Derivatives(knots[i] + Delta, right[i].p, right[i].d1, right[i].d2);
    scale[0] = std::max({ scale[0], left[i].p.norm(), right[i].p.norm() });
    scale[1] = std::max({ scale[1], left[i].d1.norm(), right[i].d1.norm() });
    scale[2] = std::max({ scale[2], left[i].d2.norm(), right[i].d2.norm() });
  }
  double worst[3] = { 0.0, 0.0, 0.0 };
  for (std::size_t i = 0; i < knots.size(); ++i)
  {
    const double jump[3] = { (right[i].p - left[i].p).norm() / scale[0], (right[i].d1 - left[i].d1).norm() / scale[1],
      (right[i].d2 - left[i].d2).norm() / scale[2] };
    for (int j = 0; j < 3; ++j)
    {
      EXPECT_LE(jump[j], 1e-5) << what << ": derivative " << j << " jumps at knot " << i << " t = " << knots[i];
      worst[j] = std::max(worst[j], jump[j]);
    }
  }
  std::cout << "  " << what << " n = " << points.size()
            << ": largest relative jump of C, C', C'' across a knot: " << worst[0] << ", " << worst[1] << ", "
            << worst[2] << "\n";
}

TEST(CubicBSpline, IsC2AcrossEveryInteriorKnot)
{
  for (int n : { 5, 6, 12, 60 })
  {
    ExpectC2<2>(RandomWalk<2>(n, 7), "2-D random walk");
    ExpectC2<3>(RandomWalk<3>(n, 8), "3-D random walk");
    ExpectC2<2>(LeafMargin<2>(n, 5), "2-D lobed margin");
    ExpectC2<3>(LeafMargin<3>(n, 5), "3-D lobed margin");
  }
}

/// C''' one-sided at t, exactly from C'' (linear on each piece) at t and t -/+ h, h inside the pieces.
template <int Dim>
void ThirdDerivatives(const CubicBSpline<Dim>& curve, double t, double h, typename CubicBSpline<Dim>::Point& left,
  typename CubicBSpline<Dim>::Point& right)
{
  const auto middle = curve.SecondDerivative(t);
  left = (middle - curve.SecondDerivative(t - h)) / h;
  right = (curve.SecondDerivative(t + h) - middle) / h;
}

TEST(CubicBSpline, NotAKnotEnds)
{
  // Knots: four 0s, t_2..t_{n-3}, four 1s; C''' is continuous at t_1 and t_{n-2} (no knot there) and jumps at the
  // knots (for points that are not on one cubic).
  const PointList<2> points = RandomWalk<2>(12, 11);
  const CubicBSpline2d curve = Build<2>(points);
  const std::vector<double>& t = curve.Parameters();
  const std::vector<double>& knots = curve.Knots();
  ASSERT_EQ(knots.size(), points.size() + 4);
  ASSERT_EQ(curve.DeBoorPoints().size(), points.size());
  for (int i = 0; i < 4; ++i)
  {
    EXPECT_EQ(knots[i], 0.0);
    EXPECT_EQ(knots[knots.size() - 1 - i], 1.0);
  }
  for (std::size_t i = 2; i + 2 < t.size(); ++i)
    EXPECT_EQ(knots[i + 2], t[i]);

  double scale = 0.0;
  for (double ti : t)
    scale = std::max(scale, curve.SecondDerivative(ti).norm());
  const double h = 1e-4;
  Eigen::Vector2d left, right;
  for (std::size_t i : { std::size_t(1), t.size() - 2 })
  {
    ThirdDerivatives(curve, t[i], h, left, right);
    EXPECT_LE((right - left).norm() * h, 1e-9 * scale) << "C''' jumps at t_" << i << ", which is not a knot";
  }
  for (std::size_t i = 2; i + 2 < t.size(); ++i)
  {
    ThirdDerivatives(curve, t[i], h, left, right);
    EXPECT_GT((right - left).norm() * h, 1e-6 * scale) << "C''' is continuous at knot t_" << i;
  }
}

TEST(CubicBSpline, DeBoorEvaluationMatchesTheBasisSum)
{
  // Evaluate (span search + de Boor) equals sum_j N_j(t) P_j with N from the Cox-de Boor recursion.
  for (int n : { 4, 5, 9, 25 })
  {
    const PointList<3> points = RandomWalk<3>(n, 21);
    const CubicBSpline3d curve = Build<3>(points);
    const auto& p = curve.DeBoorPoints();
    EXPECT_EQ(p.front(), points.front());
    EXPECT_EQ(p.back(), points.back());
    for (int i = 0; i < 97; ++i)
    {
      const double t = i / 97.0;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (std::size_t j = 0; j < p.size(); ++j)
        sum += CoxDeBoor(static_cast<int>(j), 3, t, curve.Knots()) * p[j];
      EXPECT_LE((curve.Evaluate(t) - sum).norm(), 1e-12 * Size<3>(p)) << "n = " << n << " t = " << t;
    }
  }
}

TEST(CubicBSpline, ReproducesStraightLines)
{
  const Eigen::Vector3d a(1.0, -2.0, 0.5), b(4.0, 2.0, 3.5);
  const Eigen::Vector3d direction = (b - a).normalized();
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(0.2, 1.0);
  for (int n : { 2, 3, 4, 5, 8, 50 })
  {
    for (bool equal : { true, false })
    {
      // Equally spaced, and unequally spaced: chord-length parameters are then still affine on the line.
      std::vector<double> s(n, 0.0);
      for (int i = 1; i < n; ++i)
        s[i] = s[i - 1] + (equal ? 1.0 : uniform(random));
      PointList<3> points(n);
      for (int i = 0; i < n; ++i)
        points[i] = a + (s[i] / s.back()) * (b - a);
      const CubicBSpline3d curve = Build<3>(points);
      for (int i = 0; i <= 1000; ++i)
      {
        const double t = i / 1000.0;
        const Eigen::Vector3d c = curve.Evaluate(t);
        const Eigen::Vector3d offset = c - a;
        EXPECT_LE((offset - offset.dot(direction) * direction).norm(), 1e-12) << "off the line, n = " << n;
        EXPECT_LE((c - (a + t * (b - a))).norm(), 1e-12) << "not uniform speed, n = " << n << " t = " << t;
        EXPECT_LE((curve.FirstDerivative(t) - (b - a)).norm(), 1e-10) << "n = " << n;
        EXPECT_LE(curve.SecondDerivative(t).norm(), 1e-8) << "n = " << n;
      }
    }
  }
}

TEST(CubicBSpline, ReproducesCubicPolynomialCurvesWithTheirParameters)
{
  // Not-a-knot makes the interpolant of a cubic polynomial curve the polynomial itself (given its parameters).
  auto cubic = [](double t) {
    return Eigen::Vector3d(
      1.0 + 2.0 * t - 3.0 * t * t + 4.0 * t * t * t, -1.0 + 5.0 * t * t - 2.0 * t * t * t, 0.5 - t + 0.25 * t * t * t);
  };
  auto cubicPrime = [](double t) {
    return Eigen::Vector3d(2.0 - 6.0 * t + 12.0 * t * t, 10.0 * t - 6.0 * t * t, -1.0 + 0.75 * t * t);
  };
  auto cubicSecond = [](double t) { return Eigen::Vector3d(-6.0 + 24.0 * t, 10.0 - 12.0 * t, 1.5 * t); };
  std::mt19937 random(9);
  std::uniform_real_distribution<double> uniform(0.3, 1.0);
  for (int n : { 4, 5, 6, 11, 40 })
  {
    std::vector<double> t(n, 0.0);
    for (int i = 1; i < n; ++i)
      t[i] = t[i - 1] + uniform(random);
    for (int i = 1; i + 1 < n; ++i)
      t[i] /= t.back();
    t.back() = 1.0;
    PointList<3> points(n);
    for (int i = 0; i < n; ++i)
      points[i] = cubic(t[i]);
    CubicBSpline3d curve;
    ASSERT_EQ(CubicBSpline3d::Interpolate(points, t, curve), "");
    EXPECT_EQ(curve.Parameters(), t);
    for (int i = 0; i <= 500; ++i)
    {
      const double s = i / 500.0;
      EXPECT_LE((curve.Evaluate(s) - cubic(s)).norm(), 1e-12) << "n = " << n << " t = " << s;
      EXPECT_LE((curve.FirstDerivative(s) - cubicPrime(s)).norm(), 1e-10) << "n = " << n << " t = " << s;
      EXPECT_LE((curve.SecondDerivative(s) - cubicSecond(s)).norm(), 1e-8) << "n = " << n << " t = " << s;
    }
  }
}

/// Max distance to the circle of radius R about the origin, of the curve through n points on the arc [0, 1.5*pi].
/// `warp` moves the samples off equal angles (smoothly), so chord length is then not proportional to arc length.
double CircleError(int n, double warp)
{
  const double radius = 2.0, arc = 1.5 * Pi;
  PointList<2> points(n);
  for (int i = 0; i < n; ++i)
  {
    const double s = static_cast<double>(i) / (n - 1);
    const double angle = arc * (s + warp * s * (1.0 - s));
    points[i] = radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
  }
  const CubicBSpline2d curve = Build<2>(points);
  double error = 0.0;
  const int samples = 200 * n;
  for (int i = 0; i <= samples; ++i)
    error = std::max(error, std::abs(curve.Evaluate(static_cast<double>(i) / samples).norm() - radius));
  return error;
}

TEST(CubicBSpline, CircleArcConvergesAtFourthOrder)
{
  for (double warp : { 0.0, 0.3 })
  {
    double previous = CircleError(8, warp);
    std::cout << "  circle arc, warp " << warp << ": n = 8 error " << previous << "\n";
    for (int n : { 16, 32, 64, 128 })
    {
      const double error = CircleError(n, warp);
      const double ratio = previous / error;
      std::cout << "  circle arc, warp " << warp << ": n = " << n << " error " << error << " ratio " << ratio << "\n";
      EXPECT_GT(ratio, 10.0) << "warp " << warp << " n = " << n;
      EXPECT_LT(ratio, 25.0) << "warp " << warp << " n = " << n;
      previous = error;
    }
  }
}

TEST(CubicBSpline, DerivativesMatchFiniteDifferences)
{
  // Central differences at the middle of every piece (so no knot lies within h): O(h^2) there, exact for cubics
  // up to rounding.
  for (int n : { 2, 3, 4, 7, 30 })
  {
    const PointList<3> points = LeafMargin<3>(n, 4);
    const CubicBSpline3d curve = Build<3>(points);
    std::vector<double> breaks = InteriorKnots(curve.Knots());
    breaks.insert(breaks.begin(), 0.0);
    breaks.push_back(1.0);
    double scale1 = 0.0, scale2 = 0.0;
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i)
    {
      const double t = 0.5 * (breaks[i] + breaks[i + 1]);
      scale1 = std::max(scale1, curve.FirstDerivative(t).norm());
      scale2 = std::max(scale2, curve.SecondDerivative(t).norm());
    }
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i)
    {
      const double t = 0.5 * (breaks[i] + breaks[i + 1]);
      const double h = 1e-4 * (breaks[i + 1] - breaks[i]);
      const Eigen::Vector3d d1 = (curve.Evaluate(t + h) - curve.Evaluate(t - h)) / (2.0 * h);
      const Eigen::Vector3d d2 = (curve.FirstDerivative(t + h) - curve.FirstDerivative(t - h)) / (2.0 * h);
      EXPECT_LE((curve.FirstDerivative(t) - d1).norm(), 1e-7 * scale1) << "n = " << n << " t = " << t;
      EXPECT_LE((curve.SecondDerivative(t) - d2).norm(), 1e-7 * std::max(scale2, scale1)) << "n = " << n;
      Eigen::Vector3d p, first, second;
      curve.Derivatives(t, p, first, second);
      EXPECT_EQ(p, curve.Evaluate(t));
      EXPECT_EQ(first, curve.FirstDerivative(t));
      EXPECT_EQ(second, curve.SecondDerivative(t));
    }
  }
}

TEST(CubicBSpline, TwoPointsGiveAStraightSegment)
{
  const PointList<2> points = { Eigen::Vector2d(1.0, 2.0), Eigen::Vector2d(-3.0, 5.0) };
  const CubicBSpline2d curve = Build<2>(points);
  ASSERT_EQ(curve.DeBoorPoints().size(), 4u);
  EXPECT_EQ(curve.Parameters(), (std::vector<double>{ 0.0, 1.0 }));
  for (int j = 0; j < 4; ++j)
    EXPECT_LE((curve.DeBoorPoints()[j] - (points[0] + j / 3.0 * (points[1] - points[0]))).norm(), 1e-15);
  for (int i = 0; i <= 10; ++i)
  {
    const double t = i / 10.0;
    EXPECT_LE((curve.Evaluate(t) - (points[0] + t * (points[1] - points[0]))).norm(), 1e-14);
    EXPECT_LE((curve.FirstDerivative(t) - (points[1] - points[0])).norm(), 1e-14);
    EXPECT_LE(curve.SecondDerivative(t).norm(), 1e-13);
  }
  EXPECT_NEAR(curve.Length(), 5.0, 1e-14);
}

TEST(CubicBSpline, ThreePointsGiveAParabola)
{
  const PointList<3> points = { Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(1.0, 2.0, 0.5),
    Eigen::Vector3d(3.0, 1.0, -1.0) };
  const CubicBSpline3d curve = Build<3>(points);
  EXPECT_LE(MaxInterpolationError(curve), 1e-14);
  // A parabola: constant second derivative (a cubic would have a varying one).
  const Eigen::Vector3d second = curve.SecondDerivative(0.0);
  EXPECT_GT(second.norm(), 1.0);
  for (int i = 1; i <= 10; ++i)
    EXPECT_LE((curve.SecondDerivative(i / 10.0) - second).norm(), 1e-12 * second.norm());
}

TEST(CubicBSpline, ParametersAreNormalisedChordLengths)
{
  const PointList<3> points = RandomCloud<3>(40, 4);
  const CubicBSpline3d curve = Build<3>(points);
  const std::vector<double>& t = curve.Parameters();
  ASSERT_EQ(t.size(), points.size());
  EXPECT_EQ(t.front(), 0.0);
  EXPECT_EQ(t.back(), 1.0);
  double polygon = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i)
    polygon += (points[i] - points[i - 1]).norm();
  for (std::size_t i = 1; i < points.size(); ++i)
    EXPECT_NEAR(t[i] - t[i - 1], (points[i] - points[i - 1]).norm() / polygon, 1e-14);
}

TEST(CubicBSpline, ThreeDimensionalCurveInAPlaneEqualsTheTwoDimensionalOne)
{
  const PointList<2> flat = LeafMargin<2>(23, 3);
  PointList<3> lifted;
  for (const auto& p : flat)
    lifted.emplace_back(p.x(), p.y(), 0.0);
  const CubicBSpline2d curve2 = Build<2>(flat);
  const CubicBSpline3d curve3 = Build<3>(lifted);
  for (int i = 0; i <= 100; ++i)
  {
    const double t = i / 100.0;
    EXPECT_LE((curve3.Evaluate(t).head<2>() - curve2.Evaluate(t)).norm(), 1e-13);
    EXPECT_LE(std::abs(curve3.Evaluate(t).z()), 1e-13);
  }
  EXPECT_NEAR(curve3.Length(), curve2.Length(), 1e-12 * curve2.Length());
}

TEST(CubicBSpline, ClampsParametersOutsideTheUnitInterval)
{
  const CubicBSpline2d curve = Build<2>(LeafMargin<2>(9, 2));
  EXPECT_EQ(curve.Evaluate(-0.5), curve.Evaluate(0.0));
  EXPECT_EQ(curve.Evaluate(1.5), curve.Evaluate(1.0));
  EXPECT_EQ(curve.FirstDerivative(-1e9), curve.FirstDerivative(0.0));
  EXPECT_EQ(curve.SecondDerivative(7.0), curve.SecondDerivative(1.0));
  EXPECT_TRUE(curve.Evaluate(NaN).hasNaN());
  EXPECT_EQ(curve.ArcLength(2.0), curve.Length());
  EXPECT_EQ(curve.ParameterAtArcLength(-1.0), 0.0);
  EXPECT_EQ(curve.ParameterAtArcLength(2.0 * curve.Length()), 1.0);
  const CubicBSpline2d empty;
  EXPECT_TRUE(empty.Empty());
  EXPECT_TRUE(empty.Evaluate(0.5).hasNaN());
  EXPECT_TRUE(empty.SampleEqualArcLength(10).empty());
}

TEST(CubicBSpline, RejectsBadControlPoints)
{
  CubicBSpline2d curve = Build<2>(LeafMargin<2>(6, 0));
  ASSERT_FALSE(curve.Empty());

  EXPECT_EQ(CubicBSpline2d::Interpolate({}, curve), "control points: need at least 2, got 0");
  EXPECT_TRUE(curve.Empty()) << "a failed Interpolate must leave the curve empty";
  EXPECT_EQ(
    CubicBSpline2d::Interpolate({ Eigen::Vector2d(1.0, 2.0) }, curve), "control points: need at least 2, got 1");
  EXPECT_TRUE(curve.Empty());

  PointList<3> points = RandomWalk<3>(6, 3);
  points[2].y() = NaN;
  CubicBSpline3d curve3;
  std::string message = CubicBSpline3d::Interpolate(points, curve3);
  EXPECT_TRUE(Contains(message, "control points: point 2 = (")) << message;
  EXPECT_TRUE(Contains(message, "nan")) << message;
  EXPECT_TRUE(Contains(message, "non-finite")) << message;
  EXPECT_TRUE(curve3.Empty());
  points[2].y() = std::numeric_limits<double>::infinity();
  message = CubicBSpline3d::Interpolate(points, curve3);
  EXPECT_TRUE(Contains(message, "point 2 =") && Contains(message, "non-finite")) << message;

  points = RandomWalk<3>(6, 3);
  points[4] = points[3];
  message = CubicBSpline3d::Interpolate(points, curve3);
  EXPECT_TRUE(Contains(message, "control points: points 3 and 4 coincide")) << message;
  EXPECT_TRUE(Contains(message, "consecutive points must be distinct")) << message;
  EXPECT_TRUE(curve3.Empty());
  points[4] = points[3] + Eigen::Vector3d(1e-15, 0.0, 0.0);
  message = CubicBSpline3d::Interpolate(points, curve3);
  EXPECT_TRUE(Contains(message, "control points: points 3 and 4 are only")) << message;
  EXPECT_EQ(CubicBSpline2d::Interpolate({ Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(1.0, 1.0) }, curve),
    "control points: points 0 and 1 coincide at (1, 1) (zero chord length); consecutive points must be distinct");

  // Sizes whose squares under- or overflow: a message, not a curve of length 0 or NaN.
  message = CubicBSpline2d::Interpolate({ Eigen::Vector2d(-1e308, 0.0), Eigen::Vector2d(1e308, 0.0) }, curve);
  EXPECT_EQ(message,
    "control points: the control polygon's length inf is outside [1e-100, 1e+100]; rescale the "
    "points (e.g. to cm)");
  message = CubicBSpline2d::Interpolate({ Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(3e-200, 4e-200) }, curve);
  EXPECT_TRUE(Contains(message, "control points: the control polygon's length 5e-200 is outside")) << message;

  // Points that repeat but not consecutively are fine: a closed curve.
  PointList<2> loop;
  for (int i = 0; i <= 8; ++i)
    loop.emplace_back(std::cos(2.0 * Pi * i / 8.0), std::sin(2.0 * Pi * i / 8.0));
  ASSERT_EQ(CubicBSpline2d::Interpolate(loop, curve), "");
  EXPECT_LE((curve.Evaluate(1.0) - curve.Evaluate(0.0)).norm(), 1e-15);
}

TEST(CubicBSpline, ScalesWithThePoints)
{
  // The curve of s * Q is s times the curve of Q, from tiny to huge sizes within the accepted range.
  const PointList<3> points = LeafMargin<3>(30, 3);
  const CubicBSpline3d reference = Build<3>(points);
  for (double scale : { 1e-95, 1e-40, 1e-3, 1e40, 1e95 })
  {
    PointList<3> scaled = points;
    for (auto& p : scaled)
      p *= scale;
    const CubicBSpline3d curve = Build<3>(scaled);
    ASSERT_FALSE(curve.Empty()) << scale;
    EXPECT_EQ(curve.Parameters().size(), reference.Parameters().size());
    for (std::size_t k = 0; k < points.size(); ++k)
      EXPECT_NEAR(curve.Parameters()[k], reference.Parameters()[k], 1e-14) << scale;
    for (int i = 0; i <= 50; ++i)
      EXPECT_LE((curve.Evaluate(i / 50.0) / scale - reference.Evaluate(i / 50.0)).norm(), 1e-12) << scale;
    EXPECT_NEAR(curve.Length() / scale, reference.Length(), 1e-12 * reference.Length()) << scale;
    EXPECT_NEAR(
      curve.ParameterAtArcLength(0.3 * curve.Length()), reference.ParameterAtArcLength(0.3 * reference.Length()), 1e-12)
      << scale;
  }
}

TEST(CubicBSpline, RejectsBadParameters)
{
  const PointList<2> points = LeafMargin<2>(5, 0);
  CubicBSpline2d curve;
  EXPECT_EQ(
    CubicBSpline2d::Interpolate(points, { 0.0, 0.5, 1.0 }, curve), "parameters: need one per control point (5), got 3");
  EXPECT_TRUE(Contains(CubicBSpline2d::Interpolate(points, { 0.0, 0.2, NaN, 0.7, 1.0 }, curve),
    "parameters: t[2] = nan is not a finite number"));
  EXPECT_TRUE(Contains(CubicBSpline2d::Interpolate(points, { 0.1, 0.2, 0.5, 0.7, 1.0 }, curve), "t[0] = 0.1") &&
    Contains(CubicBSpline2d::Interpolate(points, { 0.1, 0.2, 0.5, 0.7, 1.0 }, curve), "must be 0"));
  EXPECT_TRUE(Contains(CubicBSpline2d::Interpolate(points, { 0.0, 0.2, 0.5, 0.7, 0.9 }, curve), "t[4] = 0.9"));
  const std::string message = CubicBSpline2d::Interpolate(points, { 0.0, 0.5, 0.5, 0.7, 1.0 }, curve);
  EXPECT_TRUE(Contains(message, "t[2] = 0.5 does not exceed t[1] = 0.5") && Contains(message, "increase strictly"))
    << message;
  EXPECT_TRUE(curve.Empty());
  // Given parameters allow a pause (two equal consecutive points).
  PointList<2> paused = points;
  paused[2] = paused[1];
  EXPECT_EQ(CubicBSpline2d::Interpolate(paused, { 0.0, 0.2, 0.5, 0.7, 1.0 }, curve), "");
  EXPECT_LE(MaxInterpolationError(curve), 1e-12);
}

TEST(CubicBSpline, RebuildsFromItsOwnControlPoints)
{
  CubicBSpline3d curve = Build<3>(LeafMargin<3>(12, 2));
  const Eigen::Vector3d middle = curve.Evaluate(0.37);
  ASSERT_EQ(CubicBSpline3d::Interpolate(curve.ControlPoints(), curve), "");
  EXPECT_EQ(curve.ControlPoints().size(), 12u);
  EXPECT_LE((curve.Evaluate(0.37) - middle).norm(), 1e-13);
}

/// Arc length between t0 and t1 by a fine polyline, Richardson-extrapolated: independent of the Gauss table.
template <int Dim>
double PolylineLength(const CubicBSpline<Dim>& curve, double t0, double t1, int pieces)
{
  auto polyline = [&](int m) {
    double length = 0.0;
    auto previous = curve.Evaluate(t0);
    for (int i = 1; i <= m; ++i)
    {
      const auto next = curve.Evaluate(t0 + (t1 - t0) * i / m);
      length += (next - previous).norm();
      previous = next;
    }
    return length;
  };
  return (4.0 * polyline(2 * pieces) - polyline(pieces)) / 3.0;
}

TEST(CubicBSpline, ArcLengthSamplingIsEquallySpaced)
{
  const PointList<2> points = LeafMargin<2>(41, 6);
  const CubicBSpline2d curve = Build<2>(points);
  const double length = curve.Length();
  EXPECT_NEAR(length, PolylineLength(curve, 0.0, 1.0, 20000), 1e-9 * length);

  const int count = 201;
  const std::vector<double> t = curve.EqualArcLengthParameters(count);
  const PointList<2> samples = curve.SampleEqualArcLength(count);
  ASSERT_EQ(t.size(), std::size_t(count));
  ASSERT_EQ(samples.size(), std::size_t(count));
  EXPECT_EQ(samples.front(), points.front());
  EXPECT_EQ(samples.back(), points.back());
  const double spacing = length / (count - 1);
  for (int i = 1; i < count; ++i)
  {
    EXPECT_LT(t[i - 1], t[i]);
    EXPECT_EQ(samples[i], curve.Evaluate(t[i]));
    EXPECT_NEAR(PolylineLength(curve, t[i - 1], t[i], 200), spacing, 1e-8 * spacing) << "piece " << i;
  }
  // Chords at a mesh-like density (the apex is sharp: 201 samples there give chords 4% shorter than the arcs).
  const int dense = 801;
  const PointList<2> meshPoints = curve.SampleEqualArcLength(dense);
  const double meshSpacing = length / (dense - 1);
  double shortest = std::numeric_limits<double>::infinity(), longest = 0.0;
  for (int i = 1; i < dense; ++i)
  {
    const double chord = (meshPoints[i] - meshPoints[i - 1]).norm();
    shortest = std::min(shortest, chord);
    longest = std::max(longest, chord);
  }
  std::cout << "  " << dense << " equal arc-length samples: chords " << shortest / meshSpacing << " .. "
            << longest / meshSpacing << " of the arc spacing\n";
  EXPECT_GT(shortest, 0.99 * meshSpacing);
  EXPECT_LE(longest, meshSpacing * (1.0 + 1e-9));
  // Equal parameter steps are far from equal arc length on the same curve (so the check above can fail).
  const PointList<2> uniform = curve.SampleEqualParameter(dense);
  double uniformShortest = std::numeric_limits<double>::infinity(), uniformLongest = 0.0;
  for (int i = 1; i < dense; ++i)
  {
    uniformShortest = std::min(uniformShortest, (uniform[i] - uniform[i - 1]).norm());
    uniformLongest = std::max(uniformLongest, (uniform[i] - uniform[i - 1]).norm());
  }
  EXPECT_GT(uniformLongest / uniformShortest, 1.05);

  for (double s : { 0.0, 0.1, 0.25, 0.5, 0.9, 1.0 })
  {
    EXPECT_NEAR(curve.ArcLength(curve.ParameterAtArcLength(s * length)), s * length, 1e-12 * length);
    EXPECT_NEAR(curve.ArcLength(s), PolylineLength(curve, 0.0, s, 20000), 1e-9 * length);
  }
}

TEST(CubicBSpline, SamplesAtASpacing)
{
  const CubicBSpline3d curve = Build<3>(LeafMargin<3>(30, 4));
  const double length = curve.Length();
  for (double h : { 0.05, 0.3, 1.7, 1000.0 })
  {
    PointList<3> points;
    std::vector<double> t;
    ASSERT_EQ(curve.SampleAtSpacing(h, points, &t), "");
    const std::size_t pieces = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(length / h)));
    ASSERT_EQ(points.size(), pieces + 1) << "h = " << h;
    ASSERT_EQ(t.size(), points.size());
    for (std::size_t i = 1; i < points.size(); ++i)
    {
      EXPECT_LE((points[i] - points[i - 1]).norm(), h * (1.0 + 1e-9));
      EXPECT_NEAR(curve.ArcLength(t[i]) - curve.ArcLength(t[i - 1]), length / pieces, 1e-10 * length);
    }
  }
  PointList<3> points;
  EXPECT_EQ(curve.SampleAtSpacing(0.0, points), "spacing: 0 is not a positive finite number");
  EXPECT_EQ(curve.SampleAtSpacing(-1.0, points), "spacing: -1 is not a positive finite number");
  EXPECT_EQ(curve.SampleAtSpacing(NaN, points), "spacing: nan is not a positive finite number");
  EXPECT_TRUE(Contains(curve.SampleAtSpacing(1e-300, points), "more than 10000000"))
    << curve.SampleAtSpacing(1e-300, points);
  EXPECT_TRUE(points.empty());
  EXPECT_TRUE(Contains(CubicBSpline3d().SampleAtSpacing(1.0, points), "empty"));
}

TEST(CubicBSpline, TenThousandPointsBuildInLinearTime)
{
  // Not a timed assertion: the times are printed; a quadratic build would make this test crawl at 10^5.
  for (int n : { 10000, 100000 })
  {
    const PointList<3> points = RandomWalk<3>(n, 99);
    const auto start = std::chrono::steady_clock::now();
    CubicBSpline3d curve;
    ASSERT_EQ(CubicBSpline3d::Interpolate(points, curve), "");
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "  " << n << " points (3-D): built (solve + arc-length table) in " << seconds << " s\n";
    EXPECT_LE(MaxInterpolationError(curve), 1e-9 * Size<3>(points)) << "n = " << n;
    const std::vector<double> knots = InteriorKnots(curve.Knots());
    EXPECT_EQ(knots.size(), std::size_t(n - 4));
  }
  const PointList<2> points = LeafMargin<2>(10000, 40);
  const CubicBSpline2d curve = Build<2>(points);
  EXPECT_LE(MaxInterpolationError(curve), 1e-9 * Size<2>(points));
}

} // namespace
} // namespace plantmorph
