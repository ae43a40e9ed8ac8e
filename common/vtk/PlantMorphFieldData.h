// SPDX-License-Identifier: GPL-3.0-or-later
// Field data the VTK layers write: each source and filter records its parameters and results as one-value arrays
// (spec README: "each source writes its parameters as field data"). Module PlantMorph::VTKCommon; a wrapper usually writes them
// through plantmorph::FieldRecord (PlantMorphLayer.h), which uses these. Also how a core's large arrays become VTK
// arrays without a copy (AdoptArray).
#pragma once

#include "PlantMorphVTKCommonModule.h" // for export macro

#include "vtkCellArray.h"
#include "vtkDoubleArray.h" // what the wrappers writing field data used to get from here
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"

#include "plantmorph/memory/CloudArray.h"

#include <string>
#include <type_traits>

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

/// One vertex cell per point, for a cloud of `count` points (offsets and connectivity 0, 1, ..., filled threaded):
/// what a point-cloud output needs to be drawn and picked. 32-bit ids when they fit (half the memory), in memory
/// asked for huge pages (a cloud's cells are fresh memory on every update).
PLANTMORPHVTKCOMMON_EXPORT vtkSmartPointer<vtkCellArray> VertexCells(vtkIdType count);

/// A VTK array of `components` per tuple that takes over the memory of `values` (no copy; VTK frees it with
/// std::free, as CloudArray's memory is meant to be). `values` is left empty. VirtualScanner's cloud and
/// TreeFromSketchSource's mesh reach their outputs this way.
template <class ArrayT, class T, bool HugePages>
vtkSmartPointer<ArrayT> AdoptArray(CloudArray<T, HugePages>& values, int components, const char* name)
{
  static_assert(std::is_same<typename ArrayT::ValueType, T>::value, "the core's type is the output's");
  auto array = vtkSmartPointer<ArrayT>::New();
  if (name)
    array->SetName(name);
  array->SetNumberOfComponents(components);
  const auto size = static_cast<vtkIdType>(values.size());
  if (T* held = values.Release())
    array->SetArray(held, size, 0, ArrayT::VTK_DATA_ARRAY_FREE);
  return array;
}

} // namespace plantmorph
