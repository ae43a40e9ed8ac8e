// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPlantSegmentationFilter.h"
#include "PlantMorphAlgorithmHooks.h"
#include "PlantMorphLayer.h"
#include "PlantSegmentation.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTable.h"

#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkPlantSegmentationFilter);

namespace
{
/// The input is gathered whole on rank 0 and segmented there.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank;

template <typename T>
vtkSmartPointer<T> NewArray(const char* name, int components, vtkIdType tuples)
{
  auto array = vtkSmartPointer<T>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(tuples);
  return array;
}

/// The input's points, and each point's plant id (empty without PlantIdArray); "" or the error.
std::string ReadPoints(
  vtkPointSet* input, const std::string& plantIdArray, std::vector<Eigen::Vector3d>& points, std::vector<int>& plantOf)
{
  const vtkIdType n = input ? input->GetNumberOfPoints() : 0;
  vtkDataArray* ids = nullptr;
  if (!plantIdArray.empty() && plantIdArray != "None")
  {
    ids = input ? input->GetPointData()->GetArray(plantIdArray.c_str()) : nullptr;
    if (!ids || ids->GetNumberOfComponents() != 1)
      return "PlantIdArray: the input has no one-component point array named '" + plantIdArray + "'";
  }
  points.resize(static_cast<std::size_t>(n));
  plantOf.assign(ids ? static_cast<std::size_t>(n) : 0, 0);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    points[static_cast<std::size_t>(i)] = Eigen::Vector3d(p[0], p[1], p[2]);
    if (ids)
    {
      const double id = ids->GetComponent(i, 0);
      if (!std::isfinite(id) || std::abs(id) > 2e9)
        return "PlantIdArray '" + plantIdArray + "': point " + std::to_string(i) + " has no whole plant id";
      plantOf[static_cast<std::size_t>(i)] = static_cast<int>(std::lround(id));
    }
  }
  return {};
}

/// Port 0: the points as vertices with the input's point data and the labels.
void WritePoints(vtkPointSet* input, const plantmorph::SegmentationResult& r, vtkPolyData* out)
{
  const auto n = static_cast<vtkIdType>(r.organ.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  vtkNew<vtkCellArray> verts;
  auto organ = NewArray<vtkIntArray>("Organ", 1, n);
  auto leaf = NewArray<vtkIntArray>("LeafId", 1, n);
  auto confidence = NewArray<vtkDoubleArray>("SegmentationConfidence", 1, n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    points->SetPoint(i, p);
    verts->InsertNextCell(1, &i);
    organ->SetValue(i, r.organ[static_cast<std::size_t>(i)]);
    leaf->SetValue(i, r.leafId[static_cast<std::size_t>(i)]);
    confidence->SetValue(i, r.confidence[static_cast<std::size_t>(i)]);
  }
  out->SetPoints(points);
  out->SetVerts(verts);
  out->GetPointData()->PassData(input->GetPointData());
  out->GetPointData()->AddArray(organ);
  out->GetPointData()->AddArray(leaf);
  out->GetPointData()->AddArray(confidence);
  out->GetPointData()->SetActiveScalars("Organ");
}

/// Port 1: one row per leaf.
void WriteLeaves(const plantmorph::SegmentationResult& r, vtkTable* table)
{
  const auto n = static_cast<vtkIdType>(r.leaves.size());
  const char* ints[] = { "LeafId", "PlantId", "Points", "Branch" };
  const char* vectors[] = { "Base", "Centre" };
  const char* doubles[] = { "Area", "BaseGap" };
  for (const char* name : ints)
    table->AddColumn(NewArray<vtkIntArray>(name, 1, n));
  for (const char* name : doubles)
    table->AddColumn(NewArray<vtkDoubleArray>(name, 1, n));
  for (const char* name : vectors)
    table->AddColumn(NewArray<vtkDoubleArray>(name, 3, n));
  for (vtkIdType k = 0; k < n; ++k)
  {
    const plantmorph::SegmentedLeaf& leaf = r.leaves[static_cast<std::size_t>(k)];
    const double values[] = { double(leaf.leafId), double(leaf.plantId), double(leaf.points), double(leaf.branch),
      leaf.area, leaf.baseGap };
    for (int c = 0; c < 6; ++c)
      vtkDataArray::SafeDownCast(table->GetColumn(c))->SetComponent(k, 0, values[c]);
    vtkDataArray::SafeDownCast(table->GetColumnByName("Base"))->SetTuple(k, leaf.base.data());
    vtkDataArray::SafeDownCast(table->GetColumnByName("Centre"))->SetTuple(k, leaf.centre.data());
  }
}

/// Port 2: one row per plant.
void WritePlants(const plantmorph::SegmentationResult& r, vtkTable* table)
{
  const auto n = static_cast<vtkIdType>(r.plants.size());
  const char* ints[] = { "PlantId", "LeafCount", "Points", "WoodPoints", "LeafPoints", "UnassignedLeafPoints" };
  for (const char* name : ints)
    table->AddColumn(NewArray<vtkIntArray>(name, 1, n));
  table->AddColumn(NewArray<vtkDoubleArray>("Height", 1, n));
  table->AddColumn(NewArray<vtkDoubleArray>("Spacing", 1, n));
  for (vtkIdType k = 0; k < n; ++k)
  {
    const plantmorph::SegmentedPlant& p = r.plants[static_cast<std::size_t>(k)];
    const double values[] = { double(p.plantId), double(p.leafCount), double(p.points), double(p.woodPoints),
      double(p.leafPoints), double(p.unassignedLeafPoints), p.height, p.spacing };
    for (int c = 0; c < 8; ++c)
      vtkDataArray::SafeDownCast(table->GetColumn(c))->SetComponent(k, 0, values[c]);
  }
}
} // namespace

