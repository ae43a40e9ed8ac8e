// SPDX-License-Identifier: GPL-3.0-or-later
// RigidRegistration (filters/comparison/core): Umeyama recovers a known similarity from exact pairs; ICP recovers a
// known rigid transform (and a rigid transform with scale) of a cloud sampled from a curved, asymmetric leaf surface;
// the landmark subset is reproducible from the seed; bad settings are refused. Symmetric mode: a flat leaf turned and
// scaled in its plane is recovered, Rigid + scale cannot collapse, a size mismatch does not make Rigid slide along the
// leaf, and a registration that fits worse is refused with a warning.
#include "RigidRegistration.h"

#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"

#include <plantmorph/RandomStream.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <vector>

namespace plantmorph
{
namespace
{
struct Surface
{
  std::vector<double> points;
  std::vector<std::int64_t> triangles;
};

/// The ginkgo blade bent into an asymmetric dome (no symmetry ICP could slide along).
Surface CurvedBlade()
{
  LeafMeshParameters settings;
  settings.resolution = 40;
  LeafGeometry leaf;
  EXPECT_EQ(
    BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, 5.0), settings, leaf), "");
  Surface s;
  for (const auto& p : leaf.blade.points)
  {
    const double z = 0.4 * std::sin(0.9 * p.x() + 0.3) * std::cos(0.5 * p.y()) + 0.08 * p.x() * p.x() + 0.05 * p.y();
    s.points.insert(s.points.end(), { p.x(), p.y(), z });
  }
  for (const auto& t : leaf.blade.triangles)
  {
    s.triangles.insert(s.triangles.end(), { t[0], t[1], t[2] });
  }
  return s;
}

std::vector<double> Sample(const Surface& s, std::size_t count, std::uint64_t seed)
{
  RandomStream random(seed);
  std::vector<double> out;
  const auto triangles = static_cast<std::int64_t>(s.triangles.size() / 3);
  for (std::size_t i = 0; i < count; ++i)
  {
    const auto t = static_cast<std::size_t>(random.Integer(0, triangles - 1));
    double u = random.Uniform();
    double v = random.Uniform();
    if (u + v > 1)
    {
      u = 1 - u;
      v = 1 - v;
    }
    for (int k = 0; k < 3; ++k)
    {
      const double a = s.points[3 * s.triangles[3 * t] + k];
      const double b = s.points[3 * s.triangles[3 * t + 1] + k];
      const double c = s.points[3 * s.triangles[3 * t + 2] + k];
      out.push_back(a + u * (b - a) + v * (c - a));
    }
  }
  return out;
}

Eigen::Matrix4d KnownTransform(double scale)
{
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(0.12, Eigen::Vector3d::UnitZ()) *
    Eigen::AngleAxisd(-0.08, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(0.06, Eigen::Vector3d::UnitY()))
                              .toRotationMatrix();
  m.topLeftCorner<3, 3>() = scale * r;
  m.topRightCorner<3, 1>() = Eigen::Vector3d(0.15, -0.2, 0.1);
  return m;
}

/// Moves reference samples by the inverse of `truth`, so that registering them back must find `truth`.
std::vector<double> MoveBy(const std::vector<double>& points, const Eigen::Matrix4d& truth)
{
  const Eigen::Matrix4d inverse = truth.inverse();
  double m[16];
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      m[4 * r + c] = inverse(r, c);
    }
  }
  std::vector<double> out(points.size());
  ApplyTransform(m, points.data(), out.data(), points.size() / 3);
  return out;
}

TEST(RigidRegistration, UmeyamaRecoversAKnownSimilarityFromExactPairs)
{
  RandomStream random(1);
  std::vector<double> source(300);
  for (double& x : source)
  {
    x = random.Uniform(-2, 2);
  }
  const Eigen::Matrix4d truth = KnownTransform(1.7);
  double m[16];
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      m[4 * r + c] = truth(r, c);
    }
  }
  std::vector<double> target(300);
  ApplyTransform(m, source.data(), target.data(), 100);
  double fitted[16];
  ASSERT_TRUE(FitSimilarity(source.data(), target.data(), 100, true, fitted));
  for (int i = 0; i < 16; ++i)
  {
    EXPECT_NEAR(fitted[i], m[i], 1e-12);
  }
  ASSERT_TRUE(FitSimilarity(source.data(), target.data(), 100, false, fitted));
  const Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> rigid(fitted);
  const double determinant = rigid.topLeftCorner<3, 3>().determinant();
  EXPECT_NEAR(determinant, 1.0, 1e-12); // rigid: no scale
  EXPECT_FALSE(FitSimilarity(source.data(), target.data(), 2, false, fitted));
}

