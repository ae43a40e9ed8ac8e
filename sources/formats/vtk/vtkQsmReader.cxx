// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkQsmReader.h"

#include "FormatText.h"
#include "QsmTable.h"

#include "PlantMorphLayer.h"

#include <plantmorph/RangeError.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkQsmReader);

namespace
{
/// The cylinders are made whole on the first rank (a QSM is thousands of cylinders).
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank;

/// Every column as a cell array (repeated names suffixed _2, _3, ...).
void AddColumns(const plantmorph::QsmTable& t, vtkCellData* cd)
{
  std::map<std::string, int> used;
  const auto rows = static_cast<vtkIdType>(t.Rows());
  for (std::size_t c = 0; c < t.columns; ++c)
  {
    const int seen = ++used[t.names[c]];
    const std::string name = seen == 1 ? t.names[c] : t.names[c] + "_" + std::to_string(seen);
    vtkNew<vtkDoubleArray> column;
    column->SetName(name.c_str());
    column->SetNumberOfTuples(rows);
    for (vtkIdType r = 0; r < rows; ++r)
    {
      column->SetValue(r, t.values[static_cast<std::size_t>(r) * t.columns + c]);
    }
    cd->AddArray(column);
  }
}

/// One line per cylinder, or one closed tube of `sides` sides (its quads and caps one cell each).
void WriteCylinders(const plantmorph::QsmTable& t, bool tubes, int sides, vtkPolyData* out)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> radius;
  radius->SetName("Radius");
  vtkNew<vtkCellArray> cells;
  std::vector<std::array<double, 3>> ring;
  std::vector<long long> polygons;
  for (std::size_t i = 0; i < t.Rows(); ++i)
  {
    ring.clear();
    polygons.clear();
    if (tubes)
    {
      plantmorph::CylinderTube(t.start[i], t.end[i], t.radius[i], sides, points->GetNumberOfPoints(), ring, polygons);
    }
    else
    {
      ring = { t.start[i], t.end[i] };
      polygons = { 2, points->GetNumberOfPoints(), points->GetNumberOfPoints() + 1 };
    }
    for (const auto& p : ring)
    {
      points->InsertNextPoint(p.data());
      radius->InsertNextValue(t.radius[i]);
    }
    // One cell per line, or per face of a tube (Sides quads and two caps: Repeated gives each its cylinder's row).
    for (std::size_t k = 0; k < polygons.size(); k += static_cast<std::size_t>(polygons[k]) + 1)
    {
      cells->InsertNextCell(static_cast<vtkIdType>(polygons[k]));
      for (long long j = 0; j < polygons[k]; ++j)
      {
        cells->InsertCellPoint(static_cast<vtkIdType>(polygons[k + 1 + static_cast<std::size_t>(j)]));
      }
    }
  }
  out->SetPoints(points);
  out->GetPointData()->AddArray(radius);
  out->GetPointData()->SetActiveScalars("Radius");
  if (tubes)
  {
    out->SetPolys(cells);
  }
  else
  {
    out->SetLines(cells);
  }
}

/// The table with each row repeated `times` times (a tube's faces share their cylinder's values).
plantmorph::QsmTable Repeated(const plantmorph::QsmTable& t, std::size_t times)
{
  plantmorph::QsmTable r;
  r.names = t.names;
  r.columns = t.columns;
  for (std::size_t i = 0; i < t.Rows(); ++i)
  {
    for (std::size_t k = 0; k < times; ++k)
    {
      r.values.insert(r.values.end(), t.values.begin() + static_cast<std::ptrdiff_t>(i * t.columns),
        t.values.begin() + static_cast<std::ptrdiff_t>((i + 1) * t.columns));
    }
  }
  return r;
}
} // namespace

//------------------------------------------------------------------------------
vtkQsmReader::vtkQsmReader()
{
  this->SetNumberOfInputPorts(0);
}

//------------------------------------------------------------------------------
vtkQsmReader::~vtkQsmReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkQsmReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "Tubes: " << this->Tubes << "\n";
  os << indent << "Sides: " << this->Sides << "\n";
}

//------------------------------------------------------------------------------
int vtkQsmReader::CanReadFile(const char* name)
{
  std::error_code failed;
  if (!name || std::filesystem::is_directory(name, failed))
  {
    return 0;
  }
  // The first 20 lines only (at most 64 KiB each): File > Open asks every reader of .txt and .csv files.
  std::ifstream file(name, std::ios::binary);
  plantmorph::LineReader lines(file, plantmorph::kMaxQsmLineLength);
  std::string head, line;
  for (int k = 0; k < 20 && lines.Next(line); ++k)
  {
    head += line + "\n";
  }
  std::istringstream start(head);
  plantmorph::QsmTable table;
  return plantmorph::ReadQsmTable(start, table).empty() ? 1 : 0;
}

//------------------------------------------------------------------------------
int vtkQsmReader::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the QSM cylinders", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkQsmReader::Execute(plantmorph::Run& run)
{
  run.Check(plantmorph::CheckRange(this->Tubes == 0 || this->Tubes == 1, "Tubes", this->Tubes, "{0, 1}"));
  run.Check(plantmorph::CheckRange(this->Sides >= 3 && this->Sides <= 256, "Sides", this->Sides, "[3, 256]"));
  if (!this->FileName || !*this->FileName)
  {
    run.Fail("FileName is not set: give a QSM cylinder table (TreeQSM text or SimpleForest / rTwig CSV)");
  }
  const std::string name = this->FileName;
  std::error_code failed;
  std::ifstream file(name, std::ios::binary);
  if (std::filesystem::is_directory(name, failed) || !file)
  {
    run.Fail("FileName '" + name + "' cannot be opened as a file");
  }
  plantmorph::QsmTable table;
  run.Building("the cylinder table of '" + name + "'");
  const std::string error = plantmorph::ReadQsmTable(file, table);
  if (!error.empty())
  {
    run.Fail("FileName '" + name + "', " + error);
  }
  vtkPolyData* output = run.Output<vtkPolyData>(0);
  WriteCylinders(table, this->Tubes != 0, this->Sides, output);
  AddColumns(this->Tubes ? Repeated(table, static_cast<std::size_t>(this->Sides) + 2) : table, output->GetCellData());
  plantmorph::FieldRecord record;
  record.Add("SourceFile", name);
  record.WriteTo(output);
}
