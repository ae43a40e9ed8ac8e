// SPDX-License-Identifier: GPL-3.0-or-later
#include "SpaceColonization.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RandomStream.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <vector>

namespace plantmorph
{
namespace
{
/// The random stream of the dart throwing (GrowVenation's phases use streams 1-3).
constexpr std::uint64_t StreamSources = 4;

/// Point ids in a uniform grid of square cells over a box, for radius and nearest-point queries.
class PointGrid
{
public:
  /// Cells of about `cell` (fewer when there would be more than maxCells), counted in coarse cells of about
  /// `coarseCell` so that an empty neighbourhood is seen without visiting its fine cells.
  PointGrid(const Eigen::Vector2d& low, const Eigen::Vector2d& high, double cell, double coarseCell, double maxCells)
    : Low(low)
  {
    const Eigen::Vector2d extent = (high - low).cwiseMax(1e-300);
    cell = std::max(cell, 1e-12 * extent.maxCoeff());
    const double cells = (extent.x() / cell + 1.0) * (extent.y() / cell + 1.0);
    if (cells > maxCells)
      cell *= std::sqrt(cells / maxCells);
    this->Cell = cell;
    this->Width = static_cast<int>(extent.x() / cell) + 1;
    this->Height = static_cast<int>(extent.y() / cell) + 1;
    this->Cells.resize(static_cast<std::size_t>(this->Width) * this->Height);
    this->Factor = std::max(1, static_cast<int>(coarseCell / cell));
    this->CoarseWidth = (this->Width - 1) / this->Factor + 1;
    this->Coarse.assign(static_cast<std::size_t>(this->CoarseWidth) * ((this->Height - 1) / this->Factor + 1), 0);
  }

  void Insert(int id, const Eigen::Vector2d& p)
  {
    this->Cells[this->Index(p)].push_back(id);
    ++this->Coarse[this->CoarseIndex(p)];
  }
  void Remove(int id, const Eigen::Vector2d& p)
  {
    std::vector<int>& cell = this->Cells[this->Index(p)];
    cell.erase(std::find(cell.begin(), cell.end(), id));
    --this->Coarse[this->CoarseIndex(p)];
  }

  /// True when no entry lies in the coarse cells the disc (p, r) touches (so none lies within r of p).
  bool EmptyWithin(const Eigen::Vector2d& p, double r) const
  {
    const int x0 = this->Column(p.x() - r) / this->Factor, x1 = this->Column(p.x() + r) / this->Factor;
    const int y0 = this->Row(p.y() - r) / this->Factor, y1 = this->Row(p.y() + r) / this->Factor;
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        if (this->Coarse[static_cast<std::size_t>(y) * this->CoarseWidth + x] != 0)
          return false;
    return true;
  }

  /// Calls f(id) for every entry of the cells the disc (p, r) touches.
  template <typename F>
  void ForEachNear(const Eigen::Vector2d& p, double r, F f) const
  {
    const int x0 = this->Column(p.x() - r), x1 = this->Column(p.x() + r);
    const int y0 = this->Row(p.y() - r), y1 = this->Row(p.y() + r);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        for (int id : this->Cells[static_cast<std::size_t>(y) * this->Width + x])
          f(id);
  }

  bool AnyWithin(const Eigen::Vector2d& p, double r, const std::vector<Eigen::Vector2d>& points) const
  {
    bool found = false;
    this->ForEachNear(p, r, [&](int id) { found = found || (points[id] - p).squaredNorm() <= r * r; });
    return found;
  }

