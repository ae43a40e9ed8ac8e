// SPDX-License-Identifier: GPL-3.0-or-later
// Leaf ids, separate blades, the plant's summary and the columns' units (LeafPlant.h).
#include "LeafPlant.h"
#include "LeafAreaEstimate.h"
#include "PointGrid.h"

#include <plantmorph/graph/DisjointSets.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <sstream>

namespace plantmorph
{
namespace
{
/// Cubes of side radius / sqrt(3): the points of one cube are within `radius` of each other. The occupied cubes in
/// lexicographic order of their (i, j, k); a cube's points are members[offsets[c], offsets[c + 1]).
struct Cubes
{
  using Cell = std::array<std::int64_t, 3>;
  std::vector<Cell> cells;
  std::vector<int> offsets, members;

  /// Sorts (cube, id) pairs, all different, into the one order: by a radix sort on the cube's offsets from the
  /// lowest (lexicographic when packed axis after axis) with the id below them when they fit in 32 bits, else by
  /// comparisons.
  static void SortCubes(const ParallelFor& parallel, std::vector<std::pair<Cell, int>>& keyed)
  {
    if (keyed.empty())
      return;
    Cell lo = keyed.front().first, hi = lo;
    for (const auto& item : keyed)
      for (int a = 0; a < 3; ++a)
      {
        lo[a] = std::min(lo[a], item.first[a]);
        hi[a] = std::max(hi[a], item.first[a]);
      }
    int bits[3] = { 0, 0, 0 };
    for (int a = 0; a < 3; ++a)
      while (bits[a] < 40 && (std::uint64_t(hi[a] - lo[a]) >> bits[a]) != 0)
        ++bits[a];
    const int total = bits[0] + bits[1] + bits[2];
    if (total > 32)
    {
      SortInParallel(parallel, keyed, std::less<std::pair<Cell, int>>());
      return;
    }
    std::vector<std::uint64_t> packed(keyed.size());
    ForEachIndex(parallel, keyed.size(), [&](std::size_t i) {
      const Cell& c = keyed[i].first;
      const std::uint64_t cube = (std::uint64_t(c[0] - lo[0]) << (bits[1] + bits[2])) |
        (std::uint64_t(c[1] - lo[1]) << bits[2]) | std::uint64_t(c[2] - lo[2]);
      packed[i] = cube << 32 | static_cast<std::uint32_t>(keyed[i].second);
    });
    SortKeysInParallel(parallel, packed, 32, 32 + total);
    std::vector<std::pair<Cell, int>> sorted(keyed.size());
    ForEachIndex(parallel, keyed.size(), [&](std::size_t i) { sorted[i] = keyed[packed[i] & 0xffffffffu]; });
    keyed.swap(sorted);
  }

