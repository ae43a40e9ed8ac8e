// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkVenationFilter.h"
#include "PlantMorphAlgorithmHooks.h"

#include "PlantMorphLayer.h"
#include "PlantMorphLeafExchange.h"
#include "PlantMorphWholeInput.h"
#include "VeinNetworkMeasures.h"
#include "VenationGrowth.h"

#include <plantmorph/DataContract.h>
#include <plantmorph/RangeError.h>

#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkVenationFilter);

namespace
{
/// Under MPI each leaf grows whole on one rank (PlantMorphLeafExchange.h), one leaf on rank 0: the growth needs
/// the whole blade.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::LeafPerRank;

/// What the veins grew with: the pattern, the preset and one value per parameter as
/// PlantMorph.Venation.<property> (what a preset chose, visible in the Information panel).
void AddGrowth(
  plantmorph::FieldRecord& record, const plantmorph::VenationParameters& p, plantmorph::VenationPreset preset)
{
  record.Add("VenationPattern", plantmorph::VenationPatternName(p.pattern));
  record.Add("VenationPreset", plantmorph::VenationPresetName(preset));
  for (const auto& [name, value] : plantmorph::VenationParameterValues(p))
  {
    record.Add(std::string("Venation.") + name, value);
  }
}

/// The input blade as flat arrays: points, LeafUV, triangles.
struct InputBlade
{
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> uv;
  std::vector<std::array<int, 3>> triangles;
};

/// Reads the blade's points, LeafUV and triangles; a message naming what is wrong when it cannot be used.
std::string ReadBlade(vtkPolyData* input, InputBlade& blade)
{
  vtkDataArray* uvArray = input->GetPointData()->GetArray(plantmorph::arrays::LeafUV);
  if (!uvArray || uvArray->GetNumberOfComponents() != 2)
  {
    return "Input: the blade needs the point array LeafUV with 2 components (LeafOutlineSource's blades have it)";
  }
  const vtkIdType n = input->GetNumberOfPoints();
  blade.points.resize(static_cast<std::size_t>(n));
  blade.uv.resize(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    input->GetPoint(i, blade.points[i].data());
    blade.uv[i] = Eigen::Vector2d(uvArray->GetComponent(i, 0), uvArray->GetComponent(i, 1));
  }
  vtkCellArray* polys = input->GetPolys();
  vtkNew<vtkIdList> ids;
  vtkIdType cell = 0;
  for (polys->InitTraversal(); polys->GetNextCell(ids); ++cell)
  {
    if (ids->GetNumberOfIds() != 3)
    {
      std::ostringstream message;
      message << "Input: polygon " << cell << " has " << ids->GetNumberOfIds()
              << " points; the blade must be triangles (apply Triangulate first)";
      return message.str();
    }
    blade.triangles.push_back(
      { static_cast<int>(ids->GetId(0)), static_cast<int>(ids->GetId(1)), static_cast<int>(ids->GetId(2)) });
  }
  if (input->GetNumberOfStrips() > 0)
  {
    return "Input: the blade has triangle strips; apply Triangulate first";
  }
  if (blade.triangles.empty())
  {
    return "Input: the blade has no triangles";
  }
  return {};
}

/// The blade's texture coordinates (2 components) as a per-point vector, or empty.
std::vector<Eigen::Vector2d> TCoordsOf(vtkPolyData* input)
{
  std::vector<Eigen::Vector2d> result;
  vtkDataArray* tcoords = input->GetPointData()->GetTCoords();
  if (tcoords && tcoords->GetNumberOfComponents() == 2)
  {
    result.resize(static_cast<std::size_t>(tcoords->GetNumberOfTuples()));
    for (vtkIdType i = 0; i < tcoords->GetNumberOfTuples(); ++i)
      result[i] = Eigen::Vector2d(tcoords->GetComponent(i, 0), tcoords->GetComponent(i, 1));
  }
  return result;
}

/// A new double array of `count` tuples of `components`, named `name`.
vtkSmartPointer<vtkDoubleArray> NewDoubleArray(const char* name, int components, std::size_t count)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(static_cast<vtkIdType>(count));
  return array;
}

