// SPDX-License-Identifier: GPL-3.0-or-later
// vtkTreeFromSketchSource (docs/methods/tree-from-sketch.md): outputs and arrays, closed manifold branch surface,
// strokes from the input port and a CSV file, leaf instances, one piece under MPI, determinism, errors, empty outputs.
#include "TemporaryPath.h"
#include "VtkErrorCatcher.h"
#include "vtkTreeFromSketchSource.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkFeatureEdges.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataConnectivityFilter.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace
{
using plantmorph::testing::ErrorCatcher;

vtkPolyData* Output(vtkTreeFromSketchSource* s, int port)
{
  return vtkPolyData::SafeDownCast(s->GetOutputDataObject(port));
}

vtkSmartPointer<vtkPolyData> Strokes(const std::vector<std::vector<std::pair<double, double>>>& lines)
{
  auto data = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble(); // the CSV path reads doubles: compare like with like
  vtkNew<vtkCellArray> cells;
  for (const auto& line : lines)
  {
    cells->InsertNextCell(static_cast<vtkIdType>(line.size()));
    for (const auto& [x, y] : line)
      cells->InsertCellPoint(points->InsertNextPoint(x, y, 0.0));
  }
  data->SetPoints(points);
  data->SetLines(cells);
  return data;
}

const std::vector<std::vector<std::pair<double, double>>> SampleLines = {
  { { 0, 0 }, { 0.2, 3 }, { -0.1, 6 }, { 0.1, 9 }, { 0, 12 } },
  { { 0.3, 6 }, { 1.5, 7.5 }, { 3, 8.2 }, { 4, 10 } },
  { { -0.2, 4 }, { -1, 5 }, { -2.5, 5.5 }, { -3.5, 7 }, { -4, 8 } },
};
} // namespace

TEST(TreeFromSketchSource, Table1PresetGivesEveryBranchAsAClosedTubeWithArrays)
{
  vtkNew<vtkTreeFromSketchSource> source; // Preset 1 by default
  source->Update();
  vtkPolyData* branches = Output(source, 0);
  vtkPolyData* skeleton = Output(source, 1);
  vtkPolyData* leaves = Output(source, 2);
  EXPECT_EQ(skeleton->GetNumberOfLines(), 4681);
  auto* branchId = vtkIntArray::SafeDownCast(branches->GetCellData()->GetArray("BranchId"));
  ASSERT_NE(branchId, nullptr);
  ASSERT_NE(branches->GetCellData()->GetArray("ParentId"), nullptr);
  ASSERT_NE(branches->GetCellData()->GetArray("Depth"), nullptr);
  EXPECT_EQ(branchId->GetNumberOfTuples(), branches->GetNumberOfCells());
  std::set<int> ids;
  for (vtkIdType c = 0; c < branchId->GetNumberOfTuples(); ++c)
    ids.insert(branchId->GetValue(c));
  EXPECT_EQ(ids.size(), 4681u);
  EXPECT_EQ(*ids.rbegin(), 4680);
  double depthRange[2];
  branches->GetCellData()->GetArray("Depth")->GetRange(depthRange);
  EXPECT_EQ(depthRange[0], 0.0);
  EXPECT_EQ(depthRange[1], 4.0);
  ASSERT_NE(branches->GetPointData()->GetTCoords(), nullptr);
  EXPECT_STREQ(branches->GetPointData()->GetTCoords()->GetName(), "TCoords");
  ASSERT_NE(branches->GetPointData()->GetNormals(), nullptr);
  ASSERT_NE(skeleton->GetPointData()->GetArray("Radius"), nullptr);
  // Leaves: 8^4 twigs x 6 quads.
  EXPECT_EQ(leaves->GetNumberOfPolys(), 4096 * 6);
  ASSERT_NE(leaves->GetPointData()->GetTCoords(), nullptr);
  auto* model = vtkStringArray::SafeDownCast(branches->GetFieldData()->GetAbstractArray("PlantMorph.Model"));
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->GetValue(0), "TreeFromSketch");
  // Closed manifold: every edge of the surface in exactly two triangles, once in each direction.
  std::map<std::pair<vtkIdType, vtkIdType>, int> directed;
  vtkNew<vtkIdList> cell;
  vtkCellArray* polys = branches->GetPolys();
  for (polys->InitTraversal(); polys->GetNextCell(cell);)
  {
    ASSERT_EQ(cell->GetNumberOfIds(), 3);
    for (int e = 0; e < 3; ++e)
      directed[{ cell->GetId(e), cell->GetId((e + 1) % 3) }]++;
  }
  int bad = 0;
  for (const auto& [edge, count] : directed)
    bad += count != 1 || directed.count({ edge.second, edge.first }) != 1;
  EXPECT_EQ(bad, 0);
}

