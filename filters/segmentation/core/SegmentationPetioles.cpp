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
#include <queue>

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
/// A branch leaving the thicker wood within this angle (degrees) of the line that wood comes in goes on in it.
constexpr double InLineDegrees = 45.0;
/// A petiole leaves its blade's base within this angle (degrees) of the blade's midrib carried on out of the blade
/// (LeavesInLineWithTheMidrib). On the segmentation benchmark's 48 scans, 55 of the 57 thin pieces of petioles that
/// touch their blade and no other wood leave it at 18-34 degrees (its petioles drop 30 degrees below the blade, in
/// line with the midrib); the 38 such pieces of twigs at 20-144 degrees, 32 of them over 45 (its leaves turn 45
/// degrees off their twigs).
constexpr double MidribLineDegrees = 40.0;
/// A tube ends at its contacts with a blade when at most this share of its points within 2r of them lie past them
/// (TubeEndsThere).
constexpr double EndShare = 0.1;
/// A petiole's branches start at the skeleton's root up to this many r from the thicker wood: the thin wood's
/// features see the stem within r of it, the root's band is r / 2 wide, and a link or a gap link lies between.
constexpr double StalkReachRadii = 3.0;

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

/// A leaf instance's frame: its length (the extent of its points along their main axis, 2 sqrt(3 l1), a uniform
/// segment's), centre (their mean) and normal (their covariance's smallest axis).
struct LeafFrame
{
  double length = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::UnitZ();
};

std::vector<LeafFrame> LeafFrames(const std::vector<Eigen::Vector3d>& points, const PlantLabels& labels)
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
  std::vector<LeafFrame> frames(count);
  for (std::size_t l = 0; l < count; ++l)
    if (n[l] > 0.0)
    {
      frames[l].centre = sum[l] / n[l];
      const Eigen::Matrix3d c = square[l] / n[l] - frames[l].centre * frames[l].centre.transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(c);
      frames[l].length = 2.0 * std::sqrt(3.0 * std::max(0.0, solver.eigenvalues()[2]));
      frames[l].normal = solver.eigenvectors().col(0);
    }
  return frames;
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