  /// The entry nearest p within r (the lowest id among equals), or -1: rings of cells outwards from p's cell, so
  /// it looks at about as many cells as the nearest entry is far.
  int Nearest(const Eigen::Vector2d& p, double r, const std::vector<Eigen::Vector2d>& points) const
  {
    if (std::isfinite(r) && this->EmptyWithin(p, r))
      return -1;
    const int cx = this->Column(p.x()), cy = this->Row(p.y());
    int best = -1;
    double bestSquared = r * r;
    for (int k = 0;; ++k)
    {
      if (k >= 1 && (k - 1) * this->Cell > std::sqrt(bestSquared))
        break;
      if (cx - k < 0 && cy - k < 0 && cx + k >= this->Width && cy + k >= this->Height)
        break;
      for (int y = cy - k; y <= cy + k; ++y)
      {
        if (y < 0 || y >= this->Height)
          continue;
        const int step = (y == cy - k || y == cy + k) ? 1 : std::max(1, 2 * k);
        for (int x = cx - k; x <= cx + k; x += step)
        {
          if (x < 0 || x >= this->Width)
            continue;
          for (int id : this->Cells[static_cast<std::size_t>(y) * this->Width + x])
          {
            const double d = (points[id] - p).squaredNorm();
            if (d < bestSquared || (d == bestSquared && (best < 0 || id < best)))
            {
              best = id;
              bestSquared = d;
            }
          }
        }
      }
    }
    return best;
  }

private:
  int Column(double x) const
  {
    return std::clamp(static_cast<int>(std::floor((x - this->Low.x()) / this->Cell)), 0, this->Width - 1);
  }
  int Row(double y) const
  {
    return std::clamp(static_cast<int>(std::floor((y - this->Low.y()) / this->Cell)), 0, this->Height - 1);
  }
  std::size_t Index(const Eigen::Vector2d& p) const
  {
    return static_cast<std::size_t>(this->Row(p.y())) * this->Width + this->Column(p.x());
  }
  std::size_t CoarseIndex(const Eigen::Vector2d& p) const
  {
    return static_cast<std::size_t>(this->Row(p.y()) / this->Factor) * this->CoarseWidth +
      this->Column(p.x()) / this->Factor;
  }

  Eigen::Vector2d Low;
  double Cell = 1.0;
  int Width = 1, Height = 1;
  std::vector<std::vector<int>> Cells;
  int Factor = 1, CoarseWidth = 1;
  std::vector<int> Coarse; ///< entries per coarse cell of Factor x Factor cells
};

class Colonizer
{
public:
  Colonizer(const BladeLocator& locator, const VenationParameters& p, double length)
    : Locator(locator)
    , P(p)
    , Length(length)
    , Random(p.seed, StreamSources)
    , Nodes(locator.Lower(), locator.Upper(), GridCell(p, length), p.attractionDistance * length, 4.0e6)
    , Sources(locator.Lower(), locator.Upper(), GridCell(p, length), p.attractionDistance * length, 4.0e6)
  {
  }

