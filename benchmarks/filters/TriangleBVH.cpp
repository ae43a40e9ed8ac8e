// SPDX-License-Identifier: GPL-3.0-or-later
#include "TriangleBVH.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace plantmorph
{

const double TriangleBVH::Empty[6] = { 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 };

namespace
{
constexpr int Bins = 16;
constexpr std::size_t LeafSize = 4;     // always a leaf at or below this
constexpr std::size_t MaxLeafSize = 16; // a leaf above LeafSize only when no split pays
constexpr int MaxDepth = 100;           // deeper ranges become leaves (only for pathological input)
constexpr int StackSize = MaxDepth + 8;

struct Box
{
  double lo[3] = { std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
    std::numeric_limits<double>::infinity() };
  double hi[3] = { -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
    -std::numeric_limits<double>::infinity() };
  void Grow(const Box& b)
  {
    for (int k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], b.lo[k]);
      hi[k] = std::max(hi[k], b.hi[k]);
    }
  }
  void Grow(const double* x)
  {
    for (int k = 0; k < 3; ++k)
    {
      lo[k] = std::min(lo[k], x[k]);
      hi[k] = std::max(hi[k], x[k]);
    }
  }
  double HalfArea() const
  {
    if (lo[0] > hi[0])
      return 0.0;
    const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
  }
};

struct Range
{
  std::uint32_t node;
  std::size_t begin, end;
  int depth;
};

/// The split of [begin, end) with the lowest binned SAH cost: axis and bin boundary (bins below go left); axis -1
/// when no split beats a leaf (or the centroids coincide).
struct Split
{
  int axis = -1;
  int bin = 0;
  double cost = std::numeric_limits<double>::infinity();
};

Split FindSplit(const std::vector<Box>& boxes, const std::vector<double>& centroids,
  const std::vector<std::uint32_t>& refs, std::size_t begin, std::size_t end, const Box& centroidBox)
{
  Split best;
  for (int axis = 0; axis < 3; ++axis)
  {
    const double lo = centroidBox.lo[axis], extent = centroidBox.hi[axis] - lo;
    if (!(extent > 0.0))
      continue;
    const double scale = Bins / extent;
    std::array<Box, Bins> binBox;
    std::array<std::size_t, Bins> binCount{};
    for (std::size_t i = begin; i < end; ++i)
    {
      const std::uint32_t r = refs[i];
      const int b = std::min(Bins - 1, static_cast<int>((centroids[3 * r + axis] - lo) * scale));
      binBox[b].Grow(boxes[r]);
      ++binCount[b];
    }
    std::array<double, Bins> rightCost{};
    Box right;
    std::size_t rightCount = 0;
    for (int b = Bins - 1; b > 0; --b)
    {
      right.Grow(binBox[b]);
      rightCount += binCount[b];
      rightCost[b] = right.HalfArea() * static_cast<double>(rightCount);
    }
    Box left;
    std::size_t leftCount = 0;
    for (int b = 1; b < Bins; ++b)
    {
      left.Grow(binBox[b - 1]);
      leftCount += binCount[b - 1];
      const double cost = left.HalfArea() * static_cast<double>(leftCount) + rightCost[b];
      if (leftCount > 0 && leftCount < end - begin && cost < best.cost)
      {
        best.axis = axis;
        best.bin = b;
        best.cost = cost;
      }
    }
  }
  return best;
}
} // namespace

