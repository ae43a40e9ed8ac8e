#include "PointSurfaceDistance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>
#include <vector>

namespace plantmorph
{

namespace
{
constexpr double Infinity = std::numeric_limits<double>::infinity();
constexpr std::size_t TriangleLeafSize = 4;
constexpr std::size_t PointLeafSize = 8;
constexpr int StackSize = 96; // the median-split tree has depth <= log2(2^32) + 1

inline double Dot(const double a[3], const double b[3])
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/// Squared distance from p to the box [lo, hi] (0 inside).
inline double BoxDistance2(const double p[3], const double lo[3], const double hi[3])
{
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    const double below = lo[k] - p[k];
    const double above = p[k] - hi[k];
    const double d = std::max(0.0, std::max(below, above));
    d2 += d * d;
  }
  return d2;
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
std::string PointSurfaceDistance::BuildTree(std::vector<double>& lo, std::vector<double>& hi,
  std::vector<double>& centroid, std::size_t count, std::size_t leafSize)
{
  std::vector<std::uint32_t> order(count);
  std::iota(order.begin(), order.end(), 0u);
  this->Nodes.clear();
  this->Nodes.reserve(2 * (count / leafSize + 1));

  struct Task
  {
    std::size_t begin, end, parent; // parent: the node whose right child this is (npos for the root / left)
  };
  constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();
  std::vector<Task> tasks{ { 0, count, npos } };
  while (!tasks.empty())
  {
    const Task task = tasks.back();
    tasks.pop_back();
    const std::size_t nodeIndex = this->Nodes.size();
    if (task.parent != npos)
    {
      this->Nodes[task.parent].start = static_cast<std::uint32_t>(nodeIndex);
    }
    Node node{};
    double clo[3] = { Infinity, Infinity, Infinity };
    double chi[3] = { -Infinity, -Infinity, -Infinity };
    for (int k = 0; k < 3; ++k)
    {
      node.lo[k] = Infinity;
      node.hi[k] = -Infinity;
    }
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
      this->Nodes.push_back(node);
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
    node.count = 0;
    this->Nodes.push_back(node);
    // Depth first: the left child is processed next (it lands at nodeIndex + 1), the right one after its subtree.
    tasks.push_back({ mid, task.end, nodeIndex });
    tasks.push_back({ task.begin, mid, npos });
  }
  this->PrimitiveIds = std::move(order);
  this->LeafOf.assign(count, 0);
  for (std::size_t i = 0; i < count; ++i)
  {
    this->LeafOf[this->PrimitiveIds[i]] = static_cast<std::uint32_t>(i);
  }
  this->Nodes.shrink_to_fit();
  return {};
}

//------------------------------------------------------------------------------
std::string PointSurfaceDistance::BuildSurface(
  const double* points, std::size_t pointCount, const std::int64_t* triangles, std::size_t triangleCount)
{
  *this = PointSurfaceDistance();
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
      message << "triangle " << i / 3 << " refers to point " << triangles[i] << ", outside [0, " << pointCount
              << ")";
      return message.str();
    }
  }

  std::vector<double> lo(3 * triangleCount);
  std::vector<double> hi(3 * triangleCount);
  std::vector<double> centroid(3 * triangleCount);
  for (std::size_t t = 0; t < triangleCount; ++t)
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
  this->BuildTree(lo, hi, centroid, triangleCount, TriangleLeafSize);
  lo = std::vector<double>();
  hi = std::vector<double>();
  centroid = std::vector<double>();
  this->Surface = true;