/// Port 0's points: the network's points mapped onto the surface, with VeinWidth (active scalars), Region, LeafUV
/// and the blade's TCoords interpolated; "" or an internal error.
std::string WriteVeinPoints(
  vtkPolyData* input, const InputBlade& blade, const plantmorph::VenationResult& result, vtkPolyData* veins)
{
  const std::size_t count = result.nodes.size();
  vtkNew<vtkPoints> veinPoints;
  veinPoints->SetDataType(input->GetPoints()->GetDataType());
  veinPoints->SetNumberOfPoints(static_cast<vtkIdType>(count));
  auto width = NewDoubleArray(plantmorph::arrays::VeinWidth, 1, count);
  auto veinUV = NewDoubleArray(plantmorph::arrays::LeafUV, 2, count);
  vtkNew<vtkIntArray> pointRegion;
  pointRegion->SetName(plantmorph::arrays::Region);
  pointRegion->SetNumberOfTuples(static_cast<vtkIdType>(count));
  const std::vector<Eigen::Vector2d> tcoords = TCoordsOf(input);
  const bool withTCoords = !tcoords.empty() && count > 0;
  vtkNew<vtkFloatArray> veinTCoords;
  veinTCoords->SetNumberOfComponents(2);
  veinTCoords->SetNumberOfTuples(withTCoords ? static_cast<vtkIdType>(count) : 0);
  for (std::size_t i = 0; i < count; ++i)
  {
    const plantmorph::BladeLocation& at = result.location[i];
    if (at.triangle < 0)
      return "internal: a vein point fell outside the blade";
    const auto id = static_cast<vtkIdType>(i);
    veinPoints->SetPoint(id, plantmorph::InterpolateAt(blade.triangles, blade.points, at).data());
    veinUV->SetTuple(id, plantmorph::InterpolateAt(blade.triangles, blade.uv, at).data());
    width->SetValue(id, result.width[i]);
    pointRegion->SetValue(id, std::min<int>(result.order[i], plantmorph::RegionTertiaryVein));
    if (withTCoords)
      veinTCoords->SetTuple(id, plantmorph::InterpolateAt(blade.triangles, tcoords, at).data());
  }
  veins->SetPoints(veinPoints);
  veins->GetPointData()->AddArray(width);
  veins->GetPointData()->SetActiveScalars(plantmorph::arrays::VeinWidth);
  veins->GetPointData()->AddArray(pointRegion);
  veins->GetPointData()->AddArray(veinUV);
  if (withTCoords)
  {
    vtkDataArray* given = input->GetPointData()->GetTCoords();
    veinTCoords->SetName(given->GetName() ? given->GetName() : plantmorph::arrays::TCoords);
    veins->GetPointData()->SetTCoords(veinTCoords);
  }
  return {};
}

/// Port 0's cells: one polyline per vein, with VeinOrder and Region.
void WriteVeinLines(const plantmorph::VenationResult& result, vtkPolyData* veins)
{
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> veinOrder, cellRegion;
  veinOrder->SetName(plantmorph::arrays::VeinOrder);
  cellRegion->SetName(plantmorph::arrays::Region);
  for (const auto& line : result.veins)
  {
    lines->InsertNextCell(static_cast<vtkIdType>(line.nodes.size()));
    for (int id : line.nodes)
      lines->InsertCellPoint(id);
    veinOrder->InsertNextValue(line.order);
    cellRegion->InsertNextValue(std::min<int>(line.order, plantmorph::RegionTertiaryVein));
  }
  veins->SetLines(lines);
  veins->GetCellData()->AddArray(veinOrder);
  veins->GetCellData()->AddArray(cellRegion);
}

