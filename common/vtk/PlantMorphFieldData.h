// SPDX-License-Identifier: GPL-3.0-or-later
// Field data the VTK layers write: each source and filter records its parameters and results as one-value arrays
// (spec README: "each source writes its parameters as field data"). Module PlantMorph::VTKCommon; a wrapper usually
// writes them through plantmorph::FieldRecord (PlantMorphLayer.h), which uses these.
#pragma once

#include "PlantMorphVTKCommonModule.h" // for export macro

#include "vtkDoubleArray.h" // what the wrappers writing field data used to get from here
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkStringArray.h"

#include <string>

namespace plantmorph
{

/// Adds (or replaces) the one-value double array `name`.
PLANTMORPHVTKCOMMON_EXPORT void AddFieldValue(vtkFieldData* fd, const char* name, double value);

/// Adds (or replaces) the one-value string array `name`.
PLANTMORPHVTKCOMMON_EXPORT void AddFieldString(vtkFieldData* fd, const char* name, const std::string& value);

/// The PlantMorph.* parameters of `fd` as text, one "Name = value" a line ("PlantMorph." dropped): a one-value
/// array as its value, a tuple with component names as one line per component (PlantMorph.Curvature's Mu ->
/// "CurvatureMu = ..."), other arrays as their tuples in parentheses. For the panels' read-only PresetValues boxes.
PLANTMORPHVTKCOMMON_EXPORT std::string FormatParameters(vtkFieldData* fd);

} // namespace plantmorph
