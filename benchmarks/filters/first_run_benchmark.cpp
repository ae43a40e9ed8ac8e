// SPDX-License-Identifier: GPL-3.0-or-later
// What a user's first click costs: a filter's first update in a fresh process against its next updates, for our
// filters and for the VTK filter they are compared with, each in the same kind of fresh process (see
// benchmarks/README.md, "first run"). Not a Google Benchmark program: a process runs one case, so its first update is
// really the process's first, and benchmarks/first_run.sh starts one process per case and repeat.
//
//   first_run_benchmark CASE [WARM_RUNS]
//
// CASE: loop (AdaptiveLoopFilter, uniform Loop, 3 levels of a 19,600-triangle sphere: 1,254,400 triangles),
// vtkloop (vtkLoopSubdivisionFilter, the same), distance (CloudComparisonFilter, 10^6 points against a
// 203,520-triangle sphere), vtkdistance (vtkImplicitPolyDataDistance over the same points: VTK's own point-to-surface
// distance, serial). Prints one line per update: `CASE run SECONDS CPU_SECONDS PAGE_FAULTS CALLING_CPU` (run 0 is the
// first; wall time, the process's CPU time over all its threads, its minor page faults, and the CPU time of the
// calling thread alone), inputs built untimed. On a loaded machine compare the CPU times: first / warm is then still
// what the first update pays. vtkSMPTools' threads do the parallel loops while the calling thread waits, so the
// calling thread's CPU time is the update's serial part: on an idle machine with T cores the wall time is about
// CALLING_CPU + (CPU_SECONDS - CALLING_CPU) / T.
#include "vtkAdaptiveLoopFilter.h"
#include "vtkCloudComparisonFilter.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkImplicitPolyDataDistance.h"
#include "vtkLoopSubdivisionFilter.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>

#include <sys/resource.h>

namespace
{
/// A sphere of 2 * theta * (phi - 2) triangles.
vtkSmartPointer<vtkPolyData> Sphere(int theta, int phi)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(theta);
  sphere->SetPhiResolution(phi);
  sphere->Update();
  vtkSmartPointer<vtkPolyData> out = sphere->GetOutput();
  return out;
}

/// 10^6 points in a shell of radius 0.8-1.2 around the unit sphere, a fixed seed.
vtkSmartPointer<vtkPolyData> Cloud()
{
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> radius(0.4, 0.6);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(1000000);
  for (vtkIdType i = 0; i < 1000000; ++i)
  {
    double p[3] = { normal(random), normal(random), normal(random) };
    const double s = radius(random) / std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    points->SetPoint(i, p[0] * s, p[1] * s, p[2] * s);
  }
  auto cloud = vtkSmartPointer<vtkPolyData>::New();
  cloud->SetPoints(points);
  return cloud;
}

struct Cost
{
  double wall, cpu, faults, calling;
};

/// The CPU seconds (user and system) of `who` (RUSAGE_SELF: every thread; RUSAGE_THREAD: the calling one), and its
/// minor page faults so far.
void Usage(int who, double& cpu, double& faults)
{
  rusage u{};
  getrusage(who, &u);
  cpu = static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
    1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  faults = static_cast<double>(u.ru_minflt);
}

Cost Time(const std::function<void()>& run)
{
  double cpu0 = 0.0, faults0 = 0.0, cpu1 = 0.0, faults1 = 0.0, calling0 = 0.0, calling1 = 0.0, unused = 0.0;
  Usage(RUSAGE_SELF, cpu0, faults0);
  Usage(RUSAGE_THREAD, calling0, unused);
  const auto start = std::chrono::steady_clock::now();
  run();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Usage(RUSAGE_SELF, cpu1, faults1);
  Usage(RUSAGE_THREAD, calling1, unused);
  return { wall, cpu1 - cpu0, faults1 - faults0, calling1 - calling0 };
}

std::function<void()> Case(const std::string& name)
{
  if (name == "loop" || name == "vtkloop")
  {
    vtkSmartPointer<vtkPolyData> sphere = Sphere(98, 102); // 19,600 triangles
    if (name == "loop")
      return [sphere]() {
        vtkNew<vtkAdaptiveLoopFilter> filter;
        filter->SetInputData(sphere);
        filter->SetMaximumLevel(3);
        filter->SetEdgeAngleThreshold(180.0);
        filter->SetFlatnessThreshold(1.0);
        filter->SetFeatureRule(vtkAdaptiveLoopFilter::LOOP);
        filter->Update();
      };
    return [sphere]() {
      vtkNew<vtkLoopSubdivisionFilter> filter;
      filter->SetInputData(sphere);
      filter->SetNumberOfSubdivisions(3);
      filter->Update();
    };
  }
  if (name == "distance" || name == "vtkdistance")
  {
    vtkSmartPointer<vtkPolyData> sphere = Sphere(318, 322); // 203,520 triangles
    vtkSmartPointer<vtkPolyData> cloud = Cloud();
    if (name == "distance")
      return [sphere, cloud]() {
        vtkNew<vtkCloudComparisonFilter> filter;
        filter->SetInputData(0, cloud);
        filter->SetReferenceData(sphere);
        filter->Update();
      };
    return [sphere, cloud]() {
      vtkNew<vtkImplicitPolyDataDistance> distance;
      distance->SetInput(sphere);
      vtkNew<vtkDoubleArray> out;
      out->SetNumberOfValues(cloud->GetNumberOfPoints());
      for (vtkIdType i = 0; i < cloud->GetNumberOfPoints(); ++i)
        out->SetValue(i, distance->EvaluateFunction(cloud->GetPoint(i)));
    };
  }
  return {};
}
} // namespace

int main(int argc, char** argv)
{
  const std::string name = argc > 1 ? argv[1] : "";
  const int warm = argc > 2 ? std::atoi(argv[2]) : 3;
  const std::function<void()> run = Case(name);
  if (!run || warm < 0)
  {
    std::fprintf(stderr, "usage: first_run_benchmark loop|vtkloop|distance|vtkdistance [WARM_RUNS]\n");
    return 2;
  }
  for (int i = 0; i <= warm; ++i)
  {
    const Cost cost = Time(run);
    std::printf("%s %d %.4f %.4f %.0f %.4f\n", name.c_str(), i, cost.wall, cost.cpu, cost.faults, cost.calling);
  }
  return 0;
}