/// Port 1: the blade passed through, its points raised along the normals over the veins when depth is not 0.
void WriteBlade(vtkPolyData* input, const InputBlade& blade, const plantmorph::VenationBlade& plane,
  const plantmorph::VenationResult& result, double depth, vtkPolyData* bladeOut)
{
  bladeOut->ShallowCopy(input);
  if (depth != 0.0)
  {
    std::vector<Eigen::Vector3d> normals;
    vtkDataArray* given = input->GetPointData()->GetNormals();
    if (given && given->GetNumberOfComponents() == 3)
    {
      normals.resize(blade.points.size());
      for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
        given->GetTuple(i, normals[i].data());
    }
    const std::vector<Eigen::Vector3d> raised = plantmorph::RaisedAlongNormals(
      blade.points, blade.triangles, std::move(normals), plantmorph::VeinReliefHeights(plane, result, depth));
    vtkNew<vtkPoints> points;
    points->SetDataType(input->GetPoints()->GetDataType());
    points->SetNumberOfPoints(input->GetNumberOfPoints());
    for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
      points->SetPoint(i, raised[i].data());
    bladeOut->SetPoints(points);
  }
  plantmorph::FieldRecord record;
  record.Add("EmbossDepth", depth);
  record.WriteTo(bladeOut);
}

/// Field data on port 0: the network's measures and what the veins grew with (parameters, seed, preset, plane).
/// The counts are the Statistics port's (one set of numbers); AreoleAreaStd is the population standard deviation.
void WriteVeinFieldData(vtkPolyData* veins, const plantmorph::VenationResult& result,
  const plantmorph::VeinNetworkMeasures& m, const plantmorph::VenationParameters& p, plantmorph::VenationPreset preset,
  int seed, bool flat)
{
  plantmorph::FieldRecord record;
  record.AddTuple("VeinLength", { "Primary", "Secondary", "Tertiary", "Quaternary", "Veinlet" },
    { m.length[1], m.length[2], m.length[3], m.length[4], m.length[5] });
  record.Add("VeinDensity", m.vla);
  record.Add("BladeArea", m.bladeArea);
  record.Add("AreoleCount", static_cast<double>(m.areoles));
  record.Add("AreoleAreaMean", m.areoleMean);
  record.Add("AreoleAreaStd", m.areoleCV * m.areoleMean);
  record.Add("BranchPoints", static_cast<double>(m.branchPoints));
  record.Add("FreeEnds", static_cast<double>(m.freeEnds));
  record.Add("VeinSegments", static_cast<double>(result.statistics.segments));
  record.Add("Seed", static_cast<double>(seed));
  record.Add("LeafLength", result.leafLength);
  AddGrowth(record, p, preset);
  record.Add("VenationPlane", flat ? "BladePlane" : "ScaledLeafUV");
  record.WriteTo(veins);
}

/// Port 2, Statistics: one row, the measures of the network (VeinNetworkMeasures.h), lengths and areas in the
/// blade's units (VLA in units^-1, i.e. mm/mm^2 for a blade in mm).
void WriteStatistics(const plantmorph::VeinNetworkMeasures& m, vtkTable* statistics)
{
  const auto addValue = [&](const char* name, double value) {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name);
    column->InsertNextValue(value);
    statistics->AddColumn(column);
  };
  const auto addCount = [&](const char* name, std::size_t value) {
    vtkNew<vtkIdTypeArray> column;
    column->SetName(name);
    column->InsertNextValue(static_cast<vtkIdType>(value));
    statistics->AddColumn(column);
  };
  addValue("VLA", m.vla);
  addValue("TotalLength", m.totalLength);
  addValue("BladeArea", m.bladeArea);
  addCount("AreoleCount", m.areoles);
  addValue("AreoleAreaMean", m.areoleMean);
  addValue("AreoleAreaMedian", m.areoleMedian);
  addValue("AreoleAreaCV", m.areoleCV);
  addValue("Loopiness", m.loopiness);
  addCount("BranchPoints", m.branchPoints);
  addValue("BranchPointsPerArea", m.branchPointsPerArea);
  addCount("FreeEnds", m.freeEnds);
  addValue("FreeEndsPerArea", m.freeEndsPerArea);
  const char* const orders[] = { "Primary", "Secondary", "Tertiary", "Quaternary", "Veinlet" };
  for (int o = 1; o <= 5; ++o)
    addValue(("Length" + std::string(orders[o - 1])).c_str(), m.length[o]);
  for (int o = 1; o <= 5; ++o)
    addValue(("MeanWidth" + std::string(orders[o - 1])).c_str(), m.meanWidth[o]);
}

