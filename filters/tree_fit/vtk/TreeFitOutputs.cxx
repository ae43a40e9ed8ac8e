// SPDX-License-Identifier: GPL-3.0-or-later
#include "TreeFitOutputs.h"

#include "PlantMorphFieldData.h" // VertexCells

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <string>

namespace plantmorph
{
namespace treefitvtk
{
namespace
{
template <typename T>
vtkSmartPointer<T> NewArray(const char* name, int components = 1)
{
  auto array = vtkSmartPointer<T>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  return array;
}

const char* const CylinderInts[] = { "CylinderId", "ParentId", "BranchId", "BranchOrder", "SegmentId", "TreeId",
  "Measured" };
const char* const CylinderDoubles[] = { "Radius", "Length", "FitRMS", "Support", "GrowthLength", "StartX", "StartY",
  "StartZ", "EndX", "EndY", "EndZ" };

/// The cell values of cylinder `c` of tree `t`, appended `cells` times.
void AppendCylinderData(const FittedTree& t, int c, vtkIdType cells, vtkCellData* data)
{
  const TreeCylinder& cyl = t.result.cylinders[c];
  const int ints[] = { t.cylinderBase + c, cyl.parent >= 0 ? t.cylinderBase + cyl.parent : -1,
    t.branchBase + cyl.branch, cyl.order, cyl.segment, t.treeId, cyl.measured ? 1 : 0 };
  const double doubles[] = { cyl.radius, cyl.length, cyl.fitRMS, cyl.support, cyl.growthLength, cyl.start.x(),
    cyl.start.y(), cyl.start.z(), cyl.end.x(), cyl.end.y(), cyl.end.z() };
  for (vtkIdType k = 0; k < cells; ++k)
  {
    for (int a = 0; a < 7; ++a)
      data->GetArray(CylinderInts[a])->InsertNextTuple1(ints[a]);
    for (int a = 0; a < 11; ++a)
      data->GetArray(CylinderDoubles[a])->InsertNextTuple1(doubles[a]);
  }
}

/// A capped tube: `sides` quads and two caps; returns the number of cells.
vtkIdType AppendTube(const TreeCylinder& cyl, int sides, vtkPoints* points, vtkCellArray* polys)
{
  const Eigen::Vector3d axis = (cyl.end - cyl.start).normalized();
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  const vtkIdType first = points->GetNumberOfPoints();
  for (const Eigen::Vector3d* centre : { &cyl.start, &cyl.end })
    for (int k = 0; k < sides; ++k)
    {
      const double phi = 2.0 * M_PI * k / sides;
      const Eigen::Vector3d p = *centre + cyl.radius * (std::cos(phi) * u + std::sin(phi) * v);
      points->InsertNextPoint(p.data());
    }
  for (int k = 0; k < sides; ++k)
  {
    const vtkIdType next = (k + 1) % sides;
    const vtkIdType quad[4] = { first + k, first + next, first + sides + next, first + sides + k };
    polys->InsertNextCell(4, quad);
  }
  std::vector<vtkIdType> bottom, top;
  for (int k = 0; k < sides; ++k)
  {
    bottom.push_back(first + sides - 1 - k);
    top.push_back(first + sides + k);
  }
  polys->InsertNextCell(sides, bottom.data());
  polys->InsertNextCell(sides, top.data());
  return sides + 2;
}
} // namespace

void WriteCylinders(const std::vector<FittedTree>& trees, bool tubes, int sides, vtkPolyData* output)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> cells;
  for (const char* name : CylinderInts)
    output->GetCellData()->AddArray(NewArray<vtkIntArray>(name));
  for (const char* name : CylinderDoubles)
    output->GetCellData()->AddArray(NewArray<vtkDoubleArray>(name));
  for (const FittedTree& t : trees)
    for (std::size_t c = 0; c < t.result.cylinders.size(); ++c)
    {
      const TreeCylinder& cyl = t.result.cylinders[c];
      vtkIdType count = 1;
      if (tubes)
        count = AppendTube(cyl, sides, points, cells);
      else
      {
        const vtkIdType ids[2] = { points->InsertNextPoint(cyl.start.data()), points->InsertNextPoint(cyl.end.data()) };
        cells->InsertNextCell(2, ids);
      }
      AppendCylinderData(t, static_cast<int>(c), count, output->GetCellData());
    }
  output->SetPoints(points);
  if (tubes)
    output->SetPolys(cells);
  else
    output->SetLines(cells);
  output->GetCellData()->SetActiveScalars("Radius");
}

void WriteSkeleton(const std::vector<FittedTree>& trees, vtkPolyData* output)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  const char* const pointInts[] = { "BranchId", "BranchOrder", "ParentId", "TreeId" };
  for (const char* name : pointInts)
    output->GetPointData()->AddArray(NewArray<vtkIntArray>(name));
  output->GetPointData()->AddArray(NewArray<vtkDoubleArray>("Radius"));
  const char* const cellInts[] = { "BranchId", "ParentId", "Depth", "TreeId" };
  for (const char* name : cellInts)
    output->GetCellData()->AddArray(NewArray<vtkIntArray>(name));
  for (const FittedTree& t : trees)
    for (const TreeBranchRow& b : t.result.branches)
    {
      const int values[] = { t.branchBase + b.id, b.order, b.parent >= 0 ? t.branchBase + b.parent : -1, t.treeId };
      lines->InsertNextCell(static_cast<vtkIdType>(b.cylinders.size() + 1));
      for (std::size_t k = 0; k <= b.cylinders.size(); ++k)
      {
        const TreeCylinder& cyl = t.result.cylinders[b.cylinders[std::min(k, b.cylinders.size() - 1)]];
        lines->InsertCellPoint(points->InsertNextPoint(k == 0 ? cyl.start.data() : cyl.end.data()));
        for (int a = 0; a < 4; ++a)
          output->GetPointData()->GetArray(pointInts[a])->InsertNextTuple1(values[a]);
        output->GetPointData()->GetArray("Radius")->InsertNextTuple1(cyl.radius);
      }
      const int cellValues[] = { values[0], values[2], b.order, t.treeId };
      for (int a = 0; a < 4; ++a)
        output->GetCellData()->GetArray(cellInts[a])->InsertNextTuple1(cellValues[a]);
    }
  output->SetPoints(points);
  output->SetLines(lines);
  output->GetPointData()->SetActiveScalars("Radius");
}

