// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkTreeFitFilter
 * @brief   A scanned tree (a point cloud) becomes cylinders, a skeleton and the tables foresters read from a
 *          quantitative structure model (docs/methods/tree-fit.md).
 *
 * Input: any vtkPointSet with one tree, or several told apart by the integer point array named by TreeIdArray
 * (empty: the whole input is one tree). Coordinates are multiplied by Scale first; every length of the outputs is in
 * those scaled units (volumes in their cube, areas in their square, angles in degrees). WoodArray (optional) names a
 * point array telling wood from leaves: PlantMorph's Organ (VirtualScanner's truth, PlantSegmentationFilter: 0 wood)
 * marks wood by 0, any other array by a nonzero value (WoodValues overrides): only wood is fitted, and the leaves
 * count for the tree's Height (its top, leaves included; WoodHeight is the wood's). Points labelled wood that the
 * fit finds to be leaves (flat sheets hanging from a fork, clumps round a twig lying on no surface) get Wood 0 on
 * the Scan port and no cylinder.
 * Each tree is fitted by plantmorph::FitTree (filters/tree_fit/core/TreeFit.h), its loops threaded with vtkSMPTools.
 *
 * Output port 0, **Cylinders**: one line cell per cylinder (start to end), or with Tubes a capped tube of TubeSides
 * sides, cell arrays `Radius`, `Length`, `CylinderId`, `ParentId` (cylinder), `BranchId`, `BranchOrder`,
 * `SegmentId`, `TreeId`, `FitRMS`, `Support` (points per unit length; 0: a twig hidden in leaves, grown towards wood
 * apart from the tree, SegmentId -1), `Measured` (1: radius from the fit, 0: from the taper and pipe model),
 * `GrowthLength`, `StartX`, `StartY`, `StartZ`, `EndX`, `EndY`, `EndZ`: ParaView's CSV writer on this port gives
 * the table QSM tools exchange. Port 1, **Skeleton**: one polyline per branch, base to tip, point arrays `BranchId`,
 * `BranchOrder`, `ParentId`, `Radius`, `TreeId`, cell arrays `BranchId`, `ParentId`, `Depth` (= order), `TreeId`: the
 * skeleton TreeFromSketchSource takes. Port 2, **Trees**: a vtkTable, one row per tree (TreeId, Status, then
 * plantmorph::TreeTraitNames()). Port 3, **Branches**: one row per branch (TreeId, BranchId, ParentId, Order,
 * Length, Volume, BaseDiameter, Angle, Azimuth, Inclination, Height). Port 4, **Scan**: the input points (scaled)
 * with their data and `TreeId`, `CylinderId`, `BranchId`, `Wood`, `FitDistance`. BranchId and CylinderId are unique
 * over all trees.
 *
 * A tree that cannot be fitted gets its Trees row with the reason in Status (NaN traits) and a warning; the others
 * go on. When no tree can be fitted (or a property is out of range, or an array is missing) the filter reports the
 * error and every output is empty. Under MPI each tree is fitted whole on one owner rank (LeafPerRank, as
 * LeafFitFilter; common/vtk/PlantMorphOwnerExchange.h): the Scan output stays where its points are, the other ports
 * are gathered on rank 0 in TreeId order; the outputs do not depend on the number of ranks.
 */
#ifndef vtkTreeFitFilter_h
#define vtkTreeFitFilter_h

#include "PlantMorphTreeFitVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for the array names

namespace plantmorph
{
class Run;
}

class PLANTMORPHTREEFITVTK_EXPORT vtkTreeFitFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkTreeFitFilter* New();
  vtkTypeMacro(vtkTreeFitFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Factor applied to the input coordinates (0.001 for a scan in mm and outputs in m). Finite, > 0. Default 1.
  vtkSetMacro(Scale, double);
  vtkGetMacro(Scale, double);

  /// Point array telling trees apart (integer values; "None" or empty: one tree). Default "None".
  void SetTreeIdArray(const char* name);
  const char* GetTreeIdArray() const { return this->TreeIdArray.c_str(); }

  /// Point array telling wood from leaves (WoodValues says which values are wood); "None" or empty: every point is
  /// wood. Default "None".
  void SetWoodArray(const char* name);
  const char* GetWoodArray() const { return this->WoodArray.c_str(); }

  /// Which values of WoodArray are wood: 0 automatic (default: an array named "Organ", PlantMorph's organ label,
  /// marks wood by 0; any other array by a nonzero value), 1 nonzero is wood, 2 zero is wood.
  vtkSetClampMacro(WoodValues, int, 0, 2);
  vtkGetMacro(WoodValues, int);

  /// Vertical axis: 0 X, 1 Y, 2 Z (default).
  vtkSetClampMacro(UpAxis, int, 0, 2);
  vtkGetMacro(UpAxis, int);

  /// Cylinders as capped tubes (on) or as one line cell each (off, default).
  vtkSetMacro(Tubes, int);
  vtkGetMacro(Tubes, int);
  /// Sides of each tube, [3, 64]. Default 12.
  vtkSetMacro(TubeSides, int);
  vtkGetMacro(TubeSides, int);

  /// Robust deviations of a point's (log) mean neighbour distance beyond which it is an outlier (dropped unless it lies
  /// on a sparse line of such points: a branch scanned from far), [1, 100]. Default 3.
  vtkSetMacro(OutlierSigma, double);
  vtkGetMacro(OutlierSigma, double);
  /// Height above the lowest point where DBH is measured, in output units, (0, 1e6]. Default 1.3.
  vtkSetMacro(BreastHeight, double);
  vtkGetMacro(BreastHeight, double);

protected:
  vtkTreeFitFilter();
  ~vtkTreeFitFilter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Scale = 1.0;
  std::string TreeIdArray = "None";
  std::string WoodArray = "None";
  int WoodValues = 0;
  int UpAxis = 2;
  int Tubes = 0;
  int TubeSides = 12;
  double OutlierSigma = 3.0;
  double BreastHeight = 1.3;

private:
  /// RequestData's body (plantmorph::RunRequestData): reads the trees, fits each, writes the ports.
  void Execute(plantmorph::Run& run);
  vtkTreeFitFilter(const vtkTreeFitFilter&) = delete;
  void operator=(const vtkTreeFitFilter&) = delete;
};

#endif