void TriangleBVH::Build(const std::vector<double>& points, const std::vector<std::int64_t>& triangles)
{
  this->Nodes.clear();
  this->Vertices.clear();
  this->Order.clear();
  const std::size_t n = triangles.size() / 3;
  if (n == 0)
    return;
  std::vector<Box> boxes(n);
  std::vector<double> centroids(3 * n);
  std::vector<std::uint32_t> refs(n);
  for (std::size_t t = 0; t < n; ++t)
  {
    for (int k = 0; k < 3; ++k)
      boxes[t].Grow(&points[3 * static_cast<std::size_t>(triangles[3 * t + k])]);
    for (int k = 0; k < 3; ++k)
      centroids[3 * t + k] = 0.5 * (boxes[t].lo[k] + boxes[t].hi[k]);
    refs[t] = static_cast<std::uint32_t>(t);
  }
  this->Nodes.reserve(2 * n / LeafSize + 1);
  this->Nodes.push_back(Node{});
  std::vector<Range> stack{ Range{ 0, 0, n, 0 } };
  while (!stack.empty())
  {
    const Range r = stack.back();
    stack.pop_back();
    Box box, centroidBox;
    for (std::size_t i = r.begin; i < r.end; ++i)
    {
      box.Grow(boxes[refs[i]]);
      centroidBox.Grow(&centroids[3 * refs[i]]);
    }
    // Pad by a few ulps of the coordinates so rounding in the box test never culls a triangle it touches.
    for (int k = 0; k < 3; ++k)
    {
      const double pad =
        8.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(box.lo[k]), std::abs(box.hi[k]));
      this->Nodes[r.node].box[k] = box.lo[k] - pad;
      this->Nodes[r.node].box[k + 3] = box.hi[k] + pad;
    }
    const std::size_t count = r.end - r.begin;
    Split split;
    if (count > LeafSize && r.depth < MaxDepth)
    {
      split = FindSplit(boxes, centroids, refs, r.begin, r.end, centroidBox);
      // Intersection and traversal costs taken equal: a leaf costs count * area.
      const double leafCost = static_cast<double>(count) * box.HalfArea();
      if (split.axis >= 0 && count <= MaxLeafSize && split.cost + box.HalfArea() >= leafCost)
        split.axis = -1;
      if (split.axis < 0 && count > MaxLeafSize)
      {
        // Coincident centroids: halve by position in the list (any split keeps the tree correct).
        split.axis = 3;
      }
    }
    if (split.axis < 0)
    {
      Node& leaf = this->Nodes[r.node];
      leaf.first = static_cast<std::uint32_t>(r.begin);
      leaf.count = static_cast<std::uint32_t>(count);
      continue;
    }
    std::size_t middle;
    if (split.axis == 3)
    {
      middle = r.begin + count / 2;
      split.axis = 0;
    }
    else
    {
      const int axis = split.axis;
      const double lo = centroidBox.lo[axis], scale = Bins / (centroidBox.hi[axis] - lo);
      const auto it = std::partition(refs.begin() + static_cast<std::ptrdiff_t>(r.begin),
        refs.begin() + static_cast<std::ptrdiff_t>(r.end), [&](std::uint32_t t) {
          return std::min(Bins - 1, static_cast<int>((centroids[3 * t + axis] - lo) * scale)) < split.bin;
        });
      middle = static_cast<std::size_t>(it - refs.begin());
    }
    const auto firstChild = static_cast<std::uint32_t>(this->Nodes.size());
    this->Nodes[r.node].first = firstChild;
    this->Nodes[r.node].count = 0;
    this->Nodes[r.node].axis = static_cast<std::uint32_t>(split.axis);
    this->Nodes.push_back(Node{});
    this->Nodes.push_back(Node{});
    stack.push_back(Range{ firstChild + 1, middle, r.end, r.depth + 1 });
    stack.push_back(Range{ firstChild, r.begin, middle, r.depth + 1 });
  }
  this->Nodes.shrink_to_fit();
  this->Order.resize(n);
  this->Vertices.resize(9 * n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint32_t t = refs[i];
    this->Order[i] = static_cast<std::int64_t>(t);
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        this->Vertices[9 * i + 3 * k + c] = points[3 * static_cast<std::size_t>(triangles[3 * t + k]) + c];
  }
}

std::size_t TriangleBVH::MemoryBytes() const
{
  return this->Nodes.capacity() * sizeof(Node) + this->Vertices.capacity() * sizeof(double) +
    this->Order.capacity() * sizeof(std::int64_t);
}

namespace
{
/// The ray in Woop et al.'s sheared frame: kz the largest direction component, (kx, ky) the other two in an order
/// that keeps the winding, and the shear taking the direction to (0, 0, 1).
struct ShearedRay
{
  double origin[3];
  int kx, ky, kz;
  double sx, sy, sz;
};

ShearedRay Shear(const double origin[3], const double direction[3])
{
  ShearedRay r;
  for (int k = 0; k < 3; ++k)
    r.origin[k] = origin[k];
  const double ax = std::abs(direction[0]), ay = std::abs(direction[1]), az = std::abs(direction[2]);
  r.kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  r.kx = (r.kz + 1) % 3;
  r.ky = (r.kx + 1) % 3;
  if (direction[r.kz] < 0.0)
    std::swap(r.kx, r.ky);
  r.sx = direction[r.kx] / direction[r.kz];
  r.sy = direction[r.ky] / direction[r.kz];
  r.sz = 1.0 / direction[r.kz];
  return r;
}

/// Woop et al.'s watertight test; on a nearer hit than hit.t updates t, u, v and returns true.
bool IntersectTriangle(const ShearedRay& r, const double* v, TriangleHit& hit)
{
  const double a[3] = { v[0] - r.origin[0], v[1] - r.origin[1], v[2] - r.origin[2] };
  const double b[3] = { v[3] - r.origin[0], v[4] - r.origin[1], v[5] - r.origin[2] };
  const double c[3] = { v[6] - r.origin[0], v[7] - r.origin[1], v[8] - r.origin[2] };
  const double ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
  const double bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
  const double cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
  double e0 = cx * by - cy * bx;
  double e1 = ax * cy - ay * cx;
  double e2 = bx * ay - by * ax;
  if (e0 == 0.0 || e1 == 0.0 || e2 == 0.0)
  {
    // On an edge in double precision: decide in long double, as the paper falls back to higher precision.
    using L = long double;
    e0 = static_cast<double>(L(cx) * L(by) - L(cy) * L(bx));
    e1 = static_cast<double>(L(ax) * L(cy) - L(ay) * L(cx));
    e2 = static_cast<double>(L(bx) * L(ay) - L(by) * L(ax));
  }
  if ((e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0))
    return false;
  const double det = e0 + e1 + e2;
  if (det == 0.0)
    return false;
  const double az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
  const double tScaled = e0 * az + e1 * bz + e2 * cz;
  if (det > 0.0 ? (tScaled <= 0.0 || tScaled >= hit.t * det) : (tScaled >= 0.0 || tScaled <= hit.t * det))
    return false;
  const double inverse = 1.0 / det;
  hit.t = tScaled * inverse;
  hit.u = e1 * inverse;
  hit.v = e2 * inverse;
  return true;
}
} // namespace

