// SPDX-License-Identifier: GPL-3.0-or-later
#include "NewmarkIntegrator.h"

#include <plantmorph/RangeError.h>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <array>
#include <chrono>
#include <functional>
#include <cmath>
#include <sstream>
#include <utility>

namespace plantmorph
{

namespace
{
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since)
{
  return std::chrono::duration<double>(Clock::now() - since).count();
}

/// y += s * B x for a symmetric 3x3 block B (xx, xy, xz, yy, yz, zz).
inline void AddBlockTimes(const double* b, const double* x, double s, double* y)
{
  y[0] += s * (b[0] * x[0] + b[1] * x[1] + b[2] * x[2]);
  y[1] += s * (b[1] * x[0] + b[3] * x[1] + b[4] * x[2]);
  y[2] += s * (b[2] * x[0] + b[4] * x[1] + b[5] * x[2]);
}

/// The inverse of a symmetric 3x3 block; zero when it is singular.
void InvertBlock(const double* b, double* inv)
{
  const double c00 = b[3] * b[5] - b[4] * b[4];
  const double c01 = b[2] * b[4] - b[1] * b[5];
  const double c02 = b[1] * b[4] - b[2] * b[3];
  const double det = b[0] * c00 + b[1] * c01 + b[2] * c02;
  if (!(std::abs(det) > 0.0) || !std::isfinite(det))
  {
    std::fill(inv, inv + 6, 0.0);
    return;
  }
  const double s = 1.0 / det;
  inv[0] = c00 * s;
  inv[1] = c01 * s;
  inv[2] = c02 * s;
  inv[3] = (b[0] * b[5] - b[2] * b[2]) * s;
  inv[4] = (b[1] * b[2] - b[0] * b[4]) * s;
  inv[5] = (b[0] * b[3] - b[1] * b[1]) * s;
}

/// Index of the lower-triangle entry of a symmetric 3x3 block in the 6-value layout.
inline int SymIndex(int r, int c)
{
  static const int table[3][3] = { { 0, 1, 2 }, { 1, 3, 4 }, { 2, 4, 5 } };
  return table[r][c];
}

/// The sum of fn(begin, end, partial) over MassSpringThreads::ReduceChunks fixed ranges of [0, n), K sums at once,
/// each chunk's partial sums added in chunk order: bit-identical on any number of threads. fn adds into partial.
template <std::size_t K, class Function>
std::array<double, K> ChunkedSum(MassSpringThreads& threads, std::size_t n, const Function& fn)
{
  constexpr std::size_t chunks = MassSpringThreads::ReduceChunks;
  std::array<std::array<double, K>, chunks> partial{};
  const std::function<void(std::size_t)> task = [&](std::size_t c) {
    const std::size_t begin = n * c / chunks;
    const std::size_t end = n * (c + 1) / chunks;
    if (begin < end)
    {
      fn(begin, end, partial[c].data());
    }
  };
  if (threads.Threads() == 1 || n < 2048)
  {
    for (std::size_t c = 0; c < chunks; ++c)
    {
      task(c);
    }
  }
  else
  {
    threads.Tasks(chunks, task);
  }
  std::array<double, K> sum{};
  for (const std::array<double, K>& piece : partial)
  {
    for (std::size_t k = 0; k < K; ++k)
    {
      sum[k] += piece[k];
    }
  }
  return sum;
}
} // namespace

struct NewmarkIntegrator::CholeskyData
{
  std::vector<int> freeIndex;         // per node, -1 if fixed
  Eigen::SparseMatrix<double> matrix; // lower triangle, column-major
  std::vector<int> nodeEntry;         // 6 per node (lower triangle of the diagonal block), value indices
  std::vector<int> springEntry;       // 9 per compact spring (row b, column a), -1 when an end is fixed
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
  Eigen::VectorXd rhs, solution;

  /// The pattern of the free degrees of freedom's lower triangle (nodes by solver position), built and analysed
  /// once.
  void Analyse(const std::vector<char>& nodeFixed, const std::vector<SpringEnds>& ends);

private:
  /// Numbers the free nodes; their count.
  int NumberFreeNodes(const std::vector<char>& nodeFixed);
  /// The matrix's pattern: every free node's diagonal block and every free spring's off-diagonal block.
  void BuildPattern(int count, const std::vector<SpringEnds>& ends);
  /// nodeEntry and springEntry: where each block's entries sit in the matrix's values.
  void LocateEntries(const std::vector<SpringEnds>& ends);
};

int NewmarkIntegrator::CholeskyData::NumberFreeNodes(const std::vector<char>& nodeFixed)
{
  const std::size_t n = nodeFixed.size();
  this->freeIndex.assign(n, -1); // by solver position
  int count = 0;
  for (std::size_t p = 0; p < n; ++p)
  {
    if (!nodeFixed[p])
    {
      this->freeIndex[p] = count++;
    }
  }
  return count;
}

