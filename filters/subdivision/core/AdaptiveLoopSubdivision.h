// SPDX-License-Identifier: GPL-3.0-or-later
// Adaptive Loop subdivision of a triangle surface (paper 003, sec. 2.3; docs/methods/subdivision-and-curl.md,
// AdaptiveLoopFilter), on flat arrays. Plain C++17, no VTK: vtkAdaptiveLoopFilter is the thin VTK layer over this.
//
// One level, on the current mesh:
//  1. Edge table: every undirected edge (a, b), a < b, with its one or two triangles and their opposite vertices,
//     built by bucketing the triangles' vertex pairs by their smaller vertex (a counting sort over a vertex ->
//     triangle table), never by per-edge neighbour queries. An edge in three or more triangles, or a vertex whose
//     triangles form more than one fan, is a non-manifold input and an error naming the point ids.
//  2. Feature edges: boundary edges (one triangle), edges whose both ends have region 1 (the midvein) when
//     `midveinIsFeature`, and the user's `featureEdges`.
//  3. Odd points. An interior non-feature edge (v1, v2) with triangles (v1, v2, v3), (v1, v2, v4) gets the point
//     (3 v1 + 3 v2 + v3 + v4) / 8 when its dihedral angle is below `edgeAngleThreshold` degrees (180 = flat;
//     a threshold of 180 splits every interior edge, flat ones too). Feature edges: FeatureRule::Fixed never
//     splits them; Loop and Refine split them at the midpoint.
//  4. Even points. Interior (non-feature) vertex v with k incident triangles of unit normals N_i: N_v = normalised
//     sum of the N_i (eq. (1)), flatness S_v = (1/k) sum N_i . N_v = |sum N_i| / k (eq. (2)). S_v > lambda
//     (`flatnessThreshold`) keeps v in place; otherwise v' = (1 - n beta) v + beta sum(neighbours), n its number of
//     neighbours, beta = 3/16 for n = 3 and (1/n)(5/8 - (3/8 + 1/4 cos(2 pi / n))^2) for n > 3. lambda >= 1 moves
//     every interior vertex (S_v can round to 1 + 1e-16). Vertices on feature edges: Fixed and Refine keep them;
//     Loop moves a vertex with exactly two feature edges to 1/8, 3/4, 1/8 of its two feature neighbours and keeps
//     corners (one or three and more feature edges) in place. The crease rule ignores flatness.
//  5. Split every triangle by the number of its split edges: 0 stays, 1 into 2, 2 into 3 (the quad cut along its
//     shorter diagonal, measured on the new positions; a tie takes the diagonal from the unsplit edge's first
//     vertex), 3 into 4. An edge is split for both of its triangles, so there are no T-junctions. Orientation is kept.
//  Levels repeat up to `maximumLevel`; a level that would insert no point is not applied and ends the run.
//
// RefinementRule::SurfaceError replaces the paper's two angle rules (3 and 4 above) by one error estimate in length
// units, `errorTolerance` (not in the paper; the dihedral angle is what it approximates):
//  - a vertex's limit offset delta_v = |N_v . (v_inf - v)|, v_inf = (1 - n chi) v + chi sum(neighbours) its Loop
//    limit position, chi = 1 / (3 / (8 beta) + n); the normal component only, so a flat patch (of any triangle
//    shapes) has 0. A crease vertex under FeatureRule Loop: v_inf = (p + 4 v + q) / 6, the offset's component
//    across the chord p q. Feature points that never move (Fixed, Refine, corners) have 0.
//  - an interior non-feature edge (v1, v2 | v3, v4) has the error max(delta_v1, delta_v2, e, e'), where
//    e = |n . (v3 + v4 - v1 - v2)| / 8 is the distance of Loop's odd point from the chord midpoint along the edge's
//    normal n (the normalised sum of its triangles' unit normals), and e' the same from the midpoint of the chord
//    between the ends' Loop even positions (they move if another of their edges splits). It splits when
//    error >= errorTolerance. A feature edge under Loop or Refine splits when max(delta_v1, delta_v2) >=
//    errorTolerance or another edge of its triangle splits.
//  - a vertex moves (Loop's even rule, or the crease rule) only when one of its edges splits at this level, so a
//    part left unrefined is left exactly as it was: it is not smoothed again by its coarse ring at every level.
//    FlatnessThreshold is not used.
//  errorTolerance 0 splits every edge and moves every vertex (plain Loop with the feature rule, bit for bit the
//  same as EdgeAngleThreshold 180 and FlatnessThreshold 1); infinity changes nothing. The estimate is local: the
//  result's distance from the uniform Loop surface is of the order of errorTolerance, not bounded by it.
//
// RefinementRule::ChordError (not in the paper) is SurfaceError with an estimate that depends on the edge's
// direction, so a surface curved in one direction refines in that direction only (anisotropically: an edge along
// a ruling of a cylinder-like part stays, one across it splits, and the 1-to-2 and 1-to-3 splits of step 5 keep
// the mesh conforming). An interior non-feature edge (v1, v2) splits when max(s, e', e / 2) >= errorTolerance:
//  - s = |(N_v2 - N_v1) . (v2 - v1)| / 8 is the chord's sagitta kappa(t) l^2 / 8, with kappa(t) the normal
//    curvature along the edge estimated from the ends' unit normals N_v (eq. (1), feature points too): 0 along a
//    straight line of the surface whatever the curvature across it;
//  - e' is SurfaceError's distance of Loop's odd point from the chord between the ends' Loop even positions (0
//    along a ruling of a regularly meshed cylinder: the odd point and the ends move alike);
//  - e is SurfaceError's odd point against the unmoved chord, as large along a ruling as across it; half of it
//    still splits edges along a saddle's asymptotic directions (s and e' near 0 there, yet Loop bends the surface
//    next to them): on the benchmark's bent ginkgo, leaving it out needs 0.68 of uniform level 3's triangles at its
//    deviation, half of it 0.38 (benchmarks/README.md). On a cylinder this term alone splits a ruling at half
//    the tolerance of an edge across it (the limit-offset term below raises that to 2/3).
//  Two corrections where that estimate is too low for the surface Loop makes (measured on the benchmark's Fixed
//  blades, where the maximum deviation sat next to the kept margin and midvein, and at points left at a coarse
//  level; benchmarks/README.md):
//  - an edge with an end that never moves (a Fixed or Refine feature point, a Loop corner) counts twice its
//    estimate: next to a kept polygon the surface bends ever more sharply and its deviation halves per level
//    instead of quartering;
//  - the ends' limit offsets delta (SurfaceError's) count at half: the edge's error is the larger of the (doubled)
//    estimate above and max(delta_v1, delta_v2) / 2; and a point whose delta reaches the tolerance moves: when
//    none of its edges splits (it would stay delta off the limit surface), its interior non-feature edge with the
//    largest estimate (ties: the lowest edge id) splits. On a cylinder meshed in quads cut along one diagonal (valence 6), delta / 2 is 2/3 of an across
//    edge's sagitta, above half of e, so the rulings split at 2/3 of an across edge's tolerance.
//  Feature edges and vertex moves follow SurfaceError's rules. errorTolerance 0 is plain Loop bit for bit and
//  infinity changes nothing, as for SurfaceError. Vertex normals assume consistently oriented triangles.
//
// Point data: every output point is a weighted sum of current points (its stencil); the same weights are applied to
// the positions and to every component of `attributes`, so any point array follows the surface. Region (integer)
// is not interpolated: an even point keeps its region; an odd point on a boundary edge gets 4 (margin) if either
// end is 4, else the ends' common region, else 0; an odd point on an interior edge gets the ends' common region
// unless it is 4 (an interior chord between two margin points lies in the blade), else 0 (blade).
// Cell data: every output triangle records the input triangle it lies in (`origin`).
//
// Output is deterministic: the same input gives bit-identical output whatever the parallel-for runs on, because
// every result is written by exactly one loop index and sums are taken in a fixed order.
#pragma once

