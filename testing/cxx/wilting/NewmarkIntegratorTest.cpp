// SPDX-License-Identifier: GPL-3.0-or-later
// NewmarkIntegrator and MassSpringSystem against closed forms (docs/methods/wilting.md) and against VegaFEM
// 4.0's implicitNewmarkSparse on the benchmarks/wilting_plate problem.
#include "MassSpringSystem.h"
#include "NewmarkIntegrator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

namespace
{
using plantmorph::MassSpringSystem;
using plantmorph::NewmarkIntegrator;
using plantmorph::NewmarkParameters;
using plantmorph::NewmarkSolver;

constexpr double Pi = 3.14159265358979323846;

/// One spring from a fixed node at the origin to a free mass at (L, 0, 0).
void OneSpring(MassSpringSystem& system, double mass, double k, double length = 1.0)
{
  system.AddNode(Eigen::Vector3d::Zero(), 0.0, true);
  system.AddNode(Eigen::Vector3d(length, 0.0, 0.0), mass);
  system.AddSpring(0, 1, k);
  ASSERT_EQ(system.Finalize(), "");
}

NewmarkParameters Exact(double dt, NewmarkSolver solver = NewmarkSolver::Cholesky)
{
  NewmarkParameters p;
  p.timeStep = dt;
  p.maxIterations = 20;
  p.newtonTolerance = 1e-13;
  p.compressionClamp = false;
  p.solver = solver;
  p.cgTolerance = 1e-13;
  return p;
}

class OscillatorTest : public ::testing::TestWithParam<NewmarkSolver>
{
};

TEST_P(OscillatorTest, PeriodAndEnergy)
{
  const double m = 0.02;
  const double k = 8.0;
  const double omega = std::sqrt(k / m);
  const double period = 2.0 * Pi / omega;
  MassSpringSystem system;
  OneSpring(system, m, k);
  NewmarkIntegrator integrator;
  ASSERT_EQ(integrator.Setup(system, Exact(period / 200.0, GetParam())), "");
  const double amplitude = 0.1;
  integrator.SetState(
    { 0, 0, 0, amplitude, 0, 0 }, std::vector<double>(6, 0.0), { 0, 0, 0, -k * amplitude / m, 0, 0 }, 0.0);
  const auto energy = [&] {
    const double u = integrator.Displacement()[3];
    const double v = integrator.Velocity()[3];
    return 0.5 * m * v * v + 0.5 * k * u * u;
  };
  const double e0 = energy();
  EXPECT_NEAR(system.SpringEnergy(integrator.Displacement().data()), e0, 1e-15);
  double maxDrift = 0.0;
  std::vector<double> upCrossings;
  double previous = integrator.Displacement()[3];
  for (int s = 0; s < 1000; ++s)
  {
    ASSERT_EQ(integrator.Step(std::vector<double>(6, 0.0)), "");
    maxDrift = std::max(maxDrift, std::abs(energy() - e0) / e0);
    const double u = integrator.Displacement()[3];
    if (previous < 0.0 && u >= 0.0)
    {
      const double t = integrator.Time() - integrator.Parameters().timeStep * u / (u - previous);
      upCrossings.push_back(t);
    }
    previous = u;
    EXPECT_EQ(integrator.Displacement()[0], 0.0); // the fixed node
  }
  EXPECT_LT(maxDrift, 1e-6) << "average-acceleration Newmark conserves a linear system's energy";
  ASSERT_GE(upCrossings.size(), 4u);
  const double measured = (upCrossings.back() - upCrossings.front()) / static_cast<double>(upCrossings.size() - 1);
  EXPECT_NEAR(measured / period, 1.0, 0.01);
  EXPECT_NEAR(measured / period, 1.0 + std::pow(omega * integrator.Parameters().timeStep, 2) / 12.0, 1e-4)
    << "the trapezoidal rule's known period elongation";
}

INSTANTIATE_TEST_SUITE_P(
  Solvers, OscillatorTest, ::testing::Values(NewmarkSolver::Cholesky, NewmarkSolver::ConjugateGradient));

TEST(NewmarkIntegrator, RayleighDampingDecayRate)
{
  // Modal damping ratio zeta = alpha/(2 omega) + beta omega/2: the amplitude decays as exp(-zeta omega t).
  const double m = 0.01;
  const double k = 1.0;
  const double omega = std::sqrt(k / m);
  const double alpha = 0.4;
  const double beta = 0.002;
  const double rate = 0.5 * alpha + 0.5 * beta * omega * omega;
  MassSpringSystem system;
  OneSpring(system, m, k);
  NewmarkParameters p = Exact(2.0 * Pi / omega / 400.0);
  p.rayleighMass = alpha;
  p.rayleighStiffness = beta;
  NewmarkIntegrator integrator;
  ASSERT_EQ(integrator.Setup(system, p), "");
  integrator.SetState({ 0, 0, 0, 0.05, 0, 0 }, std::vector<double>(6, 0.0), { 0, 0, 0, -k * 0.05 / m, 0, 0 }, 0.0);
  // Peaks of the displacement.
  std::vector<std::pair<double, double>> peaks;
  double u2 = 0.0;
  double u1 = integrator.Displacement()[3];
  for (int s = 0; s < 4000; ++s)
  {
    ASSERT_EQ(integrator.Step(std::vector<double>(6, 0.0)), "");
    const double u = integrator.Displacement()[3];
    if (s > 0 && u1 > u2 && u1 >= u)
    {
      peaks.emplace_back(integrator.Time() - p.timeStep, u1);
    }
    u2 = u1;
    u1 = u;
  }
  ASSERT_GE(peaks.size(), 5u);
  const double measured =
    std::log(peaks.front().second / peaks.back().second) / (peaks.back().first - peaks.front().first);
  EXPECT_NEAR(measured / rate, 1.0, 0.01) << "measured " << measured << " predicted " << rate;
}

TEST(NewmarkIntegrator, HangingChainStatics)
{
  // N masses hanging from a fixed node: spring i carries the weight of the masses below it.
  const int count = 6;
  const double m = 0.05;
  const double k = 40.0;
  const double g = 981.0;
  MassSpringSystem system;
  for (int i = 0; i <= count; ++i)
  {
    system.AddNode(Eigen::Vector3d(0.0, 0.0, -1.0 * i), i == 0 ? 0.0 : m, i == 0);
  }
  for (int i = 0; i < count; ++i)
  {
    system.AddSpring(i, i + 1, k);
  }
  ASSERT_EQ(system.Finalize(), "");
  NewmarkParameters p = Exact(0.01);
  p.rayleighMass = 30.0; // heavily damped: settles
  NewmarkIntegrator integrator;
  ASSERT_EQ(integrator.Setup(system, p), "");
  std::vector<double> force(3 * (count + 1), 0.0);
  for (int i = 1; i <= count; ++i)
  {
    force[3 * i + 2] = -m * g;
  }
  for (int s = 0; s < 3000; ++s)
  {
    ASSERT_EQ(integrator.Step(force), "");
  }
  double expected = 0.0;
  for (int i = 1; i <= count; ++i)
  {
    expected -= (count - i + 1) * m * g / k; // the stretch of spring i
    EXPECT_NEAR(integrator.Displacement()[3 * i + 2], expected, 1e-7 * std::abs(expected)) << "node " << i;
    EXPECT_NEAR(integrator.Displacement()[3 * i], 0.0, 1e-12);
  }
}

TEST(NewmarkIntegrator, SecondOrderInTimeStep)
{
  // A swinging elastic pendulum (nonlinear): the tip at t = 1 s converges at second order in dt.
  const auto tipAt = [](double dt) {
    MassSpringSystem system;
    system.AddNode(Eigen::Vector3d::Zero(), 0.0, true);
    system.AddNode(Eigen::Vector3d(1.0, 0.0, 0.0), 0.1);
    system.AddSpring(0, 1, 50.0);
    EXPECT_EQ(system.Finalize(), "");
    NewmarkIntegrator integrator;
    EXPECT_EQ(integrator.Setup(system, Exact(dt)), "");
    const std::vector<double> force = { 0, 0, 0, 0, 0, -0.1 * 9.81 };
    // From rest with the consistent initial acceleration M^-1 f (starting from a = 0 instead, as VegaFEM does,
    // makes the scheme first order).
    integrator.SetState(std::vector<double>(6, 0.0), std::vector<double>(6, 0.0), { 0, 0, 0, 0, 0, -9.81 }, 0.0);
    const int steps = static_cast<int>(std::lround(1.0 / dt));
    for (int s = 0; s < steps; ++s)
    {
      EXPECT_EQ(integrator.Step(force), "");
    }
    const std::vector<double>& q = integrator.Displacement();
    return Eigen::Vector3d(q[3], q[4], q[5]);
  };
  const Eigen::Vector3d x1 = tipAt(1.0 / 100.0);
  const Eigen::Vector3d x2 = tipAt(1.0 / 200.0);
  const Eigen::Vector3d x4 = tipAt(1.0 / 400.0);
  const Eigen::Vector3d x8 = tipAt(1.0 / 800.0);
  const double d1 = (x1 - x2).norm();
  const double d2 = (x2 - x4).norm();
  const double d3 = (x4 - x8).norm();
  EXPECT_GT(x8.norm(), 0.05) << "the pendulum moved";
  EXPECT_LT(d2, d1);
  EXPECT_LT(d3, d2);
  EXPECT_NEAR(d1 / d2, 4.0, 0.6) << d1 << " " << d2;
  EXPECT_NEAR(d2 / d3, 4.0, 0.4) << d2 << " " << d3;
}

/// Options of PlateCorner beyond the plate's size.
struct PlateParameters
{
  double cgTolerance = 1e-6;
  bool extrapolate = true;
  bool interleaved = false;          ///< number the nodes (j, i, k) with k fastest instead of layer by layer
  long long* cgIterations = nullptr; ///< receives the CG iterations of the run
};

/// The wilting_plate problem (see benchmarks/wilting_plate.cpp).
Eigen::Vector3d PlateCorner(
  int nx, int ny, int steps, NewmarkSolver solver, int threads, const PlateParameters& options = PlateParameters())
{
  const auto node = [&](int i, int j, int k) {
    return options.interleaved ? (j * (nx + 1) + i) * 2 + k : (k * (ny + 1) + j) * (nx + 1) + i;
  };
  MassSpringSystem system;
  std::vector<Eigen::Vector3d> positions(static_cast<std::size_t>(2 * (nx + 1) * (ny + 1)));
  for (int k = 0; k < 2; ++k)
  {
    for (int j = 0; j <= ny; ++j)
    {
      for (int i = 0; i <= nx; ++i)
      {
        positions[static_cast<std::size_t>(node(i, j, k))] = Eigen::Vector3d(0.5 * i, 0.5 * j, 0.5 * k);
      }
    }
  }
  for (const Eigen::Vector3d& x : positions)
  {
    system.AddNode(x, 0.001, x[0] == 0.0);
  }
  std::set<std::pair<int, int>> pairs;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      std::vector<int> c;
      for (int k = 0; k < 2; ++k)
      {
        for (int dj = 0; dj < 2; ++dj)
        {
          for (int di = 0; di < 2; ++di)
          {
            c.push_back(node(i + di, j + dj, k));
          }
        }
      }
      for (int a = 0; a < 8; ++a)
      {
        for (int b = a + 1; b < 8; ++b)
        {
          pairs.insert(std::minmax(c[static_cast<std::size_t>(a)], c[static_cast<std::size_t>(b)]));
        }
      }
    }
  }
  for (const auto& pair : pairs)
  {
    system.AddSpring(pair.first, pair.second, 100.0);
  }
  EXPECT_EQ(system.Finalize(), "");
  std::vector<double> force(3 * system.NodeCount(), 0.0);
  for (std::size_t i = 0; i < system.NodeCount(); ++i)
  {
    force[3 * i + 2] = system.IsFixed(i) ? 0.0 : -0.981;
  }
  NewmarkParameters p;
  p.rayleighMass = 0.01;
  p.rayleighStiffness = 0.001;
  p.compressionClamp = false;
  p.solver = solver;
  p.threads = threads;
  p.cgTolerance = options.cgTolerance;
  p.extrapolateWarmStart = options.extrapolate;
  NewmarkIntegrator integrator;
  EXPECT_EQ(integrator.Setup(system, p), "");
  for (int s = 0; s < steps; ++s)
  {
    EXPECT_EQ(integrator.Step(force), "");
  }
  if (options.cgIterations)
  {
    *options.cgIterations = integrator.Timings().cgIterations;
  }
  const std::size_t corner = static_cast<std::size_t>(node(nx, ny, 0));
  return Eigen::Vector3d(integrator.Displacement()[3 * corner], integrator.Displacement()[3 * corner + 1],
    integrator.Displacement()[3 * corner + 2]);
}