TEST(TreeFromSketchSource, PiecesSplitBranchesAndLeavesSkeletonOnPieceZero)
{
  // Each piece holds its own branches (BranchPieces.h; the exact triangle sets: TreePiecesTest.cpp and
  // test_mpi_tree_pieces.py) and leaves; the skeleton is whole on piece 0 only.
  vtkNew<vtkTreeFromSketchSource> source;
  source->SetPreset(2);
  source->SetLeaves(1);
  source->Update();
  const vtkIdType triangles = Output(source, 0)->GetNumberOfCells();
  const vtkIdType leaves = Output(source, 2)->GetNumberOfCells();
  ASSERT_GT(leaves, 0);
  for (int pieces : { 2, 3 })
  {
    vtkIdType sumTriangles = 0, sumLeaves = 0;
    for (int piece = 0; piece < pieces; ++piece)
    {
      source->UpdatePiece(piece, pieces, 0);
      const vtkIdType mine = Output(source, 0)->GetNumberOfCells();
      EXPECT_GT(mine, 0);
      EXPECT_LT(mine, triangles);
      sumTriangles += mine;
      sumLeaves += Output(source, 2)->GetNumberOfCells();
      EXPECT_EQ(Output(source, 1)->GetNumberOfLines(), piece == 0 ? 1093 : 0) << piece << " of " << pieces;
    }
    EXPECT_EQ(sumTriangles, triangles) << pieces << " pieces";
    EXPECT_EQ(sumLeaves, leaves) << pieces << " pieces";
  }
}

TEST(TreeFromSketchSource, StrokesFromThePortAndFromACsvFileGiveTheSameTree)
{
  vtkNew<vtkTreeFromSketchSource> source;
  source->SetMode(1);
  source->SetStrokesOnly(1);
  source->SetSegmentsPerBranch(12);
  auto strokes = Strokes(SampleLines);
  source->SetInputData(0, strokes);
  source->Update();
  vtkPolyData* skeleton = Output(source, 1);
  ASSERT_EQ(skeleton->GetNumberOfLines(), 3);
  // Each branch ends straight above its stroke's last point (a Bezier curve ends at its last control point).
  vtkNew<vtkIdList> cell;
  vtkCellArray* lines = skeleton->GetLines();
  int k = 0;
  for (lines->InitTraversal(); lines->GetNextCell(cell); ++k)
  {
    double p[3];
    skeleton->GetPoint(cell->GetId(cell->GetNumberOfIds() - 1), p);
    EXPECT_NEAR(p[0], SampleLines[std::size_t(k)].back().first, 1e-9);
    EXPECT_NEAR(p[1], SampleLines[std::size_t(k)].back().second, 1e-9);
  }
  // Strokes 1 and 2 leave the image plane (theta > 0), on opposite depth sides or not, but not at z = 0.
  double bounds[6];
  skeleton->GetBounds(bounds);
  EXPECT_GT(bounds[5] - bounds[4], 0.1);
  EXPECT_EQ(Output(source, 0)->GetCellData()->GetArray("BranchId")->GetRange()[1], 2.0);

  const std::string path = plantmorph::testing::TemporaryPath("plantmorph_tree", "tree_strokes.csv");
  {
    std::ofstream csv(path);
    csv << "stroke_id,x,y\n";
    for (std::size_t s = 0; s < SampleLines.size(); ++s)
      for (const auto& [x, y] : SampleLines[s])
        csv << s << "," << x << "," << y << "\n";
  }
  vtkNew<vtkTreeFromSketchSource> fromFile;
  fromFile->SetMode(1);
  fromFile->SetStrokesOnly(1);
  fromFile->SetSegmentsPerBranch(12);
  fromFile->SetStrokeFile(path.c_str());
  fromFile->Update();
  vtkPolyData* other = Output(fromFile, 1);
  ASSERT_EQ(other->GetNumberOfPoints(), skeleton->GetNumberOfPoints());
  for (vtkIdType i = 0; i < other->GetNumberOfPoints(); ++i)
  {
    double a[3], b[3];
    skeleton->GetPoint(i, a);
    other->GetPoint(i, b);
    EXPECT_EQ(a[0], b[0]);
    EXPECT_EQ(a[1], b[1]);
    EXPECT_EQ(a[2], b[2]);
  }
  std::remove(path.c_str());
}

