// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkLeafCloudReader.h"

#include "PointCloudText.h"

#include "vtkCellArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
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
void AddPositionalArrays(
  vtkPolyData* output, const std::vector<double>& values, std::size_t columns, vtkIdType n, bool fractions)
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
    for (vtkIdType i = 0; i < n; ++i)
    {
      for (int k = 0; k < 3; ++k)
      {
        rgb->SetTypedComponent(i, k, values[i * columns + 6 + k]);
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

/// Whether the colour columns (6-8) are all within [0, 1] (fractions, scaled by 255), on this piece.
bool ColourFractions(const std::vector<double>& values, std::size_t columns)
{
  for (std::size_t i = 0; columns >= 9 && i < values.size(); i += columns)
  {
    for (std::size_t k = 6; k < 9; ++k)
    {
      if (!(values[i + k] >= 0.0 && values[i + k] <= 1.0))
      {
        return false;
      }
    }
  }
  return true;
}

/// What the pieces of one read tell each other (MPI: one piece per rank, collective), in rank order.
struct PieceSummary
{
  bool failed = false;         ///< some piece failed: every piece's output empty
  std::string error;           ///< this piece's message (with the file's line number) when it is the first to fail
  unsigned long long rows = 0; ///< data lines of all pieces
  bool fractions = true;       ///< colours all within [0, 1] on every piece
};

PieceSummary Summarize(vtkMultiProcessController* controller, const plantmorph::PointCloudTextPiece& piece,
  const std::string& error, const plantmorph::PointCloudText& cloud)
{
  PieceSummary summary;
  const unsigned long long mine[6] = { error.empty() ? 0ULL : 1ULL, cloud.Rows(), piece.lines, piece.firstNumber,
    piece.errorNumber, piece.errorNumberInFile || error.empty() ? 1ULL : 0ULL };
  const int ranks = controller ? controller->GetNumberOfProcesses() : 1;
  const int me = controller ? controller->GetLocalProcessId() : 0;
  std::vector<unsigned long long> all(mine, mine + 6);
  all.resize(6 * static_cast<std::size_t>(ranks));
  if (controller)
  {
    controller->AllGather(mine, all.data(), 6);
  }
  unsigned long long number = 1; // the file's number of each piece's first line, pieces in order
  for (int q = 0; q < ranks; ++q)
  {
    const unsigned long long* r = &all[6 * static_cast<std::size_t>(q)];
    number = r[3] ? r[3] : number;
    if (r[0] && !summary.failed)
    {
      summary.failed = true;
      if (q == me)
      {
        const unsigned long long line = r[5] ? r[4] : number - 1 + r[4];
        summary.error =
          r[5] || piece.errorWhat.empty() ? error : "line " + std::to_string(line) + ": " + piece.errorWhat;
      }
    }
    summary.rows += r[1];
    number += r[2];
  }
  int fractions = ColourFractions(cloud.values, cloud.columns) ? 1 : 0, all01 = fractions;
  if (controller)
  {
    controller->AllReduce(&fractions, &all01, 1, vtkCommunicator::MIN_OP);
  }
  summary.fractions = all01 != 0;
  return summary;
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
int vtkLeafCloudReader::RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  // Any piece of the file can be read alone (its byte range): under MPI each rank reads its own.
  outputVector->GetInformationObject(0)->Set(CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkLeafCloudReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkTable* table = vtkTable::GetData(outputVector, 1);
  output->Initialize();
  table->Initialize();
  // Piece p of N reads the lines whose preceding newline lies in bytes [p S / N, (p + 1) S / N) of the file (S
  // bytes): every line once, in file order over the pieces. Under MPI (one piece per rank) the pieces agree on
  // errors, the colour scaling and the line numbers of messages (collective).
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int piece = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    : 0;
  const int pieces = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    ? std::max(1, outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()))
    : 1;
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!controller || pieces < 2 || controller->GetNumberOfProcesses() != pieces ||
    controller->GetLocalProcessId() != piece)
  {
    controller = nullptr; // pieces read in one process (or serial): each piece alone
  }
  const bool first = piece == 0;
  // Only errors every piece finds alike are said by the first piece alone.
  const bool say = first || !controller;
  if (!this->FileName || !*this->FileName)
  {
    if (say)
    {
      vtkErrorMacro(<< "FileName is not set: give a leaf point-cloud text file (x, y, z [, nx, ny, nz [, r, g, b]])");
    }
    return 1;
  }
  std::ifstream file(this->FileName, std::ios::binary | std::ios::ate);
  const bool opened = static_cast<bool>(file);
  const std::uint64_t bytes = file ? static_cast<std::uint64_t>(std::max<std::streamoff>(0, file.tellg())) : 0;
  file.seekg(0);
  plantmorph::PointCloudText cloud;
  plantmorph::PointCloudTextPiece range;
  range.begin = bytes * static_cast<std::uint64_t>(piece) / static_cast<std::uint64_t>(pieces);
  range.end = piece + 1 == pieces ? UINT64_MAX : bytes * static_cast<std::uint64_t>(piece + 1) / pieces;
  const double span = static_cast<double>(std::max<std::uint64_t>(1, std::min(range.end, bytes) - range.begin));
  const auto progress = [&](std::uint64_t done) {
    this->UpdateProgress(0.9 * std::min(1.0, static_cast<double>(done) / span));
    return controller || !this->CheckAbort(); // under MPI a read is not aborted on one rank alone
  };
  std::string error = !opened ? std::string("cannot be opened")
    : pieces == 1             ? plantmorph::ReadPointCloudText(file, cloud, progress)
                              : plantmorph::ReadPointCloudTextPiece(file, range, cloud, progress);
  if (pieces == 1)
  {
    range.firstNumber = 1;
    range.found = error.empty();
  }
  const PieceSummary summary = Summarize(controller, range, error, cloud);
  if (summary.failed || (controller && summary.rows == 0) || (pieces > 1 && !controller && !error.empty()))
  {
    if (!summary.error.empty() || (!controller && !error.empty()))
    {
      const std::string what = summary.error.empty() ? error : summary.error;
      vtkErrorMacro(<< "FileName '" << this->FileName << (opened ? "', " : "' ") << what
                    << (!controller && !range.errorNumberInFile
                           ? " (counted from piece " + std::to_string(piece) + "'s first line)"
                           : std::string()));
    }
    else if (!summary.failed && first)
    {
      vtkErrorMacro(<< "FileName '" << this->FileName << "', no data line");
    }
    return 1;
  }
  const std::vector<double>& values = cloud.values;
  const std::size_t columns = cloud.columns;
  if (columns == 0)
  {
    return 1; // a piece before the file's first data line: nothing of its own
  }
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
    if (say)
    {
      vtkErrorMacro(<< "FileName '" << this->FileName << "': its header names the columns (" << list.str()
                    << ") but none are x, y, z or P_x, P_y, P_z (e.g. measured_x, measured_y, measured_z), so the "
                       "points are not read (output port 0 is empty; port 1 has the table)");
    }
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
    AddPositionalArrays(output, values, columns, n, summary.fractions);
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
