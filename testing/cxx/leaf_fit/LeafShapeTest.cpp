// SPDX-License-Identifier: GPL-3.0-or-later
// The leaf's shape before the fit (filters/leaf_fit/shape): petiole, base and midvein axis, on synthetic scans whose
// truth is exact. A LeafOutlineSource blade (base at the origin, midvein along +Y) is sampled uniformly by area with
// noise; a petiole of known length leaves its base as a strip one or two points wide. The fit must put the base at
// the junction (within 2 % of the length), measure the petiole (within 5 %), keep it out of the blade's Length, and
// find the midvein's direction (within 3 degrees) on narrow, wide (fan), cordate and lobed blades.
#include "LeafFit.h"
#include "LeafFitInternal.h"
#include "LeafPlant.h"
#include "LeafShape.h"
#include "PointGrid.h"

#include "BSplineLeaf.h"
#include "BladeMesher.h"
#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"
#include "SpaceCurveLeaf.h"
#include "SpaceCurvePresets.h"

#include <plantmorph/MathConstants.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace plantmorph
{
namespace
{
struct Synthetic
{
  std::vector<Eigen::Vector3d> points;
  std::vector<unsigned char> petiole; ///< 1 for the petiole's samples
  double length = 0.0;                ///< the blade's midvein, base to apex
  double petioleLength = 0.0;
};

LeafGeometry Blade(int preset, double length)
{
  LeafMeshParameters settings;
  settings.resolution = 120;
  LeafGeometry leaf;
  std::string error;
  if (preset == 0)
    error = BuildBSplineLeaf(MakeBSplinePreset(BSplinePreset::Elliptic, length, 0.45 * length, 9), settings, leaf);
  else if (preset == 1)
    error =
      BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Ginkgo, length), settings, leaf);
  else if (preset == 2)
    error = BuildBSplineLeaf(MakeBSplinePreset(BSplinePreset::PinOak, length, 0.8 * length, 9), settings, leaf);
  else if (preset == 4)
    error = BuildBSplineLeaf(MakeBSplinePreset(BSplinePreset::Cucumber, length, 0.9 * length, 9), settings, leaf);
  else if (preset == 5)
  {
    SpaceCurveMeshParameters curveSettings;
    curveSettings.resolution = settings.resolution;
    error = BuildSpaceCurveLeaf(MakeSpaceCurvePreset(SpaceCurvePreset::Figure8FiveLobes, length), curveSettings, leaf);
  }
  else if (preset == 6)
    error = BuildDeformedRectangleLeaf(
      MakeDeformedRectanglePreset(DeformedRectanglePreset::CordateBaseRoundedApex, length), settings, leaf);
  else if (preset == 7)
    error = BuildDeformedRectangleLeaf(
      MakeDeformedRectanglePreset(DeformedRectanglePreset::RoundedBaseAcuminateApex, length), settings, leaf);
  else if (preset == 8)
    error =
      BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Lobed, length), settings, leaf);
  else if (preset == 12)
    error = BuildDeformedRectangleLeaf(
      MakeDeformedRectanglePreset(DeformedRectanglePreset::AcuminateBaseEmarginateApex, length), settings, leaf);
  else if (preset == 11)
  {
    SpaceCurveMeshParameters curveSettings;
    curveSettings.resolution = settings.resolution;
    error = BuildSpaceCurveLeaf(MakeSpaceCurvePreset(SpaceCurvePreset::Watermelon, length), curveSettings, leaf);
  }
  else if (preset == 9 || preset == 10)
  {
    SpaceCurveMeshParameters curveSettings;
    curveSettings.resolution = settings.resolution;
    error = BuildSpaceCurveLeaf(
      MakeSpaceCurvePreset(preset == 9 ? SpaceCurvePreset::Figure1 : SpaceCurvePreset::Figure2, length), curveSettings,
      leaf);
  }
  else
    error =
      BuildDeformedRectangleLeaf(MakeDeformedRectanglePreset(DeformedRectanglePreset::Entire, length), settings, leaf);
  EXPECT_EQ(error, "");
  return leaf;
}

/// `count` points uniform by area on the flat blade (noise `sigma` along Z), then a petiole from the base along the
/// curve `stalk` (arc-length parametrised from the base, `petiole` long), sampled at the blade's spacing in a strip
/// `across` points wide; everything moved by `pose`.
Synthetic Scan(const LeafGeometry& leaf, int count, double sigma, double petiole,
  const std::function<Eigen::Vector3d(double)>& stalk, int across, const Eigen::Isometry3d& pose, unsigned seed = 3)
{
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const auto& P = leaf.blade.points;
  std::vector<double> cdf;
  double total = 0.0;
  for (const auto& t : leaf.blade.triangles)
  {
    const Eigen::Vector2d a = P[t[1]] - P[t[0]], b = P[t[2]] - P[t[0]];
    total += 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    cdf.push_back(total);
  }
  Synthetic scan;
  for (int i = 0; i < count; ++i)
  {
    const std::size_t k = std::lower_bound(cdf.begin(), cdf.end(), uniform(random) * total) - cdf.begin();
    const auto& t = leaf.blade.triangles[std::min(k, cdf.size() - 1)];
    double a = uniform(random), b = uniform(random);
    if (a + b > 1.0)
    {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    const Eigen::Vector2d p = P[t[0]] + a * (P[t[1]] - P[t[0]]) + b * (P[t[2]] - P[t[0]]);
    scan.points.push_back(pose * Eigen::Vector3d(p.x(), p.y(), sigma * gauss(random)));
    scan.petiole.push_back(0);
  }
  const double spacing = std::sqrt(total / count);
  for (double s = 0.5 * spacing; s <= petiole; s += spacing)
  {
    const Eigen::Vector3d c = stalk(s), d = (stalk(s + 1e-3) - c).normalized();
    const Eigen::Vector3d side = d.cross(Eigen::Vector3d::UnitZ()).normalized();
    for (int j = 0; j < across; ++j)
    {
      const double offset = (j - 0.5 * (across - 1)) * spacing + 0.2 * spacing * (uniform(random) - 0.5);
      scan.points.push_back(pose * (c + offset * side + sigma * gauss(random) * Eigen::Vector3d::UnitZ()));
      scan.petiole.push_back(1);
    }
  }
  for (std::size_t i = 1; i < leaf.midvein.size(); ++i)
    scan.length += (P[leaf.midvein[i]] - P[leaf.midvein[i - 1]]).norm();
  scan.petioleLength = petiole;
  return scan;
}

/// A straight petiole from the base, leaving it at `angle` degrees below the blade's plane, pointing along -Y.
std::function<Eigen::Vector3d(double)> Straight(double angle)
{
  const double a = angle * Pi / 180.0;
  return [a](double s) { return Eigen::Vector3d(0.0, -s * std::cos(a), -s * std::sin(a)); };
}

struct Expected
{
  double baseTolerance = 0.02;    // of the length
  double lengthTolerance = 0.01;  // relative
  double degrees = 3.0;           // midvein direction
  double petioleTolerance = 0.05; // relative
};

/// Fits `scan` (moved by `pose`) and checks base, midvein direction, Length and PetioleLength against the truth.
void ExpectShape(const Synthetic& scan, const Eigen::Isometry3d& pose, const Expected& e,
  const LeafFitParameters& options = LeafFitParameters())
{
  const LeafFitResult fit = FitLeaf(scan.points, options);
  ASSERT_EQ(fit.error, "");
  const Eigen::Vector3d base = fit.points[fit.midvein.front()];
  EXPECT_LT((base - pose * Eigen::Vector3d::Zero()).norm(), e.baseTolerance * scan.length)
    << "base " << base.transpose();
  // The midvein's direction: from the base to the point a fifth along it (the blade may curve further on).
  const Eigen::Vector3d along = (fit.points[fit.midvein[fit.midvein.size() / 5]] - base).normalized();
  const double degrees =
    std::acos(std::clamp(along.dot(pose.linear() * Eigen::Vector3d::UnitY()), -1.0, 1.0)) * 180.0 / Pi;
  EXPECT_LT(degrees, e.degrees);
  EXPECT_NEAR(fit.traits.length, scan.length, e.lengthTolerance * scan.length);
  if (scan.petioleLength > 0.0)
  {
    EXPECT_EQ(fit.traits.baseFrom, options.basePoint ? 1 : 2);
    EXPECT_NEAR(fit.traits.petioleLength, scan.petioleLength, e.petioleTolerance * scan.petioleLength);
    // The petiole's samples are the petiole, the blade's are not.
    std::size_t missed = 0, wrong = 0, petiole = 0;
    for (std::size_t i = 0; i < scan.points.size(); ++i)
    {
      petiole += scan.petiole[i];
      missed += scan.petiole[i] && !fit.petiole[i] ? 1 : 0;
      wrong += !scan.petiole[i] && fit.petiole[i] ? 1 : 0;
    }
    EXPECT_LT(missed, petiole * e.petioleTolerance * 2 + 3);
    EXPECT_LT(wrong, petiole * e.petioleTolerance * 2 + 3);
    ASSERT_GE(fit.petioleLine.size(), 2u);
    EXPECT_LT((fit.petioleLine.front() - base).norm(), e.baseTolerance * scan.length);
  }
  else
  {
    EXPECT_EQ(fit.traits.petioleLength, 0.0);
    EXPECT_TRUE(fit.petioleLine.empty());
  }
}

Eigen::Isometry3d Tilted()
{
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, 0.5, 0.8).normalized()));
  pose.translation() = Eigen::Vector3d(12.0, -40.0, 5.0);
  return pose;
}

/// A rectangular blade 40 by 60 spacings sampled on a grid of one spacing, its first row at y = 0.5 and its base
/// straight across below it, noise 0.1 spacings off its plane, placed by `pose`.
std::vector<Eigen::Vector3d> GridBlade(const Eigen::Isometry3d& pose, std::mt19937_64& random)
{
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (double x = -20.0; x <= 20.0; x += 1.0)
    for (double y = 0.5; y <= 60.0; y += 1.0)
      points.push_back(pose * Eigen::Vector3d(x, y, 0.1 * gauss(random)));
  return points;
}

TEST(LeafShape, PetioleInThePlaneIsFoundAndLeftOutOfTheBlade)
{
  // In the blade's plane and in line with the midvein, the blade's narrow end and the stalk's first samples cannot
  // be told apart: the base is placed within a point spacing (0.8 % of the length here) of the junction, and the
  // Length is within 2 %.
  const Synthetic scan = Scan(Blade(0, 100.0), 6000, 0.1, 30.0, Straight(0.0), 2, Eigen::Isometry3d::Identity());
  Expected e;
  e.lengthTolerance = 0.02;
  ExpectShape(scan, Eigen::Isometry3d::Identity(), e);
}

TEST(LeafShape, PetioleOnePointWideLeavingTheBladeDownwards)
{
  const Eigen::Isometry3d pose = Tilted();
  const Synthetic scan = Scan(Blade(0, 100.0), 6000, 0.1, 40.0, Straight(35.0), 1, pose);
  ExpectShape(scan, pose, Expected());
}

TEST(LeafShape, NoisyStalkEndsWhereItsAxisMeetsTheBlade)
{
  // A stalk 30 % of the blade's length, 2 or 3 points across, leaving the base 30 degrees below the blade, noise 1 %
  // of the length (about 2 spacings). The stalk's points scatter wider than its width, so the walk along it stops
  // short of the blade, where the points around are its own and no sheet: the junction was left out on the stalk
  // (a cordate base: PetioleLength -16 %, base 2.1-2.7 % of the length out, Length +2.0-2.7 %; the elliptic blade's
  // rounded base: -9.4 to -9.7 %, 3.3-3.6 %, +3.2-3.5 %). The blade's plane ahead, where the axis meets it, is the
  // junction; beside a rounded base the points 12 spacings ahead are half a disc, too short across for a sheet at
  // this noise, so the plane is looked for 24 spacings ahead.
  for (const int preset : { 6, 0 })
    for (const int across : { 2, 3 })
      for (const bool tilted : { false, true })
      {
        const Eigen::Isometry3d pose = tilted ? Tilted() : Eigen::Isometry3d::Identity();
        const Synthetic scan = Scan(Blade(preset, 100.0), 10000, 1.0, 30.0, Straight(30.0), across, pose);
        SCOPED_TRACE("preset " + std::to_string(preset) + ", " + std::to_string(across) + " across, tilted " +
          std::to_string(tilted));
        ExpectShape(scan, pose, Expected());
      }
}

TEST(LeafShape, ShortNarrowPetioleSaysItMayBeTheBladesAttenuateBase)
{
  // A base that narrows into a trail a point or two across looks like a thin stalk: the curled emarginate preset
  // scanned from two positions, without a petiole, had its last 5 % taken for one (base 7 % of the length up the
  // blade, Length 7 % short), and said nothing. A short petiole (LeafPlant.h: MinPetioleShare) under 2 spacings in
  // half-width is said to be possibly the blade's own: a stalk two points across and 6 % as long as the
  // attenuate-based blade, found and measured, warns; the same stalk 30 % as long does not.
  const Eigen::Isometry3d pose = Tilted();
  const LeafGeometry leaf = Blade(12, 100.0);
  for (const double petiole : { 6.0, 30.0 })
  {
    const Synthetic scan = Scan(leaf, 8000, 0.1, petiole, Straight(30.0), 2, pose);
    const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
    ASSERT_EQ(fit.error, "");
    ASSERT_EQ(fit.traits.baseFrom, 2) << "petiole " << petiole;
    EXPECT_NEAR(fit.traits.petioleLength, petiole, 0.05 * petiole);
    const std::vector<std::string> warnings = CheckFittedLeaf(fit, LeafFitParameters().resolution);
    const bool said = std::any_of(warnings.begin(), warnings.end(),
      [](const std::string& w) { return w.find("attenuate base") != std::string::npos; });
    EXPECT_EQ(said, petiole < 10.0) << "petiole " << petiole;
  }
}

TEST(LeafShape, TrailAtAnApexToldByShapeSaysItMayBeAPetiole)
{
  // A stalk one point across and 12 % of the length, sampled at 2,000 points (about 6 spacings), is too short for
  // the petiole finder: the blade's shape then tells base from apex, and the stalk, a trail a point across, was taken
  // for a drawn-out apex. The apex warning said Length may be short, not that the leaf may be turned end to end.
  // It now says so when the base and apex were told apart by the shape alone; with BasePoint it does not.
  for (const int preset : { 11, 3 })
  {
    const Synthetic scan = Scan(Blade(preset, 100.0), 2000, 0.2, 12.0, Straight(20.0), 1, Tilted(), 3);
    auto turned = [](const LeafFitResult& fit, const LeafFitParameters& options) {
      const std::vector<std::string> warnings = CheckFittedLeaf(fit, options.resolution);
      return std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) {
        return w.find("the apex is drawn out") != std::string::npos && w.find("turned end to end") != std::string::npos;
      });
    };
    const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
    ASSERT_EQ(fit.error, "");
    ASSERT_EQ(fit.traits.baseFrom, 0) << "preset " << preset;
    ASSERT_GT(fit.apexTrail, 0.0) << "preset " << preset;
    EXPECT_TRUE(turned(fit, LeafFitParameters())) << "preset " << preset;
    LeafFitParameters given;
    given.basePoint = Tilted() * Eigen::Vector3d::Zero();
    const LeafFitResult based = FitLeaf(scan.points, given);
    ASSERT_EQ(based.error, "");
    EXPECT_FALSE(turned(based, given)) << "preset " << preset;
  }
}

/// Whether a warning of CheckFittedLeaf says the base was put at a narrow end for its constant width alone.
bool SaysBaseAtStalkWidth(const LeafFitResult& fit)
{
  const std::vector<std::string> warnings = CheckFittedLeaf(fit, LeafFitParameters().resolution);
  return std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) {
    return w.find("keep one width") != std::string::npos && w.find("turned end to end") != std::string::npos;
  });
}

TEST(LeafShape, NarrowEndReadAsAStalkWithoutPetioleSaysTheLeafMayBeTurned)
{
  // The acuminate blade without a petiole, 2,000 points uniform at random, noise 1 % of its length: the noise widens
  // the tip's first two slices to one width, as a stalk's, the shape rule put the base there, and the leaf came out
  // turned end to end with no warning (one benchmark case and six of a 936-fit survey did so). The shape cannot
  // tell that tip from a stalk the petiole search missed, so the fit now says which end it took and why.
  for (const bool tilted : { false, true })
  {
    SCOPED_TRACE(tilted ? "tilted" : "flat");
    const Eigen::Isometry3d pose = tilted ? Tilted() : Eigen::Isometry3d::Identity();
    const Synthetic scan = Scan(Blade(7, 100.0), 2000, 1.0, 0.0, Straight(20.0), 1, pose, 3);
    const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
    ASSERT_EQ(fit.error, "");
    ASSERT_EQ(fit.traits.baseFrom, 0);
    const Eigen::Vector3d base = fit.points[fit.midvein.front()];
    const bool turned = (base - pose * Eigen::Vector3d::Zero()).norm() > 0.5 * scan.length;
    EXPECT_TRUE(fit.baseAtStalkWidth);
    EXPECT_TRUE(!turned || SaysBaseAtStalkWidth(fit)) << "turned end to end without a word";
    // A base given: nothing to say.
    LeafFitParameters given;
    given.basePoint = pose * Eigen::Vector3d::Zero();
    const LeafFitResult based = FitLeaf(scan.points, given);
    ASSERT_EQ(based.error, "");
    EXPECT_FALSE(SaysBaseAtStalkWidth(based));
  }
  // A stalk a point across that the petiole search missed (12 % of the length at 8,000 points) reads the same way:
  // the leaf is the right way round, and the warning says PetioleLength is then 0.
  const Synthetic stalked = Scan(Blade(3, 100.0), 8000, 0.2, 12.0, Straight(20.0), 1, Eigen::Isometry3d::Identity(), 3);
  const LeafFitResult missed = FitLeaf(stalked.points, LeafFitParameters());
  ASSERT_EQ(missed.error, "");
  if (missed.traits.baseFrom == 0 && missed.baseAtStalkWidth)
  {
    // The right way round: the base at the stalk's far end (Length includes it), not at the apex.
    EXPECT_LT((missed.points[missed.midvein.front()] - Eigen::Vector3d::Zero()).norm(), 0.2 * stalked.length);
    EXPECT_TRUE(SaysBaseAtStalkWidth(missed));
  }
  else
    ADD_FAILURE() << "the stalk was found (BaseFrom " << missed.traits.baseFrom << "): the case no longer tests this";
  // Blades without a stalk whose narrow end is a wedge or a sinus, or that have none, never say it: elliptic,
  // entire, cordate, lobed, at 2,000 and 8,000 points, noise 0.2 and 1 %.
  for (const int preset : { 0, 3, 6, 8 })
    for (const int count : { 2000, 8000 })
      for (const double noise : { 0.2, 1.0 })
      {
        const Synthetic scan = Scan(Blade(preset, 100.0), count, noise, 0.0, Straight(20.0), 1, Tilted(), 4);
        const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
        ASSERT_EQ(fit.error, "");
        EXPECT_FALSE(SaysBaseAtStalkWidth(fit)) << "preset " << preset << ", " << count << " points, noise " << noise;
      }
}

