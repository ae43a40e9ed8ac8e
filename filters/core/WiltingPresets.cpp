#include "WiltingPresets.h"

namespace plantmorph
{

std::string WiltingPresetName(WiltingPreset preset)
{
  switch (preset)
  {
    case WiltingPreset::Cucumber:
      return "Cucumber";
    case WiltingPreset::Tomato:
      return "Tomato";
    case WiltingPreset::Watermelon:
      return "Watermelon";
    default:
      return "Custom";
  }
}

void ApplyWiltingPreset(WiltingPreset preset, WiltingParameters& p)
{
  if (preset == WiltingPreset::Custom)
  {
    return;
  }
  // Stiffness ratios of the paper's fit: veins 20000, margin 8000, rest 10000.
  const double blade = 1000.0;
  p.materials[WiltingBlade] = { 0.02, blade, 0.0 };
  p.materials[WiltingVein] = { 0.04, 2.0 * blade, 0.0 };
  p.materials[WiltingMargin] = { 0.03, 0.8 * blade, 0.0 };
  p.materials[WiltingPetiole] = { 0.05, 5.0 * blade, 0.0 };
  p.gravity = 981.0;
  p.newmark.rayleighMass = 2.0;
  p.newmark.rayleighStiffness = 0.01;
  p.loadProfile = WiltingLoadProfile::Sigmoid;
  p.loadTime = 8.0;
  switch (preset)
  {
    case WiltingPreset::Cucumber:
      p.contractionSide = WiltingContractionSide::Bottom;
      p.droopForce = 2.0;
      p.contractionForce = 1.0;
      break;
    case WiltingPreset::Tomato:
      p.contractionSide = WiltingContractionSide::Top;
      p.droopForce = 0.8;
      p.contractionForce = 2.0;
      break;
    case WiltingPreset::Watermelon:
      p.contractionSide = WiltingContractionSide::Bottom;
      p.droopForce = 1.5;
      p.contractionForce = 1.0;
      break;
    default:
      break;
  }
}

} // namespace plantmorph
