// SPDX-License-Identifier: GPL-3.0-or-later
// LeafFit (fit/): synthetic scans of the project's own leaves, whose truth is known exactly. A LeafOutlineSource
// blade (Model A, B or C) is curled and bent with LeafCurl, sampled uniformly by area, given noise along its normal
// and 1 % outliers in its bounding box; the fit must give the true area and length within 1 %, a surface closer to
// the true one than the noise, and an outline within 2 % of the length (Hausdorff). Bad input gives an error.
#include "LeafFit.h"
#include "LeafPlant.h"

#include "BSplineLeaf.h"
#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"
#include "LeafCurl.h"
#include "PointSurfaceDistance.h"
#include "ReversedLoops.h"
#include "SpaceCurveLeaf.h"
#include "SpaceCurvePresets.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <thread>
#include <vector>

namespace plantmorph
{
namespace
{
/// A leaf's traits bit for bit (NaN, such as HiddenMargin of a leaf fitted without a scanner's view, equal to
/// itself): to say two fits gave the same traits.
std::vector<std::uint64_t> TraitBits(const LeafTraits& traits)
{
  const std::vector<double> values = TraitValues(traits);
  std::vector<std::uint64_t> bits(values.size());
  std::memcpy(bits.data(), values.data(), values.size() * sizeof(double));
  return bits;
}

using plantmorph::testing::ReversedOnTwoThreads;

/// A true leaf: its 3-D mesh, margins and midvein (point ids, base to apex).
struct TrueLeaf
{
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> leftMargin, rightMargin, midvein;

  double Area() const
  {
    double area = 0.0;
    for (const auto& t : triangles)
      area += 0.5 * (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]).norm();
    return area;
  }
  double MidveinLength() const
  {
    double length = 0.0;
    for (std::size_t i = 1; i < midvein.size(); ++i)
      length += (points[midvein[i]] - points[midvein[i - 1]]).norm();
    return length;
  }
};

enum class Model
{
  EllipticC, // Model C, elliptic preset
  OvateA,    // Model A, "Entire" preset (ovate: widest towards the base)
  BroadB     // Model B, paper 002 Fig. 1 (the space curve: a flat, broad leaf)
};

/// The leaf of `model`, `length` long, curled (LeafCurl's degrees), then rotated and moved by `pose`.
TrueLeaf MakeLeaf(Model model, double length, double longitudinal, double transverse,
  const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity())
{
  LeafMeshParameters settings;
  settings.resolution = 160;
  LeafGeometry leaf;
  std::string error;
  if (model == Model::EllipticC)
    error = BuildBSplineLeaf(MakeBSplinePreset(BSplinePreset::Elliptic, length, 0.45 * length, 9), settings, leaf);
  else if (model == Model::BroadB)
  {
    SpaceCurveMeshParameters curveSettings;
    curveSettings.resolution = settings.resolution;
    error = BuildSpaceCurveLeaf(MakeSpaceCurvePreset(SpaceCurvePreset::Figure1, length), curveSettings, leaf);
    // The preset's length is a half-margin's arc length: scale the leaf so its midvein is `length` long.
    double midvein = 0.0;
    for (std::size_t i = 1; i < leaf.midvein.size(); ++i)
      midvein += (leaf.blade.points[leaf.midvein[i]] - leaf.blade.points[leaf.midvein[i - 1]]).norm();
    for (auto& p : leaf.blade.points)
      p *= length / midvein;
    for (double& z : leaf.z)
      z *= length / midvein;
  }
  else
    error =
      BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Entire, length), settings, leaf);
  EXPECT_EQ(error, "");
  const std::size_t n = leaf.blade.points.size();
  std::vector<double> xyz, uv;
  for (std::size_t i = 0; i < n; ++i)
  {
    xyz.insert(xyz.end(), { leaf.blade.points[i].x(), leaf.blade.points[i].y(), leaf.z.empty() ? 0.0 : leaf.z[i] });
    uv.insert(uv.end(), { leaf.blade.uv[i].x(), leaf.blade.uv[i].y() });
  }
  TrueLeaf truth;
  truth.points.resize(n);
  LeafCurl curl;
  LeafCurlParameters parameters;
  parameters.longitudinalAngle = longitudinal;
  parameters.transverseAngle = transverse;
  EXPECT_EQ(curl.Setup(parameters, n, xyz.data(), uv.data()), "");
  for (std::size_t i = 0; i < n; ++i)
  {
    double out[3];
    curl.Map(i, &xyz[3 * i], out);
    truth.points[i] = pose * Eigen::Vector3d(out[0], out[1], out[2]);
  }
  truth.triangles = leaf.blade.triangles;
  truth.leftMargin = leaf.leftMargin;
  truth.rightMargin = leaf.rightMargin;
  truth.midvein = leaf.midvein;
  return truth;
}

