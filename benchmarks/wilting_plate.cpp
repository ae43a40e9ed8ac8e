// SPDX-License-Identifier: GPL-3.0-or-later
// wilting_plate: the VegaFEM 4.0 cross-check and Newmark speed benchmark of WiltingSimulator (docs/methods/wilting.md).
//
//   wilting_plate NX NY STEPS [--solver auto|cholesky|cg] [--threads N] [--cg-tolerance EPS] [--clamp]
//                 [--no-extrapolation]
//
// A plate of NX x NY x 1 cubes of edge 0.5 cm: node (i, j, k) at (0.5 i, 0.5 j, 0.5 k), k = 0 or 1; all 28 node
// pairs of every cube are springs (a pair shared by two cubes is one spring, stiffness not summed, as VegaFEM's
// massSpringSystem builds it from a std::set of pairs), stiffness 100, no spring damping, every node of mass 0.001,
// the nodes with i = 0 clamped, gravity as the external force m (0, 0, -981) per node, Newmark beta 0.25 gamma 0.5
// with one Newton iteration, Rayleigh alpha 0.01 beta 0.001 on the tangent stiffness (compression clamp off unless
// --clamp), dt = 1/240 s, from rest. Prints the free corner node (NX, NY, 0)'s displacement after STEPS steps,
// the steps per second (over all steps, and the median step), the assembly / solve split, and the process's CPU
// time per step (all threads): on a shared machine the wall time depends on what else runs, the CPU time much less.
// --no-extrapolation warm-starts CG from the last increment instead of 2 d_{s-1} - d_{s-2}.
//
// VegaFEM 4.0 on the same problem (22 x 22, 240 steps): (-18.0457, -0.2439, -8.2899) cm.
#include "MassSpringSystem.h"
#include "NewmarkIntegrator.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <set>
#include <string>
#include <utility>
#include <vector>