void NewmarkIntegrator::CholeskyData::BuildPattern(int count, const std::vector<SpringEnds>& ends)
{
  const std::size_t n = this->freeIndex.size();
  const std::size_t m = ends.size();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(6 * static_cast<std::size_t>(count) + 9 * m);
  for (std::size_t i = 0; i < n; ++i)
  {
    const int f = this->freeIndex[i];
    if (f < 0)
    {
      continue;
    }
    for (int r = 0; r < 3; ++r)
    {
      for (int c = 0; c <= r; ++c)
      {
        triplets.emplace_back(3 * f + r, 3 * f + c, 1.0);
      }
    }
  }
  for (std::size_t e = 0; e < m; ++e)
  {
    // The block is symmetric: its lower-triangle copy sits in the row of the later free index.
    const int f0 = this->freeIndex[static_cast<std::size_t>(ends[e].a)];
    const int f1 = this->freeIndex[static_cast<std::size_t>(ends[e].b)];
    if (f0 < 0 || f1 < 0)
    {
      continue;
    }
    const int fa = std::min(f0, f1);
    const int fb = std::max(f0, f1);
    for (int r = 0; r < 3; ++r)
    {
      for (int c = 0; c < 3; ++c)
      {
        triplets.emplace_back(3 * fb + r, 3 * fa + c, 1.0);
      }
    }
  }
  this->matrix.resize(3 * count, 3 * count);
  this->matrix.setFromTriplets(triplets.begin(), triplets.end());
  this->matrix.makeCompressed();
}

void NewmarkIntegrator::CholeskyData::LocateEntries(const std::vector<SpringEnds>& ends)
{
  const std::size_t n = this->freeIndex.size();
  const std::size_t m = ends.size();
  const double* base = this->matrix.valuePtr();
  this->nodeEntry.assign(6 * n, -1);
  this->springEntry.assign(9 * m, -1);
  for (std::size_t i = 0; i < n; ++i)
  {
    const int f = this->freeIndex[i];
    if (f < 0)
    {
      continue;
    }
    for (int r = 0; r < 3; ++r)
    {
      for (int c = 0; c <= r; ++c)
      {
        this->nodeEntry[6 * i + static_cast<std::size_t>(SymIndex(r, c))] =
          static_cast<int>(&this->matrix.coeffRef(3 * f + r, 3 * f + c) - base);
      }
    }
  }
  for (std::size_t e = 0; e < m; ++e)
  {
    // The block is symmetric: its lower-triangle copy sits in the row of the later free index.
    const int f0 = this->freeIndex[static_cast<std::size_t>(ends[e].a)];
    const int f1 = this->freeIndex[static_cast<std::size_t>(ends[e].b)];
    if (f0 < 0 || f1 < 0)
    {
      continue;
    }
    const int fa = std::min(f0, f1);
    const int fb = std::max(f0, f1);
    for (int r = 0; r < 3; ++r)
    {
      for (int c = 0; c < 3; ++c)
      {
        this->springEntry[9 * e + static_cast<std::size_t>(3 * r + c)] =
          static_cast<int>(&this->matrix.coeffRef(3 * fb + r, 3 * fa + c) - base);
      }
    }
  }
}

void NewmarkIntegrator::CholeskyData::Analyse(const std::vector<char>& nodeFixed, const std::vector<SpringEnds>& ends)
{
  const int count = this->NumberFreeNodes(nodeFixed);
  this->BuildPattern(count, ends);
  this->LocateEntries(ends);
  this->ldlt.analyzePattern(this->matrix);
  this->rhs.resize(3 * count);
  this->solution.resize(3 * count);
}

std::string ValidateNewmark(const NewmarkParameters& p)
{
  std::ostringstream message;
  if (!(p.timeStep > 0.0) || !std::isfinite(p.timeStep))
  {
    message << OutOfRange("TimeStep", p.timeStep, "(0, inf)");
  }
  else if (!(p.newmarkBeta > 0.0 && p.newmarkBeta <= 0.5))
  {
    message << OutOfRange("NewmarkBeta", p.newmarkBeta, "(0, 0.5]");
  }
  else if (!(p.newmarkGamma >= 0.5 && p.newmarkGamma <= 1.0))
  {
    message << OutOfRange("NewmarkGamma", p.newmarkGamma, "[0.5, 1]");
  }
  else if (!(p.rayleighMass >= 0.0) || !std::isfinite(p.rayleighMass))
  {
    message << OutOfRange("RayleighMass (alpha)", p.rayleighMass, "[0, inf)");
  }
  else if (!(p.rayleighStiffness >= 0.0) || !std::isfinite(p.rayleighStiffness))
  {
    message << OutOfRange("RayleighStiffness (beta)", p.rayleighStiffness, "[0, inf)");
  }
  else if (p.maxIterations < 1 || p.maxIterations > 100)
  {
    message << OutOfRange("NewtonIterations", p.maxIterations, "[1, 100]");
  }
  else if (!(p.newtonTolerance >= 0.0 && p.newtonTolerance < 1.0))
  {
    message << OutOfRange("NewtonTolerance", p.newtonTolerance, "[0, 1)");
  }
  else if (!(p.cgTolerance > 0.0 && p.cgTolerance < 1.0))
  {
    message << OutOfRange("CGTolerance", p.cgTolerance, "(0, 1)");
  }
  else if (p.cgMaxIterations < 1)
  {
    message << OutOfRange("CGMaxIterations", p.cgMaxIterations, "[1, inf)");
  }
  return message.str();
}