TEST(LeafShape, ShortStalkAsNarrowAsTheNoiseSaysItMayBeTheBladesOwn)
{
  // At 1 % range noise the acuminate preset without a petiole had its drawn-out tip taken for a stalk 0.09-0.18 of
  // Length, 2.1-3.1 spacings in half-width (the noise widens it), and its base put at the tip, silently. A stalk
  // under 0.2 of Length whose half-width is under 2 spacings plus twice FitRMS is said to be possibly the blade's
  // own: here a stalk 12 % as long, 5 points across, noise about a spacing (half-width 2.3 spacings, FitRMS 1.2:
  // not said before, under 0.1 of Length and 2 spacings). The same stalk on a scan with little noise (half-width 3.2
  // spacings, FitRMS 0.3) is wider than a trail, and a stalk 30 % as long is a petiole: neither is said.
  const Eigen::Isometry3d pose = Tilted();
  const LeafGeometry leaf = Blade(0, 100.0);
  auto said = [&](double petiole, double sigma) {
    const Synthetic scan = Scan(leaf, 8000, sigma, petiole, Straight(30.0), 5, pose);
    const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
    EXPECT_EQ(fit.error, "");
    EXPECT_EQ(fit.traits.baseFrom, 2) << "petiole " << petiole << ", noise " << sigma;
    const std::vector<std::string> warnings = CheckFittedLeaf(fit, LeafFitParameters().resolution);
    return std::any_of(warnings.begin(), warnings.end(),
      [](const std::string& w) { return w.find("drawn-out tip") != std::string::npos; });
  };
  EXPECT_TRUE(said(12.0, 0.66));
  EXPECT_FALSE(said(12.0, 0.1));
  EXPECT_FALSE(said(30.0, 0.66));
}

TEST(LeafShape, StalkUnderAnAttenuateBaseOppositeANotchedApexIsThePetiole)
{
  // A stalk two points across under a base that narrows as a parabola: beyond the stalk the blade is drawn out as a
  // drip tip is, but the other end is notched and square, so it is the apex and the stalk the petiole (the end with
  // the stalk was once taken for the apex: the base at the notch, Length 7 % short).
  const Eigen::Isometry3d pose = Tilted();
  const LeafGeometry leaf = Blade(12, 100.0);
  for (const unsigned seed : { 3u, 4u })
  {
    const Synthetic scan = Scan(leaf, 8000, 0.1, 8.0, Straight(30.0), 2, pose, seed);
    const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
    ASSERT_EQ(fit.error, "");
    EXPECT_EQ(fit.traits.baseFrom, 2) << "seed " << seed;
    EXPECT_NEAR(fit.traits.petioleLength, 8.0, 0.05 * 8.0) << "seed " << seed;
    EXPECT_NEAR(fit.traits.length, scan.length, 0.015 * scan.length) << "seed " << seed;
    const Eigen::Vector3d base = pose.inverse() * fit.points[fit.midvein.front()];
    EXPECT_LT(base.head<2>().norm(), 0.02 * scan.length) << "seed " << seed;
  }
}

TEST(LeafShape, CurvedPetioleAtAnAngleToTheMidvein)
{
  // An arc of radius 30 turning from -Y towards +X and down: 45 long.
  const auto arc = [](double s) {
    const double r = 30.0, a = s / r;
    return Eigen::Vector3d(r * (1.0 - std::cos(a)), -r * std::sin(a), -0.2 * s);
  };
  // The arc's true length with its slope: sqrt(1 + 0.04) per unit of s.
  Synthetic scan = Scan(Blade(0, 100.0), 6000, 0.1, 45.0, arc, 2, Eigen::Isometry3d::Identity());
  scan.petioleLength = 45.0 * std::sqrt(1.04);
  Expected e;
  e.lengthTolerance = 0.02; // leaves the base in the blade's plane (as above)
  ExpectShape(scan, Eigen::Isometry3d::Identity(), e);
}

TEST(LeafShape, BladeWithoutPetioleHasNone)
{
  // The elliptic blade's acute tips are wedges, not petioles.
  const Synthetic scan = Scan(Blade(0, 100.0), 6000, 0.1, 0.0, Straight(0.0), 0, Eigen::Isometry3d::Identity());
  const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  EXPECT_EQ(fit.traits.petioleLength, 0.0);
  EXPECT_EQ(std::count(fit.petiole.begin(), fit.petiole.end(), 1), 0);
  EXPECT_NEAR(fit.traits.length, scan.length, 0.01 * scan.length);
}

TEST(LeafShape, FanIsFittedAlongItsMidveinNotAcrossIt)
{
  // The ginkgo fan is wider (110) than long (77.5): its principal axis runs across it. Its base is a cusp (both
  // margins leave it along the midvein, the blade narrower than the stalk for its first 4 units), which the samples
  // leave a gap at: the stalk starts 2 units inside the blade. The cusp's first units count to the stalk: base
  // within 6 % of the length, PetioleLength within 20 %; the midvein's direction within 3 degrees.
  const auto straight = Straight(20.0);
  Synthetic scan = Scan(
    Blade(1, 50.0), 8000, 0.05, 22.0, [&](double s) { return straight(s - 2.0); }, 2, Tilted());
  scan.petioleLength = 20.0;
  Expected e;
  e.baseTolerance = 0.06;
  e.lengthTolerance = 0.06;
  e.petioleTolerance = 0.2;
  ExpectShape(scan, Tilted(), e);
}

TEST(LeafShape, FanWithBasePointIsFittedAlongItsMidvein)
{
  // Without a petiole, BasePoint gives the base; the axis is still the fan's symmetry, not its principal axis.
  const Synthetic scan = Scan(Blade(1, 50.0), 8000, 0.05, 0.0, Straight(0.0), 0, Tilted());
  LeafFitParameters options;
  options.basePoint = Tilted() * Eigen::Vector3d(0.0, -1.0, 0.0);
  Expected e;
  e.baseTolerance = 0.03;    // the cusp's samples are sparse: its end is extrapolated from few of them
  e.lengthTolerance = 0.025; // the apex is a notch between two lobes: the midvein ends at its (rounded) bottom
  ExpectShape(scan, Tilted(), e, options);
}

TEST(LeafShape, LobedBladeIsFittedAlongItsMidvein)
{
  const Synthetic scan = Scan(Blade(2, 100.0), 10000, 0.1, 25.0, Straight(10.0), 2, Tilted());
  Expected e;
  e.lengthTolerance = 0.03;
  ExpectShape(scan, Tilted(), e);
}

/// The area of a flat blade (its triangles).
double BladeArea(const LeafGeometry& leaf)
{
  double area = 0.0;
  for (const auto& t : leaf.blade.triangles)
  {
    const Eigen::Vector2d a = leaf.blade.points[t[1]] - leaf.blade.points[t[0]];
    const Eigen::Vector2d b = leaf.blade.points[t[2]] - leaf.blade.points[t[0]];
    area += 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
  }
  return area;
}

/// Adds to `scan` a stalk `length` long leaving the blade's base along `stalk`, a tube `radius` round, as scanners
/// looking along `views` (unit vectors, from each scanner into the scene) see it: its surface sampled at `spacing`
/// where it faces each scanner, every point moved along its beam by range noise `sigma`.
void AddSeenTube(Synthetic& scan, double length, double radius, double spacing, double sigma,
  const std::function<Eigen::Vector3d(double)>& stalk, const std::vector<Eigen::Vector3d>& views, unsigned seed)
{
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Eigen::Vector3d d = (stalk(1.0) - stalk(0.0)).normalized();
  const Eigen::Vector3d e1 = d.cross(Eigen::Vector3d::UnitX()).normalized(), e2 = d.cross(e1);
  const int count = static_cast<int>(2.0 * Pi * radius * length / (spacing * spacing));
  for (const Eigen::Vector3d& view : views)
    for (int i = 0; i < count; ++i)
    {
      const double s = length * uniform(random), angle = 2.0 * Pi * uniform(random);
      const Eigen::Vector3d n = std::cos(angle) * e1 + std::sin(angle) * e2;
      if (n.dot(view) >= 0.0)
        continue; // facing away from this scanner
      scan.points.push_back(stalk(s) + radius * n + sigma * gauss(random) * view);
      scan.petiole.push_back(1);
    }
  scan.petioleLength = length;
}

TEST(LeafShape, NoisyStalkSeenFromTwoSidesKeepsItsAxisBehindItsSeenSide)
{
  // Two scanners looking down at 35 degrees either side of the midvein see a stalk 1 % of the blade's length in
  // radius, with range noise of the same size. A section's extreme points across the stalk are those the noise moved
  // outwards, which on an oblique beam is also upwards: the section's ends rise, the parabola through it bent the
  // wrong way, and the stalk's axis was put a radius above its seen side, not below. That line met the blade's plane
  // short of the junction, on the stalk (the accuracy benchmark's flat elliptic and cordate blades from two positions:
  // PetioleLength -12 %, Length +4 to +5 %). Where the noise is that large the line stays on the seen points.
  const std::vector<Eigen::Vector3d> views = { Eigen::Vector3d(std::sin(0.61), 0.0, -std::cos(0.61)),
    Eigen::Vector3d(-std::sin(0.61), 0.0, -std::cos(0.61)) };
  int cordateWithin = 0, otherWithin = 0; // PetioleLength within 5 %
  for (const int preset : { 6, 0 })
    for (const unsigned seed : { 3u, 4u, 5u, 6u, 7u, 8u })
    {
      const LeafGeometry leaf = Blade(preset, 100.0);
      // Each scanner's blade: 6,000 points, moved along its beams.
      Synthetic scan;
      std::mt19937_64 random(seed + 10);
      std::normal_distribution<double> gauss(0.0, 1.0);
      for (std::size_t v = 0; v < views.size(); ++v)
      {
        const Synthetic seen = Scan(leaf, 6000, 0.0, 0.0, Straight(30.0), 1, Eigen::Isometry3d::Identity(), seed + v);
        for (const Eigen::Vector3d& p : seen.points)
        {
          scan.points.push_back(p + gauss(random) * views[v]);
          scan.petiole.push_back(0);
        }
        scan.length = seen.length;
      }
      const double spacing = std::sqrt(BladeArea(leaf) / 6000.0);
      AddSeenTube(scan, 30.0, 1.0, spacing, 1.0, Straight(30.0), views, seed);
      const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
      ASSERT_EQ(fit.error, "");
      const bool within = std::abs(fit.traits.petioleLength - 30.0) <= 0.05 * 30.0;
      const double base = fit.points[fit.midvein.front()].norm() / scan.length;
      SCOPED_TRACE("preset " + std::to_string(preset) + ", seed " + std::to_string(seed));
      EXPECT_LT(base, 0.05);
      EXPECT_NEAR(fit.traits.petioleLength, 30.0, 0.12 * 30.0);
      if (within)
        ++(preset == 6 ? cordateWithin : otherWithin);
    }
  // On the cordate blade with seed 8 the arc was bent the wrong way (PetioleLength -10.6 %, base 4.7 % of the length
  // out on the stalk, Length +4.8 %: now -1.9 %, 1.5 %, +1.7 %). The elliptic blade's rounded base leaves the walk
  // short on two seeds either way (-10 % and -7 %). On the cordate blade with seed 4 the walk now runs on past a
  // slice the noise widened and the junction lies nearer the base (1.32 -> 1.24 % of the length, the base 1.25 ->
  // 1.15 %), but PetioleLength is +5.1 % (was +4.8 %): the centre line through the stalk's two seen sides is long.
  EXPECT_GE(cordateWithin, 5);
  EXPECT_GE(otherWithin, 4);
}

TEST(LeafShape, NoisyStalkSeenFromOnePositionIsFollowedToTheBlade)
{
  // One scanner, looking straight down or 35 degrees to the side of the midvein, sees a stalk 1 % of the blade's
  // length in radius, 30 % as long, 30 degrees below the blade, with range noise of the same size along its beams.
  // The noise throws a stalk's point beyond the stalk's width in a slice here and there, and the walk towards the
  // blade stopped at the first such slice, out on the stalk (PetioleLength within 5 % on 17 and 16 of these 30
  // scans, the junction 2.3 and 2.4 % of the length from the base on average). The blade, a sheet, is wider than the
  // stalk in every slice from the junction on; a slice the next one does not follow is the noise's. Now 26 and 24,
  // the junction 1.4 % of the length from the base on average.
  for (const double tilt : { 0.0, 35.0 })
  {
    const Eigen::Vector3d view(std::sin(tilt * Pi / 180.0), 0.0, -std::cos(tilt * Pi / 180.0));
    int within = 0, fits = 0;
    double junction = 0.0; // mean distance from the base, of the length
    for (const int preset : { 0, 3, 6, 8, 4 })
    {
      const LeafGeometry leaf = Blade(preset, 100.0);
      const double spacing = std::sqrt(BladeArea(leaf) / 6000.0);
      for (const unsigned seed : { 3u, 4u, 5u, 6u, 7u, 8u })
      {
        SCOPED_TRACE(
          "tilt " + std::to_string(tilt) + ", preset " + std::to_string(preset) + ", seed " + std::to_string(seed));
        const Synthetic seen = Scan(leaf, 6000, 0.0, 0.0, Straight(30.0), 1, Eigen::Isometry3d::Identity(), seed);
        Synthetic scan;
        std::mt19937_64 random(seed + 10);
        std::normal_distribution<double> gauss(0.0, 1.0);
        for (const Eigen::Vector3d& p : seen.points)
        {
          scan.points.push_back(p + gauss(random) * view);
          scan.petiole.push_back(0);
        }
        scan.length = seen.length;
        AddSeenTube(scan, 30.0, 1.0, spacing, 1.0, Straight(30.0), { view }, seed);
        const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
        ASSERT_EQ(fit.error, "");
        ASSERT_EQ(fit.traits.baseFrom, 2);
        ASSERT_FALSE(fit.petioleLine.empty());
        EXPECT_NEAR(fit.traits.petioleLength, 30.0, 0.15 * 30.0); // up to 11.8 % (27.8 % before)
        within += std::abs(fit.traits.petioleLength - 30.0) <= 0.05 * 30.0 ? 1 : 0;
        junction += fit.petioleLine.front().norm() / scan.length;
        ++fits;
      }
    }
    SCOPED_TRACE("tilt " + std::to_string(tilt));
    EXPECT_GE(within, 22) << "of " << fits;
    EXPECT_LT(junction / fits, 0.018);
  }
}

TEST(LeafShape, CordateBladeIsMeasuredFromItsSinusWithItsLobes)
{
  // The cucumber's basal lobes reach below its base (the sinus, at the origin): Length runs from the sinus, and the
  // lobes are in the blade (Area), the sinus is not.
  const LeafGeometry leaf = Blade(4, 100.0);
  const Synthetic scan = Scan(leaf, 10000, 0.1, 0.0, Straight(0.0), 0, Tilted());
  Expected e;
  e.lengthTolerance = 0.02;
  ExpectShape(scan, Tilted(), e);
  const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  EXPECT_NEAR(fit.traits.area, BladeArea(leaf), 0.01 * BladeArea(leaf));
}

TEST(LeafShape, PetioleLeavingACordateBaseIsMeasuredFromTheSinus)
{
  // A stalk 3 points wide leaves the cucumber's sinus 30 degrees below the blade, between the basal lobes: the ball
  // the blade's opening rolls covers its first few spacings there, and the junction must still be at the sinus
  // (within 2 % of the length) and the petiole whole (within 5 %). The midvein starts at the junction (the loop
  // the points draw rounds the sinus's bottom off and crosses the midvein below it), so Length is within 1 %.
  const Synthetic scan = Scan(Blade(4, 100.0), 10000, 0.1, 30.0, Straight(30.0), 3, Tilted());
  ExpectShape(scan, Tilted(), Expected());
}

/// Calls visit(x, y) for every point of the lattice x = (i + phase) * stepX, y = j * stepY on the flat blade, triangle
/// by triangle, each point in one triangle only (half-open barycentric ranges: ties on an edge go to one side).
void ForEachLatticePoint(
  const LeafGeometry& leaf, double stepX, double phase, double stepY, const std::function<void(double, double)>& visit)
{
  const auto& P = leaf.blade.points;
  for (const auto& t : leaf.blade.triangles)
  {
    const Eigen::Vector2d a = P[t[0]], b = P[t[1]], c = P[t[2]];
    const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (!(std::abs(det) > 0.0))
      continue;
    const Eigen::Vector2d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    for (double x = (std::ceil(lo.x() / stepX - phase) + phase) * stepX; x < hi.x(); x += stepX)
      for (double y = std::ceil(lo.y() / stepY) * stepY; y < hi.y(); y += stepY)
      {
        const Eigen::Vector2d r = Eigen::Vector2d(x, y) - a;
        const double u = (r.x() * (c - a).y() - r.y() * (c - a).x()) / det;
        const double v = ((b - a).x() * r.y() - (b - a).y() * r.x()) / det;
        if (u >= 0.0 && v >= 0.0 && u + v < 1.0)
          visit(x, y);
      }
  }
}

/// The flat blade sampled on a square grid of step `step` (a scanner's regular lines, which follow a narrow tip out
/// to its end where random samples thin out), noise `sigma` along Z, then a straight petiole from the base along
/// `stalk` in a strip `across` samples wide at the same step; everything moved by `pose`. The grid's columns lie at
/// x = (i + phase) * step (phase 0.5: none along the midvein).
Synthetic GridScan(const LeafGeometry& leaf, double step, double sigma, double petiole,
  const std::function<Eigen::Vector3d(double)>& stalk, int across, const Eigen::Isometry3d& pose, double phase = 0.0)
{
  std::mt19937_64 random(5);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const auto& P = leaf.blade.points;
  Synthetic scan;
  ForEachLatticePoint(leaf, step, phase, step, [&](double x, double y) {
    scan.points.push_back(pose * Eigen::Vector3d(x, y, sigma * gauss(random)));
    scan.petiole.push_back(0);
  });
  for (double s = 0.5 * step; s <= petiole; s += step)
    for (int j = 0; j < across; ++j)
    {
      const Eigen::Vector3d c = stalk(s);
      scan.points.push_back(pose *
        (c + ((j - 0.5 * (across - 1)) * step) * Eigen::Vector3d::UnitX() +
          sigma * gauss(random) * Eigen::Vector3d::UnitZ()));
      scan.petiole.push_back(1);
    }
  for (std::size_t i = 1; i < leaf.midvein.size(); ++i)
    scan.length += (P[leaf.midvein[i]] - P[leaf.midvein[i - 1]]).norm();
  scan.petioleLength = petiole;
  return scan;
}

TEST(LeafShape, BladeOnAScannersGridHasTheAreaItsPointsSample)
{
  // A scanner's regular lines, square or a fifth farther apart across than along (a view at 35 degrees), on blades
  // with smooth margins (elliptic, entire, paper 002's Fig. 1, emarginate): the area within 0.3 % of the truth. The
  // margin was put where the smooth margins' stations estimate it, a quarter of a spacing beyond the points'
  // count, and came out 0.36-0.97 % over.
  const Eigen::Isometry3d pose = Tilted();
  for (const int preset : { 0, 3, 9, 12 })
    for (const double stretch : { 1.0, 1.22 })
    {
      const LeafGeometry leaf = Blade(preset, 100.0);
      const double length = GridScan(leaf, 1.0, 0.0, 0.0, Straight(0.0), 0, pose).length;
      const double step = 0.01 * length;
      std::mt19937_64 random(5);
      std::normal_distribution<double> gauss(0.0, 1.0);
      std::vector<Eigen::Vector3d> points;
      ForEachLatticePoint(leaf, stretch * step, 0.3, step,
        [&](double x, double y) { points.push_back(pose * Eigen::Vector3d(x, y, 0.003 * length * gauss(random))); });
      const LeafFitResult fit = FitLeaf(points, LeafFitParameters());
      ASSERT_EQ(fit.error, "");
      EXPECT_NEAR(fit.traits.area, BladeArea(leaf), 0.003 * BladeArea(leaf))
        << "preset " << preset << ", lines " << stretch << " spacings apart";
    }
}

