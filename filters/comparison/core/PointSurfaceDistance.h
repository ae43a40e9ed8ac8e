// SPDX-License-Identifier: GPL-3.0-or-later
// CloudComparisonFilter's distance engine (docs/methods/comparison.md): the exact distance from query points
// to a triangle surface, or to the nearest point of a point cloud, through a bounding volume hierarchy (BVH) on flat
// arrays. Plain C++17, no VTK: unit-tested directly against brute force.
//
// Surface mode (BuildSurface). The reference is a list of triangles over a vertex array. The distance of a query
// point p is min over all triangles of |p - c_t|, c_t the exact closest point of triangle t (Ericson, "Real-Time
// Collision Detection", 5.1.5: the Voronoi regions of the vertices, edges and face, closed forms in double
// precision). The BVH only decides which triangles need looking at: the result is the same as the brute-force
// minimum over all triangles (exact ties between triangles at the same distance go to the lowest index in the BVH's
// primitive order, whatever the order of the visit or the starting hint: a point's results do not depend on which
// other points are queried with it, so an MPI rank's piece gets the serial values bit for bit).
//
// Signed distance. The sign is that of (p - c) . N, N the angle-weighted pseudo-normal of the feature of the closest
// triangle that holds c (Baerentzen and Aanaes, "Signed distance computation using the angle weighted
// pseudonormal", IEEE TVCG 2005): the face's unit normal if c is inside the face, the sum of the unit normals of the
// faces sharing the edge if c is on an edge, and the sum of the unit normals of the faces around the vertex weighted
// by their angle at it if c is a vertex. This gives the correct inside/outside sign for every point near a closed,
// consistently oriented surface, also outside convex edges and corners where the nearest triangle's own normal
// fails. On an open surface (a leaf blade) the side is the side of the nearest feature: a point beyond the margin
// gets the sign of the margin's pseudo-normal, the edge's face normal. Face normals follow the triangles' winding
// (right-hand rule), so + is the side the normals point to; an inconsistently wound surface gives meaningless signs
// across its badly wound edges. Non-manifold edges (more than two faces) sum all their faces' normals. A point
// exactly on the surface gets signed distance 0.
//
// Degenerate triangles (zero area, NaN-free) are kept: their closest point is found on their three edges, and their
// zero normal contributes nothing to pseudo-normals.
//
// Cloud mode (BuildCloud). The reference is a point set: the distance is to the nearest reference point (Euclidean),
// the closest point is that point, and there is no signed distance (the query reports it equal to the distance).
//
// Leaves (surface mode). A leaf's triangles are also stored side by side (TrianglePack), and a query reaching the
// leaf computes their squared distances in one branch-free pass (AVX: all four at once; SSE2: two at a time): inside
// the face (all three of Ericson's barycentric numerators positive) the squared distance to the plane, else the
// smallest squared distance to the three edges (clamped projections). This selects the nearest triangle; its
// distance, closest point and sign are then computed by Ericson's method as described above, so a reported distance
// is always Ericson's for the triangle chosen. A degenerate triangle (zero normal or a zero edge) gets Ericson's
// value in its lane instead. The starting hint only sets a bound (its squared distance by the same formulas, plus
// 1e-12 relative): its leaf is visited like any other, so the choice does not depend on it.
//
// The BVH: binary, built by median splits on the longest axis of the primitives' centroid bounds, leaves of up to
// four triangles (eight points), with double-precision boxes, built one level at a time with the nodes of a level
// in parallel (the same tree as a serial build). Queries walk a 4-wide tree collapsed from it (each wide node holds
// the bounds of a binary node's four grandchildren side by side, stored depth first), so one step computes four
// children's bounds at once with SSE2 (two lanes an instruction; x86-64 always has it; other processors use the same
// formulas one lane at a time) over half as many levels. A leaf's triangles are held once, as the lanes of its pack
// (vertex, edge vectors, unit normal and original index), so the winner's closest point and sign are computed from
// memory the leaf pass has just read, and a query touches contiguous memory. A query descends nearest child first with an
// explicit stack and prunes children (and, in leaves, triangle planes) no nearer than the best distance so far.
//
// Slab bounds (surface mode). Besides its box, every lane of a wide node holds a "coin", a flat cylinder around its
// triangles (the binary nodes the collapse skips get none): its axis is the unit mean normal n of the triangles, its
// centre o is placed so that n . (x - o) over their vertices spans [-h, h], and r is the largest distance of a
// vertex from the axis. The coin is convex and holds every vertex,
// so it holds every triangle of the node, and the distance from p to the node is at least
// max(box distance, sqrt(max(0, |a| - h)^2 + max(0, l - r)^2)), a = n . (p - o) and l = |n x (p - o)| the axial and
// lateral coordinates of p. On a curved surface the box of a tilted patch reaches far off the surface, so from
// inside a sphere thousands of boxes have a box distance just below the answer and must be opened; the coin of the
// same patch is only its sagitta thick (the slab part prunes those), and from outside, where the planes of patches
// beside the nearest one pass close to p, the lateral part prunes them. A node whose normals nearly cancel (a
// closed part) has no coin (its lanes hold n = 0, h = r = 0, whose coin part is 0). (h and r are padded by
// 1e-12 relative plus the rounding of o, and the query subtracts 1e-14 of |p - o|_1 from both parts, so round-off
// does not make the bound exceed the true distance: the result is the same minimum as with box bounds only, which
// the tests check against brute force and against SetSlabBounds(false).)
//
// QueryMany (4096 points or more) visits the points in Morton (Z-curve) order of their coordinates (a 30-bit code,
// radix sorted; 16 bytes per point while sorting, 8 while querying) and starts each query from the previous one's
// nearest primitive as its first bound, which makes any cloud spatially coherent; the result does not depend on it
// (only the starting bound changes, not the minimum), and results are written in input order. The queries run in
// batches of 1024: the batch's points gathered from the input first and its results scattered back after, each in
// a loop of its own, so the processor overlaps those random accesses instead of waiting on them between searches.
//
// Threads: the builds and QueryMany take a ParallelFor hook that runs a body over sub-ranges of [0, count), so the
// VTK layer threads them with vtkSMPTools; each query only reads the structure. Results do not depend on threads.
#pragma once