NewmarkIntegrator::NewmarkIntegrator() = default;
NewmarkIntegrator::~NewmarkIntegrator() = default;

std::string NewmarkIntegrator::Setup(const MassSpringSystem& system, const NewmarkParameters& parameters)
{
  const std::string error = ValidateNewmark(parameters);
  if (!error.empty())
  {
    return error;
  }
  this->System = &system;
  this->Params = parameters;
  const double b = parameters.newmarkBeta;
  const double g = parameters.newmarkGamma;
  const double dt = parameters.timeStep;
  this->Alpha[1] = 1.0 / (b * dt * dt);
  this->Alpha[2] = 1.0 / (b * dt);
  this->Alpha[3] = (1.0 - 2.0 * b) / (2.0 * b);
  this->Alpha[4] = g / (b * dt);
  this->Alpha[5] = 1.0 - g / b;
  this->Alpha[6] = (1.0 - g / (2.0 * b)) * dt;
  if (!this->Threads || this->Threads->Threads() != std::max(1, parameters.threads))
  {
    this->Threads = std::make_unique<MassSpringThreads>(parameters.threads);
  }
  const std::size_t n = system.NodeCount();
  std::size_t freeNodes = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    freeNodes += system.IsFixed(i) ? 0 : 1;
  }
  this->Solver = parameters.solver;
  if (this->Solver == NewmarkSolver::Auto)
  {
    this->Solver = freeNodes <= AutoCholeskyMaxNodes ? NewmarkSolver::Cholesky : NewmarkSolver::ConjugateGradient;
  }
  // The solver's own node order (position p holds system node Order[p]): the rest positions sorted along the
  // longest axis, then the middle one, then the shortest, so that the nodes joined by springs are close in memory
  // (a voxel model numbered layer by layer has a layer's worth of nodes between a node and the one above it). The
  // springs sorted by their ends' positions; each node's row: its springs in that order. Every per-node sum is a
  // gather over the row in a fixed order, whatever the thread count.
  this->OrderNodes(system);
  this->OrderSprings(system);
  this->BuildRows();
  this->ResetWorkspace();
  if (this->Solver != NewmarkSolver::ConjugateGradient)
  {
    // The pattern of the free degrees of freedom's lower triangle, built and analysed once.
    auto chol = std::make_unique<CholeskyData>();
    chol->Analyse(this->NodeFixed, this->Ends);
    this->Chol = std::move(chol);
  }
  this->Timing = NewmarkTimings();
  this->Reset();
  return std::string();
}

void NewmarkIntegrator::OrderNodes(const MassSpringSystem& system)
{
  const std::size_t n = system.NodeCount();
  const std::vector<Eigen::Vector3d>& rest = system.RestPositions();
  Eigen::Vector3d low = Eigen::Vector3d::Zero();
  Eigen::Vector3d high = Eigen::Vector3d::Zero();
  if (n > 0)
  {
    low = high = rest[0];
  }
  for (const Eigen::Vector3d& x : rest)
  {
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
  }
  const Eigen::Vector3d extent = high - low;
  std::array<int, 3> axes = { 0, 1, 2 };
  std::stable_sort(axes.begin(), axes.end(), [&](int u, int w) { return extent[u] > extent[w]; });
  this->Order.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    this->Order[i] = static_cast<int>(i);
  }
  std::sort(this->Order.begin(), this->Order.end(), [&](int u, int w) {
    const Eigen::Vector3d& xu = rest[static_cast<std::size_t>(u)];
    const Eigen::Vector3d& xw = rest[static_cast<std::size_t>(w)];
    for (int axis : axes)
    {
      if (xu[axis] != xw[axis])
      {
        return xu[axis] < xw[axis];
      }
    }
    return u < w;
  });
  this->Position.resize(n);
  this->NodeMass.resize(n);
  this->NodeFixed.resize(n);
  this->RestSolver.resize(n);
  for (std::size_t p = 0; p < n; ++p)
  {
    const std::size_t i = static_cast<std::size_t>(this->Order[p]);
    this->Position[i] = static_cast<int>(p);
    this->NodeMass[p] = system.Masses()[i];
    this->NodeFixed[p] = system.IsFixed(i) ? 1 : 0;
    this->RestSolver[p] = system.RestPositions()[i];
  }
}

