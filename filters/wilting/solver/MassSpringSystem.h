// SPDX-License-Identifier: GPL-3.0-or-later
// The mass-spring system of WiltingSimulator (docs/methods/wilting.md, paper 001 sec. 1-2): point masses joined by
// linear springs. Plain C++17 + Eigen, no VTK.
//
// Formulation (chosen to be exactly that of VegaFEM's massSpringSystem, the paper's reference [19], so that the
// benchmarks/wilting_plate cross-check can agree with it to 1e-3 cm):
//
// - Spring e joins nodes a < b with stiffness k, dashpot damping c and rest length L = |X_b - X_a| (rest positions).
//   With z = x_b - x_a (x = X + u), l = |z|, n = z / l, the spring force on b is -k (l - L) n and on a +k (l - L) n
//   (eq. (3)); the "internal force" R(u) of the equations of motion M a + C v + R(u) = f is its negative.
// - Tangent stiffness block D_e = dR/dz = k [ (1 - L/l) (I - n n^T) + n n^T ] (eq. (5)); K has +D_e on the two
//   diagonal blocks (a, a), (b, b) and -D_e on (a, b), (b, a). The compression clamp replaces (1 - L/l) by
//   max(0, 1 - L/l), so K stays positive semi-definite for compressed springs (docs/methods/wilting.md).
// - Dashpot: the force on a is c (v_b - v_a) (VegaFEM's spring damping), a constant matrix c (graph Laplacian (x) I).
// - Masses are lumped (a diagonal M); fixed nodes have zero displacement, velocity and acceleration.
//
// A pair of nodes carries at most one spring (AddSpring with an existing pair adds the stiffness and damping to it:
// that is how the voxel model merges a face or an edge shared by neighbouring voxels, see WiltingVoxelizer.h).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <string>
#include <unordered_map>
#include <vector>

namespace plantmorph
{

class MassSpringThreads;

struct MassSpringSpring
{
  int a = 0;               ///< first node, a < b
  int b = 0;               ///< second node
  double stiffness = 0.0;  ///< k, force per unit length
  double damping = 0.0;    ///< c, dashpot on the relative velocity
  double restLength = 0.0; ///< L, from the rest positions
};

/// One entry of a node's adjacency: the other node and the spring joining them; `sign` is +1 when the node is the
/// spring's b end, -1 when it is its a end.
struct MassSpringNeighbour
{
  int node = 0;
  int spring = 0;
  int sign = 0;
};

class MassSpringSystem
{
public:
  /// Adds a node at rest position `rest` with lumped mass `mass` (> 0 for a free node); returns its index.
  int AddNode(const Eigen::Vector3d& rest, double mass, bool fixed = false);
  void AddMass(int node, double mass) { this->NodeMasses[static_cast<std::size_t>(node)] += mass; }
  void SetFixed(int node, bool fixed) { this->Fixed[static_cast<std::size_t>(node)] = fixed ? 1 : 0; }
  /// Adds a spring between two different nodes; if the pair already has one, adds k and c to it (summing).
  /// Returns the spring's index. The rest length is the current rest distance.
  int AddSpring(int a, int b, double stiffness, double damping = 0.0);
  /// Optional hexahedra (VTK corner order) for the inverted-voxel check of the blow-up guard.
  void AddHexahedron(const std::array<int, 8>& corners) { this->HexList.push_back(corners); }
  /// Checks the system (finite positions, positive masses of free nodes, positive rest lengths and stiffnesses)
  /// and builds the adjacency. Empty on success, else a message.
  std::string Finalize();

  std::size_t NodeCount() const { return this->Rest.size(); }
  std::size_t SpringCount() const { return this->SpringList.size(); }
  const std::vector<Eigen::Vector3d>& RestPositions() const { return this->Rest; }
  const std::vector<double>& Masses() const { return this->NodeMasses; }
  bool IsFixed(std::size_t node) const { return this->Fixed[node] != 0; }
  const std::vector<char>& FixedFlags() const { return this->Fixed; }
  const std::vector<MassSpringSpring>& Springs() const { return this->SpringList; }
  const std::vector<std::array<int, 8>>& Hexahedra() const { return this->HexList; }
  /// Neighbours of `node`, ordered by spring index (a fixed summation order).
  const MassSpringNeighbour* NeighboursBegin(std::size_t node) const
  {
    return this->Adjacency.data() + this->AdjacencyOffsets[node];
  }
  const MassSpringNeighbour* NeighboursEnd(std::size_t node) const
  {
    return this->Adjacency.data() + this->AdjacencyOffsets[node + 1];
  }

  /// Per spring, at displacement `u` (3 per node): `force` (3 per spring) = k (l - L) n, the force spring e
  /// exerts on its a end; `tangent` (6 per spring: xx, xy, xz, yy, yz, zz) = D_e, clamped if `clamp`.
  /// A zero-length spring gives n = 0 (force 0) and D_e = k I.
  void EvaluateSprings(const double* u, bool clamp, double* force, double* tangent, MassSpringThreads& threads) const;
  /// Internal force R(u) (3 per node): minus the sum of the spring forces on each node (fixed nodes included).
  void InternalForce(const double* u, double* out) const;
  /// Spring s's length |X_b + u_b - X_a - u_a| at displacement `u` (3 per node).
  double SpringLength(const MassSpringSpring& s, const double* u) const;
  /// Elastic energy sum 1/2 k (l - L)^2.
  double SpringEnergy(const double* u) const;
  /// Kinetic energy 1/2 v^T M v.
  double KineticEnergy(const double* v) const;
  /// Gravity potential -sum m g . (X + u) (zero for g = 0).
  double GravityEnergy(const double* u, const Eigen::Vector3d& gravity) const;
  /// The smallest corner Jacobian determinant over the hexahedra, each relative to its rest value (1 at rest;
  /// <= 0 means an inverted or flattened voxel). +infinity without hexahedra.
  double MinimumRelativeJacobian(const double* u) const;

private:
  std::vector<Eigen::Vector3d> Rest;
  std::vector<double> NodeMasses;
  std::vector<char> Fixed;
  std::vector<MassSpringSpring> SpringList;
  std::unordered_map<unsigned long long, int> SpringOfPair;
  std::vector<std::array<int, 8>> HexList;
  std::vector<double> RestJacobians; // 8 per hexahedron
  std::vector<std::size_t> AdjacencyOffsets;
  std::vector<MassSpringNeighbour> Adjacency;
};

} // namespace plantmorph
