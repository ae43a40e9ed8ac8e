// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkTrajectoryComparisonFilter.h"

#include "PlantMorphWholeInput.h"
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

#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkTrajectoryComparisonFilter);

namespace
{
constexpr double MaxMonotonePairs = 2e7;

struct Trajectory
{
  std::vector<double> xyz;
  std::vector<double> time; ///< empty when there is none
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

/// Reads x, y, z (and time) from a table's columns or a point set's points. Empty string or an error. `port` is
/// "Measured" or "Simulated"; "auto" columns are looked up among KnownLayouts.
std::string ReadTrajectory(
  vtkDataObject* data, const std::string named[3], const std::string& timeName, const char* port, Trajectory& out)
{
  std::ostringstream message;
  const bool measured = std::string(port) == "Measured";
  const char* inputName = measured ? "Input (measured)" : "Simulated";
  if (auto* points = vtkPointSet::SafeDownCast(data))
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
    return {};
  }
  auto* table = vtkTable::SafeDownCast(data);
  if (!table)
  {
    message << "the " << inputName << " input is missing or is neither a table nor a point set";
    return message.str();
  }
  std::vector<std::string> columns(named, named + 3);
  if (IsAuto(named[0]) && IsAuto(named[1]) && IsAuto(named[2]))
  {
    columns.clear();
    for (const auto& layout : KnownLayouts(measured))
    {
      if (HasNumericColumn(table, layout[0]) && HasNumericColumn(table, layout[1]) &&
        HasNumericColumn(table, layout[2]))
      {
        columns = layout;
        break;
      }
    }
    if (columns.empty())
    {
      message << port << "X/Y/Z: auto found none of the known x, y, z column layouts in the " << inputName
              << " table (";
      const char* separator = "";
      for (const auto& layout : KnownLayouts(measured))
      {
        message << separator << layout[0] << "/" << layout[1] << "/" << layout[2];
        separator = ", ";
      }
      message << "); choose its columns in " << port << "X, " << port << "Y and " << port << "Z (its columns:";
      for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
      {
        message << " '" << (table->GetColumnName(c) ? table->GetColumnName(c) : "") << "'";
      }
      message << ")";
      return message.str();
    }
  }
  vtkDataArray* xyz[3] = { nullptr, nullptr, nullptr };
  for (int k = 0; k < 3; ++k)
  {
    vtkAbstractArray* column = table->GetColumnByName(columns[k].c_str());
    xyz[k] = vtkDataArray::SafeDownCast(column);
    if (!xyz[k] || xyz[k]->GetNumberOfComponents() != 1)
    {
      message << port << "XYZ"[k] << ": the " << inputName << " table has no numeric column '" << columns[k]
              << "' (its columns:";
      for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
      {
        message << " '" << (table->GetColumnName(c) ? table->GetColumnName(c) : "") << "'";
      }
      message << ")";
      return message.str();
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
    index->SetValue(i, static_cast<vtkIdType>(j));
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
int vtkTrajectoryComparisonFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkTable* samples = vtkTable::GetData(outputVector, 0);
  vtkTable* summary = vtkTable::GetData(outputVector, 1);
  samples->Initialize();
  summary->Initialize();
  // Tables (a reader's, which under MPI reads its file by pieces) are gathered whole on rank 0 (collective).
  vtkSmartPointer<vtkDataObject> wholeMeasured = vtkDataObject::GetData(inputVector[0], 0);
  vtkSmartPointer<vtkDataObject> wholeSimulated = vtkDataObject::GetData(inputVector[1], 0);
  if (auto* table = vtkTable::SafeDownCast(wholeMeasured))
  {
    wholeMeasured = plantmorph::GatherRowsOnFirstRank(table);
  }
  if (auto* table = vtkTable::SafeDownCast(wholeSimulated))
  {
    wholeSimulated = plantmorph::GatherRowsOnFirstRank(table);
  }
  vtkDataObject* measuredData = wholeMeasured;
  vtkDataObject* simulatedData = wholeSimulated;
  // Both inputs empty: another MPI rank's share (readers and sources put their data on rank 0), nothing to compare
  // and nothing wrong. A single empty input is still reported below.
  const auto empty = [](vtkDataObject* data) {
    auto* table = vtkTable::SafeDownCast(data);
    auto* points = vtkPointSet::SafeDownCast(data);
    return !data || (table && table->GetNumberOfRows() == 0) || (points && points->GetNumberOfPoints() == 0);
  };
  if (empty(measuredData) && empty(simulatedData))
  {
    if (plantmorph::IsFirstRank())
    {
      vtkWarningMacro(<< "the Input (measured) and Simulated inputs are both empty (no rows or points): nothing to "
                         "compare, the outputs are empty");
    }
    return 1;
  }

  Trajectory measured;
  Trajectory simulated;
  const std::string measuredColumns[3] = { this->GetMeasuredColumn(0), this->GetMeasuredColumn(1),
    this->GetMeasuredColumn(2) };
  const std::string simulatedColumns[3] = { this->GetSimulatedColumn(0), this->GetSimulatedColumn(1),
    this->GetSimulatedColumn(2) };
  std::string error = ReadTrajectory(measuredData, measuredColumns, this->TimeColumn, "Measured", measured);
  if (error.empty())
  {
    error = ReadTrajectory(simulatedData, simulatedColumns, this->TimeColumn, "Simulated", simulated);
  }
  const std::size_t n = measured.xyz.size() / 3;
  const std::size_t m = simulated.xyz.size() / 3;
  plantmorph::TrajectoryComparison comparison;
  if (error.empty())
  {
    comparison = plantmorph::CompareTrajectories(
      measured.xyz.data(), n, simulated.xyz.data(), m, static_cast<std::size_t>(MaxMonotonePairs));
    error = comparison.error.empty() ? "" : "Input (measured) / Simulated: " + comparison.error;
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    samples->Initialize();
    summary->Initialize();
    return 1;
  }
  if (!comparison.hasMonotone)
  {
    vtkWarningMacro(<< "time-monotone matching skipped: it needs at least as many simulated samples (" << m
                    << ") as measured ones (" << n << ") and at most " << MaxMonotonePairs << " pairs");
  }
  this->UpdateProgress(0.8);

  const auto rows = static_cast<vtkIdType>(n);
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
    sample->SetValue(i, i);
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
  AddSummary(summary, fd, "MeasuredSamples", static_cast<double>(n));
  AddSummary(summary, fd, "SimulatedSamples", static_cast<double>(m));
  AddSummary(summary, fd, "ClosestMeanDistance", comparison.closest.meanDistance);
  AddSummary(summary, fd, "ClosestMaxDistance", comparison.closest.maxDistance);
  AddSummary(summary, fd, "ClosestDirectionAngle", comparison.closest.directionAngle);
  if (comparison.hasMonotone)
  {
    WriteMatch(samples, "Monotone", comparison.monotone, simulated);
    AddSummary(summary, fd, "MonotoneMeanDistance", comparison.monotone.meanDistance);
    AddSummary(summary, fd, "MonotoneMaxDistance", comparison.monotone.maxDistance);
    AddSummary(summary, fd, "MonotoneDirectionAngle", comparison.monotone.directionAngle);
  }
  this->UpdateProgress(1.0);
  return 1;
}
