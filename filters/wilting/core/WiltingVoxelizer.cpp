// SPDX-License-Identifier: GPL-3.0-or-later
#include "WiltingVoxelizer.h"

#include <plantmorph/RangeError.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

namespace plantmorph
{

namespace
{
/// The grid's order of cells and nodes: by (k, j, i).
bool CellBefore(const std::array<int, 3>& p, const std::array<int, 3>& q)
{
  return std::tie(p[2], p[1], p[0]) < std::tie(q[2], q[1], q[0]);
}
} // namespace

bool TriangleBoxOverlap(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
  const Eigen::Vector3d& low, const Eigen::Vector3d& high)
{
  const Eigen::Vector3d center = 0.5 * (low + high);
  const Eigen::Vector3d half = 0.5 * (high - low);
  const Eigen::Vector3d v[3] = { a - center, b - center, c - center };
  // The box's face normals: the triangle's bounding box against the box.
  for (int axis = 0; axis < 3; ++axis)
  {
    const double lo = std::min({ v[0][axis], v[1][axis], v[2][axis] });
    const double hi = std::max({ v[0][axis], v[1][axis], v[2][axis] });
    if (lo > half[axis] || hi < -half[axis])
    {
      return false;
    }
  }
  const Eigen::Vector3d e[3] = { v[1] - v[0], v[2] - v[1], v[0] - v[2] };
  // The nine cross products of the box's axes with the triangle's edges.
  for (int i = 0; i < 3; ++i)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      Eigen::Vector3d unit = Eigen::Vector3d::Zero();
      unit[axis] = 1.0;
      const Eigen::Vector3d p = unit.cross(e[i]);
      if (p.squaredNorm() == 0.0)
      {
        continue;
      }
      const double p0 = p.dot(v[0]);
      const double p1 = p.dot(v[1]);
      const double p2 = p.dot(v[2]);
      const double radius = half[0] * std::abs(p[0]) + half[1] * std::abs(p[1]) + half[2] * std::abs(p[2]);
      if (std::min({ p0, p1, p2 }) > radius || std::max({ p0, p1, p2 }) < -radius)
      {
        return false;
      }
    }
  }
  // The triangle's plane.
  const Eigen::Vector3d normal = e[0].cross(e[1]);
  const double distance = normal.dot(v[0]);
  const double radius = half[0] * std::abs(normal[0]) + half[1] * std::abs(normal[1]) + half[2] * std::abs(normal[2]);
  return std::abs(distance) <= radius;
}

int RegionPriority(int region)
{
  switch (region)
  {
    case 5:
      return 5;
    case 1:
      return 4;
    case 2:
      return 3;
    case 4:
      return 2;
    case 3:
      return 1;
    default:
      return 0;
  }
}

int VoxelGrid::VoxelAt(int i, int j, int k) const
{
  if (i < 0 || j < 0 || k < 0 || i >= this->dims[0] || j >= this->dims[1] || k >= this->dims[2])
  {
    return -1;
  }
  return this->voxelLookup[(static_cast<std::size_t>(k) * static_cast<std::size_t>(this->dims[1]) +
                             static_cast<std::size_t>(j)) *
      static_cast<std::size_t>(this->dims[0]) +
    static_cast<std::size_t>(i)];
}

int VoxelGrid::NodeAt(int i, int j, int k) const
{
  if (i < 0 || j < 0 || k < 0 || i > this->dims[0] || j > this->dims[1] || k > this->dims[2])
  {
    return -1;
  }
  return this->nodeLookup[(static_cast<std::size_t>(k) * static_cast<std::size_t>(this->dims[1] + 1) +
                            static_cast<std::size_t>(j)) *
      static_cast<std::size_t>(this->dims[0] + 1) +
    static_cast<std::size_t>(i)];
}

void VoxelGrid::BuildLookup()
{
  const std::size_t nx = static_cast<std::size_t>(this->dims[0]);
  const std::size_t ny = static_cast<std::size_t>(this->dims[1]);
  const std::size_t nz = static_cast<std::size_t>(this->dims[2]);
  this->voxelLookup.assign(nx * ny * nz, -1);
  for (std::size_t v = 0; v < this->voxels.size(); ++v)
  {
    const std::array<int, 3>& c = this->voxels[v];
    this->voxelLookup[(static_cast<std::size_t>(c[2]) * ny + static_cast<std::size_t>(c[1])) * nx +
      static_cast<std::size_t>(c[0])] = static_cast<int>(v);
  }
  this->nodeLookup.assign((nx + 1) * (ny + 1) * (nz + 1), -1);
  for (std::size_t n = 0; n < this->nodeIndex.size(); ++n)
  {
    const std::array<int, 3>& c = this->nodeIndex[n];
    this->nodeLookup[(static_cast<std::size_t>(c[2]) * (ny + 1) + static_cast<std::size_t>(c[1])) * (nx + 1) +
      static_cast<std::size_t>(c[0])] = static_cast<int>(n);
  }
}