/// `count` points uniform by area on the leaf, Gaussian noise `sigma` along the face normal, and `outliers`
/// points uniform in the leaf's bounding box grown by 20 %. Deterministic (fixed seed).
std::vector<Eigen::Vector3d> Scan(const TrueLeaf& leaf, int count, double sigma, int outliers, unsigned seed = 7)
{
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<double> cdf;
  double total = 0.0;
  for (const auto& t : leaf.triangles)
  {
    total += 0.5 * (leaf.points[t[1]] - leaf.points[t[0]]).cross(leaf.points[t[2]] - leaf.points[t[0]]).norm();
    cdf.push_back(total);
  }
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i)
  {
    const std::size_t k = std::lower_bound(cdf.begin(), cdf.end(), uniform(random) * total) - cdf.begin();
    const auto& t = leaf.triangles[std::min(k, cdf.size() - 1)];
    double a = uniform(random), b = uniform(random);
    if (a + b > 1.0)
    {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    const Eigen::Vector3d &p0 = leaf.points[t[0]], &p1 = leaf.points[t[1]], &p2 = leaf.points[t[2]];
    const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0).normalized();
    points.push_back(p0 + a * (p1 - p0) + b * (p2 - p0) + sigma * gauss(random) * normal);
  }
  Eigen::Vector3d lo = leaf.points.front(), hi = lo;
  for (const auto& p : leaf.points)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d pad = 0.2 * (hi - lo) + Eigen::Vector3d::Constant(0.05 * (hi - lo).norm());
  for (int i = 0; i < outliers; ++i)
  {
    const Eigen::Vector3d u(uniform(random), uniform(random), uniform(random));
    points.push_back(lo - pad + u.cwiseProduct(hi - lo + 2.0 * pad));
  }
  return points;
}

/// RMS distance of the fitted blade's vertices to the true surface.
double SurfaceRMS(const LeafFitResult& fit, const TrueLeaf& truth)
{
  std::vector<double> xyz;
  for (const auto& p : truth.points)
    xyz.insert(xyz.end(), { p.x(), p.y(), p.z() });
  std::vector<std::int64_t> tri;
  for (const auto& t : truth.triangles)
    tri.insert(tri.end(), { t[0], t[1], t[2] });
  PointSurfaceDistance distance;
  EXPECT_EQ(distance.BuildSurface(xyz.data(), truth.points.size(), tri.data(), truth.triangles.size()), "");
  double sum = 0.0;
  for (const auto& p : fit.points)
  {
    const double q[3] = { p.x(), p.y(), p.z() };
    const double d = distance.Query(q).distance;
    sum += d * d;
  }
  return std::sqrt(sum / fit.points.size());
}

double PointToPolyline(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& line)
{
  double best = 1e300;
  for (std::size_t i = 1; i < line.size(); ++i)
  {
    const Eigen::Vector3d a = line[i - 1], ab = line[i] - a;
    const double f = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
    best = std::min(best, (p - a - f * ab).norm());
  }
  return best;
}

/// Hausdorff distance between two closed outlines (each the right margin then the left margin reversed).
double OutlineHausdorff(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b)
{
  double h = 0.0;
  for (const auto& p : a)
    h = std::max(h, PointToPolyline(p, b));
  for (const auto& p : b)
    h = std::max(h, PointToPolyline(p, a));
  return h;
}

template <typename Points>
std::vector<Eigen::Vector3d> Loop(const Points& points, const std::vector<int>& right, const std::vector<int>& left)
{
  std::vector<Eigen::Vector3d> loop;
  for (int id : right)
    loop.push_back(points[id]);
  for (auto it = left.rbegin(); it != left.rend(); ++it)
    loop.push_back(points[*it]);
  return loop;
}

