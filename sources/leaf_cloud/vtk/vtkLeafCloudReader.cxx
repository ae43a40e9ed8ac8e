// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkLeafCloudReader.h"

#include "PointCloudText.h"

#include "PlantMorphLayer.h"

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
namespace
{
/// Piece p of N reads the lines whose preceding newline lies in bytes [p S / N, (p + 1) S / N) of the file (S
/// bytes): every line once, in file order over the pieces. Under MPI (one piece per rank) the pieces agree on errors,
/// the colour scaling and the line numbers of messages (collective).
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::DataParallel;

/// This piece of the file read into `cloud` (`range`: its byte range and line numbers); "" or the message.
std::string ReadPiece(vtkLeafCloudReader* self, const plantmorph::Run& run, bool& opened,
  plantmorph::PointCloudTextPiece& range, plantmorph::PointCloudText& cloud)
{
  const int piece = run.Piece(), pieces = run.Pieces();
  std::ifstream file(self->GetFileName(), std::ios::binary | std::ios::ate);
  opened = static_cast<bool>(file);
  const std::uint64_t bytes = file ? static_cast<std::uint64_t>(std::max<std::streamoff>(0, file.tellg())) : 0;
  file.seekg(0);
  range.begin = bytes * static_cast<std::uint64_t>(piece) / static_cast<std::uint64_t>(pieces);
  range.end = piece + 1 == pieces ? UINT64_MAX : bytes * static_cast<std::uint64_t>(piece + 1) / pieces;
  const double span = static_cast<double>(std::max<std::uint64_t>(1, std::min(range.end, bytes) - range.begin));
  const bool parallel = run.Controller() != nullptr;
  const auto progress = [&](std::uint64_t done) {
    self->UpdateProgress(0.9 * std::min(1.0, static_cast<double>(done) / span));
    return parallel || !self->CheckAbort(); // under MPI a read is not aborted on one rank alone
  };
  const std::string error = !opened ? std::string("cannot be opened")
    : pieces == 1                   ? plantmorph::ReadPointCloudText(file, cloud, progress)
                                    : plantmorph::ReadPointCloudTextPiece(file, range, cloud, progress);
  if (pieces == 1)
  {
    range.firstNumber = 1;
    range.found = error.empty();
  }
  return error;
}

/// Stops the run when some piece failed (each failure said by the piece that found it, with the file's line number),
/// or when the pieces of one read hold no data line at all.
void StopOnFailure(vtkLeafCloudReader* self, const plantmorph::Run& run, bool opened,
  const plantmorph::PointCloudTextPiece& range, const std::string& error, const PieceSummary& summary)
{
  vtkMultiProcessController* controller = run.Controller();
  if (!summary.failed && !(controller && summary.rows == 0) && !(run.Pieces() > 1 && !controller && !error.empty()))
  {
    return;
  }
  if (!summary.error.empty() || (!controller && !error.empty()))
  {
    const std::string what = summary.error.empty() ? error : summary.error;
    run.FailHere("FileName '" + std::string(self->GetFileName()) + (opened ? "', " : "' ") + what +
      (!controller && !range.errorNumberInFile
          ? " (counted from piece " + std::to_string(run.Piece()) + "'s first line)"
          : std::string()));
  }
  if (!summary.failed)
  {
    run.Fail("FileName '" + std::string(self->GetFileName()) + "', no data line");
  }
  run.Stop(); // another piece failed and said why
}

/// Port 1: every column as a table, named by `names` (one per column) or Column<c>.
void WriteTable(const plantmorph::PointCloudText& cloud, const std::vector<std::string>& names, vtkTable* table)
{
  const std::size_t columns = cloud.columns;
  const auto n = static_cast<vtkIdType>(cloud.values.size() / columns);
  for (std::size_t c = 0; c < columns; ++c)
  {
    vtkNew<vtkDoubleArray> column;
    const bool named = !names.empty() && !names[c].empty();
    column->SetName(named ? names[c].c_str() : ("Column" + std::to_string(c)).c_str());
    column->SetNumberOfTuples(n);
    for (vtkIdType i = 0; i < n; ++i)
    {
      column->SetValue(i, cloud.values[i * columns + c]);
    }
    table->AddColumn(column);
  }
}

/// The error of a header that names the columns but no x, y, z among them.
std::string NoCoordinatesMessage(const char* fileName, const std::vector<std::string>& names)
{
  std::ostringstream list;
  for (const auto& name : names)
  {
    list << (list.tellp() > 0 ? ", " : "") << "'" << name << "'";
  }
  return "FileName '" + std::string(fileName) + "': its header names the columns (" + list.str() +
    ") but none are x, y, z or P_x, P_y, P_z (e.g. measured_x, measured_y, measured_z), so the points are not read "
    "(output port 0 is empty; port 1 has the table)";
}

/// Port 0: the points (columns `xyz`), one vertex each, and the other columns as point arrays.
void WritePoints(const plantmorph::PointCloudText& cloud, const std::vector<std::string>& names,
  const std::size_t xyz[3], bool fractions, vtkPolyData* output)
{
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
      coordinates->SetTypedComponent(i, k, values[i * columns + xyz[k]]);
    }
  }
  vtkNew<vtkPoints> points;
  points->SetData(coordinates);
  output->SetPoints(points);
  if (xyz[0] == 0 && xyz[1] == 1 && xyz[2] == 2)
  {
    AddPositionalArrays(output, values, columns, n, fractions);
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
}
} // namespace

//------------------------------------------------------------------------------
int vtkLeafCloudReader::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the point cloud", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkLeafCloudReader::Execute(plantmorph::Run& run)
{
  if (!this->FileName || !*this->FileName)
  {
    run.Fail("FileName is not set: give a leaf point-cloud text file (x, y, z [, nx, ny, nz [, r, g, b]])");
  }
  bool opened = false;
  plantmorph::PointCloudText cloud;
  plantmorph::PointCloudTextPiece range;
  const std::string error = ReadPiece(this, run, opened, range, cloud);
  const PieceSummary summary = Summarize(run.Controller(), range, error, cloud);
  StopOnFailure(this, run, opened, range, error, summary);
  if (cloud.columns == 0)
  {
    return; // a piece before the file's first data line: nothing of its own
  }
  std::vector<std::string> names = plantmorph::SplitHeaderNames(cloud.header);
  if (names.size() != cloud.columns)
  {
    names.clear();
  }
  WriteTable(cloud, names, run.Output<vtkTable>(1));
  // A header naming the columns must name x, y, z (or P_x, P_y, P_z): points read by position from a table such as
  // the tip CSV (sample, measured_x, measured_y, ...) would be silently wrong.
  std::size_t xyz[3] = { 0, 1, 2 };
  if (!names.empty() && !NamedCoordinates(names, xyz))
  {
    run.Error(NoCoordinatesMessage(this->FileName, names));
    return;
  }
  vtkPolyData* output = run.Output<vtkPolyData>(0);
  WritePoints(cloud, names, xyz, summary.fractions, output);
  plantmorph::FieldRecord record;
  record.Add("SourceFile", std::string(this->FileName));
  record.WriteTo(output);
  this->UpdateProgress(1.0);
}
