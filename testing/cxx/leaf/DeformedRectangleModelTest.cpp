// SPDX-License-Identifier: GPL-3.0-or-later
// Model A (deformed rectangle, paper 000 eq. (1)): the map, its derivatives, its inverse, and parameter checks.
#include "DeformedRectangleModel.h"
#include "DeformedRectanglePresets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace plantmorph
{
namespace
{
constexpr double Pi = 3.14159265358979323846;

/// Eq. (1) written out by hand, with the decimal points the OCR dropped restored.
Eigen::Vector2d EquationOne(double ax, double by, double u, double v)
{
  return { ax * u + 1.1 * by * u * std::sin(Pi * v - Pi / 2),
    by * v + 0.05 * v * by * std::sin(11 * u * Pi - 1.5) - 0.6 * v * by * std::sin((u - 0.5) * Pi) };
}

TEST(DeformedRectangleModel, GinkgoPresetIsEquationOne)
{
  for (double by : { 1.0, 5.0, 37.5 })
  {
    const DeformedRectangleModel model(MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, by));
    ASSERT_EQ(model.Parameters().width, 1.1 * by);
    for (int i = 0; i <= 20; ++i)
    {
      for (int j = 0; j <= 20; ++j)
      {
        const double u = -0.5 + i / 20.0, v = j / 20.0;
        const Eigen::Vector2d expected = EquationOne(1.1 * by, by, u, v);
        const Eigen::Vector2d actual = model.Evaluate(u, v);
        EXPECT_NEAR(actual.x(), expected.x(), 1e-12 * by) << "u=" << u << " v=" << v;
        EXPECT_NEAR(actual.y(), expected.y(), 1e-12 * by) << "u=" << u << " v=" << v;
      }
    }
  }
}

TEST(DeformedRectangleModel, ScaledToItsBladeLengthBaseToApex)
{
  // Eq. (1) at u = 0: the base (0, 0) and the apex (0, b_y (1 + 0.05 sin(-1.5) - 0.6 sin(-pi/2))) = (0, 1.55013 b_y),
  // so a ginkgo blade 5 long has b_y = 5 / 1.55013 (its b_y = 5 made it 7.75 long).
  const double apex = 1.0 + 0.05 * std::sin(-1.5) + 0.6;
  DeformedRectangleParameters ginkgo = MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, 5.0);
  EXPECT_NEAR(BladeLength(ginkgo), 5.0 * apex, 1e-12);
  ASSERT_EQ(ScaleToBladeLength(ginkgo, 5.0), "");
  EXPECT_NEAR(ginkgo.length, 5.0 / apex, 1e-12);
  EXPECT_NEAR(ginkgo.width / ginkgo.length, 1.1, 1e-12) << "a_x / b_y kept: the same shape";
  EXPECT_NEAR(BladeLength(ginkgo), 5.0, 1e-12);
  // Every preset, and a bent one: Length is the distance from base to apex.
  for (int preset = 0; preset < DeformedRectanglePresetCount; ++preset)
  {
    DeformedRectangleParameters p = MakeDeformedRectanglePreset(static_cast<DeformedRectanglePreset>(preset), 3.0);
    p.bending = preset == 2 ? 0.4 : 0.0;
    ASSERT_EQ(Validate(p), "");
    const double ratio = p.width / p.length;
    ASSERT_EQ(ScaleToBladeLength(p, 7.25), "") << preset;
    EXPECT_NEAR(BladeLength(p), 7.25, 1e-12) << preset;
    EXPECT_NEAR(p.width / p.length, ratio, 1e-12) << preset;
  }
  // An apex on the base cannot be scaled to a length.
  DeformedRectangleParameters collapsed;
  collapsed.terms = { SinusoidTerm{
    SinusoidTerm::Y, SinusoidTerm::Length, -1.0, SinusoidTerm::V, 0.0, SinusoidTerm::VariableU, Pi / 2 } };
  ASSERT_EQ(Validate(collapsed), "");
  EXPECT_NE(ScaleToBladeLength(collapsed, 5.0).find("apex falls onto the base"), std::string::npos);
}

TEST(DeformedRectangleModel, CustomTermsReproduceEquationOneForAnyWidth)
{
  // The rows the Terms property documents, with a width that does not collapse the base.
  const std::vector<double> rows = { 0, 1, 1.1, 1, 1, 1, -Pi / 2, 1, 1, 0.05, 2, 11, 0, -1.5, 1, 1, -0.6, 2, 1, 0,
    -Pi / 2 };
  DeformedRectangleParameters p;
  p.width = 2.0;
  p.length = 3.0;
  ASSERT_EQ(ParseTerms(rows, p.terms), "");
  ASSERT_EQ(Validate(p), "");
  const DeformedRectangleModel model(p);
  for (double u : { -0.5, -0.17, 0.0, 0.31, 0.5 })
  {
    for (double v : { 0.0, 0.2, 0.77, 1.0 })
    {
      EXPECT_NEAR((model.Evaluate(u, v) - EquationOne(2.0, 3.0, u, v)).norm(), 0.0, 1e-12);
    }
  }
  EXPECT_EQ(FlattenTerms(p.terms), rows);
}

