// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkTreeFromSketchSource.h"
#include "PlantMorphAlgorithmHooks.h"

#include "PlantMorphFieldData.h" // AdoptArray
#include "PlantMorphLayer.h"
#include "PlantMorphWholeInput.h"
#include "BranchJunctions.h"
#include "BranchPieces.h"
#include "BranchTubes.h"
#include "TreeMerge.h"
#include "TreeStrokes.h"
#include "TreeTemplate.h"

#include <plantmorph/DataContract.h>
#include <plantmorph/RangeError.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTriangleFilter.h"
#include "vtkTypeInt32Array.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>

vtkStandardNewMacro(vtkTreeFromSketchSource);

namespace
{
/// `count` ints, unset (every caller writes them all, from threads: no serial zeroing pass, no page faults on the
/// calling thread).
vtkSmartPointer<vtkIntArray> IntArray(const char* name, vtkIdType count)
{
  plantmorph::MeshArray<int> values;
  values.resize(static_cast<std::size_t>(count));
  return plantmorph::AdoptArray<vtkIntArray>(values, 1, name);
}

/// Every value of `a` set to `value`, in parallel.
void Fill(vtkIntArray* a, int value)
{
  int* v = a->GetPointer(0);
  vtkSMPTools::For(
    0, a->GetNumberOfValues(), [v, value](vtkIdType begin, vtkIdType end) { std::fill(v + begin, v + end, value); });
}

/// The Merge input as skeleton branches: one per line cell, BranchId and ParentId from its cell arrays (whole
/// numbers), Radius from the point array. Returns an error naming what is missing.
std::string ReadSkeleton(vtkPolyData* input, std::vector<plantmorph::SkeletonBranch>& branches)
{
  const std::string hint =
    " (connect a tree skeleton: another TreeFromSketchSource's Skeleton output, port 1, or polylines with cell arrays "
    "BranchId and ParentId and a point array Radius)";
  vtkCellArray* lines = input->GetLines();
  if (!lines || lines->GetNumberOfCells() == 0)
  {
    return "Merge input is not a tree: it has no lines" + hint;
  }
  vtkDataArray* ids = input->GetCellData()->GetArray("BranchId");
  vtkDataArray* parents = input->GetCellData()->GetArray("ParentId");
  vtkDataArray* radius = input->GetPointData()->GetArray("Radius");
  if (!ids || !parents || !radius)
  {
    return std::string("Merge input is not a tree: it has no ") +
      (!ids          ? "cell array BranchId"
          : !parents ? "cell array ParentId"
                     : "point array Radius") +
      hint;
  }
  // Line cells come after vertex cells in a polydata's cell numbering.
  const vtkIdType first = input->GetNumberOfVerts();
  vtkNew<vtkIdList> pointIds;
  vtkIdType cell = first;
  for (lines->InitTraversal(); lines->GetNextCell(pointIds); ++cell)
  {
    const double id = ids->GetComponent(cell, 0), parent = parents->GetComponent(cell, 0);
    if (!std::isfinite(id) || id != std::floor(id) || !std::isfinite(parent) || parent != std::floor(parent) ||
      std::abs(id) > 4e9 || std::abs(parent) > 4e9)
    {
      return "Merge input is not a tree: line " + std::to_string(cell - first) +
        " has a BranchId or ParentId that is not a whole number" + hint;
    }
    plantmorph::SkeletonBranch b;
    b.id = static_cast<long long>(id);
    b.parentId = static_cast<long long>(parent);
    for (vtkIdType k = 0; k < pointIds->GetNumberOfIds(); ++k)
    {
      double p[3];
      input->GetPoint(pointIds->GetId(k), p);
      b.centre.emplace_back(p[0], p[1], p[2]);
      b.radii.push_back(radius->GetComponent(pointIds->GetId(k), 0));
    }
    branches.push_back(std::move(b));
  }
  return {};
}

/// The strokes: the Strokes input's lines (their x and y), else the StrokeFile's; "" or why they cannot be read.
std::string ReadStrokes(vtkPolyData* strokeInput, const std::string& strokeFile,
  std::vector<std::vector<Eigen::Vector3d>>& strokes, std::vector<std::string>& origins)
{
  if (strokeInput)
  {
    vtkCellArray* lines = strokeInput->GetLines();
    vtkNew<vtkIdList> ids;
    for (lines->InitTraversal(); lines->GetNextCell(ids);)
    {
      std::vector<Eigen::Vector3d> stroke;
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      {
        double p[3];
        strokeInput->GetPoint(ids->GetId(k), p);
        stroke.emplace_back(p[0], p[1], 0.0);
      }
      strokes.push_back(std::move(stroke));
    }
  }
  else if (!strokeFile.empty())
  {
    return plantmorph::ReadStrokeFile(strokeFile, strokes, &origins);
  }
  return {};
}

/// The Leaf input's surface as polygons: triangle strips (a Tube filter's output, for one) become triangles with
/// their cell data, so no part of the leaf is left out; the input itself is returned when it has no strips.
vtkSmartPointer<vtkPolyData> LeafPolygons(vtkPolyData* leafInput)
{
  if (!leafInput || leafInput->GetNumberOfStrips() == 0)
  {
    return leafInput;
  }
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputData(leafInput);
  triangles->PassVertsOff();
  triangles->PassLinesOff();
  triangles->Update();
  return triangles->GetOutput();
}

/// The Leaf input, checked before anything is written: "" or why it cannot be used; its length and lowest y.
std::string ValidateLeafInput(vtkPolyData* leafInput, const plantmorph::Tree& tree, const plantmorph::TreeParameters& s,
  double& leafLength, double& leafMinY)
{
  if (leafInput->GetNumberOfPolys() == 0 || leafInput->GetNumberOfPoints() == 0)
  {
    return "Leaf input has no polygons: connect a leaf mesh (e.g. LeafOutlineSource's Blade) or "
           "disconnect it for textured quads";
  }
  double bounds[6];
  leafInput->GetBounds(bounds);
  leafMinY = bounds[2];
  leafLength = bounds[3] - bounds[2];
  if (!(leafLength > 0.0) || !std::isfinite(leafLength))
  {
    return "Leaf input has no extent along +Y (its length must be positive and finite)";
  }
  const double total = static_cast<double>(tree.leaves.size()) * leafInput->GetNumberOfPoints();
  if (total > static_cast<double>(s.maxSegments) * 8.0)
  {
    std::ostringstream message;
    message << "the leaves would have " << total
            << " points, more than 8 * MaxSegments = " << 8.0 * static_cast<double>(s.maxSegments)
            << " (lower LeafCount or use a coarser Leaf input)";
    return message.str();
  }
  return {};
}

/// The outputs' `Organ` codes (the truth a scan of the tree carries to its points): the data contract's.
using plantmorph::OrganLeaf;
using plantmorph::OrganPetiole;
using plantmorph::OrganWood;

/// `Organ` = organ and `LeafId` = leafId on every point and cell of `out` (the wood: 0 and -1), so that the wood
/// and the leaves appended keep both arrays (AppendGeometry keeps the arrays all its inputs have).
void AddConstantOrganArrays(vtkPolyData* out, int organ, int leafId)
{
  const vtkIdType counts[2] = { out->GetNumberOfPoints(), out->GetNumberOfCells() };
  vtkDataSetAttributes* data[2] = { out->GetPointData(), out->GetCellData() };
  for (int k = 0; k < 2; ++k)
  {
    auto organs = IntArray(plantmorph::arrays::Organ, counts[k]),
         leaves = IntArray(plantmorph::arrays::LeafId, counts[k]);
    Fill(organs, organ);
    Fill(leaves, leafId);
    data[k]->AddArray(organs);
    data[k]->AddArray(leaves);
  }
}

/// The triangles as VTK cells: the mesh's 32-bit connectivity adopted as it is, offsets 0, 3, 6, ... (32-bit too,
/// while 3 * triangles fits; else both 64-bit, copied).
vtkNew<vtkCellArray> Triangles(plantmorph::MeshArray<std::int32_t>& triangles)
{
  const vtkIdType nt = static_cast<vtkIdType>(triangles.size() / 3);
  vtkNew<vtkCellArray> polys;
  if (3 * nt <= std::numeric_limits<std::int32_t>::max())
  {
    plantmorph::MeshArray<std::int32_t> offsets;
    offsets.resize(static_cast<std::size_t>(nt) + 1);
    std::int32_t* o = offsets.data();
    vtkSMPTools::For(0, nt + 1, [o](vtkIdType begin, vtkIdType end) {
      for (vtkIdType i = begin; i < end; ++i)
        o[i] = static_cast<std::int32_t>(3 * i);
    });
    polys->SetData(plantmorph::AdoptArray<vtkTypeInt32Array>(offsets, 1, nullptr),
      plantmorph::AdoptArray<vtkTypeInt32Array>(triangles, 1, nullptr));
    return polys;
  }
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfTuples(nt + 1);
  connectivity->SetNumberOfTuples(3 * nt);
  vtkIdType* o = offsets->GetPointer(0);
  vtkIdType* c = connectivity->GetPointer(0);
  const std::int32_t* t = triangles.data();
  vtkSMPTools::For(0, nt + 1, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
      o[i] = 3 * i;
    std::copy(t + 3 * begin, t + 3 * std::min(end, nt), c + 3 * begin);
  });
  polys->SetData(offsets, connectivity);
  triangles = plantmorph::MeshArray<std::int32_t>();
  return polys;
}

