// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkTrajectoryComparisonFilter.h"

#include "PlantMorphLayer.h"
#include "TrajectoryMatching.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkTable.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkTrajectoryComparisonFilter);

namespace
{
constexpr double MaxMonotonePairs = 2e7;

struct Trajectory
{
  std::vector<double> xyz;
  std::vector<double> time;     ///< empty when there is none
  std::vector<std::size_t> row; ///< the input row of each sample once sorted by time; empty: row i is sample i
};

bool IsAuto(const std::string& name)
{
  return name.empty() || name == "auto" || name == "Auto" || name == "AUTO";
}

/// The x, y, z column layouts recognised when the columns are "auto", in order of preference. Measured: the tip
/// table's measured_*, then generic names, then WiltingSimulator's Tip*. Simulated: WiltingSimulator's Trajectory
/// port (Tip*), the tip table's paper_sim_*, then generic names, then measured_*. So a simulated trajectory compared
/// with itself or with data/cucumber-wilting-tip.csv needs no column typed.
const std::vector<std::vector<std::string>>& KnownLayouts(bool measured)
{
  static const std::vector<std::vector<std::string>> forMeasured = { { "measured_x", "measured_y", "measured_z" },
    { "x", "y", "z" }, { "X", "Y", "Z" }, { "TipX", "TipY", "TipZ" }, { "paper_sim_x", "paper_sim_y", "paper_sim_z" },
    { "Points_0", "Points_1", "Points_2" } };
  static const std::vector<std::vector<std::string>> forSimulated = { { "TipX", "TipY", "TipZ" },
    { "paper_sim_x", "paper_sim_y", "paper_sim_z" }, { "x", "y", "z" }, { "X", "Y", "Z" },
    { "Points_0", "Points_1", "Points_2" }, { "measured_x", "measured_y", "measured_z" } };
  return measured ? forMeasured : forSimulated;
}

bool HasNumericColumn(vtkTable* table, const std::string& name)
{
  auto* column = vtkDataArray::SafeDownCast(table->GetColumnByName(name.c_str()));
  return column && column->GetNumberOfComponents() == 1;
}

/// The time column: the one named, or with "auto" the first of time, Time, t present. Empty: none.
std::string TimeColumnOf(vtkTable* table, const std::string& timeName)
{
  if (!IsAuto(timeName))
  {
    return timeName;
  }
  for (const char* name : { "time", "Time", "t" })
  {
    if (HasNumericColumn(table, name))
    {
      return name;
    }
  }
  return {};
}

/// The columns of `table` as " 'a' 'b' ...", for messages.
std::string ColumnList(vtkTable* table)
{
  std::string list;
  for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
  {
    list += " '" + std::string(table->GetColumnName(c) ? table->GetColumnName(c) : "") + "'";
  }
  return list;
}

/// x, y, z (and time, a point array named `timeName` or with "auto" time, Time or t) of a point set's points.
void ReadPointTrajectory(vtkPointSet* points, const std::string& timeName, Trajectory& out)
{
  const vtkIdType n = points->GetNumberOfPoints();
  out.xyz.resize(3 * static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    points->GetPoint(i, out.xyz.data() + 3 * i);
  }
  vtkDataArray* time = IsAuto(timeName) ? nullptr : points->GetPointData()->GetArray(timeName.c_str());
  for (const char* name : { "time", "Time", "t" })
  {
    time = time || !IsAuto(timeName) ? time : points->GetPointData()->GetArray(name);
  }
  if (time && time->GetNumberOfComponents() == 1)
  {
    out.time.resize(static_cast<std::size_t>(n));
    for (vtkIdType i = 0; i < n; ++i)
    {
      out.time[i] = time->GetComponent(i, 0);
    }
  }
}

/// A known layout whose three columns the table has, one of them not numeric (a text column, as ParaView's CSV reader
/// makes of values it cannot parse): the message saying which, else empty.
std::string NonNumericLayout(vtkTable* table, const char* port, const char* inputName, bool measured)
{
  for (const auto& layout : KnownLayouts(measured))
  {
    vtkAbstractArray* columns[3];
    for (int k = 0; k < 3; ++k)
    {
      columns[k] = table->GetColumnByName(layout[static_cast<std::size_t>(k)].c_str());
    }
    if (!columns[0] || !columns[1] || !columns[2])
    {
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      if (!HasNumericColumn(table, layout[static_cast<std::size_t>(k)]))
      {
        return std::string(port) + "X/Y/Z: the " + inputName + " table's column '" +
          layout[static_cast<std::size_t>(k)] + "' is not numeric (a " + columns[k]->GetClassName() + " of " +
          std::to_string(columns[k]->GetNumberOfComponents()) +
          " component(s)): its values are text, e.g. decimal commas or quoted numbers; read the file with Leaf Cloud "
          "Reader or convert that column";
      }
    }
  }
  return {};
}

/// The x, y, z columns to read: the named ones, or with all three "auto" the first known layout the table has.
/// Empty string or an error.
std::string ChooseColumns(vtkTable* table, const std::string named[3], const char* port, const char* inputName,
  bool measured, std::vector<std::string>& columns)
{
  columns.assign(named, named + 3);
  if (!(IsAuto(named[0]) && IsAuto(named[1]) && IsAuto(named[2])))
  {
    return {};
  }
  for (const auto& layout : KnownLayouts(measured))
  {
    if (HasNumericColumn(table, layout[0]) && HasNumericColumn(table, layout[1]) && HasNumericColumn(table, layout[2]))
    {
      columns = layout;
      return {};
    }
  }
  if (std::string nonNumeric = NonNumericLayout(table, port, inputName, measured); !nonNumeric.empty())
  {
    return nonNumeric;
  }
  std::ostringstream message;
  message << port << "X/Y/Z: auto found none of the known x, y, z column layouts in the " << inputName << " table (";
  const char* separator = "";
  for (const auto& layout : KnownLayouts(measured))
  {
    message << separator << layout[0] << "/" << layout[1] << "/" << layout[2];
    separator = ", ";
  }
  message << "); choose its columns in " << port << "X, " << port << "Y and " << port
          << "Z (its columns:" << ColumnList(table) << ")";
  return message.str();
}

/// x, y, z (and time) from a table's columns. Empty string or an error.
std::string ReadTableTrajectory(vtkTable* table, const std::string named[3], const std::string& timeName,
  const char* port, const char* inputName, bool measured, Trajectory& out)
{
  std::vector<std::string> columns;
  const std::string error = ChooseColumns(table, named, port, inputName, measured, columns);
  if (!error.empty())
  {
    return error;
  }
  vtkDataArray* xyz[3] = { nullptr, nullptr, nullptr };
  for (int k = 0; k < 3; ++k)
  {
    xyz[k] = vtkDataArray::SafeDownCast(table->GetColumnByName(columns[k].c_str()));
    if (!xyz[k] || xyz[k]->GetNumberOfComponents() != 1)
    {
      return std::string(port) + "XYZ"[k] + ": the " + inputName + " table has no numeric column '" + columns[k] +
        "' (its columns:" + ColumnList(table) + ")";
    }
  }
  const vtkIdType n = table->GetNumberOfRows();
  out.xyz.resize(3 * static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      out.xyz[3 * i + k] = xyz[k]->GetComponent(i, 0);
    }
  }
  const std::string tableTime = TimeColumnOf(table, timeName);
  vtkDataArray* time =
    tableTime.empty() ? nullptr : vtkDataArray::SafeDownCast(table->GetColumnByName(tableTime.c_str()));
  if (time && time->GetNumberOfComponents() == 1)
  {
    out.time.resize(static_cast<std::size_t>(n));
    for (vtkIdType i = 0; i < n; ++i)
    {
      out.time[i] = time->GetComponent(i, 0);
    }
  }
  return {};
}