TEST(NewmarkIntegrator, MatchesVegaFEMPlate)
{
  // VegaFEM 4.0 (massSpringSystem + ImplicitNewmarkSparse), 22 x 22 x 1 plate, t = 1 s: the free corner node.
  const Eigen::Vector3d vega(-18.0457, -0.2439, -8.2899);
  const Eigen::Vector3d ours = PlateCorner(22, 22, 240, NewmarkSolver::ConjugateGradient, 2);
  EXPECT_LT((ours - vega).cwiseAbs().maxCoeff(), 1e-3) << ours.transpose();
}

TEST(NewmarkIntegrator, MatchesVegaFEMPlateAtTheBenchmarksLooserTolerance)
{
  // wilting_plate's --cg-tolerance 5e-6 (fewer CG iterations) still agrees with VegaFEM to 1e-3 cm, and is further
  // from the exact (Cholesky) solve than the default 1e-6: the tolerance is what limits the agreement.
  const Eigen::Vector3d vega(-18.0457, -0.2439, -8.2899);
  PlateParameters loose;
  loose.cgTolerance = 5e-6;
  long long looseIterations = 0;
  loose.cgIterations = &looseIterations;
  const Eigen::Vector3d ours = PlateCorner(22, 22, 240, NewmarkSolver::ConjugateGradient, 2, loose);
  EXPECT_LT((ours - vega).cwiseAbs().maxCoeff(), 1e-3) << ours.transpose();
  PlateParameters tight;
  long long tightIterations = 0;
  tight.cgIterations = &tightIterations;
  const Eigen::Vector3d exact = PlateCorner(22, 22, 240, NewmarkSolver::Cholesky, 1);
  const Eigen::Vector3d ref = PlateCorner(22, 22, 240, NewmarkSolver::ConjugateGradient, 2, tight);
  EXPECT_LT((ref - exact).norm(), (ours - exact).norm());
  EXPECT_LT(looseIterations, tightIterations);
}