TEST(TreeFromSketchSource, LeafInputIsInstancedAtEveryLeafScaledToLeafScale)
{
  vtkNew<vtkPolyData> leaf;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(-0.5, 0, 0);
  points->InsertNextPoint(0.5, 0, 0);
  points->InsertNextPoint(0, 2, 0);
  vtkNew<vtkCellArray> triangle;
  const vtkIdType ids[3] = { 0, 1, 2 };
  triangle->InsertNextCell(3, ids);
  leaf->SetPoints(points);
  leaf->SetPolys(triangle);
  vtkNew<vtkTreeFromSketchSource> source;
  source->SetPreset(0); // Custom: Table 1's sympodial tree with depth 3 (3^3 twigs)
  source->SetTreeType(1);
  source->SetDepth(3);
  source->SetChildCount(3);
  source->SetRatio(0.0);
  source->SetLength(5.0);
  source->SetPhyllotaxisA(1);
  source->SetPhyllotaxisB(3);
  source->SetLeafCount(4);
  source->SetLeafScale(0.5);
  source->SetInputData(1, leaf);
  source->Update();
  vtkPolyData* leaves = Output(source, 2);
  EXPECT_EQ(leaves->GetNumberOfPolys(), 27 * 4);
  EXPECT_EQ(leaves->GetNumberOfPoints(), 27 * 4 * 3);
  // Each copy is LeafScale long: base midpoint to tip.
  for (vtkIdType l = 0; l < 27 * 4; ++l)
  {
    double a[3], b[3], tip[3];
    leaves->GetPoint(3 * l, a);
    leaves->GetPoint(3 * l + 1, b);
    leaves->GetPoint(3 * l + 2, tip);
    const double length = std::sqrt(std::pow(tip[0] - 0.5 * (a[0] + b[0]), 2) +
      std::pow(tip[1] - 0.5 * (a[1] + b[1]), 2) + std::pow(tip[2] - 0.5 * (a[2] + b[2]), 2));
    EXPECT_NEAR(length, 0.5, 1e-12);
  }
}

TEST(TreeFromSketchSource, SameSettingsGiveBitIdenticalOutputs)
{
  const auto build = [](vtkTreeFromSketchSource* s) {
    s->SetMode(2);
    s->SetPreset(2);
    s->SetDepth(3);
    s->SetSeed(7);
    s->AddDeletedBranch(5);
    s->AddBranchOverride(2, 3.0, NAN, NAN, 20.0, NAN);
    s->SetInputData(0, Strokes(SampleLines));
    s->Update();
  };
  vtkNew<vtkTreeFromSketchSource> a, b;
  build(a);
  build(b);
  for (int port = 0; port < 3; ++port)
  {
    vtkDataArray* pa = Output(a, port)->GetPoints()->GetData();
    vtkDataArray* pb = Output(b, port)->GetPoints()->GetData();
    ASSERT_EQ(pa->GetNumberOfValues(), pb->GetNumberOfValues());
    ASSERT_GT(pa->GetNumberOfValues(), 0);
    for (vtkIdType i = 0; i < pa->GetNumberOfValues(); ++i)
      ASSERT_EQ(pa->GetVariantValue(i).ToDouble(), pb->GetVariantValue(i).ToDouble());
  }
}