/// The points of `ids` (in their order) that have a neighbour over the links that `take` accepts.
std::vector<int> LinkedTo(
  const LinkGraph& graph, const std::vector<int>& ids, const std::function<bool(std::size_t)>& take)
{
  std::vector<int> linked;
  for (int i : ids)
    for (std::size_t e = graph.offsets[static_cast<std::size_t>(i)]; e < graph.offsets[static_cast<std::size_t>(i) + 1];
         ++e)
      if (take(static_cast<std::size_t>(graph.neighbours[e])))
      {
        linked.push_back(i);
        break;
      }
  return linked;
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

/// A piece of thin wood cut into the nodes of its skeleton: its points in bands of geodesic distance from the piece's
/// root (SkeletonBandRadii r wide), each band's connected parts a node, a node's parent the node of its nearest
/// point's predecessor on the shortest path (Verroust and Lazarus' level-set skeleton).
struct SkeletonNode
{
  std::vector<int> ids;
  int parent = -1;
  double low = 0.0;  ///< the distance of its nearest point from the root
  int leaf = -1;     ///< the leaf instances its points are linked to: -1 none, the leaf, or -2 several
  bool bare = false; ///< (subtree) a branch of at least r ends in it without a leaf: a bare twig's tip
  double high = 0.0; ///< (subtree) the largest distance from the root
  std::vector<int> children;
};

/// The skeleton's bands are this many r wide: a tube's band is one part, and a branch leaving it is its own part
/// within about a band of where it leaves.
constexpr double SkeletonBandRadii = 0.5;

int MergeLeaf(int a, int b)
{
  return a == -1 ? b : (b == -1 || a == b ? a : -2);
}

/// Geodesic distances over the links within the piece (local indices, infinite where not reached) and each point's
/// predecessor, from `roots`.
void PieceDistances(const std::vector<Eigen::Vector3d>& points, const LinkGraph& links, const std::vector<int>& ids,
  const std::vector<int>& local, const std::vector<int>& roots, std::vector<double>& distance, std::vector<int>& before)
{
  distance.assign(ids.size(), std::numeric_limits<double>::infinity());
  before.assign(ids.size(), -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (int r : roots)
  {
    const int k = local[static_cast<std::size_t>(r)];
    distance[static_cast<std::size_t>(k)] = 0.0;
    queue.emplace(0.0, k);
  }
  while (!queue.empty())
  {
    const auto [d, k] = queue.top();
    queue.pop();
    if (d > distance[static_cast<std::size_t>(k)])
      continue;
    const auto q = static_cast<std::size_t>(ids[static_cast<std::size_t>(k)]);
    for (std::size_t e = links.offsets[q]; e < links.offsets[q + 1]; ++e)
    {
      const int m = local[static_cast<std::size_t>(links.neighbours[e])];
      if (m < 0)
        continue;
      const double next = d + (points[static_cast<std::size_t>(links.neighbours[e])] - points[q]).norm();
      if (next < distance[static_cast<std::size_t>(m)])
      {
        distance[static_cast<std::size_t>(m)] = next;
        before[static_cast<std::size_t>(m)] = k;
        queue.emplace(next, m);
      }
    }
  }
}

/// The points of node v's subtree, those within `reach` of v's distance from the root only when reach > 0.
std::vector<int> Subtree(const std::vector<SkeletonNode>& nodes, int v, double reach)
{
  std::vector<int> ids;
  std::vector<int> stack{ v };
  const double limit = nodes[static_cast<std::size_t>(v)].low + reach;
  while (!stack.empty())
  {
    const SkeletonNode& n = nodes[static_cast<std::size_t>(stack.back())];
    stack.pop_back();
    if (reach > 0.0 && n.low > limit)
      continue;
    ids.insert(ids.end(), n.ids.begin(), n.ids.end());
    stack.insert(stack.end(), n.children.begin(), n.children.end());
  }
  return ids;
}

/// Whether the branch from node v ends apart from its parent's other branches: the point of its subtree farthest
/// from its fork lies farther than r from every point of its siblings' subtrees.
bool Apart(const std::vector<Eigen::Vector3d>& points, const std::vector<SkeletonNode>& nodes, int v, double radius)
{
  const std::vector<int> mine = Subtree(nodes, v, 0.0);
  const Eigen::Vector3d fork = MeanOf(points, nodes[static_cast<std::size_t>(v)].ids);
  const Eigen::Vector3d* end = &points[static_cast<std::size_t>(mine.front())];
  for (int j : mine)
    if ((points[static_cast<std::size_t>(j)] - fork).norm() > (*end - fork).norm())
      end = &points[static_cast<std::size_t>(j)];
  const SkeletonNode& parent = nodes[static_cast<std::size_t>(nodes[static_cast<std::size_t>(v)].parent)];
  for (int c : parent.children)
    if (c != v)
      for (int j : Subtree(nodes, c, 0.0))
        if ((points[static_cast<std::size_t>(j)] - *end).norm() <= radius)
          return false;
  return true;
}

/// The level-set skeleton of a piece of thin wood from `roots` (SkeletonNode), with each node's subtree's leaves,
/// bare tips and reach. `local` is scratch (-1 for every point in and out).
std::vector<SkeletonNode> PieceSkeleton(const std::vector<Eigen::Vector3d>& points, const LinkGraph& links,
  const PlantLabels& labels, const std::vector<int>& ids, const std::vector<int>& roots, double radius,
  std::vector<int>& local)
{
  for (std::size_t k = 0; k < ids.size(); ++k)
    local[static_cast<std::size_t>(ids[k])] = static_cast<int>(k);
  std::vector<double> distance;
  std::vector<int> before, node(ids.size(), -1);
  PieceDistances(points, links, ids, local, roots, distance, before);
  const double band = SkeletonBandRadii * radius;
  const auto bandOf = [&](std::size_t k) { return static_cast<long long>(std::floor(distance[k] / band)); };
  std::vector<SkeletonNode> nodes;
  for (std::size_t k = 0; k < ids.size(); ++k)
  {
    if (node[k] >= 0 || !std::isfinite(distance[k]))
      continue;
    SkeletonNode part;
    std::deque<std::size_t> queue{ k };
    node[k] = static_cast<int>(nodes.size());
    std::size_t lowest = k;
    while (!queue.empty())
    {
      const std::size_t c = queue.front();
      queue.pop_front();
      part.ids.push_back(ids[c]);
      lowest = distance[c] < distance[lowest] ? c : lowest;
      const auto q = static_cast<std::size_t>(ids[c]);
      for (std::size_t e = links.offsets[q]; e < links.offsets[q + 1]; ++e)
      {
        const auto j = static_cast<std::size_t>(links.neighbours[e]);
        const int m = local[j];
        if (m >= 0 && node[static_cast<std::size_t>(m)] < 0 && std::isfinite(distance[static_cast<std::size_t>(m)]) &&
          bandOf(static_cast<std::size_t>(m)) == bandOf(c))
        {
          node[static_cast<std::size_t>(m)] = node[k];
          queue.push_back(static_cast<std::size_t>(m));
        }
        else if (labels.leaf[j] >= 0)
          part.leaf = MergeLeaf(part.leaf, labels.leaf[j]);
      }
      part.high = std::max(part.high, distance[c]);
    }
    part.low = distance[lowest];
    part.parent = before[lowest] < 0 ? -1 : before[lowest]; // a local index: made a node below
    nodes.push_back(std::move(part));
  }
  for (SkeletonNode& v : nodes)
    v.parent = v.parent < 0 ? -1 : node[static_cast<std::size_t>(v.parent)];
  for (std::size_t v = 0; v < nodes.size(); ++v)
    if (nodes[v].parent >= 0)
      nodes[static_cast<std::size_t>(nodes[v].parent)].children.push_back(static_cast<int>(v));
  for (int j : ids)
    local[static_cast<std::size_t>(j)] = -1;
  // subtrees, from the farthest node down: a parent is always nearer the root than its children
  std::vector<std::size_t> order(nodes.size());
  for (std::size_t v = 0; v < order.size(); ++v)
    order[v] = v;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return nodes[a].low > nodes[b].low; });
  for (std::size_t v : order)
  {
    SkeletonNode& n = nodes[v];
    for (int c : n.children)
    {
      const SkeletonNode& child = nodes[static_cast<std::size_t>(c)];
      n.leaf = MergeLeaf(n.leaf, child.leaf);
      n.bare = n.bare || child.bare;
      n.high = std::max(n.high, child.high);
    }
  }
  // a bare tip: a branch without a leaf reaching at least r past where it leaves its parent, and ending farther than
  // r from the parent's other branches (not a strand of points beside them, as a tube seen at the spacing splits)
  for (std::size_t v : order)
  {
    SkeletonNode& n = nodes[v];
    if (n.leaf == -1 && n.parent >= 0 && nodes[static_cast<std::size_t>(n.parent)].leaf != -1 &&
      n.high - n.low >= radius)
      n.bare = Apart(points, nodes, static_cast<int>(v), radius);
  }
  for (std::size_t v : order)
    if (nodes[v].bare && nodes[v].parent >= 0)
      nodes[static_cast<std::size_t>(nodes[v].parent)].bare = true;
  return nodes;
}