TEST(LeafShape, BladeOnTwoPassesOrWithItsPointsSpreadHasTheAreaItsPointsSample)
{
  // Two passes' lattices superimposed (two scanner positions: one square, one with lines a fifth farther apart and
  // shifted), and one lattice whose points range noise has moved across the blade by 0.4 spacings (an oblique view
  // at 1 % noise): still regular for the count (hyperuniform), so the area within 0.5 % of the truth (-0.44 to
  // +0.24 %). The smooth margins' stations put the margin beyond where the outermost points lie: +0.46 to +2.7 %.
  // The emarginate blade's spread points also leave its narrow base's flank grazing the fitted midvein.
  const Eigen::Isometry3d pose = Tilted();
  for (const int preset : { 0, 3, 9, 12 })
    for (const bool twoPasses : { true, false })
    {
      const LeafGeometry leaf = Blade(preset, 100.0);
      const double length = GridScan(leaf, 1.0, 0.0, 0.0, Straight(0.0), 0, pose).length;
      const double step = 0.01 * length, across = twoPasses ? 0.0 : 0.4 * step;
      std::mt19937_64 random(7);
      std::normal_distribution<double> gauss(0.0, 1.0);
      std::vector<Eigen::Vector3d> points;
      auto add = [&](double x, double y) {
        points.push_back(pose *
          Eigen::Vector3d(x + across * gauss(random), y + across * gauss(random), 0.002 * length * gauss(random)));
      };
      ForEachLatticePoint(leaf, step, 0.3, step, add);
      if (twoPasses)
        ForEachLatticePoint(leaf, 1.22 * step, 0.75, 0.93 * step, add);
      const LeafFitResult fit = FitLeaf(points, LeafFitParameters());
      ASSERT_EQ(fit.error, "");
      EXPECT_NEAR(fit.traits.area, BladeArea(leaf), 0.005 * BladeArea(leaf))
        << "preset " << preset << (twoPasses ? ", two passes" : ", points spread");
    }
}

TEST(LeafShape, NoisyScanFromAboveKeepsTheBladesAreaNotTheNoisesBumps)
{
  // A lattice scan with range noise 1 % of the length along the normal (a scanner above the blade): a surface that
  // follows the noise's bumps has their area as well (+1.12 to +1.34 % on these blades at the default penalty);
  // the penalty raised for the noise (MaxNoiseTilt) leaves the blade's area within 0.7 % (+0.19 to +0.62 %), and
  // the surface on the points (their distance to it within 5 % of the noise).
  const Eigen::Isometry3d pose = Tilted();
  for (const int preset : { 0, 3, 9, 12 })
  {
    const LeafGeometry leaf = Blade(preset, 100.0);
    const double length = GridScan(leaf, 1.0, 0.0, 0.0, Straight(0.0), 0, pose).length;
    const double sigma = 0.01 * length;
    const Synthetic scan = GridScan(leaf, 0.01 * length, sigma, 0.0, Straight(0.0), 0, pose, 0.3);
    const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
    ASSERT_EQ(fit.error, "");
    EXPECT_NEAR(fit.traits.area, BladeArea(leaf), 0.007 * BladeArea(leaf)) << "preset " << preset;
    EXPECT_LT(fit.traits.fitRMS, 1.05 * sigma) << "preset " << preset;
  }
}

/// The flat blade `leaf` scanned from near its plane, beyond its base: lines across it (along X) whose samples lie
/// `step` apart, the lines themselves `step` apart at the base and farther apart towards the apex, as the beams of a
/// scanner at a grazing angle meet the blade (1 + `grazing` times `step` at the apex; 0: an even grid).
std::vector<Eigen::Vector3d> GrazingScan(const LeafGeometry& leaf, double step, double grazing, double sigma)
{
  std::mt19937_64 random(9);
  std::normal_distribution<double> gauss(0.0, 1.0);
  double top = 0.0;
  for (const auto& p : leaf.blade.points)
    top = std::max(top, p.y());
  std::vector<Eigen::Vector3d> points;
  const auto& P = leaf.blade.points;
  for (double y = 0.5 * step; y <= top; y += step * (1.0 + grazing * (y / top) * (y / top)))
    for (const auto& t : leaf.blade.triangles)
    {
      // The line's samples in this triangle (half-open barycentric ranges: one triangle per sample).
      const Eigen::Vector2d a = P[t[0]], b = P[t[1]], c = P[t[2]];
      const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
      const Eigen::Vector2d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
      if (!(std::abs(det) > 0.0) || y < lo.y() || y >= hi.y())
        continue;
      for (double x = std::ceil(lo.x() / step) * step; x < hi.x(); x += step)
      {
        const Eigen::Vector2d r = Eigen::Vector2d(x, y) - a;
        const double u = (r.x() * (c - a).y() - r.y() * (c - a).x()) / det;
        const double v = ((b - a).x() * r.y() - (b - a).y() * r.x()) / det;
        if (u >= 0.0 && v >= 0.0 && u + v < 1.0)
          points.emplace_back(x, y, sigma * gauss(random));
      }
    }
  return points;
}

TEST(LeafShape, BladeScannedAtAGrazingAngleIsSaidToBeSampledUnevenly)
{
  // Seen from near its plane, a blade is crossed by lines a spacing apart at the near end and five times farther
  // apart at the far end: a ball of 4 spacings fits in no sheet there, and the lines, as thin as a stalk, were taken
  // for a petiole 23 % of the length long (at noise 1 % of the length; on a preset scanned by VirtualScanner's
  // defaults, the blade was cut there, Length -26 %). The share of the points in the blade's sheet (0.66 here) says
  // so: no petiole is looked for, and the fit warns. The same blade scanned evenly gives no such warning.
  const LeafGeometry leaf = Blade(0, 100.0);
  const double step = 1.0;
  for (const double grazing : { 0.0, 4.0 })
  {
    SCOPED_TRACE("grazing " + std::to_string(grazing));
    const std::vector<Eigen::Vector3d> points = GrazingScan(leaf, step, grazing, 1.0);
    const fit::Petiole petiole = fit::FindPetiole(points, MedianSpacing(points));
    const LeafFitResult fit = FitLeaf(points, LeafFitParameters());
    ASSERT_EQ(fit.error, "");
    const std::vector<std::string> warnings = CheckFittedLeaf(fit, 60);
    const bool warned = std::any_of(
      warnings.begin(), warnings.end(), [](const std::string& w) { return w.find("unevenly") != std::string::npos; });
    if (grazing == 0.0)
    {
      EXPECT_GT(petiole.sheetShare, 0.9);
      EXPECT_FALSE(warned);
      continue;
    }
    EXPECT_LT(petiole.sheetShare, fit::MinSheetShareForPetiole);
    EXPECT_FALSE(petiole.found);
    EXPECT_EQ(fit.traits.petioleLength, 0.0);
    EXPECT_TRUE(warned);
  }
}

TEST(LeafShape, StalkBelowACuneateBaseEndsWhereItsAxisMeetsTheBlade)
{
  // The ginkgo's base narrows to a cusp: on a scanner's grid its last few percent of the length are as narrow as
  // the stalk and lie in line with it, so the trail the blade's opening leaves out, and the walk along it, ran on
  // into the blade. The stalk leaves the blade 30 degrees below its plane; the cusp lies in the plane: the junction
  // is where the stalk's axis meets the plane, at the base (within 2 % of the length), and the cusp's points are
  // not the petiole's.
  const Eigen::Isometry3d pose = Tilted();
  const LeafGeometry leaf = Blade(1, 100.0);
  const Synthetic probe = GridScan(leaf, 1.0, 0.0, 0.0, Straight(30.0), 0, pose);
  const double step = 0.009 * probe.length; // the benchmark's line scans: about 10^4 points on the blade
  const Synthetic scan = GridScan(leaf, step, 0.003 * probe.length, 0.3 * probe.length, Straight(30.0), 3, pose);
  const fit::Petiole petiole = fit::FindPetiole(scan.points, MedianSpacing(scan.points));
  ASSERT_TRUE(petiole.found);
  EXPECT_LT((petiole.junction - pose * Eigen::Vector3d::Zero()).norm(), 0.02 * scan.length)
    << "junction " << (pose.inverse() * petiole.junction).transpose();
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i)
    wrong += !scan.petiole[i] && petiole.member[i] ? 1 : 0;
  EXPECT_LT(wrong, 5u);
  EXPECT_NEAR(petiole.length, scan.petioleLength, 0.05 * scan.petioleLength);
}

TEST(LeafShape, CuspBaseAboveAStalkIsMeasuredFromTheJunction)
{
  // The same scan, fitted: the cusp is narrower than the closing's discs, so the loop the points draw crosses the
  // midvein a few percent of the length above the base, and the smooth margins' tip, extrapolated past the cusp's
  // last points, lies beyond the junction. The cusp runs on along the midvein down to the junction, where the
  // stalk's axis meets the blade: the midvein starts there (it started at the loop's crossing: base 3.9 % of the
  // length off, Length -3.7 %).
  const Eigen::Isometry3d pose = Tilted();
  const LeafGeometry leaf = Blade(1, 100.0);
  const double length = GridScan(leaf, 1.0, 0.0, 0.0, Straight(30.0), 0, pose).length;
  const Synthetic scan = GridScan(leaf, 0.009 * length, 0.003 * length, 0.3 * length, Straight(30.0), 3, pose);
  ExpectShape(scan, pose, Expected());
}

/// Fits `scan` with its base given and returns the fitted Length (0 on an error).
double FittedLength(const Synthetic& scan, const Eigen::Isometry3d& pose)
{
  LeafFitParameters options;
  options.basePoint = pose * Eigen::Vector3d::Zero();
  const LeafFitResult fit = FitLeaf(scan.points, options);
  EXPECT_EQ(fit.error, "");
  return fit.error.empty() ? fit.traits.length : 0.0;
}

TEST(LeafShape, AcuminateApexOnAScannersGridIsFollowedToItsEnd)
{
  // The acuminate blade's drawn-out tip is 3.5 % of the blade's width across two slices (of 20) before its end, 1 %
  // one slice before: on a scanner's grid (about 10^4 points) a point or two across, narrower than the closing's
  // discs, so the loop the points draw crosses the midvein 10-15 % of the length short of the apex. The points run
  // on along the midvein to the tip; they were taken for a stalk leaving the apex and set apart. Length is within
  // 2 % (base given; it was 13-19 % short).
  for (const Eigen::Isometry3d& pose : { Eigen::Isometry3d(Eigen::Isometry3d::Identity()), Tilted() })
  {
    const LeafGeometry leaf = Blade(7, 100.0);
    const double length = GridScan(leaf, 1.0, 0.0, 0.0, Straight(30.0), 0, pose).length;
    for (double step : { 0.007, 0.009, 0.012 })
    {
      const Synthetic scan = GridScan(leaf, step * length, 0.003 * length, 0.0, Straight(30.0), 0, pose);
      EXPECT_NEAR(FittedLength(scan, pose), scan.length, 0.02 * scan.length) << "step " << step;
    }
  }
}

/// The blade's midvein (along +Y from the base at the origin, before `pose`) up to its highest sample.
double SampledExtent(const Synthetic& scan, const Eigen::Isometry3d& pose)
{
  double highest = 0.0;
  for (std::size_t i = 0; i < scan.points.size(); ++i)
    if (!scan.petiole[i])
      highest = std::max(highest, (pose.inverse() * scan.points[i]).y());
  return highest;
}

TEST(LeafShape, AcuminateApexSampledAtRandomIsFollowedToItsLastPoints)
{
  // Random samples (10^4) thin out along the drawn-out tip: its last 8 % of the length holds about one sample in
  // 10^4, and its last samples lie up to 4 spacings apart, one at a time. The fit follows them towards their end:
  // Length within 3 % of the midvein up to the highest sample (base given; it stopped 6-9 % short of it, the tip cut
  // where it narrows below the closing's discs or taken for a stalk), and with a stalk at the base instead.
  const Eigen::Isometry3d pose = Tilted();
  const LeafGeometry leaf = Blade(7, 100.0);
  for (unsigned seed : { 3u, 4u, 5u })
  {
    const Synthetic scan = Scan(leaf, 10000, 0.3, 0.0, Straight(0.0), 0, pose, seed);
    const double extent = SampledExtent(scan, pose);
    EXPECT_NEAR(FittedLength(scan, pose), extent, 0.03 * extent) << "seed " << seed;
  }
  Synthetic scan = Scan(leaf, 10000, 0.3, 30.0, Straight(30.0), 3, pose);
  scan.length = SampledExtent(scan, pose);
  Expected e;
  e.lengthTolerance = 0.035;
  ExpectShape(scan, pose, e);
}

TEST(LeafShape, DrawnOutTipNarrowerThanTheSpacingSaysLengthMayBeShort)
{
  // The acuminate blade's tip narrows as the cube of the distance to its end: its last 10 % is under 0.4 % of the
  // length across, narrower than a scanner's lines are apart (0.8 %), and lines that miss the midvein (the grid's
  // columns a quarter step off it) see little of it: Length is 9 % short, by what no point samples, and the fit said
  // nothing. Its last samples are a trail a point or two across over about 8 spacings (MaxApexTrail: 6.5): the fit
  // says Length may be short. Apices wider than that to within a few spacings of their end (the elliptic, ginkgo,
  // pin oak, cucumber, cordate and entire blades) say nothing of it.
  const Eigen::Isometry3d pose = Tilted();
  auto drawnOut = [&](const Synthetic& scan) {
    const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
    EXPECT_EQ(fit.error, "");
    const std::vector<std::string> warnings = CheckFittedLeaf(fit, LeafFitParameters().resolution);
    return std::any_of(warnings.begin(), warnings.end(),
      [](const std::string& w) { return w.find("apex is drawn out") != std::string::npos; });
  };
  for (const int preset : { 7, 0, 1, 2, 4, 6, 13 })
  {
    const LeafGeometry leaf = Blade(preset, 100.0);
    const double length = GridScan(leaf, 1.0, 0.0, 0.0, Straight(0.0), 0, pose).length;
    const Synthetic scan = GridScan(leaf, 0.008 * length, 0.003 * length, 0.0, Straight(0.0), 0, pose, 0.25);
    EXPECT_EQ(drawnOut(scan), preset == 7) << "preset " << preset;
  }
  // Sampled at random (10^4 points), the tip's last samples lie up to 8 spacings apart: still a trail.
  for (unsigned seed : { 3u, 4u })
    EXPECT_TRUE(drawnOut(Scan(Blade(7, 100.0), 10000, 0.3, 0.0, Straight(0.0), 0, pose, seed))) << "seed " << seed;
}

TEST(LeafShape, DrawnOutTipSeenAsATrailIsTheApexNotAStalk)
{
  // A scanner's column along the midvein follows the acuminate tip a point across over its last 12-15 % of the
  // length: the petiole search finds a trail there, and the end's first two slices keep its width (0 and 0.001 of
  // the widest), so the end was read as a stalk and the blade turned end to end (base at the tip, the tip taken
  // for a petiole, Length -10 to -13 %). Beyond a stalk the blade's base widens at once; beyond this trail it goes
  // on narrowing as a drawn-out tip (its width 2 slices on under 0.35 of its width 4 slices on): the trail is the
  // tip, and the fit follows it to its end (no base given).
  const Eigen::Isometry3d pose = Tilted();
  const LeafGeometry leaf = Blade(7, 100.0);
  const double length = GridScan(leaf, 1.0, 0.0, 0.0, Straight(0.0), 0, pose).length;
  for (const double step : { 0.006, 0.008 })
  {
    SCOPED_TRACE("step " + std::to_string(step));
    const Synthetic scan = GridScan(leaf, step * length, 0.003 * length, 0.0, Straight(0.0), 0, pose);
    Expected e;
    e.lengthTolerance = 0.02;
    ExpectShape(scan, pose, e);
  }
}

/// A counter-clockwise loop in (t, s) of a blade 100 long, 60 wide, sampled every 0.25 along its margin: the
/// half-width at s is `half(s)` for s in [0, 100]; `top(t)` the apex's margin across the blade (s at t).
std::vector<Eigen::Vector2d> BladeLoop(const std::function<double(double)>& top)
{
  std::vector<Eigen::Vector2d> loop;
  const double w = 30.0;
  for (double t = -w; t < w; t += 0.25) // the lower margin, left to right
    loop.push_back({ t, -std::sqrt(std::max(0.0, 1.0 - t * t / (w * w))) * 20.0 });
  for (double t = w; t > -w; t -= 0.25) // the apex's margin, right to left
    loop.push_back({ t, top(t) });
  return loop;
}

/// The loop's crossing of t = 0 at the apex (s, index of the edge's first point).
std::pair<double, std::size_t> ApexCrossing(const std::vector<Eigen::Vector2d>& loop)
{
  std::pair<double, std::size_t> apex(-1e300, 0);
  for (std::size_t i = 0; i < loop.size(); ++i)
  {
    const Eigen::Vector2d& p = loop[i];
    const Eigen::Vector2d& q = loop[(i + 1) % loop.size()];
    if ((p.x() > 0.0) != (q.x() > 0.0))
    {
      const double s = p.y() + (q.y() - p.y()) * p.x() / (p.x() - q.x());
      if (s > apex.first)
        apex = { s, i };
    }
  }
  return apex;
}

TEST(LeafShape, ApicalNotchShallowerThanFourSpacingsIsNoTip)
{
  // A fan 100 long whose apex is a notch 2.7 % of its length deep between two rounded lobes (the ginkgo's), spacing
  // 0.9 % of the length (the benchmark's line scans): 4 spacings reach 3.6 %, deeper than the notch, and the smooth
  // margins' tip s1 extrapolated just above the lobes' tops leaves the crossing within 4 spacings of it. The loop
  // rises on both sides of the crossing to the lobes: a notch, not a tip (the midvein ran to a lobe's top).
  const double spacing = 0.9, length = 100.0;
  auto fan = [](double t) { return 77.3 + 2.7 * std::min(1.0, std::abs(t) / 6.0) - 0.004 * t * t; };
  const std::vector<Eigen::Vector2d> notch = BladeLoop(fan);
  const auto apex = ApexCrossing(notch);
  ASSERT_NEAR(apex.first, 77.3, 0.01);
  EXPECT_FALSE(fit::ApexIsTip(notch, apex, 80.5, length, spacing));
  // Tips are tips, however far s1 lies past them within 4 spacings: an acute one, a rounded one, one with a dip of
  // half a spacing at t = 0 (the loop's own wander), a terminal lobe whose lateral lobes reach higher than its tip
  // farther out (a pin oak's), and a notch shallower than 2 % of the length.
  const std::vector<std::function<double(double)>> tips = {
    [](double t) { return 80.0 - std::abs(t); },
    [](double t) { return 80.0 - 0.02 * t * t; },
    [](double t) { return 80.0 - 0.02 * t * t - 0.45 * std::max(0.0, 1.0 - std::abs(t)); },
    [](double t) { return std::abs(t) < 10.0 ? 80.0 - std::abs(t) : 70.0 + 1.5 * (std::abs(t) - 10.0); },
    [](double t) { return 78.5 + 1.5 * std::min(1.0, std::abs(t) / 6.0) - 0.004 * t * t; },
  };
  for (std::size_t k = 0; k < tips.size(); ++k)
  {
    const std::vector<Eigen::Vector2d> tip = BladeLoop(tips[k]);
    EXPECT_TRUE(fit::ApexIsTip(tip, ApexCrossing(tip), ApexCrossing(tip).first + 3.0, length, spacing)) << "tip " << k;
  }
}

