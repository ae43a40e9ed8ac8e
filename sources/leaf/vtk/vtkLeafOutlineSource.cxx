// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkLeafOutlineSource.h"
#include "PlantMorphAlgorithmHooks.h"

#include "PlantMorphLayer.h"
#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"
#include "BSplineLeaf.h"
#include "SpaceCurvePresets.h"

#include <plantmorph/DataContract.h>
#include <plantmorph/RangeError.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

vtkStandardNewMacro(vtkLeafOutlineSource);

namespace
{
using plantmorph::LeafGeometry;

/// Point arrays for the first `count` points of the leaf: coordinates, LeafUV, TCoords, Region, Normals.
void FillPoints(const LeafGeometry& leaf, vtkIdType count, vtkPolyData* output)
{
  const plantmorph::BladeMesh& blade = leaf.blade;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(count);
  vtkNew<vtkDoubleArray> uv;
  uv->SetName(plantmorph::arrays::LeafUV);
  uv->SetNumberOfComponents(2);
  uv->SetNumberOfTuples(count);
  vtkNew<vtkFloatArray> tcoords;
  tcoords->SetName(plantmorph::arrays::TCoords);
  tcoords->SetNumberOfComponents(2);
  tcoords->SetNumberOfTuples(count);
  vtkNew<vtkIntArray> region;
  region->SetName(plantmorph::arrays::Region);
  region->SetNumberOfTuples(count);
  vtkNew<vtkFloatArray> normals;
  normals->SetName(plantmorph::arrays::Normals);
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(count);
  for (vtkIdType i = 0; i < count; ++i)
  {
    points->SetPoint(i, blade.points[i].x(), blade.points[i].y(), leaf.z.empty() ? 0.0 : leaf.z[i]);
    uv->SetTypedTuple(i, blade.uv[i].data());
    const float t[2] = { static_cast<float>(leaf.tcoords[i].x()), static_cast<float>(leaf.tcoords[i].y()) };
    tcoords->SetTypedTuple(i, t);
    region->SetValue(i, blade.region[i]);
    const Eigen::Vector3d normal = leaf.normals.empty() ? Eigen::Vector3d::UnitZ() : leaf.normals[i];
    const float n[3] = { static_cast<float>(normal.x()), static_cast<float>(normal.y()),
      static_cast<float>(normal.z()) };
    normals->SetTypedTuple(i, n);
  }
  output->SetPoints(points);
  output->GetPointData()->AddArray(uv);
  output->GetPointData()->SetTCoords(tcoords);
  output->GetPointData()->AddArray(region);
  output->GetPointData()->SetNormals(normals);
}
} // namespace

