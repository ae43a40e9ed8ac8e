// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPlantMorphLASReader.h"

#include "LasFile.h"
#include "PlantMorphLayer.h"

#include "PlantMorphFieldData.h" // VertexCells
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTypeInt16Array.h"
#include "vtkTypeInt32Array.h"
#include "vtkTypeInt64Array.h"
#include "vtkTypeInt8Array.h"
#include "vtkTypeUInt16Array.h"
#include "vtkTypeUInt32Array.h"
#include "vtkTypeUInt64Array.h"
#include "vtkTypeUInt8Array.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

vtkStandardNewMacro(vtkPlantMorphLASReader);

namespace
{
/// Piece p of N reads point records [R p / N, R (p + 1) / N) of the file's R (every rank reads the header): the
/// pieces in rank order are the file's records in order. Under MPI the ranks agree on failures (collective).
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::DataParallel;

template <class ArrayT>
vtkSmartPointer<vtkDataArray> Filled(const plantmorph::LasField& field, vtkIdType n)
{
  using Value = typename ArrayT::ValueType;
  vtkNew<ArrayT> array;
  array->SetName(field.name.c_str());
  array->SetNumberOfComponents(field.components);
  array->SetNumberOfTuples(n);
  Value* out = array->GetPointer(0);
  for (std::size_t i = 0; i < field.values.size(); ++i)
  {
    out[i] = static_cast<Value>(field.values[i]);
  }
  return array.GetPointer();
}

/// The field as an array of its storage type (double when scaled).
vtkSmartPointer<vtkDataArray> MakeArray(const plantmorph::LasField& field, vtkIdType n)
{
  using T = plantmorph::LasType;
  switch (field.scaled ? T::Double : field.type)
  {
    case T::UInt8:
      return Filled<vtkTypeUInt8Array>(field, n);
    case T::Int8:
      return Filled<vtkTypeInt8Array>(field, n);
    case T::UInt16:
      return Filled<vtkTypeUInt16Array>(field, n);
    case T::Int16:
      return Filled<vtkTypeInt16Array>(field, n);
    case T::UInt32:
      return Filled<vtkTypeUInt32Array>(field, n);
    case T::Int32:
      return Filled<vtkTypeInt32Array>(field, n);
    case T::UInt64:
      return Filled<vtkTypeUInt64Array>(field, n);
    case T::Int64:
      return Filled<vtkTypeInt64Array>(field, n);
    case T::Float:
      return Filled<vtkFloatArray>(field, n);
    default:
      return Filled<vtkDoubleArray>(field, n);
  }
}

/// Colors (unsigned char x3) from the RGB field: the values themselves when all are at most 255, else / 257.
vtkSmartPointer<vtkUnsignedCharArray> DisplayColors(const plantmorph::LasField& rgb, vtkIdType n)
{
  const bool wide = std::any_of(rgb.values.begin(), rgb.values.end(), [](double v) { return v > 255; });
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < 3 * n; ++i)
  {
    const double v = rgb.values[static_cast<std::size_t>(i)];
    colors->SetValue(i, static_cast<unsigned char>(wide ? std::min(255.0, std::round(v / 257.0)) : v));
  }
  return colors;
}

/// The cloud as points with a vertex each and its fields as point arrays; each field's values are freed once its
/// array is made, so the peak holds one field twice at most.
void WriteCloud(plantmorph::LasCloud& cloud, vtkPolyData* output)
{
  const auto n = static_cast<vtkIdType>(cloud.Size());
  vtkNew<vtkDoubleArray> xyz;
  xyz->SetNumberOfComponents(3);
  xyz->SetNumberOfTuples(n);
  std::copy(cloud.xyz.begin(), cloud.xyz.end(), xyz->GetPointer(0));
  vtkNew<vtkPoints> points;
  points->SetData(xyz);
  output->SetPoints(points);
  output->SetVerts(plantmorph::VertexCells(n));
  std::vector<double>().swap(cloud.xyz);
  const bool display = !cloud.Find("Colors");
  for (plantmorph::LasField& field : cloud.fields)
  {
    output->GetPointData()->AddArray(MakeArray(field, n));
    if (field.name == "RGB" && field.components == 3 && !field.extra && display)
    {
      output->GetPointData()->SetScalars(DisplayColors(field, n));
    }
    std::vector<double>().swap(field.values);
  }
}

