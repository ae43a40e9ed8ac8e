// SPDX-License-Identifier: GPL-3.0-or-later
#include "LeafFitSplines.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>

namespace plantmorph
{

UniformBasis::UniformBasis(double a, double b, int intervals, double x)
{
  // Multiplications by 1/h and 1/6 (one division, not nine): this runs tens of millions of times a dense fit.
  constexpr double Sixth = 1.0 / 6.0;
  const double perUnit = intervals / (b - a); // 1 / h
  const double u = (x - a) * perUnit;
  this->first = std::clamp(static_cast<int>(std::floor(u)), 0, intervals - 1);
  const double f = u - this->first;
  const double g = 1.0 - f;
  const double f2 = f * f, f3 = f2 * f;
  this->value = { g * g * g * Sixth, (3.0 * f3 - 6.0 * f2 + 4.0) * Sixth,
    (-3.0 * f3 + 3.0 * f2 + 3.0 * f + 1.0) * Sixth, f3 * Sixth };
  const double half = 0.5 * perUnit;
  this->derivative = { -g * g * half, (3.0 * f2 - 4.0 * f) * half, (-3.0 * f2 + 2.0 * f + 1.0) * half, f2 * half };
}

namespace
{
/// Adds lambda * D2^T D2 along one direction of a grid of n0 x n1 controls (index i + n0 * j); dir 0 or 1.
void AddSecondDifferences(Eigen::MatrixXd& M, int n0, int n1, int dir, double lambda)
{
  for (int j = 0; j < n1; ++j)
    for (int i = 0; i < n0; ++i)
    {
      if ((dir == 0 && i + 2 >= n0) || (dir == 1 && j + 2 >= n1))
        continue;
      const int step = dir == 0 ? 1 : n0;
      const int id[3] = { i + n0 * j, i + n0 * j + step, i + n0 * j + 2 * step };
      const double c[3] = { 1.0, -2.0, 1.0 };
      for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q)
          M(id[p], id[q]) += lambda * c[p] * c[q];
    }
}
} // namespace

bool PenalizedSpline1D::Fit(double a, double b, int intervals, const std::vector<double>& x,
  const std::vector<double>& y, const std::vector<double>& w, const std::vector<double>& factor, double lambda)
{
  this->A = a;
  this->B = b;
  this->Intervals = std::max(1, intervals);
  const int n = this->Intervals + 3;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
  double total = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    const UniformBasis basis(a, b, this->Intervals, x[i]);
    const double f = factor.empty() ? 1.0 : factor[i];
    for (int p = 0; p < 4; ++p)
    {
      r[basis.first + p] += w[i] * f * basis.value[p] * y[i];
      for (int q = 0; q < 4; ++q)
        M(basis.first + p, basis.first + q) += w[i] * f * f * basis.value[p] * basis.value[q];
    }
    total += w[i];
  }
  if (!(total > 0.0))
    return false;
  AddSecondDifferences(M, n, 1, 0, lambda * total / n);
  M.diagonal().array() += 1e-12 * total / n;
  Eigen::LDLT<Eigen::MatrixXd> ldlt(M);
  if (ldlt.info() != Eigen::Success)
    return false;
  this->Control = ldlt.solve(r);
  return this->Control.allFinite();
}

void PenalizedSpline1D::SetConstant(double a, double b, double value)
{
  this->A = a;
  this->B = b;
  this->Intervals = 1;
  this->Control = Eigen::VectorXd::Constant(4, value);
}

double PenalizedSpline1D::operator()(double x) const
{
  const UniformBasis basis(this->A, this->B, this->Intervals, x);
  double v = 0.0;
  for (int p = 0; p < 4; ++p)
    v += basis.value[p] * this->Control[basis.first + p];
  return v;
}

double PenalizedSpline1D::Derivative(double x) const
{
  const UniformBasis basis(this->A, this->B, this->Intervals, x);
  double v = 0.0;
  for (int p = 0; p < 4; ++p)
    v += basis.derivative[p] * this->Control[basis.first + p];
  return v;
}

