// SPDX-License-Identifier: GPL-3.0-or-later
// The project's own bounding volume hierarchy over triangles, the virtual scanner's first ray caster, kept here only as
// virtual_scanner_benchmark's comparison: Embree (filters/scanner/core/RayCaster.h) measured faster and replaced it in
// the plugin (whichever caster measures faster is the one kept in the plugin). Built once per surface (binned SAH,
// double precision), then traversed by many beams at once, each beam independently.
//
// Exactness: the ray-triangle test is Woop, Benthin and Wald's watertight intersection (JCGT 2(1), 2013): the ray is
// sheared so it runs along +z, and the three edge functions are evaluated on the sheared vertices, each vertex
// transformed the same way whichever triangle it belongs to. An edge shared by two triangles therefore gives the
// same edge function (up to sign) in both, so a beam through a closed surface hits at least one of them: no beam
// slips through a crack. Edge functions that come out exactly zero are recomputed in long double. The box test is
// conservative (Ize 2013, "Robust BVH ray traversal": the far distance is scaled by 1 + 2 gamma(3)), and the boxes
// are padded by a few ulps at build time, so no triangle the exact test would hit is culled by its box.
#pragma once

#include "RayCaster.h" // TriangleHit

#include <cstddef>
#include <cstdint>
#include <vector>

namespace plantmorph
{

class TriangleBVH
{
public:
  /// Builds over `triangles` (three point indices each) of `points` (x, y, z each). Degenerate triangles are kept
  /// (they are never hit). Indices out of range are the caller's error (checked by ValidateMesh in VirtualScan.h).
  void Build(const std::vector<double>& points, const std::vector<std::int64_t>& triangles);

  /// The nearest hit with 0 < t < tMax of the ray origin + t * direction; no hit: triangle = -1.
  TriangleHit Intersect(const double origin[3], const double direction[3], double tMax) const;

  std::size_t TriangleCount() const { return this->Order.size(); }
  std::size_t NodeCount() const { return this->Nodes.size(); }
  /// Bytes held by the hierarchy (nodes, the triangles' copied vertices, the order).
  std::size_t MemoryBytes() const;

  /// Bounds of everything, {xmin, ymin, zmin, xmax, ymax, zmax} (all zero when empty).
  const double* Bounds() const { return this->Nodes.empty() ? Empty : this->Nodes.front().box; }

private:
  struct Node
  {
    double box[6];       // xmin, ymin, zmin, xmax, ymax, zmax
    std::uint32_t first; // leaf: first stored triangle; inner: index of the first child (the second is first + 1)
    std::uint32_t count; // leaf: triangle count (> 0); inner: 0
    std::uint32_t axis;  // inner: split axis (the child on the beam's side of it is visited first)
    std::uint32_t pad;
  };
  std::vector<Node> Nodes;
  std::vector<double> Vertices;    // 9 per triangle, in Order
  std::vector<std::int64_t> Order; // the input triangle of each stored triangle
  static const double Empty[6];
};

} // namespace plantmorph
