// SPDX-License-Identifier: GPL-3.0-or-later
// LeafCurl (filters/subdivision/core): the longitudinal and transverse curl of paper 003 Fig. 7 on real blades from
// LeafOutlineSource's core. Bending is isometric (edge lengths within 1%), the midvein stays put, angle 0 is the
// identity bit for bit, 180 degrees gives half circles with the margin at 2W/pi, curls combine in the documented order,
// relief and normals ride along the bend, and bad input is refused with the property's name.
#include "LeafCurl.h"

#include "BSplineLeaf.h"
#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <utility>
#include <vector>

namespace plantmorph
{
namespace
{
constexpr double Pi = 3.14159265358979323846;

/// A blade as flat arrays, the way the VTK layer hands it to the core.
struct Blade
{
  std::vector<double> xyz;
  std::vector<double> uv;
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> midvein;
  std::size_t Count() const { return uv.size() / 2; }
  Eigen::Vector3d Point(std::size_t i) const { return { xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2] }; }
};

Blade FromLeaf(const LeafGeometry& leaf)
{
  Blade blade;
  for (std::size_t i = 0; i < leaf.blade.points.size(); ++i)
  {
    blade.xyz.insert(blade.xyz.end(), { leaf.blade.points[i].x(), leaf.blade.points[i].y(), 0.0 });
    blade.uv.insert(blade.uv.end(), { leaf.blade.uv[i].x(), leaf.blade.uv[i].y() });
  }
  blade.triangles = leaf.blade.triangles;
  blade.midvein = leaf.midvein;
  return blade;
}

/// The elliptic B-spline leaf of paper 003 (8 long, 6 wide), fine: about 120 segments along the midvein.
Blade EllipticBlade(int resolution = 120)
{
  LeafMeshParameters settings;
  settings.resolution = resolution;
  LeafGeometry leaf;
  EXPECT_EQ(BuildBSplineLeaf(MakeBSplinePreset(BSplinePreset::Elliptic, 8.0, 6.0, 7), settings, leaf), "");
  return FromLeaf(leaf);
}

Blade GinkgoBlade(double bending = 0.0, int resolution = 100)
{
  DeformedRectangleParameters parameters = MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, 5.0);
  parameters.bending = bending;
  LeafMeshParameters settings;
  settings.resolution = resolution;
  LeafGeometry leaf;
  EXPECT_EQ(BuildDeformedRectangleLeaf(parameters, settings, leaf), "");
  return FromLeaf(leaf);
}

/// Largest relative change of an edge's length between two placements of the same mesh.
double MaxEdgeLengthChange(const Blade& before, const std::vector<double>& after)
{
  std::set<std::pair<int, int>> edges;
  for (const auto& t : before.triangles)
    for (int k = 0; k < 3; ++k)
      edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
  double worst = 0.0;
  for (const auto& [a, b] : edges)
  {
    const double flat = (before.Point(a) - before.Point(b)).norm();
    const Eigen::Vector3d pa(after[3 * a], after[3 * a + 1], after[3 * a + 2]);
    const Eigen::Vector3d pb(after[3 * b], after[3 * b + 1], after[3 * b + 2]);
    worst = std::max(worst, std::abs((pa - pb).norm() - flat) / flat);
  }
  return worst;
}

std::vector<double> Curled(
  const Blade& blade, const LeafCurlParameters& parameters, std::vector<double>* normals = nullptr)
{
  std::vector<double> xyz = blade.xyz;
  EXPECT_EQ(CurlLeaf(parameters, blade.Count(), xyz.data(), blade.uv.data(), normals ? normals->data() : nullptr), "");
  return xyz;
}

LeafCurlParameters Longitudinal(double angle)
{
  LeafCurlParameters p;
  p.longitudinalAngle = angle;
  p.transverseAngle = 0.0;
  return p;
}

