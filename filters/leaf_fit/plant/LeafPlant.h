// SPDX-License-Identifier: GPL-3.0-or-later
// LeafFitFilter on a plant (docs/methods/leaf-fit.md, "Several leaves" and "Trait reference"): which points are one
// leaf, the checks that say when a fitted leaf is not to be trusted, and the plant's own table.
// Plain C++17 (Eigen), no VTK.
//
// - Leaf ids: a LeafId is read as the integer it is (64 bits); a floating-point value that is not an integer (or is
//   NaN, infinite, or beyond 64 bits) is refused, never rounded into another leaf.
// - Separate blades: without leaf ids, the points are cut into the connected parts of the graph joining points
//   closer than SeparationRadius (a few point spacings, across a line scan's lines as well as along them). Parts too small to be a leaf (fewer than MinLeafPoints, or
//   under 5 % of the largest part: the fit's own cleaning rule) go with the nearest large part, where the fit's
//   cleaning drops them as strays. The large parts are the leaves, numbered in the order of their first point.
// - Checks of a fitted leaf: Coverage (the blade spreading over empty space) and the flat model's area against the
//   fitted blade's.
// - The plant: leaf count, total and mean area, the leaf inclination angle distribution (a histogram of 10-degree
//   classes and the beta distribution fitted by the method of moments, as Goel and Strebel 1984 and Wang et al.
//   2007 report it).
#pragma once

#include "LeafFit.h"

