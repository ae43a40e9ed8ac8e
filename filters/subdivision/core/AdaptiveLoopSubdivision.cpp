// SPDX-License-Identifier: GPL-3.0-or-later
#include "AdaptiveLoopSubdivision.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RangeError.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>

namespace plantmorph
{

namespace
{
constexpr int MaxReportedIds = 10;
/// ChordError's share of SurfaceError's isotropic estimate e (odd point against the unmoved chord), which catches
/// edges along asymptotic directions of saddles (sagitta and e' near 0, yet Loop bends the surface next to them).
/// Measured on the benchmark's Fixed blades (benchmarks/README.md), as triangles against uniform level 3's at its
/// deviation: 0 gives 0.68 (bent ginkgo) and 0.84 (pin oak), 0.25 gives 0.52 and 0.74, 0.5 gives 0.38 and 0.53,
/// 0.75 gives 0.40 and 0.54; 0.5 keeps the rulings of a cylinder at half the across edges' error.
constexpr double ChordErrorIsotropicShare = 0.5;
/// ChordError's factor on the estimate of an edge with an end that never moves (a Fixed or Refine feature point, a
/// Loop corner). Next to such a point the subdivided surface bends ever more sharply towards the kept polygon, and
/// the deviation there halves per level instead of quartering: on the benchmark's Fixed blades uniform levels 2 -> 3
/// go from 7.8e-4 to 3.6e-4 (cucumber), set next to the margin. Measured (benchmarks/README.md, Chord error with no
/// limit-offset terms): 2 gives the cucumber 0.84 / 0.59 / 0.23 of uniform levels 1-3's triangles at their
/// deviation (1 gives 0.91 / 0.77 / 0.27), 4 gives 0.84 / 0.59 / 0.23 too; the pin oak moves little with it alone.
constexpr double ChordErrorPinnedFactor = 2.0;
/// ChordError's share of an end's limit offset delta (its distance from its Loop limit position along its normal)
/// on every edge of that end. A part left at a coarse level keeps its points where they are, delta off the limit
/// surface; the chord estimates do not see that. Measured on the Fixed blades with the pinned factor 2 and the
/// forced move below: 0.5 gives the pin oak 0.85 / 0.48 / 0.36 (0 gives 0.97 / 0.70 / 0.53, 0.35 gives
/// 0.91 / 0.59 / 0.42) and the cucumber 0.81 / 0.46 / 0.26 (0 gives 0.67 / 0.44 / 0.23; 1 for every edge,
/// without the forced move, 0.97 / 0.63 / 0.26: it splits rulings and across edges alike). The numbers other
/// than 0.5's were measured with an earlier, order-dependent version of the forced move (benchmarks/README.md).
constexpr double ChordErrorLimitOffsetShare = 0.5;

/// Every level's connectivity: vertex -> corners, the edge table, and triangle -> edges.
struct EdgeTable
{
  std::vector<int> vertexCornerOffsets;         ///< nV + 1
  LoopArray<int> vertexCorners;                 ///< corner ids (3 t + c), ascending per vertex
  std::vector<int> edgeOffsets;                 ///< nV + 1: edges (v, w), w > v, of vertex v
  LoopArray<int> edgeOther;                     ///< w of every edge, ascending per v
  std::vector<int> edgeUses;                    ///< number of triangles using the edge
  std::vector<int> edgeTriangles;               ///< 2 per edge, -1 when absent
  std::vector<int> edgeOpposite;                ///< the opposite vertex in each of those triangles
  std::vector<int> triangleEdges;               ///< 3 per triangle: local edge c is (tri[c], tri[c + 1])
  std::vector<unsigned char> edgeSameDirection; ///< both triangles run along the edge the same way (misoriented)

  std::size_t NumberOfEdges() const { return this->edgeOther.size(); }