/// Whether the branch from node v continues its parent's line: of the parent's children that lead to a leaf or a
/// bare tip, it is the one whose first 2r turn least from the direction the parent's own last 2r come in. A twig
/// goes on in line past the petioles that leave it; when the parent has no 2r behind it, no branch is told apart.
bool ContinuesItsParent(
  const std::vector<Eigen::Vector3d>& points, const std::vector<SkeletonNode>& nodes, int v, double radius)
{
  const SkeletonNode& parent = nodes[static_cast<std::size_t>(nodes[static_cast<std::size_t>(v)].parent)];
  std::vector<int> behind;
  for (int u = parent.parent; u >= 0 && nodes[static_cast<std::size_t>(u)].low >= parent.low - 2.0 * radius;
       u = nodes[static_cast<std::size_t>(u)].parent)
    behind.insert(
      behind.end(), nodes[static_cast<std::size_t>(u)].ids.begin(), nodes[static_cast<std::size_t>(u)].ids.end());
  if (behind.empty())
    return false;
  const Eigen::Vector3d junction = MeanOf(points, parent.ids);
  const Eigen::Vector3d in = (junction - MeanOf(points, behind)).normalized();
  int best = -1;
  double straightest = -2.0;
  for (int c : parent.children)
  {
    const SkeletonNode& child = nodes[static_cast<std::size_t>(c)];
    if (child.leaf == -1 && !child.bare)
      continue;
    const double turn = (MeanOf(points, Subtree(nodes, c, 2.0 * radius)) - junction).normalized().dot(in);
    if (turn > straightest)
    {
      straightest = turn;
      best = c;
    }
  }
  return best == v;
}

/// Whether node v's parent forks: another of its children leads to a leaf or a bare tip over at least r.
bool ForksThere(const std::vector<SkeletonNode>& nodes, int v, double radius)
{
  for (int c : nodes[static_cast<std::size_t>(nodes[static_cast<std::size_t>(v)].parent)].children)
  {
    const SkeletonNode& child = nodes[static_cast<std::size_t>(c)];
    if (c != v && (child.leaf != -1 || child.bare) && child.high - child.low >= radius)
      return true;
  }
  return false;
}

/// What a petiole is judged and marked with.
struct PetioleScene
{
  const std::vector<Eigen::Vector3d>& points;
  const LinkGraph& links;
  const WoodCloud& wood;
  const PointGrid& grid;
  const std::vector<char>& thin;
  const std::vector<LeafFrame>& leaves; ///< per leaf instance
  const std::vector<char>& onWood;
  double radius = 0.0;      ///< the thin wood's scale r
  double followReach = 0.0; ///< how far a petiole's tube is followed into its blade
};

