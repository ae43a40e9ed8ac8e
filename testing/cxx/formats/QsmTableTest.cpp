// SPDX-License-Identifier: GPL-3.0-or-later
// QsmTable (sources/formats/core): TreeQSM text and SimpleForest / rTwig CSV cylinder tables read into cylinders
// (ends from axis and length where the table gives those), every column kept, a table written and read back bit for
// bit, closed tubes, and malformed tables refused with the line and nothing kept.
#include "FormatFixtures.h"
#include "QsmTable.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace plantmorph
{
namespace
{
std::string Read(const std::string& text, QsmTable& table)
{
  std::istringstream in(text);
  return ReadQsmTable(in, table);
}

using Point = std::array<double, 3>;

TEST(QsmTable, TreeQsmTextByPosition)
{
  QsmTable t;
  ASSERT_EQ(Read(fixtures::TreeQsmText, t), "");
  EXPECT_TRUE(t.treeQsm);
  ASSERT_EQ(t.Rows(), 3u);
  ASSERT_EQ(t.names.size(), 14u);
  EXPECT_EQ(t.names[13], "added");
  EXPECT_EQ(t.names[11], "branch_order");
  EXPECT_EQ(t.end[0], (Point{ 0, 0, 1 }));
  EXPECT_EQ(t.end[1], (Point{ 0, 0, 2 }));
  // start + length * axis: (0, 0, 0.5) + 2 (0.6, 0, 0.8).
  EXPECT_NEAR(t.end[2][0], 1.2, 1e-15);
  EXPECT_NEAR(t.end[2][2], 2.1, 1e-15);
  EXPECT_EQ(t.radius, (std::vector<double>{ 0.3, 0.2, 0.1 }));
  EXPECT_EQ(t.id, (std::vector<double>{ 1, 2, 3 }));
  EXPECT_EQ(t.parent, (std::vector<double>{ 0, 1, 1 }));
}

TEST(QsmTable, TreeQsmHeaderWithUnitsAndThreeColumnNames)
{
  const std::string header = "radius (m)\tlength (m)\tstart_point\taxis_direction\tparent\textension\tbranch\t"
                             "branch_order\tposition_in_branch\tadded\n";
  QsmTable t;
  ASSERT_EQ(Read(header + fixtures::TreeQsmText + "# Branch data\n1 2 3\n", t), "");
  EXPECT_TRUE(t.treeQsm);
  EXPECT_EQ(t.Rows(), 3u); // the branch data after the comment is not read as cylinders
  EXPECT_EQ(t.names[2], "start_x");
  EXPECT_EQ(t.names[7], "axis_z");
  EXPECT_EQ(t.end[1], (Point{ 0, 0, 2 }));
}

TEST(QsmTable, SimpleForestCsvByName)
{
  QsmTable t;
  ASSERT_EQ(Read(fixtures::SimpleForestCsv, t), "");
  EXPECT_FALSE(t.treeQsm);
  ASSERT_EQ(t.Rows(), 3u);
  EXPECT_EQ(t.columns, 13u);
  EXPECT_EQ(t.end[2], (Point{ 1, 0.5, 2 }));
  EXPECT_EQ(t.id, (std::vector<double>{ 1, 2, 3 }));
  EXPECT_EQ(t.parent, (std::vector<double>{ -1, 1, 1 }));
  EXPECT_EQ(t.values[static_cast<std::size_t>(t.Column({ "growthlength" }))], 4.0);
}

TEST(QsmTable, MissingValuesAndLogicalColumns)
{
  QsmTable t;
  ASSERT_EQ(Read("id;parent;start_x;start_y;start_z;end_x;end_y;end_z;radius;modified;note\n"
                 "1;0;0;0;0;0;0;1;0.5;TRUE;NA\n2;1;0;0;1;0;0;2;0.4;FALSE;\n",
              t),
    "");
  EXPECT_EQ(t.values[9], 1.0);
  EXPECT_EQ(t.values[11 + 9], 0.0);
  EXPECT_TRUE(std::isnan(t.values[10]));
  EXPECT_TRUE(std::isnan(t.values[11 + 10]));
}

TEST(QsmTable, WrittenAndReadBackBitForBit)
{
  std::vector<QsmCylinder> cylinders(3);
  cylinders[0] = { 1, 0, { 0, 0, 0 }, { 0.1, 1.0 / 3.0, 1 }, 0.3, 1, 0 };
  cylinders[1] = { 2, 1, { 0.1, 1.0 / 3.0, 1 }, { 1e-300, -2.5, 7 }, 0.125, 1, 0 };
  cylinders[2] = { 5, 1, { 0.1, 1.0 / 3.0, 1 }, { 3, 3, 3 }, 1e-5, 2, 1 };
  const std::vector<std::string> extra = { "growthLength", "Depth" };
  const std::vector<double> extraValues = { 1.5, 0, std::nan(""), 1, 0.25, 2 };
  std::ostringstream out;
  ASSERT_EQ(WriteQsmTable(out, cylinders, extra, extraValues), "");
  QsmTable t;
  ASSERT_EQ(Read(out.str(), t), "") << out.str();
  ASSERT_EQ(t.Rows(), 3u);
  EXPECT_EQ(t.names.size(), QsmStandardColumns().size() + 2);
  for (std::size_t i = 0; i < 3; ++i)
  {
    EXPECT_EQ(t.start[i], cylinders[i].start);
    EXPECT_EQ(t.end[i], cylinders[i].end);
    EXPECT_EQ(t.radius[i], cylinders[i].radius);
    EXPECT_EQ(t.id[i], cylinders[i].id);
    EXPECT_EQ(t.parent[i], cylinders[i].parent);
    EXPECT_EQ(
      t.values[i * t.columns + static_cast<std::size_t>(t.Column({ "branchorder" }))], cylinders[i].branchOrder);
  }
  const auto growth = static_cast<std::size_t>(t.Column({ "growthlength" }));
  EXPECT_EQ(t.values[growth], 1.5);
  EXPECT_TRUE(std::isnan(t.values[t.columns + growth]));
  // The length column is |end - start|, the axis its unit direction.
  const auto length = static_cast<std::size_t>(t.Column({ "length" }));
  EXPECT_NEAR(t.values[2 * t.columns + length], std::sqrt(2.9 * 2.9 + (3 - 1.0 / 3.0) * (3 - 1.0 / 3.0) + 4), 1e-14);
}

TEST(QsmTable, TubeIsClosedAndAtTheRadius)
{
  std::vector<Point> points;
  std::vector<long long> polygons;
  const Point a{ 1, 2, 3 }, b{ 2, 2, 5 };
  CylinderTube(a, b, 0.5, 7, 10, points, polygons);
  ASSERT_EQ(points.size(), 14u);
  std::map<std::pair<long long, long long>, int> edges;
  for (std::size_t i = 0; i < polygons.size(); i += static_cast<std::size_t>(polygons[i]) + 1)
  {
    const auto n = static_cast<std::size_t>(polygons[i]);
    for (std::size_t k = 0; k < n; ++k)
    {
      ++edges[{ polygons[i + 1 + k], polygons[i + 1 + (k + 1) % n] }];
    }
  }
  EXPECT_EQ(edges.size(), 6u * 7u); // directed: 2 rings of 7 edges and 7 side edges, each edge both ways
  for (const auto& [edge, count] : edges)
  {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({ edge.second, edge.first }), 1u) << "an edge used in one direction only: not closed";
  }
  const double d[3] = { 1 / std::sqrt(5.0), 0, 2 / std::sqrt(5.0) };
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    const Point& c = k < 7 ? a : b;
    const double r[3] = { points[k][0] - c[0], points[k][1] - c[1], points[k][2] - c[2] };
    EXPECT_NEAR(std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]), 0.5, 1e-12);
    EXPECT_NEAR(r[0] * d[0] + r[1] * d[1] + r[2] * d[2], 0.0, 1e-12);
  }
}