  int EdgeOf(int a, int b) const
  {
    if (a > b)
      std::swap(a, b);
    const auto first = this->edgeOther.begin() + this->edgeOffsets[a];
    const auto last = this->edgeOther.begin() + this->edgeOffsets[a + 1];
    const auto it = std::lower_bound(first, last, b);
    return (it != last && *it == b) ? static_cast<int>(it - this->edgeOther.begin()) : -1;
  }
};

/// Neighbours of v with larger id (larger = true) or all of them, sorted and unique, into `out`.
void GatherNeighbours(const LoopArray<int>& tri, const EdgeTable& table, int v, bool largerOnly, std::vector<int>& out)
{
  out.clear();
  for (int i = table.vertexCornerOffsets[v]; i < table.vertexCornerOffsets[v + 1]; ++i)
  {
    const int corner = table.vertexCorners[i];
    const int base = corner - corner % 3;
    const int c = corner - base;
    const int next = tri[base + (c + 1) % 3];
    const int prev = tri[base + (c + 2) % 3];
    if (!largerOnly || next > v)
      out.push_back(next);
    if (!largerOnly || prev > v)
      out.push_back(prev);
  }
  // Small lists: insertion sort beats std::sort here.
  for (std::size_t i = 1; i < out.size(); ++i)
  {
    const int x = out[i];
    std::size_t j = i;
    while (j > 0 && out[j - 1] > x)
    {
      out[j] = out[j - 1];
      --j;
    }
    out[j] = x;
  }
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

void ExclusiveScan(std::vector<int>& counts)
{
  int sum = 0;
  for (int& c : counts)
  {
    const int x = c;
    c = sum;
    sum += x;
  }
}

void BuildEdgeTable(const LoopArray<int>& tri, std::size_t nV, const ParallelForFunction& parallelFor, EdgeTable& table)
{
  const std::size_t nCorners = tri.size();
  const std::size_t nT = nCorners / 3;
  // Vertex -> corners by counting sort (ascending corner ids per vertex: deterministic).
  table.vertexCornerOffsets.assign(nV + 1, 0);
  for (std::size_t i = 0; i < nCorners; ++i)
    ++table.vertexCornerOffsets[tri[i] + 1];
  for (std::size_t v = 0; v < nV; ++v)
    table.vertexCornerOffsets[v + 1] += table.vertexCornerOffsets[v];
  table.vertexCorners.resize(nCorners);
  {
    std::vector<int> fill(table.vertexCornerOffsets.begin(), table.vertexCornerOffsets.end() - 1);
    for (std::size_t i = 0; i < nCorners; ++i)
      table.vertexCorners[fill[tri[i]]++] = static_cast<int>(i);
  }

  // Edges bucketed by their smaller vertex: count, scan, fill.
  table.edgeOffsets.assign(nV + 1, 0);
  parallelFor(nV, [&](std::size_t begin, std::size_t end) {
    std::vector<int> nbrs;
    nbrs.reserve(32);
    for (std::size_t v = begin; v < end; ++v)
    {
      GatherNeighbours(tri, table, static_cast<int>(v), true, nbrs);
      table.edgeOffsets[v] = static_cast<int>(nbrs.size());
    }
  });
  ExclusiveScan(table.edgeOffsets);
  const std::size_t nE = static_cast<std::size_t>(table.edgeOffsets[nV]);
  table.edgeOther.resize(nE);
  table.edgeUses.assign(nE, 0);
  table.edgeTriangles.assign(2 * nE, -1);
  table.edgeOpposite.assign(2 * nE, -1);
  table.edgeSameDirection.assign(nE, 0);
  table.triangleEdges.assign(3 * nT, -1);
  parallelFor(nV, [&](std::size_t begin, std::size_t end) {
    std::vector<int> nbrs;
    nbrs.reserve(32);
    for (std::size_t vv = begin; vv < end; ++vv)
    {
      const int v = static_cast<int>(vv);
      GatherNeighbours(tri, table, v, true, nbrs);
      const int first = table.edgeOffsets[v];
      std::copy(nbrs.begin(), nbrs.end(), table.edgeOther.begin() + first);
      for (int i = table.vertexCornerOffsets[v]; i < table.vertexCornerOffsets[v + 1]; ++i)
      {
        const int corner = table.vertexCorners[i];
        const int base = corner - corner % 3;
        const int c = corner - base;
        const int t = base / 3;
        const int next = tri[base + (c + 1) % 3];
        const int prev = tri[base + (c + 2) % 3];
        // (v, next) is local edge c, run from v; (prev, v) is local edge c + 2, run towards v.
        for (int side = 0; side < 2; ++side)
        {
          const int w = side == 0 ? next : prev;
          if (w <= v)
            continue;
          const int e = first + static_cast<int>(std::lower_bound(nbrs.begin(), nbrs.end(), w) - nbrs.begin());
          const int slot = table.edgeUses[e]++;
          if (slot < 2)
          {
            table.edgeTriangles[2 * e + slot] = t;
            table.edgeOpposite[2 * e + slot] = side == 0 ? prev : next;
            // Remember the direction of the first use in the flag; compare with the second.
            if (slot == 0)
              table.edgeSameDirection[e] = static_cast<unsigned char>(side);
            else
              table.edgeSameDirection[e] = static_cast<unsigned char>(table.edgeSameDirection[e] == side);
          }
          table.triangleEdges[base + (side == 0 ? c : (c + 2) % 3)] = e;
        }
      }
    }
  });
  // Edges used once: the flag held the direction, not a comparison.
  parallelFor(nE, [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
      if (table.edgeUses[e] != 2)
        table.edgeSameDirection[e] = 0;
  });
}

std::string IdList(const std::vector<std::string>& items, std::size_t total)
{
  std::ostringstream out;
  for (std::size_t i = 0; i < items.size(); ++i)
    out << (i ? ", " : "") << items[i];
  if (total > items.size())
    out << " and " << (total - items.size()) << " more";
  return out.str();
}

/// Checks ids, degenerate triangles and NaN; "" when fine.
std::string ValidateInput(const AdaptiveLoopMesh& mesh)
{
  if (mesh.points.size() % 3 != 0)
    return "points must hold x, y, z triples";
  if (mesh.triangles.size() % 3 != 0)
    return "triangles must hold three point ids each";
  const std::size_t nV = mesh.NumberOfPoints();
  if (nV >= static_cast<std::size_t>(std::numeric_limits<int>::max() / 2))
    return "too many points for 32-bit ids";
  if (mesh.attributeComponents < 0 || mesh.attributes.size() != static_cast<std::size_t>(mesh.attributeComponents) * nV)
    return "attributes must hold attributeComponents values per point";
  if (!mesh.region.empty() && mesh.region.size() != nV)
    return "region must be empty or hold one value per point";
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (!std::isfinite(mesh.points[i]))
    {
      std::ostringstream out;
      out << "point " << i / 3 << " has a non-finite coordinate (NaN or infinity)";
      return out.str();
    }
  for (std::size_t t = 0; t < mesh.NumberOfTriangles(); ++t)
  {
    const int a = mesh.triangles[3 * t], b = mesh.triangles[3 * t + 1], c = mesh.triangles[3 * t + 2];
    const int n = static_cast<int>(nV);
    if (a < 0 || b < 0 || c < 0 || a >= n || b >= n || c >= n)
    {
      std::ostringstream out;
      out << "triangle " << t << " (" << a << ", " << b << ", " << c << ") uses a point id outside [0, " << n << ")";
      return out.str();
    }
    if (a == b || b == c || c == a)
    {
      std::ostringstream out;
      out << "triangle " << t << " (" << a << ", " << b << ", " << c << ") repeats a point id (degenerate)";
      return out.str();
    }
  }
  for (const auto& e : mesh.featureEdges)
    if (e[0] < 0 || e[1] < 0 || static_cast<std::size_t>(e[0]) >= nV || static_cast<std::size_t>(e[1]) >= nV)
      return "a feature edge uses a point id outside the points";
  return "";
}

/// Non-manifold edges (three or more triangles); "" when manifold.
std::string ValidateManifoldEdges(std::size_t nV, const EdgeTable& table)
{
  std::vector<std::string> items;
  std::size_t count = 0;
  for (std::size_t v = 0; v < nV; ++v)
    for (int e = table.edgeOffsets[v]; e < table.edgeOffsets[v + 1]; ++e)
      if (table.edgeUses[e] > 2)
      {
        if (items.size() < MaxReportedIds)
        {
          std::ostringstream out;
          out << "edge (" << v << ", " << table.edgeOther[e] << ") in " << table.edgeUses[e] << " triangles";
          items.push_back(out.str());
        }
        ++count;
      }
  if (count)
    return "non-manifold input: " + IdList(items, count) +
      " (every edge must belong to one or two triangles; split the surface or remove the extra triangles)";

  return "";
}

/// Number of triangles in the fan around v reached from its first triangle by crossing shared edges.
int CountFan(const LoopArray<int>& tri, const EdgeTable& table, int v)
{
  const int k = table.vertexCornerOffsets[v + 1] - table.vertexCornerOffsets[v];
  if (k == 0)
    return 0;
  const int startCorner = table.vertexCorners[table.vertexCornerOffsets[v]];
  const int startTriangle = startCorner / 3;
  int visited = 1;
  for (int way = 0; way < 2; ++way)
  {
    int t = startTriangle;
    int c = startCorner % 3;
    int e = table.triangleEdges[3 * t + (way == 0 ? c : (c + 2) % 3)];
    for (int step = 0; step < k; ++step)
    {
      if (table.edgeUses[e] != 2)
        break;
      const int other = table.edgeTriangles[2 * e] == t ? table.edgeTriangles[2 * e + 1] : table.edgeTriangles[2 * e];
      if (other == startTriangle)
        return visited; // closed fan
      t = other;
      c = tri[3 * t] == v ? 0 : (tri[3 * t + 1] == v ? 1 : 2);
      const int e1 = table.triangleEdges[3 * t + c];
      const int e2 = table.triangleEdges[3 * t + (c + 2) % 3];
      e = e1 == e ? e2 : e1;
      ++visited;
    }
  }
  return visited;
}

std::string ValidateManifoldVertices(
  const LoopArray<int>& tri, std::size_t nV, const EdgeTable& table, const ParallelForFunction& parallelFor)
{
  std::vector<unsigned char> bad(nV, 0);
  parallelFor(nV, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v)
    {
      const int k = table.vertexCornerOffsets[v + 1] - table.vertexCornerOffsets[v];
      if (k > 1 && CountFan(tri, table, static_cast<int>(v)) != k)
        bad[v] = 1;
    }
  });
  std::vector<std::string> items;
  std::size_t count = 0;
  for (std::size_t v = 0; v < nV; ++v)
    if (bad[v])
    {
      if (items.size() < MaxReportedIds)
        items.push_back(std::to_string(v));
      ++count;
    }
  if (!count)
    return "";
  return "non-manifold input: point" + std::string(count > 1 ? "s " : " ") + IdList(items, count) +
    (count > 1 ? " join" : " joins") +
    " several separate fans of triangles (a pinched vertex); split them into separate points";
}

double LoopBeta(int n)
{
  if (n == 3)
    return 3.0 / 16.0;
  const double c = 0.375 + 0.25 * std::cos(2.0 * Pi / n);
  return (0.625 - c * c) / n;
}

/// chi of Loop's limit mask for n neighbours: v_inf = (1 - n chi) v + chi sum(neighbours).
double LoopLimitChi(int n)
{
  return 1.0 / (3.0 / (8.0 * LoopBeta(n)) + n);
}

/// |n . d| for a unit (or zero) n; the full length of d when n is zero.
double NormalComponent(const double* n, const double* d)
{
  if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0)
    return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return std::abs(n[0] * d[0] + n[1] * d[1] + n[2] * d[2]);
}

