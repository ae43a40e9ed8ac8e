// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer harness: the MTG reader (sources/formats/core/MtgRead.cpp) on arbitrary bytes. On success every relation
// points back in file order and within the scales, the feature columns have one value per entity, and the axes and
// points BuildMtgGeometry makes, written by WriteMtg (one branch per axis), read back with the same axes and the same
// points bit for bit. On error nothing is kept.
#include "MtgText.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace
{
void Require(bool condition)
{
  if (!condition)
  {
    std::abort();
  }
}

void CheckGraph(const plantmorph::MtgGraph& g)
{
  Require(g.entities.size() >= 2 && g.entities.size() <= plantmorph::kMaxMtgEntities);
  for (std::size_t e = 1; e < g.entities.size(); ++e)
  {
    const plantmorph::MtgEntity& x = g.entities[e];
    Require(x.complex >= 0 && static_cast<std::size_t>(x.complex) < e);
    Require(g.entities[static_cast<std::size_t>(x.complex)].scale == x.scale - 1);
    Require(x.parent < static_cast<long long>(e));
    Require(x.parent < 0 || g.entities[static_cast<std::size_t>(x.parent)].scale == x.scale);
  }
  for (std::size_t f = 0; f < g.features.size(); ++f)
  {
    const bool text = g.features[f].kind == plantmorph::MtgFeatureKind::Text;
    Require((text ? g.texts[f].size() : g.numbers[f].size()) == g.entities.size());
  }
}

/// The axes as a tree to write: axis a is branch a, its parent axis its parent.
std::vector<plantmorph::MtgTreeBranch> Tree(const plantmorph::MtgGeometry& geometry)
{
  std::vector<plantmorph::MtgTreeBranch> tree;
  for (std::size_t a = 0; a < geometry.axes.size(); ++a)
  {
    plantmorph::MtgTreeBranch b;
    b.id = static_cast<long long>(a);
    b.parentId = geometry.axes[a].parentAxis;
    for (const long long e : geometry.axes[a].entities)
    {
      b.points.push_back(geometry.positions[static_cast<std::size_t>(e)]);
    }
    tree.push_back(b);
  }
  return tree;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  plantmorph::MtgGraph graph;
  if (!plantmorph::ReadMtg(in, graph).empty())
  {
    Require(graph.entities.empty() && graph.features.empty());
    return 0;
  }
  CheckGraph(graph);
  const plantmorph::MtgGeometry geometry = plantmorph::BuildMtgGeometry(graph);
  bool finite = true;
  std::size_t points = 0;
  for (const plantmorph::MtgAxis& axis : geometry.axes)
  {
    Require(!axis.entities.empty());
    for (const long long e : axis.entities)
    {
      Require(graph.entities[static_cast<std::size_t>(e)].scale == geometry.scale);
      for (const double x : geometry.positions[static_cast<std::size_t>(e)])
      {
        finite = finite && std::isfinite(x);
      }
      ++points;
    }
  }
  if (!finite || geometry.axes.empty())
  {
    return 0; // a default layout past the double range (Length near 1e308) is not written
  }
  std::ostringstream out;
  Require(plantmorph::WriteMtg(out, Tree(geometry)).empty());
  std::istringstream again(out.str());
  plantmorph::MtgGraph back;
  Require(plantmorph::ReadMtg(again, back).empty());
  const plantmorph::MtgGeometry backGeometry = plantmorph::BuildMtgGeometry(back);
  Require(backGeometry.axes.size() == geometry.axes.size());
  std::size_t backPoints = 0;
  for (const plantmorph::MtgAxis& axis : backGeometry.axes)
  {
    backPoints += axis.entities.size();
  }
  Require(backPoints == points);
  return 0;
}
