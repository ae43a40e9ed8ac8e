// SPDX-License-Identifier: GPL-3.0-or-later
// Voxelisation of a leaf surface for WiltingSimulator (docs/methods/wilting.md; paper 001 sec. 1, Figs. 1-2). Plain
// C++17 + Eigen, no VTK.
//
// The input's bounding box is covered by a grid of cubes of edge h (VoxelSize, or the longest side / Resolution),
// centred on the box (so a flat leaf lies in the middle of one layer); a cube is kept when it intersects a triangle
// of the surface, decided by the exact separating-axis test of Akenine-Moeller (13 axes: the box's 3 face normals,
// the triangle's normal, and the 9 edge cross products), inclusive: a triangle touching a cube's face keeps it.
// Kept cubes share their corners (the nodes). Order is deterministic: voxels sorted by (k, j, i), nodes by (k, j, i).
//
// A voxel's Region is the most significant Region of the input points inside it (closed cube): petiole (5) over
// veins (1 midvein, then 2, then 3) over margin (4) over blade (0); a voxel with no point inside is blade.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace plantmorph
{

/// True when the triangle (a, b, c) and the axis-aligned box [low, high] intersect (closed sets).
bool TriangleBoxOverlap(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
  const Eigen::Vector3d& low, const Eigen::Vector3d& high);

/// Region significance used to label voxels (higher wins): petiole 5, midvein 4, secondary 3, margin 2, tertiary 1,
/// blade 0. Tertiary veins and veinlets are much finer than a voxel and keep the blade's material
/// (WiltingMaterialOf), so they rank below the margin: a reticulate network must not turn every voxel into vein.
int RegionPriority(int region);

struct VoxelGrid
{
  Eigen::Vector3d origin = Eigen::Vector3d::Zero(); ///< corner of grid cell (0, 0, 0)
  double h = 1.0;                                   ///< cube edge
  std::array<int, 3> dims = { 0, 0, 0 };            ///< cells along x, y, z
  std::vector<std::array<int, 3>> voxels;           ///< kept cells (i, j, k), sorted by (k, j, i)
  std::vector<std::array<int, 8>> corners;          ///< node ids of each kept cell, VTK hexahedron order
  std::vector<int> regions;                         ///< Region of each kept cell
  std::vector<Eigen::Vector3d> nodes;               ///< node positions
  std::vector<std::array<int, 3>> nodeIndex;        ///< node grid indices (i, j, k) in [0, dims]

  /// Index of the kept voxel at cell (i, j, k), or -1.
  int VoxelAt(int i, int j, int k) const;
  /// Index of the node at grid point (i, j, k), or -1.
  int NodeAt(int i, int j, int k) const;
  /// Fills the lookup tables (called by Voxelize).
  void BuildLookup();
  /// From `voxels` (sorted by (k, j, i)), `origin` and `h`: the nodes, their indices, the voxels' corners and the
  /// lookup tables.
  void BuildNodes();

private:
  std::vector<int> voxelLookup; // dims product, -1 when not kept
  std::vector<int> nodeLookup;  // (dims + 1) product
};

struct VoxelizeParameters
{
  double voxelSize = 0.0; ///< > 0: the cube edge; 0: from resolution
  int resolution = 20;    ///< cubes along the bounding box's longest side when voxelSize is 0
  std::size_t maxVoxels = 2000000;
  /// Axes along which the grid is shifted (by less than a cell, one cell added) so that a node plane passes through
  /// alignAt; the others centre the grid on the bounding box.
  std::array<bool, 3> align{ false, false, false };
  Eigen::Vector3d alignAt = Eigen::Vector3d::Zero();
};

/// Voxelises the triangles (point ids into `points`). `regions` may be empty (everything blade) or one per point.
/// Empty on success, else a message naming the property at fault.
std::string Voxelize(const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& triangles,
  const std::vector<int>& regions, const VoxelizeParameters& options, VoxelGrid& grid);

/// The blade's own midvein as a band two voxels wide wherever it lies: every point of `midvein` (ids into `points`)
/// gives Region 1 to the two kept voxels nearest it across the leaf (grid axis `across`, 0 x or 1 y: the cells
/// whose centres are nearest the point, one on each side of its nearest face) in its own row and layer(s), over
/// any lower Region (not the petiole's). Without it the band is two voxels wide only when the midvein lies exactly
/// on a voxel face (a symmetric blade with an even number of columns, the leaf the presets were fitted on) and one
/// voxel elsewhere: half the vein's bending stiffness where the wilting leaf bends most, next to its anchor, and
/// the Cucumber preset crushed that voxel inside out on fitted scans and on blades a hundredth of a centimetre off
/// symmetric.
void WidenMidvein(
  const std::vector<Eigen::Vector3d>& points, const std::vector<std::size_t>& midvein, int across, VoxelGrid& grid);

/// Where AddPetiole put the petiole.
struct PetiolePlacement
{
  int voxels = 0;                                ///< the petiole's cells (new, or the blade's on its path)
  int shift = 0;                                 ///< rows the grid grew by at its -y end
  Eigen::Vector3d end = Eigen::Vector3d::Zero(); ///< the centre of its far (cut) end, where a stand holds it
  double length = 0.0;                           ///< from the base to `end` along y (whole voxels)
  std::vector<int> endNodes;                     ///< the nodes of its far end face
};

/// Adds a straight petiole to a voxelised blade: the cells whose closed x and z ranges hold the base point (one or
/// two of each: two when the base lies on a cell face), in the round(length / h) >= 1 rows below the base's row
/// (along -y, in the blade's plane), Region 5 (petiole); cells of the blade on that path become petiole. The grid
/// grows at its -y end when the petiole leaves it (its origin moves by whole cells, so the blade's cells keep their
/// positions). Empty on success, else a message naming PetioleLength.
std::string AddPetiole(
  VoxelGrid& grid, const Eigen::Vector3d& base, double length, std::size_t maxVoxels, PetiolePlacement& petiole);

} // namespace plantmorph