void Normalise(double* n)
{
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int j = 0; j < 3; ++j)
    n[j] = len > 0.0 ? n[j] / len : 0.0;
}

/// Vertex v's unit normal: the sum of its triangles' unit normals (`normals`, 3 per triangle), normalised.
void VertexNormal(const EdgeTable& table, const std::vector<double>& normals, int v, double* normal)
{
  normal[0] = normal[1] = normal[2] = 0.0;
  for (int i = table.vertexCornerOffsets[v]; i < table.vertexCornerOffsets[v + 1]; ++i)
  {
    const double* n = normals.data() + 3 * static_cast<std::size_t>(table.vertexCorners[i] / 3);
    for (int j = 0; j < 3; ++j)
      normal[j] += n[j];
  }
  Normalise(normal);
}

int OddRegion(int ra, int rb, bool boundary)
{
  if (boundary)
  {
    if (ra == 4 || rb == 4)
      return 4;
    return ra == rb ? ra : 0;
  }
  return (ra == rb && ra != 4) ? ra : 0;
}

/// Applies one stencil (ids, weights) to positions and attributes of output point `out`.
struct StencilWriter
{
  const double* points;
  const double* attributes;
  int components;
  double* outPoints;
  double* outAttributes;

  void Copy(std::size_t out, int v) const
  {
    for (int j = 0; j < 3; ++j)
      outPoints[3 * out + j] = points[3 * static_cast<std::size_t>(v) + j];
    for (int j = 0; j < components; ++j)
      outAttributes[components * out + j] = attributes[static_cast<std::size_t>(components) * v + j];
  }

  void Apply(std::size_t out, const int* ids, const double* weights, int n) const
  {
    for (int j = 0; j < 3; ++j)
    {
      double s = 0.0;
      for (int i = 0; i < n; ++i)
        s += weights[i] * points[3 * static_cast<std::size_t>(ids[i]) + j];
      outPoints[3 * out + j] = s;
    }
    for (int j = 0; j < components; ++j)
    {
      double s = 0.0;
      for (int i = 0; i < n; ++i)
        s += weights[i] * attributes[static_cast<std::size_t>(components) * ids[i] + j];
      outAttributes[components * out + j] = s;
    }
  }
};

double Distance2(const double* p, int a, int b)
{
  double s = 0.0;
  for (int j = 0; j < 3; ++j)
  {
    const double d = p[3 * static_cast<std::size_t>(a) + j] - p[3 * static_cast<std::size_t>(b) + j];
    s += d * d;
  }
  return s;
}

/// The settings as the steps of a level read them.
struct SplitRules
{
  bool haveRegion = false;
  bool midveinIsFeature = false;
  double lambda = 1.0;
  bool splitAll = false;
  double cosLimit = 0.0;
  FeatureRule rule = FeatureRule::Fixed;
  bool byChord = false;
  bool byError = false;
  double tolerance = 0.0;
  std::size_t maximumTriangles = 0;

  SplitRules(const AdaptiveLoopParameters& settings, bool region)
    : haveRegion(region)
    , midveinIsFeature(settings.midveinIsFeature)
    , lambda(settings.flatnessThreshold)
    , splitAll(settings.edgeAngleThreshold >= 180.0)
    // dihedral < T  <=>  angle between normals > 180 - T  <=>  cos(angle) < cos(180 - T)
    , cosLimit(std::cos((180.0 - settings.edgeAngleThreshold) * Pi / 180.0))
    , rule(settings.featureRule)
    , byChord(settings.refinementRule == RefinementRule::ChordError)
    , byError(settings.refinementRule == RefinementRule::SurfaceError || byChord)
    , tolerance(settings.errorTolerance)
    , maximumTriangles(settings.maximumTriangles)
  {
  }
};

