// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkLeafOutlineSource.h"
#include "PlantMorphAlgorithmHooks.h"

#include "PlantMorphFieldData.h"
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

using plantmorph::AddFieldString;
using plantmorph::AddFieldValue;

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

/// The B-spline model's control points from polylines (see the class documentation), scaled about the base.
std::string ControlPointsFromPolylines(vtkPolyData* input, double scale, plantmorph::BSplineLeafParameters& p)
{
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
  std::vector<Eigen::Vector3d> margins[2];
  if (region)
  {
    int found = 0;
    for (std::size_t k = 0; k < lines.size(); ++k)
    {
      if (regions[k] == plantmorph::RegionMidvein && p.midvein.empty())
        p.midvein = lines[k];
      else if (regions[k] == plantmorph::RegionMargin && found < 2)
        margins[found++] = lines[k];
    }
    if (p.midvein.empty() || found < 2)
      return "needs one polyline with Region 1 (midvein) and two with Region 4 (margins)";
  }
  else
  {
    if (lines.size() != 3)
    {
      std::ostringstream message;
      message << "without a Region cell array it needs exactly 3 polylines (left margin, right margin, midvein), got "
              << lines.size();
      return message.str();
    }
    margins[0] = lines[0];
    margins[1] = lines[1];
    p.midvein = lines[2];
  }
  if (p.midvein.size() < 2)
    return "the midvein polyline needs at least 2 points";
  const Eigen::Vector3d base = p.midvein.front(), apex = p.midvein.back();
  for (std::vector<Eigen::Vector3d>& margin : margins)
  {
    if (!margin.empty() && (margin.front() - base).norm() > (margin.back() - base).norm())
      std::reverse(margin.begin(), margin.end());
  }
  if (region)
  {
    // Left is the margin on the left of the base-to-apex direction seen from +Z (positive cross product).
    auto side = [&](const std::vector<Eigen::Vector3d>& margin) {
      double sum = 0.0;
      const Eigen::Vector3d d = apex - base;
      for (const Eigen::Vector3d& x : margin)
        sum += d.x() * (x.y() - base.y()) - d.y() * (x.x() - base.x());
      return sum;
    };
    if (side(margins[0]) < side(margins[1]))
      std::swap(margins[0], margins[1]);
  }
  auto scaled = [&](std::vector<Eigen::Vector3d> points) {
    for (Eigen::Vector3d& x : points)
      x = base + scale * (x - base);
    return points;
  };
  p.midvein = scaled(p.midvein);
  p.leftMargin = scaled(margins[0]);
  p.rightMargin = scaled(margins[1]);
  return {};
}

