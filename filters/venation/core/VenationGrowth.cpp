// SPDX-License-Identifier: GPL-3.0-or-later
#include "VenationGrowth.h"

#include "PalmateFan.h"
#include "SpaceColonization.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RandomStream.h>
#include <plantmorph/RangeError.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <sstream>

namespace plantmorph
{
namespace
{
Eigen::Vector2d Rotate(const Eigen::Vector2d& d, double degrees)
{
  const double a = degrees * Pi / 180.0;
  return { std::cos(a) * d.x() - std::sin(a) * d.y(), std::sin(a) * d.x() + std::cos(a) * d.y() };
}

Eigen::Vector2d Left(const Eigen::Vector2d& d)
{
  return { -d.y(), d.x() };
}

std::string Range(const char* property, double value, const char* range)
{
  return OutOfRange(property, value, range);
}

/// The random streams, one per phase, so changing one phase's parameters leaves the others' draws alone.
enum Stream : std::uint64_t
{
  StreamSecondary = 1,
  StreamTertiary = 2,
  StreamVeinlet = 3,
};

class Grower
{
public:
  Grower(const VenationBlade& blade, const BladeLocator& locator, const VenationParameters& p,
    const std::function<bool(double)>& progress)
    : Blade(blade)
    , Locator(locator)
    , P(p)
    , Progress(progress)
    , Graph(locator.Lower() - Eigen::Vector2d::Constant(1e-6), locator.Upper() + Eigen::Vector2d::Constant(1e-6),
        CellSize(locator, p))
  {
  }

  std::string Run(VenationResult& result);

private:
  static double CellSize(const BladeLocator& locator, const VenationParameters& p)
  {
    const Eigen::Vector2d extent = locator.Upper() - locator.Lower();
    const double size = std::max(extent.x(), extent.y());
    const double detail = p.tertiary ? p.areoleSize : p.secondarySpacing * 0.5;
    return p.gridCellScale * detail * size;
  }

  bool Inside(const Eigen::Vector2d& x) const { return this->Locator.Locate(x, 1e-9 * this->Length).triangle >= 0; }
  bool KeepGoing(double fraction) const { return !this->Progress || this->Progress(fraction); }

  int NodeAt(const Eigen::Vector2d& x);
  void OrientPrimariesFromTheBase(std::vector<std::vector<int>>& paths) const;
  void AddMargin();
  /// Traces the primary u = const from the base; returns its node path.
  std::vector<int> TracePrimary(double u, int vein);
  /// Grows a curve (points after the start) from node `from`; returns the last node and whether it stopped on a
  /// vein or the margin. `stopAfter` samples at most (all when negative).
  VeinGraph::Step GrowCurve(int from, const std::vector<Eigen::Vector2d>& points, int vein, double snap);
  /// A secondary vein: its node on the midvein, side, height and directions; where it forked (if it did).
  struct Secondary
  {
    int node = -1;
    int host = 0; ///< which primary it leaves (0: the midvein)
    int side = 0;
    double v = 0.0;
    Eigen::Vector2d tangent, outward;
    int fork = -1; ///< the node where it forked (or stopped short of the margin), -1 if it met a vein first
    double exit = 0.0;
  };
  /// The secondaries of every primary path in `hosts` (the midvein; each palmate primary); the paths gain the
  /// secondaries' start nodes.
  std::string GrowSecondaries(std::vector<std::vector<int>>& hosts);
  /// Secondaries' start nodes on the primary `path` (split into it), from the base up; `total` is its length.
  std::vector<Secondary> PlaceSecondaries(RandomStream& random, std::vector<int>& path, double total, int host);
  /// How secondaries end: the pattern's own, or for palmate primaries the PalmateSecondaries choice.
  VenationPattern SecondaryPattern() const
  {
    if (this->P.pattern != VenationPattern::Palmate)
      return this->P.pattern;
    return this->P.palmateSecondaries == PalmateSecondaries::Brochidodromous ? VenationPattern::Brochidodromous
                                                                             : VenationPattern::Craspedodromous;
  }
  /// Hierarchical reticulum: the tertiary edge length factor at x (areoleGradient; 1 when it is 0).
  double AreoleScale(const Eigen::Vector2d& x) const;
  void BuildPrimaryDistance();
  /// Grows one secondary (eq. (2)) to its fork or the margin, and what continues from the fork.
  void GrowSecondary(Secondary& secondary);
  /// Loops (eq. (4)) from each fork to the fork of the next secondary above on the same side.
  void GrowSecondaryLoops(const std::vector<Secondary>& secondaries);
  std::string GrowTertiaries();
  void GrowVeinlets();
  void GrowPalmate();
  /// Sub-lobe veins (subLobeVeins): a secondary from the nearest primary in `hosts` to every sub-lobe tip; the
  /// paths gain the veins' start nodes.
  void GrowSubLobeVeins(std::vector<std::vector<int>>& hosts);
  /// Flank secondaries (flankSecondaries): straight secondaries into the blade's parts farthest from the primaries
  /// and secondaries while they are farther than secondarySpacing.
  void GrowFlankSecondaries();
  /// Splits the path at arc length `at` from its start (an existing node within 1e-9 L is reused); the node there.
  int SplitPathAt(std::vector<int>& path, double at);
  void Finish(VenationResult& result);