TEST(RigidRegistration, IcpRecoversAKnownRigidTransform)
{
  const Surface surface = CurvedBlade();
  PointSurfaceDistance reference;
  ASSERT_EQ(reference.BuildSurface(
              surface.points.data(), surface.points.size() / 3, surface.triangles.data(), surface.triangles.size() / 3),
    "");
  const Eigen::Matrix4d truth = KnownTransform(1.0);
  const std::vector<double> measured = MoveBy(Sample(surface, 3000, 2), truth);
  RegistrationParameters settings;
  settings.maximumIterations = 500;
  settings.tolerance = 1e-10;
  const RegistrationResult result = RegisterPoints(measured.data(), 3000, reference, settings);
  ASSERT_EQ(result.error, "");
  EXPECT_TRUE(result.converged) << result.iterations << " iterations";
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      EXPECT_NEAR(result.matrix[4 * r + c], truth(r, c), 1e-5) << r << "," << c;
    }
  }
  EXPECT_NEAR(result.scale, 1.0, 1e-12);
  EXPECT_LT(result.rms, 1e-5);
}

TEST(RigidRegistration, IcpWithScaleRecoversUnitsAndPose)
{
  const Surface surface = CurvedBlade();
  PointSurfaceDistance reference;
  ASSERT_EQ(reference.BuildSurface(
              surface.points.data(), surface.points.size() / 3, surface.triangles.data(), surface.triangles.size() / 3),
    "");
  const Eigen::Matrix4d truth = KnownTransform(1.1);
  const std::vector<double> measured = MoveBy(Sample(surface, 3000, 3), truth);
  RegistrationParameters settings;
  settings.withScale = true;
  settings.maximumIterations = 500;
  settings.tolerance = 1e-10;
  const RegistrationResult result = RegisterPoints(measured.data(), 3000, reference, settings);
  ASSERT_EQ(result.error, "");
  EXPECT_NEAR(result.scale, 1.1, 1e-5);
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      EXPECT_NEAR(result.matrix[4 * r + c], truth(r, c), 1e-5) << r << "," << c;
    }
  }
  // Rigid mode cannot explain the scale: it leaves a residual.
  settings.withScale = false;
  const RegistrationResult rigid = RegisterPoints(measured.data(), 3000, reference, settings);
  EXPECT_GT(rigid.rms, 100 * result.rms);
}

TEST(RigidRegistration, LandmarkSubsetIsReproducible)
{
  const Surface surface = CurvedBlade();
  PointSurfaceDistance reference;
  ASSERT_EQ(reference.BuildSurface(
              surface.points.data(), surface.points.size() / 3, surface.triangles.data(), surface.triangles.size() / 3),
    "");
  const std::vector<double> measured = MoveBy(Sample(surface, 5000, 4), KnownTransform(1.0));
  RegistrationParameters settings;
  settings.maximumLandmarks = 500;
  settings.seed = 42;
  const RegistrationResult a = RegisterPoints(measured.data(), 5000, reference, settings);
  const RegistrationResult b = RegisterPoints(measured.data(), 5000, reference, settings);
  EXPECT_EQ(a.landmarks, 500u);
  for (int i = 0; i < 16; ++i)
  {
    EXPECT_EQ(a.matrix[i], b.matrix[i]);
  }
  settings.seed = 43;
  const RegistrationResult c = RegisterPoints(measured.data(), 5000, reference, settings);
  bool differs = false;
  for (int i = 0; i < 16; ++i)
  {
    differs = differs || a.matrix[i] != c.matrix[i];
  }
  EXPECT_TRUE(differs);
}

/// A flat blade (the ginkgo fan, z = 0): point-to-plane terms cannot see it turn or grow within its plane.
Surface FlatBlade()
{
  LeafMeshParameters settings;
  settings.resolution = 40;
  LeafGeometry leaf;
  EXPECT_EQ(
    BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Entire, 5.0), settings, leaf), "");
  Surface s;
  for (const auto& p : leaf.blade.points)
    s.points.insert(s.points.end(), { p.x(), p.y(), 0.0 });
  for (const auto& t : leaf.blade.triangles)
    s.triangles.insert(s.triangles.end(), { t[0], t[1], t[2] });
  return s;
}