struct Case
{
  Model model;
  double longitudinal, transverse, noise; // noise as a fraction of the length
  int count;
  double lengthTolerance = 0.01;
  double hole = 0.0; // radius of a hole cut from the scan around the blade's centre (fraction of the length)
};

void ExpectAccurate(const Case& c, const Eigen::Isometry3d& pose = Eigen::Isometry3d::Identity())
{
  const double length = 100.0; // millimetres
  const TrueLeaf truth = MakeLeaf(c.model, length, c.longitudinal, c.transverse, pose);
  const double sigma = c.noise * length;
  const int outliers = c.count / 100;
  std::vector<Eigen::Vector3d> scan = Scan(truth, c.count, sigma, outliers);
  int kept = c.count;
  if (c.hole > 0.0)
  {
    // A hole in the scan (a missing patch, as scanners leave behind glare or occlusion), outliers kept at the end.
    const Eigen::Vector3d centre = truth.points[truth.midvein[truth.midvein.size() / 2]] +
      0.25 *
        (truth.points[truth.rightMargin[truth.rightMargin.size() / 2]] -
          truth.points[truth.midvein[truth.midvein.size() / 2]]);
    std::vector<Eigen::Vector3d> holed;
    for (int i = 0; i < c.count; ++i)
      if ((scan[i] - centre).norm() > c.hole * length)
        holed.push_back(scan[i]);
    kept = static_cast<int>(holed.size());
    holed.insert(holed.end(), scan.begin() + c.count, scan.end());
    scan = holed;
    EXPECT_LT(kept, c.count * 0.97);
  }
  LeafFitParameters options;
  options.up = pose.linear() * Eigen::Vector3d::UnitZ();
  options.basePoint = truth.points[truth.midvein.front()];
  const LeafFitResult fit = FitLeaf(scan, options);
  ASSERT_EQ(fit.error, "");
  const double area = truth.Area(), trueLength = truth.MidveinLength();
  EXPECT_NEAR(fit.traits.area / area, 1.0, 0.01) << "area " << fit.traits.area << " truth " << area;
  EXPECT_NEAR(fit.traits.length / trueLength, 1.0, c.lengthTolerance)
    << "length " << fit.traits.length << " truth " << trueLength << " base off by "
    << (fit.points[fit.midvein.front()] - truth.points[truth.midvein.front()]).norm() << " apex off by "
    << (fit.points[fit.midvein.back()] - truth.points[truth.midvein.back()]).norm();
  EXPECT_LT(SurfaceRMS(fit, truth), sigma) << "noise " << sigma;
  const double hausdorff = OutlineHausdorff(
    Loop(fit.points, fit.rightMargin, fit.leftMargin), Loop(truth.points, truth.rightMargin, truth.leftMargin));
  EXPECT_LT(hausdorff, 0.02 * trueLength);
  // The scan's own statistics: FitRMS is the noise; the outliers are not inliers; the blade is covered.
  EXPECT_NEAR(fit.traits.fitRMS / sigma, 1.0, 0.15);
  int outlierInliers = 0;
  for (int i = kept; i < kept + outliers; ++i)
    outlierInliers += fit.inlier[i];
  EXPECT_LE(outlierInliers, outliers / 10 + 1);
  EXPECT_GE(fit.traits.inliers, 0.97 * kept);
  // The hole is bridged, and Coverage says how much of the blade is: the hole's share of the area is uncovered.
  EXPECT_GT(fit.traits.coverage, c.hole > 0.0 ? 0.9 : 0.97);
  if (c.hole > 0.0)
  {
    EXPECT_LT(fit.traits.coverage, 0.99);
  }
  EXPECT_EQ(fit.traits.baseFrom, 1);
  EXPECT_LT((fit.points[fit.midvein.front()] - truth.points[truth.midvein.front()]).norm(), 0.02 * trueLength);
}

TEST(LeafFit, FlatEllipticLeafIsExact)
{
  ExpectAccurate({ Model::EllipticC, 0.0, 0.0, 0.002, 10000 });
}

