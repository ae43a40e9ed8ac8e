// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkLeafCurlFilter.h"

#include "PlantMorphLayer.h"
#include "LeafCurl.h"

#include <plantmorph/DataContract.h>

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolygon.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkLeafCurlFilter);

namespace
{
/// Under MPI the blade curls once, on rank 0, whole: the curl follows the midvein and half-widths of the whole blade.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank;

/// Recomputes the cell normals of the polygons (triangles, quads, polygons) from the curled points.
void RecomputePolygonNormals(vtkPolyData* output, vtkDataArray* cellNormals)
{
  const vtkIdType first = output->GetNumberOfVerts() + output->GetNumberOfLines();
  vtkPoints* points = output->GetPoints();
  auto polys = vtk::TakeSmartPointer(output->GetPolys()->NewIterator());
  vtkIdType cellId = first;
  for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell(), ++cellId)
  {
    vtkIdType size = 0;
    const vtkIdType* ids = nullptr;
    polys->GetCurrentCell(size, ids);
    double n[3] = { 0.0, 0.0, 0.0 };
    vtkPolygon::ComputeNormal(points, static_cast<int>(size), ids, n);
    cellNormals->SetTuple(cellId, n);
  }
}

/// The blade's points and LeafUV as flat arrays for the core (read in parallel: GetTuple into a local buffer is
/// thread-safe); "" or why the blade cannot be curled.
std::string ReadBlade(vtkPolyData* input, std::vector<double>& xyz, std::vector<double>& uv)
{
  vtkDataArray* leafUV = input->GetPointData()->GetArray(plantmorph::arrays::LeafUV);
  if (!leafUV || leafUV->GetNumberOfComponents() != 2)
  {
    return std::string("the input has no point array ") + plantmorph::arrays::LeafUV +
      " with 2 components (u in [-0.5, 0.5] across the blade, 0 on the midvein; v in [0, 1] along it), which "
      "LeafCurlFilter needs to find the midvein: curl a LeafOutlineSource blade, or a filter's output that passed "
      "LeafUV on";
  }
  const vtkIdType count = input->GetNumberOfPoints();
  vtkPoints* points = input->GetPoints();
  xyz.resize(3 * static_cast<std::size_t>(count));
  uv.resize(2 * static_cast<std::size_t>(count));
  vtkSMPTools::For(0, count, [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
    {
      points->GetPoint(i, xyz.data() + 3 * i);
      leafUV->GetTuple(i, uv.data() + 2 * i);
    }
  });
  return {};
}

/// A new array of `count` 3-component tuples of the type and name of `normals`, or null when `normals` is not a
/// 3-component array.
vtkSmartPointer<vtkDataArray> NewNormalsLike(vtkDataArray* normals, vtkIdType count)
{
  if (!normals || normals->GetNumberOfComponents() != 3)
  {
    return nullptr;
  }
  auto result = vtk::TakeSmartPointer(normals->NewInstance());
  result->SetName(normals->GetName());
  result->SetNumberOfComponents(3);
  result->SetNumberOfTuples(count);
  return result;
}

/// Every point curled into `outPoints`, and its normal from `inNormals` into `outNormals` when that is not null;
/// in blocks, each in parallel, `progress` (fraction done) told between blocks. False when it asks to stop.
bool CurlPoints(const plantmorph::LeafCurl& curl, const std::vector<double>& xyz, vtkDataArray* inNormals,
  vtkPoints* outPoints, vtkDataArray* outNormals, const std::function<bool(double)>& progress)
{
  const vtkIdType count = outPoints->GetNumberOfPoints();
  const vtkIdType block = std::max<vtkIdType>(65536, count / 20);
  for (vtkIdType start = 0; start < count; start += block)
  {
    const vtkIdType stop = std::min(count, start + block);
    vtkSMPTools::For(start, stop, [&](vtkIdType begin, vtkIdType end) {
      double out[3];
      double normal[3];
      for (vtkIdType i = begin; i < end; ++i)
      {
        if (outNormals)
        {
          inNormals->GetTuple(i, normal);
        }
        curl.Map(static_cast<std::size_t>(i), xyz.data() + 3 * i, out, outNormals ? normal : nullptr);
        outPoints->SetPoint(i, out);
        if (outNormals)
        {
          outNormals->SetTuple(i, normal);
        }
      }
    });
    if (!progress(static_cast<double>(stop) / static_cast<double>(count)))
    {
      return false;
    }
  }
  return true;
}