TEST(LeafShape, ApicalNotchEndsWhereThePointsCloseAcrossTheMidvein)
{
  // In intrinsic coordinates, a fan 100 long whose apex is a notch (its bottom at s = 100, on the midvein) between
  // two rounded lobes 2.7 beyond it (the ginkgo's), scanned in lines across it at spacings of 0.6 to 1.2 % of the
  // length, four phases each, with range noise of a third of a spacing along s (a scanner's beams are not square to
  // the blade: the benchmark's 0.3 % of the length on lines 0.9 % apart). The noise throws one or two points into
  // the notch, and the loop the points draw (the closing's discs) joins them to the blade: its crossing of the
  // midvein lay up to 1.2 spacings beyond the bottom. The midvein ends where the points close across it, moved out by
  // the loop's gap to the margin: within 0.6 of a spacing of the bottom at every spacing and phase.
  const double length = 100.0;
  auto top = [](double t) { return 100.0 + 4.0 * std::min(1.0, std::abs(t) / 8.0) - 0.004 * t * t; };
  for (const double spacing : { 0.6, 0.9, 1.2 })
    for (int phase = 0; phase < 4; ++phase)
    {
      std::mt19937_64 random(17 + phase);
      std::normal_distribution<double> gauss(0.0, 1.0);
      std::vector<Eigen::Vector2d> ts;
      for (double s = 0.25 * phase * spacing; s < length + 3.0; s += spacing)
        for (double t = -45.0 + 0.3 * phase * spacing; t < 45.0; t += spacing)
          if (std::abs(t) <= 3.0 + 0.35 * s && s <= top(t))
            ts.emplace_back(t, s + spacing / 3.0 * gauss(random));
      fit::Outline outline;
      ASSERT_EQ(fit::FitOutline(ts, LeafFitParameters(), spacing, outline), "");
      ASSERT_FALSE(fit::TraceContour(ts, spacing, true, outline).right.empty());
      EXPECT_NEAR(outline.apex, length, 0.6 * spacing) << "spacing " << spacing << ", phase " << phase;
    }
}

TEST(LeafShape, CordateBaseOnAScannersGridIsMeasuredFromTheSinusBottom)
{
  // The cucumber without a petiole on a scanner's grid (0.8 % of the length, about 10^4 points, noise 0.3 %): the
  // closing's discs (2.5 spacings) round the basal sinus's narrow V off, so the loop crosses the midvein below its
  // bottom (base 1.35 % of the length off, Length +1.02 % before). The points close across the midvein at the
  // bottom, and the midvein starts there (0.80 % and +0.47 %).
  const Eigen::Isometry3d pose = Tilted();
  const LeafGeometry leaf = Blade(4, 100.0);
  const double length = GridScan(leaf, 1.0, 0.0, 0.0, Straight(0.0), 0, pose).length;
  Expected e;
  e.baseTolerance = 0.01;
  ExpectShape(GridScan(leaf, 0.008 * length, 0.003 * length, 0.0, Straight(0.0), 0, pose), pose, e);
}

/// Blade `preset` 100 long on a grid of `grid` of its length (noise 0.3 % of it), and a stalk: a tube of radius
/// `radius` (of the length), 30 % as long, leaving the base 30 degrees below the blade, crossed by lines one step
/// apart along it; `arc(line, j)` is the angle (degrees, 0 at +X, 90 on top) of the line's j-th of `count` samples;
/// `phase` the grid's (GridScan).
Synthetic TubeScan(int preset, double grid, double radius, int count, const std::function<double(int, int)>& arc,
  const Eigen::Isometry3d& pose, double phase = 0.0)
{
  const LeafGeometry leaf = Blade(preset, 100.0);
  const double length = GridScan(leaf, 1.0, 0.0, 0.0, Straight(30.0), 0, pose).length;
  const double step = grid * length, petiole = 0.3 * length;
  Synthetic scan = GridScan(leaf, step, 0.003 * length, 0.0, Straight(30.0), 0, pose, phase);
  const auto axis = Straight(30.0);
  const Eigen::Vector3d d = (axis(1.0) - axis(0.0)).normalized(), side = Eigen::Vector3d::UnitX();
  Eigen::Vector3d up = side.cross(d).normalized();
  if (up.z() < 0.0)
    up = -up;
  int line = 0;
  for (double s = 0.5 * step; s <= petiole; s += step, ++line)
    for (int j = 0; j < count; ++j)
    {
      const double a = arc(line, j) * Pi / 180.0;
      scan.points.push_back(pose * (axis(s) + radius * length * (std::cos(a) * side + std::sin(a) * up)));
      scan.petiole.push_back(1);
    }
  scan.petioleLength = petiole;
  return scan;
}

Synthetic TubeScan(double radius, int count, const std::function<double(int, int)>& arc, const Eigen::Isometry3d& pose)
{
  return TubeScan(0, 0.006, radius, count, arc, pose);
}

/// Finds the petiole of `scan` (moved by `pose`) into `found` and checks it: found, its junction within `tolerance`
/// of the length from the true base, its length within 5 % of the true one. Call through ASSERT_NO_FATAL_FAILURE.
void ExpectStalkFound(const Synthetic& scan, const Eigen::Isometry3d& pose, double tolerance, fit::Petiole& found)
{
  found = fit::FindPetiole(scan.points, MedianSpacing(scan.points));
  ASSERT_TRUE(found.found);
  EXPECT_LT((found.junction - pose * Eigen::Vector3d::Zero()).norm(), tolerance * scan.length)
    << "junction " << (pose.inverse() * found.junction).transpose();
  EXPECT_NEAR(found.length, scan.petioleLength, 0.05 * scan.petioleLength);
}

TEST(LeafShape, StalkSeenFromAlternatingSidesIsMeasuredAlongItsAxis)
{
  // A line scan crosses a stalk (a tube of radius 1 % of the length) in lines, and each line sees the side facing
  // its pass: here the lines alternate between the tube's two upper quarters, as two passes tilted to either side
  // leave them. The centroid of each stretch of the trail lies on one side or the other, so a line through every
  // stretch zigzags across the stalk (PetioleLength +9.9 % before); measured along centroids two stalk widths
  // apart, it is the stalk's length (+0.7 %).
  const Eigen::Isometry3d pose = Tilted();
  const Synthetic scan = TubeScan(
    0.01, 3, [](int line, int j) { return line % 2 == 0 ? 45.0 * j : 180.0 - 45.0 * j; }, pose);
  fit::Petiole found;
  ASSERT_NO_FATAL_FAILURE(ExpectStalkFound(scan, pose, 0.02, found));
}

TEST(LeafShape, StalkBelowACuspSeenFromTwoSidesEndsWhereItsFittedAxisMeetsTheBlade)
{
  // The ginkgo (a cusp as narrow as the stalk, in line with it) and the pin oak on a scanner's grid, each with a
  // stalk as two passes tilted to either side see it: lines alternating between its two upper quarters. The
  // centroids of two stretches of the trail 6 spacings apart wander across the stalk and tilt the direction through
  // them (the ginkgo's junction lay 1.7 % of the length out on the stalk, PetioleLength -5.2 %); the line fitted
  // through all the stalk's first points, moved onto its axis, meets the blade's plane at the base.
  const Eigen::Isometry3d pose = Tilted();
  for (const int preset : { 1, 2 })
  {
    const Synthetic scan = TubeScan(
      preset, 0.009, 0.01, 3, [](int line, int j) { return line % 2 == 0 ? 10.0 + 35.0 * j : 170.0 - 35.0 * j; }, pose);
    SCOPED_TRACE("preset " + std::to_string(preset));
    fit::Petiole found;
    ASSERT_NO_FATAL_FAILURE(ExpectStalkFound(scan, pose, 0.01, found));
  }
}

TEST(LeafShape, StalkBeyondTheUnseenEndOfAnAcuminateBaseIsFound)
{
  // An acuminate base narrows gradually into the stalk: over its last few percent of the length it is narrower than
  // a scanner's lines are apart, and lines that do not run along the midvein (here half a step off it) miss it, so
  // the stalk (a tube of radius 1 % of the length, seen from above) begins a gap of several spacings away from the
  // blade's lowest samples, touching no part of the blade. It is the petiole all the same, and the blade runs on,
  // unseen, down to it: the base is at the junction (it was not found: the base lay 7-12 % of the length up the
  // blade and the Length was as much short).
  const Eigen::Isometry3d pose = Tilted();
  const Synthetic scan = TubeScan(
    12, 0.007, 0.01, 3, [](int, int j) { return 45.0 + 45.0 * j; }, pose, 0.5);
  fit::Petiole found;
  ASSERT_NO_FATAL_FAILURE(ExpectStalkFound(scan, pose, 0.02, found));
  EXPECT_TRUE(found.acrossGap);
  ExpectShape(scan, pose, Expected());
}

/// TubeScan's stalk (radius 1 % of the length) seen all round, as two passes from either side see it: samples over
/// 296 degrees of its circumference, as far apart as the blade's (`grid` of the length).
Synthetic TubeSeenAllRound(int preset, double grid, const Eigen::Isometry3d& pose)
{
  const int count = static_cast<int>(std::lround(0.048 / grid));
  return TubeScan(
    preset, grid, 0.01, count, [count](int, int j) { return -40.0 + 296.0 / count * j; }, pose);
}

TEST(LeafShape, StalkSeenAllRoundAsDenselyAsTheBladeIsNotTakenForBlade)
{
  // Two scans from either side see a stalk (a tube of radius 1 % of the length, 1.7 spacings) over most of its
  // circumference, as densely as the blade: a ball of the opening on it holds as many points as a ball inside the
  // blade, and the count alone took the stalk for blade (no petiole; a curled blade was then turned end to end,
  // its petiole counted in its Length). The ball's points on the stalk spread along it more than across, and are
  // round across it, not flat like a narrow strip of blade: no blade's.
  // On a finer scan (the same stalk 2.5 spacings in radius, over half the ball's) the ball's points fill the stalk
  // across as well as along it: twice as far out they are elongated again (no petiole before, the blade turned).
  const Eigen::Isometry3d pose = Tilted();
  for (const double grid : { 0.006, 0.004 })
  {
    SCOPED_TRACE("grid " + std::to_string(grid));
    const Synthetic scan = TubeSeenAllRound(0, grid, pose);
    fit::Petiole found;
    ASSERT_NO_FATAL_FAILURE(ExpectStalkFound(scan, pose, 0.02, found));
    ExpectShape(scan, pose, Expected());
  }
}

TEST(LeafShape, StalkThickerThanTheBallUnderACordateBaseIsFound)
{
  // The cordate blade and the cucumber on a fine scanner's grid (0.36 % of the length), with a stalk of radius 1 %
  // (2.8 spacings, 0.7 of the opening's ball) seen all round: a ball centred on the stalk's surface holds an arc of
  // its section, neither a sheet nor round enough to be tried in the larger ball. The stalk was taken for blade,
  // no petiole was found and the blade was turned end to end (its base at the apex); tried twice as far out, it is
  // a stalk.
  const Eigen::Isometry3d pose = Tilted();
  for (const int preset : { 6, 4 })
  {
    SCOPED_TRACE("preset " + std::to_string(preset));
    ExpectShape(TubeSeenAllRound(preset, 0.0036, pose), pose, Expected());
  }
}

TEST(LeafShape, AttenuateBaseThinnerThanItsStalkIsTheBlades)
{
  // An attenuate base narrows to a point where a thicker stalk (a tube of radius 1 % of the length, seen all round
  // by two passes) leaves it: over its last few percent it is a trail of the blade's samples a point or two across,
  // narrower than the stalk and sparser, in line with it. The stalk starts where the trail thickens to the stalk's
  // width and count, not where the blade is wider than the stalk (the junction lay 9 % of the length up the blade,
  // PetioleLength +30 %, on the curled emarginate blade scanned from two positions).
  const Eigen::Isometry3d pose = Tilted();
  for (const double grid : { 0.0045, 0.006 })
  {
    SCOPED_TRACE("grid " + std::to_string(grid));
    const Synthetic scan = TubeSeenAllRound(12, grid, pose);
    fit::Petiole found;
    ASSERT_NO_FATAL_FAILURE(ExpectStalkFound(scan, pose, 0.02, found));
  }
}

TEST(LeafShape, StalkSeenInPiecesBeyondAShadowIsMeasuredToItsEnd)
{
  // A line scan leaves gaps along a stalk where the blade shadows it: here the lines over 8 spacings of it (twice
  // the trail's link) are missing from 60 % of its length on, and its last two lines are strays the cleaning
  // removed (given apart, as `loose`). The trail ends at the gap (PetioleLength -40 % before); the pieces beyond
  // lie on the stalk's line within its radius and join it. A piece beside that line (3 radii off it) does not.
  const Eigen::Isometry3d pose = Tilted();
  const Synthetic full = TubeScan(
    0.01, 3, [](int, int j) { return 45.0 + 45.0 * j; }, pose);
  const auto axis = Straight(30.0);
  const double step = 0.006 * full.length, gapFrom = 0.6 * full.petioleLength, gapTo = gapFrom + 8.0 * step;
  const double lastLines = full.petioleLength - 2.0 * step;
  for (const bool beside : { false, true })
  {
    std::vector<Eigen::Vector3d> points, loose;
    std::vector<std::size_t> far; // ids of the pieces beyond the gap in `points`
    const Eigen::Vector3d off = beside
      ? Eigen::Vector3d(pose.linear() * (0.03 * full.length * Eigen::Vector3d::UnitX()))
      : Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < full.points.size(); ++i)
    {
      const Eigen::Vector3d local = pose.inverse() * full.points[i];
      const double along = full.petiole[i] ? (local - axis(0.0)).dot((axis(1.0) - axis(0.0)).normalized()) : -1.0;
      if (along >= gapFrom && along < gapTo)
        continue;
      if (along >= lastLines)
        loose.push_back(full.points[i] + off);
      else
      {
        if (along >= gapTo)
          far.push_back(points.size());
        points.push_back(full.points[i] + (along >= gapTo ? off : Eigen::Vector3d::Zero()));
      }
    }
    const fit::Petiole found = fit::FindPetiole(points, MedianSpacing(points), SerialFor, loose);
    ASSERT_TRUE(found.found);
    ASSERT_EQ(found.looseMember.size(), loose.size());
    const auto joined = std::count_if(far.begin(), far.end(), [&](std::size_t id) { return found.member[id] == 1; });
    const auto joinedLoose = std::count(found.looseMember.begin(), found.looseMember.end(), 1);
    if (beside)
    {
      EXPECT_EQ(joined + joinedLoose, 0) << "a piece 3 radii off the stalk's line joined it";
      EXPECT_LT(found.length, 0.7 * full.petioleLength);
      continue;
    }
    EXPECT_EQ(joined, static_cast<std::ptrdiff_t>(far.size()));
    EXPECT_EQ(joinedLoose, static_cast<std::ptrdiff_t>(loose.size()));
    EXPECT_NEAR(found.length, full.petioleLength, 0.05 * full.petioleLength);
  }
}

TEST(LeafShape, StalkSeenInSparseLinesEndsAtTheBladeNotAtItsLastLine)
{
  // A line scan may cross a stalk in lines two or three spacings apart along it (seen at a slant), two samples
  // across each: the walk towards the blade takes the empty slices between them as the stalk, up to the blade's
  // first row, which is wider than the stalk. The blade here is a rectangle sampled on a grid of one spacing, its
  // base straight across at y = 0, the stalk in its plane along -Y (so no plane meets its axis and the walk alone
  // places the junction), its lines at every phase. The junction lay at the stalk's last line, up to 2.1 spacings out
  // on it (PetioleLength -6.7 % with lines 3 apart); it is now within a spacing of the base.
  const Eigen::Isometry3d pose = Tilted();
  for (const int every : { 1, 2, 3 })
    for (const double phase : { 0.1, 0.4, 0.7 })
    {
      std::mt19937_64 random(7);
      std::vector<Eigen::Vector3d> points = GridBlade(pose, random);
      std::normal_distribution<double> gauss(0.0, 1.0);
      double farthest = 0.0;
      for (double y = -phase * every; y >= -30.0; y -= every)
      {
        for (const double x : { -0.5, 0.5 })
          points.push_back(pose * Eigen::Vector3d(x, y, 0.1 * gauss(random)));
        farthest = -y;
      }
      const fit::Petiole found = fit::FindPetiole(points, MedianSpacing(points));
      ASSERT_TRUE(found.found) << "lines " << every << " apart, phase " << phase;
      const Eigen::Vector3d junction = pose.inverse() * found.junction;
      EXPECT_LT(junction.norm(), 1.0) << "lines " << every << " apart, phase " << phase << ": junction "
                                      << junction.transpose();
      EXPECT_NEAR(found.length, farthest, 0.05 * farthest) << "lines " << every << " apart, phase " << phase;
    }
}

TEST(LeafShape, StalkTopInTheSliceThatEndsTheWalkIsTheStalks)
{
  // The blade of StalkSeenInSparseLinesEndsAtTheBladeNotAtItsLastLine (a grid of one spacing, its first row at
  // y = 0.5) and a stalk parallel to it whose top is seen 0.8 spacings above its plane, in lines 2 spacings apart,
  // two samples across each, the last line at every phase up to 2 spacings from that row. The walk towards the blade
  // takes the empty slice between two lines as the stalk and ends at the slice that holds the blade's first row,
  // wider than the stalk. Where the stalk's last line lies in that slice too (0.1 and 0.3 spacings from the row), its
  // samples were left with the blade (its lowest samples, from which the base's tip is extrapolated: the benchmark's
  // flat watermelon from above, Length +1.55 %); they are the stalk's. The junction stays within a spacing of the
  // base.
  const Eigen::Isometry3d pose = Tilted();
  for (double phase = 0.05; phase < 1.0; phase += 0.1)
  {
    std::mt19937_64 random(11);
    std::vector<Eigen::Vector3d> points = GridBlade(pose, random);
    std::normal_distribution<double> gauss(0.0, 1.0);
    const std::size_t firstStalk = points.size();
    for (double y = 0.5 - 2.0 * phase; y >= -30.0; y -= 2.0)
      for (const double x : { -0.5, 0.5 })
        points.push_back(pose * Eigen::Vector3d(x, y, 0.8 + 0.1 * gauss(random)));
    const fit::Petiole found = fit::FindPetiole(points, MedianSpacing(points));
    ASSERT_TRUE(found.found) << "phase " << phase;
    for (std::size_t i = firstStalk; i < points.size(); ++i)
      EXPECT_EQ(found.member[i], 1) << "phase " << phase << ": the stalk's sample at "
                                    << (pose.inverse() * points[i]).transpose() << " left with the blade";
    const Eigen::Vector3d junction = pose.inverse() * found.junction;
    EXPECT_LT(Eigen::Vector2d(junction.x(), junction.y()).norm(), 1.0)
      << "phase " << phase << ": junction " << junction.transpose();
  }
}

