// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkTreeFitFilter.h"

#include "PlantMorphAlgorithmHooks.h"
#include "PlantMorphLayer.h"
#include "TreeFit.h"
#include "TreeFitOutputs.h"

#include <plantmorph/RangeError.h>

#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkTable.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

vtkStandardNewMacro(vtkTreeFitFilter);

vtkTreeFitFilter::vtkTreeFitFilter()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(5);
}

void vtkTreeFitFilter::SetTreeIdArray(const char* name)
{
  const std::string value = name ? name : "";
  if (value != this->TreeIdArray)
  {
    this->TreeIdArray = value;
    this->Modified();
  }
}

void vtkTreeFitFilter::SetWoodArray(const char* name)
{
  const std::string value = name ? name : "";
  if (value != this->WoodArray)
  {
    this->WoodArray = value;
    this->Modified();
  }
}

int vtkTreeFitFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

int vtkTreeFitFilter::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 2 || port == 3 ? "vtkTable" : "vtkPolyData");
  return 1;
}

namespace
{
/// Everything fits on rank 0 (the trees are few and the fit of one is threaded).
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank;

/// A one-component point array named `name` (empty name: none), or an error naming `property`.
vtkDataArray* NamedArray(vtkPointSet* input, const std::string& name, const char* property, std::string& error)
{
  if (name.empty() || name == "None" || !error.empty())
    return nullptr;
  vtkDataArray* array = input->GetPointData()->GetArray(name.c_str());
  if (!array || array->GetNumberOfComponents() != 1)
    error = std::string(property) + ": the input has no one-component point array named '" + name + "'";
  return array;
}

/// The filter's properties as the algorithm's options, "" or the first property out of range.
std::string Options(vtkTreeFitFilter* self, plantmorph::TreeFitParameters& options)
{
  options.up = Eigen::Vector3d::Unit(self->GetUpAxis());
  options.outlierSigma = self->GetOutlierSigma();
  options.breastHeight = self->GetBreastHeight();
  std::string error = plantmorph::ValidateTreeFitParameters(options);
  const double scale = self->GetScale();
  if (error.empty() && !(std::isfinite(scale) && scale > 0.0))
    error = plantmorph::OutOfRange("Scale", scale, "(0, inf)");
  if (error.empty() && (self->GetTubeSides() < 3 || self->GetTubeSides() > 64))
    error = plantmorph::OutOfRange("TubeSides", self->GetTubeSides(), "[3, 64]");
  return error;
}

/// The scaled points, the wood labels (empty: none) and the trees' members (by TreeId, ascending).
std::string ReadTrees(vtkTreeFitFilter* self, vtkPointSet* input, std::vector<Eigen::Vector3d>& all,
  std::vector<int>& wood, std::vector<plantmorph::treefitvtk::FittedTree>& trees)
{
  std::string error;
  vtkDataArray* ids = NamedArray(input, self->GetTreeIdArray(), "TreeIdArray", error);
  vtkDataArray* labels = NamedArray(input, self->GetWoodArray(), "WoodArray", error);
  if (!error.empty())
    return error;
  const vtkIdType n = input->GetNumberOfPoints();
  std::map<int, std::vector<vtkIdType>> members;
  all.resize(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    all[i] = self->GetScale() * Eigen::Vector3d(p[0], p[1], p[2]);
    const double id = ids ? ids->GetComponent(i, 0) : 0.0;
    members[std::isfinite(id) ? static_cast<int>(std::lround(id)) : -1].push_back(i);
    if (labels)
      wood.push_back(labels->GetComponent(i, 0) != 0.0 ? 1 : 0);
  }
  for (auto& [id, points] : members)
  {
    trees.emplace_back();
    trees.back().treeId = id;
    trees.back().members = std::move(points);
  }
  return {};
}

/// Fits every tree (each threaded inside); numbers their cylinders and branches over the whole output; "" or, when
/// no tree could be fitted, every tree's error.
std::string FitAll(const std::vector<Eigen::Vector3d>& all, const std::vector<int>& wood,
  const plantmorph::TreeFitParameters& options, std::vector<plantmorph::treefitvtk::FittedTree>& trees,
  const plantmorph::Run& run)
{
  const plantmorph::ParallelFor smp = plantmorph::SMPFor();
  int cylinders = 0, branches = 0, failed = 0;
  std::ostringstream errors;
  for (std::size_t k = 0; k < trees.size(); ++k)
  {
    auto& t = trees[k];
    std::vector<Eigen::Vector3d> points;
    std::vector<int> labels;
    for (vtkIdType i : t.members)
    {
      points.push_back(all[i]);
      if (!wood.empty())
        labels.push_back(wood[i]);
    }
    t.result = plantmorph::FitTree(points, labels, options, smp);
    t.cylinderBase = cylinders;
    t.branchBase = branches;
    cylinders += static_cast<int>(t.result.cylinders.size());
    branches += static_cast<int>(t.result.branches.size());
    if (!t.result.error.empty())
    {
      ++failed;
      errors << (errors.tellp() > 0 ? "\n" : "") << "tree " << t.treeId << " (" << points.size()
             << " points): " << t.result.error;
    }
    run.UpdateProgress(static_cast<double>(k + 1) / static_cast<double>(trees.size()));
    run.StopIfAborted();
  }
  if (failed == static_cast<int>(trees.size()))
    return errors.str();
  if (failed > 0)
    run.Warn(errors.str() + "\n(those trees' rows in Trees say why; the other trees are fitted)");
  return {};
}
} // namespace

int vtkTreeFitFilter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the tree fits", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

void vtkTreeFitFilter::Execute(plantmorph::Run& run)
{
  vtkPointSet* input = run.Input<vtkPointSet>(0);
  plantmorph::TreeFitParameters options;
  run.Check(Options(this, options));
  if (!input || input->GetNumberOfPoints() == 0)
    run.Fail("the input has no points");
  std::vector<Eigen::Vector3d> all;
  std::vector<int> wood;
  std::vector<plantmorph::treefitvtk::FittedTree> trees;
  run.Check(ReadTrees(this, input, all, wood, trees));
  run.Building("the tree fits");
  run.Threaded(0, [&]() { run.Check(FitAll(all, wood, options, trees, run)); });
  run.Building("the tree outputs");
  plantmorph::treefitvtk::WriteCylinders(trees, this->Tubes != 0, this->TubeSides, run.Output<vtkPolyData>(0));
  plantmorph::treefitvtk::WriteSkeleton(trees, run.Output<vtkPolyData>(1));
  plantmorph::treefitvtk::WriteTables(trees, run.Output<vtkTable>(2), run.Output<vtkTable>(3));
  plantmorph::treefitvtk::WriteScan(input, all, trees, run.Output<vtkPolyData>(4));
  plantmorph::FieldRecord record;
  record.Add("Model", "TreeFit");
  record.Add("Scale", this->Scale);
  record.WriteTo(run.Output<vtkPolyData>(0));
  record.WriteTo(run.Output<vtkPolyData>(1));
}

void vtkTreeFitFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scale: " << this->Scale << "\n"
     << indent << "TreeIdArray: " << this->TreeIdArray << "\n"
     << indent << "WoodArray: " << this->WoodArray << "\n"
     << indent << "UpAxis: " << this->UpAxis << "\n"
     << indent << "Tubes: " << this->Tubes << "\n"
     << indent << "TubeSides: " << this->TubeSides << "\n"
     << indent << "OutlierSigma: " << this->OutlierSigma << "\n"
     << indent << "BreastHeight: " << this->BreastHeight << "\n";
}
