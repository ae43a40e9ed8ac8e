// SPDX-License-Identifier: GPL-3.0-or-later
#include "SpaceCurvePresets.h"

namespace plantmorph
{

SpaceCurveParameters MakeSpaceCurvePreset(SpaceCurvePreset preset, double length)
{
  SpaceCurveParameters p;
  p.length = length;
  CurvatureFamily& k = p.curvature;
  switch (preset)
  {
    case SpaceCurvePreset::Custom:
    case SpaceCurvePreset::Figure1:
      k.type = CurvatureFamily::Triangular;
      k.mu = 2.0;
      k.lambda = 0.7;
      break;
    case SpaceCurvePreset::Figure2:
      k.type = CurvatureFamily::Triangular;
      k.mu = 6.0;
      k.lambda = 0.9;
      break;
    case SpaceCurvePreset::Figure3:
      k.type = CurvatureFamily::Exponential;
      k.mu = 30.0;
      k.lambda = 0.0;
      k.u3 = 0.001;
      break;
    case SpaceCurvePreset::Figure4:
      // The paper prints no numbers for Fig. 4. Chosen by looking at a sweep of mu, beta and alpha4: a broad first
      // triangle, then a second one of peak h/beta that turns the margin back into a notch at the apex. The
      // positive u4 of eq. (8) shows the notch; a negative one (beta < 0) gives a pointed tip instead.
      k.type = CurvatureFamily::NotchedApex;
      k.mu = 7.0;
      k.lambda = 0.5;
      k.beta = 1.2;
      k.alpha4 = 0.4;
      k.lambda2 = 0.5;
      break;
    case SpaceCurvePreset::Figure5:
    case SpaceCurvePreset::Figure6:
      k.type = CurvatureFamily::Triangular;
      k.mu = 5.0;
      k.lambda = 0.95;
      p.torsion = k;
      p.torsion.mu = 4.0;
      // Fig. 5: the midvein is the chord ("the line through the start and end points"); Fig. 6: projected.
      p.midveinStretchZ = preset == SpaceCurvePreset::Figure5 ? 0.0 : 1.0;
      p.midveinStretchXY = 0.0;
      break;
    case SpaceCurvePreset::Figure8ThreeLobes:
    case SpaceCurvePreset::Figure8FiveLobes:
      // Fig. 8 prints no numbers. Each lobe is a broad "incomplete elliptic" leaf (a triangular curvature peaking
      // mid-margin, turning the margin by mu/2 = 1.5 rad); the next lobe starts a fifth of the way up the previous
      // one's margin, turned 45 (40 for five lobes) degrees further out and 0.85 times its size: deep sinuses,
      // lobes radiating from the base, as the paper's description ("3 or 5 lobes, deep notches") asks.
      k.type = CurvatureFamily::Triangular;
      k.mu = 3.0;
      k.lambda = 0.5;
      p.lobes = preset == SpaceCurvePreset::Figure8ThreeLobes ? 3 : 5;
      p.lobeStart = 0.2;
      p.lobeAngle = preset == SpaceCurvePreset::Figure8ThreeLobes ? 45.0 : 40.0;
      p.lobeScale = 0.85;
      break;
    case SpaceCurvePreset::Watermelon:
      // Not in paper 002: a watermelon (Citrullus lanatus) leaf is deeply 3-5-lobed and each lobe is itself
      // pinnately lobed. Fig. 8's five lobes, each with two sub-lobes a side between LobeStart and its tip, the
      // sinuses cutting half-way to the lobe's axis (deep, rounded sinuses).
      p = MakeSpaceCurvePreset(SpaceCurvePreset::Figure8FiveLobes, length);
      p.subLobes = 2;
      p.subLobeDepth = 0.5;
      break;
    case SpaceCurvePreset::WatermelonPinnatifid:
      // A watermelon leaf is pinnatifid: its sinuses reach nearly to the midrib and the middle lobe is the longest.
      // The union of Fig. 8's lobes leaves shallow sinuses (their bottoms 0.7 of the tips' distance from the base)
      // and longer side lobes (they start a fifth of the way up lobe 1's margin): here the lobes start near the
      // common base (LobeStart 0.03), each side lobe 0.8 times the size of the one inside it, and the sinuses are
      // cut to 0.2 of the shorter lobe's length from the base (the middle lobe 4.28, its neighbours 3.59, the
      // outer 2.99 for a CurveLength of 5; the sinuses 0.72 from the base, a sixth of the leaf's length).
      p = MakeSpaceCurvePreset(SpaceCurvePreset::Watermelon, length);
      p.lobeStart = 0.03;
      p.lobeScale = 0.8;
      p.sinusDepth = 0.8;
      break;
  }
  return p;
}

std::string SpaceCurvePresetName(SpaceCurvePreset preset)
{
  static const char* const names[SpaceCurvePresetCount] = { "Custom", "Paper002Figure1", "Paper002Figure2",
    "Paper002Figure3", "Paper002Figure4", "Paper002Figure5", "Paper002Figure6", "Paper002Figure8ThreeLobes",
    "Paper002Figure8FiveLobes", "Watermelon", "WatermelonPinnatifid" };
  const int index = static_cast<int>(preset);
  return index >= 0 && index < SpaceCurvePresetCount ? names[index] : "Unknown";
}

} // namespace plantmorph