RegistrationParameters Symmetric(const Surface& s, bool withScale)
{
  RegistrationParameters settings;
  settings.withScale = withScale;
  settings.maximumIterations = 300;
  settings.tolerance = 1e-9;
  settings.referencePoints = s.points.data();
  settings.referenceCount = s.points.size() / 3;
  return settings;
}

// Before symmetric ICP, a flat leaf turned 6 degrees in its plane and scaled 1.08 came back as the identity from Rigid
// + scale.
TEST(RigidRegistration, SymmetricIcpRecoversAnInPlaneTurnAndScaleOfAFlatLeaf)
{
  const Surface surface = FlatBlade();
  PointSurfaceDistance reference;
  ASSERT_EQ(reference.BuildSurface(
              surface.points.data(), surface.points.size() / 3, surface.triangles.data(), surface.triangles.size() / 3),
    "");
  Eigen::Matrix4d truth = Eigen::Matrix4d::Identity();
  truth.topLeftCorner<3, 3>() =
    1.08 * Eigen::AngleAxisd(6.0 * 3.14159265358979 / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  truth.topRightCorner<3, 1>() = Eigen::Vector3d(0.12, -0.05, 0.0);
  const std::vector<double> measured = MoveBy(Sample(surface, 6000, 5), truth);
  // The one-sided point-to-plane ICP cannot see it: it stays at the start (the old failure, kept as a witness).
  RegistrationParameters oneSided = Symmetric(surface, true);
  oneSided.referencePoints = nullptr;
  const RegistrationResult blind = RegisterPoints(measured.data(), 6000, reference, oneSided);
  ASSERT_EQ(blind.error, "");
  EXPECT_LT(std::abs(blind.matrix[1]), 1e-6); // no turn found
  const RegistrationResult result = RegisterPoints(measured.data(), 6000, reference, Symmetric(surface, true));
  ASSERT_EQ(result.error, "");
  EXPECT_FALSE(result.worse);
  const Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> m(result.matrix);
  // Point-to-point pairs of a sampled cloud are biased at the outline by about half the sample spacing (0.02 here,
  // on a blade 5 long): the scale comes out about 1 % high.
  EXPECT_NEAR(result.scale, 1.08, 0.015);
  const double angle = std::atan2(m(1, 0), m(0, 0)) * 180.0 / 3.14159265358979;
  EXPECT_NEAR(angle, 6.0, 0.3);
  EXPECT_NEAR(m(0, 3), 0.12, 0.05);
  EXPECT_NEAR(m(1, 3), -0.05, 0.05);
  EXPECT_LT(result.symmetricAfter, 0.5 * result.symmetricBefore);
}

// Before symmetric ICP, Rigid + scale shrank a measured cloud to a point (zeros on the matrix's diagonal, distances 0).
// A noisy scan of a slightly different leaf is the case: shrinking it lowers every point-to-plane distance.
TEST(RigidRegistration, SymmetricIcpWithScaleCannotCollapse)
{
  const Surface surface = CurvedBlade();
  PointSurfaceDistance reference;
  ASSERT_EQ(reference.BuildSurface(
              surface.points.data(), surface.points.size() / 3, surface.triangles.data(), surface.triangles.size() / 3),
    "");
  std::vector<double> measured = Sample(surface, 4000, 9);
  RandomStream random(11);
  for (double& x : measured)
    x = 0.93 * x + random.Uniform(-0.15, 0.15); // 7 % smaller, noise of 3 % of the length
  const RegistrationResult result = RegisterPoints(measured.data(), 4000, reference, Symmetric(surface, true));
  ASSERT_EQ(result.error, "");
  EXPECT_GT(result.scale, 0.95);
  EXPECT_LT(result.scale, 1.2);
  EXPECT_NEAR(result.scale, 1.0 / 0.93, 0.03);
  EXPECT_LE(result.symmetricAfter, result.symmetricBefore);
}

// Before symmetric ICP, Rigid ICP with a few per cent size mismatch slid a curled blade along itself and fitted worse
// than no registration. Symmetric pairs keep it centred, and the guard never returns a worse fit.
TEST(RigidRegistration, RigidIcpWithASizeMismatchNeverFitsWorse)
{
  const Surface surface = CurvedBlade();
  PointSurfaceDistance reference;
  ASSERT_EQ(reference.BuildSurface(
              surface.points.data(), surface.points.size() / 3, surface.triangles.data(), surface.triangles.size() / 3),
    "");
  for (double mismatch : { 0.9, 1.05 })
  {
    std::vector<double> measured = Sample(surface, 3000, 4);
    for (double& x : measured)
      x *= mismatch;
    const RegistrationResult result = RegisterPoints(measured.data(), 3000, reference, Symmetric(surface, false));
    ASSERT_EQ(result.error, "");
    EXPECT_LE(result.symmetricAfter, result.symmetricBefore) << mismatch;
    EXPECT_NEAR(result.scale, 1.0, 1e-9);
    // No sliding along the leaf: the registered cloud's centroid lands on the true cloud's (the leaf's own), within
    // 5 % of the blade's length of 5 (3.4 % at a 10 % mismatch; the shipped scan used to slide 4.9 cm along its leaf).
    const std::vector<double> truth = Sample(surface, 3000, 4);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(), after = Eigen::Vector3d::Zero();
    std::vector<double> moved(measured.size());
    ApplyTransform(result.matrix, measured.data(), moved.data(), 3000);
    for (std::size_t i = 0; i < measured.size(); i += 3)
    {
      centre += Eigen::Vector3d(truth[i], truth[i + 1], truth[i + 2]);
      after += Eigen::Vector3d(moved[i], moved[i + 1], moved[i + 2]);
    }
    EXPECT_LT((after - centre).norm() / 3000.0, 0.25) << mismatch;
  }
}

// The guard: a registration that would fit worse is refused with a warning and the identity. One iteration of a
// rigid fit whose pairs are all rejected but three far ones cannot do better than no registration at all.
TEST(RigidRegistration, AWorseRegistrationIsRefusedWithAWarning)
{
  const Surface surface = CurvedBlade();
  PointSurfaceDistance reference;
  ASSERT_EQ(reference.BuildSurface(
              surface.points.data(), surface.points.size() / 3, surface.triangles.data(), surface.triangles.size() / 3),
    "");
  // Exactly on the reference except three stray points far above it: any move that follows the strays is worse.
  std::vector<double> measured = Sample(surface, 2000, 6);
  for (int k = 0; k < 3; ++k)
  {
    measured[3 * k] = 10.0 * k;
    measured[3 * k + 1] = 5.0;
    measured[3 * k + 2] = 30.0 + 7.0 * k;
  }
  RegistrationParameters settings = Symmetric(surface, true);
  settings.maximumIterations = 1;
  settings.rejectDistance = 1e6;
  const RegistrationResult result = RegisterPoints(measured.data(), 2000, reference, settings);
  ASSERT_EQ(result.error, "");
  ASSERT_TRUE(result.worse) << result.symmetricAfter << " vs " << result.symmetricBefore;
  EXPECT_GT(result.symmetricAfter, result.symmetricBefore);
  EXPECT_NE(result.warning.find("made the fit worse"), std::string::npos);
  for (int i = 0; i < 16; ++i)
    EXPECT_EQ(result.matrix[i], (i % 5 == 0) ? 1.0 : 0.0);
  EXPECT_EQ(result.scale, 1.0);
}

TEST(RigidRegistration, BadSettings)
{
  RegistrationParameters settings;
  settings.maximumIterations = 0;
  EXPECT_NE(ValidateRegistrationParameters(settings).find("RegistrationIterations"), std::string::npos);
  settings = RegistrationParameters();
  settings.tolerance = 0;
  EXPECT_NE(ValidateRegistrationParameters(settings).find("RegistrationTolerance"), std::string::npos);
  settings = RegistrationParameters();
  PointSurfaceDistance empty;
  const std::vector<double> points = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
  EXPECT_NE(RegisterPoints(points.data(), 3, empty, settings).error, "");
  // Everything rejected: a clear error, not a crash.
  PointSurfaceDistance far;
  const std::vector<double> cloud = { 10, 10, 10, 11, 10, 10, 10, 11, 10 };
  ASSERT_EQ(far.BuildCloud(cloud.data(), 3), "");
  settings.rejectDistance = 0.5;
  const std::vector<double> spread = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 0, 1, 0, 1, 0, 1, 1, 1, 1, 1 };
  EXPECT_NE(RegisterPoints(spread.data(), 8, far, settings).error.find("landmark pairs"), std::string::npos);
}

