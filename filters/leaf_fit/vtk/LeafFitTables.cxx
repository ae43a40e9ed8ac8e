// SPDX-License-Identifier: GPL-3.0-or-later
#include "LeafFitTables.h"

#include "LeafAreaEstimate.h"
#include "LeafFit.h"
#include "LeafPlant.h"
#include <plantmorph/DataContract.h>

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTypeInt64Array.h"

#include <algorithm>
#include <limits>

namespace plantmorph
{
namespace fittable
{
namespace
{
template <typename T>
std::string ReadTyped(vtkDataArray* array, const std::string& name, std::vector<std::int64_t>& ids)
{
  const vtkIdType n = array->GetNumberOfTuples();
  ids.resize(static_cast<std::size_t>(n));
  const T* values = static_cast<const T*>(array->GetVoidPointer(0)); // one component: contiguous
  for (vtkIdType i = 0; i < n; ++i)
  {
    if constexpr (std::numeric_limits<T>::is_integer)
    {
      if constexpr (!std::numeric_limits<T>::is_signed && sizeof(T) >= sizeof(std::int64_t))
        if (values[i] > static_cast<T>(std::numeric_limits<std::int64_t>::max()))
          return "LeafIdArray: '" + name + "' holds " + std::to_string(values[i]) +
            ", beyond the 64-bit signed integers leaf ids are read as";
      ids[i] = static_cast<std::int64_t>(values[i]);
    }
    else
    {
      const std::string error = LeafIdOf(static_cast<double>(values[i]), name, ids[i]);
      if (!error.empty())
        return error;
    }
  }
  return {};
}

/// Collective GatherV onto rank 0 of every rank's `send` (type T); `received` is filled on rank 0.
template <typename T>
void GatherOnFirst(vtkMultiProcessController* c, std::vector<T>& send, std::vector<T>& received)
{
  const int ranks = c->GetNumberOfProcesses();
  vtkIdType mine = static_cast<vtkIdType>(send.size());
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(ranks), 0), offsets(lengths.size(), 0);
  c->AllGather(&mine, lengths.data(), 1);
  for (std::size_t q = 1; q < lengths.size(); ++q)
    offsets[q] = offsets[q - 1] + lengths[q - 1];
  received.assign(static_cast<std::size_t>(offsets.back() + lengths.back()), T{});
  static thread_local T dummy{};
  c->GatherV(send.empty() ? &dummy : send.data(), received.empty() ? &dummy : received.data(), mine, lengths.data(),
    offsets.data(), 0);
}

/// Each row's traits, and whether it was fitted.
std::vector<LeafTraits> RowTraits(const std::vector<Row>& rows, std::vector<bool>& fitted)
{
  std::vector<LeafTraits> traits(rows.size());
  fitted.assign(rows.size(), false);
  for (std::size_t r = 0; r < rows.size(); ++r)
  {
    fitted[r] = rows[r].status != static_cast<int>(LeafStatus::Failed);
    traits[r] = TraitsFromValues(rows[r].values);
  }
  return traits;
}

/// The Traits table's EstimatedArea and AreaRule (LeafAreaEstimate.h), after its other columns.
void AddEstimatedAreas(const std::vector<Row>& rows, vtkTable* traits)
{
  std::vector<bool> fitted;
  const LeafAreaEstimates estimates = EstimateLeafAreas(RowTraits(rows, fitted), fitted);
  vtkNew<vtkDoubleArray> area, rule;
  area->SetName("EstimatedArea");
  rule->SetName("AreaRule");
  for (std::size_t r = 0; r < rows.size(); ++r)
  {
    area->InsertNextValue(estimates.area[r]);
    rule->InsertNextValue(
      estimates.rule[r] < 0 ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(estimates.rule[r]));
  }
  traits->AddColumn(area);
  traits->AddColumn(rule);
}
} // namespace

std::string ReadLeafIds(vtkDataArray* array, const std::string& name, std::vector<std::int64_t>& ids)
{
  switch (array->GetDataType())
  {
    vtkTemplateMacro(return ReadTyped<VTK_TT>(array, name, ids));
    default:
      return "LeafIdArray: '" + name + "' is not a numeric array";
  }
}

namespace
{
/// Collective AllGatherV of every rank's `send` (type T), in rank order.
template <typename T>
std::vector<T> AllGatherValues(vtkMultiProcessController* controller, std::vector<T> send)
{
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(controller->GetNumberOfProcesses()), 0);
  std::vector<vtkIdType> offsets(lengths.size(), 0);
  vtkIdType mine = static_cast<vtkIdType>(send.size());
  controller->AllGather(&mine, lengths.data(), 1);
  for (std::size_t q = 1; q < lengths.size(); ++q)
    offsets[q] = offsets[q - 1] + lengths[q - 1];
  std::vector<T> all(static_cast<std::size_t>(offsets.back() + lengths.back()), T());
  T dummy = T();
  controller->AllGatherV(
    send.empty() ? &dummy : send.data(), all.empty() ? &dummy : all.data(), mine, lengths.data(), offsets.data());
  return all;
}
} // namespace