/// Whether thin points `ids` touching leaf instance `leaf` at `onLeaf` may be its petiole by their size and place: at
/// least ShortestPetioleRadii r long, at most the leaf's length, beside the leaf's base (a leaf no link joins to the
/// wood may be touched anywhere).
bool PetioleSized(const PetioleScene& scene, const PlantLabels& labels, const std::vector<int>& ids,
  const std::vector<int>& onLeaf, int leaf)
{
  const double length = Extent(scene.points, ids);
  if (onLeaf.empty() || length < ShortestPetioleRadii * scene.radius ||
    length > PetioleLengthLeaves * scene.leaves[static_cast<std::size_t>(leaf)].length)
    return false;
  if (!scene.onWood[static_cast<std::size_t>(leaf)])
    return true;
  double toBase = std::numeric_limits<double>::infinity();
  for (int j : onLeaf)
    toBase = std::min(
      toBase, (scene.points[static_cast<std::size_t>(j)] - labels.leaves[static_cast<std::size_t>(leaf)].base).norm());
  return toBase <= scene.radius;
}

/// Whether thin points `ids` touching leaf instance `leaf` at `onLeaf` leave the blade in line with its midrib: from
/// their contacts' mean, their farthest point lies within MidribLineDegrees of the way out of the blade there (from
/// the blade's centre to the contacts, in the blade's plane). A petiole carries its blade on from the base; a twig
/// passes beside the base of a leaf on its side, or turns off its midrib by the leaf's angle at its tip.
bool LeavesInLineWithTheMidrib(
  const PetioleScene& scene, const std::vector<int>& ids, const std::vector<int>& onLeaf, int leaf)
{
  const LeafFrame& frame = scene.leaves[static_cast<std::size_t>(leaf)];
  const Eigen::Vector3d contact = MeanOf(scene.points, onLeaf);
  Eigen::Vector3d out = contact - frame.centre;
  out -= out.dot(frame.normal) * frame.normal;
  Eigen::Vector3d far = contact;
  for (int j : ids)
    if ((scene.points[static_cast<std::size_t>(j)] - contact).norm() > (far - contact).norm())
      far = scene.points[static_cast<std::size_t>(j)];
  const double along = (far - contact).norm() * out.norm();
  return along > 0.0 && (far - contact).dot(out) > std::cos(MidribLineDegrees * Pi / 180.0) * along;
}

/// Marks `ids`, the leaf's points its tube goes on into past `onLeaf` (FollowTube) and `foot` petiole of leaf
/// instance `leaf` (LeafId -1), and gives the leaf its PetioleLength and base. Returns the points marked.
std::size_t MarkPetiole(const PetioleScene& scene, const std::vector<int>& ids, const std::vector<int>& onLeaf,
  const std::vector<int>& foot, int leaf, std::vector<char>& seen, PlantLabels& labels)
{
  const auto intoLeaf = [&](std::size_t j) { return labels.leaf[j] == leaf; };
  const std::vector<int> tip = FollowTube(scene.points, scene.links,
    FitTubeEnd(scene.points, ids, onLeaf, 2.0 * scene.radius), onLeaf, scene.followReach, intoLeaf, seen);
  for (const std::vector<int>* part : { &ids, &tip, &foot })
    for (int j : *part)
    {
      labels.organ[static_cast<std::size_t>(j)] = OrganPetiole;
      labels.leaf[static_cast<std::size_t>(j)] = -1;
    }
  SegmentedLeaf& blade = labels.leaves[static_cast<std::size_t>(leaf)];
  blade.points -= static_cast<long long>(tip.size());
  std::vector<int> all = ids;
  all.insert(all.end(), tip.begin(), tip.end());
  all.insert(all.end(), foot.begin(), foot.end());
  blade.petioleLength = std::max(blade.petioleLength, Extent(scene.points, all));
  MoveBase(scene.points, scene.links, labels, tip.empty() ? onLeaf : tip, blade);
  return all.size();
}

/// The roots a piece's skeleton grows from: its points linked to thicker wood, or, meeting none, its point farthest
/// from its leaf contacts over its links (a petiole whose stem the scan did not see ends there).
std::vector<int> PieceRoots(const PetioleScene& scene, const ThinPiece& piece, std::vector<int>& local)
{
  if (!piece.thick.empty())
    return piece.thick;
  for (std::size_t k = 0; k < piece.ids.size(); ++k)
    local[static_cast<std::size_t>(piece.ids[k])] = static_cast<int>(k);
  std::vector<double> distance;
  std::vector<int> before;
  PieceDistances(scene.points, scene.links, piece.ids, local, piece.onLeaf, distance, before);
  for (int j : piece.ids)
    local[static_cast<std::size_t>(j)] = -1;
  std::size_t far = distance.size();
  for (std::size_t k = 0; k < distance.size(); ++k)
    if (std::isfinite(distance[k]) && (far == distance.size() || distance[k] > distance[far]))
      far = k;
  return far == distance.size() ? std::vector<int>{} : std::vector<int>{ piece.ids[far] };
}