//------------------------------------------------------------------------------
vtkLeafOutlineSource::vtkLeafOutlineSource()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
void vtkLeafOutlineSource::ClearTerms()
{
  this->TermsElementCount = -1;
  if (!this->Terms.empty())
  {
    this->Terms.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkLeafOutlineSource::AddTerm(
  double target, double scale, double amplitude, double multiplier, double frequency, double variable, double phase)
{
  this->Terms.insert(this->Terms.end(), { target, scale, amplitude, multiplier, frequency, variable, phase });
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkLeafOutlineSource::SetTermsElementCount(int count)
{
  if (count != this->TermsElementCount)
  {
    this->TermsElementCount = count;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
const char* vtkLeafOutlineSource::GetPresetValues()
{
  const int preset = this->Model == SPACE_CURVE ? this->SpaceCurvePreset
    : this->Model == B_SPLINE                   ? this->BSplinePreset
                                                : this->Preset;
  if (preset == 0)
  {
    this->PresetValues = "Custom: the properties are used as set.";
  }
  else if (this->LastParameters.empty())
  {
    this->PresetValues = "Apply to see the values the preset uses.";
  }
  else
  {
    this->PresetValues =
      "The named preset made this leaf with (the greyed properties are not used):\n" + this->LastParameters;
  }
  return this->PresetValues.c_str();
}

//------------------------------------------------------------------------------
namespace
{
void AddPoint(std::vector<double>& list, double x, double y, double z, vtkObject* owner)
{
  list.insert(list.end(), { x, y, z });
  owner->Modified();
}

void ClearPoints(std::vector<double>& list, vtkObject* owner)
{
  if (!list.empty())
  {
    list.clear();
    owner->Modified();
  }
}

/// Points of xyz triples, scaled about `origin`.
std::vector<Eigen::Vector3d> ScaledPoints(const std::vector<double>& xyz, double scale, const Eigen::Vector3d& origin)
{
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
  {
    points.push_back(origin + scale * (Eigen::Vector3d(xyz[i], xyz[i + 1], xyz[i + 2]) - origin));
  }
  return points;
}

/// The B-spline model's control points from the polylines of the ControlPoints input (ControlPointsFromLines).
std::string ControlPointsFromPolylines(vtkPolyData* input, double scale, plantmorph::BSplineLeafParameters& p)
{
  if (!input || input->GetNumberOfLines() == 0)
  {
    return "BSplinePreset 'ControlPoints input' needs polylines connected to the ControlPoints input";
  }
  std::vector<std::vector<Eigen::Vector3d>> lines;
  std::vector<int> regions;
  vtkDataArray* region = input->GetCellData()->GetArray(plantmorph::arrays::Region);
  vtkCellArray* cells = input->GetLines();
  vtkNew<vtkIdList> ids;
  const vtkIdType firstLine = input->GetNumberOfVerts(); // lines follow vertices in cell order
  cells->InitTraversal();
  for (vtkIdType k = 0; cells->GetNextCell(ids); ++k)
  {
    std::vector<Eigen::Vector3d> line;
    for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
    {
      const double* x = input->GetPoint(ids->GetId(i));
      line.emplace_back(x[0], x[1], x[2]);
    }
    lines.push_back(line);
    regions.push_back(region ? static_cast<int>(region->GetTuple1(firstLine + k)) : -1);
  }
  const std::string error = plantmorph::ControlPointsFromLines(lines, region ? &regions : nullptr, scale, p);
  return error.empty() ? error : "ControlPoints input: " + error;
}

void AddPointList(plantmorph::FieldRecord& fd, const char* name, const std::vector<Eigen::Vector3d>& points)
{
  std::vector<double> xyz;
  for (const Eigen::Vector3d& p : points)
  {
    xyz.insert(xyz.end(), { p.x(), p.y(), p.z() });
  }
  fd.AddRows(name, 3, xyz);
}
} // namespace

void vtkLeafOutlineSource::ClearMidveinPoints()
{
  ClearPoints(this->MidveinPoints, this);
}
void vtkLeafOutlineSource::AddMidveinPoint(double x, double y, double z)
{
  AddPoint(this->MidveinPoints, x, y, z, this);
}
void vtkLeafOutlineSource::ClearLeftMarginPoints()
{
  ClearPoints(this->LeftMarginPoints, this);
}
void vtkLeafOutlineSource::AddLeftMarginPoint(double x, double y, double z)
{
  AddPoint(this->LeftMarginPoints, x, y, z, this);
}
void vtkLeafOutlineSource::ClearRightMarginPoints()
{
  ClearPoints(this->RightMarginPoints, this);
}
void vtkLeafOutlineSource::AddRightMarginPoint(double x, double y, double z)
{
  AddPoint(this->RightMarginPoints, x, y, z, this);
}

//------------------------------------------------------------------------------
void vtkLeafOutlineSource::SetControlPointsConnection(int, vtkAlgorithmOutput* output)
{
  this->SetInputConnection(0, output);
}

//------------------------------------------------------------------------------
int vtkLeafOutlineSource::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkLeafOutlineSource::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  const bool growing = this->Growth != 0 && this->ValidateGrowth().empty();
  std::vector<double> times;
  for (int k = 0; growing && k < this->GrowthTimeSteps; ++k)
  {
    times.push_back(static_cast<double>(k) / (this->GrowthTimeSteps - 1));
  }
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    vtkInformation* info = outputVector->GetInformationObject(port);
    info->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
    if (growing)
    {
      const double range[2] = { 0.0, 1.0 };
      info->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), times.data(), static_cast<int>(times.size()));
      info->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
    }
    else
    {
      info->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
      info->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
namespace
{
/// The leaf is one piece: made whole on piece 0, the other pieces stay empty (no duplicates under MPI).
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank;

/// The growth time asked of the output (clamped to [0, 1]; 0 when none is asked) and the size it gives.
void GrowthOf(vtkInformation* info, double initialScale, double& time, double& scale)
{
  if (info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    time = std::clamp(info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()), 0.0, 1.0);
  }
  scale = initialScale + (1.0 - initialScale) * time;
}

/// Port 0: the blade's points and triangles, every triangle of Region blade.
void WriteBlade(const LeafGeometry& leaf, vtkPolyData* blade)
{
  FillPoints(leaf, static_cast<vtkIdType>(leaf.blade.points.size()), blade);
  vtkNew<vtkCellArray> triangles;
  triangles->AllocateExact(
    static_cast<vtkIdType>(leaf.blade.triangles.size()), 3 * static_cast<vtkIdType>(leaf.blade.triangles.size()));
  for (const auto& t : leaf.blade.triangles)
  {
    const vtkIdType ids[3] = { t[0], t[1], t[2] };
    triangles->InsertNextCell(3, ids);
  }
  blade->SetPolys(triangles);
  vtkNew<vtkIntArray> bladeRegion;
  bladeRegion->SetName(plantmorph::arrays::Region);
  bladeRegion->SetNumberOfTuples(triangles->GetNumberOfCells());
  bladeRegion->FillValue(plantmorph::RegionBlade);
  blade->GetCellData()->AddArray(bladeRegion);
}

/// Port 1: the outline polylines (margins, midvein, lobe midveins). Their points are the blade's first points (the
/// mesher keeps the outline's).
void WriteOutline(const LeafGeometry& leaf, vtkPolyData* outline)
{
  vtkIdType outlinePoints = 0;
  std::vector<std::pair<const std::vector<int>*, int>> polylines = { { &leaf.leftMargin, plantmorph::RegionMargin },
    { &leaf.rightMargin, plantmorph::RegionMargin }, { &leaf.midvein, plantmorph::RegionMidvein } };
  for (const std::vector<int>& lobeMidvein : leaf.lobeMidveins)
  {
    polylines.emplace_back(&lobeMidvein, plantmorph::RegionMidvein);
  }
  for (const auto& line : polylines)
  {
    outlinePoints = std::max<vtkIdType>(outlinePoints, *std::max_element(line.first->begin(), line.first->end()) + 1);
  }
  FillPoints(leaf, outlinePoints, outline);
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> lineRegion;
  lineRegion->SetName(plantmorph::arrays::Region);
  for (const auto& line : polylines)
  {
    lines->InsertNextCell(static_cast<vtkIdType>(line.first->size()));
    for (int id : *line.first)
    {
      lines->InsertCellPoint(id);
    }
    lineRegion->InsertNextValue(line.second);
  }
  outline->SetLines(lines);
  outline->GetCellData()->AddArray(lineRegion);
}
} // namespace

//------------------------------------------------------------------------------
int vtkLeafOutlineSource::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the leaf blade", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkLeafOutlineSource::Execute(plantmorph::Run& run)
{
  if (this->TermsElementCount >= 0 && static_cast<std::size_t>(this->TermsElementCount) != this->Terms.size())
  {
    // ParaView pushed only the whole rows: a partial row means the user's list is not rows of seven.
    run.Fail(plantmorph::OutOfRange("Terms", std::to_string(this->TermsElementCount) + " numbers", "{0, 7, 14, ...}",
      "rows of seven: Target, Scale, Amplitude, Multiplier, Frequency, Variable, Phase; the last row has " +
        std::to_string(this->TermsElementCount % 7)));
  }
  if (this->MaxVertices < 3)
  {
    run.Fail(plantmorph::OutOfRange("MaxVertices", this->MaxVertices, "[3, inf)"));
  }
  // Growth: the requested time (clamped to [0, 1]) sets the size.
  double scale = 1.0;
  double time = 0.0;
  if (this->Growth)
  {
    run.Check(this->ValidateGrowth());
    GrowthOf(run.OutputInformation(0), this->GrowthInitialScale, time, scale);
  }
  plantmorph::FieldRecord parameters;
  LeafGeometry leaf;
  this->WarnAboutPresetOverrides();
  this->LastParameters.clear();
  const std::string error = this->BuildLeaf(leaf, parameters, scale, run.Input<vtkPolyData>(0));
  if (error == "aborted")
  {
    run.Stop();
  }
  run.Check(error);
  run.Building("the leaf's outputs");
  vtkPolyData* blade = run.Output<vtkPolyData>(0);
  vtkPolyData* outline = run.Output<vtkPolyData>(1);
  WriteBlade(leaf, blade);
  this->UpdateProgress(0.95);
  WriteOutline(leaf, outline);
  if (this->Growth)
  {
    parameters.Add("PlantMorph.GrowthFraction", time);
    parameters.Add("PlantMorph.GrowthScale", scale);
  }
  this->LastParameters = parameters.Text();
  // Parameters as field data on both outputs, and the time they show.
  for (vtkPolyData* output : { blade, outline })
  {
    if (this->Growth)
    {
      output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), time);
    }
    parameters.WriteTo(output);
  }
  if (leaf.uvInversionFailures > 0)
  {
    vtkWarningMacro(<< leaf.uvInversionFailures
                    << " interior points got an approximate LeafUV (the map could not be inverted there)");
  }
  this->UpdateProgress(1.0);
}

//------------------------------------------------------------------------------
std::string vtkLeafOutlineSource::ValidateGrowth() const
{
  std::ostringstream message;
  if (this->GrowthTimeSteps < 2 || this->GrowthTimeSteps > 10000)
  {
    message << plantmorph::OutOfRange("GrowthTimeSteps", this->GrowthTimeSteps, "[2, 10000]");
  }
  else if (!(this->GrowthInitialScale > 0.0 && this->GrowthInitialScale <= 1.0))
  {
    message << plantmorph::OutOfRange("GrowthInitialScale", this->GrowthInitialScale, "(0, 1]");
  }
  return message.str();
}

//------------------------------------------------------------------------------
std::string vtkLeafOutlineSource::MeshParameters(plantmorph::LeafMeshParameters& settings)
{
  if (this->MeshQuality != 0 && this->MeshQuality != 1)
  {
    std::ostringstream message;
    message << plantmorph::OutOfRange("MeshQuality", this->MeshQuality, "{0, 1}", "0 paper, 1 quality");
    return message.str();
  }
  settings.resolution = this->Resolution;
  settings.quality = this->MeshQuality == 1;
  settings.maxVertices = static_cast<std::size_t>(this->MaxVertices);
  settings.progress = plantmorph::Progress(this);
  return {};
}

//------------------------------------------------------------------------------
void vtkLeafOutlineSource::WarnAboutPresetOverrides()
{
  vtkNew<vtkLeafOutlineSource> defaults;
  const int preset = this->Model == SPACE_CURVE ? this->SpaceCurvePreset
    : this->Model == B_SPLINE                   ? this->BSplinePreset
                                                : this->Preset;
  plantmorph::PresetOverrides overrides(this->Model == SPACE_CURVE ? "SpaceCurvePreset"
      : this->Model == B_SPLINE                                    ? "BSplinePreset"
                                                                   : "Preset");
  if (preset == 0 || this->Model < DEFORMED_RECTANGLE || this->Model > B_SPLINE)
  {
    return;
  }
  // Each model's properties that only its Custom preset uses.
#define PLANTMORPH_CHECK(model, name)                                                                                  \
  if (this->Model == (model))                                                                                          \
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, name)
  PLANTMORPH_CHECK(DEFORMED_RECTANGLE, Width);
  PLANTMORPH_CHECK(DEFORMED_RECTANGLE, Terms);
  PLANTMORPH_CHECK(SPACE_CURVE, CurvatureFunction);
  PLANTMORPH_CHECK(SPACE_CURVE, CurvatureMu);
  PLANTMORPH_CHECK(SPACE_CURVE, CurvatureLambda);
  PLANTMORPH_CHECK(SPACE_CURVE, CurvatureN1);
  PLANTMORPH_CHECK(SPACE_CURVE, CurvatureN2);
  PLANTMORPH_CHECK(SPACE_CURVE, CurvatureB1);
  PLANTMORPH_CHECK(SPACE_CURVE, CurvatureU3);
  PLANTMORPH_CHECK(SPACE_CURVE, CurvatureBeta);
  PLANTMORPH_CHECK(SPACE_CURVE, CurvatureAlpha4);
  PLANTMORPH_CHECK(SPACE_CURVE, CurvatureLambda2);
  PLANTMORPH_CHECK(SPACE_CURVE, TorsionFunction);
  PLANTMORPH_CHECK(SPACE_CURVE, TorsionEta);
  PLANTMORPH_CHECK(SPACE_CURVE, TorsionLambda);
  PLANTMORPH_CHECK(SPACE_CURVE, TorsionN1);
  PLANTMORPH_CHECK(SPACE_CURVE, TorsionN2);
  PLANTMORPH_CHECK(SPACE_CURVE, TorsionB1);
  PLANTMORPH_CHECK(SPACE_CURVE, TorsionU3);
  PLANTMORPH_CHECK(SPACE_CURVE, TorsionBeta);
  PLANTMORPH_CHECK(SPACE_CURVE, TorsionAlpha4);
  PLANTMORPH_CHECK(SPACE_CURVE, TorsionLambda2);
  PLANTMORPH_CHECK(SPACE_CURVE, MidveinStretchZ);
  PLANTMORPH_CHECK(SPACE_CURVE, MidveinStretchXY);
  PLANTMORPH_CHECK(SPACE_CURVE, Lobes);
  PLANTMORPH_CHECK(SPACE_CURVE, LobeStart);
  PLANTMORPH_CHECK(SPACE_CURVE, LobeAngle);
  PLANTMORPH_CHECK(SPACE_CURVE, LobeScale);
  PLANTMORPH_CHECK(SPACE_CURVE, SubLobes);
  PLANTMORPH_CHECK(SPACE_CURVE, SubLobeDepth);
  PLANTMORPH_CHECK(SPACE_CURVE, SinusDepth);
  PLANTMORPH_CHECK(B_SPLINE, MidveinPoints);
  PLANTMORPH_CHECK(B_SPLINE, LeftMarginPoints);
  PLANTMORPH_CHECK(B_SPLINE, RightMarginPoints);
#undef PLANTMORPH_CHECK
  overrides.Warn(this);
}

