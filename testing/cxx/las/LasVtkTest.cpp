// SPDX-License-Identifier: GPL-3.0-or-later
// LASReader and the LAS writer as VTK classes (sources/las/vtk): a point set with labels and colours written and
// read back; the writer's refusals leave no file (not even the partial one); the reader's refusals leave an empty
// output and name the file.
#include "vtkPlantMorphLASReader.h"
#include "vtkPlantMorphLASWriter.h"

#include "TemporaryPath.h"
#include "VtkErrorCatcher.h"

#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedShortArray.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace
{
vtkNew<vtkPolyData> LabelledCloud()
{
  vtkNew<vtkPolyData> cloud;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->InsertNextPoint(0.1, 0.2, 0.3);
  points->InsertNextPoint(-12.5, 3.0, 1e-4);
  points->InsertNextPoint(7.25, -8.0, 2.5);
  cloud->SetPoints(points);
  vtkNew<vtkIntArray> leaf;
  leaf->SetName("LeafId");
  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("Colors");
  colors->SetNumberOfComponents(3);
  for (int i = 0; i < 3; ++i)
  {
    leaf->InsertNextValue(10 * i - 1);
    colors->InsertNextTuple3(40 * i, 255 - i, 7);
  }
  cloud->GetPointData()->AddArray(leaf);
  cloud->GetPointData()->AddArray(colors);
  return cloud;
}

std::string TemporaryPath(const std::string& name)
{
  return plantmorph::testing::TemporaryPath("plantmorph_las_vtk", name);
}
} // namespace

TEST(LasVtk, WrittenCloudReadsBackWithItsLabelsAndColours)
{
  const std::string path = TemporaryPath("labels.las");
  vtkNew<vtkPlantMorphLASWriter> writer;
  writer->SetInputData(LabelledCloud());
  writer->SetFileName(path.c_str());
  ASSERT_EQ(writer->Write(), 1);
  EXPECT_NE(std::string(writer->GetLastWriteSummary()).find("extra bytes: LeafId"), std::string::npos)
    << writer->GetLastWriteSummary();
  vtkNew<vtkPlantMorphLASReader> reader;
  EXPECT_EQ(reader->CanReadFile(path.c_str()), 1);
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* back = reader->GetOutput();
  ASSERT_EQ(back->GetNumberOfPoints(), 3);
  double scale[3];
  back->GetFieldData()->GetArray("PlantMorph.LASScale")->GetTuple(0, scale);
  vtkNew<vtkPolyData> original;
  original->DeepCopy(LabelledCloud());
  for (vtkIdType i = 0; i < 3; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      EXPECT_LE(std::abs(back->GetPoint(i)[k] - original->GetPoint(i)[k]), 0.5 * scale[k] * (1 + 1e-9));
    }
    EXPECT_EQ(back->GetPointData()->GetArray("LeafId")->GetComponent(i, 0), 10 * i - 1);
    EXPECT_EQ(back->GetPointData()->GetArray("LeafId")->GetDataType(), VTK_INT);
    for (int c = 0; c < 3; ++c)
    {
      const double colour = original->GetPointData()->GetArray("Colors")->GetComponent(i, c);
      EXPECT_EQ(back->GetPointData()->GetArray("RGB")->GetComponent(i, c), 257 * colour);
      EXPECT_EQ(back->GetPointData()->GetArray("Colors")->GetComponent(i, c), colour);
    }
  }
  EXPECT_EQ(back->GetPointData()->GetScalars(), back->GetPointData()->GetArray("Colors"));
  std::remove(path.c_str());
}

TEST(LasVtk, RefusedWritesLeaveNoFile)
{
  vtkNew<plantmorph::testing::ErrorCatcher> catcher;
  vtkNew<vtkPlantMorphLASWriter> writer;
  writer->AddObserver(vtkCommand::ErrorEvent, catcher);
  writer->SetInputData(LabelledCloud());
  const std::string path = TemporaryPath("refused.las");
  writer->SetFileName(path.c_str());
  writer->SetVersion(3);
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_NE(catcher->Messages.find("Version = 1.3"), std::string::npos) << catcher->Messages;
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".partial"));
  writer->SetVersion(4);
  const std::string nowhere = TemporaryPath("no-such-folder/cloud.las");
  writer->SetFileName(nowhere.c_str());
  catcher->Messages.clear();
  EXPECT_EQ(writer->Write(), 0);
  EXPECT_NE(catcher->Messages.find("cannot be written"), std::string::npos) << catcher->Messages;
  EXPECT_FALSE(std::filesystem::exists(nowhere));
}

TEST(LasVtk, RefusedReadsLeaveAnEmptyOutputNamingTheFile)
{
  const std::string path = TemporaryPath("not-las.las");
  {
    FILE* file = std::fopen(path.c_str(), "wb");
    std::fputs("x y z\n1 2 3\n", file);
    std::fclose(file);
  }
  vtkNew<plantmorph::testing::ErrorCatcher> catcher;
  vtkNew<vtkPlantMorphLASReader> reader;
  reader->AddObserver(vtkCommand::ErrorEvent, catcher);
  EXPECT_EQ(reader->CanReadFile(path.c_str()), 0);
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_NE(catcher->Messages.find("not-las.las"), std::string::npos) << catcher->Messages;
  EXPECT_NE(catcher->Messages.find("File Signature"), std::string::npos) << catcher->Messages;
  std::remove(path.c_str());
  // A .laz file that is not LAS at all still gets the hint that LAZ needs decompressing.
  const std::string laz = TemporaryPath("scan.laz");
  {
    FILE* file = std::fopen(laz.c_str(), "wb");
    std::fputs("LASF", file);
    std::fclose(file);
  }
  catcher->Messages.clear();
  reader->SetFileName(laz.c_str());
  reader->Update();
  EXPECT_NE(catcher->Messages.find("LASzip-compressed"), std::string::npos) << catcher->Messages;
  std::remove(laz.c_str());
  catcher->Messages.clear();
  reader->SetFileName(TemporaryPath("missing.las").c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_NE(catcher->Messages.find("cannot be opened"), std::string::npos) << catcher->Messages;
}