/// Port 0: the branch surfaces, with Normals, TCoords and each triangle's BranchId, ParentId and Depth. The mesh's
/// arrays are handed over to the output uncopied (`mesh` is left empty).
void WriteBranches(plantmorph::TubeMesh& mesh, const plantmorph::Tree& tree, vtkPolyData* branchesOut)
{
  const vtkIdType nt = static_cast<vtkIdType>(mesh.TriangleCount());
  auto branchId = IntArray("BranchId", nt), parentId = IntArray("ParentId", nt), depth = IntArray("Depth", nt);
  int* ids[3] = { branchId->GetPointer(0), parentId->GetPointer(0), depth->GetPointer(0) };
  plantmorph::SMPFor()(tree.branches.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t)
    {
      const plantmorph::TreeBranch& b = tree.branches[t];
      const auto first = mesh.triangleOffsets[t], last = mesh.triangleOffsets[t + 1];
      std::fill(ids[0] + first, ids[0] + last, b.id);
      std::fill(ids[1] + first, ids[1] + last, b.parentId);
      std::fill(ids[2] + first, ids[2] + last, b.depth);
    }
  });
  vtkNew<vtkPoints> points;
  points->SetData(plantmorph::AdoptArray<vtkDoubleArray>(mesh.points, 3, nullptr));
  branchesOut->SetPoints(points);
  branchesOut->SetPolys(Triangles(mesh.triangles));
  branchesOut->GetPointData()->SetNormals(
    plantmorph::AdoptArray<vtkFloatArray>(mesh.normals, 3, plantmorph::arrays::Normals));
  branchesOut->GetPointData()->SetTCoords(
    plantmorph::AdoptArray<vtkFloatArray>(mesh.tcoords, 2, plantmorph::arrays::TCoords));
  branchesOut->GetCellData()->AddArray(branchId);
  branchesOut->GetCellData()->AddArray(parentId);
  branchesOut->GetCellData()->AddArray(depth);
  mesh = plantmorph::TubeMesh();
}

