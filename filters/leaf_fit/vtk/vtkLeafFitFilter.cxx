// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkLeafFitFilter.h"
#include "PlantMorphAlgorithmHooks.h"

#include "LeafFit.h"
#include "LeafFitExchange.h"
#include "PlantMorphFieldData.h"
#include "PlantMorphLayer.h"

#include <plantmorph/DataContract.h>
#include <plantmorph/RangeError.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkLeafFitFilter);

namespace
{
template <typename T>
vtkSmartPointer<T> NewArray(const char* name, int components)
{
  auto array = vtkSmartPointer<T>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  return array;
}

/// The petiole's centre line (Region 5, LeafUV 0), junction to far end, appended to the Outline; nothing without one.
void AppendPetiole(
  const plantmorph::LeafFitResult& r, int leafId, vtkPoints* outlinePoints, vtkCellArray* lines, vtkPolyData* outline)
{
  if (r.petioleLine.size() < 2)
    return;
  lines->InsertNextCell(static_cast<vtkIdType>(r.petioleLine.size()));
  for (const auto& p : r.petioleLine)
  {
    lines->InsertCellPoint(outlinePoints->InsertNextPoint(p.data()));
    outline->GetPointData()->GetArray(plantmorph::arrays::LeafUV)->InsertNextTuple2(0.0, 0.0);
    outline->GetPointData()->GetArray("LeafId")->InsertNextTuple1(leafId);
  }
  outline->GetCellData()->GetArray(plantmorph::arrays::Region)->InsertNextTuple1(plantmorph::RegionPetiole);
  outline->GetCellData()->GetArray("LeafId")->InsertNextTuple1(leafId);
}

/// The blade and outline of one leaf appended to the outputs.
void AppendLeaf(const plantmorph::LeafFitResult& r, int leafId, vtkPoints* points, vtkCellArray* triangles,
  vtkPolyData* blade, vtkPoints* outlinePoints, vtkCellArray* lines, vtkPolyData* outline)
{
  const vtkIdType offset = points->GetNumberOfPoints();
  auto get = [](vtkPolyData* pd, const char* name) { return pd->GetPointData()->GetArray(name); };
  for (std::size_t i = 0; i < r.points.size(); ++i)
  {
    points->InsertNextPoint(r.points[i].data());
    get(blade, plantmorph::arrays::LeafUV)->InsertNextTuple2(r.leafUV[i].x(), r.leafUV[i].y());
    get(blade, plantmorph::arrays::TCoords)->InsertNextTuple2(r.tcoords[i].x(), r.tcoords[i].y());
    get(blade, plantmorph::arrays::Region)->InsertNextTuple1(r.region[i]);
    get(blade, plantmorph::arrays::Normals)->InsertNextTuple3(r.normals[i].x(), r.normals[i].y(), r.normals[i].z());
    get(blade, "LeafId")->InsertNextTuple1(leafId);
    get(blade, "Support")->InsertNextTuple1(r.support[i]);
  }
  for (const auto& t : r.triangles)
  {
    const vtkIdType ids[3] = { offset + t[0], offset + t[1], offset + t[2] };
    triangles->InsertNextCell(3, ids);
    blade->GetCellData()->GetArray(plantmorph::arrays::Region)->InsertNextTuple1(plantmorph::RegionBlade);
    blade->GetCellData()->GetArray("LeafId")->InsertNextTuple1(leafId);
  }
  const std::vector<int>* polylines[3] = { &r.leftMargin, &r.rightMargin, &r.midvein };
  const int regions[3] = { plantmorph::RegionMargin, plantmorph::RegionMargin, plantmorph::RegionMidvein };
  for (int k = 0; k < 3; ++k)
  {
    lines->InsertNextCell(static_cast<vtkIdType>(polylines[k]->size()));
    for (int id : *polylines[k])
    {
      lines->InsertCellPoint(outlinePoints->InsertNextPoint(r.points[id].data()));
      outline->GetPointData()
        ->GetArray(plantmorph::arrays::LeafUV)
        ->InsertNextTuple2(r.leafUV[id].x(), r.leafUV[id].y());
      outline->GetPointData()->GetArray("LeafId")->InsertNextTuple1(leafId);
    }
    outline->GetCellData()->GetArray(plantmorph::arrays::Region)->InsertNextTuple1(regions[k]);
    outline->GetCellData()->GetArray("LeafId")->InsertNextTuple1(leafId);
  }
  AppendPetiole(r, leafId, outlinePoints, lines, outline);
  // The fitted Model C control points, for LeafOutlineSource (B-spline, Custom).
  const std::vector<Eigen::Vector3d>* model[6] = { &r.modelMidvein, &r.modelLeftMargin, &r.modelRightMargin,
    &r.flatMidvein, &r.flatLeftMargin, &r.flatRightMargin };
  const char* names[6] = { "MidveinPoints", "LeftMarginPoints", "RightMarginPoints", "FlatMidveinPoints",
    "FlatLeftMarginPoints", "FlatRightMarginPoints" };
  for (int k = 0; k < 6; ++k)
  {
    const std::string name = "PlantMorph.FitModel." + std::to_string(leafId) + "." + names[k];
    auto array = NewArray<vtkDoubleArray>(name.c_str(), 3);
    for (const auto& p : *model[k])
      array->InsertNextTuple(p.data());
    blade->GetFieldData()->AddArray(array);
  }
  plantmorph::AddFieldValue(blade->GetFieldData(),
    ("PlantMorph.FitModel." + std::to_string(leafId) + ".ControlPoints").c_str(), r.modelControlPoints);
}
} // namespace

