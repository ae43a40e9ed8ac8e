// SPDX-License-Identifier: GPL-3.0-or-later
#include "PointSurfaceDistance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PLANTMORPH_AVX_SEARCH 1
#endif

namespace plantmorph
{

namespace
{
constexpr double Infinity = std::numeric_limits<double>::infinity();
constexpr std::size_t TriangleLeafSize = 4;
constexpr std::size_t PointLeafSize = 8;
constexpr int StackSize = 96; // the 4-wide tree has depth <= 17 (median splits of < 2^32), <= 3 entries a level

inline double Dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// Ericson 5.1.5 on a triangle given as a, ab = b - a, ac = c - a; writes the barycentric weights (v, w) of the
/// closest point a + v ab + w ac, and its feature.
inline void ClosestOnTriangle(const double ap[3], const double ab[3], const double ac[3], double& v, double& w,
  TriangleFeature& feature, int& index)
{
  const double d1 = Dot(ab, ap);
  const double d2 = Dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0)
  {
    v = w = 0.0;
    feature = TriangleFeature::Vertex;
    index = 0;
    return;
  }
  const double bp[3] = { ap[0] - ab[0], ap[1] - ab[1], ap[2] - ab[2] };
  const double d3 = Dot(ab, bp);
  const double d4 = Dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3)
  {
    v = 1.0;
    w = 0.0;
    feature = TriangleFeature::Vertex;
    index = 1;
    return;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
  {
    v = d1 / (d1 - d3);
    w = 0.0;
    feature = TriangleFeature::Edge;
    index = 0;
    return;
  }
  const double cp[3] = { ap[0] - ac[0], ap[1] - ac[1], ap[2] - ac[2] };
  const double d5 = Dot(ab, cp);
  const double d6 = Dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6)
  {
    v = 0.0;
    w = 1.0;
    feature = TriangleFeature::Vertex;
    index = 2;
    return;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
  {
    v = 0.0;
    w = d2 / (d2 - d6);
    feature = TriangleFeature::Edge;
    index = 2;
    return;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
  {
    w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    v = 1.0 - w;
    feature = TriangleFeature::Edge;
    index = 1;
    return;
  }
  const double sum = va + vb + vc;
  if (sum > 0.0 && std::isfinite(sum))
  {
    v = vb / sum;
    w = vc / sum;
    feature = TriangleFeature::Face;
    index = 0;
    return;
  }
  // Degenerate triangle (zero area): the closest of its three edges.
  const auto onSegment = [](const double q[3], const double from[3], const double dir[3]) {
    const double len2 = Dot(dir, dir);
    if (len2 <= 0.0)
    {
      return 0.0;
    }
    const double t = (Dot(q, dir) - Dot(from, dir)) / len2;
    return std::clamp(t, 0.0, 1.0);
  };
  const double zero[3] = { 0.0, 0.0, 0.0 };
  const double bc[3] = { ac[0] - ab[0], ac[1] - ab[1], ac[2] - ab[2] };
  double best = Infinity;
  const double tbc = onSegment(ap, ab, bc);
  // (v, w) of the closest point on edges (a, b), (a, c) and (b, c), and their edge indices.
  const double weights[3][2] = { { onSegment(ap, zero, ab), 0.0 }, { 0.0, onSegment(ap, zero, ac) },
    { 1.0 - tbc, tbc } };
  const int edgeOf[3] = { 0, 2, 1 };
  for (int e = 0; e < 3; ++e)
  {
    const double x[3] = { weights[e][0] * ab[0] + weights[e][1] * ac[0] - ap[0],
      weights[e][0] * ab[1] + weights[e][1] * ac[1] - ap[1], weights[e][0] * ab[2] + weights[e][1] * ac[2] - ap[2] };
    const double d2e = Dot(x, x);
    if (d2e < best)
    {
      best = d2e;
      v = weights[e][0];
      w = weights[e][1];
      feature = TriangleFeature::Edge;
      index = edgeOf[e];
    }
  }
}

void Cross(const double a[3], const double b[3], double out[3])
{
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

/// Asks for the cache line holding `address` (for writing or reading) ahead of its use; nothing where the compiler
/// has no prefetch.
inline void Prefetch(const double* address, bool write)
{
#if defined(__GNUC__)
  if (write)
  {
    __builtin_prefetch(address, 1);
  }
  else
  {
    __builtin_prefetch(address, 0);
  }
#else
  (void)address;
  (void)write;
#endif
}

/// The squared distance from p to a non-degenerate triangle (ap = p - a, edges ab and ac, unit normal n), branch
/// free: the squared plane distance inside the face, else the nearest of the three edges. The same operations in the
/// same order as the lanes of the query's leaf pass (PointSurfaceDistanceSearch.inc); the search uses it only for
/// the starting hint's bound.
inline double RegularDistance2(const double ap[3], const double ab[3], const double ac[3], const double n[3])
{
  const double bc[3] = { ac[0] - ab[0], ac[1] - ab[1], ac[2] - ab[2] };
  const double bp[3] = { ap[0] - ab[0], ap[1] - ab[1], ap[2] - ab[2] };
  const double cp[3] = { ap[0] - ac[0], ap[1] - ac[1], ap[2] - ac[2] };
  const double d1 = Dot(ab, ap);
  const double d2 = Dot(ac, ap);
  const double d3 = Dot(ab, bp);
  const double d4 = Dot(ac, bp);
  const double d5 = Dot(ab, cp);
  const double d6 = Dot(ac, cp);
  const double va = d3 * d6 - d5 * d4;
  const double vb = d5 * d2 - d1 * d6;
  const double vc = d1 * d4 - d3 * d2;
  const double plane = Dot(n, ap);
  const auto clamp01 = [](double t) { // as max(t, 0) then min(t, 1) of the lanes (maxpd, minpd), signed zeros too
    t = t > 0.0 ? t : 0.0;
    return t < 1.0 ? t : 1.0;
  };
  const double tab = clamp01(d1 / Dot(ab, ab));
  const double tac = clamp01(d2 / Dot(ac, ac));
  const double tbc = clamp01(Dot(bc, bp) / Dot(bc, bc));
  const double eab[3] = { ap[0] - tab * ab[0], ap[1] - tab * ab[1], ap[2] - tab * ab[2] };
  const double eac[3] = { ap[0] - tac * ac[0], ap[1] - tac * ac[1], ap[2] - tac * ac[2] };
  const double ebc[3] = { bp[0] - tbc * bc[0], bp[1] - tbc * bc[1], bp[2] - tbc * bc[2] };
  const double edge = std::min(std::min(Dot(eab, eab), Dot(eac, eac)), Dot(ebc, ebc));
  return va > 0.0 && vb > 0.0 && vc > 0.0 ? plane * plane : edge;
}

/// Ericson's squared distance from p (ap = p - a) to the triangle (a, ab, ac): for degenerate triangles.
inline double EricsonDistance2(const double ap[3], const double ab[3], const double ac[3])
{
  double v = 0.0;
  double w = 0.0;
  TriangleFeature feature;
  int index = 0;
  ClosestOnTriangle(ap, ab, ac, v, w, feature, index);
  const double d[3] = { v * ab[0] + w * ac[0] - ap[0], v * ab[1] + w * ac[1] - ap[1], v * ab[2] + w * ac[2] - ap[2] };
  return Dot(d, d);
}

/// The keys of QueryMany's visiting order: 30-bit Morton code << 32 | input index, sorted by the code
/// (SortKeysInParallel: a radix sort over fixed blocks, stable, so equal codes stay in input order and the order is
/// the serial sort's whatever the threads).
UnsetVector<std::uint64_t> MortonOrder(const double* points, std::size_t count, const ParallelFor& parallelFor)
{
  const std::size_t blockSize = std::max<std::size_t>(std::size_t(1) << 14, (count + 63) / 64);
  const std::size_t blocks = (count + blockSize - 1) / blockSize;
  // Runs f(block, first, last) for every block, the blocks spread over the ParallelFor's ranges.
  const auto forBlocks = [&](const auto& f) {
    parallelFor(count, [&](std::size_t begin, std::size_t end) {
      for (std::size_t b = (begin + blockSize - 1) / blockSize; b < blocks && b * blockSize < end; ++b)
      {
        f(b, b * blockSize, std::min(count, (b + 1) * blockSize));
      }
    });
  };
  // The finite coordinates' bounds, per block and then over the blocks (min and max: exact in any order).
  std::vector<double> blockBounds(6 * blocks);
  forBlocks([&](std::size_t b, std::size_t first, std::size_t last) {
    double* bound = blockBounds.data() + 6 * b;
    for (int k = 0; k < 3; ++k)
    {
      bound[k] = Infinity;
      bound[3 + k] = -Infinity;
    }
    for (std::size_t i = first; i < last; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        const double x = points[3 * i + k];
        if (std::isfinite(x))
        {
          bound[k] = std::min(bound[k], x);
          bound[3 + k] = std::max(bound[3 + k], x);
        }
      }
    }
  });
  double lo[3] = { Infinity, Infinity, Infinity };
  double hi[3] = { -Infinity, -Infinity, -Infinity };
  for (std::size_t b = 0; b < blocks; ++b)
  {
    for (int k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], blockBounds[6 * b + k]);
      hi[k] = std::max(hi[k], blockBounds[6 * b + 3 + k]);
    }
  }
  const auto spread = [](std::uint64_t v) { // 10 bits -> every third bit
    v &= 0x3ff;
    v = (v | v << 16) & 0x30000ffULL;
    v = (v | v << 8) & 0x300f00fULL;
    v = (v | v << 4) & 0x30c30c3ULL;
    v = (v | v << 2) & 0x9249249ULL;
    return v;
  };
  UnsetVector<std::uint64_t> order(count);
  parallelFor(count, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      std::uint64_t code = 0;
      for (int k = 0; k < 3; ++k)
      {
        const double extent = hi[k] - lo[k];
        const double x = points[3 * i + k];
        const double t = extent > 0.0 && std::isfinite(x) ? (x - lo[k]) / extent : 0.0;
        code |= spread(static_cast<std::uint64_t>(std::clamp(t, 0.0, 1.0) * 1023.0)) << k;
      }
      order[i] = code << 32 | static_cast<std::uint64_t>(i);
    }
  });
  SortKeysInParallel(parallelFor, order, 32, 62);
  return order;
}

