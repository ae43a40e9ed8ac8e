// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPlantSegmentationFilter
 * @brief   A scanned plant (a point cloud) becomes its organs and its leaf instances, wood and leaves
 *          (docs/methods/segmentation.md).
 *
 * Input: any vtkPointSet with one plant, or several told apart by the integer point array named by PlantIdArray
 * ("None" or empty: the whole input is one plant). Only its points are used (the method estimates its own normals). Every
 * threshold is a multiple of the plant's own point spacing (plantmorph::SegmentPlants,
 * filters/segmentation/core/PlantSegmentation.h; features threaded with vtkSMPTools, results independent of the
 * threads).
 *
 * Output port 0, **Points**: the input points as vertices with their point data and `Organ` (0 wood, 1 leaf, 2
 * petiole: thin wood from one leaf's base to thicker wood, or carrying the blade's midrib on where the scan did not
 * see the stem it leaves),
 * `LeafId` (-1 off the leaves and on leaf fragments smaller than MinimumLeafPoints) and `SegmentationConfidence`
 * ([0, 1]). Port 1, **Leaves**: a vtkTable, one row per leaf: LeafId, PlantId, Points, Area (a first estimate from
 * the points, in input units squared), Base (x, y, z: the leaf's point nearest the wood), Centre, Branch (the wood
 * segment it grows on), BaseGap, PetioleLength (0: no petiole found). Port 2, **Plants**: one row per plant: PlantId,
 * LeafCount, Height (along UpAxis), Points, WoodPoints, LeafPoints, UnassignedLeafPoints, Spacing, PetiolePoints.
 *
 * Under MPI each plant is segmented whole on one owner rank (LeafPerRank, as LeafFitFilter does with leaves;
 * common/vtk/PlantMorphOwnerExchange.h): Points stays where its points are, Leaves and Plants are gathered on rank 0;
 * the labels and tables do not depend on the number of ranks. Bad input (no points, fewer
 * than 20 in a plant, NaN, a plant without wood or without leaves, a missing PlantIdArray, properties out of range)
 * gives an error naming the problem and empty outputs.
 */
#ifndef vtkPlantSegmentationFilter_h
#define vtkPlantSegmentationFilter_h

#include "PlantMorphSegmentationVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for PlantIdArray

namespace plantmorph
{
class Run;
}

class PLANTMORPHSEGMENTATIONVTK_EXPORT vtkPlantSegmentationFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkPlantSegmentationFilter* New();
  vtkTypeMacro(vtkPlantSegmentationFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Point array telling plants apart (integer values; "None" or empty: one plant). Default "None".
  void SetPlantIdArray(const char* name);
  const char* GetPlantIdArray() const { return this->PlantIdArray.c_str(); }

  ///@{
  /// The method's controls (plantmorph::SegmentationParameters); ranges and defaults are the proxy's
  /// (xml/PlantSegmentationFilter.xml). Setters do not clamp: a value out of range is reported when the filter runs.
  vtkSetMacro(UpAxis, int);
  vtkGetMacro(UpAxis, int);
  vtkSetMacro(FeatureScale, double);
  vtkGetMacro(FeatureScale, double);
  vtkSetMacro(LinkScale, double);
  vtkGetMacro(LinkScale, double);
  vtkSetMacro(NormalAngle, double);
  vtkGetMacro(NormalAngle, double);
  vtkSetMacro(CreaseVariation, double);
  vtkGetMacro(CreaseVariation, double);
  vtkSetMacro(SheetCoherence, double);
  vtkGetMacro(SheetCoherence, double);
  vtkSetMacro(MaximumLeafElongation, double);
  vtkGetMacro(MaximumLeafElongation, double);
  vtkSetMacro(MinimumLeafPoints, int);
  vtkGetMacro(MinimumLeafPoints, int);
  ///@}

protected:
  vtkPlantSegmentationFilter();
  ~vtkPlantSegmentationFilter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::string PlantIdArray = "None";
  int UpAxis = 2;
  double FeatureScale = 4.0;
  double LinkScale = 2.5;
  double NormalAngle = 25.0;
  double CreaseVariation = 0.02;
  double SheetCoherence = 0.8;
  double MaximumLeafElongation = 12.0;
  int MinimumLeafPoints = 50;

private:
  /// RequestData's body (plantmorph::RunRequestData): reads the points, segments them, writes the three ports.
  void Execute(plantmorph::Run& run);
  vtkPlantSegmentationFilter(const vtkPlantSegmentationFilter&) = delete;
  void operator=(const vtkPlantSegmentationFilter&) = delete;
};

#endif