/// Whether a branch leaving the root of its piece's skeleton at `foot` goes on in the line of the wood there: its
/// first 2r (`start`) turn less than InLineDegrees from the main axis of the other wood within StalkReachRadii r of
/// where its points end on the stem's side (along its tube; of the foot when it has none), or
/// that wood has no axis (under 6 points, or not AxisElongation times longer than wide): nothing shows a fork there.
/// The other wood is the wood, thin or not, but the branch's points `mine` and those on the branch's way to the stem
/// (ahead of the foot along its tube `tube`, pointing out of the branch, within twice its radius of its axis: the
/// branch's own foot, which the features saw beside the stem). A twig thin over its last stretch carrying a leaf at
/// its tip goes on in line past the last place its points flicker thick; a petiole leaves its stem's side.
bool InLineWithTheWood(const PetioleScene& scene, const std::vector<int>& mine, const std::vector<int>& start,
  const std::vector<int>& foot, const TubeEnd& tube, std::vector<char>& mark)
{
  const Eigen::Vector3d at = MeanOf(scene.points, foot);
  double reached = 0.0; // how far the branch's points go on along its tube past the foot, into the stem
  for (int j : mine)
  {
    mark[static_cast<std::size_t>(j)] = 1;
    if (tube.valid)
      reached = std::max(reached, (scene.points[static_cast<std::size_t>(j)] - tube.centre).dot(tube.axis));
  }
  std::vector<int> near, other;
  scene.grid.Within(
    tube.valid ? Eigen::Vector3d(tube.centre + reached * tube.axis) : at, StalkReachRadii * scene.radius, near);
  for (int k : near)
  {
    const Eigen::Vector3d d = scene.wood.points[static_cast<std::size_t>(k)] - tube.centre;
    const double along = d.dot(tube.axis);
    const bool onItsWay = tube.valid && along > 0.0 && (d - along * tube.axis).norm() < 2.0 * tube.radius;
    if (!mark[static_cast<std::size_t>(scene.wood.ids[static_cast<std::size_t>(k)])] && !onItsWay)
      other.push_back(k);
  }
  for (int j : mine)
    mark[static_cast<std::size_t>(j)] = 0;
  const LocalTube stem = FitLocalTube(scene.wood.points, other);
  if (other.size() < 6 || !stem.hasAxis)
    return true;
  const Eigen::Vector3d out = (MeanOf(scene.points, start) - at).normalized();
  return std::abs(out.dot(stem.axis)) > std::cos(InLineDegrees * Pi / 180.0);
}