/// Reads x, y, z (and time) from a table's columns or a point set's points. Empty string or an error. `port` is
/// "Measured" or "Simulated"; "auto" columns are looked up among KnownLayouts.
std::string ReadTrajectory(
  vtkDataObject* data, const std::string named[3], const std::string& timeName, const char* port, Trajectory& out)
{
  const bool measured = std::string(port) == "Measured";
  const char* inputName = measured ? "Input (measured)" : "Simulated";
  if (auto* points = vtkPointSet::SafeDownCast(data))
  {
    ReadPointTrajectory(points, timeName, out);
    return {};
  }
  auto* table = vtkTable::SafeDownCast(data);
  if (!table)
  {
    return "the " + std::string(inputName) + " input is missing or is neither a table nor a point set";
  }
  return ReadTableTrajectory(table, named, timeName, port, inputName, measured, out);
}

/// The samples of `t` in time order: a stable sort by its time when some row comes before an earlier time (the
/// matchings take the samples in the order given). "" when already in order or without times, else the warning
/// that says it sorted, naming the first row out of order. A time that is not finite is an error in `error`.
std::string SortByTime(Trajectory& t, const char* inputName, std::string& error)
{
  const std::size_t n = t.time.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!std::isfinite(t.time[i]))
    {
      error = "the " + std::string(inputName) + " input's time at row " + std::to_string(i) +
        " is not finite (TimeColumn; rows are numbered from 0)";
      return {};
    }
  }
  std::size_t late = 1;
  while (late < n && t.time[late - 1] <= t.time[late])
    ++late;
  if (late >= n)
    return {};
  std::ostringstream warning;
  warning << "the " << inputName << " input's rows are not in time order (row " << late << ", time " << t.time[late]
          << ", follows row " << late - 1 << ", time " << t.time[late - 1]
          << "; rows numbered from 0): its samples are sorted by time (stable) before matching; the Sample and "
             "Index columns give the input rows";
  t.row.resize(n);
  std::iota(t.row.begin(), t.row.end(), std::size_t{ 0 });
  std::stable_sort(t.row.begin(), t.row.end(), [&](std::size_t a, std::size_t b) { return t.time[a] < t.time[b]; });
  const std::vector<double> xyz = t.xyz, time = t.time;
  for (std::size_t i = 0; i < n; ++i)
  {
    t.time[i] = time[t.row[i]];
    std::copy(xyz.begin() + 3 * t.row[i], xyz.begin() + 3 * t.row[i] + 3, t.xyz.begin() + 3 * i);
  }
  return warning.str();
}

