// SPDX-License-Identifier: GPL-3.0-or-later
// WiltingSimulation in physical units (WiltingLatticeOf, docs/methods/wilting.md "Physical units"): the
// conversion's closed forms, a cantilever strip under its own weight against beam theory at several voxel sizes, the
// size scaling of geometrically similar leaves, and a curl whose arc does not depend on the voxel size.
#include "WiltingPresets.h"
#include "WiltingSimulation.h"
#include "WiltingTestBlades.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{
using namespace plantmorph;

/// A flat strip [-w/2, w/2] x [0, l] in z = 0 on an nx x ny grid (nx even), LeafUV (u, v), the points of its base
/// edge y = 0 Region 5 (the anchors: the nodes within AnchorRadius of them are held), the others blade.
WiltingInput Strip(double w, double l, int nx, int ny)
{
  return GridBlade(w, l, nx, ny, [](int, int j) { return j == 0 ? 5 : 0; });
}

/// Gravity only, one material everywhere (the petiole row too), heavily damped to reach the static shape.
WiltingParameters StripParameters(double youngs, double thickness)
{
  WiltingParameters p;
  p.units = WiltingUnits::Physical;
  p.bladeThickness = thickness;
  for (WiltingMaterial& m : p.materials)
  {
    m = { 1.0, youngs, 0.0 };
  }
  p.gravity = 981.0;
  p.droopForce = 0.0;
  p.contractionForce = 0.0;
  p.loadProfile = WiltingLoadProfile::Constant;
  p.newmark.rayleighMass = 150.0;
  p.newmark.rayleighStiffness = 0.0;
  p.newmark.timeStep = 1.0 / 200.0;
  p.newmark.maxIterations = 1;
  p.duration = 0.6;
  p.frameInterval = 0.2;
  return p;
}

/// The tip's displacement at the end of the run (the tip: LeafUV v = 1, u = 0).
Eigen::Vector3d TipDisplacement(const WiltingInput& in, const WiltingParameters& p, int* substeps = nullptr)
{
  WiltingSimulation simulation;
  EXPECT_EQ(simulation.Setup(in, p), "");
  EXPECT_EQ(simulation.Run(), "");
  if (substeps)
  {
    *substeps = simulation.Substeps();
  }
  return simulation.Frames().back().tip - in.points[static_cast<std::size_t>(simulation.TipPoint())];
}
} // namespace

TEST(WiltingPhysicalUnits, LatticeValuesFollowTheClosedForms)
{
  WiltingParameters p;
  ApplyWiltingPreset(WiltingPreset::Tomato, p);
  ASSERT_EQ(p.units, WiltingUnits::Physical);
  p.curlStrain = 0.1;
  p.materials[WiltingBlade].damping = 0.5;
  const double t = 0.8;
  const WiltingMaterial& blade = p.materials[WiltingBlade];
  for (const double h : { 1.6, 0.8, 0.4 })
  {
    double share = 0.0;
    int substeps = 0;
    const WiltingParameters q = WiltingLatticeOf(p, h, t, &share, &substeps);
    const WiltingMaterial& m = q.materials[WiltingBlade];
    EXPECT_EQ(q.units, WiltingUnits::Lattice);
    // D = 3/2 k h^2 = E t^3 / 12 per width; mass rho t h^2 per voxel; loads p h^2; curvature d / t on a layer h.
    EXPECT_NEAR(1.5 * m.stiffness * h * h, blade.stiffness * t * t * t / 12.0, 1e-9 * blade.stiffness);
    EXPECT_NEAR(m.density * h * h * h, blade.density * t * h * h, 1e-15);
    EXPECT_NEAR(m.damping, 0.5 * m.stiffness, 1e-12 * m.stiffness);
    EXPECT_NEAR(q.droopForce, p.droopForce * h * h, 1e-12);
    EXPECT_NEAR(q.contractionForce, p.contractionForce * h * h, 1e-12);
    EXPECT_NEAR(q.curlStrain / h, p.curlStrain / t, 1e-15);
    // The contraction's moment about the mid-plane: (share - (1 - share)) F h / 2 = F t / 2.
    EXPECT_NEAR((2.0 * share - 1.0) * h / 2.0, t / 2.0, 1e-15);
    EXPECT_EQ(substeps, h >= t ? 1 : static_cast<int>(std::ceil((t / h) * (t / h))));
    EXPECT_NEAR(q.newmark.timeStep * substeps, p.newmark.timeStep, 1e-15);
    EXPECT_EQ(q.throughStiffness, h > t ? (h / t) * (h / t) : 1.0);
  }
  // At h = t the physical model is the lattice one (all of the contraction on its face, one step).
  double share = 0.0;
  int substeps = 0;
  WiltingLatticeOf(p, t, t, &share, &substeps);
  EXPECT_EQ(share, 1.0);
  EXPECT_EQ(substeps, 1);
  // Lattice units pass through unchanged.
  WiltingParameters lattice = p;
  lattice.units = WiltingUnits::Lattice;
  EXPECT_EQ(WiltingLatticeOf(lattice, 0.3, t).materials[WiltingBlade].stiffness, blade.stiffness);
}

