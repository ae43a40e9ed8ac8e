// SPDX-License-Identifier: GPL-3.0-or-later
// LeafFit (fit/): fit time against point count (10^3 to 10^6 points on one leaf) and against leaf count (threaded
// over leaves), on synthetic scans of LeafOutlineSource's elliptic Model C leaf (100 mm long, 45 mm wide) curled by
// LeafCurl (40 degrees longitudinal, 30 transverse), noise 0.2 mm along the normal and 1 % outliers. Counters give
// the accuracy against the known truth: area_err and length_err (relative), fit_rms (mm).
#include "LeafFit.h"

#include "BSplineLeaf.h"
#include "LeafCurl.h"

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <random>
#include <thread>
#include <vector>

namespace
{
using namespace plantmorph;

struct Truth
{
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  double area = 0.0, length = 0.0;
};

Truth MakeTruth()
{
  LeafMeshParameters settings;
  settings.resolution = 200;
  LeafGeometry leaf;
  BuildBSplineLeaf(MakeBSplinePreset(BSplinePreset::Elliptic, 100.0, 45.0, 9), settings, leaf);
  std::vector<double> xyz, uv;
  for (std::size_t i = 0; i < leaf.blade.points.size(); ++i)
  {
    xyz.insert(xyz.end(), { leaf.blade.points[i].x(), leaf.blade.points[i].y(), 0.0 });
    uv.insert(uv.end(), { leaf.blade.uv[i].x(), leaf.blade.uv[i].y() });
  }
  LeafCurlParameters curl;
  curl.longitudinalAngle = 40.0;
  curl.transverseAngle = 30.0;
  LeafCurl map;
  map.Setup(curl, leaf.blade.points.size(), xyz.data(), uv.data());
  Truth truth;
  for (std::size_t i = 0; i < leaf.blade.points.size(); ++i)
  {
    double out[3];
    map.Map(i, &xyz[3 * i], out);
    truth.points.emplace_back(out[0], out[1], out[2]);
  }
  truth.triangles = leaf.blade.triangles;
  for (const auto& t : truth.triangles)
    truth.area += 0.5 * (truth.points[t[1]] - truth.points[t[0]]).cross(truth.points[t[2]] - truth.points[t[0]]).norm();
  for (std::size_t i = 1; i < leaf.midvein.size(); ++i)
    truth.length += (truth.points[leaf.midvein[i]] - truth.points[leaf.midvein[i - 1]]).norm();
  return truth;
}

const Truth& TheTruth()
{
  static const Truth truth = MakeTruth();
  return truth;
}

std::vector<Eigen::Vector3d> Scan(int count, unsigned seed)
{
  const Truth& truth = TheTruth();
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 0.2);
  std::vector<double> cdf;
  double total = 0.0;
  for (const auto& t : truth.triangles)
  {
    total += (truth.points[t[1]] - truth.points[t[0]]).cross(truth.points[t[2]] - truth.points[t[0]]).norm();
    cdf.push_back(total);
  }
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i)
  {
    const auto k = std::min<std::size_t>(
      std::lower_bound(cdf.begin(), cdf.end(), uniform(random) * total) - cdf.begin(), cdf.size() - 1);
    const auto& t = truth.triangles[k];
    double a = uniform(random), b = uniform(random);
    if (a + b > 1.0)
    {
      a = 1.0 - a;
      b = 1.0 - b;
    }
    const Eigen::Vector3d &p0 = truth.points[t[0]], &p1 = truth.points[t[1]], &p2 = truth.points[t[2]];
    points.push_back(p0 + a * (p1 - p0) + b * (p2 - p0) + gauss(random) * (p1 - p0).cross(p2 - p0).normalized());
  }
  for (int i = 0; i < count / 100; ++i)
    points.emplace_back(
      -40.0 + 80.0 * uniform(random), -10.0 + 120.0 * uniform(random), -20.0 + 40.0 * uniform(random));
  return points;
}

unsigned Threads()
{
  return std::max(1u, std::thread::hardware_concurrency());
}

/// One thread per core, each taking every Threads()-th index.
ParallelFor Pool()
{
  const unsigned threads = Threads();
  return [threads](std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
    std::vector<std::thread> workers;
    for (unsigned w = 0; w < threads; ++w)
      workers.emplace_back([&, w] {
        for (std::size_t i = w; i < count; i += threads)
          body(i, i + 1);
      });
    for (auto& t : workers)
      t.join();
  };
}

/// One leaf of range(0) points, serial (range(1) = 0) or its searches and per-point steps threaded (1).
void BM_FitOneLeaf(benchmark::State& state)
{
  const std::vector<Eigen::Vector3d> scan = Scan(static_cast<int>(state.range(0)), 1);
  const ParallelFor parallel = state.range(1) ? Pool() : ParallelFor(SerialFor);
  LeafFitResult fit;
  for (auto _ : state)
  {
    fit = FitLeaf(scan, LeafFitParameters(), parallel);
    benchmark::DoNotOptimize(fit.points.data());
  }
  if (!fit.error.empty())
  {
    state.SkipWithError(fit.error.c_str());
    return;
  }
  state.counters["points"] = static_cast<double>(scan.size());
  state.counters["area_err"] = fit.traits.area / TheTruth().area - 1.0;
  state.counters["length_err"] = fit.traits.length / TheTruth().length - 1.0;
  state.counters["fit_rms"] = fit.traits.fitRMS;
  state.counters["threads"] = state.range(1) ? Threads() : 1;
}
BENCHMARK(BM_FitOneLeaf)
  ->ArgsProduct({ { 1000, 10000, 100000, 1000000 }, { 0, 1 } })
  ->Unit(benchmark::kMillisecond)
  ->UseRealTime();

/// Leaves of 10^4 points each, fitted with one thread per leaf (range(1) = 1) or serially (0).
void BM_FitLeaves(benchmark::State& state)
{
  std::vector<std::vector<Eigen::Vector3d>> leaves;
  for (int k = 0; k < state.range(0); ++k)
    leaves.push_back(Scan(10000, 10 + k));
  const unsigned threads = Threads();
  const ParallelFor pool = Pool();
  for (auto _ : state)
  {
    const auto results = FitLeaves(leaves, LeafFitParameters(), state.range(1) ? pool : ParallelFor(SerialFor));
    benchmark::DoNotOptimize(results.data());
  }
  state.counters["leaves"] = static_cast<double>(leaves.size());
  state.counters["threads"] = state.range(1) ? threads : 1;
}
BENCHMARK(BM_FitLeaves)->ArgsProduct({ { 1, 4, 16 }, { 0, 1 } })->Unit(benchmark::kMillisecond)->UseRealTime();
} // namespace

BENCHMARK_MAIN();