void NewmarkIntegrator::OrderSprings(const MassSpringSystem& system)
{
  const std::size_t m = system.SpringCount();
  const std::vector<MassSpringSpring>& springs = system.Springs();
  std::vector<int> springOrder(m);
  for (std::size_t e = 0; e < m; ++e)
  {
    springOrder[e] = static_cast<int>(e);
  }
  const auto lowHigh = [&](int e) {
    const int pa = this->Position[static_cast<std::size_t>(springs[static_cast<std::size_t>(e)].a)];
    const int pb = this->Position[static_cast<std::size_t>(springs[static_cast<std::size_t>(e)].b)];
    return std::make_pair(std::min(pa, pb), std::max(pa, pb));
  };
  std::sort(springOrder.begin(), springOrder.end(), [&](int u, int w) { return lowHigh(u) < lowHigh(w); });
  this->SystemSpring = springOrder;
  this->Ends.resize(m);
  this->Blocks.assign(m, SpringBlock{ 0.0, { 0.0, 0.0, 0.0 } });
  this->Material.resize(m);
  this->SpringTerm.assign(3 * m, 0.0);
  for (std::size_t e = 0; e < m; ++e)
  {
    const MassSpringSpring& spring = springs[static_cast<std::size_t>(springOrder[e])];
    // The spring's a end is its end earlier in the solver's order (the physics is symmetric in the two ends), so
    // the arithmetic depends on the geometry only, not on the system's numbering.
    const std::pair<int, int> ends = lowHigh(springOrder[e]);
    this->Ends[e] = { ends.first, ends.second };
    this->Material[e] = { spring.stiffness, spring.damping, spring.restLength };
  }
}

void NewmarkIntegrator::BuildRows()
{
  const std::size_t n = this->Order.size();
  const std::size_t m = this->Ends.size();
  this->RowOffsets.assign(n + 1, 0);
  for (const SpringEnds& ends : this->Ends)
  {
    ++this->RowOffsets[static_cast<std::size_t>(ends.a) + 1];
    ++this->RowOffsets[static_cast<std::size_t>(ends.b) + 1];
  }
  for (std::size_t p = 0; p < n; ++p)
  {
    this->RowOffsets[p + 1] += this->RowOffsets[p];
  }
  this->Rows.resize(2 * m);
  this->RowSign.resize(2 * m);
  std::vector<int> fill(this->RowOffsets.begin(), this->RowOffsets.end() - 1);
  for (std::size_t e = 0; e < m; ++e)
  {
    const int pa = this->Ends[e].a;
    const int pb = this->Ends[e].b;
    const std::size_t ka = static_cast<std::size_t>(fill[static_cast<std::size_t>(pa)]++);
    const std::size_t kb = static_cast<std::size_t>(fill[static_cast<std::size_t>(pb)]++);
    this->Rows[ka] = { pb, static_cast<int>(e) };
    this->RowSign[ka] = -1; // g_e is -R on the spring's a end
    this->Rows[kb] = { pa, static_cast<int>(e) };
    this->RowSign[kb] = 1;
  }
}

void NewmarkIntegrator::ResetWorkspace()
{
  const std::size_t n = this->Order.size();
  this->NodeBlock.assign(6 * n, 0.0);
  this->Rhs.assign(3 * n, 0.0);
  this->Delta.assign(3 * n, 0.0);
  this->PreviousDelta.assign(3 * n, 0.0);
  this->OlderDelta.assign(3 * n, 0.0);
  this->WarmSteps = 0;
  this->Chol.reset();
  this->CGr.clear();
  this->CGz.clear();
  this->CGd.clear();
  this->CGq.clear();
  this->CGw.clear();
  this->Precond.clear();
  if (this->Solver == NewmarkSolver::ConjugateGradient)
  {
    this->CGr.assign(3 * n, 0.0);
    this->CGz.assign(3 * n, 0.0);
    this->CGd.assign(3 * n, 0.0);
    this->CGq.assign(3 * n, 0.0);
    this->CGw.assign(3 * n, 0.0);
    this->Precond.assign(6 * n, 0.0);
  }
}

void NewmarkIntegrator::Reset()
{
  const std::size_t n3 = 3 * this->System->NodeCount();
  this->Q.assign(n3, 0.0);
  this->V.assign(n3, 0.0);
  this->A.assign(n3, 0.0);
  this->SolverQ.assign(n3, 0.0);
  this->SolverV.assign(n3, 0.0);
  this->SolverA.assign(n3, 0.0);
  this->PreviousDelta.assign(n3, 0.0);
  this->OlderDelta.assign(n3, 0.0);
  this->WarmSteps = 0;
  this->CurrentTime = 0.0;
}

void NewmarkIntegrator::SetState(
  const std::vector<double>& q, const std::vector<double>& v, const std::vector<double>& a, double time)
{
  this->Q = q;
  this->V = v;
  this->A = a;
  const std::size_t n = this->System->NodeCount();
  this->SolverQ.assign(3 * n, 0.0);
  this->SolverV.assign(3 * n, 0.0);
  this->SolverA.assign(3 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t p = 3 * static_cast<std::size_t>(this->Position[i]);
    for (std::size_t c = 0; c < 3; ++c)
    {
      if (this->System->IsFixed(i))
      {
        this->Q[3 * i + c] = this->V[3 * i + c] = this->A[3 * i + c] = 0.0;
      }
      this->SolverQ[p + c] = this->Q[3 * i + c];
      this->SolverV[p + c] = this->V[3 * i + c];
      this->SolverA[p + c] = this->A[3 * i + c];
    }
  }
  std::fill(this->PreviousDelta.begin(), this->PreviousDelta.end(), 0.0);
  std::fill(this->OlderDelta.begin(), this->OlderDelta.end(), 0.0);
  this->WarmSteps = 0;
  this->CurrentTime = time;
}

