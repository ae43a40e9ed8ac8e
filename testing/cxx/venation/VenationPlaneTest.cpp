// SPDX-License-Identifier: GPL-3.0-or-later
// The blade's working plane, the vein points' way back onto the surface, the relief's raising along the normals,
// and the parameters a preset sets as VenationFilter shows them (docs/methods/venation.md).
#include "VenationBlade.h"
#include "VenationGrowth.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <sstream>
#include <string>

namespace
{
using namespace plantmorph;

/// A rectangle [0, w] x [0, l] of nx x ny cells, two triangles each, in z = 0, LeafUV (x / w - 1/2, y / l).
struct Grid
{
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> uv;
  std::vector<std::array<int, 3>> triangles;
};
Grid Rectangle(double w, double l, int nx, int ny)
{
  Grid g;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
    {
      g.points.emplace_back(w * i / nx, l * j / ny, 0.0);
      g.uv.emplace_back(static_cast<double>(i) / nx - 0.5, static_cast<double>(j) / ny);
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
    {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      g.triangles.push_back({ a, b, d });
      g.triangles.push_back({ a, d, c });
    }
  return g;
}

TEST(VenationWorkingPlane, FlatBladeInZIsItsOwnXY)
{
  Grid g = Rectangle(3.0, 5.0, 3, 5);
  for (auto& x : g.points)
    x.z() = 2.5;
  bool flat = false;
  const std::vector<Eigen::Vector2d> plane = VenationWorkingPlane(g.points, g.uv, g.triangles, flat);
  EXPECT_TRUE(flat);
  for (std::size_t i = 0; i < g.points.size(); ++i)
    EXPECT_EQ(plane[i], g.points[i].head<2>());
}

TEST(VenationWorkingPlane, TiltedPlaneBladeKeepsItsDistances)
{
  Grid g = Rectangle(3.0, 5.0, 3, 5);
  const Eigen::Matrix3d turn =
    (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 0.5).normalized()) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
  for (auto& x : g.points)
    x = turn * x + Eigen::Vector3d(1, -2, 3);
  bool flat = false;
  const std::vector<Eigen::Vector2d> plane = VenationWorkingPlane(g.points, g.uv, g.triangles, flat);
  EXPECT_TRUE(flat);
  // An isometry of the blade's plane: every pair of points as far apart as on the blade.
  for (std::size_t i = 0; i < g.points.size(); i += 5)
    for (std::size_t j = 0; j < g.points.size(); j += 3)
      EXPECT_NEAR((plane[i] - plane[j]).norm(), (g.points[i] - g.points[j]).norm(), 1e-9);
}

TEST(VenationWorkingPlane, CurvedBladeIsLeafUVScaledByItsStretch)
{
  // A rectangle 4 wide and 10 long rolled about the y axis into a cylinder arc of radius 1.5 (a rolled leaf, too
  // curved to project onto a plane near its size: 0.73 of its area): lengths along y and along the arc are kept,
  // so the stretch is close to the width along u and the length along v.
  Grid g = Rectangle(4.0, 10.0, 16, 10);
  for (auto& x : g.points)
  {
    const double angle = (x.x() - 2.0) / 1.5;
    x = Eigen::Vector3d(1.5 * std::sin(angle), x.y(), 1.5 * (1.0 - std::cos(angle)));
  }
  bool flat = true;
  const std::vector<Eigen::Vector2d> plane = VenationWorkingPlane(g.points, g.uv, g.triangles, flat);
  EXPECT_FALSE(flat);
  const double su = plane[1].x() / g.uv[1].x(), sv = plane.back().y() / g.uv.back().y();
  EXPECT_NEAR(su, 4.0, 0.01); // chords of 0.25 on an arc of radius 1.5 are 0.9988 of their arcs
  EXPECT_NEAR(sv, 10.0, 0.01);
  for (std::size_t i = 0; i < g.points.size(); ++i)
  {
    EXPECT_DOUBLE_EQ(plane[i].x(), su * g.uv[i].x());
    EXPECT_DOUBLE_EQ(plane[i].y(), sv * g.uv[i].y());
  }
}

TEST(VenationWorkingPlane, GentlyBentFittedBladeKeepsItsShapeNotItsLeafUVRectangle)
{
  // A blade tapering from 4 wide at its base to 0.4 at its apex, 10 long, bent along its length (z = 0.03 y^2)
  // and across (z += 0.05 x^2), with LeafUV as LeafFitFilter gives it: u = +-0.5 at both margins at every height.
  // Scaled LeafUV would make it a rectangle (secondaries then grow nearly across it); it projects onto its plane one
  // to one, so the working plane is that projection: 0.55 as wide at mid-length as at the base, 0.1 at the apex.
  Grid g = Rectangle(4.0, 10.0, 16, 20);
  for (auto& x : g.points)
  {
    const double taper = 1.0 - 0.9 * x.y() / 10.0, across = (x.x() - 2.0) * taper;
    x = Eigen::Vector3d(across, x.y(), 0.03 * x.y() * x.y() + 0.05 * across * across);
  }
  bool flat = false;
  const std::vector<Eigen::Vector2d> plane = VenationWorkingPlane(g.points, g.uv, g.triangles, flat);
  EXPECT_TRUE(flat);
  // The extent of the rows v = 0, 0.5 and 1 in the working plane.
  const auto extent = [&](double v) {
    double best = 0.0;
    for (std::size_t i = 0; i < g.uv.size(); ++i)
      for (std::size_t j = 0; j < g.uv.size(); ++j)
        if (std::abs(g.uv[i].y() - v) < 1e-9 && std::abs(g.uv[j].y() - v) < 1e-9)
          best = std::max(best, (plane[i] - plane[j]).norm());
    return best;
  };
  EXPECT_NEAR(extent(0.5) / extent(0.0), 0.55, 0.03);
  EXPECT_NEAR(extent(1.0) / extent(0.0), 0.1, 0.01);
  EXPECT_NEAR(extent(0.0), 4.0, 0.1);
}

TEST(VenationBlade, InterpolateAtIsTheBarycentricCombination)
{
  const Grid g = Rectangle(2.0, 2.0, 1, 1);
  BladeLocation at;
  at.triangle = 1; // points 0, 3, 2: (0, 0), (2, 2), (0, 2)
  at.weights = Eigen::Vector3d(0.25, 0.5, 0.25);
  const Eigen::Vector3d x = InterpolateAt(g.triangles, g.points, at);
  EXPECT_DOUBLE_EQ(x.x(), 1.0);
  EXPECT_DOUBLE_EQ(x.y(), 1.5);
  EXPECT_EQ(x.z(), 0.0);
  const Eigen::Vector2d uv = InterpolateAt(g.triangles, g.uv, at);
  EXPECT_DOUBLE_EQ(uv.x(), 0.0);
  EXPECT_DOUBLE_EQ(uv.y(), 0.75);
}

TEST(VenationBlade, RaisedAlongNormalsMovesEachPointItsHeightAlongItsUnitNormal)
{
  const Grid g = Rectangle(2.0, 3.0, 2, 3);
  std::vector<double> heights(g.points.size());
  for (std::size_t i = 0; i < heights.size(); ++i)
    heights[i] = 0.1 * static_cast<double>(i);
  // No normals given: the triangles' (counter-clockwise seen from +z: up).
  std::vector<Eigen::Vector3d> raised = RaisedAlongNormals(g.points, g.triangles, {}, heights);
  for (std::size_t i = 0; i < g.points.size(); ++i)
  {
    EXPECT_EQ(raised[i].head<2>(), g.points[i].head<2>());
    EXPECT_NEAR(raised[i].z(), heights[i], 1e-15);
  }
  // Given normals, of any length, are made unit; a zero normal raises along +z.
  std::vector<Eigen::Vector3d> normals(g.points.size(), Eigen::Vector3d(0.0, -3.0, 0.0));
  normals[4] = Eigen::Vector3d::Zero();
  raised = RaisedAlongNormals(g.points, g.triangles, normals, heights);
  EXPECT_NEAR(raised[2].y(), g.points[2].y() - heights[2], 1e-15);
  EXPECT_EQ(raised[2].z(), 0.0);
  EXPECT_NEAR(raised[4].z(), heights[4], 1e-15);
}

TEST(VenationPresets, DescriptionListsEveryValueThePresetSets)
{
  for (int k = 1; k < VenationPresetCount; ++k)
  {
    const auto preset = static_cast<VenationPreset>(k);
    const VenationParameters p = MakeVenationPreset(preset);
    const std::vector<std::pair<const char*, double>> values = VenationParameterValues(p);
    const std::string text = DescribeVenationPreset(preset);
    EXPECT_EQ(text.rfind(VenationPresetName(preset) + " sets", 0), 0u) << text;
    std::istringstream lines(text);
    std::string line;
    std::getline(lines, line); // the title
    std::size_t n = 0;
    for (; std::getline(lines, line); ++n)
    {
      ASSERT_LT(n, values.size());
      EXPECT_EQ(line.rfind(std::string(values[n].first) + " = ", 0), 0u) << line;
    }
    EXPECT_EQ(n, values.size());
    EXPECT_NE(text.find("\nPattern = " + VenationPatternName(p.pattern) + "\n"), std::string::npos);
    EXPECT_EQ(values[1].second, p.primaries);
    EXPECT_EQ(values[5].second, p.secondarySpacing);
  }
}
} // namespace
