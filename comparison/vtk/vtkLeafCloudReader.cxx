#include "vtkLeafCloudReader.h"

#include "PointCloudText.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkLeafCloudReader);

namespace
{
vtkDoubleArray* NewArray(vtkPolyData* output, const std::string& name, int components, vtkIdType n)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name.c_str());
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(n);
  output->GetPointData()->AddArray(a);
  return a;
}

std::string Lower(std::string text)
{
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

/// The x, y, z columns a header names: x, y, z (any case), else the first prefix P with P_x, P_y, P_z (e.g.
/// measured_x, measured_y, measured_z). False when it names none.
bool NamedCoordinates(const std::vector<std::string>& names, std::size_t xyz[3])
{
  const auto find = [&](const std::string& wanted) {
    for (std::size_t c = 0; c < names.size(); ++c)
    {
      if (Lower(names[c]) == wanted)
      {
        return c;
      }
    }
    return names.size();
  };
  for (std::size_t c = 0; c < names.size(); ++c)
  {
    const std::string name = Lower(names[c]);
    const bool bare = name == "x";
    const bool suffixed = name.size() > 2 && name.compare(name.size() - 2, 2, "_x") == 0;
    if (!bare && !suffixed)
    {
      continue;
    }
    const std::string prefix = name.substr(0, name.size() - 1);
    xyz[0] = c;
    xyz[1] = find(prefix + "y");
    xyz[2] = find(prefix + "z");
    if (xyz[1] < names.size() && xyz[2] < names.size())
    {
      return true;
    }
  }
  return false;
}

/// Columns after x, y, z by position (files without a header naming the columns, or naming x, y, z first):
/// normals, colours, scalars.
void AddPositionalArrays(vtkPolyData* output, const std::vector<double>& values, std::size_t columns, vtkIdType n)
{
  std::size_t next = 3;
  if (columns >= 6)
  {
    vtkDoubleArray* normals = NewArray(output, "Normals", 3, n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        normals->SetTypedComponent(i, k, values[i * columns + 3 + k]);
      }
    }
    output->GetPointData()->SetNormals(normals);
    next = 6;
  }
  if (columns >= 9)
  {
    vtkDoubleArray* rgb = NewArray(output, "RGB", 3, n);
    bool fractions = true;
    for (vtkIdType i = 0; i < n; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        const double v = values[i * columns + 6 + k];
        rgb->SetTypedComponent(i, k, v);
        fractions = fractions && v >= 0.0 && v <= 1.0;
      }
    }
    vtkNew<vtkUnsignedCharArray> colors;
    colors->SetName("Colors");
    colors->SetNumberOfComponents(3);
    colors->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        const double v = rgb->GetTypedComponent(i, k) * (fractions ? 255.0 : 1.0);
        colors->SetTypedComponent(i, k, static_cast<unsigned char>(std::lround(std::clamp(v, 0.0, 255.0))));
      }
    }
    output->GetPointData()->SetScalars(colors);
    next = 9;
  }
  for (std::size_t c = next; c < columns; ++c)
  {
    const std::string name = c == 9 ? std::string("Scalar") : "Column" + std::to_string(c);
    vtkDoubleArray* column = NewArray(output, name, 1, n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      column->SetValue(i, values[i * columns + c]);
    }
  }
}

/// Every column but x, y, z as a point array named by the header (x, y, z named elsewhere than columns 0-2).
void AddNamedArrays(vtkPolyData* output, const std::vector<double>& values, const std::vector<std::string>& names,
  const std::size_t xyz[3], vtkIdType n)
{
  const std::size_t columns = names.size();
  for (std::size_t c = 0; c < columns; ++c)
  {
    if (c == xyz[0] || c == xyz[1] || c == xyz[2])
    {
      continue;
    }
    vtkDoubleArray* column = NewArray(output, names[c].empty() ? "Column" + std::to_string(c) : names[c], 1, n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      column->SetValue(i, values[i * columns + c]);
    }
  }
}
} // namespace

//------------------------------------------------------------------------------
vtkLeafCloudReader::vtkLeafCloudReader()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
int vtkLeafCloudReader::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkPolyData" : "vtkTable");
  return 1;
}

//------------------------------------------------------------------------------
vtkLeafCloudReader::~vtkLeafCloudReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkLeafCloudReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}