void NewmarkIntegrator::Assemble(const std::vector<double>& force, double& residualNorm2)
{
  const MassSpringSystem& system = *this->System;
  MassSpringThreads& threads = *this->Threads;
  const double beta = this->Params.rayleighStiffness;
  const double alpha = this->Params.rayleighMass;
  const double a4 = this->Alpha[4];
  const double c1 = 1.0 + a4 * beta;
  const double c2 = this->Alpha[1] + a4 * alpha;
  const bool clamp = this->Params.compressionClamp;
  const double* masses = this->NodeMass.data();
  const char* fixed = this->NodeFixed.data();
  const int* order = this->Order.data();
  const double* v = this->SolverV.data();
  const double* q = this->SolverQ.data();
  const double* accel = this->SolverA.data();
  const double* f = force.data();
  const Eigen::Vector3d* rest = this->RestSolver.data();
  const SpringEnds* ends = this->Ends.data();
  const SpringMaterial* materials = this->Material.data();
  SpringBlock* blocks = this->Blocks.data();
  double* terms = this->SpringTerm.data();
  // Springs (each writes only its own records): the spring force f = k (l - L) n, the tangent
  // D = k [g I + (1 - g) n n^T] (g = 1 - L/l, clamped at 0 if asked), the system block c1 D + a4 c I = s I + t n n^T,
  // and the residual's g_e = f + (beta D + c I)(v_b - v_a), which is -R on a and +R on b.
  threads.For(this->Ends.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
    {
      SpringBlock& spring = blocks[e];
      const SpringMaterial& material = materials[e];
      const std::size_t ia = 3 * static_cast<std::size_t>(ends[e].a);
      const std::size_t ib = 3 * static_cast<std::size_t>(ends[e].b);
      const Eigen::Vector3d& xa = rest[ends[e].a];
      const Eigen::Vector3d& xb = rest[ends[e].b];
      const double z[3] = { xb[0] + q[ib] - xa[0] - q[ia], xb[1] + q[ib + 1] - xa[1] - q[ia + 1],
        xb[2] + q[ib + 2] - xa[2] - q[ia + 2] };
      const double length = std::sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
      const double k = material.stiffness;
      double g = 1.0;
      double magnitude = 0.0;
      double n[3] = { 0.0, 0.0, 0.0 };
      if (length > 0.0)
      {
        const double inv = 1.0 / length;
        n[0] = z[0] * inv;
        n[1] = z[1] * inv;
        n[2] = z[2] * inv;
        magnitude = k * (length - material.restLength);
        g = 1.0 - material.restLength * inv;
        if (clamp && g < 0.0)
        {
          g = 0.0;
        }
      }
      // t = c1 k (1 - g) = c1 k L / l >= 0 (1 - g is never clamped), so the block is s I + m m^T, m = sqrt(t) n.
      spring.s = c1 * k * g + a4 * material.damping;
      const double root = std::sqrt(c1 * k * (1.0 - g));
      spring.m[0] = root * n[0];
      spring.m[1] = root * n[1];
      spring.m[2] = root * n[2];
      const double dv[3] = { v[ib] - v[ia], v[ib + 1] - v[ia + 1], v[ib + 2] - v[ia + 2] };
      const double ndv = n[0] * dv[0] + n[1] * dv[1] + n[2] * dv[2];
      const double iso = beta * k * g + material.damping;
      const double along = magnitude + beta * k * (1.0 - g) * ndv;
      for (std::size_t c = 0; c < 3; ++c)
      {
        terms[3 * e + c] = along * n[c] + iso * dv[c];
      }
    }
  });
  // Nodes, in the solver's order (each gathers its row): r = M (accel + alpha vel) - f - sum_a g_e + sum_b g_e,
  // the diagonal block c2 m I + sum of the blocks; fixed nodes drop out; -r becomes the right-hand side; the
  // preconditioner for CG.
  const bool cg = this->Solver == NewmarkSolver::ConjugateGradient;
  const int* offsets = this->RowOffsets.data();
  const RowEntry* rows = this->Rows.data();
  const signed char* signs = this->RowSign.data();
  double* r = this->Rhs.data();
  double* diag = this->NodeBlock.data();
  double* precond = cg ? this->Precond.data() : nullptr;
  residualNorm2 = ChunkedSum<1>(threads, system.NodeCount(), [&](std::size_t begin, std::size_t end, double* sum) {
    for (std::size_t i = begin; i < end; ++i)
    {
      double* ri = r + 3 * i;
      double* d = diag + 6 * i;
      if (fixed[i])
      {
        ri[0] = ri[1] = ri[2] = 0.0;
        std::fill(d, d + 6, 0.0);
        if (cg)
        {
          std::fill(precond + 6 * i, precond + 6 * i + 6, 0.0);
        }
        continue;
      }
      const double m = masses[i];
      const std::size_t j = 3 * static_cast<std::size_t>(order[i]); // the system's node
      double res[3];
      for (std::size_t c = 0; c < 3; ++c)
      {
        res[c] = m * (accel[3 * i + c] + alpha * v[3 * i + c]) - f[j + c];
      }
      double block[6] = { c2 * m, 0.0, 0.0, c2 * m, 0.0, c2 * m };
      for (int k = offsets[i]; k < offsets[i + 1]; ++k)
      {
        const RowEntry& entry = rows[k];
        const SpringBlock& spring = blocks[entry.spring];
        const double* g = terms + 3 * static_cast<std::size_t>(entry.spring);
        const double sign = signs[k];
        res[0] += sign * g[0];
        res[1] += sign * g[1];
        res[2] += sign * g[2];
        const double* mv = spring.m;
        block[0] += spring.s + mv[0] * mv[0];
        block[1] += mv[0] * mv[1];
        block[2] += mv[0] * mv[2];
        block[3] += spring.s + mv[1] * mv[1];
        block[4] += mv[1] * mv[2];
        block[5] += spring.s + mv[2] * mv[2];
      }
      sum[0] += res[0] * res[0] + res[1] * res[1] + res[2] * res[2];
      ri[0] = -res[0];
      ri[1] = -res[1];
      ri[2] = -res[2];
      std::copy(block, block + 6, d);
      if (cg)
      {
        InvertBlock(d, precond + 6 * i);
      }
    }
  })[0];
}

