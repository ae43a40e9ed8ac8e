// SPDX-License-Identifier: GPL-3.0-or-later
// WiltingSimulator presets (docs/methods/wilting.md; paper 001 sec. 3): materials and loads for the paper's leaves.
//   Cucumber: droop with the margin and apex curling down (contraction towards the base on the voxels' bottom
//             nodes, earlier than the droop; the -x half drooping a little more), fitted to the paper's measured tip trajectory on a leaf of the
//             measured size (examples/calibrate_wilting.py; docs/wilting-calibration.md) at Resolution 14 on a 20 cm
//             leaf, AnchorRadius 3, TimeStep 1/60 s, one Newton iteration; in physical units (WiltingUnits), so
//             verified at Resolution 14-30 on 5-40 cm leaves. Every preset holds the leaf as the fit did, within
//             3 / 22.308 of its longest side of the base (anchorFraction; AnchorRadius is not used), so the same
//             preset gives the same wilting in leaf lengths and seconds on leaves of any size.
//   Tomato:   the margin curls up (loads on the top nodes), less droop.
//   Watermelon: a lobed leaf (feed it a palmate LeafOutlineSource blade); droop, lobes curling down.
// The paper's fitted triples (mass, stiffness, damping) print as veins "1000, 20000, 500", margin "5000, 8000,
// 500", rest "8000, 10000, 500" without units or decimal points; Tomato and Watermelon keep their stiffness ratios
// (veins 2, margin 0.8, blade 1) with densities in g, cm, s (not fitted: no measurements); the Cucumber's are fitted.
// All three are in physical units (Young's moduli and pressures in dyn/cm^2; WiltingLatticeOf).
#pragma once

#include "WiltingSimulation.h"

#include <string>

namespace plantmorph
{

enum class WiltingPreset : int
{
  Custom = 0,
  Cucumber = 1,
  Tomato = 2,
  Watermelon = 3
};
inline constexpr int WiltingPresetCount = 4;

std::string WiltingPresetName(WiltingPreset preset);
/// Sets the preset's materials, loads, profile and damping in `parameters` (Custom leaves them alone).
void ApplyWiltingPreset(WiltingPreset preset, WiltingParameters& parameters);
/// What a named preset sets, for the read-only PresetValues box of WiltingSimulator's panel: a title line, then one
/// "Property = value" line per property it sets (materials as density, stiffness, damping; enumerations as their
/// numbers), each value the shortest text that reads back as exactly the preset's, then a line on the units.
std::string DescribeWiltingPreset(WiltingPreset preset);

} // namespace plantmorph