//------------------------------------------------------------------------------
namespace
{
/// The Custom space curve's parameters from the properties (curvature, torsion, stretches, lobes).
void ReadCustomSpaceCurve(vtkLeafOutlineSource* self, plantmorph::SpaceCurveParameters& parameters)
{
  plantmorph::CurvatureFamily& k = parameters.curvature;
  k.type = static_cast<plantmorph::CurvatureFamily::Type>(self->GetCurvatureFunction());
  k.mu = self->GetCurvatureMu();
  k.lambda = self->GetCurvatureLambda();
  k.n1 = self->GetCurvatureN1();
  k.n2 = self->GetCurvatureN2();
  k.b1 = self->GetCurvatureB1();
  k.u3 = self->GetCurvatureU3();
  k.beta = self->GetCurvatureBeta();
  k.alpha4 = self->GetCurvatureAlpha4();
  k.lambda2 = self->GetCurvatureLambda2();
  plantmorph::CurvatureFamily& t = parameters.torsion;
  t.type = static_cast<plantmorph::CurvatureFamily::Type>(self->GetTorsionFunction());
  t.mu = self->GetTorsionEta();
  t.lambda = self->GetTorsionLambda();
  t.n1 = self->GetTorsionN1();
  t.n2 = self->GetTorsionN2();
  t.b1 = self->GetTorsionB1();
  t.u3 = self->GetTorsionU3();
  t.beta = self->GetTorsionBeta();
  t.alpha4 = self->GetTorsionAlpha4();
  t.lambda2 = self->GetTorsionLambda2();
  parameters.midveinStretchZ = self->GetMidveinStretchZ();
  parameters.midveinStretchXY = self->GetMidveinStretchXY();
  parameters.lobes = self->GetLobes();
  parameters.lobeStart = self->GetLobeStart();
  parameters.lobeAngle = self->GetLobeAngle();
  parameters.lobeScale = self->GetLobeScale();
  parameters.subLobes = self->GetSubLobes();
  parameters.subLobeDepth = self->GetSubLobeDepth();
  parameters.sinusDepth = self->GetSinusDepth();
}

/// The space-curve leaf's PlantMorph.* field data.
void RecordSpaceCurve(vtkLeafOutlineSource* self, plantmorph::SpaceCurvePreset preset,
  const plantmorph::SpaceCurveParameters& parameters, plantmorph::FieldRecord& fd)
{
  fd.Add("PlantMorph.Model", "SpaceCurve");
  fd.Add("PlantMorph.Preset", plantmorph::SpaceCurvePresetName(preset));
  fd.Add("PlantMorph.CurveLength", parameters.length);
  for (const auto& family : { std::make_pair("PlantMorph.Curvature", &parameters.curvature),
         std::make_pair("PlantMorph.Torsion", &parameters.torsion) })
  {
    const plantmorph::CurvatureFamily& f = *family.second;
    fd.AddTuple(family.first, { "Function", "Mu", "Lambda", "N1", "N2", "B1", "U3", "Beta", "Alpha4", "Lambda2" },
      { static_cast<double>(f.type), f.mu, f.lambda, f.n1, f.n2, f.b1, f.u3, f.beta, f.alpha4, f.lambda2 });
  }
  fd.Add("PlantMorph.Opening", parameters.opening);
  fd.Add("PlantMorph.MidveinStretchZ", parameters.midveinStretchZ);
  fd.Add("PlantMorph.MidveinStretchXY", parameters.midveinStretchXY);
  fd.Add("PlantMorph.InitialAngle", parameters.initialAngle);
  fd.Add("PlantMorph.IntegrationMethod", self->GetIntegrationMethod());
  fd.Add("PlantMorph.Resolution", self->GetResolution());
  fd.Add("PlantMorph.StripColumns", self->GetStripColumns());
  fd.Add("PlantMorph.Lobes", parameters.lobes);
  if (parameters.lobes > 1)
  {
    fd.Add("PlantMorph.LobeStart", parameters.lobeStart);
    fd.Add("PlantMorph.LobeAngle", parameters.lobeAngle);
    fd.Add("PlantMorph.LobeScale", parameters.lobeScale);
    if (parameters.subLobes > 0) // only then, so blades without sub-lobes keep their field data
    {
      fd.Add("PlantMorph.SubLobes", parameters.subLobes);
      fd.Add("PlantMorph.SubLobeDepth", parameters.subLobeDepth);
    }
    if (parameters.sinusDepth > 0.0) // only then, so blades with the union's sinuses keep their field data
      fd.Add("PlantMorph.SinusDepth", parameters.sinusDepth);
    fd.Add("PlantMorph.MeshQuality", self->GetMeshQuality());
  }
}

/// A named B-spline preset's control points from BladeLength, BladeWidth and ControlPointCount; "" or the message.
std::string MakeBSpline(vtkLeafOutlineSource* self, plantmorph::BSplinePreset preset, double scale,
  plantmorph::BSplineLeafParameters& parameters)
{
  const double length = self->GetBladeLength(), width = self->GetBladeWidth();
  const int count = self->GetControlPointCount();
  if (!(std::isfinite(length) && length > 0 && length <= 1e6))
  {
    return plantmorph::OutOfRange("BladeLength", length, "(0, 1e6]");
  }
  if (!(std::isfinite(width) && width > 0 && width <= 1e6))
  {
    return plantmorph::OutOfRange("BladeWidth", width, "(0, 1e6]");
  }
  if (count < 3 || count > 1000)
  {
    return plantmorph::OutOfRange("ControlPointCount", count, "[3, 1000]");
  }
  parameters = plantmorph::MakeBSplinePreset(preset, scale * length, scale * width, count);
  return {};
}
} // namespace