void NewmarkIntegrator::MultiplyRow(std::size_t i, const double* x, double* y) const
{
  // (A x)_i = c2 m_i x_i + sum over the row's springs of the spring's block s I + m m^T on (x_i - x_j).
  const double cm = (this->Alpha[1] + this->Alpha[4] * this->Params.rayleighMass) * this->NodeMass[i];
  const double* xi = x + 3 * i;
  double y0 = cm * xi[0];
  double y1 = cm * xi[1];
  double y2 = cm * xi[2];
  const RowEntry* rows = this->Rows.data();
  const SpringBlock* blocks = this->Blocks.data();
  const int end = this->RowOffsets[i + 1];
  for (int k = this->RowOffsets[i]; k < end; ++k)
  {
    const SpringBlock& block = blocks[rows[k].spring];
    const double* xj = x + 3 * static_cast<std::size_t>(rows[k].node);
    const double d0 = xi[0] - xj[0];
    const double d1 = xi[1] - xj[1];
    const double d2 = xi[2] - xj[2];
    const double md = block.m[0] * d0 + block.m[1] * d1 + block.m[2] * d2;
    y0 += block.s * d0 + md * block.m[0];
    y1 += block.s * d1 + md * block.m[1];
    y2 += block.s * d2 + md * block.m[2];
  }
  y[0] = y0;
  y[1] = y1;
  y[2] = y2;
}

double NewmarkIntegrator::MultiplySystem(const double* x, double* y) const
{
  // y = A x on the free nodes (0 on fixed nodes), and x^T A x. x must be zero on fixed nodes.
  const char* fixed = this->NodeFixed.data();
  return ChunkedSum<1>(*this->Threads, this->System->NodeCount(), [&](std::size_t begin, std::size_t end, double* sum) {
    for (std::size_t i = begin; i < end; ++i)
    {
      double* yi = y + 3 * i;
      if (fixed[i])
      {
        yi[0] = yi[1] = yi[2] = 0.0;
        continue;
      }
      this->MultiplyRow(i, x, yi);
      sum[0] += x[3 * i] * yi[0] + x[3 * i + 1] * yi[1] + x[3 * i + 2] * yi[2];
    }
  })[0];
}

