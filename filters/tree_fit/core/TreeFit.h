// SPDX-License-Identifier: GPL-3.0-or-later
// TreeFitFilter's algorithm (docs/methods/tree-fit.md): a scanned tree (a point cloud) becomes a quantitative
// structure model: cylinders with radius, length, parent, branch and order; its skeleton; a trait and a branch table.
// Plain C++17 (Eigen), no VTK.
//
// The method, per tree (every threshold is a multiple of the point spacing s, the median over the points of the mean
// distance to their 6 nearest neighbours; nothing is in absolute units):
//  1. Check: enough points, finite coordinates, a cloud that is neither a line nor a plane.
//  2. Clean: points whose mean neighbour distance is an outlier on a log scale (density falls with the distance to
//     the scanner, multiplicatively) are dropped, unless they lie on a sparse line: a branch scanned from far, whose
//     sparse points (points labelled leaf among them, each point's spacing taken among every point) lie within 8 of
//     their own spacings along a line (spread across it at most 0.3 of that along it), the line's spacing changing as
//     slowly as the range does, over at least 12 spacings; the neighbour graph (10 nearest within 8 s) is split into
//     connected components, and components are joined to the one holding the base across gaps up to 25 s (the
//     occlusion gaps of a scan), and a part apart across a longer hidden stretch (up to 60 s and the part's own length)
//     where its end is a tube whose axis points back at the tree within 45 degrees; what stays apart is not wood of
//     this tree. Inside a component, a gap of up to 4 s at
//     a chain's far end is bridged where the shortest path round it is 50 s longer (a junction hidden by leaves).
//  3. Skeleton: geodesic (Dijkstra) distance from the base (the lowest bin width of points), points binned by it into
//     level sets of width 6 s; the connected components of each bin are nodes; each node's parent is the node its
//     nearest-to-base point's shortest path comes from (a tree by construction). Two chains that are one stem's
//     level sets split side by side (both sides on one circle, bin by bin) become one. Side chains shorter than 3
//     bins are pruned (their points go to the fork). Side chains that leave their fork as flat sheets wider than a
//     twig's section, and lie at least half in sheets, are leaves labelled wood: they go back to the leaves. Chains of
//     nodes between forks are segments.
//  4. Cylinders: each segment is cut into pieces about two radii long; each piece gets a robust cylinder (circle fit
//     of the cross-section about the chain's direction, then Gauss-Newton on axis and radius with Huber weights);
//     where the chain's centroids give no direction and that fit lies off its points, it is fitted again from the
//     line through its segment's centroids and the fit lying closer to the points is kept.
//  5. Radii: a fit is "measured" only where the points support it (enough points, an arc of the circle seen of at
//     least 150 degrees and at least 5 s long, radius above 3 noise deviations, residuals below half the radius, and
//     within a factor 2 of the model below; in a scan with points labelled leaf, not wider than the model with a
//     residual scale above 2 noise deviations and 5 % of the radius: a ring of leaf points labelled wood round a
//     twig, fitted all round, unless the cylinder is a fork's). Every other cylinder gets its radius from the pipe
//     model: radius = a GL^b (GL: growth length, the length of the cylinder and everything it carries), a and b
//     fitted to the measured cylinders in log space (b = 1/2, area proportional to what is carried, when they do not
//     determine it), times the branch's own level (the geometric mean of its measured/model ratios): twigs are never
//     fitted from a handful of noisy points, so they are not inflated. A chain's tip run of unmeasured cylinders whose
//     points lie, most of them, more than 3 noise deviations off both the modelled surface and the ring they make
//     about the axis is leaves labelled wood: it goes back to the leaves and the cylinders are fitted again.
//  6. Branches: the trunk starts at the base; at every fork it goes on into the child most aligned with it and
//     carrying most among those turning under 25 degrees (two codominant children turning alike end it), and it ends
//     where it would turn sharply (more than 25 degrees: a lateral at a leader's thin tip is a branch), but a straight
//     stem stays one branch however heavy the laterals leaving it (a whorl's stub, parted from the first child one
//     cylinder before the others, goes on from the branch ending there); each other child starts a branch
//     of order parent + 1. Junctions: a cylinder near a fork wider than its branch's taper before it holds the
//     child's first points, not the branch: its radius follows the taper between the measured cylinders either side.
//     Traits and the branch table follow.
//  7. Hidden twigs (only when the scan has points labelled leaf): wood labelled wood that step 2 could not connect to
//     the tree (the leaves hide the twigs between) is gathered in clusters 8 s wide; those further than 16 s from
//     every fitted surface draw the nearest chain tip they lie ahead of, or grown twig end, within 60 s, which grows
//     6 s towards them (space colonization) until each is within 16 s of a twig end; grown twigs of under three
//     steps are dropped. The grown cylinders have no points (Support 0, not measured); step 5 runs again on all
//     cylinders, so that they get the pipe model's radii and the wood below them carries them.
// The fit does not depend on the order of the points (they are sorted first) nor on the thread count.
// Deterministic: no random numbers; the parallel loops write per index only.
#pragma once

