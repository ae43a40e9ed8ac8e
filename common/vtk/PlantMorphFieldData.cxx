// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantMorphFieldData.h"
#include "PlantMorphAlgorithmHooks.h" // SMPFor

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkStringArray.h"
#include "vtkTypeInt32Array.h"
#include "vtkTypeInt64Array.h"

#include <cstdint>
#include <limits>
#include <sstream>

namespace plantmorph
{

namespace
{
/// The vertex cells of VertexCells with ids of IdArray's type, in CloudArray memory (huge pages) adopted by VTK.
template <class IdArray>
vtkSmartPointer<vtkCellArray> VertexCellsOf(vtkIdType count)
{
  using Id = typename IdArray::ValueType;
  CloudArray<Id> offsets, connectivity;
  offsets.resize(static_cast<std::size_t>(count) + 1);
  connectivity.resize(static_cast<std::size_t>(count));
  Id* off = offsets.data();
  Id* conn = connectivity.data();
  // SMPFor, not vtkSMPTools::For: ParaView starts vtkSMPTools on its Sequential backend, and the readers and filters
  // that call this are not all inside a threaded scope.
  ForEachIndex(
    SMPFor(), static_cast<std::size_t>(count), [&](std::size_t i) { off[i] = conn[i] = static_cast<Id>(i); },
    std::size_t(1) << 16);
  off[count] = static_cast<Id>(count);
  auto verts = vtkSmartPointer<vtkCellArray>::New();
  verts->SetData(AdoptArray<IdArray>(offsets, 1, nullptr), AdoptArray<IdArray>(connectivity, 1, nullptr));
  return verts;
}
} // namespace

vtkSmartPointer<vtkCellArray> VertexCells(vtkIdType count)
{
  if (count < std::numeric_limits<std::int32_t>::max())
    return VertexCellsOf<vtkTypeInt32Array>(count);
  return VertexCellsOf<vtkTypeInt64Array>(count);
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