  const VenationBlade& Blade;
  const BladeLocator& Locator;
  const VenationParameters& P;
  const std::function<bool(double)>& Progress;
  VeinGraph Graph;
  double Length = 1.0; ///< leaf length L
  double Width = 1.0;  ///< blade width across the axis
  double Step = 0.01;  ///< sampling step of traced curves
  double Snap = 1e-9;  ///< tertiary snap distance
  Eigen::Vector2d Base = Eigen::Vector2d::Zero(), Apex = Eigen::Vector2d::Zero(), Axis = Eigen::Vector2d::UnitY();
  int BaseNode = -1;
  std::vector<int> Midvein;      ///< node path of the midvein (pinnate patterns)
  std::vector<int> PrimaryVeins; ///< palmate: the primaries' vein ids
  /// Distance to the nearest primary on a grid over the blade's box (areoleGradient), and its largest value inside.
  std::vector<double> PrimaryDistance;
  int DistanceCells = 0;
  double DistanceCell = 1.0, DistanceFar = 1.0;
  std::vector<double> JunctionAngles;
};

int Grower::NodeAt(const Eigen::Vector2d& x)
{
  const double tolerance = 1e-9 * this->Length;
  const auto& nodes = this->Graph.Nodes();
  for (std::size_t i = 0; i < nodes.size(); ++i)
  {
    if ((nodes[i] - x).norm() <= tolerance)
      return static_cast<int>(i);
  }
  const auto& edges = this->Graph.Edges();
  for (std::size_t e = 0; e < edges.size(); ++e)
  {
    const Eigen::Vector2d foot = ClosestOnSegment(x, nodes[edges[e].a], nodes[edges[e].b]);
    if ((foot - x).norm() <= tolerance)
      return this->Graph.SplitEdge(static_cast<int>(e), foot);
  }
  return this->Graph.AddNode(x);
}

void Grower::OrientPrimariesFromTheBase(std::vector<std::vector<int>>& paths) const
{
  // A primary runs from its end nearer the base out (the base, or where it branches off a neighbour).
  const auto& nodes = this->Graph.Nodes();
  for (int vein : this->PrimaryVeins)
  {
    std::vector<int>& path = paths[static_cast<std::size_t>(vein)];
    if (path.size() >= 2 && (nodes[path.back()] - this->Base).norm() < (nodes[path.front()] - this->Base).norm())
      std::reverse(path.begin(), path.end());
  }
}

void Grower::AddMargin()
{
  const int margin = this->Graph.AddVein(VeinOrderMargin);
  for (const std::vector<int>& loop : this->Locator.BoundaryLoops())
  {
    std::vector<int> nodes;
    for (int v : loop)
      nodes.push_back(this->Graph.AddNode(this->Blade.points[v]));
    for (std::size_t i = 0; i < nodes.size(); ++i)
      this->Graph.AddEdge(nodes[i], nodes[(i + 1) % nodes.size()], margin);
  }
}

VeinGraph::Step Grower::GrowCurve(int from, const std::vector<Eigen::Vector2d>& points, int vein, double snap)
{
  VeinGraph::Step step;
  step.node = from;
  for (const Eigen::Vector2d& x : points)
  {
    if ((x - this->Graph.Nodes()[step.node]).norm() <= 1e-9 * this->Length)
      continue;
    step = this->Graph.Grow(step.node, x, vein, snap);
    if (step.stopped)
      break;
  }
  return step;
}

std::vector<int> Grower::TracePrimary(double u, int vein)
{
  const int pieces = std::max(8, static_cast<int>(std::ceil(this->Length / this->Step)));
  std::vector<int> path = { this->BaseNode };
  for (int k = 1; k <= pieces; ++k)
  {
    const Eigen::Vector2d x = this->Locator.PointAtUV(Eigen::Vector2d(u, static_cast<double>(k) / pieces));
    if ((x - this->Graph.Nodes()[path.back()]).norm() <= 1e-9 * this->Length)
      continue;
    const VeinGraph::Step step = this->Graph.Grow(path.back(), x, vein, 1e-7 * this->Length);
    if (step.node != path.back())
      path.push_back(step.node);
    if (step.stopped)
      break;
  }
  return path;
}

std::string Grower::GrowSecondaries(std::vector<std::vector<int>>& hosts)
{
  RandomStream random(this->P.seed, StreamSecondary);
  const auto& nodes = this->Graph.Nodes();
  std::vector<Secondary> secondaries;
  for (std::size_t host = 0; host < hosts.size(); ++host)
  {
    // Arc length along the primary's path.
    double total = 0.0;
    for (std::size_t i = 1; i < hosts[host].size(); ++i)
      total += (nodes[hosts[host][i]] - nodes[hosts[host][i - 1]]).norm();
    if (!(total > 0.0))
      continue;
    const std::vector<Secondary> placed = this->PlaceSecondaries(random, hosts[host], total, static_cast<int>(host));
    secondaries.insert(secondaries.end(), placed.begin(), placed.end());
  }
  // Grown in turn from the base up over all primaries, so no primary's secondaries claim the space first.
  std::stable_sort(
    secondaries.begin(), secondaries.end(), [](const Secondary& a, const Secondary& b) { return a.v < b.v; });
  for (Secondary& secondary : secondaries)
    this->GrowSecondary(secondary);
  if (!this->KeepGoing(0.35))
    return "aborted";
  this->GrowSecondaryLoops(secondaries);
  return {};
}

std::vector<Grower::Secondary> Grower::PlaceSecondaries(
  RandomStream& random, std::vector<int>& path, double total, int host)
{
  const auto& nodes = this->Graph.Nodes();
  const double spacing = this->P.secondarySpacing * this->Length;
  struct Branch
  {
    double at = 0.0; ///< arc length along the midvein
    int side = 0;    ///< 0 left, 1 right
  };
  std::vector<Branch> branches;
  for (int side = 0; side < 2; ++side)
  {
    for (double s = spacing; s < total - 0.5 * spacing; s += spacing)
    {
      const double at = s + random.Uniform(0.0, 0.5 * spacing);
      if (at < total - 0.5 * spacing)
        branches.push_back({ at, side });
    }
  }
  std::stable_sort(branches.begin(), branches.end(), [](const Branch& a, const Branch& b) { return a.at < b.at; });

  // Branch nodes on the midvein, in order from the base (the path gains the new nodes as it goes).
  std::vector<Secondary> secondaries;
  std::size_t segment = 0;
  double start = 0.0; // arc length at path[segment]
  for (const Branch& branch : branches)
  {
    while (segment + 1 < path.size() && start + (nodes[path[segment + 1]] - nodes[path[segment]]).norm() < branch.at)
    {
      start += (nodes[path[segment + 1]] - nodes[path[segment]]).norm();
      ++segment;
    }
    if (segment + 1 >= path.size())
      break;
    const Eigen::Vector2d a = nodes[path[segment]], b = nodes[path[segment + 1]];
    const double piece = (b - a).norm();
    const Eigen::Vector2d tangent = (b - a) / piece;
    const Eigen::Vector2d x = a + std::min(piece, branch.at - start) * tangent;
    int node;
    if ((x - a).norm() <= 1e-9 * this->Length)
      node = path[segment];
    else if ((x - b).norm() <= 1e-9 * this->Length)
      node = path[segment + 1];
    else
    {
      node = this->Graph.SplitEdge(this->Graph.FindEdge(path[segment], path[segment + 1]), x);
      path.insert(path.begin() + static_cast<std::ptrdiff_t>(segment) + 1, node);
      start += (x - a).norm();
      ++segment;
    }
    Secondary secondary;
    secondary.node = node;
    secondary.host = host;
    secondary.side = branch.side;
    secondary.v = branch.at / total;
    secondary.tangent = tangent;
    secondary.outward = branch.side == 0 ? Left(tangent) : Eigen::Vector2d(-Left(tangent));
    secondaries.push_back(secondary);
  }
  return secondaries;
}

void Grower::GrowSecondary(Secondary& secondary)
{
  const auto& nodes = this->Graph.Nodes();
  const VenationPattern pattern = this->SecondaryPattern();
  const double w = this->Width;
  const double sMax = 4.0 * w + this->Length;
  const bool forks = pattern != VenationPattern::Craspedodromous;
  const double forkAt = pattern == VenationPattern::Reticulodromous ? 0.5 : this->P.forkFraction;
  const double theta = this->P.divergenceAngle + (this->P.divergenceAngleApex - this->P.divergenceAngle) * secondary.v;
  const double slope = 1.0 / std::tan(theta * Pi / 180.0);
  const double k = this->P.curvatureBase + (this->P.curvatureApex - this->P.curvatureBase) * secondary.v;
  const Eigen::Vector2d origin = nodes[secondary.node];
  // Its reach: the lateral distance to the margin along the straight line at the divergence angle. The arch of
  // eq. (2) rises k*s^2/(10*reach) on top of that line: it turns towards the apex by a bounded angle (at the
  // margin its slope is cot(theta) + k/5) however wide the blade, so it runs out to the margin instead of
  // bending up along the midvein where the blade is wide (the printed k*w*(s/w)^2 starts perpendicular).
  double reach = this->Step;
  for (double s = this->Step; s <= sMax && this->Inside(origin + s * (secondary.outward + slope * secondary.tangent));
       s += this->Step)
    reach = s;
  double bend = k;
  auto at = [&](double s) {
    return Eigen::Vector2d(
      origin + s * secondary.outward + (s * slope + bend * s * s / (10.0 * reach)) * secondary.tangent);
  };
  // A palmate primary's secondary only where it has room: none where the neighbouring primary (or the margin)
  // lies within half a spacing along its start (between diverging primaries near the base, at a lobe's tip).
  if (this->P.pattern == VenationPattern::Palmate &&
    this->Graph.FirstCrossing(secondary.node, at(0.5 * this->P.secondarySpacing * this->Length), 0.0) <= 1.0)
    return;
  // It forks where it has come forkAt of the way across the half-blade at its height: where the margin lies
  // within (1 - forkAt)/forkAt of its distance from the midvein, straight on outwards (brochidodromous loops
  // then run in the outer part of the half-blade however wide it is). An arch that would leave the blade (through
  // the apex side, on a blade wide near its apex) before it gets there is bent less, by half up to three times;
  // failing that it forks at forkAt of its way out. Reticulodromous veins stop halfway along their way out.
  const bool across = forks && pattern != VenationPattern::Reticulodromous;
  double exit = 0.0, forkS = sMax;
  for (int attempt = 0; attempt < 4; ++attempt, bend *= 0.5)
  {
    exit = 0.0;
    for (double s = this->Step; s <= sMax && this->Inside(at(s)); s += this->Step)
      exit = s;
    forkS = forks ? forkAt * exit : sMax;
    bool found = false;
    for (double s = this->Step; across && s < exit && !found; s += this->Step)
    {
      found = !this->Inside(at(s) + s * (1.0 - forkAt) / forkAt * secondary.outward);
      if (found)
        forkS = s;
    }
    if (found || !across || bend == 0.0)
      break;
  }
  secondary.exit = exit;
  const int vein = this->Graph.AddVein(VeinOrderSecondary);
  const int toFork = std::max(1, static_cast<int>(std::ceil(forkS / this->Step)));
  const double ds = forks ? std::max(forkS, 1e-12 * this->Length) / toFork : this->Step;
  // A short first piece, so the vein leaves the midvein at the divergence angle itself rather than along the
  // chord of a curved step.
  std::vector<Eigen::Vector2d> first = { at(std::min(0.125 * ds, 0.01 * reach)) };
  for (int j = 1; j <= toFork && (forks || j * ds <= sMax); ++j)
    first.push_back(at(j * ds));
  if (!forks)
  {
    for (double s = (toFork + 1) * ds; s <= sMax + ds; s += ds)
      first.push_back(at(s));
  }
  VeinGraph::Step step = this->GrowCurve(secondary.node, first, vein, 1e-7 * this->Length);
  if (step.stopped || !forks)
    return; // met the margin or a vein
  secondary.fork = step.node;
  const bool continues = pattern == VenationPattern::Semicraspedodromous || pattern == VenationPattern::Cladodromous;
  if (continues)
  {
    std::vector<Eigen::Vector2d> rest;
    for (double s = (toFork + 1) * ds; s <= sMax + ds; s += ds)
      rest.push_back(at(s));
    this->GrowCurve(step.node, rest, vein, 1e-7 * this->Length);
  }
  if (pattern == VenationPattern::Cladodromous)
  {
    // Eq. (3): the branch turns towards the base, y = y_f - c*sqrt(w*x), to the margin.
    const Eigen::Vector2d fork = nodes[secondary.fork];
    std::vector<Eigen::Vector2d> branch;
    for (double x = this->Step; x <= sMax; x += this->Step)
      branch.push_back(fork + x * secondary.outward - this->P.branchCurvature * std::sqrt(w * x) * secondary.tangent);
    this->GrowCurve(secondary.fork, branch, this->Graph.AddVein(VeinOrderSecondary), 1e-7 * this->Length);
  }
}

void Grower::GrowSecondaryLoops(const std::vector<Secondary>& secondaries)
{
  const auto& nodes = this->Graph.Nodes();
  const VenationPattern pattern = this->SecondaryPattern();
  const bool loops = pattern == VenationPattern::Brochidodromous || pattern == VenationPattern::Semicraspedodromous ||
    pattern == VenationPattern::Eucamptodromous;
  for (int side = 0; side < 2 && loops; ++side)
  {
    std::vector<const Secondary*> list;
    for (const Secondary& s : secondaries)
    {
      if (s.side == side)
        list.push_back(&s);
    }
    // Each primary's own, in order along it.
    std::stable_sort(
      list.begin(), list.end(), [](const Secondary* a, const Secondary* b) { return a->host < b->host; });
    for (std::size_t i = 0; i < list.size(); ++i)
    {
      const Secondary& low = *list[i];
      if (low.fork < 0)
        continue;
      const Eigen::Vector2d from = nodes[low.fork];
      const Secondary* high = nullptr;
      for (std::size_t j = i + 1; j < list.size() && !high && list[j]->host == low.host; ++j)
        high = list[j]->fork >= 0 ? list[j] : nullptr;
      if (!high)
      {
        // The topmost: on to the margin (brochidodromous) as the paper's last arch does.
        if (pattern == VenationPattern::Brochidodromous)
        {
          std::vector<Eigen::Vector2d> rest;
          for (double t = this->Step; t <= 4.0 * this->Length; t += this->Step)
            rest.push_back(from + t * (low.tangent + 0.3 * low.outward).normalized());
          this->GrowCurve(low.fork, rest, this->Graph.AddVein(VeinOrderSecondary), 1e-7 * this->Length);
        }
        continue;
      }
      const Eigen::Vector2d to = nodes[high->fork];
      const Eigen::Vector2d d = to - from;
      const double dy = d.dot(low.tangent), dx = d.dot(low.outward);
      const int pieces = std::max(4, static_cast<int>(std::ceil(d.norm() / this->Step)));
      const bool free = pattern == VenationPattern::Eucamptodromous;
      // Brochidodromous loops arch out towards the margin: the chord between the forks plus an outward bulge,
      // sin(pi t) along it, of half the room left between the chord's middle and the margin (at most 0.3 of the
      // chord), so each loop runs in the outer part of the half-blade (eq. (4)'s cubic stays inside the chord
      // and, where the blade widens, bends in towards the midvein).
      double bulge = 0.0;
      if (pattern == VenationPattern::Brochidodromous)
      {
        const Eigen::Vector2d middle = from + 0.5 * d;
        double room = 0.0;
        for (double s = this->Step; s <= this->Width && this->Inside(middle + s * low.outward); s += this->Step)
          room = s;
        bulge = std::min(0.5 * room, 0.3 * d.norm());
      }
      std::vector<Eigen::Vector2d> curve;
      for (int j = 1; j <= (free ? pieces / 2 : pieces); ++j)
      {
        const double t = static_cast<double>(j) / pieces;
        if (pattern == VenationPattern::Brochidodromous)
          curve.push_back(from + t * d + bulge * std::sin(Pi * t) * low.outward);
        else
          curve.push_back(from + t * dy * low.tangent + t * t * t * dx * low.outward);
      }
      const int loopVein = this->Graph.AddVein(VeinOrderSecondary);
      if (free)
        this->GrowCurve(low.fork, curve, loopVein, 1e-7 * this->Length);
      else
      {
        curve.pop_back(); // the last point is the upper fork itself: joined to its node, not a copy of it
        const VeinGraph::Step step = this->GrowCurve(low.fork, curve, loopVein, 1e-7 * this->Length);
        if (!step.stopped)
          this->Graph.Connect(step.node, high->fork, loopVein, 1e-7 * this->Length);
      }
    }
  }
}

void Grower::BuildPrimaryDistance()
{
  const Eigen::Vector2d low = this->Locator.Lower(), extent = this->Locator.Upper() - low;
  this->DistanceCells = 96;
  this->DistanceCell = std::max(extent.x(), extent.y()) / this->DistanceCells;
  const int n = this->DistanceCells;
  this->PrimaryDistance.assign(static_cast<std::size_t>(n) * n, 0.0);
  this->DistanceFar = 0.0;
  const auto& nodes = this->Graph.Nodes();
  std::vector<std::array<Eigen::Vector2d, 2>> primaries;
  for (const VeinGraph::Edge& edge : this->Graph.Edges())
  {
    if (this->Graph.Order(edge.vein) == VeinOrderPrimary)
      primaries.push_back({ nodes[edge.a], nodes[edge.b] });
  }
  for (int y = 0; y < n; ++y)
  {
    for (int x = 0; x < n; ++x)
    {
      const Eigen::Vector2d c = low + this->DistanceCell * Eigen::Vector2d(x + 0.5, y + 0.5);
      double best = std::numeric_limits<double>::max();
      for (const auto& [a, b] : primaries)
        best = std::min(best, (ClosestOnSegment(c, a, b) - c).norm());
      this->PrimaryDistance[static_cast<std::size_t>(y) * n + x] = best;
      if (this->Inside(c))
        this->DistanceFar = std::max(this->DistanceFar, best);
    }
  }
}

double Grower::AreoleScale(const Eigen::Vector2d& x) const
{
  const double g = this->P.areoleGradient;
  if (g == 0.0 || this->PrimaryDistance.empty() || !(this->DistanceFar > 0.0))
    return 1.0;
  const int n = this->DistanceCells;
  const Eigen::Vector2d r = (x - this->Locator.Lower()) / this->DistanceCell;
  const int cx = std::clamp(static_cast<int>(r.x()), 0, n - 1), cy = std::clamp(static_cast<int>(r.y()), 0, n - 1);
  const double d = this->PrimaryDistance[static_cast<std::size_t>(cy) * n + cx];
  return 1.0 + g * (1.0 - 2.0 * std::min(1.0, d / this->DistanceFar));
}

std::string Grower::GrowTertiaries()
{
  RandomStream random(this->P.seed, StreamTertiary);
  const double areole = this->P.areoleSize * this->Length;
  // The shortest tertiary edges set the count (a hierarchical reticulum's are 1 - areoleGradient of the size).
  const double shortest = areole * (1.0 - this->P.areoleGradient);
  const double expected = this->Locator.Area() / (shortest * shortest);
  if (3.0 * expected > static_cast<double>(this->P.maxSegments))
  {
    std::ostringstream message;
    message << "AreoleSize = " << this->P.areoleSize << " would need about " << static_cast<long long>(3.0 * expected)
            << " vein segments, more than MaxSegments = " << this->P.maxSegments << "; raise AreoleSize";
    return message.str();
  }
  const std::size_t budget =
    std::min<std::size_t>(this->P.maxSegments, static_cast<std::size_t>(40.0 * expected) + 100);
  this->Snap = 0.15 * areole;
  if (this->P.areoleGradient > 0.0)
    this->BuildPrimaryDistance();

  struct Front
  {
    int node;
    Eigen::Vector2d direction;
    int vein;
  };
  std::deque<Front> fronts;

  // Seeds on the secondaries (on the primaries when there are none, and always on fanned palmate ones: a lobe
  // whose primary has no room for secondaries is not left bare; paper 000's palmate construction, which the
  // Cucumber wilting preset was fitted on, keeps its seeds), every three areoles, alternate sides.
  std::vector<int> hosts; // every secondary (loops and branches too), or every primary when there are none
  for (int order : { VeinOrderSecondary, VeinOrderPrimary })
  {
    for (std::size_t v = 0; v < this->Graph.Veins().size(); ++v)
    {
      if (this->Graph.Order(static_cast<int>(v)) == order)
        hosts.push_back(static_cast<int>(v));
    }
    if (!hosts.empty() && !(this->P.pattern == VenationPattern::Palmate && this->P.palmateFan))
      break;
  }
  const std::vector<std::vector<int>> paths = this->Graph.VeinPaths();
  for (int host : hosts)
  {
    std::vector<int> path = paths[host];
    const auto& nodes = this->Graph.Nodes();
    double carried = areole * random.Uniform(0.5, 1.5);
    for (std::size_t i = 0; i + 1 < path.size(); ++i)
    {
      const Eigen::Vector2d a = nodes[path[i]], b = nodes[path[i + 1]];
      const double piece = (b - a).norm();
      if (carried >= piece || piece <= 0.0)
      {
        carried -= piece;
        continue;
      }
      const Eigen::Vector2d along = (b - a) / piece;
      const Eigen::Vector2d x = a + carried * along;
      const double scale = this->AreoleScale(x);
      const int edge = this->Graph.FindEdge(path[i], path[i + 1]);
      if (edge < 0)
        break;
      const int node = this->Graph.SplitEdge(edge, x);
      path.insert(path.begin() + static_cast<std::ptrdiff_t>(i) + 1, node);
      carried = areole * random.Uniform(1.0, 2.0) * scale;
      // A first edge to each side, away from the vein.
      for (const Eigen::Vector2d& normal : { Left(along), Eigen::Vector2d(-Left(along)) })
      {
        const Eigen::Vector2d direction = Rotate(normal, random.Uniform(-20.0, 20.0));
        const int vein = this->Graph.AddVein(VeinOrderTertiary);
        const VeinGraph::Step step = this->Graph.Grow(
          node, this->Graph.Nodes()[node] + areole * random.Uniform(0.6, 1.4) * scale * direction, vein, this->Snap);
        if (!step.stopped)
          fronts.push_back({ step.node, direction, vein });
      }
    }
  }

  std::size_t grown = 0;
  const double minimum = this->P.minJunctionAngle;
  while (!fronts.empty() && grown < budget)
  {
    const Front front = fronts.front();
    fronts.pop_front();
    // Junction: the incoming edge (reversed) and two new edges, angles alpha, beta, gamma around the node.
    double alpha = 120.0, beta = 120.0;
    for (int attempt = 0; attempt < 32; ++attempt)
    {
      const double a = random.Normal(120.0, this->P.junctionAngleDeviation);
      const double b = random.Normal(120.0, this->P.junctionAngleDeviation);
      if (a >= minimum && b >= minimum && 360.0 - a - b >= minimum)
      {
        alpha = a;
        beta = b;
        break;
      }
    }
    const Eigen::Vector2d back = -front.direction;
    const Eigen::Vector2d first = Rotate(back, alpha), second = Rotate(back, alpha + beta);
    this->JunctionAngles.push_back(alpha);
    this->JunctionAngles.push_back(beta);
    this->JunctionAngles.push_back(360.0 - alpha - beta);
    const Eigen::Vector2d origin = this->Graph.Nodes()[front.node];
    const double scale = this->AreoleScale(origin);
    for (int branch = 0; branch < 2; ++branch)
    {
      const Eigen::Vector2d direction = branch == 0 ? first : second;
      const int vein = branch == 0 ? front.vein : this->Graph.AddVein(VeinOrderTertiary);
      const VeinGraph::Step step =
        this->Graph.Grow(front.node, origin + areole * random.Uniform(0.6, 1.4) * scale * direction, vein, this->Snap);
      ++grown;
      if (!step.stopped)
        fronts.push_back({ step.node, direction, vein });
    }
    if (grown % 4096 == 0 && !this->KeepGoing(0.4 + 0.4 * std::min(1.0, grown / (3.0 * expected))))
      return "aborted";
  }
  // Out of budget: every remaining front runs straight on until it meets a vein or the margin.
  const double reach = 2.0 * (this->Locator.Upper() - this->Locator.Lower()).norm();
  for (const Front& front : fronts)
    this->Graph.Grow(front.node, this->Graph.Nodes()[front.node] + reach * front.direction, front.vein, this->Snap);
  return {};
}

void Grower::GrowVeinlets()
{
  RandomStream random(this->P.seed, StreamVeinlet);
  const double length = this->P.veinletLength * this->P.areoleSize * this->Length;
  const std::vector<VeinGraph::Face> faces = this->Graph.Faces();
  for (const VeinGraph::Face& face : faces)
  {
    if (face.touchesMargin || face.area < 4.0 * length * length || face.nodes.size() < 3)
      continue;
    const std::size_t i = static_cast<std::size_t>(random.Integer(0, static_cast<std::int64_t>(face.nodes.size()) - 1));
    const int a = face.nodes[i], b = face.nodes[(i + 1) % face.nodes.size()];
    const int edge = this->Graph.FindEdge(a, b);
    if (edge < 0)
      continue;
    const Eigen::Vector2d pa = this->Graph.Nodes()[a], pb = this->Graph.Nodes()[b];
    if ((pb - pa).norm() < 0.5 * length)
      continue;
    int node = this->Graph.SplitEdge(edge, 0.5 * (pa + pb));
    Eigen::Vector2d direction = Left((pb - pa).normalized()); // the face lies on the left of its CCW edges
    const int vein = this->Graph.AddVein(VeinOrderVeinlet);
    const int pieces = static_cast<int>(random.Integer(1, 3));
    for (int k = 0; k < pieces; ++k)
    {
      const Eigen::Vector2d target = this->Graph.Nodes()[node] + length * random.Uniform(0.6, 1.0) * direction;
      if (this->Graph.FirstCrossing(node, target, 0.25 * length) <= 1.0)
        break; // a veinlet ends free, short of anything
      node = this->Graph.Grow(node, target, vein, 0.0).node;
      direction = Rotate(direction, random.Normal(0.0, 25.0));
    }
  }
}

void Grower::GrowPalmate()
{
  // End points on the blade's margin, fanned over its angular extent seen from the base, one group per primary
  // (PalmateFan.h: lobe tips, basal lobes of cordate blades, an even spread on entire blades).
  // Without the fan (paper 000): evenly along the canonical leaf's far edge v = 1, grown in LeafUV.
  // A lobed blade's primaries run each to its lobe's tip undivided: dichotomous forks (ForkLevels) are the fan of an
  // entire blade (the ginkgo); forked, a lobe's vein would end on both sides of its tip and none at it.
  PalmateFanParameters settings;
  settings.primaries = this->P.palmateVeins;
  settings.levels = this->P.forkLevels;
  PalmateFan fan = this->P.palmateFan
    ? FindPalmateFan(this->Blade, this->Locator, this->Base, this->Axis, this->Length, settings)
    : PalmateFan{};
  if (!fan.lobeTips.empty() && settings.levels > 0)
  {
    settings.levels = 0;
    fan = FindPalmateFan(this->Blade, this->Locator, this->Base, this->Axis, this->Length, settings);
  }
  const int levels = settings.levels;
  const int groups = this->P.palmateFan ? static_cast<int>(fan.ends.size()) : this->P.palmateVeins;
  const int count = groups << levels;
  std::vector<Eigen::Vector2d> ends(count), endsUV(count);
  for (int j = 0; j < count && !this->P.palmateFan; ++j)
    ends[j] = endsUV[j] = Eigen::Vector2d(-0.5 + (j + 0.5) / count, 1.0);
  for (int r = 0; r < groups && this->P.palmateFan; ++r)
  {
    for (int j = 0; j < (1 << levels); ++j)
    {
      const Eigen::Vector2d x = fan.ends[r][j];
      ends[(r << levels) + j] = x;
      BladeLocation at = this->Locator.Locate(x, 1e-7 * this->Length);
      if (at.triangle < 0)
        at = this->Locator.Locate(x, 1e-3 * this->Length);
      endsUV[(r << levels) + j] =
        at.triangle >= 0 ? this->Locator.Interpolate(this->Blade.uv, at) : Eigen::Vector2d(0.0, 1.0);
    }
  }
  // Fork growth fractions: level d forks at forkTime[d].
  std::vector<double> forkTime(levels + 2, 1.0);
  forkTime[0] = 0.0;
  // Paper 000: evenly after the first. With the fan, geometrically from forkSize towards full size (forkSize^(1 -
  // (d - 1)/levels)): most dichotomies in the lower part of the blade, so the veins spread over the whole width
  // early and the outermost follow the flanks (the ginkgo's lower flanks are not left bare).
  for (int d = 1; d <= levels; ++d)
    forkTime[d] = this->P.palmateFan ? std::pow(this->P.forkSize, 1.0 - static_cast<double>(d - 1) / levels)
                                     : this->P.forkSize + (d - 1) * (1.0 - this->P.forkSize) / levels;
  // The path of an end point through the growing leaf: the leaf grows about its base, P(g) = B + g*(p(g) - B),
  // where that stays inside the blade (a blade star-shaped from its base: straight primaries); otherwise it grows
  // in LeafUV, P(g) = F(g*p(g)) (F: LeafUV to the blade), which never leaves it (a cusp-like base, basal lobes).
  bool plane = this->P.palmateFan;
  const std::vector<Eigen::Vector2d>* space = &ends;
  auto mean = [&](int first, int size) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int j = first; j < first + size; ++j)
      sum += (*space)[j];
    return Eigen::Vector2d(sum / size);
  };
  // The parameter of the group [first, first + size) at depth d and growth g.
  std::function<Eigen::Vector2d(int, int, int, double)> parameter = [&](int d, int first, int size, double g) {
    if (d == 0)
      return mean(first, size);
    const int parentSize = 2 * size;
    const int parentFirst = (first / parentSize) * parentSize;
    const Eigen::Vector2d parent = parameter(d - 1, parentFirst, parentSize, g);
    if (g <= forkTime[d])
      return parent;
    // The two branches move linearly apart: over the rest of the growth in paper 000's construction; with the
    // fan, by the next fork (the last level: by full size), so at every stage the veins are spread evenly over
    // the fan rather than bunched until the leaf is full grown (a ginkgo's dozens of nearly parallel veins).
    const double until = this->P.palmateFan ? forkTime[d + 1] : 1.0;
    const double f = std::min(1.0, (g - forkTime[d]) / (until - forkTime[d]));
    return Eigen::Vector2d(parent + f * (mean(first, size) - mean(parentFirst, parentSize)));
  };
  // In LeafUV the path arches up by g*(1 - g)*(1 - v)/4 in v: an end on the base edge v = 0 (a cordate blade's
  // basal lobe) is reached through the blade rather than along its margin. With the fan its u grows as
  // sqrt(g) u_end (the same law for every vein, so their order across the blade is kept): a vein takes its share
  // of the width early, so the outer veins of a fan run along its flanks (a ginkgo's marginal veins) instead of up
  // the middle. Paper 000's construction (no fan) keeps u = g u_end: the Cucumber wilting preset was fitted on it.
  // Dichotomous veins (fork levels) reach their full u by the first fork, sqrt(g / forkSize), and then run along
  // the blade's curves u = constant between forks: in LeafUV a tree of nearly parallel veins filling the whole
  // width, so on a fan (the ginkgo) the outermost run down its flanks rather than leaving them bare.
  const bool fanned = this->P.palmateFan;
  const double spread = levels > 0 ? forkTime[1] : 1.0;
  // Dichotomous veins grown in LeafUV take their u evenly spread in the ends' order, so no two share one (the ends
  // on a flank all have u = +-0.5 and would run along one curve), and move to the end's own u over the last
  // stretch so each still ends on its margin point.
  std::vector<Eigen::Vector2d> evenUV = endsUV;
  const double direction = count > 1 && endsUV.back().x() < endsUV.front().x() ? -1.0 : 1.0;
  for (int j = 0; j < count && fanned && levels > 0; ++j)
    evenUV[j].x() = direction * (-0.5 + (j + 0.5) / count);
  auto at = [&](int d, int first, int size, double g) {
    Eigen::Vector2d p = parameter(d, first, size, g);
    if (plane)
      return Eigen::Vector2d(this->Base + g * (p - this->Base));
    if (fanned && levels > 0 && d == levels)
      p.x() += (g - forkTime[levels]) / (1.0 - forkTime[levels]) * (endsUV[first].x() - evenUV[first].x());
    // (An end on a flank, u = +-0.5, is approached from just inside, so the vein does not run on the margin.)
    const double across = fanned ? std::sqrt(std::min(1.0, g / spread)) * (1.0 - (1.0 - g) / (4.0 * count)) : g;
    return this->Locator.PointAtUV(Eigen::Vector2d(across * p.x(), g * p.y() + 0.25 * g * (1.0 - g) * (1.0 - p.y())));
  };
  auto pieces = [&](int d) {
    const double g0 = forkTime[d], g1 = d == levels ? 1.0 : forkTime[d + 1];
    return std::max(2, static_cast<int>(std::ceil(2.0 * (g1 - g0) * this->Length / this->Step)));
  };
  // Straight paths only if every one stays inside the blade (all or none, so paths of both kinds never cross).
  // An unforked vein whose ray from the base leaves the blade (a fitted scan's notch beside the petiole, a lobe
  // behind a deep sinus, a basal lobe behind the base) may instead branch off a neighbour's ray, the one nearer the
  // axis first, at the first of 40 points along it (every 0.02 of it) from which the straight segment to its end
  // stays inside: `branch[j]` is that neighbour, `from[j]` the point. Only if some vein can do neither do all grow
  // in LeafUV (a fitted blade's LeafUV near the base is too narrow for them: they stopped at the margin there).
  auto inside = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const int n = std::max(2, static_cast<int>(std::ceil(2.0 * (b - a).norm() / this->Step)));
    for (int k = 1; k <= n; ++k)
    {
      if (this->Locator.Locate(a + std::min(static_cast<double>(k) / n, 1.0 - 1e-6) * (b - a), 1e-6 * this->Length)
            .triangle < 0)
        return false;
    }
    return true;
  };
  std::vector<int> branch(count, -1);
  std::vector<Eigen::Vector2d> from(count, this->Base);
  std::vector<char> straight(count, 1);
  for (int j = 0; j < count && plane; ++j)
  {
    for (int d = 0; d <= levels && plane; ++d)
    {
      const int size = 1 << (levels - d), first = (j / size) * size;
      const double g0 = forkTime[d], g1 = d == levels ? 1.0 : forkTime[d + 1];
      const int n = pieces(d);
      for (int k = 1; k <= n && straight[j]; ++k)
      {
        const double g = std::min(g0 + (g1 - g0) * k / n, 1.0 - 1e-6);
        straight[j] = this->Locator.Locate(at(d, first, size, g), 1e-6 * this->Length).triangle >= 0;
      }
      plane = straight[j] || levels == 0;
    }
  }
  for (int j = 0; j < count && plane; ++j)
  {
    if (straight[j])
      continue;
    // Its neighbours in the ends' order (right to left), the one nearer the axis first.
    const int axisward = Left(this->Axis).dot(ends[j] - this->Base) < 0.0 ? j + 1 : j - 1;
    for (int o : { axisward, 2 * j - axisward })
    {
      if (o < 0 || o >= count || !straight[o])
        continue;
      for (int k = 1; k <= 40 && branch[j] < 0; ++k)
      {
        const Eigen::Vector2d q = this->Base + (0.02 * k) * (ends[o] - this->Base);
        if (inside(q, ends[j]))
        {
          branch[j] = o;
          from[j] = q;
        }
      }
    }
    plane = branch[j] >= 0;
  }
  if (!plane)
    space = fanned && levels > 0 ? &evenUV : &endsUV;
  std::function<void(int, int, int, int)> grow = [&](int d, int first, int size, int from) {
    const double g0 = forkTime[d], g1 = d == levels ? 1.0 : forkTime[d + 1];
    const int n = pieces(d);
    std::vector<Eigen::Vector2d> points;
    for (int k = 1; k <= n; ++k)
      points.push_back(at(d, first, size, g0 + (g1 - g0) * k / n));
    const int vein = this->Graph.AddVein(d == 0 ? VeinOrderPrimary : VeinOrderSecondary);
    if (d == 0)
      this->PrimaryVeins.push_back(vein);
    const VeinGraph::Step step = this->GrowCurve(from, points, vein, 1e-7 * this->Length);
    if (d == levels || (step.stopped && step.hitVein == 0))
      return;
    grow(d + 1, first, size / 2, step.node);
    grow(d + 1, first + size / 2, size / 2, step.node);
  };
  for (int r = 0; r < groups; ++r)
  {
    if (!plane || straight[r << levels])
      grow(0, r << levels, 1 << levels, this->BaseNode);
  }
  for (int r = 0; r < count && plane && levels == 0; ++r)
  {
    if (straight[r])
      continue;
    const int n = std::max(2, static_cast<int>(std::ceil(2.0 * (ends[r] - from[r]).norm() / this->Step)));
    std::vector<Eigen::Vector2d> points;
    for (int k = 1; k <= n; ++k)
      points.push_back(from[r] + (static_cast<double>(k) / n) * (ends[r] - from[r]));
    const int vein = this->Graph.AddVein(VeinOrderPrimary);
    this->PrimaryVeins.push_back(vein);
    this->GrowCurve(this->NodeAt(from[r]), points, vein, 1e-7 * this->Length);
  }
}