bool AllFinite(const double* values, std::size_t count)
{
  for (std::size_t i = 0; i < count; ++i)
  {
    if (!std::isfinite(values[i]))
    {
      return false;
    }
  }
  return true;
}

#if defined(PLANTMORPH_AVX_SEARCH)
bool DetectAvx()
{
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx");
}
/// Whether the processor has AVX (the build uses the default x86-64 flags: AVX code runs only behind this check).
const bool CpuHasAvx = DetectAvx();
#endif
} // namespace

//------------------------------------------------------------------------------
void ClosestPointOnTriangle(const double p[3], const double a[3], const double b[3], const double c[3],
  double closest[3], TriangleFeature& feature, int& index)
{
  const double ab[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double ac[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
  const double ap[3] = { p[0] - a[0], p[1] - a[1], p[2] - a[2] };
  double v = 0.0;
  double w = 0.0;
  ClosestOnTriangle(ap, ab, ac, v, w, feature, index);
  for (int k = 0; k < 3; ++k)
  {
    closest[k] = a[k] + v * ab[k] + w * ac[k];
  }
}

//------------------------------------------------------------------------------
std::string PointSurfaceDistance::BuildTree(const UnsetVector<double>& lo, const UnsetVector<double>& hi,
  const UnsetVector<double>& centroid, std::size_t count, std::size_t leafSize, std::vector<std::uint32_t>& nodeRange,
  const ParallelFor& parallelFor)
{
  // The shape of the tree depends only on the sizes (a range of m > leafSize splits into m / 2 and m - m / 2), so
  // the depth-first index of every node is known before building: the left child follows its parent, the right one
  // follows the left subtree, of NodeCount(m / 2) nodes. The sizes on one level differ by at most one, so the node
  // counts of all sizes that occur fit a small table. That lets the tree be built one level at a time, the nodes of
  // a level in parallel (each sorts only its own part of `order`), giving the same tree as a serial build.
  std::map<std::size_t, std::size_t> nodeCount; // range size -> nodes in its subtree
  {
    std::vector<std::size_t> sizes{ count };
    std::vector<std::size_t> all;
    while (!sizes.empty())
    {
      std::vector<std::size_t> next;
      for (const std::size_t m : sizes)
      {
        all.push_back(m);
        if (m > leafSize)
        {
          next.push_back(m / 2);
          next.push_back(m - m / 2);
        }
      }
      std::sort(next.begin(), next.end());
      next.erase(std::unique(next.begin(), next.end()), next.end());
      sizes = std::move(next);
    }
    std::sort(all.begin(), all.end());
    for (const std::size_t m : all) // increasing, so the children's counts are known
    {
      nodeCount[m] = m <= leafSize ? 1 : 1 + nodeCount.at(m / 2) + nodeCount.at(m - m / 2);
    }
  }
  const std::size_t total = nodeCount.at(count);
  std::vector<std::uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  this->Nodes.resize(total); // every node is written by its task below
  nodeRange.assign(2 * total, 0);

  struct Task
  {
    std::size_t begin, end, node;
  };
  std::vector<Task> tasks{ { 0, count, 0 } }; // one level, in increasing `begin`
  while (!tasks.empty())
  {
    std::vector<Task> children(2 * tasks.size(), Task{ 0, 0, 0 });
    // Each element range of the ParallelFor builds the nodes whose ranges start in it.
    parallelFor(count, [&](std::size_t first, std::size_t last) {
      auto it =
        std::lower_bound(tasks.begin(), tasks.end(), first, [](const Task& t, std::size_t b) { return t.begin < b; });
      for (; it != tasks.end() && it->begin < last; ++it)
      {
        const Task task = *it;
        Node& node = this->Nodes[task.node];
        nodeRange[2 * task.node] = static_cast<std::uint32_t>(task.begin);
        nodeRange[2 * task.node + 1] = static_cast<std::uint32_t>(task.end);
        double clo[3] = { Infinity, Infinity, Infinity };
        double chi[3] = { -Infinity, -Infinity, -Infinity };
        for (int k = 0; k < 3; ++k)
        {
          node.lo[k] = Infinity;
          node.hi[k] = -Infinity;
          node.o[k] = node.n[k] = 0.0; // no coin (BuildSlabs sets them on a surface)
        }
        node.h = node.r = 0.0;
        for (std::size_t i = task.begin; i < task.end; ++i)
        {
          const std::size_t id = order[i];
          for (int k = 0; k < 3; ++k)
          {
            node.lo[k] = std::min(node.lo[k], lo[3 * id + k]);
            node.hi[k] = std::max(node.hi[k], hi[3 * id + k]);
            clo[k] = std::min(clo[k], centroid[3 * id + k]);
            chi[k] = std::max(chi[k], centroid[3 * id + k]);
          }
        }
        const std::size_t n = task.end - task.begin;
        if (n <= leafSize)
        {
          node.start = static_cast<std::uint32_t>(task.begin);
          node.count = static_cast<std::uint32_t>(n);
          continue;
        }
        int axis = 0;
        for (int k = 1; k < 3; ++k)
        {
          if (chi[k] - clo[k] > chi[axis] - clo[axis])
          {
            axis = k;
          }
        }
        const std::size_t mid = task.begin + n / 2;
        std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(task.begin),
          order.begin() + static_cast<std::ptrdiff_t>(mid), order.begin() + static_cast<std::ptrdiff_t>(task.end),
          [&](std::uint32_t x, std::uint32_t y) {
            const double cx = centroid[3 * x + axis];
            const double cy = centroid[3 * y + axis];
            return cx < cy || (cx == cy && x < y);
          });
        const std::size_t right = task.node + 1 + nodeCount.at(n / 2);
        node.count = 0;
        node.start = static_cast<std::uint32_t>(right);
        const std::size_t slot = static_cast<std::size_t>(it - tasks.begin());
        children[2 * slot] = { task.begin, mid, task.node + 1 };
        children[2 * slot + 1] = { mid, task.end, right };
      }
    });
    tasks.clear();
    for (const Task& child : children)
    {
      if (child.end > child.begin)
      {
        tasks.push_back(child);
      }
    }
  }
  this->PrimitiveIds = std::move(order);
  this->LeafOf.assign(count, 0);
  parallelFor(count, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      this->LeafOf[this->PrimitiveIds[i]] = static_cast<std::uint32_t>(i);
    }
  });
  return {};
}

