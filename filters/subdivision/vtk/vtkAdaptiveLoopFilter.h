// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkAdaptiveLoopFilter
 * @brief   Adaptive Loop subdivision of a triangle surface (paper 003, sec. 2.3; docs/methods/subdivision-and-curl.md).
 *
 * Related publications:
 * - [P003] Lu Shenglian, Guo Xinyu, Li Changfeng, "Accurate modelling and rendering of 3-D plant leaves" (in
 *   Chinese), Journal of Image and Graphics 14(4):731-737, 2009: sec. 2.3, eqs. (1)-(5), Fig. 5;
 * - Loop's stencils: C. Loop, "Smooth subdivision surfaces based on triangles", M.S. thesis, University of Utah,
 *   1987.
 * Full references: docs/references.md. What the code does, and where and why it departs from the paper:
 * docs/methods/subdivision-and-curl.md.
 *
 * Subdivides where the surface bends and leaves flat parts alone. Per level:
 *
 * - **Odd (edge) points.** An interior edge shared by triangles (v1, v2, v3) and (v1, v2, v4) gets the point
 *   (3 v1 + 3 v2 + v3 + v4) / 8 when the dihedral angle between its triangles is below EdgeAngleThreshold
 *   (180 degrees = flat; 180 splits every edge).
 * - **Even (old) points.** A vertex's flatness S_v is the mean of N_i . N_v over its k triangles (N_v the
 *   normalised mean of their unit normals N_i). If S_v > FlatnessThreshold it stays; otherwise it moves by Loop's
 *   rule, (1 - n beta) v + beta * sum of its n neighbours, beta = 3/16 for n = 3, else
 *   (5/8 - (3/8 + cos(2 pi / n) / 4)^2) / n. FlatnessThreshold = 1 moves every vertex.
 * - **Splits.** Each triangle splits by the number of its split edges: into 2, 3 (the quad cut along its shorter
 *   diagonal) or 4. An edge is split for both its triangles: no T-junctions, no cracks.
 * - **Feature edges** are boundary edges, edges whose two ends have point Region 1 (the midvein; MidveinFeatures)
 *   and the segments of the input's line cells that are mesh edges (LineFeatures). FeatureRule Fixed (the paper)
 *   never splits or moves them, so margin and midvein keep their input polygons bit for bit; Loop applies Loop's
 *   crease rules (edge midpoints; 1/8, 3/4, 1/8 along a feature curve; corners stay); Refine splits feature edges at
 *   their midpoints without moving feature points.
 * - Levels repeat up to MaximumLevel and stop early when a level would insert no point.
 * - **RefinementRule SURFACE_ERROR** (not in the paper) replaces the two angle rules by one estimate in model
 *   units: an interior edge splits when its estimated distance from Loop's surface reaches ErrorTolerance, the
 *   largest of its odd point's distance from the chord midpoint, |n . (v3 + v4 - v1 - v2)| / 8 (and from the
 *   midpoint of the chord between its ends' smoothed positions), and its two ends' distances from their Loop limit
 *   positions (all along the normal, so flat parts of any mesh score 0); a vertex
 *   moves only when one of its edges splits (parts left unrefined are left exactly as they were). ErrorTolerance 0
 *   is plain Loop subdivision with the feature rule; a huge one changes nothing. See
 *   filters/subdivision/core/AdaptiveLoopSubdivision.h.
 * - **RefinementRule CHORD_ERROR** (not in the paper) is SURFACE_ERROR with a direction-dependent estimate, so a
 *   leaf curved in one direction (LeafCurlFilter's cylinder wraps) refines mostly across its curvature: an
 *   interior edge splits when the largest of its chord's sagitta |(N2 - N1) . (v2 - v1)| / 8 (N the ends' unit
 *   normals: curvature along the edge times length squared over 8), its odd point's distance from the chord
 *   between its ends' smoothed positions and half SURFACE_ERROR's distance from the unmoved chord (doubled for
 *   an edge with an end that never moves, such as a Fixed margin or midvein point), or half an end's distance
 *   from its Loop limit position, reaches ErrorTolerance; a vertex whose limit distance reaches it moves (its
 *   edge with the largest estimate splits if no other does). Edges along straight lines of the surface stay
 *   longer, so triangles grow thin along the rulings. Vertices move as for SURFACE_ERROR; ErrorTolerance 0 is
 *   plain Loop.
 *
 * With EdgeAngleThreshold = 180, FlatnessThreshold = 1, FeatureRule = Loop and MidveinFeatures and LineFeatures off,
 * the output is plain Loop subdivision, the same as vtkLoopSubdivisionFilter's (which stores float points).
 *
 * Output: the triangles only (input vertices and lines are not passed; lines serve as feature markers). Points keep
 * the input's precision (float or double). Every point array is interpolated with the positions' weights (each
 * component; integer arrays rounded; the active normals renormalised). The point array `Region` is propagated, not
 * interpolated: even points keep theirs; an odd point on a boundary edge gets 4 (margin) if an end is 4, else the
 * ends' common value, else 0; an odd point on an interior edge gets the ends' common value unless it is 4, else 0
 * (blade). Cell data: every triangle inherits its input cell's values. Field data: the input's, plus
 * `AdaptiveLoop.TrianglesPerLevel` and `AdaptiveLoop.PointsPerLevel` (vtkIdTypeArray, entry 0 the input's, then one
 * per level applied).
 *
 * Errors, each a vtkErrorMacro and an empty output (never a partial one): a property out of its range or NaN (the
 * message names it and its range), non-finite coordinates, a non-manifold edge (three or more triangles) or vertex
 * (triangles forming separate fans), naming the point ids; polygons or strips when TriangulateNonTriangles is off;
 * an input with points but no polygons; more than MaximumTriangles triangles. An input without points gives an
 * empty output silently (the empty pieces of other MPI ranks). Progress is reported and abort honoured.
 * The per-point and per-edge loops run in parallel with vtkSMPTools; the output is the same for any thread count.
 */