//------------------------------------------------------------------------------
std::string vtkLeafOutlineSource::BuildLeaf(
  LeafGeometry& leaf, plantmorph::FieldRecord& fd, double scale, vtkPolyData* controlPoints)
{
  if (this->Model == DEFORMED_RECTANGLE)
  {
    return this->BuildDeformedRectangle(leaf, fd, scale);
  }
  if (this->Model == SPACE_CURVE)
  {
    return this->BuildSpaceCurve(leaf, fd, scale);
  }
  if (this->Model == B_SPLINE)
  {
    return this->BuildBSpline(leaf, fd, scale, controlPoints);
  }
  std::ostringstream message;
  message << plantmorph::OutOfRange(
    "Model", this->Model, "{0, 1, 2}", "0 deformed rectangle, 1 space curve, 2 B-spline");
  return message.str();
}

//------------------------------------------------------------------------------
// Paper 000: the deformed rectangle.
std::string vtkLeafOutlineSource::BuildDeformedRectangle(LeafGeometry& leaf, plantmorph::FieldRecord& fd, double scale)
{
  if (this->Preset < 0 || this->Preset >= plantmorph::DeformedRectanglePresetCount)
  {
    return plantmorph::OutOfRange(
      "Preset", this->Preset, "[0, " + std::to_string(plantmorph::DeformedRectanglePresetCount - 1) + "]");
  }
  const double bladeLength = scale * this->Length;
  if (!(std::isfinite(bladeLength) && bladeLength > 0.0 && bladeLength <= 1e6))
  {
    return plantmorph::OutOfRange("Length", this->Length, "(0, 1e6]", "the blade's length from base to apex");
  }
  const auto preset = static_cast<plantmorph::DeformedRectanglePreset>(this->Preset);
  // The rectangle first at b_y = Length (a_x: the preset's proportion, or Width for Custom), then a_x and b_y
  // scaled together so the blade is Length long from base to apex.
  plantmorph::DeformedRectangleParameters parameters = plantmorph::MakeDeformedRectanglePreset(preset, bladeLength);
  if (preset == plantmorph::DeformedRectanglePreset::Custom)
  {
    parameters.width = scale * this->Width;
    const std::string termError = plantmorph::ParseTerms(this->Terms, parameters.terms);
    if (!termError.empty())
    {
      return termError;
    }
  }
  parameters.bending = this->Bending;
  parameters.asymmetry = this->Asymmetry;
  if (plantmorph::Validate(parameters).empty())
  {
    const std::string scaleError = plantmorph::ScaleToBladeLength(parameters, bladeLength);
    if (!scaleError.empty())
    {
      return scaleError;
    }
  }
  plantmorph::LeafMeshParameters settings;
  const std::string settingsError = this->MeshParameters(settings);
  if (!settingsError.empty())
  {
    return settingsError;
  }
  const std::string error = plantmorph::BuildDeformedRectangleLeaf(parameters, settings, leaf);
  if (!error.empty())
  {
    return error;
  }
  fd.Add("PlantMorph.Model", "DeformedRectangle");
  fd.Add("PlantMorph.Preset", plantmorph::PresetName(preset));
  fd.Add("PlantMorph.Length", bladeLength);
  fd.Add("PlantMorph.RectangleWidth", parameters.width);
  fd.Add("PlantMorph.RectangleHeight", parameters.length);
  fd.Add("PlantMorph.Bending", parameters.bending);
  fd.Add("PlantMorph.Asymmetry", parameters.asymmetry);
  fd.Add("PlantMorph.Resolution", this->Resolution);
  fd.Add("PlantMorph.MeshQuality", this->MeshQuality);
  fd.AddRows("PlantMorph.Terms", plantmorph::TermColumns, plantmorph::FlattenTerms(parameters.terms));
  return {};
}

