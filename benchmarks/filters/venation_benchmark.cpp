// SPDX-License-Identifier: GPL-3.0-or-later
// Venation growth cost versus network size (is growth linear in the network's size?): plantmorph::GrowVenation with the
// paper mulberry preset (brochidodromous secondaries, reticulate tertiaries) on one fixed blade, AreoleSize halved step
// by step so the network grows from about 10^3 to 10^6 vein segments. The cost per segment should stay flat: every
// crossing test goes through the vein graph's uniform grid and touches only the cells a new segment passes.
//
// Families (argument: AreoleSize in units of 1e-5 leaf lengths):
//   BM_Venation            the plugin's growth (grid cells of about one areole)
//   BM_VenationBruteForce  the same growth with one grid cell for everything (gridCellScale huge): every crossing
//                          test looks at every edge. The alternative the grid replaces; run up to ~2e4 segments.
//   BM_SpaceColonization   VenationPattern::SpaceColonization on the same blade (argument: KillDistance k in units
//                          of 1e-5 leaf lengths), AttractionDistance 10 k and SourceDensity 3000 (0.01 / k)^2 darts
//                          per L^2, so the network keeps its look while it grows from about 10^3 to 10^6 segments;
//                          every attraction, kill and dart query goes through uniform grids (SpaceColonization.cpp).
//
// Counters: segments (vein edges, margin excluded), seg_per_s, s_per_seg (CPU seconds per segment), areoles,
// peak_bytes / peak_ratio (peak above the baseline over the blade's and the network's bytes; see PeakMemory.h).
//
//   build/bin/venation_benchmark [--benchmark_filter=BM_Venation/ or =BM_SpaceColonization]
#include "PeakMemory.h"

#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"
#include "VenationGrowth.h"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>
#include <vector>

namespace
{
using plantmorph_benchmarks::PeakMemoryProbe;

/// The blade every run grows on: the "Entire" ovate preset, 5 cm, quality mesh with Resolution 100 (~4*10^4
/// triangles), built once.
const plantmorph::VenationBlade& Blade()
{
  static const plantmorph::VenationBlade blade = [] {
    plantmorph::LeafMeshParameters settings;
    settings.resolution = 100;
    plantmorph::LeafGeometry leaf;
    plantmorph::BuildDeformedRectangleLeaf(
      plantmorph::MakeDeformedRectanglePreset(plantmorph::DeformedRectanglePreset::Entire, 5.0), settings, leaf);
    return plantmorph::VenationBlade{ leaf.blade.points, leaf.blade.uv, leaf.blade.triangles };
  }();
  return blade;
}

double BladeBytes(const plantmorph::VenationBlade& blade)
{
  return static_cast<double>(blade.points.size() * sizeof(blade.points[0]) + blade.uv.size() * sizeof(blade.uv[0]) +
    blade.triangles.size() * sizeof(blade.triangles[0]));
}

double NetworkBytes(const plantmorph::VenationResult& r)
{
  std::size_t bytes = r.nodes.size() * (sizeof(r.nodes[0]) + sizeof(r.location[0]) + sizeof(double) + sizeof(int));
  for (const auto& v : r.veins)
    bytes += v.nodes.size() * sizeof(int) + sizeof(v);
  return static_cast<double>(bytes);
}

void Run(benchmark::State& state, double gridCellScale)
{
  const plantmorph::VenationBlade& blade = Blade();
  plantmorph::VenationParameters p = plantmorph::MakeVenationPreset(plantmorph::VenationPreset::PaperMulberry);
  p.areoleSize = 1e-5 * static_cast<double>(state.range(0));
  p.gridCellScale = gridCellScale;
  p.maxSegments = 20000000;
  std::size_t segments = 0, areoles = 0;
  double outBytes = 0.0;
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    plantmorph::VenationResult result;
    const std::string error = plantmorph::GrowVenation(blade, p, result);
    if (!error.empty())
    {
      state.SkipWithError(error.c_str());
      return;
    }
    benchmark::DoNotOptimize(result.nodes.data());
    segments = result.statistics.segments;
    areoles = result.statistics.areoles;
    outBytes = NetworkBytes(result);
  }
  memory.Report(state, BladeBytes(blade), outBytes);
  const double n = static_cast<double>(segments);
  state.counters["segments"] = n;
  state.counters["areoles"] = static_cast<double>(areoles);
  state.counters["seg_per_s"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["s_per_seg"] =
    benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_Venation(benchmark::State& state)
{
  Run(state, 1.0);
}

void BM_VenationBruteForce(benchmark::State& state)
{
  Run(state, 1e9);
}

void BM_SpaceColonization(benchmark::State& state)
{
  const plantmorph::VenationBlade& blade = Blade();
  plantmorph::VenationParameters p;
  p.pattern = plantmorph::VenationPattern::SpaceColonization;
  p.killDistance = 1e-5 * static_cast<double>(state.range(0));
  p.attractionDistance = 10.0 * p.killDistance;
  p.sourceDensity = 3000.0 * (0.01 / p.killDistance) * (0.01 / p.killDistance);
  p.maxSegments = 20000000;
  std::size_t segments = 0;
  double outBytes = 0.0;
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    plantmorph::VenationResult result;
    const std::string error = plantmorph::GrowVenation(blade, p, result);
    if (!error.empty())
    {
      state.SkipWithError(error.c_str());
      return;
    }
    benchmark::DoNotOptimize(result.nodes.data());
    segments = result.statistics.segments;
    outBytes = static_cast<double>(result.nodes.size() * (sizeof(result.nodes[0]) + sizeof(result.location[0]) + 12));
  }
  memory.Report(state, 0.0, outBytes);
  const double n = static_cast<double>(segments);
  state.counters["segments"] = n;
  state.counters["seg_per_s"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["s_per_seg"] =
    benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
} // namespace

// AreoleSize 0.04 .. 0.00125 leaf lengths: about 10^3 .. 10^6 segments on this blade.
BENCHMARK(BM_Venation)
  ->ArgName("areole_1e-5")
  ->Arg(4000)
  ->Arg(2000)
  ->Arg(1000)
  ->Arg(500)
  ->Arg(250)
  ->Arg(125)
  ->Unit(benchmark::kMillisecond)
  ->MinTime(0.2);
BENCHMARK(BM_VenationBruteForce)
  ->ArgName("areole_1e-5")
  ->Arg(4000)
  ->Arg(2000)
  ->Arg(1000)
  ->Unit(benchmark::kMillisecond)
  ->MinTime(0.2);

// KillDistance 0.01 .. 0.0003 leaf lengths: about 10^3 .. 10^6 segments on this blade.
BENCHMARK(BM_SpaceColonization)
  ->ArgName("kill_1e-5")
  ->Arg(1000)
  ->Arg(500)
  ->Arg(250)
  ->Arg(125)
  ->Arg(63)
  ->Arg(32)
  ->Unit(benchmark::kMillisecond)
  ->MinTime(0.2);

int main(int argc, char** argv)
{
  Blade(); // build the blade before any measurement
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  benchmark::AddCustomContext("blade", "Entire preset, 5 cm, Resolution 100 (quality)");
  benchmark::AddCustomContext("venation", "PaperMulberry preset, AreoleSize = argument * 1e-5 leaf lengths");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