/// Port 3, Areole histogram: one row per bin, its lower and upper area edges and how many areoles it holds.
void WriteHistogram(const plantmorph::AreoleHistogram& h, vtkTable* histogram)
{
  vtkNew<vtkDoubleArray> lower, upper;
  lower->SetName("BinLower");
  upper->SetName("BinUpper");
  vtkNew<vtkIdTypeArray> count;
  count->SetName("Count");
  for (std::size_t b = 0; b < h.count.size(); ++b)
  {
    lower->InsertNextValue(h.lower[b]);
    upper->InsertNextValue(h.upper[b]);
    count->InsertNextValue(static_cast<vtkIdType>(h.count[b]));
  }
  histogram->AddColumn(lower);
  histogram->AddColumn(upper);
  histogram->AddColumn(count);
}
} // namespace

//------------------------------------------------------------------------------
vtkVenationFilter::vtkVenationFilter()
{
  this->SetNumberOfOutputPorts(4);
}

//------------------------------------------------------------------------------
int vtkVenationFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
const char* vtkVenationFilter::GetPresetValues()
{
  std::ostringstream text;
  if (this->Preset <= 0 || this->Preset >= plantmorph::VenationPresetCount)
  {
    text << (this->Preset == 0 ? "Custom: the properties below are used as set."
                               : "Preset is out of range: no veins grow.");
  }
  else
  {
    text << plantmorph::DescribeVenationPreset(static_cast<plantmorph::VenationPreset>(this->Preset));
  }
  this->PresetValues = text.str();
  return this->PresetValues.c_str();
}

//------------------------------------------------------------------------------
void vtkVenationFilter::WarnAboutPresetOverrides()
{
  if (this->Preset == 0)
  {
    return;
  }
  vtkNew<vtkVenationFilter> defaults;
  plantmorph::PresetOverrides overrides("Preset");
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, Pattern);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, PrimaryCount);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, PrimarySpread);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ParallelVeins);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ParallelSpread);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, SecondarySpacing);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, DivergenceAngle);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, DivergenceAngleApex);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, SecondaryCurvatureBase);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, SecondaryCurvatureApex);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ForkFraction);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, BranchCurvature);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, Tertiary);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, AreoleSize);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, AreoleGradient);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, MinJunctionAngle);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, JunctionAngleDeviation);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, Veinlets);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, VeinletLength);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, PalmateVeins);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, PalmateEnds);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ForkLevels);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, PalmateSecondaries);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, SubLobeVeins);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, FlankSecondaries);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ForkSize);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, KillDistance);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, AttractionDistance);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, SourceDensity);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, MurrayExponent);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, GrowthStart);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ClosedVenation);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, MarginalGrowth);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, PrimaryWidth);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, PrimaryTaper);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, SecondaryWidthRatio);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, TertiaryWidthRatio);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, VeinletWidthRatio);
  overrides.Warn(this);
}

//------------------------------------------------------------------------------
int vtkVenationFilter::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port < 2 ? "vtkPolyData" : "vtkTable");
  return 1;
}

