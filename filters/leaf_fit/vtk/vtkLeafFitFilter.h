// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkLeafFitFilter
 * @brief   A scanned leaf (a point cloud) becomes a PlantMorph leaf and its traits (docs/methods/leaf-fit.md).
 *
 * Input: any vtkPointSet with one leaf, or several told apart by the integer point array named by LeafIdArray
 * (empty: the whole input is one leaf). Only its points are used; coordinates are multiplied by Scale first.
 * Every leaf is fitted by plantmorph::FitLeaf (filters/leaf_fit/core/LeafFit.h; leaves in parallel with vtkSMPTools).
 *
 * Output port 0, **Blade**: one triangulated blade per leaf, with point arrays `LeafUV`, `TCoords`, `Region`,
 * `Normals` (the data contract), `LeafId` and `Support` (distance to the nearest inlier scan point), cell arrays
 * `Region` and `LeafId`. Field data: for every leaf, its fitted Model C control points,
 * `PlantMorph.FitModel.<LeafId>.MidveinPoints`, `.LeftMarginPoints`, `.RightMarginPoints` (3-component arrays,
 * base to apex): LeafOutlineSource with Model B-spline, BSplinePreset Custom and these three lists rebuilds the
 * leaf where its curvature lets LeafOutlineSource mesh it in one plane; `.FlatMidveinPoints`,
 * `.FlatLeftMarginPoints`, `.FlatRightMarginPoints` give the same leaf laid flat (intrinsic coordinates, base at
 * the origin, midvein along +Y), which rebuilds (then curl it with LeafCurlFilter): when ModelControlPoints
 * interpolating points fold it (a margin close to the midvein), fewer are given (by twos, down to 3; the count used
 * is `.ControlPoints`), and if none rebuilds a warning names the leaf. Port 1, **Outline**: left margin, right margin and midvein of each leaf (cell `Region` 4, 4, 1, `LeafId`).
 * Port 2, **Traits**: a vtkTable, one row per leaf, fitted or not (LeafId, plantmorph::TraitNames(), Status,
 * Message, LengthUnit; LeafFitTables.h). Port 3, **Scan**: the input points (scaled) with their point data and
 * `FitDistance`, `Inlier`, `LeafId`. Port 4, **Plant**: one row for the whole input (leaf count, total and mean
 * area, the leaf inclination angle distribution: plantmorph::PlantColumnNames()).
 *
 * Without LeafIdArray the points are cut into the separate blades they form (plantmorph::SeparateLeaves, a warning
 * says how many), each fitted as a leaf. A leaf that cannot be fitted gets a row with Status 2, NaN traits and the
 * reason in Message, and a warning; the others are fitted as usual (only when no leaf fits is it an error). A
 * fitted leaf whose checks fail (plantmorph::CheckFittedLeaf: a base that is a guess, BaseFrom 3, low Coverage, a
 * flat model of another area) gets Status 1, the warning in Message, and the warning said.
 *
 * Under MPI each rank fits its own leaves (common/vtk/PlantMorphOwnerExchange.h): every leaf gets one owner rank
 * (largest leaves first, each to the least loaded rank), its points are sent there from every rank that holds some,
 * and it is fitted there; Blade and Outline stay on the owner, Scan on the ranks holding the points (the owners send
 * FitDistance and Inlier back), and the Traits rows are gathered onto rank 0 in LeafId order. Each leaf is fitted on
 * its points in lexicographic order of their coordinates, so the results are bit-identical to a serial run
 * whatever the ranks and however the points were split. Bad input (too few points, a line, NaN, no leaf shape, a
 * missing LeafIdArray, properties out of range) gives an error naming the problem and empty outputs.
 */
#ifndef vtkLeafFitFilter_h
#define vtkLeafFitFilter_h

#include "PlantMorphFitVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for LeafIdArray

namespace plantmorph
{
class Run;
}