/// A piece of thin wood that is no petiole as a whole, cut at its skeleton's forks (PieceSkeleton): a twig's thin
/// end carrying several leaves on petioles, or a piece cut off from the thicker wood by the scan. A branch is a leaf's
/// petiole when everything past its fork leads to that leaf alone (no other leaf, no bare tip of r or more) and it
/// has a petiole's size (PetioleSized), and
/// - at the skeleton's root, the wood it meets there (its root's points: where the thin wood touches thicker wood,
///   which spreads over the junction, so one petiole may leave it as several branches, taken together) is no twig
///   it goes on in line with (InLineWithTheWood);
/// - within the thin wood, its fork is one (another branch of r or more leads to a leaf or a bare tip, and it ends
///   apart from it) and it leaves its parent's line (ContinuesItsParent).
/// The piece from its root is never one: with thicker wood it was judged as a whole, and a thin piece that touches one
/// leaf and nothing else is as often a twig's end whose stem the scan did not see (on the accuracy benchmark's plants
/// without petioles, 130-500 points of twigs per scan). Returns the points marked.
std::size_t SplitPiece(const PetioleScene& scene, const ThinPiece& piece, std::vector<char>& seen,
  std::vector<char>& mark, std::vector<int>& local, PlantLabels& labels)
{
  const std::vector<int> roots = PieceRoots(scene, piece, local);
  if (roots.empty())
    return 0;
  const std::vector<SkeletonNode> nodes =
    PieceSkeleton(scene.points, scene.links, labels, piece.ids, roots, scene.radius, local);
  std::size_t made = 0;
  const auto petiole = [&](const std::vector<int>& ids, const std::vector<int>& onLeaf, int leaf) {
    made += MarkPetiole(scene, ids, onLeaf, {}, leaf, seen, labels);
  };
  for (const SkeletonNode& root : nodes)
  {
    if (root.parent >= 0)
      continue;
    std::vector<int> leaves; // the leaves some branch from this root leads to alone, each once
    for (int c : root.children)
    {
      const SkeletonNode& n = nodes[static_cast<std::size_t>(c)];
      if (n.leaf >= 0 && !n.bare && std::find(leaves.begin(), leaves.end(), n.leaf) == leaves.end())
        leaves.push_back(n.leaf);
    }
    for (int leaf : leaves)
    {
      std::vector<int> ids, foot, start;
      for (int c : root.children)
      {
        const SkeletonNode& n = nodes[static_cast<std::size_t>(c)];
        if (n.leaf != leaf || n.bare)
          continue;
        const std::vector<int> mine = Subtree(nodes, c, 0.0), first = Subtree(nodes, c, 2.0 * scene.radius);
        ids.insert(ids.end(), mine.begin(), mine.end());
        start.insert(start.end(), first.begin(), first.end());
        foot.insert(foot.end(), n.ids.begin(), n.ids.end());
      }
      // the branches leave the thin wood where it meets the thicker wood; their tube goes on to the stem's surface
      // through the root's thin points and the thicker wood's (FollowTube)
      for (int j : ids)
        mark[static_cast<std::size_t>(j)] = 1;
      const TubeEnd tube = FitTubeEnd(scene.points, ids, foot, 2.0 * scene.radius);
      const std::vector<int> stalk = FollowTube(
        scene.points, scene.links, tube, foot, StalkReachRadii * scene.radius,
        [&](std::size_t j) { return labels.organ[j] == OrganWood; }, mark);
      for (int j : ids)
        mark[static_cast<std::size_t>(j)] = 0;
      std::vector<int> all = ids;
      all.insert(all.end(), stalk.begin(), stalk.end());
      const std::vector<int> onLeaf = LinkedTo(scene.links, ids, [&](std::size_t j) { return labels.leaf[j] == leaf; });
      if (PetioleSized(scene, labels, all, onLeaf, leaf) && !InLineWithTheWood(scene, all, start, foot, tube, mark))
        petiole(all, onLeaf, leaf);
    }
  }
  for (std::size_t v = 0; v < nodes.size(); ++v)
  {
    const SkeletonNode& n = nodes[v];
    if (n.leaf < 0 || n.bare || n.parent < 0 || nodes[static_cast<std::size_t>(n.parent)].parent < 0)
      continue;
    const SkeletonNode& parent = nodes[static_cast<std::size_t>(n.parent)];
    const int me = static_cast<int>(v);
    if ((parent.leaf == n.leaf && !parent.bare) || !ForksThere(nodes, me, scene.radius) ||
      !Apart(scene.points, nodes, me, scene.radius))
      continue; // not the fork's first node, or no fork
    const std::vector<int> ids = Subtree(nodes, me, 0.0);
    const std::vector<int> onLeaf = LinkedTo(scene.links, ids, [&](std::size_t j) { return labels.leaf[j] == n.leaf; });
    if (PetioleSized(scene, labels, ids, onLeaf, n.leaf) && !ContinuesItsParent(scene.points, nodes, me, scene.radius))
      petiole(ids, onLeaf, n.leaf);
  }
  return made;
}
/// Whether the tube `tube` (its axis pointing out of the wood `wood`, into the blade) ends at its contacts with the
/// blade `onLeaf` (its centre their mean): of the wood points inside it (within its radius of its axis) from r / 2
/// to 2r off the centre, the contacts left out, at most EndShare lie ahead (towards the blade). A petiole ends at
/// its blade's base; a twig carrying a leaf on its side goes on past the leaf's base on both sides.
bool TubeEndsThere(
  const PetioleScene& scene, const TubeEnd& tube, const std::vector<int>& wood, std::vector<int> onLeaf)
{
  std::sort(onLeaf.begin(), onLeaf.end());
  std::size_t ahead = 0, behind = 0;
  for (int j : wood)
  {
    const Eigen::Vector3d d = scene.points[static_cast<std::size_t>(j)] - tube.centre;
    const double along = d.dot(tube.axis);
    if (std::abs(along) < 0.5 * scene.radius || std::abs(along) > 2.0 * scene.radius ||
      (d - along * tube.axis).norm() > tube.radius || std::binary_search(onLeaf.begin(), onLeaf.end(), j))
      continue;
    (along > 0.0 ? ahead : behind) += 1;
  }
  return behind > 0 && static_cast<double>(ahead) <= EndShare * static_cast<double>(behind);
}

/// The points of a piece (`member`) inside the tube `tube` (within `width` of its axis) that its contacts `from`
/// reach over the links, walked along it up to `reach`, and where the tube meets other wood: the least distance
/// along the axis, past the first r, of a walked point linked to a piece point more than twice `width` off the axis
/// (the stem the tube leaves; infinity when it meets none). The walked points past that junction by more than `width`
/// are left out.
struct TubeWalk
{
  std::vector<int> ids;
  double junction = std::numeric_limits<double>::infinity();
};