//------------------------------------------------------------------------------
std::string vtkVenationFilter::ValidateSettings()
{
  if (this->Preset < 0 || this->Preset >= plantmorph::VenationPresetCount)
  {
    return plantmorph::OutOfRange(
      "Preset", this->Preset, "[0, " + std::to_string(plantmorph::VenationPresetCount - 1) + "]");
  }
  if (!std::isfinite(this->EmbossDepth) || std::abs(this->EmbossDepth) > 1e3)
  {
    return plantmorph::OutOfRange("EmbossDepth", this->EmbossDepth, "[-1e3, 1e3]");
  }
  if (this->MaxSegments < 100 || this->MaxSegments > 100000000)
  {
    return plantmorph::OutOfRange("MaxSegments", this->MaxSegments, "[100, 1e8]");
  }
  if (this->AreoleHistogramBins < 1 || this->AreoleHistogramBins > 10000)
  {
    return plantmorph::OutOfRange("AreoleHistogramBins", this->AreoleHistogramBins, "[1, 10000]");
  }
  return {};
}

//------------------------------------------------------------------------------
void vtkVenationFilter::ReadCustomParameters(plantmorph::VenationParameters& p)
{
  p.pattern = static_cast<plantmorph::VenationPattern>(this->Pattern);
  p.primaries = this->PrimaryCount;
  p.primarySpread = this->PrimarySpread;
  p.parallelVeins = this->ParallelVeins;
  p.parallelSpread = this->ParallelSpread;
  p.secondarySpacing = this->SecondarySpacing;
  p.divergenceAngle = this->DivergenceAngle;
  p.divergenceAngleApex = this->DivergenceAngleApex;
  p.curvatureBase = this->SecondaryCurvatureBase;
  p.curvatureApex = this->SecondaryCurvatureApex;
  p.forkFraction = this->ForkFraction;
  p.branchCurvature = this->BranchCurvature;
  p.tertiary = this->Tertiary;
  p.areoleSize = this->AreoleSize;
  p.areoleGradient = this->AreoleGradient;
  p.minJunctionAngle = this->MinJunctionAngle;
  p.junctionAngleDeviation = this->JunctionAngleDeviation;
  p.veinlets = this->Veinlets;
  p.veinletLength = this->VeinletLength;
  p.palmateVeins = this->PalmateVeins;
  p.palmateFan = this->PalmateEnds != 0;
  p.forkLevels = this->ForkLevels;
  p.palmateSecondaries = static_cast<plantmorph::PalmateSecondaries>(this->PalmateSecondaries);
  p.subLobeVeins = this->SubLobeVeins != 0;
  p.flankSecondaries = this->FlankSecondaries != 0;
  p.forkSize = this->ForkSize;
  p.killDistance = this->KillDistance;
  p.attractionDistance = this->AttractionDistance;
  p.sourceDensity = this->SourceDensity;
  p.murrayExponent = this->MurrayExponent;
  p.growthStart = this->GrowthStart;
  p.closedVenation = this->ClosedVenation;
  p.marginalGrowth = this->MarginalGrowth;
  p.primaryWidth = this->PrimaryWidth;
  p.primaryTaper = this->PrimaryTaper;
  p.secondaryWidthRatio = this->SecondaryWidthRatio;
  p.tertiaryWidthRatio = this->TertiaryWidthRatio;
  p.veinletWidthRatio = this->VeinletWidthRatio;
}

//------------------------------------------------------------------------------
std::string vtkVenationFilter::MakeParameters(plantmorph::VenationParameters& p)
{
  if (std::string error = this->ValidateSettings(); !error.empty())
  {
    return error;
  }
  const auto preset = static_cast<plantmorph::VenationPreset>(this->Preset);
  this->WarnAboutPresetOverrides();
  p = plantmorph::MakeVenationPreset(preset);
  if (preset == plantmorph::VenationPreset::Custom)
  {
    this->ReadCustomParameters(p);
  }
  p.seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(this->Seed));
  p.maxSegments = static_cast<std::size_t>(this->MaxSegments);
  return {};
}