TEST(DeformedRectangleModel, BaseIsAtTheOriginAndMidveinIsUZero)
{
  for (int k = 1; k < DeformedRectanglePresetCount; ++k)
  {
    DeformedRectangleParameters p = MakeDeformedRectanglePreset(static_cast<DeformedRectanglePreset>(k), 5.0);
    p.asymmetry = 0.3;
    const DeformedRectangleModel model(p);
    EXPECT_LT(model.Evaluate(0.0, 0.0).norm(), 1e-14) << PresetName(static_cast<DeformedRectanglePreset>(k));
    // Asymmetry leaves the midvein where it was.
    p.asymmetry = 0.0;
    const DeformedRectangleModel symmetric(p);
    for (double v : { 0.1, 0.5, 0.9 })
      EXPECT_NEAR((model.Evaluate(0.0, v) - symmetric.Evaluate(0.0, v)).norm(), 0.0, 1e-12);
  }
}

TEST(DeformedRectangleModel, JacobianMatchesFiniteDifferences)
{
  for (int k = 0; k < DeformedRectanglePresetCount; ++k)
  {
    DeformedRectangleParameters p = MakeDeformedRectanglePreset(static_cast<DeformedRectanglePreset>(k), 5.0);
    p.bending = 0.2;
    p.asymmetry = -0.35;
    const DeformedRectangleModel model(p);
    const double h = 1e-6;
    for (double u : { -0.45, -0.1, 0.0, 0.23, 0.49 })
    {
      for (double v : { 0.01, 0.3, 0.64, 0.99 })
      {
        Eigen::Matrix2d numeric;
        numeric.col(0) = (model.Evaluate(u + h, v) - model.Evaluate(u - h, v)) / (2 * h);
        numeric.col(1) = (model.Evaluate(u, v + h) - model.Evaluate(u, v - h)) / (2 * h);
        EXPECT_LT((model.Jacobian(u, v) - numeric).norm(), 1e-5 * (1 + numeric.norm()))
          << PresetName(static_cast<DeformedRectanglePreset>(k)) << " u=" << u << " v=" << v;
      }
    }
  }
}

TEST(DeformedRectangleModel, InvertRecoversParameters)
{
  std::mt19937_64 random(42);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int k = 1; k < DeformedRectanglePresetCount; ++k)
  {
    const DeformedRectangleModel model(MakeDeformedRectanglePreset(static_cast<DeformedRectanglePreset>(k), 5.0));
    for (int trial = 0; trial < 200; ++trial)
    {
      const Eigen::Vector2d uv(-0.49 + 0.98 * uniform(random), 0.02 + 0.96 * uniform(random));
      const Eigen::Vector2d guess =
        uv + Eigen::Vector2d(0.01 * (uniform(random) - 0.5), 0.01 * (uniform(random) - 0.5));
      Eigen::Vector2d found;
      ASSERT_TRUE(model.Invert(model.Evaluate(uv.x(), uv.y()), guess, found))
        << PresetName(static_cast<DeformedRectanglePreset>(k)) << " at " << uv.transpose();
      EXPECT_LT((found - uv).norm(), 1e-8);
    }
  }
}

TEST(DeformedRectangleModel, BadTermsAreRejectedWithTheirRowAndRange)
{
  std::vector<SinusoidTerm> terms;
  EXPECT_NE(ParseTerms({ 0, 1, 1 }, terms).find("rows of 7"), std::string::npos);
  EXPECT_NE(ParseTerms({ 2, 1, 1, 1, 1, 1, 0 }, terms).find("row 0, Target = 2"), std::string::npos);
  EXPECT_NE(ParseTerms({ 0, 1, 1, 1, 1, 1, 0, 0, 0, std::nan(""), 0, 1, 0, 0 }, terms).find("row 1, Amplitude"),
    std::string::npos);
  EXPECT_NE(ParseTerms({ 0, 1, 1, 4, 1, 1, 0 }, terms).find("Multiplier = 4"), std::string::npos);
  EXPECT_NE(ParseTerms({ 0, 1, 1, 1, 1, 0.5, 0 }, terms).find("Variable = 0.5"), std::string::npos);
  EXPECT_NE(ParseTerms({ 0, 1, 1, 1, 1e9, 1, 0 }, terms).find("Frequency"), std::string::npos);
  EXPECT_TRUE(terms.empty());
}

TEST(DeformedRectangleModel, BadParametersNameThePropertyAndRange)
{
  DeformedRectangleParameters good = MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, 5.0);
  EXPECT_EQ(Validate(good), "");
  auto check = [&](auto change, const char* expected) {
    DeformedRectangleParameters p = good;
    change(p);
    const std::string message = Validate(p);
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  };
  check([](auto& p) { p.length = std::nan(""); }, "Length (b_y) = nan is outside the accepted range (0, 1e6]");
  check([](auto& p) { p.length = 0.0; }, "Length (b_y)");
  check([](auto& p) { p.width = -1.0; }, "Width (a_x) = -1 is outside the accepted range [0, 1e6]");
  check([](auto& p) { p.asymmetry = 1.0; }, "Asymmetry = 1 is outside the accepted range (-1, 1)");
  check([](auto& p) { p.bending = std::numeric_limits<double>::infinity(); }, "Bending");
}

} // namespace
} // namespace plantmorph
