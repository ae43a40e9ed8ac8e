// SPDX-License-Identifier: GPL-3.0-or-later
// PlantSegmentationFilter's algorithm (docs/methods/segmentation.md): a scanned plant (a point cloud) becomes its
// organs, wood and leaves, and its leaf instances. Plain C++17 (Eigen), no VTK, no training data.
//
// Per plant, every length a multiple of the cloud's own point spacing s (the median nearest-neighbour distance,
// MedianSpacing):
//  1. Features (threaded): the covariance of the points within r and 2r of each point, r = FeatureScale * s, or
//     12 times the range noise when that is wider (the noise: the lower quartile of the plane-fit residual); its
//     eigenvalues l1 >= l2 >= l3 give the spread sqrt(l2) / radius across the main axis, the surface variation
//     l3 / (l1 + l2 + l3) and the normal (the eigenvector of l3, at scale r). The covariances are summed from the
//     moments of grid cells (side r / 8 at r, r / 2 at 2r; SegmentationGrid.h), once per cell: linear in the points.
//  2. Sheets: region growing over the radius graph (edges shorter than LinkScale * s) from the flattest points,
//     joining a neighbour whose normal is within NormalAngle of the current point's, never through a point that is
//     thin at both scales (spread below 0.2: twigs and petioles stop it) nor from a point on a crease (surface
//     variation above the plant's median by CreaseVariation: where two leaves cross, a fold, a junction).
//  3. Classification of each region from its own covariance and normals: a leaf is a sheet (its points' normals
//     agree with the region's plane normal on average by more than SheetCoherence) that is not a long strip (its
//     length over width below MaximumLeafElongation), is wider than the features' neighbourhood (2r) and is no
//     piece of a cylinder (normals sharing an axis along the region's length within 25 degrees and turning around
//     it by an arc of about 80 degrees or more, spread over the arc: not in two groups, as a blade folded along its
//     midrib into a V has them, and filling it: no empty arc of NormalAngle between groups, as blades fanned around
//     a twig leave); the rest is wood. Two strips near each other that together are such a V, as wide
//     as a leaf, with the points around them in one half's plane or the other's, are the halves of a blade folded by
//     more than about 60 degrees (the crease between them stops the growing): one leaf region. A region that is no sheet (incoherent) yet wide,
//     not a strip and no cylinder is several leaves grown into one: it is grown again inside itself with every
//     point's normal within NormalAngle of its piece's seed (no drift from leaf to leaf), and its pieces are judged
//     in turn. A coherent region curved across at r (over three quarters of its points, its own points within r lie
//     3 noises or more off their plane: the sides of twigs thinner than r, whose smoothed normals face the scanner)
//     is wood, a leaf-shaped one after it is grown again as above. A flat strip (coherent, no cylinder, judged wood
//     only for being narrower than 2r or long) is leaf
//     when the points within three links around it lie in its plane (under r / 10 off it) or there are none: a
//     tube's facet has the next facets turning away around it. A flat strip whose surroundings are not flat is
//     still leaf when no wood lies within r / 2 of it (once its region has taken the small regions around it) and
//     its own normals turn about its length by under an rms 6 degrees: a leaf seen narrow among other leaves, which
//     make its surroundings uneven; a twig's strip lies beside the twig's other strips or turns with its surface.
//     A strip left wood is leaf still when the points within three links around it are under 40 % wood and its own
//     normals turn about its length by under an rms 10 degrees (the features' error) (its own points at least a quarter of its points): a
//     leaf's strip at its base beside its twig, among leaf points. Alone, such a strip gets no LeafId. Points of regions too small to judge take
//     the organ of the nearest judged region (breadth-first over the radius graph; a leaf region's only within 2r of
//     the judged point its spread started from: beyond lies the twig the leaf sits on), linear ones are wood.
//     A thick cylinder keeps its whole surface: the judged wood is fitted, in slices of 8r along each wood region's
//     axis, with circles of radius at least r (refitted to all the wood of the slice near them), and the leaf points
//     on such a circle (within 3 times the range noise or a spacing, their normals within NormalAngle of its radius)
//     become wood when they are at least a quarter of their region: a trunk's face grown into a sheet whose normals
//     turn too little for a cylinder (an arc under 80 degrees) was a leaf; a leaf beside the trunk meets the shell in a line.
//     Points whose whole component of the radius graph has fewer than 12 points (a surface at a grazing angle, its
//     rows farther apart than the links) take the organ most other points within r around them have, leaf when
//     there are none (a leaf turned edge on; a branch is scanned along its length in a line of linked points).
//     A whole component of the links, all wood, flat (under a tenth of its width thick) and farther than r from other
//     wood is leaf; so is a piece of the wood alone 3r or more from other wood, compact (under 4 widths long) and flat
//     within the range noise (under 2.5 noises off its plane): a leaf's piece judged wood on a noisy scan.
//  4. Leaf instances. Small wood pieces (fewer than MinimumLeafPoints points) touching one leaf region only are
//     that leaf's thin margins and tips: they join it. A wood piece touching two leaf regions or more and nothing
//     else, its points no farther off those regions' local planes than their own points, is the leaves' contact
//     (noisy normals there break it into regions too small to judge as sheets): leaf, its points joining the
//     instance of the region whose plane is nearest once the instances are made. A leaf region that meets the wood
//     (within two links) at places more than 4r apart is several leaves touching: it is split between those bases,
//     each point to the base nearest along the region. A part under a quarter of the plant's median part (a leaf's
//     tip or rim cut off by a fold or crease) that touches other leaf parts joins the one it shares the most links
//     with among those it is a piece of (their seam not under 0.8 of each one's extent along it and the two,
//     unfolded about the seam's line, leaving no notches where it ends; or it lies within r of that part's plane,
//     or the two continue one sheet), smallest first; one that is a piece of none is a leaf seen small beside
//     another and gets no instance (leaf, LeafId -1), unless it is flat and spreads over a third of the plant's
//     typical part along and across (a leaf seen sparsely, at a grazing angle, or a young leaf: it keeps its part;
//     so does a part of flat strips only where the noise widened r); then a larger part joins the touching part it
//     shares the most links with among those continuing its sheet (planes within NormalAngle, both together off their common plane
//     by under r): a leaf cut in two by a crease.
//     A leaf's rows seen at a grazing angle (farther apart than the links: each row its own one-row strip, or cut
//     off from every region) join a leaf part: parts with no leaf shape (under MinimumLeafPoints, or only flat strips
//     and cut-off points) join a part within 2r lying in one plane with it (off it by under r / 4) that the
//     features' normals of both agree with (within about half of NormalAngle), spanning no more than a leaf
//     together; rows that reach no leaf part are an instance of their own when as wide as a leaf and apart from
//     other leaves, or when their rows are one leaf's: parallel, shortening towards both ends, or towards one end
//     only (a leaf cut across by a shadow or another leaf).
//     Parts that do not touch join when they lie in one plane (planes within half of NormalAngle, both off their
//     common plane by under r / 4) within 4r of each other, nearest first, or farther apart when together they span
//     no more than a leaf (the 90th percentile of the flat parts' spans, plus r / 4, plus r for what a piece took in
//     at a contact beyond the leaf's end): a leaf seen in pieces through a gap in the scan (the shadow of a leaf or
//     twig in front of it, as wide as what casts it). Then a part whose
//     normals form two groups more than NormalAngle apart, meeting over a seam shorter than 0.8 of each group's
//     extent along it, is two leaves whose margins touch: cut there, each side holding at least MinimumLeafPoints
//     (a crease of one blade runs from margin to margin of at least one side, whatever the side's size). So is one
//     whose groups, unfolded about the seam's line into one plane, leave notches where the seam ends (their convex
//     hulls under 0.95 of the hull of both: a blade folded or curled along any line unfolds into its own outline;
//     two leaves' outlines meet at an angle), whatever the seam's length. The joins above then run again (a side
//     may be a piece of a third leaf). Last, the parts that do not touch are joined once more with each part's plane
//     taken without its points r or more off it when those are at most a twentieth of it (a neighbour's margin or a
//     twig's side taken in at a contact, which lifts one leaf's pieces off their common plane).
//     Each leaf part of at least MinimumLeafPoints points is then a leaf, unless it is the wood's surface grown into
//     a sheet: bent off its plane by over r / 4 (root mean square) with over 0.6 of its points within 2r of the wood
//     (leaf, LeafId -1), or curved across at r as above (a twig's side cut out of a blade's region: wood). A leaf
//     point linked to another leaf goes to the leaf whose plane it lies nearest; a leaf
//     point of no leaf, or of a leaf whose plane it lies off, goes to a leaf within about 2r whose plane it lies on
//     (within 3 times the noise, at least half a spacing, and nearer than its own leaf's by as much: a strip of a
//     leaf's margin or its rows seen at a grazing angle, cut off from it, given to a neighbour); then a
//     twig lying in a leaf's plane along its margin, taken into the leaf, goes back to the wood: from the wood within
//     r of the leaf, the twig's line is walked through the leaf while its band's points stand off the blade's plane
//     as a twig's surface does, with the blade on one side of it (SegmentationTwigs.cpp). LeafId numbers
//     them over all plants in the order of their lowest point index (deterministic). Smaller leaf regions stay leaf
//     points with LeafId -1. Each leaf's base is first its point nearest the wood along the link graph (step 7 moves
//     it); the branch it grows on is the wood segment (a wood region, or a connected piece of thin wood, numbered per
//     plant) of that wood point; its area is the area of the cells of side 2s its points occupy in its own principal plane (a
//     first estimate: occluded parts are missing, a curled leaf is seen flattened).
//  5. Petioles (Organ 2): a connected piece of thin wood (the wood within t = FeatureScale * s around each point,
//     leaf points left out, a tube of radius under t / 2; pieces in line joined across gaps of up to 2t, and the
//     blade or the stem reached across such a gap along the tube's axis, as a scan breaks a petiole) that touches
//     one leaf instance only, beside its base (or anywhere, for a leaf no link joins to the wood), meets thicker
//     wood at one place (wood that is not thin going on farther than 3t: not a fork of twigs), does not continue
//     that wood's axis at its end (the thin tip of a twig), reaches no farther from it than the leaf contact
//     (nothing beyond the leaf) and is 3t to one leaf length long; its tube
//     is followed on past both ends into the blade and the stem, where the features saw their surface beside it.
//     A piece that is no petiole as a whole (a twig's thin end carrying several leaves on petioles) is cut at the
//     forks of its level-set skeleton: a branch leading to one leaf alone, of a petiole's size, leaving the side of
//     its stem (not going on in the line of the thin or thicker wood it leaves) is that leaf's petiole.
//     Petiole points have LeafId -1; the leaf's base moves to the blade's; PetioleLength is their extent along
//     their main axis.
//  6. Confidence in [0, 1]: how far the region's coherence is from the leaf/wood threshold, for judged regions;
//     half that for points that took their organ from a neighbour.
//  7. WoodDistance: each point's distance to the plant's nearest wood or petiole point (exact within 2 features'
//     radii, then between cubes of that side; a blade on a petiole meets the petiole, not the twig). A leaf's base
//     touches its twig and its apex is usually free, so LeafFitFilter turns a leaf whose midvein's apex end lies
//     clearly nearer the wood than its base end (its shape alone cannot tell an obovate blade from an ovate one
//     turned round, and a leaf seen in part often has no shape to tell from). A leaf without a petiole then gets its
//     base at its point of the least WoodDistance - LeafBaseCentreWeight x its distance from the leaf's centre
//     (near the wood, at an end of the leaf: the point fewest links from the wood is often a margin touching other
//     wood), its Branch and BaseGap from the wood point nearest that base.
// Everything is deterministic: the same cloud gives the same labels whatever the threads.
#pragma once