TriangleHit TriangleBVH::Intersect(const double origin[3], const double direction[3], double tMax) const
{
  TriangleHit hit;
  hit.t = tMax;
  if (this->Nodes.empty())
    return hit;
  const ShearedRay ray = Shear(origin, direction);
  double inverse[3];
  int sign[3];
  for (int k = 0; k < 3; ++k)
  {
    inverse[k] = direction[k] != 0.0 ? 1.0 / direction[k] : std::copysign(1e300, direction[k]);
    sign[k] = inverse[k] < 0.0 ? 1 : 0;
  }
  // Ize 2013: the far slab distances scaled up by 1 + 2 gamma(3) make the box test conservative.
  constexpr double eps = std::numeric_limits<double>::epsilon() / 2.0;
  constexpr double farScale = 1.0 + 2.0 * (3.0 * eps / (1.0 - 3.0 * eps));
  auto boxEntry = [&](const Node& node, double limit) {
    const double* b = node.box;
    double t0 = (b[3 * sign[0] + 0] - origin[0]) * inverse[0];
    double t1 = (b[3 * (1 - sign[0]) + 0] - origin[0]) * inverse[0] * farScale;
    t0 = std::max(t0, (b[3 * sign[1] + 1] - origin[1]) * inverse[1]);
    t1 = std::min(t1, (b[3 * (1 - sign[1]) + 1] - origin[1]) * inverse[1] * farScale);
    t0 = std::max(t0, (b[3 * sign[2] + 2] - origin[2]) * inverse[2]);
    t1 = std::min(t1, (b[3 * (1 - sign[2]) + 2] - origin[2]) * inverse[2] * farScale);
    t0 = std::max(t0, 0.0);
    t1 = std::min(t1, limit);
    return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
  };
  if (boxEntry(this->Nodes[0], hit.t) == std::numeric_limits<double>::infinity())
    return hit;
  std::uint32_t stack[StackSize];
  double stackEntry[StackSize]; // where the beam enters each pushed box (it was tested when pushed)
  int top = 0;
  std::uint32_t current = 0;
  std::int64_t stored = -1;
  while (true)
  {
    const Node& node = this->Nodes[current];
    if (node.count > 0)
    {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
      {
        if (IntersectTriangle(ray, &this->Vertices[9 * static_cast<std::size_t>(i)], hit))
          stored = i;
      }
    }
    else
    {
      std::uint32_t near = node.first, far = node.first + 1;
      if (sign[node.axis])
        std::swap(near, far);
      const double tNear = boxEntry(this->Nodes[near], hit.t);
      const double tFar = boxEntry(this->Nodes[far], hit.t);
      const bool hitNear = tNear != std::numeric_limits<double>::infinity();
      const bool hitFar = tFar != std::numeric_limits<double>::infinity();
      if (hitNear && hitFar)
      {
        if (tFar < tNear)
        {
          std::swap(near, far);
          stackEntry[top] = tNear;
        }
        else
        {
          stackEntry[top] = tFar;
        }
        stack[top++] = far;
        current = near;
        continue;
      }
      if (hitNear || hitFar)
      {
        current = hitNear ? near : far;
        continue;
      }
    }
    // Pop, skipping boxes the beam enters beyond the nearest hit found since they were pushed.
    bool found = false;
    while (top > 0)
    {
      --top;
      if (stackEntry[top] <= hit.t)
      {
        current = stack[top];
        found = true;
        break;
      }
    }
    if (!found)
      break;
  }
  hit.triangle = stored >= 0 ? this->Order[static_cast<std::size_t>(stored)] : -1;
  if (stored < 0)
    hit.t = tMax;
  return hit;
}

} // namespace plantmorph