//------------------------------------------------------------------------------
int vtkLeafCloudReader::CanReadFile(const char* name)
{
  std::ifstream file(name ? name : "", std::ios::binary);
  return file && plantmorph::LooksLikePointCloudText(file) ? 1 : 0;
}

//------------------------------------------------------------------------------
int vtkLeafCloudReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkTable* table = vtkTable::GetData(outputVector, 1);
  output->Initialize();
  table->Initialize();
  // The file is read whole by piece 0; under MPI the other ranks stay empty, so no point appears twice.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) &&
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) > 0)
  {
    return 1;
  }
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro(<< "FileName is not set: give a leaf point-cloud text file (x, y, z [, nx, ny, nz [, r, g, b]])");
    return 1;
  }
  std::ifstream file(this->FileName, std::ios::binary | std::ios::ate);
  if (!file)
  {
    vtkErrorMacro(<< "FileName '" << this->FileName << "' cannot be opened");
    return 1;
  }
  const auto size = static_cast<double>(std::max<std::streamoff>(1, file.tellg()));
  file.seekg(0);
  plantmorph::PointCloudText cloud;
  const std::string error = plantmorph::ReadPointCloudText(file, cloud, [&](std::uint64_t bytes) {
    this->UpdateProgress(0.9 * static_cast<double>(bytes) / size);
    return !this->CheckAbort();
  });
  if (!error.empty())
  {
    vtkErrorMacro(<< "FileName '" << this->FileName << "', " << error);
    return 1;
  }
  const std::vector<double>& values = cloud.values;
  const std::size_t columns = cloud.columns;
  const auto n = static_cast<vtkIdType>(values.size() / columns);
  // Port 1: every column as a table, named by the header line when it has one name per column.
  std::vector<std::string> names = plantmorph::SplitHeaderNames(cloud.header);
  if (names.size() != columns)
  {
    names.clear();
  }
  for (std::size_t c = 0; c < columns; ++c)
  {
    vtkNew<vtkDoubleArray> column;
    const bool named = !names.empty() && !names[c].empty();
    column->SetName(named ? names[c].c_str() : ("Column" + std::to_string(c)).c_str());
    column->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      column->SetValue(i, values[i * columns + c]);
    }
    table->AddColumn(column);
  }

  // Port 0: the points. A header naming the columns must name x, y, z (or P_x, P_y, P_z): points read by position
  // from a table such as the tip CSV (sample, measured_x, measured_y, ...) would be silently wrong.
  std::size_t xyz[3] = { 0, 1, 2 };
  if (!names.empty() && !NamedCoordinates(names, xyz))
  {
    std::ostringstream list;
    for (const auto& name : names)
    {
      list << (list.tellp() > 0 ? ", " : "") << "'" << name << "'";
    }
    vtkErrorMacro(<< "FileName '" << this->FileName << "': its header names the columns (" << list.str()
                  << ") but none are x, y, z or P_x, P_y, P_z (e.g. measured_x, measured_y, measured_z), so the "
                     "points are not read (output port 0 is empty; port 1 has the table)");
    return 1;
  }
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      coordinates->SetTypedComponent(i, k, values[i * columns + xyz[k]]);
    }
  }
  vtkNew<vtkPoints> points;
  points->SetData(coordinates);
  output->SetPoints(points);
  if (xyz[0] == 0 && xyz[1] == 1 && xyz[2] == 2)
  {
    AddPositionalArrays(output, values, columns, n);
  }
  else
  {
    AddNamedArrays(output, values, names, xyz, n);
  }

  vtkNew<vtkIdTypeArray> offsets;
  vtkNew<vtkIdTypeArray> connectivity;
  offsets->SetNumberOfTuples(n + 1);
  connectivity->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i <= n; ++i)
  {
    offsets->SetValue(i, i);
    if (i < n)
    {
      connectivity->SetValue(i, i);
    }
  }
  vtkNew<vtkCellArray> verts;
  verts->SetData(offsets, connectivity);
  output->SetVerts(verts);

  vtkNew<vtkStringArray> source;
  source->SetName("PlantMorph.SourceFile");
  source->InsertNextValue(this->FileName);
  output->GetFieldData()->AddArray(source);
  this->UpdateProgress(1.0);
  return 1;
}
