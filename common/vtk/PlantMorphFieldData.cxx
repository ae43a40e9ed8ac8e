// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantMorphFieldData.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkNew.h"
#include "vtkSMPTools.h"
#include "vtkStringArray.h"

#include <sstream>

namespace plantmorph
{

vtkSmartPointer<vtkCellArray> VertexCells(vtkIdType count)
{
  vtkNew<vtkIdTypeArray> offsets;
  vtkNew<vtkIdTypeArray> connectivity;
  offsets->SetNumberOfTuples(count + 1);
  connectivity->SetNumberOfTuples(count);
  vtkSMPTools::For(0, count + 1, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
    {
      offsets->SetValue(i, i);
      if (i < count)
        connectivity->SetValue(i, i);
    }
  });
  auto verts = vtkSmartPointer<vtkCellArray>::New();
  verts->SetData(offsets, connectivity);
  return verts;
}

/// Adds (or replaces) the one-value double array `name`.
void AddFieldValue(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->InsertNextValue(value);
  fd->AddArray(array);
}

/// Adds (or replaces) the one-value string array `name`.
void AddFieldString(vtkFieldData* fd, const char* name, const std::string& value)
{
  vtkNew<vtkStringArray> array;
  array->SetName(name);
  array->InsertNextValue(value);
  fd->AddArray(array);
}

/// The PlantMorph.* parameters of `fd` as text, one "Name = value" a line ("PlantMorph." dropped): a one-value
/// array as its value, a tuple with component names as one line per component (PlantMorph.Curvature's Mu ->
/// "CurvatureMu = ..."), other arrays as their tuples in parentheses. For the panels' read-only PresetValues boxes.
std::string FormatParameters(vtkFieldData* fd)
{
  std::ostringstream text;
  const std::string prefix = "PlantMorph.";
  for (int a = 0; a < fd->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = fd->GetAbstractArray(a);
    const std::string full = array && array->GetName() ? array->GetName() : "";
    if (full.compare(0, prefix.size(), prefix) != 0 || array->GetNumberOfTuples() == 0)
      continue;
    const std::string name = full.substr(prefix.size());
    const int components = array->GetNumberOfComponents();
    if (array->GetNumberOfTuples() == 1 && components == 1)
    {
      text << name << " = " << array->GetVariantValue(0).ToString() << "\n";
    }
    else if (array->GetNumberOfTuples() == 1 && array->GetComponentName(0))
    {
      for (int c = 0; c < components; ++c)
        text << name << (array->GetComponentName(c) ? array->GetComponentName(c) : std::to_string(c).c_str()) << " = "
             << array->GetVariantValue(c).ToString() << "\n";
    }
    else
    {
      text << name << " =";
      for (vtkIdType t = 0; t < array->GetNumberOfTuples(); ++t)
      {
        text << (t ? ", (" : " (");
        for (int c = 0; c < components; ++c)
          text << (c ? " " : "") << array->GetVariantValue(t * components + c).ToString();
        text << ")";
      }
      text << "\n";
    }
  }
  return text.str();
}

} // namespace plantmorph
