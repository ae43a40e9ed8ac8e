// SPDX-License-Identifier: GPL-3.0-or-later
// LeafFitFilter's algorithm (docs/methods/leaf-fit.md): a scanned leaf (a point cloud) becomes a PlantMorph leaf and its traits.
// Plain C++17 (Eigen, the sources' blade mesher), no VTK.
//
// The method, per leaf:
//  1. Check: enough points, finite coordinates, not a line, not a blob (the cloud must be a sheet).
//  2. Clean: statistical outlier removal on the k nearest neighbours (mean neighbour distance beyond the median by
//     more than OutlierSigma robust deviations), then the largest connected component of a radius graph, with the
//     components of at least 5 % of it and the sheets beside it (a gap no wider than their own extent: a lobe seen
//     beyond a shadow across its neck).
//  3. Petiole and frame (shape/LeafShape.h): a thin trail of points leaving the blade is the petiole; it is set
//     apart (PetioleLength, Region 5 on the scan) and the blade alone is fitted. The base is the blade point nearest
//     BasePoint when one is given, else the petiole's junction with the blade; the midvein axis is the line through
//     the base across which the blade is most nearly its own mirror image (so wide, fan-shaped, cordate and lobed
//     blades get their real midvein), or the line to ApexPoint when one is given. Without either hint, the axis of
//     symmetry through the blade's centroid, its base end the one nearer the widest cross-section (ovate leaves).
//  4. Intrinsic coordinates: the cloud is cut in slices across its length; in every slice a quadratic
//     cross-section curve (in the slice's own principal frame, so tilted and twisted sections fit) and its centre;
//     the curves' parameters are smoothed along the length. The midvein is the curve through the centres; every
//     point gets s (arc length along the midvein from the base) and t (signed arc length along its cross-section
//     from the midvein, positive to the right looking at the upper side with the apex up). Rolled and bent leaves
//     thus flatten into the plane (t, s) the way LeafOutlineSource lays a flat blade out (x = t, y = s).
//  5. Outline: in the plane (t, s), the outermost point of each slice across s (two point spacings thick), moved
//     out by the expected gap between the outermost sample and the true margin (from the slice's density), fitted by
//     a penalised B-spline t = phi(s) g(s) (phi = sqrt of the distance to both ends, so rounded and acute tips
//     fit). Base and apex: extrapolated from the order statistics of s (the last samples never reach a tip).
//     The mesh's outline is the points' own boundary (LeafFitContour.cpp), snapped to these margins where it runs
//     along them: sinuses, notches and lobes (also below a cordate base) are kept, and the midvein runs from the
//     basal sinus (or the base's tip) to the apex (or the bottom of an apical notch).
//  6. Surface: a tensor cubic B-spline (s, t) -> 3-D, fitted by penalised least squares (second differences of
//     the control points in both directions) and iteratively reweighted (Huber) against remaining outliers.
//  7. Mesh: plantmorph::MeshBlade (LeafOutlineSource's blade mesher, quality mode) on the outline in (t, s),
//     mapped to 3-D by the surface. LeafUV: v = (s - s_base) / (s_apex - s_base), u = t scaled so the margins are at
//     +-0.5.
// Everything is deterministic: no random numbers, no dependence on threads (leaves are fitted independently).
#pragma once

#include <plantmorph/ParallelFor.h>

