// SPDX-License-Identifier: GPL-3.0-or-later
// Space curves from curvature and torsion: the Frenet-Serret equations in arc length (paper 002 eq. (1), with the
// OCR's psi*beta corrected to psi*gamma, docs/methods/leaf-outline.md):
//
//   dr/ds = T,  dT/ds = phi*N,  dN/ds = -phi*T + psi*B,  dB/ds = -psi*N.
//
// Two integrators: classical RK4 with a fixed number of steps, and the embedded Dormand-Prince 5(4) pair with
// error control (the paper's "4th or 5th order Runge-Kutta"). Both re-orthonormalise the frame after every step
// (Gram-Schmidt on T and N, B = T x N), step exactly onto the requested output points and onto the breakpoints
// where phi or psi has a kink (so no step straddles one and RK4 keeps its order), and stop with a message rather
// than loop forever. Plain C++ (Eigen), no VTK; shared by leaf outlines and tree branches.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace plantmorph
{

struct FrenetFrame
{
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d tangent = Eigen::Vector3d::UnitX();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
  Eigen::Vector3d binormal = Eigen::Vector3d::UnitZ();
};

enum class FrenetMethod : int
{
  RK4 = 0,  ///< classical fourth order, `steps` equal steps per output interval piece
  RK45 = 1, ///< Dormand-Prince 5(4) with error control to `tolerance`
};

struct FrenetParameters
{
  FrenetMethod method = FrenetMethod::RK45;
  int stepsPerOutput = 4;   ///< RK4: steps between consecutive output points (at least 1)
  double tolerance = 1e-10; ///< RK45: error per step, relative to the curve length
  long maxSteps = 10000000; ///< either method: more steps than this is an error, never a hang
};

/// Statistics of one integration.
struct FrenetReport
{
  long steps = 0;    ///< accepted steps
  long rejected = 0; ///< RK45 steps rejected by the error control
};

using CurveFunction = std::function<double(double s)>;

/// Integrates from s = 0 with the initial frame (orthonormalised first) to s = outputs.back(), returning the frame at
/// each of the non-decreasing arc lengths in `outputs` (outputs[0] must be 0). `breakpoints` are arc lengths where
/// curvature or torsion is not smooth. Returns an empty string on success, otherwise a message, with `frames` empty.
std::string IntegrateFrenet(const CurveFunction& curvature, const CurveFunction& torsion, const FrenetFrame& initial,
  const std::vector<double>& outputs, const std::vector<double>& breakpoints, const FrenetParameters& settings,
  std::vector<FrenetFrame>& frames, FrenetReport* report = nullptr);

/// n + 1 equally spaced arc lengths 0, S/n, ..., S.
std::vector<double> UniformArcLengths(double length, int pieces);

} // namespace plantmorph