#include <plantmorph/ParallelFor.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace plantmorph
{

struct TreeFitParameters
{
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ(); ///< unit vertical: heights, DBH, angles, crown
  double outlierSigma =
    3.0; ///< [1, 100]: robust deviations (log mean neighbour distance) beyond which a point is dropped
  double breastHeight = 1.3; ///< (0, 1e6]: DBH is measured this far above the lowest point (output units)
};

/// Empty when every option is finite and in range; otherwise the message naming the option and its range.
std::string ValidateTreeFitParameters(const TreeFitParameters& options);

inline constexpr int MinTreePoints = 100;

struct TreeCylinder
{
  Eigen::Vector3d start = Eigen::Vector3d::Zero(), end = Eigen::Vector3d::Zero();
  double radius = 0, length = 0;
  double fittedRadius = 0; ///< the least-squares radius (also where it was not used)
  int parent = -1;         ///< cylinder id, -1 at the base
  int branch = -1, order = 0, segment = -1;
  int points = 0;          ///< points assigned to it
  double fitRMS = 0;       ///< RMS distance of its points to its surface (final radius)
  double support = 0;      ///< points per unit length
  double coverage = 0;     ///< degrees of the circle its points cover
  bool measured = false;   ///< radius from the fit (else from the taper and pipe model)
  double growthLength = 0; ///< its length plus every length it carries
  /// unit direction of the skeleton through it: the line fitted to its nodes' centroids (widened along its chain);
  /// zero when not known
  Eigen::Vector3d path = Eigen::Vector3d::Zero();
};

struct TreeBranchRow
{
  int id = 0, parent = -1, order = 0;
  double length = 0, volume = 0, baseDiameter = 0;
  double angle = 0;           ///< degrees between its base direction and its parent's direction there (NaN: trunk)
  double azimuth = 0;         ///< degrees of its base direction in the horizontal plane, from the first horizontal axis
  double inclination = 0;     ///< degrees of its base direction above the horizontal plane
  double height = 0;          ///< height of its base above the lowest point
  std::vector<int> cylinders; ///< base to tip
};

struct TreeTraits
{
  double height = 0, dbh = 0, trunkVolume = 0, branchVolume = 0, totalVolume = 0, trunkLength = 0;
  double totalBranchLength = 0; ///< every branch except the trunk
  double branchCount = 0;       ///< branches except the trunk
  double order1 = 0, order2 = 0, order3 = 0, order4Plus = 0;
  double crownProjectedArea = 0, crownBaseHeight = 0;
  double points = 0, woodPoints = 0, fitRMS = 0, spacing = 0, noise = 0, cylinders = 0;
  double measuredVolumeFraction = 0; ///< share of the volume whose radius was measured
  /// `height` is the tree's (its top, leaves included, above the wood's lowest point, as foresters measure it);
  /// this is the wood's alone (the same without leaf points)
  double woodHeight = 0;
};

/// Names of the traits, in the order TreeTraitValues() lists them (the Trees table's columns after TreeId).
std::vector<std::string> TreeTraitNames();
std::vector<double> TreeTraitValues(const TreeTraits& traits);

struct TreeFitResult
{
  std::string error; ///< empty on success; then everything below is filled, else everything is empty
  std::vector<TreeCylinder> cylinders;
  std::vector<TreeBranchRow> branches; ///< branch 0 is the trunk
  // One entry per input point.
  std::vector<int> pointCylinder, pointBranch; ///< -1: not on the tree's wood
  std::vector<unsigned char> wood;             ///< 1: used as this tree's wood
  std::vector<double> fitDistance;             ///< signed distance to its cylinder's surface; NaN if none
  TreeTraits traits;
};

/// Fits one tree. `woodLabel`: empty, or one value per point (nonzero: wood; only those are used). Never throws for
/// bad input: the result's error says what is wrong. Loops inside run through `parallel`.
TreeFitResult FitTree(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& woodLabel,
  const TreeFitParameters& options, const ParallelFor& parallel = SerialFor);

} // namespace plantmorph
