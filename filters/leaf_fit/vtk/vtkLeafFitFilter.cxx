// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkLeafFitFilter.h"
#include "PlantMorphAlgorithmHooks.h"

#include "LeafFit.h"
#include "LeafFitScannerView.h"
#include "LeafFitTables.h"
#include "PlantMorphOwnerExchange.h"
#include "LeafPlant.h"
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
#include "vtkTypeInt64Array.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <iterator>
#include <map>
#include <numeric>
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
void AppendPetiole(const plantmorph::LeafFitResult& r, std::int64_t leafId, vtkPoints* outlinePoints,
  vtkCellArray* lines, vtkPolyData* outline)
{
  if (r.petioleLine.size() < 2)
    return;
  lines->InsertNextCell(static_cast<vtkIdType>(r.petioleLine.size()));
  for (const auto& p : r.petioleLine)
  {
    lines->InsertCellPoint(outlinePoints->InsertNextPoint(p.data()));
    outline->GetPointData()->GetArray(plantmorph::arrays::LeafUV)->InsertNextTuple2(0.0, 0.0);
    vtkTypeInt64Array::SafeDownCast(outline->GetPointData()->GetArray(plantmorph::arrays::LeafId))
      ->InsertNextValue(leafId);
  }
  outline->GetCellData()->GetArray(plantmorph::arrays::Region)->InsertNextTuple1(plantmorph::RegionPetiole);
  vtkTypeInt64Array::SafeDownCast(outline->GetCellData()->GetArray(plantmorph::arrays::LeafId))
    ->InsertNextValue(leafId);
}

/// The blade and outline of one leaf appended to the outputs.
void AppendLeaf(const plantmorph::LeafFitResult& r, std::int64_t leafId, vtkPoints* points, vtkCellArray* triangles,
  vtkPolyData* blade, vtkPoints* outlinePoints, vtkCellArray* lines, vtkPolyData* outline)
{
  const vtkIdType offset = points->GetNumberOfPoints();
  auto get = [](vtkPolyData* pd, const char* name) { return pd->GetPointData()->GetArray(name); };
  auto addId = [leafId](vtkFieldData* data) {
    vtkTypeInt64Array::SafeDownCast(data->GetArray(plantmorph::arrays::LeafId))->InsertNextValue(leafId);
  };
  for (std::size_t i = 0; i < r.points.size(); ++i)
  {
    points->InsertNextPoint(r.points[i].data());
    get(blade, plantmorph::arrays::LeafUV)->InsertNextTuple2(r.leafUV[i].x(), r.leafUV[i].y());
    get(blade, plantmorph::arrays::TCoords)->InsertNextTuple2(r.tcoords[i].x(), r.tcoords[i].y());
    get(blade, plantmorph::arrays::Region)->InsertNextTuple1(r.region[i]);
    get(blade, plantmorph::arrays::Normals)->InsertNextTuple3(r.normals[i].x(), r.normals[i].y(), r.normals[i].z());
    addId(blade->GetPointData());
    get(blade, "Support")->InsertNextTuple1(r.support[i]);
  }
  for (const auto& t : r.triangles)
  {
    const vtkIdType ids[3] = { offset + t[0], offset + t[1], offset + t[2] };
    triangles->InsertNextCell(3, ids);
    blade->GetCellData()->GetArray(plantmorph::arrays::Region)->InsertNextTuple1(plantmorph::RegionBlade);
    addId(blade->GetCellData());
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
      addId(outline->GetPointData());
    }
    outline->GetCellData()->GetArray(plantmorph::arrays::Region)->InsertNextTuple1(regions[k]);
    addId(outline->GetCellData());
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
  this->SetNumberOfOutputPorts(5);
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

void vtkLeafFitFilter::SetInputUnit(const char* unit)
{
  const std::string value = unit ? unit : "";
  if (value != this->InputUnit)
  {
    this->InputUnit = value;
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
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 2 || port == 4 ? "vtkTable" : "vtkPolyData");
  return 1;
}

namespace
{
/// Per-point values the owners send back for the Scan port: FitDistance, Inlier, Region, and the blade the point
/// belongs to when the points are cut into separate blades.
constexpr int ScanValues = 4;

/// The leaf's points in lexicographic order of their coordinates (ties keep their order: they are equal points), so
/// that a fit does not depend on the order the points arrive in (input order, or pieces gathered from MPI ranks).
/// Sorted through `parallel` by (x, y, z, index), a total order whose sort is the stable sort by (x, y, z), when the
/// coordinates are numbers (NaN orders nothing: then the serial stable sort, whose order the fit's error names).
std::vector<std::size_t> CanonicalOrder(
  const std::vector<Eigen::Vector3d>& points, const plantmorph::ParallelFor& parallel)
{
  std::vector<std::size_t> order(points.size());
  const auto before = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    return p.x() != q.x() ? p.x() < q.x() : p.y() != q.y() ? p.y() < q.y() : p.z() < q.z();
  };
  if (!std::all_of(points.begin(), points.end(), [](const Eigen::Vector3d& p) { return !p.hasNaN(); }))
  {
    std::iota(order.begin(), order.end(), std::size_t{ 0 });
    std::stable_sort(
      order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return before(points[a], points[b]); });
    return order;
  }
  std::vector<std::pair<Eigen::Vector3d, std::size_t>> keyed(points.size());
  plantmorph::ForEachIndex(parallel, points.size(), [&](std::size_t i) { keyed[i] = { points[i], i }; });
  plantmorph::SortInParallel(parallel, keyed, [](const auto& a, const auto& b) {
    const Eigen::Vector3d &p = a.first, &q = b.first;
    return p.x() != q.x() ? p.x() < q.x()
      : p.y() != q.y()    ? p.y() < q.y()
      : p.z() != q.z()    ? p.z() < q.z()
                          : a.second < b.second;
  });
  plantmorph::ForEachIndex(parallel, points.size(), [&](std::size_t i) { order[i] = keyed[i].second; });
  return order;
}

