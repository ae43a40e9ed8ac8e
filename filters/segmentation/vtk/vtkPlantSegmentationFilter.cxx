// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPlantSegmentationFilter.h"
#include "PlantMorphAlgorithmHooks.h"
#include "PlantMorphLayer.h"
#include "PlantMorphOwnerExchange.h"
#include "PlantSegmentation.h"

#include "PlantMorphFieldData.h" // VertexCells
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
#include <map>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkPlantSegmentationFilter);

namespace
{
/// Each plant (each PlantIdArray value) is segmented whole on one owner rank (common/vtk/PlantMorphOwnerExchange.h);
/// the Points output stays where its points are, the Leaves and Plants tables are gathered on rank 0.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::LeafPerRank;
/// Values per point sent to the owners (x, y, z) and back (organ, leaf index in its plant, confidence, wood
/// distance); per plant gathered on rank 0: its row (PlantValues), then LeafValues per leaf.
constexpr int SendWidth = 3, ReturnWidth = 4, PlantValues = 9, LeafValues = 11;

template <typename T>
vtkSmartPointer<T> NewArray(const char* name, int components, vtkIdType tuples)
{
  auto array = vtkSmartPointer<T>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(tuples);
  return array;
}

/// This rank's piece: its coordinates (SendWidth per point), each point's plant id and the plants' members.
struct LocalInput
{
  std::vector<double> xyz;
  std::vector<int> plantOf;
  plantmorph::LocalGroups plants;
};

/// Reads this rank's piece (none, or no points: nothing, no error); "" or the error (a missing PlantIdArray, a plant
/// id that is no whole number, a non-finite coordinate: point numbers are the piece's).
std::string ReadPoints(vtkPointSet* input, const std::string& plantIdArray, LocalInput& in)
{
  const vtkIdType n = input ? input->GetNumberOfPoints() : 0;
  vtkDataArray* ids = nullptr;
  if (n > 0 && !plantIdArray.empty() && plantIdArray != "None")
  {
    ids = input->GetPointData()->GetArray(plantIdArray.c_str());
    if (!ids || ids->GetNumberOfComponents() != 1)
      return "PlantIdArray: the input has no one-component point array named '" + plantIdArray + "'";
  }
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      return "point " + std::to_string(i) + " has a non-finite coordinate (" + std::to_string(p[0]) + ", " +
        std::to_string(p[1]) + ", " + std::to_string(p[2]) + "): remove NaN and infinite points first";
    const double id = ids ? ids->GetComponent(i, 0) : 0.0;
    if (!std::isfinite(id) || std::abs(id) > 2e9)
      return "PlantIdArray '" + plantIdArray + "': point " + std::to_string(i) + " has no whole plant id";
    in.plantOf.push_back(static_cast<int>(std::lround(id)));
    in.plants[in.plantOf.back()].push_back(i);
    in.xyz.insert(in.xyz.end(), { p[0], p[1], p[2] });
  }
  return {};
}

/// Segments the plants this rank owns (each threaded inside): per plant, ReturnWidth values per point (`values`) and
/// a block, its row and its leaves' rows (`blocks`); "" or the first failing plant's error.
std::string SegmentOwned(const plantmorph::OwnerExchange& exchange, const std::vector<std::vector<double>>& sent,
  const plantmorph::SegmentationParameters& p, std::vector<std::vector<double>>& values,
  std::vector<std::vector<double>>& blocks)
{
  const std::vector<std::size_t> owned = exchange.Owned();
  for (std::size_t k = 0; k < sent.size(); ++k)
  {
    std::vector<Eigen::Vector3d> points(sent[k].size() / SendWidth);
    for (std::size_t i = 0; i < points.size(); ++i)
      points[i] = Eigen::Vector3d(sent[k][SendWidth * i], sent[k][SendWidth * i + 1], sent[k][SendWidth * i + 2]);
    const plantmorph::SegmentationResult r = plantmorph::SegmentPlants(points, {}, p, plantmorph::SMPFor());
    const auto id = static_cast<long long>(exchange.Ids()[owned[k]]);
    if (!r.error.empty())
      return (exchange.Ids().size() > 1 ? "plant " + std::to_string(id) + ": " : std::string()) + r.error;
    values.emplace_back();
    for (std::size_t i = 0; i < points.size(); ++i)
      values.back().insert(
        values.back().end(), { double(r.organ[i]), double(r.leafId[i]), r.confidence[i], r.woodDistance[i] });
    const plantmorph::SegmentedPlant& plant = r.plants.front();
    blocks.push_back(
      { double(id), double(plant.leafCount), double(plant.points), double(plant.woodPoints), double(plant.leafPoints),
        double(plant.unassignedLeafPoints), plant.height, plant.spacing, double(plant.petiolePoints) });
    for (const plantmorph::SegmentedLeaf& leaf : r.leaves)
      blocks.back().insert(blocks.back().end(),
        { double(leaf.points), double(leaf.branch), leaf.area, leaf.baseGap, leaf.base.x(), leaf.base.y(),
          leaf.base.z(), leaf.centre.x(), leaf.centre.y(), leaf.centre.z(), leaf.petioleLength });
  }
  return {};
}

