// SPDX-License-Identifier: GPL-3.0-or-later
// Leaf Cloud Reader's read rate (is a 10^7-point scan read at a disk-like rate, in linear time?): a text point cloud
// written like the shipped scans (data/leaf-clouds/) read by the reader as ParaView runs it, and by its VTK-free parser
// alone.
//
// Families (see benchmarks/README.md, "leaf_cloud_reader_benchmark"):
//   BM_LeafCloudReader/points:N/columns:C   vtkLeafCloudReader::Update() on a file of N points: C = 3 is the sugar
//                                            beet format ("%.4f,%.4f,%.4f"), C = 10 the soybean one (x y z, normal,
//                                            colour fractions, scalar, "%f" comma-separated). Both output ports.
//   BM_PointCloudText/points:N/columns:C    plantmorph::ReadPointCloudText alone on the same file (the parse).
// The file is written once per size (untimed) into the temporary directory and removed afterwards.
// Counters: MB_per_s (10^6 bytes of file per CPU second of the reading thread: the reader is serial, and on the
// shared 2-core machine wall time also measures the neighbours; the Time column is wall time), pts_per_s,
// file_bytes, peak memory (PeakMemory.h).
#include "../PeakMemory.h"

#include "PointCloudText.h"
#include "vtkLeafCloudReader.h"

#include "vtkNew.h"
#include "vtkPolyData.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace
{
using plantmorph_benchmarks::PeakMemoryProbe;

/// Writes N points of C columns; returns the path.
std::string WriteCloud(long long points, int columns)
{
  const std::string path = (std::filesystem::temp_directory_path() /
    ("plantmorph_cloud_" + std::to_string(points) + "_" + std::to_string(columns) + ".txt"))
                             .string();
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file)
  {
    return {};
  }
  std::uint64_t state = 88172645463325252ull; // xorshift64: reproducible file contents
  const auto next = [&state]() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  for (long long i = 0; i < points; ++i)
  {
    const double x = 200.0 * next() - 100.0, y = 200.0 * next() - 100.0, z = 150.0 * next();
    if (columns == 3)
    {
      std::fprintf(file, "%.4f,%.4f,%.4f\n", x, y, z);
    }
    else
    {
      std::fprintf(file, "%f,%f,%f,%f,%f,%f,%f,%f,%f,%f\n", x, y, z, next() - 0.5, next() - 0.5, -next(), next(),
        next(), next(), next());
    }
  }
  std::fclose(file);
  return path;
}

void Report(benchmark::State& state, const std::string& path, long long points, const PeakMemoryProbe& memory)
{
  const double bytes = static_cast<double>(std::filesystem::file_size(path));
  const double runs = static_cast<double>(state.iterations());
  state.counters["MB_per_s"] = benchmark::Counter(bytes * runs / 1e6, benchmark::Counter::kIsRate);
  state.counters["pts_per_s"] = benchmark::Counter(static_cast<double>(points) * runs, benchmark::Counter::kIsRate);
  state.counters["file_bytes"] = plantmorph_benchmarks::Bytes(bytes);
  memory.Report(state, bytes);
  std::filesystem::remove(path);
}

void BM_LeafCloudReader(benchmark::State& state)
{
  const long long points = state.range(0);
  const std::string path = WriteCloud(points, static_cast<int>(state.range(1)));
  if (path.empty())
  {
    state.SkipWithError("cannot write the cloud file");
    return;
  }
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    vtkNew<vtkLeafCloudReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    if (reader->GetOutput()->GetNumberOfPoints() != points)
    {
      state.SkipWithError("wrong point count");
      break;
    }
  }
  Report(state, path, points, memory);
}

void BM_PointCloudText(benchmark::State& state)
{
  const long long points = state.range(0);
  const std::string path = WriteCloud(points, static_cast<int>(state.range(1)));
  if (path.empty())
  {
    state.SkipWithError("cannot write the cloud file");
    return;
  }
  PeakMemoryProbe memory;
  memory.Start();
  for (auto _ : state)
  {
    std::ifstream in(path, std::ios::binary);
    plantmorph::PointCloudText cloud;
    const std::string error = plantmorph::ReadPointCloudText(in, cloud);
    if (!error.empty() || cloud.Rows() != static_cast<std::size_t>(points))
    {
      state.SkipWithError(error.empty() ? "wrong point count" : error.c_str());
      break;
    }
    benchmark::DoNotOptimize(cloud.values.data());
  }
  Report(state, path, points, memory);
}

BENCHMARK(BM_LeafCloudReader)
  ->ArgNames({ "points", "columns" })
  ->Args({ 100000, 3 })
  ->Args({ 10000000, 3 })
  ->Args({ 1000000, 10 })
  ->Unit(benchmark::kMillisecond)
  ->Iterations(3);
BENCHMARK(BM_PointCloudText)
  ->ArgNames({ "points", "columns" })
  ->Args({ 10000000, 3 })
  ->Args({ 1000000, 10 })
  ->Unit(benchmark::kMillisecond)
  ->Iterations(3);
} // namespace

BENCHMARK_MAIN();