/// The input's cell normals, those of the polygons recomputed from the curled points (others kept).
void CurlCellNormals(vtkPolyData* input, vtkPolyData* output)
{
  vtkDataArray* inCellNormals = input->GetCellData()->GetNormals();
  if (inCellNormals && inCellNormals->GetNumberOfComponents() == 3 && output->GetNumberOfPolys() > 0)
  {
    auto outCellNormals = vtk::TakeSmartPointer(inCellNormals->NewInstance());
    outCellNormals->DeepCopy(inCellNormals);
    RecomputePolygonNormals(output, outCellNormals);
    output->GetCellData()->SetNormals(outCellNormals);
  }
}

/// The curled points (new points of the input's precision) and normals (new, of the normals' type: the input's are
/// shared with it) of `input` into `output`, and its polygons' cell normals recomputed; false when `progress` asks
/// to stop.
bool CurlInto(const plantmorph::LeafCurl& curl, const std::vector<double>& xyz, vtkPolyData* input, vtkPolyData* output,
  const std::function<bool(double)>& progress)
{
  vtkNew<vtkPoints> outPoints;
  outPoints->SetDataType(input->GetPoints()->GetDataType());
  outPoints->SetNumberOfPoints(input->GetNumberOfPoints());
  vtkDataArray* inNormals = input->GetPointData()->GetNormals();
  const vtkSmartPointer<vtkDataArray> outNormals = NewNormalsLike(inNormals, input->GetNumberOfPoints());
  if (!CurlPoints(curl, xyz, inNormals, outPoints, outNormals, progress))
  {
    return false;
  }
  output->SetPoints(outPoints);
  if (outNormals)
  {
    output->GetPointData()->SetNormals(outNormals);
  }
  CurlCellNormals(input, output);
  return true;
}
} // namespace

//------------------------------------------------------------------------------
vtkLeafCurlFilter::vtkLeafCurlFilter() = default;

//------------------------------------------------------------------------------
void vtkLeafCurlFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LongitudinalAngle: " << this->LongitudinalAngle << "\n";
  os << indent << "TransverseAngle: " << this->TransverseAngle << "\n";
  os << indent << "TransverseCenter: " << this->TransverseCenter << "\n";
}

//------------------------------------------------------------------------------
int vtkLeafCurlFilter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the curled leaf", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkLeafCurlFilter::Execute(plantmorph::Run& run)
{
  vtkPolyData* input = run.Input<vtkPolyData>(0);
  vtkPolyData* output = run.Output<vtkPolyData>(0);
  if (!input)
  {
    return;
  }
  plantmorph::LeafCurlParameters parameters;
  parameters.longitudinalAngle = this->LongitudinalAngle;
  parameters.transverseAngle = this->TransverseAngle;
  parameters.transverseCenter = this->TransverseCenter;
  run.Check(plantmorph::ValidateLeafCurl(parameters));
  if (input->GetNumberOfPoints() == 0)
  {
    run.Warn("the Input is empty (no points): nothing to curl, the output is empty");
    return;
  }
  std::vector<double> xyz, uv;
  run.Check(ReadBlade(input, xyz, uv));
  plantmorph::LeafCurl curl;
  run.Check(curl.Setup(parameters, static_cast<std::size_t>(input->GetNumberOfPoints()), xyz.data(), uv.data()));
  run.UpdateProgress(0.1);
  output->ShallowCopy(input);
  plantmorph::FieldRecord record;
  record.Add("LongitudinalAngle", this->LongitudinalAngle);
  record.Add("TransverseAngle", this->TransverseAngle);
  record.Add("TransverseCenter", this->TransverseCenter);
  record.WriteTo(output);
  // An identity curl keeps the input's own points: bit-identical.
  if (!curl.IsIdentity() && !CurlInto(curl, xyz, input, output, run.Progress(0.1, 0.95)))
  {
    run.Stop();
  }
  run.UpdateProgress(1.0);
}