//------------------------------------------------------------------------------
// Paper 002: the space curve (and palmate) leaf.
std::string vtkLeafOutlineSource::BuildSpaceCurve(LeafGeometry& leaf, plantmorph::FieldRecord& fd, double scale)
{
  std::ostringstream message;
  if (this->SpaceCurvePreset < 0 || this->SpaceCurvePreset >= plantmorph::SpaceCurvePresetCount)
  {
    return plantmorph::OutOfRange(
      "SpaceCurvePreset", this->SpaceCurvePreset, "[0, " + std::to_string(plantmorph::SpaceCurvePresetCount - 1) + "]");
  }
  if (this->IntegrationMethod != 0 && this->IntegrationMethod != 1)
  {
    message << plantmorph::OutOfRange("IntegrationMethod", this->IntegrationMethod, "{0, 1}", "0 RK4, 1 RK45");
    return message.str();
  }
  const auto preset = static_cast<plantmorph::SpaceCurvePreset>(this->SpaceCurvePreset);
  plantmorph::SpaceCurveParameters parameters = plantmorph::MakeSpaceCurvePreset(preset, scale * this->CurveLength);
  if (preset == plantmorph::SpaceCurvePreset::Custom)
  {
    ReadCustomSpaceCurve(this, parameters);
  }
  parameters.opening = this->Opening;
  parameters.initialAngle = this->InitialAngle;
  parameters.method = static_cast<plantmorph::FrenetMethod>(this->IntegrationMethod);
  plantmorph::SpaceCurveMeshParameters settings;
  settings.resolution = this->Resolution;
  settings.columns = this->StripColumns;
  plantmorph::LeafMeshParameters meshSettings;
  const std::string settingsError = this->MeshParameters(meshSettings);
  if (!settingsError.empty())
  {
    return settingsError;
  }
  settings.quality = meshSettings.quality;
  settings.maxVertices = meshSettings.maxVertices;
  settings.progress = meshSettings.progress;
  this->UpdateProgress(0.1);
  const std::string error = plantmorph::BuildSpaceCurveLeaf(parameters, settings, leaf);
  if (!error.empty())
  {
    return error;
  }
  RecordSpaceCurve(this, preset, parameters, fd);
  return {};
}