void WriteTables(const std::vector<FittedTree>& trees, vtkTable* treeTable, vtkTable* branchTable)
{
  const std::vector<std::string> names = TreeTraitNames();
  auto treeIds = NewArray<vtkIntArray>("TreeId");
  auto status = NewArray<vtkStringArray>("Status");
  treeTable->AddColumn(treeIds);
  treeTable->AddColumn(status);
  for (const std::string& name : names)
    treeTable->AddColumn(NewArray<vtkDoubleArray>(name.c_str()));
  const char* const branchInts[] = { "TreeId", "BranchId", "ParentId", "Order" };
  const char* const branchDoubles[] = { "Length", "Volume", "BaseDiameter", "Angle", "Azimuth", "Inclination",
    "Height" };
  for (const char* name : branchInts)
    branchTable->AddColumn(NewArray<vtkIntArray>(name));
  for (const char* name : branchDoubles)
    branchTable->AddColumn(NewArray<vtkDoubleArray>(name));
  for (const FittedTree& t : trees)
  {
    treeIds->InsertNextValue(t.treeId);
    status->InsertNextValue(t.result.error.empty() ? "ok" : t.result.error);
    const std::vector<double> values = TreeTraitValues(t.result.traits);
    for (std::size_t c = 0; c < names.size(); ++c)
      vtkDoubleArray::SafeDownCast(treeTable->GetColumn(static_cast<vtkIdType>(c + 2)))
        ->InsertNextValue(t.result.error.empty() ? values[c] : std::numeric_limits<double>::quiet_NaN());
    for (const TreeBranchRow& b : t.result.branches)
    {
      const int ints[] = { t.treeId, t.branchBase + b.id, b.parent >= 0 ? t.branchBase + b.parent : -1, b.order };
      const double doubles[] = { b.length, b.volume, b.baseDiameter, b.angle, b.azimuth, b.inclination, b.height };
      for (int a = 0; a < 4; ++a)
        vtkIntArray::SafeDownCast(branchTable->GetColumn(a))->InsertNextValue(ints[a]);
      for (int a = 0; a < 7; ++a)
        vtkDoubleArray::SafeDownCast(branchTable->GetColumn(4 + a))->InsertNextValue(doubles[a]);
    }
  }
}

void WriteScan(vtkPointSet* input, const std::vector<Eigen::Vector3d>& all, const std::vector<int>& treeOf,
  const std::vector<double>& values, const std::map<int, std::pair<int, int>>& bases, vtkPolyData* output)
{
  const auto n = static_cast<vtkIdType>(all.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  auto treeId = NewArray<vtkIntArray>("TreeId");
  auto cylinder = NewArray<vtkIntArray>("CylinderId");
  auto branch = NewArray<vtkIntArray>("BranchId");
  auto wood = NewArray<vtkUnsignedCharArray>("Wood");
  auto distance = NewArray<vtkDoubleArray>("FitDistance");
  for (auto* array : { static_cast<vtkDataArray*>(treeId), static_cast<vtkDataArray*>(cylinder),
         static_cast<vtkDataArray*>(branch), static_cast<vtkDataArray*>(wood), static_cast<vtkDataArray*>(distance) })
    array->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    points->SetPoint(i, all[i].data());
    const double* v = values.data() + 4 * i;
    const auto base = bases.find(treeOf[i]);
    const bool known = base != bases.end();
    treeId->SetValue(i, treeOf[i]);
    cylinder->SetValue(i, known && v[0] >= 0 ? base->second.first + static_cast<int>(v[0]) : -1);
    branch->SetValue(i, known && v[1] >= 0 ? base->second.second + static_cast<int>(v[1]) : -1);
    wood->SetValue(i, v[2] == 1.0 ? 1 : 0);
    distance->SetValue(i, v[3]);
  }
  output->SetPoints(points);
  output->SetVerts(plantmorph::VertexCells(n));
  output->GetPointData()->PassData(input->GetPointData());
  for (auto* array : { static_cast<vtkDataArray*>(treeId), static_cast<vtkDataArray*>(cylinder),
         static_cast<vtkDataArray*>(branch), static_cast<vtkDataArray*>(wood), static_cast<vtkDataArray*>(distance) })
    output->GetPointData()->AddArray(array);
  output->GetPointData()->SetActiveScalars("FitDistance");
}

} // namespace treefitvtk
} // namespace plantmorph
