// SPDX-License-Identifier: GPL-3.0-or-later
#include <plantmorph/CurvatureFamily.h>
#include <plantmorph/RangeError.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace plantmorph
{
namespace
{
/// A triangle rising linearly from 0 at `start` to `peak` at start + lambda*width, falling to 0 at start + width.
double Triangle(double s, double start, double width, double lambda, double peak)
{
  const double x = (s - start) / width;
  if (x < 0.0 || x > 1.0)
    return 0.0;
  if (x < lambda)
    return peak * x / lambda;
  return lambda < 1.0 ? peak * (1.0 - x) / (1.0 - lambda) : peak;
}
} // namespace

std::string CurvatureFamily::Validate(double length, const std::string& name) const
{
  std::ostringstream message;
  auto bad = [&](const char* parameter, double value, const char* range) {
    message << OutOfRange(name + parameter, value, range);
    return message.str();
  };
  if (!std::isfinite(length) || !(length > 0.0))
    return bad("Length", length, "(0, inf)");
  if (type < Constant || type > NotchedApex)
    return bad("Function", static_cast<double>(type), "0 (constant) to 4 (notched apex)");
  if (!std::isfinite(mu) || std::abs(mu) > 1e4)
    return bad("Mu", mu, "[-1e4, 1e4] (peak value times length)");
  if (!std::isfinite(lambda) || lambda < 0.0 || lambda > 1.0)
    return bad("Lambda", lambda, "[0, 1]");
  if (type == Power)
  {
    if (!std::isfinite(n1) || n1 <= 0.0 || n1 > 100.0)
      return bad("N1", n1, "(0, 100]");
    if (!std::isfinite(n2) || n2 <= 0.0 || n2 > 100.0)
      return bad("N2", n2, "(0, 100]");
  }
  if (type == Exponential)
  {
    // Logarithms of the three values: all positive.
    if (!(mu > 0.0))
      return bad("Mu", mu, "(0, 1e4] for the exponential family");
    if (!std::isfinite(b1) || b1 <= 0.0)
      return bad("B1", b1, "(0, inf)");
    if (!std::isfinite(u3) || u3 <= 0.0)
      return bad("U3", u3, "(0, inf)");
  }
  if (type == NotchedApex)
  {
    if (!std::isfinite(beta) || std::abs(beta) <= 1.0)
      return bad("Beta", beta, "|beta| > 1");
    if (!std::isfinite(alpha4) || alpha4 <= 0.0 || alpha4 >= 1.0)
      return bad("Alpha4", alpha4, "(0, 1)");
    if (!std::isfinite(lambda2) || lambda2 < 0.0 || lambda2 > 1.0)
      return bad("Lambda2", lambda2, "[0, 1]");
  }
  return {};
}

double CurvatureFamily::Evaluate(double s, double length) const
{
  const double S = length;
  const double h = this->mu / S;
  s = std::clamp(s, 0.0, S);
  switch (this->type)
  {
    case Constant:
      return h;
    case Triangular:
      return Triangle(s, 0.0, S, this->lambda, h);
    case Power:
    {
      const double peak = this->lambda * S;
      if (s < peak)
        return h * std::pow(s / peak, this->n1);
      return this->lambda < 1.0 ? h * std::pow((S - s) / ((1.0 - this->lambda) * S), this->n2) : h;
    }
    case Exponential:
    {
      const double peak = this->lambda * S;
      if (s < peak)
      {
        const double b2 = (std::log(h) - std::log(this->b1)) / peak;
        return this->b1 * std::exp(b2 * s);
      }
      if (this->lambda >= 1.0)
        return h;
      // b3 * exp(-b4 s) with b3 = u3 exp(b4 S), written as u3 exp(b4 (S - s)) to avoid overflow.
      const double b4 = (std::log(h) - std::log(this->u3)) / (S - peak);
      return this->u3 * std::exp(b4 * (S - s));
    }
    case NotchedApex:
    {
      const double s4 = S / (1.0 + this->alpha4);
      if (s <= s4)
        return Triangle(s, 0.0, s4, this->lambda, h);
      return Triangle(s, s4, this->alpha4 * s4, this->lambda2, h / this->beta);
    }
  }
  return 0.0;
}

std::vector<double> CurvatureFamily::Breakpoints(double length) const
{
  std::vector<double> points;
  switch (this->type)
  {
    case Constant:
      break;
    case Triangular:
    case Power:
    case Exponential:
      points.push_back(this->lambda * length);
      break;
    case NotchedApex:
    {
      const double s4 = length / (1.0 + this->alpha4);
      points = { this->lambda * s4, s4, s4 + this->lambda2 * this->alpha4 * s4 };
      break;
    }
  }
  points.erase(
    std::remove_if(points.begin(), points.end(), [&](double p) { return !(p > 0.0 && p < length); }), points.end());
  return points;
}

} // namespace plantmorph