/// The points of the leaves a rank owns, and their wood distances (LeafInput::woodDistance; a leaf with none known
/// has an empty vector).
struct OwnedLeaves
{
  std::vector<std::vector<Eigen::Vector3d>> points;
  std::vector<std::vector<double>> woodDistance;
  std::vector<std::vector<int>> scanner; ///< per point, its ScanPosition (-1 unknown)
};

/// One leaf fitted on this rank: a leaf of the exchange (`group`, an index into the owned leaves) or, without
/// LeafIdArray, one of the separate blades its points form (`piece`).
struct Piece
{
  std::size_t group = 0;
  int piece = 0;
  std::size_t points = 0;
  plantmorph::LeafFitResult fit;
  std::vector<std::string> warnings;
};

/// What this rank fitted: the pieces, and per owned leaf FitDistance, Inlier and piece of every point, in the order
/// the points came (OwnerExchange::ReturnValues, width ScanValues).
struct OwnedFits
{
  std::vector<Piece> pieces;
  std::vector<std::vector<double>> values;
  std::vector<plantmorph::LeafSeparation> separations; // per owned leaf when separating
};

/// Per owned leaf, FitDistance, Inlier, Region and piece of every point, in the order its points came: the fits'
/// points are in canonical order (`orders`), cut into pieces (`pieceOf`), a leaf's first piece at `firstPiece`.
void FillScanValues(const std::vector<std::vector<std::size_t>>& orders, const std::vector<std::vector<int>>& pieceOf,
  const std::vector<std::size_t>& firstPiece, OwnedFits& owned)
{
  std::vector<std::size_t> next(owned.pieces.size(), 0);
  owned.values.assign(orders.size(), {});
  for (std::size_t k = 0; k < orders.size(); ++k)
  {
    owned.values[k].assign(ScanValues * orders[k].size(), 0.0);
    for (std::size_t j = 0; j < orders[k].size(); ++j)
    {
      const std::size_t q = firstPiece[k] + static_cast<std::size_t>(pieceOf[k][j]);
      const plantmorph::LeafFitResult& fit = owned.pieces[q].fit;
      const std::size_t at = next[q]++;
      double* v = &owned.values[k][ScanValues * orders[k][j]];
      v[0] = fit.error.empty() ? fit.fitDistance[at] : std::numeric_limits<double>::quiet_NaN();
      v[1] = fit.error.empty() ? fit.inlier[at] : 0.0;
      v[2] = fit.error.empty() && fit.petiole[at] ? plantmorph::RegionPetiole : plantmorph::RegionBlade;
      v[3] = pieceOf[k][j];
    }
  }
}