TubeWalk WalkTube(const PetioleScene& scene, const TubeEnd& tube, const std::vector<int>& from, double width,
  double reach, const std::vector<int>& member, std::vector<char>& mark)
{
  TubeWalk walk;
  std::deque<int> queue;
  for (int j : from)
    if (!mark[static_cast<std::size_t>(j)])
    {
      mark[static_cast<std::size_t>(j)] = 1;
      walk.ids.push_back(j);
      queue.push_back(j);
    }
  const auto place = [&](std::size_t j, double& along) {
    const Eigen::Vector3d d = scene.points[j] - tube.centre;
    along = d.dot(tube.axis);
    return (d - along * tube.axis).norm();
  };
  while (!queue.empty())
  {
    const auto q = static_cast<std::size_t>(queue.front());
    queue.pop_front();
    double alongQ = 0.0;
    place(q, alongQ);
    for (std::size_t e = scene.links.offsets[q]; e < scene.links.offsets[q + 1]; ++e)
    {
      const auto j = static_cast<std::size_t>(scene.links.neighbours[e]);
      if (member[j] != 1 || mark[j])
        continue;
      double along = 0.0;
      const double off = place(j, along);
      if (off > 2.0 * width && alongQ > scene.radius)
        walk.junction = std::min(walk.junction, alongQ);
      if (off > width || along < -width || along > reach)
        continue;
      mark[j] = 1;
      walk.ids.push_back(static_cast<int>(j));
      queue.push_back(static_cast<int>(j));
    }
  }
  for (int j : walk.ids)
    mark[static_cast<std::size_t>(j)] = 0;
  std::vector<int> kept;
  for (int j : walk.ids)
  {
    double along = 0.0;
    place(static_cast<std::size_t>(j), along);
    if (along <= walk.junction + width)
      kept.push_back(j);
  }
  walk.ids = kept;
  return walk;
}

/// Whether the wood a walked tube met (`walk`, `width` its walk's width) is a stem it leaves: the piece's points
/// `wood` within 2r of the junction and more than twice `width` off the tube's axis are no tube going on within
/// InLineDegrees of its axis (a twig bending on, which its points leave too, is). A stem crossing the tube, the
/// surface of a thicker one (no axis), or a few points (under 6) beside the tube's foot are.
bool MeetsAStem(
  const PetioleScene& scene, const TubeEnd& tube, const TubeWalk& walk, double width, const std::vector<int>& wood)
{
  const Eigen::Vector3d at = tube.centre + walk.junction * tube.axis;
  std::vector<Eigen::Vector3d> off;
  std::vector<int> ids;
  for (int j : wood)
  {
    const Eigen::Vector3d d = scene.points[static_cast<std::size_t>(j)] - tube.centre;
    const double along = d.dot(tube.axis);
    if ((scene.points[static_cast<std::size_t>(j)] - at).norm() < 2.0 * scene.radius &&
      (d - along * tube.axis).norm() > 2.0 * width)
    {
      ids.push_back(static_cast<int>(off.size()));
      off.push_back(scene.points[static_cast<std::size_t>(j)]);
    }
  }
  const LocalTube stem = FitLocalTube(off, ids);
  return off.size() < 6 || !stem.hasAxis || std::abs(stem.axis.dot(tube.axis)) < std::cos(InLineDegrees * Pi / 180.0);
}