/// What one level knows of its input mesh's edges and vertices, step by step.
struct LevelState
{
  std::vector<double> normals;        ///< unit triangle normals, 3 per triangle (when needed)
  std::vector<unsigned char> marked;  ///< user-marked feature edges
  std::vector<int> edgeFirst;         ///< smaller vertex of every edge
  std::vector<unsigned char> feature; ///< boundary, midvein, user-marked
  std::vector<int> oddId;             ///< 1/0 split flags, then the output point ids (-1: no split)
  std::vector<int> featureCount;      ///< feature edges per vertex
  std::vector<int> featureNbr;        ///< first two feature neighbours per vertex
  std::vector<double> limitOffset;    ///< SurfaceError, ChordError: offset from the limit along the normal
  std::vector<double> vertexNormal;   ///< ChordError: unit vertex normals (eq. (1))
  std::vector<double> chordEstimate;  ///< ChordError: every interior non-feature edge's estimate
  std::vector<double> loopMove;       ///< SurfaceError, ChordError: Loop's move of every vertex
  FeatureRule rule = FeatureRule::Fixed;

  /// Points that never move (feature points under Fixed and Refine, corners under Loop): the estimates, the limit
  /// offsets and the even points all use this.
  bool Pinned(int v) const
  {
    const int f = this->featureCount[static_cast<std::size_t>(v)];
    return f > 0 && (this->rule != FeatureRule::Loop || f != 2);
  }
};

/// Unit triangle normals (not needed when every edge splits and every vertex moves).
void ComputeTriangleNormals(
  const AdaptiveLoopMesh& mesh, const SplitRules& rules, const ParallelForFunction& parallelFor, LevelState& s)
{
  const std::size_t nT = mesh.NumberOfTriangles();
  const LoopArray<int>& tri = mesh.triangles;
  const double* P = mesh.points.data();
  const bool needNormals = rules.byError || !rules.splitAll || rules.lambda < 1.0;
  std::vector<double>& normals = s.normals;
  normals.assign(needNormals ? 3 * nT : 0, 0.0);
  parallelFor(needNormals ? nT : 0, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
    {
      const double* a = P + 3 * static_cast<std::size_t>(tri[3 * t]);
      const double* b = P + 3 * static_cast<std::size_t>(tri[3 * t + 1]);
      const double* c = P + 3 * static_cast<std::size_t>(tri[3 * t + 2]);
      const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
      const double w[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
      double n[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0] };
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (int j = 0; j < 3; ++j)
        normals[3 * t + j] = len > 0.0 ? n[j] / len : 0.0;
    }
  });
}

/// Feature edges (boundary, midvein, user-marked) and feature vertices: their feature-edge count and first two
/// feature neighbours (serial, in edge order).
void ClassifyFeatures(const AdaptiveLoopMesh& mesh, const EdgeTable& table, const SplitRules& rules,
  const ParallelForFunction& parallelFor, LevelState& s)
{
  const std::size_t nV = mesh.NumberOfPoints();
  const std::size_t nE = table.NumberOfEdges();
  s.marked.assign(nE, 0);
  for (const auto& fe : mesh.featureEdges)
  {
    const int e = table.EdgeOf(fe[0], fe[1]);
    if (e >= 0)
      s.marked[e] = 1;
  }
  s.edgeFirst.assign(nE, 0);
  s.feature.assign(nE, 0);
  s.oddId.assign(nE, 0);
  parallelFor(nV, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v)
      for (int e = table.edgeOffsets[v]; e < table.edgeOffsets[v + 1]; ++e)
        s.edgeFirst[e] = static_cast<int>(v);
  });
  parallelFor(nE, [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
    {
      const int a = s.edgeFirst[e], b = table.edgeOther[e];
      s.feature[e] = table.edgeUses[e] == 1 || s.marked[e] ||
        (rules.midveinIsFeature && rules.haveRegion && mesh.region[a] == 1 && mesh.region[b] == 1);
    }
  });

  s.featureCount.assign(nV, 0);
  s.featureNbr.assign(2 * nV, -1);
  for (std::size_t e = 0; e < nE; ++e)
    if (s.feature[e])
    {
      const int a = s.edgeFirst[e], b = table.edgeOther[e];
      if (s.featureCount[a] < 2)
        s.featureNbr[2 * a + s.featureCount[a]] = b;
      if (s.featureCount[b] < 2)
        s.featureNbr[2 * b + s.featureCount[b]] = a;
      ++s.featureCount[a];
      ++s.featureCount[b];
    }
}

/// SurfaceError and ChordError: every vertex's limit offset along its normal and Loop's move of it at this level;
/// ChordError: every vertex's unit normal (eq. (1)), feature vertices too.
void EstimateLimitOffsets(const AdaptiveLoopMesh& mesh, const EdgeTable& table, const SplitRules& rules,
  const ParallelForFunction& parallelFor, LevelState& s)
{
  const std::size_t nV = mesh.NumberOfPoints();
  const std::size_t nE = table.NumberOfEdges();
  const LoopArray<int>& tri = mesh.triangles;
  const double* P = mesh.points.data();
  const bool byError = rules.byError, byChord = rules.byChord;
  s.limitOffset.assign(byError ? nV : 0, 0.0);
  s.vertexNormal.assign(byChord ? 3 * nV : 0, 0.0);
  parallelFor(byChord ? nV : 0, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v)
      VertexNormal(table, s.normals, static_cast<int>(v), s.vertexNormal.data() + 3 * v);
  });
  s.chordEstimate.assign(byChord ? nE : 0, 0.0);
  s.loopMove.assign(byError ? 3 * nV : 0, 0.0);
  parallelFor(byError ? nV : 0, [&](std::size_t begin, std::size_t end) {
    std::vector<int> nbrs;
    nbrs.reserve(32);
    for (std::size_t vv = begin; vv < end; ++vv)
    {
      const int v = static_cast<int>(vv);
      const int k = table.vertexCornerOffsets[v + 1] - table.vertexCornerOffsets[v];
      const int f = s.featureCount[vv];
      const double* pv = P + 3 * vv;
      if (k == 0 || s.Pinned(v))
        continue; // never moves
      if (f == 2)
      {
        const double* p = P + 3 * static_cast<std::size_t>(s.featureNbr[2 * vv]);
        const double* q = P + 3 * static_cast<std::size_t>(s.featureNbr[2 * vv + 1]);
        double d[3], chord[3];
        for (int j = 0; j < 3; ++j)
        {
          d[j] = (p[j] + q[j] - 2.0 * pv[j]) / 6.0;
          s.loopMove[3 * vv + j] = (p[j] + q[j] - 2.0 * pv[j]) / 8.0;
          chord[j] = q[j] - p[j];
        }
        Normalise(chord);
        const double along = d[0] * chord[0] + d[1] * chord[1] + d[2] * chord[2];
        for (int j = 0; j < 3; ++j)
          d[j] -= along * chord[j];
        s.limitOffset[vv] = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        continue;
      }
      double normal[3];
      VertexNormal(table, s.normals, v, normal);
      GatherNeighbours(tri, table, v, false, nbrs);
      const int n = static_cast<int>(nbrs.size());
      const double chi = LoopLimitChi(n), beta = LoopBeta(n);
      double d[3] = { 0.0, 0.0, 0.0 };
      for (int w : nbrs)
        for (int j = 0; j < 3; ++j)
          d[j] += P[3 * static_cast<std::size_t>(w) + j] - pv[j];
      for (int j = 0; j < 3; ++j)
      {
        s.loopMove[3 * vv + j] = beta * d[j];
        d[j] *= chi;
      }
      s.limitOffset[vv] = NormalComponent(normal, d);
    }
  });
}

