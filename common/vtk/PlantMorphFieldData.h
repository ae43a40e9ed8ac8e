// Field data the VTK layers write: each source and filter records its parameters and results as one-value arrays
// (spec README: "each source writes its parameters as field data"). Header-only, for the VTK modules (the rest of
// common/ is VTK-free).
#pragma once

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkStringArray.h"

#include <string>

namespace plantmorph
{

/// Adds (or replaces) the one-value double array `name`.
inline void AddFieldValue(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->InsertNextValue(value);
  fd->AddArray(array);
}

/// Adds (or replaces) the one-value string array `name`.
inline void AddFieldString(vtkFieldData* fd, const char* name, const std::string& value)
{
  vtkNew<vtkStringArray> array;
  array->SetName(name);
  array->InsertNextValue(value);
  fd->AddArray(array);
}

} // namespace plantmorph