#include <plantmorph/ParallelFor.h>
#include <plantmorph/memory/CloudArray.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace plantmorph
{

/// How feature edges (boundary, midvein, user-marked) are treated.
enum class FeatureRule : int
{
  Fixed = 0,  ///< the paper: feature edges never split, feature points never move
  Loop = 1,   ///< Loop's crease rules: midpoints on feature edges, 1/8 3/4 1/8 along feature curves, corners stay
  Refine = 2, ///< feature edges split at their midpoints, feature points stay: the curves gain samples, not shape
};

/// Which rule decides where to refine.
enum class RefinementRule : int
{
  DihedralAngle = 0, ///< the paper: edges by their dihedral angle, vertices by their flatness
  SurfaceError = 1,  ///< edges by the estimated distance of the unrefined surface from Loop's (errorTolerance)
  ChordError = 2,    ///< edges by their chord's estimated distance from the surface along the edge (errorTolerance)
};

/// Runs body(begin, end) over sub-ranges covering [0, n), possibly concurrently (plantmorph/ParallelFor.h; the
/// default SerialFor runs body(0, n) on the calling thread).
using ParallelForFunction = ParallelFor;

struct AdaptiveLoopParameters
{
  double edgeAngleThreshold = 170.0; ///< degrees in [0, 180]: split interior edges whose dihedral angle is below
  double flatnessThreshold = 0.999;  ///< lambda in [0, 1]: keep vertices flatter than it (1: move all)
  int maximumLevel = 2;              ///< levels in [0, MaxAdaptiveLoopLevel]
  FeatureRule featureRule = FeatureRule::Fixed;
  RefinementRule refinementRule = RefinementRule::DihedralAngle;
  double errorTolerance = 0.001; ///< length units in [0, inf] (SurfaceError): split where the estimate reaches it
  bool midveinIsFeature = true;  ///< edges whose two ends have region 1 are feature edges
  std::size_t maximumTriangles = 50000000; ///< a level that would make more is refused with an error (memory guard)
  ParallelForFunction parallelFor;         ///< empty: serial
  std::function<bool(double)> progress;    ///< fraction in [0, 1]; returning false aborts (result.aborted, empty mesh)
};

inline constexpr int MaxAdaptiveLoopLevel = 10;
inline constexpr std::size_t MaxAdaptiveLoopTriangles = 500000000; ///< ids stay within int

/// The mesh's big arrays: numbers left unset when an array grows (each level's output arrays are written whole by
/// the threads, and zero-filling them first was a serial pass over fresh memory, about a fifth of a first update,
/// whose memory is all fresh), in memory the VTK wrapper adopts as its output arrays instead of copying them
/// (plantmorph::CloudArray; plain pages: the arrays are written once and handed over).
template <class T>
using LoopArray = CloudArray<T, false>;

/// A triangle surface on flat arrays.
struct AdaptiveLoopMesh
{
  LoopArray<double> points;                     ///< x, y, z of every point
  LoopArray<int> triangles;                     ///< three point ids per triangle
  int attributeComponents = 0;                  ///< values per point in `attributes`
  LoopArray<double> attributes;                 ///< per point, interleaved; interpolated with the position stencils
  std::vector<int> region;                      ///< per point, or empty; see the Region rule above
  std::vector<std::array<int, 2>> featureEdges; ///< user-marked feature edges (point pairs, any order)
  LoopArray<int> origin;                        ///< output only: per triangle, the input triangle it lies in

  std::size_t NumberOfPoints() const { return this->points.size() / 3; }
  std::size_t NumberOfTriangles() const { return this->triangles.size() / 3; }
};

struct AdaptiveLoopResult
{
  AdaptiveLoopMesh mesh;                      ///< empty on error or abort
  std::vector<std::size_t> trianglesPerLevel; ///< [0] the input's, then one entry per applied level
  std::vector<std::size_t> pointsPerLevel;    ///< same, points
  int levels = 0;                             ///< levels applied
  std::string error;                          ///< non-empty: the input or settings were refused; mesh is empty
  bool aborted = false;
};

/// Empty when the settings are valid, else a message naming the setting and its accepted range.
std::string ValidateAdaptiveLoopParameters(const AdaptiveLoopParameters& settings);

/// Subdivides `input`. Errors (bad settings, NaN coordinates, ids out of range, degenerate or non-manifold
/// triangles, too many triangles) leave result.mesh empty with result.error set; nothing is half made.
/// Takes `input` by value: pass std::move(mesh) when it is no longer needed, to save a copy.
AdaptiveLoopResult AdaptiveLoopSubdivide(AdaptiveLoopMesh input, const AdaptiveLoopParameters& settings);

/// Scales the 3-component attribute at `offset` of every point of `mesh` (every tuple of `attributes`) to unit length (interpolated normals are
/// shorter than 1); a zero vector stays zero. `parallelFor` empty: serial.
void NormalizeAttributeVectors(AdaptiveLoopMesh& mesh, int offset, const ParallelForFunction& parallelFor = {});

} // namespace plantmorph
