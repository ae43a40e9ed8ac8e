// SPDX-License-Identifier: GPL-3.0-or-later
// LeafFitFilter's leaf ids and tables (docs/methods/leaf-fit.md, "Several leaves" and "Trait reference").
//
// - Leaf ids are read as 64-bit integers (any integer array type; a floating-point array's values must be whole
//   numbers: plantmorph::LeafIdOf). Ranks agree on the sorted union of the ids (collective), and the owner exchange
//   (PlantMorphOwnerExchange.h)
//   works on each id's index in it, so ids beyond the int range (0 and 2^32) stay apart.
// - The rows: every leaf the filter meets gets one row, fitted or not; a rank's rows (trait values, 64-bit ids and
//   messages) are gathered onto rank 0 (collective) and sorted by LeafId.
// - Traits (port 2): LeafId, plantmorph::TraitNames(), Status (plantmorph::LeafStatus), Message, LengthUnit; field
//   data PlantMorph.ColumnUnits (one unit per column). Plant (port 4): one row, plantmorph::PlantColumnNames().
#pragma once

#include "vtkType.h"

#include <cstdint>
#include <string>
#include <vector>

class vtkDataArray;
class vtkMultiProcessController;
class vtkTable;

namespace plantmorph
{
namespace fittable
{

/// Every value of a one-component array as a 64-bit leaf id; an error naming the array and a bad value.
std::string ReadLeafIds(vtkDataArray* array, const std::string& name, std::vector<std::int64_t>& ids);

/// Collective: the sorted union over the ranks of the sorted, distinct `local` ids.
std::vector<std::int64_t> UnionOfIds(vtkMultiProcessController* controller, const std::vector<std::int64_t>& local);

/// Collective: every rank's `local` values, in rank order (callers use what does not depend on the order).
std::vector<double> ValuesOfAllRanks(vtkMultiProcessController* controller, const std::vector<double>& local);

/// One Traits row: the leaf's id, status, trait values (TraitNames() order; NaN when not fitted) and message.
struct Row
{
  std::int64_t leafId = 0;
  int status = 0;
  std::vector<double> values;
  std::string message;
};

/// Collective: every rank's rows on rank 0, sorted by LeafId (empty elsewhere).
std::vector<Row> GatherRows(vtkMultiProcessController* controller, const std::vector<Row>& rows);

/// Fills the Traits table (port 2) with `rows`; `lengthUnit` the output length unit ("" unknown).
void FillTraitsTable(const std::vector<Row>& rows, const std::string& lengthUnit, vtkTable* traits);

/// Fills the Plant table (port 4): one row summarising `rows` and `unassignedLeafPoints` leaf points on no leaf.
void FillPlantTable(
  const std::vector<Row>& rows, const std::string& lengthUnit, double unassignedLeafPoints, vtkTable* plant);

} // namespace fittable
} // namespace plantmorph