  Cubes(const std::vector<Eigen::Vector3d>& points, double side, const ParallelFor& parallel)
  {
    std::vector<std::pair<Cell, int>> keyed(points.size());
    ForEachIndex(parallel, points.size(), [&](std::size_t i) {
      keyed[i] = { { static_cast<std::int64_t>(std::floor(points[i].x() / side)),
                     static_cast<std::int64_t>(std::floor(points[i].y() / side)),
                     static_cast<std::int64_t>(std::floor(points[i].z() / side)) },
        static_cast<int>(i) };
    });
    SortCubes(parallel, keyed);
    this->members.resize(keyed.size());
    for (std::size_t i = 0; i < keyed.size(); ++i)
    {
      if (i == 0 || keyed[i].first != keyed[i - 1].first)
      {
        this->cells.push_back(keyed[i].first);
        this->offsets.push_back(static_cast<int>(i));
      }
      this->members[i] = keyed[i].second;
    }
    this->offsets.push_back(static_cast<int>(keyed.size()));
  }
};

/// True when a point of cube a is within sqrt(r2) of a point of cube b.
bool Near(const std::vector<Eigen::Vector3d>& points, const Cubes& cubes, int a, int b, double r2)
{
  for (int i = cubes.offsets[a]; i < cubes.offsets[a + 1]; ++i)
    for (int j = cubes.offsets[b]; j < cubes.offsets[b + 1]; ++j)
      if ((points[cubes.members[i]] - points[cubes.members[j]]).squaredNorm() <= r2)
        return true;
  return false;
}

/// The offsets from a cube to the cubes it may join: up to two apart along each axis, each pair once (the offsets
/// after (0, 0, 0) in lexicographic order), the adjacent ones first, so that on a continuous sheet the farther ones
/// are mostly joined already when they come and need no search.
std::vector<Cubes::Cell> JoinOffsets()
{
  std::vector<Cubes::Cell> offsets;
  for (std::int64_t reach = 1; reach <= 2; ++reach)
    for (std::int64_t dx = 0; dx <= reach; ++dx)
      for (std::int64_t dy = -reach; dy <= reach; ++dy)
        for (std::int64_t dz = -reach; dz <= reach; ++dz)
        {
          const Cubes::Cell d = { dx, dy, dz };
          if (d > Cubes::Cell{ 0, 0, 0 } && std::max({ std::abs(dx), std::abs(dy), std::abs(dz) }) == reach)
            offsets.push_back(d);
        }
  return offsets;
}

/// Connected parts of the points at `radius`, as parts of the cubes (a cube's points are one part): two cubes up to
/// two apart along each axis are joined when any of their points are within `radius`, looked for only while they are
/// apart. Each part is named by its first cube (a union keeps the smaller root), so the parts and their names do not
/// depend on the order the pairs are joined in. The cubes are cut into blocks of consecutive cubes joined side by
/// side: a block joins its own pairs (writing only its own cubes' parents, which stay in the block) and lists the
/// pairs that reach a later block, joined after, one block after the other. Each offset is one merge-like walk over
/// a block's sorted cubes (adding an offset keeps their order): no hashing, memory in order.
std::vector<int> CubeParts(
  const std::vector<Eigen::Vector3d>& points, const Cubes& cubes, double radius, const ParallelFor& parallel)
{
  const int m = static_cast<int>(cubes.cells.size());
  DisjointSets<int> parts(static_cast<std::size_t>(m));
  const double r2 = radius * radius;
  const std::vector<Cubes::Cell> offsets = JoinOffsets();
  const int blocks = std::clamp(m / 512, 1, 64);
  std::vector<std::vector<std::pair<int, int>>> later(blocks);
  parallel(static_cast<std::size_t>(blocks), [&](std::size_t firstBlock, std::size_t lastBlock) {
    for (std::size_t block = firstBlock; block < lastBlock; ++block)
    {
      const int lo = static_cast<int>(static_cast<std::int64_t>(m) * block / blocks);
      const int hi = static_cast<int>(static_cast<std::int64_t>(m) * (block + 1) / blocks);
      for (const Cubes::Cell& d : offsets)
      {
        const auto shifted = [&](int a) {
          const Cubes::Cell& c = cubes.cells[a];
          return Cubes::Cell{ c[0] + d[0], c[1] + d[1], c[2] + d[2] };
        };
        int b = lo < hi ? static_cast<int>(
                            std::lower_bound(cubes.cells.begin(), cubes.cells.end(), shifted(lo)) - cubes.cells.begin())
                        : m;
        for (int a = lo; a < hi && b < m; ++a)
        {
          const Cubes::Cell target = shifted(a);
          while (b < m && cubes.cells[b] < target)
            ++b;
          if (b == m || cubes.cells[b] != target)
            continue;
          if (b >= hi)
          {
            later[block].emplace_back(a, b);
            continue;
          }
          const int ra = parts.Find(a), rb = parts.Find(b);
          if (ra != rb && Near(points, cubes, a, b, r2))
            parts.JoinRoots(ra, rb);
        }
      }
    }
  });
  for (const auto& pairs : later)
    for (const auto& [a, b] : pairs)
    {
      const int ra = parts.Find(a), rb = parts.Find(b);
      if (ra != rb && Near(points, cubes, a, b, r2))
        parts.JoinRoots(ra, rb);
    }
  // Every parent precedes its cube: in cube order, a cube's root is its parent's.
  std::vector<int>& parent = parts.Links();
  for (int c = 0; c < m; ++c)
    parent[c] = parent[parent[c]];
  return std::move(parent);
}
} // namespace

std::string LeafIdOf(double value, const std::string& array, std::int64_t& id)
{
  // 2^63 is exact in double; every double below it in magnitude that is an integer converts exactly.
  const double limit = 9223372036854775808.0;
  if (std::isfinite(value) && std::floor(value) == value && value >= -limit && value < limit)
  {
    id = static_cast<std::int64_t>(value);
    return {};
  }
  std::ostringstream message;
  message.precision(17);
  message << "LeafIdArray: '" << array << "' holds " << value
          << (std::isfinite(value) ? ", not an integer" : ", not a number")
          << ": leaf ids must be integers (an integer array, or whole numbers in a floating-point one)";
  return message.str();
}

LeafSeparation SeparateLeaves(const std::vector<Eigen::Vector3d>& points, const ParallelFor& parallel)
{
  LeafSeparation result;
  result.leafOf.assign(points.size(), 0);
  result.count = 1;
  std::vector<int> finite;
  std::vector<Eigen::Vector3d> finitePoints;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i].allFinite())
    {
      finite.push_back(static_cast<int>(i));
      finitePoints.push_back(points[i]);
    }
  if (finitePoints.size() < 2)
    return result;
  // The spacing across the points' densest direction as well: a line scan's points are much closer along a line
  // than the lines are, and a radius from the nearest-neighbour spacing alone cuts one leaf into its lines. Both
  // spacings search one grid.
  {
    const PointGrid grid(finitePoints, PointGrid::CellFor(finitePoints, 4.0), parallel);
    result.radius = SeparationSpacings *
      std::max(MedianSpacing(finitePoints, grid, parallel), CrossSpacing(finitePoints, grid, parallel));
  }
  if (!(result.radius > 0.0))
    return result;
  const Cubes cubes(finitePoints, result.radius / std::sqrt(3.0), parallel);
  const std::vector<int> root = CubeParts(finitePoints, cubes, result.radius, parallel);
  const int m = static_cast<int>(finitePoints.size());
  std::vector<int> partOf(m);
  ForEachIndex(parallel, cubes.cells.size(), [&](std::size_t c) {
    for (int k = cubes.offsets[c]; k < cubes.offsets[c + 1]; ++k)
      partOf[cubes.members[k]] = root[c];
  });
  std::vector<int> size(cubes.cells.size(), 0);
  for (int i = 0; i < m; ++i)
    ++size[partOf[i]];
  const int largest = *std::max_element(size.begin(), size.end());
  // The large parts, numbered in the order of their first point.
  std::vector<int> leafOfPart(cubes.cells.size(), -1);
  int count = 0;
  std::vector<Eigen::Vector3d> leafPoints;
  std::vector<int> leafIds;
  for (int i = 0; i < m; ++i)
  {
    const int part = partOf[i];
    if (leafOfPart[part] < 0 && size[part] >= MinLeafPoints && size[part] * 20 >= largest)
      leafOfPart[part] = count++;
    if (leafOfPart[part] >= 0)
    {
      leafPoints.push_back(finitePoints[i]);
      leafIds.push_back(leafOfPart[part]);
    }
  }
  if (count <= 1)
    return result;
  // The small parts' points go with the nearest leaf.
  const PointGrid leaves(leafPoints, PointGrid::CellFor(leafPoints, 4.0), parallel);
  std::vector<unsigned char> seen(cubes.cells.size(), 0);
  for (int i = 0; i < m; ++i)
  {
    int leaf = leafOfPart[partOf[i]];
    if (leaf < 0)
    {
      leaf = leafIds[leaves.Nearest(finitePoints[i], 1).front().second];
      result.strayParts += seen[partOf[i]] ? 0 : 1;
      seen[partOf[i]] = 1;
    }
    result.leafOf[finite[i]] = leaf;
  }
  result.count = count;
  return result;
}

