#include "vtkLeafFitFilter.h"
#include "PlantMorphAlgorithmHooks.h"

#include "LeafFit.h"
#include "PlantMorphFieldData.h"

#include <plantmorph/DataContract.h>
#include <plantmorph/RangeError.h>

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"

#include <cmath>
#include <map>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkLeafFitFilter);

namespace
{
template <typename T>
vtkSmartPointer<T> NewArray(const char* name, int components)
{
  auto array = vtkSmartPointer<T>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  return array;
}

/// The blade and outline of one leaf appended to the outputs.
void AppendLeaf(const plantmorph::LeafFitResult& r, int leafId, vtkPoints* points, vtkCellArray* triangles,
  vtkPolyData* blade, vtkPoints* outlinePoints, vtkCellArray* lines, vtkPolyData* outline)
{
  const vtkIdType offset = points->GetNumberOfPoints();
  auto get = [](vtkPolyData* pd, const char* name) { return pd->GetPointData()->GetArray(name); };
  for (std::size_t i = 0; i < r.points.size(); ++i)
  {
    points->InsertNextPoint(r.points[i].data());
    get(blade, plantmorph::arrays::LeafUV)->InsertNextTuple2(r.leafUV[i].x(), r.leafUV[i].y());
    get(blade, plantmorph::arrays::TCoords)->InsertNextTuple2(r.tcoords[i].x(), r.tcoords[i].y());
    get(blade, plantmorph::arrays::Region)->InsertNextTuple1(r.region[i]);
    get(blade, plantmorph::arrays::Normals)->InsertNextTuple3(r.normals[i].x(), r.normals[i].y(), r.normals[i].z());
    get(blade, "LeafId")->InsertNextTuple1(leafId);
    get(blade, "Support")->InsertNextTuple1(r.support[i]);
  }
  for (const auto& t : r.triangles)
  {
    const vtkIdType ids[3] = { offset + t[0], offset + t[1], offset + t[2] };
    triangles->InsertNextCell(3, ids);
    blade->GetCellData()->GetArray(plantmorph::arrays::Region)->InsertNextTuple1(plantmorph::RegionBlade);
    blade->GetCellData()->GetArray("LeafId")->InsertNextTuple1(leafId);
  }
  const std::vector<int>* polylines[3] = { &r.leftMargin, &r.rightMargin, &r.midvein };
  const int regions[3] = { plantmorph::RegionMargin, plantmorph::RegionMargin, plantmorph::RegionMidvein };
  for (int k = 0; k < 3; ++k)
  {
    lines->InsertNextCell(static_cast<vtkIdType>(polylines[k]->size()));
    for (int id : *polylines[k])
    {
      lines->InsertCellPoint(outlinePoints->InsertNextPoint(r.points[id].data()));
      outline->GetPointData()->GetArray(plantmorph::arrays::LeafUV)->InsertNextTuple2(r.leafUV[id].x(), r.leafUV[id].y());
      outline->GetPointData()->GetArray("LeafId")->InsertNextTuple1(leafId);
    }
    outline->GetCellData()->GetArray(plantmorph::arrays::Region)->InsertNextTuple1(regions[k]);
    outline->GetCellData()->GetArray("LeafId")->InsertNextTuple1(leafId);
  }
  // The fitted Model C control points, for LeafOutlineSource (B-spline, Custom).
  const std::vector<Eigen::Vector3d>* model[6] = { &r.modelMidvein, &r.modelLeftMargin, &r.modelRightMargin,
    &r.flatMidvein, &r.flatLeftMargin, &r.flatRightMargin };
  const char* names[6] = { "MidveinPoints", "LeftMarginPoints", "RightMarginPoints", "FlatMidveinPoints",
    "FlatLeftMarginPoints", "FlatRightMarginPoints" };
  for (int k = 0; k < 6; ++k)
  {
    const std::string name = "PlantMorph.FitModel." + std::to_string(leafId) + "." + names[k];
    auto array = NewArray<vtkDoubleArray>(name.c_str(), 3);
    for (const auto& p : *model[k])
      array->InsertNextTuple(p.data());
    blade->GetFieldData()->AddArray(array);
  }
}
} // namespace

vtkLeafFitFilter::vtkLeafFitFilter()
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(4);
}

