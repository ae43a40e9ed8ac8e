// SPDX-License-Identifier: GPL-3.0-or-later
// Steps 5-6 of the tree fit (TreeFit.h): which fitted radii the points support, the growth-length (pipe model)
// radius everywhere else, and the branches.
#include "TreeFitInternal.h"

#include <plantmorph/statistics/Median.h>
#include <algorithm>
#include <cmath>
#include <limits>

namespace plantmorph
{
namespace treefit
{
namespace
{
constexpr int MinMeasuredPoints = 12;
constexpr double MinCoverage = 150.0;   // degrees
constexpr double MinArcSpacings = 5.0;  // the arc seen, in spacings
constexpr double MinRadiusNoise = 3.0;  // noise deviations
constexpr double MaxScaleRadius = 0.35; // residual scale / radius
// In a scan with points labelled leaf, a fit wider than its model whose residual scale is above LeafScaleNoise noise
// deviations and LeafScaleRadius of its radius is a ring of leaf points labelled wood round a twig, not the twig.
constexpr double LeafScaleNoise = 2.0;
constexpr double LeafScaleRadius = 0.05;
// In such a scan, a stem's fit whose residual scale is above LeafScaleNoise noise deviations and whose axis turns more
// than LeanAngle from the stem's last clean fit below it holds a lateral's first points beside the stem's.
constexpr double LeanAngle = 6.0;   // degrees
constexpr double ModelFactor = 2.0; // a measured radius this far from the model is not trusted...
constexpr double StrongCoverage = 240.0, StrongRadiusNoise = 10.0; // ...unless the fit is this good
constexpr int MinStrongPoints = 50;
constexpr double ContinueShare = 0.25;    // of the heaviest child's carried volume
constexpr double CodominantShare = 0.5;   // of the heaviest child's carried volume
constexpr double ForkMargin = 10.0;       // degrees: codominant children turning less apart than this end the branch
constexpr double BulgeFactor = 1.05;      // a measured cylinder this much wider than its parent is a junction
constexpr double BulgeRunDiameters = 4.0; // a run of junctions longer than this (its widest diameters) is a branch
constexpr double KinkAngle = 25.0;
constexpr double IncomingReaches = 2.5; // a branch's incoming direction is its own past this length (reaches)
constexpr double KinkReaches = 4.0;     // a kink still turns this far on (reaches): a junction's wiggle does not...
constexpr double KinkKept = 0.5;        // ...by more than KinkAngle or this share of its turn at the link
constexpr std::size_t ChildBaseCylinders = 3; // a child's base radius: its first measured cylinder among these
constexpr double TaperMargin = 1.15;          // a measured cylinder near a fork this much above its branch's taper...
constexpr std::size_t TaperCylinders =
  5; // ...fitted over this many measured cylinders before it, is a junction      // degrees: a child turning more than this from its parent starts a branch

constexpr double PathAngle = 20.0; // degrees: a cylinder turning more from the skeleton's path is not followed

/// The direction an unmeasured cylinder c (a junction) goes on in from `before`, the cylinder under it: along its
/// axis, unless that turns from c's path by more than PathAngle (a cylinder fitted tilted: the ones above would
/// lean with it, the stem does not); then along the path (when known).
Eigen::Vector3d Onward(const TreeCylinder& before, const TreeCylinder& c)
{
  const Eigen::Vector3d axis = (before.end - before.start).normalized();
  return c.path.isZero() || axis.dot(c.path) >= std::cos(PathAngle * M_PI / 180.0) ? axis : c.path;
}

/// log r = a + b log GL fitted (Huber IRLS, weights sqrt(points)) to the measured cylinders; b = 1/2 (the pipe model:
/// area proportional to what is carried) when they do not span a factor 3 of growth length or are fewer than 5.
void FitModel(const std::vector<TreeCylinder>& cylinders, double& a, double& b)
{
  std::vector<double> x, y, w;
  for (const auto& c : cylinders)
    if (c.measured)
    {
      x.push_back(std::log(c.growthLength));
      y.push_back(std::log(c.fittedRadius));
      w.push_back(std::sqrt(static_cast<double>(c.points)));
    }
  b = 0.5;
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  const bool spans = x.size() >= 5 && *hi - *lo >= std::log(3.0);
  std::vector<double> weight = w;
  for (int iteration = 0; iteration < 20; ++iteration)
  {
    if (spans)
    {
      double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (std::size_t i = 0; i < x.size(); ++i)
      {
        sw += weight[i], sx += weight[i] * x[i], sy += weight[i] * y[i];
        sxx += weight[i] * x[i] * x[i], sxy += weight[i] * x[i] * y[i];
      }
      const double det = sw * sxx - sx * sx;
      b = det > 0 ? std::clamp((sw * sxy - sx * sy) / det, 0.25, 1.0) : 0.5;
    }
    double sw = 0, sr = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      sw += weight[i], sr += weight[i] * (y[i] - b * x[i]);
    a = sr / sw;
    std::vector<double> absolute;
    for (std::size_t i = 0; i < x.size(); ++i)
      absolute.push_back(std::abs(y[i] - a - b * x[i]));
    const double k = 1.345 * std::max(RobustScale(absolute), 0.05);
    for (std::size_t i = 0; i < x.size(); ++i)
      weight[i] = w[i] * std::min(1.0, k / std::max(absolute[i], 1e-12));
  }
}

/// Of the paths from `origin` through cylinder `at` (`along` the length before it), each followed through every fork
/// up to `distance` or a tip, the end whose direction from `origin` lies nearest `reference` (`best`: its cosine).
void NearestPathEnd(const std::vector<TreeCylinder>& cylinders, const std::vector<std::vector<int>>& children,
  const Eigen::Vector3d& origin, int at, double along, double distance, const Eigen::Vector3d& reference,
  Eigen::Vector3d& end, double& best)
{
  along += cylinders[at].length;
  if (along < distance && !children[at].empty())
  {
    for (int c : children[at])
      NearestPathEnd(cylinders, children, origin, c, along, distance, reference, end, best);
    return;
  }
  const Eigen::Vector3d d = cylinders[at].end - origin;
  const double cosine = d.norm() > 0 ? d.normalized().dot(reference) : -2.0;
  if (cosine > best)
  {
    best = cosine;
    end = cylinders[at].end;
  }
}

/// The direction from the start of cylinder `k` to a point `distance` further along the tree, through its forks
/// along the path whose end lies nearest the direction `reference` (the parent's, coming in): over a long stretch the
/// lean of the junction cylinders averages out, and a junction leaning towards a lateral does not lead the chord into
/// it. Paths are judged by where they end, not by their first cylinder: a twig that starts along the branch and runs
/// back down beside it (a strip of the branch reached from its far end) ends behind the fork.
Eigen::Vector3d FarDirection(const std::vector<TreeCylinder>& cylinders, const std::vector<std::vector<int>>& children,
  int k, double distance, const Eigen::Vector3d& reference)
{
  const Eigen::Vector3d origin = cylinders[k].start;
  Eigen::Vector3d end = cylinders[k].end;
  double best = -3.0;
  NearestPathEnd(cylinders, children, origin, k, 0.0, distance, reference, end, best);
  const Eigen::Vector3d d = end - origin;
  return d.norm() > 0 ? d.normalized() : Eigen::Vector3d(cylinders[k].end - cylinders[k].start).normalized();
}

/// The unit chord of the chain of single children from cylinder `k` between the lengths `from` and `to` along it
/// (cylinder ends); false when the chain forks or ends before `to`.
bool ChainChord(const std::vector<TreeCylinder>& cylinders, const std::vector<std::vector<int>>& children, int k,
  double from, double to, Eigen::Vector3d& chord)
{
  Eigen::Vector3d first = cylinders[k].start;
  bool started = false;
  for (double along = 0;;)
  {
    along += cylinders[k].length;
    if (!started && along >= from)
    {
      first = cylinders[k].end;
      started = true;
    }
    else if (started && along >= to)
    {
      chord = cylinders[k].end - first;
      if (!(chord.norm() > 0))
        return false;
      chord.normalize();
      return true;
    }
    if (children[k].size() != 1)
      return false;
    k = children[k].front();
  }
}

/// Where a branch ends at a fork, the child (-1: none) that is still the junction: its chain forks again within
/// `reach` (one reach of the parent: the children's surfaces still touch there). Where three or more branches leave
/// one point (a sympodial whorl), the level sets part them one after the other, and the stub between the first and
/// the second parting would be a branch of its own, a cylinder long, its children one order too deep. It goes on
/// from the branch that ends, so that every branch leaving the whorl is of the next order. The heaviest such child
/// whose own fork is codominant (its two heaviest children each carrying at least CodominantShare of the other): a
/// lateral whose first sub-branch leaves near its base is no whorl, and the branch does not run on into it.
int JunctionStub(const std::vector<TreeCylinder>& cylinders, const std::vector<std::vector<int>>& children,
  const std::vector<double>& carried, int p, double reach)
{
  int stub = -1;
  for (int k : children[p])
  {
    double along = cylinders[k].length;
    int at = k;
    while (children[at].size() == 1 && along <= reach)
      along += cylinders[at = children[at].front()].length;
    if (children[at].size() < 2 || along > reach || (stub >= 0 && carried[k] <= carried[stub]))
      continue;
    std::vector<double> loads; // the stub's own fork is a whorl's too: its two heaviest children codominant
    for (int c : children[at])
      loads.push_back(carried[c]);
    std::sort(loads.rbegin(), loads.rend());
    if (loads[1] >= CodominantShare * loads[0])
      stub = k;
  }
  return stub;
}

/// Per cylinder, its children's ids.
std::vector<std::vector<int>> ChildLists(const std::vector<TreeCylinder>& cylinders)
{
  std::vector<std::vector<int>> children(cylinders.size());
  for (std::size_t k = 0; k < cylinders.size(); ++k)
    if (cylinders[k].parent >= 0)
      children[cylinders[k].parent].push_back(static_cast<int>(k));
  return children;
}

/// Per cylinder, the child that continues its branch (-1: none; the branch ends there). At a fork, the children
/// that go on within KinkAngle of the parent are the candidates (as AdTree and the QSM tools: the continuation is the
/// child most aligned with the stem and carrying most), light ones (under ContinueShare of the heaviest candidate:
/// a sliver of the stem's level sets) left out; of those within ForkMargin of the straightest, the one carrying most
/// goes on, however light beside a lateral turning away (a leader goes on past a heavier lateral, and a straight
/// stem stays one branch), unless two codominant children (each carrying at least CodominantShare of the heaviest
/// child) turn alike (within ForkMargin): a sympodial fork or a Y ends the branch, each child a branch of the next
/// order. A single child that turns more than KinkAngle from its parent, and KinkReaches on still turns more than
/// KinkAngle or KinkKept of that turn, does not continue it either: a branch does not bend sharply, a lateral at a
/// leader's thin tip does (its first cylinders would otherwise lengthen the leader); a junction's leaning cylinders
/// come back to the stem's line, while the far chord of a lateral only comes back part of the way where it follows
/// a twig of the lateral that turns up; a branch younger than IncomingReaches has no direction of its own to turn
/// from yet: it does not kink, and at a fork its heaviest child goes on. Directions are chords over a few parent
/// radii, away from the junction (whose cylinders hold both branches and lean): the parent's from below it and never
/// across its own branch's start (parents are decided first: cylinder ids grow from the base), each child's ahead of
/// it (FarDirection).
std::vector<int> ContinuingChildren(
  const std::vector<TreeCylinder>& cylinders, const std::vector<double>& radius, const std::vector<double>& carried)
{
  const std::size_t n = cylinders.size();
  const std::vector<std::vector<int>> children = ChildLists(cylinders);
  std::vector<int> continuing(n, -1);
  // Whether cylinder q continues its parent's branch (false at a branch's first cylinder).
  const auto continues = [&](int q) { return cylinders[q].parent >= 0 && continuing[cylinders[q].parent] == q; };
  const auto reachOf = [&](int p) { return std::max(4.0 * radius[p], 2.0 * cylinders[p].length); };
  // The direction coming into the end of cylinder p: the chord from two reaches to half a reach below it, within
  // its branch so far.
  const auto incoming = [&](int p) {
    const double reach = reachOf(p);
    int near = continues(p) ? cylinders[p].parent : p;
    for (double along = cylinders[p].length; continues(near) && along < 0.5 * reach;)
      along += cylinders[near = cylinders[near].parent].length;
    int far = near;
    for (double along = 0; continues(far) && along < 2.0 * reach;)
      along += cylinders[far = cylinders[far].parent].length;
    const Eigen::Vector3d d = cylinders[near].end - cylinders[far].start;
    return d.norm() > 0 ? d.normalized() : (cylinders[p].end - cylinders[p].start).normalized().eval();
  };
  // The length of p's branch up to p's end: under IncomingReaches reaches, its incoming direction is that of its
  // first cylinders, which at a junction still follow the parent's axis (a young branch measured from there turns by
  // its own branching angle at every link, and cut at each it would climb an order each time).
  const auto history = [&](int p) {
    double along = cylinders[p].length;
    for (int q = p; continues(q);)
      along += cylinders[q = cylinders[q].parent].length;
    return along;
  };
  const auto degrees = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
  };
  // How much the chain turns where single child k follows p: its first reach against p's incoming direction, and
  // the same from half a reach to one and a half (0 when the chain forks or ends before): a junction's cylinders
  // lean towards the child that leaves there, but the stem past them goes on straight.
  const auto turn = [&](int p, int k) {
    Eigen::Vector3d d, far;
    const double reach = reachOf(p);
    if (!ChainChord(cylinders, children, k, 0.0, reach, d) ||
      !ChainChord(cylinders, children, k, 0.5 * reach, 1.5 * reach, far))
      return 0.0;
    const Eigen::Vector3d in = incoming(p);
    return std::min(degrees(d, in), degrees(far, in));
  };
  for (std::size_t p = 0; p < n; ++p)
  {
    if (children[p].empty())
      continue;
    const double reach = reachOf(static_cast<int>(p));
    const Eigen::Vector3d dp = incoming(static_cast<int>(p));
    double heaviest = 0;
    for (int k : children[p])
      heaviest = std::max(heaviest, carried[k]);
    const auto angle = [&](const Eigen::Vector3d& d) { return degrees(d, dp); };
    if (children[p].size() == 1)
    {
      // A kink: the chain turns sharply here, and more than at the next link (a bend seen from a reach before it
      // is placed where it is).
      const int k = children[p].front();
      continuing[p] = k;
      const double here = turn(static_cast<int>(p), k);
      if (here > KinkAngle && history(static_cast<int>(p)) >= IncomingReaches * reach &&
        angle(FarDirection(cylinders, children, k, KinkReaches * reach, dp)) > std::min(KinkAngle, KinkKept * here) &&
        !(children[k].size() == 1 && turn(k, children[k].front()) > here))
        continuing[p] = -1;
      continue;
    }
    // The children that go on within KinkAngle of the parent's direction; among those carrying at least
    // ContinueShare of the heaviest of them (a split sliver of the stem is not its continuation), the straightest
    // ones (within ForkMargin of the straightest) and of them the one carrying most.
    // A branch younger than IncomingReaches has no direction of its own yet (its first cylinders follow its
    // parent's axis): every child is a candidate and the heaviest goes on.
    const bool young = history(static_cast<int>(p)) < IncomingReaches * reach;
    std::vector<std::pair<double, int>> angles; // (degrees, child), aligned children
    double heaviestAligned = 0;
    for (int k : children[p])
    {
      const double a = angle(FarDirection(cylinders, children, k, 2.0 * reach, dp));
      if (a <= KinkAngle || young)
      {
        angles.emplace_back(a, k);
        heaviestAligned = std::max(heaviestAligned, carried[k]);
      }
    }
    angles.erase(std::remove_if(angles.begin(), angles.end(),
                   [&](const auto& a) { return carried[a.second] < ContinueShare * heaviestAligned; }),
      angles.end());
    std::sort(angles.begin(), angles.end());
    if (!angles.empty())
    {
      int chosen = angles[0].second;
      for (const auto& [a, k] : angles)
        if ((young || a <= angles[0].first + ForkMargin) && carried[k] > carried[chosen])
          chosen = k;
      // Codominant children (each carrying at least half the heaviest) turning alike: the branch ends at the fork.
      const auto codominant = [&](int k) { return carried[k] >= CodominantShare * heaviest; };
      const bool fork = angles.size() > 1 && codominant(angles[0].second) && codominant(angles[1].second) &&
        angles[1].first - angles[0].first < ForkMargin;
      if (!fork)
        continuing[p] = chosen;
    }
    if (continuing[p] < 0)
      continuing[p] = JunctionStub(cylinders, children, carried, static_cast<int>(p), reach);
  }
  return continuing;
}

/// Branches: the trunk from the base, at every fork the aligned child carrying the most volume continues its parent's
/// branch (ContinuingChildren).
void AssignBranches(TreeFitResult& result, const std::vector<double>& radius)
{
  auto& cylinders = result.cylinders;
  const std::size_t n = cylinders.size();
  std::vector<double> carried(n, 0.0);
  for (std::size_t k = n; k-- > 0;)
  {
    carried[k] += M_PI * radius[k] * radius[k] * cylinders[k].length;
    if (cylinders[k].parent >= 0)
      carried[cylinders[k].parent] += carried[k];
  }
  const std::vector<int> continuing = ContinuingChildren(cylinders, radius, carried);
  result.branches.clear();
  for (std::size_t k = 0; k < n; ++k)
  {
    TreeCylinder& c = cylinders[k];
    if (c.parent >= 0 && continuing[c.parent] == static_cast<int>(k))
    {
      c.branch = cylinders[c.parent].branch;
      c.order = cylinders[c.parent].order;
    }
    else
    {
      TreeBranchRow row;
      row.id = static_cast<int>(result.branches.size());
      row.parent = c.parent >= 0 ? cylinders[c.parent].branch : -1;
      row.order = c.parent >= 0 ? cylinders[c.parent].order + 1 : 0;
      result.branches.push_back(row);
      c.branch = row.id;
      c.order = row.order;
    }
    result.branches[c.branch].cylinders.push_back(static_cast<int>(k));
  }
}

/// A child branch leaves the level sets only where its surface parts from its parent's, some way past the fork: its
/// first cylinder is extended back along its axis to the parent's surface (the parent's cylinders near the fork).
void SeatBranches(TreeFitResult& result)
{
  auto& cylinders = result.cylinders;
  const std::vector<std::vector<int>> children = ChildLists(cylinders);
  for (const TreeBranchRow& branch : result.branches)
  {
    TreeCylinder& first = cylinders[branch.cylinders.front()];
    if (first.parent < 0)
      continue;
    std::vector<int> near;
    for (int q = first.parent, back = 0; q >= 0 && back < 4; q = cylinders[q].parent, ++back)
      near.push_back(q);
    for (int q = first.parent, ahead = 0; ahead < 3;)
    {
      int next = -1;
      for (int c : children[q])
        if (cylinders[c].branch == cylinders[first.parent].branch)
          next = c;
      if (next < 0)
        break;
      near.push_back(next);
      q = next;
      ++ahead;
    }
    const Eigen::Vector3d d = (first.end - first.start).normalized();
    const double reach = 2.0 * std::max(first.length, 3.0 * cylinders[first.parent].radius);
    const double step = std::max(reach / 200.0, 1e-9);
    for (double t = 0; t <= reach; t += step)
    {
      const Eigen::Vector3d x = first.start - t * d;
      const bool inside = std::any_of(near.begin(), near.end(),
        [&](int q) { return SegmentDistance(x, cylinders[q].start, cylinders[q].end) <= cylinders[q].radius; });
      if (inside)
      {
        first.start = x;
        first.length += t;
        break;
      }
    }
  }
}
/// Junctions: where a child branch leaves, its first points fall in the parent's level sets, and the cylinder fitted
/// there is wider than the branch and leans towards the child (a bulge). A measured cylinder that is its parent's only
/// child and wider than it by more than BulgeFactor (and two noise deviations) is such a junction: its radius is not
/// measured (the model gives it, never wider than its parent) and it goes on along its parent's axis. A junction's
/// bulge spans the stem's cylinders holding the child's first points, a few of its own diameters; a run of them
/// longer than BulgeRunDiameters of its widest is a branch wider than the stem's tip it goes on from (a lateral
/// leaving a leader's tip), not a junction: each of its cylinders from there aims from the one before at its own
/// fitted end (when the axis line lies more than its fitted radius from that), or the run, each in line with the
/// tip, leaves the bending branch's points and takes the trunk along into it.
void FlattenBulges(double noise, std::vector<TreeCylinder>& cylinders)
{
  std::vector<int> childCount(cylinders.size(), 0);
  for (const auto& c : cylinders)
    if (c.parent >= 0)
      ++childCount[c.parent];
  std::vector<double> width(cylinders.size(), std::numeric_limits<double>::quiet_NaN());  // measured or carried on
  std::vector<double> runLength(cylinders.size(), 0.0), runRadius(cylinders.size(), 0.0); // the run of junctions
  for (std::size_t k = 0; k < cylinders.size(); ++k)
  {
    TreeCylinder& c = cylinders[k];
    if (c.measured)
      width[k] = c.fittedRadius;
    const int p = c.parent;
    if (p < 0 || childCount[p] != 1 || !c.measured || !std::isfinite(width[p]))
      continue;
    if (c.fittedRadius <= BulgeFactor * width[p] + 2.0 * noise)
      continue;
    c.measured = false;
    width[k] = width[p];
    runLength[k] = runLength[p] + c.length;
    runRadius[k] = std::max(runRadius[p], c.fittedRadius);
    const Eigen::Vector3d fittedEnd = c.end;
    c.start = cylinders[p].end;
    c.end = c.start + c.length * Onward(cylinders[p], c);
    if (runLength[k] > 2.0 * BulgeRunDiameters * runRadius[k] && (c.end - fittedEnd).norm() > c.fittedRadius)
      c.end = c.start + c.length * (fittedEnd - c.start).normalized();
  }
}
/// FlattenBulges along the branches, once they are known, with the branch's own taper: near a fork (within two
/// cylinders of one), a measured cylinder wider than the taper of the measured cylinders before it allows
/// (TaperMargin and two noise deviations; the taper a least-squares line over the last TaperCylinders of them,
/// never rising, never below half the last width) is a junction: a stem carrying laterals thicker than itself can
/// hold several in a row, each narrower than the one before but all wider than the stem. Away from forks a stem may
/// taper unevenly (butt swell): nothing is flagged there.
void FlattenBranchBulges(double noise, TreeFitResult& result)
{
  auto& cylinders = result.cylinders;
  std::vector<int> childCount(cylinders.size(), 0);
  for (const auto& c : cylinders)
    if (c.parent >= 0)
      ++childCount[c.parent];
  for (const TreeBranchRow& branch : result.branches)
  {
    const auto& ids = branch.cylinders;
    const auto nearFork = [&](std::size_t j) {
      for (std::size_t i = j >= 2 ? j - 2 : 0; i <= std::min(ids.size() - 1, j + 2); ++i)
        if (childCount[ids[i]] > 1)
          return true;
      return j < 2 && cylinders[ids[0]].parent >= 0 && childCount[cylinders[ids[0]].parent] > 1;
    };
    std::vector<std::pair<double, double>> taper; // (length along the branch to the middle, radius), accepted
    double along = 0;
    for (std::size_t j = 0; j < ids.size(); along += cylinders[ids[j]].length, ++j)
    {
      TreeCylinder& c = cylinders[ids[j]];
      if (!c.measured)
        continue;
      const double s = along + 0.5 * c.length;
      if (!taper.empty() && nearFork(j))
      {
        const std::size_t first = taper.size() > TaperCylinders ? taper.size() - TaperCylinders : 0;
        double sw = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
        for (std::size_t i = first; i < taper.size(); ++i)
          sw += 1, sx += taper[i].first, sy += taper[i].second, sxx += taper[i].first * taper[i].first,
            sxy += taper[i].first * taper[i].second;
        const double det = sw * sxx - sx * sx;
        const double slope = det > 1e-12 ? std::min(0.0, (sw * sxy - sx * sy) / det) : 0.0;
        const double last = taper.back().second;
        const double expected = std::max(last + slope * (s - taper.back().first), 0.5 * last);
        if (c.fittedRadius > TaperMargin * expected + 2.0 * noise)
        {
          c.measured = false;
          if (j > 0)
          {
            const TreeCylinder& before = cylinders[ids[j - 1]];
            c.start = before.end;
            c.end = c.start + c.length * Onward(before, c);
          }
          continue;
        }
      }
      taper.emplace_back(s, c.fittedRadius);
    }
  }
}

/// The length along a branch (its cylinders `ids`, base first) to each cylinder's middle.
std::vector<double> MiddlesAlong(const std::vector<TreeCylinder>& cylinders, const std::vector<int>& ids)
{
  std::vector<double> middle(ids.size(), 0.0);
  double along = 0;
  for (std::size_t j = 0; j < ids.size(); ++j)
  {
    middle[j] = along + 0.5 * cylinders[ids[j]].length;
    along += cylinders[ids[j]].length;
  }
  return middle;
}

/// A stem never thickens towards its tip. Where laterals leave it, their first points fall in its level sets and the
/// cylinders fitted there hold them beside the stem's own; when each such fit is only a little wider than the one
/// before, none is a bulge against its neighbour (FlattenBulges) nor against a taper that the run itself raises
/// (FlattenBranchBulges), and the stem creeps wider over metres. Along each branch, a measured cylinder wider than
/// the narrowest measured one below it (by `margin` noise deviations), where a measured one further up is narrower
/// than that again (the stem comes back down: a bump, not a thicker stem), is a junction when it is wider than the
/// taper between those two by TaperMargin and two noise deviations: its radius is not measured (InterpolateTaper
/// gives it). A stem tapering in steps (a capped segment per fork) never rises, so it is not judged.
void FlattenTaperBumps(double noise, double margin, TreeFitResult& result)
{
  auto& cylinders = result.cylinders;
  for (const TreeBranchRow& branch : result.branches)
  {
    const auto& ids = branch.cylinders;
    const std::vector<double> middle = MiddlesAlong(cylinders, ids);
    std::size_t below = ids.size(); // the narrowest measured cylinder below, not a junction
    for (std::size_t j = 0; j < ids.size(); ++j)
    {
      TreeCylinder& c = cylinders[ids[j]];
      if (!c.measured)
        continue;
      if (below == ids.size() || c.fittedRadius <= cylinders[ids[below]].fittedRadius)
      {
        below = j;
        continue;
      }
      const double low = cylinders[ids[below]].fittedRadius;
      if (c.fittedRadius <= low + margin * noise)
        continue;
      std::size_t above = j + 1;
      while (above < ids.size() && !(cylinders[ids[above]].measured && cylinders[ids[above]].fittedRadius < low))
        ++above;
      if (above == ids.size())
        continue;
      const double t = (middle[j] - middle[below]) / (middle[above] - middle[below]);
      const double expected = (1 - t) * low + t * cylinders[ids[above]].fittedRadius;
      if (c.fittedRadius > TaperMargin * expected + 2.0 * noise)
        c.measured = false;
    }
  }
}

/// Behind leaves a stem's own points are few where laterals leave it, and a cylinder fitted there holds the laterals'
/// first points beside the stem's: it leans towards them, lies wider than the stem and its points lie far off its
/// surface; a clean fit of the stem (residual scale within LeafScaleNoise noise deviations) follows the stem's line.
/// Along each stem (a branch without parent), a measured cylinder whose residual scale is above LeafScaleNoise noise
/// deviations and whose axis turns more than LeanAngle from the last clean fit below it is not measured (the taper
/// between the measured fits either side gives its radius, InterpolateTaper) and goes on from the cylinder below along
/// that fit's axis.
void FlattenLeaningFits(double noise, TreeFitResult& result)
{
  auto& cylinders = result.cylinders;
  const double cosLean = std::cos(LeanAngle * M_PI / 180.0);
  for (const TreeBranchRow& branch : result.branches)
  {
    if (branch.parent >= 0)
      continue;
    Eigen::Vector3d clean = Eigen::Vector3d::Zero(); // the axis of the last clean fit below
    for (int k : branch.cylinders)
    {
      TreeCylinder& c = cylinders[k];
      const Eigen::Vector3d axis = c.end - c.start;
      if (!c.measured || axis.norm() <= 0)
        continue;
      if (c.fitRMS <= LeafScaleNoise * noise)
        clean = axis.normalized();
      else if (clean.norm() > 0 && axis.normalized().dot(clean) < cosLean)
      {
        c.measured = false;
        if (c.parent >= 0 && cylinders[c.parent].branch == c.branch)
          c.start = cylinders[c.parent].end;
        c.end = c.start + c.length * clean;
      }
    }
  }
}

/// Along each branch, a run of cylinders whose radius is not measured, between two that are, follows the taper
/// between them (linear in the length along the branch): a junction or an occluded stretch of a stem.
void InterpolateTaper(TreeFitResult& result)
{
  auto& cylinders = result.cylinders;
  for (const TreeBranchRow& branch : result.branches)
  {
    const auto& ids = branch.cylinders;
    const std::vector<double> middle = MiddlesAlong(cylinders, ids);
    for (std::size_t j = 0, last = ids.size(); j < ids.size(); ++j)
    {
      if (!cylinders[ids[j]].measured)
        continue;
      if (last < j && j - last > 1)
        for (std::size_t i = last + 1; i < j; ++i)
        {
          const double t = (middle[i] - middle[last]) / (middle[j] - middle[last]);
          cylinders[ids[i]].radius = (1 - t) * cylinders[ids[last]].radius + t * cylinders[ids[j]].radius;
        }
      last = j;
    }
  }
}

/// The stretch at a branch's end that the points did not support (its cylinders after its last measured one, all of
/// them when none is measured: wood a segmentation called leaf, or hidden) ends at a fork whose children's bases
/// were measured: there the branch carries no more cross-section than they do (the pipe model: its end radius at
/// most the square root of the sum of their squared radii, a child's taken at its first measured cylinder within
/// ChildBaseCylinders, else its own). The stretch follows the taper from the last measured radius to that end
/// radius; with none measured, the pipe model down the branch from its end: at each cylinder the cross-section of
/// the side branches leaving it is added, a measured one's own, another's the end's share of its growth length
/// (their modelled radii are the inflated ones); never wider than the model made it. Without
/// this the stretch takes its parent branch's level of the model, and the model's growth length counts whatever
/// hangs from the stretch: sym-small behind the segmentation, first-order branches at 0.081 m to their ends for
/// 0.062.
void CapUnmeasuredEnds(TreeFitResult& result)
{
  auto& cylinders = result.cylinders;
  const std::vector<std::vector<int>> children = ChildLists(cylinders);
  const auto baseRadius = [&](int first, bool& measured) {
    const auto& ids = result.branches[cylinders[first].branch].cylinders;
    for (std::size_t j = 0; j < std::min(ids.size(), ChildBaseCylinders); ++j)
      if (cylinders[ids[j]].measured)
        return measured = true, cylinders[ids[j]].radius;
    return cylinders[first].radius;
  };
  for (const TreeBranchRow& branch : result.branches)
  {
    const auto& ids = branch.cylinders;
    const int end = ids.back();
    if (children[end].empty() || cylinders[end].measured)
      continue;
    double area = 0, endLength = 0; // the end's children: cross-section and growth length
    bool anyMeasured = false;
    for (int c : children[end])
    {
      endLength += cylinders[c].growthLength;
      bool measured = false;
      const double r = baseRadius(c, measured);
      area += r * r;
      anyMeasured = anyMeasured || measured;
    }
    const double cap = std::sqrt(area);
    if (!anyMeasured || !(cap < cylinders[end].radius))
      continue;
    std::size_t last = ids.size(); // the last measured cylinder of the branch
    for (std::size_t j = 0; j < ids.size(); ++j)
      if (cylinders[ids[j]].measured)
        last = j;
    std::vector<double> middle(ids.size()); // length along the branch to each cylinder's middle
    double along = 0;
    for (std::size_t j = 0; j < ids.size(); along += cylinders[ids[j]].length, ++j)
      middle[j] = along + 0.5 * cylinders[ids[j]].length;
    if (last < ids.size())
    {
      for (std::size_t j = last + 1; j < ids.size(); ++j)
      {
        const double t = (middle[j] - middle[last]) / std::max(along - middle[last], 1e-300);
        TreeCylinder& c = cylinders[ids[j]];
        c.radius = std::min(c.radius, (1 - t) * cylinders[ids[last]].radius + t * cap);
      }
      continue;
    }
    double carried = cap * cap; // the cross-section carried, from the end down: what leaves on the way adds to it
    for (std::size_t j = ids.size(); j-- > 0;)
    {
      TreeCylinder& c = cylinders[ids[j]];
      if (j + 1 < ids.size())
        for (int k : children[ids[j]])
          if (k != ids[j + 1])
          {
            bool measured = false;
            const double r = baseRadius(k, measured);
            carried += measured ? r * r : cap * cap * cylinders[k].growthLength / endLength;
          }
      c.radius = std::min(c.radius, std::sqrt(carried));
    }
  }
}
} // namespace

std::string ModelRadii(double spacing, TreeFitResult& result, bool leafLabelled)
{
  auto& cylinders = result.cylinders;
  const std::size_t n = cylinders.size();
  // The scan's noise: the residual scale of the well-covered fits.
  std::vector<double> scales, all;
  for (const auto& c : cylinders)
    if (std::isfinite(c.fittedRadius))
    {
      all.push_back(c.fitRMS);
      if (c.points >= 30 && c.coverage >= 180.0)
        scales.push_back(c.fitRMS);
    }
  double noise = !scales.empty() ? Median(scales) : !all.empty() ? Median(all) : 0.5 * spacing;
  noise = std::max(noise, 1e-3 * spacing);
  result.traits.noise = noise;
  for (auto& c : cylinders)
  {
    const double r = c.fittedRadius;
    c.measured = std::isfinite(r) && c.points >= MinMeasuredPoints && c.coverage >= MinCoverage &&
      r * c.coverage * M_PI / 180.0 >= MinArcSpacings * spacing && r >= MinRadiusNoise * noise &&
      c.fitRMS <= MaxScaleRadius * r;
  }
  FlattenBulges(noise, cylinders);
  for (std::size_t k = n; k-- > 0;)
  {
    cylinders[k].growthLength += std::max(cylinders[k].length, 1e-12);
    if (cylinders[k].parent >= 0)
      cylinders[cylinders[k].parent].growthLength += cylinders[k].growthLength;
  }
  const std::vector<std::vector<int>> children = ChildLists(cylinders);
  double a = 0, b = 0.5;
  for (int round = 0; round < 3; ++round)
  {
    if (std::none_of(cylinders.begin(), cylinders.end(), [](const TreeCylinder& c) { return c.measured; }))
      return "no part of the cloud has points enough to measure a radius: too sparse, too noisy, or not a tree";
    FitModel(cylinders, a, b);
    for (std::size_t k = 0; k < n; ++k)
    {
      TreeCylinder& c = cylinders[k];
      if (!c.measured)
        continue;
      const double model = std::exp(a + b * std::log(c.growthLength));
      const double ratio = c.fittedRadius / model;
      const bool strong =
        c.coverage >= StrongCoverage && c.points >= MinStrongPoints && c.fittedRadius >= StrongRadiusNoise * noise;
      // leaves all round a twig: the circle is theirs (the wood a minority inside it), fitted all round but with its
      // points as far off it as leaves lie; a fork's cylinder holds the child's first points, so it is not judged
      const bool leafRing = leafLabelled && children[k].size() <= 1 && ratio > 1.0 &&
        c.fitRMS > std::max(LeafScaleNoise * noise, LeafScaleRadius * c.fittedRadius);
      if (leafRing || (!strong && (ratio > ModelFactor || ratio < 1.0 / ModelFactor)))
        c.measured = false;
    }
  }
  std::vector<double> model(n), first(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    model[k] = std::exp(a + b * std::log(cylinders[k].growthLength));
    first[k] = cylinders[k].measured ? cylinders[k].fittedRadius : model[k];
  }
  AssignBranches(result, first);
  FlattenBranchBulges(noise, result);
  FlattenTaperBumps(noise, 2.0, result);
  if (leafLabelled)
  {
    FlattenLeaningFits(noise, result);
    // The leaning fits set the taper the first pass judged against: a clean fit on the laterals' surface between them
    // (on the stem's line, as wide as the stem below and wider than the true stem) was judged against fits as wide
    // as itself, or not at all within two noise deviations of the narrowest below. On the fits left, every measured
    // fit wider than the narrowest below it is judged (the threshold over the taper unchanged).
    FlattenTaperBumps(noise, 0.0, result);
  }
  // Each branch's level: the geometric mean of its measured / model ratios, else its parent branch's.
  std::vector<double> level(result.branches.size(), 1.0);
  for (const auto& branch : result.branches)
  {
    double sum = 0, count = 0;
    for (int k : branch.cylinders)
      if (cylinders[k].measured)
      {
        sum += std::log(cylinders[k].fittedRadius / model[k]);
        count += 1;
      }
    level[branch.id] = count > 0 ? std::exp(std::clamp(sum / count, -std::log(ModelFactor), std::log(ModelFactor)))
                                 : (branch.parent >= 0 ? level[branch.parent] : 1.0);
  }
  for (std::size_t k = 0; k < n; ++k)
  {
    TreeCylinder& c = cylinders[k];
    if (c.measured)
      c.radius = c.fittedRadius;
    else
    {
      c.radius = level[c.branch] * model[k];
      if (c.parent >= 0)
        c.radius = std::min(c.radius, cylinders[c.parent].radius); // no modelled cylinder wider than what carries it
    }
  }
  InterpolateTaper(result);
  CapUnmeasuredEnds(result);
  SeatBranches(result);
  return {};
}

} // namespace treefit
} // namespace plantmorph