TEST(LeafFit, FlatOvateLeafWithMoreNoise)
{
  // Length within 1.1 %: the acute apex's random samples end about 1 mm short of it (-1.05 %); a surface that
  // followed the noise's bumps added 0.09 % of midvein back (-0.96 %) until the penalty was raised for the noise.
  ExpectAccurate({ Model::OvateA, 0.0, 0.0, 0.005, 10000, 0.011 });
}

TEST(LeafFit, RolledLeaf)
{
  ExpectAccurate({ Model::EllipticC, 70.0, 0.0, 0.003, 12000 });
}

TEST(LeafFit, BentLeaf)
{
  // Bent 50 degrees at both ends: its acute apex was placed 1.4 mm beyond the true one (1.4 % long) until the tips
  // were estimated from their samples' expected spacing (TipBeyond in filters/leaf_fit/core/LeafFitIntrinsic.cpp).
  ExpectAccurate({ Model::OvateA, 0.0, 50.0, 0.003, 12000 });
}

TEST(LeafFit, RolledBentTiltedLeaf)
{
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 0.5).normalized()));
  pose.pretranslate(Eigen::Vector3d(250.0, -40.0, 13.0));
  ExpectAccurate({ Model::EllipticC, 40.0, 30.0, 0.002, 15000 }, pose);
}

TEST(LeafFit, RolledLeafWithAHole)
{
  ExpectAccurate({ Model::EllipticC, 50.0, 0.0, 0.003, 12000, 0.01, 0.06 });
}

TEST(LeafFit, FlatSpaceCurveLeaf)
{
  // Model B (paper 002 Fig. 1): a broad leaf whose margin meets the midvein at a blunt base.
  ExpectAccurate({ Model::BroadB, 0.0, 0.0, 0.003, 12000 });
}

TEST(LeafFit, RolledBentSpaceCurveLeaf)
{
  ExpectAccurate({ Model::BroadB, 40.0, 30.0, 0.003, 15000 });
}

TEST(LeafFit, ADenseLeafIsFittedOnASampleAsAccurately)
{
  // 3 x 10^5 points, three times MaxFitPoints: the fit runs on a sample and every other point follows it (the
  // inlier, FitRMS and outlier checks count all of them).
  ASSERT_GT(300000u, 2 * MaxFitPoints);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 0.5).normalized()));
  ExpectAccurate({ Model::EllipticC, 40.0, 30.0, 0.002, 300000 }, pose);
}

TEST(LeafFit, ADenseLeafThreadedIsTheSerialFitAndEveryPointHasItsOutputs)
{
  const TrueLeaf truth = MakeLeaf(Model::OvateA, 80.0, 30.0, 0.0);
  const std::vector<Eigen::Vector3d> scan = Scan(truth, 2 * static_cast<int>(MaxFitPoints), 0.1, 2000, 5);
  const ParallelFor reversed = ReversedOnTwoThreads();
  const LeafFitResult serial = FitLeaf(scan, LeafFitParameters());
  const LeafFitResult threaded = FitLeaf(scan, LeafFitParameters(), reversed);
  ASSERT_EQ(serial.error, "");
  ASSERT_EQ(threaded.error, "");
  EXPECT_EQ(TraitBits(threaded.traits), TraitBits(serial.traits));
  EXPECT_EQ(threaded.points, serial.points);
  EXPECT_EQ(threaded.inlier, serial.inlier);
  int inliers = 0, placed = 0;
  for (std::size_t i = 0; i < scan.size(); ++i)
  {
    ASSERT_EQ(threaded.fitDistance[i], serial.fitDistance[i]) << "point " << i;
    ASSERT_TRUE(std::isfinite(serial.fitDistance[i])) << "point " << i;
    placed += std::isfinite(serial.intrinsic[i].x()) ? 1 : 0;
    inliers += serial.inlier[i];
  }
  // Every blade point (the sample's and the others) has its (t, s) and is an inlier, the outliers are not.
  EXPECT_GE(placed, 0.995 * (scan.size() - 2000)) << placed;
  EXPECT_GE(inliers, 0.99 * (scan.size() - 2000)) << inliers;
  EXPECT_LE(inliers, scan.size() - 2000 + 200) << inliers;
  EXPECT_EQ(static_cast<double>(inliers), serial.traits.inliers);
  // The fit is the truth's: FitRMS the noise, the area within 1 %.
  EXPECT_NEAR(serial.traits.fitRMS / 0.1, 1.0, 0.15);
  EXPECT_NEAR(serial.traits.area / truth.Area(), 1.0, 0.01);
}