TEST(NewmarkIntegrator, ExtrapolatedWarmStartSavesIterationsNotAccuracy)
{
  // Starting CG from 2 d_{s-1} - d_{s-2} instead of d_{s-1}: fewer iterations, the same answer to the tolerance.
  long long withIterations = 0;
  long long withoutIterations = 0;
  PlateParameters with;
  with.cgIterations = &withIterations;
  PlateParameters without;
  without.extrapolate = false;
  without.cgIterations = &withoutIterations;
  const Eigen::Vector3d a = PlateCorner(22, 22, 120, NewmarkSolver::ConjugateGradient, 1, with);
  const Eigen::Vector3d b = PlateCorner(22, 22, 120, NewmarkSolver::ConjugateGradient, 1, without);
  const Eigen::Vector3d exact = PlateCorner(22, 22, 120, NewmarkSolver::Cholesky, 1);
  EXPECT_LT(withIterations, withoutIterations);
  EXPECT_LT((a - exact).norm(), 5e-4) << a.transpose() << " / " << exact.transpose();
  EXPECT_LT((b - exact).norm(), 5e-4) << b.transpose() << " / " << exact.transpose();
}

TEST(NewmarkIntegrator, NodeNumberingDoesNotChangeTheResult)
{
  // The solver orders nodes and springs by their rest positions, so two numberings of the same plate give the
  // same bits, on the CG path (1 and 2 threads) and the Cholesky path.
  PlateParameters interleaved;
  interleaved.interleaved = true;
  for (int threads : { 1, 2 })
  {
    EXPECT_EQ(PlateCorner(40, 30, 8, NewmarkSolver::ConjugateGradient, threads),
      PlateCorner(40, 30, 8, NewmarkSolver::ConjugateGradient, threads, interleaved));
  }
  EXPECT_EQ(
    PlateCorner(6, 5, 20, NewmarkSolver::Cholesky, 1), PlateCorner(6, 5, 20, NewmarkSolver::Cholesky, 1, interleaved));
}