#include <plantmorph/ParallelFor.h>
#include <plantmorph/memory/HugePages.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

namespace plantmorph
{

/// The allocator of the distance structure's big arrays. Elements of a trivial type are left unset when the array
/// grows (value-initialisation would zero them on the calling thread: a serial pass and its page faults, before the
/// parallel loops that write every element anyway), and arrays of 4 MiB or more go on transparent huge pages
/// (AllocateOnHugePages): in a fresh process every page of such an array is new memory, and its first write faulted
/// once per 4 KiB (a 10^6-point query against 203,520 triangles took 42.8 k faults on its first update, 2-6 k on the
/// next).
template <class T>
struct UnsetAllocator
{
  using value_type = T;
  UnsetAllocator() = default;
  template <class U>
  UnsetAllocator(const UnsetAllocator<U>&) noexcept
  {
  }
  static bool OnHugePages(std::size_t n) { return HugePagesPossible && WorthHugePages(n * sizeof(T)); }
  T* allocate(std::size_t n)
  {
    if (OnHugePages(n))
    {
      return static_cast<T*>(AllocateOnHugePages(n * sizeof(T)));
    }
    return std::allocator<T>().allocate(n);
  }
  void deallocate(T* p, std::size_t n) noexcept
  {
    if (OnHugePages(n))
    {
      std::free(p);
      return;
    }
    std::allocator<T>().deallocate(p, n);
  }
  template <class U>
  void construct(U* p) noexcept
  {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args)
  {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  friend bool operator==(const UnsetAllocator&, const UnsetAllocator&) { return true; }
  friend bool operator!=(const UnsetAllocator&, const UnsetAllocator&) { return false; }

private:
#ifdef __linux__
  static constexpr bool HugePagesPossible = true;
#else
  static constexpr bool HugePagesPossible = false;
#endif
};
template <class T>
using UnsetVector = std::vector<T, UnsetAllocator<T>>;

// ParallelFor and SerialFor (the default, serial) come from plantmorph/ParallelFor.h, shared by every algorithm.

/// Which feature of a triangle holds its closest point.
enum class TriangleFeature : std::uint8_t
{
  Face = 0,
  Edge = 1,   ///< the edge `index` of the triangle: 0 = (a, b), 1 = (b, c), 2 = (c, a)
  Vertex = 2, ///< the vertex `index` of the triangle: 0 = a, 1 = b, 2 = c
};

/// Exact closest point of triangle (a, b, c) to p (Ericson 5.1.5). Returns the closest point in `closest`, and which
/// feature of the triangle holds it. Degenerate triangles are handled (closest point on their edges).
void ClosestPointOnTriangle(const double p[3], const double a[3], const double b[3], const double c[3],
  double closest[3], TriangleFeature& feature, int& index);

struct DistanceQueryResult
{
  double distance = 0.0;       ///< unsigned distance to the reference
  double signedDistance = 0.0; ///< signed by the pseudo-normal (surface mode); = distance in cloud mode
  double closest[3] = { 0.0, 0.0, 0.0 };
  std::int64_t primitive = -1; ///< index of the nearest triangle (surface) or reference point (cloud)
};

class PointSurfaceDistance
{
public:
  /// Builds the surface structure: `points` holds pointCount x,y,z triples, `triangles` triangleCount triples of
  /// point indices. Returns an empty string, or an error (index out of range, non-finite coordinate, no triangle)
  /// and leaves the object empty.
  std::string BuildSurface(const double* points, std::size_t pointCount, const std::int64_t* triangles,
    std::size_t triangleCount, const ParallelFor& parallelFor = SerialFor);

