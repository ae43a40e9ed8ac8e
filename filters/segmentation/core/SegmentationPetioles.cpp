// SPDX-License-Identifier: GPL-3.0-or-later
// Step 6 of the segmentation (PlantSegmentation.h): petioles, the thin wood that carries one leaf from its base to
// the thicker wood.
#include "SegmentationSteps.h"

#include "PointGrid.h"

#include <plantmorph/MathConstants.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>

namespace plantmorph
{
namespace segmentation
{
namespace
{
/// A wood point is thin when the wood within the features' radius r around it is a tube of radius under this
/// fraction of r (2 spacings at the default FeatureScale of 4): its width across its main axis, sqrt(2 l2) for
/// points spread around a tube (l2 the covariance's middle eigenvalue), is below it. A patch of a stem thicker than
/// r gives about 0.7 r (a disk of radius r: l2 = r^2 / 4).
constexpr double ThinRadiusFraction = 0.5;
/// At most this many wood neighbours (every k-th) enter a thin point's covariance.
constexpr std::size_t ThinSample = 128;
/// A petiole's tube, followed past its ends (FollowTube), is this many times the radius of its points near the end
/// (their 90th percentile off its axis): room for the noise.
constexpr double TubeMargin = 1.25;
/// A petiole meets the thicker wood at one place: its points linked to it lie within this many r of their mean (a
/// twig whose thinness flickers along its length, thick at every bud and fork, meets it all along). At a petiole's
/// foot on a twig one to three r thick, the petiole's last points flicker thin and not (the twig's surface enters
/// their neighbourhood): their contacts spread over up to 2r (1.6-1.8 r on the benchmark's petioled plant).
constexpr double ContactRadii = 2.5;
/// A petiole touches the thicker wood at its foot: under this share of its points are linked to it over the scan's
/// own links, gaps not bridged (on the benchmark's petioled plant 0.1-0.3, with the bridged contacts). A strip of thin points along a twig's flank, or a few thin points bridged
/// beside it, touch it all along (on the simulated shrub and herb, 21 of 22, 25 of 26 and 4 of 4 points).
constexpr double ContactShare = 0.5;
/// A petiole's thin piece is at least this many r long: shorter, it cannot be told from the thin flicker of the
/// features at a leaf's junction with a twig (on the simulated shrub and tree, pieces of 1 to 4 links).
constexpr double ShortestPetioleRadii = 3.0;
/// A petiole meets thicker wood when the wood that is not thin goes on from its contacts farther than this many r
/// (MeetsThickerWood).
constexpr double ThickerReachRadii = 3.0;
/// A petiole is at most this many times its leaf's length (the blade's extent along its main axis).
constexpr double PetioleLengthLeaves = 1.0;
/// A scan breaks a petiole into pieces (the blade's shadow, rows of the scan passing beside a tube thinner than the
/// spacing): a thin point is linked across a gap of up to this many r to the points that lie inside its tube (within
/// ThinRadiusFraction r of the axis of the wood around it), thin ones only when it lies inside theirs too (collinear
/// pieces), so a broken petiole is one piece from the blade to the thicker wood.
constexpr double GapRadii = 2.0;
/// Across a gap, a thin point reaches the blade within this angle (degrees) of its tube's axis: a petiole meets its
/// blade at an angle (the blade's base narrows to a point, and the blade turns off the petiole's axis, 30 degrees on
/// the benchmark's petioled plant), so the blade's first points lie off the tube.
constexpr double GapConeDegrees = 45.0;
/// A thin point's tube has an axis when the thin wood within 2r around it is at least this many times longer than
/// wide (the covariance's largest eigenvalue over its middle one; a tube of radius 0.5 r seen over 2r from its end
/// gives 3.7).
constexpr double AxisElongation = 2.0;

/// The mean of points[ids] (ids not empty).
Eigen::Vector3d MeanOf(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids)
{
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int j : ids)
    mean += points[static_cast<std::size_t>(j)];
  return mean / static_cast<double>(ids.size());
}

/// The tube the points cloud[near] (every k-th, at most ThinSample) lie on: its centre (their mean), axis (their
/// main axis, when they are AxisElongation times longer than wide) and width across the axis, sqrt(2 l2) (l2 the
/// covariance's middle eigenvalue): a tube's radius for points spread around it, 0.7 r for a disk of radius r.
struct LocalTube
{
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::Zero();
  double width = 0.0;
  bool hasAxis = false;
};

LocalTube FitLocalTube(const std::vector<Eigen::Vector3d>& cloud, const std::vector<int>& near)
{
  LocalTube tube;
  if (near.size() < 3)
    return tube;
  const std::size_t stride = (near.size() + ThinSample - 1) / ThinSample;
  double count = 0.0;
  for (std::size_t q = 0; q < near.size(); q += stride, count += 1.0)
    tube.centre += cloud[static_cast<std::size_t>(near[q])];
  tube.centre /= count;
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  for (std::size_t q = 0; q < near.size(); q += stride)
  {
    const Eigen::Vector3d d = cloud[static_cast<std::size_t>(near[q])] - tube.centre;
    c += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(c / count);
  const Eigen::Vector3d l = solver.eigenvalues().cwiseMax(0.0);
  tube.width = std::sqrt(2.0 * l[1]);
  tube.axis = solver.eigenvectors().col(2);
  tube.hasAxis = l[2] > AxisElongation * l[1];
  return tube;
}

/// The plant's wood points (`ids` their indices in the cloud) and a grid over them.
struct WoodCloud
{
  std::vector<Eigen::Vector3d> points;
  std::vector<int> ids;
};

/// Per point, whether it is wood and the wood within r around it is a thin tube (width under ThinRadiusFraction r).
/// Leaf points are left out of the neighbourhood, so a petiole stays thin up to the blade.
std::vector<char> ThinWood(
  const WoodCloud& wood, const PointGrid& grid, std::size_t n, double radius, const ParallelFor& parallel)
{
  std::vector<char> thin(n, 0);
  parallel(wood.points.size(), [&](std::size_t begin, std::size_t end) {
    std::vector<int> near;
    for (std::size_t k = begin; k < end; ++k)
    {
      grid.Within(wood.points[k], radius, near);
      thin[static_cast<std::size_t>(wood.ids[k])] =
        near.size() >= 3 && FitLocalTube(wood.points, near).width < ThinRadiusFraction * radius;
    }
  });
  return thin;
}

/// Per thin point, the tube of the thin wood within `reach` (2r) around it: twice the features' ball, so a point
/// at a piece's end, with the piece on one side only, still sees it longer than wide.
std::vector<LocalTube> ThinTubes(const WoodCloud& wood, const PointGrid& grid, const std::vector<char>& thin,
  double reach, const ParallelFor& parallel)
{
  std::vector<LocalTube> tubes(thin.size());
  parallel(wood.points.size(), [&](std::size_t begin, std::size_t end) {
    std::vector<int> near, thinNear;
    for (std::size_t k = begin; k < end; ++k)
    {
      const auto i = static_cast<std::size_t>(wood.ids[k]);
      if (!thin[i])
        continue;
      grid.Within(wood.points[k], reach, near);
      thinNear.clear();
      for (int q : near)
        if (thin[static_cast<std::size_t>(wood.ids[static_cast<std::size_t>(q)])])
          thinNear.push_back(q);
      tubes[i] = FitLocalTube(wood.points, thinNear);
    }
  });
  return tubes;
}

/// Whether q lies inside `tube` (within `width` of its axis).
bool InsideTube(const LocalTube& tube, const Eigen::Vector3d& q, double width)
{
  const Eigen::Vector3d d = q - tube.centre;
  return tube.hasAxis && (d - d.dot(tube.axis) * tube.axis).norm() < width;
}

/// The link graph with the gaps a scan leaves in thin wood bridged (GapRadii): each thin point with a tube axis is
/// linked to the points farther than a link and within GapRadii r that are thin wood inside its tube whose own tube
/// holds it (collinear pieces), thicker wood inside its tube (the stem it leaves) or a leaf instance's points within
/// GapConeDegrees of its axis (the blade it enters). Links both ways, each point's neighbours ascending.
LinkGraph BridgeGaps(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, const PlantLabels& labels,
  const std::vector<char>& thin, const std::vector<LocalTube>& tubes, double radius, double link,
  const ParallelFor& parallel)
{
  const std::size_t n = points.size();
  const double reach = GapRadii * radius, width = ThinRadiusFraction * radius;
  const double cone = std::cos(GapConeDegrees * Pi / 180.0);
  std::vector<int> thinIds;
  for (std::size_t i = 0; i < n; ++i)
    if (thin[i] && tubes[i].hasAxis)
      thinIds.push_back(static_cast<int>(i));
  if (thinIds.empty())
    return graph;
  const PointGrid grid(points, reach);
  std::vector<std::vector<int>> extra(thinIds.size());
  parallel(thinIds.size(), [&](std::size_t begin, std::size_t end) {
    std::vector<int> near;
    for (std::size_t k = begin; k < end; ++k)
    {
      const auto p = static_cast<std::size_t>(thinIds[k]);
      grid.Within(points[p], reach, near);
      for (int q : near)
      {
        const auto j = static_cast<std::size_t>(q);
        const Eigen::Vector3d d = points[j] - points[p];
        if (d.norm() < link)
          continue;
        const bool wood = labels.organ[j] == OrganWood;
        const bool inside = InsideTube(tubes[p], points[j], width);
        if ((wood && thin[j] && inside && InsideTube(tubes[j], points[p], width)) || (wood && !thin[j] && inside) ||
          (labels.leaf[j] >= 0 && std::abs(d.dot(tubes[p].axis)) >= cone * d.norm()))
          extra[k].push_back(q);
      }
    }
  });
  std::vector<std::vector<int>> added(n);
  for (std::size_t k = 0; k < thinIds.size(); ++k)
    for (int q : extra[k])
    {
      added[static_cast<std::size_t>(thinIds[k])].push_back(q);
      added[static_cast<std::size_t>(q)].push_back(thinIds[k]);
    }
  LinkGraph bridged;
  bridged.offsets.assign(n + 1, 0);
  bridged.neighbours.reserve(graph.neighbours.size());
  for (std::size_t i = 0; i < n; ++i)
  {
    std::vector<int>& mine = added[i];
    if (mine.empty()) // no gap link: its links as they are
    {
      bridged.neighbours.insert(bridged.neighbours.end(),
        graph.neighbours.begin() + static_cast<std::ptrdiff_t>(graph.offsets[i]),
        graph.neighbours.begin() + static_cast<std::ptrdiff_t>(graph.offsets[i + 1]));
      bridged.offsets[i + 1] = bridged.neighbours.size();
      continue;
    }
    mine.insert(mine.end(), graph.neighbours.begin() + static_cast<std::ptrdiff_t>(graph.offsets[i]),
      graph.neighbours.begin() + static_cast<std::ptrdiff_t>(graph.offsets[i + 1]));
    std::sort(mine.begin(), mine.end());
    mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
    bridged.neighbours.insert(bridged.neighbours.end(), mine.begin(), mine.end());
    bridged.offsets[i + 1] = bridged.neighbours.size();
    std::vector<int>().swap(mine);
  }
  return bridged;
}

/// Whether the wood a thin piece meets at `contacts` is thicker wood and not a fork of thin wood: the wood that is
/// not thin linked to the contacts reaches, over the links through wood that is not thin, farther than
/// ThickerReachRadii r from them. At a fork of twigs the wood is not thin only around the fork itself (two twigs in
/// a neighbourhood spread it), within about r; a stem or a branch thicker than a petiole goes on. `mark` is scratch
/// (all 0 in and out).
bool MeetsThickerWood(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, const PlantLabels& labels,
  const std::vector<char>& thin, const std::vector<int>& contacts, double radius, std::vector<char>& mark)
{
  const Eigen::Vector3d mean = MeanOf(points, contacts);
  const auto thick = [&](std::size_t j) { return labels.organ[j] == OrganWood && !thin[j]; };
  std::vector<int> reached;
  std::deque<int> queue;
  bool far = false;
  const auto visit = [&](std::size_t q) {
    for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1] && !far; ++e)
    {
      const auto j = static_cast<std::size_t>(graph.neighbours[e]);
      if (mark[j] || !thick(j))
        continue;
      mark[j] = 1;
      reached.push_back(static_cast<int>(j));
      queue.push_back(static_cast<int>(j));
      far = (points[j] - mean).norm() > ThickerReachRadii * radius;
    }
  };
  for (int c : contacts)
    visit(static_cast<std::size_t>(c));
  while (!queue.empty() && !far)
  {
    const auto q = static_cast<std::size_t>(queue.front());
    queue.pop_front();
    visit(q);
  }
  for (int j : reached)
    mark[static_cast<std::size_t>(j)] = 0;
  return far;
}

/// Each leaf's length: the extent of its points along their main axis (2 sqrt(3 l1), a uniform segment's).
std::vector<double> LeafLengths(const std::vector<Eigen::Vector3d>& points, const PlantLabels& labels)
{
  const std::size_t count = labels.leaves.size();
  std::vector<double> n(count, 0.0);
  std::vector<Eigen::Vector3d> sum(count, Eigen::Vector3d::Zero());
  std::vector<Eigen::Matrix3d> square(count, Eigen::Matrix3d::Zero());
  for (std::size_t i = 0; i < points.size(); ++i)
    if (labels.leaf[i] >= 0)
    {
      const auto l = static_cast<std::size_t>(labels.leaf[i]);
      n[l] += 1.0;
      sum[l] += points[i];
      square[l] += points[i] * points[i].transpose();
    }
  std::vector<double> length(count, 0.0);
  for (std::size_t l = 0; l < count; ++l)
    if (n[l] > 0.0)
    {
      const Eigen::Vector3d mean = sum[l] / n[l];
      const Eigen::Matrix3d c = square[l] / n[l] - mean * mean.transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(c, Eigen::EigenvaluesOnly);
      length[l] = 2.0 * std::sqrt(3.0 * std::max(0.0, solver.eigenvalues()[2]));
    }
  return length;
}

/// One connected piece of thin wood and what it touches over the link graph.
struct ThinPiece
{
  std::vector<int> ids;
  int leaf = -1; ///< the one leaf instance it touches (-1: none)
  bool severalLeaves = false;
  std::vector<int> thick;  ///< its points linked to thicker wood
  std::vector<int> onLeaf; ///< its points linked to the leaf
};

ThinPiece CollectPiece(
  const LinkGraph& graph, const PlantLabels& labels, const std::vector<char>& thin, int seed, std::vector<char>& seen)
{
  ThinPiece piece;
  std::deque<int> queue{ seed };
  seen[static_cast<std::size_t>(seed)] = 1;
  while (!queue.empty())
  {
    const int q = queue.front();
    queue.pop_front();
    piece.ids.push_back(q);
    bool thickContact = false, leafContact = false;
    for (std::size_t e = graph.offsets[static_cast<std::size_t>(q)]; e < graph.offsets[static_cast<std::size_t>(q) + 1];
         ++e)
    {
      const auto j = static_cast<std::size_t>(graph.neighbours[e]);
      if (labels.organ[j] == OrganWood && !thin[j])
        thickContact = true;
      else if (labels.organ[j] == OrganWood && !seen[j])
      {
        seen[j] = 1;
        queue.push_back(static_cast<int>(j));
      }
      else if (labels.leaf[j] >= 0)
      {
        leafContact = true;
        piece.severalLeaves = piece.severalLeaves || (piece.leaf >= 0 && piece.leaf != labels.leaf[j]);
        piece.leaf = labels.leaf[j];
      }
    }
    if (thickContact)
      piece.thick.push_back(q);
    if (leafContact)
      piece.onLeaf.push_back(q);
  }
  return piece;
}

/// Hops over the piece (`member`) from `sources` (multi-source breadth-first) into `hops` (-1 elsewhere); returns
/// the largest.
int FarthestHops(
  const LinkGraph& graph, const std::vector<int>& sources, std::vector<int>& hops, const std::vector<char>& member)
{
  std::deque<int> queue;
  for (int s : sources)
  {
    hops[static_cast<std::size_t>(s)] = 0;
    queue.push_back(s);
  }
  int farthest = 0;
  while (!queue.empty())
  {
    const auto q = static_cast<std::size_t>(queue.front());
    queue.pop_front();
    farthest = std::max(farthest, hops[q]);
    for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
    {
      const auto j = static_cast<std::size_t>(graph.neighbours[e]);
      if (member[j] && hops[j] < 0)
      {
        hops[j] = hops[q] + 1;
        queue.push_back(static_cast<int>(j));
      }
    }
  }
  return farthest;
}

/// The tube a piece of thin wood ends in at its contact points `end`: its axis (through `centre`, along `axis`, unit,
/// pointing out of the piece) and radius, from the piece's points within `reach` of the contacts' mean.
struct TubeEnd
{
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::UnitZ();
  double radius = 0.0;
  bool valid = false;
};

TubeEnd FitTubeEnd(
  const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids, const std::vector<int>& end, double reach)
{
  TubeEnd tube;
  const Eigen::Vector3d contact = MeanOf(points, end);
  std::vector<int> near;
  for (int j : ids)
    if ((points[static_cast<std::size_t>(j)] - contact).norm() < reach)
      near.push_back(j);
  if (near.size() < 6)
    return tube;
  Eigen::Vector3d mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(
    Scatter(points, near, mean) / static_cast<double>(near.size()));
  tube.axis = solver.eigenvectors().col(2);
  if (tube.axis.dot(contact - mean) < 0.0)
    tube.axis = -tube.axis;
  tube.centre = contact;
  std::vector<double> off;
  for (int j : near)
  {
    const Eigen::Vector3d d = points[static_cast<std::size_t>(j)] - mean;
    off.push_back((d - d.dot(tube.axis) * tube.axis).norm());
  }
  std::nth_element(off.begin(), off.begin() + static_cast<std::ptrdiff_t>(off.size() * 9 / 10), off.end());
  tube.radius = TubeMargin * off[off.size() * 9 / 10];
  tube.valid = true;
  return tube;
}

/// Whether a point has a neighbour (over the links) that `take` accepts off the tube (farther than its radius):
/// it lies where the tube meets a surface (the blade it enters, the stem it leaves), not on the tube alone.
bool BesideTheTube(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, const TubeEnd& tube,
  std::size_t i, const std::function<bool(std::size_t)>& take)
{
  for (std::size_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e)
  {
    const auto j = static_cast<std::size_t>(graph.neighbours[e]);
    const Eigen::Vector3d d = points[j] - tube.centre;
    if (take(j) && (d - d.dot(tube.axis) * tube.axis).norm() > tube.radius)
      return true;
  }
  return false;
}

/// The points a petiole's tube goes on into past its contact `end`, where its own features could not see it as thin:
/// breadth-first from the contacts over the points `take` accepts that lie inside the tube (within its radius of its
/// axis) and at most `reach` beyond the contact along it. Into the blade: the tube's end the blade's region grew
/// over; into the stem: the tube's foot within r of the stem, whose neighbourhood holds the stem's surface.
std::vector<int> FollowTube(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, const TubeEnd& tube,
  const std::vector<int>& end, double reach, const std::function<bool(std::size_t)>& take, std::vector<char>& mark)
{
  std::vector<int> added;
  if (!tube.valid)
    return added;
  std::deque<int> queue(end.begin(), end.end());
  while (!queue.empty())
  {
    const auto q = static_cast<std::size_t>(queue.front());
    queue.pop_front();
    for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
    {
      const auto j = static_cast<std::size_t>(graph.neighbours[e]);
      if (mark[j] || !take(j))
        continue;
      const Eigen::Vector3d d = points[j] - tube.centre;
      const double along = d.dot(tube.axis);
      if (along < -tube.radius || along > reach || (d - along * tube.axis).norm() > tube.radius ||
        BesideTheTube(points, graph, tube, j, take))
        continue;
      mark[j] = 1;
      added.push_back(static_cast<int>(j));
      queue.push_back(static_cast<int>(j));
    }
  }
  for (int j : added)
    mark[static_cast<std::size_t>(j)] = 0;
  return added;
}

/// The extent of points[ids] along their main axis: a petiole's length (its chord when it curves).
double Extent(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids)
{
  Eigen::Vector3d mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(Scatter(points, ids, mean));
  const Eigen::Vector3d axis = solver.eigenvectors().col(2);
  double low = 0.0, high = 0.0;
  for (int j : ids)
  {
    const double t = (points[static_cast<std::size_t>(j)] - mean).dot(axis);
    low = std::min(low, t);
    high = std::max(high, t);
  }
  return high - low;
}

/// The leaf's base moves to the blade's: its point linked to the petiole's end `end` nearest their mean.
void MoveBase(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, const PlantLabels& labels,
  const std::vector<int>& end, SegmentedLeaf& leaf)
{
  const Eigen::Vector3d mean = MeanOf(points, end);
  double best = std::numeric_limits<double>::infinity();
  for (int q : end)
    for (std::size_t e = graph.offsets[static_cast<std::size_t>(q)]; e < graph.offsets[static_cast<std::size_t>(q) + 1];
         ++e)
    {
      const auto j = static_cast<std::size_t>(graph.neighbours[e]);
      const double d = (points[j] - mean).norm();
      if (labels.leaf[j] == leaf.leafId && d < best)
      {
        best = d;
        leaf.base = points[j];
      }
    }
}

/// The largest distance of points[ids] from their mean.
double Reach(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids)
{
  const Eigen::Vector3d mean = MeanOf(points, ids);
  double reach = 0.0;
  for (int j : ids)
    reach = std::max(reach, (points[static_cast<std::size_t>(j)] - mean).norm());
  return reach;
}

/// Whether a thin piece ending in `foot` (its tube at the thicker wood, the axis pointing into that wood) continues
/// the thicker wood's own axis at its end: the thicker wood within 2r of the contact lies ahead of the contact only
/// (under 2 % of it more than r behind) and along the foot's axis (nine tenths of it within r of the axis line).
/// That is the tapering tip of a twig, thin for its last stretch, the twig going on behind it in line; a petiole
/// leaves the side of its stem, whose wood spreads across the petiole's axis (up to 2r off it within 2r) or goes on
/// behind the contact.
bool ContinuesTheWood(
  const WoodCloud& wood, const PointGrid& grid, const std::vector<char>& thin, const TubeEnd& foot, double radius)
{
  if (!foot.valid)
    return false;
  std::vector<int> near, thick;
  grid.Within(foot.centre, 2.0 * radius, near);
  for (int k : near)
    if (!thin[static_cast<std::size_t>(wood.ids[static_cast<std::size_t>(k)])])
      thick.push_back(k);
  if (thick.size() < 6)
    return false;
  std::size_t behind = 0;
  std::vector<double> off;
  for (int k : thick)
  {
    const Eigen::Vector3d d = wood.points[static_cast<std::size_t>(k)] - foot.centre;
    const double along = d.dot(foot.axis);
    behind += along < -radius ? 1 : 0;
    off.push_back((d - along * foot.axis).norm());
  }
  std::nth_element(off.begin(), off.begin() + static_cast<std::ptrdiff_t>(off.size() * 9 / 10), off.end());
  return static_cast<double>(behind) < 0.02 * static_cast<double>(thick.size()) && off[off.size() * 9 / 10] < radius;
}

/// How many of the points `ids` have a neighbour over the links that `take` accepts.
std::size_t LinkedTo(const LinkGraph& graph, const std::vector<int>& ids, const std::function<bool(std::size_t)>& take)
{
  std::size_t count = 0;
  for (int i : ids)
    for (std::size_t e = graph.offsets[static_cast<std::size_t>(i)]; e < graph.offsets[static_cast<std::size_t>(i) + 1];
         ++e)
      if (take(static_cast<std::size_t>(graph.neighbours[e])))
      {
        ++count;
        break;
      }
  return count;
}

/// Per leaf instance, whether one of its points is linked to the wood: a leaf cut off from it by a gap in the scan
/// has no base where it meets the wood (its base is any of its points).
std::vector<char> LeavesOnTheWood(const LinkGraph& graph, const PlantLabels& labels)
{
  std::vector<char> on(labels.leaves.size(), 0);
  for (std::size_t i = 0; i + 1 < graph.offsets.size(); ++i)
    if (labels.leaf[i] >= 0)
      for (std::size_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e)
        if (labels.organ[static_cast<std::size_t>(graph.neighbours[e])] == OrganWood)
          on[static_cast<std::size_t>(labels.leaf[i])] = 1;
  return on;
}
} // namespace

