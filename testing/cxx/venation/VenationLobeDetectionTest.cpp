// SPDX-License-Identifier: GPL-3.0-or-later
// Lobe detection on the margin (PalmateFan.h): a lobe is a margin maximum of the distance from the base whose sinuses
// on both sides are deep (prominence, in leaf lengths) and whose lobe is large (area beyond its sinuses), so scan
// noise, serration and a thin flap beside the petiole never make a lobe. Synthetic blades, fanned from the base:
// five lobes of length 1 between sinuses at 0.45, or an entire blade, with radial noise and teeth on the margin.
#include "PalmateFan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

namespace
{
using namespace plantmorph;
constexpr double Pi = 3.14159265358979323846;
const double LobeAngles[5] = { -80.0, -40.0, 0.0, 40.0, 80.0 }; // degrees from the axis (+y), positive to the left

/// A blade fanned from the base at the origin over [-110, 110] degrees from +y: radius `radius(phi)` plus uniform
/// noise of +-`noise` and teeth of height `teeth` every 3 degrees.
struct Synthetic
{
  VenationBlade blade;
  BladeLocator locator;
};

template <typename Radius>
void Make(Synthetic& s, Radius radius, double noise, double teeth, unsigned seed)
{
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  VenationBlade& b = s.blade;
  b.points.push_back(Eigen::Vector2d::Zero());
  const int n = 660;
  for (int k = 0; k <= n; ++k)
  {
    const double phi = -110.0 + 220.0 * k / n;
    const double tooth = teeth * (1.0 - std::abs(std::fmod(phi + 110.0, 3.0) / 1.5 - 1.0));
    const double r = radius(phi) + noise * uniform(random) + tooth;
    const double a = phi * Pi / 180.0;
    b.points.emplace_back(-r * std::sin(a), r * std::cos(a));
  }
  for (int k = 1; k <= n; ++k)
    b.triangles.push_back({ 0, k, k + 1 });
  b.uv = b.points;
  ASSERT_EQ(s.locator.Build(b), "");
}

double Lobed(double phi)
{
  double bump = 0.0;
  for (double centre : LobeAngles)
    bump = std::max(bump, std::exp(-std::pow((phi - centre) / 11.0, 2.0)));
  return 0.45 + 0.55 * bump;
}

PalmateFan Fan(const Synthetic& s)
{
  return FindPalmateFan(s.blade, s.locator, Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitY(), 1.0, {});
}
} // namespace

TEST(LobeDetection, FiveLobesAreFoundThroughNoiseAndTeeth)
{
  // noise and teeth up to 3 % of the length each (a scan's range noise is 0.2 %); seeds vary the noise.
  for (double noise : { 0.0, 0.01, 0.03 })
  {
    for (double teeth : { 0.0, 0.02, 0.03 })
    {
      for (unsigned seed : { 1u, 2u, 3u })
      {
        Synthetic s;
        Make(s, Lobed, noise, teeth, seed);
        const PalmateFan fan = Fan(s);
        ASSERT_EQ(fan.lobeTips.size(), 5u) << "noise " << noise << ", teeth " << teeth << ", seed " << seed;
        ASSERT_EQ(fan.ends.size(), 5u);
        for (int k = 0; k < 5; ++k)
        {
          const double a = LobeAngles[k] * Pi / 180.0;
          const Eigen::Vector2d truth(-std::sin(a), std::cos(a));
          double gap = 1e300;
          for (const Eigen::Vector2d& tip : fan.lobeTips)
            gap = std::min(gap, (tip - truth).norm());
          // The tip found is a noisy vertex near the true tip: within the noise and teeth plus half a lobe's
          // flat top (the lobe is within 0.01 of its maximum over +-1.5 degrees).
          EXPECT_LT(gap, noise + teeth + 0.03) << "lobe at " << LobeAngles[k] << " degrees";
        }
      }
    }
  }
}

TEST(LobeDetection, NoiseAndTeethOnAnEntireBladeMakeNoLobe)
{
  for (double noise : { 0.01, 0.03 })
  {
    for (double teeth : { 0.02, 0.03 })
    {
      Synthetic s;
      Make(
        s, [](double phi) { return std::cos(phi * Pi / 180.0 * 0.7); }, noise, teeth, 5);
      const PalmateFan fan = Fan(s);
      EXPECT_TRUE(fan.lobeTips.empty()) << fan.lobeTips.size() << " lobes at noise " << noise << ", teeth " << teeth;
      EXPECT_EQ(fan.ends.size(), 4u); // the default PalmateVeins, spread over the blade
    }
  }
}

TEST(LobeDetection, AThinFlapBesideTheBaseIsNoLobe)
{
  // Behind the lobes on the right the blade is 0.1 long, with a 2-degree strip out to 0.4 (a fitted scan's margin
  // beside the petiole): as prominent as a lobe (0.3 over its sinuses) but 0.003 of the length squared in area,
  // against 0.08 for the smallest lobe.
  Synthetic s;
  Make(
    s, [](double phi) { return phi >= -102.0 ? Lobed(phi) : (phi > -109.0 && phi < -107.0 ? 0.4 : 0.1); }, 0.01, 0.0,
    7);
  const PalmateFan fan = Fan(s);
  EXPECT_EQ(fan.lobeTips.size(), 5u);
  for (const Eigen::Vector2d& tip : fan.lobeTips)
    EXPECT_GT(tip.norm(), 0.9) << "a lobe tip at " << tip.transpose();
  // Without the area the flap is a sixth lobe: the prominence alone cannot tell it.
  PalmateFanParameters prominenceOnly;
  prominenceOnly.lobeArea = 0.0;
  EXPECT_EQ(FindPalmateFan(s.blade, s.locator, Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitY(), 1.0, prominenceOnly)
              .lobeTips.size(),
    6u);
}