BetaFit FitBetaDistribution(const std::vector<double>& degrees)
{
  BetaFit beta;
  std::vector<double> t;
  for (double d : degrees)
    if (std::isfinite(d))
      t.push_back(std::clamp(d / 90.0, 0.0, 1.0));
  if (t.size() < 2)
    return beta;
  const double n = static_cast<double>(t.size());
  const double mean = std::accumulate(t.begin(), t.end(), 0.0) / n;
  double variance = 0.0;
  for (double x : t)
    variance += (x - mean) * (x - mean);
  variance /= n;
  if (!(variance > 0.0) || !(mean > 0.0 && mean < 1.0))
    return beta;
  const double common = mean * (1.0 - mean) / variance - 1.0;
  if (!(common > 0.0))
    return beta; // more spread than any beta distribution has (all angles at 0 and 90)
  beta.nu = mean * common;
  beta.mu = (1.0 - mean) * common;
  beta.valid = true;
  return beta;
}

double BetaDensity(const BetaFit& beta, double degrees)
{
  const double t = degrees / 90.0;
  if (!beta.valid || !(t > 0.0 && t < 1.0))
    return 0.0;
  const double logB = std::lgamma(beta.mu) + std::lgamma(beta.nu) - std::lgamma(beta.mu + beta.nu);
  return std::exp((beta.nu - 1.0) * std::log(t) + (beta.mu - 1.0) * std::log1p(-t) - logB) / 90.0;
}