vtkLeafFitFilter::vtkLeafFitFilter()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(4);
}

void vtkLeafFitFilter::SetLeafIdArray(const char* name)
{
  const std::string value = name ? name : "";
  if (value != this->LeafIdArray)
  {
    this->LeafIdArray = value;
    this->Modified();
  }
}

int vtkLeafFitFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

int vtkLeafFitFilter::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 2 ? "vtkTable" : "vtkPolyData");
  return 1;
}

namespace
{
/// Per-point values the owners send back for the Scan port: FitDistance, Inlier, Region.
constexpr int ScanValues = 3;

/// The leaf's points in lexicographic order of their coordinates (ties keep their order: they are equal points), so
/// that a fit does not depend on the order the points arrive in (input order, or pieces gathered from MPI ranks).
std::vector<std::size_t> CanonicalOrder(const std::vector<Eigen::Vector3d>& points)
{
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const Eigen::Vector3d &p = points[a], &q = points[b];
    return p.x() != q.x() ? p.x() < q.x() : p.y() != q.y() ? p.y() < q.y() : p.z() < q.z();
  });
  return order;
}

/// Fits the leaves this rank owns (threaded over leaves), each on its points in canonical order; `values` gets,
/// per leaf, FitDistance, Inlier and Region (5 on the petiole, else 0) of every point in the order the points came.
std::vector<plantmorph::LeafFitResult> FitOwned(const std::vector<std::vector<Eigen::Vector3d>>& leaves,
  const plantmorph::LeafFitParameters& options, std::vector<std::vector<double>>& values)
{
  std::vector<std::vector<std::size_t>> orders(leaves.size());
  std::vector<std::vector<Eigen::Vector3d>> sorted(leaves.size());
  for (std::size_t k = 0; k < leaves.size(); ++k)
  {
    orders[k] = CanonicalOrder(leaves[k]);
    for (std::size_t i : orders[k])
      sorted[k].push_back(leaves[k][i]);
  }
  const plantmorph::ParallelFor smp = plantmorph::SMPFor(1); // one leaf per task: leaves differ in size
  std::vector<plantmorph::LeafFitResult> results = plantmorph::FitLeaves(sorted, options, smp);
  values.assign(leaves.size(), {});
  for (std::size_t k = 0; k < leaves.size(); ++k)
  {
    if (!results[k].error.empty())
      continue;
    values[k].assign(ScanValues * leaves[k].size(), 0.0);
    for (std::size_t j = 0; j < orders[k].size(); ++j)
    {
      values[k][ScanValues * orders[k][j]] = results[k].fitDistance[j];
      values[k][ScanValues * orders[k][j] + 1] = results[k].inlier[j];
      values[k][ScanValues * orders[k][j] + 2] =
        results[k].petiole[j] ? plantmorph::RegionPetiole : plantmorph::RegionBlade;
    }
  }
  return results;
}