bool TensorSurface::Fit(const Eigen::Vector2d& tRange, const Eigen::Vector2d& sRange, int nt, int ns,
  const std::vector<Eigen::Vector2d>& ts, const std::vector<Eigen::Vector3d>& X, const std::vector<double>& w,
  double lambda, const ParallelFor& parallel)
{
  this->T = tRange;
  this->S = sRange;
  this->Nt = std::max(1, nt);
  this->Ns = std::max(1, ns);
  const int n0 = this->Nt + 3, n1 = this->Ns + 3, n = n0 * n1;
  // The normal equations: each point adds a 16 x 16 block over the 4 x 4 controls of its knot cell. Blocks are
  // summed per cell first (contiguous memory: on 10^6 points scattered updates of the big matrix were memory-bound),
  // then added into the matrix, which is solved as the sparse system it is. The cells are summed in parallel, each
  // cell's points in index order, so every cell's sum is the serial one, bit for bit.
  const int cells = std::max(1, (n0 - 3) * (n1 - 3));
  const std::size_t count = ts.size();
  std::vector<int> cellOf(count);
  ForEachIndex(parallel, count, [&](std::size_t i) {
    if (!(w[i] > 0.0))
    {
      cellOf[i] = -1;
      return;
    }
    const UniformBasis bt(this->T[0], this->T[1], this->Nt, ts[i].x());
    const UniformBasis bs(this->S[0], this->S[1], this->Ns, ts[i].y());
    cellOf[i] = bt.first + (n0 - 3) * bs.first;
  });
  std::vector<std::size_t> start(static_cast<std::size_t>(cells) + 1, 0);
  double total = 0.0;
  for (std::size_t i = 0; i < count; ++i)
    if (cellOf[i] >= 0)
    {
      ++start[static_cast<std::size_t>(cellOf[i]) + 1];
      total += w[i];
    }
  for (int cell = 0; cell < cells; ++cell)
    start[cell + 1] += start[cell];
  // Stripes of consecutive cells with about equal point counts; each stripe reads the points in index order and
  // sums those of its cells (sequential reads; every cell's points in the serial order).
  constexpr int Stripes = 8;
  std::vector<int> stripeFirst(Stripes + 1, cells);
  stripeFirst[0] = 0;
  for (int k = 1, cell = 0; k < Stripes; ++k)
  {
    while (cell < cells && start[cell] * Stripes < start.back() * k)
      ++cell;
    stripeFirst[k] = cell;
  }
  std::vector<double> gram(static_cast<std::size_t>(cells) * 256, 0.0), rhs(static_cast<std::size_t>(cells) * 48, 0.0);
  parallel(Stripes, [&](std::size_t firstStripe, std::size_t lastStripe) {
    const int lo = stripeFirst[firstStripe], hi = stripeFirst[lastStripe];
    if (lo >= hi)
      return;
    for (std::size_t i = 0; i < count; ++i)
    {
      const int cell = cellOf[i];
      if (cell < lo || cell >= hi)
        continue;
      const UniformBasis bt(this->T[0], this->T[1], this->Nt, ts[i].x());
      const UniformBasis bs(this->S[0], this->S[1], this->Ns, ts[i].y());
      double v[16];
      for (int q = 0; q < 4; ++q)
        for (int p = 0; p < 4; ++p)
          v[p + 4 * q] = bt.value[p] * bs.value[q];
      double* g = &gram[static_cast<std::size_t>(cell) * 256];
      double* r = &rhs[static_cast<std::size_t>(cell) * 48];
      // The lower triangle (b <= a) only: the solver reads the lower triangle (SimplicialLDLT's default), which
      // is mirrored below, so the fit is the one summed over the whole block, bit for bit, at half the work.
      for (int a = 0; a < 16; ++a)
      {
        const double wa = w[i] * v[a];
        for (int c = 0; c < 3; ++c)
          r[3 * a + c] += wa * X[i][c];
        for (int b = 0; b <= a; ++b)
          g[16 * a + b] += wa * v[b];
      }
    }
  });
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(n, 3);
  for (int cell = 0; cell < cells; ++cell)
  {
    if (start[cell] == start[cell + 1])
      continue;
    const int firstT = cell % (n0 - 3), firstS = cell / (n0 - 3);
    int id[16];
    for (int q = 0; q < 4; ++q)
      for (int p = 0; p < 4; ++p)
        id[p + 4 * q] = firstT + p + n0 * (firstS + q);
    const double* g = &gram[static_cast<std::size_t>(cell) * 256];
    const double* h = &rhs[static_cast<std::size_t>(cell) * 48];
    for (int a = 0; a < 16; ++a)
    {
      for (int c = 0; c < 3; ++c)
        r(id[a], c) += h[3 * a + c];
      for (int b = 0; b <= a; ++b)
        M(id[a], id[b]) += g[16 * a + b]; // id[b] <= id[a]: the lower triangle
    }
  }
  M.triangularView<Eigen::StrictlyUpper>() = M.transpose();
  if (!(total > 0.0))
    return false;
  const double scale = lambda * total / n;
  AddSecondDifferences(M, n0, n1, 0, scale);
  AddSecondDifferences(M, n0, n1, 1, scale);
  M.diagonal().array() += 1e-10 * total / n;
  const Eigen::SparseMatrix<double> sparse = M.sparseView();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(sparse);
  if (solver.info() != Eigen::Success)
    return false;
  this->Control = solver.solve(r);
  return solver.info() == Eigen::Success && this->Control.allFinite();
}

