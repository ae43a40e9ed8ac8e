// SPDX-License-Identifier: GPL-3.0-or-later
// The steps of one plant's segmentation (PlantSegmentation.h explains the method). Internal to the method.
#pragma once

#include "PlantSegmentation.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace plantmorph
{
class PointGrid;
namespace segmentation
{

/// Per point of one plant: the covariance features at the two scales.
struct PointFeatures
{
  std::vector<Eigen::Vector3d> normal;    ///< unit, at scale r
  std::vector<float> spread;              ///< width across the main axis over the radius, at r and 2r: the larger
  std::vector<float> variation;           ///< l3 / (l1 + l2 + l3) at r: 0 on a plane
  std::vector<Eigen::Vector3d> direction; ///< unit main axis at scale r; zero with under 3 points (nothing measured)
  std::vector<float> nearSpread;          ///< width across the main axis over the radius, at r alone
  double radius = 0.0;                    ///< r: FeatureScale spacings, or wider on a noisy cloud
  double noise = 0.0;                     ///< the range noise measured (NoiseLevel)
};

/// The radius graph: each point's neighbours closer than LinkScale * s, in ascending index (CSR).
struct LinkGraph
{
  std::vector<std::size_t> offsets;
  std::vector<int> neighbours;
};

/// The connected component of `seed` in the link graph among the points `member(j)` accepts, in the order a
/// breadth-first walk reaches them (the seed first, whether or not `member` accepts it). Every point reached is marked
/// in `seen`, the seed too; a marked point is not entered again.
template <class Member>
void LinkComponent(
  const LinkGraph& graph, std::size_t seed, Member&& member, std::vector<char>& seen, std::vector<int>& component)
{
  component.assign(1, static_cast<int>(seed));
  seen[seed] = 1;
  for (std::size_t k = 0; k < component.size(); ++k)
  {
    const auto q = static_cast<std::size_t>(component[k]);
    for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
    {
      const auto j = static_cast<std::size_t>(graph.neighbours[e]);
      if (!seen[j] && member(j))
      {
        seen[j] = 1;
        component.push_back(static_cast<int>(j));
      }
    }
  }
}

/// One plant's labels: per point organ, leaf (index in `leaves`, -1 off them) and confidence.
struct PlantLabels
{
  std::vector<int> organ, leaf;
  std::vector<double> confidence;
  std::vector<SegmentedLeaf> leaves; ///< leafId: the index in this plant
  std::vector<int> woodSegment;      ///< per point, the wood segment (Branch) of a wood point, -1 elsewhere
  SegmentedPlant plant;
};

/// The lower quartile of the plane-fit residual (sqrt of the smallest covariance eigenvalue) within r over a
/// sample of the points: the range noise on the flattest quarter of the cloud (leaves, wide trunks).
double NoiseLevel(const std::vector<Eigen::Vector3d>& points, double r, const ParallelFor& parallel);

/// Features and the link graph (threaded, deterministic).
void ComputeFeatures(const std::vector<Eigen::Vector3d>& points, double spacing, const SegmentationParameters& p,
  const ParallelFor& parallel, PointFeatures& features, LinkGraph& graph);

/// A neighbourhood narrower than this fraction of its radius across its main axis is a line: at both scales, a
/// point too thin to carry a sheet (IsLinear); at r alone, one scan row of a surface seen at a grazing angle (IsRow).
inline constexpr float LineSpread = 0.2f;

/// A point too thin to carry a sheet: its neighbourhood narrow at both scales (a twig or petiole thinner than
/// about 0.4 r; a leaf's margin, a half disk, spreads 0.26).
inline bool IsLinear(const PointFeatures& f, std::size_t i)
{
  return f.spread[i] < LineSpread;
}

/// A point whose neighbourhood of radius r is a line (LineSpread at r alone, at least 3 points measured): one scan
/// row of a surface seen at a grazing angle, its next rows beyond r. Its smallest eigenvector is any direction across
/// the row, so its normal is not measured; its main axis (the row's direction) is, and the surface's plane contains
/// it.
inline bool IsRow(const PointFeatures& f, std::size_t i)
{
  return f.direction[i].squaredNorm() > 0.0 && f.nearSpread[i] < LineSpread;
}

/// What the features measured of the surface at point i, as a matrix whose quadratic form n^T M n says how well a
/// plane of unit normal n agrees with it (1 at best, 0 at worst): n_i n_i^T for a measured normal (a neighbourhood
/// spread across its main axis); I - d_i d_i^T for a neighbourhood that is a line of direction d_i (the plane
/// contains the line: this is the best agreement over the normals such a neighbourhood allows); zero, with
/// `weight` 0, when the neighbourhood holds under 3 points. `weight` is 1 otherwise.
inline Eigen::Matrix3d SurfaceEvidence(const PointFeatures& f, std::size_t i, double& weight)
{
  const Eigen::Vector3d& d = f.direction[i];
  if (d.squaredNorm() == 0.0)
  {
    weight = 0.0;
    return Eigen::Matrix3d::Zero();
  }
  weight = 1.0;
  if (IsRow(f, i))
    return Eigen::Matrix3d::Identity() - d * d.transpose();
  return f.normal[i] * f.normal[i].transpose();
}
/// The mean of points[ids] (into `mean`, ids not empty) and their scatter matrix about it (the sum of the outer
/// products; divided by the count it is their covariance). Every point is used, unlike the sampled per-point features.
Eigen::Matrix3d Scatter(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, Eigen::Vector3d& mean);

/// The moments of a leaf part's points (count, mean, scatter about the mean), merged in constant time when two
/// parts join: its best plane and its spread off it.
struct PartMoments
{
  double count = 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();

  /// The moments of points[ids].
  static PartMoments Of(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids)
  {
    PartMoments m;
    m.count = static_cast<double>(ids.size());
    m.scatter = Scatter(points, ids, m.mean);
    return m;
  }

  PartMoments Merged(const PartMoments& o) const
  {
    PartMoments m;
    m.count = count + o.count;
    const Eigen::Vector3d d = o.mean - mean;
    m.mean = mean + d * (o.count / m.count);
    m.scatter = scatter + o.scatter + d * d.transpose() * (count * o.count / m.count);
    return m;
  }
  /// The principal spreads (standard deviations along the covariance's eigenvectors), smallest first: the spread
  /// off the best plane, across the long axis in it, along it.
  Eigen::Vector3d Spreads() const
  {
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter / count).eigenvalues().cwiseMax(0.0).cwiseSqrt();
  }
  /// The normal of the best plane (unit) and the spread off it (the root mean square distance).
  Eigen::Vector3d Normal(double& spread) const
  {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter / count);
    spread = std::sqrt(std::max(0.0, solver.eigenvalues()[0]));
    return solver.eigenvectors().col(0);
  }
};

