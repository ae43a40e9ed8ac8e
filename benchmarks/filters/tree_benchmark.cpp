// SPDX-License-Identifier: GPL-3.0-or-later
// TreeFromSketchSource benchmark (docs/methods/tree-from-sketch.md): segments per second and bytes per segment from
// 10^3 to 10^6 skeleton segments, for the algorithm layer (template growth + watertight tubes, serial) and for the
// whole VTK source (template, tubes through vtkSMPTools, arrays, skeleton, no leaves); second argument: the joints, 0
// seated tubes (BuildTubes), 1 welded (BuildWeldedTubes, the source's default).
//
// Sizes: Table 1's left template (monopodial 3/8, 8 children) at depth 2..5 with SegmentsPerBranch chosen to reach
// about 10^3, 10^4, 10^5 and 10^6 segments (the exact count is reported as `segments`), 6 sides.
//
//   tree_benchmark --benchmark_counters_tabular=true
#include "BranchJunctions.h"
#include "BranchTubes.h"
#include "TreeStrokes.h"
#include "TreeTemplate.h"

#include "vtkTreeFromSketchSource.h"

#include "vtkCellArray.h"
#include "vtkNew.h"
#include "vtkPolyData.h"

#include "PeakMemory.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

using plantmorph_benchmarks::PeakMemoryProbe;

namespace
{
struct Size
{
  int depth;
  int segmentsPerBranch;
};

/// 10^(3 + index) segments: depth 2 (73 branches) x 14, depth 3 (585) x 17, depth 4 (4681) x 21, depth 5 (37449) x 27.
Size SizeFor(int index)
{
  const Size sizes[] = { { 2, 14 }, { 3, 17 }, { 4, 21 }, { 5, 27 } };
  return sizes[index];
}

plantmorph::TreeParameters Settings(int index)
{
  plantmorph::TreeParameters s;
  plantmorph::ApplyTreePreset(1, s);
  s.depth = SizeFor(index).depth;
  s.segmentsPerBranch = SizeFor(index).segmentsPerBranch;
  s.leaves = false;
  return s;
}

double MeshBytes(const plantmorph::TubeMesh& m)
{
  return static_cast<double>(m.points.size() * sizeof(double) + m.normals.size() * sizeof(float) +
    m.tcoords.size() * sizeof(float) + m.triangles.size() * sizeof(std::int32_t) +
    (m.pointOffsets.size() + m.triangleOffsets.size()) * sizeof(std::int64_t));
}

void BM_TreeCore(benchmark::State& state)
{
  const plantmorph::TreeParameters s = Settings(static_cast<int>(state.range(0)));
  const bool welded = state.range(1) == 1;
  double segments = 0.0, bytes = 0.0, triangles = 0.0;
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    plantmorph::Tree tree;
    if (!plantmorph::BuildTree(s, {}, tree).empty())
    {
      state.SkipWithError("BuildTree failed");
      return;
    }
    const std::vector<plantmorph::TubeInput> tubes = plantmorph::TreeTubeInputs(tree);
    plantmorph::TubeMesh mesh;
    if (!(welded ? plantmorph::BuildWeldedTubes(tubes, s.sides, mesh) : plantmorph::BuildTubes(tubes, s.sides, mesh))
           .empty())
    {
      state.SkipWithError("BuildTubes failed");
      return;
    }
    segments = static_cast<double>(tree.SegmentCount());
    bytes = MeshBytes(mesh);
    triangles = static_cast<double>(mesh.TriangleCount());
    benchmark::DoNotOptimize(mesh.points.data());
  }
  memory.Report(state, 0.0, bytes);
  state.counters["segments"] = segments;
  state.counters["triangles"] = triangles;
  state.counters["seg_per_s"] = benchmark::Counter(segments, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["mesh_B_per_seg"] = bytes / segments;
  state.counters["peak_B_per_seg"] = memory.Peak() / segments;
}

void BM_TreeSource(benchmark::State& state)
{
  const Size size = SizeFor(static_cast<int>(state.range(0)));
  double segments = 0.0, bytes = 0.0;
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    vtkNew<vtkTreeFromSketchSource> source;
    source->SetPreset(0); // Custom: the class defaults are Table 1's left template, Depth varies
    source->SetDepth(size.depth);
    source->SetSegmentsPerBranch(size.segmentsPerBranch);
    source->SetLeaves(0);
    source->SetJoints(state.range(1) == 1 ? 0 : 1);
    source->Update();
    vtkPolyData* branches = vtkPolyData::SafeDownCast(source->GetOutputDataObject(0));
    vtkPolyData* skeleton = vtkPolyData::SafeDownCast(source->GetOutputDataObject(1));
    segments = static_cast<double>(skeleton->GetNumberOfPoints() - skeleton->GetNumberOfLines());
    bytes = static_cast<double>(branches->GetActualMemorySize() + skeleton->GetActualMemorySize()) * 1024.0;
    benchmark::DoNotOptimize(branches->GetNumberOfCells());
  }
  memory.Report(state, 0.0, bytes);
  state.counters["segments"] = segments;
  state.counters["seg_per_s"] = benchmark::Counter(segments, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["out_B_per_seg"] = bytes / segments;
  state.counters["peak_B_per_seg"] = memory.Peak() / segments;
}
} // namespace