/// Fits the leaves this rank owns (threaded over leaves), each on its points in canonical order; with `separate`
/// (no LeafIdArray) each leaf's points are first cut into their separate blades, each fitted as a leaf. Leaves with
/// wood distances are then turned to put their base at the end nearer the wood (plantmorph::OrientByWood), with the
/// axis shape of every rank's leaves (collective: every rank calls it).
OwnedFits FitOwned(vtkMultiProcessController* controller, const OwnedLeaves& own,
  const plantmorph::LeafFitParameters& options, bool separate)
{
  const std::vector<std::vector<Eigen::Vector3d>>& leaves = own.points;
  OwnedFits owned;
  std::vector<std::vector<std::size_t>> orders(leaves.size());
  std::vector<std::vector<int>> pieceOf(leaves.size());
  std::vector<std::vector<Eigen::Vector3d>> sorted;
  std::vector<std::vector<double>> sortedWood;
  const plantmorph::ParallelFor smp = plantmorph::SMPFor(1); // one leaf per task: leaves differ in size
  for (std::size_t k = 0; k < leaves.size(); ++k)
  {
    orders[k] = CanonicalOrder(leaves[k], smp);
    std::vector<Eigen::Vector3d> points(orders[k].size());
    plantmorph::ForEachIndex(smp, points.size(), [&](std::size_t j) { points[j] = leaves[k][orders[k][j]]; });
    owned.separations.push_back(separate ? plantmorph::SeparateLeaves(points, smp) : plantmorph::LeafSeparation());
    plantmorph::LeafSeparation& cut = owned.separations.back();
    if (!separate)
      cut.leafOf.assign(points.size(), 0);
    const std::size_t first = sorted.size();
    sorted.resize(first + std::max(cut.count, 1));
    sortedWood.resize(sorted.size());
    if (!own.woodDistance[k].empty())
      for (std::size_t j = 0; j < orders[k].size(); ++j)
        sortedWood[first + static_cast<std::size_t>(cut.leafOf[j])].push_back(own.woodDistance[k][orders[k][j]]);
    for (int p = 0; p < std::max(cut.count, 1); ++p)
      owned.pieces.push_back({ k, p, 0, {}, {} });
    if (cut.count <= 1)           // one blade: its points as they are
      sorted[first].swap(points); // (leaves `points` empty)
    for (std::size_t j = 0; j < points.size(); ++j)
      sorted[first + cut.leafOf[j]].push_back(points[j]);
    pieceOf[k] = cut.leafOf;
  }
  std::vector<plantmorph::LeafFitResult> results = plantmorph::FitLeaves(sorted, options, smp);
  const std::optional<double> shape = plantmorph::PlantAxisShape(
    plantmorph::fittable::ValuesOfAllRanks(controller, plantmorph::AxisShapes(results, sorted, sortedWood)));
  plantmorph::OrientByWood(sorted, sortedWood, options, results, smp, shape);
  std::vector<std::size_t> firstPiece(leaves.size(), 0);
  for (std::size_t q = 0; q < results.size(); ++q)
  {
    Piece& piece = owned.pieces[q];
    if (piece.piece == 0)
      firstPiece[piece.group] = q;
    piece.points = sorted[q].size();
    piece.fit = std::move(results[q]);
    if (piece.fit.error.empty())
      piece.warnings = plantmorph::CheckFittedLeaf(piece.fit, options.resolution);
  }
  FillScanValues(orders, pieceOf, firstPiece, owned);
  return owned;
}