//------------------------------------------------------------------------------
std::vector<std::uint8_t> PointSurfaceDistance::WideLanes() const
{
  // The binary nodes CollapseToWideNodes makes lanes of (the same walk): a root that is a leaf, else every child of
  // a collapsed node that is a leaf and the grandchildren under every inner child, collapsed in turn when inner.
  std::vector<std::uint8_t> lane(this->Nodes.size(), 0);
  if (this->Nodes[0].count > 0)
  {
    lane[0] = 1;
    return lane;
  }
  std::vector<std::uint32_t> pending{ 0 };
  const auto take = [&](std::uint32_t node) {
    lane[node] = 1;
    if (this->Nodes[node].count == 0)
    {
      pending.push_back(node);
    }
  };
  while (!pending.empty())
  {
    const std::uint32_t binary = pending.back();
    pending.pop_back();
    for (const std::uint32_t child : { binary + 1, this->Nodes[binary].start })
    {
      if (this->Nodes[child].count > 0)
      {
        lane[child] = 1;
      }
      else
      {
        take(child + 1);
        take(this->Nodes[child].start);
      }
    }
  }
  return lane;
}

//------------------------------------------------------------------------------
void PointSurfaceDistance::BuildSlabs(const std::vector<std::uint32_t>& nodeRange, const ParallelFor& parallelFor)
{
  // Only the nodes that become lanes of the wide tree need a coin (about half: the collapse skips every other
  // level); the others get none.
  const std::vector<std::uint8_t> lane = this->WideLanes();
  parallelFor(this->Nodes.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      Node& node = this->Nodes[i];
      const std::size_t first = nodeRange[2 * i];
      const std::size_t last = lane[i] ? nodeRange[2 * i + 1] : first;
      double n[3] = { 0.0, 0.0, 0.0 };
      for (std::size_t t = first; t < last; ++t)
      {
        for (int k = 0; k < 3; ++k)
        {
          n[k] += this->Triangles[t].n[k];
        }
      }
      const double length = std::sqrt(Dot(n, n));
      node.n[0] = node.n[1] = node.n[2] = node.h = node.r = 0.0;
      node.o[0] = node.o[1] = node.o[2] = 0.0;
      // No slab when the normals cancel (a closed or strongly curved part): it would be no tighter than the box.
      if (!(length > 0.25 * static_cast<double>(last - first)))
      {
        continue;
      }
      const double o[3] = { 0.5 * (node.lo[0] + node.hi[0]), 0.5 * (node.lo[1] + node.hi[1]),
        0.5 * (node.lo[2] + node.hi[2]) };
      for (int k = 0; k < 3; ++k)
      {
        n[k] /= length;
      }
      double lo = Infinity;
      double hi = -Infinity;
      double lateral2 = 0.0;
      for (std::size_t t = first; t < last; ++t)
      {
        const Triangle& tri = this->Triangles[t];
        const double a[3] = { tri.a[0] - o[0], tri.a[1] - o[1], tri.a[2] - o[2] };
        const double vertices[3][3] = { { a[0], a[1], a[2] }, { a[0] + tri.ab[0], a[1] + tri.ab[1], a[2] + tri.ab[2] },
          { a[0] + tri.ac[0], a[1] + tri.ac[1], a[2] + tri.ac[2] } };
        for (const auto& v : vertices)
        {
          const double axial = Dot(n, v);
          double side[3];
          Cross(n, v, side);
          lo = std::min(lo, axial);
          hi = std::max(hi, axial);
          lateral2 = std::max(lateral2, Dot(side, side));
        }
      }
      const double extent = std::max({ node.hi[0] - node.lo[0], node.hi[1] - node.lo[1], node.hi[2] - node.lo[2] });
      for (int k = 0; k < 3; ++k)
      {
        node.n[k] = n[k];
      }
      const double c = 0.5 * (lo + hi);
      for (int k = 0; k < 3; ++k)
      {
        node.o[k] = o[k] + c * n[k];
      }
      // The rounding of the centre moves the coin by up to a few ulps of |o|: pad h and r by that too.
      const double shift = 1e-14 * (std::fabs(node.o[0]) + std::fabs(node.o[1]) + std::fabs(node.o[2]));
      node.h = 0.5 * (hi - lo) * (1.0 + 1e-12) + 1e-12 * extent + shift; // round-off pads (see the header)
      node.r = std::sqrt(lateral2) * (1.0 + 1e-12) + 1e-12 * extent + shift;
    }
  });
}