bool NewmarkIntegrator::SolveCG()
{
  // Preconditioned CG in Chronopoulos and Gear's form (one synchronisation per half iteration; the same iterates
  // as the textbook form in exact arithmetic): with u = P r and w = A u,
  //   gamma = r.u, delta = u.w, beta = gamma / gamma_old, alpha = gamma / (delta - beta gamma / alpha_old),
  //   p = u + beta p, s = w + beta s (= A p), x += alpha p, r -= alpha s.
  // Each iteration is two passes over the nodes: a local one (the updates, u = P r and gamma) and a gathering one
  // (w = A u and delta). Stop when r.u <= CGTolerance^2 b.P b (VegaFEM's Jacobi CG test with x0 = 0).
  MassSpringThreads& threads = *this->Threads;
  const std::size_t n = this->System->NodeCount();
  const char* fixed = this->NodeFixed.data();
  double* x = this->Delta.data();
  double* r = this->CGr.data();
  double* u = this->CGz.data();
  double* p = this->CGd.data();
  double* s = this->CGq.data();
  double* w = this->CGw.data();
  const double* b = this->Rhs.data();
  const double* P = this->Precond.data();
  // r = b - A x for the warm start x, u = P r, gamma = r.u, b.P b.
  std::array<double, 2> sums = ChunkedSum<2>(threads, n, [&](std::size_t begin, std::size_t end, double* sum) {
    for (std::size_t i = begin; i < end; ++i)
    {
      double* ri = r + 3 * i;
      double* ui = u + 3 * i;
      if (fixed[i])
      {
        std::fill(ri, ri + 3, 0.0);
        std::fill(ui, ui + 3, 0.0);
        std::fill(p + 3 * i, p + 3 * i + 3, 0.0);
        std::fill(s + 3 * i, s + 3 * i + 3, 0.0);
        x[3 * i] = x[3 * i + 1] = x[3 * i + 2] = 0.0;
        continue;
      }
      double ax[3];
      this->MultiplyRow(i, x, ax);
      const double* bi = b + 3 * i;
      double pb[3] = { 0.0, 0.0, 0.0 };
      AddBlockTimes(P + 6 * i, bi, 1.0, pb);
      sum[1] += pb[0] * bi[0] + pb[1] * bi[1] + pb[2] * bi[2];
      ri[0] = bi[0] - ax[0];
      ri[1] = bi[1] - ax[1];
      ri[2] = bi[2] - ax[2];
      ui[0] = ui[1] = ui[2] = 0.0;
      AddBlockTimes(P + 6 * i, ri, 1.0, ui);
      sum[0] += ri[0] * ui[0] + ri[1] * ui[1] + ri[2] * ui[2];
      // p and s start at zero (beta = 0 in the first iteration).
      std::fill(p + 3 * i, p + 3 * i + 3, 0.0);
      std::fill(s + 3 * i, s + 3 * i + 3, 0.0);
    }
  });
  double gamma = sums[0];
  const double bNorm = sums[1];
  if (!(bNorm > 0.0))
  {
    std::fill(x, x + 3 * n, 0.0);
    return std::isfinite(bNorm);
  }
  const double threshold = this->Params.cgTolerance * this->Params.cgTolerance * bNorm;
  int iteration = 0;
  double alpha = 0.0;
  double beta = 0.0;
  double gammaOld = 0.0;
  while (std::isfinite(gamma) && gamma > threshold && iteration < this->Params.cgMaxIterations)
  {
    // w = A u, delta = u.w
    const double delta = this->MultiplySystem(u, w);
    const double curvature = iteration == 0 ? delta : delta - beta * gamma / alpha; // p.A p
    if (!(curvature > 0.0) || !std::isfinite(curvature))
    {
      return false; // not positive definite (or NaN)
    }
    alpha = gamma / curvature;
    gammaOld = gamma;
    const double a = alpha;
    const double bt = beta;
    gamma = ChunkedSum<1>(threads, n, [&](std::size_t begin, std::size_t end, double* sum) {
      for (std::size_t i = begin; i < end; ++i)
      {
        if (fixed[i])
        {
          continue;
        }
        for (std::size_t c = 3 * i; c < 3 * i + 3; ++c)
        {
          p[c] = u[c] + bt * p[c];
          s[c] = w[c] + bt * s[c];
          x[c] += a * p[c];
          r[c] -= a * s[c];
        }
        double* ui = u + 3 * i;
        ui[0] = ui[1] = ui[2] = 0.0;
        AddBlockTimes(P + 6 * i, r + 3 * i, 1.0, ui);
        sum[0] += r[3 * i] * ui[0] + r[3 * i + 1] * ui[1] + r[3 * i + 2] * ui[2];
      }
    })[0];
    beta = gamma / gammaOld;
    ++iteration;
  }
  this->Timing.cgIterations += iteration;
  return std::isfinite(gamma) && gamma <= threshold;
}

bool NewmarkIntegrator::SolveCholesky()
{
  CholeskyData& chol = *this->Chol;
  const MassSpringSystem& system = *this->System;
  double* values = chol.matrix.valuePtr();
  const std::size_t n = system.NodeCount();
  this->Threads->For(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const int f = chol.freeIndex[i];
      if (f < 0)
      {
        continue;
      }
      for (int k = 0; k < 6; ++k)
      {
        values[chol.nodeEntry[6 * i + static_cast<std::size_t>(k)]] =
          this->NodeBlock[6 * i + static_cast<std::size_t>(k)];
      }
      for (int c = 0; c < 3; ++c)
      {
        chol.rhs[3 * f + c] = this->Rhs[3 * i + static_cast<std::size_t>(c)];
      }
    }
  });
  this->Threads->For(this->Blocks.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
    {
      const int* entry = &chol.springEntry[9 * e];
      if (entry[0] < 0)
      {
        continue;
      }
      const SpringBlock& spring = this->Blocks[e];
      for (int r = 0; r < 3; ++r)
      {
        for (int c = 0; c < 3; ++c)
        {
          values[entry[3 * r + c]] = -(spring.m[r] * spring.m[c] + (r == c ? spring.s : 0.0));
        }
      }
    }
  });
  chol.ldlt.factorize(chol.matrix);
  if (chol.ldlt.info() != Eigen::Success)
  {
    return false;
  }
  chol.solution = chol.ldlt.solve(chol.rhs);
  if (chol.ldlt.info() != Eigen::Success || !chol.solution.allFinite())
  {
    return false;
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    const int f = chol.freeIndex[i];
    for (int c = 0; c < 3; ++c)
    {
      this->Delta[3 * i + static_cast<std::size_t>(c)] = f < 0 ? 0.0 : chol.solution[3 * f + c];
    }
  }
  return true;
}

