// SPDX-License-Identifier: GPL-3.0-or-later
// Internal steps of plantmorph::FitLeaf (LeafFit.h), shared by its source files. Not installed, not API.
#pragma once

#include "LeafFit.h"
#include "LeafFitSplines.h"
#include "LeafShape.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace plantmorph
{
namespace fit
{

/// The leaf's local frame: X to the right, Y from the base to the apex, Z the upper side (X x Y = Z).
struct Frame
{
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity(); ///< columns X, Y, Z
  Eigen::Vector3d Local(const Eigen::Vector3d& p) const { return this->axes.transpose() * (p - this->origin); }
  Eigen::Vector3d World(const Eigen::Vector3d& q) const { return this->origin + this->axes * q; }
};

/// The points sorted into square buckets `width` wide from `origin` over `nx` by `ny` of them (a counting sort):
/// bucket c holds the points order[first[c]] .. order[first[c + 1] - 1]. Near(p, k, visit) visits the points of the
/// buckets within k of p's.
struct Buckets
{
  Eigen::Vector2d origin;
  double width;
  int nx, ny;
  std::vector<std::size_t> first, order;
  Buckets(const std::vector<Eigen::Vector2d>& ts, const Eigen::Vector2d& from, double w, double spanX, double spanY)
    : origin(from)
    , width(w)
    , nx(static_cast<int>(spanX / w) + 1)
    , ny(static_cast<int>(spanY / w) + 1)
    , first(static_cast<std::size_t>(nx) * ny + 1, 0)
    , order(ts.size())
  {
    for (const auto& p : ts)
      ++first[Of(p) + 1];
    for (std::size_t c = 0; c + 1 < first.size(); ++c)
      first[c + 1] += first[c];
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t k = 0; k < ts.size(); ++k)
      order[next[Of(ts[k])]++] = k;
  }
  std::size_t Of(const Eigen::Vector2d& p) const
  {
    return static_cast<std::size_t>(std::clamp(static_cast<int>((p.x() - origin.x()) / width), 0, nx - 1)) +
      static_cast<std::size_t>(nx) * std::clamp(static_cast<int>((p.y() - origin.y()) / width), 0, ny - 1);
  }
  template <typename Visit>
  void Near(const Eigen::Vector2d& p, int k, const Visit& visit) const
  {
    const std::size_t b = Of(p);
    const int i0 = static_cast<int>(b % nx), j0 = static_cast<int>(b / nx);
    for (int j = std::max(0, j0 - k); j <= std::min(ny - 1, j0 + k); ++j)
      for (int i = std::max(0, i0 - k); i <= std::min(nx - 1, i0 + k); ++i)
      {
        const std::size_t c = static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * j;
        for (std::size_t m = first[c]; m < first[c + 1]; ++m)
          visit(order[m]);
      }
  }
};

/// Checks the raw points: count, finite coordinates, not a line, not a blob. Empty string: usable.
std::string ValidateCloud(const std::vector<Eigen::Vector3d>& points);

/// Statistical outlier removal and the largest connected parts (and the sheets beside the largest, a gap no wider than
/// their own extent from it); keep[i] = 1 for kept points. Sets `spacing` (the
/// median nearest-neighbour distance of the kept points).
/// The neighbour searches run through `parallel`.
std::string CleanCloud(const std::vector<Eigen::Vector3d>& points, double outlierSigma,
  std::vector<unsigned char>& keep, double& spacing, const ParallelFor& parallel = SerialFor);

/// Whether a short stalk found on a leaf's points (`points`, the stalk's among them) is the blade's own drawn-out
/// tip: a trail a point or two wide looks the same whether it is a stalk or the last part of an acuminate apex at the
/// scan's resolution. The stalk is the tip when it is shorter than 0.15 of the leaf's extent along the line from the
/// centroid to its junction and the leaf's narrow end there is drawn out, as BaseAtPlusY's narrow-end test says of
/// an apex (not a fan's base, not opposite a square end, not of constant width).
bool StalkIsTheBladesTip(const std::vector<Eigen::Vector3d>& points, const Petiole& petiole, double spacing);

/// The frame of the blade's points (base and axis chosen as LeafFit.h says; `petiole` found on them and the
/// petiole's points); baseFrom one of BaseFromShape, BaseFromPoint, BaseFromPetiole, BaseFromGuess (LeafFit.h),
/// `guess` saying why a guess (else None); `stalkWidth` true when the shape put the base at a narrow end for its
/// constant width alone (LeafFitResult).
/// Its searches run through `parallel` (the frame does not depend on the threads).
Frame LeafFrame(const std::vector<Eigen::Vector3d>& points, const LeafFitParameters& options, double spacing,
  const Petiole& petiole, int& baseFrom, BaseGuess& guess, bool& stalkWidth, const ParallelFor& parallel = SerialFor);

/// Smoothed cross-sections along the leaf (in local coordinates) and the intrinsic coordinates they give.
class CrossSections
{
public:
  /// From local points (X, Y, Z) `spacing` apart. Empty string on success.
  std::string Build(const std::vector<Eigen::Vector3d>& local, double spacing);
  /// (t, s) of a local point.
  Eigen::Vector2d Intrinsic(const Eigen::Vector3d& q) const;

private:
  void Section(double Y, double& angle, double& c0, double& c1, double& c2, double& centre) const;
  Eigen::Vector3d MidveinAt(double Y) const;
  /// The midvein's position across the slices (Centre), robust to a slice whose centre lies far off its neighbours'.
  bool FitCentre(int intervals, const std::vector<double>& Y, const std::vector<double>& centre,
    const std::vector<double>& w, double lambda, double spacing);
  PenalizedSpline1D Angle, C0, C1, C2, Centre;
  double Y0 = 0.0, Y1 = 1.0;
  std::vector<double> TableY, TableS; // the midvein's arc length from Y0
};

/// The outline in (t, s): margins t = phi(s) g(s) between the base s0 and the apex s1.
struct Outline
{
  double s0 = 0.0, s1 = 1.0;     ///< the smooth margins' ends (the blade's lowest and highest s)
  double base = 0.0, apex = 1.0; ///< the midvein's ends (a cordate blade's base is at its sinus, above s0)
  /// Where s0 would be if the base were rounded (a cusp's tip lies farther beyond its lowest samples): whether the
  /// base is a tip or a notch is judged against it.
  double roundS0 = 0.0;
  /// s of the petiole's junction with the blade when the petiole gives the base (NaN otherwise): at a sinus, where
  /// the loop the points draw rounds the bottom off, the midvein starts there.
  double junction = std::numeric_limits<double>::quiet_NaN();
  /// Whether that junction is where the stalk's axis meets the blade's plane (a stalk leaving the blade at an angle),
  /// not only where the thin trail of points ends.
  bool junctionMeetsPlane = false;
  /// Whether the stalk begins a gap away from the blade's samples (Petiole::acrossGap): the blade runs on, unseen,
  /// down to the junction.
  bool junctionAcrossGap = false;
  double stalkHalfWidth = 0.0;   ///< that petiole's half-width about its axis
  PenalizedSpline1D right, left; // g for the right margin (> 0) and for minus the left margin (> 0)
  double Phi(double s) const;
  double Right(double s) const;
  double Left(double s) const; ///< negative
};

/// Fits the outline to intrinsic coordinates (t, s) of the kept points.
std::string FitOutline(
  const std::vector<Eigen::Vector2d>& ts, const LeafFitParameters& options, double spacing, Outline& outline);

/// The outline as the points draw it, in (t, s): the right margin (t > 0) and the left one (t < 0), each from the
/// base (0, base) to the apex (0, apex). Where the points' boundary is not one such loop, the smooth margins kept
/// within a spacing of it (`features` false); empty only when the points draw no loop.
struct Contour
{
  std::vector<Eigen::Vector2d> right, left;
  bool features = false; ///< the loop departs from the smooth margins somewhere (a sinus, a notch, a lobe)
};

/// The boundary of the points (t, s) (the closing of discs of 2.5 spacings about them, holes filled, moved out by
/// the gap to the margin: measured against the smooth margins where it runs along them, else the level at which
/// the contour encloses the area the points sample), so lobes, sinuses and a cordate base are kept and not bridged. Sets
/// outline.base and outline.apex: the crossings of the midvein (t = 0) that bound it, a tip's end from the smooth
/// outline's extrapolated s0 or s1 (the last points never reach a tip; a base tip no more than a spacing past a
/// petiole's junction that meets the blade's plane), a sinus's from outline.junction when that
/// lies a little above the crossing (the discs round its bottom off), else where the points close across t = 0, as
/// an apical notch's between two lobes (moved out by the loop's gap to the margin: the scan's noise throws points
/// into the notch, which the loop joins to the blade).
/// `snap`: where the loop runs along the smooth margins (from a spacing outside to three inside), their points are
/// taken. The grid's distance transforms run through `parallel`, row by row and column by column (the contour does
/// not depend on the threads).
Contour TraceContour(const std::vector<Eigen::Vector2d>& ts, double spacing, bool snap, Outline& outline,
  const ParallelFor& parallel = SerialFor);

/// A blade's sparsely sampled parts in (t, s) (MinSparseGap, MaxSparseGap, MinSparsePoints): the segments that join
/// their points, and how far beyond each of their points the margin may lie.
struct SparseParts
{
  std::vector<std::pair<std::size_t, std::size_t>> bridges; ///< indices into ts, each pair once, in a fixed order
  std::vector<std::pair<std::size_t, double>> reaches;      ///< a sparse point and SparseMarginShare of its gap
};

/// The blade's sparse parts: each point whose gap is sparse joined to its nearest neighbour in each of eight sectors
/// of 45 degrees within 1.5 times its gap, where that neighbour is sparse too, and the groups so joined of at least
/// MinSparsePoints and MinSparseWidth gaps across. Dense parts, margins, sinuses and points off the blade get none
/// (their near neighbours fill a half plane, or more than half their sectors are empty), nor do a stray group or a
/// trail beside the blade. Searches through `parallel`; the result does not depend on the threads.
SparseParts FindSparseParts(
  const std::vector<Eigen::Vector2d>& ts, double spacing, const ParallelFor& parallel = SerialFor);

/// Whether a loop's apex crossing of the midvein (`apex`: s, index of the crossing edge's first point on the
/// counter-clockwise loop in (t, s)) is a tip, not a notch or sinus: within the larger of 4 spacings and
/// MinNotchDepth of the blade's extent below the smooth margins' tip s1, unless the loop rises on both sides of the
/// crossing, each above it by more than MinNotchDepth of the extent and 2 spacings before falling that far below it
/// (two lobes about a notch: a tip falls away on both sides). The depth below s1 alone depends on how far s1 is
/// extrapolated past the lobes, which the scan's noise moves by a spacing (the ginkgo's notch is 2.7 % of its
/// length, 3 spacings at the benchmark's scans).
bool ApexIsTip(const std::vector<Eigen::Vector2d>& loop, const std::pair<double, std::size_t>& apex, double s1,
  double extent, double spacing);

/// How far the blade's highest samples run on as a trail a point or two across (slices a spacing thick whose
/// samples lie within 1.5 spacings of one another across), down from the highest sample: a drawn-out tip narrower
/// than the scan's spacing, whose end may lie beyond its last samples. The trail may leave gaps of up to 8 spacings
/// (random samples along a tip a quarter of a spacing across lie about 4 apart); 0 when the highest slice is wider.
double ApexTrail(const std::vector<Eigen::Vector2d>& ts, double spacing);

/// Fills result.traits from the finished blade (points, triangles, margins, Support, FitDistance, Inlier) and the
/// surface (in the local frame whose axes, in world coordinates, are the columns of `axes`).
void ComputeTraits(const TensorSurface& surface, const Outline& outline, const LeafFitParameters& options,
  const Eigen::Matrix3d& axes, LeafFitResult& result);

} // namespace fit
} // namespace plantmorph