/// The extent of points[ids] along the unit `axis` through `mean`: from the lowest to the highest.
double ExtentAlong(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, const Eigen::Vector3d& mean,
  const Eigen::Vector3d& axis);

/// Region growing of smooth sheets: each point's region (-1: linear points, never grown); returns the count.
int GrowRegions(const PointFeatures& features, const LinkGraph& graph, const SegmentationParameters& p,
  const ParallelFor& parallel, std::vector<int>& region);

/// Petioles (step 5 of PlantSegmentation.h; docs/methods/segmentation.md gives every threshold): each connected
/// piece of thin wood (the wood within t = FeatureScale s around each point, leaf points left out, a tube of radius
/// under t / 2; connected over the links and, across the gaps a scan leaves, along the tube's axis within 2t) that
/// touches one leaf instance only beside its base, meets thicker wood at one place (not a fork of twigs, not the
/// end of a twig it continues), leads to that leaf only and is 3t to one leaf length long becomes Organ 2, with the leaf's and the
/// thicker wood's points inside its tube past its two ends; so does such a piece that meets no other wood (its stem
/// unseen) when it carries the blade's midrib on (leaves the blade within 40 degrees of it), and, in a piece that is
/// no petiole as a whole, the tube that ends at a leaf's base walked from the blade to where it meets its stem, when
/// it carries the midrib on. Petiole points leave
/// their leaf (LeafId -1, the leaf's Points and base updated); the leaf's PetioleLength is the petiole's extent.
/// Returns the points made petiole.
std::size_t FindPetioles(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const LinkGraph& graph,
  double spacing, const SegmentationParameters& p, const ParallelFor& parallel, PlantLabels& labels);