/// Whether interior non-feature edge e splits by SurfaceError or ChordError (ChordError also records its estimate).
bool SplitsByError(
  const AdaptiveLoopMesh& mesh, const EdgeTable& table, const SplitRules& rules, std::size_t e, LevelState& s)
{
  const double* P = mesh.points.data();
  const int a = s.edgeFirst[e], b = table.edgeOther[e];
  const int t0 = table.edgeTriangles[2 * e], t1 = table.edgeTriangles[2 * e + 1];
  const double* n0 = s.normals.data() + 3 * static_cast<std::size_t>(t0);
  const double* n1 = s.normals.data() + 3 * static_cast<std::size_t>(t1);
  const double sign = table.edgeSameDirection[e] ? -1.0 : 1.0;
  double normal[3] = { n0[0] + sign * n1[0], n0[1] + sign * n1[1], n0[2] + sign * n1[2] };
  Normalise(normal);
  const double* pa = P + 3 * static_cast<std::size_t>(a);
  const double* pb = P + 3 * static_cast<std::size_t>(b);
  const double* pc = P + 3 * static_cast<std::size_t>(table.edgeOpposite[2 * e]);
  const double* pd = P + 3 * static_cast<std::size_t>(table.edgeOpposite[2 * e + 1]);
  // The odd point's offset from the chord midpoint, before and after the ends' Loop moves (whether they
  // move depends on their other edges).
  double d[3], moved[3];
  for (int j = 0; j < 3; ++j)
  {
    d[j] = (pc[j] + pd[j] - pa[j] - pb[j]) / 8.0;
    moved[j] =
      d[j] - 0.5 * (s.loopMove[3 * static_cast<std::size_t>(a) + j] + s.loopMove[3 * static_cast<std::size_t>(b) + j]);
  }
  double error;
  if (rules.byChord)
  {
    // The chord's own sagitta, kappa(t) l^2 / 8 with the normal curvature along the edge
    // kappa(t) = (N_b - N_a) . t / l (zero along a ruling of a cylinder, whatever the curvature across
    // it), the odd point's offset from the moved chord (zero there too on a regular mesh), and a share of
    // its offset from the unmoved chord.
    const double* na = s.vertexNormal.data() + 3 * static_cast<std::size_t>(a);
    const double* nb = s.vertexNormal.data() + 3 * static_cast<std::size_t>(b);
    double sagitta = 0.0;
    for (int j = 0; j < 3; ++j)
      sagitta += (nb[j] - na[j]) * (pb[j] - pa[j]);
    error = std::max({ std::abs(sagitta) / 8.0, NormalComponent(normal, moved),
      ChordErrorIsotropicShare * NormalComponent(normal, d) });
    if (s.Pinned(a) || s.Pinned(b))
      error *= ChordErrorPinnedFactor;
    s.chordEstimate[e] = error;
    error = std::max(error, ChordErrorLimitOffsetShare * std::max(s.limitOffset[a], s.limitOffset[b]));
  }
  else
    error =
      std::max({ NormalComponent(normal, d), NormalComponent(normal, moved), s.limitOffset[a], s.limitOffset[b] });
  return error >= rules.tolerance;
}

/// Every edge's split flag (1/0 in oddId) by the refinement rule; feature edges by the feature rule.
void FlagSplitEdges(const AdaptiveLoopMesh& mesh, const EdgeTable& table, const SplitRules& rules,
  const ParallelForFunction& parallelFor, LevelState& s)
{
  parallelFor(table.NumberOfEdges(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
    {
      const int a = s.edgeFirst[e], b = table.edgeOther[e];
      bool split;
      if (s.feature[e])
        split = rules.rule != FeatureRule::Fixed &&
          (!rules.byError || std::max(s.limitOffset[a], s.limitOffset[b]) >= rules.tolerance);
      else if (rules.byError)
        split = SplitsByError(mesh, table, rules, e, s);
      else if (rules.splitAll)
        split = true;
      else
      {
        const double* n0 = s.normals.data() + 3 * static_cast<std::size_t>(table.edgeTriangles[2 * e]);
        const double* n1 = s.normals.data() + 3 * static_cast<std::size_t>(table.edgeTriangles[2 * e + 1]);
        double dot = n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2];
        if (table.edgeSameDirection[e])
          dot = -dot; // inconsistently oriented neighbours: compare as if oriented alike
        split = dot < rules.cosLimit;
      }
      s.oddId[e] = split ? 1 : 0;
    }
  });
}

/// ChordError: a point whose limit offset reaches the tolerance moves: when none of its edges splits (so it would
/// stay where it is, delta off the limit surface), its interior non-feature edge with the largest estimate splits
/// (ties: the lowest edge id). Decided on the flags set above, written after all reads.
void ForceMovesOffTheLimit(std::size_t nV, const EdgeTable& table, const SplitRules& rules,
  const ParallelForFunction& parallelFor, LevelState& s)
{
  std::vector<int> forced(nV, -1);
  parallelFor(nV, [&](std::size_t begin, std::size_t end) {
    for (std::size_t vv = begin; vv < end; ++vv)
    {
      if (!(s.limitOffset[vv] >= rules.tolerance))
        continue;
      const int v = static_cast<int>(vv);
      int best = -1;
      bool moves = false;
      for (int i = table.vertexCornerOffsets[v]; i < table.vertexCornerOffsets[v + 1] && !moves; ++i)
      {
        const int corner = table.vertexCorners[i];
        const int base = corner - corner % 3;
        const int c = corner - base;
        for (const int e : { table.triangleEdges[base + c], table.triangleEdges[base + (c + 2) % 3] })
        {
          moves = moves || s.oddId[e] != 0;
          if (!s.feature[e] &&
            (best < 0 || s.chordEstimate[e] > s.chordEstimate[best] ||
              (s.chordEstimate[e] == s.chordEstimate[best] && e < best)))
            best = e;
        }
      }
      if (!moves)
        forced[vv] = best;
    }
  });
  for (std::size_t v = 0; v < nV; ++v)
    if (forced[v] >= 0)
      s.oddId[forced[v]] = 1;
}