#include <plantmorph/DataContract.h>
#include <plantmorph/ParallelFor.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace plantmorph
{

struct SegmentationParameters
{
  int upAxis = 2;                      ///< 0 X, 1 Y, 2 Z: the vertical, for heights and the plant's base
  double featureScale = 4.0;           ///< [2, 50] spacings: radius of the covariance features (and twice it)
  double linkScale = 2.5;              ///< [1.5, 20] spacings: neighbours closer than this are linked
  double normalAngle = 25.0;           ///< (0, 90) degrees: largest normal turn between linked points of a sheet
  double creaseVariation = 0.02;       ///< (0, 1): surface variation above the median that stops the growing
  double sheetCoherence = 0.8;         ///< (0, 1): mean |n . region normal| above which a region is a sheet
  double maximumLeafElongation = 12.0; ///< [1, 1000]: length over width of a leaf (longer strips are wood)
  int minimumLeafPoints = 50;          ///< [1, 1e9]: a leaf region with fewer points gets no LeafId
};

/// Empty when every parameter is finite and in range; otherwise the message naming it and its range.
std::string ValidateSegmentationParameters(const SegmentationParameters& parameters);

/// One leaf instance (a row of the leaves table).
struct SegmentedLeaf
{
  int leafId = -1;
  int plantId = 0;
  long long points = 0;
  double area = 0.0;                              ///< first estimate: occupied cells in the leaf's principal plane
  Eigen::Vector3d base = Eigen::Vector3d::Zero(); ///< near the wood at an end of the leaf (LeafBaseCentreWeight)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  int branch = -1;            ///< the wood segment of the wood point nearest the base (-1: the plant has no wood)
  double baseGap = 0.0;       ///< distance from the base to that wood point
  double petioleLength = 0.0; ///< from the base to where its petiole meets thicker wood (0: no petiole found)
};

/// One plant (a row of the plants table).
struct SegmentedPlant
{
  int plantId = 0;
  long long points = 0, woodPoints = 0, leafPoints = 0, unassignedLeafPoints = 0;
  long long petiolePoints = 0; ///< Organ 2 (counted in neither woodPoints nor leafPoints)
  int leafCount = 0;
  double height = 0.0;  ///< extent along the up axis
  double spacing = 0.0; ///< MedianSpacing: the spacing the thresholds derive from
};

struct SegmentationResult
{
  std::vector<int> organ;         ///< per point, Organ
  std::vector<int> leafId;        ///< per point, -1 off the leaves
  std::vector<double> confidence; ///< per point, [0, 1]
  /// per point, the distance to its plant's nearest wood or petiole point (0 on them): exact within WoodDistanceReach
  /// features' radii, beyond that between cubes of that side (never under it)
  std::vector<double> woodDistance;
  std::vector<SegmentedLeaf> leaves;
  std::vector<SegmentedPlant> plants;
  std::string error; ///< non-empty: nothing else is filled
};

/// Segments `points` (the plants told apart by `plantOf`, one value per point; empty: one plant, id 0). Errors
/// (returned in `error`, the rest empty): a non-finite coordinate, a plant with fewer than MinimumPlantPoints
/// points, a plant where no wood or no leaf is found, a plant whose points lie on one plane (their spread off it
/// below half the features' radius: a board or the ground scanned in lines looks like twigs and leaves), bad
/// parameters.
SegmentationResult SegmentPlants(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& plantOf,
  const SegmentationParameters& parameters, const ParallelFor& parallel = SerialFor);

inline constexpr int MinimumPlantPoints = 20;
/// WoodDistance is exact up to this many features' radii (FeatureScale spacings): a leaf's base touches its twig,
/// within a few spacings. Beyond, it is measured between the centroids of cubes of that side (of the point's and of
/// the wood's), searched in a grid of WoodDistanceCoarseCell times that side: off by about a cube, which does not
/// change which end of a leaf is the nearer.
inline constexpr double WoodDistanceReach = 2.0;
inline constexpr double WoodDistanceCoarseCell = 4.0;

} // namespace plantmorph