void vtkLeafFitFilter::SetLeafIdArray(const char* name)
{
  const std::string value = name ? name : "";
  if (value != this->LeafIdArray)
  {
    this->LeafIdArray = value;
    this->Modified();
  }
}

int vtkLeafFitFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

int vtkLeafFitFilter::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 2 ? "vtkTable" : "vtkPolyData");
  return 1;
}

int vtkLeafFitFilter::RequestData(vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPointSet* input = vtkPointSet::GetData(inputVector[0], 0);
  vtkPolyData* blade = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* outline = vtkPolyData::GetData(outputVector, 1);
  vtkTable* traits = vtkTable::GetData(outputVector, 2);
  vtkPolyData* scan = vtkPolyData::GetData(outputVector, 3);
  if (!input || !blade || !outline || !traits || !scan)
    return 0;
  const vtkIdType n = input->GetNumberOfPoints();
  if (n == 0)
    return 1; // an empty piece (MPI ranks without leaves): empty outputs, no error

  // Options and the leaves' points.
  plantmorph::LeafFitParameters options;
  options.up = Eigen::Vector3d::Unit(this->UpAxis);
  if (this->UseBasePoint)
    options.basePoint = Eigen::Vector3d(this->BasePoint[0], this->BasePoint[1], this->BasePoint[2]);
  options.surfaceSmoothing = this->SurfaceSmoothing;
  options.outlineSmoothing = this->OutlineSmoothing;
  options.outlineControlPoints = this->OutlineControlPoints;
  options.outlierSigma = this->OutlierSigma;
  options.resolution = this->Resolution;
  options.modelControlPoints = this->ModelControlPoints;
  std::string error = plantmorph::ValidateLeafFitParameters(options);
  if (error.empty() && !(std::isfinite(this->Scale) && this->Scale > 0.0))
    error = plantmorph::OutOfRange("Scale", this->Scale, "(0, inf)");
  vtkDataArray* ids = nullptr;
  if (error.empty() && !this->LeafIdArray.empty())
  {
    ids = input->GetPointData()->GetArray(this->LeafIdArray.c_str());
    if (!ids || ids->GetNumberOfComponents() != 1)
      error = "LeafIdArray: the input has no one-component point array named '" + this->LeafIdArray + "'";
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  std::vector<Eigen::Vector3d> all(n);
  std::vector<int> leafOf(n, 0);
  std::map<int, std::vector<vtkIdType>> members;
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    all[i] = this->Scale * Eigen::Vector3d(p[0], p[1], p[2]);
    const double id = ids ? ids->GetComponent(i, 0) : 0.0;
    leafOf[i] = std::isfinite(id) ? static_cast<int>(std::lround(id)) : -1;
    members[leafOf[i]].push_back(i);
  }
  std::vector<int> leafIds;
  std::vector<std::vector<Eigen::Vector3d>> leaves;
  for (const auto& m : members)
  {
    leafIds.push_back(m.first);
    leaves.emplace_back();
    for (vtkIdType i : m.second)
      leaves.back().push_back(all[i]);
  }
  const plantmorph::ParallelFor smp = plantmorph::SMPFor(1); // one leaf per task: leaves differ in size
  const std::vector<plantmorph::LeafFitResult> results = plantmorph::FitLeaves(leaves, options, smp);
  for (std::size_t k = 0; k < results.size(); ++k)
    if (!results[k].error.empty())
    {
      std::ostringstream message;
      message << "leaf " << leafIds[k] << " (" << leaves[k].size() << " points): " << results[k].error;
      vtkErrorMacro(<< message.str());
      return 0;
    }

  // Blade and Outline.
  vtkNew<vtkPoints> points, outlinePoints;
  points->SetDataTypeToDouble();
  outlinePoints->SetDataTypeToDouble();
  vtkNew<vtkCellArray> triangles, lines;
  blade->GetPointData()->AddArray(NewArray<vtkDoubleArray>(plantmorph::arrays::LeafUV, 2));
  blade->GetPointData()->SetTCoords(NewArray<vtkFloatArray>(plantmorph::arrays::TCoords, 2));
  blade->GetPointData()->AddArray(NewArray<vtkIntArray>(plantmorph::arrays::Region, 1));
  blade->GetPointData()->SetNormals(NewArray<vtkFloatArray>(plantmorph::arrays::Normals, 3));
  blade->GetPointData()->AddArray(NewArray<vtkIntArray>("LeafId", 1));
  blade->GetPointData()->AddArray(NewArray<vtkDoubleArray>("Support", 1));
  blade->GetCellData()->AddArray(NewArray<vtkIntArray>(plantmorph::arrays::Region, 1));
  blade->GetCellData()->AddArray(NewArray<vtkIntArray>("LeafId", 1));
  outline->GetPointData()->AddArray(NewArray<vtkDoubleArray>(plantmorph::arrays::LeafUV, 2));
  outline->GetPointData()->AddArray(NewArray<vtkIntArray>("LeafId", 1));
  outline->GetCellData()->AddArray(NewArray<vtkIntArray>(plantmorph::arrays::Region, 1));
  outline->GetCellData()->AddArray(NewArray<vtkIntArray>("LeafId", 1));
  for (std::size_t k = 0; k < results.size(); ++k)
    AppendLeaf(results[k], leafIds[k], points, triangles, blade, outlinePoints, lines, outline);
  blade->SetPoints(points);
  blade->SetPolys(triangles);
  outline->SetPoints(outlinePoints);
  outline->SetLines(lines);
  plantmorph::AddFieldValue(blade->GetFieldData(), "PlantMorph.Scale", this->Scale);

  // Traits.
  auto leafColumn = NewArray<vtkIntArray>("LeafId", 1);
  traits->AddColumn(leafColumn);
  const std::vector<std::string> names = plantmorph::TraitNames();
  for (const std::string& name : names)
    traits->AddColumn(NewArray<vtkDoubleArray>(name.c_str(), 1));
  for (std::size_t k = 0; k < results.size(); ++k)
  {
    leafColumn->InsertNextValue(leafIds[k]);
    const std::vector<double> values = plantmorph::TraitValues(results[k].traits);
    for (std::size_t c = 0; c < names.size(); ++c)
      vtkDoubleArray::SafeDownCast(traits->GetColumnByName(names[c].c_str()))->InsertNextValue(values[c]);
  }

  // Scan: the scaled input points, their data, and the fit's per-point arrays.
  vtkNew<vtkPoints> scanPoints;
  scanPoints->SetDataTypeToDouble();
  scanPoints->SetNumberOfPoints(n);
  vtkNew<vtkCellArray> verts;
  for (vtkIdType i = 0; i < n; ++i)
  {
    scanPoints->SetPoint(i, all[i].data());
    verts->InsertNextCell(1, &i);
  }
  scan->SetPoints(scanPoints);
  scan->SetVerts(verts);
  scan->GetPointData()->PassData(input->GetPointData());
  auto distance = NewArray<vtkDoubleArray>("FitDistance", 1);
  auto inlier = NewArray<vtkUnsignedCharArray>("Inlier", 1);
  auto leafId = NewArray<vtkIntArray>("LeafId", 1);
  distance->SetNumberOfTuples(n);
  inlier->SetNumberOfTuples(n);
  leafId->SetNumberOfTuples(n);
  for (std::size_t k = 0; k < results.size(); ++k)
  {
    const std::vector<vtkIdType>& m = members[leafIds[k]];
    for (std::size_t j = 0; j < m.size(); ++j)
    {
      distance->SetValue(m[j], results[k].fitDistance[j]);
      inlier->SetValue(m[j], results[k].inlier[j]);
      leafId->SetValue(m[j], leafIds[k]);
    }
  }
  scan->GetPointData()->AddArray(distance);
  scan->GetPointData()->AddArray(inlier);
  scan->GetPointData()->AddArray(leafId);
  scan->GetPointData()->SetActiveScalars("FitDistance");
  return 1;
}

void vtkLeafFitFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Scale: " << this->Scale << "\n"
     << indent << "LeafIdArray: " << this->LeafIdArray << "\n"
     << indent << "UpAxis: " << this->UpAxis << "\n"
     << indent << "UseBasePoint: " << this->UseBasePoint << "\n"
     << indent << "SurfaceSmoothing: " << this->SurfaceSmoothing << "\n"
     << indent << "OutlineSmoothing: " << this->OutlineSmoothing << "\n"
     << indent << "OutlineControlPoints: " << this->OutlineControlPoints << "\n"
     << indent << "OutlierSigma: " << this->OutlierSigma << "\n"
     << indent << "Resolution: " << this->Resolution << "\n"
     << indent << "ModelControlPoints: " << this->ModelControlPoints << "\n";
}