void PrepareOutputs(vtkPolyData* blade, vtkPolyData* outline, vtkTable* traits)
{
  blade->GetPointData()->AddArray(NewArray<vtkDoubleArray>(plantmorph::arrays::LeafUV, 2));
  blade->GetPointData()->SetTCoords(NewArray<vtkFloatArray>(plantmorph::arrays::TCoords, 2));
  blade->GetPointData()->AddArray(NewArray<vtkIntArray>(plantmorph::arrays::Region, 1));
  blade->GetPointData()->SetNormals(NewArray<vtkFloatArray>(plantmorph::arrays::Normals, 3));
  blade->GetPointData()->AddArray(NewArray<vtkIntArray>("LeafId", 1));
  blade->GetPointData()->AddArray(NewArray<vtkDoubleArray>("Support", 1));
  blade->GetCellData()->AddArray(NewArray<vtkIntArray>(plantmorph::arrays::Region, 1));
  blade->GetCellData()->AddArray(NewArray<vtkIntArray>("LeafId", 1));
  outline->GetPointData()->AddArray(NewArray<vtkDoubleArray>(plantmorph::arrays::LeafUV, 2));
  outline->GetPointData()->AddArray(NewArray<vtkIntArray>("LeafId", 1));
  outline->GetCellData()->AddArray(NewArray<vtkIntArray>(plantmorph::arrays::Region, 1));
  outline->GetCellData()->AddArray(NewArray<vtkIntArray>("LeafId", 1));
  traits->AddColumn(NewArray<vtkIntArray>("LeafId", 1));
  for (const std::string& name : plantmorph::TraitNames())
    traits->AddColumn(NewArray<vtkDoubleArray>(name.c_str(), 1));
}

/// The Traits table from rows of (LeafId, TraitValues...).
void FillTraits(const std::vector<double>& rows, vtkTable* traits)
{
  const std::vector<std::string> names = plantmorph::TraitNames();
  const std::size_t width = names.size() + 1;
  for (std::size_t at = 0; at + width <= rows.size(); at += width)
  {
    vtkIntArray::SafeDownCast(traits->GetColumn(0))->InsertNextValue(static_cast<int>(rows[at]));
    for (std::size_t c = 0; c < names.size(); ++c)
      vtkDoubleArray::SafeDownCast(traits->GetColumn(static_cast<vtkIdType>(c + 1)))->InsertNextValue(rows[at + 1 + c]);
  }
}

/// Scan: the scaled input points, their data, and the fit's per-point arrays (`values`: FitDistance, Inlier and
/// Region of every point).
void FillScan(vtkPointSet* input, const std::vector<Eigen::Vector3d>& all, const std::vector<int>& leafOf,
  const std::vector<double>& values, vtkPolyData* scan)
{
  const auto n = static_cast<vtkIdType>(all.size());
  vtkNew<vtkPoints> scanPoints;
  scanPoints->SetDataTypeToDouble();
  scanPoints->SetNumberOfPoints(n);
  vtkNew<vtkCellArray> verts;
  auto distance = NewArray<vtkDoubleArray>("FitDistance", 1);
  auto inlier = NewArray<vtkUnsignedCharArray>("Inlier", 1);
  auto region = NewArray<vtkIntArray>(plantmorph::arrays::Region, 1);
  region->SetNumberOfTuples(n);
  auto leafId = NewArray<vtkIntArray>("LeafId", 1);
  distance->SetNumberOfTuples(n);
  inlier->SetNumberOfTuples(n);
  leafId->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    scanPoints->SetPoint(i, all[i].data());
    verts->InsertNextCell(1, &i);
    distance->SetValue(i, values[ScanValues * i]);
    inlier->SetValue(i, values[ScanValues * i + 1] != 0.0 ? 1 : 0);
    region->SetValue(
      i, values[ScanValues * i + 2] == plantmorph::RegionPetiole ? plantmorph::RegionPetiole : plantmorph::RegionBlade);
    leafId->SetValue(i, leafOf[i]);
  }
  scan->SetPoints(scanPoints);
  scan->SetVerts(verts);
  scan->GetPointData()->PassData(input->GetPointData());
  scan->GetPointData()->AddArray(distance);
  scan->GetPointData()->AddArray(inlier);
  scan->GetPointData()->AddArray(region);
  scan->GetPointData()->AddArray(leafId);
  scan->GetPointData()->SetActiveScalars("FitDistance");
}
} // namespace

