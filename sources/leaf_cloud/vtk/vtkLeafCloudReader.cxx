// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkLeafCloudReader.h"

#include "PointCloudText.h"

#include "PlantMorphLayer.h"

#include "PlantMorphFieldData.h" // VertexCells
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
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
#include <array>
#include <filesystem>
#include <initializer_list>
#include <limits>
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
/// measured_x, measured_y, measured_z; not normal_ or n_, the normals). False when it names none.
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
  xyz[0] = find("x"), xyz[1] = find("y"), xyz[2] = find("z");
  if (xyz[0] < names.size() && xyz[1] < names.size() && xyz[2] < names.size())
  {
    return true;
  }
  for (std::size_t c = 0; c < names.size(); ++c)
  {
    const std::string name = Lower(names[c]);
    const bool suffixed = name.size() > 2 && name.compare(name.size() - 2, 2, "_x") == 0;
    if (!suffixed || name == "normal_x" || name == "n_x")
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

/// Which column is what: the header's names, or the positional layout of files without one.
struct ColumnLayout
{
  static constexpr std::size_t None = std::numeric_limits<std::size_t>::max();
  std::vector<std::string> names; ///< one per column, or empty (no header naming every column)
  std::size_t xyz[3] = { 0, 1, 2 };
  std::size_t normals[3] = { None, None, None };
  std::size_t rgb[3] = { None, None, None };
  bool coordinatesFound = true;
};

/// The first triple of `names` (lower case) that names three columns, in `found`; false when none does.
bool NamedTriple(const std::vector<std::string>& names, std::initializer_list<std::array<const char*, 3>> triples,
  std::size_t found[3])
{
  for (const auto& triple : triples)
  {
    std::size_t at[3];
    for (int k = 0; k < 3; ++k)
    {
      at[k] = std::find(names.begin(), names.end(), triple[static_cast<std::size_t>(k)]) - names.begin();
    }
    if (at[0] < names.size() && at[1] < names.size() && at[2] < names.size())
    {
      std::copy(at, at + 3, found);
      return true;
    }
  }
  return false;
}

/// The layout: by the header's names when it names every column (x, y, z in any order; r, g, b or red, green, blue
/// the colours; nx, ny, nz or normal_x, normal_y, normal_z the normals; any other name its own array), else by
/// position (x, y, z, normals, colours).
ColumnLayout LayoutOf(const plantmorph::PointCloudText& cloud)
{
  ColumnLayout layout;
  layout.names = plantmorph::SplitHeaderNames(cloud.header);
  if (layout.names.size() != cloud.columns)
  {
    layout.names.clear();
  }
  if (layout.names.empty())
  {
    for (std::size_t k = 0; k < 3; ++k)
    {
      layout.normals[k] = cloud.columns >= 6 ? 3 + k : ColumnLayout::None;
      layout.rgb[k] = cloud.columns >= 9 ? 6 + k : ColumnLayout::None;
    }
    return layout;
  }
  std::vector<std::string> lower;
  for (const auto& name : layout.names)
  {
    lower.push_back(Lower(name));
  }
  layout.coordinatesFound = NamedCoordinates(layout.names, layout.xyz);
  NamedTriple(lower, { { "r", "g", "b" }, { "red", "green", "blue" } }, layout.rgb);
  NamedTriple(lower,
    { { "nx", "ny", "nz" }, { "normal_x", "normal_y", "normal_z" }, { "normalx", "normaly", "normalz" },
      { "n_x", "n_y", "n_z" } },
    layout.normals);
  return layout;
}

/// A point array of the columns `at` (1 or 3 components).
vtkDoubleArray* AddColumns(vtkPolyData* output, const std::vector<double>& values, std::size_t columns,
  const std::string& name, const std::size_t* at, int components, vtkIdType n)
{
  vtkDoubleArray* array = NewArray(output, name, components, n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    for (int k = 0; k < components; ++k)
    {
      array->SetTypedComponent(i, k, values[static_cast<std::size_t>(i) * columns + at[k]]);
    }
  }
  return array;
}

/// `RGB` (the file's values) and `Colors` (unsigned char, the active scalars; fractions scaled by 255).
void AddColours(vtkPolyData* output, const std::vector<double>& values, std::size_t columns, const std::size_t rgb[3],
  vtkIdType n, bool fractions)
{
  vtkDoubleArray* file = AddColumns(output, values, columns, "RGB", rgb, 3, n);
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      const double v = file->GetTypedComponent(i, k) * (fractions ? 255.0 : 1.0);
      colors->SetTypedComponent(i, k, static_cast<unsigned char>(std::lround(std::clamp(v, 0.0, 255.0))));
    }
  }
  output->GetPointData()->SetScalars(colors);
}