void VoxelGrid::BuildNodes()
{
  // Nodes: the corners of kept cells.
  std::vector<std::array<int, 3>> corners;
  corners.reserve(8 * this->voxels.size());
  for (const std::array<int, 3>& v : this->voxels)
  {
    for (int dk = 0; dk < 2; ++dk)
    {
      for (int dj = 0; dj < 2; ++dj)
      {
        for (int di = 0; di < 2; ++di)
        {
          corners.push_back({ v[0] + di, v[1] + dj, v[2] + dk });
        }
      }
    }
  }
  std::sort(corners.begin(), corners.end(), CellBefore);
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  this->nodeIndex = corners;
  this->nodes.clear();
  this->nodes.reserve(corners.size());
  for (const std::array<int, 3>& c : corners)
  {
    this->nodes.push_back(this->origin + this->h * Eigen::Vector3d(c[0], c[1], c[2]));
  }
  this->BuildLookup();
  this->corners.clear();
  this->corners.reserve(this->voxels.size());
  for (const std::array<int, 3>& v : this->voxels)
  {
    const int i = v[0];
    const int j = v[1];
    const int k = v[2];
    this->corners.push_back({ this->NodeAt(i, j, k), this->NodeAt(i + 1, j, k), this->NodeAt(i + 1, j + 1, k),
      this->NodeAt(i, j + 1, k), this->NodeAt(i, j, k + 1), this->NodeAt(i + 1, j, k + 1),
      this->NodeAt(i + 1, j + 1, k + 1), this->NodeAt(i, j + 1, k + 1) });
  }
}