void Grower::GrowFlankSecondaries()
{
  const double L = this->Length, reach = this->P.secondarySpacing * L;
  // Sample points over the blade (a 64 x 64 grid over its box, those inside).
  const Eigen::Vector2d low = this->Locator.Lower(), extent = this->Locator.Upper() - low;
  std::vector<Eigen::Vector2d> samples;
  for (int y = 0; y < 64; ++y)
  {
    for (int x = 0; x < 64; ++x)
    {
      const Eigen::Vector2d point = low + Eigen::Vector2d((x + 0.5) / 64 * extent.x(), (y + 0.5) / 64 * extent.y());
      if (this->Inside(point))
        samples.push_back(point);
    }
  }
  // Each sample's distance to the nearest primary or secondary edge, brought up to date with the edges added
  // since (splitting an edge keeps its geometry, so older distances stay right).
  const auto& nodes = this->Graph.Nodes();
  const auto& edges = this->Graph.Edges();
  std::vector<double> distance(samples.size(), std::numeric_limits<double>::infinity());
  auto nearest = [&](const Eigen::Vector2d& point, std::size_t from, double& best, int& bestEdge,
                   Eigen::Vector2d& bestFoot) {
    for (std::size_t e = from; e < edges.size(); ++e)
    {
      const int order = this->Graph.Order(edges[e].vein);
      if (order != VeinOrderPrimary && order != VeinOrderSecondary)
        continue;
      const Eigen::Vector2d foot = ClosestOnSegment(point, nodes[edges[e].a], nodes[edges[e].b]);
      const double r = (foot - point).norm();
      if (r < best)
      {
        best = r;
        bestEdge = static_cast<int>(e);
        bestFoot = foot;
      }
    }
  };
  std::size_t seen = 0;
  for (int added = 0; added < 8; ++added)
  {
    double farthest = 0.0;
    std::size_t far = samples.size();
    for (std::size_t i = 0; i < samples.size(); ++i)
    {
      int edge = -1;
      Eigen::Vector2d foot;
      nearest(samples[i], seen, distance[i], edge, foot);
      if (std::isfinite(distance[i]) && distance[i] > farthest)
      {
        farthest = distance[i];
        far = i;
      }
    }
    seen = edges.size();
    if (far == samples.size() || farthest <= reach)
      return;
    // The farthest sample's foot on its nearest vein, found afresh (a node there, or an end of the edge within
    // 1e-9 L), then straight through the sample to the margin.
    const Eigen::Vector2d target = samples[far];
    double best = std::numeric_limits<double>::infinity();
    int edgeAt = -1;
    Eigen::Vector2d foot = target;
    nearest(target, 0, best, edgeAt, foot);
    const VeinGraph::Edge edge = edges[edgeAt];
    int from = edge.a;
    if ((foot - nodes[edge.b]).norm() <= 1e-9 * L)
      from = edge.b;
    else if ((foot - nodes[edge.a]).norm() > 1e-9 * L)
      from = this->Graph.SplitEdge(edgeAt, foot);
    const Eigen::Vector2d origin = nodes[from], direction = (target - origin).normalized();
    std::vector<Eigen::Vector2d> line;
    for (double step = this->Step; step <= 4.0 * L; step += this->Step)
      line.push_back(origin + step * direction);
    this->GrowCurve(from, line, this->Graph.AddVein(VeinOrderSecondary), 1e-7 * L);
  }
}