vtkPlantSegmentationFilter::vtkPlantSegmentationFilter()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(3);
}

void vtkPlantSegmentationFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PlantIdArray: " << this->PlantIdArray << "\n"
     << indent << "UpAxis: " << this->UpAxis << "\n"
     << indent << "FeatureScale: " << this->FeatureScale << "\n"
     << indent << "LinkScale: " << this->LinkScale << "\n"
     << indent << "NormalAngle: " << this->NormalAngle << "\n"
     << indent << "CreaseVariation: " << this->CreaseVariation << "\n"
     << indent << "SheetCoherence: " << this->SheetCoherence << "\n"
     << indent << "MaximumLeafElongation: " << this->MaximumLeafElongation << "\n"
     << indent << "MinimumLeafPoints: " << this->MinimumLeafPoints << "\n";
}

void vtkPlantSegmentationFilter::SetPlantIdArray(const char* name)
{
  const std::string value = name ? name : "";
  if (value != this->PlantIdArray)
  {
    this->PlantIdArray = value;
    this->Modified();
  }
}

int vtkPlantSegmentationFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

int vtkPlantSegmentationFilter::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkPolyData" : "vtkTable");
  return 1;
}

int vtkPlantSegmentationFilter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the plant segmentation", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

void vtkPlantSegmentationFilter::Execute(plantmorph::Run& run)
{
  plantmorph::SegmentationParameters p;
  p.upAxis = this->UpAxis;
  p.featureScale = this->FeatureScale;
  p.linkScale = this->LinkScale;
  p.normalAngle = this->NormalAngle;
  p.creaseVariation = this->CreaseVariation;
  p.sheetCoherence = this->SheetCoherence;
  p.maximumLeafElongation = this->MaximumLeafElongation;
  p.minimumLeafPoints = this->MinimumLeafPoints;
  run.Check(plantmorph::ValidateSegmentationParameters(p));
  vtkPointSet* input = run.Input<vtkPointSet>(0);
  std::vector<Eigen::Vector3d> points;
  std::vector<int> plantOf;
  run.Check(ReadPoints(input, this->PlantIdArray, points, plantOf));
  run.Building("the segmentation of " + std::to_string(points.size()) + " points");
  plantmorph::SegmentationResult result;
  run.Threaded(0, [&]() { result = plantmorph::SegmentPlants(points, plantOf, p, plantmorph::SMPFor()); });
  run.Check(result.error);
  this->UpdateProgress(0.9);
  WritePoints(input, result, run.Output<vtkPolyData>(0));
  WriteLeaves(result, run.Output<vtkTable>(1));
  WritePlants(result, run.Output<vtkTable>(2));
  plantmorph::FieldRecord record;
  record.Add("Model", "PlantSegmentation");
  record.Add("LeafCount", static_cast<double>(result.leaves.size()));
  record.Add("PlantCount", static_cast<double>(result.plants.size()));
  run.WriteToEveryOutput(record);
}