/// Port 1: the skeleton, one polyline per branch with its Radius, BranchId, ParentId and Depth.
void WriteSkeleton(const plantmorph::Tree& tree, vtkPolyData* skeletonOut)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> radius;
  radius->SetName("Radius");
  vtkNew<vtkCellArray> lines;
  const vtkIdType nb = static_cast<vtkIdType>(tree.branches.size());
  auto branchId = IntArray("BranchId", nb), parentId = IntArray("ParentId", nb), depth = IntArray("Depth", nb);
  vtkIdType next = 0;
  for (vtkIdType t = 0; t < nb; ++t)
  {
    const plantmorph::TreeBranch& b = tree.branches[static_cast<std::size_t>(t)];
    lines->InsertNextCell(static_cast<vtkIdType>(b.centre.size()));
    for (std::size_t k = 0; k < b.centre.size(); ++k)
    {
      points->InsertNextPoint(b.centre[k].data());
      radius->InsertNextValue(b.radii[k]);
      lines->InsertCellPoint(next++);
    }
    branchId->SetValue(t, b.id);
    parentId->SetValue(t, b.parentId);
    depth->SetValue(t, b.depth);
  }
  skeletonOut->SetPoints(points);
  skeletonOut->SetLines(lines);
  skeletonOut->GetPointData()->AddArray(radius);
  skeletonOut->GetPointData()->SetActiveScalars("Radius");
  skeletonOut->GetCellData()->AddArray(branchId);
  skeletonOut->GetCellData()->AddArray(parentId);
  skeletonOut->GetCellData()->AddArray(depth);
}

/// The leaves port's arrays while WriteLeaves fills them.
struct LeafArrays
{
  vtkNew<vtkPoints> points;
  vtkNew<vtkFloatArray> tcoords;
  vtkNew<vtkFloatArray> normals;
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkIntArray> branchId;
  vtkNew<vtkIntArray> cellLeafId, cellOrgan, pointLeafId, pointOrgan;
};

/// A textured quad of side `scale` at the leaf's place (no Leaf input).
void AppendQuadLeaf(const plantmorph::TreeLeaf& leaf, double scale, LeafArrays& out)
{
  const vtkIdType first = out.points->GetNumberOfPoints();
  const Eigen::Vector3d n = leaf.axes.col(2);
  const double half = 0.5 * scale;
  const Eigen::Vector3d x = leaf.axes.col(0), y = leaf.axes.col(1);
  const Eigen::Vector3d corners[4] = { leaf.origin - half * x, leaf.origin + half * x,
    leaf.origin + half * x + scale * y, leaf.origin - half * x + scale * y };
  const float uv[4][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } };
  out.polys->InsertNextCell(4);
  for (int k = 0; k < 4; ++k)
  {
    out.points->InsertNextPoint(corners[k].data());
    out.tcoords->InsertNextTuple2(uv[k][0], uv[k][1]);
    out.normals->InsertNextTuple3(n.x(), n.y(), n.z());
    out.polys->InsertCellPoint(first + k);
    out.pointLeafId->InsertNextValue(leaf.id);
    out.pointOrgan->InsertNextValue(OrganLeaf);
  }
  out.branchId->InsertNextValue(leaf.branchId);
  out.cellLeafId->InsertNextValue(leaf.id);
  out.cellOrgan->InsertNextValue(OrganLeaf);
}

void AppendLeafCells(const plantmorph::TreeLeaf& leaf, vtkPolyData* leafInput, vtkIdType first, LeafArrays& out);

/// A copy of the Leaf input (its base at y = leafMinY, scaled by `scale`) at the leaf's place, with its TCoords and
/// Normals (turned) when it has them.
void AppendInputLeaf(const plantmorph::TreeLeaf& leaf, vtkPolyData* leafInput, double scale, double leafLength,
  double leafMinY, LeafArrays& out)
{
  const vtkIdType first = out.points->GetNumberOfPoints();
  const Eigen::Vector3d n = leaf.axes.col(2);
  vtkDataArray* leafTCoords = leafInput->GetPointData()->GetTCoords();
  if (!leafTCoords)
  {
    leafTCoords = leafInput->GetPointData()->GetArray(plantmorph::arrays::TCoords);
  }
  vtkDataArray* leafNormals = leafInput->GetPointData()->GetNormals();
  for (vtkIdType k = 0; k < leafInput->GetNumberOfPoints(); ++k)
  {
    double p[3];
    leafInput->GetPoint(k, p);
    const Eigen::Vector3d local(p[0], p[1] - leafMinY, p[2]);
    const Eigen::Vector3d world = leaf.origin + leaf.axes * (scale * local);
    out.points->InsertNextPoint(world.data());
    if (leafTCoords && leafTCoords->GetNumberOfComponents() >= 2)
    {
      out.tcoords->InsertNextTuple2(leafTCoords->GetComponent(k, 0), leafTCoords->GetComponent(k, 1));
    }
    else
    {
      out.tcoords->InsertNextTuple2(0.5 + local.x() / leafLength, local.y() / leafLength);
    }
    Eigen::Vector3d normal = n;
    if (leafNormals && leafNormals->GetNumberOfComponents() == 3)
    {
      normal = leaf.axes *
        Eigen::Vector3d(
          leafNormals->GetComponent(k, 0), leafNormals->GetComponent(k, 1), leafNormals->GetComponent(k, 2));
    }
    out.normals->InsertNextTuple3(normal.x(), normal.y(), normal.z());
  }
  AppendLeafCells(leaf, leafInput, first, out);
}