TEST(TreeFromSketchSource, BadInputGivesAnErrorNamingItAndEmptyOutputs)
{
  struct Case
  {
    std::string expected;
    std::function<void(vtkTreeFromSketchSource*)> apply;
  };
  const std::vector<Case> cases = {
    { "Length", [](vtkTreeFromSketchSource* s) { s->SetPreset(0), s->SetLength(-1); } },
    { "Ratio", [](vtkTreeFromSketchSource* s) { s->SetPreset(0), s->SetRatio(NAN); } },
    { "Sides", [](vtkTreeFromSketchSource* s) { s->SetSides(2); } },
    { "Joints = 2 is outside the accepted range [0, 1]", [](vtkTreeFromSketchSource* s) { s->SetJoints(2); } },
    { "MaxSegments", [](vtkTreeFromSketchSource* s) { s->SetMaxSegments(1000); } },
    { "Preset", [](vtkTreeFromSketchSource* s) { s->SetPreset(9); } },
    { "Strokes input", [](vtkTreeFromSketchSource* s) { s->SetMode(1); } },
    { "stroke 1",
      [](vtkTreeFromSketchSource* s) {
        s->SetMode(1);
        s->SetInputData(0, Strokes({ { { 0, 0 }, { 0, 1 } }, { { 1, 1 } } }));
      } },
    { "not finite",
      [](vtkTreeFromSketchSource* s) {
        s->SetMode(1);
        s->SetInputData(0, Strokes({ { { 0, 0 }, { 0, NAN } } }));
      } },
    { "StrokeFile",
      [](vtkTreeFromSketchSource* s) {
        s->SetMode(1);
        s->SetStrokeFile("/nonexistent/strokes.csv");
      } },
    { "BranchOverrides", [](vtkTreeFromSketchSource* s) { s->AddBranchOverride(-3, 1, 1, 0.5, 10, 10); } },
    // What ParaView's push of BranchOverrides = [1, 2, 3] does: no whole row, then the raw count.
    { "BranchOverrides = 3 numbers is outside the accepted range {0, 6, 12, ...}",
      [](vtkTreeFromSketchSource* s) {
        s->ClearBranchOverrides();
        s->SetBranchOverridesElementCount(3);
      } },
    { "Merge input is not a tree: it has no lines",
      [](vtkTreeFromSketchSource* s) {
        vtkNew<vtkTreeFromSketchSource> second; // its Branches port: triangles, not a skeleton
        second->SetDepth(1);
        second->Update();
        auto surface = vtkSmartPointer<vtkPolyData>::New();
        surface->DeepCopy(Output(second, 0));
        s->SetInputData(2, surface);
      } },
    { "Merge input is not a tree: it has no cell array ParentId",
      [](vtkTreeFromSketchSource* s) {
        auto lines = Strokes({ { { 0, 0 }, { 0, 1 } } });
        vtkNew<vtkIntArray> ids;
        ids->SetName("BranchId");
        ids->InsertNextValue(0);
        lines->GetCellData()->AddArray(ids);
        s->SetInputData(2, lines);
      } },
    { "Merge input is not a tree: 2 branches have ParentId -1",
      [](vtkTreeFromSketchSource* s) {
        vtkNew<vtkTreeFromSketchSource> second;
        second->SetPreset(2);
        second->SetDepth(1);
        second->Update();
        auto skeleton = vtkSmartPointer<vtkPolyData>::New();
        skeleton->DeepCopy(Output(second, 1));
        vtkDataArray::SafeDownCast(skeleton->GetCellData()->GetArray("ParentId"))->SetComponent(1, 0, -1);
        s->SetInputData(2, skeleton);
      } },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkTreeFromSketchSource> source;
    vtkNew<ErrorCatcher> catcher;
    source->AddObserver(vtkCommand::ErrorEvent, catcher);
    c.apply(source);
    source->Update();
    EXPECT_NE(catcher->Messages.find(c.expected), std::string::npos) << c.expected << ": " << catcher->Messages;
    for (int port = 0; port < 3; ++port)
      EXPECT_EQ(Output(source, port)->GetNumberOfPoints(), 0) << c.expected;
  }
}