TEST(LeafShape, StalksFarSideByTheJunctionIsTheStalks)
{
  // The grid blade of StalkSeenInSparseLinesEndsAtTheBladeNotAtItsLastLine and a tube of radius 1.5 spacings leaving
  // its base 30 degrees below its plane, seen from above on its top (from 40 to 140 degrees round its axis, in lines
  // a spacing apart at five phases), and six samples of its far side 1 to 3 spacings from the base (what a second
  // scanner position or the inside of a cut tube shows), 0.7 radii below its axis. The line through the seen side's
  // centroids lies 0.8 radii above the axis, so those samples lay beyond the stalk's width from it: the walk
  // towards the blade ended on them and left them with the blade (its lowest samples, from which the base's tip is
  // extrapolated: the benchmark's curled watermelon from two positions, Length +1.07 %). They are the stalk's, within
  // its width of its own axis; the junction stays within the stalk's radius of the base.
  const Eigen::Isometry3d pose = Tilted();
  const double pi = std::acos(-1.0), radius = 1.5, slope = pi / 6.0;
  const Eigen::Vector3d along(0.0, -std::cos(slope), -std::sin(slope)), across(1.0, 0.0, 0.0);
  const Eigen::Vector3d up(0.0, -std::sin(slope), std::cos(slope));
  auto onTube = [&](double t, double angle, double r) {
    return pose * (t * along + r * (std::cos(angle) * across + std::sin(angle) * up));
  };
  for (double phase = 0.0; phase < 1.0; phase += 0.2)
  {
    std::mt19937_64 random(7);
    std::vector<Eigen::Vector3d> points = GridBlade(pose, random);
    std::normal_distribution<double> gauss(0.0, 1.0);
    for (double t = phase; t <= 30.0; t += 1.0)
      for (int k = 0; k <= 3; ++k)
        points.push_back(
          onTube(t, (2.0 + 5.0 * k / 3.0) * pi / 9.0, radius) + 0.05 * gauss(random) * (pose.linear() * up));
    const std::size_t firstFar = points.size();
    for (const double t : { 1.0, 2.0, 3.0 })
      for (const double angle : { -0.5 * pi - 0.3, -0.5 * pi + 0.3 })
        points.push_back(onTube(t, angle, 0.7 * radius));
    const fit::Petiole found = fit::FindPetiole(points, MedianSpacing(points));
    ASSERT_TRUE(found.found) << "phase " << phase;
    for (std::size_t i = firstFar; i < points.size(); ++i)
      EXPECT_EQ(found.member[i], 1) << "phase " << phase << ": the far side's sample at "
                                    << (pose.inverse() * points[i]).transpose() << " left with the blade";
    const Eigen::Vector3d junction = pose.inverse() * found.junction;
    EXPECT_LT(junction.norm(), radius) << "phase " << phase << ": junction " << junction.transpose();
  }
}

/// A stalk of radius `radius` leaving the grid blade's straight base 30 degrees below its plane (along `along`, 30
/// spacings), scanned by parallel-ray passes looking down `tilts` degrees to either side of the blade's length (by
/// default 35 degrees to each side, as the accuracy benchmark's two positions are), each on a grid of rays `step`
/// apart across and along, shifted by `phase` steps; the blade hides what lies under it. Range noise `noise`
/// spacings along each ray.
std::vector<Eigen::Vector3d> StalkSeenInPasses(double radius, double step, double phase, const Eigen::Vector3d& along,
  std::mt19937_64& random, const std::vector<double>& tilts = { -35.0, 35.0 }, double noise = 0.05)
{
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Eigen::Vector3d> seen;
  for (const double degrees : tilts)
  {
    const double tilt = degrees * Pi / 180.0;
    const Eigen::Vector3d v(std::sin(tilt), 0.0, -std::cos(tilt)), e1(0.0, 1.0, 0.0);
    const Eigen::Vector3d e2 = v.cross(e1).normalized();
    const Eigen::Vector3d d = v - v.dot(along) * along;
    for (double a = -30.0 + phase * step; a <= 2.0 * radius; a += step)
      for (double b = -3.0 * radius + phase * step; b <= 3.0 * radius; b += step)
      {
        const Eigen::Vector3d o = a * e1 + b * e2 - 100.0 * v;
        const Eigen::Vector3d m = o - o.dot(along) * along;
        const double A = d.squaredNorm(), B = 2.0 * m.dot(d), C = m.squaredNorm() - radius * radius;
        if (B * B - 4.0 * A * C < 0.0)
          continue;
        const double lambda = (-B - std::sqrt(B * B - 4.0 * A * C)) / (2.0 * A);
        const Eigen::Vector3d p = o + lambda * v;
        const double t = p.dot(along);
        const double toBlade = -o.z() / v.z(); // where the ray crosses the blade's plane
        const Eigen::Vector3d q = o + toBlade * v;
        if (t < 0.0 || t > 30.0 || (toBlade < lambda && std::abs(q.x()) <= 20.5 && q.y() >= 0.0))
          continue;
        seen.push_back(p + noise * gauss(random) * v);
      }
  }
  return seen;
}

TEST(LeafShape, StalkSeenFromAboveMeetsTheBladeOnItsFittedAxis)
{
  // The grid blade and a stalk of radius 1.5 to 2.5 spacings leaving its base 30 degrees below it, seen from above
  // by one parallel-ray pass (StalkSeenInPasses with one tilt, rays a spacing apart, five phases, range noise
  // 0.1 and 0.3 spacings). The walk towards the blade ends at the stalk's top where it meets the blade; the line
  // through two bins' centroids, moved by the seen side's offset, met the blade's plane up to 2.2 spacings inside
  // the blade (the benchmark's lobed blade with a petiole: Length -1.2 to -1.8 %), the line fitted through the
  // stalk's points, moved onto its axis, meets it within a radius of the base.
  const Eigen::Isometry3d pose = Tilted();
  const double slope = Pi / 6.0;
  const Eigen::Vector3d along(0.0, -std::cos(slope), -std::sin(slope));
  for (const double radius : { 1.5, 2.0, 2.5 })
    for (const double noise : { 0.1, 0.3 })
      for (double phase = 0.0; phase < 1.0; phase += 0.2)
      {
        std::mt19937_64 random(5);
        std::vector<Eigen::Vector3d> points = GridBlade(pose, random);
        for (const Eigen::Vector3d& p : StalkSeenInPasses(radius, 1.0, phase, along, random, { 0.0 }, noise))
          points.push_back(pose * p);
        const fit::Petiole found = fit::FindPetiole(points, MedianSpacing(points));
        ASSERT_TRUE(found.found) << "radius " << radius << ", noise " << noise << ", phase " << phase;
        const Eigen::Vector3d junction = pose.inverse() * found.junction;
        EXPECT_LT(junction.y(), 0.5) << "radius " << radius << ", noise " << noise << ", phase " << phase
                                     << ": junction inside the blade at " << junction.transpose();
        EXPECT_LT(junction.norm(), radius)
          << "radius " << radius << ", noise " << noise << ", phase " << phase << ": junction " << junction.transpose();
      }
}

TEST(LeafShape, StalksFlanksSeenFromTwoSidesAreTheStalks)
{
  // The grid blade and a stalk of radius 3 spacings seen from two sides (StalkSeenInPasses), each pass's rays 1.4
  // spacings apart (the two passes together about as dense as the blade): each sees a flank down to its axis and
  // below, a radius out to the side (the benchmark's acuminate blade from two positions at 0.1 % noise, its stalk's
  // radius 2.5 spacings). The seen side's offset from the
  // axis is most of a radius; a flank point lay beyond the stalk's width, less half that offset, of its own axis,
  // ended the walk towards the blade 4 radii out on the stalk (PetioleLength -12 %, base 4.3 % of the length off).
  // The flanks are the stalk's: the junction lies within the stalk's radius of the base at every phase.
  const Eigen::Isometry3d pose = Tilted();
  const double radius = 3.0, slope = Pi / 6.0;
  const Eigen::Vector3d along(0.0, -std::cos(slope), -std::sin(slope));
  for (double phase = 0.0; phase < 1.0; phase += 0.25)
  {
    std::mt19937_64 random(11);
    std::vector<Eigen::Vector3d> points = GridBlade(pose, random);
    for (const Eigen::Vector3d& p : StalkSeenInPasses(radius, 1.4, phase, along, random))
      points.push_back(pose * p);
    const fit::Petiole found = fit::FindPetiole(points, MedianSpacing(points));
    ASSERT_TRUE(found.found) << "phase " << phase;
    const Eigen::Vector3d junction = pose.inverse() * found.junction;
    EXPECT_LT(junction.norm(), radius) << "phase " << phase << ": junction " << junction.transpose();
  }
}

/// The scan without the points for which `cut(x, y)` holds (in the blade's plane, before the pose), then posed.
Synthetic Without(Synthetic scan, const std::function<bool(double, double)>& cut, const Eigen::Isometry3d& pose)
{
  Synthetic kept = scan;
  kept.points.clear();
  kept.petiole.clear();
  for (std::size_t i = 0; i < scan.points.size(); ++i)
    if (!cut(scan.points[i].x(), scan.points[i].y()))
    {
      kept.points.push_back(pose * scan.points[i]);
      kept.petiole.push_back(scan.petiole[i]);
    }
  return kept;
}