/// The Leaf input's polygons of one leaf copy (its points from `first` on), with BranchId, LeafId and Organ: a cell
/// of Region petiole (the Leaf input's cell array, when it has one) is petiole, and its points unless a blade cell
/// uses them too.
void AppendLeafCells(const plantmorph::TreeLeaf& leaf, vtkPolyData* leafInput, vtkIdType first, LeafArrays& out)
{
  vtkNew<vtkIdList> ids;
  vtkCellArray* cells = leafInput->GetPolys();
  vtkDataArray* region = leafInput->GetCellData()->GetArray(plantmorph::arrays::Region);
  std::vector<int> pointOrgan(static_cast<std::size_t>(leafInput->GetNumberOfPoints()), -1);
  vtkIdType cell = leafInput->GetNumberOfVerts() + leafInput->GetNumberOfLines();
  for (cells->InitTraversal(); cells->GetNextCell(ids); ++cell)
  {
    const bool petiole = region && region->GetNumberOfTuples() > cell &&
      region->GetComponent(cell, 0) == static_cast<double>(plantmorph::RegionPetiole);
    out.polys->InsertNextCell(ids->GetNumberOfIds());
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      out.polys->InsertCellPoint(first + ids->GetId(k));
      int& organ = pointOrgan[static_cast<std::size_t>(ids->GetId(k))];
      organ = petiole ? (organ == -1 ? OrganPetiole : organ) : OrganLeaf;
    }
    out.branchId->InsertNextValue(leaf.branchId);
    out.cellLeafId->InsertNextValue(leaf.id);
    out.cellOrgan->InsertNextValue(petiole ? OrganPetiole : OrganLeaf);
  }
  for (const int organ : pointOrgan)
  {
    out.pointLeafId->InsertNextValue(leaf.id);
    out.pointOrgan->InsertNextValue(organ == OrganPetiole ? OrganPetiole : OrganLeaf);
  }
}

/// Port 2: the leaves, copies of the Leaf input (or textured quads without one) at each leaf's place, each its
/// TreeLeaf::length long.
void WriteLeaves(const std::vector<plantmorph::TreeLeaf>& leaves, vtkPolyData* leafInput, double leafLength,
  double leafMinY, vtkPolyData* leavesOut)
{
  LeafArrays out;
  out.points->SetDataTypeToDouble();
  out.tcoords->SetName(plantmorph::arrays::TCoords);
  out.tcoords->SetNumberOfComponents(2);
  out.normals->SetName(plantmorph::arrays::Normals);
  out.normals->SetNumberOfComponents(3);
  out.branchId->SetName("BranchId");
  out.cellLeafId->SetName(plantmorph::arrays::LeafId);
  out.cellOrgan->SetName(plantmorph::arrays::Organ);
  out.pointLeafId->SetName(plantmorph::arrays::LeafId);
  out.pointOrgan->SetName(plantmorph::arrays::Organ);
  for (const plantmorph::TreeLeaf& leaf : leaves)
  {
    const double scale = leafInput ? leaf.length / leafLength : leaf.length;
    if (leafInput)
    {
      AppendInputLeaf(leaf, leafInput, scale, leafLength, leafMinY, out);
    }
    else
    {
      AppendQuadLeaf(leaf, scale, out);
    }
  }
  leavesOut->SetPoints(out.points);
  leavesOut->SetPolys(out.polys);
  leavesOut->GetPointData()->SetTCoords(out.tcoords);
  leavesOut->GetPointData()->SetNormals(out.normals);
  leavesOut->GetCellData()->AddArray(out.branchId);
  leavesOut->GetCellData()->AddArray(out.cellLeafId);
  leavesOut->GetCellData()->AddArray(out.cellOrgan);
  leavesOut->GetPointData()->AddArray(out.pointLeafId);
  leavesOut->GetPointData()->AddArray(out.pointOrgan);
}

/// A small input (strokes, a leaf, a skeleton to merge) whole on every rank, for a tree made by pieces. Collective:
/// every rank calls it for the same connected ports. Rank 0's input is broadcast when no other rank holds different
/// data (our sources make it on rank 0 alone; a programmable source makes it on every rank, the same); an input split
/// over the ranks (D3, a partitioned reader) is first gathered on rank 0 (PlantMorphWholeInput.h). Serially the input
/// itself.
vtkSmartPointer<vtkPolyData> WholeOnEveryRank(vtkPolyData* piece)
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!controller || controller->GetNumberOfProcesses() < 2)
  {
    return piece;
  }
  const int ranks = controller->GetNumberOfProcesses();
  const vtkIdType mine[2] = { piece ? piece->GetNumberOfPoints() : 0, piece ? piece->GetNumberOfCells() : 0 };
  std::vector<vtkIdType> all(2 * static_cast<std::size_t>(ranks));
  controller->AllGather(mine, all.data(), 2);
  bool split = false;
  for (int rank = 1; rank < ranks; ++rank)
  {
    const std::size_t r = 2 * static_cast<std::size_t>(rank);
    split = split || (all[r] > 0 && (all[r] != all[0] || all[r + 1] != all[1]));
  }
  vtkSmartPointer<vtkPolyData> whole = piece;
  if (split)
  {
    whole = plantmorph::GatherOnFirstRank(piece);
  }
  if (controller->GetLocalProcessId() != 0 || !whole)
  {
    whole = vtkSmartPointer<vtkPolyData>::New();
  }
  controller->Broadcast(whole, 0);
  return whole;
}

