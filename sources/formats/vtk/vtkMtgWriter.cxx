// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkMtgWriter.h"

#include "MtgText.h"

#include "PlantMorphLayer.h"
#include "WriterPieces.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkMtgWriter);

namespace
{
/// The whole input gathered on the first rank, which writes the file.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank;

/// The input's lines as branches; "" or what is missing.
std::string Branches(vtkPolyData* input, std::vector<plantmorph::MtgTreeBranch>& branches)
{
  const std::string hint = " (write a tree skeleton: TreeFromSketchSource's Skeleton output, port 1, or polylines with "
                           "cell arrays BranchId and ParentId and a point array Radius)";
  vtkCellArray* lines = input ? input->GetLines() : nullptr;
  if (!lines || lines->GetNumberOfCells() == 0)
  {
    return "the input has no lines" + hint;
  }
  vtkDataArray* ids = input->GetCellData()->GetArray("BranchId");
  vtkDataArray* parents = input->GetCellData()->GetArray("ParentId");
  vtkDataArray* radius = input->GetPointData()->GetArray("Radius");
  if (!ids || !parents)
  {
    return std::string("the input has no cell array ") + (ids ? "ParentId" : "BranchId") + hint;
  }
  vtkNew<vtkIdList> pointIds;
  vtkIdType cell = input->GetNumberOfVerts();
  for (lines->InitTraversal(); lines->GetNextCell(pointIds); ++cell)
  {
    const double id = ids->GetComponent(cell, 0), parent = parents->GetComponent(cell, 0);
    if (!(std::abs(id) < 9e15) || id != std::floor(id) || !(std::abs(parent) < 9e15) || parent != std::floor(parent))
    {
      return "line " + std::to_string(cell - input->GetNumberOfVerts()) +
        " has a BranchId or ParentId that is not a whole number";
    }
    plantmorph::MtgTreeBranch b;
    b.id = static_cast<long long>(id);
    b.parentId = static_cast<long long>(parent);
    for (vtkIdType k = 0; k < pointIds->GetNumberOfIds(); ++k)
    {
      std::array<double, 3> p;
      input->GetPoint(pointIds->GetId(k), p.data());
      b.points.push_back(p);
      if (radius)
      {
        b.radii.push_back(radius->GetComponent(pointIds->GetId(k), 0));
      }
    }
    branches.push_back(std::move(b));
  }
  return {};
}
} // namespace

//------------------------------------------------------------------------------
vtkMtgWriter::vtkMtgWriter() = default;

//------------------------------------------------------------------------------
vtkMtgWriter::~vtkMtgWriter()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
void vtkMtgWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}

//------------------------------------------------------------------------------
int vtkMtgWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

//------------------------------------------------------------------------------
vtkTypeBool vtkMtgWriter::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (request->Has(vtkStreamingDemandDrivenPipeline::REQUEST_UPDATE_EXTENT()))
  {
    plantmorph::RequestRankPiece(inputVector[0]->GetInformationObject(0));
    return 1;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkMtgWriter::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the MTG file", request, inputVector, outputVector,
    [this](plantmorph::Run& run) { this->Execute(run); });
}

//------------------------------------------------------------------------------
void vtkMtgWriter::Execute(plantmorph::Run& run)
{
  if (!this->FileName || !*this->FileName)
  {
    run.Fail("FileName is not set: give the MTG file to write (*.mtg)");
  }
  std::vector<plantmorph::MtgTreeBranch> branches;
  run.Check(Branches(run.Input<vtkPolyData>(0), branches));
  std::ostringstream text; // written whole before the file is touched: a refused tree leaves it as it was
  const std::string error = plantmorph::WriteMtg(text, branches);
  if (!error.empty())
  {
    run.Fail("FileName '" + std::string(this->FileName) + "': " + error);
  }
  std::ofstream file(this->FileName, std::ios::binary | std::ios::trunc);
  if (!(file << text.str()) || !file.flush())
  {
    run.Fail("FileName '" + std::string(this->FileName) + "' cannot be written");
  }
}