//------------------------------------------------------------------------------
// Paper 003: the B-spline leaf (Model C).
std::string vtkLeafOutlineSource::BuildBSpline(
  LeafGeometry& leaf, plantmorph::FieldRecord& fd, double scale, vtkPolyData* controlPoints)
{
  // One past the algorithm's presets: the control points come from the input port.
  const int fromInput = plantmorph::BSplinePresetCount;
  if (this->BSplinePreset < 0 || this->BSplinePreset > fromInput)
  {
    return plantmorph::OutOfRange("BSplinePreset", this->BSplinePreset, "[0, " + std::to_string(fromInput) + "]");
  }
  const auto preset = static_cast<plantmorph::BSplinePreset>(this->BSplinePreset);
  plantmorph::BSplineLeafParameters parameters;
  std::string source = this->BSplinePreset == fromInput ? "ControlPointsInput" : plantmorph::BSplinePresetName(preset);
  if (this->BSplinePreset == fromInput)
  {
    const std::string inputError = ControlPointsFromPolylines(controlPoints, scale, parameters);
    if (!inputError.empty())
    {
      return inputError;
    }
  }
  else if (preset == plantmorph::BSplinePreset::Custom)
  {
    const Eigen::Vector3d base = this->MidveinPoints.size() >= 3
      ? Eigen::Vector3d(this->MidveinPoints[0], this->MidveinPoints[1], this->MidveinPoints[2])
      : Eigen::Vector3d::Zero();
    parameters.midvein = ScaledPoints(this->MidveinPoints, scale, base);
    parameters.leftMargin = ScaledPoints(this->LeftMarginPoints, scale, base);
    parameters.rightMargin = ScaledPoints(this->RightMarginPoints, scale, base);
  }
  else
  {
    const std::string presetError = MakeBSpline(this, preset, scale, parameters);
    if (!presetError.empty())
    {
      return presetError;
    }
  }
  plantmorph::LeafMeshParameters settings;
  const std::string settingsError = this->MeshParameters(settings);
  if (!settingsError.empty())
  {
    return settingsError;
  }
  const std::string error = plantmorph::BuildBSplineLeaf(parameters, settings, leaf);
  if (!error.empty())
  {
    return error;
  }
  fd.Add("PlantMorph.Model", "BSpline");
  fd.Add("PlantMorph.Preset", source);
  AddPointList(fd, "PlantMorph.MidveinPoints", parameters.midvein);
  AddPointList(fd, "PlantMorph.LeftMarginPoints", parameters.leftMargin);
  AddPointList(fd, "PlantMorph.RightMarginPoints", parameters.rightMargin);
  fd.Add("PlantMorph.Resolution", this->Resolution);
  fd.Add("PlantMorph.MeshQuality", this->MeshQuality);
  return {};
}

