#include "NewmarkIntegrator.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

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

/// Fixed number of spatial parts (slabs along the longest axis) the springs are cut into: the same on any number
/// of threads, so every sum is taken in the same order.
constexpr std::size_t Parts = 16;
} // namespace

struct NewmarkIntegrator::CholeskyData
{
  std::vector<int> freeIndex; // per node, -1 if fixed
  Eigen::SparseMatrix<double> matrix; // lower triangle, column-major
  std::vector<int> nodeEntry;   // 6 per node (lower triangle of the diagonal block), value indices
  std::vector<int> springEntry; // 9 per compact spring (row b, column a), -1 when an end is fixed
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt;
  Eigen::VectorXd rhs, solution;
};

std::string ValidateNewmark(const NewmarkParameters& p)
{
  std::ostringstream message;
  if (!(p.timeStep > 0.0) || !std::isfinite(p.timeStep))
  {
    message << "TimeStep must be a positive finite number (got " << p.timeStep << ")";
  }
  else if (!(p.newmarkBeta > 0.0 && p.newmarkBeta <= 0.5))
  {
    message << "NewmarkBeta must be in (0, 0.5] (got " << p.newmarkBeta << ")";
  }
  else if (!(p.newmarkGamma >= 0.5 && p.newmarkGamma <= 1.0))
  {
    message << "NewmarkGamma must be in [0.5, 1] (got " << p.newmarkGamma << ")";
  }
  else if (!(p.rayleighMass >= 0.0) || !std::isfinite(p.rayleighMass))
  {
    message << "RayleighMass (alpha) must be >= 0 and finite (got " << p.rayleighMass << ")";
  }
  else if (!(p.rayleighStiffness >= 0.0) || !std::isfinite(p.rayleighStiffness))
  {
    message << "RayleighStiffness (beta) must be >= 0 and finite (got " << p.rayleighStiffness << ")";
  }
  else if (p.maxIterations < 1 || p.maxIterations > 100)
  {
    message << "NewtonIterations must be in [1, 100] (got " << p.maxIterations << ")";
  }
  else if (!(p.newtonTolerance >= 0.0 && p.newtonTolerance < 1.0))
  {
    message << "NewtonTolerance must be in [0, 1) (got " << p.newtonTolerance << ")";
  }
  else if (!(p.cgTolerance > 0.0 && p.cgTolerance < 1.0))
  {
    message << "CGTolerance must be in (0, 1) (got " << p.cgTolerance << ")";
  }
  else if (p.cgMaxIterations < 1)
  {
    message << "CGMaxIterations must be >= 1 (got " << p.cgMaxIterations << ")";
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
  const std::size_t m = system.SpringCount();
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
  // Spatial parts: slabs of the rest bounding box's longest axis; a spring belongs to the part of its two ends, or
  // to the joining springs when they differ.
  {
    const std::vector<Eigen::Vector3d>& rest = system.RestPositions();
    Eigen::Vector3d low = Eigen::Vector3d::Constant(0.0);
    Eigen::Vector3d high = Eigen::Vector3d::Constant(0.0);
    if (n > 0)
    {
      low = high = rest[0];
    }
    for (const Eigen::Vector3d& x : rest)
    {
      low = low.cwiseMin(x);
      high = high.cwiseMax(x);
    }
    int axis = 0;
    (high - low).maxCoeff(&axis);
    const double extent = high[axis] - low[axis];
    std::vector<std::size_t> part(n, 0);
    for (std::size_t i = 0; i < n; ++i)
    {
      const double f = extent > 0.0 ? (rest[i][axis] - low[axis]) / extent : 0.0;
      part[i] = std::min(Parts - 1, static_cast<std::size_t>(f * static_cast<double>(Parts)));
    }
    std::vector<std::vector<int>> members(Parts + 1);
    const std::vector<MassSpringSpring>& springs = system.Springs();
    for (std::size_t e = 0; e < m; ++e)
    {
      const std::size_t pa = part[static_cast<std::size_t>(springs[e].a)];
      const std::size_t pb = part[static_cast<std::size_t>(springs[e].b)];
      members[pa == pb ? pa : Parts].push_back(static_cast<int>(e));
    }
    this->Compact.clear();
    this->Compact.reserve(m);
    this->Material.clear();
    this->Material.reserve(m);
    this->PartOffsets.assign(1, 0);
    for (const std::vector<int>& list : members)
    {
      for (int e : list)
      {
        const MassSpringSpring& spring = springs[static_cast<std::size_t>(e)];
        this->Compact.push_back({ spring.a, spring.b, 0.0, 0.0, { 0.0, 0.0, 0.0 } });
        this->Material.push_back({ spring.stiffness, spring.damping, spring.restLength });
      }
      this->PartOffsets.push_back(this->Compact.size());
    }
  }
  this->NodeBlock.assign(6 * n, 0.0);
  this->Rhs.assign(3 * n, 0.0);
  this->Delta.assign(3 * n, 0.0);
  this->PreviousDelta.assign(3 * n, 0.0);
  this->Chol.reset();
  this->CGr.clear();
  this->CGz.clear();
  this->CGd.clear();
  this->CGq.clear();
  this->Precond.clear();
  if (this->Solver == NewmarkSolver::ConjugateGradient)
  {
    this->CGr.assign(3 * n, 0.0);
    this->CGz.assign(3 * n, 0.0);
    this->CGd.assign(3 * n, 0.0);
    this->CGq.assign(3 * n, 0.0);
    this->Precond.assign(6 * n, 0.0);
  }
  else
  {
    // The pattern of the free degrees of freedom's lower triangle, built and analysed once.
    auto chol = std::make_unique<CholeskyData>();
    chol->freeIndex.assign(n, -1);
    int count = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!system.IsFixed(i))
      {
        chol->freeIndex[i] = count++;
      }
    }
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(6 * static_cast<std::size_t>(count) + 9 * m);
    for (std::size_t i = 0; i < n; ++i)
    {
      const int f = chol->freeIndex[i];
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
      const int fa = chol->freeIndex[static_cast<std::size_t>(this->Compact[e].a)];
      const int fb = chol->freeIndex[static_cast<std::size_t>(this->Compact[e].b)];
      if (fa < 0 || fb < 0)
      {
        continue;
      }
      for (int r = 0; r < 3; ++r)
      {
        for (int c = 0; c < 3; ++c)
        {
          triplets.emplace_back(3 * fb + r, 3 * fa + c, 1.0);
        }
      }
    }
    chol->matrix.resize(3 * count, 3 * count);
    chol->matrix.setFromTriplets(triplets.begin(), triplets.end());
    chol->matrix.makeCompressed();
    const double* base = chol->matrix.valuePtr();
    chol->nodeEntry.assign(6 * n, -1);
    chol->springEntry.assign(9 * m, -1);
    for (std::size_t i = 0; i < n; ++i)
    {
      const int f = chol->freeIndex[i];
      if (f < 0)
      {
        continue;
      }
      for (int r = 0; r < 3; ++r)
      {
        for (int c = 0; c <= r; ++c)
        {
          chol->nodeEntry[6 * i + static_cast<std::size_t>(SymIndex(r, c))] =
            static_cast<int>(&chol->matrix.coeffRef(3 * f + r, 3 * f + c) - base);
        }
      }
    }
    for (std::size_t e = 0; e < m; ++e)
    {
      const int fa = chol->freeIndex[static_cast<std::size_t>(this->Compact[e].a)];
      const int fb = chol->freeIndex[static_cast<std::size_t>(this->Compact[e].b)];
      if (fa < 0 || fb < 0)
      {
        continue;
      }
      for (int r = 0; r < 3; ++r)
      {
        for (int c = 0; c < 3; ++c)
        {
          chol->springEntry[9 * e + static_cast<std::size_t>(3 * r + c)] =
            static_cast<int>(&chol->matrix.coeffRef(3 * fb + r, 3 * fa + c) - base);
        }
      }
    }
    chol->ldlt.analyzePattern(chol->matrix);
    chol->rhs.resize(3 * count);
    chol->solution.resize(3 * count);
    this->Chol = std::move(chol);
  }
  this->Timing = NewmarkTimings();
  this->Reset();
  return std::string();
}