  // Triangles in leaf order, and their unit normals.
  std::vector<double> faceNormals(3 * triangleCount);
  this->Triangles.resize(triangleCount);
  for (std::size_t i = 0; i < triangleCount; ++i)
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
  }

  // Pseudo-normals. Vertices: angle-weighted sums of the unit face normals around them.
  this->TriangleVertices.assign(triangles, triangles + 3 * triangleCount);
  this->VertexNormals.assign(3 * pointCount, 0.0);
  for (std::size_t t = 0; t < triangleCount; ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
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
        this->VertexNormals[3 * triangles[3 * t + corner] + k] += angle * faceNormals[3 * t + k];
      }
    }
  }
  // Edges: sums of the unit normals of the faces sharing them (found by sorting the undirected edges).
  struct EdgeUse
  {
    std::int64_t lo, hi;
    std::size_t slot; // 3 * triangle + local edge
  };
  std::vector<EdgeUse> uses(3 * triangleCount);
  for (std::size_t t = 0; t < triangleCount; ++t)
  {
    for (int e = 0; e < 3; ++e)
    {
      const std::int64_t u = triangles[3 * t + e];
      const std::int64_t v = triangles[3 * t + (e + 1) % 3];
      uses[3 * t + e] = { std::min(u, v), std::max(u, v), 3 * t + static_cast<std::size_t>(e) };
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.lo < y.lo || (x.lo == y.lo && (x.hi < y.hi || (x.hi == y.hi && x.slot < y.slot)));
  });
  this->EdgeNormals.assign(9 * triangleCount, 0.0);
  for (std::size_t first = 0; first < uses.size();)
  {
    std::size_t last = first;
    double sum[3] = { 0.0, 0.0, 0.0 };
    while (last < uses.size() && uses[last].lo == uses[first].lo && uses[last].hi == uses[first].hi)
    {
      for (int k = 0; k < 3; ++k)
      {
        sum[k] += faceNormals[3 * (uses[last].slot / 3) + k];
      }
      ++last;
    }
    for (std::size_t i = first; i < last; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        this->EdgeNormals[3 * uses[i].slot + k] = sum[k];
      }
    }
    first = last;
  }
  return {};
}

//------------------------------------------------------------------------------
std::string PointSurfaceDistance::BuildCloud(const double* points, std::size_t pointCount)
{
  *this = PointSurfaceDistance();
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
  std::vector<double> lo(points, points + 3 * pointCount);
  std::vector<double> hi = lo;
  std::vector<double> centroid = lo;
  this->BuildTree(lo, hi, centroid, pointCount, PointLeafSize);
  this->Surface = false;
  this->CloudPoints.resize(3 * pointCount);
  for (std::size_t i = 0; i < pointCount; ++i)
  {
    const std::size_t id = this->PrimitiveIds[i];
    for (int k = 0; k < 3; ++k)
    {
      this->CloudPoints[3 * i + k] = points[3 * id + k];
    }
  }
  return {};
}

//------------------------------------------------------------------------------
inline double PointSurfaceDistance::PrimitiveDistance2(std::size_t leafIndex, const double p[3], double best2) const
{
  if (!this->Surface)
  {
    const double* q = this->CloudPoints.data() + 3 * leafIndex;
    const double d[3] = { p[0] - q[0], p[1] - q[1], p[2] - q[2] };
    return Dot(d, d);
  }
  const Triangle& tri = this->Triangles[leafIndex];
  const double ap[3] = { p[0] - tri.a[0], p[1] - tri.a[1], p[2] - tri.a[2] };
  const double plane = Dot(ap, tri.n);
  if (plane * plane > best2)
  {
    return Infinity; // the triangle's plane alone is farther than the best so far
  }
  double v = 0.0;
  double w = 0.0;
  TriangleFeature feature;
  int index = 0;
  ClosestOnTriangle(ap, tri.ab, tri.ac, v, w, feature, index);
  const double d[3] = { v * tri.ab[0] + w * tri.ac[0] - ap[0], v * tri.ab[1] + w * tri.ac[1] - ap[1],
    v * tri.ab[2] + w * tri.ac[2] - ap[2] };
  return Dot(d, d);
}

