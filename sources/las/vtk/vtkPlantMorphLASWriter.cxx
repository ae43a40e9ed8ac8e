// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPlantMorphLASWriter.h"

#include "LasFile.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkErrorCode.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <new>
#include <sstream>

vtkStandardNewMacro(vtkPlantMorphLASWriter);

namespace
{
plantmorph::LasType TypeOf(int vtkType)
{
  using T = plantmorph::LasType;
  switch (vtkType)
  {
    case VTK_CHAR:
    case VTK_SIGNED_CHAR:
      return T::Int8;
    case VTK_UNSIGNED_CHAR:
      return T::UInt8;
    case VTK_SHORT:
      return T::Int16;
    case VTK_UNSIGNED_SHORT:
      return T::UInt16;
    case VTK_INT:
      return T::Int32;
    case VTK_UNSIGNED_INT:
      return T::UInt32;
    case VTK_LONG:
    case VTK_LONG_LONG:
    case VTK_ID_TYPE:
      return sizeof(long) == 4 && vtkType == VTK_LONG ? T::Int32 : T::Int64;
    case VTK_UNSIGNED_LONG:
    case VTK_UNSIGNED_LONG_LONG:
      return sizeof(unsigned long) == 4 && vtkType == VTK_UNSIGNED_LONG ? T::UInt32 : T::UInt64;
    case VTK_FLOAT:
      return T::Float;
    default:
      return T::Double;
  }
}

plantmorph::LasField FieldOf(vtkDataArray* array, const std::string& name, double factor = 1.0, int components = 0)
{
  plantmorph::LasField field;
  field.name = name;
  field.type = TypeOf(array->GetDataType());
  field.components = components > 0 ? components : array->GetNumberOfComponents();
  const vtkIdType n = array->GetNumberOfTuples();
  field.values.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(field.components));
  for (vtkIdType i = 0; i < n; ++i)
  {
    for (int c = 0; c < field.components; ++c)
    {
      field.values[static_cast<std::size_t>(i * field.components + c)] = factor * array->GetComponent(i, c);
    }
  }
  return field;
}

/// The points and numeric point arrays of `input` as a LAS cloud (with the scale and offset its field data keeps).
plantmorph::LasCloud CloudOf(vtkPointSet* input, std::vector<std::string>& skipped)
{
  plantmorph::LasCloud cloud;
  const vtkIdType n = input->GetNumberOfPoints();
  cloud.xyz.resize(static_cast<std::size_t>(3 * n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    input->GetPoint(i, &cloud.xyz[static_cast<std::size_t>(3 * i)]);
  }
  vtkPointData* pd = input->GetPointData();
  vtkDataArray* colors = pd->GetArray("Colors");
  const bool rgbFromColors = !pd->GetArray("RGB") && colors && colors->GetDataType() == VTK_UNSIGNED_CHAR &&
    colors->GetNumberOfComponents() >= 3;
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* abstract = pd->GetAbstractArray(a);
    vtkDataArray* array = vtkDataArray::SafeDownCast(abstract);
    const std::string name = abstract->GetName() ? abstract->GetName() : "Array" + std::to_string(a);
    if (name.rfind("vtk", 0) == 0 || (array == colors && (rgbFromColors || pd->GetArray("RGB"))))
    {
      continue;
    }
    if (!array)
    {
      skipped.push_back(name);
      continue;
    }
    cloud.fields.push_back(FieldOf(array, name));
  }
  if (rgbFromColors)
  {
    plantmorph::LasField rgb = FieldOf(colors, "RGB", 257.0, 3);
    rgb.type = plantmorph::LasType::UInt16;
    cloud.fields.push_back(std::move(rgb));
  }
  // By name: the extra bytes' order does not depend on the order of the arrays (MPI's gathering sorts them).
  std::stable_sort(cloud.fields.begin(), cloud.fields.end(),
    [](const plantmorph::LasField& a, const plantmorph::LasField& b) { return a.name < b.name; });
  vtkFieldData* fd = input->GetFieldData();
  vtkDataArray* scale = fd ? fd->GetArray("PlantMorph.LASScale") : nullptr;
  vtkDataArray* offset = fd ? fd->GetArray("PlantMorph.LASOffset") : nullptr;
  if (scale && offset && scale->GetNumberOfComponents() == 3 && offset->GetNumberOfComponents() == 3 &&
    scale->GetNumberOfTuples() == 1 && offset->GetNumberOfTuples() == 1)
  {
    for (int k = 0; k < 3; ++k)
    {
      cloud.header.scale[static_cast<std::size_t>(k)] = scale->GetComponent(0, k);
      cloud.header.offset[static_cast<std::size_t>(k)] = offset->GetComponent(0, k);
    }
  }
  vtkDataArray* encoding = fd ? fd->GetArray("PlantMorph.LASGlobalEncoding") : nullptr;
  vtkDataArray* source = fd ? fd->GetArray("PlantMorph.LASFileSourceId") : nullptr;
  cloud.header.globalEncoding = encoding ? static_cast<std::uint16_t>(encoding->GetComponent(0, 0)) : 0;
  cloud.header.fileSourceId = source ? static_cast<std::uint16_t>(source->GetComponent(0, 0)) : 0;
  return cloud;
}