  /// Builds the cloud structure over pointCount x,y,z triples. Returns an empty string or an error (non-finite
  /// coordinate, no point) and leaves the object empty.
  std::string BuildCloud(const double* points, std::size_t pointCount, const ParallelFor& parallelFor = SerialFor);

  /// Whether queries use the nodes' slab bounds (surface mode; default on). Off gives the same results with box
  /// bounds only (for tests and benchmarks of the bound).
  void SetSlabBounds(bool on) { this->SlabBounds = on; }
  bool GetSlabBounds() const { return this->SlabBounds; }

  /// Whether queries use the AVX traversal where the processor has AVX (default on). Off gives the same results bit
  /// for bit with the SSE2 one (for tests and benchmarks of both).
  void SetAvx(bool on) { this->Avx = on; }
  bool GetAvx() const { return this->Avx; }

  bool IsEmpty() const { return this->WideNodes.empty(); }
  bool IsSurface() const { return this->Surface; }
  std::size_t GetNumberOfPrimitives() const { return this->PrimitiveIds.size(); }

  /// One query. `hint` (a primitive index from an earlier query, or -1) only sets the starting bound.
  DistanceQueryResult Query(const double p[3], std::int64_t hint = -1) const;

  /// count queries over x,y,z triples in `points`; any of the output arrays may be null. `closest` gets x,y,z
  /// triples, `primitive` the nearest triangle or point index. `progress`, if set, is called on the calling thread
  /// between blocks of queries with the fraction done; returning false stops the queries (outputs then partial).
  void QueryMany(const double* points, std::size_t count, double* distance, double* signedDistance, double* closest,
    std::int64_t* primitive, const ParallelFor& parallelFor = SerialFor,
    const std::function<bool(double)>& progress = nullptr) const;

  /// The unit normal of triangle `triangle` (original index; zero for a degenerate triangle). Surface mode only.
  void GetTriangleNormal(std::int64_t triangle, double normal[3]) const;

