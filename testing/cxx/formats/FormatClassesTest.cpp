// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK classes over the MTG and QSM cores (sources/formats/vtk): the reader's arrays and Connect Branches, errors
// naming FileName and the line with empty outputs, a refused tree leaving an existing file as it was, the QSM writer's
// cylinders of a skeleton (each branch's first cylinder the child of its parent's segment ending nearest to it), and
// the QSM reader's probe of the first lines.
#include "FormatFixtures.h"
#include "TemporaryPath.h"
#include "VtkErrorCatcher.h"
#include "vtkMtgReader.h"
#include "vtkMtgWriter.h"
#include "vtkQsmReader.h"
#include "vtkQsmWriter.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace
{
using plantmorph::testing::ErrorCatcher;

std::string WriteFile(const std::string& name, const std::string& text)
{
  const std::string path = plantmorph::testing::TemporaryPath("plantmorph_formats", name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string ReadFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(MtgReader, ArraysAndConnectBranches)
{
  const std::string path = WriteFile("explicit.mtg", plantmorph::fixtures::ExplicitMtg);
  vtkNew<vtkMtgReader> reader;
  reader->SetFileName(path.c_str());
  EXPECT_EQ(reader->CanReadFile(path.c_str()), 1);
  reader->Update();
  vtkPolyData* out = reader->GetOutput();
  ASSERT_EQ(out->GetNumberOfLines(), 2);
  EXPECT_EQ(out->GetNumberOfPoints(), 7); // 4 trunk + the bearer E2 + 2 branch
  auto* parent = vtkIntArray::SafeDownCast(out->GetCellData()->GetArray("ParentId"));
  ASSERT_NE(parent, nullptr);
  EXPECT_EQ(parent->GetValue(1), 0);
  auto* label = vtkStringArray::SafeDownCast(out->GetPointData()->GetAbstractArray("Label"));
  auto* plant = vtkStringArray::SafeDownCast(out->GetPointData()->GetAbstractArray("Scale1Label"));
  ASSERT_NE(label, nullptr);
  ASSERT_NE(plant, nullptr);
  EXPECT_EQ(label->GetValue(4), "E2"); // the branch's first point is its bearer
  EXPECT_EQ(plant->GetValue(6), "P1");
  double p[3];
  out->GetPoint(4, p);
  EXPECT_EQ(p[2], 2.0);
  EXPECT_EQ(out->GetPointData()->GetArray("Radius")->GetComponent(0, 0), 1.0);
  reader->ConnectBranchesOff();
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 6);
  std::filesystem::remove(path);
}

TEST(MtgReader, MalformedFileNamesFileAndLineAndLeavesNothing)
{
  std::string text = plantmorph::fixtures::ExplicitMtg;
  text.replace(text.find("^<E4"), 4, "^<Q4");
  const std::string path = WriteFile("bad.mtg", text);
  vtkNew<vtkMtgReader> reader;
  vtkNew<ErrorCatcher> catcher;
  reader->AddObserver(vtkCommand::ErrorEvent, catcher);
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_NE(catcher->Messages.find("FileName '" + path + "', line 34: symbol 'Q' is not declared in CLASSES"),
    std::string::npos)
    << catcher->Messages;
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), 0);
  std::filesystem::remove(path);
}

/// A trunk of three points and a branch from near its middle point, as TreeFromSketchSource's Skeleton.
vtkNew<vtkPolyData> Skeleton(bool withIds)
{
  vtkNew<vtkPolyData> skeleton;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  const double xyz[5][3] = { { 0, 0, 0 }, { 0, 1, 0 }, { 0, 2, 0 }, { 0.1, 1.1, 0 }, { 1, 2, 0 } };
  for (const auto& p : xyz)
  {
    points->InsertNextPoint(p);
  }
  skeleton->SetPoints(points);
  vtkNew<vtkCellArray> lines;
  const vtkIdType trunk[3] = { 0, 1, 2 }, branch[2] = { 3, 4 };
  lines->InsertNextCell(3, trunk);
  lines->InsertNextCell(2, branch);
  skeleton->SetLines(lines);
  vtkNew<vtkDoubleArray> radius;
  radius->SetName("Radius");
  for (const double r : { 0.4, 0.3, 0.2, 0.1, 0.05 })
  {
    radius->InsertNextValue(r);
  }
  skeleton->GetPointData()->AddArray(radius);
  if (withIds)
  {
    vtkNew<vtkIntArray> id, parent;
    id->SetName("BranchId");
    parent->SetName("ParentId");
    id->InsertNextValue(4);
    id->InsertNextValue(9);
    parent->InsertNextValue(-1);
    parent->InsertNextValue(4);
    skeleton->GetCellData()->AddArray(id);
    skeleton->GetCellData()->AddArray(parent);
  }
  return skeleton;
}

TEST(MtgWriter, RefusedTreeLeavesTheFileAsItWas)
{
  const std::string path = WriteFile("kept.mtg", "what was there\n");
  vtkNew<vtkMtgWriter> writer;
  vtkNew<ErrorCatcher> catcher;
  writer->AddObserver(vtkCommand::ErrorEvent, catcher);
  writer->SetFileName(path.c_str());
  writer->SetInputData(Skeleton(false));
  writer->Write();
  EXPECT_NE(catcher->Messages.find("the input has no cell array BranchId"), std::string::npos) << catcher->Messages;
  EXPECT_EQ(ReadFile(path), "what was there\n");
  // With ids it writes, and the reader gives the polylines back (Connect Branches off).
  writer->SetInputData(Skeleton(true));
  writer->Write();
  vtkNew<vtkMtgReader> reader;
  reader->SetFileName(path.c_str());
  reader->ConnectBranchesOff();
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 5);
  EXPECT_NE(ReadFile(path).find("^<S2\t\t0\t1\t0\t0.6\n\t+A9/S1\t"), std::string::npos) << ReadFile(path);
  std::filesystem::remove(path);
}

TEST(QsmWriter, SkeletonSegmentsBecomeCylindersWithTheirParents)
{
  const std::string path = WriteFile("skeleton.csv", "");
  vtkNew<vtkQsmWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(Skeleton(true));
  writer->Write();
  // Trunk segments 1, 2; the branch's one segment 3, child of the trunk segment ending at (0, 1, 0): 1.
  EXPECT_EQ(ReadFile(path),
    "ID,parentID,startX,startY,startZ,endX,endY,endZ,axisX,axisY,axisZ,radius,length,branchID,branchOrder\n"
    "1,0,0,0,0,0,1,0,0,1,0,0.35,1,4,0\n"
    "2,1,0,1,0,0,2,0,0,1,0,0.25,1,4,0\n"
    "3,1,0.1,1.1,0,1,2,0,0.7071067811865476,0.7071067811865475,0,0.07500000000000001,1.2727922061357855,9,1\n");
  vtkNew<vtkQsmReader> reader;
  EXPECT_EQ(reader->CanReadFile(path.c_str()), 1);
  const std::string cloud = WriteFile("cloud.xyz", "1 2 3\n4 5 6\n");
  EXPECT_EQ(reader->CanReadFile(cloud.c_str()), 0);
  std::filesystem::remove(path);
  std::filesystem::remove(cloud);
}
} // namespace