/// A feature edge also splits when another edge of its triangle does: the curve gains samples where the surface
/// next to it is refined. Decided on the interior edges' flags (set above), written after all reads.
void SplitFeatureEdgesBesideSplits(const EdgeTable& table, const ParallelForFunction& parallelFor, LevelState& s)
{
  const std::size_t nE = table.NumberOfEdges();
  std::vector<unsigned char> alsoSplit(nE, 0);
  parallelFor(nE, [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
    {
      if (!s.feature[e] || s.oddId[e])
        continue;
      for (int side = 0; side < 2; ++side)
      {
        const int t = table.edgeTriangles[2 * e + side];
        if (t < 0)
          continue;
        for (int c = 0; c < 3; ++c)
        {
          const int other = table.triangleEdges[3 * static_cast<std::size_t>(t) + c];
          if (other != static_cast<int>(e) && !s.feature[other] && s.oddId[other])
            alsoSplit[e] = 1;
        }
      }
    }
  });
  for (std::size_t e = 0; e < nE; ++e)
    if (alsoSplit[e])
      s.oddId[e] = 1;
}

/// Turns the split flags into output point ids (nV, nV + 1, ... in edge order; -1: no split); the split count.
int NumberOddPoints(std::size_t nV, std::vector<int>& oddId)
{
  int nSplit = 0;
  for (std::size_t e = 0; e < oddId.size(); ++e)
  {
    const int s = oddId[e];
    oddId[e] = s ? static_cast<int>(nV) + nSplit : -1;
    nSplit += s;
  }
  return nSplit;
}

/// Children per triangle (offsets, nT + 1) and the output triangle count; "" or the MaximumTriangles error.
std::string CountChildren(const EdgeTable& table, std::size_t nT, const std::vector<int>& oddId,
  std::size_t maximumTriangles, int level, const ParallelForFunction& parallelFor, std::vector<int>& childOffsets,
  std::size_t& nTout)
{
  childOffsets.assign(nT + 1, 0);
  parallelFor(nT, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
    {
      int n = 1;
      for (int c = 0; c < 3; ++c)
        n += oddId[table.triangleEdges[3 * t + c]] >= 0 ? 1 : 0;
      childOffsets[t] = n;
    }
  });
  nTout = 0;
  for (std::size_t t = 0; t < nT; ++t)
  {
    const int n = childOffsets[t];
    childOffsets[t] = static_cast<int>(nTout);
    nTout += static_cast<std::size_t>(n);
    if (nTout > maximumTriangles)
    {
      std::ostringstream out;
      out << "level " << level + 1 << " would make more than MaximumTriangles = " << maximumTriangles
          << " triangles (accepted range [1, " << MaxAdaptiveLoopTriangles
          << "]); lower MaximumLevel or raise MaximumTriangles";
      return out.str();
    }
  }
  childOffsets[nT] = static_cast<int>(nTout);
  return "";
}

/// Even points: kept (pinned, unsplit under the error rules, flat enough), crease rule, or Loop's stencil.
void WriteEvenPoints(const AdaptiveLoopMesh& mesh, const EdgeTable& table, const SplitRules& rules, const LevelState& s,
  const StencilWriter& writer, const ParallelForFunction& parallelFor, AdaptiveLoopMesh& next)
{
  const LoopArray<int>& tri = mesh.triangles;
  parallelFor(mesh.NumberOfPoints(), [&](std::size_t begin, std::size_t end) {
    std::vector<int> ids;
    std::vector<double> weights;
    std::vector<int> nbrs;
    nbrs.reserve(32);
    for (std::size_t vv = begin; vv < end; ++vv)
    {
      const int v = static_cast<int>(vv);
      if (rules.haveRegion)
        next.region[vv] = mesh.region[vv];
      const int k = table.vertexCornerOffsets[v + 1] - table.vertexCornerOffsets[v];
      const int f = s.featureCount[vv];
      if (k == 0 || s.Pinned(v))
      {
        writer.Copy(vv, v);
        continue;
      }
      if (rules.byError)
      {
        // Moves only when one of its edges splits at this level.
        bool anySplit = false;
        for (int i = table.vertexCornerOffsets[v]; i < table.vertexCornerOffsets[v + 1] && !anySplit; ++i)
        {
          const int corner = table.vertexCorners[i];
          const int base = corner - corner % 3;
          const int c = corner - base;
          anySplit =
            s.oddId[table.triangleEdges[base + c]] >= 0 || s.oddId[table.triangleEdges[base + (c + 2) % 3]] >= 0;
        }
        if (!anySplit)
        {
          writer.Copy(vv, v);
          continue;
        }
      }
      if (f == 2)
      {
        const int crease[3] = { v, s.featureNbr[2 * vv], s.featureNbr[2 * vv + 1] };
        const double creaseWeights[3] = { 0.75, 0.125, 0.125 };
        writer.Apply(vv, crease, creaseWeights, 3);
        continue;
      }
      if (!rules.byError && rules.lambda < 1.0)
      {
        double sum[3] = { 0.0, 0.0, 0.0 };
        for (int i = table.vertexCornerOffsets[v]; i < table.vertexCornerOffsets[v + 1]; ++i)
        {
          const double* n = s.normals.data() + 3 * static_cast<std::size_t>(table.vertexCorners[i] / 3);
          sum[0] += n[0];
          sum[1] += n[1];
          sum[2] += n[2];
        }
        const double flatness = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]) / k;
        if (flatness > rules.lambda)
        {
          writer.Copy(vv, v);
          continue;
        }
      }
      GatherNeighbours(tri, table, v, false, nbrs);
      const int n = static_cast<int>(nbrs.size());
      const double beta = LoopBeta(n);
      ids.assign(1, v);
      weights.assign(1, 1.0 - n * beta);
      for (int w : nbrs)
      {
        ids.push_back(w);
        weights.push_back(beta);
      }
      writer.Apply(vv, ids.data(), weights.data(), n + 1);
    }
  });
}

