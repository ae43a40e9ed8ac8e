// SPDX-License-Identifier: GPL-3.0-or-later
// Presets of Model B (space-curve leaf) reproducing paper 002's figures. The paper gives mu, lambda and eta; where
// it gives no numbers (Fig. 4's notch) the values are chosen so the figure's feature shows, and say so below.
#pragma once

#include "SpaceCurveLeaf.h"

#include <string>

namespace plantmorph
{

enum class SpaceCurvePreset : int
{
  Custom = 0,            ///< the user's curvature, torsion and midvein properties
  Figure1 = 1,           ///< triangular curvature, mu = 2, lambda = 0.7: a flat, broad leaf
  Figure2 = 2,           ///< triangular curvature, mu = 6, lambda = 0.9: a flat leaf with a strongly bent tip
  Figure3 = 3,           ///< exponential curvature, lambda = 0, u3 = 0.001, h*S = 30: turns as it grows (phototropism)
  Figure4 = 4,           ///< notched apex ("duck tongue", eq. (8))
  Figure5 = 5,           ///< 3-D: curvature mu = 5 and torsion eta = 4, lambda = 0.95; the midvein is the chord
  Figure6 = 6,           ///< Fig. 5 with the midvein projected from the margins onto the symmetry plane
  Figure8ThreeLobes = 7, ///< palmate, 3 lobes (Fig. 8; numbers chosen, the paper prints none)
  Figure8FiveLobes = 8,  ///< palmate, 5 lobes (Fig. 8; numbers chosen, the paper prints none)
  Watermelon = 9,        ///< Fig. 8's five lobes, each pinnately lobed: two sub-lobes a side (not in the paper)
  WatermelonPinnatifid = 10, ///< the same, deeply lobed: sinuses cut nearly to the base, the middle lobe longest
};

inline constexpr int SpaceCurvePresetCount = 11;

/// The preset's parameters for a half-margin of arc length `length` (Custom: the default parameters).
SpaceCurveParameters MakeSpaceCurvePreset(SpaceCurvePreset preset, double length);

/// A short name ("Paper002Figure1", ...), used in field data.
std::string SpaceCurvePresetName(SpaceCurvePreset preset);

} // namespace plantmorph