std::vector<std::int64_t> UnionOfIds(vtkMultiProcessController* controller, const std::vector<std::int64_t>& local)
{
  if (!controller || controller->GetNumberOfProcesses() < 2)
    return local;
  std::vector<vtkTypeInt64> all = AllGatherValues(controller, std::vector<vtkTypeInt64>(local.begin(), local.end()));
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  return std::vector<std::int64_t>(all.begin(), all.end());
}

std::vector<double> ValuesOfAllRanks(vtkMultiProcessController* controller, const std::vector<double>& local)
{
  if (!controller || controller->GetNumberOfProcesses() < 2)
    return local;
  return AllGatherValues(controller, local);
}

std::vector<Row> GatherRows(vtkMultiProcessController* controller, const std::vector<Row>& rows)
{
  std::vector<Row> all = rows;
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    // Three flat buffers: the values, the ids and statuses, the messages (each ended by a zero byte).
    const std::size_t width = TraitNames().size();
    std::vector<double> values, allValues;
    std::vector<vtkTypeInt64> ids, allIds;
    std::vector<char> text, allText;
    for (const Row& row : rows)
    {
      values.insert(values.end(), row.values.begin(), row.values.end());
      ids.push_back(row.leafId);
      ids.push_back(row.status);
      text.insert(text.end(), row.message.begin(), row.message.end());
      text.push_back('\0');
    }
    GatherOnFirst(controller, values, allValues);
    GatherOnFirst(controller, ids, allIds);
    GatherOnFirst(controller, text, allText);
    all.assign(allIds.size() / 2, Row());
    std::size_t at = 0;
    for (std::size_t r = 0; r < all.size(); ++r)
    {
      all[r].leafId = allIds[2 * r];
      all[r].status = static_cast<int>(allIds[2 * r + 1]);
      all[r].values.assign(allValues.begin() + r * width, allValues.begin() + (r + 1) * width);
      all[r].message = std::string(allText.data() + at);
      at += all[r].message.size() + 1;
    }
    if (controller->GetLocalProcessId() != 0)
      return {};
  }
  std::stable_sort(all.begin(), all.end(), [](const Row& a, const Row& b) { return a.leafId < b.leafId; });
  return all;
}

void FillTraitsTable(const std::vector<Row>& rows, const std::string& lengthUnit, vtkTable* traits)
{
  const std::vector<std::string> names = TraitNames();
  vtkNew<vtkTypeInt64Array> leafId;
  leafId->SetName(plantmorph::arrays::LeafId);
  traits->AddColumn(leafId);
  for (const std::string& name : names)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name.c_str());
    traits->AddColumn(column);
  }
  vtkNew<vtkIntArray> status;
  status->SetName("Status");
  vtkNew<vtkStringArray> message, unit, units;
  message->SetName("Message");
  unit->SetName("LengthUnit");
  for (const Row& row : rows)
  {
    leafId->InsertNextValue(row.leafId);
    for (std::size_t c = 0; c < names.size(); ++c)
      vtkDoubleArray::SafeDownCast(traits->GetColumn(static_cast<vtkIdType>(c + 1)))->InsertNextValue(row.values[c]);
    status->InsertNextValue(row.status);
    message->InsertNextValue(row.message);
    unit->InsertNextValue(lengthUnit);
  }
  traits->AddColumn(status);
  traits->AddColumn(message);
  traits->AddColumn(unit);
  AddEstimatedAreas(rows, traits);
  units->SetName("PlantMorph.ColumnUnits");
  for (vtkIdType c = 0; c < traits->GetNumberOfColumns(); ++c)
    units->InsertNextValue(ColumnUnit(traits->GetColumnName(c), lengthUnit));
  traits->GetFieldData()->AddArray(units);
}

void FillPlantTable(
  const std::vector<Row>& rows, const std::string& lengthUnit, double unassignedLeafPoints, vtkTable* plant)
{
  std::vector<bool> fitted;
  const std::vector<LeafTraits> traits = RowTraits(rows, fitted);
  const PlantSummary summary = SummarizePlant(traits, fitted, unassignedLeafPoints);
  const std::vector<std::string> columns = PlantColumnNames();
  const std::vector<double> values = PlantColumnValues(summary);
  vtkNew<vtkStringArray> units, unit;
  units->SetName("PlantMorph.ColumnUnits");
  for (std::size_t c = 0; c < columns.size(); ++c)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(columns[c].c_str());
    column->InsertNextValue(values[c]);
    plant->AddColumn(column);
    units->InsertNextValue(ColumnUnit(columns[c], lengthUnit));
  }
  unit->SetName("LengthUnit");
  unit->InsertNextValue(lengthUnit);
  plant->AddColumn(unit);
  units->InsertNextValue(ColumnUnit("LengthUnit", lengthUnit));
  plant->GetFieldData()->AddArray(units);
}

} // namespace fittable
} // namespace plantmorph
