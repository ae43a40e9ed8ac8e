// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkLeafCurlFilter
 * @brief   Curls a leaf blade: longitudinal curl about the midvein, transverse curl about the mid-line (paper 003
 *          sec. 3, Fig. 7; docs/methods/subdivision-and-curl.md).
 *
 * Related publication: [P003] Lu Shenglian, Guo Xinyu, Li Changfeng, "Accurate modelling and rendering of 3-D plant
 * leaves" (in Chinese), Journal of Image and Graphics 14(4):731-737, 2009: sec. 3, Fig. 7.
 * Full references: docs/references.md. What the code does, and where and why it departs from the paper:
 * docs/methods/subdivision-and-curl.md.
 *
 * vtkLeafCurlFilter bends a PlantMorph leaf (any vtkPolyData carrying the point array `LeafUV`, as every
 * LeafOutlineSource blade and outline does) without stretching it:
 *
 * - **Longitudinal curl**: the two halves roll about the midvein. A point at lateral distance d from the midvein
 *   (measured in the flat blade: d = x - x_mid(y), negative on the left half) goes to arc length d on a circle
 *   of radius R = W / LongitudinalAngle tangent to the blade at the midvein, W the half-width of its half (the
 *   largest |d| on that side). The widest point of each margin turns through exactly LongitudinalAngle; every row
 *   lies on the same cylinder, so the bending is exactly isometric (a cylinder wrap) when the midvein is straight.
 *   At 180 degrees the widest row of each half is a half circle and its margin is 2W/pi above the midvein.
 * - **Transverse curl**: the apex part and the base part bend about the mid-line, the line across the blade at
 *   v = TransverseCenter on the midvein, by the same construction along the blade (one radius per part, its length
 *   over TransverseAngle).
 *
 * Both combine, longitudinal first. Positive angles bend towards +Z (the blade's upper side), negative ones
 * towards -Z. Angle 0 is the identity: both 0 gives the input's points, bit for bit.
 *
 * The midvein is the set of points whose LeafUV u is 0; LeafUV is required (without it the filter reports an
 * error naming the array and outputs nothing). The input's x and y are taken as the flat blade; on non-flat input
 * (a twisted space-curve leaf, a leaf curled already) each curl bends space, carrying every point's height above
 * the midvein (above the mid-line's height, for the transverse curl) along the bent surface's normal. A bent
 * midvein (Model A's Bending) is followed, the blade rolling about it, but lengths are then kept only
 * approximately. See plantmorph::LeafCurl (filters/subdivision/core/LeafCurl.h) for the formulas.
 *
 * Arrays: every point, cell and field array passes through unchanged (TCoords stays the active texture
 * coordinates, so textures follow the curl, as the paper shows), except the active point normals, which are
 * rotated with the surface (the bend's Jacobian), and active cell normals of polygons, which are recomputed. The
 * output points keep the input's precision. The filter adds field data `PlantMorph.LongitudinalAngle`,
 * `PlantMorph.TransverseAngle` and `PlantMorph.TransverseCenter`.
 *
 * Errors (a vtkErrorMacro naming the property or array and the accepted range, and an empty output, never a
 * crash): an angle outside [-360, 360] or not finite, TransverseCenter outside [0, 1], no LeafUV (double or float,
 * two components), no midvein point (u = 0), a non-finite coordinate or LeafUV. An empty input gives an empty
 * output without an error (pieces other than 0 of a PlantMorph source are empty under MPI).
 *
 * The per-point mapping runs in parallel (vtkSMPTools) in blocks, reporting progress and honouring abort between
 * blocks.
 */
#ifndef vtkLeafCurlFilter_h
#define vtkLeafCurlFilter_h

#include "PlantMorphSubdivisionVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

namespace plantmorph
{
class Run;
}

class PLANTMORPHSUBDIVISIONVTK_EXPORT vtkLeafCurlFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkLeafCurlFilter* New();
  vtkTypeMacro(vtkLeafCurlFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  // The setters do not clamp: a value outside its range is reported as an error when the filter runs (and the
  // output is empty), so a typo in a script is seen instead of silently replaced by the range's end.

  ///@{
  /**
   * Longitudinal curl, in degrees: the angle the margin's tangent turns through at the widest point of each half,
   * the halves rolling about the midvein. Positive rolls the halves up (+Z, the upper side inwards), negative
   * down. 180: each half a half circle; 360: each half a full circle. Range [-360, 360]. Default 90.
   */
  vtkSetMacro(LongitudinalAngle, double);
  vtkGetMacro(LongitudinalAngle, double);
  ///@}

  ///@{
  /**
   * Transverse curl, in degrees: the angle the apex's (and the base's) tangent turns through, the apex and base
   * parts bending about the mid-line. Positive bends both ends up (+Z), negative down. Range [-360, 360].
   * Default 0 (no transverse curl).
   */
  vtkSetMacro(TransverseAngle, double);
  vtkGetMacro(TransverseAngle, double);
  ///@}

  ///@{
  /**
   * Where the mid-line of the transverse curl crosses the midvein, as LeafUV v (0 base, 1 apex). The base part
   * (below it) and the apex part (above it) both turn through TransverseAngle. Range and default:
   * xml/LeafCurlFilter.xml (the help page).
   */
  vtkSetMacro(TransverseCenter, double);
  vtkGetMacro(TransverseCenter, double);
  ///@}

protected:
  vtkLeafCurlFilter();
  ~vtkLeafCurlFilter() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// RequestData's body (PlantMorphLayer.h): the whole blade curled on rank 0.
  void Execute(plantmorph::Run& run);

  double LongitudinalAngle = 90.0;
  double TransverseAngle = 0.0;
  double TransverseCenter = 0.5;

private:
  vtkLeafCurlFilter(const vtkLeafCurlFilter&) = delete;
  void operator=(const vtkLeafCurlFilter&) = delete;
};

#endif