void NewmarkIntegrator::WarmStart()
{
  // The first Newton iteration's increment changes smoothly from step to step (it is about v dt): start CG from
  // its linear extrapolation 2 d_{s-1} - d_{s-2} once two are known, else from the last one.
  double* x = this->Delta.data();
  const double* d1 = this->PreviousDelta.data();
  const double* d2 = this->OlderDelta.data();
  const std::size_t n3 = this->Delta.size();
  if (this->WarmSteps < 2 || !this->Params.extrapolateWarmStart)
  {
    std::copy(d1, d1 + n3, x);
    return;
  }
  this->Threads->For(n3, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
    {
      x[k] = 2.0 * d1[k] - d2[k];
    }
  });
}

void NewmarkIntegrator::SetRestLengths(const std::vector<double>& restLengths)
{
  for (std::size_t e = 0; e < this->Material.size(); ++e)
  {
    this->Material[e].restLength = restLengths[static_cast<std::size_t>(this->SystemSpring[e])];
  }
}

std::string NewmarkIntegrator::Step(const std::vector<double>& force)
{
  const MassSpringSystem& system = *this->System;
  const std::size_t n3 = 3 * system.NodeCount();
  if (force.size() != n3)
  {
    return "the external force has the wrong size";
  }
  this->Q1.resize(n3);
  this->V1.resize(n3);
  this->A1.resize(n3);
  const double* a = this->Alpha;
  double* q = this->SolverQ.data();
  double* v = this->SolverV.data();
  double* acc = this->SolverA.data();
  double* q1 = this->Q1.data();
  double* v1 = this->V1.data();
  double* a1 = this->A1.data();
  // (All in the solver's node order.) Keep the step's start; the iterate's velocity and acceleration at q = q_s.
  this->Threads->For(n3, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
    {
      q1[k] = q[k];
      v1[k] = v[k];
      a1[k] = acc[k];
      acc[k] = -a[2] * v1[k] - a[3] * a1[k];
      v[k] = a[5] * v1[k] + a[6] * a1[k];
    }
  });
  double error0 = 0.0;
  std::string failure;
  for (int iteration = 0; iteration < this->Params.maxIterations; ++iteration)
  {
    const Clock::time_point assemblyStart = Clock::now();
    double error = 0.0;
    this->Assemble(force, error);
    this->Timing.assemblySeconds += Seconds(assemblyStart);
    if (!std::isfinite(error))
    {
      failure = "a non-finite force or residual";
      break;
    }
    if (iteration == 0)
    {
      error0 = error;
    }
    if (error == 0.0 ||
      (iteration > 0 && error <= this->Params.newtonTolerance * this->Params.newtonTolerance * error0))
    {
      break;
    }
    const Clock::time_point solveStart = Clock::now();
    bool solved = false;
    if (this->Solver == NewmarkSolver::Cholesky)
    {
      solved = this->SolveCholesky();
    }
    else
    {
      if (iteration == 0)
      {
        this->WarmStart();
      }
      else
      {
        std::fill(this->Delta.begin(), this->Delta.end(), 0.0);
      }
      solved = this->SolveCG();
    }
    this->Timing.solveSeconds += Seconds(solveStart);
    ++this->Timing.newtonIterations;
    if (!solved)
    {
      failure = this->Solver == NewmarkSolver::Cholesky
        ? "the sparse Cholesky (LDLT) factorisation failed: the system matrix is singular"
        : "conjugate gradients did not converge (the system matrix is not positive definite, or CGMaxIterations "
          "is too small)";
      break;
    }
    if (iteration == 0)
    {
      this->OlderDelta.swap(this->PreviousDelta);
      this->PreviousDelta = this->Delta;
      this->WarmSteps = std::min(this->WarmSteps + 1, 2);
    }
    // q += dq, then the iterate's velocity and acceleration.
    const double* dq = this->Delta.data();
    this->Threads->For(n3, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k)
      {
        q[k] += dq[k];
        const double du = q[k] - q1[k];
        acc[k] = a[1] * du - a[2] * v1[k] - a[3] * a1[k];
        v[k] = a[4] * du + a[5] * v1[k] + a[6] * a1[k];
      }
    });
  }
  bool finite = failure.empty();
  if (finite)
  {
    const double bad = ChunkedSum<1>(*this->Threads, n3, [&](std::size_t begin, std::size_t end, double* sum) {
      for (std::size_t k = begin; k < end; ++k)
      {
        sum[0] += std::isfinite(q[k]) && std::isfinite(v[k]) ? 0.0 : 1.0;
      }
    })[0];
    finite = bad == 0.0;
  }
  if (!finite)
  {
    if (failure.empty())
    {
      failure = "a non-finite displacement or velocity";
    }
    this->SolverQ = this->Q1;
    this->SolverV = this->V1;
    this->SolverA = this->A1;
    return failure;
  }
  // The state in the system's node order.
  const int* position = this->Position.data();
  this->Threads->For(system.NodeCount(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const std::size_t p = 3 * static_cast<std::size_t>(position[i]);
      for (std::size_t c = 0; c < 3; ++c)
      {
        this->Q[3 * i + c] = q[p + c];
        this->V[3 * i + c] = v[p + c];
        this->A[3 * i + c] = acc[p + c];
      }
    }
  });
  this->CurrentTime += this->Params.timeStep;
  ++this->Timing.steps;
  return std::string();
}

} // namespace plantmorph
