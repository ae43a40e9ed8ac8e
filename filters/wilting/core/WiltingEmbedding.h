// SPDX-License-Identifier: GPL-3.0-or-later
// Embedding of the input leaf in the wilting voxel model (docs/methods/wilting.md; paper 001 sec. 2, end).
// Plain C++17 + Eigen, no VTK.
//
// Bind() finds each input point's voxel once: the kept voxel whose closed cube contains it (the lowest (k, j, i)
// one when it lies on a shared face), or else the kept voxel whose centre is nearest (a line point just outside the
// voxelised surface; its local coordinates then lie outside [0, 1] and the interpolation extrapolates linearly).
// Interpolate() moves every point by the interpolation of the node displacements:
//   - trilinear: the eight corners of its voxel, weights (1-x or x)(1-y or y)(1-z or z) of the local coordinates;
//   - tricubic (optional): Catmull-Rom (cubic convolution) weights over the 4 x 4 x 4 nodes around the voxel along
//     every axis whose outer nodes all exist, and linear weights along the others (a one- or two-layer leaf has no
//     outer layers in z, so it is bicubic in the leaf's plane there). Catmull-Rom reproduces linear fields, so both
//     schemes give back the input exactly for zero displacement and any affine motion.
#pragma once

#include "WiltingVoxelizer.h"

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace plantmorph
{

class WiltingEmbedding
{
public:
  /// Binds the points (once). Empty on success, else a message (no voxels).
  std::string Bind(const VoxelGrid& grid, const std::vector<Eigen::Vector3d>& points, bool tricubic);

  /// Displacement of every bound point (3 per point) from the node displacements (3 per node).
  void Interpolate(const double* nodeDisplacement, double* pointDisplacement) const;
  /// Any per-node field of `components` values per node, interpolated to the points.
  void InterpolateField(const double* nodeField, int components, double* pointField) const;

  std::size_t PointCount() const { return this->Offsets.empty() ? 0 : this->Offsets.size() - 1; }
  /// The voxel each point was bound to.
  const std::vector<int>& Voxels() const { return this->Voxel; }

private:
  std::vector<int> Voxel;
  std::vector<std::size_t> Offsets; // per point into Nodes/Weights
  std::vector<int> Nodes;
  std::vector<double> Weights;
};

} // namespace plantmorph