TEST(LeafShape, ToothHookedOverTheMidveinLeavesTheMidveinFromTheBase)
{
  // An elliptic blade 100 long (a petiole 25 long at its base says which end is the base) with a slit 2 wide, 4 to
  // 6 below the tip, cut from the left margin across the midvein: the tooth above it is hooked over the midvein, and
  // the traced outline crosses the midvein four times. The midvein is the longest piece of it inside the blade,
  // from the base (to the slit, or to the tip): the top two crossings made it the piece above the slit, 2 long.
  const Synthetic scan = Scan(Blade(0, 100.0), 10000, 0.1, 25.0, Straight(10.0), 2, Eigen::Isometry3d::Identity());
  const double tip = scan.length;
  const Synthetic slit = Without(
    scan, [&](double x, double y) { return y > tip - 6.0 && y < tip - 4.0 && x < 2.0; }, Tilted());
  const LeafFitResult fit = FitLeaf(slit.points, LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  EXPECT_LT((fit.points[fit.midvein.front()] - Tilted() * Eigen::Vector3d::Zero()).norm(), 0.02 * tip);
  EXPECT_GT(fit.traits.length, 0.93 * tip);
  EXPECT_LT(fit.traits.length, 1.01 * tip);
}

TEST(LeafShape, DeepApicalNotchIsTheApex)
{
  // The same blade with a notch 10 deep (10 % of it) on the midvein: a real notch, the midvein ends at its bottom.
  const Synthetic scan = Scan(Blade(0, 100.0), 10000, 0.1, 25.0, Straight(10.0), 2, Eigen::Isometry3d::Identity());
  const double tip = scan.length;
  Synthetic notched = Without(
    scan, [&](double x, double y) { return y > tip - 10.0 + 2.0 * std::abs(x); }, Tilted());
  notched.length = tip - 10.0;
  Expected e;
  e.lengthTolerance = 0.02;
  ExpectShape(notched, Tilted(), e);
}

TEST(LeafShape, FanWithoutPetioleOrHintsIsFittedAlongItsMidvein)
{
  // No petiole, no BasePoint: the axis of symmetry through the centroid (not the principal axis across the fan), the
  // base at the narrow end (the fan is widest at its top).
  const Synthetic scan = Scan(Blade(1, 50.0), 8000, 0.05, 0.0, Straight(0.0), 0, Tilted());
  Expected e;
  e.baseTolerance = 0.03;
  e.lengthTolerance = 0.025; // the apex is a notch between two lobes: the midvein ends at its (rounded) bottom
  ExpectShape(scan, Tilted(), e);
}

TEST(LeafShape, AcuminateTipWithoutPetioleIsTheApex)
{
  // Paper 000's rounded base and acuminate apex, no petiole and no hints. The drawn-out tip narrows to a point over
  // a fifth of the blade: narrow at one end like a stalk, but a stalk keeps its width along its length and the tip's
  // width grows from its point. Densely sampled, its last part is a trail a point or two wide, as a stalk's. The base
  // is the rounded end, whatever the density and the pose.
  for (const int count : { 3000, 10000, 30000 })
    for (const bool tilted : { false, true })
    {
      const Eigen::Isometry3d pose = tilted ? Tilted() : Eigen::Isometry3d::Identity();
      const Synthetic scan = Scan(Blade(7, 100.0), count, 0.1, 0.0, Straight(0.0), 0, pose, 3 + count);
      const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
      ASSERT_EQ(fit.error, "");
      const Eigen::Vector3d base = fit.points[fit.midvein.front()];
      EXPECT_LT((base - pose * Eigen::Vector3d::Zero()).norm(), 0.02 * scan.length)
        << count << " points, tilted " << tilted << ": base " << base.transpose() << " from " << fit.traits.baseFrom
        << " petiole " << fit.traits.petioleLength;
      const Eigen::Vector3d along = (fit.points[fit.midvein[fit.midvein.size() / 5]] - base).normalized();
      EXPECT_GT(along.dot(pose.linear() * Eigen::Vector3d::UnitY()), std::cos(3.0 * Pi / 180.0))
        << count << " points, tilted " << tilted;
      EXPECT_EQ(fit.traits.petioleLength, 0.0) << count << " points, tilted " << tilted; // the tip is no stalk
    }
}

TEST(LeafShape, ObovateBladeSaysItsBaseIsAGuess)
{
  // Paper 002's Fig. 1 blade (a cuneate base and an acute apex, its area centre 1.8 % of its length towards the apex)
  // and Fig. 2 blade (a narrow base widening to a blunt apex, 0.67 of the widest across at its end; 6.5 % off), no
  // petiole and no hints. Obovate blades are as common as ovate ones, so the wider half does not tell the base: the
  // base found is right, or the fit says it is a guess (BaseFrom 3), never a silent half turn (Fig. 2 was turned
  // end to end with BaseFrom 0).
  for (const int preset : { 9, 10 })
    for (const int count : { 8000, 30000 })
      for (const bool tilted : { false, true })
      {
        const Eigen::Isometry3d pose = tilted ? Tilted() : Eigen::Isometry3d::Identity();
        const Synthetic scan = Scan(Blade(preset, 100.0), count, 0.1, 0.0, Straight(0.0), 0, pose, 7 + count);
        const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
        ASSERT_EQ(fit.error, "");
        const Eigen::Vector3d base = fit.points[fit.midvein.front()];
        const bool right = (base - pose * Eigen::Vector3d::Zero()).norm() < 0.02 * scan.length;
        EXPECT_TRUE(right || fit.traits.baseFrom == 3)
          << "preset " << preset << ", " << count << " points, tilted " << tilted << ": base " << base.transpose()
          << " from " << fit.traits.baseFrom;
      }
}

/// Each point's distance to the segment from a to b (a twig).
std::vector<double> DistancesToSegment(
  const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  std::vector<double> distance;
  for (const Eigen::Vector3d& p : points)
  {
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    distance.push_back((p - a - t * (b - a)).norm());
  }
  return distance;
}

TEST(LeafShape, ALeafsBaseIsTheEndNearerItsWood)
{
  // Paper 002's Fig. 2 blade, obovate (its wider half is the apex's), no petiole: the shape alone cannot tell its
  // base (BaseFrom 3, at the wider half). A twig across the blade's plane 2 % of its length beyond one end: that
  // end becomes the base (BaseFrom 4), turning the first fit where it put the base at the other end. A twig along the
  // blade's side, as near both ends, tells nothing: the fit stays as it was. Not with BasePoint.
  for (const bool tilted : { false, true })
  {
    const Eigen::Isometry3d pose = tilted ? Tilted() : Eigen::Isometry3d::Identity();
    const Synthetic scan = Scan(Blade(10, 100.0), 8000, 0.1, 0.0, Straight(0.0), 0, pose, 11);
    const Eigen::Vector3d base = pose * Eigen::Vector3d::Zero(), apex = pose * Eigen::Vector3d(0.0, scan.length, 0.0);
    const Eigen::Vector3d normal = pose.linear() * Eigen::Vector3d::UnitZ();
    const std::vector<std::vector<Eigen::Vector3d>> leaves{ scan.points };
    int turned = 0;
    for (const bool atBase : { true, false })
    {
      const Eigen::Vector3d end = atBase ? base : apex, out = (end - (base + apex) / 2.0).normalized();
      const Eigen::Vector3d twig = end + 2.0 * out;
      std::vector<LeafFitResult> fits = FitLeaves(leaves, LeafFitParameters());
      ASSERT_EQ(fits[0].error, "");
      const int before = fits[0].traits.baseFrom;
      turned +=
        OrientByWood(leaves, { DistancesToSegment(scan.points, twig - 30.0 * normal, twig + 30.0 * normal) }, {}, fits);
      const Eigen::Vector3d fitted = fits[0].points[fits[0].midvein.front()];
      EXPECT_LT((fitted - end).norm(), 0.03 * scan.length)
        << "tilted " << tilted << ", twig at the " << (atBase ? "base" : "apex") << ": base " << fitted.transpose()
        << " (BaseFrom " << before << " -> " << fits[0].traits.baseFrom << ")";
      EXPECT_TRUE(fits[0].traits.baseFrom == BaseFromWood || (before == 0 && fits[0].traits.baseFrom == 0));
      EXPECT_TRUE(CheckFittedLeaf(fits[0], 60).empty() || fits[0].traits.baseFrom != 3);
    }
    EXPECT_EQ(turned, 1) << "tilted " << tilted; // the first fit had one end: one of the two twigs turns it
    // A twig along the side: the same distance from both ends. A base from the shape stays as it was. (A guessed
    // base would move to the side nearest the twig: a leaf lying along a twig it does not grow from is where the
    // wood's base point misleads; AGuessedBaseMovesToWhereTheLeafMeetsItsWood.)
    std::vector<LeafFitResult> fits = FitLeaves(leaves, LeafFitParameters());
    fits[0].traits.baseFrom = BaseFromShape;
    const LeafFitResult first = fits[0];
    const Eigen::Vector3d side = pose.linear() * Eigen::Vector3d(60.0, 0.0, 0.0);
    EXPECT_EQ(OrientByWood(leaves, { DistancesToSegment(scan.points, base + side, apex + side) }, {}, fits), 0);
    EXPECT_EQ(fits[0].traits.baseFrom, first.traits.baseFrom);
    EXPECT_EQ(fits[0].points[fits[0].midvein.front()], first.points[first.midvein.front()]);
    // With BasePoint the user's base stands
    LeafFitParameters hinted;
    hinted.basePoint = apex;
    fits = FitLeaves(leaves, hinted);
    const Eigen::Vector3d twig = base - 2.0 * (apex - base).normalized();
    EXPECT_EQ(OrientByWood(
                leaves, { DistancesToSegment(scan.points, twig - 30.0 * normal, twig + 30.0 * normal) }, hinted, fits),
      0);
    EXPECT_EQ(fits[0].traits.baseFrom, 1);
  }
}

TEST(LeafShape, AGuessedBaseMovesToWhereTheLeafMeetsItsWood)
{
  // An elliptic blade (100 long, 45 wide) whose first fit ran across it, from one side margin to the other (as a
  // fan seen in part is fitted across its width), with that base a guess (BaseFrom 3). Its twig lies 2 % of its
  // length beyond its true base: both ends of the fitted midvein are as far from it, so the ends tell nothing, but
  // the leaf's point near the wood at an end of the leaf (WoodBasePoint) is the true base. The leaf is fitted again
  // from there (BaseFrom 4): its Length is its length, its base the true base. A base from the blade's shape
  // (BaseFrom 0) is not moved so.
  const Synthetic scan = Scan(Blade(0, 100.0), 8000, 0.1, 0.0, Straight(0.0), 0, Eigen::Isometry3d::Identity(), 11);
  const std::vector<std::vector<Eigen::Vector3d>> leaves{ scan.points };
  const Eigen::Vector3d base = Eigen::Vector3d::Zero(), twig = base - Eigen::Vector3d(0.0, 2.0, 0.0);
  const std::vector<std::vector<double>> wood{ DistancesToSegment(
    scan.points, twig - Eigen::Vector3d(0.0, 0.0, 30.0), twig + Eigen::Vector3d(0.0, 0.0, 30.0)) };
  const std::optional<std::size_t> at = WoodBasePoint(scan.points, wood[0]);
  ASSERT_TRUE(at.has_value());
  EXPECT_LT((scan.points[*at] - base).norm(), 0.03 * scan.length) << scan.points[*at].transpose();
  LeafFitParameters across;
  across.basePoint = Eigen::Vector3d(-30.0, 50.0, 0.0); // beyond a side margin, halfway along the blade
  across.apexPoint = Eigen::Vector3d(30.0, 50.0, 0.0);
  for (const int from : { BaseFromGuess, BaseFromShape })
  {
    std::vector<LeafFitResult> fits = FitLeaves(leaves, across);
    ASSERT_EQ(fits[0].error, "");
    ASSERT_LT(fits[0].traits.length, 0.6 * scan.length); // across the blade
    fits[0].traits.baseFrom = from;
    EXPECT_NE(EndNearerTheWood(fits[0], scan.points, wood[0]), WoodEnd::Apex); // the ends do not turn it
    const int again = OrientByWood(leaves, wood, LeafFitParameters(), fits);
    if (from == BaseFromShape)
    {
      EXPECT_EQ(again, 0);
      EXPECT_LT(fits[0].traits.length, 0.6 * scan.length);
      continue;
    }
    EXPECT_EQ(again, 1);
    EXPECT_EQ(fits[0].traits.baseFrom, BaseFromWood);
    EXPECT_NEAR(fits[0].traits.length, scan.length, 0.02 * scan.length);
    EXPECT_LT((fits[0].points[fits[0].midvein.front()] - base).norm(), 0.03 * scan.length);
  }
}

TEST(LeafShape, AWoodBasePointThatTurnsALeafFromItsPlantsShapeIsDropped)
{
  // An elliptic blade (100 long, 45 wide) fitted along its length, its base a guess (the blade is the same at both
  // ends), lies against a twig it does not grow from: the twig stands across the blade's plane 2 beyond the middle of
  // its side margin. Both ends are as far from it, so the ends tell nothing, and the leaf's point near the wood
  // (WoodBasePoint) is on that side: alone, the leaf is fitted again from there, across its width (Length about 45).
  // On a plant whose leaves are longer than wide (their Width over Length 0.45, the blade's own) that refit is
  // dropped: its ratio (about 2) is the plant's turned over. The first fit's axis stands, and so does its guess.
  const Synthetic scan = Scan(Blade(0, 100.0), 8000, 0.1, 0.0, Straight(0.0), 0, Eigen::Isometry3d::Identity(), 11);
  const std::vector<std::vector<Eigen::Vector3d>> leaves{ scan.points };
  double right = 0; // the side margin's x at mid-length
  for (const Eigen::Vector3d& p : scan.points)
    if (std::abs(p.y() - 0.5 * scan.length) < 2.0)
      right = std::max(right, p.x());
  const Eigen::Vector3d twig(right + 2.0, 0.5 * scan.length, 0.0);
  const std::vector<std::vector<double>> wood{ DistancesToSegment(
    scan.points, twig - Eigen::Vector3d(0.0, 0.0, 30.0), twig + Eigen::Vector3d(0.0, 0.0, 30.0)) };
  const std::optional<std::size_t> at = WoodBasePoint(scan.points, wood[0]);
  ASSERT_TRUE(at.has_value());
  ASSERT_LT((scan.points[*at] - twig).norm(), 0.1 * scan.length) << scan.points[*at].transpose();
  const std::optional<double> plant = PlantAxisShape({ std::log(0.44), std::log(0.45), std::log(0.47) });
  ASSERT_TRUE(plant.has_value());
  EXPECT_NEAR(*plant, std::log(0.45), 1e-12);
  for (const bool withPlant : { false, true })
  {
    std::vector<LeafFitResult> fits = FitLeaves(leaves, LeafFitParameters());
    ASSERT_EQ(fits[0].error, "");
    ASSERT_NEAR(fits[0].traits.length, scan.length, 0.03 * scan.length); // along the blade
    fits[0].traits.baseFrom = BaseFromGuess;
    const LeafFitResult first = fits[0];
    const int again =
      OrientByWood(leaves, wood, LeafFitParameters(), fits, SerialFor, withPlant ? plant : std::nullopt);
    if (!withPlant)
    {
      EXPECT_EQ(again, 1);
      EXPECT_LT(fits[0].traits.length, 0.6 * scan.length); // across: the misleading twig alone decides
      continue;
    }
    EXPECT_EQ(again, 0);
    EXPECT_EQ(fits[0].traits.baseFrom, BaseFromGuess);
    EXPECT_EQ(fits[0].traits.length, first.traits.length);
    EXPECT_EQ(fits[0].points[fits[0].midvein.front()], first.points[first.midvein.front()]);
  }
  // The plant's shape does not hold back a move that brings the leaf to it: the same blade fitted across, its twig
  // beyond its true base (AGuessedBaseMovesToWhereTheLeafMeetsItsWood), is fitted along its length.
  const Eigen::Vector3d baseTwig(0.0, -2.0, 0.0);
  const std::vector<std::vector<double>> baseWood{ DistancesToSegment(
    scan.points, baseTwig - Eigen::Vector3d(0.0, 0.0, 30.0), baseTwig + Eigen::Vector3d(0.0, 0.0, 30.0)) };
  LeafFitParameters across;
  across.basePoint = Eigen::Vector3d(-30.0, 50.0, 0.0);
  across.apexPoint = Eigen::Vector3d(30.0, 50.0, 0.0);
  std::vector<LeafFitResult> fits = FitLeaves(leaves, across);
  ASSERT_EQ(fits[0].error, "");
  fits[0].traits.baseFrom = BaseFromGuess;
  EXPECT_EQ(OrientByWood(leaves, baseWood, LeafFitParameters(), fits, SerialFor, plant), 1);
  EXPECT_NEAR(fits[0].traits.length, scan.length, 0.02 * scan.length);
  EXPECT_LT(fits[0].points[fits[0].midvein.front()].norm(), 0.03 * scan.length);
}

TEST(LeafShape, ALeafFittedAcrossItsWidthIsFittedAlongThePlantsAxis)
{
  // The elliptic blade (100 long, 45 wide) fitted across its width, from one side margin to the other, its base from
  // the shape (so the wood's base point does not move it) and its twig 2 beyond its true base: an end of the fitted
  // Width. Its ends are as far from the twig, so they tell nothing. On a plant whose leaves are 0.45 as wide as long
  // the fit's ratio (about 2.2) is the plant's turned over and the wood lies by an end of its Width: it is fitted
  // again from there, along its length (BaseFrom 4). Without the plant's shape, or with the twig by the middle of a
  // long side (the fitted midvein's base end: the wood says the leaf grows from there), it stays across.
  const Synthetic scan = Scan(Blade(0, 100.0), 8000, 0.1, 0.0, Straight(0.0), 0, Eigen::Isometry3d::Identity(), 11);
  const std::vector<std::vector<Eigen::Vector3d>> leaves{ scan.points };
  const auto twigAt = [&](const Eigen::Vector3d& at) {
    return std::vector<std::vector<double>>{ DistancesToSegment(
      scan.points, at - Eigen::Vector3d(0.0, 0.0, 30.0), at + Eigen::Vector3d(0.0, 0.0, 30.0)) };
  };
  LeafFitParameters across;
  across.basePoint = Eigen::Vector3d(-30.0, 50.0, 0.0);
  across.apexPoint = Eigen::Vector3d(30.0, 50.0, 0.0);
  const std::optional<double> plant = PlantAxisShape({ std::log(0.44), std::log(0.45), std::log(0.47) });
  ASSERT_TRUE(plant.has_value());
  for (int variant = 0; variant < 3; ++variant)
  {
    std::vector<LeafFitResult> fits = FitLeaves(leaves, across);
    ASSERT_EQ(fits[0].error, "");
    ASSERT_LT(fits[0].traits.length, 0.6 * scan.length);
    fits[0].traits.baseFrom = BaseFromShape;
    const bool side = variant == 2;
    const auto wood = twigAt(side ? Eigen::Vector3d(-25.0, 50.0, 0.0) : Eigen::Vector3d(0.0, -2.0, 0.0));
    const int again =
      OrientByWood(leaves, wood, LeafFitParameters(), fits, SerialFor, variant > 0 ? plant : std::nullopt);
    if (variant != 1)
    {
      EXPECT_EQ(again, 0) << variant;
      EXPECT_LT(fits[0].traits.length, 0.6 * scan.length) << variant;
      continue;
    }
    EXPECT_EQ(again, 1);
    EXPECT_EQ(fits[0].traits.baseFrom, BaseFromWood);
    EXPECT_NEAR(fits[0].traits.length, scan.length, 0.02 * scan.length);
    EXPECT_LT(fits[0].points[fits[0].midvein.front()].norm(), 0.03 * scan.length);
  }
}

TEST(LeafShape, ThePlantsAxisShapeIsTheMedianOfTheLeavesWhoseAxisTheWoodTells)
{
  // A leaf counts (its log Width over Length) when an end of its midvein lies nearer the wood than the ends of its
  // Width: the elliptic blade (100 long, 45 wide) with a twig beyond its base or its apex counts, whatever its base
  // was found from, as it was fitted; fitted across its width with the twig beyond its true base (an end of the
  // fitted Width), it counts turned over, the blade's own ratio. A leaf not fitted, or one whose base the user gave,
  // does not count. A twig by the middle of its long side (an end of its Width) misleads: the leaf reads as grown
  // from its side and counts turned over; the median over the plant's leaves outvotes a few such.
  const Synthetic scan = Scan(Blade(0, 100.0), 8000, 0.1, 0.0, Straight(0.0), 0, Eigen::Isometry3d::Identity(), 11);
  const std::vector<LeafFitResult> fitted = FitLeaves({ scan.points }, LeafFitParameters());
  ASSERT_EQ(fitted[0].error, "");
  const Eigen::Vector3d base = fitted[0].points[fitted[0].midvein.front()];
  const Eigen::Vector3d apex = fitted[0].points[fitted[0].midvein.back()];
  const auto twigAt = [&](const Eigen::Vector3d& at) {
    return DistancesToSegment(scan.points, at - Eigen::Vector3d(0.0, 0.0, 30.0), at + Eigen::Vector3d(0.0, 0.0, 30.0));
  };
  const auto twigBeyond = [&](const Eigen::Vector3d& end, const Eigen::Vector3d& other) {
    return twigAt(end + 2.0 * (end - other).normalized());
  };
  LeafFitParameters acrossFit;
  acrossFit.basePoint = Eigen::Vector3d(-30.0, 50.0, 0.0);
  acrossFit.apexPoint = Eigen::Vector3d(30.0, 50.0, 0.0);
  const LeafFitResult across = FitLeaves({ scan.points }, acrossFit)[0];
  ASSERT_EQ(across.error, "");
  ASSERT_LT(across.traits.length, 0.6 * scan.length);
  std::vector<LeafFitResult> fits(7, fitted[0]);
  fits[0].traits.baseFrom = BaseFromShape;
  fits[1].traits.baseFrom = BaseFromShape;
  fits[2].traits.baseFrom = BaseFromGuess;
  fits[3].error = "too few points";
  fits[4].traits.baseFrom = BaseFromPoint;
  fits[5] = across;
  fits[5].traits.baseFrom = BaseFromGuess;
  double right = 0; // the side margin's x at mid-length
  for (const Eigen::Vector3d& p : scan.points)
    if (std::abs(p.y() - 0.5 * scan.length) < 2.0)
      right = std::max(right, p.x());
  const std::vector<std::vector<Eigen::Vector3d>> leaves(7, scan.points);
  const std::vector<std::vector<double>> wood{ twigBeyond(base, apex), twigBeyond(apex, base), twigBeyond(base, apex),
    twigBeyond(base, apex), twigBeyond(base, apex), twigAt(Eigen::Vector3d(0.0, -2.0, 0.0)),
    twigAt(Eigen::Vector3d(right + 2.0, 0.5 * scan.length, 0.0)) };
  EXPECT_EQ(AxisNearerTheWood(fits[0], scan.points, wood[0]), WoodAxis::Along);
  EXPECT_EQ(AxisNearerTheWood(fits[5], scan.points, wood[5]), WoodAxis::Across);
  EXPECT_EQ(AxisNearerTheWood(fits[6], scan.points, wood[6]), WoodAxis::Across);
  const std::vector<double> shapes = AxisShapes(fits, leaves, wood);
  ASSERT_EQ(shapes.size(), 5u);
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_NEAR(shapes[k], std::log(fitted[0].traits.width / fitted[0].traits.length), 1e-12);
  EXPECT_NEAR(shapes[0], std::log(0.45), 0.05);
  EXPECT_NEAR(shapes[3], -std::log(across.traits.width / across.traits.length), 1e-12);
  EXPECT_NEAR(shapes[3], std::log(0.45), 0.1);
  EXPECT_NEAR(shapes[4], -shapes[0], 1e-12);
  EXPECT_NEAR(*PlantAxisShape(shapes), std::log(0.45), 0.1);
  // The median does not depend on the order (the middle two's mean for an even count); none under
  // MinAxisShapeLeaves values, and none for leaves about as wide as long (the ratio then cannot tell the axis).
  EXPECT_NEAR(*PlantAxisShape({ std::log(0.4), std::log(0.5), std::log(0.45) }), std::log(0.45), 1e-12);
  EXPECT_FALSE(PlantAxisShape({ std::log(0.4), std::log(0.5) }).has_value());
  const std::vector<double> four{ std::log(0.5), std::log(0.3), std::log(0.4), std::log(0.6) };
  const std::vector<double> reversed(four.rbegin(), four.rend());
  EXPECT_NEAR(*PlantAxisShape(four), 0.5 * (std::log(0.4) + std::log(0.5)), 1e-12);
  EXPECT_EQ(*PlantAxisShape(four), *PlantAxisShape(reversed));
  EXPECT_FALSE(PlantAxisShape({ std::log(0.9), std::log(1.1), std::log(1.05) }).has_value());
  EXPECT_TRUE(PlantAxisShape({ std::log(1.4), std::log(1.5), std::log(1.45) }).has_value());
}

TEST(LeafShape, BladeSampledDenserOnOneSideKeepsItsMidveinAxis)
{
  // A scanner seeing a blade obliquely samples its near side more densely than its far side. An elliptic blade
  // (100 long, 45 wide) is symmetric about both its axes; sampled twice as densely at one margin as at the other,
  // its points' centroid lies off the midvein, a mirror line along the midvein through that point leaves a band of
  // mirror images off the blade, and the line across it looked more symmetric (Length 45, the width). No petiole
  // and no hints: the base may be at either end (the blade is the same at both), the midvein must lie along it.
  const Synthetic uniform = Scan(Blade(0, 100.0), 16000, 0.1, 0.0, Straight(0.0), 0, Eigen::Isometry3d::Identity());
  Synthetic scan = uniform;
  scan.points.clear();
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> keep(0.0, 1.0);
  for (const auto& p : uniform.points)
    if (keep(random) < 0.75 + 0.25 * p.x() / 22.5) // 1 at the right margin (x = 22.5), 0.5 at the left
      scan.points.push_back(Tilted() * p);
  const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  const Eigen::Vector3d base = fit.points[fit.midvein.front()], apex = fit.points[fit.midvein.back()];
  const Eigen::Vector3d along = Tilted().linear() * Eigen::Vector3d::UnitY();
  EXPECT_GT(std::abs((apex - base).normalized().dot(along)), std::cos(3.0 * Pi / 180.0));
  EXPECT_NEAR(fit.traits.length, scan.length, 0.01 * scan.length);
  const double toBase = (base - Tilted() * Eigen::Vector3d::Zero()).norm(),
               toApex = (base - Tilted() * Eigen::Vector3d(0.0, 100.0, 0.0)).norm();
  EXPECT_LT(std::min(toBase, toApex), 0.02 * scan.length);
}

TEST(LeafShape, SymmetryAxisOfAFanThroughItsBase)
{
  // The core step alone: points of the ginkgo fan, the axis through its base, hinted across the fan.
  const LeafGeometry leaf = Blade(1, 50.0);
  std::vector<Eigen::Vector3d> points;
  for (const auto& p : leaf.blade.points)
    points.emplace_back(p.x(), p.y(), 0.0);
  const Eigen::Vector3d axis =
    fit::SymmetryAxis(points, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), Eigen::Vector3d(1.0, 0.2, 0.0), 0.5);
  EXPECT_GT(std::abs(axis.y()), std::cos(2.0 * Pi / 180.0));
}

TEST(LeafShape, ApexPointTurnsASymmetricBladeAround)
{
  // An ellipse is symmetric end to end: the apex hint decides which end is the base.
  const Synthetic scan = Scan(Blade(0, 100.0), 5000, 0.1, 0.0, Straight(0.0), 0, Eigen::Isometry3d::Identity());
  for (double apexY : { 100.0, 0.0 })
  {
    LeafFitParameters options;
    options.apexPoint = Eigen::Vector3d(0.0, apexY, 0.0);
    const LeafFitResult fit = FitLeaf(scan.points, options);
    ASSERT_EQ(fit.error, "");
    EXPECT_LT((fit.points[fit.midvein.back()] - *options.apexPoint).norm(), 2.0);
    EXPECT_LT((fit.points[fit.midvein.front()] - Eigen::Vector3d(0.0, 100.0 - apexY, 0.0)).norm(), 2.0);
  }
}

TEST(LeafShape, BasePointAtThePetiolesEndGivesTheJunction)
{
  const Synthetic scan = Scan(Blade(3, 100.0), 6000, 0.1, 30.0, Straight(0.0), 2, Eigen::Isometry3d::Identity());
  LeafFitParameters options;
  options.basePoint = Eigen::Vector3d(0.0, -30.0, 0.0);
  const LeafFitResult fit = FitLeaf(scan.points, options);
  ASSERT_EQ(fit.error, "");
  EXPECT_EQ(fit.traits.baseFrom, 1);
  EXPECT_LT(fit.points[fit.midvein.front()].norm(), 2.0);
  EXPECT_NEAR(fit.traits.petioleLength, 30.0, 1.5);
}

} // namespace
} // namespace plantmorph

