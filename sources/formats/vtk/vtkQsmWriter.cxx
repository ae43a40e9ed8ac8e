// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkQsmWriter.h"

#include "FormatText.h"
#include "QsmTable.h"

#include "PlantMorphLayer.h"
#include "WriterPieces.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkQsmWriter);

namespace
{
/// The whole input gathered on the first rank, which writes the file.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank;

/// The one-component numeric cell array whose normalised name is one of `names`, or null.
vtkDataArray* CellArray(vtkPolyData* input, std::initializer_list<const char*> names)
{
  vtkCellData* cd = input->GetCellData();
  for (const char* wanted : names)
  {
    for (int a = 0; a < cd->GetNumberOfArrays(); ++a)
    {
      vtkDataArray* array = cd->GetArray(a);
      if (array && array->GetName() && array->GetNumberOfComponents() == 1 &&
        plantmorph::NormalName(array->GetName()) == wanted)
      {
        return array;
      }
    }
  }
  return nullptr;
}

double Value(vtkDataArray* array, vtkIdType cell, double otherwise)
{
  return array ? array->GetComponent(cell, 0) : otherwise;
}

/// The cell data a cylinder table keeps as its own columns (not written again as extra columns).
bool Standard(const std::string& name)
{
  static const std::set<std::string> standard = { "id", "cylinderid", "parentid", "parent", "startx", "starty",
    "startz", "endx", "endy", "endz", "axisx", "axisy", "axisz", "radius", "length", "branchid", "branch",
    "branchorder", "depth" };
  return standard.count(plantmorph::NormalName(name)) > 0;
}

/// Every line cell: its point ids (line cells come after the vertex cells in cell numbering).
std::vector<std::vector<vtkIdType>> Lines(vtkPolyData* input)
{
  std::vector<std::vector<vtkIdType>> lines;
  vtkNew<vtkIdList> ids;
  vtkCellArray* cells = input->GetLines();
  for (cells->InitTraversal(); cells->GetNextCell(ids);)
  {
    lines.emplace_back(ids->begin(), ids->end());
  }
  return lines;
}

/// Cylinders of a table as vtkQsmReader makes it (two points per line, parent and (else the row number) ID cell
/// arrays).
std::vector<plantmorph::QsmCylinder> TableCylinders(
  vtkPolyData* input, const std::vector<std::vector<vtkIdType>>& lines, vtkDataArray* id, vtkDataArray* parent)
{
  vtkDataArray* radius = CellArray(input, { "radius" });
  vtkDataArray* pointRadius = input->GetPointData()->GetArray("Radius");
  vtkDataArray* branch = CellArray(input, { "branchid", "branch" });
  vtkDataArray* order = CellArray(input, { "branchorder" });
  const vtkIdType first = input->GetNumberOfVerts();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<plantmorph::QsmCylinder> cylinders;
  for (std::size_t i = 0; i < lines.size(); ++i)
  {
    const vtkIdType cell = first + static_cast<vtkIdType>(i);
    plantmorph::QsmCylinder c;
    c.id = Value(id, cell, static_cast<double>(i + 1));
    c.parent = parent->GetComponent(cell, 0);
    input->GetPoint(lines[i][0], c.start.data());
    input->GetPoint(lines[i][1], c.end.data());
    c.radius = radius ? radius->GetComponent(cell, 0)
      : pointRadius   ? 0.5 * (pointRadius->GetComponent(lines[i][0], 0) + pointRadius->GetComponent(lines[i][1], 0))
                      : nan;
    c.branch = Value(branch, cell, 0.0);
    c.branchOrder = Value(order, cell, 0.0);
    cylinders.push_back(c);
  }
  return cylinders;
}

/// Cylinders of polylines with a Radius point array (each segment one); `lineOf` each cylinder's line.
std::vector<plantmorph::QsmCylinder> SkeletonCylinders(
  vtkPolyData* input, const std::vector<std::vector<vtkIdType>>& lines, std::vector<std::size_t>& lineOf)
{
  vtkDataArray* radius = input->GetPointData()->GetArray("Radius");
  vtkDataArray* branch = CellArray(input, { "branchid" });
  vtkDataArray* parent = CellArray(input, { "parentid" });
  vtkDataArray* order = CellArray(input, { "branchorder", "depth" });
  const vtkIdType first = input->GetNumberOfVerts();
  std::vector<plantmorph::QsmPolyline> polylines(lines.size());
  for (std::size_t i = 0; i < lines.size(); ++i)
  {
    const vtkIdType cell = first + static_cast<vtkIdType>(i);
    plantmorph::QsmPolyline& p = polylines[i];
    p.branchId = Value(branch, cell, static_cast<double>(i));
    p.parentId = Value(parent, cell, std::numeric_limits<double>::quiet_NaN());
    p.order = Value(order, cell, std::numeric_limits<double>::quiet_NaN());
    for (const vtkIdType id : lines[i])
    {
      std::array<double, 3> x;
      input->GetPoint(id, x.data());
      p.points.push_back(x);
      p.radii.push_back(radius->GetComponent(id, 0));
    }
  }
  return plantmorph::CylindersOfPolylines(polylines, lineOf);
}

/// The extra columns: every other one-component numeric cell array, each cylinder its line's value.
void Extras(vtkPolyData* input, const std::vector<std::size_t>& lineOf, std::vector<std::string>& names,
  std::vector<double>& values)
{
  std::vector<vtkDataArray*> arrays;
  vtkCellData* cd = input->GetCellData();
  for (int a = 0; a < cd->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = cd->GetArray(a);
    if (array && array->GetName() && array->GetNumberOfComponents() == 1 && !Standard(array->GetName()))
    {
      arrays.push_back(array);
      names.emplace_back(array->GetName());
    }
  }
  for (const std::size_t line : lineOf)
  {
    for (vtkDataArray* array : arrays)
    {
      values.push_back(array->GetComponent(input->GetNumberOfVerts() + static_cast<vtkIdType>(line), 0));
    }
  }
}
} // namespace