void PrepareOutputs(vtkPolyData* blade, vtkPolyData* outline)
{
  blade->GetPointData()->AddArray(NewArray<vtkDoubleArray>(plantmorph::arrays::LeafUV, 2));
  blade->GetPointData()->SetTCoords(NewArray<vtkFloatArray>(plantmorph::arrays::TCoords, 2));
  blade->GetPointData()->AddArray(NewArray<vtkIntArray>(plantmorph::arrays::Region, 1));
  blade->GetPointData()->SetNormals(NewArray<vtkFloatArray>(plantmorph::arrays::Normals, 3));
  blade->GetPointData()->AddArray(NewArray<vtkTypeInt64Array>(plantmorph::arrays::LeafId, 1));
  blade->GetPointData()->AddArray(NewArray<vtkDoubleArray>("Support", 1));
  blade->GetCellData()->AddArray(NewArray<vtkIntArray>(plantmorph::arrays::Region, 1));
  blade->GetCellData()->AddArray(NewArray<vtkTypeInt64Array>(plantmorph::arrays::LeafId, 1));
  outline->GetPointData()->AddArray(NewArray<vtkDoubleArray>(plantmorph::arrays::LeafUV, 2));
  outline->GetPointData()->AddArray(NewArray<vtkTypeInt64Array>(plantmorph::arrays::LeafId, 1));
  outline->GetCellData()->AddArray(NewArray<vtkIntArray>(plantmorph::arrays::Region, 1));
  outline->GetCellData()->AddArray(NewArray<vtkTypeInt64Array>(plantmorph::arrays::LeafId, 1));
}

/// The leaves of the local piece: scaled points, each point's leaf id (64 bits; 0 without LeafIdArray) and, once
/// the ranks agreed on every id (UnionOfIds), each leaf's point ids keyed by the index of its id.
struct LeafInput
{
  std::vector<Eigen::Vector3d> points;
  std::vector<std::int64_t> ids;
  bool separate = false; ///< no LeafIdArray: the points are cut into their separate blades
  std::vector<std::int64_t> leafIds;
  plantmorph::LocalGroups members;
  double unassignedLeafPoints = 0; ///< points with a negative id that the input's Organ array calls leaf (1)
  /// per point, the input's WoodDistance (PlantSegmentationFilter's) when OrientByWood is on; else NaN
  std::vector<double> woodDistance;
  /// per point, its scanner and range (the input's ScanPosition and Range; empty without them)
  plantmorph::fittable::ScanRanges scan;

  /// The LeafId a fitted piece gets: its blade's number when separating, else its leaf's id.
  std::int64_t OutputId(std::size_t leaf, int piece) const { return this->separate ? piece : this->leafIds[leaf]; }
};