int Grower::SplitPathAt(std::vector<int>& path, double at)
{
  const auto& nodes = this->Graph.Nodes();
  double start = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
  {
    const Eigen::Vector2d a = nodes[path[i]], b = nodes[path[i + 1]];
    const double piece = (b - a).norm();
    if (start + piece < at && i + 2 < path.size())
    {
      start += piece;
      continue;
    }
    const double t = std::clamp(at - start, 0.0, piece);
    if (t <= 1e-9 * this->Length)
      return path[i];
    if (piece - t <= 1e-9 * this->Length)
      return path[i + 1];
    const int node = this->Graph.SplitEdge(this->Graph.FindEdge(path[i], path[i + 1]), a + t / piece * (b - a));
    path.insert(path.begin() + static_cast<std::ptrdiff_t>(i) + 1, node);
    return node;
  }
  return path.back();
}

void Grower::GrowSubLobeVeins(std::vector<std::vector<int>>& hosts)
{
  if (this->Locator.BoundaryLoops().empty())
    return;
  const std::vector<int>& loop = this->Locator.BoundaryLoops().front();
  const std::size_t n = loop.size();
  const double L = this->Length;
  // The distance of every boundary vertex to the nearest primary: which host, and the arc length of its foot.
  std::vector<double> d(n, std::numeric_limits<double>::infinity()), footAt(n, 0.0);
  std::vector<int> nearest(n, -1);
  std::vector<Eigen::Vector2d> foot(n, Eigen::Vector2d::Zero());
  for (std::size_t h = 0; h < hosts.size(); ++h)
  {
    const auto& nodes = this->Graph.Nodes();
    double along = 0.0;
    for (std::size_t k = 0; k + 1 < hosts[h].size(); ++k)
    {
      const Eigen::Vector2d a = nodes[hosts[h][k]], b = nodes[hosts[h][k + 1]];
      const double piece = (b - a).norm();
      for (std::size_t i = 0; i < n && piece > 0.0; ++i)
      {
        const Eigen::Vector2d x = this->Blade.points[loop[i]];
        const double t = std::clamp((x - a).dot(b - a) / (piece * piece), 0.0, 1.0);
        const double distance = (a + t * (b - a) - x).norm();
        if (distance < d[i])
        {
          d[i] = distance;
          nearest[i] = static_cast<int>(h);
          footAt[i] = along + t * piece;
          foot[i] = a + t * (b - a);
        }
      }
      along += piece;
    }
  }
  // Concave (reflex) vertices of the counter-clockwise loop, judged over neighbours at least 0.01 L away.
  auto neighbour = [&](std::size_t i, int direction) {
    const Eigen::Vector2d x = this->Blade.points[loop[i]];
    std::size_t j = i;
    for (std::size_t step = 0; step < n; ++step)
    {
      j = (j + n + static_cast<std::size_t>(direction)) % n;
      if ((this->Blade.points[loop[j]] - x).norm() >= 0.01 * L)
        break;
    }
    return this->Blade.points[loop[j]];
  };
  std::vector<char> concave(n, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector2d x = this->Blade.points[loop[i]];
    const Eigen::Vector2d in = x - neighbour(i, -1), out = neighbour(i, 1) - x;
    concave[i] = in.x() * out.y() - in.y() * out.x() < 0.0;
  }
  const double prominence = 0.02 * L, end = 0.01 * L;
  // A sinus on the way from i in `direction`: the first concave vertex prominence lower before a higher d or a
  // primary's end, then the lowest d of its stretch of concave vertices (n if none).
  auto sinus = [&](std::size_t i, int direction) {
    std::size_t j = i;
    for (std::size_t step = 1; step < n; ++step)
    {
      j = (j + n + static_cast<std::size_t>(direction)) % n;
      if (d[j] > d[i] || d[j] < end)
        return n;
      if (concave[j] && d[i] - d[j] >= prominence)
      {
        // The sinus's bottom: the lowest d in this stretch of concave vertices.
        std::size_t bottom = j;
        for (std::size_t next = (j + n + static_cast<std::size_t>(direction)) % n; concave[next] && d[next] >= end;
             next = (next + n + static_cast<std::size_t>(direction)) % n)
          bottom = d[next] < d[bottom] ? next : bottom;
        return bottom;
      }
    }
    return n;
  };
  // The sub-lobe's tip: the vertex halfway (in length along the margin) between the bottoms of its two sinuses,
  // which must be at least 0.08 L apart along it.
  std::vector<std::size_t> tips;
  for (std::size_t i = 0; i < n; ++i)
  {
    const double before = d[(i + n - 1) % n], after = d[(i + 1) % n];
    if (nearest[i] < 0 || !(d[i] > before && d[i] >= after) || !(d[i] >= prominence + end))
      continue;
    const std::size_t low = sinus(i, -1), high = sinus(i, 1);
    if (low == n || high == n)
      continue;
    double half = 0.0;
    for (std::size_t k = low; k != high; k = (k + 1) % n)
      half += 0.5 * (this->Blade.points[loop[(k + 1) % n]] - this->Blade.points[loop[k]]).norm();
    if (2.0 * half < 0.08 * L)
      continue; // a notch where two lobes' margins cross, not a sub-lobe
    std::size_t tip = low;
    for (double along = 0.0; tip != high; tip = (tip + 1) % n)
    {
      const double piece = (this->Blade.points[loop[(tip + 1) % n]] - this->Blade.points[loop[tip]]).norm();
      if (along + 0.5 * piece >= half)
        break;
      along += piece;
    }
    if (std::find(tips.begin(), tips.end(), tip) == tips.end())
      tips.push_back(tip);
  }
  for (std::size_t i : tips)
  {
    std::vector<int>& path = hosts[nearest[i]];
    const double v = footAt[i] / std::max(footAt[i] + d[i], 1e-12 * L); // a rough height along the primary
    const double theta = this->P.divergenceAngle + (this->P.divergenceAngleApex - this->P.divergenceAngle) * v;
    const double back = 0.5 * d[i] / std::tan(theta * Pi / 180.0);
    const int from = this->SplitPathAt(path, std::max(footAt[i] - back, std::min(footAt[i], 0.02 * L)));
    const Eigen::Vector2d p0 = this->Graph.Nodes()[from], tip = this->Blade.points[loop[i]];
    const Eigen::Vector2d control = 0.5 * (foot[i] + tip);
    const int pieces = std::max(4, static_cast<int>(std::ceil((tip - p0).norm() / this->Step)));
    std::vector<Eigen::Vector2d> curve;
    for (int k = 1; k <= pieces; ++k)
    {
      const double t = static_cast<double>(k) / pieces;
      curve.push_back((1 - t) * (1 - t) * p0 + 2 * t * (1 - t) * control + t * t * tip);
    }
    curve.back() = tip;
    this->GrowCurve(from, curve, this->Graph.AddVein(VeinOrderSecondary), 1e-7 * L);
  }
}

