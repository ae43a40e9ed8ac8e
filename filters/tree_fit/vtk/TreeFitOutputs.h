// SPDX-License-Identifier: GPL-3.0-or-later
// vtkTreeFitFilter's output ports from the fitted trees (vtkTreeFitFilter.h lists the ports and their arrays).
#pragma once

#include "TreeFit.h"

#include "vtkType.h"

#include <Eigen/Core>

#include <map>
#include <utility>
#include <vector>

class vtkPointSet;
class vtkPolyData;
class vtkTable;

namespace plantmorph
{
namespace treefitvtk
{

/// One tree of the input: its id, its points' ids in the input, its fit, and the first global cylinder and branch id.
struct FittedTree
{
  int treeId = 0;
  std::vector<vtkIdType> members;
  TreeFitResult result;
  int cylinderBase = 0, branchBase = 0;
};

/// Port 0: one line (or, with tubes, a capped tube of `sides` sides) per cylinder.
void WriteCylinders(const std::vector<FittedTree>& trees, bool tubes, int sides, vtkPolyData* output);
/// Port 1: one polyline per branch, base to tip.
void WriteSkeleton(const std::vector<FittedTree>& trees, vtkPolyData* output);
/// Ports 2 and 3: the Trees and Branches tables.
void WriteTables(const std::vector<FittedTree>& trees, vtkTable* treeTable, vtkTable* branchTable);
/// Port 4: the (scaled) input points with their data and the per-point results: `treeOf` each point's TreeId,
/// `values` four per point (its cylinder and branch in its tree, -1 for none; wood 0/1; FitDistance), `bases` each
/// tree's first cylinder and branch id.
void WriteScan(vtkPointSet* input, const std::vector<Eigen::Vector3d>& points, const std::vector<int>& treeOf,
  const std::vector<double>& values, const std::map<int, std::pair<int, int>>& bases, vtkPolyData* output);

} // namespace treefitvtk
} // namespace plantmorph