/// Scan: the scaled input points, their data, and the fit's per-point arrays (`values`: FitDistance, Inlier, Region
/// and piece of every point).
void FillScan(vtkPointSet* input, const LeafInput& in, const std::vector<double>& values, vtkPolyData* scan)
{
  const auto n = static_cast<vtkIdType>(in.points.size());
  auto coordinates = NewArray<vtkDoubleArray>("Points", 3);
  auto distance = NewArray<vtkDoubleArray>("FitDistance", 1);
  auto inlier = NewArray<vtkUnsignedCharArray>("Inlier", 1);
  auto region = NewArray<vtkIntArray>(plantmorph::arrays::Region, 1);
  auto leafId = NewArray<vtkTypeInt64Array>(plantmorph::arrays::LeafId, 1);
  coordinates->SetNumberOfTuples(n);
  for (vtkDataArray* array : std::initializer_list<vtkDataArray*>{ distance, inlier, region, leafId })
    array->SetNumberOfTuples(n);
  plantmorph::ForEachIndex(plantmorph::SMPFor(), static_cast<std::size_t>(n), [&](std::size_t j) {
    const auto i = static_cast<vtkIdType>(j);
    std::copy(in.points[j].data(), in.points[j].data() + 3, coordinates->GetPointer(3 * i));
    const double* v = &values[ScanValues * j];
    distance->SetValue(i, v[0]);
    inlier->SetValue(i, v[1] == 1.0 ? 1 : 0);
    region->SetValue(i, v[2] == plantmorph::RegionPetiole ? plantmorph::RegionPetiole : plantmorph::RegionBlade);
    leafId->SetValue(i, in.separate ? static_cast<std::int64_t>(v[3]) : in.ids[j]);
  });
  vtkNew<vtkPoints> scanPoints;
  scanPoints->SetData(coordinates);
  scan->SetPoints(scanPoints);
  scan->SetVerts(plantmorph::VertexCells(n));
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

/// The properties' error (empty when they are fine).
std::string CheckProperties(vtkLeafFitFilter* self)
{
  std::string error = plantmorph::ValidateLeafFitParameters(Options(self));
  const int baseCount = self->GetBasePointElementCount();
  if (baseCount >= 0 && baseCount != 3)
    error = plantmorph::OutOfRange(
      "BasePoint", std::to_string(baseCount) + " numbers", "3 numbers (x, y, z)", "the value given was not set");
  const int apexCount = self->GetApexPointElementCount();
  if (error.empty() && apexCount >= 0 && apexCount != 3)
    error = plantmorph::OutOfRange(
      "ApexPoint", std::to_string(apexCount) + " numbers", "3 numbers (x, y, z)", "the value given was not set");
  const double scale = self->GetScale();
  if (error.empty() && !(std::isfinite(scale) && scale > 0.0))
    error = plantmorph::OutOfRange("Scale", scale, "(0, inf)");
  return error;
}

/// The points on no leaf (a negative id) that are leaf: Organ 1 in the input's point array named Organ (PlantMorph's
/// organ label, PlantSegmentationFilter's output); none without that array (a point on no leaf may be wood).
double CountUnassignedLeafPoints(vtkPointSet* input, const std::vector<std::int64_t>& ids)
{
  vtkDataArray* organ = input->GetPointData()->GetArray(plantmorph::arrays::Organ);
  if (!organ || organ->GetNumberOfComponents() != 1)
    return 0.0;
  double count = 0.0;
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (ids[i] < 0 && organ->GetComponent(static_cast<vtkIdType>(i), 0) == plantmorph::OrganLeaf)
      count += 1.0;
  return count;
}

/// Per point, the input's WoodDistance point array (PlantSegmentationFilter's, scaled as the points), NaN where it
/// has none or OrientByWood is off.
std::vector<double> ReadWoodDistance(vtkLeafFitFilter* self, vtkPointSet* input)
{
  const vtkIdType n = input->GetNumberOfPoints();
  std::vector<double> distance(static_cast<std::size_t>(n), std::numeric_limits<double>::quiet_NaN());
  vtkDataArray* array =
    self->GetOrientByWood() ? input->GetPointData()->GetArray(plantmorph::arrays::WoodDistance) : nullptr;
  if (array && array->GetNumberOfComponents() == 1)
    for (vtkIdType i = 0; i < n; ++i)
      distance[static_cast<std::size_t>(i)] = self->GetScale() * array->GetComponent(i, 0);
  return distance;
}

/// The local piece's points (scaled) and each point's leaf id; an error message for bad properties, a missing
/// LeafIdArray or ids that are not integers (nothing is checked on an empty piece).
std::string ReadLeaves(vtkLeafFitFilter* self, vtkPointSet* input, LeafInput& in)
{
  const vtkIdType n = input->GetNumberOfPoints();
  const std::string leafIdArray = self->GetLeafIdArray();
  in.separate = leafIdArray.empty() || leafIdArray == "None"; // "None": the XML menu's entry for no array
  if (n == 0)
    return {}; // an empty piece (MPI ranks without leaves): nothing to check
  std::string error = CheckProperties(self);
  vtkDataArray* ids = nullptr;
  if (error.empty() && !in.separate)
  {
    ids = input->GetPointData()->GetArray(leafIdArray.c_str());
    if (!ids || ids->GetNumberOfComponents() != 1)
      error = "LeafIdArray: the input has no one-component point array named '" + leafIdArray + "'";
  }
  if (error.empty() && ids)
    error = plantmorph::fittable::ReadLeafIds(ids, leafIdArray, in.ids);
  if (!error.empty())
  {
    in.ids.clear();
    return error;
  }
  if (!ids)
    in.ids.assign(static_cast<std::size_t>(n), 0);
  in.unassignedLeafPoints = CountUnassignedLeafPoints(input, in.ids);
  in.woodDistance = ReadWoodDistance(self, input);
  in.scan = plantmorph::fittable::ReadScanRanges(input, self->GetScale());
  in.points.resize(n);
  const double scale = self->GetScale();
  vtkDataArray* coordinates = input->GetPoints()->GetData();
  plantmorph::ForEachIndex(plantmorph::SMPFor(), static_cast<std::size_t>(n), [&](std::size_t i) {
    double p[3];
    coordinates->GetTuple(static_cast<vtkIdType>(i), p); // the thread-safe form (into the caller's numbers)
    in.points[i] = scale * Eigen::Vector3d(p[0], p[1], p[2]);
  });
  return {};
}

/// Collective: the ranks agree on every leaf id; each local leaf's points are keyed by the index of its id. A
/// negative id is a point on no leaf (PlantSegmentationFilter's LeafId -1: wood, petioles, leaf points it could give
/// to no leaf): it is fitted with no leaf and keeps its id on the Scan port.
void IndexLeaves(vtkMultiProcessController* controller, LeafInput& in)
{
  std::vector<std::int64_t> distinct;
  std::copy_if(in.ids.begin(), in.ids.end(), std::back_inserter(distinct), [](std::int64_t id) { return id >= 0; });
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  in.leafIds = plantmorph::fittable::UnionOfIds(controller, distinct);
  for (std::size_t i = 0; i < in.ids.size(); ++i)
  {
    if (in.ids[i] < 0)
      continue;
    const auto at = std::lower_bound(in.leafIds.begin(), in.leafIds.end(), in.ids[i]) - in.leafIds.begin();
    in.members[static_cast<vtkTypeInt64>(at)].push_back(static_cast<vtkIdType>(i));
  }
}

/// Collective: the points of every leaf this rank owns (Owned() order), each the concatenation over ranks, in rank
/// order, of that rank's points of the leaf in its input order, with their wood distances.
OwnedLeaves SendPoints(const plantmorph::OwnerExchange& exchange, const LeafInput& in)
{
  constexpr int Width = 5; // x, y, z, wood distance, scanner
  std::vector<double> flat(Width * in.points.size());
  for (std::size_t i = 0; i < in.points.size(); ++i)
  {
    for (int c = 0; c < 3; ++c)
      flat[Width * i + c] = in.points[i][c];
    flat[Width * i + 3] = in.woodDistance[i];
    flat[Width * i + 4] = in.scan.scanner.empty() ? -1.0 : in.scan.scanner[i];
  }
  OwnedLeaves leaves;
  for (const std::vector<double>& values : exchange.SendValues(in.members, flat, Width))
  {
    const std::size_t n = values.size() / Width;
    leaves.points.emplace_back(n);
    leaves.woodDistance.emplace_back(n);
    leaves.scanner.emplace_back(n);
    bool known = false;
    for (std::size_t j = 0; j < n; ++j)
    {
      leaves.points.back()[j] = { values[Width * j], values[Width * j + 1], values[Width * j + 2] };
      leaves.woodDistance.back()[j] = values[Width * j + 3];
      leaves.scanner.back()[j] = static_cast<int>(values[Width * j + 4]);
      known = known || std::isfinite(values[Width * j + 3]);
    }
    if (!known)
      leaves.woodDistance.back().clear();
  }
  return leaves;
}
} // namespace