/// Every column but x, y, z as point arrays: normals and colours as the layout says, the others by name (the
/// header's, else Column<c>; the unnamed tenth column of the scans `Scalar`).
void AddArrays(vtkPolyData* output, const std::vector<double>& values, const ColumnLayout& layout, std::size_t columns,
  vtkIdType n, bool fractions)
{
  if (layout.normals[0] != ColumnLayout::None)
  {
    output->GetPointData()->SetNormals(AddColumns(output, values, columns, "Normals", layout.normals, 3, n));
  }
  if (layout.rgb[0] != ColumnLayout::None)
  {
    AddColours(output, values, columns, layout.rgb, n, fractions);
  }
  const auto used = [&](std::size_t c) {
    for (const std::size_t* triple : { layout.xyz, layout.normals, layout.rgb })
    {
      if (c == triple[0] || c == triple[1] || c == triple[2])
      {
        return true;
      }
    }
    return false;
  };
  for (std::size_t c = 0; c < columns; ++c)
  {
    if (!used(c))
    {
      const bool named = !layout.names.empty() && !layout.names[c].empty();
      const std::string name = named     ? layout.names[c]
        : c == 9 && layout.names.empty() ? std::string("Scalar")
                                         : "Column" + std::to_string(c);
      AddColumns(output, values, columns, name, &c, 1, n);
    }
  }
}

/// Whether the colour columns are all within [0, 1] (fractions, scaled by 255), on this piece.
bool ColourFractions(const std::vector<double>& values, std::size_t columns, const std::size_t rgb[3])
{
  for (std::size_t i = 0; rgb[0] != ColumnLayout::None && i < values.size(); i += columns)
  {
    for (std::size_t k = 0; k < 3; ++k)
    {
      if (!(values[i + rgb[k]] >= 0.0 && values[i + rgb[k]] <= 1.0))
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
  const std::string& error, const plantmorph::PointCloudText& cloud, const ColumnLayout& layout)
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
  int fractions = ColourFractions(cloud.values, cloud.columns, layout.rgb) ? 1 : 0, all01 = fractions;
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
  std::error_code failed;
  if (!name || std::filesystem::is_directory(name, failed))
  {
    return 0;
  }
  std::ifstream file(name, std::ios::binary);
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
  std::error_code failed;
  const bool directory = std::filesystem::is_directory(self->GetFileName(), failed);
  std::ifstream file(self->GetFileName(), std::ios::binary | std::ios::ate);
  opened = static_cast<bool>(file) && !directory;
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
  const std::string error = directory ? std::string("is a directory, not a point-cloud text file")
    : !opened                         ? std::string("cannot be opened")
    : pieces == 1                     ? plantmorph::ReadPointCloudText(file, cloud, progress)
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
void WritePoints(
  const plantmorph::PointCloudText& cloud, const ColumnLayout& layout, bool fractions, vtkPolyData* output)
{
  const std::size_t* xyz = layout.xyz;
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
  AddArrays(output, values, layout, columns, n, fractions);
  output->SetVerts(plantmorph::VertexCells(n));
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
  const ColumnLayout layout = LayoutOf(cloud);
  const PieceSummary summary = Summarize(run.Controller(), range, error, cloud, layout);
  StopOnFailure(this, run, opened, range, error, summary);
  if (cloud.columns == 0)
  {
    return; // a piece before the file's first data line: nothing of its own
  }
  WriteTable(cloud, layout.names, run.Output<vtkTable>(1));
  // A header naming the columns must name x, y, z (or P_x, P_y, P_z): points read by position from a table such as
  // the tip CSV (sample, measured_x, measured_y, ...) would be silently wrong.
  if (!layout.coordinatesFound)
  {
    run.Error(NoCoordinatesMessage(this->FileName, layout.names));
    return;
  }
  vtkPolyData* output = run.Output<vtkPolyData>(0);
  WritePoints(cloud, layout, summary.fractions, output);
  plantmorph::FieldRecord record;
  record.Add("SourceFile", std::string(this->FileName));
  record.WriteTo(output);
  this->UpdateProgress(1.0);
}
