// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK layer of Leaf Cloud Reader over its VTK-free parser (sources/leaf_cloud/core/PointCloudText): the soybean
// layout's arrays, progress up to 1, and the hostile files (one line of 2*10^6 columns, binary junk) refused with an
// error naming FileName and the line, and empty outputs.
#include "TemporaryPath.h"
#include "VtkErrorCatcher.h"
#include "vtkLeafCloudReader.h"

#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace
{
using plantmorph::testing::ErrorCatcher;

std::string WriteFile(const std::string& name, const std::string& text)
{
  const std::string path = plantmorph::testing::TemporaryPath("plantmorph_leafcloud", name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

class ProgressRecorder : public vtkCommand
{
public:
  static ProgressRecorder* New() { return new ProgressRecorder; }
  void Execute(vtkObject*, unsigned long, void* data) override { this->Values.push_back(*static_cast<double*>(data)); }
  std::vector<double> Values;
};

TEST(LeafCloudReader, SoybeanLayoutArraysAndProgress)
{
  const std::string path = WriteFile("soybean.txt",
    "x,y,z,nx,ny,nz,r,g,b,s\n3.821000,28.178904,108.244029,0.510049,0.127189,-0.850690,0.176471,0.247059,0.141176,"
    "0.470588\n# a comment\n5.295000,28.651904,110.582029,0.510422,-0.054324,-0.858207,0.160784,0.400000,0.000000,"
    "0.231373\n");
  vtkNew<vtkLeafCloudReader> reader;
  vtkNew<ProgressRecorder> progress;
  reader->AddObserver(vtkCommand::ProgressEvent, progress);
  reader->SetFileName(path.c_str());
  EXPECT_EQ(reader->CanReadFile(path.c_str()), 1);
  reader->Update();
  vtkPolyData* cloud = reader->GetOutput();
  ASSERT_EQ(cloud->GetNumberOfPoints(), 2);
  EXPECT_EQ(cloud->GetNumberOfVerts(), 2);
  double p[3];
  cloud->GetPoint(1, p);
  EXPECT_EQ(p[0], 5.295);
  EXPECT_EQ(p[2], 110.582029);
  EXPECT_EQ(cloud->GetPointData()->GetNormals()->GetComponent(0, 2), -0.850690);
  auto* colors = vtkUnsignedCharArray::SafeDownCast(cloud->GetPointData()->GetScalars());
  ASSERT_NE(colors, nullptr);
  EXPECT_EQ(colors->GetValue(4), 102);                                           // 0.4 * 255 = 102
  EXPECT_EQ(cloud->GetPointData()->GetArray("s")->GetComponent(1, 0), 0.231373); // the header's name
  vtkTable* table = vtkTable::SafeDownCast(reader->GetOutputDataObject(1));
  ASSERT_NE(table, nullptr);
  EXPECT_EQ(table->GetNumberOfColumns(), 10);
  EXPECT_NE(table->GetColumnByName("nz"), nullptr);
  ASSERT_FALSE(progress.Get()->Values.empty());
  EXPECT_EQ(progress.Get()->Values.back(), 1.0);
  std::filesystem::remove(path);
}

TEST(LeafCloudReader, HostileFilesAreRefusedWithEmptyOutputs)
{
  std::string wide;
  for (int i = 0; i < 2000000; ++i)
    wide += "1.5 ";
  std::string junk;
  for (int i = 0; i < 300000; ++i)
    junk += static_cast<char>((static_cast<unsigned>(i) * 7919u + 13u) % 256u);
  const std::vector<std::pair<std::string, std::string>> cases = { { wide + "\n", "line 1: longer than" },
    { wide.substr(0, 100000) + "\n", "line 1: more than 1000 columns" },
    { "1 2 3\n4 5 1e999\n", "line 2: column 3 is a number beyond the range of a double" }, { junk, "line " } };
  for (const auto& [text, words] : cases)
  {
    const std::string path = WriteFile("hostile.txt", text);
    vtkNew<vtkLeafCloudReader> reader;
    vtkNew<ErrorCatcher> catcher;
    reader->AddObserver(vtkCommand::ErrorEvent, catcher);
    reader->SetFileName(path.c_str());
    reader->Update();
    EXPECT_NE(catcher.Get()->Messages.find("FileName '" + path + "', " + words), std::string::npos)
      << catcher.Get()->Messages;
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
    EXPECT_EQ(vtkTable::SafeDownCast(reader->GetOutputDataObject(1))->GetNumberOfColumns(), 0);
    EXPECT_EQ(reader->CanReadFile(path.c_str()), text.compare(0, 6, "1 2 3\n") == 0 ? 1 : 0); // the first 20 lines
    std::filesystem::remove(path);
  }
}
namespace
{
/// Reads `text`; the error messages in `messages`.
vtkPolyData* ReadText(vtkLeafCloudReader* reader, const std::string& text, std::string& messages)
{
  const std::string path = WriteFile("columns.txt", text);
  vtkNew<ErrorCatcher> catcher;
  reader->AddObserver(vtkCommand::ErrorEvent, catcher);
  reader->SetFileName(path.c_str());
  reader->Update();
  messages = catcher.Get()->Messages;
  std::filesystem::remove(path);
  return reader->GetOutput();
}

/// The points' coordinates, flattened.
std::vector<double> Coordinates(vtkPolyData* cloud)
{
  std::vector<double> xyz;
  for (vtkIdType i = 0; i < cloud->GetNumberOfPoints(); ++i)
  {
    double p[3];
    cloud->GetPoint(i, p);
    xyz.insert(xyz.end(), p, p + 3);
  }
  return xyz;
}
} // namespace

TEST(LeafCloudReader, HeaderNamesTheColumnsInEverySeparator)
{
  std::string messages;
  {
    // x,y,z,r,g,b: the colours are Colors (unsigned char, active scalars), never normals.
    vtkNew<vtkLeafCloudReader> reader;
    vtkPolyData* cloud = ReadText(reader, "x,y,z,r,g,b\n1,2,3,255,0,0\n4,5,6,0,128,255\n", messages);
    EXPECT_EQ(messages, "");
    EXPECT_EQ(cloud->GetPointData()->GetNormals(), nullptr);
    EXPECT_EQ(cloud->GetPointData()->GetArray("Normals"), nullptr);
    auto* colors = vtkUnsignedCharArray::SafeDownCast(cloud->GetPointData()->GetScalars());
    ASSERT_NE(colors, nullptr);
    EXPECT_STREQ(colors->GetName(), "Colors");
    EXPECT_EQ(colors->GetValue(0), 255);
    EXPECT_EQ(colors->GetValue(5), 255);
    EXPECT_EQ(colors->GetValue(4), 128);
    EXPECT_EQ(Coordinates(cloud), (std::vector<double>{ 1, 2, 3, 4, 5, 6 }));
  }
  // Space-, comma-, semicolon- and tab-separated headers; x, y, z in any order; unknown columns by their names.
  const std::vector<std::pair<std::string, std::vector<double>>> cases = {
    { "id x y z\n7 1 2 3\n", { 1, 2, 3 } },
    { "z y id x\n1 2 7 3\n", { 3, 2, 1 } },
    { "z;id;y;x\n1;7;2;3\n", { 3, 2, 1 } },
    { "x\tid\ty\tz\n1\t7\t2\t3\n", { 1, 2, 3 } },
    { "x,y,z,id\n1,2,3,7\n", { 1, 2, 3 } },
    { "id,x,y,z\n7,1,2,3\n", { 1, 2, 3 } },
  };
  for (const auto& [text, xyz] : cases)
  {
    vtkNew<vtkLeafCloudReader> reader;
    vtkPolyData* cloud = ReadText(reader, text, messages);
    EXPECT_EQ(messages, "") << text;
    EXPECT_EQ(Coordinates(cloud), xyz) << text;
    ASSERT_NE(cloud->GetPointData()->GetArray("id"), nullptr) << text;
    EXPECT_EQ(cloud->GetPointData()->GetArray("id")->GetComponent(0, 0), 7.0) << text;
    EXPECT_EQ(cloud->GetPointData()->GetNormals(), nullptr) << text;
  }
  {
    // Known names in any order: normals and colours (fractions scaled), intensity and classification kept by name.
    vtkNew<vtkLeafCloudReader> reader;
    vtkPolyData* cloud = ReadText(reader,
      "intensity;red;green;blue;normal_x;normal_y;normal_z;classification;X;Y;Z\n"
      "0.5;1;0.5;0;0;0;1;2;10;20;30\n",
      messages);
    EXPECT_EQ(messages, "");
    EXPECT_EQ(Coordinates(cloud), (std::vector<double>{ 10, 20, 30 }));
    ASSERT_NE(cloud->GetPointData()->GetNormals(), nullptr);
    EXPECT_EQ(cloud->GetPointData()->GetNormals()->GetComponent(0, 2), 1.0);
    auto* colors = vtkUnsignedCharArray::SafeDownCast(cloud->GetPointData()->GetScalars());
    ASSERT_NE(colors, nullptr);
    EXPECT_EQ(colors->GetValue(1), 128); // 0.5 * 255 rounded
    EXPECT_EQ(cloud->GetPointData()->GetArray("intensity")->GetComponent(0, 0), 0.5);
    EXPECT_EQ(cloud->GetPointData()->GetArray("classification")->GetComponent(0, 0), 2.0);
  }
  {
    // No header: the positional layout as before (normals, colours, Scalar).
    vtkNew<vtkLeafCloudReader> reader;
    vtkPolyData* cloud = ReadText(reader, "1 2 3 0 0 1 1 0 0 9 8\n", messages);
    EXPECT_EQ(messages, "");
    ASSERT_NE(cloud->GetPointData()->GetNormals(), nullptr);
    EXPECT_EQ(cloud->GetPointData()->GetArray("Scalar")->GetComponent(0, 0), 9.0);
    EXPECT_EQ(cloud->GetPointData()->GetArray("Column10")->GetComponent(0, 0), 8.0);
  }
}

TEST(LeafCloudReader, ByteOrderMarkDecimalCommasLineEndsAndDirectories)
{
  std::string messages;
  {
    vtkNew<vtkLeafCloudReader> reader;
    EXPECT_EQ(Coordinates(ReadText(reader,
                "\xEF\xBB\xBF"
                "1 2 3\n4 5 6\n",
                messages)),
      (std::vector<double>{ 1, 2, 3, 4, 5, 6 }));
    EXPECT_EQ(messages, "");
  }
  {
    vtkNew<vtkLeafCloudReader> reader;
    EXPECT_EQ(Coordinates(ReadText(reader, "\xEF\xBB\xBFz,y,x\n1,2,3\n", messages)), (std::vector<double>{ 3, 2, 1 }));
    EXPECT_EQ(messages, "");
  }
  const std::vector<std::pair<std::string, std::string>> refused = {
    { "1,5 2,5 3,5\n4,5 5,5 6,5\n", "', line 1: decimal commas ('1,5' would read as two numbers)" },
    { "x;y;z\n1,5;2,5;3,5\n", "', line 2: decimal commas" },
    { "x y z\r1 2 3\r4 5 6\r", "', line 1: its lines end in a carriage return alone (old Mac line ends)" },
  };
  for (const auto& [text, words] : refused)
  {
    vtkNew<vtkLeafCloudReader> reader;
    vtkPolyData* cloud = ReadText(reader, text, messages);
    EXPECT_NE(messages.find(words), std::string::npos) << messages;
    EXPECT_EQ(cloud->GetNumberOfPoints(), 0);
    EXPECT_EQ(vtkTable::SafeDownCast(reader->GetOutputDataObject(1))->GetNumberOfColumns(), 0);
  }
  const std::string directory = std::filesystem::temp_directory_path().string();
  vtkNew<vtkLeafCloudReader> reader;
  vtkNew<ErrorCatcher> catcher;
  reader->AddObserver(vtkCommand::ErrorEvent, catcher);
  reader->SetFileName(directory.c_str());
  EXPECT_EQ(reader->CanReadFile(directory.c_str()), 0);
  reader->Update();
  EXPECT_NE(catcher.Get()->Messages.find("FileName '" + directory + "' is a directory"), std::string::npos)
    << catcher.Get()->Messages;
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(LeafCloudReader, PiecesHoldTheWholeFileInOrder)
{
  // Each piece (as an MPI rank asks for it) reads its byte range; together, in piece order, the serial points, arrays
  // and table rows, bit for bit. (The colour scale is decided per piece when the pieces are read in one process,
  // as here; under MPI the ranks agree on it: test_mpi_cloud_comparison.py.)
  std::string text = "# a scan\nx y z nx ny nz r g b\n";
  for (int i = 0; i < 3000; ++i)
  {
    text += std::to_string(i * 0.001) + " " + std::to_string(-i) + " 1e-3 0 0 1 " + (i % 100 == 7 ? "200" : "0.5") +
      " 0.25 1\n" + (i % 333 == 0 ? "// comment\n" : "");
  }
  const std::string path = WriteFile("pieces.txt", text);
  vtkNew<vtkLeafCloudReader> whole;
  whole->SetFileName(path.c_str());
  whole->Update();
  const vtkIdType n = whole->GetOutput()->GetNumberOfPoints();
  ASSERT_EQ(n, 3000);
  for (int pieces : { 2, 3, 7 })
  {
    std::vector<double> points, normals, rows;
    for (int piece = 0; piece < pieces; ++piece)
    {
      vtkNew<vtkLeafCloudReader> reader;
      reader->SetFileName(path.c_str());
      reader->UpdatePiece(piece, pieces, 0);
      vtkPolyData* part = reader->GetOutput();
      EXPECT_EQ(part->GetNumberOfVerts(), part->GetNumberOfPoints());
      for (vtkIdType i = 0; i < part->GetNumberOfPoints(); ++i)
      {
        double p[3];
        part->GetPoint(i, p);
        points.insert(points.end(), p, p + 3);
        normals.push_back(part->GetPointData()->GetArray("Normals")->GetComponent(i, 2));
      }
      vtkTable* table = vtkTable::SafeDownCast(reader->GetOutputDataObject(1));
      EXPECT_EQ(table->GetNumberOfRows(), part->GetNumberOfPoints());
      for (vtkIdType i = 0; i < table->GetNumberOfRows(); ++i)
      {
        rows.push_back(table->GetValue(i, 1).ToDouble());
      }
    }
    ASSERT_EQ(points.size(), 3u * static_cast<std::size_t>(n)) << pieces << " pieces";
    for (vtkIdType i = 0; i < n; ++i)
    {
      double p[3];
      whole->GetOutput()->GetPoint(i, p);
      EXPECT_TRUE(p[0] == points[3 * i] && p[1] == points[3 * i + 1] && p[2] == points[3 * i + 2]) << i;
      EXPECT_EQ(rows[static_cast<std::size_t>(i)], p[1]);
    }
    EXPECT_EQ(normals, std::vector<double>(static_cast<std::size_t>(n), 1.0));
  }
  std::filesystem::remove(path);
}

} // namespace