std::string Grower::Run(VenationResult& result)
{
  // Leaf frame: base, apex, length along the midvein u = 0, width across the base-apex axis.
  this->Base = this->Locator.PointAtUV(Eigen::Vector2d(0.0, 0.0));
  this->Apex = this->Locator.PointAtUV(Eigen::Vector2d(0.0, 1.0));
  double length = 0.0;
  Eigen::Vector2d previous = this->Base;
  for (int k = 1; k <= 512; ++k)
  {
    const Eigen::Vector2d x = this->Locator.PointAtUV(Eigen::Vector2d(0.0, k / 512.0));
    length += (x - previous).norm();
    previous = x;
  }
  if (!(length > 0.0))
    return "LeafUV: the blade's midvein (u = 0 from v = 0 to 1) has no length";
  this->Length = length;
  this->Axis = (this->Apex - this->Base).norm() > 0.0 ? Eigen::Vector2d((this->Apex - this->Base).normalized())
                                                      : Eigen::Vector2d::UnitY();
  double low = 0.0, high = 0.0;
  for (const Eigen::Vector2d& x : this->Blade.points)
  {
    const double across = (x - this->Base).dot(Left(this->Axis));
    low = std::min(low, across);
    high = std::max(high, across);
  }
  this->Width = std::max(high - low, 1e-6 * length);
  this->Step = std::clamp(this->Locator.EdgeLength(), length / 400.0, length / 40.0);
  if (this->P.tertiary)
    this->Step = std::min(this->Step, 0.5 * this->P.areoleSize * length);

  this->AddMargin();
  this->BaseNode = this->NodeAt(this->Base);
  if (!this->KeepGoing(0.05))
    return "aborted";

  const VenationPattern pattern = this->P.pattern;
  if (pattern == VenationPattern::Palmate)
  {
    this->GrowPalmate();
    if (this->P.palmateSecondaries != PalmateSecondaries::None || this->P.subLobeVeins)
    {
      std::vector<std::vector<int>> paths = this->Graph.VeinPaths();
      this->OrientPrimariesFromTheBase(paths);
      std::vector<std::vector<int>> hosts;
      for (int vein : this->PrimaryVeins)
      {
        hosts.push_back(paths[vein]);
      }
      if (this->P.subLobeVeins)
        this->GrowSubLobeVeins(hosts);
      const std::string error =
        this->P.palmateSecondaries != PalmateSecondaries::None ? this->GrowSecondaries(hosts) : std::string();
      if (!error.empty())
        return error;
    }
  }
  else
  {
    std::vector<double> primaries = { 0.0 };
    if (pattern == VenationPattern::Arcuate || pattern == VenationPattern::Parallel)
    {
      primaries.clear();
      const bool parallel = pattern == VenationPattern::Parallel;
      const int n = parallel ? this->P.parallelVeins : this->P.primaries;
      const double spread = parallel ? this->P.parallelSpread : this->P.primarySpread;
      for (int i = 0; i < n; ++i)
        primaries.push_back(n == 1 ? 0.0 : spread * (2.0 * i / (n - 1) - 1.0));
      // The midvein (or the one nearest it) first, so the others join it rather than the reverse.
      std::stable_sort(
        primaries.begin(), primaries.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
    }
    for (double u : primaries)
    {
      const int vein = this->Graph.AddVein(VeinOrderPrimary);
      std::vector<int> path = this->TracePrimary(u, vein);
      if (u == 0.0)
        this->Midvein = path;
    }
    if (this->Midvein.size() < 2)
      return "LeafUV: no midvein could be traced along u = 0 (is LeafUV the canonical leaf's (u, v)?)";
    if (pattern != VenationPattern::Arcuate && pattern != VenationPattern::Parallel)
    {
      std::vector<std::vector<int>> hosts = { this->Midvein };
      const std::string error = this->GrowSecondaries(hosts);
      this->Midvein = hosts.front();
      if (!error.empty())
        return error;
      if (this->P.flankSecondaries)
        this->GrowFlankSecondaries();
    }
  }
  if (!this->KeepGoing(0.4))
    return "aborted";
  if (this->P.tertiary)
  {
    const std::string error = this->GrowTertiaries();
    if (!error.empty())
      return error;
  }
  if (!this->KeepGoing(0.85))
    return "aborted";
  if (this->P.veinlets && this->P.tertiary)
    this->GrowVeinlets();
  // True orders in the reticulum: tertiaries join primaries or secondaries, the rest subdivide areoles (order 4).
  const std::vector<int> orders = ReticulumOrders(this->Graph);
  for (std::size_t vein = 0; vein < orders.size(); ++vein)
    this->Graph.SetOrder(static_cast<int>(vein), orders[vein]);
  this->Finish(result);
  return {};
}

void Grower::Finish(VenationResult& result)
{
  result = VenationResult();
  result.leafLength = this->Length;
  result.junctionAngles = this->JunctionAngles;
  const auto& nodes = this->Graph.Nodes();
  std::vector<std::vector<int>> paths = this->Graph.VeinPaths();
  this->OrientPrimariesFromTheBase(paths);
  std::vector<int> id(nodes.size(), -1);
  const double widest = this->P.primaryWidth * this->Length;
  VenationStatistics& stats = result.statistics;
  for (std::size_t vein = 0; vein < paths.size(); ++vein)
  {
    const int order = this->Graph.Order(static_cast<int>(vein));
    if (order == VeinOrderMargin || paths[vein].size() < 2)
      continue;
    VenationResult::Polyline line;
    line.order = order;
    double total = 0.0;
    for (std::size_t i = 1; i < paths[vein].size(); ++i)
      total += (nodes[paths[vein][i]] - nodes[paths[vein][i - 1]]).norm();
    stats.length[order] += total;
    stats.segments += paths[vein].size() - 1;
    double along = 0.0;
    for (std::size_t i = 0; i < paths[vein].size(); ++i)
    {
      const int n = paths[vein][i];
      if (i > 0)
        along += (nodes[n] - nodes[paths[vein][i - 1]]).norm();
      const double f = total > 0.0 ? along / total : 0.0;
      double width = widest * this->P.veinletWidthRatio;
      if (order == VeinOrderPrimary)
        width = widest * (1.0 - (1.0 - this->P.primaryTaper) * f);
      else if (order == VeinOrderSecondary)
        width = widest * this->P.secondaryWidthRatio * (1.0 - 0.5 * f);
      else if (order == VeinOrderTertiary)
        width = widest * this->P.tertiaryWidthRatio;
      else if (order == VeinOrderQuaternary) // between the tertiaries and the veinlets, never wider than a tertiary
        width =
          widest * std::min(this->P.tertiaryWidthRatio, 0.5 * (this->P.tertiaryWidthRatio + this->P.veinletWidthRatio));
      if (id[n] < 0)
      {
        id[n] = static_cast<int>(result.nodes.size());
        result.nodes.push_back(nodes[n]);
        result.width.push_back(width);
        result.order.push_back(order);
      }
      else
      {
        result.width[id[n]] = std::max(result.width[id[n]], width);
        result.order[id[n]] = std::min(result.order[id[n]], order);
      }
      line.nodes.push_back(id[n]);
    }
    result.veins.push_back(line);
  }
  for (const Eigen::Vector2d& x : result.nodes)
  {
    BladeLocation at = this->Locator.Locate(x, 1e-7 * this->Length);
    if (at.triangle < 0)
      at = this->Locator.Locate(x, 1e-3 * this->Length);
    result.location.push_back(at);
  }
  stats.bladeArea = this->Locator.Area();
  double total = 0.0;
  for (int o = 1; o < VeinOrderCount; ++o)
    total += stats.length[o];
  stats.density = total / stats.bladeArea;
  const std::vector<int> degree = this->Graph.VeinDegrees();
  const std::vector<char> margin = this->Graph.OnMargin();
  for (std::size_t n = 0; n < nodes.size(); ++n)
  {
    stats.branchPoints += degree[n] >= 3;
    stats.freeEnds += degree[n] == 1 && !margin[n];
  }
  double sum = 0.0, sumSquares = 0.0;
  for (const VeinGraph::Face& face : this->Graph.Faces(false))
  {
    if (face.touchesMargin)
      continue;
    ++stats.areoles;
    sum += face.area;
    sumSquares += face.area * face.area;
  }
  if (stats.areoles > 0)
  {
    stats.areoleAreaMean = sum / stats.areoles;
    stats.areoleAreaStd =
      std::sqrt(std::max(0.0, sumSquares / stats.areoles - stats.areoleAreaMean * stats.areoleAreaMean));
  }
}

} // namespace