void AddPointList(vtkFieldData* fd, const char* name, const std::vector<Eigen::Vector3d>& points)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(3);
  for (const Eigen::Vector3d& p : points)
  {
    a->InsertNextTuple(p.data());
  }
  fd->AddArray(a);
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
int vtkLeafOutlineSource::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* blade = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* outline = vtkPolyData::GetData(outputVector, 1);
  blade->Initialize();
  outline->Initialize();

  // The leaf is one piece: piece 0 makes it, the others stay empty (no duplicates under MPI).
  const int piece = outputVector->GetInformationObject(0)->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
  if (piece > 0)
  {
    return 1;
  }

  if (this->TermsElementCount >= 0 && static_cast<std::size_t>(this->TermsElementCount) != this->Terms.size())
  {
    // ParaView pushed only the whole rows: a partial row means the user's list is not rows of seven.
    vtkErrorMacro(
      << plantmorph::OutOfRange("Terms", std::to_string(this->TermsElementCount) + " numbers", "{0, 7, 14, ...}",
           "rows of seven: Target, Scale, Amplitude, Multiplier, Frequency, Variable, Phase; the last row has " +
             std::to_string(this->TermsElementCount % 7)));
    return 1;
  }
  if (this->MaxVertices < 3)
  {
    vtkErrorMacro(<< plantmorph::OutOfRange("MaxVertices", this->MaxVertices, "[3, inf)"));
    return 1;
  }
  // Growth: the requested time (clamped to [0, 1]) sets the size.
  double scale = 1.0;
  double time = 0.0;
  if (this->Growth)
  {
    const std::string growthError = this->ValidateGrowth();
    if (!growthError.empty())
    {
      vtkErrorMacro(<< growthError);
      return 1;
    }
    vtkInformation* info = outputVector->GetInformationObject(0);
    if (info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
    {
      time = std::clamp(info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()), 0.0, 1.0);
    }
    scale = this->GrowthInitialScale + (1.0 - this->GrowthInitialScale) * time;
  }
  vtkNew<vtkFieldData> parameters;
  LeafGeometry leaf;
  vtkPolyData* controlPoints =
    inputVector[0]->GetNumberOfInformationObjects() > 0 ? vtkPolyData::GetData(inputVector[0], 0) : nullptr;
  this->WarnAboutPresetOverrides();
  this->LastParameters.clear();
  const std::string error = this->BuildLeaf(leaf, parameters, scale, controlPoints);
  if (!error.empty())
  {
    if (error != "aborted")
    {
      vtkErrorMacro(<< error);
    }
    return 1;
  }

  // Port 0: the blade.
  const vtkIdType numberOfPoints = static_cast<vtkIdType>(leaf.blade.points.size());
  FillPoints(leaf, numberOfPoints, blade);
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
  this->UpdateProgress(0.95);

  // Port 1: the outline polylines. Their points are the blade's first points (the mesher keeps the outline's).
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

  if (this->Growth)
  {
    AddFieldValue(parameters, "PlantMorph.GrowthFraction", time);
    AddFieldValue(parameters, "PlantMorph.GrowthScale", scale);
  }
  this->LastParameters = plantmorph::FormatParameters(parameters);
  // Parameters as field data on both outputs, and the time they show.
  for (vtkPolyData* output : { blade, outline })
  {
    if (this->Growth)
    {
      output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), time);
    }
    for (int a = 0; a < parameters->GetNumberOfArrays(); ++a)
    {
      output->GetFieldData()->AddArray(parameters->GetAbstractArray(a));
    }
  }
  if (leaf.uvInversionFailures > 0)
  {
    vtkWarningMacro(<< leaf.uvInversionFailures
                    << " interior points got an approximate LeafUV (the map could not be inverted there)");
  }
  this->UpdateProgress(1.0);
  return 1;
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
  std::ostringstream ignored;
  const auto check = [&](const char* name, bool changed) {
    if (changed)
    {
      ignored << (ignored.tellp() > 0 ? ", " : "") << name;
    }
  };
#define PLANTMORPH_CHECK(name) check(#name, this->name != defaults->name)
  std::string presetName;
  if (this->Model == DEFORMED_RECTANGLE && this->Preset != 0)
  {
    presetName = "Preset";
    PLANTMORPH_CHECK(Width);
    PLANTMORPH_CHECK(Terms);
  }
  else if (this->Model == SPACE_CURVE && this->SpaceCurvePreset != 0)
  {
    presetName = "SpaceCurvePreset";
    PLANTMORPH_CHECK(CurvatureFunction);
    PLANTMORPH_CHECK(CurvatureMu);
    PLANTMORPH_CHECK(CurvatureLambda);
    PLANTMORPH_CHECK(CurvatureN1);
    PLANTMORPH_CHECK(CurvatureN2);
    PLANTMORPH_CHECK(CurvatureB1);
    PLANTMORPH_CHECK(CurvatureU3);
    PLANTMORPH_CHECK(CurvatureBeta);
    PLANTMORPH_CHECK(CurvatureAlpha4);
    PLANTMORPH_CHECK(CurvatureLambda2);
    PLANTMORPH_CHECK(TorsionFunction);
    PLANTMORPH_CHECK(TorsionEta);
    PLANTMORPH_CHECK(TorsionLambda);
    PLANTMORPH_CHECK(TorsionN1);
    PLANTMORPH_CHECK(TorsionN2);
    PLANTMORPH_CHECK(TorsionB1);
    PLANTMORPH_CHECK(TorsionU3);
    PLANTMORPH_CHECK(TorsionBeta);
    PLANTMORPH_CHECK(TorsionAlpha4);
    PLANTMORPH_CHECK(TorsionLambda2);
    PLANTMORPH_CHECK(MidveinStretchZ);
    PLANTMORPH_CHECK(MidveinStretchXY);
    PLANTMORPH_CHECK(Lobes);
    PLANTMORPH_CHECK(LobeStart);
    PLANTMORPH_CHECK(LobeAngle);
    PLANTMORPH_CHECK(LobeScale);
    PLANTMORPH_CHECK(SubLobes);
    PLANTMORPH_CHECK(SubLobeDepth);
  }
  else if (this->Model == B_SPLINE && this->BSplinePreset != 0)
  {
    presetName = "BSplinePreset";
    PLANTMORPH_CHECK(MidveinPoints);
    PLANTMORPH_CHECK(LeftMarginPoints);
    PLANTMORPH_CHECK(RightMarginPoints);
  }
