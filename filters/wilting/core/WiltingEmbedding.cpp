// SPDX-License-Identifier: GPL-3.0-or-later
#include "WiltingEmbedding.h"

#include <array>
#include <cmath>
#include <limits>

namespace plantmorph
{

namespace
{
/// Catmull-Rom weights of the nodes at offsets -1, 0, 1, 2 for a local coordinate t in [0, 1].
std::array<double, 4> CatmullRom(double t)
{
  const double t2 = t * t;
  const double t3 = t2 * t;
  return { 0.5 * (-t3 + 2.0 * t2 - t), 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0), 0.5 * (-3.0 * t3 + 4.0 * t2 + t),
    0.5 * (t3 - t2) };
}
} // namespace

std::string WiltingEmbedding::Bind(const VoxelGrid& grid, const std::vector<Eigen::Vector3d>& points, bool tricubic)
{
  this->Voxel.assign(points.size(), -1);
  this->Offsets.assign(1, 0);
  this->Nodes.clear();
  this->Weights.clear();
  if (grid.voxels.empty())
  {
    return "the voxel model is empty";
  }
  for (std::size_t p = 0; p < points.size(); ++p)
  {
    const Eigen::Vector3d local = (points[p] - grid.origin) / grid.h;
    int voxel = -1;
    // The containing voxel (closed cube), lowest (k, j, i) first.
    std::array<int, 2> range[3];
    for (int axis = 0; axis < 3; ++axis)
    {
      const double f = std::floor(local[axis]);
      const int cell = static_cast<int>(f);
      range[axis] = { local[axis] == f ? cell - 1 : cell, cell };
    }
    for (int k = range[2][0]; k <= range[2][1] && voxel < 0; ++k)
    {
      for (int j = range[1][0]; j <= range[1][1] && voxel < 0; ++j)
      {
        for (int i = range[0][0]; i <= range[0][1] && voxel < 0; ++i)
        {
          voxel = grid.VoxelAt(i, j, k);
        }
      }
    }
    if (voxel < 0)
    {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t v = 0; v < grid.voxels.size(); ++v)
      {
        const Eigen::Vector3d centre(grid.voxels[v][0] + 0.5, grid.voxels[v][1] + 0.5, grid.voxels[v][2] + 0.5);
        const double d = (centre - local).squaredNorm();
        if (d < best)
        {
          best = d;
          voxel = static_cast<int>(v);
        }
      }
    }
    this->Voxel[p] = voxel;
    const std::array<int, 3>& cell = grid.voxels[static_cast<std::size_t>(voxel)];
    const Eigen::Vector3d t(local[0] - cell[0], local[1] - cell[1], local[2] - cell[2]);
    // Per axis: cubic (4 offsets) if allowed, else linear (2 offsets).
    std::array<bool, 3> cubic = { tricubic, tricubic, tricubic };
    const bool inside = t.minCoeff() >= 0.0 && t.maxCoeff() <= 1.0;
    if (!inside)
    {
      cubic = { false, false, false };
    }
    for (int attempt = 0; attempt < 4; ++attempt)
    {
      bool complete = true;
      for (int dk = cubic[2] ? -1 : 0; complete && dk <= (cubic[2] ? 2 : 1); ++dk)
      {
        for (int dj = cubic[1] ? -1 : 0; complete && dj <= (cubic[1] ? 2 : 1); ++dj)
        {
          for (int di = cubic[0] ? -1 : 0; complete && di <= (cubic[0] ? 2 : 1); ++di)
          {
            complete = grid.NodeAt(cell[0] + di, cell[1] + dj, cell[2] + dk) >= 0;
          }
        }
      }
      if (complete)
      {
        break;
      }
      // Drop the cubic axes one at a time: z first (the leaf's thickness), then y, then x.
      for (int axis = 2; axis >= 0; --axis)
      {
        if (cubic[static_cast<std::size_t>(axis)])
        {
          cubic[static_cast<std::size_t>(axis)] = false;
          break;
        }
      }
    }
    std::array<std::array<double, 4>, 3> w{};
    for (int axis = 0; axis < 3; ++axis)
    {
      if (cubic[static_cast<std::size_t>(axis)])
      {
        w[static_cast<std::size_t>(axis)] = CatmullRom(t[axis]);
      }
      else
      {
        w[static_cast<std::size_t>(axis)] = { 1.0 - t[axis], t[axis], 0.0, 0.0 };
      }
    }
    for (int dk = cubic[2] ? -1 : 0; dk <= (cubic[2] ? 2 : 1); ++dk)
    {
      for (int dj = cubic[1] ? -1 : 0; dj <= (cubic[1] ? 2 : 1); ++dj)
      {
        for (int di = cubic[0] ? -1 : 0; di <= (cubic[0] ? 2 : 1); ++di)
        {
          const double weight = w[0][static_cast<std::size_t>(di + (cubic[0] ? 1 : 0))] *
            w[1][static_cast<std::size_t>(dj + (cubic[1] ? 1 : 0))] *
            w[2][static_cast<std::size_t>(dk + (cubic[2] ? 1 : 0))];
          this->Nodes.push_back(grid.NodeAt(cell[0] + di, cell[1] + dj, cell[2] + dk));
          this->Weights.push_back(weight);
        }
      }
    }
    this->Offsets.push_back(this->Nodes.size());
  }
  return std::string();
}

void WiltingEmbedding::Interpolate(const double* nodeDisplacement, double* pointDisplacement) const
{
  this->InterpolateField(nodeDisplacement, 3, pointDisplacement);
}

void WiltingEmbedding::InterpolateField(const double* nodeField, int components, double* pointField) const
{
  const std::size_t c = static_cast<std::size_t>(components);
  for (std::size_t p = 0; p + 1 < this->Offsets.size(); ++p)
  {
    double* out = pointField + c * p;
    for (std::size_t k = 0; k < c; ++k)
    {
      out[k] = 0.0;
    }
    for (std::size_t e = this->Offsets[p]; e < this->Offsets[p + 1]; ++e)
    {
      const double* in = nodeField + c * static_cast<std::size_t>(this->Nodes[e]);
      for (std::size_t k = 0; k < c; ++k)
      {
        out[k] += this->Weights[e] * in[k];
      }
    }
  }
}

} // namespace plantmorph
