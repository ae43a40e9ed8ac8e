// SPDX-License-Identifier: GPL-3.0-or-later
// Presets of Model A (deformed rectangle): the ginkgo leaf of paper 000 eq. (1), the margin types of its Fig. 1 and
// the base/apex shapes of its Fig. 2, each written as sinusoid terms so users can start from one and edit its rows.
//
// Shapes are built from a width profile G(v): x = a_x*u*G(v) (the margin is the graph x = a_x*G(v)/2 over y, so it
// never folds while G > 0 on (0, 1)); base and apex shapes come from y terms (1 - v)*B*b_y*cos(pi*u) (B < 0 rounds
// the base, B > 0 notches it: cordate) and v*A*b_y*cos(pi*u) (A > 0 rounds the apex, A < 0 notches it: emarginate).
#pragma once

#include "DeformedRectangleModel.h"

#include <string>

namespace plantmorph
{

enum class DeformedRectanglePreset : int
{
  Custom = 0,                      ///< the user's Width, Length and Terms
  Ginkgo = 1,                      ///< paper 000 eq. (1): fan with an erose upper margin, a_x = 1.1*b_y
  Entire = 2,                      ///< Fig. 1a: smooth (entire) ovate margin
  Serrate = 3,                     ///< Fig. 1b: serrate margin, forward-pointing teeth
  Lobed = 4,                       ///< Fig. 1c: shallowly lobed margin
  Parted = 5,                      ///< Fig. 1d: deeply parted margin
  AcuteBaseAcuteApex = 6,          ///< Fig. 2a
  RoundedBaseAcuminateApex = 7,    ///< Fig. 2b
  CordateBaseRoundedApex = 8,      ///< Fig. 2c
  AcuminateBaseEmarginateApex = 9, ///< Fig. 2d
};

inline constexpr int DeformedRectanglePresetCount = 10;

/// The preset's parameters for a leaf of initial rectangle height `length` (b_y); the width a_x follows the preset's
/// proportion. Custom returns default parameters with no terms (a plain rectangle of width 1.1*length).
DeformedRectangleParameters MakeDeformedRectanglePreset(DeformedRectanglePreset preset, double length);

/// A short name ("Ginkgo", "Serrate", ...), used in field data.
std::string PresetName(DeformedRectanglePreset preset);

} // namespace plantmorph
