// SPDX-License-Identifier: GPL-3.0-or-later
// The MTG and QSM parsers and writers (sources/formats/core) on synthetic trees of 10^3 to 10^6 segments: a binary
// tree of 8-point branches written as MTG (plant / axis / segment) and as a QSM CSV, then read back (MTG: the graph
// and its axes and points). Counters: entities or cylinders per second, file bytes per second, and peak memory with
// peak_ratio = peak / file size (the parsers hold one line besides what they build).
//
//   build/bin/formats_benchmark --benchmark_counters_tabular=true
#include "MtgText.h"
#include "PeakMemory.h"
#include "QsmTable.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using plantmorph_benchmarks::PeakMemoryProbe;

/// A tree of `segments` points in branches of 8: branch b's parent (b - 1) / 2, starting on its parent's middle.
std::vector<plantmorph::MtgTreeBranch> Tree(std::size_t segments)
{
  std::vector<plantmorph::MtgTreeBranch> tree(segments / 8);
  for (std::size_t b = 0; b < tree.size(); ++b)
  {
    plantmorph::MtgTreeBranch& branch = tree[b];
    branch.id = static_cast<long long>(b);
    branch.parentId = b == 0 ? -1 : static_cast<long long>((b - 1) / 2);
    const std::array<double, 3> start = b == 0 ? std::array<double, 3>{ 0, 0, 0 } : tree[(b - 1) / 2].points[4];
    const double angle = 2.39996 * static_cast<double>(b);
    for (int k = 0; k < 8; ++k)
    {
      branch.points.push_back(
        { start[0] + 0.1 * k * std::cos(angle), start[1] + 0.3 * k, start[2] + 0.1 * k * std::sin(angle) });
      branch.radii.push_back(0.1 / (1.0 + 0.1 * k + std::log2(1.0 + static_cast<double>(b))));
    }
  }
  return tree;
}

std::string MtgText(std::size_t segments)
{
  std::ostringstream out;
  plantmorph::WriteMtg(out, Tree(segments));
  return out.str();
}

std::string QsmText(std::size_t segments)
{
  std::vector<plantmorph::QsmPolyline> lines;
  for (const plantmorph::MtgTreeBranch& b : Tree(segments))
  {
    plantmorph::QsmPolyline line;
    line.branchId = static_cast<double>(b.id);
    line.parentId = static_cast<double>(b.parentId);
    line.points = b.points;
    line.radii = b.radii;
    lines.push_back(line);
  }
  std::vector<std::size_t> lineOf;
  std::ostringstream out;
  plantmorph::WriteQsmTable(out, plantmorph::CylindersOfPolylines(lines, lineOf));
  return out.str();
}

void Rates(benchmark::State& state, double items, double bytes)
{
  state.counters["items_per_s"] = benchmark::Counter(items, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["bytes_per_s"] =
    benchmark::Counter(bytes, benchmark::Counter::kIsIterationInvariantRate, benchmark::Counter::OneK::kIs1024);
  state.counters["items"] = items;
}

void BM_ReadMtg(benchmark::State& state)
{
  const std::string text = MtgText(static_cast<std::size_t>(state.range(0)));
  PeakMemoryProbe memory;
  memory.Start();
  std::size_t entities = 0;
  for (auto _ : state)
  {
    std::istringstream in(text);
    plantmorph::MtgGraph graph;
    const std::string error = plantmorph::ReadMtg(in, graph);
    const plantmorph::MtgGeometry geometry = plantmorph::BuildMtgGeometry(graph);
    benchmark::DoNotOptimize(geometry.positions.data());
    if (!error.empty())
    {
      state.SkipWithError(error.c_str());
      break;
    }
    entities = graph.entities.size();
  }
  memory.Report(state, static_cast<double>(text.size()));
  Rates(state, static_cast<double>(entities), static_cast<double>(text.size()));
}

void BM_WriteMtg(benchmark::State& state)
{
  const auto tree = Tree(static_cast<std::size_t>(state.range(0)));
  std::size_t bytes = 0;
  for (auto _ : state)
  {
    std::ostringstream out;
    plantmorph::WriteMtg(out, tree);
    bytes = out.str().size();
  }
  Rates(state, static_cast<double>(state.range(0)), static_cast<double>(bytes));
}

void BM_ReadQsm(benchmark::State& state)
{
  const std::string text = QsmText(static_cast<std::size_t>(state.range(0)));
  PeakMemoryProbe memory;
  memory.Start();
  std::size_t rows = 0;
  for (auto _ : state)
  {
    std::istringstream in(text);
    plantmorph::QsmTable table;
    const std::string error = plantmorph::ReadQsmTable(in, table);
    benchmark::DoNotOptimize(table.values.data());
    if (!error.empty())
    {
      state.SkipWithError(error.c_str());
      break;
    }
    rows = table.Rows();
  }
  memory.Report(state, static_cast<double>(text.size()));
  Rates(state, static_cast<double>(rows), static_cast<double>(text.size()));
}

BENCHMARK(BM_ReadMtg)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WriteMtg)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadQsm)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMillisecond);
} // namespace

BENCHMARK_MAIN();