void NewmarkIntegrator::Reset()
{
  const std::size_t n3 = 3 * this->System->NodeCount();
  this->Q.assign(n3, 0.0);
  this->V.assign(n3, 0.0);
  this->A.assign(n3, 0.0);
  this->PreviousDelta.assign(n3, 0.0);
  this->CurrentTime = 0.0;
}

void NewmarkIntegrator::SetState(
  const std::vector<double>& q, const std::vector<double>& v, const std::vector<double>& a, double time)
{
  this->Q = q;
  this->V = v;
  this->A = a;
  for (std::size_t i = 0; i < this->System->NodeCount(); ++i)
  {
    if (this->System->IsFixed(i))
    {
      for (int c = 0; c < 3; ++c)
      {
        this->Q[3 * i + c] = this->V[3 * i + c] = this->A[3 * i + c] = 0.0;
      }
    }
  }
  std::fill(this->PreviousDelta.begin(), this->PreviousDelta.end(), 0.0);
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
  const double* masses = system.Masses().data();
  const double* v = this->V.data();
  const double* q = this->Q.data();
  const double* accel = this->A.data();
  const Eigen::Vector3d* rest = system.RestPositions().data();
  double* r = this->Rhs.data();
  double* diag = this->NodeBlock.data();
  // Nodes: r = M (accel + alpha vel) - f, diagonal block c2 m I.
  threads.For(system.NodeCount(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const double m = masses[i];
      for (std::size_t c = 0; c < 3; ++c)
      {
        r[3 * i + c] = m * (accel[3 * i + c] + alpha * v[3 * i + c]) - force[3 * i + c];
      }
      double* d = diag + 6 * i;
      d[0] = d[3] = d[5] = c2 * m;
      d[1] = d[2] = d[4] = 0.0;
    }
  });
  // Springs, part by part (parts in parallel: they touch disjoint nodes), then the joining springs: the spring
  // force f = k (l - L) n, the tangent D = k [g I + (1 - g) n n^T] (g = 1 - L/l, clamped at 0 if asked), the
  // system block c1 D + a4 c I = s I + t n n^T, the residual's g_e = f + (beta D + c I)(v_b - v_a), which is
  // -R on a and +R on b.
  const auto springs = [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
    {
      CompactSpring& spring = this->Compact[e];
      const SpringMaterial& material = this->Material[e];
      const std::size_t ia = 3 * static_cast<std::size_t>(spring.a);
      const std::size_t ib = 3 * static_cast<std::size_t>(spring.b);
      const Eigen::Vector3d& xa = rest[spring.a];
      const Eigen::Vector3d& xb = rest[spring.b];
      const double z[3] = { xb[0] + q[ib] - xa[0] - q[ia], xb[1] + q[ib + 1] - xa[1] - q[ia + 1],
        xb[2] + q[ib + 2] - xa[2] - q[ia + 2] };
      const double length = std::sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
      const double k = material.stiffness;
      double g = 1.0;
      double magnitude = 0.0;
      if (length > 0.0)
      {
        const double inv = 1.0 / length;
        spring.n[0] = z[0] * inv;
        spring.n[1] = z[1] * inv;
        spring.n[2] = z[2] * inv;
        magnitude = k * (length - material.restLength);
        g = 1.0 - material.restLength * inv;
        if (clamp && g < 0.0)
        {
          g = 0.0;
        }
      }
      else
      {
        spring.n[0] = spring.n[1] = spring.n[2] = 0.0;
      }
      const double* n = spring.n;
      spring.s = c1 * k * g + a4 * material.damping;
      spring.t = c1 * k * (1.0 - g);
      const double dv[3] = { v[ib] - v[ia], v[ib + 1] - v[ia + 1], v[ib + 2] - v[ia + 2] };
      const double ndv = n[0] * dv[0] + n[1] * dv[1] + n[2] * dv[2];
      const double iso = beta * k * g + material.damping;
      const double along = magnitude + beta * k * (1.0 - g) * ndv;
      for (std::size_t c = 0; c < 3; ++c)
      {
        const double ge = along * n[c] + iso * dv[c];
        r[ia + c] -= ge;
        r[ib + c] += ge;
      }
      const double block[6] = { spring.s + spring.t * n[0] * n[0], spring.t * n[0] * n[1], spring.t * n[0] * n[2],
        spring.s + spring.t * n[1] * n[1], spring.t * n[1] * n[2], spring.s + spring.t * n[2] * n[2] };
      double* da = diag + 6 * static_cast<std::size_t>(spring.a);
      double* db = diag + 6 * static_cast<std::size_t>(spring.b);
      for (std::size_t c = 0; c < 6; ++c)
      {
        da[c] += block[c];
        db[c] += block[c];
      }
    }
  };
  threads.Tasks(Parts, [&](std::size_t p) { springs(this->PartOffsets[p], this->PartOffsets[p + 1]); });
  springs(this->PartOffsets[Parts], this->PartOffsets[Parts + 1]);
  // Nodes again: fixed nodes drop out; -r becomes the right-hand side; the preconditioner for CG.
  const bool cg = this->Solver == NewmarkSolver::ConjugateGradient;
  residualNorm2 = threads.Sum(system.NodeCount(), [&](std::size_t begin, std::size_t end) {
    double sum = 0.0;
    for (std::size_t i = begin; i < end; ++i)
    {
      double* ri = r + 3 * i;
      if (system.IsFixed(i))
      {
        ri[0] = ri[1] = ri[2] = 0.0;
        std::fill(diag + 6 * i, diag + 6 * i + 6, 0.0);
        if (cg)
        {
          std::fill(&this->Precond[6 * i], &this->Precond[6 * i] + 6, 0.0);
        }
        continue;
      }
      sum += ri[0] * ri[0] + ri[1] * ri[1] + ri[2] * ri[2];
      ri[0] = -ri[0];
      ri[1] = -ri[1];
      ri[2] = -ri[2];
      if (cg)
      {
        InvertBlock(diag + 6 * i, &this->Precond[6 * i]);
      }
    }
    return sum;
  });
}