//------------------------------------------------------------------------------
void vtkLeafOutlineSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Model: " << this->Model << "\n";
  os << indent << "Preset: " << this->Preset << "\n";
  os << indent << "Length: " << this->Length << "\n";
  os << indent << "Width: " << this->Width << "\n";
  os << indent << "Terms: " << this->GetNumberOfTerms() << " rows\n";
  os << indent << "Bending: " << this->Bending << "\n";
  os << indent << "Asymmetry: " << this->Asymmetry << "\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "MeshQuality: " << this->MeshQuality << "\n";
  os << indent << "MaxVertices: " << this->MaxVertices << "\n";
  os << indent << "SpaceCurvePreset: " << this->SpaceCurvePreset << "\n";
  os << indent << "CurveLength: " << this->CurveLength << "\n";
  os << indent << "CurvatureFunction: " << this->CurvatureFunction << " Mu " << this->CurvatureMu << " Lambda "
     << this->CurvatureLambda << "\n";
  os << indent << "TorsionFunction: " << this->TorsionFunction << " Eta " << this->TorsionEta << " Lambda "
     << this->TorsionLambda << "\n";
  os << indent << "Opening: " << this->Opening << "\n";
  os << indent << "MidveinStretch: Z " << this->MidveinStretchZ << " XY " << this->MidveinStretchXY << "\n";
  os << indent << "IntegrationMethod: " << this->IntegrationMethod << "\n";
  os << indent << "StripColumns: " << this->StripColumns << "\n";
  os << indent << "Lobes: " << this->Lobes << " (start " << this->LobeStart << ", angle " << this->LobeAngle
     << ", scale " << this->LobeScale << ")\n";
  os << indent << "Growth: " << this->Growth << " (" << this->GrowthTimeSteps << " steps from scale "
     << this->GrowthInitialScale << ")\n";
}