//------------------------------------------------------------------------------
void PointSurfaceDistance::CollapseToWideNodes(const ParallelFor& parallelFor)
{
  // Every wide node takes the grandchildren of a binary inner node as its children (a child that is a leaf stays
  // one lane), so the 4-wide tree has half the levels. Serial: it only copies bounds; the leaves' triangle packs
  // are filled after it, in parallel.
  this->WideNodes.clear();
  const auto emptyLanes = [](WideNode& wide) {
    for (int j = 0; j < 4; ++j)
    {
      for (int k = 0; k < 3; ++k)
      {
        wide.lo[k][j] = Infinity;
        wide.hi[k][j] = -Infinity;
        wide.o[k][j] = wide.n[k][j] = 0.0;
      }
      wide.h[j] = wide.r[j] = 0.0;
      wide.start[j] = wide.count[j] = 0;
    }
  };
  // Depth first (a stack of binary inner nodes still to collapse, with their wide node), so a subtree's wide nodes
  // lie together in memory, as its queries need them.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pending;
  // Room for the most wide nodes a tree of this many binary nodes can need (about twice what it uses); the room
  // beyond what is written is never touched (no page of it faulted in), so it is kept rather than copied into a
  // fitting array (a second fresh array and its page faults on the calling thread: 2.7 k on 203,520 triangles).
  this->WideNodes.reserve(this->Nodes.size() / 2 + 1);
  std::vector<std::uint32_t> packLeaf; // pack -> its binary leaf
  this->WideNodes.emplace_back();
  emptyLanes(this->WideNodes[0]);
  // Lane j of wide node `wideIndex` becomes binary node `binary`: its bounds, and a leaf range or a new wide node.
  const auto fillLane = [&](std::uint32_t wideIndex, int j, std::uint32_t binary) {
    const Node& c = this->Nodes[binary];
    std::uint32_t start = c.start;
    if (c.count > 0 && this->Surface)
    {
      start = static_cast<std::uint32_t>(packLeaf.size());
      packLeaf.push_back(binary);
    }
    if (c.count == 0)
    {
      start = static_cast<std::uint32_t>(this->WideNodes.size());
      this->WideNodes.emplace_back();
      emptyLanes(this->WideNodes.back());
      pending.emplace_back(binary, start);
    }
    WideNode& wide = this->WideNodes[wideIndex];
    for (int k = 0; k < 3; ++k)
    {
      wide.lo[k][j] = c.lo[k];
      wide.hi[k][j] = c.hi[k];
      wide.o[k][j] = c.o[k];
      wide.n[k][j] = c.n[k];
    }
    wide.h[j] = c.h;
    wide.r[j] = c.r;
    wide.start[j] = start;
    wide.count[j] = c.count;
  };
  if (this->Nodes[0].count > 0) // the whole tree is one leaf: a root with one lane
  {
    fillLane(0, 0, 0);
  }
  else
  {
    pending.emplace_back(0, 0);
  }
  while (!pending.empty())
  {
    const auto [binary, wideIndex] = pending.back();
    pending.pop_back();
    int j = 0;
    for (const std::uint32_t child : { binary + 1, this->Nodes[binary].start })
    {
      const Node& c = this->Nodes[child];
      if (c.count > 0)
      {
        fillLane(wideIndex, j++, child);
      }
      else
      {
        const std::uint32_t rightGrandchild = c.start;
        fillLane(wideIndex, j++, child + 1);
        fillLane(wideIndex, j++, rightGrandchild);
      }
    }
  }
  this->Packs.resize(packLeaf.size());
  if (this->Surface)
  {
    this->PackLaneOf.resize(this->PrimitiveIds.size());
  }
  parallelFor(packLeaf.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const Node& leaf = this->Nodes[packLeaf[i]];
      this->Packs[i] = this->MakePack(leaf.start, leaf.count);
      for (std::uint32_t j = 0; j < leaf.count; ++j)
      {
        this->PackLaneOf[this->PrimitiveIds[leaf.start + j]] = static_cast<std::uint32_t>(4 * i + j);
      }
    }
  });
  this->Nodes = UnsetVector<Node>();
}