#include <plantmorph/DataContract.h>

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace plantmorph
{

/// The integer a LeafId value stands for; an error (naming `array` and the value) when it is NaN, infinite, not an
/// integer or outside the 64-bit integers.
std::string LeafIdOf(double value, const std::string& array, std::int64_t& id);

/// The radius at which points are one blade: SeparationSpacings times the larger of the median nearest-neighbour
/// distance and CrossSpacing (the distance between a line scan's lines).
inline constexpr double SeparationSpacings = 6.0;

struct LeafSeparation
{
  std::vector<int> leafOf; ///< for every point, its leaf 0 .. count-1
  int count = 0;           ///< number of leaves
  double radius = 0.0;     ///< the joining radius used
  int strayParts = 0;      ///< small parts given to the nearest leaf
};

/// The separate blades of `points` (rules above). Points with non-finite coordinates go to leaf 0 (the fit then
/// refuses them by name). The grids, sorts and joins run through `parallel`; the result does not depend on it.
LeafSeparation SeparateLeaves(const std::vector<Eigen::Vector3d>& points, const ParallelFor& parallel = SerialFor);

/// Status of a Traits row.
enum class LeafStatus
{
  Fitted = 0,  ///< fitted, nothing to say
  Warning = 1, ///< fitted, but a check below failed: the Message says which
  Failed = 2   ///< not fitted (the Message says why); the traits are NaN
};

/// Coverage below which a fitted blade is said to spread over empty space. On the shipped scans: 0.997 and 0.999
/// (soybean leaflets 15 and 36), 0.924 (sugar beet 29 August); below it 0.879 (4 September, a flap spread over the
/// petiole), 0.813 (30 August, the petiole taken for the apex), 0.854 (soybean leaflet 1).
inline constexpr double MinCoverage = 0.9;
/// The least share of the points in the blade's sheet (LeafFitResult::sheetShare) a fit is trusted with: 0.96 or
/// more on the accuracy benchmark's scans; 0.61 and 0.74 on two of the shipped soybean leaflets, 0.35-0.77 on
/// simulated leaves scanned at a grazing angle (Length 12-27 % short).
inline constexpr double MinSheetShare = 0.85;

/// The longest trail of samples a point or two across at the apex (LeafFitResult::apexTrail), in the outline's
/// spacings, a fit is trusted with: an acute apex of half-angle theta is under 1.5 spacings across over its last
/// 0.75 / tan(theta) spacings (1.8 at the ovate envelope's 23 degrees), random samples thin out along it and add up to
/// about 4 (6.2 at most over 144 random scans of twelve blades without a drawn-out tip); the acuminate preset's tip
/// gives 5-18 on the accuracy benchmark's scans, 8-36 at random.
inline constexpr double MaxApexTrail = 6.5;
/// A petiole shorter than this share of the blade's Length and narrower than MaxNarrowPetiole point spacings plus
/// twice FitRMS (its half-width; the scan's noise widens a trail) may be the blade's own attenuate base or drawn-out
/// tip: a base or tip that narrows into a trail a point or two across looks like a thin stalk. The curled emarginate
/// preset from two positions, without a petiole: 0.053 of Length, half-width 1.3 spacings, base 7 % of the length up
/// the blade. At 1 % range noise the acuminate preset without a petiole: its tip taken for a stalk 0.09-0.18 of
/// Length, half-width 2.1-3.1 spacings with FitRMS 1.4-1.6, the base put at the tip. The accuracy benchmark's
/// petioles are 0.27-0.33 of Length, the shipped sugar beets' 0.53-0.91.
inline constexpr double MinPetioleShare = 0.2;
inline constexpr double MaxNarrowPetiole = 2.0;
/// Relative difference of areas beyond which the flat model is said not to be the fitted blade.
inline constexpr double MaxModelAreaError = 0.02;

/// The warnings of a successful fit, one sentence each: the model's own (modelWarning), a base that is a guess
/// (BaseFrom 3: the blade is the same at both ends, or only its wider half tells them apart), a scan that samples
/// the blade unevenly (sheetShare under MinSheetShare), an apex drawn out beyond what the scan resolves (apexTrail
/// over MaxApexTrail spacings), a base put at a narrow end of constant width where no petiole was found
/// (baseAtStalkWidth: a missed stalk or a widened tip), a short narrow petiole that may be the blade's attenuate base
/// or tip (MinPetioleShare, MaxNarrowPetiole), low Coverage, and the flat
/// Model C leaf (flatMidvein, flatLeftMargin, flatRightMargin rebuilt by LeafOutlineSource's B-spline leaf at
/// `resolution`) whose area differs from the fitted blade's (the Area trait) by more than MaxModelAreaError.
std::vector<std::string> CheckFittedLeaf(const LeafFitResult& fit, int resolution);

/// The ends of a leaf are compared over its points within this fraction of its Length of each end...
inline constexpr double WoodEndReach = 0.15;
/// ...and one is the nearer the wood when its points come nearer it than the other's by this fraction of Length
/// (swept on 18 scans of six plants: any difference turned the fewest leaves wrongly, 0.05 one more on 9 of them
/// and none fewer; 0.2 and a ratio of the distances of 0.5 to 0.8 many more).
inline constexpr double WoodEndMargin = 0.05;
/// A base the shape only guessed, or a petiole's junction, is put where the leaf meets its wood (WoodBasePoint,
/// LeafBaseCentreWeight) unless the wood tells the midvein's ends apart and that point lies within this fraction of
/// Length of one of them (swept on the herb, shrub and petioled shrub, 18 scans: 0.15, 0.25 and 0.4 left 251, 249
/// and 250 of 734 leaves based over a quarter of their length off).
inline constexpr double WoodBaseEndReach = 0.25;

enum class WoodEnd
{
  Unknown, ///< no wood distances, or both ends about as near the wood
  Base,    ///< the midvein's base end is the nearer
  Apex     ///< the midvein's apex end is the nearer: the leaf is turned end to end
};

/// Which end of `fit`'s midvein lies nearer the plant's wood: per end, the smallest `woodDistance` (one per point of
/// `points`, the points fitted; NaN: unknown) among the points within WoodEndReach of its Length of that end.
WoodEnd EndNearerTheWood(
  const LeafFitResult& fit, const std::vector<Eigen::Vector3d>& points, const std::vector<double>& woodDistance);

/// The index of the leaf's point of the least `woodDistance` minus LeafBaseCentreWeight times its distance from the
/// points' centroid (NaN distances skipped): the point near the wood at an end of the leaf, where a leaf meets its
/// twig or petiole. Nothing when no point has a distance.
std::optional<std::size_t> WoodBasePoint(
  const std::vector<Eigen::Vector3d>& points, const std::vector<double>& woodDistance);

enum class WoodAxis
{
  Unknown, ///< no wood distances, or the ends along and across the midvein about as near the wood
  Along,   ///< an end of the midvein is the nearer: the leaf grows from there, its midvein runs as fitted
  Across   ///< an end of its Width is the nearer: the leaf grows from its side as fitted, it was fitted across
};

/// Which of a fit's axes runs to the wood: per end of its midvein and of its Width (its blade points of the least
/// and the greatest flat `t`), the smallest `woodDistance` among `points` within WoodEndReach of its shorter extent;
/// the nearer pair's nearest end by WoodEndMargin of its longer extent decides. `widthEnd`, when given, gets the end
/// of its Width nearer the wood.
WoodAxis AxisNearerTheWood(const LeafFitResult& fit, const std::vector<Eigen::Vector3d>& points,
  const std::vector<double>& woodDistance, Eigen::Vector3d* widthEnd = nullptr);

/// The leaves of one plant share a shape (LeafAreaEstimate.h), and with it the ratio of Width to Length along their
/// midvein: a fan is wider than long, an elliptic blade longer than wide. The log of Width over Length of each fit
/// whose axis the wood tells (AxisNearerTheWood; not with BasePoint): as fitted where an end of its midvein lies
/// nearer the wood, turned over where an end of its Width does (the leaf grows from that side: it was fitted across
/// its width). These are the values the plant's axis shape (PlantAxisShape) is the median of, gathered over every
/// leaf of the plant (over the ranks that own them). The shape alone is not enough: from one position with noise
/// 1 % of the leaf's length, most fans whose base the shape found were fitted across their width (the median ratio
/// 0.72 on the benchmark's shrub, whose fans are 1.43 as wide as long). Nor is a base end the shape and the wood
/// agree on (what was taken before): the benchmark's default blade is a lens about as symmetric across its width as
/// along its midvein, and on the shrub of many leaf sizes from one position 6 of the 13 fits whose base the shape
/// found were across (Width over Length under 1, the blade's 1.35); which axis runs to the wood tells them apart.
std::vector<double> AxisShapes(const std::vector<LeafFitResult>& fits,
  const std::vector<std::vector<Eigen::Vector3d>>& leaves, const std::vector<std::vector<double>>& woodDistance);
/// Leaves whose axis the wood tells needed for the plant's axis shape.
inline constexpr int MinAxisShapeLeaves = 3;
/// The plant's log Width over Length: the median of `shapes` (every leaf's AxisShapes; the middle two's mean for an
/// even count, so the order the values come in does not matter). Nothing under MinAxisShapeLeaves values, nor when
/// the leaves are about as wide as long (the median's size under WoodShapeMargin): a leaf fitted across its width
/// then has about the same ratio, and the ratio cannot tell the axis.
std::optional<double> PlantAxisShape(std::vector<double> shapes);
/// A refit from the wood's base point (below) is dropped when its log Width over Length lies farther from the
/// plant's than the first fit's by more than this: 0.2, a ratio 22 % further off. A fan fitted across its width has
/// the ratio turned over (log 1.43 against log 0.70 on the benchmark's default blade, 0.72 apart), while the ratio of
/// leaves of one plant fitted along their midvein spreads by a few percent. Swept on the shrub and the shrub of many
/// leaf sizes from one and four positions (115 leaves a wood base point moved): 0.1, 0.2 and 0.3 dropped 25, 21 and
/// 19 moves, of which 3, 1 and 1 had put the base within a quarter of the leaf's length of the true base.
inline constexpr double WoodShapeMargin = 0.2;

/// A leaf fitted across its width and fitted again along the plant's axis keeps the refit only when its Coverage
/// (the share of the blade near the points) falls by no more than this. On a deeply lobed blade seen in part (the
/// benchmark's palmate watermelon blade) the refit from a lobe at the end of its width spanned the gaps between its
/// lobes: Coverage 0.77 -> 0.68 and 0.91 -> 0.79, Area +33 % and +25 %, where a fan's refit along its true axis
/// keeps or raises its Coverage.
inline constexpr double MaxTurnCoverageLoss = 0.02;

/// A leaf grows from its twig or its petiole: its base touches the wood, its apex is usually free. For each fit
/// whose base the shape, the petiole search or a guess chose (BaseFrom 0, 2, 3; not with BasePoint or ApexPoint in
/// `options`):
/// - a base that is a guess or a petiole's junction (BaseFrom 3, 2) moves to the WoodBasePoint, fitted again with
///   its base there (as BasePoint would put it: the midvein then follows the blade's symmetry from that base, so a
///   fan fitted across its width finds its length), unless the wood tells the midvein's ends apart
///   (EndNearerTheWood) and that point lies within WoodBaseEndReach of its Length of one of them;
/// - else, where the apex end lies nearer the wood, the leaf is fitted again with its base at that end; where the
///   wood confirms a guessed base, the guess stands.
/// With the plant's axis shape (`plantAxisShape`, PlantAxisShape), a move to the WoodBasePoint whose refit has a
/// Width over Length farther from the plant's than the first fit's (by more than WoodShapeMargin in log) is dropped:
/// the wood's base point was a twig the leaf lies against at its side (a fan's corner by a twig turned the fan
/// across), so the first fit's axis stands and only its ends are compared by the wood, as for a base from the shape.
/// Then, with the plant's axis shape, a leaf still fitted across its width (its Width over Length turned over lies
/// nearer the plant's than as fitted, by more than WoodShapeMargin, and an end of its Width lies nearer the wood
/// than its midvein's ends: AxisNearerTheWood gives Across) is fitted again from that end of its Width, and kept
/// when that brings its ratio nearer the plant's by WoodShapeMargin and its Coverage falls by no more than
/// MaxTurnCoverageLoss.
/// All of them get BaseFrom BaseFromWood. `woodDistance` has one vector per leaf (empty: that leaf is left as it
/// is); a refit that fails leaves the first fit. Returns how many leaves were fitted again.
int OrientByWood(const std::vector<std::vector<Eigen::Vector3d>>& leaves,
  const std::vector<std::vector<double>>& woodDistance, const LeafFitParameters& options,
  std::vector<LeafFitResult>& fits, const ParallelFor& parallel = SerialFor,
  std::optional<double> plantAxisShape = std::nullopt);

/// The area of the flat Model C leaf of `fit` as LeafOutlineSource rebuilds it (NaN when it does not rebuild).
double FlatModelArea(const LeafFitResult& fit, int resolution);
/// The area of the fitted blade laid flat (its (t, s) mesh).
double FlatBladeArea(const LeafFitResult& fit);

/// A beta distribution of t = angle / 90 degrees, density t^(nu - 1) (1 - t)^(mu - 1) / B(mu, nu) (Goel and
/// Strebel 1984): mean nu / (mu + nu).
struct BetaFit
{
  double mu = 0.0, nu = 0.0;
  bool valid = false; ///< false with fewer than 2 angles, or none strictly inside (0, 90), or no spread
};

/// Method of moments on angles in degrees [0, 90] (Wang et al. 2007): with m and v the mean and the (population)
/// variance of t, nu = m (m (1 - m) / v - 1), mu = (1 - m) (m (1 - m) / v - 1).
BetaFit FitBetaDistribution(const std::vector<double>& degrees);

/// The density of `beta` at angle `degrees` per degree (the density of t divided by 90).
double BetaDensity(const BetaFit& beta, double degrees);

inline constexpr int InclinationClasses = 9; ///< 10-degree classes over [0, 90]

struct PlantSummary
{
  int leaves = 0;       ///< leaves fitted
  int failed = 0;       ///< leaves not fitted
  double totalArea = 0; ///< sum of the fitted leaves' Area
  double meanArea = 0;  ///< totalArea / leaves
  double meanInclination = 0;
  std::vector<double> inclinationFraction; ///< fraction of fitted leaves per 10-degree class (90 in the last)
  BetaFit beta;
  /// Sum of the fitted leaves' EstimatedArea (LeafAreaEstimate.h: a leaf seen in part from the plant's shape)
  double totalEstimatedArea = 0;
  int wholeLeaves = 0; ///< the leaves seen whole the plant's shape was taken from (0: fewer than MinWholeLeaves)
  double unassignedLeafPoints = 0; ///< leaf points on no leaf (a negative LeafId and Organ 1)
  /// Their area at the fitted leaves' points per area (LeafAreaEstimate.h), part of totalEstimatedArea
  double unassignedLeafArea = 0;
};

/// The plant's summary from its leaves' traits; `fitted[i]` false for leaves that were not fitted. The estimated
/// areas need each leaf's Area, ProjectedLength, ProjectedWidth, Coverage and Points; `unassignedLeafPoints` leaf
/// points on no leaf add their area to the estimated total.
PlantSummary SummarizePlant(
  const std::vector<LeafTraits>& traits, const std::vector<bool>& fitted, double unassignedLeafPoints = 0.0);

/// The plant table's column names and values, in the same order ("LeafCount", ...).
std::vector<std::string> PlantColumnNames();
std::vector<double> PlantColumnValues(const PlantSummary& plant);

/// The unit of a Traits or Plant column, `lengthUnit` standing for the output length unit ("mm" gives "mm^2" for
/// areas, "1/mm" for curvatures); "" for a name this does not know.
std::string ColumnUnit(const std::string& column, const std::string& lengthUnit);

/// The output length unit of input coordinates in `unit` multiplied by `scale`: a metric unit's name when the
/// product is one ("mm" and 0.1 give "cm"), the unit itself for scale 1, else "(<1/scale> <unit>)"; "" for an
/// empty unit.
std::string ScaledUnit(const std::string& unit, double scale);

} // namespace plantmorph