void ExpectRefused(const std::string& text, const std::string& words)
{
  QsmTable t;
  const std::string error = Read(text, t);
  EXPECT_NE(error.find(words), std::string::npos) << "error: " << error;
  EXPECT_EQ(t.Rows(), 0u);
  EXPECT_TRUE(t.start.empty());
}

TEST(QsmTable, MalformedTablesNameTheLineAndKeepNothing)
{
  const std::string csv = fixtures::SimpleForestCsv;
  ExpectRefused(csv + "4,1,0,0,x,0,0,1,0.1,1,1,1,3\n", "line 5: column 5 is not a number: 'x'");
  ExpectRefused(csv + "4,1,0,0\n", "line 5: 4 columns where the first row has 13");
  ExpectRefused(csv.substr(0, csv.find('\n') + 1), "no cylinder row");
  ExpectRefused("ID,parentID,startX,startY,startZ,endX,endY,endZ\n1,0,0,0,0,0,0,1\n", "names no radius column");
  ExpectRefused("ID,parentID,startX,startY,startZ,radius\n1,0,0,0,0,1\n", "names no endX, endY, endZ");
  ExpectRefused("1 2 3 4\n", "line 1: no header and 4 columns");
  ExpectRefused(csv + "4,1,0,0,NA,0,0,1,0.1,1,1,1,3\n", "cylinder 4 (table row 4) has a missing start");
  ExpectRefused(csv + std::string(kMaxQsmLineLength + 1, '1') + "\n", "line 5: longer than");
  ExpectRefused(std::string("1 2\0 3\n", 7), "line 1: holds a NUL byte");
  ExpectRefused("", "no cylinder row");
}
} // namespace
} // namespace plantmorph
