#include "vtkLeafCloudReader.h"

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
enum class LineKind
{
  Skip,
  Data,
  Bad,
};

/// Splits a line into numbers. Skip for blank and comment lines, Bad if a token is not a finite number.
LineKind ParseLine(const std::string& line, std::vector<double>& values)
{
  values.clear();
  std::size_t start = line.find_first_not_of(" \t\r");
  if (start == std::string::npos || line[start] == '#' || line.compare(start, 2, "//") == 0)
  {
    return LineKind::Skip;
  }
  const char* p = line.c_str() + start;
  const char* end = line.c_str() + line.size();
  while (p < end)
  {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r'))
    {
      ++p;
    }
    if (p >= end)
    {
      break;
    }
    char* next = nullptr;
    errno = 0;
    const double v = std::strtod(p, &next);
    if (next == p || !std::isfinite(v))
    {
      return LineKind::Bad;
    }
    values.push_back(v);
    p = next;
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r'))
    {
      ++p;
    }
    if (p < end && (*p == ',' || *p == ';'))
    {
      ++p;
    }
    else if (p < end && !(*(p - 1) == ' ' || *(p - 1) == '\t'))
    {
      return LineKind::Bad; // two numbers glued together, or junk after a number
    }
  }
  return values.empty() ? LineKind::Skip : LineKind::Data;
}

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
  std::ifstream file(name ? name : "");
  std::string line;
  std::vector<double> values;
  for (int lines = 0; lines < 20 && std::getline(file, line); ++lines)
  {
    const LineKind kind = ParseLine(line, values);
    if (kind == LineKind::Data)
    {
      return values.size() >= 3 ? 1 : 0;
    }
  }
  return 0;
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
  std::ifstream file(this->FileName);
  if (!file)
  {
    vtkErrorMacro(<< "FileName '" << this->FileName << "' cannot be opened");
    return 1;
  }

  std::vector<double> values;
  std::vector<double> row;
  std::size_t columns = 0;
  std::string line;
  std::size_t lineNumber = 0;
  bool firstLine = true;
  std::string header;
  while (std::getline(file, line))
  {
    ++lineNumber;
    const LineKind kind = ParseLine(line, row);
    if (kind == LineKind::Skip)
    {
      continue;
    }
    if (kind == LineKind::Bad)
    {
      if (firstLine && columns == 0)
      {
        firstLine = false; // a header line
        header = line;
        continue;
      }
      vtkErrorMacro(<< "FileName '" << this->FileName << "', line " << lineNumber
                    << ": not a list of finite numbers separated by commas, semicolons or spaces: '"
                    << line.substr(0, 80) << "'");
      return 1;
    }
    firstLine = false;
    if (columns == 0)
    {
      columns = row.size();
      if (columns < 3)
      {
        vtkErrorMacro(<< "FileName '" << this->FileName << "', line " << lineNumber << ": " << columns
                      << " column(s); a point needs at least x, y, z");
        return 1;
      }
    }
    else if (row.size() != columns)
    {
      vtkErrorMacro(<< "FileName '" << this->FileName << "', line " << lineNumber << ": " << row.size()
                    << " columns where the first data line has " << columns);
      return 1;
    }
    values.insert(values.end(), row.begin(), row.end());
  }
  if (columns == 0)
  {
    vtkErrorMacro(<< "FileName '" << this->FileName << "' has no data line");
    return 1;
  }

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
  std::vector<std::string> names;
  {
    std::string name;
    for (char c : header + ",")
    {
      if (c == ',' || c == ';' || c == '\t')
      {
        const std::size_t b = name.find_first_not_of(" \r");
        const std::size_t e = name.find_last_not_of(" \r");
        names.push_back(b == std::string::npos ? std::string() : name.substr(b, e - b + 1));
        name.clear();
      }
      else
      {
        name += c;
      }
    }
  }
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
  return 1;
}