TEST(NewmarkIntegrator, SolversAgreeAndThreadsAreBitIdentical)
{
  const Eigen::Vector3d cholesky = PlateCorner(6, 5, 60, NewmarkSolver::Cholesky, 1);
  const Eigen::Vector3d cg = PlateCorner(6, 5, 60, NewmarkSolver::ConjugateGradient, 1);
  EXPECT_LT((cholesky - cg).norm(), 1e-4) << cholesky.transpose() << " / " << cg.transpose();
  EXPECT_GT(cholesky.norm(), 0.1);
  // A plate large enough for the threaded paths (more than 2048 nodes): 1, 2 and 3 threads, same bits.
  const Eigen::Vector3d one = PlateCorner(40, 30, 8, NewmarkSolver::ConjugateGradient, 1);
  const Eigen::Vector3d two = PlateCorner(40, 30, 8, NewmarkSolver::ConjugateGradient, 2);
  const Eigen::Vector3d three = PlateCorner(40, 30, 8, NewmarkSolver::ConjugateGradient, 3);
  EXPECT_EQ(one, two);
  EXPECT_EQ(one, three);
}

TEST(NewmarkIntegrator, TangentStiffnessIsTheForceDerivative)
{
  // Finite differences of R(u) against the springs' tangent blocks, stretched and compressed, clamp off and on.
  MassSpringSystem system;
  system.AddNode(Eigen::Vector3d(0.1, -0.2, 0.3), 1.0);
  system.AddNode(Eigen::Vector3d(1.0, 0.5, -0.4), 1.0);
  system.AddSpring(0, 1, 7.0);
  ASSERT_EQ(system.Finalize(), "");
  plantmorph::MassSpringThreads threads(1);
  for (double scale : { 1.3, 0.6 })
  {
    const Eigen::Vector3d d = system.RestPositions()[1] - system.RestPositions()[0];
    std::vector<double> u = { 0, 0, 0, (scale - 1.0) * d[0] + 0.05, (scale - 1.0) * d[1], (scale - 1.0) * d[2] };
    double force[3];
    double tangent[6];
    system.EvaluateSprings(u.data(), false, force, tangent, threads);
    std::vector<double> r0(6);
    std::vector<double> r1(6);
    for (int c = 0; c < 3; ++c)
    {
      const double h = 1e-6;
      std::vector<double> up = u;
      std::vector<double> down = u;
      up[3 + static_cast<std::size_t>(c)] += h;
      down[3 + static_cast<std::size_t>(c)] -= h;
      system.InternalForce(up.data(), r1.data());
      system.InternalForce(down.data(), r0.data());
      const int index[3][3] = { { 0, 1, 2 }, { 1, 3, 4 }, { 2, 4, 5 } };
      for (int row = 0; row < 3; ++row)
      {
        const double derivative =
          (r1[3 + static_cast<std::size_t>(row)] - r0[3 + static_cast<std::size_t>(row)]) / (2 * h);
        EXPECT_NEAR(derivative, tangent[index[row][c]], 1e-6);
      }
    }
    double clamped[6];
    system.EvaluateSprings(u.data(), true, force, clamped, threads);
    const Eigen::Vector3d z = d * scale + Eigen::Vector3d(0.05, 0, 0);
    if (z.norm() < d.norm())
    {
      // Compressed: the clamp leaves only k n n^T, whose trace is k.
      EXPECT_NEAR(clamped[0] + clamped[3] + clamped[5], 7.0, 1e-12);
    }
  }
}

TEST(NewmarkIntegrator, BadInput)
{
  MassSpringSystem system;
  OneSpring(system, 1.0, 1.0);
  NewmarkIntegrator integrator;
  NewmarkParameters p;
  p.timeStep = -1.0;
  EXPECT_NE(integrator.Setup(system, p).find("TimeStep"), std::string::npos);
  p.timeStep = 0.01;
  p.newmarkBeta = 0.7;
  EXPECT_NE(integrator.Setup(system, p).find("NewmarkBeta"), std::string::npos);
  MassSpringSystem broken;
  broken.AddNode(Eigen::Vector3d::Zero(), 1.0);
  broken.AddNode(Eigen::Vector3d::Zero(), 1.0);
  broken.AddSpring(0, 1, 1.0);
  EXPECT_NE(broken.Finalize(), ""); // zero rest length
  MassSpringSystem massless;
  massless.AddNode(Eigen::Vector3d::Zero(), 0.0);
  EXPECT_NE(massless.Finalize(), "");
}

} // namespace