vtkDoubleArray* NewColumn(vtkTable* table, const std::string& name, vtkIdType rows)
{
  vtkNew<vtkDoubleArray> column;
  column->SetName(name.c_str());
  column->SetNumberOfTuples(rows);
  table->AddColumn(column);
  return column;
}

void WriteMatch(
  vtkTable* table, const std::string& prefix, const plantmorph::TrajectoryMatch& match, const Trajectory& simulated)
{
  const auto rows = static_cast<vtkIdType>(match.distance.size());
  vtkNew<vtkIdTypeArray> index;
  index->SetName((prefix + "Index").c_str());
  index->SetNumberOfTuples(rows);
  table->AddColumn(index);
  vtkDoubleArray* time = simulated.time.empty() ? nullptr : NewColumn(table, prefix + "Time", rows);
  vtkDoubleArray* x = NewColumn(table, prefix + "X", rows);
  vtkDoubleArray* y = NewColumn(table, prefix + "Y", rows);
  vtkDoubleArray* z = NewColumn(table, prefix + "Z", rows);
  vtkDoubleArray* d = NewColumn(table, prefix + "Distance", rows);
  vtkDoubleArray* dx = NewColumn(table, prefix + "DX", rows);
  vtkDoubleArray* dy = NewColumn(table, prefix + "DY", rows);
  vtkDoubleArray* dz = NewColumn(table, prefix + "DZ", rows);
  for (vtkIdType i = 0; i < rows; ++i)
  {
    const std::size_t j = match.simulatedIndex[i];
    index->SetValue(i, static_cast<vtkIdType>(simulated.row.empty() ? j : simulated.row[j]));
    if (time)
    {
      time->SetValue(i, simulated.time[j]);
    }
    x->SetValue(i, simulated.xyz[3 * j]);
    y->SetValue(i, simulated.xyz[3 * j + 1]);
    z->SetValue(i, simulated.xyz[3 * j + 2]);
    d->SetValue(i, match.distance[i]);
    dx->SetValue(i, match.delta[3 * i]);
    dy->SetValue(i, match.delta[3 * i + 1]);
    dz->SetValue(i, match.delta[3 * i + 2]);
  }
}