/// The rotation angle of a row-major 4x4 matrix's upper-left block (radians).
double RotationAngle(const double matrix[16])
{
  const Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> m(matrix);
  return Eigen::AngleAxisd(Eigen::Matrix3d(m.topLeftCorner<3, 3>())).angle();
}

// The count and the flag tell what happened: RegistrationIterations = 1 used to report 2 iterations and converged
// with 0.0011 of a 0.05 rad turn recovered, the default 100 reported 101 (the symmetric stage's and the polish's
// counts added, their flags or-ed). Now the count never exceeds the budget and converged means the transform
// returned met the tolerance, so a converged result has recovered the turn.
TEST(RigidRegistration, IterationsStayWithinTheBudgetAndConvergedMeansRecovered)
{
  const Surface surface = CurvedBlade();
  PointSurfaceDistance reference;
  ASSERT_EQ(reference.BuildSurface(
              surface.points.data(), surface.points.size() / 3, surface.triangles.data(), surface.triangles.size() / 3),
    "");
  Eigen::Matrix4d truth = Eigen::Matrix4d::Identity();
  truth.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const std::vector<double> measured = MoveBy(Sample(surface, 3000, 21), truth);
  for (const int budget : { 1, 2, 5, 100, 300 })
  {
    RegistrationParameters settings = Symmetric(surface, false);
    settings.maximumIterations = budget;
    settings.tolerance = 1e-7;
    const RegistrationResult result = RegisterPoints(measured.data(), 3000, reference, settings);
    ASSERT_EQ(result.error, "");
    EXPECT_GE(result.iterations, 1) << budget;
    EXPECT_LE(result.iterations, budget);
    const double angle = RotationAngle(result.matrix);
    if (result.converged)
    {
      EXPECT_NEAR(angle, 0.05, 1e-3) << budget << " iterations: converged but " << angle << " rad recovered";
    }
    if (budget == 1)
    {
      EXPECT_FALSE(result.converged) << "one iteration recovered " << angle << " rad of 0.05";
    }
  }
  // One-sided (no reference points) likewise.
  RegistrationParameters oneSided;
  oneSided.maximumIterations = 1;
  const RegistrationResult one = RegisterPoints(measured.data(), 3000, reference, oneSided);
  ASSERT_EQ(one.error, "");
  EXPECT_EQ(one.iterations, 1);
}