double NewmarkIntegrator::MultiplySystem(const double* x, double* y) const
{
  // y = A x with A = c2 M + sum over springs of the spring's block on (x_b - x_a) (the blocks' Laplacian), and
  // x^T A x from the same pass: sum c2 m |x_i|^2 + sum (x_b - x_a)^T B (x_b - x_a). x is zero on fixed nodes; y is
  // meaningful only on free nodes.
  const MassSpringSystem& system = *this->System;
  const double c2 = this->Alpha[1] + this->Alpha[4] * this->Params.rayleighMass;
  const double* masses = system.Masses().data();
  double energy = this->Threads->Sum(system.NodeCount(), [&](std::size_t begin, std::size_t end) {
    double sum = 0.0;
    for (std::size_t i = begin; i < end; ++i)
    {
      const double cm = c2 * masses[i];
      for (std::size_t c = 0; c < 3; ++c)
      {
        y[3 * i + c] = cm * x[3 * i + c];
        sum += cm * x[3 * i + c] * x[3 * i + c];
      }
    }
    return sum;
  });
  const auto springs = [&](std::size_t begin, std::size_t end) {
    double sum = 0.0;
    for (std::size_t e = begin; e < end; ++e)
    {
      const CompactSpring& spring = this->Compact[e];
      const std::size_t ia = 3 * static_cast<std::size_t>(spring.a);
      const std::size_t ib = 3 * static_cast<std::size_t>(spring.b);
      const double dx[3] = { x[ib] - x[ia], x[ib + 1] - x[ia + 1], x[ib + 2] - x[ia + 2] };
      const double tn = spring.t * (spring.n[0] * dx[0] + spring.n[1] * dx[1] + spring.n[2] * dx[2]);
      for (std::size_t c = 0; c < 3; ++c)
      {
        const double w = spring.s * dx[c] + tn * spring.n[c];
        y[ia + c] -= w;
        y[ib + c] += w;
        sum += dx[c] * w;
      }
    }
    return sum;
  };
  double partial[Parts + 1] = {};
  this->Threads->Tasks(
    Parts, [&](std::size_t p) { partial[p] = springs(this->PartOffsets[p], this->PartOffsets[p + 1]); });
  partial[Parts] = springs(this->PartOffsets[Parts], this->PartOffsets[Parts + 1]);
  for (double p : partial)
  {
    energy += p;
  }
  return energy;
}