TEST(TreeFromSketchSource, SecondTreeOnTheMergePortKeepsItsShapeAndGetsIdsAfterThisTreesOwn)
{
  vtkNew<vtkTreeFromSketchSource> second;
  second->SetPreset(2);
  second->Update();
  vtkPolyData* secondSkeleton = Output(second, 1);
  vtkNew<vtkTreeFromSketchSource> first;
  first->SetPreset(0); // Custom: the defaults (Table 1 left) with Depth 2
  first->SetDepth(2);
  first->Update();
  const vtkIdType own = Output(first, 1)->GetNumberOfCells();

  vtkNew<vtkTreeFromSketchSource> merged;
  merged->SetPreset(0);
  merged->SetDepth(2);
  merged->SetInputConnection(2, second->GetOutputPort(1));
  merged->SetMergeParentBranch(-1);
  merged->SetMergeOffset(8.0, 0.0, 0.0);
  merged->SetMergeAngle(0.0);
  vtkNew<ErrorCatcher> catcher;
  merged->AddObserver(vtkCommand::ErrorEvent, catcher);
  merged->Update();
  ASSERT_EQ(catcher->Messages, "");
  vtkPolyData* skeleton = Output(merged, 1);
  ASSERT_EQ(skeleton->GetNumberOfCells(), own + secondSkeleton->GetNumberOfCells());
  const double base = skeleton->GetFieldData()->GetArray("PlantMorph.MergeIdBase")->GetTuple1(0);
  EXPECT_EQ(base, 1 + 8 + 64); // SubtreeSize(8, 2)
  // Every merged polyline is the second tree's, moved by the offset (a second trunk, angle 0, rotation 0).
  vtkDataArray* ids = skeleton->GetCellData()->GetArray("BranchId");
  vtkDataArray* secondIds = secondSkeleton->GetCellData()->GetArray("BranchId");
  std::map<int, vtkIdType> secondCell;
  for (vtkIdType c = 0; c < secondSkeleton->GetNumberOfCells(); ++c)
    secondCell[int(secondIds->GetTuple1(c))] = c;
  int checked = 0;
  vtkNew<vtkIdList> a, b;
  for (vtkIdType c = own; c < skeleton->GetNumberOfCells(); ++c)
  {
    const int source = int(ids->GetTuple1(c) - base);
    ASSERT_TRUE(secondCell.count(source)) << source;
    skeleton->GetCellPoints(c, a);
    secondSkeleton->GetCellPoints(secondCell[source], b);
    ASSERT_EQ(a->GetNumberOfIds(), b->GetNumberOfIds());
    for (vtkIdType k = 0; k < a->GetNumberOfIds(); ++k)
    {
      double p[3], q[3];
      skeleton->GetPoint(a->GetId(k), p);
      secondSkeleton->GetPoint(b->GetId(k), q);
      EXPECT_NEAR(p[0], q[0] + 8.0, 1e-12);
      EXPECT_NEAR(p[1], q[1], 1e-12);
      EXPECT_NEAR(p[2], q[2], 1e-12);
    }
    ++checked;
  }
  EXPECT_EQ(checked, secondSkeleton->GetNumberOfCells());
  // Welded (default): every child is either welded or a counted fallback; the two trunks stand apart.
  vtkDataArray* junctions = skeleton->GetFieldData()->GetArray("PlantMorph.Junctions");
  ASSERT_NE(junctions, nullptr);
  ASSERT_EQ(junctions->GetNumberOfComponents(), 6);
  EXPECT_EQ(junctions->GetComponent(0, 1) + junctions->GetComponent(0, 5), double(skeleton->GetNumberOfCells() - 2));
  EXPECT_GT(junctions->GetComponent(0, 1), 0.0);
  EXPECT_EQ(skeleton->GetFieldData()->GetArray("PlantMorph.JointRingVertices")->GetComponent(0, 0), 0.0);
  // Seated tubes: the joint report covers every child's base ring (the second trunk has none): 6 vertices a child.
  merged->SetJoints(1);
  merged->Update();
  ASSERT_EQ(catcher->Messages, "");
  skeleton = Output(merged, 1);
  vtkDataArray* joints = skeleton->GetFieldData()->GetArray("PlantMorph.JointRingVertices");
  ASSERT_NE(joints, nullptr);
  ASSERT_EQ(joints->GetNumberOfComponents(), 4);
  double ringVertices = 0.0;
  for (int c = 0; c < 4; ++c)
    ringVertices += joints->GetComponent(0, c);
  EXPECT_EQ(ringVertices, 6.0 * double(skeleton->GetNumberOfCells() - 2));
  EXPECT_GT(joints->GetComponent(0, 0), 0.0);
  // Deleting a merged branch by its id removes it with its subtree.
  merged->AddDeletedBranch(int(base) + 1);
  merged->Update();
  EXPECT_EQ(
    Output(merged, 1)->GetNumberOfCells(), own + secondSkeleton->GetNumberOfCells() - (1 + 3 + 9 + 27 + 81 + 243));
}

