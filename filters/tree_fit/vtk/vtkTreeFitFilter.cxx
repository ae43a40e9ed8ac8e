// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkTreeFitFilter.h"

#include "PlantMorphAlgorithmHooks.h"
#include "PlantMorphLayer.h"
#include "TreeFit.h"
#include "PlantMorphOwnerExchange.h"
#include "TreeFitExchange.h"
#include "TreeFitOutputs.h"
#include <plantmorph/DataContract.h>

#include <plantmorph/RangeError.h>

#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkTable.h"

#include <algorithm>
#include <limits>
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
/// Each tree is fitted whole on one owner rank (common/vtk/PlantMorphOwnerExchange.h); the Scan output stays where
/// its points are, the fitted trees are gathered on rank 0.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::LeafPerRank;
/// Values per point sent to the owners (x, y, z, wood label) and back (cylinder, branch, wood, distance).
constexpr int SendWidth = 4, ReturnWidth = 4;

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

/// This rank's piece: the scaled points with their wood label (1 without WoodArray), the TreeId of each (-1 for a
/// TreeId that is not a finite number) and the trees' members.
struct LocalInput
{
  std::vector<Eigen::Vector3d> points;
  std::vector<double> sent; ///< SendWidth values per point
  std::vector<int> treeOf;
  plantmorph::LocalGroups trees;
};

/// Reads this rank's piece (none, or no points: nothing, no error); "" or the missing array.
std::string ReadTrees(vtkTreeFitFilter* self, vtkPointSet* input, LocalInput& in)
{
  const vtkIdType n = input ? input->GetNumberOfPoints() : 0;
  if (n == 0)
    return {};
  std::string error;
  vtkDataArray* ids = NamedArray(input, self->GetTreeIdArray(), "TreeIdArray", error);
  vtkDataArray* labels = NamedArray(input, self->GetWoodArray(), "WoodArray", error);
  if (!error.empty())
    return error;
  // Which value is wood: PlantMorph's Organ label (scanner truth, segmentation) marks wood by 0, a wood flag by 1.
  const int mode = self->GetWoodValues();
  const bool zeroIsWood = mode == 2 || (mode == 0 && std::string(self->GetWoodArray()) == plantmorph::arrays::Organ);
  in.points.resize(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    in.points[i] = self->GetScale() * Eigen::Vector3d(p[0], p[1], p[2]);
    const double id = ids ? ids->GetComponent(i, 0) : 0.0;
    in.treeOf.push_back(std::isfinite(id) ? static_cast<int>(std::lround(id)) : -1);
    in.trees[in.treeOf.back()].push_back(i);
    in.sent.insert(in.sent.end(),
      { in.points[i].x(), in.points[i].y(), in.points[i].z(),
        !labels || ((labels->GetComponent(i, 0) == 0.0) == zeroIsWood) ? 1.0 : 0.0 });
  }
  return {};
}

/// Fits the trees this rank owns (each threaded inside); `values` gets, per owned tree, ReturnWidth values per point.
std::vector<plantmorph::TreeFitResult> FitOwned(const std::vector<std::vector<double>>& sent, bool labelled,
  const plantmorph::TreeFitParameters& options, bool serial, const plantmorph::Run& run,
  std::vector<std::vector<double>>& values)
{
  const plantmorph::ParallelFor smp = plantmorph::SMPFor();
  std::vector<plantmorph::TreeFitResult> fits;
  for (std::size_t k = 0; k < sent.size(); ++k)
  {
    const std::size_t n = sent[k].size() / SendWidth;
    std::vector<Eigen::Vector3d> points(n);
    std::vector<int> labels;
    for (std::size_t i = 0; i < n; ++i)
    {
      points[i] = Eigen::Vector3d(sent[k][SendWidth * i], sent[k][SendWidth * i + 1], sent[k][SendWidth * i + 2]);
      if (labelled)
        labels.push_back(sent[k][SendWidth * i + 3] != 0.0 ? 1 : 0);
    }
    fits.push_back(plantmorph::FitTree(points, labels, options, smp));
    const plantmorph::TreeFitResult& fit = fits.back();
    values.emplace_back();
    for (std::size_t i = 0; i < n; ++i)
    {
      const bool ok = fit.error.empty();
      values.back().insert(values.back().end(),
        { ok ? static_cast<double>(fit.pointCylinder[i]) : -1.0, ok ? static_cast<double>(fit.pointBranch[i]) : -1.0,
          ok ? static_cast<double>(fit.wood[i]) : 0.0,
          ok ? fit.fitDistance[i] : std::numeric_limits<double>::quiet_NaN() });
    }
    run.UpdateProgress(static_cast<double>(k + 1) / static_cast<double>(sent.size()));
    if (serial)
      run.StopIfAborted(); // under MPI the other ranks wait in the exchange: no stop half-way
  }
  return fits;
}