VenationParameters MakeVenationPreset(VenationPreset preset)
{
  VenationParameters p;
  switch (preset)
  {
    case VenationPreset::Custom:
      break;
    case VenationPreset::PaperMulberry:
      p.pattern = VenationPattern::Brochidodromous;
      p.divergenceAngle = 45.0;
      p.divergenceAngleApex = 70.0;
      p.secondarySpacing = 0.11;
      p.forkFraction = 0.75;
      p.tertiary = true;
      p.areoleSize = 0.045;
      p.flankSecondaries = true; // a broad blade's flanks below the lowest secondaries get their own
      break;
    case VenationPreset::Ginkgo:
      // Two veins enter from the petiole and fork dichotomously, five times, into 64 nearly parallel veins that
      // fan out to the whole margin (a real ginkgo leaf has some 40-60 at its margin).
      p.pattern = VenationPattern::Palmate;
      p.palmateVeins = 2;
      p.forkLevels = 5;
      p.forkSize = 0.08;
      p.tertiary = false;
      p.primaryWidth = 0.006;
      p.primaryTaper = 0.7;
      p.secondaryWidthRatio = 0.8;
      break;
    case VenationPreset::Poplar:
      p.pattern = VenationPattern::Semicraspedodromous;
      p.divergenceAngle = 50.0;
      p.divergenceAngleApex = 60.0;
      p.secondarySpacing = 0.12;
      p.forkFraction = 0.7;
      p.tertiary = true;
      p.areoleSize = 0.035;
      p.veinlets = true;
      break;
    case VenationPreset::Cucumber:
      // Cucumis sativus: palmate (actinodromous), five primaries from the petiole ending at the tips of the
      // shallow lobes and of the cordate blade's basal lobes; each sends craspedodromous secondaries out to the
      // (dentate) margin, and a hierarchical reticulum fills the rest: coarser beside the primaries, finer
      // towards the margin.
      p.pattern = VenationPattern::Palmate;
      p.palmateVeins = 5;
      p.forkLevels = 0;
      p.palmateSecondaries = PalmateSecondaries::Craspedodromous;
      p.secondarySpacing = 0.1;
      p.divergenceAngle = 50.0;
      p.divergenceAngleApex = 60.0;
      p.curvatureBase = 0.5;
      p.curvatureApex = 1.5;
      p.tertiary = true;
      p.areoleSize = 0.04;
      p.areoleGradient = 0.5;
      p.primaryWidth = 0.018;
      p.primaryTaper = 0.35;
      p.secondaryWidthRatio = 0.55;
      break;
    case VenationPreset::Tomato:
      // Solanum lycopersicum: the leaf is pinnately compound; the model grows one blade, so this is a leaflet's
      // venation (pinnate, secondaries at 50-65 deg looping inside the margin with branches to its teeth,
      // reticulate tertiaries and veinlets). Grow it on each leaflet.
      p.pattern = VenationPattern::Semicraspedodromous;
      p.divergenceAngle = 50.0;
      p.divergenceAngleApex = 65.0;
      p.secondarySpacing = 0.13;
      p.forkFraction = 0.75;
      p.tertiary = true;
      p.areoleSize = 0.04;
      p.veinlets = true;
      break;
    case VenationPreset::Watermelon:
      // Citrullus lanatus: palmately veined, the blade deeply cut into three to five lobes that are themselves
      // pinnately lobed: one primary to each lobe tip (PalmateFan's lobe tips), craspedodromous secondaries off
      // it out into the lobe's flanks (its sub-lobes), a fine hierarchical reticulum with veinlets.
      p.pattern = VenationPattern::Palmate;
      p.palmateVeins = 5;
      p.forkLevels = 0;
      p.palmateSecondaries = PalmateSecondaries::Craspedodromous;
      p.subLobeVeins = true; // a secondary to every sub-lobe's tip (none on a blade without sub-lobes)
      p.secondarySpacing = 0.08;
      p.divergenceAngle = 45.0;
      p.divergenceAngleApex = 55.0;
      p.curvatureBase = 0.5;
      p.curvatureApex = 1.5;
      p.tertiary = true;
      p.areoleSize = 0.03;
      p.areoleGradient = 0.35;
      p.veinlets = true;
      p.primaryWidth = 0.015;
      p.primaryTaper = 0.3;
      p.secondaryWidthRatio = 0.6;
      break;
  }
  return p;
}