//------------------------------------------------------------------------------
PointSurfaceDistance::TrianglePack PointSurfaceDistance::MakePack(std::uint32_t first, std::uint32_t count) const
{
  TrianglePack pack{};
  pack.first = first;
  pack.irregular = 0;
  for (std::uint32_t j = 0; j < 4; ++j)
  {
    const std::uint32_t i = first + (j < count ? j : 0);
    const Triangle& tri = this->Triangles[i];
    for (int k = 0; k < 3; ++k)
    {
      pack.a[k][j] = tri.a[k];
      pack.ab[k][j] = tri.ab[k];
      pack.ac[k][j] = tri.ac[k];
      pack.n[k][j] = tri.n[k];
    }
    pack.id[j] = this->PrimitiveIds[i];
    if (!this->Regular[i])
    {
      pack.irregular |= 1u << j;
    }
  }
  return pack;
}

//------------------------------------------------------------------------------
std::string PointSurfaceDistance::BuildSurface(const double* points, std::size_t pointCount,
  const std::int64_t* triangles, std::size_t triangleCount, const ParallelFor& parallelFor)
{
  const bool slabBounds = this->SlabBounds;
  const bool avx = this->Avx;
  *this = PointSurfaceDistance();
  this->SlabBounds = slabBounds;
  this->Avx = avx;
  if (triangleCount == 0)
  {
    return "the reference surface has no triangle";
  }
  if (triangleCount >= std::numeric_limits<std::uint32_t>::max() / 2)
  {
    return "the reference surface has too many triangles (at most 2^31)";
  }
  if (!AllFinite(points, 3 * pointCount))
  {
    return "the reference surface has a non-finite (NaN or infinite) point coordinate";
  }
  for (std::size_t i = 0; i < 3 * triangleCount; ++i)
  {
    if (triangles[i] < 0 || static_cast<std::size_t>(triangles[i]) >= pointCount)
    {
      std::ostringstream message;
      message << "triangle " << i / 3 << " refers to point " << triangles[i] << ", outside [0, " << pointCount << ")";
      return message.str();
    }
  }

  UnsetVector<double> lo(3 * triangleCount);
  UnsetVector<double> hi(3 * triangleCount);
  UnsetVector<double> centroid(3 * triangleCount);
  parallelFor(triangleCount, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
    {
      const double* v[3] = { points + 3 * triangles[3 * t], points + 3 * triangles[3 * t + 1],
        points + 3 * triangles[3 * t + 2] };
      for (int k = 0; k < 3; ++k)
      {
        lo[3 * t + k] = std::min({ v[0][k], v[1][k], v[2][k] });
        hi[3 * t + k] = std::max({ v[0][k], v[1][k], v[2][k] });
        centroid[3 * t + k] = (v[0][k] + v[1][k] + v[2][k]) / 3.0;
      }
    }
  });
  std::vector<std::uint32_t> nodeRange;
  this->BuildTree(lo, hi, centroid, triangleCount, TriangleLeafSize, nodeRange, parallelFor);
  lo = UnsetVector<double>();
  hi = UnsetVector<double>();
  centroid = UnsetVector<double>();
  this->Surface = true;

  // Triangles in leaf order, and their unit normals.
  UnsetVector<double> faceNormals(3 * triangleCount);
  this->Triangles.resize(triangleCount);
  this->Regular.resize(triangleCount);
  parallelFor(triangleCount, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const std::size_t t = this->PrimitiveIds[i];
      const double* a = points + 3 * triangles[3 * t];
      const double* b = points + 3 * triangles[3 * t + 1];
      const double* c = points + 3 * triangles[3 * t + 2];
      Triangle& tri = this->Triangles[i];
      for (int k = 0; k < 3; ++k)
      {
        tri.a[k] = a[k];
        tri.ab[k] = b[k] - a[k];
        tri.ac[k] = c[k] - a[k];
      }
      Cross(tri.ab, tri.ac, tri.n);
      const double length = std::sqrt(Dot(tri.n, tri.n));
      for (int k = 0; k < 3; ++k)
      {
        tri.n[k] = length > 0.0 ? tri.n[k] / length : 0.0;
        faceNormals[3 * t + k] = tri.n[k];
      }
      const double bc[3] = { tri.ac[0] - tri.ab[0], tri.ac[1] - tri.ab[1], tri.ac[2] - tri.ab[2] };
      this->Regular[i] = length > 0.0 && Dot(tri.ab, tri.ab) > 0.0 && Dot(tri.ac, tri.ac) > 0.0 && Dot(bc, bc) > 0.0;
    }
  });
  this->BuildSlabs(nodeRange, parallelFor);
  nodeRange = std::vector<std::uint32_t>();
  this->CollapseToWideNodes(parallelFor);
  this->Triangles = UnsetVector<Triangle>(); // the packs hold them now
  this->Regular = std::vector<std::uint8_t>();
  this->LeafOf = std::vector<std::uint32_t>();

  // Pseudo-normals, from the corners around each vertex (a counting sort of the 3 * triangleCount corners by
  // vertex, in corner order, so every sum below adds its terms in triangle order whatever the threads).
  this->TriangleVertices.resize(3 * triangleCount);
  parallelFor(triangleCount, [&](std::size_t begin, std::size_t end) {
    std::copy(triangles + 3 * begin, triangles + 3 * end, this->TriangleVertices.begin() + 3 * begin);
  });
  std::vector<std::size_t> cornerStart(pointCount + 1, 0);
  for (std::size_t i = 0; i < 3 * triangleCount; ++i)
  {
    ++cornerStart[static_cast<std::size_t>(triangles[i]) + 1];
  }
  for (std::size_t v = 0; v < pointCount; ++v)
  {
    cornerStart[v + 1] += cornerStart[v];
  }
  UnsetVector<std::size_t> corners(3 * triangleCount); // 3 * triangle + corner, grouped by vertex
  {
    std::vector<std::size_t> fill(cornerStart.begin(), cornerStart.end() - 1);
    for (std::size_t i = 0; i < 3 * triangleCount; ++i)
    {
      corners[fill[static_cast<std::size_t>(triangles[i])]++] = i;
    }
  }
  // Vertices: angle-weighted sums of the unit face normals around them.
  this->VertexNormals.resize(3 * pointCount);
  parallelFor(pointCount, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v)
    {
      double* sum = this->VertexNormals.data() + 3 * v;
      sum[0] = sum[1] = sum[2] = 0.0;
      for (std::size_t j = cornerStart[v]; j < cornerStart[v + 1]; ++j)
      {
        const std::size_t t = corners[j] / 3;
        const std::size_t corner = corners[j] % 3;
        const double* p0 = points + 3 * triangles[3 * t + corner];
        const double* p1 = points + 3 * triangles[3 * t + (corner + 1) % 3];
        const double* p2 = points + 3 * triangles[3 * t + (corner + 2) % 3];
        const double e1[3] = { p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2] };
        const double e2[3] = { p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2] };
        const double l1 = std::sqrt(Dot(e1, e1));
        const double l2 = std::sqrt(Dot(e2, e2));
        if (l1 <= 0.0 || l2 <= 0.0)
        {
          continue;
        }
        const double angle = std::acos(std::clamp(Dot(e1, e2) / (l1 * l2), -1.0, 1.0));
        for (int k = 0; k < 3; ++k)
        {
          sum[k] += angle * faceNormals[3 * t + k];
        }
      }
    }
  });
  // Edges: sums of the unit normals of the faces sharing them (the triangles around the edge's first vertex that
  // also hold its second; each triangle once). An edge from a vertex to itself (a degenerate triangle's) is shared
  // only by degenerate triangles, whose normals are zero.
  this->EdgeNormals.resize(9 * triangleCount);
  parallelFor(triangleCount, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
    {
      std::fill_n(this->EdgeNormals.data() + 9 * t, 9, 0.0);
      for (int e = 0; e < 3; ++e)
      {
        const std::int64_t u = triangles[3 * t + e];
        const std::int64_t w = triangles[3 * t + (e + 1) % 3];
        if (u == w)
        {
          continue;
        }
        double* sum = this->EdgeNormals.data() + 9 * t + 3 * e;
        std::size_t previous = std::numeric_limits<std::size_t>::max();
        const std::size_t vertex = static_cast<std::size_t>(u);
        for (std::size_t j = cornerStart[vertex]; j < cornerStart[vertex + 1]; ++j)
        {
          const std::size_t s = corners[j] / 3;
          if (s == previous)
          {
            continue;
          }
          previous = s;
          if (triangles[3 * s] == w || triangles[3 * s + 1] == w || triangles[3 * s + 2] == w)
          {
            for (int k = 0; k < 3; ++k)
            {
              sum[k] += faceNormals[3 * s + k];
            }
          }
        }
      }
    }
  });
  return {};
}

