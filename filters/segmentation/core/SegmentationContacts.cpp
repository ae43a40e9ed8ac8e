// SPDX-License-Identifier: GPL-3.0-or-later
// Two leaves grown into one instance through the place where their margins touch (step 5 of PlantSegmentation.h;
// docs/methods/segmentation.md gives the numbers): cut at that seam.
#include "SegmentationSteps.h"

#include "PointGrid.h"
#include "SegmentationGrid.h"

#include <plantmorph/PlaneFit.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <deque>
#include <utility>

namespace plantmorph
{
namespace segmentation
{
namespace
{

/// Iterations of the two-axis clustering of the normals (it settles in 3-4 on two planes).
constexpr int AxisIterations = 10;
/// Fewer seam points than this: the two sides do not touch (pieces of a leaf joined across a gap).
constexpr std::size_t SeamPoints = 3;
/// Quantiles bounding a set's extent along a line (robust to a few stray points).
constexpr double SpanQuantile = 0.02;

/// The unit eigenvector of the largest eigenvalue of a symmetric 3x3 matrix.
Eigen::Vector3d MainAxis(const Eigen::Matrix3d& m)
{
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m).eigenvectors().col(2);
}

/// Each point of `ids` in one of two groups by its normal's axis (normals have no sign): the two axes start on
/// either side of the main axis of the normals' second moments and settle like two-means. Returns false when a
/// group is empty; `side` (per entry of ids) 0 or 1, `axes` the two groups' axes.
bool TwoNormalGroups(const std::vector<Eigen::Vector3d>& normal, const std::vector<int>& ids, std::vector<int>& side,
  Eigen::Vector3d axes[2])
{
  Eigen::Matrix3d all = Eigen::Matrix3d::Zero();
  for (int j : ids)
    all += normal[static_cast<std::size_t>(j)] * normal[static_cast<std::size_t>(j)].transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(all);
  axes[0] = (solver.eigenvectors().col(2) + solver.eigenvectors().col(1)).normalized();
  axes[1] = (solver.eigenvectors().col(2) - solver.eigenvectors().col(1)).normalized();
  side.assign(ids.size(), 0);
  for (int iteration = 0; iteration < AxisIterations; ++iteration)
  {
    Eigen::Matrix3d moment[2] = { Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero() };
    std::size_t count[2] = { 0, 0 };
    for (std::size_t k = 0; k < ids.size(); ++k)
    {
      const Eigen::Vector3d& n = normal[static_cast<std::size_t>(ids[k])];
      side[k] = std::abs(n.dot(axes[0])) >= std::abs(n.dot(axes[1])) ? 0 : 1;
      moment[side[k]] += n * n.transpose();
      ++count[side[k]];
    }
    if (count[0] == 0 || count[1] == 0)
      return false;
    axes[0] = MainAxis(moment[0]);
    axes[1] = MainAxis(moment[1]);
  }
  return true;
}

/// Makes each side one piece: the largest linked component of each side's points keeps its side, the other points
/// go to the side that reaches them first over the links within the part (breadth-first from both at once); points
/// neither reaches (pieces joined across a gap) keep their own side. `local` maps a point to its entry in ids (-1
/// elsewhere).
void ConnectSides(
  const LinkGraph& graph, const std::vector<int>& ids, const std::vector<int>& local, std::vector<int>& side)
{
  std::vector<int> component(ids.size(), -1);
  std::vector<std::size_t> sizes;
  std::size_t largest[2] = { 0, 0 };
  int largestId[2] = { -1, -1 };
  for (std::size_t seed = 0; seed < ids.size(); ++seed)
  {
    if (component[seed] >= 0)
      continue;
    const int c = static_cast<int>(sizes.size());
    std::vector<std::size_t> stack = { seed };
    component[seed] = c;
    std::size_t size = 0;
    while (!stack.empty())
    {
      const std::size_t k = stack.back();
      stack.pop_back();
      ++size;
      const auto q = static_cast<std::size_t>(ids[k]);
      for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
      {
        const int m = local[static_cast<std::size_t>(graph.neighbours[e])];
        if (m >= 0 && component[static_cast<std::size_t>(m)] < 0 && side[static_cast<std::size_t>(m)] == side[seed])
        {
          component[static_cast<std::size_t>(m)] = c;
          stack.push_back(static_cast<std::size_t>(m));
        }
      }
    }
    sizes.push_back(size);
    const int s = side[seed];
    if (size > largest[s])
    {
      largest[s] = size;
      largestId[s] = c;
    }
  }
  std::vector<int> owner(ids.size(), -1);
  std::deque<std::size_t> queue;
  for (std::size_t k = 0; k < ids.size(); ++k)
    if (component[k] == largestId[side[k]])
    {
      owner[k] = side[k];
      queue.push_back(k);
    }
  while (!queue.empty())
  {
    const std::size_t k = queue.front();
    queue.pop_front();
    const auto q = static_cast<std::size_t>(ids[k]);
    for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
    {
      const int m = local[static_cast<std::size_t>(graph.neighbours[e])];
      if (m >= 0 && owner[static_cast<std::size_t>(m)] < 0)
      {
        owner[static_cast<std::size_t>(m)] = owner[k];
        queue.push_back(static_cast<std::size_t>(m));
      }
    }
  }
  for (std::size_t k = 0; k < ids.size(); ++k)
    if (owner[k] >= 0)
      side[k] = owner[k];
}

/// The extent of `values` between its SpanQuantile and 1 - SpanQuantile quantiles (values reordered).
double Span(std::vector<double>& values)
{
  const auto at = [&values](double q) {
    const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
    std::nth_element(values.begin(), values.begin() + k, values.end());
    return values[static_cast<std::size_t>(k)];
  };
  return at(1.0 - SpanQuantile) - at(SpanQuantile);
}

/// Whether the two sides, unfolded about the seam's line into one plane (a point at (its position along the line,
/// its distance from the line), one side's distances negated), leave notches where the seam ends: the sum of the
/// sides' convex hulls' areas under NotchedHullFraction of the hull of both. A blade folded or curled along any line
/// unfolds into its own outline, whose halves' hulls fill the whole's; two leaves meet at an angle where the seam
/// ends, each outline turning away from the other's.
bool SidesLeaveNotches(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& mean,
  const Eigen::Vector3d& line, const std::vector<int>& seam, const std::vector<int>& sideA,
  const std::vector<int>& sideB)
{
  const auto unfold = [&](int j, double sign) {
    const Eigen::Vector3d d = points[static_cast<std::size_t>(j)] - mean;
    const double u = d.dot(line);
    return Eigen::Vector2d(u, sign * (d - u * line).norm());
  };
  std::vector<Eigen::Vector2d> both, one;
  double sum = 0.0;
  for (const std::vector<int>* ids : { &sideA, &sideB })
  {
    const double sign = ids == &sideA ? -1.0 : 1.0;
    one.clear();
    for (int j : *ids)
      one.push_back(unfold(j, sign));
    both.insert(both.end(), one.begin(), one.end());
    for (int j : seam) // the seam's line in both: the sides' hulls would leave the band along it out
      one.emplace_back(unfold(j, 0.0));
    sum += ConvexHullArea(one);
  }
  const double whole = ConvexHullArea(std::move(both));
  return whole > 0.0 && sum < NotchedHullFraction * whole;
}

/// Whether the `seam` between two sides says they are two leaves: its extent along its own line under SeamFraction
/// of each side's extent along it, or the sides unfolded about that line leave notches (SidesLeaveNotches).
bool SeamSaysTwoLeaves(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& seam,
  const std::vector<int>& sideA, const std::vector<int>& sideB)
{
  Eigen::Vector3d mean;
  const Eigen::Vector3d line = MainAxis(Scatter(points, seam, mean));
  std::vector<double> along;
  for (int j : seam)
    along.push_back((points[static_cast<std::size_t>(j)] - mean).dot(line));
  const double seamSpan = Span(along);
  bool shorter = true;
  for (const std::vector<int>* ids : { &sideA, &sideB })
  {
    along.clear();
    for (int j : *ids)
      along.push_back((points[static_cast<std::size_t>(j)] - mean).dot(line));
    shorter = shorter && seamSpan < SeamFraction * Span(along);
  }
  return shorter || SidesLeaveNotches(points, mean, line, seam, sideA, sideB);
}

/// Whether the seam between the two sides (their points linked to the other side) is short: its extent along its
/// own line under SeamFraction of each side's extent along that line. A crease of one blade (a fold along the
/// midrib, a roll across the width, a bend along the length, a folded tip) runs from margin to margin of at least
/// one side; two leaves whose margins touch meet over part of each.
bool SeamIsShort(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph, const std::vector<int>& ids,
  const std::vector<int>& local, const std::vector<int>& side)
{
  std::vector<int> seam;
  for (std::size_t k = 0; k < ids.size(); ++k)
  {
    const auto q = static_cast<std::size_t>(ids[k]);
    for (std::size_t e = graph.offsets[q]; e < graph.offsets[q + 1]; ++e)
    {
      const int m = local[static_cast<std::size_t>(graph.neighbours[e])];
      if (m >= 0 && side[static_cast<std::size_t>(m)] != side[k])
      {
        seam.push_back(ids[k]);
        break;
      }
    }
  }
  if (seam.size() < SeamPoints)
    return false;
  std::vector<int> sides[2];
  for (std::size_t k = 0; k < ids.size(); ++k)
    if (side[k] == 0 || side[k] == 1)
      sides[side[k]].push_back(ids[k]);
  return SeamSaysTwoLeaves(points, seam, sides[0], sides[1]);
}
} // namespace

bool ShortSeamBetween(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph,
  const std::vector<int>& partOf, int a, int b, const std::vector<int>& idsA, const std::vector<int>& idsB,
  bool touchSaysTwo)
{
  std::vector<int> seam;
  const auto linkedTo = [&](int j, int other) {
    for (std::size_t e = graph.offsets[static_cast<std::size_t>(j)]; e < graph.offsets[static_cast<std::size_t>(j) + 1];
         ++e)
    {
      const auto q = static_cast<std::size_t>(graph.neighbours[e]);
      if (q < partOf.size() && partOf[q] == other)
        return true;
    }
    return false;
  };
  for (int j : idsA)
    if (linkedTo(j, b))
      seam.push_back(j);
  for (int j : idsB)
    if (linkedTo(j, a))
      seam.push_back(j);
  if (seam.size() < SeamPoints)
    return touchSaysTwo; // a touch at a point or two: no crease runs there
  return SeamSaysTwoLeaves(points, seam, idsA, idsB);
}

namespace
{
/// The extent of points[ids] along their main axis (ExtentAlong: from the lowest to the highest, as the leaf length
/// is measured).
double ExtentAlongMainAxis(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids)
{
  Eigen::Vector3d mean;
  const Eigen::Vector3d axis = MainAxis(Scatter(points, ids, mean));
  return ExtentAlong(points, ids, mean, axis);
}

/// Whether the part `ids` is cut in two, and then its sides (per entry of ids, in `side`). `local` is scratch: -1 for
/// every point in and out. A part longer than `longest` (when above 0) is cut whatever its seam.
bool CutInTwo(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const LinkGraph& graph, double cosine,
  std::size_t smallest, double longest, const std::vector<int>& ids, std::vector<int>& local, std::vector<int>& side)
{
  Eigen::Vector3d axes[2];
  if (ids.size() < 2 * smallest || !TwoNormalGroups(f.normal, ids, side, axes) ||
    std::abs(axes[0].dot(axes[1])) >= cosine)
    return false;
  for (std::size_t m = 0; m < ids.size(); ++m)
    local[static_cast<std::size_t>(ids[m])] = static_cast<int>(m);
  ConnectSides(graph, ids, local, side);
  const auto first = static_cast<std::size_t>(std::count(side.begin(), side.end(), 0));
  const bool cut = first >= smallest && ids.size() - first >= smallest &&
    ((longest > 0.0 && ExtentAlongMainAxis(points, ids) > longest) || SeamIsShort(points, graph, ids, local, side));
  for (int j : ids)
    local[static_cast<std::size_t>(j)] = -1;
  return cut;
}
} // namespace

std::size_t CutAtShortSeams(const std::vector<Eigen::Vector3d>& points, const PointFeatures& f, const LinkGraph& graph,
  double cosine, std::size_t smallest, double longest, const ParallelFor& parallel,
  std::vector<std::vector<int>>& parts)
{
  // The parts as given are judged each on its own, side by side (few are cut); the sides of a cut are appended and
  // judged in turn, in the same order as one pass over the parts would.
  // Per given part: whole, cut in the parallel pass (its sides in `sides`), or cut and replaced by its first side,
  // which is judged again here.
  enum Judged : char
  {
    Whole,
    CutAhead,
    JudgeAgain
  };
  const std::size_t given = parts.size();
  std::vector<Judged> judged(given, Whole);
  std::vector<std::vector<int>> sides(given);
  parallel(given, [&](std::size_t begin, std::size_t end) {
    std::vector<int> local(points.size(), -1), side;
    for (std::size_t k = begin; k < end; ++k)
      if (CutInTwo(points, f, graph, cosine, smallest, longest, parts[k], local, side))
      {
        judged[k] = CutAhead;
        sides[k] = side;
      }
  });
  std::vector<int> local(points.size(), -1), side;
  std::size_t cuts = 0;
  for (std::size_t k = 0; k < parts.size(); ++k)
  {
    const std::vector<int>& ids = parts[k];
    bool cut = false;
    if (k < given && judged[k] == CutAhead)
    {
      cut = true;
      side.swap(sides[k]);
    }
    else if (k >= given || judged[k] == JudgeAgain)
      cut = CutInTwo(points, f, graph, cosine, smallest, longest, ids, local, side);
    if (!cut)
      continue;
    if (k < given)
      judged[k] = JudgeAgain;
    std::vector<int> halves[2];
    for (std::size_t m = 0; m < ids.size(); ++m)
      halves[side[m]].push_back(ids[m]);
    parts[k] = std::move(halves[0]);
    parts.push_back(std::move(halves[1]));
    ++cuts;
    --k; // the first side may hold a third leaf
  }
  return cuts;
}

namespace
{
/// A leaf point held by no kept part (LeafPointsOntoTheirPlane's label).
constexpr int FreeLeafPoint = -2;
/// A part's plane in a block counts where its points there spread across their main direction by at least this
/// fraction of a cell (root mean square): a row alone lies in any plane through it; two rows a link apart (2.5
/// spacings, in cells of twice the features' radius of 4 spacings: a root mean square of 0.16 cells) give one.
constexpr double PlaneSpread = 0.15;

/// A part's plane through its points in a block of cells.
struct BlockPlane
{
  int part = -1;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::UnitZ();
};

/// Per cell of `grid`, the label its points share, or MixedCell.
constexpr int MixedCell = -3;

/// What LeafPointsOntoTheirPlane's passes look at: the points (`sub`, positions in `points`), their labels (a kept
/// part, or FreeLeafPoint), per cell the label its points share (or MixedCell), the moments of each kept part's
/// points in it (ascending part), and whether a point of it moved in the pass before.
struct PlaneScene
{
  const std::vector<Eigen::Vector3d>& points;
  const std::vector<int>& sub;
  const CellGrid& grid;
  const LinkGraph& graph;
  std::vector<int> label, cellLabel, position; // position: each point's in sub, -1 when not looked at
  std::vector<std::vector<std::pair<int, PartMoments>>> moments;
  std::vector<char> changed;

