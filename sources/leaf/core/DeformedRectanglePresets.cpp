// SPDX-License-Identifier: GPL-3.0-or-later
#include "DeformedRectanglePresets.h"

#include <plantmorph/MathConstants.h>

#include <vector>

namespace plantmorph
{
namespace
{
/// One sinusoid in v: amplitude * sin(frequency*pi*v + phase).
struct Wave
{
  double amplitude;
  double frequency;
  double phase;
};

SinusoidTerm Term(SinusoidTerm::Target target, SinusoidTerm::Scale scale, double amplitude,
  SinusoidTerm::Multiplier multiplier, double frequency, SinusoidTerm::Variable variable, double phase)
{
  SinusoidTerm t;
  t.target = target;
  t.scale = scale;
  t.amplitude = amplitude;
  t.multiplier = multiplier;
  t.frequency = frequency;
  t.variable = variable;
  t.phase = phase;
  return t;
}

/// Product of two wave sums, expanded into a wave sum: sin(a)sin(b) = (cos(a - b) - cos(a + b))/2.
std::vector<Wave> Multiply(const std::vector<Wave>& first, const std::vector<Wave>& second)
{
  std::vector<Wave> product;
  for (const Wave& a : first)
  {
    for (const Wave& b : second)
    {
      const double amplitude = 0.5 * a.amplitude * b.amplitude;
      product.push_back({ amplitude, a.frequency - b.frequency, a.phase - b.phase + Pi / 2 });
      product.push_back({ -amplitude, a.frequency + b.frequency, a.phase + b.phase + Pi / 2 });
    }
  }
  return product;
}

/// x = a_x*u*G(v), G the wave sum: cancel the model's own a_x*u and add a_x*u*wave for every wave.
void SetWidthProfile(DeformedRectangleParameters& p, const std::vector<Wave>& profile)
{
  p.terms.push_back(
    Term(SinusoidTerm::X, SinusoidTerm::Width, -1.0, SinusoidTerm::U, 0.0, SinusoidTerm::VariableV, Pi / 2));
  for (const Wave& w : profile)
  {
    p.terms.push_back(Term(SinusoidTerm::X, SinusoidTerm::Width, w.amplitude, SinusoidTerm::U, w.frequency,
      SinusoidTerm::VariableV, w.phase));
  }
}

/// y += (1 - v)*amount*b_y*cos(pi*u): shapes the base edge (amount < 0 rounds it, > 0 makes it cordate).
void ShapeBase(DeformedRectangleParameters& p, double amount)
{
  p.terms.push_back(
    Term(SinusoidTerm::Y, SinusoidTerm::Length, amount, SinusoidTerm::One, 1.0, SinusoidTerm::VariableU, Pi / 2));
  p.terms.push_back(
    Term(SinusoidTerm::Y, SinusoidTerm::Length, -amount, SinusoidTerm::V, 1.0, SinusoidTerm::VariableU, Pi / 2));
}

/// y += v*amount*b_y*cos(pi*u): shapes the apex edge (amount > 0 rounds it, < 0 makes it emarginate).
void ShapeApex(DeformedRectangleParameters& p, double amount)
{
  p.terms.push_back(
    Term(SinusoidTerm::Y, SinusoidTerm::Length, amount, SinusoidTerm::V, 1.0, SinusoidTerm::VariableU, Pi / 2));
}

/// The ovate envelope of Fig. 1: G(v) = sin(pi v) + 0.25 sin(2 pi v) = sin(pi v)(1 + 0.5 cos(pi v)) >= 0.
const std::vector<Wave> OvateEnvelope = { { 1.0, 1.0, 0.0 }, { 0.25, 2.0, 0.0 } };

/// Ovate envelope times (1 + the given wave sum): margin teeth or lobes that vanish at base and apex.
std::vector<Wave> ModulatedOvate(const std::vector<Wave>& modulation)
{
  std::vector<Wave> profile = OvateEnvelope;
  for (const Wave& w : Multiply(OvateEnvelope, modulation))
    profile.push_back(w);
  return profile;
}
} // namespace

DeformedRectangleParameters MakeDeformedRectanglePreset(DeformedRectanglePreset preset, double length)
{
  DeformedRectangleParameters p;
  p.length = length;
  p.width = 1.1 * length;
  switch (preset)
  {
    case DeformedRectanglePreset::Custom:
      break;
    case DeformedRectanglePreset::Ginkgo:
      // Eq. (1): x = a_x u + 1.1 b_y u sin(pi v - pi/2)
      //          y = b_y v + 0.05 v b_y sin(11 u pi - 1.5) - 0.6 v b_y sin((u - 0.5) pi), with a_x = 1.1 b_y.
      p.terms = {
        Term(SinusoidTerm::X, SinusoidTerm::Length, 1.1, SinusoidTerm::U, 1.0, SinusoidTerm::VariableV, -Pi / 2),
        Term(SinusoidTerm::Y, SinusoidTerm::Length, 0.05, SinusoidTerm::V, 11.0, SinusoidTerm::VariableU, -1.5),
        Term(SinusoidTerm::Y, SinusoidTerm::Length, -0.6, SinusoidTerm::V, 1.0, SinusoidTerm::VariableU, -Pi / 2),
      };
      break;
    case DeformedRectanglePreset::Entire:
      p.width = 0.55 * length;
      SetWidthProfile(p, OvateEnvelope);
      break;
    case DeformedRectanglePreset::Serrate:
      // Two Fourier terms of a sawtooth: teeth with a long back and a short front, pointing to the apex.
      p.width = 0.55 * length;
      SetWidthProfile(p, ModulatedOvate({ { -0.07, 18.0, 0.0 }, { 0.035, 36.0, 0.0 } }));
      break;
    case DeformedRectanglePreset::Lobed:
      p.width = 0.7 * length;
      SetWidthProfile(p, ModulatedOvate({ { 0.3, 7.0, -Pi / 2 } }));
      break;
    case DeformedRectanglePreset::Parted:
      p.width = 0.6 * length;
      SetWidthProfile(p, ModulatedOvate({ { 0.7, 5.0, -Pi / 2 } }));
      break;
    case DeformedRectanglePreset::AcuteBaseAcuteApex:
      p.width = 0.5 * length;
      SetWidthProfile(p, { { 1.0, 1.0, 0.0 } });
      break;
    case DeformedRectanglePreset::RoundedBaseAcuminateApex:
      // G = sin(t) + 0.5 sin(2t), t = 0.8 pi v + 0.2 pi: G(0) > 0, and G'(1) = 0 draws the apex out. The base
      // curve's depth meets the side margin tangentially: B = 2 G(0) / (pi G'(0)).
      p.width = 0.46 * length;
      SetWidthProfile(p, { { 1.0, 0.8, 0.2 * Pi }, { 0.5, 1.6, 0.4 * Pi } });
      ShapeBase(p, -0.24);
      break;
    case DeformedRectanglePreset::CordateBaseRoundedApex:
      p.width = 0.6 * length;
      SetWidthProfile(p, { { 1.0, 0.7, 0.15 * Pi } });
      ShapeBase(p, 0.12);
      ShapeApex(p, 0.15);
      break;
    case DeformedRectanglePreset::AcuminateBaseEmarginateApex:
      // G = (1 - cos(1.3 pi v))/2: starts tangent to the midvein (acuminate), stays wide at the apex for the notch.
      p.width = 0.7 * length;
      SetWidthProfile(p, { { 0.5, 0.0, Pi / 2 }, { -0.5, 1.3, Pi / 2 } });
      ShapeApex(p, -0.12);
      break;
  }
  return p;
}

std::string PresetName(DeformedRectanglePreset preset)
{
  static const char* const names[DeformedRectanglePresetCount] = { "Custom", "Ginkgo", "Entire", "Serrate", "Lobed",
    "Parted", "AcuteBaseAcuteApex", "RoundedBaseAcuminateApex", "CordateBaseRoundedApex",
    "AcuminateBaseEmarginateApex" };
  const int index = static_cast<int>(preset);
  return index >= 0 && index < DeformedRectanglePresetCount ? names[index] : "Unknown";
}

} // namespace plantmorph