/// On rank 0: the plants' and leaves' rows from the gathered blocks (plants in ascending id, their leaves numbered
/// on in that order); returns each plant's first LeafId (Ids() order), then the leaf count.
std::vector<double> Assemble(const std::vector<std::vector<double>>& blocks, plantmorph::SegmentationResult& r)
{
  std::vector<double> firstLeaf;
  for (const std::vector<double>& b : blocks)
  {
    firstLeaf.push_back(static_cast<double>(r.leaves.size()));
    plantmorph::SegmentedPlant plant;
    plant.plantId = static_cast<int>(b[0]);
    plant.leafCount = static_cast<int>(b[1]);
    plant.points = static_cast<long long>(b[2]);
    plant.woodPoints = static_cast<long long>(b[3]);
    plant.leafPoints = static_cast<long long>(b[4]);
    plant.unassignedLeafPoints = static_cast<long long>(b[5]);
    plant.height = b[6];
    plant.spacing = b[7];
    plant.petiolePoints = static_cast<long long>(b[8]);
    r.plants.push_back(plant);
    for (std::size_t at = PlantValues; at + LeafValues <= b.size(); at += LeafValues)
    {
      plantmorph::SegmentedLeaf leaf;
      leaf.leafId = static_cast<int>(r.leaves.size());
      leaf.plantId = plant.plantId;
      leaf.points = static_cast<long long>(b[at]);
      leaf.branch = static_cast<int>(b[at + 1]);
      leaf.area = b[at + 2];
      leaf.baseGap = b[at + 3];
      leaf.base = Eigen::Vector3d(b[at + 4], b[at + 5], b[at + 6]);
      leaf.centre = Eigen::Vector3d(b[at + 7], b[at + 8], b[at + 9]);
      leaf.petioleLength = b[at + 10];
      r.leaves.push_back(leaf);
    }
  }
  firstLeaf.push_back(static_cast<double>(r.leaves.size()));
  return firstLeaf;
}

/// Port 0: this rank's points as vertices with their point data and the labels their owners sent back (`values`,
/// ReturnWidth per point; the leaf index numbered on from its plant's first LeafId).
void WritePoints(vtkPointSet* input, const LocalInput& in, const plantmorph::OwnerExchange& exchange,
  const std::vector<double>& values, const std::vector<double>& firstLeaf, vtkPolyData* out)
{
  const auto n = static_cast<vtkIdType>(in.plantOf.size());
  std::map<vtkTypeInt64, double> first;
  for (std::size_t k = 0; k < exchange.Ids().size(); ++k)
    first[exchange.Ids()[k]] = firstLeaf[k];
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  auto organ = NewArray<vtkIntArray>(plantmorph::arrays::Organ, 1, n);
  auto leaf = NewArray<vtkIntArray>(plantmorph::arrays::LeafId, 1, n);
  auto confidence = NewArray<vtkDoubleArray>("SegmentationConfidence", 1, n);
  auto woodDistance = NewArray<vtkDoubleArray>(plantmorph::arrays::WoodDistance, 1, n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    points->SetPoint(i, &in.xyz[static_cast<std::size_t>(SendWidth * i)]);
    const double* v = &values[static_cast<std::size_t>(ReturnWidth * i)];
    organ->SetValue(i, static_cast<int>(v[0]));
    leaf->SetValue(i, v[1] >= 0.0 ? static_cast<int>(first[in.plantOf[static_cast<std::size_t>(i)]] + v[1]) : -1);
    confidence->SetValue(i, v[2]);
    woodDistance->SetValue(i, v[3]);
  }
  out->SetPoints(points);
  out->SetVerts(plantmorph::VertexCells(n));
  out->GetPointData()->PassData(input->GetPointData());
  out->GetPointData()->AddArray(organ);
  out->GetPointData()->AddArray(leaf);
  out->GetPointData()->AddArray(confidence);
  out->GetPointData()->AddArray(woodDistance);
  out->GetPointData()->SetActiveScalars(plantmorph::arrays::Organ);
}