Eigen::Vector3d TensorSurface::operator()(double t, double s) const
{
  const UniformBasis bt(this->T[0], this->T[1], this->Nt, t);
  const UniformBasis bs(this->S[0], this->S[1], this->Ns, s);
  const int n0 = this->Nt + 3;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int q = 0; q < 4; ++q)
    for (int p = 0; p < 4; ++p)
      x += bt.value[p] * bs.value[q] * this->Control.row(bt.first + p + n0 * (bs.first + q)).transpose();
  return x;
}

void TensorSurface::Derivatives(double t, double s, Eigen::Vector3d& dt, Eigen::Vector3d& ds) const
{
  Eigen::Vector3d x;
  this->Evaluate(t, s, x, dt, ds);
}

void TensorSurface::Evaluate(double t, double s, Eigen::Vector3d& x, Eigen::Vector3d& dt, Eigen::Vector3d& ds) const
{
  const UniformBasis bt(this->T[0], this->T[1], this->Nt, t);
  const UniformBasis bs(this->S[0], this->S[1], this->Ns, s);
  const int n0 = this->Nt + 3;
  x.setZero();
  dt.setZero();
  ds.setZero();
  for (int q = 0; q < 4; ++q)
    for (int p = 0; p < 4; ++p)
    {
      const Eigen::Vector3d c = this->Control.row(bt.first + p + n0 * (bs.first + q)).transpose();
      x += bt.value[p] * bs.value[q] * c;
      dt += bt.derivative[p] * bs.value[q] * c;
      ds += bt.value[p] * bs.derivative[q] * c;
    }
}

Eigen::Vector3d TensorSurface::Normal(double t, double s) const
{
  Eigen::Vector3d x, normal;
  this->PointAndNormal(t, s, x, normal);
  return normal;
}

void TensorSurface::PointAndNormal(double t, double s, Eigen::Vector3d& x, Eigen::Vector3d& normal) const
{
  Eigen::Vector3d dt, ds;
  this->Evaluate(t, s, x, dt, ds);
  const Eigen::Vector3d n = dt.cross(ds);
  const double norm = n.norm();
  normal = norm > 0.0 ? Eigen::Vector3d(n / norm) : Eigen::Vector3d::UnitZ();
}

} // namespace plantmorph