//------------------------------------------------------------------------------
std::string PointSurfaceDistance::BuildCloud(
  const double* points, std::size_t pointCount, const ParallelFor& parallelFor)
{
  const bool slabBounds = this->SlabBounds;
  const bool avx = this->Avx;
  *this = PointSurfaceDistance();
  this->SlabBounds = slabBounds;
  this->Avx = avx;
  if (pointCount == 0)
  {
    return "the reference point set has no point";
  }
  if (pointCount >= std::numeric_limits<std::uint32_t>::max() / 2)
  {
    return "the reference point set has too many points (at most 2^31)";
  }
  if (!AllFinite(points, 3 * pointCount))
  {
    return "the reference point set has a non-finite (NaN or infinite) coordinate";
  }
  const UnsetVector<double> lo(points, points + 3 * pointCount);
  const UnsetVector<double>& hi = lo;
  const UnsetVector<double>& centroid = lo;
  std::vector<std::uint32_t> nodeRange;
  this->BuildTree(lo, hi, centroid, pointCount, PointLeafSize, nodeRange, parallelFor);
  this->CollapseToWideNodes(parallelFor);
  this->Surface = false;
  this->CloudPoints.resize(3 * pointCount);
  parallelFor(pointCount, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const std::size_t id = this->PrimitiveIds[i];
      for (int k = 0; k < 3; ++k)
      {
        this->CloudPoints[3 * i + k] = points[3 * id + k];
      }
    }
  });
  return {};
}