/// A crease of one blade runs across a whole side of it: a seam shorter than this fraction of each side's extent
/// along it is where two leaves touch (CutAtShortSeams). A fold, roll or bend spans a side from margin to margin
/// (about 1 for at least one side); the 21 merged pairs of leaves looked at on the simulated tree and herb
/// (their margins touching) give 0.04-0.76 for both.
inline constexpr double SeamFraction = 0.8;

/// Two sides unfolded about their seam's line (each point at its position along the line and its distance from it,
/// one side's distances negated) whose convex hulls' areas sum to under this fraction of the hull of both are two
/// leaves, whatever the seam's length: their outlines meet at an angle where the seam ends and leave notches. A
/// blade folded, rolled or curled along any line unfolds into its own outline: 0.99-1.00 for the synthetic folded,
/// rolled, curled and tip-folded blades; 0.84-0.96 for the 22 pairs of leaves at an angle merged into one instance
/// on the simulated tree and shrub (flat blades about 45 degrees apart, in 11 of them meeting along the whole edge
/// of the smaller one, the seam 0.84-1.16 of its extent).
inline constexpr double NotchedHullFraction = 0.95;

/// Two touching leaves grown into one leaf part (their normals turn smoothly across the contact): each part of at
/// least 2 `smallest` points (a leaf's fewest, MinimumLeafPoints) whose normals form two groups with axes further
/// apart than `cosine` (half of NormalAngle), each group made one linked piece, is cut between them when each side
/// has at least `smallest` points and their seam (the points linked to the other side) is shorter than SeamFraction
/// of each side's extent along it, or the sides unfolded about the seam leave notches (NotchedHullFraction); each
/// side is looked at again. A part longer than `longest` along its main axis (more than any leaf of the plant; 0:
/// no such bound) is cut between its two normal groups whatever its seam: several leaves meeting at a node, or
/// along their margins, whose sides meet over a long seam. The parts are judged on `parallel`; the cuts are the
/// same on any number of threads. Returns the cuts made.
std::size_t CutAtShortSeams(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const LinkGraph& graph,
  double cosine, std::size_t smallest, double longest, const ParallelFor& parallel,
  std::vector<std::vector<int>>& parts);

/// Whether two touching parts `a` and `b` (their points idsA and idsB; partOf maps a point to its part, -1 or short
/// of the point elsewhere) meet over a short seam: the points of either linked to the other, along their own line,
/// shorter than SeamFraction of each part's extent along that line (or fewer than three such points, unless
/// `touchSaysTwo` is false: a line of missing points between two pieces of one sheet leaves no seam), or the two
/// unfolded about that line leave notches where it ends (NotchedHullFraction). A crease that cut a piece off its
/// leaf runs across the piece from margin to margin and unfolds into the leaf's outline; a leaf touching another
/// meets it over part of its margin, or at an angle where the seam ends.
bool ShortSeamBetween(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph,
  const std::vector<int>& partOf, int a, int b, const std::vector<int>& idsA, const std::vector<int>& idsB,
  bool touchSaysTwo = true);