namespace
{
/// The filter's properties as the algorithm's options.
plantmorph::LeafFitParameters Options(vtkLeafFitFilter* self)
{
  plantmorph::LeafFitParameters options;
  options.up = Eigen::Vector3d::Unit(self->GetUpAxis());
  if (self->GetUseBasePoint())
  {
    const double* base = self->GetBasePoint();
    options.basePoint = Eigen::Vector3d(base[0], base[1], base[2]);
  }
  if (self->GetUseApexPoint())
  {
    const double* apex = self->GetApexPoint();
    options.apexPoint = Eigen::Vector3d(apex[0], apex[1], apex[2]);
  }
  options.surfaceSmoothing = self->GetSurfaceSmoothing();
  options.outlineSmoothing = self->GetOutlineSmoothing();
  options.outlineControlPoints = self->GetOutlineControlPoints();
  options.outlierSigma = self->GetOutlierSigma();
  options.resolution = self->GetResolution();
  options.modelControlPoints = self->GetModelControlPoints();
  return options;
}

/// The local piece's points (scaled), each point's LeafId and each leaf's point ids; an error message for bad
/// properties or a missing LeafIdArray (nothing is checked on an empty piece).
std::string ReadLeaves(vtkLeafFitFilter* self, vtkPointSet* input, std::vector<Eigen::Vector3d>& all,
  std::vector<int>& leafOf, std::map<int, std::vector<vtkIdType>>& members)
{
  const vtkIdType n = input->GetNumberOfPoints();
  if (n == 0)
    return {}; // an empty piece (MPI ranks without leaves): nothing to check
  const double scale = self->GetScale();
  const std::string leafIdArray = self->GetLeafIdArray();
  std::string error = plantmorph::ValidateLeafFitParameters(Options(self));
  const int baseCount = self->GetBasePointElementCount();
  if (baseCount >= 0 && baseCount != 3)
    error = plantmorph::OutOfRange(
      "BasePoint", std::to_string(baseCount) + " numbers", "3 numbers (x, y, z)", "the value given was not set");
  const int apexCount = self->GetApexPointElementCount();
  if (error.empty() && apexCount >= 0 && apexCount != 3)
    error = plantmorph::OutOfRange(
      "ApexPoint", std::to_string(apexCount) + " numbers", "3 numbers (x, y, z)", "the value given was not set");
  if (error.empty() && !(std::isfinite(scale) && scale > 0.0))
    error = plantmorph::OutOfRange("Scale", scale, "(0, inf)");
  vtkDataArray* ids = nullptr;
  if (error.empty() && !leafIdArray.empty())
  {
    ids = input->GetPointData()->GetArray(leafIdArray.c_str());
    if (!ids || ids->GetNumberOfComponents() != 1)
      error = "LeafIdArray: the input has no one-component point array named '" + leafIdArray + "'";
  }
  if (!error.empty())
    return error;
  all.resize(n);
  leafOf.assign(n, 0);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    all[i] = scale * Eigen::Vector3d(p[0], p[1], p[2]);
    const double id = ids ? ids->GetComponent(i, 0) : 0.0;
    leafOf[i] = std::isfinite(id) ? static_cast<int>(std::lround(id)) : -1;
    members[leafOf[i]].push_back(i);
  }
  return {};
}

} // namespace