//------------------------------------------------------------------------------
DistanceQueryResult PointSurfaceDistance::Query(const double p[3], std::int64_t hint) const
{
  DistanceQueryResult result;
  if (this->Nodes.empty())
  {
    result.distance = result.signedDistance = Infinity;
    return result;
  }
  double best2 = Infinity;
  std::size_t bestLeaf = std::numeric_limits<std::size_t>::max();
  if (hint >= 0 && static_cast<std::size_t>(hint) < this->LeafOf.size())
  {
    bestLeaf = this->LeafOf[static_cast<std::size_t>(hint)];
    best2 = this->PrimitiveDistance2(bestLeaf, p, Infinity);
  }

  std::uint32_t stack[StackSize];
  double stackDistance[StackSize];
  int top = 0;
  stack[top] = 0;
  stackDistance[top++] = BoxDistance2(p, this->Nodes[0].lo, this->Nodes[0].hi);
  while (top > 0)
  {
    --top;
    if (stackDistance[top] >= best2)
    {
      continue;
    }
    const std::uint32_t nodeIndex = stack[top];
    const Node& node = this->Nodes[nodeIndex];
    if (node.count > 0)
    {
      for (std::size_t i = node.start; i < node.start + node.count; ++i)
      {
        const double d2 = this->PrimitiveDistance2(i, p, best2);
        if (d2 < best2)
        {
          best2 = d2;
          bestLeaf = i;
        }
      }
      continue;
    }
    const std::uint32_t left = nodeIndex + 1;
    const std::uint32_t right = node.start;
    const double dl = BoxDistance2(p, this->Nodes[left].lo, this->Nodes[left].hi);
    const double dr = BoxDistance2(p, this->Nodes[right].lo, this->Nodes[right].hi);
    // Push the farther child first so the nearer one is visited next.
    if (dl <= dr)
    {
      if (dr < best2)
      {
        stack[top] = right;
        stackDistance[top++] = dr;
      }
      if (dl < best2)
      {
        stack[top] = left;
        stackDistance[top++] = dl;
      }
    }
    else
    {
      if (dl < best2)
      {
        stack[top] = left;
        stackDistance[top++] = dl;
      }
      if (dr < best2)
      {
        stack[top] = right;
        stackDistance[top++] = dr;
      }
    }
  }

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
  const std::size_t original = this->PrimitiveIds[bestLeaf];
  result.primitive = static_cast<std::int64_t>(original);
  if (!this->Surface)
  {
    const double* q = this->CloudPoints.data() + 3 * bestLeaf;
    for (int k = 0; k < 3; ++k)
    {
      result.closest[k] = q[k];
    }
    result.distance = result.signedDistance = std::sqrt(best2);
    return result;
  }
  const Triangle& tri = this->Triangles[bestLeaf];
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
void PointSurfaceDistance::QueryMany(const double* points, std::size_t count, double* distance,
  double* signedDistance, double* closest, std::int64_t* primitive, const ParallelFor& parallelFor) const
{
  // Queries run in Morton (Z-curve) order of the points, so consecutive queries are near each other and each one
  // starts from its predecessor's nearest primitive as a tight first bound. Results go to the input order.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order;
  const bool sorted = count >= 4096 && count < std::numeric_limits<std::uint32_t>::max();
  if (sorted)
  {
    double lo[3] = { Infinity, Infinity, Infinity };
    double hi[3] = { -Infinity, -Infinity, -Infinity };
    for (std::size_t i = 0; i < count; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        const double x = points[3 * i + k];
        if (std::isfinite(x))
        {
          lo[k] = std::min(lo[k], x);
          hi[k] = std::max(hi[k], x);
        }
      }
    }
    const auto spread = [](std::uint64_t v) { // 21 bits -> every third bit
      v &= 0x1fffff;
      v = (v | v << 32) & 0x1f00000000ffffULL;
      v = (v | v << 16) & 0x1f0000ff0000ffULL;
      v = (v | v << 8) & 0x100f00f00f00f00fULL;
      v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
      v = (v | v << 2) & 0x1249249249249249ULL;
      return v;
    };
    order.resize(count);
    parallelFor(count, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
      {
        std::uint64_t code = 0;
        for (int k = 0; k < 3; ++k)
        {
          const double extent = hi[k] - lo[k];
          const double x = points[3 * i + k];
          const double t = extent > 0.0 && std::isfinite(x) ? (x - lo[k]) / extent : 0.0;
          code |= spread(static_cast<std::uint64_t>(std::clamp(t, 0.0, 1.0) * 2097151.0)) << k;
        }
        order[i] = { code, static_cast<std::uint32_t>(i) };
      }
    });
    std::sort(order.begin(), order.end());
  }
  parallelFor(count, [&](std::size_t begin, std::size_t end) {
    std::int64_t hint = -1;
    for (std::size_t s = begin; s < end; ++s)
    {
      const std::size_t i = sorted ? order[s].second : s;
      const DistanceQueryResult r = this->Query(points + 3 * i, hint);
      hint = r.primitive;
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
  });
}

//------------------------------------------------------------------------------
void PointSurfaceDistance::GetTriangleNormal(std::int64_t triangle, double normal[3]) const
{
  const Triangle& tri = this->Triangles[this->LeafOf[static_cast<std::size_t>(triangle)]];
  normal[0] = tri.n[0];
  normal[1] = tri.n[1];
  normal[2] = tri.n[2];
}

//------------------------------------------------------------------------------
std::size_t PointSurfaceDistance::MemoryBytes() const
{
  return this->Nodes.capacity() * sizeof(Node) + this->PrimitiveIds.capacity() * sizeof(std::uint32_t) +
    this->LeafOf.capacity() * sizeof(std::uint32_t) + this->Triangles.capacity() * sizeof(Triangle) +
    this->CloudPoints.capacity() * sizeof(double) + this->TriangleVertices.capacity() * sizeof(std::int64_t) +
    this->EdgeNormals.capacity() * sizeof(double) + this->VertexNormals.capacity() * sizeof(double);
}

} // namespace plantmorph