  std::string Run(VenationResult& result, const std::function<bool(double)>& progress);

private:
  static double GridCell(const VenationParameters& p, double length)
  {
    return std::max(p.killDistance, 0.5 / std::sqrt(p.sourceDensity)) * length;
  }
  bool Inside(const Eigen::Vector2d& x) const { return this->Locator.Locate(x, 1e-9 * this->Length).triangle >= 0; }
  /// Whether the segment a-b stays inside the blade: b and points along it every half mesh edge (at most 16).
  bool InsideAlong(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const
  {
    const double spacing = std::max(0.5 * this->Locator.EdgeLength(), 1e-12 * this->Length);
    const int samples = std::clamp(static_cast<int>(std::ceil((b - a).norm() / spacing)), 1, 16);
    for (int i = samples; i >= 1; --i)
    {
      if (!this->Inside(a + (static_cast<double>(i) / samples) * (b - a)))
        return false;
    }
    return true;
  }
  /// Marginal growth: whether x lies within `band` of the margin (a point of the circle of that radius about it,
  /// sampled every 30 degrees, lies outside the blade).
  bool NearMargin(const Eigen::Vector2d& x, double band) const
  {
    for (int k = 0; k < 12; ++k)
    {
      const double angle = k * Pi / 6.0;
      if (!this->Inside(x + band * Eigen::Vector2d(std::cos(angle), std::sin(angle))))
        return true;
    }
    return false;
  }
  int AddNode(const Eigen::Vector2d& x, int parent);
  /// Closed venation: the nodes within `reach` of source `id` in its relative neighbourhood (no other node is
  /// closer both to the source and to them), in id order.
  std::vector<int> Neighbourhood(int id, double reach) const;
  /// Closed venation: removes every source whose relative neighbourhood has all come within the kill distance,
  /// joining the veins that met there; returns whether any was removed.
  void CloseSources(double reach, double kill);
  /// Throws the darts of the blade's growth from the current stage to `stage`.
  void ThrowDarts(double stage);
  /// One step of attraction, growth and killing at the current stage; the number of nodes added.
  std::size_t Step();
  void Finish(VenationResult& result) const;

  const BladeLocator& Locator;
  const VenationParameters& P;
  double Length;
  RandomStream Random;
  double Stage = 1.0;
  double DartCarry = 0.0;
  std::vector<Eigen::Vector2d> NodePoints, SourcePoints;
  std::vector<int> Parent;
  std::vector<std::pair<int, int>> Links; ///< closed venation: where veins met at a source (they make the loops)
  std::vector<int> Live;                  ///< the sources not yet killed, in the order they were born
  /// Per source: the step before which no vein node can come within the attraction distance (nodes advance at most
  /// one vein step a step and the distances only shrink as the blade grows), so far sources are not searched again.
  std::vector<std::size_t> Wake;
  std::size_t Steps = 0;
  PointGrid Nodes, Sources;
};

int Colonizer::AddNode(const Eigen::Vector2d& x, int parent)
{
  const int id = static_cast<int>(this->NodePoints.size());
  this->NodePoints.push_back(x);
  this->Parent.push_back(parent);
  this->Nodes.Insert(id, x);
  return id;
}

void Colonizer::ThrowDarts(double stage)
{
  const Eigen::Vector2d low = this->Locator.Lower(), extent = this->Locator.Upper() - low;
  // Darts over the bounding box, so that sourceDensity of them per unit (physical) blade area land in the blade.
  const double box = extent.x() * extent.y() / (this->Length * this->Length);
  const double darts = this->P.sourceDensity * (stage * stage - this->Stage * this->Stage) * box + this->DartCarry;
  const auto count = static_cast<std::int64_t>(std::floor(darts));
  this->DartCarry = darts - static_cast<double>(count);
  const double birth = 0.5 / std::sqrt(this->P.sourceDensity) * this->Length / stage;
  // Marginal growth: only darts within one attraction distance (physical, at this stage) of the margin count.
  const double band = this->P.attractionDistance * this->Length / stage;
  for (std::int64_t i = 0; i < count; ++i)
  {
    const double x = this->Random.Uniform(), y = this->Random.Uniform();
    const Eigen::Vector2d dart = low + Eigen::Vector2d(x * extent.x(), y * extent.y());
    if (!this->Inside(dart) || (this->P.marginalGrowth && !this->NearMargin(dart, band)) ||
      this->Sources.AnyWithin(dart, birth, this->SourcePoints) || this->Nodes.AnyWithin(dart, birth, this->NodePoints))
      continue;
    const int id = static_cast<int>(this->SourcePoints.size());
    this->SourcePoints.push_back(dart);
    this->Sources.Insert(id, dart);
    this->Live.push_back(id);
    this->Wake.push_back(0);
  }
  this->Stage = stage;
}

std::vector<int> Colonizer::Neighbourhood(int id, double reach) const
{
  const Eigen::Vector2d& x = this->SourcePoints[id];
  std::vector<int> near;
  this->Nodes.ForEachNear(x, reach, [&](int n) {
    if ((this->NodePoints[n] - x).squaredNorm() <= reach * reach)
      near.push_back(n);
  });
  std::sort(near.begin(), near.end());
  std::vector<int> kept;
  for (int v : near)
  {
    const double dv = (this->NodePoints[v] - x).squaredNorm();
    bool shadowed = false;
    for (std::size_t k = 0; k < near.size() && !shadowed; ++k)
    {
      const int u = near[k];
      shadowed = u != v && (this->NodePoints[u] - x).squaredNorm() < dv &&
        (this->NodePoints[u] - this->NodePoints[v]).squaredNorm() < dv;
    }
    if (!shadowed)
      kept.push_back(v);
  }
  return kept;
}

void Colonizer::CloseSources(double reach, double kill)
{
  std::vector<char> removed(this->SourcePoints.size(), 0);
  bool any = false;
  for (int id : this->Live)
  {
    if (this->Wake[id] > this->Steps)
      continue;
    const std::vector<int> near = this->Neighbourhood(id, reach);
    const Eigen::Vector2d& x = this->SourcePoints[id];
    if (near.empty())
      continue;
    bool reached = true;
    int closest = near.front();
    for (int v : near)
    {
      reached = reached && (this->NodePoints[v] - x).norm() <= kill;
      if ((this->NodePoints[v] - x).squaredNorm() < (this->NodePoints[closest] - x).squaredNorm())
        closest = v;
    }
    if (!reached)
      continue;
    for (int v : near)
    {
      if (v != closest && this->Parent[v] != closest && this->Parent[closest] != v)
        this->Links.emplace_back(closest, v);
    }
    removed[id] = 1;
    any = true;
    this->Sources.Remove(id, x);
  }
  if (any)
    this->Live.erase(
      std::remove_if(this->Live.begin(), this->Live.end(), [&](int id) { return removed[id] != 0; }), this->Live.end());
}

std::size_t Colonizer::Step()
{
  ++this->Steps;
  // Every source's nearest node within the attraction distance (searched a few steps further, to know how long it
  // may sleep); when no source has one, the distance doubles for this step until one has.
  const double reach = this->P.attractionDistance * this->Length / this->Stage;
  const double step = 0.5 * this->P.killDistance * this->Length / this->Stage;
  std::vector<int> target(this->Live.size(), -1);
  bool any = false;
  for (std::size_t i = 0; i < this->Live.size(); ++i)
  {
    const int id = this->Live[i];
    if (this->Wake[id] > this->Steps)
      continue;
    const Eigen::Vector2d& x = this->SourcePoints[id];
    const int n = this->Nodes.Nearest(x, reach + 8.0 * step, this->NodePoints);
    const double d = n >= 0 ? (this->NodePoints[n] - x).norm() : reach + 8.0 * step;
    if (n >= 0 && d <= reach)
    {
      target[i] = n;
      any = true;
    }
    else
      this->Wake[id] = this->Steps + static_cast<std::size_t>(std::max(0.0, std::floor((d - reach) / step)));
  }
  const Eigen::Vector2d extent = this->Locator.Upper() - this->Locator.Lower();
  for (double wider = 2.0 * reach; !any && !this->Live.empty() && wider < 4.0 * extent.norm(); wider *= 2.0)
  {
    for (std::size_t i = 0; i < this->Live.size(); ++i)
    {
      target[i] = this->Nodes.Nearest(this->SourcePoints[this->Live[i]], wider, this->NodePoints);
      any = any || target[i] >= 0;
    }
  }
  // The mean direction of each attracted node's sources, nodes in the order their first source was born.
  std::vector<int> attracted;
  std::vector<Eigen::Vector2d> direction;
  std::vector<int> slot(this->NodePoints.size(), -1);
  const double kill = this->P.killDistance * this->Length / this->Stage;
  for (std::size_t i = 0; i < this->Live.size(); ++i)
  {
    if (target[i] < 0)
      continue;
    std::vector<int> pulled = { target[i] };
    if (this->P.closedVenation)
      pulled = this->Neighbourhood(
        this->Live[i], std::max(reach, (this->NodePoints[target[i]] - this->SourcePoints[this->Live[i]]).norm()));
    for (int n : pulled)
    {
      const Eigen::Vector2d d = this->SourcePoints[this->Live[i]] - this->NodePoints[n];
      const double norm = d.norm();
      if (!(norm > 0.0) || (this->P.closedVenation && norm <= kill))
        continue; // closed: a vein that has reached the source waits there for the others
      if (slot[n] < 0)
      {
        slot[n] = static_cast<int>(attracted.size());
        attracted.push_back(n);
        direction.emplace_back(Eigen::Vector2d::Zero());
      }
      direction[slot[n]] += d / norm;
    }
  }
  std::vector<int> added;
  for (std::size_t k = 0; k < attracted.size(); ++k)
  {
    const double norm = direction[k].norm();
    if (!(norm > 1e-9))
      continue; // sources pulling equally in opposite directions
    const Eigen::Vector2d from = this->NodePoints[attracted[k]];
    const Eigen::Vector2d x = from + step / norm * direction[k];
    if (!this->InsideAlong(from, x) || this->Nodes.AnyWithin(x, 1e-3 * step, this->NodePoints))
      continue;
    added.push_back(this->AddNode(x, attracted[k]));
  }
  if (this->P.closedVenation)
  {
    this->CloseSources(reach, kill);
    return added.size();
  }
  // Kill the sources the new nodes came within the kill distance of (open venation).
  std::vector<char> killed;
  for (int n : added)
  {
    std::vector<int> near;
    this->Sources.ForEachNear(this->NodePoints[n], kill, [&](int id) {
      if ((this->SourcePoints[id] - this->NodePoints[n]).squaredNorm() <= kill * kill)
        near.push_back(id);
    });
    for (int id : near)
    {
      if (killed.size() < this->SourcePoints.size())
        killed.resize(this->SourcePoints.size(), 0);
      killed[id] = 1;
      this->Sources.Remove(id, this->SourcePoints[id]);
    }
  }
  if (!killed.empty())
    this->Live.erase(
      std::remove_if(this->Live.begin(), this->Live.end(), [&](int id) { return killed[id] != 0; }), this->Live.end());
  return added.size();
}

std::string Colonizer::Run(VenationResult& result, const std::function<bool(double)>& progress)
{
  const double start = this->P.growthStart;
  // The blade's margin advances half a vein step per step, so the vein tips keep up with it.
  const double grow = 0.25 * this->P.killDistance;
  this->Stage = 0.0;
  this->AddNode(this->Locator.PointAtUV(Eigen::Vector2d(0.0, 0.0)), -1);
  this->ThrowDarts(start);
  const std::size_t limit = static_cast<std::size_t>((1.0 - start) / grow + 20.0 / this->P.killDistance) + 1000;
  for (std::size_t step = 0; step < limit; ++step)
  {
    const std::size_t added = this->Step();
    if (this->NodePoints.size() > this->P.maxSegments + 1)
    {
      std::ostringstream message;
      message << "MaxSegments: space colonization needs more than " << this->P.maxSegments
              << " vein segments; raise MaxSegments or KillDistance, or lower SourceDensity";
      return message.str();
    }
    if (this->Stage < 1.0)
      this->ThrowDarts(std::min(1.0, this->Stage + grow));
    else if (added == 0 || this->Live.empty())
      break;
    if (progress && step % 16 == 0 && !progress(0.05 + 0.85 * (this->Stage - start) / std::max(1.0 - start, 1e-9)))
      return "aborted";
  }
  if (this->NodePoints.size() < 2)
    return "SourceDensity: no auxin source drew a vein from the base; raise SourceDensity or AttractionDistance";
  this->Finish(result);
  return {};
}

void Colonizer::Finish(VenationResult& result) const
{
  const std::size_t count = this->NodePoints.size();
  // Pipe model: children always come after their parent, so one backward sweep gives every node's width.
  std::vector<double> flux(count, 0.0);
  std::vector<int> children(count, 0), heaviest(count, -1);
  const double n = this->P.murrayExponent;
  for (std::size_t i = count; i-- > 0;)
  {
    if (children[i] == 0)
      flux[i] = 1.0;
    const int parent = this->Parent[i];
    if (parent < 0)
      continue;
    flux[parent] += flux[i]; // w_parent^n = sum of w_child^n
    ++children[parent];
    const int h = heaviest[parent];
    if (h < 0 || flux[i] > flux[h] || (flux[i] == flux[h] && static_cast<int>(i) < h))
      heaviest[parent] = static_cast<int>(i);
  }
  // flux holds sum of w^n over the free ends below; the width is its n-th root, scaled to primaryWidth at the base.
  result = VenationResult();
  result.leafLength = this->Length;
  result.nodes = this->NodePoints;
  const double base = std::pow(flux[0], 1.0 / n);
  for (std::size_t i = 0; i < count; ++i)
    result.width.push_back(this->P.primaryWidth * this->Length * std::pow(flux[i], 1.0 / n) / base);
  result.order.assign(count, VeinOrderQuaternary);
  std::vector<std::vector<int>> kids(count);
  for (std::size_t i = 1; i < count; ++i)
    kids[this->Parent[i]].push_back(static_cast<int>(i));
  // Veins: from each start, follow the heaviest child; every other child starts a vein one order higher.
  struct Start
  {
    int from, first, order;
  };
  std::vector<Start> starts = { { -1, 0, VeinOrderPrimary } };
  VenationStatistics& stats = result.statistics;
  while (!starts.empty())
  {
    const Start s = starts.back();
    starts.pop_back();
    VenationResult::Polyline line;
    line.order = s.order;
    if (s.from >= 0)
      line.nodes.push_back(s.from);
    for (int at = s.first; at >= 0; at = heaviest[at])
    {
      line.nodes.push_back(at);
      result.order[at] = std::min(result.order[at], s.order);
      for (auto k = kids[at].rbegin(); k != kids[at].rend(); ++k)
      {
        if (*k != heaviest[at])
          starts.push_back({ at, *k, std::min(s.order + 1, static_cast<int>(VeinOrderQuaternary)) });
      }
    }
    if (line.nodes.size() < 2)
      continue;
    for (std::size_t i = 1; i < line.nodes.size(); ++i)
      stats.length[line.order] += (result.nodes[line.nodes[i]] - result.nodes[line.nodes[i - 1]]).norm();
    stats.segments += line.nodes.size() - 1;
    result.veins.push_back(std::move(line));
  }
  // Closed venation: where veins met at a source, a short vein of the finer order joins them.
  std::vector<int> degree(count, 0);
  for (std::size_t i = 0; i < count; ++i)
    degree[i] = children[i] + (this->Parent[i] >= 0 ? 1 : 0);
  for (const auto& link : this->Links)
  {
    VenationResult::Polyline line;
    line.order = std::max(result.order[link.first], result.order[link.second]);
    line.nodes = { link.first, link.second };
    stats.length[line.order] += (result.nodes[link.first] - result.nodes[link.second]).norm();
    ++stats.segments;
    ++degree[link.first];
    ++degree[link.second];
    result.veins.push_back(std::move(line));
  }
  for (const Eigen::Vector2d& x : result.nodes)
  {
    BladeLocation at = this->Locator.Locate(x, 1e-7 * this->Length);
    if (at.triangle < 0)
      at = this->Locator.Locate(x, 1e-3 * this->Length);
    result.location.push_back(at);
  }
  stats.bladeArea = this->Locator.Area();
  stats.density = (stats.length[1] + stats.length[2] + stats.length[3] + stats.length[4]) / stats.bladeArea;
  for (std::size_t i = 0; i < count; ++i)
  {
    stats.branchPoints += degree[i] >= 3;
    stats.freeEnds += degree[i] == 1 && i > 0; // node 0 is the base, on the margin
  }
}

} // namespace

std::string GrowSpaceColonization(const BladeLocator& locator, const VenationParameters& parameters,
  VenationResult& result, const std::function<bool(double)>& progress)
{
  result = VenationResult();
  double length = 0.0;
  Eigen::Vector2d previous = locator.PointAtUV(Eigen::Vector2d(0.0, 0.0));
  for (int k = 1; k <= 512; ++k)
  {
    const Eigen::Vector2d x = locator.PointAtUV(Eigen::Vector2d(0.0, k / 512.0));
    length += (x - previous).norm();
    previous = x;
  }
  if (!(length > 0.0))
    return "LeafUV: the blade's midvein (u = 0 from v = 0 to 1) has no length";
  Colonizer colonizer(locator, parameters, length);
  const std::string error = colonizer.Run(result, progress);
  if (!error.empty())
    result = VenationResult();
  return error;
}

} // namespace plantmorph