LeafCurlParameters Transverse(double angle, double center = 0.5)
{
  LeafCurlParameters p;
  p.longitudinalAngle = 0.0;
  p.transverseAngle = angle;
  p.transverseCenter = center;
  return p;
}

TEST(LeafCurl, ZeroAnglesAreTheIdentityBitForBit)
{
  Blade blade = GinkgoBlade(0.1, 40);
  for (std::size_t i = 0; i < blade.Count(); ++i)
    blade.xyz[3 * i + 2] = 0.01 * std::sin(7.0 * blade.xyz[3 * i]); // a little relief, so z is not all zero
  std::vector<double> normals(blade.xyz.size());
  for (std::size_t i = 0; i < normals.size(); ++i)
    normals[i] = 0.1 + 0.37 * std::sin(1.0 + static_cast<double>(i)); // not unit: the identity must not normalise
  const std::vector<double> normalsBefore = normals;
  LeafCurlParameters p;
  p.longitudinalAngle = 0.0;
  p.transverseAngle = 0.0;
  p.transverseCenter = 0.3;
  const std::vector<double> xyz = Curled(blade, p, &normals);
  EXPECT_EQ(std::memcmp(xyz.data(), blade.xyz.data(), xyz.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(normals.data(), normalsBefore.data(), normals.size() * sizeof(double)), 0);
}

class CurlAngles : public ::testing::TestWithParam<double>
{
};

TEST_P(CurlAngles, LongitudinalCurlIsIsometricAndKeepsTheMidvein)
{
  for (const Blade& blade : { EllipticBlade(), GinkgoBlade() })
  {
    const std::vector<double> xyz = Curled(blade, Longitudinal(GetParam()));
    const double change = MaxEdgeLengthChange(blade, xyz);
    EXPECT_LT(change, 0.01) << "angle " << GetParam();
    RecordProperty("max_edge_length_change", std::to_string(change));
    // The bending really happened: something left the plane.
    double maxZ = 0.0;
    for (std::size_t i = 0; i < blade.Count(); ++i)
      maxZ = std::max(maxZ, std::abs(xyz[3 * i + 2]));
    EXPECT_GT(maxZ, 0.1);
    for (int id : blade.midvein)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(xyz[3 * id + k], blade.xyz[3 * id + k]) << "midvein point " << id << " moved";
    // Bending across the blade: nothing moves along it.
    for (std::size_t i = 0; i < blade.Count(); ++i)
      ASSERT_EQ(xyz[3 * i + 1], blade.xyz[3 * i + 1]);
  }
}

TEST_P(CurlAngles, TransverseCurlIsIsometric)
{
  for (const Blade& blade : { EllipticBlade(), GinkgoBlade() })
  {
    const std::vector<double> xyz = Curled(blade, Transverse(GetParam(), 0.4));
    EXPECT_LT(MaxEdgeLengthChange(blade, xyz), 0.01) << "angle " << GetParam();
    for (std::size_t i = 0; i < blade.Count(); ++i)
      ASSERT_EQ(xyz[3 * i], blade.xyz[3 * i]) << "transverse curl moved a point across the blade";
  }
}

INSTANTIATE_TEST_SUITE_P(LeafCurl, CurlAngles, ::testing::Values(30.0, 180.0, -120.0, 360.0));

TEST(LeafCurl, At180DegreesEachHalfIsAHalfCircleWithItsMarginAt2WOverPi)
{
  const Blade blade = EllipticBlade();
  LeafCurl curl;
  ASSERT_EQ(curl.Setup(Longitudinal(180.0), blade.Count(), blade.xyz.data(), blade.uv.data()), "");
  const double widths[2] = { curl.LeftHalfWidth(), curl.RightHalfWidth() };
  EXPECT_NEAR(widths[0], 3.0, 0.05); // the elliptic preset is 6 wide
  EXPECT_NEAR(widths[1], 3.0, 0.05);
  const std::vector<double> xyz = Curled(blade, Longitudinal(180.0));
  int widest[2] = { -1, -1 };
  for (std::size_t i = 0; i < blade.Count(); ++i)
  {
    const double d = curl.LateralDistance(i);
    const int side = d < 0.0 ? 0 : 1;
    const double radius = widths[side] / Pi;
    // On the circle of radius W/pi tangent to the blade at the midvein (x = 0 for this leaf), above it...
    const double x = xyz[3 * i], z = xyz[3 * i + 2];
    EXPECT_NEAR(std::hypot(x, z - radius), radius, 1e-12 * radius);
    // ...at arc length |d| from the midvein (the angle at the circle's centre is |d| / R).
    const double angle = std::atan2(std::abs(x), radius - z);
    EXPECT_NEAR(angle * radius, std::abs(d), 1e-9);
    if (std::abs(std::abs(d) - widths[side]) == 0.0)
      widest[side] = static_cast<int>(i);
  }
  for (int side = 0; side < 2; ++side)
  {
    ASSERT_GE(widest[side], 0);
    const int i = widest[side];
    // The margin's widest point has turned through 180 degrees: straight above the midvein at 2W/pi.
    const Eigen::Vector3d margin(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    const Eigen::Vector3d midvein(0.0, blade.xyz[3 * i + 1], 0.0);
    EXPECT_NEAR((margin - midvein).norm(), 2.0 * widths[side] / Pi, 1e-12);
    EXPECT_NEAR(margin.x(), 0.0, 1e-12);
  }
}

TEST(LeafCurl, At180DegreesTransverselyApexAndBaseMeetAboveTheMidLine)
{
  const Blade blade = EllipticBlade();
  LeafCurl curl;
  ASSERT_EQ(curl.Setup(Transverse(180.0, 0.5), blade.Count(), blade.xyz.data(), blade.uv.data()), "");
  EXPECT_NEAR(curl.MidLineY(), 4.0, 0.01); // v = 0.5 on the 8-long midvein
  EXPECT_NEAR(curl.ApexLength(), 4.0, 0.01);
  EXPECT_NEAR(curl.BaseLength(), 4.0, 0.01);
  const std::vector<double> xyz = Curled(blade, Transverse(180.0, 0.5));
  const int base = blade.midvein.front(), apex = blade.midvein.back();
  for (int id : { base, apex })
  {
    const double length = id == apex ? curl.ApexLength() : curl.BaseLength();
    EXPECT_NEAR(xyz[3 * id + 1], curl.MidLineY(), 1e-12);
    EXPECT_NEAR(xyz[3 * id + 2], 2.0 * length / Pi, 1e-12);
  }
  for (std::size_t i = 0; i < blade.Count(); ++i)
  {
    const double e = blade.xyz[3 * i + 1] - curl.MidLineY();
    const double radius = (e < 0.0 ? curl.BaseLength() : curl.ApexLength()) / Pi;
    EXPECT_NEAR(std::hypot(xyz[3 * i + 1] - curl.MidLineY(), xyz[3 * i + 2] - radius), radius, 1e-12);
  }
}

TEST(LeafCurl, AnUncentredMidLineGivesBothPartsTheFullAngle)
{
  const Blade blade = EllipticBlade(60);
  const std::vector<double> xyz = Curled(blade, Transverse(90.0, 0.25));
  LeafCurl curl;
  ASSERT_EQ(curl.Setup(Transverse(90.0, 0.25), blade.Count(), blade.xyz.data(), blade.uv.data()), "");
  EXPECT_NEAR(curl.MidLineY(), 2.0, 0.01);
  // At 90 degrees the ends stand upright: apex and base at height L (their part's length) over the mid-line,
  // L * 2/pi in front of / behind it.
  const int base = blade.midvein.front(), apex = blade.midvein.back();
  EXPECT_NEAR(xyz[3 * apex + 2], curl.ApexLength() * 2.0 / Pi, 1e-12);
  EXPECT_NEAR(xyz[3 * apex + 1] - curl.MidLineY(), curl.ApexLength() * 2.0 / Pi, 1e-12);
  EXPECT_NEAR(xyz[3 * base + 2], curl.BaseLength() * 2.0 / Pi, 1e-12);
  EXPECT_NEAR(curl.MidLineY() - xyz[3 * base + 1], curl.BaseLength() * 2.0 / Pi, 1e-12);
}

TEST(LeafCurl, NegativeAnglesRollDownAsTheMirrorImage)
{
  const Blade blade = EllipticBlade(40);
  LeafCurlParameters up, down;
  up.longitudinalAngle = 70.0;
  up.transverseAngle = 40.0;
  down.longitudinalAngle = -70.0;
  down.transverseAngle = -40.0;
  const std::vector<double> a = Curled(blade, up), b = Curled(blade, down);
  for (std::size_t i = 0; i < blade.Count(); ++i)
  {
    EXPECT_GE(a[3 * i + 2], 0.0);
    EXPECT_NEAR(a[3 * i], b[3 * i], 1e-12);
    EXPECT_NEAR(a[3 * i + 1], b[3 * i + 1], 1e-12);
    EXPECT_NEAR(a[3 * i + 2], -b[3 * i + 2], 1e-12);
  }
}

TEST(LeafCurl, CombinedCurlIsLongitudinalThenTransverse)
{
  const Blade blade = GinkgoBlade(0.0, 40);
  LeafCurlParameters both;
  both.longitudinalAngle = 120.0;
  both.transverseAngle = 60.0;
  both.transverseCenter = 0.4;
  const std::vector<double> combined = Curled(blade, both);
  Blade rolled = blade;
  rolled.xyz = Curled(blade, Longitudinal(both.longitudinalAngle));
  const std::vector<double> sequence = Curled(rolled, Transverse(both.transverseAngle, both.transverseCenter));
  Blade bent = blade;
  bent.xyz = Curled(blade, Transverse(both.transverseAngle, both.transverseCenter));
  const std::vector<double> reversed = Curled(bent, Longitudinal(both.longitudinalAngle));
  double differenceFromSequence = 0.0, differenceFromReversed = 0.0;
  for (std::size_t k = 0; k < combined.size(); ++k)
  {
    differenceFromSequence = std::max(differenceFromSequence, std::abs(combined[k] - sequence[k]));
    differenceFromReversed = std::max(differenceFromReversed, std::abs(combined[k] - reversed[k]));
  }
  EXPECT_LT(differenceFromSequence, 1e-12);
  EXPECT_GT(differenceFromReversed, 0.1) << "the order should matter";
}

TEST(LeafCurl, NormalsFollowTheCurledSurface)
{
  const Blade blade = EllipticBlade(100);
  for (const auto& [longitudinal, transverse] : { std::pair{ 150.0, 0.0 }, { 0.0, -100.0 }, { 120.0, 60.0 } })
  {
    LeafCurlParameters p;
    p.longitudinalAngle = longitudinal;
    p.transverseAngle = transverse;
    std::vector<double> normals(blade.xyz.size(), 0.0);
    for (std::size_t i = 0; i < blade.Count(); ++i)
      normals[3 * i + 2] = 1.0;
    const std::vector<double> xyz = Curled(blade, p, &normals);
    double worst = 1.0;
    for (const auto& t : blade.triangles)
    {
      Eigen::Vector3d q[3];
      for (int k = 0; k < 3; ++k)
        q[k] = Eigen::Vector3d(xyz[3 * t[k]], xyz[3 * t[k] + 1], xyz[3 * t[k] + 2]);
      const Eigen::Vector3d face = (q[1] - q[0]).cross(q[2] - q[0]).normalized();
      for (int k = 0; k < 3; ++k)
      {
        const Eigen::Vector3d n(normals[3 * t[k]], normals[3 * t[k] + 1], normals[3 * t[k] + 2]);
        EXPECT_NEAR(n.norm(), 1.0, 1e-12);
        worst = std::min(worst, face.dot(n));
      }
    }
    EXPECT_GT(worst, 0.99) << "curl " << longitudinal << ", " << transverse;
  }
}

TEST(LeafCurl, NormalsAreTheSurfacesNormalsEvenWhereACombinedCurlFolds)
{
  // A small blade (midvein x = 0, 0 <= y <= 5, margins at |x| = 2.75) and one probe point, curled 160 and 70 degrees:
  // the rolled halves rise above the transverse radius near the apex and that part turns inside out. The mapped
  // normal must still be the normal of the mapped surface, (dP/dx x dP/dy) / |...|, by central differences.
  LeafCurlParameters p;
  p.longitudinalAngle = 160.0;
  p.transverseAngle = 70.0;
  const double uv[] = { 0, 0, 0, 1, 0.5, 0.5, -0.5, 0.5, 0.3, 0.9 };
  const auto map = [&](double x, double y, double* normal) {
    const double xyz[] = { 0, 0, 0, 0, 5, 0, 2.75, 2.5, 0, -2.75, 2.5, 0, x, y, 0 };
    LeafCurl curl;
    EXPECT_EQ(curl.Setup(p, 5, xyz, uv), "");
    Eigen::Vector3d out;
    curl.Map(4, xyz + 12, out.data(), normal);
    return out;
  };
  int folded = 0;
  for (const auto& [x, y] : { std::pair{ 1.0, 4.8 }, { 2.5, 4.8 }, { -2.5, 4.9 }, { 2.5, 0.3 }, { -1.5, 1.0 } })
  {
    double normal[3] = { 0.0, 0.0, 1.0 };
    map(x, y, normal);
    const double step = 1e-6;
    const Eigen::Vector3d dx = (map(x + step, y, nullptr) - map(x - step, y, nullptr)) / (2 * step);
    const Eigen::Vector3d dy = (map(x, y + step, nullptr) - map(x, y - step, nullptr)) / (2 * step);
    const Eigen::Vector3d surface = dx.cross(dy).normalized();
    EXPECT_GT(surface.dot(Eigen::Vector3d(normal[0], normal[1], normal[2])), 1.0 - 1e-8) << x << ", " << y;
    folded += normal[2] < 0.0 && y > 2.5 ? 1 : 0;
  }
  EXPECT_GT(folded, 0) << "the probe should include a folded point";
}

TEST(LeafCurl, ReliefRidesAlongTheBentNormal)
{
  // A non-flat input: the flat blade lifted by a bump h(x, y) along +Z. The curled bumpy blade is the curled flat
  // blade plus h times the curled normal (Barr's bending), and a uniform lift just lifts the result.
  const Blade flat = EllipticBlade(40);
  LeafCurlParameters p;
  p.longitudinalAngle = 140.0;
  std::vector<double> normals(flat.xyz.size(), 0.0);
  for (std::size_t i = 0; i < flat.Count(); ++i)
    normals[3 * i + 2] = 1.0;
  const std::vector<double> curledFlat = Curled(flat, p, &normals);
  Blade bumpy = flat, lifted = flat;
  std::vector<double> heights(flat.Count());
  for (std::size_t i = 0; i < flat.Count(); ++i)
  {
    const bool onMidvein = std::abs(flat.uv[2 * i]) <= MidveinTolerance;
    heights[i] = onMidvein ? 0.0 : 0.05 * std::sin(flat.xyz[3 * i]) * std::cos(0.5 * flat.xyz[3 * i + 1]);
    bumpy.xyz[3 * i + 2] = heights[i];
    lifted.xyz[3 * i + 2] = 0.7;
  }
  const std::vector<double> curledBumpy = Curled(bumpy, p);
  const std::vector<double> curledLifted = Curled(lifted, p);
  for (std::size_t i = 0; i < flat.Count(); ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_NEAR(curledBumpy[3 * i + k], curledFlat[3 * i + k] + heights[i] * normals[3 * i + k], 1e-12);
      EXPECT_NEAR(curledLifted[3 * i + k], curledFlat[3 * i + k] + (k == 2 ? 0.7 : 0.0), 1e-12);
    }
  }
}

TEST(LeafCurl, ABentMidveinIsFollowedAndStaysPut)
{
  // Model A with Bending: the midvein is a curve x_mid(y). It does not move, and the blade rolls about it; lengths
  // are then only approximately kept (the lateral distance is measured along x, not across the bent vein).
  const Blade blade = GinkgoBlade(0.15, 100);
  const std::vector<double> xyz = Curled(blade, Longitudinal(120.0));
  for (int id : blade.midvein)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(xyz[3 * id + k], blade.xyz[3 * id + k]);
  const double change = MaxEdgeLengthChange(blade, xyz);
  RecordProperty("bent_midvein_max_edge_length_change", std::to_string(change));
  EXPECT_LT(change, 0.25);
}

TEST(LeafCurl, BadParametersAndInputAreRefusedByName)
{
  const Blade blade = EllipticBlade(10);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::pair<LeafCurlParameters, const char*> cases[] = {
    { { nan, 0.0, 0.5 }, "LongitudinalAngle" },
    { { 361.0, 0.0, 0.5 }, "LongitudinalAngle" },
    { { -400.0, 0.0, 0.5 }, "LongitudinalAngle" },
    { { 10.0, nan, 0.5 }, "TransverseAngle" },
    { { 10.0, 720.0, 0.5 }, "TransverseAngle" },
    { { 10.0, 10.0, -0.1 }, "TransverseCenter" },
    { { 10.0, 10.0, nan }, "TransverseCenter" },
    { { 10.0, std::numeric_limits<double>::infinity(), 0.5 }, "TransverseAngle" },
  };
  for (const auto& [parameters, property] : cases)
  {
    std::vector<double> xyz = blade.xyz;
    const std::string error = CurlLeaf(parameters, blade.Count(), xyz.data(), blade.uv.data());
    EXPECT_NE(error.find(property), std::string::npos) << error;
    EXPECT_NE(error.find("accepted range"), std::string::npos) << error;
    EXPECT_EQ(xyz, blade.xyz) << "a refused curl must not touch the points";
  }
  // Edge values are accepted.
  std::vector<double> xyz = blade.xyz;
  EXPECT_EQ(CurlLeaf({ 360.0, -360.0, 1.0 }, blade.Count(), xyz.data(), blade.uv.data()), "");
  EXPECT_EQ(CurlLeaf({ -360.0, 360.0, 0.0 }, blade.Count(), xyz.data(), blade.uv.data()), "");

  // Input: non-finite coordinates or LeafUV, no midvein, no points.
  Blade bad = blade;
  bad.xyz[3 * 5 + 1] = nan;
  xyz = bad.xyz;
  EXPECT_NE(CurlLeaf({}, bad.Count(), xyz.data(), bad.uv.data()).find("point 5"), std::string::npos);
  bad = blade;
  bad.uv[2 * 7 + 1] = nan;
  EXPECT_NE(CurlLeaf({}, bad.Count(), bad.xyz.data(), bad.uv.data()).find("LeafUV"), std::string::npos);
  bad = blade;
  for (std::size_t i = 0; i < bad.Count(); ++i)
    bad.uv[2 * i] = 0.25;
  xyz = bad.xyz;
  EXPECT_NE(CurlLeaf({}, bad.Count(), xyz.data(), bad.uv.data()).find("midvein"), std::string::npos);
  EXPECT_EQ(xyz, bad.xyz);
  EXPECT_NE(CurlLeaf({}, 0, nullptr, nullptr), "");
}

} // namespace
} // namespace plantmorph