std::string Voxelize(const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& triangles,
  const std::vector<int>& regions, const VoxelizeParameters& options, VoxelGrid& grid)
{
  grid = VoxelGrid();
  if (points.empty() || triangles.empty())
  {
    return "the input has no triangles to voxelise (WiltingSimulator needs a leaf surface)";
  }
  if (!regions.empty() && regions.size() != points.size())
  {
    return "the Region array does not have one value per point";
  }
  Eigen::Vector3d low = points[0];
  Eigen::Vector3d high = points[0];
  for (const Eigen::Vector3d& p : points)
  {
    if (!p.allFinite())
    {
      return "the input has a non-finite point coordinate";
    }
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  for (const std::array<int, 3>& t : triangles)
  {
    for (int id : t)
    {
      if (id < 0 || static_cast<std::size_t>(id) >= points.size())
      {
        return "a triangle refers to a point that does not exist";
      }
    }
  }
  const Eigen::Vector3d extent = high - low;
  const double longest = extent.maxCoeff();
  if (!(longest > 0.0))
  {
    return "the input's points all coincide: nothing to voxelise";
  }
  double h = options.voxelSize;
  if (!(h > 0.0))
  {
    if (options.resolution < 1)
    {
      return OutOfRange("Resolution", options.resolution, "[1, inf)", "when VoxelSize is 0");
    }
    h = longest / options.resolution;
  }
  std::array<int, 3> dims{};
  double cells = 1.0;
  for (int axis = 0; axis < 3; ++axis)
  {
    const double count = std::max(1.0, std::ceil(extent[axis] / h * (1.0 - 1e-12)));
    cells *= count;
    if (count > 1e7 || cells > 1e12)
    {
      std::ostringstream message;
      message << "VoxelSize " << h << " is too small for a leaf of size " << longest << " (grid too large)";
      return message.str();
    }
    dims[axis] = static_cast<int>(count);
  }
  Eigen::Vector3d origin;
  for (int axis = 0; axis < 3; ++axis)
  {
    origin[axis] = 0.5 * (low[axis] + high[axis]) - 0.5 * h * dims[axis];
  }
  for (int axis = 0; axis < 3; ++axis)
  {
    const double local = (options.alignAt[axis] - origin[axis]) / h;
    const double offset = local - std::round(local);
    if (options.align[static_cast<std::size_t>(axis)] && std::abs(offset) > 1e-9)
    {
      origin[axis] += (offset > 0.0 ? offset - 1.0 : offset) * h;
      dims[axis] += 1;
    }
  }
  grid.origin = origin;
  grid.h = h;
  grid.dims = dims;
  // Candidate cells of each triangle's bounding box, tested exactly.
  std::vector<std::array<int, 3>> kept;
  const auto cellOf = [&](double x, int axis) {
    return std::clamp(static_cast<int>(std::floor((x - origin[axis]) / h)), 0, dims[axis] - 1);
  };
  for (const std::array<int, 3>& t : triangles)
  {
    const Eigen::Vector3d& a = points[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d& b = points[static_cast<std::size_t>(t[1])];
    const Eigen::Vector3d& c = points[static_cast<std::size_t>(t[2])];
    const Eigen::Vector3d tlow = a.cwiseMin(b).cwiseMin(c);
    const Eigen::Vector3d thigh = a.cwiseMax(b).cwiseMax(c);
    // One cell of slack on each side: a triangle on a cell face touches both cells.
    std::array<int, 3> from{};
    std::array<int, 3> to{};
    for (int axis = 0; axis < 3; ++axis)
    {
      from[axis] = std::max(0, cellOf(tlow[axis], axis) - 1);
      to[axis] = std::min(dims[axis] - 1, cellOf(thigh[axis], axis) + 1);
    }
    for (int k = from[2]; k <= to[2]; ++k)
    {
      for (int j = from[1]; j <= to[1]; ++j)
      {
        for (int i = from[0]; i <= to[0]; ++i)
        {
          const Eigen::Vector3d cellLow = origin + h * Eigen::Vector3d(i, j, k);
          if (TriangleBoxOverlap(a, b, c, cellLow, cellLow + Eigen::Vector3d::Constant(h)))
          {
            kept.push_back({ i, j, k });
          }
        }
      }
    }
    if (kept.size() > 8 * options.maxVoxels)
    {
      kept.clear();
      std::ostringstream message;
      message << "the voxel model would exceed " << options.maxVoxels << " voxels: increase VoxelSize";
      return message.str();
    }
  }
  std::sort(kept.begin(), kept.end(), CellBefore);
  kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
  if (kept.size() > options.maxVoxels)
  {
    std::ostringstream message;
    message << "the voxel model would have " << kept.size() << " voxels, more than " << options.maxVoxels
            << ": increase VoxelSize";
    return message.str();
  }
  grid.voxels = kept;
  grid.BuildNodes();
  // Regions: the most significant Region of the points in each voxel (closed cube: a point on a face counts for
  // every voxel sharing it).
  grid.regions.assign(kept.size(), 0);
  if (!regions.empty())
  {
    std::vector<int> best(kept.size(), -1);
    for (std::size_t p = 0; p < points.size(); ++p)
    {
      const Eigen::Vector3d local = (points[p] - origin) / h;
      std::array<int, 2> range[3];
      for (int axis = 0; axis < 3; ++axis)
      {
        const double f = std::floor(local[axis]);
        const int cell = static_cast<int>(f);
        range[axis] = { local[axis] == f ? cell - 1 : cell, cell };
      }
      for (int k = range[2][0]; k <= range[2][1]; ++k)
      {
        for (int j = range[1][0]; j <= range[1][1]; ++j)
        {
          for (int i = range[0][0]; i <= range[0][1]; ++i)
          {
            const int v = grid.VoxelAt(i, j, k);
            if (v >= 0 && RegionPriority(regions[p]) > best[static_cast<std::size_t>(v)])
            {
              best[static_cast<std::size_t>(v)] = RegionPriority(regions[p]);
              grid.regions[static_cast<std::size_t>(v)] = regions[p];
            }
          }
        }
      }
    }
  }
  return std::string();
}

void WidenMidvein(
  const std::vector<Eigen::Vector3d>& points, const std::vector<std::size_t>& midvein, int across, VoxelGrid& grid)
{
  for (const std::size_t p : midvein)
  {
    const Eigen::Vector3d local = (points[p] - grid.origin) / grid.h;
    std::array<int, 2> range[3];
    for (int axis = 0; axis < 3; ++axis)
    {
      // Across: the two cells nearest the point (whose shared face is its nearest); along and in z: the cells
      // holding it (closed, as Voxelize's regions).
      const double f = std::floor(axis == across ? local[axis] - 0.5 : local[axis]);
      const int cell = static_cast<int>(f);
      range[axis] = axis == across ? std::array<int, 2>{ cell, cell + 1 }
                                   : std::array<int, 2>{ local[axis] == f ? cell - 1 : cell, cell };
    }
    for (int k = range[2][0]; k <= range[2][1]; ++k)
    {
      for (int j = range[1][0]; j <= range[1][1]; ++j)
      {
        for (int i = range[0][0]; i <= range[0][1]; ++i)
        {
          const int v = grid.VoxelAt(i, j, k);
          if (v >= 0 && RegionPriority(grid.regions[static_cast<std::size_t>(v)]) < RegionPriority(1))
          {
            grid.regions[static_cast<std::size_t>(v)] = 1;
          }
        }
      }
    }
  }
}

std::string AddPetiole(
  VoxelGrid& grid, const Eigen::Vector3d& base, double length, std::size_t maxVoxels, PetiolePlacement& petiole)
{
  petiole = PetiolePlacement();
  if (!(length > 0.0) || !std::isfinite(length))
  {
    return OutOfRange("PetioleLength", length, "(0, inf)", "to add a petiole");
  }
  const double h = grid.h;
  const double rows = std::max(1.0, std::round(length / h));
  if (rows > 1e6 || grid.voxels.size() + static_cast<std::size_t>(rows) * 4 > maxVoxels)
  {
    std::ostringstream message;
    message << "PetioleLength " << length << " is too long for voxels of " << h << " (more than " << maxVoxels
            << " voxels)";
    return message.str();
  }
  const int n = static_cast<int>(rows);
  // The cells whose closed x (z) range holds the base: one, or two when the base lies on a cell face.
  const auto around = [&](int axis) {
    const double local = (base[axis] - grid.origin[axis]) / h;
    const double cell = std::floor(local + 0.5);
    const int upper = std::clamp(static_cast<int>(std::floor(local)), 0, grid.dims[axis] - 1);
    if (std::abs(local - cell) <= 1e-6 && cell >= 1.0 && cell <= grid.dims[axis] - 1.0)
    {
      return std::array<int, 2>{ static_cast<int>(cell) - 1, static_cast<int>(cell) };
    }
    return std::array<int, 2>{ upper, upper };
  };
  const std::array<int, 2> columns = around(0);
  const std::array<int, 2> layers = around(2);
  const int baseRow = std::clamp(static_cast<int>(std::floor((base[1] - grid.origin[1]) / h)), 0, grid.dims[1] - 1);
  // Rows baseRow - 1 down to baseRow - n; the grid grows by `shift` rows at its -y end when they leave it.
  const int shift = std::max(0, n - baseRow);
  const std::vector<std::array<int, 3>> blade = std::move(grid.voxels);
  const std::vector<int> bladeRegions = std::move(grid.regions);
  std::vector<std::array<int, 3>> added;
  for (int j = baseRow - n; j < baseRow; ++j)
  {
    for (int k = layers[0]; k <= layers[1]; ++k)
    {
      for (int i = columns[0]; i <= columns[1]; ++i)
      {
        added.push_back({ i, j + shift, k });
      }
    }
  }
  grid.voxels.clear();
  grid.voxels.reserve(blade.size() + added.size());
  for (const std::array<int, 3>& c : blade)
  {
    grid.voxels.push_back({ c[0], c[1] + shift, c[2] });
  }
  grid.voxels.insert(grid.voxels.end(), added.begin(), added.end());
  std::sort(grid.voxels.begin(), grid.voxels.end(), CellBefore);
  grid.voxels.erase(std::unique(grid.voxels.begin(), grid.voxels.end()), grid.voxels.end());
  grid.dims[1] += shift;
  grid.origin[1] -= shift * h;
  grid.BuildNodes();
  // Regions: the blade's cells keep theirs, the petiole's (new or on its path) are petiole (5).
  grid.regions.assign(grid.voxels.size(), 5);
  for (std::size_t v = 0; v < blade.size(); ++v)
  {
    grid.regions[static_cast<std::size_t>(grid.VoxelAt(blade[v][0], blade[v][1] + shift, blade[v][2]))] =
      bladeRegions[v];
  }
  for (const std::array<int, 3>& c : added)
  {
    grid.regions[static_cast<std::size_t>(grid.VoxelAt(c[0], c[1], c[2]))] = 5;
  }
  petiole.voxels = static_cast<int>(added.size());
  petiole.shift = shift;
  const int endRow = baseRow - n + shift;
  for (int k = layers[0]; k <= layers[1] + 1; ++k)
  {
    for (int i = columns[0]; i <= columns[1] + 1; ++i)
    {
      petiole.endNodes.push_back(grid.NodeAt(i, endRow, k));
    }
  }
  petiole.end = Eigen::Vector3d(base[0], grid.origin[1] + h * endRow, base[2]);
  petiole.length = base[1] - petiole.end[1];
  return std::string();
}

} // namespace plantmorph
