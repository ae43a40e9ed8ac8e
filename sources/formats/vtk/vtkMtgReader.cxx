// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkMtgReader.h"

#include "MtgText.h"

#include "PlantMorphLayer.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkMtgReader);

namespace
{
/// The tree is made whole on the first rank (an MTG is read in one pass; plants are small next to their scans).
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank;

/// The points of every axis in order: (entity, axis) per point, a branch's bearer first when `connect`.
std::vector<long long> PointEntities(const plantmorph::MtgGeometry& g, bool connect, std::vector<vtkIdType>& sizes)
{
  std::vector<long long> entities;
  for (const plantmorph::MtgAxis& axis : g.axes)
  {
    const bool bearer = connect && axis.bearer >= 0;
    if (bearer)
    {
      entities.push_back(axis.bearer);
    }
    entities.insert(entities.end(), axis.entities.begin(), axis.entities.end());
    sizes.push_back(static_cast<vtkIdType>(axis.entities.size() + (bearer ? 1 : 0)));
  }
  return entities;
}

/// The feature columns as point arrays, and Radius from the first diameter feature.
void AddFeatures(const plantmorph::MtgGraph& graph, const std::vector<long long>& entities, vtkPointData* pd)
{
  const auto n = static_cast<vtkIdType>(entities.size());
  for (std::size_t f = 0; f < graph.features.size(); ++f)
  {
    const bool text = graph.features[f].kind == plantmorph::MtgFeatureKind::Text;
    vtkSmartPointer<vtkAbstractArray> array = text
      ? vtkSmartPointer<vtkAbstractArray>(vtkSmartPointer<vtkStringArray>::New())
      : vtkSmartPointer<vtkAbstractArray>(vtkSmartPointer<vtkDoubleArray>::New());
    array->SetName(graph.features[f].name.c_str());
    array->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      const auto e = static_cast<std::size_t>(entities[static_cast<std::size_t>(i)]);
      if (text)
      {
        static_cast<vtkStringArray*>(array.Get())->SetValue(i, graph.texts[f][e]);
      }
      else
      {
        static_cast<vtkDoubleArray*>(array.Get())->SetValue(i, graph.numbers[f][e]);
      }
    }
    pd->AddArray(array);
  }
  for (const char* name : { "diam", "Diameter", "diameter", "TopDia", "TopDiameter" })
  {
    const int f = graph.FeatureIndex(name);
    if (f >= 0 && graph.features[static_cast<std::size_t>(f)].kind != plantmorph::MtgFeatureKind::Text)
    {
      vtkNew<vtkDoubleArray> radius;
      radius->SetName("Radius");
      radius->SetNumberOfTuples(n);
      for (vtkIdType i = 0; i < n; ++i)
      {
        radius->SetValue(i, 0.5 * graph.numbers[static_cast<std::size_t>(f)][static_cast<std::size_t>(entities[i])]);
      }
      pd->AddArray(radius);
      pd->SetActiveScalars("Radius");
      return;
    }
  }
}

/// EntityId, Label, and the coarser scales' Scale<s>Id and Scale<s>Label.
void AddEntities(const plantmorph::MtgGraph& graph, int scale, const std::vector<long long>& entities, vtkPointData* pd)
{
  const auto n = static_cast<vtkIdType>(entities.size());
  for (int s = scale; s >= 1; --s)
  {
    vtkNew<vtkIdTypeArray> ids;
    vtkNew<vtkStringArray> labels;
    const std::string stem = s == scale ? std::string() : "Scale" + std::to_string(s);
    ids->SetName((s == scale ? std::string("EntityId") : stem + "Id").c_str());
    labels->SetName((s == scale ? std::string("Label") : stem + "Label").c_str());
    ids->SetNumberOfTuples(n);
    labels->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      long long e = entities[static_cast<std::size_t>(i)];
      while (e >= 0 && graph.entities[static_cast<std::size_t>(e)].scale > s)
      {
        e = graph.entities[static_cast<std::size_t>(e)].complex;
      }
      const bool found = e >= 0 && graph.entities[static_cast<std::size_t>(e)].scale == s;
      ids->SetValue(i, found ? static_cast<vtkIdType>(e) : -1);
      labels->SetValue(i, found ? graph.entities[static_cast<std::size_t>(e)].Label() : std::string());
    }
    pd->AddArray(ids);
    pd->AddArray(labels);
  }
}