TEST(TreeFromSketchSource, WeldedBranchesAreOneClosedManifoldPerTreeAndSeatedTubesAreNot)
{
  // VTK's own edge and connectivity filters as oracles: no boundary or non-manifold edge, one region per tree plus
  // one per fallback child; seated tubes give one region per branch (every tube closed on its own).
  for (int preset = 1; preset <= 3; ++preset)
  {
    for (int joints : { 0, 1 })
    {
      vtkNew<vtkTreeFromSketchSource> source;
      source->SetPreset(preset);
      source->SetDepth(2);
      source->SetLeaves(0);
      source->SetJoints(joints);
      source->Update();
      vtkPolyData* branches = Output(source, 0);
      vtkNew<vtkFeatureEdges> edges;
      edges->SetInputData(branches);
      edges->BoundaryEdgesOn();
      edges->NonManifoldEdgesOn();
      edges->FeatureEdgesOff();
      edges->ManifoldEdgesOff();
      edges->Update();
      EXPECT_EQ(edges->GetOutput()->GetNumberOfLines(), 0) << preset << " " << joints;
      vtkNew<vtkPolyDataConnectivityFilter> regions;
      regions->SetInputData(branches);
      regions->SetExtractionModeToAllRegions();
      regions->Update();
      const double fallback = branches->GetFieldData()->GetArray("PlantMorph.Junctions")->GetComponent(0, 5);
      const vtkIdType branchCount = Output(source, 1)->GetNumberOfCells();
      EXPECT_EQ(regions->GetNumberOfExtractedRegions(), joints == 0 ? 1 + vtkIdType(fallback) : branchCount)
        << preset << " " << joints;
    }
  }
}

TEST(TreeFromSketchSource, StrokeErrorsOfAFileNameTheFileAndTheLine)
{
  const std::string file = plantmorph::testing::TemporaryPath("plantmorph_tree", "zero_stroke.csv");
  std::ofstream(file) << "stroke_id,x,y\n1,0,0\n1,0,10\n2,0,5\n2,0,5\n";
  vtkNew<vtkTreeFromSketchSource> source;
  vtkNew<ErrorCatcher> catcher;
  source->AddObserver(vtkCommand::ErrorEvent, catcher);
  source->SetMode(1);
  source->SetStrokesOnly(1);
  source->SetStrokeFile(file.c_str());
  source->Update();
  EXPECT_NE(
    catcher->Messages.find("StrokeFile '" + file + "', stroke 1 (stroke_id '2' from line 4): "), std::string::npos)
    << catcher->Messages;
  EXPECT_EQ(catcher->Messages.find("Strokes input"), std::string::npos) << catcher->Messages;
  for (int port = 0; port < 3; ++port)
    EXPECT_EQ(Output(source, port)->GetNumberOfPoints(), 0);
  std::remove(file.c_str());
}

TEST(TreeFromSketchSource, LongAndCutStrokeFilesBuildTreesOrFailCleanly)
{
  // Files that crashed the regex reader (a 2,000-point polyline, a 5,000-command path, a file cut inside a long
  // attribute) and the bow that came out straight.
  std::string points, path = "M 0,0";
  for (int i = 0; i < 2000; ++i)
    points += std::to_string(i % 50) + "," + std::to_string(-i) + " ";
  for (int i = 1; i <= 5000; ++i)
    path += " L " + std::to_string((i * 3) % 40) + "," + std::to_string(-i);
  const std::string head = "<svg xmlns=\"http://www.w3.org/2000/svg\">";
  const std::string polyline = head + "<polyline points=\"" + points + "\"/></svg>";
  const std::vector<std::pair<std::string, std::string>> files = { { "polyline.svg", polyline },
    { "path.svg", head + "<path d=\"" + path + "\"/></svg>" },
    { "truncated.svg", polyline.substr(0, polyline.size() / 2) },
    { "bow.svg", head + "<path d=\"M 0,100 C 40,66 40,33 0,0\"/></svg>" } };
  for (const auto& [name, text] : files)
  {
    const std::string file = plantmorph::testing::TemporaryPath("plantmorph_tree", name);
    std::ofstream(file) << text;
    vtkNew<vtkTreeFromSketchSource> source;
    vtkNew<ErrorCatcher> catcher;
    source->AddObserver(vtkCommand::ErrorEvent, catcher);
    source->SetMode(1);
    source->SetStrokesOnly(1);
    source->SetStrokeFile(file.c_str());
    source->Update();
    vtkPolyData* skeleton = Output(source, 1);
    if (name == "truncated.svg")
    {
      EXPECT_NE(catcher->Messages.find("not well-formed XML"), std::string::npos) << catcher->Messages;
      for (int port = 0; port < 3; ++port)
        EXPECT_EQ(Output(source, port)->GetNumberOfPoints(), 0);
    }
    else
    {
      EXPECT_EQ(catcher->Messages, "") << name;
      EXPECT_GT(skeleton->GetNumberOfPoints(), 1) << name;
    }
    if (name == "bow.svg")
    {
      // The trunk follows the bow (its Bezier control points are flattened-curve points, up to x = 30 away from
      // the chord x = 0); the old reader kept only the end points and gave a straight trunk at x = 0.
      double bounds[6];
      skeleton->GetBounds(bounds);
      EXPECT_GT(bounds[1], 15.0);
      EXPECT_NEAR(bounds[0], 0.0, 1e-9);
    }
    std::remove(file.c_str());
  }
}

