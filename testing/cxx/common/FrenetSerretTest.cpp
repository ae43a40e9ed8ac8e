// SPDX-License-Identifier: GPL-3.0-or-later
// Frenet-Serret integration and the curvature families of paper 002: closed forms (circle, helix), RK4's order,
// RK45's error control, the similarity theorem and its failure for the exponential family.
#include <plantmorph/CurvatureFamily.h>
#include <plantmorph/FrenetSerret.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>

namespace plantmorph
{
namespace
{
constexpr double Pi = 3.14159265358979323846;

FrenetFrame StandardFrame()
{
  return FrenetFrame(); // r = 0, T = x, N = y, B = z
}

std::vector<FrenetFrame> Integrate(const CurveFunction& phi, const CurveFunction& psi, double length, int pieces,
  FrenetParameters settings, const std::vector<double>& breakpoints = {}, const FrenetFrame& start = FrenetFrame())
{
  std::vector<FrenetFrame> frames;
  const std::string error =
    IntegrateFrenet(phi, psi, start, UniformArcLengths(length, pieces), breakpoints, settings, frames);
  EXPECT_EQ(error, "");
  return frames;
}

FrenetParameters RK4(int stepsPerOutput = 1)
{
  FrenetParameters s;
  s.method = FrenetMethod::RK4;
  s.stepsPerOutput = stepsPerOutput;
  return s;
}

FrenetParameters RK45(double tolerance)
{
  FrenetParameters s;
  s.method = FrenetMethod::RK45;
  s.tolerance = tolerance;
  return s;
}

TEST(FrenetSerret, ConstantCurvatureIsACircleAndRK4IsFourthOrder)
{
  const double R = 2.0, S = 1.5 * Pi * R;
  const auto phi = [&](double) { return 1.0 / R; };
  auto endError = [&](int pieces) {
    const std::vector<FrenetFrame> f = Integrate(phi, nullptr, S, pieces, RK4());
    const Eigen::Vector3d exact(R * std::sin(S / R), R * (1 - std::cos(S / R)), 0.0);
    double worst = 0.0;
    for (std::size_t i = 0; i < f.size(); ++i)
    {
      const double s = S * i / (f.size() - 1);
      const Eigen::Vector3d e(R * std::sin(s / R), R * (1 - std::cos(s / R)), 0.0);
      worst = std::max(worst, (f[i].position - e).norm());
      EXPECT_NEAR(f[i].position.z(), 0.0, 1e-15); // psi = 0: a plane curve
    }
    EXPECT_LT((f.back().position - exact).norm(), 1e-2);
    return worst;
  };
  const double coarse = endError(24), fine = endError(48), finer = endError(96);
  // Halving the step cuts the error by 2^4 = 16 for a fourth-order method.
  EXPECT_GT(coarse / fine, 12.0);
  EXPECT_LT(coarse / fine, 20.0);
  EXPECT_GT(fine / finer, 12.0);
  EXPECT_LT(fine / finer, 20.0);
}

TEST(FrenetSerret, ConstantCurvatureAndTorsionIsAHelix)
{
  const double phi = 0.8, psi = 0.3, w2 = phi * phi + psi * psi;
  const double radius = phi / w2, pitch = 2 * Pi * psi / w2;
  const double S = 3 * 2 * Pi / std::sqrt(w2); // three turns
  const std::vector<FrenetFrame> f =
    Integrate([&](double) { return phi; }, [&](double) { return psi; }, S, 300, RK45(1e-12));
  // Axis along the Darboux vector psi*T + phi*B, through the centre of curvature of the start.
  const Eigen::Vector3d axis = (psi * Eigen::Vector3d::UnitX() + phi * Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d centre = radius * Eigen::Vector3d::UnitY();
  for (std::size_t i = 0; i < f.size(); ++i)
  {
    const double s = S * i / (f.size() - 1);
    const Eigen::Vector3d d = f[i].position - centre;
    EXPECT_NEAR((d - d.dot(axis) * axis).norm(), radius, 1e-9) << "s = " << s;
    // Advance along the axis: one pitch per turn (a turn is 2 pi / sqrt(phi^2 + psi^2) of arc length).
    EXPECT_NEAR(f[i].position.dot(axis), pitch * s * std::sqrt(w2) / (2 * Pi), 1e-9) << "s = " << s;
  }
}

TEST(FrenetSerret, FrameStaysOrthonormalAndRightHanded)
{
  const std::vector<FrenetFrame> f = Integrate(
    [](double s) { return 2.0 + std::sin(3 * s); }, [](double s) { return 0.5 * std::cos(s); }, 10.0, 200, RK4(2));
  for (const FrenetFrame& frame : f)
  {
    EXPECT_NEAR(frame.tangent.norm(), 1.0, 1e-14);
    EXPECT_NEAR(frame.normal.norm(), 1.0, 1e-14);
    EXPECT_NEAR(frame.tangent.dot(frame.normal), 0.0, 1e-14);
    EXPECT_LT((frame.binormal - frame.tangent.cross(frame.normal)).norm(), 1e-14);
  }
}

TEST(FrenetSerret, RK45MeetsItsTolerance)
{
  const double R = 1.0, S = 2 * Pi;
  const auto phi = [&](double) { return 1.0 / R; };
  for (double tolerance : { 1e-6, 1e-9, 1e-12 })
  {
    FrenetReport report;
    std::vector<FrenetFrame> f;
    ASSERT_EQ(
      IntegrateFrenet(phi, nullptr, StandardFrame(), UniformArcLengths(S, 4), {}, RK45(tolerance), f, &report), "");
    // Back to the start after a full turn; the global error stays within a modest multiple of the step tolerance.
    EXPECT_LT(f.back().position.norm(), 200 * tolerance * S) << "tolerance " << tolerance;
    EXPECT_GT(report.steps, 0);
  }
}

TEST(FrenetSerret, BreakpointsKeepRK4FourthOrderOnAKinkedCurvature)
{
  CurvatureFamily triangle;
  triangle.type = CurvatureFamily::Triangular;
  triangle.mu = 4.0;
  triangle.lambda = 0.7137; // the kink falls between output points
  const double S = 2.0;
  const auto phi = [&](double s) { return triangle.Evaluate(s, S); };
  const std::vector<FrenetFrame> exact = Integrate(phi, nullptr, S, 10, RK45(1e-13), triangle.Breakpoints(S));
  auto error = [&](int steps, bool withBreakpoints) {
    const std::vector<FrenetFrame> f =
      Integrate(phi, nullptr, S, 10, RK4(steps), withBreakpoints ? triangle.Breakpoints(S) : std::vector<double>{});
    return (f.back().position - exact.back().position).norm();
  };
  EXPECT_GT(error(8, true) / error(16, true), 12.0);
  // Without them a step straddles the kink and the order drops (the error falls far less than 16x).
  EXPECT_LT(error(8, false) / error(16, false), 8.0);
}

/// The chord r(S) - r(0) of the half-margin for a family at length S (paper 002's initial frame).
Eigen::Vector3d Chord(const CurvatureFamily& curvature, const CurvatureFamily* torsion, double S,
  std::vector<FrenetFrame>* frames = nullptr)
{
  FrenetFrame start;
  start.tangent = Eigen::Vector3d(std::cos(Pi / 4), -std::sin(Pi / 4), 0);
  start.normal = Eigen::Vector3d(std::sin(Pi / 4), std::cos(Pi / 4), 0);
  std::vector<double> breaks = curvature.Breakpoints(S);
  if (torsion)
  {
    const std::vector<double> more = torsion->Breakpoints(S);
    breaks.insert(breaks.end(), more.begin(), more.end());
  }
  std::vector<FrenetFrame> f = Integrate([&](double s) { return curvature.Evaluate(s, S); },
    torsion ? CurveFunction([&](double s) { return torsion->Evaluate(s, S); }) : CurveFunction(), S, 64, RK4(4), breaks,
    start);
  if (frames)
    *frames = f;
  return f.back().position - f.front().position;
}

TEST(FrenetSerret, GrowingWithFixedMuIsExactlySimilar)
{
  CurvatureFamily triangle; // paper 002 Fig. 1: mu = 2, lambda = 0.7
  triangle.type = CurvatureFamily::Triangular;
  triangle.mu = 2.0;
  triangle.lambda = 0.7;
  CurvatureFamily power = triangle;
  power.type = CurvatureFamily::Power;
  power.n1 = 2.0;
  power.n2 = 0.5;
  CurvatureFamily notched = triangle;
  notched.type = CurvatureFamily::NotchedApex;
  notched.mu = 6.0;
  CurvatureFamily torsion = triangle; // paper 002 Fig. 5: eta = 4
  torsion.mu = 4.0;
  torsion.lambda = 0.95;
  for (const CurvatureFamily* family : { &triangle, &power, &notched })
  {
    for (const CurvatureFamily* twist : { static_cast<const CurvatureFamily*>(nullptr), &std::as_const(torsion) })
    {
      std::vector<FrenetFrame> small, large;
      const Eigen::Vector3d a = Chord(*family, twist, 1.0, &small);
      const Eigen::Vector3d b = Chord(*family, twist, 3.5, &large);
      EXPECT_LT((a.normalized() - b.normalized()).norm(), 1e-9) << "chord direction, type " << family->type;
      // Not only the chord: the whole curve is a scaled copy.
      for (std::size_t i = 0; i < small.size(); ++i)
        ASSERT_LT((large[i].position / 3.5 - small[i].position).norm(), 1e-9) << "type " << family->type;
    }
  }
}

TEST(FrenetSerret, ExponentialFamilyWithFixedU3TurnsAsItGrows)
{
  CurvatureFamily exponential; // paper 002 Fig. 3: lambda = 0, u3 = 0.001, h*S = 30
  exponential.type = CurvatureFamily::Exponential;
  exponential.mu = 30.0;
  exponential.lambda = 0.0;
  exponential.u3 = 0.001;
  const Eigen::Vector3d a = Chord(exponential, nullptr, 1.0).normalized();
  const Eigen::Vector3d b = Chord(exponential, nullptr, 3.0).normalized();
  const double degrees = std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180 / Pi;
  EXPECT_GT(degrees, 1.0) << "the growth direction must turn";
}

TEST(CurvatureFamily, ValuesAtThePeaksAndEnds)
{
  const double S = 2.0;
  CurvatureFamily f;
  f.mu = 3.0;
  f.lambda = 0.25;
  f.type = CurvatureFamily::Triangular;
  EXPECT_DOUBLE_EQ(f.Evaluate(0.5, S), 1.5);
  EXPECT_DOUBLE_EQ(f.Evaluate(0.0, S), 0.0);
  EXPECT_DOUBLE_EQ(f.Evaluate(S, S), 0.0);
  f.type = CurvatureFamily::Power;
  f.n1 = 3.0;
  EXPECT_DOUBLE_EQ(f.Evaluate(0.25, S), 1.5 * 0.125);
  f.type = CurvatureFamily::Exponential;
  f.b1 = 0.2;
  f.u3 = 0.01;
  EXPECT_NEAR(f.Evaluate(0.0, S), 0.2, 1e-14);
  EXPECT_NEAR(f.Evaluate(0.5, S), 1.5, 1e-14);
  EXPECT_NEAR(f.Evaluate(S, S), 0.01, 1e-14);
  f.type = CurvatureFamily::NotchedApex;
  f.alpha4 = 0.5;
  f.beta = 3.0;
  f.lambda2 = 0.5;
  const double s4 = S / 1.5;
  EXPECT_NEAR(f.Evaluate(0.25 * s4, S), 1.5, 1e-14);
  EXPECT_NEAR(f.Evaluate(s4, S), 0.0, 1e-14);
  EXPECT_NEAR(f.Evaluate(s4 + 0.25 * s4, S), 0.5, 1e-14);
  EXPECT_EQ(f.Breakpoints(S).size(), 3u);
}

TEST(CurvatureFamily, BadParametersNameTheParameterAndRange)
{
  CurvatureFamily f;
  EXPECT_EQ(f.Validate(1.0, "Curvature"), "");
  EXPECT_EQ(f.Validate(0.0, "Curvature"), "CurvatureLength = 0 is outside the accepted range (0, inf)");
  f.lambda = 1.5;
  EXPECT_EQ(f.Validate(1.0, "Curvature"), "CurvatureLambda = 1.5 is outside the accepted range [0, 1]");
  f.lambda = 0.5;
  f.mu = std::nan("");
  EXPECT_NE(f.Validate(1.0, "Torsion").find("TorsionMu = nan"), std::string::npos);
  f.mu = 2.0;
  f.type = CurvatureFamily::Exponential;
  f.u3 = 0.0;
  EXPECT_NE(f.Validate(1.0, "Curvature").find("CurvatureU3"), std::string::npos);
  f.type = CurvatureFamily::NotchedApex;
  f.beta = 0.5;
  EXPECT_NE(f.Validate(1.0, "Curvature").find("CurvatureBeta"), std::string::npos);
}

TEST(FrenetSerret, BadInputIsAnErrorNotACrashOrAHang)
{
  std::vector<FrenetFrame> f;
  const auto one = [](double) { return 1.0; };
  EXPECT_NE(IntegrateFrenet(one, nullptr, FrenetFrame(), { 0.0, 0.0 }, {}, RK4(), f).find("length"), std::string::npos);
  EXPECT_NE(IntegrateFrenet(one, nullptr, FrenetFrame(), { 0.5, 1.0 }, {}, RK4(), f).find("s = 0"), std::string::npos);
  FrenetFrame parallel;
  parallel.normal = parallel.tangent;
  EXPECT_NE(
    IntegrateFrenet(one, nullptr, parallel, { 0.0, 1.0 }, {}, RK4(), f).find("initial frame"), std::string::npos);
  EXPECT_NE(IntegrateFrenet(
              [](double s) { return s > 0.5 ? std::nan("") : 1.0; }, nullptr, FrenetFrame(), { 0.0, 1.0 }, {}, RK4(), f)
              .find("not finite"),
    std::string::npos);
  FrenetParameters limited = RK45(1e-14);
  limited.maxSteps = 50;
  EXPECT_NE(IntegrateFrenet([](double) { return 1e3; }, nullptr, FrenetFrame(), { 0.0, 10.0 }, {}, limited, f)
              .find("integration failed"),
    std::string::npos);
  EXPECT_TRUE(f.empty());
}

} // namespace
} // namespace plantmorph