PlantSummary SummarizePlant(
  const std::vector<LeafTraits>& traits, const std::vector<bool>& fitted, double unassignedLeafPoints)
{
  PlantSummary plant;
  plant.unassignedLeafPoints = unassignedLeafPoints;
  plant.inclinationFraction.assign(InclinationClasses, 0.0);
  std::vector<double> angles;
  for (std::size_t i = 0; i < traits.size(); ++i)
  {
    if (i < fitted.size() && !fitted[i])
    {
      ++plant.failed;
      continue;
    }
    ++plant.leaves;
    plant.totalArea += traits[i].area;
    angles.push_back(traits[i].inclination);
  }
  if (plant.leaves == 0)
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    plant.meanArea = plant.meanInclination = plant.totalEstimatedArea = nan;
    plant.unassignedLeafArea = unassignedLeafPoints > 0.0 ? nan : 0.0;
    return plant;
  }
  plant.meanArea = plant.totalArea / plant.leaves;
  plant.meanInclination = std::accumulate(angles.begin(), angles.end(), 0.0) / plant.leaves;
  for (double a : angles)
  {
    const int k = std::clamp(static_cast<int>(std::floor(a / 10.0)), 0, InclinationClasses - 1);
    plant.inclinationFraction[k] += 1.0 / plant.leaves;
  }
  plant.beta = FitBetaDistribution(angles);
  const LeafAreaEstimates estimates = EstimateLeafAreas(traits, fitted);
  for (std::size_t i = 0; i < traits.size(); ++i)
    if (!(i < fitted.size() && !fitted[i]))
      plant.totalEstimatedArea += estimates.area[i];
  plant.wholeLeaves = estimates.shape.valid ? estimates.shape.wholeLeaves : 0;
  plant.unassignedLeafArea = UnassignedLeafArea(traits, fitted, unassignedLeafPoints);
  if (std::isfinite(plant.unassignedLeafArea))
    plant.totalEstimatedArea += plant.unassignedLeafArea;
  return plant;
}

std::vector<std::string> PlantColumnNames()
{
  std::vector<std::string> names = { "LeafCount", "FailedLeaves", "TotalLeafArea", "MeanLeafArea",
    "MeanLeafInclination", "InclinationBetaMu", "InclinationBetaNu" };
  for (int k = 0; k < InclinationClasses; ++k)
    names.push_back("Inclination" + std::to_string(10 * k) + "_" + std::to_string(10 * k + 10));
  names.push_back("TotalEstimatedLeafArea");
  names.push_back("WholeLeaves");
  names.push_back("UnassignedLeafPoints");
  names.push_back("UnassignedLeafArea");
  return names;
}

