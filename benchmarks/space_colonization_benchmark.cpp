// Space colonization venation cost versus network size (issue 22 item 3): plantmorph::GrowVenation with
// VenationPattern::SpaceColonization on one fixed blade, the kill distance k halved step by step with the source
// density scaled as 1/k^2 (3000 darts per L^2 at k = 0.01 L), so the network grows from about 10^3 to 10^6 vein
// segments with the same look. Near-linear cost means s_per_seg stays about flat: every attraction, kill and
// dart-throwing query goes through uniform grids (SpaceColonization.cpp).
//
// Argument: KillDistance in units of 1e-5 leaf lengths. Counters: segments, seg_per_s, s_per_seg (CPU seconds per
// segment), peak_bytes / peak_ratio (see PeakMemory.h).
//
//   build/bin/space_colonization_benchmark
#include "PeakMemory.h"

#include "DeformedRectangleLeaf.h"
#include "DeformedRectanglePresets.h"
#include "VenationGrowth.h"

#include <benchmark/benchmark.h>

#include <string>

namespace
{
using plantmorph_benchmarks::PeakMemoryProbe;

/// The "Entire" ovate preset, 5 cm, Resolution 100 (~4*10^4 triangles), built once.
const plantmorph::VenationBlade& Blade()
{
  static const plantmorph::VenationBlade blade = [] {
    plantmorph::LeafMeshSettings settings;
    settings.resolution = 100;
    plantmorph::LeafGeometry leaf;
    plantmorph::BuildDeformedRectangleLeaf(
      plantmorph::MakeDeformedRectanglePreset(plantmorph::DeformedRectanglePreset::Entire, 5.0), settings, leaf);
    return plantmorph::VenationBlade{ leaf.blade.points, leaf.blade.uv, leaf.blade.triangles };
  }();
  return blade;
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

// KillDistance 0.01 .. 0.0003 leaf lengths: about 10^3 .. 10^6 segments on this blade.
BENCHMARK(BM_SpaceColonization)->ArgName("kill_1e-5")->Arg(1000)->Arg(500)->Arg(250)->Arg(125)->Arg(63)->Arg(32)
  ->Unit(benchmark::kMillisecond)->MinTime(0.2);

int main(int argc, char** argv)
{
  Blade(); // build the blade before any measurement
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