TEST(LeafFit, SmallScansStayWithinTheirDocumentedRange)
{
  // The verified point-count range (docs/methods/leaf-fit.md, "Limits, measured"): each tip is placed from its few
  // nearest samples, so its error is a fraction of the point spacing, which grows as 1 / sqrt(points). Curled leaves
  // of all three models, 0.2 % noise, 1 % outliers, three scans each: from 5000 points area and length within 1 %;
  // at 1000 points within 5 % (length) and 2 % (area).
  for (Model model : { Model::EllipticC, Model::OvateA, Model::BroadB })
  {
    const TrueLeaf truth = MakeLeaf(model, 100.0, 30.0, 20.0);
    for (int count : { 1000, 5000 })
      for (unsigned seed = 1; seed <= 3; ++seed)
      {
        LeafFitParameters options;
        options.basePoint = truth.points[truth.midvein.front()];
        const LeafFitResult fit = FitLeaf(Scan(truth, count, 0.2, count / 100, seed), options);
        ASSERT_EQ(fit.error, "");
        const double area = fit.traits.area / truth.Area() - 1.0;
        const double length = fit.traits.length / truth.MidveinLength() - 1.0;
        // 1.1 % at 5000: the worst of the nine scans is 1.003 % since the blade follows the points' own outline.
        EXPECT_LT(std::abs(area), count >= 5000 ? 0.011 : 0.02)
          << "model " << static_cast<int>(model) << ", " << count << " points, seed " << seed;
        EXPECT_LT(std::abs(length), count >= 5000 ? 0.01 : 0.05)
          << "model " << static_cast<int>(model) << ", " << count << " points, seed " << seed;
      }
  }
}