std::vector<double> PlantColumnValues(const PlantSummary& plant)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> values = { static_cast<double>(plant.leaves), static_cast<double>(plant.failed), plant.totalArea,
    plant.meanArea, plant.meanInclination, plant.beta.valid ? plant.beta.mu : nan,
    plant.beta.valid ? plant.beta.nu : nan };
  for (int k = 0; k < InclinationClasses; ++k)
    values.push_back(k < static_cast<int>(plant.inclinationFraction.size()) ? plant.inclinationFraction[k] : nan);
  values.push_back(plant.totalEstimatedArea);
  values.push_back(static_cast<double>(plant.wholeLeaves));
  values.push_back(plant.unassignedLeafPoints);
  values.push_back(plant.unassignedLeafArea);
  return values;
}

std::string ColumnUnit(const std::string& column, const std::string& lengthUnit)
{
  const std::string L = lengthUnit.empty() ? "L" : lengthUnit;
  static const std::map<std::string, int> kinds = {
    // 0 length, 1 area, 2 1/length, 3 degrees, 4 dimensionless, 5 count, 6 code or id, 7 text
    { "Length", 0 }, { "Width", 0 }, { "ProjectedLength", 0 }, { "ProjectedWidth", 0 }, { "Perimeter", 0 },
    { "FitRMS", 0 }, { "FitP95", 0 }, { "FitMax", 0 }, { "Spacing", 0 }, { "PetioleLength", 0 }, { "Area", 1 },
    { "ProjectedArea", 1 }, { "HorizontalArea", 1 }, { "TotalLeafArea", 1 }, { "MeanLeafArea", 1 },
    { "EstimatedArea", 1 }, { "TotalEstimatedLeafArea", 1 }, { "AreaRule", 6 }, { "WholeLeaves", 5 },
    { "UnassignedLeafPoints", 5 }, { "UnassignedLeafArea", 1 }, { "RollingCurvature", 2 }, { "Bending", 3 },
    { "Rolling", 3 }, { "Inclination", 3 }, { "Azimuth", 3 }, { "MidveinInclination", 3 }, { "MeanLeafInclination", 3 },
    { "AspectRatio", 4 }, { "Coverage", 4 }, { "HiddenMargin", 4 }, { "InclinationBetaMu", 4 },
    { "InclinationBetaNu", 4 }, { "Points", 5 }, { "Inliers", 5 }, { "LeafCount", 5 }, { "FailedLeaves", 5 },
    { "LeafId", 6 }, { "BaseFrom", 6 }, { "ExtentsSeen", 6 }, { "Status", 6 }, { "Message", 7 }, { "LengthUnit", 7 }
  };
  const auto it = kinds.find(column);
  if (it == kinds.end())
    return column.rfind("Inclination", 0) == 0 && column.find('_') != std::string::npos ? "1" : "";
  switch (it->second)
  {
    case 0:
      return L;
    case 1:
      return L + "^2";
    case 2:
      return "1/" + L;
    case 3:
      return "degrees";
    case 4:
      return "1";
    case 5:
      return "count";
    case 6:
      return "code";
    default:
      return "text";
  }
}

std::string ScaledUnit(const std::string& unit, double scale)
{
  if (unit.empty() || !(scale > 0.0) || !std::isfinite(scale))
    return {};
  static const std::vector<std::pair<std::string, double>> metres = { { "km", 1e3 }, { "m", 1.0 }, { "dm", 0.1 },
    { "cm", 1e-2 }, { "mm", 1e-3 }, { "um", 1e-6 }, { "nm", 1e-9 } };
  double size = 0.0;
  for (const auto& u : metres)
    if (u.first == unit)
      size = u.second;
  if (scale == 1.0)
    return unit;
  if (size > 0.0)
    for (const auto& u : metres)
      if (std::abs(size / scale / u.second - 1.0) < 1e-9)
        return u.first;
  std::ostringstream name;
  name.precision(12);
  name << "(" << 1.0 / scale << " " << unit << ")";
  return name.str();
}

} // namespace plantmorph