/// A whole component of the link graph called wood, of at least JudgedRegionPoints points, that is flat (its
/// smallest principal spread under FlatPieceThickness of the middle one; not two twigs' sides forking in one plane:
/// none curved across at r by 3 range noises `noise`, CurvedAcross) and lies farther than the features' radius
/// r from every other wood point is a leaf's, or a piece of one, that the regions' judging called a strip: a branch
/// is a tube, flat only where the scan sees a narrow arc of a thick one, and the rest of that branch lies within r.
/// Over the 42 stored scans of the segmentation benchmark (six plants) such pieces held 2,925 leaf points and no wood
/// point (within 3 spacings of other wood instead of 4: 10 wood points more; not flat, mostly wood). Returns the
/// points made leaf.
std::size_t FlatPiecesAwayFromWood(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, double radius,
  double noise, std::vector<int>& organ, std::vector<double>& confidence);

/// A piece of wood (a component of the links among the wood points, of at least JudgedRegionPoints points) that lies
/// NoisyPieceApart (3) features' radii r or more from all other wood, is compact (its length under
/// NoisyPieceElongation, 4, widths) and is flat within the range noise `noise` measured (its spread off its plane
/// under NoisyPieceThickness, 2.5, of it) is a leaf's: on a noisy scan the regions' judging calls pieces of leaves
/// wood (a margin's strip, a piece beyond a crease, normals turned by the noise), and those are as thick as the
/// noise, so at 1 % noise only a wide one is flat for FlatPiecesAwayFromWood (its thickness under a tenth of its
/// width), and they touch their leaf's other points, so they are no whole component of the link graph. A twig's piece
/// seen apart from its wood is long and thin, a thick branch's thicker than the noise on a scan of low noise. On the
/// 48 stored scans of the segmentation benchmark: leaf IoU at least 0.98 on 45 -> 48, wood IoU at least 0.90 on 39
/// -> 42 (benchmarks/README.md). Judged all at once on the organs as they stand. Returns the points made leaf.
std::size_t NoisyFlatPiecesAwayFromWood(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph,
  double radius, double noise, std::vector<int>& organ, std::vector<double>& confidence);

/// How LeafPointsOntoTheirPlane moves points: cells of side `cell` (twice the features' radius), the `margin` a point
/// must lie within of a plane and nearer it than its own part's, `borderMargin` for a point linked to another part,
/// and up to `passes` passes.
struct PlaneMoves
{
  double cell = 0.0, margin = 0.0, borderMargin = 0.0;
  int passes = 3;
};

/// Leaf points in the wrong instance, or in none, go to the leaf whose plane they lie in. Where two instances touch,
/// the border between them is drawn by the order the regions grew and joined in, not by the leaves' surfaces: a margin
/// row or two of one leaf goes to its neighbour, and the leaf's fitted area loses that strip (a row of a leaf 1 long,
/// 0.007 apart, is about 3 % of its area). A strip of a leaf's margin, or rows of it seen at a grazing angle (farther
/// apart than the links), may go to a neighbouring leaf it is not linked to, or to no leaf. Such points lie in their
/// own leaf's plane and off the neighbour's by about their distance from it (on the 4-position scan of the shrub of
/// varied leaf sizes, 0.0005 off the one and 0.008-0.03 off the other), so the plane tells them apart where the nearest
/// points do not. The points in cells of side `rule.cell`; in each cell's 3 x 3 x 3 block, the plane of each kept part
/// (`kept`) with at least PlanePoints points there, spread across their main direction (not a row alone). A point of a
/// kept part linked (`graph`) to a point of another kept part goes to the part, among those it is linked to, whose
/// plane it lies nearest, when nearer than its own part's by more than `rule.borderMargin`; any other point of a kept
/// part, to the part whose plane it lies on within `rule.margin` and nearer than its own part's by more than
/// `rule.margin`; a leaf point (`organ`) in no kept part, to the part whose plane it lies nearest within `rule.margin`.
/// Each of up to `rule.passes` passes decides on the parts as they are (a move does not change another's plane in that
/// pass), threaded on `parallel`, the same on any number of threads; a row moved lets the next row reach the border in
/// the next pass. Two leaves side by side in one plane keep their border: no plane is nearer. Returns the points moved.
std::size_t LeafPointsOntoTheirPlane(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph,
  const std::vector<int>& organ, const PlaneMoves& rule, const std::vector<char>& kept, const ParallelFor& parallel,
  std::vector<std::vector<int>>& parts);