namespace plantmorph
{
namespace
{
/// Poses turning the blade about arbitrary axes (in its plane and out of it), each also moved.
std::vector<Eigen::Isometry3d> ArbitraryPoses()
{
  std::vector<Eigen::Isometry3d> poses;
  std::mt19937_64 random(11);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (int i = 0; i < 6; ++i)
  {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d axis(gauss(random), gauss(random), gauss(random));
    pose.rotate(Eigen::AngleAxisd(0.5 + 1.0 * i, axis.normalized()));
    pose.translation() = Eigen::Vector3d(gauss(random), gauss(random), gauss(random)) * 30.0;
    poses.push_back(pose);
  }
  return poses;
}
} // namespace

TEST(LeafShape, PalmatelyLobedBladeWithoutPetioleHasItsBaseAtTheLobesMeeting)
{
  // Paper 002's five-lobed palmate blade, no petiole and no hints: the middle lobe's tip is acute (its end slices a
  // twentieth of the blade's width, like a stalk), but it is the apex, a terminal lobe with the lateral lobes
  // beginning abruptly beside it; the base is where the lobes meet. The base within 2 % of the length in every pose
  // (a turned leaf puts it at the middle lobe's tip, 95 % away). The midvein's first fifth leaves the base 3.35
  // degrees off the true one and Length is 4.4 % short in every pose: the midvein's own accuracy on this blade,
  // apart from which end is the base.
  const LeafGeometry leaf = Blade(5, 50.0);
  for (const Eigen::Isometry3d& pose : ArbitraryPoses())
  {
    const Synthetic scan = Scan(leaf, 8000, 0.05, 0.0, Straight(0.0), 0, pose);
    Expected e;
    e.degrees = 4.0;
    e.lengthTolerance = 0.05;
    ExpectShape(scan, pose, e);
  }
}

TEST(LeafShape, CordateBladeWithoutPetioleHasItsBaseAtTheSinus)
{
  // Two cordate blades (the cucumber's, and a cordate base with a rounded apex), no petiole and no hints, turned
  // every way: the base is the sinus between the basal lobes.
  for (int preset : { 4, 6 })
  {
    const LeafGeometry leaf = Blade(preset, 100.0);
    for (const Eigen::Isometry3d& pose : ArbitraryPoses())
    {
      const Synthetic scan = Scan(leaf, 8000, 0.1, 0.0, Straight(0.0), 0, pose);
      Expected e;
      e.lengthTolerance = 0.02;
      ExpectShape(scan, pose, e);
    }
  }
}

TEST(LeafShape, ShallowlyLobedBladeWithoutPetioleHasItsApexAtItsTerminalLobe)
{
  // Paper 000's shallowly lobed blade (Fig. 1c), no petiole and no hints, turned every way. Its apex is a blunt
  // terminal lobe, narrow enough (its two end slices 0.05 and 0.09 of the widest) to pass for a stalk; the sinuses
  // beside it (the width falls from 0.52 to 0.46 of the widest, then rises to the lateral lobes) make it the apex.
  const LeafGeometry leaf = Blade(8, 100.0);
  for (const Eigen::Isometry3d& pose : ArbitraryPoses())
    ExpectShape(Scan(leaf, 8000, 0.1, 0.0, Straight(0.0), 0, pose), pose, Expected());
}

TEST(LeafShape, BladesTheOutlineCannotOrientTakeTheirHint)
{
  // Three blades whose points, laid in their plane, give no sign of which end is the base: paper 000's rounded base
  // with an acuminate apex (Fig. 2b; scanned, the drawn-out tip's last thin tenth has almost no points and the slice
  // widths read 0.02, 0.05, 0.10, 0.17 ... 1 ... 0.36 of the widest from the tip, the ginkgo fan's from its base),
  // and paper 002's Fig. 1 and 2 blades (obovate: an ovate blade turned round). ApexPoint at the true apex (or
  // BasePoint at the base) puts them right in every pose.
  for (int preset : { 7, 9, 10 })
  {
    const LeafGeometry leaf = Blade(preset, 100.0);
    const auto poses = ArbitraryPoses();
    for (std::size_t k = 0; k < poses.size(); k += 2)
    {
      const Synthetic scan = Scan(leaf, 8000, 0.1, 0.0, Straight(0.0), 0, poses[k]);
      LeafFitParameters options;
      if (k % 4 == 0)
      {
        const Eigen::Vector2d tip = leaf.blade.points[leaf.midvein.back()];
        options.apexPoint = poses[k] * Eigen::Vector3d(tip.x(), tip.y(), 0.0);
      }
      else
        options.basePoint = poses[k] * Eigen::Vector3d::Zero();
      Expected e;
      e.lengthTolerance = preset == 7 ? 0.15 : 0.01; // the acuminate tip's last thin tenth is hardly scanned
      ExpectShape(scan, poses[k], e, options);
    }
  }
}

TEST(LeafShape, MidveinFollowsTheTerminalLobeBesideOneLateralLobesTip)
{
  // An idealised palmate blade in the fit's own frame (Y along the axis, X across, Z the normal): a terminal lobe
  // 10 wide along Y from 0 to 100, and the tips of the two lateral lobes, 55 long across, at slightly different
  // heights (Y 61-63 on the right, 57-59 on the left), as a scan of a palmately lobed blade has them when its axis is
  // turned by half a degree (the watermelon's lobes reach 2.9 of its 4.3 units of length sideways). Some of the
  // cross-sections hold one tip and not the other: their centres lie some 30 units to one side. The midvein (t = 0)
  // must stay on the terminal lobe's middle: before, the cross-sections' least-squares centre line followed the
  // one-sided slices, and on the watermelon scanned from above the terminal lobe's tip lay off t = 0, where the loop
  // the points draw crossed t = 0 below it (Length -6.5 %).
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Eigen::Vector3d> local;
  const double density = 1.5; // points per unit area
  auto fill = [&](double x0, double x1, double y0, double y1) {
    const int count = static_cast<int>(density * (x1 - x0) * (y1 - y0));
    for (int i = 0; i < count; ++i)
      local.emplace_back(x0 + (x1 - x0) * uniform(random), y0 + (y1 - y0) * uniform(random), 0.05 * gauss(random));
  };
  fill(-5.0, 5.0, 0.0, 100.0);
  fill(5.0, 60.0, 61.0, 63.0);
  fill(-60.0, -5.0, 57.0, 59.0);
  const double spacing = 1.0 / std::sqrt(density);
  fit::CrossSections sections;
  ASSERT_EQ(sections.Build(local, spacing), "");
  for (double y = 2.0; y <= 98.0; y += 2.0)
    EXPECT_LT(std::abs(sections.Intrinsic(Eigen::Vector3d(0.0, y, 0.0)).x()), spacing) << "Y " << y;
}

/// The flat blade scanned in lines across it (along X, `across` apart along Y), each pass's points `step` apart
/// along its lines starting at `phase` (a fraction of the step); one pass per phase, all on the same lines (as two
/// passes tilted to either side of the leaf's length leave them), noise `sigma` along Z.
std::vector<Eigen::Vector3d> LineScans(
  const LeafGeometry& leaf, double across, double step, const std::vector<double>& phases, double sigma)
{
  std::mt19937_64 random(7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (double phase : phases)
    ForEachLatticePoint(
      leaf, step, phase, across, [&](double x, double y) { points.emplace_back(x, y, sigma * gauss(random)); });
  return points;
}

TEST(LeafShape, LobedBladeScannedTwiceAlongTheSameLinesKeepsItsArea)
{
  // The pin oak's lobes, scanned as the benchmark's passes scan them (about 10^4 points a pass): lines `across`
  // apart, points 1.2 times that apart along them (a view tilted 35 degrees), the second pass's points halfway
  // between the first's on the same lines (the nearest neighbour half as far as the lines are apart). The loop
  // through the outermost points lies inside the margin by a gap the smooth margins cannot measure (they do not
  // follow the lobes): it is measured by the points' count, each point standing for 1 / density of the blade.
  // Area within 1 % from one pass and from two (two were -2.3 % when the gap was measured against the smooth
  // margins).
  const LeafGeometry leaf = Blade(2, 100.0);
  const double area = BladeArea(leaf), across = std::sqrt(area / 1e4);
  for (const std::vector<double>& phases : { std::vector<double>{ 0.0 }, std::vector<double>{ 0.0, 0.5 } })
  {
    const LeafFitResult fit = FitLeaf(LineScans(leaf, across, 1.2 * across, phases, 0.1), LeafFitParameters());
    ASSERT_EQ(fit.error, "");
    EXPECT_NEAR(fit.traits.area, area, 0.01 * area) << "passes " << phases.size();
  }
}

TEST(LeafShape, LobedBladesSampledAtRandomKeepTheirArea)
{
  // The lobed blade and the pin oak (100 long), 8000 points uniform at random by area (noise 0.1): their lobes keep
  // the loop off the smooth margins, so the area comes from the points' density. A kernel's sum taken at a point
  // holds the point itself, which a lattice's sum needs and random points' does not (15 % of the density at the
  // nearest-neighbour spacing random points have), and random points leave gaps twice a lattice's at the same
  // density, read as holes when measured in nearest-neighbour spacings: the area came out 9 % short (lobed 4054
  // against 4471), where a scanner's lattice of the same density is within 1 %. Each sample within 1.5 % of the
  // blade's area (its own count's statistics), the mean over four samples within 0.5 %.
  for (int preset : { 8, 2 })
  {
    const LeafGeometry leaf = Blade(preset, 100.0);
    const double area = BladeArea(leaf);
    double mean = 0.0;
    for (unsigned seed = 3; seed < 7; ++seed)
    {
      const Synthetic scan = Scan(leaf, 8000, 0.1, 0.0, Straight(0.0), 0, Tilted(), seed);
      const LeafFitResult fit = FitLeaf(scan.points, LeafFitParameters());
      ASSERT_EQ(fit.error, "");
      EXPECT_NEAR(fit.traits.area, area, 0.015 * area) << "preset " << preset << ", seed " << seed;
      mean += fit.traits.area / 4.0;
    }
    EXPECT_NEAR(mean, area, 0.005 * area) << "preset " << preset;
  }
}

TEST(LeafShape, LobeSeenBeyondAShadowAcrossItsNeckIsKept)
{
  // The lobed blade (preset Lobed, 100 long) at a plant scan's density (8000 points, 0.4 apart) and 0.1 noise, with a
  // shadow 3 wide (7 spacings) across the neck of its right basal lobe, from below the base's right side to beyond
  // the sinus above the lobe, as an occluding twig casts it on a leaf of a scanned plant: the lobe's points (under
  // 5 % of the blade's) are a part of their own, a gap narrower than the lobe from the blade. They are the blade's:
  // every one an inlier, and the blade's area is the area the points sample (the band in the shadow left out, within
  // 1.5 % of the blade's area: the notch the loop draws into the shadow).
  const LeafGeometry leaf = Blade(8, 100.0);
  const double step = std::sqrt(BladeArea(leaf) / 8000.0);
  Synthetic whole;
  whole.points = LineScans(leaf, step, 1.2 * step, { 0.0 }, 0.1);
  const Eigen::Vector2d a(8.0, 2.0), b(30.0, 31.0), along = (b - a).normalized();
  std::vector<Eigen::Vector3d> points;
  std::vector<unsigned char> lobe;
  for (const Eigen::Vector3d& p : whole.points)
  {
    const Eigen::Vector2d q = p.head<2>() - a;
    const double beyond = along.x() * q.y() - along.y() * q.x(); // < 0: right of the line, towards the lobe
    const double at = std::clamp(q.dot(along), 0.0, (b - a).norm());
    if ((q - at * along).norm() < 1.5)
      continue;
    points.push_back(Tilted() * p);
    lobe.push_back(beyond < 0.0 && p.y() < b.y() ? 1 : 0);
  }
  const double lobeCount = static_cast<double>(std::count(lobe.begin(), lobe.end(), 1));
  ASSERT_GT(lobeCount, 0.01 * points.size());
  ASSERT_LT(lobeCount, 0.05 * points.size());
  const LeafFitResult fit = FitLeaf(points, LeafFitParameters());
  ASSERT_EQ(fit.error, "");
  int lobeInliers = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    lobeInliers += lobe[i] && fit.inlier[i] ? 1 : 0;
  EXPECT_EQ(lobeInliers, static_cast<int>(lobeCount));
  const double area = BladeArea(leaf), seen = area * points.size() / whole.points.size();
  EXPECT_NEAR(fit.traits.area, seen, 0.015 * area) << "blade " << area << ", seen " << seen;
}

TEST(LeafShape, PalmateBladeSeenDenserWhereTwoViewsOverlapKeepsItsArea)
{
  // The watermelon's blade (palmate, five sub-lobed lobes; 100 long) at a plant scan's density: one view's lines
  // across it (about 8000 points, 1.2 times as far apart along the lines as the lines are), and a second view's on
  // the same lines, halfway between the first's points, over bands 6 of the lines' spacings wide and 12 apart, as
  // the part of a leaf that two views of a plant both see, broken by the twigs' shadows. The second view's points add
  // no area: the fit must give the area of the first view's alone, within 1 %. A point stands for one over the
  // density of its window, the kernel's mean over places spread evenly across the window (not over the points, which
  // the dense bands' outnumber: their mean density left the blade 5.8 % short of the first view's fit; the mean of
  // one over the density at the points, 1.7 % short; the places' mean, 0.3 % over).
  const LeafGeometry leaf = Blade(11, 100.0);
  const double area = BladeArea(leaf), across = std::sqrt(area / 8000.0 / 1.2);
  std::vector<Eigen::Vector3d> one = LineScans(leaf, across, 1.2 * across, { 0.0 }, 0.1), both = one;
  for (const Eigen::Vector3d& p : LineScans(leaf, across, 1.2 * across, { 0.5 }, 0.1))
    if (std::fmod(p.x() + 1000.0 * across, 12.0 * across) < 6.0 * across)
      both.push_back(p);
  for (auto* points : { &one, &both })
    for (Eigen::Vector3d& p : *points)
      p = Tilted() * p;
  const LeafFitResult alone = FitLeaf(one, LeafFitParameters()), fit = FitLeaf(both, LeafFitParameters());
  ASSERT_EQ(alone.error, "");
  ASSERT_EQ(fit.error, "");
  EXPECT_NEAR(alone.traits.area, area, 0.01 * area);
  EXPECT_NEAR(fit.traits.area, alone.traits.area, 0.01 * alone.traits.area)
    << "points " << both.size() << " and " << one.size() << ", blade " << area;
}

/// The blade's margin as segments in the blade's plane: its right side from base to apex, then its left side.
std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> Margin(const LeafGeometry& leaf)
{
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> margin;
  for (const std::vector<int>* side : { &leaf.rightMargin, &leaf.leftMargin })
    for (std::size_t k = 0; k + 1 < side->size(); ++k)
      margin.emplace_back(leaf.blade.points[(*side)[k]], leaf.blade.points[(*side)[k + 1]]);
  return margin;
}

/// The distance from p to the nearest of the margin's segments.
double MarginDistance(const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& margin, const Eigen::Vector2d& p)
{
  double best = 1e300;
  for (const auto& [a, b] : margin)
  {
    const double along = std::clamp((p - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-300), 0.0, 1.0);
    best = std::min(best, (a + along * (b - a) - p).norm());
  }
  return best;
}

TEST(LeafShape, BladeSeenByOneViewOnlyNearItsMarginKeepsItsArea)
{
  // A plant scanned from several sides: the neighbouring leaves hide a leaf's margins from some of the views, so its
  // points thin out towards the margin. The lobed blade, the pin oak and the watermelon (100 long; lobes keep the
  // loop off the smooth margins, so the area comes from the points' count) at a plant scan's density: one view's
  // lines across the whole blade (about 8000 points), a second view's on the same lines, halfway between the
  // first's points, wherever the blade lies deeper than `band` (3 to 8) inside its margin. The second view's points
  // add no area. With the density read only 4 sigma deep (about 7 here) the thinner band was counted at the inside's
  // density: the blades came out 2-15 % smaller than the first view's alone (mean 5.6 %, the pin oak -15.4 % with the
  // band 3 wide). Read from 2 sigma deep, they come out 0-8 % smaller (mean 3.4 %): better, not yet right (a density
  // that changes within a window of 3 tiles is averaged over it).
  double sum = 0.0;
  int cases = 0;
  for (int preset : { 8, 2, 11 })
  {
    const LeafGeometry leaf = Blade(preset, 100.0);
    const double area = BladeArea(leaf), across = std::sqrt(area / 8000.0 / 1.2);
    std::vector<Eigen::Vector3d> one = LineScans(leaf, across, 1.2 * across, { 0.0 }, 0.1);
    const std::vector<Eigen::Vector3d> second = LineScans(leaf, across, 1.2 * across, { 0.5 }, 0.1);
    const auto margin = Margin(leaf);
    std::vector<double> depth;
    for (const Eigen::Vector3d& p : second)
      depth.push_back(MarginDistance(margin, p.head<2>()));
    for (Eigen::Vector3d& p : one)
      p = Tilted() * p;
    const LeafFitResult alone = FitLeaf(one, LeafFitParameters());
    ASSERT_EQ(alone.error, "");
    EXPECT_NEAR(alone.traits.area, area, 0.01 * area) << "preset " << preset;
    for (double band : { 3.0, 4.0, 6.0, 8.0 })
    {
      std::vector<Eigen::Vector3d> both = one;
      for (std::size_t k = 0; k < second.size(); ++k)
        if (depth[k] > band)
          both.push_back(Tilted() * second[k]);
      const LeafFitResult fit = FitLeaf(both, LeafFitParameters());
      ASSERT_EQ(fit.error, "");
      const double error = std::abs(fit.traits.area / alone.traits.area - 1.0);
      EXPECT_LT(error, 0.08) << "preset " << preset << ", band " << band << ": " << fit.traits.area << " against "
                             << alone.traits.area;
      sum += error;
      ++cases;
    }
  }
  EXPECT_LT(sum / cases, 0.04) << "the mean error over the " << cases << " cases";
}

TEST(LeafShape, BladeEndsWithinASpacingOfTheStalksJunction)
{
  // In intrinsic coordinates (t across, s along the midvein; spacing 1), an elliptic blade 100 long and 44 wide on
  // a scanner's grid, its base at s = 0, and a stalk of radius 1 leaving it 30 degrees below its plane. The
  // stalk's top (the side a scanner sees) lies within a radius of the blade's plane for 1 / tan 30 radii past the
  // junction, 1 / sin 30 = 2 radii back along the midvein: its samples there (two a line, at t = +-0.5) are taken
  // as the blade's. The lowest samples then do not thin out like a free tip's, and the tip extrapolated from them
  // lay 2.0 spacings beyond the junction (Length +2 %); the blade ends within a spacing of it. Without a junction
  // the tip is extrapolated beyond the lowest samples as before.
  std::vector<Eigen::Vector2d> ts;
  for (double s = 0.5; s < 100.0; s += 1.0)
  {
    const double half = 22.0 * std::sqrt(1.0 - (s - 50.0) * (s - 50.0) / 2500.0);
    for (double t = std::floor(-half) + 0.5; t <= half; t += 1.0)
      if (std::abs(t) <= half)
        ts.emplace_back(t, s);
  }
  for (double s = -0.5; s > -2.0; s -= 1.0)
    for (double t : { -0.5, 0.5 })
      ts.emplace_back(t, s);
  for (const bool stalk : { false, true })
  {
    fit::Outline outline;
    ASSERT_EQ(fit::FitOutline(ts, LeafFitParameters(), 1.0, outline), "");
    if (stalk)
    {
      outline.junction = 0.0;
      outline.junctionMeetsPlane = true;
    }
    ASSERT_FALSE(fit::TraceContour(ts, 1.0, true, outline).right.empty());
    if (stalk)
      EXPECT_GE(outline.base, -1.0 - 1e-9) << "the blade's tip extrapolated past the junction";
    else
      EXPECT_LT(outline.base, -1.5) << "without a junction the tip lies beyond the lowest samples";
    EXPECT_NEAR(outline.apex, 100.0, 1.0);
  }
}

TEST(LeafShape, SinusClosedByTheStalksFirstSpacingsEndsAtTheJunction)
{
  // In intrinsic coordinates (spacing 1), a cordate blade on a grid: its sinus a V with its bottom at s = 0, the
  // basal lobes reaching 11.5 below it. A stalk leaves the bottom below the blade's plane; its first spacings, within
  // the opening's ball of the blade, are counted as blade: a strip 3 wide down to s = -6.5. The points close across
  // the midvein down there, and the sinus's bottom was taken at the strip's end (the cordate blade on a flat leaf
  // with a petiole scanned from two positions: base 2.4 % of the length off, Length +2.3 %). Where the stalk's
  // axis meets the blade's plane above that, and only the stalk's width lies across the midvein between, the
  // bottom is the junction (0.8 %, -0.9 %). A blade whose sinus really reaches below the junction keeps its
  // bottom; without the junction's plane, so does the strip.
  auto bottom = [](double sinus, bool stalk, bool meets) {
    std::vector<Eigen::Vector2d> ts;
    for (double s = sinus - 11.5; s < 100.0; s += 1.0)
    {
      const double half = 28.0 * std::sqrt(std::max(0.0, 1.0 - (s - 40.0) * (s - 40.0) / (60.0 * 60.0)));
      for (double t = -std::floor(half); t <= half; t += 1.0)
        if (s >= sinus - std::abs(t))
          ts.emplace_back(t, s);
    }
    for (double s = -0.5; stalk && s > -7.0; s -= 1.0)
      for (double t : { -1.0, 0.0, 1.0 })
        if (s < -std::abs(t))
          ts.emplace_back(t, s);
    fit::Outline outline;
    EXPECT_EQ(fit::FitOutline(ts, LeafFitParameters(), 1.0, outline), "");
    outline.junction = 0.0;
    outline.junctionMeetsPlane = meets;
    outline.stalkHalfWidth = 1.0;
    EXPECT_FALSE(fit::TraceContour(ts, 1.0, true, outline).right.empty());
    EXPECT_NEAR(outline.apex, 100.0, 1.0);
    return outline.base;
  };
  EXPECT_NEAR(bottom(0.0, true, true), 0.0, 1e-9) << "the stalk's strip below the junction";
  EXPECT_NEAR(bottom(0.0, true, false), -6.5, 1.0) << "no junction in the blade's plane: the strip is blade";
  EXPECT_NEAR(bottom(-6.5, false, true), -6.5, 1.0) << "the blade's own sinus below the junction";
}

TEST(LeafShape, JunctionBelowASinusCrossingKeepsTheBasalLobes)
{
  // In intrinsic coordinates (spacing 1), a cordate blade on a grid: its sinus a notch 10 wide with its bottom at
  // s = 0, the basal lobes beside it reaching 11.5 below, and a stalk's junction 1.5 below the bottom, where the
  // stalk's axis meets the blade's plane (placed to about a radius). The loop crosses the midvein a spacing or so
  // above the junction, too close for a gap between them, and no point lies within 4 of the midvein there: the base
  // was read as a cusp running down to the junction and both lobes were cut off (the curled cucumber from two
  // positions at 0.1 % noise: Area -6.8 %). The lobes reaching below the junction on both sides make it a sinus:
  // the contour keeps them and encloses the points' area.
  std::vector<Eigen::Vector2d> ts;
  for (double s = -11.5; s < 100.0; s += 1.0)
  {
    const double half = 28.0 * std::sqrt(std::max(0.0, 1.0 - (s - 40.0) * (s - 40.0) / (60.0 * 60.0)));
    for (double t = -std::floor(half); t <= half; t += 1.0)
      if (s >= 0.0 || std::abs(t) >= 5.0)
        ts.emplace_back(t, s);
  }
  fit::Outline outline;
  ASSERT_EQ(fit::FitOutline(ts, LeafFitParameters(), 1.0, outline), "");
  outline.junction = -1.5;
  outline.junctionMeetsPlane = true;
  outline.stalkHalfWidth = 1.0;
  const fit::Contour contour = fit::TraceContour(ts, 1.0, true, outline);
  ASSERT_FALSE(contour.right.empty());
  double lowest = 1e300;
  for (const auto* side : { &contour.right, &contour.left })
    for (const auto& p : *side)
      lowest = std::min(lowest, p.y());
  EXPECT_LT(lowest, -9.0) << "the basal lobes were cut off";
  // Each grid point stands for one unit of area.
  std::vector<Eigen::Vector2d> polygon(contour.right.begin(), contour.right.end());
  polygon.insert(polygon.end(), contour.left.rbegin(), contour.left.rend());
  std::vector<int> loop(polygon.size());
  std::iota(loop.begin(), loop.end(), 0);
  EXPECT_NEAR(
    std::abs(PolygonArea(polygon, loop)), static_cast<double>(ts.size()), 0.02 * static_cast<double>(ts.size()));
  EXPECT_GT(outline.base, -2.5) << "the base below the sinus's bottom";
}

TEST(LeafShape, BladeWiderThanItsStalkAtItsLowestLineEndsAtTheJunction)
{
  // In intrinsic coordinates (spacing 1), an elliptic blade 100 long and 44 wide, its base at s = 0 where a stalk
  // of half-width 1 meets it, scanned in lines across it 1.8 apart along s, points a spacing apart along them; the
  // first line falls on the stalk at s = -0.2 (taken into the stalk, not the blade), the next on the blade at
  // s = 1.6, already 12 wide. Lines hold their samples at one s, so the lowest do not thin out like a free tip's:
  // the tip extrapolated from them lay 1.4 spacings inside the blade (on the benchmark's curled watermelon
  // scanned obliquely 1.4 % of the length, its junction within 0.3 % of the true base). A blade wider than the stalk
  // there (more than its width and a spacing) does not narrow to a free tip between its lowest line and the
  // stalk: it ends at the junction. Where its lowest samples are no wider than the stalk (the stalk's own top, or a
  // narrow base) or no junction lies below the tip, the tip is extrapolated as before.
  auto blade = [](double narrowTo) {
    std::vector<Eigen::Vector2d> ts;
    for (double s = 1.6; s < 100.0; s += 1.8)
    {
      const double ellipse = 22.0 * std::sqrt(1.0 - (s - 50.0) * (s - 50.0) / 2500.0);
      const double half = s < narrowTo ? std::min(1.0, ellipse) : ellipse;
      for (double t = std::floor(-half) + 0.5; t <= half; t += 1.0)
        if (std::abs(t) <= half)
          ts.emplace_back(t, s);
    }
    return ts;
  };
  auto base = [](const std::vector<Eigen::Vector2d>& ts, double junction, double half) {
    fit::Outline outline;
    EXPECT_EQ(fit::FitOutline(ts, LeafFitParameters(), 1.0, outline), "");
    outline.junction = junction;
    outline.stalkHalfWidth = half;
    EXPECT_FALSE(fit::TraceContour(ts, 1.0, true, outline).right.empty());
    return outline.base;
  };
  const std::vector<Eigen::Vector2d> wide = blade(0.0);
  const double free = base(wide, std::nan(""), 1.0);
  EXPECT_GT(free, 0.5) << "without a junction the tip is extrapolated beyond the lowest line";
  EXPECT_NEAR(base(wide, 0.0, 1.0), 0.0, 1e-9) << "the wide blade ends at the junction";
  EXPECT_EQ(base(wide, 0.0, 6.0), free) << "a stalk as wide as the blade's lowest line";
  EXPECT_EQ(base(wide, 2.0, 1.0), free) << "a junction above the extrapolated tip";
  // A base whose two lowest lines are no wider than the stalk (its top seen in two columns, or a narrow base): the
  // junction does not end it.
  const std::vector<Eigen::Vector2d> narrow = blade(4.0);
  EXPECT_EQ(base(narrow, 0.0, 1.0), base(narrow, std::nan(""), 1.0)) << "a base as narrow as the stalk";
}

} // namespace plantmorph

namespace plantmorph
{

namespace
{

/// The farthest a point of the region the blade is meshed in (the contour, or the smooth margins when there is
/// none) lies from the nearest of `ts`, sampled every half spacing (spacing 1).
double FarthestFromThePoints(const std::vector<Eigen::Vector2d>& ts, const fit::Contour& contour, const fit::Outline& o)
{
  std::vector<Eigen::Vector2d> polygon;
  if (contour.right.empty())
  {
    for (double s = o.s0; s <= o.s1; s += 0.25)
      polygon.push_back({ o.Right(s), s });
    for (double s = o.s1; s >= o.s0; s -= 0.25)
      polygon.push_back({ o.Left(s), s });
  }
  else
  {
    polygon.assign(contour.right.begin(), contour.right.end());
    polygon.insert(polygon.end(), contour.left.rbegin(), contour.left.rend());
  }
  auto inside = [&](const Eigen::Vector2d& p) {
    bool in = false;
    for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++)
      if ((polygon[i].y() > p.y()) != (polygon[j].y() > p.y()) &&
        p.x() < polygon[i].x() +
            (polygon[j].x() - polygon[i].x()) * (p.y() - polygon[i].y()) / (polygon[j].y() - polygon[i].y()))
        in = !in;
    return in;
  };
  double farthest = 0.0;
  for (double s = o.s0; s <= o.s1; s += 0.5)
    for (double t = -40.0; t <= 40.0; t += 0.5)
      if (inside({ t, s }))
      {
        double nearest = 1e300;
        for (const auto& q : ts)
          nearest = std::min(nearest, (q - Eigen::Vector2d(t, s)).squaredNorm());
        farthest = std::max(farthest, std::sqrt(nearest));
      }
  return farthest;
}

} // namespace

TEST(LeafShape, BladeStaysOnThePointsWhereTheirLoopGivesNoContour)
{
  // In intrinsic coordinates (spacing 1): a blade 70 long and 44 wide from s = 30 to 100 on a grid, below it a bare
  // base: a strip of points 3 wide along the midrib that wanders off t = 0 (t from 0.5 to 2.5 up to s = 15, from
  // 3.5 to 5.5 above), and single points 8 apart along the two margins of a wedge (t = +-0.7 s), which the smooth
  // margins follow (a sugar beet's base scanned along its midrib and its margins only). The loop the points draw
  // crosses t = 0 where the strip leaves it, so it gives no contour; the smooth margins' wedge then spread the
  // blade over ground no point samples, 7.8 spacings from the nearest. The blade keeps to the loop: no part of it
  // farther from a point than the discs' 2.5 spacings, the gap to the margin (under a spacing on a grid) and the
  // spacing the margins may pass the loop (3.5 here).
  std::vector<Eigen::Vector2d> ts;
  for (double s = 30.5; s < 100.0; s += 1.0)
  {
    const double half = 22.0 * std::sqrt(1.0 - (s - 30.0) * (s - 30.0) / 4900.0);
    for (double t = std::floor(-half) + 0.5; t <= half; t += 1.0)
      ts.emplace_back(t, s);
  }
  for (double s = 0.5; s < 30.0; s += 1.0)
    for (double t : { 0.5, 1.5, 2.5 })
      ts.emplace_back(s < 15.0 ? t : t + 3.0, s);
  for (double s = 4.0; s < 30.0; s += 8.0)
    for (double side : { -1.0, 1.0 })
      ts.emplace_back(side * 0.7 * s, s);
  fit::Outline outline;
  ASSERT_EQ(fit::FitOutline(ts, LeafFitParameters(), 1.0, outline), "");
  const fit::Outline smooth = outline;
  const fit::Contour contour = fit::TraceContour(ts, 1.0, true, outline);
  EXPECT_LT(FarthestFromThePoints(ts, contour, outline), 4.5) << "the blade spreads beyond the points' loop";
  EXPECT_GT(FarthestFromThePoints(ts, fit::Contour(), smooth), 4.5) << "the smooth margins do not test the case";
}

} // namespace plantmorph

