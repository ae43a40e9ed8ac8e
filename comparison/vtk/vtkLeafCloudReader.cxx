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
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      coordinates->SetTypedComponent(i, k, values[i * columns + k]);
    }
  }
  vtkNew<vtkPoints> points;
  points->SetData(coordinates);
  output->SetPoints(points);

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

  // Port 1: every column as a table, named by the header line when it has one name per column.
  const std::vector<std::string> names = plantmorph::SplitHeaderNames(cloud.header);
  for (std::size_t c = 0; c < columns; ++c)
  {
    vtkNew<vtkDoubleArray> column;
    const bool named = names.size() == columns && !names[c].empty();
    column->SetName(named ? names[c].c_str() : ("Column" + std::to_string(c)).c_str());
    column->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      column->SetValue(i, values[i * columns + c]);
    }
    table->AddColumn(column);
  }

  vtkNew<vtkStringArray> source;
  source->SetName("PlantMorph.SourceFile");
  source->InsertNextValue(this->FileName);
  output->GetFieldData()->AddArray(source);
  this->UpdateProgress(1.0);
  return 1;
}