/// The fewest of a part's points in a block that give its plane there.
inline constexpr int PlanePoints = 10;
/// LeafPointsOntoTheirPlane's border margin, in point spacings; its other margin is this or
inline constexpr double PlaneMargin = 0.5;
/// this many times the noise measured (NoiseLevel), the larger. Away from the border, at 1 % noise half a spacing
/// moved more points to a wrong leaf than to their own (the shrub of varied sizes from four positions: of 924 moved,
/// 312 to their own leaf, 473 to another): a point's distance to its own plane varies by the noise.
inline constexpr double PlaneNoiseMargin = 3.0;

/// A twig lying along a leaf's edge in the leaf's plane is taken into the leaf's instance where it is thinner than
/// the features' radius: its surface, smoothed over r, has the blade's normal, and at 1 % noise r (12 times the
/// noise) is wider than the twig. The leaf's fitted blade then reaches over the twig (on the shrub of varied leaf
/// sizes from four positions at 1 % noise, 4,684 wood points in leaf instances, leaves up to 10 % over their area).
/// From the wood points within r of a kept part (`kept`), the twig's line (TwigLineAt in SegmentationTwigs.cpp) is
/// walked through the part a window at a time, and the part's points in its band are wood while the window stands
/// off the blade's plane as a twig's surface does, beside the blade's edge. Each part is judged against the wood as
/// it was before the step (threaded on `parallel`, the same on any number of threads); the points taken leave
/// `parts` and become wood (`organ`, confidence 0.5). Returns the points moved.
std::size_t TwigsAlongLeafEdges(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& wood,
  const PointGrid& woodGrid, const std::vector<char>& kept, double radius, double spacing, const ParallelFor& parallel,
  std::vector<std::vector<int>>& parts, std::vector<int>& organ, std::vector<double>& confidence);
/// The wood points a twig's line is fitted to: at least this many in a ball of 2r, 4r or 8r (TwigLineBalls balls).
inline constexpr std::size_t TwigLinePoints = 10;
inline constexpr int TwigLineBalls = 3;
/// A ball's wood is a line when its spread across its main axis (the middle eigenvalue of its covariance) is under
/// this share of its spread along it (a fifth of the standard deviation).
inline constexpr double TwigLineSpread = 0.04;
/// A window along the line: at least this many of the part's points in the band, r / 2 long and at least this many
/// spacings.
inline constexpr std::size_t TwigWindowPoints = 6;
inline constexpr double TwigWindowSpacings = 10.0;
/// The blade's points around a window that give its plane (and a part this small is not looked at).
inline constexpr std::size_t TwigPlanePoints = 20;
/// A window is a twig's surface when its points stand off the blade's plane by more than this many times the
/// blade's own points (root mean square) and by more than TwigBump of the band's width...
inline constexpr double TwigOffPlane = 1.5;
inline constexpr double TwigBump = 0.25;
/// ... when the blade's points beside it on the line's other side are at most this share of those on its side...
inline constexpr double TwigOtherSide = 0.1;
/// ... and its points' mean lies within this share of the band's width of the line.
inline constexpr double TwigCentred = 0.35;
/// A part that would lose more than this share of its points to twigs keeps them all.
inline constexpr double TwigPartShare = 0.25;

/// The whole segmentation of one plant; "" or the reason it cannot be segmented.
std::string SegmentPlant(const std::vector<Eigen::Vector3d>& points, const SegmentationParameters& p,
  const ParallelFor& parallel, PlantLabels& labels);

} // namespace segmentation
} // namespace plantmorph