/// What the joints cost: the tubes of the 10^6-segment tree alone (serial), without parents (arg 0: every tube
/// stands alone), seated (arg 1: base rings seated on the parents) and welded (arg 2: convex-hull junctions).
void BM_TreeTubesJoints(benchmark::State& state)
{
  const plantmorph::TreeParameters s = Settings(3);
  plantmorph::Tree tree;
  if (!plantmorph::BuildTree(s, {}, tree).empty())
  {
    state.SkipWithError("BuildTree failed");
    return;
  }
  std::vector<plantmorph::TubeInput> tubes = plantmorph::TreeTubeInputs(tree);
  if (state.range(0) == 0)
  {
    for (plantmorph::TubeInput& t : tubes)
      t.parent = -1;
  }
  plantmorph::JointReport joints;
  plantmorph::JunctionReport junctions;
  for (auto _ : state)
  {
    plantmorph::TubeMesh mesh;
    const std::string error = state.range(0) == 2
      ? plantmorph::BuildWeldedTubes(tubes, s.sides, mesh, plantmorph::SerialFor, &junctions)
      : plantmorph::BuildTubes(tubes, s.sides, mesh, plantmorph::SerialFor, &joints);
    if (!error.empty())
    {
      state.SkipWithError("BuildTubes failed");
      return;
    }
    benchmark::DoNotOptimize(mesh.points.data());
  }
  state.counters["segments"] = static_cast<double>(tree.SegmentCount());
  state.counters["seated"] = static_cast<double>(joints.seated);
  state.counters["missed"] = static_cast<double>(joints.missed);
  state.counters["clamped"] = static_cast<double>(joints.clamped);
  state.counters["buried"] = static_cast<double>(joints.buried);
  state.counters["junctions"] = static_cast<double>(junctions.junctions);
  state.counters["welded"] = static_cast<double>(junctions.welded);
  state.counters["merged"] = static_cast<double>(junctions.merged);
  state.counters["fallback"] = static_cast<double>(junctions.fallback);
}

/// Eq. (2) for n two-point strokes (a stroke file of rows stroke_id, x, y): a trunk, then each stroke starts within
/// 0.5 of a random point of an earlier one and runs 1 to 20 in a random direction. Args: n, search (0 the grid,
/// 1 exhaustive).
void BM_StrokeAttach(benchmark::State& state)
{
  const auto n = static_cast<std::size_t>(state.range(0));
  std::mt19937_64 random(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::vector<Eigen::Vector3d>> strokes = { { Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 100, 0) } };
  while (strokes.size() < n)
  {
    const auto& from = strokes[static_cast<std::size_t>(unit(random) * double(strokes.size())) % strokes.size()];
    const Eigen::Vector3d start =
      from[unit(random) < 0.5 ? 0 : 1] + Eigen::Vector3d(unit(random) - 0.5, unit(random) - 0.5, 0);
    const double angle = 6.283185307179586 * unit(random), length = 1.0 + 19.0 * unit(random);
    strokes.push_back({ start, start + length * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0) });
  }
  plantmorph::TreeParameters s;
  s.mode = plantmorph::TreeMode::Strokes;
  s.strokesOnly = true;
  s.leaves = false;
  const auto search = state.range(1) ? plantmorph::StrokeSearch::Exhaustive : plantmorph::StrokeSearch::Grid;
  for (auto _ : state)
  {
    plantmorph::Tree tree;
    if (!plantmorph::AddStrokes(s, strokes, tree, search).empty())
    {
      state.SkipWithError("AddStrokes failed");
    }
    benchmark::DoNotOptimize(tree.branches.data());
  }
  state.counters["strokes"] = static_cast<double>(n);
}

// CPU time is the process's (every thread's): the source's tubes and arrays run on vtkSMPTools' threads.
BENCHMARK(BM_TreeCore)
  ->ArgsProduct({ { 0, 1, 2, 3 }, { 0, 1 } })
  ->Unit(benchmark::kMillisecond)
  ->MeasureProcessCPUTime()
  ->UseRealTime();
BENCHMARK(BM_TreeTubesJoints)->DenseRange(0, 2)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_TreeSource)
  ->ArgsProduct({ { 0, 1, 2, 3 }, { 0, 1 } })
  ->Unit(benchmark::kMillisecond)
  ->MeasureProcessCPUTime()
  ->UseRealTime();

BENCHMARK(BM_StrokeAttach)
  ->ArgsProduct({ { 10000, 40000, 100000 }, { 0, 1 } })
  ->Unit(benchmark::kMillisecond)
  ->Iterations(1)
  ->UseRealTime();

BENCHMARK_MAIN();