namespace
{
/// The venation of one whole leaf, `input`: the four outputs filled, or a message naming what went wrong.
std::string GrowOnLeaf(vtkVenationFilter* self, vtkPolyData* input, const plantmorph::VenationParameters& p,
  double progressBegin, double progressEnd, vtkPolyData* veins, vtkPolyData* bladeOut, vtkTable* statistics,
  vtkTable* histogram)
{
  InputBlade blade;
  std::string error = ReadBlade(input, blade);
  if (!error.empty())
    return error;
  bool flat = true;
  const plantmorph::VenationBlade plane{
    plantmorph::VenationWorkingPlane(blade.points, blade.uv, blade.triangles, flat), blade.uv, blade.triangles
  };
  plantmorph::VenationResult result;
  error = plantmorph::GrowVenation(plane, p, result, plantmorph::Progress(self, progressBegin, progressEnd));
  plantmorph::VeinNetworkMeasures measures;
  if (error.empty())
    error = plantmorph::MeasureVenation(plane, result, measures);
  if (error.empty())
    error = WriteVeinPoints(input, blade, result, veins);
  if (!error.empty())
    return error;
  WriteVeinLines(result, veins);
  WriteVeinFieldData(
    veins, result, measures, p, static_cast<plantmorph::VenationPreset>(self->GetPreset()), self->GetSeed(), flat);
  WriteStatistics(measures, statistics);
  WriteHistogram(plantmorph::MakeAreoleHistogram(measures.areoleAreas, self->GetAreoleHistogramBins()), histogram);
  WriteBlade(input, blade, plane, result, self->GetEmbossDepth(), bladeOut);
  return {};
}

/// Field data of the veins of several leaves: what every leaf grew with (each leaf's measures are its Statistics
/// row) and how many leaves the whole input has; the blades' EmbossDepth.
void WriteLeavesFieldData(vtkPolyData* veins, vtkPolyData* blades, const plantmorph::VenationParameters& p,
  plantmorph::VenationPreset preset, int seed, std::size_t leaves, double depth)
{
  plantmorph::FieldRecord record;
  record.Add("LeafCount", static_cast<double>(leaves));
  record.Add("Seed", static_cast<double>(seed));
  AddGrowth(record, p, preset);
  record.WriteTo(veins);
  plantmorph::FieldRecord blade;
  blade.Add("EmbossDepth", depth);
  blade.WriteTo(blades);
}
} // namespace

//------------------------------------------------------------------------------
int vtkVenationFilter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the venation", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkVenationFilter::Execute(plantmorph::Run& run)
{
  vtkPolyData* input = run.Input<vtkPolyData>(0);
  if (!input)
  {
    return;
  }
  // Several leaves (PlantMorphLeafExchange.h: a LeafId array, or connected blades): each grows on one rank.
  const plantmorph::LeafPlan plan(input);
  run.StopIfAnyRankFailed(plan.AnyRank(!plan.Error().empty()), plan.Error());
  if (plan.LeafIds().size() > 1)
  {
    this->GrowLeaves(run, plan);
    return;
  }
  // One leaf: under MPI the veins grow once, on rank 0, on the whole blade (gathered there if it was split).
  const vtkSmartPointer<vtkPolyData> wholeBlade = plantmorph::GatherOnFirstRank(input);
  if (wholeBlade->GetNumberOfPoints() == 0)
  {
    // Another rank: the blade is on rank 0, nothing to grow here, no error. On rank 0 the whole blade is empty.
    run.Warn("the Input (the blade) is empty (no points): no veins grow, the outputs are empty");
    return;
  }
  plantmorph::VenationParameters p;
  run.CheckHere(this->MakeParameters(p));
  run.CheckHere(GrowOnLeaf(this, wholeBlade, p, 0.0, 0.95, run.Output<vtkPolyData>(0), run.Output<vtkPolyData>(1),
    run.Output<vtkTable>(2), run.Output<vtkTable>(3)));
  run.UpdateProgress(1.0);
}

