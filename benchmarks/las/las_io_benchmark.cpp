// SPDX-License-Identifier: GPL-3.0-or-later
// The LAS reader and writer (sources/las/core): points per second and bytes per second of LAS 1.4 point format 7
// with PlantMorph's five labels as extra bytes (61-byte records), in memory (no disk), against the point count, with
// the peak memory the read adds (the cloud's arrays: 8 bytes per value, so about 150 bytes a point here).
//   build/bin/las_io_benchmark --benchmark_counters_tabular=true
#include "LasFile.h"
#include "PeakMemory.h"

#include <benchmark/benchmark.h>

#include <random>
#include <sstream>
#include <string>

namespace
{
plantmorph::LasCloud LabelledScan(std::size_t n)
{
  std::mt19937 random(1);
  std::uniform_real_distribution<double> coordinate(-5.0, 5.0);
  plantmorph::LasCloud cloud;
  cloud.xyz.resize(3 * n);
  for (double& v : cloud.xyz)
  {
    v = coordinate(random);
  }
  const auto add = [&](const char* name, plantmorph::LasType type, int components, unsigned top) {
    plantmorph::LasField field;
    field.name = name;
    field.type = type;
    field.components = components;
    field.values.resize(n * static_cast<std::size_t>(components));
    for (double& v : field.values)
    {
      v = static_cast<double>(random() % top);
    }
    cloud.fields.push_back(std::move(field));
  };
  using T = plantmorph::LasType;
  add("Intensity", T::UInt16, 1, 65536);
  add("ReturnNumber", T::UInt8, 1, 15);
  add("Classification", T::UInt8, 1, 256);
  add("GpsTime", T::Double, 1, 1000000);
  add("RGB", T::UInt16, 3, 65536);
  add("LeafId", T::Int32, 1, 40);
  add("Organ", T::UInt8, 1, 5);
  add("BranchId", T::Int64, 1, 1000);
  add("BeamId", T::Int64, 1, 2000000000);
  add("ScanPosition", T::Int32, 1, 8);
  return cloud;
}

std::string Written(std::size_t n)
{
  std::ostringstream out;
  plantmorph::WriteLas(out, LabelledScan(n), plantmorph::LasWriteOptions());
  return out.str();
}

void BM_ReadLas(benchmark::State& state)
{
  const std::string bytes = Written(static_cast<std::size_t>(state.range(0)));
  plantmorph_benchmarks::PeakMemoryProbe probe;
  probe.Start();
  for (auto _ : state)
  {
    std::istringstream in(bytes);
    plantmorph::LasCloud cloud;
    const std::string error = plantmorph::ReadLas(in, bytes.size(), cloud);
    if (!error.empty())
    {
      state.SkipWithError(error.c_str());
    }
    benchmark::DoNotOptimize(cloud.xyz.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(bytes.size()));
  probe.Report(state, static_cast<double>(bytes.size()));
}

void BM_WriteLas(benchmark::State& state)
{
  const plantmorph::LasCloud cloud = LabelledScan(static_cast<std::size_t>(state.range(0)));
  std::size_t size = 0;
  for (auto _ : state)
  {
    std::ostringstream out;
    plantmorph::WriteLas(out, cloud, plantmorph::LasWriteOptions());
    size = static_cast<std::size_t>(out.tellp());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.SetBytesProcessed(state.iterations() * static_cast<std::int64_t>(size));
}
} // namespace

BENCHMARK(BM_ReadLas)->Arg(100000)->Arg(1000000)->Arg(4000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WriteLas)->Arg(100000)->Arg(1000000)->Arg(4000000)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