  /// Bytes held by the structure (for memory reports).
  std::size_t MemoryBytes() const;

private:
  struct Node ///< a node of the binary tree (built, then collapsed into WideNodes)
  {
    double lo[3];
    double hi[3];
    double o[3];         ///< coin centre
    double n[3];         ///< coin axis (unit, or 0 when the node has none; cloud mode: 0)
    double h;            ///< coin half-thickness, padded (0: no coin)
    double r;            ///< coin radius: largest distance of a vertex from the axis, padded
    std::uint32_t start; ///< leaf: first primitive (in leaf order); inner: index of the right child
    std::uint32_t count; ///< leaf: number of primitives; inner: 0
  };
  /// A node of the 4-wide tree the queries walk: the bounds of up to four children side by side (lane j of every
  /// array is child j), so one query computes the four bounds at once (SSE2, two lanes at a time). A child is a
  /// leaf (count > 0: primitives [start, start + count) in leaf order) or another wide node (count 0: its index).
  /// An unused lane has an empty box (lo = +inf, hi = -inf: bound +inf) and no coin.
  struct alignas(32) WideNode
  {
    double lo[3][4];
    double hi[3][4];
    double o[3][4];
    double n[3][4];
    double h[4];
    double r[4];
    std::uint32_t start[4];
    std::uint32_t count[4];
  };
  struct Triangle ///< a triangle in leaf order: vertex a, edges ab and ac, unit normal (0 when degenerate)
  {
    double a[3];
    double ab[3];
    double ac[3];
    double n[3];
  };
  /// A leaf's triangles side by side (lane j of every array is its triangle `first + j`; unused lanes repeat lane
  /// 0), so the query computes their squared distances at once, without branches (surface mode; a leaf lane of a
  /// wide node then holds the pack's index in `start`).
  struct alignas(32) TrianglePack
  {
    double a[3][4];
    double ab[3][4];
    double ac[3][4];
    double n[3][4];
    std::uint32_t first;     ///< the leaf's first triangle, in leaf order
    std::uint32_t irregular; ///< bit j: triangle j is degenerate (its distance is Ericson's, computed on its own)
    std::uint32_t id[4];     ///< lane j's original triangle index (in the alignment's room: the size is unchanged)
  };

  std::string BuildTree(const UnsetVector<double>& lo, const UnsetVector<double>& hi,
    const UnsetVector<double>& centroid, std::size_t count, std::size_t leafSize, std::vector<std::uint32_t>& nodeRange,
    const ParallelFor& parallelFor);
  std::vector<std::uint8_t> WideLanes() const;
  void BuildSlabs(const std::vector<std::uint32_t>& nodeRange, const ParallelFor& parallelFor);
  void CollapseToWideNodes(const ParallelFor& parallelFor);
  TrianglePack MakePack(std::uint32_t first, std::uint32_t count) const;
  // The traversal (PointSurfaceDistanceSearch.inc) compiled for SSE2 and for AVX (x86-64 only), and the result
  // from the nearest primitive it found.
  DistanceQueryResult SearchSse2(const double p[3], std::int64_t hint) const;
  DistanceQueryResult SearchAvx(const double p[3], std::int64_t hint) const;
  DistanceQueryResult QueryResult(const double p[3], double best2, std::size_t bestLeaf, std::size_t bestPack) const;
  double PrimitiveDistance2(std::size_t leafIndex, const double p[3]) const; ///< cloud mode
  double HintDistance2(std::size_t hint, const double p[3]) const;
  static Triangle LaneTriangle(const TrianglePack& pack, std::uint32_t lane);
  static double LaneDistance2(const TrianglePack& pack, std::uint32_t lane, const double p[3]);

  bool Surface = false;
  bool SlabBounds = true;
  bool Avx = true;
  UnsetVector<Node> Nodes;                 ///< binary tree, during the build only
  UnsetVector<WideNode> WideNodes;         ///< the tree the queries walk; root 0 (room beyond it untouched)
  std::vector<std::uint32_t> PrimitiveIds; ///< leaf order -> original triangle or point index
  std::vector<std::uint32_t> LeafOf;       ///< cloud mode: original index -> leaf order
  UnsetVector<Triangle> Triangles;         ///< surface mode, leaf order, during the build only
  std::vector<std::uint8_t> Regular;       ///< the same: 1 unless degenerate (see TrianglePack)
  // Surface mode: the queries read the triangles from the packs only, so the winner's lane is in the cache the leaf
  // pass has just filled.
  UnsetVector<TrianglePack> Packs;       ///< one per leaf
  UnsetVector<std::uint32_t> PackLaneOf; ///< original triangle -> 4 * pack + lane (packs < 2^30: >= 2 triangles each)
  std::vector<double> CloudPoints;       ///< cloud mode, leaf order, x,y,z
  // Signed distance data (surface mode, by original triangle index): vertex ids, edge pseudo-normals; vertex
  // pseudo-normals by point index.
  UnsetVector<std::int64_t> TriangleVertices;
  UnsetVector<double> EdgeNormals;   ///< 9 per triangle: edges (a,b), (b,c), (c,a)
  UnsetVector<double> VertexNormals; ///< 3 per point
};

} // namespace plantmorph