//------------------------------------------------------------------------------
inline double PointSurfaceDistance::PrimitiveDistance2(std::size_t leafIndex, const double p[3]) const
{
  const double* q = this->CloudPoints.data() + 3 * leafIndex;
  const double d[3] = { p[0] - q[0], p[1] - q[1], p[2] - q[2] };
  return Dot(d, d);
}

//------------------------------------------------------------------------------
inline PointSurfaceDistance::Triangle PointSurfaceDistance::LaneTriangle(const TrianglePack& pack, std::uint32_t lane)
{
  Triangle tri;
  for (int k = 0; k < 3; ++k)
  {
    tri.a[k] = pack.a[k][lane];
    tri.ab[k] = pack.ab[k][lane];
    tri.ac[k] = pack.ac[k][lane];
    tri.n[k] = pack.n[k][lane];
  }
  return tri;
}

//------------------------------------------------------------------------------
inline double PointSurfaceDistance::LaneDistance2(const TrianglePack& pack, std::uint32_t lane, const double p[3])
{
  const Triangle tri = LaneTriangle(pack, lane);
  const double ap[3] = { p[0] - tri.a[0], p[1] - tri.a[1], p[2] - tri.a[2] };
  return (pack.irregular >> lane & 1u) ? EricsonDistance2(ap, tri.ab, tri.ac)
                                       : RegularDistance2(ap, tri.ab, tri.ac, tri.n);
}

//------------------------------------------------------------------------------
inline double PointSurfaceDistance::HintDistance2(std::size_t hint, const double p[3]) const
{
  if (!this->Surface)
  {
    return this->PrimitiveDistance2(this->LeafOf[hint], p);
  }
  const std::uint32_t at = this->PackLaneOf[hint];
  return LaneDistance2(this->Packs[at / 4], at % 4, p);
}

//------------------------------------------------------------------------------
// The traversal, once with SSE2 bounds (as this file is compiled: every x86-64 processor has SSE2) and, on x86-64,
// once more compiled for AVX with four-lane bounds, used when the processor has AVX (checked once at load time).
#define PLANTMORPH_SEARCH SearchSse2
#define PLANTMORPH_SEARCH_AVX 0
#include "PointSurfaceDistanceSearch.inc"
#undef PLANTMORPH_SEARCH
#undef PLANTMORPH_SEARCH_AVX
#if defined(PLANTMORPH_AVX_SEARCH)
#pragma GCC push_options
#pragma GCC target("avx")
#define PLANTMORPH_SEARCH SearchAvx
#define PLANTMORPH_SEARCH_AVX 1
#include "PointSurfaceDistanceSearch.inc"
#undef PLANTMORPH_SEARCH
#undef PLANTMORPH_SEARCH_AVX
#pragma GCC pop_options
#endif

//------------------------------------------------------------------------------
DistanceQueryResult PointSurfaceDistance::Query(const double p[3], std::int64_t hint) const
{
  if (this->WideNodes.empty())
  {
    DistanceQueryResult result;
    result.distance = result.signedDistance = Infinity;
    return result;
  }
#if defined(PLANTMORPH_AVX_SEARCH)
  if (this->Avx && CpuHasAvx)
  {
    return this->SearchAvx(p, hint);
  }
#endif
  return this->SearchSse2(p, hint);
}

//------------------------------------------------------------------------------
DistanceQueryResult PointSurfaceDistance::QueryResult(
  const double p[3], double best2, std::size_t bestLeaf, std::size_t bestPack) const
{
  DistanceQueryResult result;
  if (bestLeaf == std::numeric_limits<std::size_t>::max())
  {
    // Only when p has a NaN coordinate (every comparison fails).
    result.distance = result.signedDistance = std::numeric_limits<double>::quiet_NaN();
    for (double& c : result.closest)
    {
      c = std::numeric_limits<double>::quiet_NaN();
    }
    return result;
  }
  if (!this->Surface)
  {
    result.primitive = static_cast<std::int64_t>(this->PrimitiveIds[bestLeaf]);
    const double* q = this->CloudPoints.data() + 3 * bestLeaf;
    for (int k = 0; k < 3; ++k)
    {
      result.closest[k] = q[k];
    }
    result.distance = result.signedDistance = std::sqrt(best2);
    return result;
  }
  const TrianglePack& pack = this->Packs[bestPack];
  const std::uint32_t lane = static_cast<std::uint32_t>(bestLeaf - pack.first);
  const std::size_t original = pack.id[lane];
  result.primitive = static_cast<std::int64_t>(original);
  const Triangle tri = LaneTriangle(pack, lane);
  const double ap[3] = { p[0] - tri.a[0], p[1] - tri.a[1], p[2] - tri.a[2] };
  double v = 0.0;
  double w = 0.0;
  TriangleFeature feature;
  int index = 0;
  ClosestOnTriangle(ap, tri.ab, tri.ac, v, w, feature, index);
  double offset[3];
  for (int k = 0; k < 3; ++k)
  {
    result.closest[k] = tri.a[k] + v * tri.ab[k] + w * tri.ac[k];
    offset[k] = ap[k] - v * tri.ab[k] - w * tri.ac[k];
  }
  result.distance = std::sqrt(Dot(offset, offset));
  const double* normal = tri.n;
  if (feature == TriangleFeature::Edge)
  {
    normal = this->EdgeNormals.data() + 9 * original + 3 * index;
  }
  else if (feature == TriangleFeature::Vertex)
  {
    normal = this->VertexNormals.data() + 3 * this->TriangleVertices[3 * original + index];
  }
  result.signedDistance = Dot(offset, normal) < 0.0 ? -result.distance : result.distance;
  return result;
}