std::string VenationPresetName(VenationPreset preset)
{
  static const char* const names[VenationPresetCount] = { "Custom", "PaperMulberry", "Ginkgo", "Poplar", "Cucumber",
    "Tomato", "Watermelon" };
  const int i = static_cast<int>(preset);
  return i >= 0 && i < VenationPresetCount ? names[i] : "Unknown";
}

std::string VenationPatternName(VenationPattern pattern)
{
  static const char* const names[VenationPatternCount] = { "Craspedodromous", "Semicraspedodromous", "Brochidodromous",
    "Eucamptodromous", "Reticulodromous", "Cladodromous", "Arcuate", "Parallel", "Palmate", "SpaceColonization" };
  const int i = static_cast<int>(pattern);
  return i >= 0 && i < VenationPatternCount ? names[i] : "Unknown";
}

std::string ValidateVenationParameters(const VenationParameters& p)
{
  auto in = [](double x, double low, double high) { return std::isfinite(x) && x >= low && x <= high; };
  const int pattern = static_cast<int>(p.pattern);
  if (pattern < 0 || pattern >= VenationPatternCount)
    return Range("Pattern", pattern, "[0, 9]");
  if (p.primaries < 1 || p.primaries > 51)
    return Range("PrimaryCount", p.primaries, "[1, 51]");
  if (!in(p.primarySpread, 0.0, 0.49))
    return Range("PrimarySpread", p.primarySpread, "[0, 0.49]");
  if (p.parallelVeins < 1 || p.parallelVeins > 101)
    return Range("ParallelVeins", p.parallelVeins, "[1, 101]");
  if (!in(p.parallelSpread, 0.0, 0.49))
    return Range("ParallelSpread", p.parallelSpread, "[0, 0.49]");
  if (!in(p.secondarySpacing, 0.005, 1.0))
    return Range("SecondarySpacing", p.secondarySpacing, "[0.005, 1] leaf lengths");
  if (!in(p.divergenceAngle, 5.0, 90.0))
    return Range("DivergenceAngle", p.divergenceAngle, "[5, 90] degrees");
  if (!in(p.divergenceAngleApex, 5.0, 90.0))
    return Range("DivergenceAngleApex", p.divergenceAngleApex, "[5, 90] degrees");
  if (!in(p.curvatureBase, 0.0, 50.0) || !in(p.curvatureApex, 0.0, 50.0))
    return Range("SecondaryCurvature", !in(p.curvatureBase, 0.0, 50.0) ? p.curvatureBase : p.curvatureApex, "[0, 50]");
  if (!in(p.forkFraction, 0.05, 0.98))
    return Range("ForkFraction", p.forkFraction, "[0.05, 0.98]");
  if (!in(p.branchCurvature, 0.0, 10.0))
    return Range("BranchCurvature", p.branchCurvature, "[0, 10]");
  if (!in(p.areoleSize, 0.001, 0.5))
    return Range("AreoleSize", p.areoleSize, "[0.001, 0.5] leaf lengths");
  if (!in(p.areoleGradient, 0.0, 0.8))
    return Range("AreoleGradient", p.areoleGradient, "[0, 0.8]");
  const int palmateSecondaries = static_cast<int>(p.palmateSecondaries);
  if (palmateSecondaries < 0 || palmateSecondaries >= PalmateSecondariesCount)
    return Range("PalmateSecondaries", palmateSecondaries, "[0, 2]");
  if (!in(p.minJunctionAngle, 0.0, 110.0))
    return Range("MinJunctionAngle", p.minJunctionAngle, "[0, 110] degrees");
  if (!in(p.junctionAngleDeviation, 0.0, 60.0))
    return Range("JunctionAngleDeviation", p.junctionAngleDeviation, "[0, 60] degrees");
  if (!in(p.veinletLength, 0.05, 2.0))
    return Range("VeinletLength", p.veinletLength, "[0.05, 2] areole sizes");
  if (p.palmateVeins < 1 || p.palmateVeins > 64)
    return Range("PalmateVeins", p.palmateVeins, "[1, 64]");
  if (p.forkLevels < 0 || p.forkLevels > 5)
    return Range("ForkLevels", p.forkLevels, "[0, 5]");
  if (!in(p.forkSize, 0.01, 0.99))
    return Range("ForkSize", p.forkSize, "[0.01, 0.99]");
  if (!in(p.primaryWidth, 0.0, 0.2))
    return Range("PrimaryWidth", p.primaryWidth, "[0, 0.2] leaf lengths");
  if (!in(p.primaryTaper, 0.0, 1.0))
    return Range("PrimaryTaper", p.primaryTaper, "[0, 1]");
  for (const double ratio : { p.secondaryWidthRatio, p.tertiaryWidthRatio, p.veinletWidthRatio })
  {
    if (!in(ratio, 0.0, 1.0))
      return Range("VeinWidthRatio", ratio, "[0, 1]");
  }
  if (!in(p.killDistance, 0.0002, 0.2))
    return Range("KillDistance", p.killDistance, "[0.0002, 0.2] leaf lengths");
  if (!in(p.attractionDistance, p.killDistance, 2.0))
    return Range("AttractionDistance", p.attractionDistance, "[KillDistance, 2] leaf lengths");
  if (!in(p.sourceDensity, 1.0, 1.0e8))
    return Range("SourceDensity", p.sourceDensity, "[1, 1e8] per leaf length squared");
  if (!in(p.murrayExponent, 1.0, 4.0))
    return Range("MurrayExponent", p.murrayExponent, "[1, 4]");
  if (!in(p.growthStart, 0.02, 1.0))
    return Range("GrowthStart", p.growthStart, "[0.02, 1]");
  if (!(p.gridCellScale > 0.0) || !std::isfinite(p.gridCellScale))
    return Range("gridCellScale", p.gridCellScale, "(0, inf)");
  if (p.maxSegments < 100)
    return Range("MaxSegments", static_cast<double>(p.maxSegments), "[100, ...)");
  return {};
}