int main(int argc, char** argv)
{
  if (argc < 4)
  {
    std::fprintf(stderr,
      "usage: %s NX NY STEPS [--solver auto|cholesky|cg] [--threads N] [--cg-tolerance EPS] [--clamp] "
      "[--no-extrapolation]\n",
      argv[0]);
    return 2;
  }
  const int nx = std::atoi(argv[1]);
  const int ny = std::atoi(argv[2]);
  const int steps = std::atoi(argv[3]);
  if (nx < 1 || ny < 1 || steps < 1)
  {
    std::fprintf(stderr, "NX, NY and STEPS must be positive\n");
    return 2;
  }
  plantmorph::NewmarkParameters parameters;
  parameters.timeStep = 1.0 / 240.0;
  parameters.newmarkBeta = 0.25;
  parameters.newmarkGamma = 0.5;
  parameters.rayleighMass = 0.01;
  parameters.rayleighStiffness = 0.001;
  parameters.maxIterations = 1;
  parameters.compressionClamp = false;
  parameters.solver = plantmorph::NewmarkSolver::Auto;
  parameters.cgTolerance = 1e-6;
  parameters.threads = 0;
  for (int a = 4; a < argc; ++a)
  {
    const std::string option = argv[a];
    if (option == "--solver" && a + 1 < argc)
    {
      const std::string value = argv[++a];
      parameters.solver = value == "cholesky" ? plantmorph::NewmarkSolver::Cholesky
        : value == "cg"                       ? plantmorph::NewmarkSolver::ConjugateGradient
                                              : plantmorph::NewmarkSolver::Auto;
    }
    else if (option == "--threads" && a + 1 < argc)
    {
      parameters.threads = std::atoi(argv[++a]);
    }
    else if (option == "--cg-tolerance" && a + 1 < argc)
    {
      parameters.cgTolerance = std::atof(argv[++a]);
    }
    else if (option == "--no-extrapolation")
    {
      parameters.extrapolateWarmStart = false;
    }
    else if (option == "--clamp")
    {
      parameters.compressionClamp = true;
    }
    else
    {
      std::fprintf(stderr, "unknown option %s\n", option.c_str());
      return 2;
    }
  }

  const auto node = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  plantmorph::MassSpringSystem system;
  for (int k = 0; k < 2; ++k)
  {
    for (int j = 0; j <= ny; ++j)
    {
      for (int i = 0; i <= nx; ++i)
      {
        system.AddNode(Eigen::Vector3d(0.5 * i, 0.5 * j, 0.5 * k), 0.001, i == 0);
      }
    }
  }
  std::set<std::pair<int, int>> pairs;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      int corners[8];
      int c = 0;
      for (int k = 0; k < 2; ++k)
      {
        for (int dj = 0; dj < 2; ++dj)
        {
          for (int di = 0; di < 2; ++di)
          {
            corners[c++] = node(i + di, j + dj, k);
          }
        }
      }
      for (int p = 0; p < 8; ++p)
      {
        for (int q = p + 1; q < 8; ++q)
        {
          pairs.insert(std::minmax(corners[p], corners[q]));
        }
      }
    }
  }
  for (const auto& pair : pairs)
  {
    system.AddSpring(pair.first, pair.second, 100.0, 0.0);
  }
  const std::string error = system.Finalize();
  if (!error.empty())
  {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  const std::size_t n = system.NodeCount();
  std::vector<double> force(3 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
  {
    force[3 * i + 2] = system.IsFixed(i) ? 0.0 : -0.001 * 981.0;
  }
  plantmorph::NewmarkIntegrator integrator;
  const std::string setupError = integrator.Setup(system, parameters);
  if (!setupError.empty())
  {
    std::fprintf(stderr, "%s\n", setupError.c_str());
    return 1;
  }
  std::vector<double> stepSeconds;
  stepSeconds.reserve(static_cast<std::size_t>(steps));
  // CPU time of the whole process (all threads) over the steps: the work, which other jobs on a shared machine
  // inflate far less than the wall time.
  const auto cpuNow = [] {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  };
  const double cpuStart = cpuNow();
  const auto start = std::chrono::steady_clock::now();
  for (int s = 0; s < steps; ++s)
  {
    const auto stepStart = std::chrono::steady_clock::now();
    const std::string stepError = integrator.Step(force);
    stepSeconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - stepStart).count());
    if (!stepError.empty())
    {
      std::fprintf(stderr, "step %d: %s\n", s + 1, stepError.c_str());
      return 1;
    }
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cpu = cpuNow() - cpuStart;
  std::vector<double> sorted = stepSeconds;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const std::size_t corner = static_cast<std::size_t>(node(nx, ny, 0));
  const std::vector<double>& q = integrator.Displacement();
  const plantmorph::NewmarkTimings& timing = integrator.Timings();
  const bool cholesky = integrator.ActiveSolver() == plantmorph::NewmarkSolver::Cholesky;
  std::printf("plate %d x %d x 1 cubes: %zu nodes, %zu springs, %d steps of dt = 1/240 s (t = %.6g s)\n", nx, ny, n,
    system.SpringCount(), steps, integrator.Time());
  std::printf("corner node (%d, %d, 0) displacement: %.6f %.6f %.6f cm\n", nx, ny, q[3 * corner], q[3 * corner + 1],
    q[3 * corner + 2]);
  std::printf("solver %s, %d threads: %.2f steps/s overall, %.2f steps/s median step\n", cholesky ? "cholesky" : "cg",
    parameters.threads <= 0 ? 0 : parameters.threads, steps / total, 1.0 / median);
  std::printf("per step: assembly %.3f ms, solve %.3f ms%s; per node: %.3f us\n", 1e3 * timing.assemblySeconds / steps,
    1e3 * timing.solveSeconds / steps,
    cholesky ? ""
             : (" (" + std::to_string(timing.cgIterations / std::max(1LL, timing.newtonIterations)) + " CG iterations)")
                 .c_str(),
    1e6 * median / static_cast<double>(n));
  std::printf("CPU time (all threads): %.3f ms per step (%.2f steps per CPU second)\n", 1e3 * cpu / steps, steps / cpu);
  return 0;
}