/// The polylines, their cell arrays and the point arrays.
void WriteAxes(const plantmorph::MtgGraph& graph, const plantmorph::MtgGeometry& g, bool connect, vtkPolyData* out)
{
  std::vector<vtkIdType> sizes;
  const std::vector<long long> entities = PointEntities(g, connect, sizes);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(entities.size()));
  for (std::size_t i = 0; i < entities.size(); ++i)
  {
    points->SetPoint(static_cast<vtkIdType>(i), g.positions[static_cast<std::size_t>(entities[i])].data());
  }
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> branchId, parentId, order;
  branchId->SetName("BranchId");
  parentId->SetName("ParentId");
  order->SetName("BranchOrder");
  vtkIdType next = 0;
  for (std::size_t a = 0; a < g.axes.size(); ++a)
  {
    lines->InsertNextCell(sizes[a]);
    for (vtkIdType k = 0; k < sizes[a]; ++k)
    {
      lines->InsertCellPoint(next++);
    }
    branchId->InsertNextValue(static_cast<int>(a));
    parentId->InsertNextValue(static_cast<int>(g.axes[a].parentAxis));
    order->InsertNextValue(g.axes[a].order);
  }
  out->SetPoints(points);
  out->SetLines(lines);
  out->GetCellData()->AddArray(branchId);
  out->GetCellData()->AddArray(parentId);
  out->GetCellData()->AddArray(order);
  AddEntities(graph, g.scale, entities, out->GetPointData());
  AddFeatures(graph, entities, out->GetPointData());
}
} // namespace

//------------------------------------------------------------------------------
vtkMtgReader::vtkMtgReader()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
vtkMtgReader::~vtkMtgReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkMtgReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ConnectBranches: " << this->ConnectBranches << "\n";
}

//------------------------------------------------------------------------------
int vtkMtgReader::CanReadFile(const char* name)
{
  std::error_code failed;
  if (!name || std::filesystem::is_directory(name, failed))
  {
    return 0;
  }
  std::ifstream file(name, std::ios::binary);
  std::string line;
  for (int k = 0; k < 50 && std::getline(file, line) && line.size() < 4096; ++k)
  {
    const std::size_t start = line.find_first_not_of(" \t\xEF\xBB\xBF");
    for (const char* section : { "CODE", "CLASSES", "MTG" })
    {
      if (start != std::string::npos && line.compare(start, std::string(section).size(), section) == 0)
      {
        return 1;
      }
    }
  }
  return 0;
}

//------------------------------------------------------------------------------
int vtkMtgReader::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the MTG tree", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkMtgReader::Execute(plantmorph::Run& run)
{
  if (!this->FileName || !*this->FileName)
  {
    run.Fail("FileName is not set: give an MTG file (FORM-A text, *.mtg)");
  }
  const std::string name = this->FileName;
  std::error_code failed;
  std::ifstream file(name, std::ios::binary);
  if (std::filesystem::is_directory(name, failed) || !file)
  {
    run.Fail("FileName '" + name + "' cannot be opened as a file");
  }
  plantmorph::MtgGraph graph;
  run.Building("the MTG graph of '" + name + "'");
  const std::string error = plantmorph::ReadMtg(file, graph);
  if (!error.empty())
  {
    run.Fail("FileName '" + name + "', " + error);
  }
  const plantmorph::MtgGeometry geometry = plantmorph::BuildMtgGeometry(graph);
  if (!geometry.warning.empty())
  {
    run.Warn("FileName '" + name + "': " + geometry.warning);
  }
  vtkPolyData* output = run.Output<vtkPolyData>(0);
  WriteAxes(graph, geometry, this->ConnectBranches != 0, output);
  plantmorph::FieldRecord record;
  record.Add("SourceFile", name);
  record.Add("MtgScale", static_cast<double>(geometry.scale));
  record.Add("ExplicitCoordinates", geometry.explicitCoordinates ? 1.0 : 0.0);
  record.WriteTo(output);
}