/// The piece this request asks for; pieces below 1 (a request without them) mean the whole tree.
void RequestedPiece(vtkInformation* info, int& piece, int& pieces)
{
  piece = info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    ? info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    : 0;
  pieces = info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    ? info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    : 1;
  if (pieces < 1)
  {
    piece = 0, pieces = 1;
  }
}

/// The leaves on the selected branches (all of them without a selection), in the tree's order.
std::vector<plantmorph::TreeLeaf> LeavesOf(const plantmorph::Tree& tree, const std::vector<char>* selected)
{
  if (!selected)
  {
    return tree.leaves;
  }
  std::set<int> ids;
  for (std::size_t t = 0; t < tree.branches.size(); ++t)
  {
    if ((*selected)[t])
    {
      ids.insert(tree.branches[t].id);
    }
  }
  std::vector<plantmorph::TreeLeaf> leaves;
  for (const plantmorph::TreeLeaf& leaf : tree.leaves)
  {
    if (ids.count(leaf.branchId))
    {
      leaves.push_back(leaf);
    }
  }
  return leaves;
}
/// BranchOverrides' rows of six (BranchId, length, radius, u, angle, rotation) into `s.overrides`; "" or the
/// message naming the bad row.
std::string ReadBranchOverrides(const std::vector<double>& rows, plantmorph::TreeParameters& s)
{
  for (std::size_t r = 0; r + 6 <= rows.size(); r += 6)
  {
    const double id = rows[r];
    if (!std::isfinite(id) || id < 0 || id > std::numeric_limits<int>::max() || id != std::floor(id))
    {
      return "BranchOverrides row " + std::to_string(r / 6) + ": " +
        plantmorph::OutOfRange("BranchId", id, "[0, 2147483647]", "a whole number");
    }
    // NaN or <= -1000 keeps: ParaView 5.11 state files do not keep NaN (it loads as 0), so -1000 is the
    // spelling that survives a save and a load.
    const auto keep = [](double v) { return v <= -1000.0 ? std::numeric_limits<double>::quiet_NaN() : v; };
    plantmorph::BranchOverride& o = s.overrides[static_cast<int>(id)];
    o.length = keep(rows[r + 1]);
    o.radius = keep(rows[r + 2]);
    o.u = keep(rows[r + 3]);
    o.angle = keep(rows[r + 4]);
    o.rotation = keep(rows[r + 5]);
  }
  return {};
}
} // namespace

//------------------------------------------------------------------------------
vtkTreeFromSketchSource::vtkTreeFromSketchSource()
{
  this->SetNumberOfInputPorts(3);
  this->SetNumberOfOutputPorts(3);
}

void vtkTreeFromSketchSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << this->Mode << "\n"
     << indent << "Preset: " << this->Preset << "\n"
     << indent << "TreeType: " << this->TreeType << "\n"
     << indent << "Length: " << this->Length << "\n"
     << indent << "Radius: " << this->Radius << "\n"
     << indent << "Depth: " << this->Depth << "\n"
     << indent << "Phyllotaxis: " << this->PhyllotaxisA << "/" << this->PhyllotaxisB << "\n"
     << indent << "ChildCount: " << this->ChildCount << "\n"
     << indent << "Ratio: " << this->Ratio << "\n"
     << indent << "SegmentsPerBranch: " << this->SegmentsPerBranch << "\n"
     << indent << "Sides: " << this->Sides << "\n"
     << indent << "Joints: " << this->Joints << "\n"
     << indent << "StrokeFile: " << this->StrokeFile << "\n"
     << indent << "Leaves: " << this->Leaves << " type " << this->LeafType << " count " << this->LeafCount << "\n"
     << indent << "Seed: " << this->Seed << "\n"
     << indent << "Merge: parent " << this->MergeParentBranch << " u " << this->MergeU << " angle " << this->MergeAngle
     << " rotation " << this->MergeRotation << " scale " << this->MergeScale << "\n"
     << indent << "DeletedBranches: " << this->DeletedBranches.size() << "\n"
     << indent << "BranchOverrides: " << this->BranchOverrides.size() / 6 << "\n";
}

void vtkTreeFromSketchSource::SetStrokeFile(const char* path)
{
  const std::string value = path ? path : "";
  if (value != this->StrokeFile)
  {
    this->StrokeFile = value;
    this->Modified();
  }
}

void vtkTreeFromSketchSource::ClearDeletedBranches()
{
  if (!this->DeletedBranches.empty())
  {
    this->DeletedBranches.clear();
    this->Modified();
  }
}

void vtkTreeFromSketchSource::AddDeletedBranch(int id)
{
  this->DeletedBranches.push_back(id);
  this->Modified();
}

void vtkTreeFromSketchSource::ClearBranchOverrides()
{
  this->BranchOverridesElementCount = -1;
  if (!this->BranchOverrides.empty())
  {
    this->BranchOverrides.clear();
    this->Modified();
  }
}