void AddSummary(vtkTable* summary, vtkFieldData* fd, const std::string& name, double value)
{
  NewColumn(summary, name, 1)->SetValue(0, value);
  vtkNew<vtkDoubleArray> a;
  a->SetName(name.c_str());
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}
} // namespace

//------------------------------------------------------------------------------
vtkTrajectoryComparisonFilter::vtkTrajectoryComparisonFilter()
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
void vtkTrajectoryComparisonFilter::SetMeasuredColumns(const char* x, const char* y, const char* z)
{
  const char* names[3] = { x, y, z };
  for (int k = 0; k < 3; ++k)
  {
    this->MeasuredColumns[k] = names[k] ? names[k] : "";
  }
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkTrajectoryComparisonFilter::SetSimulatedColumns(const char* x, const char* y, const char* z)
{
  const char* names[3] = { x, y, z };
  for (int k = 0; k < 3; ++k)
  {
    this->SimulatedColumns[k] = names[k] ? names[k] : "";
  }
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkTrajectoryComparisonFilter::SetColumn(std::string& column, const char* name)
{
  const std::string value = name ? name : "";
  if (value != column)
  {
    column = value;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkTrajectoryComparisonFilter::SetTimeColumn(const char* name)
{
  const std::string value = name ? name : "";
  if (value != this->TimeColumn)
  {
    this->TimeColumn = value;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkTrajectoryComparisonFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MeasuredColumns: " << this->GetMeasuredColumn(0) << " " << this->GetMeasuredColumn(1) << " "
     << this->GetMeasuredColumn(2) << "\n";
  os << indent << "SimulatedColumns: " << this->GetSimulatedColumn(0) << " " << this->GetSimulatedColumn(1) << " "
     << this->GetSimulatedColumn(2) << "\n";
  os << indent << "TimeColumn: " << this->TimeColumn << "\n";
}

//------------------------------------------------------------------------------
int vtkTrajectoryComparisonFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Remove(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE());
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkTable");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

//------------------------------------------------------------------------------
namespace
{
/// Tables (a reader's, which under MPI reads its file by pieces) and point sets are gathered whole on rank 0, which
/// compares them alone.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank;

/// Both inputs empty (no rows or points): nothing to compare and nothing wrong.
bool BothEmpty(vtkDataObject* measured, vtkDataObject* simulated)
{
  const auto empty = [](vtkDataObject* data) {
    auto* table = vtkTable::SafeDownCast(data);
    auto* points = vtkPointSet::SafeDownCast(data);
    return !data || (table && table->GetNumberOfRows() == 0) || (points && points->GetNumberOfPoints() == 0);
  };
  return empty(measured) && empty(simulated);
}

/// Port 0: one row per measured sample with its matches; port 1 (and port 0's field data): the summary.
void WriteComparison(const Trajectory& measured, const Trajectory& simulated,
  const plantmorph::TrajectoryComparison& comparison, vtkTable* samples, vtkTable* summary)
{
  const auto rows = static_cast<vtkIdType>(measured.xyz.size() / 3);
  vtkNew<vtkIdTypeArray> sample;
  sample->SetName("Sample");
  sample->SetNumberOfTuples(rows);
  samples->AddColumn(sample);
  vtkDoubleArray* mx = NewColumn(samples, "MeasuredX", rows);
  vtkDoubleArray* my = NewColumn(samples, "MeasuredY", rows);
  vtkDoubleArray* mz = NewColumn(samples, "MeasuredZ", rows);
  vtkDoubleArray* mt = measured.time.empty() ? nullptr : NewColumn(samples, "MeasuredTime", rows);
  for (vtkIdType i = 0; i < rows; ++i)
  {
    sample->SetValue(i, measured.row.empty() ? i : static_cast<vtkIdType>(measured.row[i]));
    mx->SetValue(i, measured.xyz[3 * i]);
    my->SetValue(i, measured.xyz[3 * i + 1]);
    mz->SetValue(i, measured.xyz[3 * i + 2]);
    if (mt)
    {
      mt->SetValue(i, measured.time[i]);
    }
  }
  WriteMatch(samples, "Closest", comparison.closest, simulated);
  vtkFieldData* fd = samples->GetFieldData();
  AddSummary(summary, fd, "MeasuredSamples", static_cast<double>(rows));
  AddSummary(summary, fd, "SimulatedSamples", static_cast<double>(simulated.xyz.size() / 3));
  AddSummary(summary, fd, "ClosestMeanDistance", comparison.closest.meanDistance);
  AddSummary(summary, fd, "ClosestMaxDistance", comparison.closest.maxDistance);
  // An angle with a direction that is the zero vector (a trajectory that does not move) is left out (Execute warns).
  if (!std::isnan(comparison.closest.directionAngle))
    AddSummary(summary, fd, "ClosestDirectionAngle", comparison.closest.directionAngle);
  if (comparison.hasMonotone)
  {
    WriteMatch(samples, "Monotone", comparison.monotone, simulated);
    AddSummary(summary, fd, "MonotoneMeanDistance", comparison.monotone.meanDistance);
    AddSummary(summary, fd, "MonotoneMaxDistance", comparison.monotone.maxDistance);
    if (!std::isnan(comparison.monotone.directionAngle))
      AddSummary(summary, fd, "MonotoneDirectionAngle", comparison.monotone.directionAngle);
  }
}

/// The warning for the direction angles left out (NaN: a direction that is the zero vector); "" when none is.
std::string UndefinedAngles(const plantmorph::TrajectoryComparison& comparison)
{
  std::string left;
  if (std::isnan(comparison.closest.directionAngle))
    left = "ClosestDirectionAngle";
  if (comparison.hasMonotone && std::isnan(comparison.monotone.directionAngle))
    left += std::string(left.empty() ? "" : " and ") + "MonotoneDirectionAngle";
  if (left.empty())
    return {};
  return left +
    " left out of the summary: the measured trajectory's first and last samples coincide, or those of "
    "the simulated samples matched to them (a trajectory that does not move has no direction)";
}
} // namespace

//------------------------------------------------------------------------------
int vtkTrajectoryComparisonFilter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the trajectory comparison", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkTrajectoryComparisonFilter::Execute(plantmorph::Run& run)
{
  vtkDataObject* measuredData = run.Input(0);
  vtkDataObject* simulatedData = run.Input(1);
  if (BothEmpty(measuredData, simulatedData))
  {
    run.Warn("the Input (measured) and Simulated inputs are both empty (no rows or points): nothing to compare, the "
             "outputs are empty");
    return;
  }
  Trajectory measured;
  Trajectory simulated;
  const std::string measuredColumns[3] = { this->GetMeasuredColumn(0), this->GetMeasuredColumn(1),
    this->GetMeasuredColumn(2) };
  const std::string simulatedColumns[3] = { this->GetSimulatedColumn(0), this->GetSimulatedColumn(1),
    this->GetSimulatedColumn(2) };
  run.Check(ReadTrajectory(measuredData, measuredColumns, this->TimeColumn, "Measured", measured));
  run.Check(ReadTrajectory(simulatedData, simulatedColumns, this->TimeColumn, "Simulated", simulated));
  for (auto* trajectory : { &measured, &simulated })
  {
    std::string error;
    const std::string sorted =
      SortByTime(*trajectory, trajectory == &measured ? "Input (measured)" : "Simulated", error);
    run.Check(error);
    if (!sorted.empty())
      run.Warn(sorted);
  }
  const std::size_t n = measured.xyz.size() / 3;
  const std::size_t m = simulated.xyz.size() / 3;
  const plantmorph::TrajectoryComparison comparison = plantmorph::CompareTrajectories(
    measured.xyz.data(), n, simulated.xyz.data(), m, static_cast<std::size_t>(MaxMonotonePairs));
  if (!comparison.error.empty())
  {
    run.Fail("Input (measured) / Simulated: " + comparison.error);
  }
  if (!comparison.hasMonotone)
  {
    vtkWarningMacro(<< "time-monotone matching skipped: it needs at least as many simulated samples (" << m
                    << ") as measured ones (" << n << ") and at most " << MaxMonotonePairs << " pairs");
  }
  const std::string undefined = UndefinedAngles(comparison);
  if (!undefined.empty())
    run.Warn(undefined);
  this->UpdateProgress(0.8);
  WriteComparison(measured, simulated, comparison, run.Output<vtkTable>(0), run.Output<vtkTable>(1));
  this->UpdateProgress(1.0);
}