#undef PLANTMORPH_CHECK
  if (ignored.tellp() > 0)
  {
    vtkWarningMacro(<< "these properties are changed from their defaults but not used, because " << presetName
                    << " is a named preset that sets them itself: " << ignored.str() << ". Set " << presetName
                    << " to Custom (0) to use them.");
  }
}

//------------------------------------------------------------------------------
std::string vtkLeafOutlineSource::BuildLeaf(
  LeafGeometry& leaf, vtkFieldData* fd, double scale, vtkPolyData* controlPoints)
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
std::string vtkLeafOutlineSource::BuildDeformedRectangle(LeafGeometry& leaf, vtkFieldData* fd, double scale)
{
  std::ostringstream message;
  if (this->Preset < 0 || this->Preset >= plantmorph::DeformedRectanglePresetCount)
  {
    message << plantmorph::OutOfRange(
      "Preset", this->Preset, "[0, " + std::to_string(plantmorph::DeformedRectanglePresetCount - 1) + "]");
    return message.str();
  }
  const double bladeLength = scale * this->Length;
  if (!(std::isfinite(bladeLength) && bladeLength > 0.0 && bladeLength <= 1e6))
  {
    message << plantmorph::OutOfRange("Length", this->Length, "(0, 1e6]", "the blade's length from base to apex");
    return message.str();
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
  AddFieldString(fd, "PlantMorph.Model", "DeformedRectangle");
  AddFieldString(fd, "PlantMorph.Preset", plantmorph::PresetName(preset));
  AddFieldValue(fd, "PlantMorph.Length", bladeLength);
  AddFieldValue(fd, "PlantMorph.RectangleWidth", parameters.width);
  AddFieldValue(fd, "PlantMorph.RectangleHeight", parameters.length);
  AddFieldValue(fd, "PlantMorph.Bending", parameters.bending);
  AddFieldValue(fd, "PlantMorph.Asymmetry", parameters.asymmetry);
  AddFieldValue(fd, "PlantMorph.Resolution", this->Resolution);
  AddFieldValue(fd, "PlantMorph.MeshQuality", this->MeshQuality);
  vtkNew<vtkDoubleArray> terms;
  terms->SetName("PlantMorph.Terms");
  terms->SetNumberOfComponents(plantmorph::TermColumns);
  const std::vector<double> flat = plantmorph::FlattenTerms(parameters.terms);
  terms->SetNumberOfTuples(static_cast<vtkIdType>(parameters.terms.size()));
  std::copy(flat.begin(), flat.end(), terms->GetPointer(0));
  fd->AddArray(terms);
  return {};
}

//------------------------------------------------------------------------------
// Paper 002: the space curve (and palmate) leaf.
std::string vtkLeafOutlineSource::BuildSpaceCurve(LeafGeometry& leaf, vtkFieldData* fd, double scale)
{
  std::ostringstream message;
  if (this->SpaceCurvePreset < 0 || this->SpaceCurvePreset >= plantmorph::SpaceCurvePresetCount)
  {
    message << plantmorph::OutOfRange(
      "SpaceCurvePreset", this->SpaceCurvePreset, "[0, " + std::to_string(plantmorph::SpaceCurvePresetCount - 1) + "]");
    return message.str();
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
    plantmorph::CurvatureFamily& k = parameters.curvature;
    k.type = static_cast<plantmorph::CurvatureFamily::Type>(this->CurvatureFunction);
    k.mu = this->CurvatureMu;
    k.lambda = this->CurvatureLambda;
    k.n1 = this->CurvatureN1;
    k.n2 = this->CurvatureN2;
    k.b1 = this->CurvatureB1;
    k.u3 = this->CurvatureU3;
    k.beta = this->CurvatureBeta;
    k.alpha4 = this->CurvatureAlpha4;
    k.lambda2 = this->CurvatureLambda2;
    plantmorph::CurvatureFamily& t = parameters.torsion;
    t.type = static_cast<plantmorph::CurvatureFamily::Type>(this->TorsionFunction);
    t.mu = this->TorsionEta;
    t.lambda = this->TorsionLambda;
    t.n1 = this->TorsionN1;
    t.n2 = this->TorsionN2;
    t.b1 = this->TorsionB1;
    t.u3 = this->TorsionU3;
    t.beta = this->TorsionBeta;
    t.alpha4 = this->TorsionAlpha4;
    t.lambda2 = this->TorsionLambda2;
    parameters.midveinStretchZ = this->MidveinStretchZ;
    parameters.midveinStretchXY = this->MidveinStretchXY;
    parameters.lobes = this->Lobes;
    parameters.lobeStart = this->LobeStart;
    parameters.lobeAngle = this->LobeAngle;
    parameters.lobeScale = this->LobeScale;
    parameters.subLobes = this->SubLobes;
    parameters.subLobeDepth = this->SubLobeDepth;
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
  AddFieldString(fd, "PlantMorph.Model", "SpaceCurve");
  AddFieldString(fd, "PlantMorph.Preset", plantmorph::SpaceCurvePresetName(preset));
  AddFieldValue(fd, "PlantMorph.CurveLength", parameters.length);
  for (const auto& family : { std::make_pair("PlantMorph.Curvature", &parameters.curvature),
         std::make_pair("PlantMorph.Torsion", &parameters.torsion) })
  {
    const plantmorph::CurvatureFamily& f = *family.second;
    vtkNew<vtkDoubleArray> values;
    values->SetName(family.first);
    values->SetNumberOfComponents(10);
    values->SetComponentName(0, "Function");
    values->SetComponentName(1, "Mu");
    values->SetComponentName(2, "Lambda");
    values->SetComponentName(3, "N1");
    values->SetComponentName(4, "N2");
    values->SetComponentName(5, "B1");
    values->SetComponentName(6, "U3");
    values->SetComponentName(7, "Beta");
    values->SetComponentName(8, "Alpha4");
    values->SetComponentName(9, "Lambda2");
    const double tuple[10] = { static_cast<double>(f.type), f.mu, f.lambda, f.n1, f.n2, f.b1, f.u3, f.beta, f.alpha4,
      f.lambda2 };
    values->InsertNextTuple(tuple);
    fd->AddArray(values);
  }
  AddFieldValue(fd, "PlantMorph.Opening", parameters.opening);
  AddFieldValue(fd, "PlantMorph.MidveinStretchZ", parameters.midveinStretchZ);
  AddFieldValue(fd, "PlantMorph.MidveinStretchXY", parameters.midveinStretchXY);
  AddFieldValue(fd, "PlantMorph.InitialAngle", parameters.initialAngle);
  AddFieldValue(fd, "PlantMorph.IntegrationMethod", this->IntegrationMethod);
  AddFieldValue(fd, "PlantMorph.Resolution", this->Resolution);
  AddFieldValue(fd, "PlantMorph.StripColumns", this->StripColumns);
  AddFieldValue(fd, "PlantMorph.Lobes", parameters.lobes);
  if (parameters.lobes > 1)
  {
    AddFieldValue(fd, "PlantMorph.LobeStart", parameters.lobeStart);
    AddFieldValue(fd, "PlantMorph.LobeAngle", parameters.lobeAngle);
    AddFieldValue(fd, "PlantMorph.LobeScale", parameters.lobeScale);
    if (parameters.subLobes > 0) // only then, so blades without sub-lobes keep their field data
    {
      AddFieldValue(fd, "PlantMorph.SubLobes", parameters.subLobes);
      AddFieldValue(fd, "PlantMorph.SubLobeDepth", parameters.subLobeDepth);
    }
    AddFieldValue(fd, "PlantMorph.MeshQuality", this->MeshQuality);
  }
  return {};
}

//------------------------------------------------------------------------------
// Paper 003: the B-spline leaf (Model C).
std::string vtkLeafOutlineSource::BuildBSpline(
  LeafGeometry& leaf, vtkFieldData* fd, double scale, vtkPolyData* controlPoints)
{
  std::ostringstream message;
  // One past the algorithm's presets: the control points come from the input port.
  const int fromInput = plantmorph::BSplinePresetCount;
  if (this->BSplinePreset < 0 || this->BSplinePreset > fromInput)
  {
    message << plantmorph::OutOfRange("BSplinePreset", this->BSplinePreset, "[0, " + std::to_string(fromInput) + "]");
    return message.str();
  }
  const auto preset = static_cast<plantmorph::BSplinePreset>(this->BSplinePreset);
  plantmorph::BSplineLeafParameters parameters;
  std::string source = this->BSplinePreset == fromInput ? "ControlPointsInput" : plantmorph::BSplinePresetName(preset);
  if (this->BSplinePreset == fromInput)
  {
    if (!controlPoints || controlPoints->GetNumberOfLines() == 0)
    {
      return "BSplinePreset 'ControlPoints input' needs polylines connected to the ControlPoints input";
    }
    const std::string inputError = ControlPointsFromPolylines(controlPoints, scale, parameters);
    if (!inputError.empty())
    {
      return "ControlPoints input: " + inputError;
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
    if (!(std::isfinite(this->BladeLength) && this->BladeLength > 0 && this->BladeLength <= 1e6))
    {
      message << plantmorph::OutOfRange("BladeLength", this->BladeLength, "(0, 1e6]");
      return message.str();
    }
    if (!(std::isfinite(this->BladeWidth) && this->BladeWidth > 0 && this->BladeWidth <= 1e6))
    {
      message << plantmorph::OutOfRange("BladeWidth", this->BladeWidth, "(0, 1e6]");
      return message.str();
    }
    if (this->ControlPointCount < 3 || this->ControlPointCount > 1000)
    {
      message << plantmorph::OutOfRange("ControlPointCount", this->ControlPointCount, "[3, 1000]");
      return message.str();
    }
    parameters = plantmorph::MakeBSplinePreset(
      preset, scale * this->BladeLength, scale * this->BladeWidth, this->ControlPointCount);
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
  AddFieldString(fd, "PlantMorph.Model", "BSpline");
  AddFieldString(fd, "PlantMorph.Preset", source);
  AddPointList(fd, "PlantMorph.MidveinPoints", parameters.midvein);
  AddPointList(fd, "PlantMorph.LeftMarginPoints", parameters.leftMargin);
  AddPointList(fd, "PlantMorph.RightMarginPoints", parameters.rightMargin);
  AddFieldValue(fd, "PlantMorph.Resolution", this->Resolution);
  AddFieldValue(fd, "PlantMorph.MeshQuality", this->MeshQuality);
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