class PLANTMORPHFITVTK_EXPORT vtkLeafFitFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkLeafFitFilter* New();
  vtkTypeMacro(vtkLeafFitFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Factor applied to the input coordinates (0.1 for a scan in mm and a model in cm). Finite, > 0. Default 1.
  vtkSetMacro(Scale, double);
  vtkGetMacro(Scale, double);

  /// Point array telling leaves apart (integer values of any type, read as 64-bit integers; floating-point values
  /// must be whole numbers). Empty or "None" (default): the separate blades the points form are the leaves.
  void SetLeafIdArray(const char* name);
  const char* GetLeafIdArray() const { return this->LeafIdArray.c_str(); }

  /// The unit of the input coordinates ("mm", the default; "" unknown): with Scale it gives the output length unit
  /// written with the tables (their LengthUnit column and PlantMorph.ColumnUnits field data).
  void SetInputUnit(const char* unit);
  const char* GetInputUnit() const { return this->InputUnit.c_str(); }

  /// Vertical axis: 0 X, 1 Y, 2 Z (default). For Inclination, Azimuth, HorizontalArea and the upper side.
  vtkSetClampMacro(UpAxis, int, 0, 2);
  vtkGetMacro(UpAxis, int);

  /// With UseBasePoint, the blade point nearest BasePoint (in scaled coordinates) is the leaf's base; otherwise the
  /// base is the petiole's junction with the blade, or found from the shape. Default off.
  vtkSetMacro(UseBasePoint, int);
  vtkGetMacro(UseBasePoint, int);
  vtkSetVector3Macro(BasePoint, double);
  vtkGetVector3Macro(BasePoint, double);
  /// The number of values the BasePoint property held (its server-side helper, vtkSICountedDoubleVectorProperty,
  /// sets it; a state file with another count than 3 is not pushed, and the filter then refuses to run naming
  /// BasePoint). -1: not given.
  vtkSetMacro(BasePointElementCount, int);
  vtkGetMacro(BasePointElementCount, int);
  /// With UseApexPoint, the blade point nearest ApexPoint (in scaled coordinates) is on the midvein's apex side
  /// (with a base, the midvein runs from the base towards it). Default off.
  vtkSetMacro(UseApexPoint, int);
  vtkGetMacro(UseApexPoint, int);
  vtkSetVector3Macro(ApexPoint, double);
  vtkGetVector3Macro(ApexPoint, double);
  /// As BasePointElementCount, for ApexPoint.
  vtkSetMacro(ApexPointElementCount, int);
  vtkGetMacro(ApexPointElementCount, int);
  /// On (default): where the input has a point array WoodDistance (PlantSegmentationFilter writes it: each point's
  /// distance to its plant's wood or petioles), a guessed base or a petiole's junction moves to where the leaf meets
  /// the wood (plantmorph::OrientByWood), a leaf whose midvein's apex end lies nearer the wood than its base end (by
  /// over 5 % of its Length) is fitted again with its base there, and a guessed base the wood confirms stands
  /// (BaseFrom 4). A move to where the leaf meets the wood that turns the leaf's Width over Length away from the
  /// plant's (the input's leaves whose shape and wood agree on their base) is dropped: the leaf lies against a twig it
  /// does not grow from. Not with UseBasePoint or UseApexPoint.
  vtkSetMacro(OrientByWood, int);
  vtkGetMacro(OrientByWood, int);

  ///@{
  /// Fit controls (plantmorph::LeafFitParameters): SurfaceSmoothing, OutlineSmoothing, OutlineControlPoints,
  /// OutlierSigma, Resolution (segments along the midvein), ModelControlPoints. Their ranges and defaults are the
  /// proxy's (xml/LeafFitFilter.xml, shown on its help page).
  vtkSetMacro(SurfaceSmoothing, double);
  vtkGetMacro(SurfaceSmoothing, double);
  vtkSetMacro(OutlineSmoothing, double);
  vtkGetMacro(OutlineSmoothing, double);
  vtkSetMacro(OutlineControlPoints, int);
  vtkGetMacro(OutlineControlPoints, int);
  vtkSetMacro(OutlierSigma, double);
  vtkGetMacro(OutlierSigma, double);
  vtkSetMacro(Resolution, int);
  vtkGetMacro(Resolution, int);
  vtkSetMacro(ModelControlPoints, int);
  vtkGetMacro(ModelControlPoints, int);
  ///@}

protected:
  vtkLeafFitFilter();
  ~vtkLeafFitFilter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Scale = 1.0;
  std::string LeafIdArray = "None";
  std::string InputUnit = "mm";
  int UpAxis = 2;
  int UseBasePoint = 0;
  double BasePoint[3] = { 0.0, 0.0, 0.0 };
  int BasePointElementCount = -1;
  int UseApexPoint = 0;
  double ApexPoint[3] = { 0.0, 0.0, 0.0 };
  int ApexPointElementCount = -1;
  int OrientByWood = 1;
  double SurfaceSmoothing = 1.0;
  double OutlineSmoothing = 1.0;
  int OutlineControlPoints = 16;
  double OutlierSigma = 3.0;
  int Resolution = 60;
  int ModelControlPoints = 20;

private:
  /// RequestData's body (plantmorph::RunRequestData): reads the leaves, fits each on its owner rank, writes the ports.
  void Execute(plantmorph::Run& run);
  vtkLeafFitFilter(const vtkLeafFitFilter&) = delete;
  void operator=(const vtkLeafFitFilter&) = delete;
};

#endif