#ifndef vtkAdaptiveLoopFilter_h
#define vtkAdaptiveLoopFilter_h

#include "PlantMorphSubdivisionVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for MakeSettings and Subdivide

namespace plantmorph
{
struct AdaptiveLoopParameters;
class Run;
}

class PLANTMORPHSUBDIVISIONVTK_EXPORT vtkAdaptiveLoopFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkAdaptiveLoopFilter* New();
  vtkTypeMacro(vtkAdaptiveLoopFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum RefinementRuleType
  {
    DIHEDRAL_ANGLE = 0,
    SURFACE_ERROR = 1,
    CHORD_ERROR = 2
  };

  enum FeatureRuleType
  {
    FIXED = 0,
    LOOP = 1,
    REFINE = 2
  };

  ///@{
  /**
   * Most subdivision levels. Range [0, 10]. Default 2. Each level at most quadruples the triangle count; the run
   * stops earlier when a level would insert no point.
   */
  vtkSetMacro(MaximumLevel, int);
  vtkGetMacro(MaximumLevel, int);
  ///@}

  ///@{
  /**
   * Dihedral angle in degrees below which an interior non-feature edge is split (180 is flat). Range [0, 180].
   * Default 170. 180 splits every interior edge; 0 splits none.
   */
  vtkSetMacro(EdgeAngleThreshold, double);
  vtkGetMacro(EdgeAngleThreshold, double);
  ///@}

  ///@{
  /**
   * Flatness lambda: a non-feature vertex with flatness S_v > lambda keeps its place. Range [0, 1]. Default 0.999.
   * 1 moves every vertex (plain Loop smoothing).
   */
  vtkSetMacro(FlatnessThreshold, double);
  vtkGetMacro(FlatnessThreshold, double);
  ///@}

  ///@{
  /**
   * Where to refine: DIHEDRAL_ANGLE (0, default, the paper: EdgeAngleThreshold and FlatnessThreshold),
   * SURFACE_ERROR (1: ErrorTolerance; FlatnessThreshold and EdgeAngleThreshold unused) or CHORD_ERROR (2:
   * ErrorTolerance, anisotropic: edges along straight lines of the surface stay). Range [0, 2].
   */
  vtkSetMacro(RefinementRule, int);
  vtkGetMacro(RefinementRule, int);
  ///@}

  ///@{
  /**
   * SURFACE_ERROR's and CHORD_ERROR's tolerance in model units, range [0, inf]: an edge splits where the
   * estimated distance of the unrefined surface from Loop's reaches it. Default 0.001. 0 splits everything (plain Loop with FeatureRule).
   */
  vtkSetMacro(ErrorTolerance, double);
  vtkGetMacro(ErrorTolerance, double);
  ///@}

  ///@{
  /**
   * Feature edges' rule: FIXED (0, default, the paper: never split, never moved), LOOP (1, Loop's crease rules) or
   * REFINE (2, split at midpoints, points never moved).
   */
  vtkSetMacro(FeatureRule, int);
  vtkGetMacro(FeatureRule, int);
  ///@}

  ///@{
  /**
   * Edges whose two ends have point Region 1 (midvein) are feature edges. Default on. Needs a point array Region.
   */
  vtkSetMacro(MidveinFeatures, vtkTypeBool);
  vtkGetMacro(MidveinFeatures, vtkTypeBool);
  vtkBooleanMacro(MidveinFeatures, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Segments of the input's line and polyline cells that are edges of the surface are feature edges (mark your own
   * creases by appending lines along them). Default on.
   */
  vtkSetMacro(LineFeatures, vtkTypeBool);
  vtkGetMacro(LineFeatures, vtkTypeBool);
  vtkBooleanMacro(LineFeatures, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Polygons with more than three points and triangle strips are triangulated first (on, default), or refused
   * with an error naming the first such cell (off).
   */
  vtkSetMacro(TriangulateNonTriangles, vtkTypeBool);
  vtkGetMacro(TriangulateNonTriangles, vtkTypeBool);
  vtkBooleanMacro(TriangulateNonTriangles, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Memory guard: a level that would make more triangles than this is an error (and an empty output). Range
   * [1, 5e8]. Default 5e7 (about 3 GB of output).
   */
  vtkSetMacro(MaximumTriangles, vtkIdType);
  vtkGetMacro(MaximumTriangles, vtkIdType);
  ///@}

  ///@{
  /**
   * Threads for the per-point, per-edge and per-triangle loops: 0 (default) as many as vtkSMPTools estimates
   * (all cores), 1 serial, n at most n. When VTK's SMP backend is Sequential (Debian's ParaView unless
   * VTK_SMP_BACKEND_IN_USE is set) the filter runs its own loops with the STDThread backend, restored afterwards.
   * Outputs estimated under 2e5 triangles always run serially (threads cost more than they save there).
   * Range [0, 256]. The output does not depend on it.
   */
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

protected:
  vtkAdaptiveLoopFilter();
  ~vtkAdaptiveLoopFilter() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int MaximumLevel = 2;
  double EdgeAngleThreshold = 170.0;
  double FlatnessThreshold = 0.999;
  int FeatureRule = FIXED;
  int RefinementRule = DIHEDRAL_ANGLE;
  double ErrorTolerance = 0.001;
  vtkTypeBool MidveinFeatures = 1;
  vtkTypeBool LineFeatures = 1;
  vtkTypeBool TriangulateNonTriangles = 1;
  vtkIdType MaximumTriangles = 50000000;
  int NumberOfThreads = 0;

private:
  /// RequestData's body (PlantMorphLayer.h): the whole surface subdivided on rank 0.
  void Execute(plantmorph::Run& run);
  /// `input` (not empty) subdivided into `output`; "" or why it cannot be, `aborted` when the user stopped it.
  std::string Subdivide(vtkPolyData* input, vtkPolyData* output, bool& aborted);
  /// The properties as the core's settings; "" or a message naming the property out of range.
  std::string MakeSettings(plantmorph::AdaptiveLoopParameters& settings);

  vtkAdaptiveLoopFilter(const vtkAdaptiveLoopFilter&) = delete;
  void operator=(const vtkAdaptiveLoopFilter&) = delete;
};

#endif