namespace
{
/// Each leaf is fitted whole on one owner rank (common/vtk/PlantMorphOwnerExchange.h); the Scan output stays where
/// its points are.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::LeafPerRank;

/// The Traits rows of this rank's pieces; their failures and warnings said here (WarnHere). `errors` gets the
/// failures, one line each ("leaf <id> (<n> points): <error>").
std::vector<plantmorph::fittable::Row> PieceRows(const LeafInput& in, const std::vector<std::size_t>& owned,
  const OwnedFits& fits, const plantmorph::Run& run, std::string& errors)
{
  std::vector<plantmorph::fittable::Row> rows;
  const std::size_t width = plantmorph::TraitNames().size();
  for (const Piece& piece : fits.pieces)
  {
    plantmorph::fittable::Row row;
    row.leafId = in.OutputId(owned[piece.group], piece.piece);
    const std::string leaf = "leaf " + std::to_string(row.leafId) + " (" + std::to_string(piece.points) + " points)";
    if (!piece.fit.error.empty())
    {
      row.status = static_cast<int>(plantmorph::LeafStatus::Failed);
      row.values.assign(width, std::numeric_limits<double>::quiet_NaN());
      row.message = piece.fit.error;
      errors += (errors.empty() ? "" : "\n") + leaf + ": " + piece.fit.error;
    }
    else
    {
      row.values = plantmorph::TraitValues(piece.fit.traits);
      for (const std::string& warning : piece.warnings)
        row.message += (row.message.empty() ? "" : "; ") + warning;
      row.status =
        static_cast<int>(row.message.empty() ? plantmorph::LeafStatus::Fitted : plantmorph::LeafStatus::Warning);
      if (!row.message.empty())
        run.WarnHere(leaf + ": " + row.message);
    }
    rows.push_back(row);
  }
  return rows;
}

/// Collective: each fitted leaf's HiddenMargin (LeafFitScannerView.h), from the scanners that gave its points; what
/// could not be done said as a warning on rank 0 (it is the same on every rank).
void JudgeViews(const plantmorph::Run& run, vtkMultiProcessController* controller, LeafInput& in,
  const std::vector<std::size_t>& owned, const OwnedLeaves& leaves, const Eigen::Vector3d& up, OwnedFits& fits)
{
  std::vector<plantmorph::fittable::LeafView> views;
  for (Piece& piece : fits.pieces)
  {
    plantmorph::fittable::LeafView view;
    view.fit = &piece.fit;
    view.leaf = in.separate ? -1 : static_cast<std::int64_t>(owned[piece.group]);
    for (const int s : leaves.scanner[piece.group])
      if (s >= 0)
      {
        if (view.pointsFrom.size() <= static_cast<std::size_t>(s))
          view.pointsFrom.resize(static_cast<std::size_t>(s) + 1, 0.0);
        view.pointsFrom[static_cast<std::size_t>(s)] += 1.0;
      }
    views.push_back(std::move(view));
  }
  if (!in.separate && !in.scan.scanner.empty()) // without LeafIdArray the blades are not known before the fit
  {
    in.scan.leaf.assign(in.points.size(), -1);
    for (const auto& [leaf, members] : in.members)
      for (const vtkIdType i : members)
        in.scan.leaf[static_cast<std::size_t>(i)] = leaf;
  }
  const std::string warning = plantmorph::fittable::SetHiddenMargins(controller, in.points, in.scan, up, views);
  if (!warning.empty() && run.Rank() == 0)
    run.WarnHere(warning);
}

/// Says, as a warning, how the points were cut into separate blades (without LeafIdArray).
void WarnSeparation(const LeafInput& in, const OwnedFits& fits, const plantmorph::Run& run)
{
  for (const plantmorph::LeafSeparation& cut : fits.separations)
    if (in.separate && cut.count > 1)
    {
      std::ostringstream message;
      message << "LeafIdArray is empty and the points form " << cut.count << " separate blades (points closer than "
              << cut.radius << " joined): each is fitted as a leaf, LeafId 0 to " << cut.count - 1
              << "; name a LeafIdArray to say which points are one leaf";
      run.WarnHere(message.str());
    }
}

/// Blade and Outline of the leaves this rank fitted; the Traits and Plant tables from every rank's rows, gathered on
/// rank 0 in LeafId order (collective).
void WriteFits(const LeafInput& in, const std::vector<std::size_t>& owned, const OwnedFits& fits,
  const std::vector<plantmorph::fittable::Row>& rows, const std::string& lengthUnit, double scale,
  const plantmorph::Run& run)
{
  vtkPolyData* blade = run.Output<vtkPolyData>(0);
  vtkPolyData* outline = run.Output<vtkPolyData>(1);
  PrepareOutputs(blade, outline);
  vtkNew<vtkPoints> points, outlinePoints;
  points->SetDataTypeToDouble();
  outlinePoints->SetDataTypeToDouble();
  vtkNew<vtkCellArray> triangles, lines;
  for (const Piece& piece : fits.pieces)
    if (piece.fit.error.empty())
      AppendLeaf(piece.fit, in.OutputId(owned[piece.group], piece.piece), points, triangles, blade, outlinePoints,
        lines, outline);
  blade->SetPoints(points);
  blade->SetPolys(triangles);
  outline->SetPoints(outlinePoints);
  outline->SetLines(lines);
  plantmorph::FieldRecord record;
  record.Add("Scale", scale);
  record.Add("LengthUnit", lengthUnit);
  record.WriteTo(blade);
  const std::vector<plantmorph::fittable::Row> all = plantmorph::fittable::GatherRows(run.Controller(), rows);
  const double unassigned = plantmorph::SumOverRanks(run.Controller(), in.unassignedLeafPoints);
  if (run.Rank() != 0)
    return;
  plantmorph::fittable::FillTraitsTable(all, lengthUnit, run.Output<vtkTable>(2));
  plantmorph::fittable::FillPlantTable(all, lengthUnit, unassigned, run.Output<vtkTable>(4));
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
  // The local piece's leaves; then (collective) every leaf's id, each leaf's owner (PlantMorphOwnerExchange.h), and the
  // points of the leaves this rank owns. Every rank takes part even when its piece is empty or wrong; the ranks stop
  // together, each saying its own error.
  vtkMultiProcessController* controller = run.Controller();
  LeafInput in;
  const std::string error = ReadLeaves(this, input, in);
  IndexLeaves(controller, in);
  const plantmorph::OwnerExchange exchange(controller, in.members);
  run.StopIfAnyRankFailed(exchange.AnyRank(!error.empty()), error);
  if (exchange.Ids().empty()) // no points on any rank (every rank finds it alike): empty outputs
    run.Fail(exchange.AnyRank(!in.ids.empty())
        ? "LeafIdArray: no point has a LeafId of 0 or more (a negative LeafId is a point on no leaf)"
        : "Input: the point cloud has no points (LeafFitFilter fits the points of one or more scanned leaves)");
  const std::vector<std::size_t> owned = exchange.Owned();
  const OwnedLeaves leaves = SendPoints(exchange, in);
  OwnedFits fits = FitOwned(controller, leaves, Options(this), in.separate);
  JudgeViews(run, controller, in, owned, leaves, Options(this).up, fits);
  WarnSeparation(in, fits, run);
  std::string errors;
  const std::vector<plantmorph::fittable::Row> rows = PieceRows(in, owned, fits, run, errors);
  const bool fittedHere =
    std::any_of(fits.pieces.begin(), fits.pieces.end(), [](const Piece& piece) { return piece.fit.error.empty(); });
  // No leaf fitted anywhere: an error (each rank says its leaves'); else the failed leaves get their rows.
  run.StopIfAnyRankFailed(!exchange.AnyRank(fittedHere), errors);
  if (!errors.empty())
    run.WarnHere("not fitted (the other leaves are; their Traits rows have Status 2 and the reason):\n" + errors);
  const std::string unit = plantmorph::ScaledUnit(this->InputUnit, this->Scale);
  WriteFits(in, owned, fits, rows, unit, this->Scale, run);
  // Scan: stays where its points are; the owners send each point's FitDistance, Inlier, Region and blade back.
  const std::vector<double> pointValues =
    exchange.ReturnValues(in.members, static_cast<vtkIdType>(in.points.size()), fits.values, ScanValues);
  if (!in.points.empty())
    FillScan(input, in, pointValues, run.Output<vtkPolyData>(3));
}

void vtkLeafFitFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scale: " << this->Scale << "\n"
     << indent << "LeafIdArray: " << this->LeafIdArray << "\n"
     << indent << "InputUnit: " << this->InputUnit << "\n"
     << indent << "UpAxis: " << this->UpAxis << "\n"
     << indent << "UseBasePoint: " << this->UseBasePoint << "\n"
     << indent << "UseApexPoint: " << this->UseApexPoint << "\n"
     << indent << "OrientByWood: " << this->OrientByWood << "\n"
     << indent << "SurfaceSmoothing: " << this->SurfaceSmoothing << "\n"
     << indent << "OutlineSmoothing: " << this->OutlineSmoothing << "\n"
     << indent << "OutlineControlPoints: " << this->OutlineControlPoints << "\n"
     << indent << "OutlierSigma: " << this->OutlierSigma << "\n"
     << indent << "Resolution: " << this->Resolution << "\n"
     << indent << "ModelControlPoints: " << this->ModelControlPoints << "\n";
}
