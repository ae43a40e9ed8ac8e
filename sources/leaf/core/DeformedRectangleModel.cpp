// SPDX-License-Identifier: GPL-3.0-or-later
#include "DeformedRectangleModel.h"

#include <plantmorph/MathConstants.h>
#include <plantmorph/RangeError.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace plantmorph
{
namespace
{
// Largest |amplitude| and |frequency| a term may have: far beyond any leaf, small enough that sampling stays sane.
constexpr double MaxAmplitude = 100.0;
constexpr double MaxFrequency = 1000.0;

bool IsWholeIn(double value, int low, int high)
{
  return std::isfinite(value) && value == std::floor(value) && value >= low && value <= high;
}
} // namespace

std::string ParseTerms(const std::vector<double>& flat, std::vector<SinusoidTerm>& terms)
{
  terms.clear();
  if (flat.size() % TermColumns != 0)
  {
    std::ostringstream message;
    message << "Terms: expected rows of " << TermColumns
            << " numbers [Target, Scale, Amplitude, Multiplier, Frequency, Variable, Phase], got " << flat.size()
            << " numbers";
    return message.str();
  }
  const char* names[TermColumns] = { "Target", "Scale", "Amplitude", "Multiplier", "Frequency", "Variable", "Phase" };
  for (std::size_t row = 0; row < flat.size() / TermColumns; ++row)
  {
    const double* r = &flat[row * TermColumns];
    auto fail = [&](int column, const char* accepted) {
      std::ostringstream message;
      message << "Terms: row " << row << ", " << names[column] << " = " << r[column] << " is not " << accepted;
      return message.str();
    };
    if (!IsWholeIn(r[0], 0, 1))
      return fail(0, "0 (x) or 1 (y)");
    if (!IsWholeIn(r[1], 0, 1))
      return fail(1, "0 (Width a_x) or 1 (Length b_y)");
    if (!std::isfinite(r[2]) || std::abs(r[2]) > MaxAmplitude)
      return fail(2, "a finite number in [-100, 100]");
    if (!IsWholeIn(r[3], 0, 3))
      return fail(3, "0 (1), 1 (u), 2 (v) or 3 (u*v)");
    if (!std::isfinite(r[4]) || std::abs(r[4]) > MaxFrequency)
      return fail(4, "a finite number in [-1000, 1000]");
    if (!IsWholeIn(r[5], 0, 1))
      return fail(5, "0 (u) or 1 (v)");
    if (!std::isfinite(r[6]))
      return fail(6, "a finite number");
    SinusoidTerm term;
    term.target = static_cast<SinusoidTerm::Target>(static_cast<int>(r[0]));
    term.scale = static_cast<SinusoidTerm::Scale>(static_cast<int>(r[1]));
    term.amplitude = r[2];
    term.multiplier = static_cast<SinusoidTerm::Multiplier>(static_cast<int>(r[3]));
    term.frequency = r[4];
    term.variable = static_cast<SinusoidTerm::Variable>(static_cast<int>(r[5]));
    term.phase = r[6];
    terms.push_back(term);
  }
  return {};
}

std::vector<double> FlattenTerms(const std::vector<SinusoidTerm>& terms)
{
  std::vector<double> flat;
  flat.reserve(terms.size() * TermColumns);
  for (const SinusoidTerm& t : terms)
  {
    flat.insert(flat.end(),
      { static_cast<double>(t.target), static_cast<double>(t.scale), t.amplitude, static_cast<double>(t.multiplier),
        t.frequency, static_cast<double>(t.variable), t.phase });
  }
  return flat;
}

std::string Validate(const DeformedRectangleParameters& p)
{
  std::ostringstream message;
  if (!std::isfinite(p.length) || p.length <= 0.0 || p.length > 1e6)
    message << plantmorph::OutOfRange("Length (b_y)", p.length, "(0, 1e6]");
  else if (!std::isfinite(p.width) || p.width < 0.0 || p.width > 1e6)
    message << plantmorph::OutOfRange("Width (a_x)", p.width, "[0, 1e6]");
  else if (!std::isfinite(p.bending) || std::abs(p.bending) > 10.0)
    message << plantmorph::OutOfRange("Bending", p.bending, "[-10, 10]");
  else if (!std::isfinite(p.asymmetry) || std::abs(p.asymmetry) >= 1.0)
    message << plantmorph::OutOfRange("Asymmetry", p.asymmetry, "(-1, 1)");
  else
  {
    std::vector<SinusoidTerm> parsed;
    std::string termError = ParseTerms(FlattenTerms(p.terms), parsed);
    if (!termError.empty())
      return termError;
  }
  return message.str();
}

double BladeLength(const DeformedRectangleParameters& parameters)
{
  const DeformedRectangleModel model(parameters);
  return (model.Evaluate(0.0, 1.0) - model.Evaluate(0.0, 0.0)).norm();
}

std::string ScaleToBladeLength(DeformedRectangleParameters& parameters, double length)
{
  const double current = BladeLength(parameters);
  if (!(current > 1e-12 * std::max(parameters.width, parameters.length)) || !std::isfinite(current))
    return "Terms: the apex falls onto the base (the midvein u = 0 has no length), so the blade cannot be made "
           "Length long";
  const double factor = length / current;
  parameters.width *= factor;
  parameters.length *= factor;
  return {};
}

DeformedRectangleModel::DeformedRectangleModel(DeformedRectangleParameters parameters)
  : Params(std::move(parameters))
  , Base(Eigen::Vector2d::Zero())
{
  this->Base = this->EvaluateUntranslated(0.0, 0.0);
}

double DeformedRectangleModel::Size() const
{
  return std::max(this->Params.width, this->Params.length);
}

void DeformedRectangleModel::SumTerms(
  SinusoidTerm::Target target, double u, double v, double& value, double& du, double& dv) const
{
  value = du = dv = 0.0;
  for (const SinusoidTerm& t : this->Params.terms)
  {
    if (t.target != target)
      continue;
    const double scale = t.amplitude * (t.scale == SinusoidTerm::Width ? this->Params.width : this->Params.length);
    double m = 1.0, dmdu = 0.0, dmdv = 0.0;
    switch (t.multiplier)
    {
      case SinusoidTerm::One:
        break;
      case SinusoidTerm::U:
        m = u;
        dmdu = 1.0;
        break;
      case SinusoidTerm::V:
        m = v;
        dmdv = 1.0;
        break;
      case SinusoidTerm::UV:
        m = u * v;
        dmdu = v;
        dmdv = u;
        break;
    }
    const double w = t.variable == SinusoidTerm::VariableU ? u : v;
    const double angle = t.frequency * Pi * w + t.phase;
    const double s = std::sin(angle);
    const double dsdw = t.frequency * Pi * std::cos(angle);
    value += scale * m * s;
    du += scale * (dmdu * s + (t.variable == SinusoidTerm::VariableU ? m * dsdw : 0.0));
    dv += scale * (dmdv * s + (t.variable == SinusoidTerm::VariableV ? m * dsdw : 0.0));
  }
}

Eigen::Vector2d DeformedRectangleModel::EvaluateUntranslated(double u, double v) const
{
  const DeformedRectangleParameters& p = this->Params;
  double tx, txu, txv, ty, tyu, tyv;
  this->SumTerms(SinusoidTerm::X, u, v, tx, txu, txv);
  this->SumTerms(SinusoidTerm::Y, u, v, ty, tyu, tyv);
  double x = p.width * u + tx + p.bending * p.length * v * v;
  if (p.asymmetry != 0.0)
  {
    double mx, mxu, mxv;
    this->SumTerms(SinusoidTerm::X, 0.0, v, mx, mxu, mxv);
    const double xMid = mx + p.bending * p.length * v * v;
    x = xMid + (1.0 + p.asymmetry * std::sin(Pi * u)) * (x - xMid);
  }
  return { x, p.length * v + ty };
}

Eigen::Vector2d DeformedRectangleModel::Evaluate(double u, double v) const
{
  return this->EvaluateUntranslated(u, v) - this->Base;
}

Eigen::Matrix2d DeformedRectangleModel::Jacobian(double u, double v) const
{
  const DeformedRectangleParameters& p = this->Params;
  double tx, txu, txv, ty, tyu, tyv;
  this->SumTerms(SinusoidTerm::X, u, v, tx, txu, txv);
  this->SumTerms(SinusoidTerm::Y, u, v, ty, tyu, tyv);
  const double bend = p.bending * p.length * v * v;
  const double dbend = 2.0 * p.bending * p.length * v;
  double xu = p.width + txu;
  double xv = txv + dbend;
  if (p.asymmetry != 0.0)
  {
    double mx, mxu, mxv;
    this->SumTerms(SinusoidTerm::X, 0.0, v, mx, mxu, mxv);
    const double x = p.width * u + tx + bend;
    const double xMid = mx + bend;
    const double xMidV = mxv + dbend;
    const double factor = 1.0 + p.asymmetry * std::sin(Pi * u);
    const double factorU = p.asymmetry * Pi * std::cos(Pi * u);
    xu = factorU * (x - xMid) + factor * xu;
    xv = xMidV + factor * (xv - xMidV);
  }
  Eigen::Matrix2d j;
  j << xu, xv, tyu, p.length + tyv;
  return j;
}

bool DeformedRectangleModel::Invert(
  const Eigen::Vector2d& point, const Eigen::Vector2d& guess, Eigen::Vector2d& uv) const
{
  const double tolerance = 1e-10 * this->Size();
  auto clamp = [](Eigen::Vector2d& q) {
    q.x() = std::clamp(q.x(), -0.5, 0.5);
    q.y() = std::clamp(q.y(), 0.0, 1.0);
  };
  uv = guess;
  clamp(uv);
  Eigen::Vector2d residual = this->Evaluate(uv.x(), uv.y()) - point;
  double error = residual.norm();
  for (int iteration = 0; iteration < 50 && error > tolerance; ++iteration)
  {
    const Eigen::Matrix2d j = this->Jacobian(uv.x(), uv.y());
    const double det = j.determinant();
    if (!std::isfinite(det) || std::abs(det) < 1e-300)
      return false;
    const Eigen::Vector2d step = -j.inverse() * residual;
    // Damped Newton: halve the step until the residual falls (or the step is negligible).
    double t = 1.0;
    for (int halving = 0; halving < 30; ++halving, t *= 0.5)
    {
      Eigen::Vector2d trial = uv + t * step;
      clamp(trial);
      const Eigen::Vector2d trialResidual = this->Evaluate(trial.x(), trial.y()) - point;
      if (trialResidual.norm() < error)
      {
        uv = trial;
        residual = trialResidual;
        error = trialResidual.norm();
        break;
      }
    }
    if (t < 1e-8)
      break;
  }
  return error <= tolerance;
}

} // namespace plantmorph