/// On rank 0: every tree's fit (from the gathered blocks), numbered over the whole output; "" or, when no tree could
/// be fitted, every tree's error; `warning` the failed trees when some could.
std::string Assemble(const plantmorph::OwnerExchange& exchange, const std::vector<std::vector<double>>& blocks,
  std::vector<plantmorph::treefitvtk::FittedTree>& trees, std::string& warning)
{
  int cylinders = 0, branches = 0;
  std::size_t failed = 0;
  std::ostringstream errors;
  for (std::size_t k = 0; k < blocks.size(); ++k)
  {
    trees.emplace_back();
    auto& t = trees.back();
    t.treeId = static_cast<int>(exchange.Ids()[k]);
    t.result = plantmorph::treefitvtk::UnpackFit(std::vector<double>(blocks[k].begin() + 1, blocks[k].end()));
    t.cylinderBase = cylinders;
    t.branchBase = branches;
    cylinders += static_cast<int>(t.result.cylinders.size());
    branches += static_cast<int>(t.result.branches.size());
    if (!t.result.error.empty())
    {
      ++failed;
      errors << (errors.tellp() > 0 ? "\n" : "") << "tree " << t.treeId << " (" << blocks[k][0]
             << " points): " << t.result.error;
    }
  }
  if (failed == trees.size())
    return errors.str();
  if (failed > 0)
    warning = errors.str() + "\n(those trees' rows in Trees say why; the other trees are fitted)";
  return {};
}
/// Collective: rank 0 numbers the trees and writes Cylinders, Skeleton, Trees and Branches; every rank writes the
/// Scan of its own points with the values their trees' owners send back. Stops on every rank when no tree was fitted.
void WriteOutputs(vtkTreeFitFilter* self, plantmorph::Run& run, vtkPointSet* input, const LocalInput& in,
  const plantmorph::OwnerExchange& exchange, const std::vector<std::vector<double>>& blocks,
  const std::vector<std::vector<double>>& values)
{
  std::vector<plantmorph::treefitvtk::FittedTree> trees;
  std::string failure, warning;
  std::vector<double> shared; // no tree fitted (0/1), then each tree's first cylinder and branch id
  if (exchange.Rank() == 0)
  {
    failure = Assemble(exchange, blocks, trees, warning);
    shared.push_back(failure.empty() ? 0.0 : 1.0);
    for (const auto& t : trees)
      shared.insert(shared.end(), { static_cast<double>(t.cylinderBase), static_cast<double>(t.branchBase) });
  }
  exchange.Broadcast(shared);
  const std::vector<double> pointValues =
    exchange.ReturnValues(in.trees, static_cast<vtkIdType>(in.points.size()), values, ReturnWidth);
  run.StopIfAnyRankFailed(shared.front() != 0.0, failure);
  if (!warning.empty())
    run.Warn(warning);
  run.Building("the tree outputs");
  if (exchange.Rank() == 0)
  {
    plantmorph::treefitvtk::WriteCylinders(
      trees, self->GetTubes() != 0, self->GetTubeSides(), run.Output<vtkPolyData>(0));
    plantmorph::treefitvtk::WriteSkeleton(trees, run.Output<vtkPolyData>(1));
    plantmorph::treefitvtk::WriteTables(trees, run.Output<vtkTable>(2), run.Output<vtkTable>(3));
    plantmorph::FieldRecord record;
    record.Add("Model", "TreeFit");
    record.Add("Scale", self->GetScale());
    record.WriteTo(run.Output<vtkPolyData>(0));
    record.WriteTo(run.Output<vtkPolyData>(1));
  }
  std::map<int, std::pair<int, int>> bases;
  for (std::size_t k = 0; k < exchange.Ids().size(); ++k)
    bases[static_cast<int>(exchange.Ids()[k])] = { static_cast<int>(shared[1 + 2 * k]),
      static_cast<int>(shared[2 + 2 * k]) };
  if (!in.points.empty())
    plantmorph::treefitvtk::WriteScan(input, in.points, in.treeOf, pointValues, bases, run.Output<vtkPolyData>(4));
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
  plantmorph::TreeFitParameters options;
  run.Check(Options(this, options));
  // Every rank takes part in every exchange, even with an empty or wrong piece; the ranks stop together.
  vtkPointSet* input = run.Input<vtkPointSet>(0);
  LocalInput in;
  const std::string error = ReadTrees(this, input, in);
  const plantmorph::OwnerExchange exchange(run.Controller(), in.trees);
  run.StopIfAnyRankFailed(exchange.AnyRank(!error.empty()), error);
  if (exchange.Ids().empty())
    run.Fail("the input has no points");
  run.Building("the tree fits");
  std::vector<std::vector<double>> values;
  std::vector<plantmorph::TreeFitResult> fits;
  const auto sent = exchange.SendValues(in.trees, in.sent, SendWidth);
  const bool labelled = !this->WoodArray.empty() && this->WoodArray != "None";
  run.Threaded(0, [&]() { fits = FitOwned(sent, labelled, options, exchange.Ranks() == 1, run, values); });
  std::vector<std::vector<double>> packed;
  for (std::size_t k = 0; k < fits.size(); ++k) // each block: the tree's point count, then its fit
  {
    packed.push_back({ static_cast<double>(sent[k].size() / SendWidth) });
    const std::vector<double> fit = plantmorph::treefitvtk::PackFit(fits[k]);
    packed.back().insert(packed.back().end(), fit.begin(), fit.end());
  }
  WriteOutputs(this, run, input, in, exchange, exchange.GatherBlocks(packed), values);
}

void vtkTreeFitFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scale: " << this->Scale << "\n"
     << indent << "TreeIdArray: " << this->TreeIdArray << "\n"
     << indent << "WoodArray: " << this->WoodArray << "\n"
     << indent << "WoodValues: " << this->WoodValues << "\n"
     << indent << "UpAxis: " << this->UpAxis << "\n"
     << indent << "Tubes: " << this->Tubes << "\n"
     << indent << "TubeSides: " << this->TubeSides << "\n"
     << indent << "OutlierSigma: " << this->OutlierSigma << "\n"
     << indent << "BreastHeight: " << this->BreastHeight << "\n";
}