plantmorph::FieldRecord HeaderRecord(const plantmorph::LasHeaderInfo& h, const char* fileName)
{
  plantmorph::FieldRecord record;
  record.Add("SourceFile", std::string(fileName));
  record.Add("LASVersion", std::to_string(h.versionMajor) + "." + std::to_string(h.versionMinor));
  record.Add("LASPointFormat", static_cast<double>(h.pointFormat));
  record.AddTuple("LASScale", { "X", "Y", "Z" }, { h.scale[0], h.scale[1], h.scale[2] });
  record.AddTuple("LASOffset", { "X", "Y", "Z" }, { h.offset[0], h.offset[1], h.offset[2] });
  record.Add("LASSystemIdentifier", h.systemIdentifier);
  record.Add("LASGeneratingSoftware", h.generatingSoftware);
  record.Add("LASGlobalEncoding", static_cast<double>(h.globalEncoding));
  record.Add("LASFileSourceId", static_cast<double>(h.fileSourceId));
  return record;
}
/// This piece's point records of the file `name` (every record serially); "" or the error.
std::string ReadPiece(const std::string& name, const plantmorph::Run& run, plantmorph::LasCloud& cloud)
{
  std::error_code failed;
  if (std::filesystem::is_directory(name, failed))
  {
    return "is a directory, not a LAS file";
  }
  std::ifstream file(name, std::ios::binary | std::ios::ate);
  if (!file)
  {
    return "cannot be opened";
  }
  const auto size = static_cast<std::uint64_t>(std::max<std::streamoff>(0, file.tellg()));
  const std::string extension = name.size() >= 4 ? name.substr(name.size() - 4) : name;
  // Under MPI a read is not stopped on one rank alone (Abort acts serially).
  const std::function<bool(double)> progress = run.Controller() ? std::function<bool(double)>() : run.Progress(0, 0.9);
  std::string error = plantmorph::ReadLas(file, size, cloud, progress, { run.Piece(), run.Pieces() });
  if (!error.empty() && (extension == ".laz" || extension == ".LAZ") && error.find("LAZ") == std::string::npos)
  {
    error += " (a .laz file is LASzip-compressed: decompress it first, laszip -i file.laz -o file.las)";
  }
  return error;
}
} // namespace

//------------------------------------------------------------------------------
vtkPlantMorphLASReader::vtkPlantMorphLASReader()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
vtkPlantMorphLASReader::~vtkPlantMorphLASReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkPlantMorphLASReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}

//------------------------------------------------------------------------------
int vtkPlantMorphLASReader::CanReadFile(const char* name)
{
  std::error_code failed;
  if (!name || std::filesystem::is_directory(name, failed))
  {
    return 0;
  }
  std::ifstream file(name, std::ios::binary);
  return file && plantmorph::LooksLikeLas(file) ? 1 : 0;
}

//------------------------------------------------------------------------------
int vtkPlantMorphLASReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  // Any piece of the file can be read alone (its share of the point records): under MPI each rank reads its own.
  outputVector->GetInformationObject(0)->Set(CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkPlantMorphLASReader::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the LAS point cloud", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkPlantMorphLASReader::Execute(plantmorph::Run& run)
{
  if (!this->FileName || !*this->FileName)
  {
    run.Fail("FileName is not set: give a LAS point-cloud file (.las)");
  }
  const std::string name = this->FileName;
  plantmorph::LasCloud cloud;
  run.Building("the points of '" + name + "'");
  std::string error = ReadPiece(name, run, cloud);
  // Collective under MPI: a failure of every rank (the header's, the same on all) is said once; a piece's own
  // failure (a read stopped, a file that shrank) by the rank that met it; either way every rank stops.
  if (run.AnyRank(!error.empty()))
  {
    error = error.empty() ? error : "FileName '" + name + "', " + error;
    if (!run.AnyRank(error.empty()))
    {
      run.Fail(error);
    }
    run.StopIfAnyRankFailed(true, error);
  }
  vtkPolyData* output = run.Output<vtkPolyData>(0);
  WriteCloud(cloud, output);
  HeaderRecord(cloud.header, this->FileName).WriteTo(output);
  this->UpdateProgress(1.0);
}
