// SPDX-License-Identifier: GPL-3.0-or-later
// MtgText (sources/formats/core): FORM-A files in the shapes OpenAlea's documentation shows read into the entities,
// relations and features they code, the axes and points they become, a tree written and read back bit for bit, and
// malformed files refused with the line and nothing kept.
#include "FormatFixtures.h"
#include "MtgText.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace plantmorph
{
namespace
{
std::string Read(const std::string& text, MtgGraph& graph)
{
  std::istringstream in(text);
  return ReadMtg(in, graph);
}

/// The entity labelled `label` (the n-th of that label in file order).
long long Find(const MtgGraph& g, const std::string& label, int n = 0)
{
  for (std::size_t e = 0; e < g.entities.size(); ++e)
  {
    if (g.entities[e].Label() == label && n-- == 0)
    {
      return static_cast<long long>(e);
    }
  }
  return -1;
}

std::vector<std::string> Labels(const MtgGraph& g, const MtgAxis& axis)
{
  std::vector<std::string> labels;
  for (const long long e : axis.entities)
  {
    labels.push_back(g.entities[static_cast<std::size_t>(e)].Label());
  }
  return labels;
}

TEST(MtgText, ExplicitCoordinatesScalesContinuationAndMissingValues)
{
  MtgGraph g;
  ASSERT_EQ(Read(fixtures::ExplicitMtg, g), "");
  EXPECT_EQ(g.code, "FORM-A");
  ASSERT_EQ(g.classes.size(), 4u);
  EXPECT_EQ(g.classes[3].symbol, "E");
  EXPECT_EQ(g.classes[3].scale, 3);
  EXPECT_EQ(g.classes[3].definition, "EXPLICIT");
  EXPECT_EQ(g.description.size(), 3u);
  ASSERT_EQ(g.features.size(), 7u);
  EXPECT_EQ(g.features[5].kind, MtgFeatureKind::Integer);
  EXPECT_EQ(g.features[6].kind, MtgFeatureKind::Text); // DD/MM/YY kept as written
  // $ P1 U1 E1 E2 E1' E2' U2 E3 E4
  ASSERT_EQ(g.entities.size(), 10u);
  const long long e2 = Find(g, "E2"), branch1 = Find(g, "E1", 1), branch2 = Find(g, "E2", 1), e3 = Find(g, "E3");
  EXPECT_EQ(g.entities[static_cast<std::size_t>(branch1)].parent, e2);
  EXPECT_EQ(g.entities[static_cast<std::size_t>(branch1)].edge, '+');
  EXPECT_EQ(g.entities[static_cast<std::size_t>(branch2)].parent, branch1);
  EXPECT_EQ(g.entities[static_cast<std::size_t>(branch2)].edge, '<');
  // "^<U2/E3": U2 follows U1 and E3 follows E2 (the relation carried to the finer scale).
  EXPECT_EQ(g.entities[static_cast<std::size_t>(Find(g, "U2"))].parent, Find(g, "U1"));
  EXPECT_EQ(g.entities[static_cast<std::size_t>(e3)].parent, e2);
  EXPECT_EQ(g.entities[static_cast<std::size_t>(e3)].edge, '<');
  EXPECT_EQ(g.entities[static_cast<std::size_t>(e3)].complex, Find(g, "U2"));
  const int diam = g.FeatureIndex("diam"), note = g.FeatureIndex("note"), nb = g.FeatureIndex("nb");
  EXPECT_EQ(g.numbers[static_cast<std::size_t>(diam)][static_cast<std::size_t>(e2)], 1.8);
  EXPECT_TRUE(std::isnan(g.numbers[static_cast<std::size_t>(diam)][static_cast<std::size_t>(branch2)]));
  EXPECT_EQ(g.texts[static_cast<std::size_t>(note)][static_cast<std::size_t>(branch1)], "side");
  EXPECT_EQ(g.texts[static_cast<std::size_t>(note)][static_cast<std::size_t>(e2)], "");
  EXPECT_EQ(g.numbers[static_cast<std::size_t>(nb)][static_cast<std::size_t>(branch2)], 1.0);
  EXPECT_EQ(g.texts[6][static_cast<std::size_t>(Find(g, "E1"))], "12/05/21");

  const MtgGeometry geometry = BuildMtgGeometry(g);
  EXPECT_TRUE(geometry.explicitCoordinates);
  EXPECT_EQ(geometry.scale, 3);
  EXPECT_EQ(geometry.warning, "");
  ASSERT_EQ(geometry.axes.size(), 2u);
  EXPECT_EQ(Labels(g, geometry.axes[0]), (std::vector<std::string>{ "E1", "E2", "E3", "E4" }));
  EXPECT_EQ(Labels(g, geometry.axes[1]), (std::vector<std::string>{ "E1", "E2" }));
  EXPECT_EQ(geometry.axes[1].bearer, e2);
  EXPECT_EQ(geometry.axes[1].parentAxis, 0);
  EXPECT_EQ(geometry.axes[1].order, 1);
  EXPECT_EQ(geometry.positions[static_cast<std::size_t>(Find(g, "E4"))], (std::array<double, 3>{ 0.25, 0, 4 }));
  EXPECT_EQ(geometry.positions[static_cast<std::size_t>(branch2)], (std::array<double, 3>{ 2, 0, 4 }));
}

TEST(MtgText, ImplicitCoordinatesGetTheDefaultLayoutAndSaySo)
{
  MtgGraph g;
  ASSERT_EQ(Read(fixtures::ImplicitMtg, g), "");
  const MtgGeometry geometry = BuildMtgGeometry(g);
  EXPECT_FALSE(geometry.explicitCoordinates);
  EXPECT_NE(geometry.warning.find("no entity has XX, YY, ZZ"), std::string::npos);
  EXPECT_EQ(geometry.scale, 3);
  ASSERT_EQ(geometry.axes.size(), 2u);
  EXPECT_EQ(Labels(g, geometry.axes[0]), (std::vector<std::string>{ "I1", "I2", "I3", "I4" }));
  // The trunk along +y, one Length (2, then 1 where missing) per internode.
  const auto at = [&](const char* label, int n) {
    return geometry.positions[static_cast<std::size_t>(Find(g, label, n))];
  };
  EXPECT_EQ(at("I1", 0), (std::array<double, 3>{ 0, 2, 0 }));
  EXPECT_EQ(at("I4", 0), (std::array<double, 3>{ 0, 5, 0 }));
  // The branch from I4 at 45 degrees, its internodes of Length 1.
  const auto b = at("I2", 1);
  EXPECT_NEAR(b[0], -std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(b[1], 5 + std::sqrt(2.0), 1e-14);
  EXPECT_EQ(geometry.axes[1].bearer, Find(g, "I4"));
}

TEST(MtgText, MonopodialShapeWithRangesAndDeepColumns)
{
  MtgGraph g;
  ASSERT_EQ(Read(fixtures::MonopodialMtg, g), "");
  EXPECT_EQ(g.entities.size(), 18u);
  const MtgGeometry geometry = BuildMtgGeometry(g);
  EXPECT_EQ(geometry.scale, 4);
  ASSERT_EQ(geometry.axes.size(), 3u);
  EXPECT_EQ(Labels(g, geometry.axes[0]), (std::vector<std::string>{ "E1", "E2", "E3", "E4", "E5", "E6", "E7" }));
  EXPECT_EQ(Labels(g, geometry.axes[1]), (std::vector<std::string>{ "E1", "E2", "E3" }));
  EXPECT_EQ(Labels(g, geometry.axes[2]), (std::vector<std::string>{ "E1", "E2" }));
  EXPECT_EQ(geometry.axes[2].order, 2);
  EXPECT_EQ(geometry.axes[2].parentAxis, 1);
  // "^<U2" then "^/E4": E4 follows E3 of U1.
  const long long e4 = Find(g, "E4");
  EXPECT_EQ(g.entities[static_cast<std::size_t>(e4)].parent, Find(g, "E3", 1));
  const int diam = g.FeatureIndex("diam");
  EXPECT_EQ(g.numbers[static_cast<std::size_t>(diam)][static_cast<std::size_t>(Find(g, "E7"))], 1.5);
  EXPECT_TRUE(std::isnan(g.numbers[static_cast<std::size_t>(diam)][static_cast<std::size_t>(Find(g, "E6"))]));
  EXPECT_EQ(g.numbers[static_cast<std::size_t>(diam)][static_cast<std::size_t>(Find(g, "E2", 2))], 1.3);
}

TEST(MtgText, TreeWrittenAndReadBackBitForBit)
{
  std::vector<MtgTreeBranch> tree(4);
  tree[0] = { 0, -1, { { 0, 0, 0 }, { 0.1, 0, 1.0 / 3.0 }, { 0, 0.2, 2 } }, { 0.3, 0.2, 0.1 } };
  tree[1] = { 1, 0, { { 0.15, 0, 0.35 }, { 1, 0, 2 } }, { 0.1, 1e-17 } };
  tree[2] = { 7, 1, { { 0.5, 0, 1.5 }, { 0.5, 1, 1.5 }, { 0.5, 2, 1.75 } }, { 0.05, 0.04, 0.03 } };
  tree[3] = { 3, 0, { { 0.01, 0, 0.01 }, { -1, -0.5, 0.5 } }, { 0.2, 0.1 } };
  std::ostringstream out;
  ASSERT_EQ(WriteMtg(out, tree), "");
  MtgGraph g;
  ASSERT_EQ(Read(out.str(), g), "") << out.str();
  const MtgGeometry geometry = BuildMtgGeometry(g);
  ASSERT_TRUE(geometry.explicitCoordinates);
  EXPECT_EQ(geometry.scale, 3);
  ASSERT_EQ(geometry.axes.size(), 4u);
  const int diam = g.FeatureIndex("diam");
  std::map<std::string, std::size_t> axisOfBranch; // by its axis label A<id>
  for (std::size_t a = 0; a < geometry.axes.size(); ++a)
  {
    const MtgEntity& first = g.entities[static_cast<std::size_t>(geometry.axes[a].entities.front())];
    axisOfBranch[g.entities[static_cast<std::size_t>(first.complex)].Label()] = a;
  }
  for (const MtgTreeBranch& b : tree)
  {
    const MtgAxis& axis = geometry.axes[axisOfBranch.at("A" + std::to_string(b.id))];
    ASSERT_EQ(axis.entities.size(), b.points.size());
    for (std::size_t k = 0; k < b.points.size(); ++k)
    {
      const auto e = static_cast<std::size_t>(axis.entities[k]);
      EXPECT_EQ(geometry.positions[e], b.points[k]);
      EXPECT_EQ(g.numbers[static_cast<std::size_t>(diam)][e], 2 * b.radii[k]);
    }
  }
  // Each branch on its parent's point nearest to its start: 1 on the trunk's second, 3 on its first, 7 on 1's second.
  const auto bearerLabel = [&](long long id) {
    const MtgAxis& axis = geometry.axes[axisOfBranch.at("A" + std::to_string(id))];
    return g.entities[static_cast<std::size_t>(axis.bearer)].Label();
  };
  EXPECT_EQ(bearerLabel(1), "S2");
  EXPECT_EQ(bearerLabel(3), "S1");
  EXPECT_EQ(bearerLabel(7), "S2");
  EXPECT_EQ(geometry.axes[axisOfBranch.at("A7")].order, 2);
  EXPECT_EQ(geometry.axes[axisOfBranch.at("A0")].bearer, -1);
}

TEST(MtgText, WriterRefusesCyclesAndNegativeIds)
{
  std::ostringstream out;
  std::vector<MtgTreeBranch> cycle(2);
  cycle[0] = { 0, 1, { { 0, 0, 0 } }, {} };
  cycle[1] = { 1, 0, { { 0, 0, 1 } }, {} };
  EXPECT_NE(WriteMtg(out, cycle).find("cycle"), std::string::npos);
  cycle[0].id = -2;
  EXPECT_NE(WriteMtg(out, cycle).find("negative"), std::string::npos);
}

/// The rules openalea.mtg's reader follows beyond the grammar's plain cases (its own data files use them).
TEST(MtgText, OpenAleaReadingRules)
{
  const auto read = [](const std::string& rows, MtgGraph& g) {
    const std::string whole = fixtures::ExplicitMtg;
    return Read(whole.substr(0, whole.find("ENTITY-CODE")) + "ENTITY-CODE\t\t\t\tXX\tYY\tZZ\n" + rows, g);
  };
  MtgGraph g;
  // A '/' that skips a scale makes an unnamed complex between.
  ASSERT_EQ(read("/P1/E1\n", g), "");
  const MtgEntity& skipped = g.entities[static_cast<std::size_t>(g.entities[3].complex)];
  EXPECT_EQ(skipped.scale, 2);
  EXPECT_EQ(skipped.symbol, "");
  EXPECT_EQ(skipped.complex, Find(g, "P1"));
  // Column 0 without '^' goes on from the line above; a '/' to a coarser scale starts a new plant.
  ASSERT_EQ(read("/P1/U1\n/E1<E2\n/P2/U1/E1\n", g), "");
  EXPECT_EQ(g.entities[static_cast<std::size_t>(Find(g, "E1"))].complex, Find(g, "U1"));
  EXPECT_EQ(g.entities[static_cast<std::size_t>(Find(g, "P2"))].complex, 0);
  EXPECT_EQ(g.entities[static_cast<std::size_t>(Find(g, "E1", 1))].parent, -1);
  // After a line that went coarser ("^+U2"), a '^<E3' in its column follows the internode that line stood on.
  ASSERT_EQ(read("/P1\n\t/U1\n\t\t/E1\n\t\t^<E2\n\t\t^+U2\n\t\t\t/E1\n\t\t\t^<E2\n\t\t^<E3\n", g), "");
  const MtgEntity& e3 = g.entities[static_cast<std::size_t>(Find(g, "E3"))];
  EXPECT_EQ(e3.parent, Find(g, "E2"));
  EXPECT_EQ(e3.edge, '<');
  EXPECT_EQ(e3.complex, Find(g, "U1"));
  EXPECT_EQ(g.entities[static_cast<std::size_t>(Find(g, "E1", 1))].parent, Find(g, "E2"));
  EXPECT_EQ(g.entities[static_cast<std::size_t>(Find(g, "E1", 1))].edge, '+');
}

TEST(MtgText, UnmeasuredEntitiesAreSpreadAlongTheirAxis)
{
  MtgGraph g;
  const std::string whole = fixtures::ExplicitMtg;
  const std::string head = whole.substr(0, whole.find("/P1/U1/E1"));
  // E2..E4 of the run E2<<E5 measured at E5 only; E6 after the last measured one; a branch measured at its end.
  ASSERT_EQ(Read(head + "/P1/U1/E1\t\t\t0\t0\t0\n^<E2<<E5\t\t\t0\t0\t4\n\t+E1<E2\t\t2\t0\t4\n^<E6\n", g), "");
  const MtgGeometry geometry = BuildMtgGeometry(g);
  EXPECT_EQ(geometry.placedWithoutCoordinates, 5u);
  EXPECT_NE(geometry.warning.find("5 entities of scale 3 have no XX, YY, ZZ"), std::string::npos) << geometry.warning;
  const auto at = [&](const char* label, int n = 0) {
    return geometry.positions[static_cast<std::size_t>(Find(g, label, n))];
  };
  EXPECT_EQ(at("E2"), (std::array<double, 3>{ 0, 0, 1 }));
  EXPECT_EQ(at("E3"), (std::array<double, 3>{ 0, 0, 2 }));
  EXPECT_EQ(at("E4"), (std::array<double, 3>{ 0, 0, 3 }));
  EXPECT_EQ(at("E6"), (std::array<double, 3>{ 0, 0, 4 }));
  // The branch on E5 (0, 0, 4): its E1 halfway to its measured E2 (2, 0, 4).
  EXPECT_EQ(at("E1", 1), (std::array<double, 3>{ 1, 0, 4 }));
}

void ExpectRefused(const std::string& text, const std::string& words)
{
  MtgGraph g;
  const std::string error = Read(text, g);
  EXPECT_NE(error.find(words), std::string::npos) << "error: " << error;
  EXPECT_TRUE(g.entities.empty());
  EXPECT_TRUE(g.features.empty());
}

/// The explicit fixture with its MTG: data replaced by `rows` (line 29 is the first row).
std::string WithRows(const std::string& rows)
{
  const std::string whole = fixtures::ExplicitMtg;
  return whole.substr(0, whole.find("/P1/U1/E1")) + rows;
}

TEST(MtgText, MalformedFilesNameTheLineAndKeepNothing)
{
  ExpectRefused(WithRows("/P1/U1/X1\t\t\t0\t0\t1\n"), "line 29: symbol 'X' is not declared in CLASSES");
  ExpectRefused(WithRows("/P1/U1/E1\n\t^<E2\n"), "line 30: '^' in column 1, but no earlier line");
  ExpectRefused(WithRows("/P1/U1/E1\t\t\tone\n"), "line 29: feature 'XX' is REAL but its value is 'one'");
  ExpectRefused(WithRows("/P1/U1/E1\t\t\t0\t0\t1\t1\tx\t2.5\n"), "line 29: feature 'nb' is INT");
  ExpectRefused(WithRows("/P1/U1/E1\n^+U2\n^/E2<<E1\n"), "line 31: '<<E1' continues E2");
  ExpectRefused(WithRows("/P1/U1/E1\n^<E2<<E999999\n"), "at most 100000 further");
  ExpectRefused(WithRows("/P1/U1/E1\n^E2\n"), "line 30: expected '/', '<' or '+'");
  ExpectRefused(WithRows("/P1/U1/E1\n^<E2\n*(Date=1/1/21)\n"), "line 31: '*' (the dated observations");
  ExpectRefused(WithRows("/P1/U1/E1\t\t\t0\t0\t1\t1\tx\t2\t1/1/1\textra\n"), "line 29: a value in column 10");
  ExpectRefused(WithRows("/P1/U1/E1\t+E2\n"), "line 29: two codes on one line");
  ExpectRefused(WithRows("/P1/U1/E1\n^<E2\n^+E3++E5\n"), "line 31: '++'");
  ExpectRefused(WithRows(std::string("/P1/U1/E1\n^<E2\0\n", 16)), "line 30: holds a NUL byte");
  ExpectRefused(WithRows("/P1/U1/E1\n" + std::string(kMaxMtgLineLength + 1, 'x') + "\n"), "line 30: longer than");
  ExpectRefused("", "no MTG: section");
  ExpectRefused("CODE:\tFORM-A\nMTG:\n", "line 2: MTG: before any CLASSES");
  ExpectRefused("CODE:\tFORM-A\nCLASSES:\nSYMBOL\tSCALE\nP\tone\n", "line 4: a CLASSES row");
  const std::string header = WithRows("");
  ExpectRefused(header.substr(0, header.find("ENTITY-CODE")) + "ENTITY-CODE\t\tWidth\n", "column 'Width'");
  ExpectRefused(header, "the MTG: section has no entity");
  ExpectRefused("garbage\n", "line 1: text outside the sections");
}
} // namespace
} // namespace plantmorph