std::size_t FindPetioles(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const LinkGraph& graph,
  double spacing, const SegmentationParameters& p, const ParallelFor& parallel, PlantLabels& labels)
{
  // the thin wood's scale: FeatureScale spacings (the features' radius before any widening for noise, which would
  // let a stem's surface into a petiole's neighbourhood far along it)
  const double radius = p.featureScale * spacing, link = p.linkScale * spacing;
  const std::size_t n = points.size();
  WoodCloud wood;
  for (std::size_t i = 0; i < n; ++i)
    if (labels.organ[i] == OrganWood)
    {
      wood.points.push_back(points[i]);
      wood.ids.push_back(static_cast<int>(i));
    }
  if (wood.points.empty())
    return 0;
  const PointGrid grid(wood.points, radius);
  const std::vector<char> thin = ThinWood(wood, grid, n, radius, parallel);
  const std::vector<char> onWood = LeavesOnTheWood(graph, labels);
  const LinkGraph links = BridgeGaps(
    points, graph, labels, thin, ThinTubes(wood, grid, thin, 2.0 * radius, parallel), radius, link, parallel);
  const std::vector<double> leafLength = LeafLengths(points, labels);
  // The hops a petiole may run on past its leaf contact away from the thicker wood: the blade's own junction, where
  // the tube enters the blade within about r.
  const int slack = static_cast<int>(std::ceil(radius / link)) + 1;
  std::vector<char> seen(n, 0), member(n, 0), mark(n, 0);
  std::vector<int> hops(n, -1);
  const auto thick = [&](std::size_t j) { return labels.organ[j] == OrganWood && !thin[j]; };
  std::size_t made = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!thin[i] || seen[i] || labels.organ[i] != OrganWood)
      continue;
    const ThinPiece piece = CollectPiece(links, labels, thin, static_cast<int>(i), seen);
    if (piece.leaf < 0 || piece.severalLeaves || piece.thick.empty() ||
      Reach(points, piece.thick) > ContactRadii * radius ||
      static_cast<double>(LinkedTo(graph, piece.ids, thick)) >= ContactShare * static_cast<double>(piece.ids.size()))
      continue; // a bare twig, a twig carrying several leaves, thin wood meeting no thicker wood, at several places
                // or all along
    SegmentedLeaf& leaf = labels.leaves[static_cast<std::size_t>(piece.leaf)];
    // it starts at the leaf's base (the leaf's point nearest the wood is beside it; a leaf cut off from the wood
    // by a gap has no base but where the piece meets it)
    double toBase = std::numeric_limits<double>::infinity();
    for (int j : piece.onLeaf)
      toBase = std::min(toBase, (points[static_cast<std::size_t>(j)] - leaf.base).norm());
    if (toBase > radius && onWood[static_cast<std::size_t>(piece.leaf)])
      continue;
    // it leads to that leaf only: from the thicker wood, nothing lies beyond the leaf contact (a twig going on
    // past the leaf, or branching off to a bare tip, reaches farther)
    for (int j : piece.ids)
      member[static_cast<std::size_t>(j)] = 1;
    const int farthest = FarthestHops(links, piece.thick, hops, member);
    const bool thicker = MeetsThickerWood(points, links, labels, thin, piece.thick, radius, mark);
    int leafHops = 0;
    for (int j : piece.onLeaf)
      leafHops = std::max(leafHops, hops[static_cast<std::size_t>(j)]);
    const double length = Extent(points, piece.ids);
    for (int j : piece.ids)
    {
      member[static_cast<std::size_t>(j)] = 0;
      hops[static_cast<std::size_t>(j)] = -1;
    }
    if (!thicker || farthest > leafHops + slack || length < ShortestPetioleRadii * radius ||
      length > PetioleLengthLeaves * leafLength[static_cast<std::size_t>(piece.leaf)])
      continue;
    const TubeEnd footEnd = FitTubeEnd(points, piece.ids, piece.thick, 2.0 * radius);
    if (ContinuesTheWood(wood, grid, thin, footEnd, radius))
      continue; // the thin tip of a twig carrying a leaf at its end
    // the tube goes on past both ends, where the features saw the stem's or the blade's surface beside it
    const auto intoLeaf = [&](std::size_t j) { return labels.leaf[j] == piece.leaf; };
    const std::vector<int> tip = FollowTube(points, links, FitTubeEnd(points, piece.ids, piece.onLeaf, 2.0 * radius),
      piece.onLeaf, 2.0 * std::max(radius, f.radius), intoLeaf, seen);
    const std::vector<int> foot = FollowTube(points, links, footEnd, piece.thick, 2.0 * radius, thick, seen);
    for (const std::vector<int>* part : { &piece.ids, &tip, &foot })
      for (int j : *part)
      {
        labels.organ[static_cast<std::size_t>(j)] = OrganPetiole;
        labels.leaf[static_cast<std::size_t>(j)] = -1;
      }
    leaf.points -= static_cast<long long>(tip.size());
    std::vector<int> all = piece.ids;
    all.insert(all.end(), tip.begin(), tip.end());
    all.insert(all.end(), foot.begin(), foot.end());
    leaf.petioleLength = std::max(leaf.petioleLength, Extent(points, all));
    MoveBase(points, links, labels, tip.empty() ? piece.onLeaf : tip, leaf);
    made += piece.ids.size() + tip.size() + foot.size();
  }
  return made;
}

} // namespace segmentation
} // namespace plantmorph
