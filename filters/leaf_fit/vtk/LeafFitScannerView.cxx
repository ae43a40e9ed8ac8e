// SPDX-License-Identifier: GPL-3.0-or-later
#include "LeafFitScannerView.h"

#include "LeafFitTables.h" // ValuesOfAllRanks
#include "ScannerView.h"

#include <plantmorph/DataContract.h>
#include <plantmorph/statistics/Median.h>

#include "PlantMorphAlgorithmHooks.h" // SMPFor

#include "vtkDataArray.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace plantmorph
{
namespace fittable
{
namespace
{
/// More scanner positions than this: the ScanPosition array means something else, and no view is judged.
constexpr int MaxScanners = 1024;
/// The least points of a leaf from one scanner to measure that scanner's spacing on it.
constexpr double MinPointsForSpacing = 20.0;

using Positions = std::vector<std::optional<Eigen::Vector3d>>;

/// Collective: the number of scanner positions over every rank's points (0 when none is known).
int CountScanners(vtkMultiProcessController* controller, const ScanRanges& scan)
{
  double largest = -1.0;
  for (const int s : scan.scanner)
    largest = std::max(largest, static_cast<double>(s));
  const std::vector<double> all = ValuesOfAllRanks(controller, { largest });
  const double count = *std::max_element(all.begin(), all.end()) + 1.0;
  return count > MaxScanners ? 0 : static_cast<int>(count);
}

/// Collective: each scanner's position from every rank's points and ranges, the equations added in rank order.
Positions SolvePositions(
  vtkMultiProcessController* controller, const std::vector<Eigen::Vector3d>& points, const ScanRanges& scan, int count)
{
  std::vector<RangeEquations> local(static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < points.size(); ++i)
    if (scan.scanner[i] >= 0)
      local[static_cast<std::size_t>(scan.scanner[i])].Add(points[i], scan.range[i]);
  std::vector<double> flat;
  for (const RangeEquations& equations : local)
  {
    const std::vector<double> values = equations.Values();
    flat.insert(flat.end(), values.begin(), values.end());
  }
  const std::vector<double> all = ValuesOfAllRanks(controller, flat);
  const std::size_t width = flat.size();
  std::vector<RangeEquations> summed(static_cast<std::size_t>(count));
  for (std::size_t rank = 0; width > 0 && rank < all.size() / width; ++rank)
    for (std::size_t s = 0; s < summed.size(); ++s)
      summed[s].Add(&all[rank * width + s * 22]);
  Positions positions;
  for (const RangeEquations& equations : summed)
    positions.push_back(ScannerPosition(equations));
  return positions;
}

/// The points the leaf holds from all scanners together.
double PointsOf(const LeafView& leaf)
{
  double total = 0.0;
  for (const double n : leaf.pointsFrom)
    total += n;
  return total;
}

/// Collective: each scanner's depth cell (DepthCellSpacings times its angular spacing: the median over the fitted
/// leaves it saw of their spacing, widened by the share of their points it gave, over their range); 0 when none.
std::vector<double> DepthCells(
  vtkMultiProcessController* controller, const std::vector<LeafView>& leaves, const Positions& positions)
{
  std::vector<double> local; // (scanner, angular spacing) pairs
  for (const LeafView& leaf : leaves)
  {
    if (!leaf.fit || !leaf.fit->error.empty() || !(leaf.fit->traits.spacing > 0.0) || leaf.fit->points.empty())
      continue;
    const double total = PointsOf(leaf);
    const Eigen::Vector3d centre = BladeCentre(*leaf.fit);
    for (std::size_t s = 0; s < leaf.pointsFrom.size() && s < positions.size(); ++s)
      if (positions[s] && leaf.pointsFrom[s] >= MinPointsForSpacing && leaf.pointsFrom[s] >= ScannerSawShare * total)
      {
        // A share f of the leaf's points: that scanner's own points are f times as dense, 1 / sqrt(f) as far apart.
        local.push_back(static_cast<double>(s));
        local.push_back(
          leaf.fit->traits.spacing / std::sqrt(leaf.pointsFrom[s] / total) / (centre - *positions[s]).norm());
      }
  }
  const std::vector<double> all = ValuesOfAllRanks(controller, local);
  std::vector<double> cells(positions.size(), 0.0);
  for (std::size_t s = 0; s < positions.size(); ++s)
  {
    std::vector<double> spacings;
    for (std::size_t k = 0; k + 1 < all.size(); k += 2)
      if (all[k] == static_cast<double>(s) && std::isfinite(all[k + 1]) && all[k + 1] > 0.0)
        spacings.push_back(all[k + 1]);
    if (!spacings.empty())
      cells[s] = DepthCellSpacings * Median(spacings);
  }
  return cells;
}

/// Collective: each scanner's depth map from every rank's points of it (empty maps where its position or cell is
/// not known).
std::vector<DepthMap> DepthMaps(vtkMultiProcessController* controller, const std::vector<Eigen::Vector3d>& points,
  const ScanRanges& scan, const Positions& positions, const std::vector<double>& cells, const Eigen::Vector3d& up)
{
  std::vector<DepthMap> maps(positions.size());
  for (std::size_t s = 0; s < positions.size(); ++s)
  {
    if (!positions[s] || !(cells[s] > 0.0))
      continue; // alike on every rank: positions and cells came from every rank's values
    maps[s].position = *positions[s];
    maps[s].cells = DirectionCells(up, cells[s]);
    std::vector<Eigen::Vector3d> mine;
    std::vector<std::int64_t> leaves;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (scan.scanner[i] == static_cast<int>(s))
      {
        mine.push_back(points[i]);
        leaves.push_back(i < scan.leaf.size() ? scan.leaf[i] : -1);
      }
    std::vector<double> flat;
    for (const CellRange& cell : maps[s].CellRanges(mine, leaves))
      flat.insert(flat.end(), { static_cast<double>(cell.key), cell.range, static_cast<double>(cell.leaf) });
    const std::vector<double> all = ValuesOfAllRanks(controller, flat); // keys and leaf numbers below 2^53: exact
    std::vector<CellRange> cells(all.size() / 3);
    for (std::size_t k = 0; k < cells.size(); ++k)
      cells[k] = { static_cast<std::int64_t>(all[3 * k]), all[3 * k + 1], static_cast<std::int64_t>(all[3 * k + 2]) };
    maps[s].Merge(std::move(cells));
  }
  return maps;
}
} // namespace

ScanRanges ReadScanRanges(vtkPointSet* input, double scale)
{
  ScanRanges scan;
  vtkDataArray* range = input->GetPointData()->GetArray(arrays::Range);
  vtkDataArray* position = input->GetPointData()->GetArray(arrays::ScanPosition);
  if (!range || !position || range->GetNumberOfComponents() != 1 || position->GetNumberOfComponents() != 1)
    return scan;
  const vtkIdType n = input->GetNumberOfPoints();
  scan.scanner.resize(static_cast<std::size_t>(n));
  scan.range.resize(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double s = position->GetComponent(i, 0);
    const bool whole = std::isfinite(s) && s >= 0.0 && s < MaxScanners && s == std::floor(s);
    scan.scanner[static_cast<std::size_t>(i)] = whole ? static_cast<int>(s) : -1;
    scan.range[static_cast<std::size_t>(i)] = scale * range->GetComponent(i, 0);
  }
  return scan;
}

namespace
{
/// The unsolved scanner positions a warning names; the rest are counted.
constexpr std::size_t MaxNamedPositions = 10;

/// The positions not solved, by number: the first MaxNamedPositions of them and how many more (a line scanner's
/// every line is a position of its own, in a plane: hundreds of them); empty when every position was solved.
std::string UnsolvedPositions(const Positions& positions)
{
  std::string unsolved;
  std::size_t named = 0, more = 0;
  for (std::size_t s = 0; s < positions.size(); ++s)
    if (!positions[s])
    {
      if (named == MaxNamedPositions)
      {
        ++more;
        continue;
      }
      unsolved += (unsolved.empty() ? "" : ", ") + std::to_string(s);
      ++named;
    }
  if (more > 0)
    unsolved += " and " + std::to_string(more) + " more";
  return unsolved;
}
} // namespace

std::string SetHiddenMargins(vtkMultiProcessController* controller, const std::vector<Eigen::Vector3d>& points,
  const ScanRanges& scan, const Eigen::Vector3d& up, std::vector<LeafView>& leaves)
{
  const bool known = scan.scanner.size() == points.size() && scan.range.size() == points.size();
  const ScanRanges none{ std::vector<int>(points.size(), -1), std::vector<double>(points.size(), 0.0), {} };
  const ScanRanges& here = known ? scan : none;
  const int count = CountScanners(controller, here);
  if (count <= 0)
    return {}; // alike on every rank
  const Positions positions = SolvePositions(controller, points, here, count);
  const std::string unsolved = UnsolvedPositions(positions);
  const std::vector<double> cells = DepthCells(controller, leaves, positions);
  const std::vector<DepthMap> maps = DepthMaps(controller, points, here, positions, cells, up);
  ForEachIndex(
    SMPFor(1), leaves.size(),
    [&](std::size_t k) {
      LeafView& leaf = leaves[k];
      if (!leaf.fit || !leaf.fit->error.empty())
        return;
      const double total = PointsOf(leaf);
      std::vector<const DepthMap*> sawIt;
      for (std::size_t s = 0; s < leaf.pointsFrom.size() && s < maps.size(); ++s)
        if (maps[s].cells.Valid() && leaf.pointsFrom[s] > 0.0 && leaf.pointsFrom[s] >= ScannerSawShare * total)
          sawIt.push_back(&maps[s]);
      const MarginView view = ViewOfMargin(*leaf.fit, leaf.fit->traits.spacing, sawIt, leaf.leaf);
      leaf.fit->traits.hiddenMargin = view.hidden;
      leaf.fit->traits.extentsSeen = view.extentsSeen;
    },
    1);
  if (unsolved.empty())
    return {};
  return "Range and ScanPosition: no scanner position was solved from the ranges of the points of ScanPosition " +
    unsolved +
    " (their ranges are no distances from one place, as a moving scanner's or a Range of another meaning, or the "
    "points lie on one plane, which two places see alike), so HiddenMargin leaves them out (NaN where no other "
    "position saw the leaf)";
}

} // namespace fittable
} // namespace plantmorph