/// Odd points: the midpoint on feature edges, Loop's edge stencil elsewhere; their regions.
void WriteOddPoints(const AdaptiveLoopMesh& mesh, const EdgeTable& table, const SplitRules& rules, const LevelState& s,
  const StencilWriter& writer, const ParallelForFunction& parallelFor, AdaptiveLoopMesh& next)
{
  parallelFor(table.NumberOfEdges(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
    {
      const int id = s.oddId[e];
      if (id < 0)
        continue;
      const int a = s.edgeFirst[e], b = table.edgeOther[e];
      if (s.feature[e])
      {
        const int ids[2] = { a, b };
        const double w[2] = { 0.5, 0.5 };
        writer.Apply(static_cast<std::size_t>(id), ids, w, 2);
      }
      else
      {
        const int ids[4] = { a, b, table.edgeOpposite[2 * e], table.edgeOpposite[2 * e + 1] };
        const double w[4] = { 0.375, 0.375, 0.125, 0.125 };
        writer.Apply(static_cast<std::size_t>(id), ids, w, 4);
      }
      if (rules.haveRegion)
        next.region[id] = OddRegion(mesh.region[a], mesh.region[b], table.edgeUses[e] == 1);
    }
  });
}

/// Each triangle's children (1 to 4 by its split edges; two splits cut along the shorter diagonal) and their origin.
void WriteChildren(const AdaptiveLoopMesh& mesh, const EdgeTable& table, const std::vector<int>& oddId,
  const std::vector<int>& childOffsets, const ParallelForFunction& parallelFor, AdaptiveLoopMesh& next)
{
  const LoopArray<int>& tri = mesh.triangles;
  const double* Q = next.points.data();
  parallelFor(mesh.NumberOfTriangles(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
    {
      const int v[3] = { tri[3 * t], tri[3 * t + 1], tri[3 * t + 2] };
      const int m[3] = { oddId[table.triangleEdges[3 * t]], oddId[table.triangleEdges[3 * t + 1]],
        oddId[table.triangleEdges[3 * t + 2]] };
      int* out = next.triangles.data() + 3 * static_cast<std::size_t>(childOffsets[t]);
      const int nChildren = childOffsets[t + 1] - childOffsets[t];
      const auto put = [&out](int a, int b, int c) {
        out[0] = a;
        out[1] = b;
        out[2] = c;
        out += 3;
      };
      const int splitCount = nChildren - 1;
      if (splitCount == 0)
        put(v[0], v[1], v[2]);
      else if (splitCount == 3)
      {
        put(v[0], m[0], m[2]);
        put(m[0], v[1], m[1]);
        put(m[2], m[1], v[2]);
        put(m[0], m[1], m[2]);
      }
      else if (splitCount == 1)
      {
        const int c = m[0] >= 0 ? 0 : (m[1] >= 0 ? 1 : 2);
        const int a = v[c], b = v[(c + 1) % 3], o = v[(c + 2) % 3];
        put(a, m[c], o);
        put(m[c], b, o);
      }
      else
      {
        const int c = m[0] < 0 ? 0 : (m[1] < 0 ? 1 : 2); // the unsplit edge (a, b)
        const int a = v[c], b = v[(c + 1) % 3], o = v[(c + 2) % 3];
        const int m1 = m[(c + 1) % 3], m2 = m[(c + 2) % 3]; // on (b, o) and (o, a)
        put(m1, o, m2);
        if (Distance2(Q, a, m1) <= Distance2(Q, b, m2))
        {
          put(a, b, m1);
          put(a, m1, m2);
        }
        else
        {
          put(a, b, m2);
          put(b, m1, m2);
        }
      }
      for (int i = childOffsets[t]; i < childOffsets[t + 1]; ++i)
        next.origin[i] = mesh.origin[t];
    }
  });
}

/// User-marked feature edges follow their halves.
void CarryMarkedFeatureEdges(const EdgeTable& table, const LevelState& s, AdaptiveLoopMesh& next)
{
  for (std::size_t e = 0; e < table.NumberOfEdges(); ++e)
    if (s.marked[e])
    {
      const int a = s.edgeFirst[e], b = table.edgeOther[e];
      if (s.oddId[e] >= 0)
      {
        next.featureEdges.push_back({ a, s.oddId[e] });
        next.featureEdges.push_back({ s.oddId[e], b });
      }
      else
        next.featureEdges.push_back({ a, b });
    }
}

enum class LevelOutcome
{
  Subdivided,
  Converged, ///< no edge splits: nothing would change but smoothing
  Aborted,
  Failed
};

/// One level of `mesh` (whose edge table is `table`) into `next`: classify, decide the splits, write the points and
/// the children. Reports progress at 0.5 and 0.75 of the level through `progressAt`.
LevelOutcome SubdivideLevel(const AdaptiveLoopMesh& mesh, const EdgeTable& table, const SplitRules& rules, int level,
  const ParallelForFunction& parallelFor, const std::function<bool(double)>& progressAt, AdaptiveLoopMesh& next,
  std::string& error)
{
  const std::size_t nV = mesh.NumberOfPoints();
  const std::size_t nT = mesh.NumberOfTriangles();
  LevelState s;
  s.rule = rules.rule;
  ComputeTriangleNormals(mesh, rules, parallelFor, s);
  ClassifyFeatures(mesh, table, rules, parallelFor, s);
  EstimateLimitOffsets(mesh, table, rules, parallelFor, s);
  FlagSplitEdges(mesh, table, rules, parallelFor, s);
  if (rules.byChord)
    ForceMovesOffTheLimit(nV, table, rules, parallelFor, s);
  if (rules.byError && rules.rule != FeatureRule::Fixed)
    SplitFeatureEdgesBesideSplits(table, parallelFor, s);
  const int nSplit = NumberOddPoints(nV, s.oddId);
  if (nSplit == 0)
    return LevelOutcome::Converged;

  std::vector<int> childOffsets;
  std::size_t nTout = 0;
  error = CountChildren(table, nT, s.oddId, rules.maximumTriangles, level, parallelFor, childOffsets, nTout);
  if (!error.empty())
    return LevelOutcome::Failed;
  const std::size_t nVout = nV + static_cast<std::size_t>(nSplit);
  if (!progressAt(0.5))
    return LevelOutcome::Aborted;

  const int D = mesh.attributeComponents;
  next.attributeComponents = D;
  next.points.resize(3 * nVout);
  next.attributes.resize(static_cast<std::size_t>(D) * nVout);
  if (rules.haveRegion)
    next.region.resize(nVout);
  const StencilWriter writer{ mesh.points.data(), mesh.attributes.data(), D, next.points.data(),
    next.attributes.data() };
  WriteEvenPoints(mesh, table, rules, s, writer, parallelFor, next);
  WriteOddPoints(mesh, table, rules, s, writer, parallelFor, next);
  if (!progressAt(0.75))
    return LevelOutcome::Aborted;

  next.triangles.resize(3 * nTout);
  next.origin.resize(nTout);
  WriteChildren(mesh, table, s.oddId, childOffsets, parallelFor, next);
  CarryMarkedFeatureEdges(table, s, next);
  return LevelOutcome::Subdivided;
}

} // namespace