// Measured points that cannot determine a transform (on a line, 3 points, 500 copies of one point) keep the
// identity with a warning saying why, converged false: any rotation about the line or point fits them as well.
TEST(RigidRegistration, UndeterminedMeasuredCloudsKeepTheIdentityWithAWarning)
{
  const Surface surface = CurvedBlade();
  PointSurfaceDistance reference;
  ASSERT_EQ(reference.BuildSurface(
              surface.points.data(), surface.points.size() / 3, surface.triangles.data(), surface.triangles.size() / 3),
    "");
  std::vector<double> line, identical, three = { 0.1, 0.2, 0.0, 1.0, 0.3, 0.1, 0.5, 1.2, 0.2 };
  for (int i = 0; i < 200; ++i)
    line.insert(line.end(), { 0.01 * i, 0.02 * i + 0.5, 0.1 });
  for (int i = 0; i < 500; ++i)
    identical.insert(identical.end(), { 0.3, 0.4, 0.2 });
  const struct
  {
    const std::vector<double>& points;
    const char* says;
  } cases[] = { { line, "lie on one line" }, { three, "only 3 distinct points" }, { identical, "the same point" } };
  for (const auto& c : cases)
  {
    for (const bool symmetric : { false, true })
    {
      RegistrationParameters settings = symmetric ? Symmetric(surface, false) : RegistrationParameters();
      const RegistrationResult result = RegisterPoints(c.points.data(), c.points.size() / 3, reference, settings);
      ASSERT_EQ(result.error, "") << c.says;
      EXPECT_NE(result.warning.find(c.says), std::string::npos) << result.warning;
      EXPECT_NE(result.warning.find("not determined"), std::string::npos) << result.warning;
      EXPECT_FALSE(result.converged) << c.says;
      EXPECT_EQ(result.iterations, 0) << c.says;
      for (int i = 0; i < 16; ++i)
        EXPECT_EQ(result.matrix[i], (i % 5 == 0) ? 1.0 : 0.0) << c.says;
    }
  }
  EXPECT_EQ(UndeterminedRegistration(surface.points.data(), surface.points.size() / 3, true), "");
}

} // namespace
} // namespace plantmorph