//------------------------------------------------------------------------------
vtkQsmWriter::vtkQsmWriter() = default;

//------------------------------------------------------------------------------
vtkQsmWriter::~vtkQsmWriter()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkQsmWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}

//------------------------------------------------------------------------------
int vtkQsmWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
vtkTypeBool vtkQsmWriter::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (request->Has(vtkStreamingDemandDrivenPipeline::REQUEST_UPDATE_EXTENT()))
  {
    plantmorph::RequestRankPiece(inputVector[0]->GetInformationObject(0));
    return 1;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkQsmWriter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the QSM table", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkQsmWriter::Execute(plantmorph::Run& run)
{
  if (!this->FileName || !*this->FileName)
  {
    run.Fail("FileName is not set: give the CSV file to write");
  }
  vtkPolyData* input = run.Input<vtkPolyData>(0);
  const std::vector<std::vector<vtkIdType>> lines =
    input && input->GetLines() ? Lines(input) : std::vector<std::vector<vtkIdType>>();
  if (lines.empty())
  {
    run.Fail("the input has no lines: write cylinders (QSM Reader's lines) or polylines with a point array Radius");
  }
  vtkDataArray* id = CellArray(input, { "id", "cylinderid" });
  vtkDataArray* parent = CellArray(input, { "parentid", "parent" });
  // A cylinder table: two points per line and a parent column, and cylinder ids or no BranchId (TreeQSM's table
  // has parent but no ID; a skeleton of one-segment branches has BranchId and ParentId, branch ids, not cylinders').
  const bool pairs = std::all_of(lines.begin(), lines.end(), [](const auto& l) { return l.size() == 2; });
  const bool table = pairs && parent && (id || !CellArray(input, { "branchid" }));
  if (!table && !input->GetPointData()->GetArray("Radius"))
  {
    run.Fail("the input's polylines have no point array Radius (and are not a cylinder table: two points per line "
             "with cell arrays ID and parentID)");
  }
  std::vector<std::size_t> lineOf;
  std::vector<plantmorph::QsmCylinder> cylinders;
  if (table)
  {
    cylinders = TableCylinders(input, lines, id, parent);
    for (std::size_t i = 0; i < lines.size(); ++i)
    {
      lineOf.push_back(i);
    }
  }
  else
  {
    cylinders = SkeletonCylinders(input, lines, lineOf);
  }
  std::vector<std::string> names;
  std::vector<double> values;
  Extras(input, lineOf, names, values);
  std::ostringstream text;
  run.Check(plantmorph::WriteQsmTable(text, cylinders, names, values));
  std::ofstream file(this->FileName, std::ios::binary | std::ios::trunc);
  if (!(file << text.str()) || !file.flush())
  {
    run.Fail("FileName '" + std::string(this->FileName) + "' cannot be written");
  }
}