std::string ValidateAdaptiveLoopParameters(const AdaptiveLoopParameters& s)
{
  std::ostringstream out;
  if (!(s.edgeAngleThreshold >= 0.0 && s.edgeAngleThreshold <= 180.0))
    out << plantmorph::OutOfRange("EdgeAngleThreshold", s.edgeAngleThreshold, "[0, 180]", "degrees");
  else if (!(s.flatnessThreshold >= 0.0 && s.flatnessThreshold <= 1.0))
    out << plantmorph::OutOfRange("FlatnessThreshold", s.flatnessThreshold, "[0, 1]");
  else if (s.maximumLevel < 0 || s.maximumLevel > MaxAdaptiveLoopLevel)
    out << plantmorph::OutOfRange("MaximumLevel", s.maximumLevel, "[0, " + std::to_string(MaxAdaptiveLoopLevel) + "]");
  else if (static_cast<int>(s.featureRule) < 0 || static_cast<int>(s.featureRule) > 2)
    out << plantmorph::OutOfRange(
      "FeatureRule", static_cast<int>(s.featureRule), "{0, 1, 2}", "0 Fixed, 1 Loop, 2 Refine");
  else if (s.maximumTriangles < 1 || s.maximumTriangles > MaxAdaptiveLoopTriangles)
    out << plantmorph::OutOfRange(
      "MaximumTriangles", s.maximumTriangles, "[1, " + std::to_string(MaxAdaptiveLoopTriangles) + "]");
  else if (static_cast<int>(s.refinementRule) < 0 || static_cast<int>(s.refinementRule) > 2)
    out << plantmorph::OutOfRange("RefinementRule", static_cast<int>(s.refinementRule), "{0, 1, 2}",
      "0 Dihedral angle, 1 Surface error, 2 Chord error");
  else if (!(s.errorTolerance >= 0.0))
    out << plantmorph::OutOfRange("ErrorTolerance", s.errorTolerance, "[0, inf]", "model units");
  return out.str();
}

AdaptiveLoopResult AdaptiveLoopSubdivide(AdaptiveLoopMesh input, const AdaptiveLoopParameters& settings)
{
  AdaptiveLoopResult result;
  const auto fail = [&result](std::string message) {
    result.mesh = AdaptiveLoopMesh();
    result.error = std::move(message);
    result.trianglesPerLevel.clear();
    result.pointsPerLevel.clear();
    result.levels = 0;
    return result;
  };
  const auto aborted = [] {
    AdaptiveLoopResult stopped;
    stopped.aborted = true;
    return stopped;
  };
  if (std::string error = ValidateAdaptiveLoopParameters(settings); !error.empty())
    return fail(error);
  if (std::string error = ValidateInput(input); !error.empty())
    return fail(error);

  const ParallelForFunction parallelFor = settings.parallelFor ? settings.parallelFor : ParallelForFunction(SerialFor);
  const auto report = [&settings](double fraction) { return !settings.progress || settings.progress(fraction); };

  AdaptiveLoopMesh mesh = std::move(input);
  mesh.origin.resize(mesh.NumberOfTriangles());
  std::iota(mesh.origin.begin(), mesh.origin.end(), 0);
  result.trianglesPerLevel.push_back(mesh.NumberOfTriangles());
  result.pointsPerLevel.push_back(mesh.NumberOfPoints());
  const SplitRules rules(settings, !mesh.region.empty());

  // Progress: level L costs about 4^L of level 0.
  double totalWork = 0.0;
  for (int l = 0; l < settings.maximumLevel; ++l)
    totalWork += std::pow(4.0, l);
  double doneWork = 0.0;

  // The input's edge table, checked for manifoldness whatever the level count.
  EdgeTable table;
  BuildEdgeTable(mesh.triangles, mesh.NumberOfPoints(), parallelFor, table);
  if (std::string error = ValidateManifoldEdges(mesh.NumberOfPoints(), table); !error.empty())
    return fail(error);
  if (std::string error = ValidateManifoldVertices(mesh.triangles, mesh.NumberOfPoints(), table, parallelFor);
      !error.empty())
    return fail(error);

  for (int level = 0; level < settings.maximumLevel; ++level)
  {
    const double levelWork = std::pow(4.0, level);
    const std::function<bool(double)> progressAt = [&](double phase) {
      return report((doneWork + phase * levelWork) / std::max(totalWork, 1.0));
    };
    if (!progressAt(0.0))
      return aborted();
    if (level > 0)
      BuildEdgeTable(mesh.triangles, mesh.NumberOfPoints(), parallelFor, table);
    if (!progressAt(0.3))
      return aborted();

    AdaptiveLoopMesh next;
    std::string error;
    const LevelOutcome outcome = SubdivideLevel(mesh, table, rules, level, parallelFor, progressAt, next, error);
    if (outcome == LevelOutcome::Converged)
      break;
    if (outcome == LevelOutcome::Aborted)
      return aborted();
    if (outcome == LevelOutcome::Failed)
      return fail(error);

    mesh = std::move(next);
    ++result.levels;
    result.trianglesPerLevel.push_back(mesh.NumberOfTriangles());
    result.pointsPerLevel.push_back(mesh.NumberOfPoints());
    doneWork += levelWork;
  }
  if (!report(1.0))
    return aborted();
  result.mesh = std::move(mesh);
  return result;
}

void NormalizeAttributeVectors(AdaptiveLoopMesh& mesh, int offset, const ParallelForFunction& parallelFor)
{
  const std::size_t stride = static_cast<std::size_t>(mesh.attributeComponents);
  const std::size_t count = stride > 0 ? mesh.attributes.size() / stride : 0; // the points may be freed already
  const auto body = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      double* n = mesh.attributes.data() + stride * i + static_cast<std::size_t>(offset);
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (len > 0.0)
      {
        n[0] /= len;
        n[1] /= len;
        n[2] /= len;
      }
    }
  };
  if (parallelFor)
  {
    parallelFor(count, body);
  }
  else
  {
    body(0, count);
  }
}

} // namespace plantmorph