std::string Joined(const std::vector<std::string>& names)
{
  std::string text;
  for (const auto& name : names)
  {
    text += (text.empty() ? "" : ", ") + name;
  }
  return text.empty() ? "none" : text;
}
} // namespace

//------------------------------------------------------------------------------
vtkPlantMorphLASWriter::vtkPlantMorphLASWriter() = default;

//------------------------------------------------------------------------------
vtkPlantMorphLASWriter::~vtkPlantMorphLASWriter()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkPlantMorphLASWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "Version: 1." << this->Version << "\n";
  os << indent << "PointFormat: " << this->PointFormat << "\n";
  os << indent << "Scale: " << this->Scale << "\n";
}

//------------------------------------------------------------------------------
int vtkPlantMorphLASWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

//------------------------------------------------------------------------------
void vtkPlantMorphLASWriter::WriteData()
{
  this->Summary.clear();
  vtkPointSet* input = vtkPointSet::SafeDownCast(this->GetInput());
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro("FileName is not set: give the LAS file to write (.las)");
    this->SetErrorCode(vtkErrorCode::NoFileNameError);
    return;
  }
  const std::string name = this->FileName;
  plantmorph::LasWriteOptions options;
  options.versionMinor = this->Version;
  options.pointFormat = this->PointFormat;
  options.scale = this->Scale;
  std::string error = plantmorph::ValidateLasWriteOptions(options);
  std::vector<std::string> skipped;
  plantmorph::LasWriteReport report;
  const std::string partial = name + ".partial";
  try
  {
    const plantmorph::LasCloud cloud = input ? CloudOf(input, skipped) : plantmorph::LasCloud();
    std::ofstream file;
    if (error.empty())
    {
      file.open(partial, std::ios::binary | std::ios::trunc);
      error = file ? plantmorph::WriteLas(file, cloud, options, &report) : "cannot be written";
      file.close();
    }
  }
  catch (const std::bad_alloc&)
  {
    error = "ran out of memory building the LAS records";
  }
  if (error.empty() && std::rename(partial.c_str(), name.c_str()) != 0)
  {
    error = "cannot be written (renaming " + partial + " failed)";
  }
  if (!error.empty())
  {
    std::remove(partial.c_str());
    vtkErrorMacro("FileName '" << name << "', " << error << " (no file written)");
    this->SetErrorCode(vtkErrorCode::CannotOpenFileError);
    return;
  }
  std::ostringstream summary;
  summary << "point format " << report.pointFormat << "; standard: " << Joined(report.standard)
          << "; extra bytes: " << Joined(report.extra) << "; scale: " << report.scale[0] << " " << report.scale[1]
          << " " << report.scale[2] << "; offset: " << report.offset[0] << " " << report.offset[1] << " "
          << report.offset[2];
  this->Summary = summary.str();
  if (!skipped.empty())
  {
    vtkWarningMacro("FileName '" << name << "': arrays that are not numeric are not written: " << Joined(skipped));
  }
}