TEST(WiltingPhysicalUnits, CantileverSagsAsBeamTheorySaysAtEveryVoxelSize)
{
  // A strip of length L = 20, width 1, thickness t = 1, density 1, under gravity, held by its first row of voxels
  // (the leaf is held by whole voxels: those whose centre is within AnchorRadius of its base edge), so clamped at
  // y = h with a free length L - h: Euler-Bernoulli (plate strip, bending stiffness D = E t^3 / 12 per width, load
  // rho t g per area) puts its tip rho t g (L - h)^4 / (8 D) down, 0.2 cm ((L - h) / L)^4 for
  // E = 1.5 rho g L^4 / (t^2 0.2). The lattice's own Poisson ratio (1/3: the face diagonals) lets a narrow strip bend
  // anticlastically, up to 1 / (1 - 1/9) = 1.125 times softer than a plate in cylindrical bending: the tip within
  // [0.95, 1.2] times beam theory at every voxel edge, and the voxel edges' (1 and 0.5) tips over beam theory within
  // 6 % of each other (the same plate, not a stiffness that fades as the voxels shrink).
  const double length = 20.0, t = 1.0, sag = 0.2;
  const double youngs = 1.5 * 981.0 * std::pow(length, 4) / (t * t * sag);
  const WiltingInput in = Strip(1.0, length, 8, 160);
  std::vector<double> tips;
  for (const int r : { 20, 40 }) // h = 1 (= t), 0.5
  {
    WiltingParameters p = StripParameters(youngs, t);
    p.resolution = r;
    const double h = length / r;
    p.anchorRadius = 0.75 * h; // the first row of voxels (centres h / 2 from the base edge, h / 2 off its plane)
    int substeps = 0;
    const Eigen::Vector3d d = TipDisplacement(in, p, &substeps);
    EXPECT_EQ(substeps, r == 20 ? 1 : 4);
    const double theory = sag * std::pow((length - h) / length, 4);
    EXPECT_GT(-d[2], 0.95 * theory) << "R " << r;
    EXPECT_LT(-d[2], 1.2 * theory) << "R " << r;
    tips.push_back(-d[2] / theory);
  }
  for (const double tip : tips)
  {
    EXPECT_NEAR(tip / tips.back(), 1.0, 0.06) << tips[0] << " " << tips[1];
  }
}

TEST(WiltingPhysicalUnits, BiggerLeavesDroopMoreAsTheScalingSays)
{
  // Geometrically similar strips, L and 2 L, the same material, at the same Resolution (the same lattice, scaled):
  // with the default thickness t = L / 14 the bending stiffness E t^3 / 12 grows as L^3 and the weight per area
  // rho t g as L, so the small-deflection sag over the length, rho t g L^3 / (8 D), grows as L: twice at 2 L; with
  // a fixed thickness it grows as L^3: eight times. (Pressures, strains and the curl are scale-free with the default
  // thickness: only gravity depends on the size.)
  const double length = 10.0;
  const WiltingInput small = Strip(1.0, length, 8, 80);
  WiltingInput big = small;
  for (Eigen::Vector3d& x : big.points)
  {
    x *= 2.0;
  }
  const double t = length / 14.0;
  WiltingParameters p = StripParameters(1.5 * 981.0 * std::pow(length, 4) / (t * t * 0.05), 0.0);
  p.resolution = 20;
  p.anchorRadius = 0.75 * length / 20.0;
  const double sagSmall = -TipDisplacement(small, p)[2] / length;
  WiltingParameters bigP = p;
  bigP.anchorRadius *= 2.0;
  const double sagBig = -TipDisplacement(big, bigP)[2] / (2.0 * length);
  EXPECT_GT(sagSmall, 0.0);
  EXPECT_NEAR(sagBig / sagSmall, 2.0, 0.06);
  bigP.bladeThickness = t; // the small strip's default, now fixed: voxels at most t thick (CoarseVoxelError)
  bigP.resolution = 28;
  bigP.anchorRadius = 0.75 * 2.0 * length / 28.0;
  const double sagBigThin = -TipDisplacement(big, bigP)[2] / (2.0 * length);
  EXPECT_NEAR(sagBigThin / sagSmall, 8.0, 0.5);
}

TEST(WiltingPhysicalUnits, CurlArcDoesNotDependOnTheVoxelSize)
{
  // CurlStrain d in physical units: curvature d / t whatever the voxel edge (in lattice units it was d / h). A
  // weightless strip with only the curl takes that arc from its held base row (the petiole row has no curl): the
  // tip's drop (1 - cos(k s)) / k over the curled length s = L - h.
  const double length = 10.0, t = length / 14.0, d = 0.05, k = d / t;
  const WiltingInput in = Strip(1.0, length, 8, 80);
  for (const int r : { 14, 20, 28 })
  {
    WiltingParameters p = StripParameters(1e8, 0.0); // stiff enough to settle in the run (rate omega^2 / alpha)
    p.gravity = 0.0;
    p.curlStrain = d;
    p.resolution = r;
    p.anchorRadius = 0.75 * length / r;
    const double h = length / r, s = length - h;
    const Eigen::Vector3d tip = TipDisplacement(in, p);
    EXPECT_NEAR(-tip[2], (1.0 - std::cos(k * s)) / k, 0.04 * length) << "R " << r;
  }
}
