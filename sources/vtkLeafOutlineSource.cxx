#include "vtkLeafOutlineSource.h"

#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"

#include <plantmorph/DataContract.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <sstream>

vtkStandardNewMacro(vtkLeafOutlineSource);

namespace
{
using plantmorph::LeafGeometry;

void AddFieldValue(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

void AddFieldString(vtkFieldData* fd, const char* name, const std::string& value)
{
  vtkNew<vtkStringArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

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
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
void vtkLeafOutlineSource::ClearTerms()
{
  if (!this->Terms.empty())
  {
    this->Terms.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkLeafOutlineSource::AddTerm(double target, double scale, double amplitude, double multiplier,
  double frequency, double variable, double phase)
{
  this->Terms.insert(this->Terms.end(), { target, scale, amplitude, multiplier, frequency, variable, phase });
  this->Modified();
}

//------------------------------------------------------------------------------
int vtkLeafOutlineSource::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    outputVector->GetInformationObject(port)->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkLeafOutlineSource::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* blade = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* outline = vtkPolyData::GetData(outputVector, 1);
  blade->Initialize();
  outline->Initialize();

  // The leaf is one piece: piece 0 makes it, the others stay empty (no duplicates under MPI).
  const int piece =
    outputVector->GetInformationObject(0)->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
  if (piece > 0)
  {
    return 1;
  }

  if (this->Model != DEFORMED_RECTANGLE)
  {
    vtkErrorMacro("Model = " << this->Model << " is not available; accepted: 0 (deformed rectangle)");
    return 1;
  }
  if (this->Preset < 0 || this->Preset >= plantmorph::DeformedRectanglePresetCount)
  {
    vtkErrorMacro("Preset = " << this->Preset << " is outside the accepted range [0, "
                              << plantmorph::DeformedRectanglePresetCount - 1 << "]");
    return 1;
  }
  if (this->MeshQuality != 0 && this->MeshQuality != 1)
  {
    vtkErrorMacro("MeshQuality = " << this->MeshQuality << " is not 0 (paper) or 1 (quality)");
    return 1;
  }
  if (this->MaxVertices < 3)
  {
    vtkErrorMacro("MaxVertices = " << this->MaxVertices << " must be at least 3");
    return 1;
  }

  const auto preset = static_cast<plantmorph::DeformedRectanglePreset>(this->Preset);
  plantmorph::DeformedRectangleParameters parameters =
    plantmorph::MakeDeformedRectanglePreset(preset, this->Length);
  if (preset == plantmorph::DeformedRectanglePreset::Custom)
  {
    parameters.width = this->Width;
    const std::string termError = plantmorph::ParseTerms(this->Terms, parameters.terms);
    if (!termError.empty())
    {
      vtkErrorMacro(<< termError);
      return 1;
    }
  }
  parameters.bending = this->Bending;
  parameters.asymmetry = this->Asymmetry;

  plantmorph::LeafMeshSettings settings;
  settings.resolution = this->Resolution;
  settings.quality = this->MeshQuality == 1;
  settings.maxVertices = static_cast<std::size_t>(this->MaxVertices);
  settings.progress = [this](double fraction) {
    this->UpdateProgress(fraction);
    return !this->GetAbortExecute();
  };

  LeafGeometry leaf;
  const std::string error = plantmorph::BuildDeformedRectangleLeaf(parameters, settings, leaf);
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
  triangles->AllocateExact(static_cast<vtkIdType>(leaf.blade.triangles.size()),
    3 * static_cast<vtkIdType>(leaf.blade.triangles.size()));
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
  for (const std::vector<int>* line : { &leaf.leftMargin, &leaf.rightMargin, &leaf.midvein })
  {
    outlinePoints = std::max<vtkIdType>(outlinePoints, *std::max_element(line->begin(), line->end()) + 1);
  }
  FillPoints(leaf, outlinePoints, outline);
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIntArray> lineRegion;
  lineRegion->SetName(plantmorph::arrays::Region);
  const std::pair<const std::vector<int>*, int> polylines[3] = { { &leaf.leftMargin, plantmorph::RegionMargin },
    { &leaf.rightMargin, plantmorph::RegionMargin }, { &leaf.midvein, plantmorph::RegionMidvein } };
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

  // Parameters as field data on both outputs.
  for (vtkPolyData* output : { blade, outline })
  {
    vtkFieldData* fd = output->GetFieldData();
    AddFieldString(fd, "PlantMorph.Model", "DeformedRectangle");
    AddFieldString(fd, "PlantMorph.Preset", plantmorph::PresetName(preset));
    AddFieldValue(fd, "PlantMorph.Length", parameters.length);
    AddFieldValue(fd, "PlantMorph.Width", parameters.width);
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
}