namespace
{
/// Each leaf is fitted whole on one owner rank (LeafFitExchange.h); the Scan output stays where its points are.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::LeafPerRank;

/// The failed fits of this rank's leaves, one line each ("leaf <id> (<n> points): <error>"); empty when none failed.
std::string FitErrors(const plantmorph::fitmpi::LeafExchange& exchange, const std::vector<std::size_t>& owned,
  const std::vector<std::vector<Eigen::Vector3d>>& leaves, const std::vector<plantmorph::LeafFitResult>& results)
{
  std::ostringstream message;
  for (std::size_t k = 0; k < results.size(); ++k)
    if (!results[k].error.empty())
      message << (message.tellp() > 0 ? "\n" : "") << "leaf " << exchange.LeafIds()[owned[k]] << " ("
              << leaves[k].size() << " points): " << results[k].error;
  return message.str();
}

/// Blade and Outline of the leaves this rank fitted; their Traits rows, gathered on rank 0 in LeafId order
/// (collective).
void WriteFits(const plantmorph::fitmpi::LeafExchange& exchange, const std::vector<std::size_t>& owned,
  const std::vector<plantmorph::LeafFitResult>& results, double scale, const plantmorph::Run& run)
{
  vtkPolyData* blade = run.Output<vtkPolyData>(0);
  vtkPolyData* outline = run.Output<vtkPolyData>(1);
  vtkTable* traits = run.Output<vtkTable>(2);
  PrepareOutputs(blade, outline, traits);
  vtkNew<vtkPoints> points, outlinePoints;
  points->SetDataTypeToDouble();
  outlinePoints->SetDataTypeToDouble();
  vtkNew<vtkCellArray> triangles, lines;
  std::vector<double> rows;
  for (std::size_t k = 0; k < results.size(); ++k)
  {
    const int leafId = exchange.LeafIds()[owned[k]];
    AppendLeaf(results[k], leafId, points, triangles, blade, outlinePoints, lines, outline);
    rows.push_back(leafId);
    const std::vector<double> row = plantmorph::TraitValues(results[k].traits);
    rows.insert(rows.end(), row.begin(), row.end());
  }
  blade->SetPoints(points);
  blade->SetPolys(triangles);
  outline->SetPoints(outlinePoints);
  outline->SetLines(lines);
  plantmorph::FieldRecord record;
  record.Add("Scale", scale);
  record.WriteTo(blade);
  const int width = static_cast<int>(plantmorph::TraitNames().size()) + 1;
  FillTraits(exchange.GatherRows(rows, width), traits);
}
} // namespace

int vtkLeafFitFilter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the leaf fits", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

void vtkLeafFitFilter::Execute(plantmorph::Run& run)
{
  vtkPointSet* input = run.Input<vtkPointSet>(0);
  // The local piece's leaves; then (collective, LeafFitExchange.h) each leaf's owner, and the points of the leaves
  // this rank owns. Every rank takes part even when its piece is empty or wrong; the ranks stop together, each
  // saying its own error.
  std::vector<Eigen::Vector3d> all;
  std::vector<int> leafOf;
  plantmorph::fitmpi::LocalLeaves members;
  const std::string error = ReadLeaves(this, input, all, leafOf, members);
  const plantmorph::fitmpi::LeafExchange exchange(vtkMultiProcessController::GetGlobalController(), members);
  run.StopIfAnyRankFailed(exchange.AnyRank(!error.empty()), error);
  if (exchange.LeafIds().empty())
    return; // no points on any rank: empty outputs, no error
  const std::vector<std::size_t> owned = exchange.Owned();
  const std::vector<std::vector<Eigen::Vector3d>> leaves = exchange.SendPoints(members, all);
  std::vector<std::vector<double>> values;
  const std::vector<plantmorph::LeafFitResult> results = FitOwned(leaves, Options(this), values);
  const std::string fitErrors = FitErrors(exchange, owned, leaves, results);
  run.StopIfAnyRankFailed(exchange.AnyRank(!fitErrors.empty()), fitErrors);
  for (std::size_t k = 0; k < results.size(); ++k)
    if (!results[k].modelWarning.empty())
      run.WarnHere("leaf " + std::to_string(exchange.LeafIds()[owned[k]]) + ": " + results[k].modelWarning);
  WriteFits(exchange, owned, results, this->Scale, run);
  // Scan: stays where its points are; the owners send each point's FitDistance, Inlier and Region back.
  const std::vector<double> pointValues =
    exchange.ReturnValues(members, static_cast<vtkIdType>(all.size()), values, ScanValues);
  if (!all.empty())
    FillScan(input, all, leafOf, pointValues, run.Output<vtkPolyData>(3));
}

void vtkLeafFitFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scale: " << this->Scale << "\n"
     << indent << "LeafIdArray: " << this->LeafIdArray << "\n"
     << indent << "UpAxis: " << this->UpAxis << "\n"
     << indent << "UseBasePoint: " << this->UseBasePoint << "\n"
     << indent << "UseApexPoint: " << this->UseApexPoint << "\n"
     << indent << "SurfaceSmoothing: " << this->SurfaceSmoothing << "\n"
     << indent << "OutlineSmoothing: " << this->OutlineSmoothing << "\n"
     << indent << "OutlineControlPoints: " << this->OutlineControlPoints << "\n"
     << indent << "OutlierSigma: " << this->OutlierSigma << "\n"
     << indent << "Resolution: " << this->Resolution << "\n"
     << indent << "ModelControlPoints: " << this->ModelControlPoints << "\n";
}