/// The petioles SplitPiece did not find in a piece of thin wood that is no petiole as a whole, each from its leaf
/// (one without a petiole yet): the tube the piece's wood within 2r of its contacts with the leaf lies in
/// (FitTubeEnd), when the contacts lie within ContactRadii r of their mean (a twig along the blade's edge touches it
/// all along) and the tube ends there (TubeEndsThere), walked away from the blade (WalkTube, within its radius or
/// r / 2 of its axis, no farther than the leaf is long). It is the leaf's petiole when the walk met its stem, has a
/// petiole's size and place (PetioleSized) and leaves the blade in line with its midrib (LeavesInLineWithTheMidrib).
/// A twig's thin end carrying several leaves on petioles is one piece, and where a petiole runs beside the twig
/// before it leaves it, its skeleton has no fork to cut at.
std::size_t PetiolesFromTheirLeaves(const PetioleScene& scene, const ThinPiece& piece, std::vector<char>& seen,
  std::vector<char>& mark, std::vector<int>& member, PlantLabels& labels)
{
  std::vector<int> leaves;
  for (int i : piece.ids)
    for (std::size_t e = scene.links.offsets[static_cast<std::size_t>(i)];
         e < scene.links.offsets[static_cast<std::size_t>(i) + 1]; ++e)
    {
      const int leaf = labels.leaf[static_cast<std::size_t>(scene.links.neighbours[e])];
      if (leaf >= 0 && std::find(leaves.begin(), leaves.end(), leaf) == leaves.end())
        leaves.push_back(leaf);
    }
  std::sort(leaves.begin(), leaves.end());
  std::size_t made = 0;
  for (int leaf : leaves)
  {
    if (labels.leaves[static_cast<std::size_t>(leaf)].petioleLength > 0.0)
      continue;
    std::vector<int> wood;
    for (int j : piece.ids)
      if (labels.organ[static_cast<std::size_t>(j)] == OrganWood)
      {
        wood.push_back(j);
        member[static_cast<std::size_t>(j)] = 1;
      }
    const std::vector<int> onLeaf = LinkedTo(scene.links, wood, [&](std::size_t j) { return labels.leaf[j] == leaf; });
    const TubeEnd tube = onLeaf.empty() ? TubeEnd{} : FitTubeEnd(scene.points, wood, onLeaf, 2.0 * scene.radius);
    TubeEnd away = tube;
    away.axis = -tube.axis;
    const double reach = PetioleLengthLeaves * scene.leaves[static_cast<std::size_t>(leaf)].length;
    const double width = std::max(tube.radius, ThinRadiusFraction * scene.radius);
    TubeWalk walk;
    if (tube.valid && Reach(scene.points, onLeaf) <= ContactRadii * scene.radius &&
      TubeEndsThere(scene, tube, wood, onLeaf))
      walk = WalkTube(scene, away, onLeaf, width, reach, member, mark);
    for (int j : wood)
      member[static_cast<std::size_t>(j)] = -1;
    if (std::isfinite(walk.junction) && MeetsAStem(scene, away, walk, width, wood) &&
      PetioleSized(scene, labels, walk.ids, onLeaf, leaf) && LeavesInLineWithTheMidrib(scene, walk.ids, onLeaf, leaf))
      made += MarkPetiole(scene, walk.ids, onLeaf, {}, leaf, seen, labels);
  }
  return made;
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
  const std::vector<LeafFrame> leaves = LeafFrames(points, labels);
  // The hops a petiole may run on past its leaf contact away from the thicker wood: the blade's own junction, where
  // the tube enters the blade within about r.
  const int slack = static_cast<int>(std::ceil(radius / link)) + 1;
  std::vector<char> seen(n, 0), member(n, 0), mark(n, 0);
  std::vector<int> hops(n, -1), local(n, -1);
  const auto thick = [&](std::size_t j) { return labels.organ[j] == OrganWood && !thin[j]; };
  const PetioleScene scene{ points, links, wood, grid, thin, leaves, onWood, radius, 2.0 * std::max(radius, f.radius) };
  // a piece that is no petiole as a whole: cut at its skeleton's forks, then its leaves' petioles walked from them
  const auto split = [&](const ThinPiece& piece) {
    const std::size_t cut = SplitPiece(scene, piece, seen, mark, local, labels);
    return cut + PetiolesFromTheirLeaves(scene, piece, seen, mark, local, labels);
  };
  std::size_t made = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!thin[i] || seen[i] || labels.organ[i] != OrganWood)
      continue;
    const ThinPiece piece = CollectPiece(links, labels, thin, static_cast<int>(i), seen);
    if (piece.leaf < 0)
      continue; // a bare twig
    if (piece.thick.empty() && !piece.severalLeaves &&
      PetioleSized(scene, labels, piece.ids, piece.onLeaf, piece.leaf) &&
      LeavesInLineWithTheMidrib(scene, piece.ids, piece.onLeaf, piece.leaf))
    {
      // a petiole whose stem the scan did not see, or did not link to it: it carries its blade's midrib on
      made += MarkPetiole(scene, piece.ids, piece.onLeaf, {}, piece.leaf, seen, labels);
      continue;
    }
    if (piece.severalLeaves || piece.thick.empty() || Reach(points, piece.thick) > ContactRadii * radius ||
      static_cast<double>(LinkedTo(graph, piece.ids, thick).size()) >=
        ContactShare * static_cast<double>(piece.ids.size()) ||
      !PetioleSized(scene, labels, piece.ids, piece.onLeaf, piece.leaf))
    {
      // a twig carrying several leaves, thin wood meeting no thicker wood, at several places or all along: its
      // branches may be petioles
      made += split(piece);
      continue;
    }
    // it leads to that leaf only: from the thicker wood, nothing lies beyond the leaf contact (a twig going on
    // past the leaf, or branching off to a bare tip, reaches farther)
    for (int j : piece.ids)
      member[static_cast<std::size_t>(j)] = 1;
    const int farthest = FarthestHops(links, piece.thick, hops, member);
    const bool thicker = MeetsThickerWood(points, links, labels, thin, piece.thick, radius, mark);
    int leafHops = 0;
    for (int j : piece.onLeaf)
      leafHops = std::max(leafHops, hops[static_cast<std::size_t>(j)]);
    for (int j : piece.ids)
    {
      member[static_cast<std::size_t>(j)] = 0;
      hops[static_cast<std::size_t>(j)] = -1;
    }
    const TubeEnd footEnd = FitTubeEnd(points, piece.ids, piece.thick, 2.0 * radius);
    if (!thicker || farthest > leafHops + slack || ContinuesTheWood(wood, grid, thin, footEnd, radius))
    {
      made += split(piece);
      continue; // also the thin tip of a twig carrying a leaf at its end
    }
    // the tube goes on past both ends, where the features saw the stem's or the blade's surface beside it
    const std::vector<int> foot = FollowTube(points, links, footEnd, piece.thick, 2.0 * radius, thick, seen);
    made += MarkPetiole(scene, piece.ids, piece.onLeaf, foot, piece.leaf, seen, labels);
  }
  return made;
}

} // namespace segmentation
} // namespace plantmorph