//------------------------------------------------------------------------------
void vtkVenationFilter::GrowLeaves(plantmorph::Run& run, const plantmorph::LeafPlan& plan)
{
  // Collective: the leaves this rank owns, whole; each grows as it would alone (same parameters, same Seed).
  const std::vector<vtkSmartPointer<vtkPolyData>> leaves = plan.Leaves();
  const std::vector<plantmorph::LeafIdType> owned = plan.Owned();
  const bool wide = plan.WideIds();
  plantmorph::VenationParameters p;
  std::string error = owned.empty() ? std::string() : this->MakeParameters(p);
  vtkNew<vtkAppendPolyData> appendVeins, appendBlades;
  vtkNew<vtkTable> statisticsRows, histogramRows;
  for (std::size_t k = 0; k < leaves.size() && error.empty(); ++k)
  {
    vtkNew<vtkPolyData> leafVeins, leafBlade;
    vtkNew<vtkTable> leafStatistics, leafHistogram;
    const double share = 0.95 / static_cast<double>(leaves.size());
    error =
      GrowOnLeaf(this, leaves[k], p, k * share, (k + 1) * share, leafVeins, leafBlade, leafStatistics, leafHistogram);
    if (!error.empty())
    {
      error = "leaf " + std::to_string(owned[k]) + ": " + error;
      break;
    }
    plantmorph::MarkLeaf(leafVeins, owned[k], wide);
    plantmorph::MarkLeaf(leafBlade, owned[k], wide);
    appendVeins->AddInputData(leafVeins);
    appendBlades->AddInputData(leafBlade);
    plantmorph::AppendRows(statisticsRows, plantmorph::WithLeafColumn(leafStatistics, owned[k], wide));
    plantmorph::AppendRows(histogramRows, plantmorph::WithLeafColumn(leafHistogram, owned[k], wide));
  }
  if (plan.AnyRank(!error.empty()))
  {
    run.CheckHere(error);
    run.Stop(); // every rank's outputs stay empty
  }
  if (!leaves.empty())
  {
    appendVeins->Update();
    appendBlades->Update();
    run.Output(0)->ShallowCopy(appendVeins->GetOutput());
    run.Output(1)->ShallowCopy(appendBlades->GetOutput());
    WriteLeavesFieldData(run.Output<vtkPolyData>(0), run.Output<vtkPolyData>(1), p,
      static_cast<plantmorph::VenationPreset>(this->Preset), this->Seed, plan.LeafIds().size(), this->EmbossDepth);
  }
  // Collective: the tables' rows (one Statistics row per leaf, its histogram's rows) on rank 0, in LeafId order.
  run.Output(2)->ShallowCopy(plan.GatherRows(statisticsRows));
  run.Output(3)->ShallowCopy(plan.GatherRows(histogramRows));
  run.UpdateProgress(1.0);
}

//------------------------------------------------------------------------------
void vtkVenationFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Preset: " << this->Preset << "\n";
  os << indent << "Pattern: " << this->Pattern << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "SecondarySpacing: " << this->SecondarySpacing << "\n";
  os << indent << "DivergenceAngle: " << this->DivergenceAngle << " .. " << this->DivergenceAngleApex << "\n";
  os << indent << "Tertiary: " << this->Tertiary << " (AreoleSize " << this->AreoleSize << ")\n";
  os << indent << "Veinlets: " << this->Veinlets << "\n";
  os << indent << "PalmateVeins: " << this->PalmateVeins << " (ForkLevels " << this->ForkLevels << ")\n";
  os << indent << "KillDistance: " << this->KillDistance << " (AttractionDistance " << this->AttractionDistance
     << ", SourceDensity " << this->SourceDensity << ", MurrayExponent " << this->MurrayExponent << ", GrowthStart "
     << this->GrowthStart << ", MarginalGrowth " << this->MarginalGrowth << ")\n";
  os << indent << "EmbossDepth: " << this->EmbossDepth << "\n";
  os << indent << "MaxSegments: " << this->MaxSegments << "\n";
  os << indent << "AreoleHistogramBins: " << this->AreoleHistogramBins << "\n";
}