#include <Eigen/Core>

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace plantmorph
{

struct LeafFitParameters
{
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ(); ///< unit vertical, for Inclination, Azimuth, HorizontalArea
  std::optional<Eigen::Vector3d> basePoint;      ///< the blade point nearest it is the base
  std::optional<Eigen::Vector3d> apexPoint;      ///< the blade point nearest it is on the midvein's apex side
  double surfaceSmoothing = 1.0; ///< [0.1, 1e6]: weight of the surface's bending penalty (1: the default balance)
  double outlineSmoothing = 1.0; ///< [0, 1e6]: weight of the margins' curvature penalty
  int outlineControlPoints = 16; ///< [4, 200]: B-spline control points per margin
  double outlierSigma = 3.0; ///< [1, 100]: robust deviations of the neighbour distance beyond which a point is dropped
  int resolution = 60;       ///< [4, 1000]: segments along the midvein of the output mesh
  int modelControlPoints = 20; ///< [3, 100]: Model C control points per margin in the fitted model (at most:
                               ///< fewer when that many fold the flat model, LeafFitResult::modelControlPoints)
};

/// The smallest SurfaceSmoothing: below it the penalised surface leaves the points where they are sparse (on the
/// shipped scans Length grows by up to 29 % at 0.01, and 20-160 fold at 0).
inline constexpr double MinSurfaceSmoothing = 0.1;

/// The most the scan's noise may tilt the fitted surface: where the noise left in an unpenalised fit (the points'
/// scatter over the square root of the points per knot cell, over the knot spacing) would tilt it more, the bending
/// penalty is raised by the square of the ratio. A surface that follows the noise's bumps has their area too
/// (about half the tilt's square: at 1 % range noise the accuracy benchmark's scans from above read +0.4 to +1.7 %);
/// at 0.03, +0.05 %. The ratio depends on the knot cells, not on the leaf's size or the scan's density alone.
inline constexpr double MaxNoiseTilt = 0.03;
/// The most the points' scatter about the surface may grow when the penalty is raised for the noise: more, and the
/// surface is leaving shape it should follow, so the raise is halved (in its logarithm) until it does not, or
/// dropped. On the accuracy benchmark's scans at 1 % noise the scatter grows 0.0-2.2 % (median 0.65 %) at the full
/// raise (2-11 fold); on the shipped real scans 2-11 % (their folds and curl), 1.2-1.9 % at the raises kept (1.7-2.2
/// fold on five of them).
inline constexpr double MaxNoiseScatterGrowth = 1.02;

/// Empty when every option is finite and in range; otherwise the message naming the option and its range.
std::string ValidateLeafFitParameters(const LeafFitParameters& options);

inline constexpr int MinLeafPoints = 50;

/// The most points a leaf is fitted on: a denser leaf is fitted on a deterministic sample of about this many
/// (PointGrid.h's SampleIds), which holds area and length within 0.25 % on the benchmark's leaf, and its other points
/// get their FitDistance, Inlier, (t, s) and petiole from that fit, so the cost grows linearly above it.
inline constexpr std::size_t MaxFitPoints = 100000;

/// The most vertices a fitted blade's mesh may have: a blade needing more (a Resolution too fine for it) is refused
/// with a message, so that no input makes the mesher run for minutes.
inline constexpr std::size_t MaxBladeVertices = 400000;

/// The shallowest apical notch (or basal sinus) taken for the midvein's end, as a fraction of the blade's extent
/// along it (the default ginkgo's apical notch is 2.7 %): shallower indentations at a tip (a tooth, the gap between
/// two scan lines) are part of the margin, and the midvein ends at the tip's envelope.
inline constexpr double MinNotchDepth = 0.02;

/// The largest number variance (over the mean) of the points' counts in discs of radius 2.5 sides (the side of the area
/// a point stands for: the square root of the blade's area over the count) for a scan to count as regular. Points on
/// a scanner's lattice, or on several lattices superimposed (two positions), are hyperuniform: a disc's count varies
/// only with the lattice's cells its rim cuts, so the ratio is small (the accuracy benchmark's line scans 0.04-0.35 at
/// 0.3 % range noise, up to 0.57 at 1 %). Points at random give about 1 (0.77-1.8 on the unit tests and on 156 uniform samples;
/// more where the density varies), and so do the shipped soybean scans (1.1-2.8, holes and overlapping rows) and two of the three
/// sugar beets (1.0, 2.1). On a regular scan the blade's area comes from the points' count and the outline is kept as
/// the points draw it (see TraceContour), since the count does not depend on how the points near the margin spread.
inline constexpr double MaxGridNumberVariance = 0.7;
/// The fewest discs wholly inside the blade from which the number variance is taken (fewer: not regular). With 100
/// (about 600 points) random points' ratio stays above 0.77 (156 samples of 13 presets, 2,000-30,000 points).
inline constexpr int MinGridWindows = 100;

/// A blade's sparsely sampled parts (a scanner's lines far apart where it saw the blade at a grazing angle, or from
/// one position of several) are joined point to point before the outline is traced, so that the closing's discs of
/// 2.5 spacings do not drop them (see FindSparseParts). A point is in such a part when the fifth nearest of its
/// nearest neighbours in eight sectors of 45 degrees (its gap) lies farther than MinSparseGap times the blade's
/// median gap or the spacing (a lattice's lie at 1 and 1.4 steps, a line scan's across its lines at about the lines'
/// distance), within MaxSparseGap spacings, and its near neighbours lie along one line at most (not over a half
/// plane, as at a margin, a sinus or the edge of a hole); it is joined to its sector neighbours within 1.5 gaps.
inline constexpr double MinSparseGap = 2.0;
inline constexpr double MaxSparseGap = 10.0;
/// The fewest points a sparse part joins (fewer: a stray group beside the blade, which is not joined).
inline constexpr std::size_t MinSparsePoints = 30;
/// The least width of a sparse part across its longest extent, in its gaps (a narrower group is a trail: a twig's or
/// stalk's points left with the leaf, which would draw the blade out along it; one at a shrub leaf's base measured
/// 2.4, a blade's half sampled on a lattice 5 or 6 spacings apart 3.5 and 3.0).
inline constexpr double MinSparseWidth = 2.75;
/// How far beyond a sparse part's outermost points its margin is taken, as a share of their gap: the margin lies
/// about half a step beyond the last samples, and the gap is a lattice's diagonal step (1.4 steps) or about a line
/// scan's step across its lines.
inline constexpr double SparseMarginShare = 0.4;
/// The share of the blade's area its sparse parts may add to the closing of its points' discs for a regular grid's
/// count still to give the area (TraceContour): a few spread points near a tip or in a base's wedge change it
/// little, while a count over a large sparse part would give its points the area the dense part's stand for.
inline constexpr double MinSparseShare = 0.02;

/// Why a leaf's base is a guess (Traits' BaseFrom 3): no BasePoint, ApexPoint or petiole, and the outline either
/// is the same at both ends (an ellipse) or differs only in which half is wider, which is the base of an ovate blade
/// and the apex of an obovate one (the wider half is taken as the base).
enum class BaseGuess
{
  None,
  SameAtBothEnds,
  WiderHalf
};

/// Where a leaf's base came from (LeafTraits::baseFrom, the Traits column BaseFrom): its shape, BasePoint, the
/// petiole's junction, a guess (LeafFitResult::baseGuess says why), the plant's wood (OrientByWood).
inline constexpr int BaseFromShape = 0, BaseFromPoint = 1, BaseFromPetiole = 2, BaseFromGuess = 3, BaseFromWood = 4;

struct LeafTraits
{
  double length = 0, width = 0, projectedLength = 0, projectedWidth = 0;
  double area = 0, projectedArea = 0, horizontalArea = 0, perimeter = 0, aspectRatio = 0;
  double bending = 0; ///< degrees the midvein turns out of the blade (its normal curvature integrated base to apex)
  double rolling = 0; ///< degrees the cross-section turns from margin to margin (mean along the leaf)
  double rollingCurvature = 0; ///< mean cross-section curvature (1 / length unit), signed: + rolls up
  double inclination = 0;      ///< degrees between the blade's mean normal and `up` (0: the blade lies horizontal)
  double azimuth = 0; ///< degrees of the midvein (base to apex) in the horizontal plane, from the first horizontal axis
  double midveinInclination = 0; ///< degrees of the midvein's base tangent above the horizontal plane
  double points = 0, inliers = 0;
  double fitRMS = 0, fitP95 = 0, fitMax = 0; ///< scan-to-blade distances of the inliers
  double coverage = 0;                       ///< fraction of blade area whose Support is below twice the point spacing
  double spacing = 0;                        ///< median nearest-neighbour distance of the inliers
  /// 0: the shape, 1: BasePoint, 2: the petiole's junction, 3: a guess (no base point, apex point or petiole, and
  /// the outline does not tell which end is the base: LeafFitResult::baseGuess says why; CheckFittedLeaf warns),
  /// 4: from the plant's wood, the end nearer it or where the leaf meets it (OrientByWood, LeafPlant.h, on
  /// PlantSegmentationFilter's WoodDistance)
  int baseFrom = BaseFromShape;
  double petioleLength = 0; ///< arc length of the petiole's centre line (0: no petiole found)
  /// The share of the blade's margin past which the scanner's view was blocked by something nearer to it, from every
  /// scanner that saw the leaf (ScannerView.h, filters/leaf_fit/plant): the leaf may go on there, hidden. NaN when
  /// the scanners' positions are not known (the input has no Range and ScanPosition point arrays).
  double hiddenMargin = std::numeric_limits<double>::quiet_NaN();
  /// Which extents the scanners saw whole (ScannerView.h): 1 the Length (the margin about both ends of the midvein
  /// seen free), 2 the Width (about the widest point of both sides), 3 both, 0 neither; NaN with hiddenMargin.
  double extentsSeen = std::numeric_limits<double>::quiet_NaN();
  /// The spacing Coverage is measured in: the larger of `spacing` and half the spacing across a line scan's lines
  /// (CrossSpacing), the gaps a scan leaves on the blade (not a column of the table).
  double coverageSpacing = 0;
};

/// Names of the traits, in the order TraitValues() lists them (the Traits table's columns after LeafId).
std::vector<std::string> TraitNames();
std::vector<double> TraitValues(const LeafTraits& traits);
/// The traits of a row of TraitValues() (a default LeafTraits when `values` is not such a row).
LeafTraits TraitsFromValues(const std::vector<double>& values);

struct LeafFitResult
{
  std::string error; ///< empty on success; then everything below is filled, else everything is empty
  // The scan, one entry per input point.
  std::vector<double> fitDistance; ///< signed distance to the blade (along its normal); NaN for dropped points
  std::vector<unsigned char> inlier;
  std::vector<Eigen::Vector2d> intrinsic;   ///< (t, s) of every point (NaN for dropped points)
  std::vector<unsigned char> petiole;       ///< 1 for the points of the petiole (not fitted: Inlier 0)
  std::vector<Eigen::Vector3d> petioleLine; ///< the petiole's centre line, junction to far end (empty: none)
  // The blade: the mesher's output mapped to 3-D.
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> flat; ///< (t, s - s_base) of every blade point: the blade laid flat
  std::vector<Eigen::Vector2d> leafUV;
  std::vector<Eigen::Vector2d> tcoords; ///< eq. (6) of the flat blade
  std::vector<Eigen::Vector3d> normals;
  std::vector<int> region;
  std::vector<double> support; ///< distance to the nearest inlier
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> leftMargin, rightMargin, midvein; ///< base to apex, ids into points
  // The model LeafOutlineSource rebuilds (Model C, Custom preset): 3-D control points.
  std::vector<Eigen::Vector3d> modelMidvein, modelLeftMargin, modelRightMargin;
  /// The same leaf laid flat (x = t, y = s - s_base, z = 0: the intrinsic layout, base at the origin, midvein along
  /// +Y, as LeafOutlineSource makes leaves): always a valid flat Model C leaf, also when the 3-D one folds in the
  /// least-squares plane LeafOutlineSource meshes 3-D control points in.
  std::vector<Eigen::Vector3d> flatMidvein, flatLeftMargin, flatRightMargin;
  /// Control points per curve in the model: `modelControlPoints` of the options, or fewer (by twos) when the flat
  /// model folded in LeafOutlineSource with that many (its interpolating margin crossed the midvein).
  int modelControlPoints = 0;
  /// Empty when the flat model rebuilds in LeafOutlineSource; else why it does not (the model is still given).
  std::string modelWarning;
  /// The share of the cleaned points in the blade's sheet (fit::Petiole::sheetShare): low where the scan samples the
  /// blade unevenly (its lines far apart over part of it), where thin parts and the outline are uncertain.
  double sheetShare = 1.0;
  /// False when the sheet's share was too low to tell a petiole from sparse blade (none was looked for).
  bool petioleLookedFor = true;
  /// Why the base is a guess (Traits' baseFrom 3), else None.
  BaseGuess baseGuess = BaseGuess::None;
  /// True when the base and apex were told apart by the blade's shape alone: no BasePoint, ApexPoint or petiole, and
  /// not a guess (Traits' baseFrom 0 without ApexPoint).
  bool orientedByShape = false;
  /// True when the shape put the base at the blade's one narrow end because its end slices keep one width, as a
  /// stalk's do, and no petiole was found there: a stalk the petiole search missed (a point across, or short), or a
  /// drawn-out tip whose first slices the noise or a coarse scan widened to the same width (then turned end to end).
  bool baseAtStalkWidth = false;
  /// How far the blade's last samples at the apex run on as a trail a point across, within the outline's spacing
  /// (Traits' coverage spacing) of the midvein (fit::ApexTrail): a drawn-out tip narrower than the scan's spacing,
  /// which may go on unseen beyond them. 0 when the apex is wider than that to its end.
  double apexTrail = 0.0;
  /// The petiole's half-width about its axis (fit::Petiole::halfWidth; 0 without a petiole).
  double petioleHalfWidth = 0.0;
  /// True when the blade's apex is a drawn-out tip whose last samples are a trail a point or two across: narrower
  /// than the scan's spacing there, it may run on unseen beyond them (Length short by that much).
  bool apexBeyondSamples = false;
  LeafTraits traits;
};

/// Fits one leaf. Never throws for bad input: the result's error says what is wrong. Its point searches and
/// per-point steps run through `parallel`; the result does not depend on it.
LeafFitResult FitLeaf(const std::vector<Eigen::Vector3d>& points, const LeafFitParameters& options,
  const ParallelFor& parallel = SerialFor);

/// Fits several leaves (each its own point set) through `parallel`; results in the leaves' order, identical to
/// fitting them one by one. A single leaf is fitted with `parallel` inside it.
std::vector<LeafFitResult> FitLeaves(const std::vector<std::vector<Eigen::Vector3d>>& leaves,
  const LeafFitParameters& options, const ParallelFor& parallel = SerialFor);

} // namespace plantmorph
