// SPDX-License-Identifier: GPL-3.0-or-later
// The vein network of VenationFilter while it grows, in the blade's flat working plane (docs/methods/venation.md).
//
// Nodes are 2-D points; edges are straight segments, each belonging to one vein (a path grown in one go) of one
// order (0 the margin, 1 primary, 2 secondary, 3 tertiary, 4 free-ending veinlet). The margin is part of the graph,
// so a vein that would leave the blade crosses it and stops there, exactly like a vein that meets another vein:
// Grow() stops a new segment at its first crossing with any existing edge and turns the crossing into a shared node
// by splitting the edge it met (a T-junction, never a near miss). A segment whose end lands within the snap distance
// of an edge is extended onto it, in its own direction. A uniform grid of edges makes each query touch only the cells the segment passes,
// so growth costs about the same per segment however large the network gets.
//
// Faces() walks the planar graph (every crossing is a node, so it is planar): its bounded faces are the blade's
// regions between veins, areoles when no margin edge bounds them.
//
// Plain C++17 + Eigen, no VTK.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <vector>

namespace plantmorph
{

enum VeinOrderValue : int
{
  VeinOrderMargin = 0,
  VeinOrderPrimary = 1,
  VeinOrderSecondary = 2,
  VeinOrderTertiary = 3,   ///< reticulum veins joining two primaries or secondaries (percurrent, ReticulumOrders)
  VeinOrderQuaternary = 4, ///< the finer reticulum: veins that only subdivide areoles (and higher orders)
  VeinOrderVeinlet = 5,    ///< free-ending veinlets inside areoles
};
inline constexpr int VeinOrderCount = 6; ///< margin (0) to veinlet (5), for arrays indexed by order

class VeinGraph
{
public:
  struct Edge
  {
    int a = -1, b = -1;
    int vein = -1;
  };
  struct Vein
  {
    int order = VeinOrderMargin;
  };
  /// Where a grown segment ended: its end node, and whether it stopped on an existing edge (a junction or the
  /// margin) rather than at its free end.
  struct Step
  {
    int node = -1;
    bool stopped = false;
    int hitVein = -1; ///< the vein it stopped on, or -1
  };
  /// A face of the planar graph: its boundary node loop (counter-clockwise for bounded faces) and signed area.
  struct Face
  {
    std::vector<int> nodes;
    double area = 0.0;
    bool touchesMargin = false;
  };

  /// A graph over `lower`..`upper` (every node must lie inside, with a margin) with grid cells of about `cellSize`.
  VeinGraph(const Eigen::Vector2d& lower, const Eigen::Vector2d& upper, double cellSize);

  int AddNode(const Eigen::Vector2d& point);
  int AddVein(int order);
  /// Adds the edge a-b to `vein` without any crossing test (for the margin and trusted curves).
  int AddEdge(int a, int b, int vein);

  /// Grows a segment of `vein` from node `from` towards `to`: stops at the first crossing with an existing edge
  /// (not one at `from`), which becomes a shared node on that edge; if the end lands within `snap` of an edge it
  /// is carried onto it (its direction never changes). A crossing exactly at an end of the edge it meets reuses that
  /// end node.
  Step Grow(int from, const Eigen::Vector2d& to, int vein, double snap);

  /// Joins node `from` to the existing node `to` with an edge of `vein`, unless the segment meets another edge
  /// first (not one at either node): then it stops there as Grow() does.
  Step Connect(int from, int to, int vein, double snap);

  /// Would a segment from node `from` to `to` (plus `snap`) meet an existing edge? The fraction along it, or
  /// a value > 1 when it meets nothing.
  double FirstCrossing(int from, const Eigen::Vector2d& to, double snap) const;

  /// The edge joining nodes a and b, or -1.
  int FindEdge(int a, int b) const;

  /// Splits `edge` at `point` (which must lie on it) and returns the new node.
  int SplitEdge(int edge, const Eigen::Vector2d& point);

  const std::vector<Eigen::Vector2d>& Nodes() const { return this->NodeList; }
  const std::vector<Edge>& Edges() const { return this->EdgeList; }
  const std::vector<Vein>& Veins() const { return this->VeinList; }
  int Order(int vein) const { return this->VeinList[vein].order; }

  /// Changes a vein's order (ReticulumOrders).
  void SetOrder(int vein, int order) { this->VeinList[vein].order = order; }

  /// Each vein's nodes in order along it (a vein is a path; the margin, a closed loop, starts and ends on one node).
  std::vector<std::vector<int>> VeinPaths() const;

  /// Number of non-margin edges at every node.
  std::vector<int> VeinDegrees() const;
  /// Whether each node lies on a margin edge.
  std::vector<char> OnMargin() const;

  /// The bounded faces of the planar graph (area > 0), each with whether a margin edge bounds it; without their
  /// node loops when `withNodes` is false (areas only, much less memory).
  std::vector<Face> Faces(bool withNodes = true) const;

private:
  struct CellRange
  {
    int x0, y0, x1, y1;
  };
  CellRange Cells(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double pad) const;
  void Register(int edge);
  /// First crossing of segment p-q with an edge not incident to `ignore`: its edge and fraction along p-q.
  int Crossing(const Eigen::Vector2d& p, const Eigen::Vector2d& q, int ignore, double& t, Eigen::Vector2d& point,
    int ignoreToo = -1) const;

  std::vector<Eigen::Vector2d> NodeList;
  std::vector<Edge> EdgeList;
  std::vector<Vein> VeinList;
  // Incidence as linked lists in flat arrays: FirstEdge[node] starts the list, NextEdge[2e] continues it at edge
  // e's end a, NextEdge[2e + 1] at its end b (no vector per node).
  std::vector<int> FirstEdge;
  std::vector<int> NextEdge;
  Eigen::Vector2d Lower, Upper;
  double CellSize;
  int Width, Height;
  // The grid: CellHead[cell] starts a list of entries; entry k holds edge EntryEdge[k], next entry EntryNext[k].
  std::vector<int> CellHead;
  std::vector<int> EntryEdge, EntryNext;
  mutable std::vector<int> Visit; ///< query stamp per edge, so an edge in several cells is tested once
  mutable int Stamp = 0;
};

/// The reticulum's orders (docs/methods/venation.md "Vein orders"): every vein of order VeinOrderTertiary as grown
/// (one vein is one front's path, from where it started to where it stopped, through the junctions it made on the
/// way) stays a tertiary if both its ends lie on primaries or secondaries (order <= 2, the margin not counting): a
/// vein joining them across the intercostal area; otherwise, starting or ending on another reticulum vein, it only
/// subdivides an areole and becomes VeinOrderQuaternary. Other veins keep their order. The new order of every vein.
std::vector<int> ReticulumOrders(const VeinGraph& graph);

} // namespace plantmorph