/// Port 1: one row per leaf.
void WriteLeaves(const plantmorph::SegmentationResult& r, vtkTable* table)
{
  const auto n = static_cast<vtkIdType>(r.leaves.size());
  const char* ints[] = { "LeafId", "PlantId", "Points", "Branch" };
  const char* vectors[] = { "Base", "Centre" };
  const char* doubles[] = { "Area", "BaseGap", "PetioleLength" };
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
      leaf.area, leaf.baseGap, leaf.petioleLength };
    for (int c = 0; c < 7; ++c)
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
  table->AddColumn(NewArray<vtkIntArray>("PetiolePoints", 1, n));
  for (vtkIdType k = 0; k < n; ++k)
  {
    const plantmorph::SegmentedPlant& p = r.plants[static_cast<std::size_t>(k)];
    const double values[] = { double(p.plantId), double(p.leafCount), double(p.points), double(p.woodPoints),
      double(p.leafPoints), double(p.unassignedLeafPoints), p.height, p.spacing, double(p.petiolePoints) };
    for (int c = 0; c < 9; ++c)
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
  // Every rank takes part in every exchange, even with an empty or wrong piece; the ranks stop together.
  vtkPointSet* input = run.Input<vtkPointSet>(0);
  LocalInput in;
  const std::string error = ReadPoints(input, this->PlantIdArray, in);
  const plantmorph::OwnerExchange exchange(run.Controller(), in.plants);
  run.StopIfAnyRankFailed(exchange.AnyRank(!error.empty()), error);
  if (exchange.Ids().empty())
    run.Fail("the input has no points");
  run.Building("the segmentation of the plants");
  const auto sent = exchange.SendValues(in.plants, in.xyz, SendWidth);
  std::vector<std::vector<double>> values, blocks;
  std::string failed;
  run.Threaded(0, [&]() { failed = SegmentOwned(exchange, sent, p, values, blocks); });
  run.StopIfAnyRankFailed(exchange.AnyRank(!failed.empty()), failed);
  this->UpdateProgress(0.9);
  plantmorph::SegmentationResult result;
  std::vector<double> firstLeaf;
  const std::vector<std::vector<double>> gathered = exchange.GatherBlocks(blocks);
  if (exchange.Rank() == 0)
    firstLeaf = Assemble(gathered, result);
  exchange.Broadcast(firstLeaf);
  const std::vector<double> pointValues =
    exchange.ReturnValues(in.plants, static_cast<vtkIdType>(in.plantOf.size()), values, ReturnWidth);
  if (!in.plantOf.empty())
    WritePoints(input, in, exchange, pointValues, firstLeaf, run.Output<vtkPolyData>(0));
  if (exchange.Rank() == 0)
  {
    WriteLeaves(result, run.Output<vtkTable>(1));
    WritePlants(result, run.Output<vtkTable>(2));
  }
  plantmorph::FieldRecord record;
  record.Add("Model", "PlantSegmentation");
  record.Add("LeafCount", firstLeaf.back());
  record.Add("PlantCount", static_cast<double>(exchange.Ids().size()));
  run.WriteToEveryOutput(record);
}