namespace plantmorph
{
namespace
{
/// The base's offset (s, spacing 1) above the true base at s = 0 of a blade 100 long whose half-width is `half(s)`,
/// scanned in lines across it one spacing apart (the first `shift` above the base), points `along` apart on each
/// starting `phase` of that from the midvein; fitted in intrinsic coordinates. `round`: the offset a rounded tip's
/// extrapolation (q = 1.5) gives.
double BaseOffset(const std::function<double(double)>& half, double along, double phase, double shift, double& round)
{
  std::vector<Eigen::Vector2d> ts;
  for (double s = shift; s < 100.0; s += 1.0)
  {
    const double h = half(s);
    for (double t = (std::floor(-h / along - phase) + phase) * along; t <= h; t += along)
      if (std::abs(t) <= h)
        ts.emplace_back(t, s);
  }
  fit::Outline outline;
  EXPECT_EQ(fit::FitOutline(ts, LeafFitParameters(), 1.0, outline), "");
  EXPECT_FALSE(fit::TraceContour(ts, 1.0, true, outline).right.empty());
  round = outline.roundS0;
  return outline.base;
}
} // namespace

TEST(LeafShape, CuspBaseScannedInLinesIsExtrapolatedAsACusp)
{
  // A base narrowing to a cusp, half-width 0.04 s^2 (the ginkgo's at the benchmark's scans, in spacings), scanned
  // in lines: near its tip it is narrower than the step between a line's points, so the lowest samples are single
  // points of the column nearest the midvein, reaching down as far as the cusp is wider than that column's offset.
  // Extrapolated as a rounded tip (q = 1.5) from them, the base lay 2.05 spacings (2 % of the length) inside the
  // blade on average over 40 positions of the lines and columns (the benchmark's six ginkgo rows without a petiole
  // read -0.17 to -1.45 %). The width profile above the tip says it is a cusp (q = 1.5 p, p its exponent): on
  // average the base is within a spacing (1 % of the length, the Length goal; 0.58 now). A rounded base (an
  // ellipse) and a wedge keep q = 1.5: their base does not move.
  auto cusp = [](double s) { return 0.04 * s * s * std::sqrt(std::max(0.0, 1.0 - s / 100.0)); };
  auto ellipse = [](double s) { return 22.0 * std::sqrt(std::max(0.0, 1.0 - (s - 50.0) * (s - 50.0) / 2500.0)); };
  auto wedge = [](double s) { return 0.5 * s * std::sqrt(std::max(0.0, 1.0 - s / 100.0)); };
  double offset = 0.0, roundOffset = 0.0;
  int count = 0;
  for (double along : { 1.0, 1.2 })
    for (double phase = 0.05; phase < 0.5; phase += 0.1)
      for (double shift : { 0.0, 0.25, 0.5, 0.75 })
      {
        double round = 0.0;
        offset += BaseOffset(cusp, along, phase, shift, round);
        roundOffset += round;
        ++count;
        for (const auto& half : { std::function<double(double)>(ellipse), std::function<double(double)>(wedge) })
        {
          const double base = BaseOffset(half, along, phase, shift, round);
          EXPECT_EQ(base, round) << "a rounded base or a wedge: along " << along << " phase " << phase;
        }
      }
  EXPECT_GT(roundOffset / count, 1.5) << "a rounded tip's extrapolation lies inside the cusp";
  EXPECT_LT(std::abs(offset / count), 1.0) << "the cusp's base (mean over the lines' positions)";
}
} // namespace plantmorph

namespace plantmorph
{
namespace
{
/// The area inside a contour: the right margin from base to apex, then the left one back.
double AreaInside(const fit::Contour& contour)
{
  std::vector<Eigen::Vector2d> loop(contour.right.begin(), contour.right.end());
  loop.insert(loop.end(), contour.left.rbegin(), contour.left.rend());
  double twice = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i)
  {
    const Eigen::Vector2d& a = loop[i];
    const Eigen::Vector2d& b = loop[(i + 1) % loop.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * std::abs(twice);
}

/// An elliptic blade in intrinsic coordinates (spacing 1): 100 long, 56 wide, on a unit lattice, except where
/// t > `from`, which a lattice `sparse` apart samples (a scanner's lines far apart at a grazing angle).
std::vector<Eigen::Vector2d> PartlySparseEllipse(double from, double sparse)
{
  std::vector<Eigen::Vector2d> ts;
  auto inside = [](double t, double s) { return (t / 28.0) * (t / 28.0) + (s - 50.0) * (s - 50.0) / 2500.0 < 1.0; };
  for (double s = 0.3; s < 100.0; s += 1.0)
    for (double t = -27.6; t < from; t += 1.0)
      if (inside(t, s))
        ts.emplace_back(t, s);
  for (double s = 0.3; s < 100.0; s += sparse)
    for (double t = from + 0.4 + sparse / 2.0; t < 28.0; t += sparse)
      if (inside(t, s))
        ts.emplace_back(t, s);
  return ts;
}

double TracedArea(const std::vector<Eigen::Vector2d>& ts)
{
  fit::Outline outline;
  if (!fit::FitOutline(ts, LeafFitParameters(), 1.0, outline).empty())
    return 0.0;
  return AreaInside(fit::TraceContour(ts, 1.0, true, outline));
}
} // namespace

TEST(LeafShape, ASparselySampledPartOfTheBladeIsKept)
{
  // The right half of the blade sampled on a lattice 5 or 6 spacings apart (a scanner's lines at a grazing angle):
  // the closing's discs of 2.5 spacings do not reach across, and much of that half was left out (the contour 14 and
  // 46 % short of the ellipse's area). Its points are joined, and its margin taken 0.4 of its gap beyond them (3.5
  // and 2.8 % short: the contour cuts the chords between its outermost points).
  const double truth = Pi * 28.0 * 50.0;
  for (double sparse : { 5.0, 6.0 })
  {
    const std::vector<Eigen::Vector2d> ts = PartlySparseEllipse(0.0, sparse);
    EXPECT_FALSE(fit::FindSparseParts(ts, 1.0).bridges.empty());
    EXPECT_NEAR(TracedArea(ts) / truth, 1.0, 0.04) << "lines " << sparse << " apart";
  }
  // Evenly sampled, the blade has no sparse part, at any lattice's spacing (the median gap sets the scale).
  EXPECT_TRUE(fit::FindSparseParts(PartlySparseEllipse(30.0, 1.0), 1.0).bridges.empty());
  std::vector<Eigen::Vector2d> coarse = PartlySparseEllipse(30.0, 1.0);
  for (auto& p : coarse)
    p *= 4.0;
  EXPECT_TRUE(fit::FindSparseParts(coarse, 1.0).bridges.empty());
}

TEST(LeafShape, AStrayGroupOfPointsBesideTheBladeIsNotJoinedToIt)
{
  // A blade sampled evenly, and beside its right flank, 2 to 3 spacings off, two rows of 6 points 5 apart (a piece
  // of a neighbouring leaf): the group is sparse, but too small to be a part of the blade, and the contour is the
  // blade's alone.
  const std::vector<Eigen::Vector2d> blade = PartlySparseEllipse(30.0, 1.0);
  std::vector<Eigen::Vector2d> ts = blade;
  for (int row = 0; row < 2; ++row)
    for (int k = 0; k < 6; ++k)
      ts.emplace_back(30.5 + 5.0 * row, 25.0 + 5.0 * k);
  EXPECT_TRUE(fit::FindSparseParts(ts, 1.0).bridges.empty());
  EXPECT_NEAR(TracedArea(ts) / TracedArea(blade), 1.0, 0.01);
}

} // namespace plantmorph
