// SPDX-License-Identifier: GPL-3.0-or-later
// The tree fit's internal steps (TreeFit.h describes the method). Plain C++17 (Eigen), no VTK.
#pragma once

#include "TreeFit.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <string>
#include <tuple>
#include <vector>

namespace plantmorph
{
namespace treefit
{

/// A symmetric weighted graph in compressed rows: the neighbours of i are target[offset[i]] .. target[offset[i+1]-1].
struct Graph
{
  std::vector<int> offset, target;
  std::vector<double> weight;
};

/// The cleaned wood of one tree: its points (a subset of the input), their ids in the input, the neighbour graph,
/// geodesic distances from the base and each point's predecessor on its shortest path (-1 at the base).
struct Wood
{
  std::vector<Eigen::Vector3d> points;
  std::vector<int> input;
  double spacing = 0;
  Graph graph;
  std::vector<double> geodesic;
  std::vector<int> previous;
  bool leafLabelled = false; ///< the scan has points labelled leaf: wood labels that may hold leaves
};

/// Median over the points of the mean distance to their 6 nearest neighbours.
double PointSpacing(const std::vector<Eigen::Vector3d>& points, const ParallelFor& parallel);

/// Steps 1-2 and the geodesic distances of step 3 on the `candidates` (ids into `points`): "" or why the cloud is no
/// tree. `others` (ids into `points`, the points labelled leaf; empty without labels): those of them on a sparse line
/// (a far branch the labels call leaf) joined to the tree are wood too, and are added to `candidates`.
std::string CleanAndConnect(const std::vector<Eigen::Vector3d>& points, std::vector<int>& candidates,
  const std::vector<int>& others, const TreeFitParameters& options, const ParallelFor& parallel, Wood& wood);

/// The mean of the points `ids` of `points` and the eigen-decomposition of their scatter about it.
struct PointAxes
{
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
};
PointAxes AxesOf(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids);

/// Step 2's joining across a stretch of a branch hidden longer than the gaps the neighbour graph bridges (leaves in
/// front of it, or its base scanned too sparsely to be kept): `group` per point (-1: none), `base` the group holding
/// the base. A group apart whose points within twice its gap of the tree make a tube (at least 12 spacings long, its
/// spread across under half its spread along) that ends at its point nearest the tree (in its outer quarter, or within
/// its width of its end) and whose axis, out of the group there, reaches a tree point within 45 degrees, no farther
/// than 60 spacings nor than the tube is long, is joined to the nearest such point; shortest first, each pass against
/// the tree as it stands. The bridges (length, point, point).
std::vector<std::tuple<double, int, int>> BridgesAlongAxes(
  const std::vector<Eigen::Vector3d>& points, const std::vector<int>& group, int base, double spacing);

/// A level-set node: the points (ids into Wood::points) of one connected component of one bin.
struct Node
{
  int bin = 0, parent = -1;
  std::vector<int> points;
  std::vector<int> children;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
};

struct Skeleton
{
  double binWidth = 0;
  std::vector<Node> nodes;
  std::vector<std::vector<int>> segments; ///< node chains, base to tip; segment 0 starts at the root
  std::vector<int> segmentParent;         ///< the segment whose last node a segment's first node hangs from
  std::vector<int> nodeOf;                ///< per wood point: its node (pruned points: the fork node)
  std::vector<unsigned char> fitted;      ///< per wood point: used in the cylinder fits (0 for pruned side chains)
};

/// Step 3 on the cleaned wood.
Skeleton BuildSkeleton(const Wood& wood);

/// Removes the subtree under `node` (itself included): each of its points goes to node `to` (-1: none, the leaves)
/// unfitted, and its nodes are marked removed. The caller drops `node` from its parent's children.
void CutSubtree(
  std::vector<Node>& nodes, int node, int to, std::vector<int>& nodeOf, std::vector<unsigned char>& fitted);

/// The nodes' centroids (of their fitted points) and the segments, from the node tree as it stands.
void Segments(const Wood& wood, Skeleton& s);

/// A unit frame (u, v) normal to unit `axis`.
void Frame(const Eigen::Vector3d& axis, Eigen::Vector3d& u, Eigen::Vector3d& v);

/// Kasa's algebraic circle fit of the points projected on the plane through c spanned by (u, v): circle = (a, b, r)
/// in that plane; false when the points determine no circle.
bool CircleFit(const std::vector<Eigen::Vector3d>& q, const Eigen::Vector3d& c, const Eigen::Vector3d& u,
  const Eigen::Vector3d& v, Eigen::Vector3d& circle);

/// One cylinder fit on points: axis through `point` along unit `axis`, `radius`; residual statistics.
struct CylinderFit
{
  Eigen::Vector3d point = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::UnitZ();
  double radius = 0, rms = 0, scale = 0, coverage = 0;
  bool ok = false;
};

/// A robust cylinder through `points` started from direction `axis0` (step 4), its axis turning at most `maxTilt`
/// degrees from it (else fitted along axis0). ok is false when it cannot be fitted.
CylinderFit FitCylinder(
  const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& axis0, double spacing, double maxTilt = 35.0);

/// Steps 4-6 (everything but the traits): cylinders, branches and the points' cylinder; "" or why no radius could
/// be measured anywhere. `fitted` (when given): the cylinders as step 4 leaves them, before step 5.
std::string FitCylinders(const Wood& wood, const Skeleton& skeleton, const TreeFitParameters& options,
  const ParallelFor& parallel, TreeFitResult& result, std::vector<int>& woodCylinder,
  std::vector<TreeCylinder>* fitted = nullptr);

/// Step 7: twigs hidden in leaves. Clusters of `apart` (the points labelled wood that the fit could not connect to the
/// tree) further than a few spacings from every surface of the `modelled` cylinders draw the nearest chain tip ahead
/// of them or grown twig end within reach, which grows towards them in steps (space colonization) until every
/// cluster is reached or none is in reach; grown twigs of under three steps are dropped. The grown cylinders (no
/// points, no fitted radius: step 5 gives them the pipe model's) are appended to `cylinders`, the same cylinders as
/// step 4 left them; returns how many.
int GrowHiddenTwigs(const std::vector<Eigen::Vector3d>& apart, double spacing,
  const std::vector<TreeCylinder>& modelled, std::vector<TreeCylinder>& cylinders);

/// The distance from x to the segment [a, b] (a point when a = b).
inline double SegmentDistance(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((x - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return (x - a - t * ab).norm();
}

/// Chains whose fitted points lie (InsideShare of them) on or in the cylinders of branches not hanging from them,
/// within half a radius or two spacings of their surfaces: strips of one stem's surface that became chains side by
/// side. The lighter first, each joins those cylinders' nodes (its points and the chains hanging from it); the
/// segments are made again. Whether any chain was merged (then the cylinders are to be fitted again).
bool MergeInsideChains(const Wood& wood, const TreeFitResult& fit, Skeleton& s);

/// Chains that are leaves, not wood (a segmentation labels leaf points packed round the twigs wood): the run of
/// cylinders up to a chain's tip (the whole chain, with every chain hanging from it) none of which is measured and
/// each of which has under half of its fitted points within 3 noise deviations of its modelled surface and under half
/// within as much of the ring its points make about its axis goes back to the leaves: its points get no node. The
/// segments are made again. Whether any chain went (then the cylinders are to be fitted again).
bool ReturnOffSurfaceChains(
  const Wood& wood, const TreeFitResult& fit, const std::vector<int>& woodCylinder, Skeleton& s);

/// An unmeasured cylinder's solid (more than 3 noise deviations inside its modelled surface) holds no scan point, since
/// wood is opaque: where it holds points labelled leaf (`woodLabel` 0), at least three and more than four times as
/// many as it and its surface (within 3 noise deviations) hold points labelled wood, the model made it too wide, and
/// its radius becomes the median distance of those leaf points from its axis (at least 3 noise deviations).
void NarrowLeafFilledCylinders(
  const std::vector<Eigen::Vector3d>& points, const std::vector<int>& woodLabel, double spacing, TreeFitResult& result);

/// Step 5-6 on the fitted cylinders (fitRMS holding each fit's robust residual scale): the noise, which radii are
/// measured, the growth-length model for the others, branches and orders; "" or why no radius is measured.
/// `leafLabelled`: the scan has points labelled leaf, so fits round leaf points labelled wood are not trusted.
std::string ModelRadii(double spacing, TreeFitResult& result, bool leafLabelled = false);

/// The trait table and the branch rows' angles, heights and volumes from the cylinders; the height reaches the sparse
/// last points of a tip above the cleaned wood (`candidates`: the points that may be wood, ids into `points`).
void ComputeTraits(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& candidates, const Wood& wood,
  const TreeFitParameters& options, TreeFitResult& result);

} // namespace treefit
} // namespace plantmorph