//------------------------------------------------------------------------------
void PointSurfaceDistance::QueryMany(const double* points, std::size_t count, double* distance, double* signedDistance,
  double* closest, std::int64_t* primitive, const ParallelFor& parallelFor,
  const std::function<bool(double)>& progress) const
{
  // Queries run in Morton (Z-curve) order of the points, so consecutive queries are near each other and each one
  // starts from its predecessor's nearest primitive as a tight first bound. Results go to the input order.
  // The order: key = 30-bit Morton code (10 bits an axis) << 32 | input index, sorted by an LSD radix sort on the
  // code's three 10-bit digits (stable, so equal codes stay in input order).
  UnsetVector<std::uint64_t> order;
  const bool sorted = count >= 4096 && count < std::numeric_limits<std::uint32_t>::max();
  if (sorted)
  {
    order = MortonOrder(points, count, parallelFor);
  }
  // Batches of queries: the batch's points are first gathered from the input into a small buffer and its results
  // scattered back after, each in a tight loop of its own (random accesses the processor overlaps), rather than one
  // random read and several random writes between two searches (15% of the time on a randomly ordered cloud).
  constexpr std::size_t Batch = 1024;
  // In input order the batch's points and results are scattered over the arrays: each loop asks for the cache lines
  // of the point `Ahead` places on, so their misses (and those of the results' first writes) overlap.
  constexpr std::size_t Ahead = 16;
  const auto body = [&](std::size_t offset) {
    return [&, offset](std::size_t begin, std::size_t end) {
      std::int64_t hint = -1;
      std::vector<double> batchPoints(3 * Batch);
      std::vector<DistanceQueryResult> results(Batch);
      const auto inputIndex = [&](std::size_t s) {
        return sorted ? static_cast<std::size_t>(order[s] & 0xffffffffULL) : s;
      };
      for (std::size_t first = offset + begin; first < offset + end; first += Batch)
      {
        const std::size_t size = std::min(Batch, offset + end - first);
        for (std::size_t j = 0; j < size; ++j)
        {
          if (sorted && j + Ahead < size)
          {
            Prefetch(points + 3 * inputIndex(first + j + Ahead), false);
          }
          const double* p = points + 3 * inputIndex(first + j);
          batchPoints[3 * j] = p[0]; // element by element: std::copy_n here became a memmove call
          batchPoints[3 * j + 1] = p[1];
          batchPoints[3 * j + 2] = p[2];
        }
        for (std::size_t j = 0; j < size; ++j)
        {
          results[j] = this->Query(&batchPoints[3 * j], hint);
          hint = results[j].primitive;
        }
        for (std::size_t j = 0; j < size; ++j)
        {
          if (sorted && j + Ahead < size)
          {
            const std::size_t next = inputIndex(first + j + Ahead);
            for (double* out : { distance, signedDistance })
            {
              if (out)
              {
                Prefetch(out + next, true);
              }
            }
            if (closest)
            {
              Prefetch(closest + 3 * next, true);
              Prefetch(closest + 3 * next + 2, true); // the triple may straddle two cache lines
            }
          }
          const std::size_t i = inputIndex(first + j);
          const DistanceQueryResult& r = results[j];
          if (distance)
          {
            distance[i] = r.distance;
          }
          if (signedDistance)
          {
            signedDistance[i] = r.signedDistance;
          }
          if (closest)
          {
            closest[3 * i] = r.closest[0];
            closest[3 * i + 1] = r.closest[1];
            closest[3 * i + 2] = r.closest[2];
          }
          if (primitive)
          {
            primitive[i] = r.primitive;
          }
        }
      }
    };
  };
  // Blocks only for progress reports (each block is one parallel loop).
  const std::size_t block = progress ? std::max<std::size_t>(std::size_t(1) << 16, count / 20) : count;
  for (std::size_t start = 0; start < count; start += block)
  {
    const std::size_t stop = std::min(count, start + block);
    parallelFor(stop - start, body(start));
    if (progress && !progress(static_cast<double>(stop) / static_cast<double>(count)))
    {
      return;
    }
  }
}

//------------------------------------------------------------------------------
void PointSurfaceDistance::GetTriangleNormal(std::int64_t triangle, double normal[3]) const
{
  const std::uint32_t at = this->PackLaneOf[static_cast<std::size_t>(triangle)];
  for (int k = 0; k < 3; ++k)
  {
    normal[k] = this->Packs[at / 4].n[k][at % 4];
  }
}

//------------------------------------------------------------------------------
std::size_t PointSurfaceDistance::MemoryBytes() const
{
  return this->WideNodes.size() * sizeof(WideNode) + this->PrimitiveIds.capacity() * sizeof(std::uint32_t) +
    this->LeafOf.capacity() * sizeof(std::uint32_t) + this->Triangles.capacity() * sizeof(Triangle) +
    this->Regular.capacity() + this->Packs.capacity() * sizeof(TrianglePack) +
    this->PackLaneOf.capacity() * sizeof(std::uint32_t) + this->CloudPoints.capacity() * sizeof(double) +
    this->TriangleVertices.capacity() * sizeof(std::int64_t) + this->EdgeNormals.capacity() * sizeof(double) +
    this->VertexNormals.capacity() * sizeof(double);
}

} // namespace plantmorph