bool NewmarkIntegrator::SolveCG()
{
  MassSpringThreads& threads = *this->Threads;
  const std::size_t n = this->System->NodeCount();
  double* x = this->Delta.data();
  double* r = this->CGr.data();
  double* z = this->CGz.data();
  double* d = this->CGd.data();
  double* q = this->CGq.data();
  const double* b = this->Rhs.data();
  const double* P = this->Precond.data();
  // b^T P b, and r = b - A x for the warm start x.
  const double bNorm = threads.Sum(n, [&](std::size_t begin, std::size_t end) {
    double sum = 0.0;
    for (std::size_t i = begin; i < end; ++i)
    {
      double pb[3] = { 0, 0, 0 };
      AddBlockTimes(P + 6 * i, b + 3 * i, 1.0, pb);
      sum += pb[0] * b[3 * i] + pb[1] * b[3 * i + 1] + pb[2] * b[3 * i + 2];
    }
    return sum;
  });
  if (!(bNorm > 0.0))
  {
    std::fill(x, x + 3 * n, 0.0);
    return std::isfinite(bNorm);
  }
  const double threshold = this->Params.cgTolerance * this->Params.cgTolerance * bNorm;
  this->MultiplySystem(x, q);
  double delta = threads.Sum(n, [&](std::size_t begin, std::size_t end) {
    double sum = 0.0;
    for (std::size_t i = begin; i < end; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        r[3 * i + c] = b[3 * i + c] - q[3 * i + c];
      }
      z[3 * i] = z[3 * i + 1] = z[3 * i + 2] = 0.0;
      AddBlockTimes(P + 6 * i, r + 3 * i, 1.0, z + 3 * i);
      for (int c = 0; c < 3; ++c)
      {
        d[3 * i + c] = z[3 * i + c];
        sum += r[3 * i + c] * z[3 * i + c];
      }
    }
    return sum;
  });
  int iteration = 0;
  while (delta > threshold && iteration < this->Params.cgMaxIterations)
  {
    const double dq = this->MultiplySystem(d, q);
    if (!(dq > 0.0))
    {
      return false; // not positive definite (or NaN)
    }
    const double step = delta / dq;
    const double deltaNew = threads.Sum(n, [&](std::size_t begin, std::size_t end) {
      double sum = 0.0;
      for (std::size_t i = begin; i < end; ++i)
      {
        for (int c = 0; c < 3; ++c)
        {
          x[3 * i + c] += step * d[3 * i + c];
          r[3 * i + c] -= step * q[3 * i + c];
        }
        z[3 * i] = z[3 * i + 1] = z[3 * i + 2] = 0.0;
        AddBlockTimes(P + 6 * i, r + 3 * i, 1.0, z + 3 * i);
        sum += r[3 * i] * z[3 * i] + r[3 * i + 1] * z[3 * i + 1] + r[3 * i + 2] * z[3 * i + 2];
      }
      return sum;
    });
    const double ratio = deltaNew / delta;
    delta = deltaNew;
    threads.For(3 * n, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k)
      {
        d[k] = z[k] + ratio * d[k];
      }
    });
    ++iteration;
  }
  this->Timing.cgIterations += iteration;
  return std::isfinite(delta) && delta <= threshold;
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
        values[chol.nodeEntry[6 * i + static_cast<std::size_t>(k)]] = this->NodeBlock[6 * i + static_cast<std::size_t>(k)];
      }
      for (int c = 0; c < 3; ++c)
      {
        chol.rhs[3 * f + c] = this->Rhs[3 * i + static_cast<std::size_t>(c)];
      }
    }
  });
  this->Threads->For(this->Compact.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
    {
      const int* entry = &chol.springEntry[9 * e];
      if (entry[0] < 0)
      {
        continue;
      }
      const CompactSpring& spring = this->Compact[e];
      for (int r = 0; r < 3; ++r)
      {
        for (int c = 0; c < 3; ++c)
        {
          values[entry[3 * r + c]] = -(spring.t * spring.n[r] * spring.n[c] + (r == c ? spring.s : 0.0));
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

std::string NewmarkIntegrator::Step(const std::vector<double>& force)
{
  const MassSpringSystem& system = *this->System;
  const std::size_t n3 = 3 * system.NodeCount();
  if (force.size() != n3)
  {
    return "the external force has the wrong size";
  }
  this->Q1 = this->Q;
  this->V1 = this->V;
  this->A1 = this->A;
  const double* a = this->Alpha;
  for (std::size_t k = 0; k < n3; ++k)
  {
    this->A[k] = -a[2] * this->V1[k] - a[3] * this->A1[k];
    this->V[k] = a[5] * this->V1[k] + a[6] * this->A1[k];
  }
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
    if (error == 0.0 || (iteration > 0 && error <= this->Params.newtonTolerance * this->Params.newtonTolerance * error0))
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
        this->Delta = this->PreviousDelta;
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
      this->PreviousDelta = this->Delta;
    }
    for (std::size_t k = 0; k < n3; ++k)
    {
      this->Q[k] += this->Delta[k];
      const double dq = this->Q[k] - this->Q1[k];
      this->A[k] = a[1] * dq - a[2] * this->V1[k] - a[3] * this->A1[k];
      this->V[k] = a[4] * dq + a[5] * this->V1[k] + a[6] * this->A1[k];
    }
  }
  bool finite = failure.empty();
  for (std::size_t k = 0; finite && k < n3; ++k)
  {
    finite = std::isfinite(this->Q[k]) && std::isfinite(this->V[k]);
  }
  if (!finite)
  {
    if (failure.empty())
    {
      failure = "a non-finite displacement or velocity";
    }
    this->Q = this->Q1;
    this->V = this->V1;
    this->A = this->A1;
    return failure;
  }
  this->CurrentTime += this->Params.timeStep;
  ++this->Timing.steps;
  return std::string();
}

} // namespace plantmorph