void vtkTreeFromSketchSource::AddBranchOverride(
  double id, double length, double radius, double u, double angle, double rotation)
{
  this->BranchOverrides.insert(this->BranchOverrides.end(), { id, length, radius, u, angle, rotation });
  this->Modified();
}

void vtkTreeFromSketchSource::SetBranchOverridesElementCount(int count)
{
  if (count != this->BranchOverridesElementCount)
  {
    this->BranchOverridesElementCount = count;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkTreeFromSketchSource::SetStrokesConnection(int, vtkAlgorithmOutput* output)
{
  this->SetInputConnection(0, output);
}

void vtkTreeFromSketchSource::SetLeafConnection(int, vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

void vtkTreeFromSketchSource::SetMergeTreeConnection(int, vtkAlgorithmOutput* output)
{
  this->SetInputConnection(2, output);
}

void vtkTreeFromSketchSource::WarnAboutPresetOverrides(const plantmorph::TreeParameters& used)
{
  if (this->Preset == 0)
  {
    return;
  }
  // A property the user changed from its default while a named preset is on is not what the output has: say so.
  vtkNew<vtkTreeFromSketchSource> defaults;
  std::ostringstream ignored;
  const auto check = [&](const char* name, double set, double byDefault, double byPreset) {
    if (set != byDefault && set != byPreset)
    {
      ignored << (ignored.tellp() > 0 ? ", " : "") << name << " = " << set << " (the preset's: " << byPreset << ")";
    }
  };
  check("TreeType", this->TreeType, defaults->TreeType, static_cast<int>(used.type));
  check("Length", this->Length, defaults->Length, used.length);
  check("Radius", this->Radius, defaults->Radius, used.radius);
  check("Depth", this->Depth, defaults->Depth, used.depth);
  check("PhyllotaxisA", this->PhyllotaxisA, defaults->PhyllotaxisA, used.phyllotaxisA);
  check("PhyllotaxisB", this->PhyllotaxisB, defaults->PhyllotaxisB, used.phyllotaxisB);
  check("ChildCount", this->ChildCount, defaults->ChildCount, used.childCount);
  check("Ratio", this->Ratio, defaults->Ratio, used.ratio);
  if (ignored.tellp() > 0)
  {
    vtkWarningMacro(<< "Preset \"" << plantmorph::TreePresetName(this->Preset) << "\" sets TreeType, Length, Radius, "
                    << "Depth, PhyllotaxisA/B, ChildCount and Ratio, so these values are not used: " << ignored.str()
                    << ". Set Preset to Custom (0) to use them.");
  }
}

const char* vtkTreeFromSketchSource::GetPresetValues()
{
  std::ostringstream text;
  if (this->Preset <= 0 || this->Preset >= plantmorph::TreePresetCount)
  {
    text << (this->Preset == 0 ? "Custom: the template properties are used as set." : "Preset is out of range.");
  }
  else
  {
    plantmorph::TreeParameters s;
    plantmorph::ApplyTreePreset(this->Preset, s);
    text << plantmorph::TreePresetName(this->Preset) << " sets (the greyed properties are not used):\nTreeType = "
         << (s.type == plantmorph::TreeType::Monopodial ? "Monopodial" : "Sympodial") << "\nLength = " << s.length
         << "\nRadius = " << s.radius << "\nDepth = " << s.depth << "\nPhyllotaxisA = " << s.phyllotaxisA
         << "\nPhyllotaxisB = " << s.phyllotaxisB << "\nChildCount = " << s.childCount << "\nRatio = " << s.ratio;
  }
  this->PresetValues = text.str();
  return this->PresetValues.c_str();
}

int vtkTreeFromSketchSource::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkTreeFromSketchSource::RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector* out)
{
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    out->GetInformationObject(port)->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
  }
  return 1;
}

//------------------------------------------------------------------------------
std::string vtkTreeFromSketchSource::ReadProperties(plantmorph::TreeParameters& s)
{
  if (this->BranchOverridesElementCount >= 0 &&
    static_cast<std::size_t>(this->BranchOverridesElementCount) != this->BranchOverrides.size())
  {
    // ParaView pushed only the whole rows: a partial row means the user's list is not rows of six.
    return plantmorph::OutOfRange("BranchOverrides", std::to_string(this->BranchOverridesElementCount) + " numbers",
      "{0, 6, 12, ...}",
      "rows of six: BranchId, length, radius, u, angle, rotation; the last row has " +
        std::to_string(this->BranchOverridesElementCount % 6));
  }
  if (this->Preset < 0 || this->Preset >= plantmorph::TreePresetCount)
  {
    return plantmorph::OutOfRange("Preset", this->Preset, "[0, 3]", "0 Custom, 1-3 Table 1");
  }
  s.mode = static_cast<plantmorph::TreeMode>(this->Mode);
  s.type = static_cast<plantmorph::TreeType>(this->TreeType);
  s.length = this->Length;
  s.radius = this->Radius;
  s.depth = this->Depth;
  s.phyllotaxisA = this->PhyllotaxisA;
  s.phyllotaxisB = this->PhyllotaxisB;
  s.childCount = this->ChildCount;
  s.ratio = this->Ratio;
  plantmorph::ApplyTreePreset(this->Preset, s);
  this->WarnAboutPresetOverrides(s);
  s.lengthScale = this->LengthScale;
  s.monopodialAngle = this->MonopodialAngle;
  s.sympodialAngle = this->SympodialAngle;
  s.segmentsPerBranch = this->SegmentsPerBranch;
  s.twigScale = this->TwigScale;
  s.sides = this->Sides;
  s.maxSegments = this->MaxSegments;
  s.strokeControlPoints = this->StrokeControlPoints;
  s.strokeLengthRatio = this->StrokeLengthRatio;
  s.strokesOnly = this->StrokesOnly != 0;
  s.strokeSubtreeDepth = this->StrokeSubtreeDepth;
  s.leaves = this->Leaves != 0;
  s.leafType = static_cast<plantmorph::LeafType>(this->LeafType);
  s.leafCount = this->LeafCount;
  s.leafRatio = this->LeafRatio;
  s.leafScale = this->LeafScale;
  s.leafAngle = this->LeafAngle;
  s.leafTipScale = this->LeafTipScale;
  s.leafScaleSpread = this->LeafScaleSpread;
  s.seed = static_cast<std::uint64_t>(static_cast<std::int64_t>(this->Seed));
  s.mergeParent = this->MergeParentBranch;
  s.mergeU = this->MergeU;
  s.mergeAngle = this->MergeAngle;
  s.mergeRotation = this->MergeRotation;
  s.mergeScale = this->MergeScale;
  s.mergeOffset = Eigen::Vector3d(this->MergeOffset[0], this->MergeOffset[1], this->MergeOffset[2]);
  s.deletedBranches.insert(this->DeletedBranches.begin(), this->DeletedBranches.end());
  return ReadBranchOverrides(this->BranchOverrides, s);
}

//------------------------------------------------------------------------------
void vtkTreeFromSketchSource::FillFieldData(plantmorph::FieldRecord& parameters, const plantmorph::TreeParameters& s,
  const plantmorph::Tree& tree, std::size_t strokeCount, const plantmorph::JointReport& joints,
  const plantmorph::JunctionReport& junctions) const
{
  parameters.Add("Model", "TreeFromSketch");
  parameters.Add("TreePreset", plantmorph::TreePresetName(this->Preset));
  parameters.Add("Mode", this->Mode);
  parameters.Add("TreeType", static_cast<int>(s.type));
  parameters.Add("Length", s.length);
  parameters.Add("Radius", s.radius);
  parameters.Add("Depth", s.depth);
  parameters.Add("PhyllotaxisA", s.phyllotaxisA);
  parameters.Add("PhyllotaxisB", s.phyllotaxisB);
  parameters.Add("ChildCount", s.childCount);
  parameters.Add("Ratio", s.ratio);
  parameters.Add("SegmentsPerBranch", s.segmentsPerBranch);
  parameters.Add("Seed", this->Seed);
  parameters.Add("BranchCount", static_cast<double>(tree.branches.size()));
  parameters.Add("SegmentCount", static_cast<double>(tree.SegmentCount()));
  parameters.Add("LeafCount", static_cast<double>(tree.leaves.size()));
  parameters.Add("StrokeCount", static_cast<double>(strokeCount));
  parameters.Add("MergeIdBase", static_cast<double>(tree.mergeIdBase));
  parameters.AddTuple("JointRingVertices", { "Seated", "Missed", "Clamped", "Buried" },
    { double(joints.seated), double(joints.missed), double(joints.clamped), double(joints.buried) });
  parameters.Add("Joints", this->Joints);
  parameters.AddTuple("Junctions", { "Junctions", "Welded", "Merged", "AtEnds", "Narrowed", "Fallback" },
    { double(junctions.junctions), double(junctions.welded), double(junctions.merged), double(junctions.endJunctions),
      double(junctions.narrowed), double(junctions.fallback) });
  std::vector<double> strokes;
  for (const plantmorph::StrokeReport& r : tree.strokes)
  {
    strokes.insert(
      strokes.end(), { double(r.branchId), double(r.parentId), r.lambda, r.recommendedTheta, r.theta, r.rotation });
  }
  parameters.AddRows(
    "Strokes", 6, strokes, { "BranchId", "ParentId", "Lambda", "RecommendedTheta", "Theta", "RotationAngle" });
}

//------------------------------------------------------------------------------
namespace
{
/// Every piece builds the same (small) skeleton and then its own share of the branch surfaces
/// (sources/tree/tubes/BranchPieces.h); the small inputs are made whole on every rank first.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::DataParallel;

/// The branch surfaces of this piece (all of them with one piece) and the build's reports.
struct Surfaces
{
  plantmorph::TubeMesh mesh;
  plantmorph::JointReport joints;
  plantmorph::JunctionReport junctions;
  std::vector<char> selected; // the branches of this piece; empty: all
};

/// Welded by convex-hull junctions into one closed surface per tree (Joints 0), or each branch its own closed tube
/// with its base ring seated on its parent (Joints 1). A piece builds the branches the plan gives it.
void BuildSurfaces(const plantmorph::Run& run, const plantmorph::Tree& tree, const plantmorph::TreeParameters& s,
  int joints, int piece, int pieces, Surfaces& out)
{
  const std::vector<plantmorph::TubeInput> tubes = plantmorph::TreeTubeInputs(tree);
  if (pieces > 1)
  {
    out.selected =
      plantmorph::TubesOfPiece(plantmorph::PlanPieces(tubes, plantmorph::MergedRoots(tree), pieces), piece);
  }
  const std::vector<char>* only = pieces > 1 ? &out.selected : nullptr;
  run.Check(joints == 0
      ? plantmorph::BuildWeldedTubes(tubes, s.sides, out.mesh, plantmorph::SMPFor(), &out.junctions, only)
      : plantmorph::BuildTubes(tubes, s.sides, out.mesh, plantmorph::SMPFor(), &out.joints, only));
}

/// Which piece (of how many) the port this update is for asks (the other ports' requests may be absent or stale).
void PieceAsked(const plantmorph::Run& run, int& piece, int& pieces)
{
  vtkInformation* request = run.RequestInformation();
  const int port =
    request && request->Has(vtkExecutive::FROM_OUTPUT_PORT()) ? request->Get(vtkExecutive::FROM_OUTPUT_PORT()) : 0;
  RequestedPiece(run.OutputInformation(port >= 0 && port < 3 ? port : 0), piece, pieces);
}

/// The Leaf input with its length and base (ValidateLeafInput), and this piece.
struct LeafInput
{
  vtkPolyData* data;
  double length;
  double minY;
};
struct Piece
{
  int number;
  int count;
};

/// The three ports and their PlantMorph.* field data.
void WriteOutputs(vtkAlgorithm* self, plantmorph::Run& run, const plantmorph::TreeParameters& s,
  const plantmorph::Tree& tree, Surfaces& surfaces, const LeafInput& leafInput, const Piece& piece,
  plantmorph::FieldRecord& parameters)
{
  if (piece.count > 1)
  {
    vtkNew<vtkIntArray> where;
    where->SetName("PlantMorph.Piece");
    where->SetNumberOfComponents(2);
    where->SetComponentName(0, "Piece");
    where->SetComponentName(1, "Pieces");
    where->InsertNextTuple2(piece.number, piece.count);
    parameters.AddArray(where);
  }
  run.Building("the tree's outputs");
  WriteBranches(surfaces.mesh, tree, run.Output<vtkPolyData>(0)); // hands the mesh over: left empty
  AddConstantOrganArrays(run.Output<vtkPolyData>(0), OrganWood, -1);
  self->UpdateProgress(0.8);
  if (piece.number == 0)
  {
    WriteSkeleton(tree, run.Output<vtkPolyData>(1)); // small: whole on piece 0 (see the class documentation)
  }
  const std::vector<plantmorph::TreeLeaf> leaves = LeavesOf(tree, piece.count > 1 ? &surfaces.selected : nullptr);
  if (s.leaves && !leaves.empty())
  {
    WriteLeaves(leaves, leafInput.data, leafInput.length, leafInput.minY, run.Output<vtkPolyData>(2));
  }
  run.WriteToEveryOutput(parameters);
}
} // namespace

//------------------------------------------------------------------------------
int vtkTreeFromSketchSource::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(
    this, Policy, "the tree", request, inputVector, outputVector, [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkTreeFromSketchSource::Execute(plantmorph::Run& run)
{
  int piece = 0, pieces = 1;
  PieceAsked(run, piece, pieces);
  if (piece < 0 || piece >= pieces)
  {
    return; // no such piece: nothing (a streaming request beyond the last piece)
  }
  // The small inputs whole on every rank (collective: before anything may stop on one rank but not another).
  vtkSmartPointer<vtkPolyData> inputs[3];
  for (int port = 0; port < 3; ++port)
  {
    inputs[port] =
      this->GetNumberOfInputConnections(port) > 0 ? WholeOnEveryRank(run.Input<vtkPolyData>(port)) : nullptr;
  }
  inputs[1] = LeafPolygons(inputs[1]);
  plantmorph::TreeParameters s;
  run.Check(this->ReadProperties(s));
  // Strokes: the input's lines, else the file. A second tree to merge: a skeleton (lines) with BranchId and
  // ParentId on its cells and Radius on its points.
  std::vector<std::vector<Eigen::Vector3d>> strokes;
  std::vector<std::string> origins; // where each stroke of the StrokeFile comes from, for errors
  if (s.mode != plantmorph::TreeMode::Template)
  {
    run.Check(ReadStrokes(inputs[0], this->StrokeFile, strokes, origins));
  }
  std::vector<plantmorph::SkeletonBranch> second;
  vtkPolyData* mergeInput = inputs[2];
  if (mergeInput)
  {
    run.Check(ReadSkeleton(mergeInput, second));
  }
  this->UpdateProgress(0.05);
  if (this->Joints != 0 && this->Joints != 1)
  {
    run.Fail(plantmorph::OutOfRange("Joints", this->Joints, "[0, 1]", "0 Welded, 1 Seated tubes"));
  }
  plantmorph::Tree tree;
  const std::string built = plantmorph::BuildTree(s, strokes, mergeInput ? &second : nullptr, tree);
  run.Check(
    inputs[0] || this->StrokeFile.empty() ? built : plantmorph::StrokeFileError(built, this->StrokeFile, origins));
  this->UpdateProgress(0.3);
  run.StopIfAborted();
  run.Building("the tree's branch surfaces");
  Surfaces surfaces;
  BuildSurfaces(run, tree, s, this->Joints, piece, pieces, surfaces);
  this->UpdateProgress(0.6);
  // Leaf geometry input: validated before anything is written.
  double leafLength = 0.0, leafMinY = 0.0;
  if (s.leaves && inputs[1])
  {
    run.Check(ValidateLeafInput(inputs[1], tree, s, leafLength, leafMinY));
  }
  plantmorph::FieldRecord parameters;
  this->FillFieldData(parameters, s, tree, strokes.size(), surfaces.joints, surfaces.junctions);
  WriteOutputs(this, run, s, tree, surfaces, { inputs[1], leafLength, leafMinY }, { piece, pieces }, parameters);
  this->UpdateProgress(1.0);
}
