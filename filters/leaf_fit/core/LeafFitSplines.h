// SPDX-License-Identifier: GPL-3.0-or-later
// Penalised uniform cubic B-splines for the leaf fit (P-splines, Eilers and Marx): a curve y = phi(x) g(x) for the
// margins and the parameters of the cross-sections, and a tensor surface (t, s) -> 3-D for the blade. Least
// squares plus lambda times the squared second differences of the control points (a discrete curvature penalty).
// Plain C++17 (Eigen), no VTK.
#pragma once

#include <plantmorph/ParallelFor.h>

#include <Eigen/Core>

#include <array>
#include <vector>

namespace plantmorph
{

/// Values (and first derivatives, per unit of the parameter) of the four uniform cubic B-splines that are non-zero
/// at x, on `intervals` intervals of [a, b]; `first` is the first control point's index. Outside [a, b] the end
/// pieces are extended (polynomial extrapolation).
struct UniformBasis
{
  int first = 0;
  std::array<double, 4> value{}, derivative{};
  UniformBasis(double a, double b, int intervals, double x);
};

class PenalizedSpline1D
{
public:
  PenalizedSpline1D() = default;
  /// Fits g on [a, b] (intervals >= 1) to samples y_i ~ factor_i g(x_i) with weights w_i >= 0, minimising
  /// sum w_i (y_i - factor_i g(x_i))^2 + lambda * (sum w_i / controls) * |D2 c|^2. Returns false when the system
  /// is singular (no data).
  bool Fit(double a, double b, int intervals, const std::vector<double>& x, const std::vector<double>& y,
    const std::vector<double>& w, const std::vector<double>& factor, double lambda);
  /// A constant g (used when a parameter has no data).
  void SetConstant(double a, double b, double value);
  double operator()(double x) const;
  double Derivative(double x) const;

private:
  double A = 0.0, B = 1.0;
  int Intervals = 1;
  Eigen::VectorXd Control = Eigen::VectorXd::Zero(4);
};

class TensorSurface
{
public:
  /// Fits S on [t0, t1] x [s0, s1] with nt x ns intervals to samples X_i ~ S(t_i, s_i), weights w_i; penalty as
  /// PenalizedSpline1D's, second differences along both parameters. False when singular. The normal equations are
  /// summed knot cell by knot cell through `parallel`, each cell's points in index order: the same numbers however
  /// the cells are spread over threads.
  bool Fit(const Eigen::Vector2d& tRange, const Eigen::Vector2d& sRange, int nt, int ns,
    const std::vector<Eigen::Vector2d>& ts, const std::vector<Eigen::Vector3d>& X, const std::vector<double>& w,
    double lambda, const ParallelFor& parallel = SerialFor);
  Eigen::Vector3d operator()(double t, double s) const;
  /// dS/dt and dS/ds at (t, s).
  void Derivatives(double t, double s, Eigen::Vector3d& dt, Eigen::Vector3d& ds) const;
  /// S, dS/dt and dS/ds at (t, s) from one evaluation of the bases (the same numbers as operator() and Derivatives).
  void Evaluate(double t, double s, Eigen::Vector3d& x, Eigen::Vector3d& dt, Eigen::Vector3d& ds) const;
  /// Unit normal dS/dt x dS/ds (the upper side of a blade laid out with t to the right and s up).
  Eigen::Vector3d Normal(double t, double s) const;
  /// S and the unit normal at (t, s) from one evaluation of the bases (the same numbers as operator() and Normal).
  void PointAndNormal(double t, double s, Eigen::Vector3d& x, Eigen::Vector3d& normal) const;

private:
  Eigen::Vector2d T{ 0.0, 1.0 }, S{ 0.0, 1.0 };
  int Nt = 1, Ns = 1;
  Eigen::MatrixXd Control; // ((Nt + 3) * (Ns + 3)) x 3, index i + (Nt + 3) * j
};

} // namespace plantmorph