TEST(TreeFromSketchSource, EveryLeafHasItsOwnLeafIdAndEveryCellItsOrgan)
{
  // A two-triangle leaf: a blade triangle and a petiole triangle (cell array Region, 5 the petiole).
  vtkNew<vtkPolyData> leaf;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(-0.5, 0.2, 0);
  points->InsertNextPoint(0.5, 0.2, 0);
  points->InsertNextPoint(0, 2, 0);
  points->InsertNextPoint(0, 0, 0);
  vtkNew<vtkCellArray> cells;
  const vtkIdType blade[3] = { 0, 1, 2 }, petiole[3] = { 3, 1, 0 };
  cells->InsertNextCell(3, blade);
  cells->InsertNextCell(3, petiole);
  vtkNew<vtkIntArray> region;
  region->SetName("Region");
  region->InsertNextValue(0);
  region->InsertNextValue(5);
  leaf->SetPoints(points);
  leaf->SetPolys(cells);
  leaf->GetCellData()->AddArray(region);
  vtkNew<vtkTreeFromSketchSource> source;
  source->SetPreset(2); // sympodial: 3^6 twigs
  source->SetLeafCount(2);
  source->SetInputData(1, leaf);
  source->Update();
  vtkPolyData* leaves = Output(source, 2);
  vtkPolyData* wood = Output(source, 0);
  const vtkIdType count = 729 * 2;
  ASSERT_EQ(leaves->GetNumberOfCells(), 2 * count);
  auto* cellLeaf = vtkIntArray::SafeDownCast(leaves->GetCellData()->GetArray("LeafId"));
  auto* cellOrgan = vtkIntArray::SafeDownCast(leaves->GetCellData()->GetArray("Organ"));
  auto* pointLeaf = vtkIntArray::SafeDownCast(leaves->GetPointData()->GetArray("LeafId"));
  auto* pointOrgan = vtkIntArray::SafeDownCast(leaves->GetPointData()->GetArray("Organ"));
  ASSERT_TRUE(cellLeaf && cellOrgan && pointLeaf && pointOrgan);
  std::set<int> ids;
  for (vtkIdType c = 0; c < leaves->GetNumberOfCells(); ++c)
  {
    ids.insert(cellLeaf->GetValue(c));
    EXPECT_EQ(cellLeaf->GetValue(c), c / 2); // the leaf's index in the tree's order
    EXPECT_EQ(cellOrgan->GetValue(c), c % 2 == 0 ? 1 : 2);
  }
  EXPECT_EQ(ids.size(), static_cast<std::size_t>(count));
  for (vtkIdType p = 0; p < leaves->GetNumberOfPoints(); ++p)
  {
    EXPECT_EQ(pointLeaf->GetValue(p), p / 4);
    EXPECT_EQ(pointOrgan->GetValue(p), p % 4 == 3 ? 2 : 1); // only the petiole's own point is petiole
  }
  for (const char* name : { "LeafId", "Organ" })
  {
    double range[2];
    wood->GetCellData()->GetArray(name)->GetRange(range);
    EXPECT_EQ(range[0], name[0] == 'L' ? -1.0 : 0.0);
    EXPECT_EQ(range[1], range[0]);
    ASSERT_NE(wood->GetPointData()->GetArray(name), nullptr);
  }
  // Pieces keep the serial ids: each leaf once, with the same LeafId.
  std::multiset<int> pieceIds;
  for (int piece = 0; piece < 3; ++piece)
  {
    source->UpdatePiece(piece, 3, 0);
    vtkDataArray* mine = Output(source, 2)->GetCellData()->GetArray("LeafId");
    for (vtkIdType c = 0; mine && c < mine->GetNumberOfTuples(); c += 2)
      pieceIds.insert(static_cast<int>(mine->GetComponent(c, 0)));
  }
  EXPECT_EQ(pieceIds, std::multiset<int>(ids.begin(), ids.end()));
}