TEST(LeafFit, TraitsOfAFlatLeafHaveTheirClosedForms)
{
  const TrueLeaf truth = MakeLeaf(Model::EllipticC, 100.0, 0.0, 0.0);
  const LeafFitResult fit = FitLeaf(Scan(truth, 8000, 0.1, 0), LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  // Flat, in the XY plane, up +Z: no bending, no rolling, horizontal, every projection the area itself.
  EXPECT_LT(fit.traits.bending, 1.0);
  EXPECT_LT(std::abs(fit.traits.rolling), 1.0);
  EXPECT_LT(fit.traits.inclination, 1.0);
  EXPECT_NEAR(fit.traits.projectedArea / fit.traits.area, 1.0, 1e-3);
  EXPECT_NEAR(fit.traits.horizontalArea / fit.traits.area, 1.0, 1e-3);
  EXPECT_NEAR(fit.traits.width / 45.0, 1.0, 0.02);
  EXPECT_NEAR(fit.traits.aspectRatio, fit.traits.length / fit.traits.width, 1e-12);
  // The midvein runs along +Y or -Y (the elliptic leaf is symmetric: either end may be taken as the base), and the
  // fit says that its base is a guess (BaseFrom 3, with a warning) rather than pick an end silently.
  EXPECT_LT(std::min(std::abs(fit.traits.azimuth - 90.0), std::abs(fit.traits.azimuth - 270.0)), 1.0);
  EXPECT_EQ(fit.traits.baseFrom, 3);
  const std::vector<std::string> warnings = CheckFittedLeaf(fit, LeafFitParameters().resolution);
  EXPECT_EQ(std::count_if(warnings.begin(), warnings.end(),
              [](const std::string& w) { return w.find("same at both ends") != std::string::npos; }),
    1);
  // The data contract: LeafUV in range, margins at +-0.5, the midvein at 0, one Region per point.
  ASSERT_EQ(fit.leafUV.size(), fit.points.size());
  ASSERT_EQ(fit.region.size(), fit.points.size());
  for (const auto& uv : fit.leafUV)
  {
    EXPECT_LE(std::abs(uv.x()), 0.5);
    EXPECT_GE(uv.y(), 0.0);
    EXPECT_LE(uv.y(), 1.0);
  }
  for (std::size_t i = 1; i + 1 < fit.rightMargin.size(); ++i)
    EXPECT_EQ(fit.leafUV[fit.rightMargin[i]].x(), 0.5);
  for (int id : fit.midvein)
    EXPECT_EQ(fit.leafUV[id].x(), 0.0);
}

TEST(LeafFit, RollingAndBendingHaveTheirSigns)
{
  const TrueLeaf rolled = MakeLeaf(Model::EllipticC, 100.0, 60.0, 0.0);
  const LeafFitResult up = FitLeaf(Scan(rolled, 8000, 0.1, 0), LeafFitParameters());
  ASSERT_EQ(up.error, "");
  EXPECT_GT(up.traits.rolling, 20.0);
  const TrueLeaf bent = MakeLeaf(Model::EllipticC, 100.0, 0.0, 60.0);
  const LeafFitResult fit = FitLeaf(Scan(bent, 8000, 0.1, 0), LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  // Both ends turn by 60 degrees: the tangents at base and apex differ by about 120 degrees (less: 2 % in).
  EXPECT_NEAR(fit.traits.bending, 120.0, 10.0);
}

TEST(LeafFit, OvateLeafTakesItsWiderHalfAsItsBaseAndSaysSo)
{
  // Without a petiole or a hint only the wider half tells the ends of an ovate blade apart, and an obovate blade
  // is the same outline turned round: the base is taken at the wider half, and the fit says that is a guess.
  const TrueLeaf truth = MakeLeaf(Model::OvateA, 100.0, 0.0, 0.0);
  const LeafFitResult fit = FitLeaf(Scan(truth, 8000, 0.1, 0), LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  EXPECT_LT((fit.points[fit.midvein.front()] - truth.points[truth.midvein.front()]).norm(), 3.0);
  EXPECT_EQ(fit.traits.baseFrom, 3);
  EXPECT_EQ(fit.baseGuess, BaseGuess::WiderHalf);
  const std::vector<std::string> warnings = CheckFittedLeaf(fit, LeafFitParameters().resolution);
  EXPECT_EQ(std::count_if(warnings.begin(), warnings.end(),
              [](const std::string& w) { return w.find("wider half") != std::string::npos; }),
    1);
}

TEST(LeafFit, ModelCControlPointsRebuildTheLeaf)
{
  const TrueLeaf truth = MakeLeaf(Model::OvateA, 100.0, 0.0, 0.0);
  const LeafFitResult fit = FitLeaf(Scan(truth, 10000, 0.2, 100), LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  BSplineLeafParameters model{ fit.modelMidvein, fit.modelLeftMargin, fit.modelRightMargin };
  LeafMeshParameters settings;
  settings.resolution = 60;
  LeafGeometry rebuilt;
  ASSERT_EQ(BuildBSplineLeaf(model, settings, rebuilt), "");
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i < rebuilt.blade.points.size(); ++i)
    points.emplace_back(
      rebuilt.blade.points[i].x(), rebuilt.blade.points[i].y(), rebuilt.z.empty() ? 0.0 : rebuilt.z[i]);
  double area = 0.0;
  for (const auto& t : rebuilt.blade.triangles)
    area += 0.5 * (points[t[1]] - points[t[0]]).cross(points[t[2]] - points[t[0]]).norm();
  EXPECT_NEAR(area / fit.traits.area, 1.0, 0.01);
  EXPECT_LT(OutlineHausdorff(
              Loop(points, rebuilt.rightMargin, rebuilt.leftMargin), Loop(fit.points, fit.rightMargin, fit.leftMargin)),
    0.01 * fit.traits.length);
}

TEST(LeafFit, LeavesFitInParallelAsOneByOne)
{
  std::vector<std::vector<Eigen::Vector3d>> leaves;
  leaves.push_back(Scan(MakeLeaf(Model::EllipticC, 80.0, 30.0, 0.0), 3000, 0.1, 30, 1));
  leaves.push_back(Scan(MakeLeaf(Model::OvateA, 60.0, 0.0, 20.0), 4000, 0.1, 40, 2));
  leaves.push_back(Scan(MakeLeaf(Model::EllipticC, 50.0, 0.0, 0.0), 2500, 0.05, 0, 3));
  const ParallelFor threads = [](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    std::vector<std::thread> pool;
    for (std::size_t i = 0; i < count; ++i)
      pool.emplace_back(body, i, i + 1);
    for (auto& t : pool)
      t.join();
  };
  const auto parallel = FitLeaves(leaves, LeafFitParameters(), threads);
  ASSERT_EQ(parallel.size(), 3u);
  for (std::size_t i = 0; i < leaves.size(); ++i)
  {
    const LeafFitResult serial = FitLeaf(leaves[i], LeafFitParameters());
    ASSERT_EQ(parallel[i].error, "");
    EXPECT_EQ(TraitBits(parallel[i].traits), TraitBits(serial.traits));
    EXPECT_EQ(parallel[i].points, serial.points);
  }
  EXPECT_NE(parallel[0].traits.area, parallel[1].traits.area);
}

TEST(LeafFit, OneLeafThreadedInsideIsTheSerialFit)
{
  // 2*10^4 points: several blocks of the per-point loops, handed out in reverse order on two threads.
  const std::vector<Eigen::Vector3d> scan = Scan(MakeLeaf(Model::EllipticC, 80.0, 30.0, 0.0), 20000, 0.1, 200, 4);
  const ParallelFor reversed = ReversedOnTwoThreads();
  const LeafFitResult serial = FitLeaf(scan, LeafFitParameters());
  const LeafFitResult threaded = FitLeaves({ scan }, LeafFitParameters(), reversed).front();
  ASSERT_EQ(serial.error, "");
  ASSERT_EQ(threaded.error, "");
  EXPECT_EQ(TraitBits(threaded.traits), TraitBits(serial.traits));
  EXPECT_EQ(threaded.points, serial.points);
  EXPECT_EQ(threaded.support, serial.support);
  EXPECT_EQ(threaded.inlier, serial.inlier);
  EXPECT_EQ(threaded.petiole, serial.petiole);
  for (std::size_t i = 0; i < scan.size(); ++i)
    ASSERT_EQ(threaded.fitDistance[i], serial.fitDistance[i]) << "point " << i;
}

void ExpectError(const std::vector<Eigen::Vector3d>& points, const std::string& words,
  const LeafFitParameters& options = LeafFitParameters())
{
  const LeafFitResult fit = FitLeaf(points, options);
  EXPECT_NE(fit.error.find(words), std::string::npos) << "error: '" << fit.error << "'";
  EXPECT_TRUE(fit.points.empty());
  EXPECT_TRUE(fit.triangles.empty());
  EXPECT_TRUE(fit.fitDistance.empty());
  EXPECT_EQ(fit.traits.area, 0.0);
}

TEST(LeafFit, BadInputGivesAClearError)
{
  const std::vector<Eigen::Vector3d> leaf = Scan(MakeLeaf(Model::EllipticC, 50.0, 0.0, 0.0), 2000, 0.05, 0);
  ExpectError({}, "too few points: 0");
  ExpectError(std::vector<Eigen::Vector3d>(leaf.begin(), leaf.begin() + 20), "too few points: 20");
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 500; ++i)
    line.emplace_back(0.1 * i, 0.2 * i, -0.05 * i);
  ExpectError(line, "line");
  std::vector<Eigen::Vector3d> withNaN = leaf;
  withNaN[17].y() = std::nan("");
  ExpectError(withNaN, "1 point(s) with a NaN");
  std::mt19937_64 random(3);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Eigen::Vector3d> blob;
  for (int i = 0; i < 3000; ++i)
    blob.emplace_back(gauss(random), gauss(random), gauss(random));
  ExpectError(blob, "no leaf shape");
  // A thick slab: flat enough to pass the first check, but no surface to lie on.
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Vector3d> slab;
  for (int i = 0; i < 3000; ++i)
    slab.emplace_back(50.0 * uniform(random), 20.0 * uniform(random), 8.0 * uniform(random));
  ExpectError(slab, "no leaf shape");
  LeafFitParameters options;
  options.resolution = 2;
  ExpectError(leaf, "Resolution = 2 is outside the accepted range [4, 1000]", options);
  options = LeafFitParameters();
  options.surfaceSmoothing = -1.0;
  ExpectError(leaf, "SurfaceSmoothing", options);
}

} // namespace
} // namespace plantmorph
