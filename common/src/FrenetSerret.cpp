// SPDX-License-Identifier: GPL-3.0-or-later
#include <plantmorph/FrenetSerret.h>
#include <plantmorph/RangeError.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace plantmorph
{
namespace
{
using State = Eigen::Matrix<double, 12, 1>; // r, T, N, B

State Pack(const FrenetFrame& f)
{
  State y;
  y << f.position, f.tangent, f.normal, f.binormal;
  return y;
}

FrenetFrame Unpack(const State& y)
{
  FrenetFrame f;
  f.position = y.segment<3>(0);
  f.tangent = y.segment<3>(3);
  f.normal = y.segment<3>(6);
  f.binormal = y.segment<3>(9);
  return f;
}

/// Gram-Schmidt on T and N, then B = T x N: keeps the frame orthonormal and right-handed against drift.
bool Orthonormalise(State& y)
{
  Eigen::Vector3d t = y.segment<3>(3);
  Eigen::Vector3d n = y.segment<3>(6);
  const double tn = t.norm();
  if (!(tn > 1e-12) || !std::isfinite(tn))
    return false;
  t /= tn;
  n -= n.dot(t) * t;
  const double nn = n.norm();
  if (!(nn > 1e-12) || !std::isfinite(nn))
    return false;
  n /= nn;
  y.segment<3>(3) = t;
  y.segment<3>(6) = n;
  y.segment<3>(9) = t.cross(n);
  return true;
}

class Equations
{
public:
  Equations(const CurveFunction& curvature, const CurveFunction& torsion)
    : Curvature(curvature)
    , Torsion(torsion)
  {
  }

  State operator()(double s, const State& y)
  {
    const double phi = this->Curvature(s);
    const double psi = this->Torsion ? this->Torsion(s) : 0.0;
    if (!std::isfinite(phi) || !std::isfinite(psi))
    {
      if (this->BadAt < 0)
        this->BadAt = s;
    }
    State d;
    d.segment<3>(0) = y.segment<3>(3);
    d.segment<3>(3) = phi * y.segment<3>(6);
    d.segment<3>(6) = -phi * y.segment<3>(3) + psi * y.segment<3>(9);
    d.segment<3>(9) = -psi * y.segment<3>(6);
    return d;
  }

  double BadAt = -1.0; ///< first arc length where curvature or torsion was not finite

private:
  const CurveFunction& Curvature;
  const CurveFunction& Torsion;
};

State StepRK4(Equations& f, double s, const State& y, double h)
{
  const State k1 = f(s, y);
  const State k2 = f(s + 0.5 * h, y + 0.5 * h * k1);
  const State k3 = f(s + 0.5 * h, y + 0.5 * h * k2);
  const State k4 = f(s + h, y + h * k3);
  return y + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

/// One Dormand-Prince 5(4) step: the fifth-order solution, and the difference to the embedded fourth-order one.
State StepDormandPrince(Equations& f, double s, const State& y, double h, State& error)
{
  const State k1 = f(s, y);
  const State k2 = f(s + h / 5.0, y + h * (k1 / 5.0));
  const State k3 = f(s + 3.0 * h / 10.0, y + h * (3.0 / 40.0 * k1 + 9.0 / 40.0 * k2));
  const State k4 = f(s + 4.0 * h / 5.0, y + h * (44.0 / 45.0 * k1 - 56.0 / 15.0 * k2 + 32.0 / 9.0 * k3));
  const State k5 = f(s + 8.0 * h / 9.0,
    y + h * (19372.0 / 6561.0 * k1 - 25360.0 / 2187.0 * k2 + 64448.0 / 6561.0 * k3 - 212.0 / 729.0 * k4));
  const State k6 = f(s + h,
    y +
      h *
        (9017.0 / 3168.0 * k1 - 355.0 / 33.0 * k2 + 46732.0 / 5247.0 * k3 + 49.0 / 176.0 * k4 - 5103.0 / 18656.0 * k5));
  const State y5 =
    y + h * (35.0 / 384.0 * k1 + 500.0 / 1113.0 * k3 + 125.0 / 192.0 * k4 - 2187.0 / 6784.0 * k5 + 11.0 / 84.0 * k6);
  const State k7 = f(s + h, y5);
  const State y4 = y +
    h *
      (5179.0 / 57600.0 * k1 + 7571.0 / 16695.0 * k3 + 393.0 / 640.0 * k4 - 92097.0 / 339200.0 * k5 +
        187.0 / 2100.0 * k6 + 1.0 / 40.0 * k7);
  error = y5 - y4;
  return y5;
}
} // namespace

std::vector<double> UniformArcLengths(double length, int pieces)
{
  std::vector<double> s(static_cast<std::size_t>(std::max(pieces, 1)) + 1);
  for (std::size_t i = 0; i < s.size(); ++i)
    s[i] = length * static_cast<double>(i) / static_cast<double>(s.size() - 1);
  s.back() = length;
  return s;
}

std::string IntegrateFrenet(const CurveFunction& curvature, const CurveFunction& torsion, const FrenetFrame& initial,
  const std::vector<double>& outputs, const std::vector<double>& breakpoints, const FrenetParameters& settings,
  std::vector<FrenetFrame>& frames, FrenetReport* report)
{
  frames.clear();
  if (report)
    *report = FrenetReport();
  if (!curvature)
    return "curvature: no function given";
  if (outputs.empty() || outputs.front() != 0.0)
    return "arc lengths: the first output must be s = 0";
  for (std::size_t i = 0; i < outputs.size(); ++i)
  {
    if (!std::isfinite(outputs[i]) || (i > 0 && outputs[i] < outputs[i - 1]))
      return "arc lengths: outputs must be finite and non-decreasing";
  }
  const double length = outputs.back();
  if (!(length > 0.0))
    return "arc lengths: the curve length must be positive";
  if (settings.method == FrenetMethod::RK4 && settings.stepsPerOutput < 1)
    return "RK4: at least one step per output interval";
  if (settings.method == FrenetMethod::RK45 && !(settings.tolerance > 0.0 && settings.tolerance < 1.0))
    return "RK45: " + OutOfRange("Tolerance", settings.tolerance, "(0, 1)");

  State y = Pack(initial);
  if (!y.allFinite() || !Orthonormalise(y))
    return "initial frame: tangent and normal must be finite, non-zero and not parallel";

  // Every place a step must end: outputs and the breakpoints inside (0, length).
  std::vector<double> stops(outputs.begin() + 1, outputs.end());
  for (double b : breakpoints)
  {
    if (std::isfinite(b) && b > 0.0 && b < length)
      stops.push_back(b);
  }
  std::sort(stops.begin(), stops.end());
  stops.erase(std::unique(stops.begin(), stops.end()), stops.end());

  Equations f(curvature, torsion);
  const double outputSpacing = outputs.size() > 1 ? length / static_cast<double>(outputs.size() - 1) : length;
  const double scale = std::max(length, 1e-300);
  std::size_t nextOutput = 1;
  frames.push_back(Unpack(y));
  double s = 0.0;
  double h = outputSpacing > 0.0 ? outputSpacing : length;
  long steps = 0, rejected = 0;
  for (double stop : stops)
  {
    if (settings.method == FrenetMethod::RK4)
    {
      const double span = stop - s;
      const long n =
        span > 0.0 ? std::max(1L, std::lround(std::ceil(settings.stepsPerOutput * span / outputSpacing - 1e-9))) : 0L;
      for (long k = 0; k < n; ++k)
      {
        const double from = s + span * static_cast<double>(k) / static_cast<double>(n);
        const double to = k + 1 == n ? stop : s + span * static_cast<double>(k + 1) / static_cast<double>(n);
        y = StepRK4(f, from, y, to - from);
        if (!Orthonormalise(y) || ++steps > settings.maxSteps)
          break;
      }
    }
    else
    {
      while (s < stop && steps <= settings.maxSteps)
      {
        const double step = std::min(h, stop - s);
        State error;
        State next = StepDormandPrince(f, s, y, step, error);
        // Position error relative to the curve's length, frame error absolute: both against the tolerance.
        const double norm =
          std::max(error.segment<3>(0).cwiseAbs().maxCoeff() / scale, error.segment<9>(3).cwiseAbs().maxCoeff()) /
          settings.tolerance;
        if (!std::isfinite(norm))
          break;
        if (norm <= 1.0)
        {
          s = s + step >= stop * (1 - 1e-15) ? stop : s + step;
          y = next;
          if (!Orthonormalise(y))
            break;
          ++steps;
        }
        else
        {
          ++rejected;
          if (rejected > settings.maxSteps)
            break;
        }
        const double factor = norm > 0.0 ? 0.9 * std::pow(norm, -0.2) : 5.0;
        h = step * std::clamp(factor, 0.2, 5.0);
        if (!(h > length * 1e-15))
          break;
      }
    }
    if (f.BadAt >= 0.0)
    {
      std::ostringstream message;
      message << "curvature or torsion is not finite at s = " << f.BadAt;
      frames.clear();
      return message.str();
    }
    if (!y.allFinite() || steps > settings.maxSteps || (settings.method == FrenetMethod::RK45 && s < stop))
    {
      frames.clear();
      std::ostringstream message;
      message << "integration failed before s = " << stop << " (" << steps
              << " steps): the curvature or torsion is too large or the tolerance too small";
      return message.str();
    }
    s = stop;
    while (nextOutput < outputs.size() && outputs[nextOutput] <= stop)
    {
      frames.push_back(Unpack(y));
      ++nextOutput;
    }
  }
  if (report)
  {
    report->steps = steps;
    report->rejected = rejected;
  }
  return {};
}

} // namespace plantmorph