std::string GrowVenation(const VenationBlade& blade, const VenationParameters& parameters, VenationResult& result,
  const std::function<bool(double)>& progress)
{
  result = VenationResult();
  std::string error = ValidateVenationParameters(parameters);
  if (!error.empty())
    return error;
  BladeLocator locator;
  error = locator.Build(blade);
  if (!error.empty())
    return "Input: " + error;
  if (parameters.pattern == VenationPattern::SpaceColonization)
    return GrowSpaceColonization(locator, parameters, result, progress);
  Grower grower(blade, locator, parameters, progress);
  error = grower.Run(result);
  if (!error.empty())
    result = VenationResult();
  return error;
}

std::vector<double> VeinReliefHeights(const VenationBlade& blade, const VenationResult& veins, double depth)
{
  std::vector<double> height(blade.points.size(), 0.0);
  if (depth == 0.0 || veins.nodes.empty())
    return height;
  double widest = 0.0;
  for (double w : veins.width)
    widest = std::max(widest, w);
  if (!(widest > 0.0))
    return height;
  // A grid of vein segments with cells of the widest vein's width: each point looks at its own cell's neighbours.
  Eigen::Vector2d low = veins.nodes.front(), high = low;
  for (const Eigen::Vector2d& x : veins.nodes)
  {
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
  }
  low -= Eigen::Vector2d::Constant(widest);
  high += Eigen::Vector2d::Constant(widest);
  const double cell = std::max(widest, std::sqrt((high - low).prod() / 4.0e6));
  const int nx = std::max(1, static_cast<int>(std::ceil((high.x() - low.x()) / cell)));
  const int ny = std::max(1, static_cast<int>(std::ceil((high.y() - low.y()) / cell)));
  std::vector<std::vector<std::array<int, 2>>> grid(static_cast<std::size_t>(nx) * ny);
  auto cellOf = [&](const Eigen::Vector2d& x) {
    return std::array<int, 2>{ std::clamp(static_cast<int>((x.x() - low.x()) / cell), 0, nx - 1),
      std::clamp(static_cast<int>((x.y() - low.y()) / cell), 0, ny - 1) };
  };
  for (const auto& line : veins.veins)
  {
    for (std::size_t i = 0; i + 1 < line.nodes.size(); ++i)
    {
      const int a = line.nodes[i], b = line.nodes[i + 1];
      const auto c0 = cellOf(veins.nodes[a].cwiseMin(veins.nodes[b]));
      const auto c1 = cellOf(veins.nodes[a].cwiseMax(veins.nodes[b]));
      for (int y = c0[1]; y <= c1[1]; ++y)
      {
        for (int x = c0[0]; x <= c1[0]; ++x)
          grid[static_cast<std::size_t>(y) * nx + x].push_back({ a, b });
      }
    }
  }
  for (std::size_t i = 0; i < blade.points.size(); ++i)
  {
    const Eigen::Vector2d& p = blade.points[i];
    const auto c = cellOf(p);
    double best = 0.0;
    for (int y = std::max(0, c[1] - 1); y <= std::min(ny - 1, c[1] + 1); ++y)
    {
      for (int x = std::max(0, c[0] - 1); x <= std::min(nx - 1, c[0] + 1); ++x)
      {
        for (const auto& [a, b] : grid[static_cast<std::size_t>(y) * nx + x])
        {
          const Eigen::Vector2d d = veins.nodes[b] - veins.nodes[a];
          const double t = std::clamp((p - veins.nodes[a]).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
          const double distance = (veins.nodes[a] + t * d - p).norm();
          const double w = (1.0 - t) * veins.width[a] + t * veins.width[b];
          if (w > 0.0 && distance < w)
          {
            const double r = distance / w;
            best = std::max(best, (w / widest) * (1.0 - r * r) * (1.0 - r * r));
          }
        }
      }
    }
    height[i] = depth * best;
  }
  return height;
}

std::vector<std::pair<const char*, double>> VenationParameterValues(const VenationParameters& p)
{
  return { { "Pattern", static_cast<double>(p.pattern) }, { "PrimaryCount", p.primaries },
    { "PrimarySpread", p.primarySpread }, { "ParallelVeins", p.parallelVeins }, { "ParallelSpread", p.parallelSpread },
    { "SecondarySpacing", p.secondarySpacing }, { "DivergenceAngle", p.divergenceAngle },
    { "DivergenceAngleApex", p.divergenceAngleApex }, { "SecondaryCurvatureBase", p.curvatureBase },
    { "SecondaryCurvatureApex", p.curvatureApex }, { "ForkFraction", p.forkFraction },
    { "BranchCurvature", p.branchCurvature }, { "Tertiary", p.tertiary ? 1.0 : 0.0 }, { "AreoleSize", p.areoleSize },
    { "AreoleGradient", p.areoleGradient }, { "MinJunctionAngle", p.minJunctionAngle },
    { "JunctionAngleDeviation", p.junctionAngleDeviation }, { "Veinlets", p.veinlets ? 1.0 : 0.0 },
    { "VeinletLength", p.veinletLength }, { "PalmateVeins", p.palmateVeins },
    { "PalmateEnds", p.palmateFan ? 1.0 : 0.0 }, { "ForkLevels", p.forkLevels },
    { "PalmateSecondaries", static_cast<double>(p.palmateSecondaries) }, { "SubLobeVeins", p.subLobeVeins ? 1.0 : 0.0 },
    { "FlankSecondaries", p.flankSecondaries ? 1.0 : 0.0 }, { "ForkSize", p.forkSize },
    { "MarginalGrowth", p.marginalGrowth ? 1.0 : 0.0 }, { "PrimaryWidth", p.primaryWidth },
    { "PrimaryTaper", p.primaryTaper }, { "SecondaryWidthRatio", p.secondaryWidthRatio },
    { "TertiaryWidthRatio", p.tertiaryWidthRatio }, { "VeinletWidthRatio", p.veinletWidthRatio } };
}

std::string DescribeVenationPreset(VenationPreset preset)
{
  const VenationParameters p = MakeVenationPreset(preset);
  std::ostringstream text;
  text << VenationPresetName(preset) << " sets (the greyed properties are not used):";
  for (const auto& [name, value] : VenationParameterValues(p))
  {
    text << "\n" << name << " = ";
    if (std::string(name) == "Pattern")
      text << VenationPatternName(p.pattern);
    else
      text << value;
  }
  return text.str();
}

} // namespace plantmorph