  const Eigen::Vector3d& At(int s) const { return points[static_cast<std::size_t>(sub[static_cast<std::size_t>(s)])]; }

  /// The other kept parts point s of a kept part is linked to, into `linked` (empty: not on a border).
  void LinkedParts(int s, std::vector<int>& linked) const
  {
    linked.clear();
    const int own = label[static_cast<std::size_t>(s)];
    const auto i = static_cast<std::size_t>(sub[static_cast<std::size_t>(s)]);
    for (std::size_t e = graph.offsets[i]; own >= 0 && e < graph.offsets[i + 1]; ++e)
    {
      const int at = position[static_cast<std::size_t>(graph.neighbours[e])];
      const int other = at >= 0 ? label[static_cast<std::size_t>(at)] : -1;
      if (other >= 0 && other != own && std::find(linked.begin(), linked.end(), other) == linked.end())
        linked.push_back(other);
    }
  }

  /// Cell c's label (cellLabel) and its parts' moments (moments), from its points' labels.
  void Summarise(std::size_t c)
  {
    const int first = label[static_cast<std::size_t>(*grid.Begin(c))];
    cellLabel[c] = first;
    std::vector<std::pair<int, PartMoments>>& parts = moments[c];
    parts.clear();
    std::vector<int> ids;
    for (const int* it = grid.Begin(c); it != grid.End(c); ++it)
    {
      const int own = label[static_cast<std::size_t>(*it)];
      cellLabel[c] = own == first ? cellLabel[c] : MixedCell;
      if (own >= 0 && std::none_of(parts.begin(), parts.end(), [&](const auto& m) { return m.first == own; }))
        parts.emplace_back(own, PartMoments());
    }
    std::sort(parts.begin(), parts.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (auto& [part, m] : parts)
    {
      ids.clear();
      for (const int* it = grid.Begin(c); it != grid.End(c); ++it)
        if (label[static_cast<std::size_t>(*it)] == part)
          ids.push_back(sub[static_cast<std::size_t>(*it)]);
      m = PartMoments::Of(points, ids);
    }
  }
};

/// The planes of the kept parts with at least PlanePoints points in the cells `cells`, from their moments, in
/// ascending part; only those whose points spread across their main direction by at least `width` (root mean
/// square).
std::vector<BlockPlane> PlanesInBlock(const PlaneScene& scene, const std::vector<std::size_t>& cells, double width)
{
  std::vector<std::pair<int, PartMoments>> sums;
  for (std::size_t c : cells)
    for (const auto& [part, m] : scene.moments[c])
    {
      const auto it = std::find_if(sums.begin(), sums.end(), [&](const auto& x) { return x.first == part; });
      if (it == sums.end())
        sums.emplace_back(part, m);
      else
        it->second = it->second.Merged(m);
    }
  std::sort(sums.begin(), sums.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<BlockPlane> planes;
  for (const auto& [part, m] : sums)
  {
    if (m.count < PlanePoints)
      continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(m.scatter / m.count);
    // a plane only where the points spread across their main direction (a row alone lies in any plane through it)
    if (solver.eigenvalues()[1] >= width * width)
      planes.push_back({ part, m.mean, solver.eigenvectors().col(0) });
  }
  return planes;
}

/// Whether cell c's block is worth a look: it holds more than one label, and (after the first pass) a point of it
/// moved in the pass before. Read a cell at a time (up to 27, into `cells`), not a point at a time.
bool BlockToJudge(
  const PlaneScene& scene, std::size_t c, int pass, const CellGrid::Block& block, std::vector<std::size_t>& cells)
{
  const int first = scene.cellLabel[c];
  bool mixed = first == MixedCell, changed = pass == 0;
  const int* order = scene.grid.Ordered().data();
  cells.clear();
  for (int r = 0; r < block.runs; ++r)
    for (std::size_t o = block.begin[r]; o < block.end[r];)
    {
      const auto cell = static_cast<std::size_t>(scene.grid.CellOfPoint(static_cast<std::size_t>(order[o])));
      mixed = mixed || scene.cellLabel[cell] != first;
      changed = changed || scene.changed[cell];
      cells.push_back(cell);
      o = static_cast<std::size_t>(scene.grid.End(cell) - order);
    }
  return mixed && changed;
}

/// The moves (position in sub, part) of cell c's points by LeafPointsOntoTheirPlane's rule, into `moves`.
void MovesInCell(
  const PlaneScene& scene, std::size_t c, int pass, const PlaneMoves& rule, std::vector<std::pair<int, int>>& moves)
{
  const std::vector<int>& label = scene.label;
  CellGrid::Block block;
  scene.grid.BlockAround(scene.At(*scene.grid.Begin(c)), block);
  std::vector<std::size_t> cells;
  if (!BlockToJudge(scene, c, pass, block, cells))
    return;
  const std::vector<BlockPlane> planes = PlanesInBlock(scene, cells, PlaneSpread * scene.grid.Cell());
  const auto distance = [&](const BlockPlane& plane, const Eigen::Vector3d& q) {
    return std::abs((q - plane.centroid).dot(plane.normal));
  };
  std::vector<int> linked;
  for (const int* it = scene.grid.Begin(c); it != scene.grid.End(c); ++it)
  {
    linked.clear();
    const int own = label[static_cast<std::size_t>(*it)];
    const Eigen::Vector3d& q = scene.At(*it);
    double limit = rule.margin; // on the plane within the margin
    if (own >= 0)
    {
      const auto mine =
        std::find_if(planes.begin(), planes.end(), [&](const BlockPlane& plane) { return plane.part == own; });
      if (mine == planes.end())
        continue;
      // nearer it than its own part's by the margin; on the border, to a part it is linked to, by the border's margin
      scene.LinkedParts(*it, linked);
      limit =
        linked.empty() ? std::min(limit, distance(*mine, q) - rule.margin) : distance(*mine, q) - rule.borderMargin;
    }
    int to = -1;
    for (const BlockPlane& plane : planes)
      if (const double d = distance(plane, q); plane.part != own && d < limit &&
          (linked.empty() || std::find(linked.begin(), linked.end(), plane.part) != linked.end()))
      {
        limit = d;
        to = plane.part;
      }
    if (to >= 0)
      moves.emplace_back(*it, to);
  }
}
} // namespace

std::size_t LeafPointsOntoTheirPlane(const std::vector<Eigen::Vector3d>& points, const LinkGraph& graph,
  const std::vector<int>& organ, const PlaneMoves& rule, const std::vector<char>& kept, const ParallelFor& parallel,
  std::vector<std::vector<int>>& parts)
{
  if (std::none_of(kept.begin(), kept.end(), [](char k) { return k != 0; }))
    return 0;
  std::vector<int> holder(points.size(), -1); // the part (kept or not) holding each point
  for (std::size_t k = 0; k < parts.size(); ++k)
    for (int j : parts[k])
      holder[static_cast<std::size_t>(j)] = static_cast<int>(k);
  std::vector<int> sub; // the points looked at: the kept parts' and the other leaf points
  std::vector<Eigen::Vector3d> at;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (organ[i] == OrganLeaf || (holder[i] >= 0 && kept[static_cast<std::size_t>(holder[i])]))
    {
      sub.push_back(static_cast<int>(i));
      at.push_back(points[i]);
    }
  const CellGrid grid(at, rule.cell, parallel);
  PlaneScene scene{ points, sub, grid, graph, std::vector<int>(sub.size()), std::vector<int>(grid.CellCount()),
    std::vector<int>(points.size(), -1), std::vector<std::vector<std::pair<int, PartMoments>>>(grid.CellCount()),
    std::vector<char>(grid.CellCount(), 0) };
  for (std::size_t s = 0; s < sub.size(); ++s)
  {
    const int k = holder[static_cast<std::size_t>(sub[s])];
    scene.label[s] = k >= 0 && kept[static_cast<std::size_t>(k)] ? k : FreeLeafPoint;
    scene.position[static_cast<std::size_t>(sub[s])] = static_cast<int>(s);
  }
  std::vector<char> moving(points.size(), 0);
  std::size_t moved = 0;
  for (int pass = 0; pass < rule.passes; ++pass)
  {
    parallel(grid.CellCount(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t c = begin; c < end; ++c)
        if (pass == 0 || scene.changed[c]) // a point keeps its cell: only the cells it moved in change
          scene.Summarise(c);
    });
    std::vector<std::vector<std::pair<int, int>>> movesOf(grid.CellCount());
    parallel(grid.CellCount(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t c = begin; c < end; ++c)
        MovesInCell(scene, c, pass, rule, movesOf[c]);
    });
    std::fill(moving.begin(), moving.end(), 0);
    std::fill(scene.changed.begin(), scene.changed.end(), 0);
    std::vector<char> touched(parts.size(), 0); // the parts a point left or joined
    std::size_t now = 0;
    for (std::size_t c = 0; c < movesOf.size(); ++c)
      for (const auto& [s, to] : movesOf[c])
      {
        const auto i = static_cast<std::size_t>(sub[static_cast<std::size_t>(s)]);
        moving[i] = 1;
        scene.changed[c] = 1;
        if (holder[i] >= 0)
          touched[static_cast<std::size_t>(holder[i])] = 1;
        touched[static_cast<std::size_t>(to)] = 1;
        parts[static_cast<std::size_t>(to)].push_back(static_cast<int>(i));
        holder[i] = to;
        scene.label[static_cast<std::size_t>(s)] = to; // a kept part: planes are only the kept parts'
        ++now;
      }
    if (now == 0)
      break;
    for (std::size_t k = 0; k < parts.size(); ++k)
    {
      if (!touched[k])
        continue;
      std::vector<int>& ids = parts[k];
      ids.erase(std::remove_if(ids.begin(), ids.end(),
                  [&](int j) {
                    const auto u = static_cast<std::size_t>(j);
                    return moving[u] && holder[u] != static_cast<int>(k);
                  }),
        ids.end());
      std::sort(ids.begin(), ids.end());
    }
    moved += now;
  }
  return moved;
}

} // namespace segmentation
} // namespace plantmorph
