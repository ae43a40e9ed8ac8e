// SPDX-License-Identifier: GPL-3.0-or-later
#include "WiltingConversion.h"

#include "PlantMorphLayer.h"
#include "PlantMorphLeafExchange.h"
#include "WiltingFrames.h"
#include "WiltingPresets.h"
#include "vtkWiltingSimulator.h"

#include <plantmorph/DataContract.h>
#include <plantmorph/RangeError.h>

#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace plantmorph
{
namespace
{
/// The simulation's points: the surface's, then the veins' (they mark vein voxels through their Region and follow
/// the voxels like every surface point; they are not voxelised themselves).
void ReadPoints(vtkPolyData* input, vtkPolyData* veins, WiltingInput& in)
{
  const vtkIdType pointCount = input->GetNumberOfPoints();
  const vtkIdType veinCount = veins ? veins->GetNumberOfPoints() : 0;
  in.points.resize(static_cast<std::size_t>(pointCount + veinCount));
  for (vtkIdType i = 0; i < pointCount; ++i)
  {
    input->GetPoint(i, in.points[static_cast<std::size_t>(i)].data());
  }
  for (vtkIdType i = 0; i < veinCount; ++i)
  {
    veins->GetPoint(i, in.points[static_cast<std::size_t>(pointCount + i)].data());
  }
}

/// The surface's polygons as triangle fans.
void ReadTriangles(vtkPolyData* input, WiltingInput& in)
{
  auto polys = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell())
  {
    vtkIdType size = 0;
    const vtkIdType* ids = nullptr;
    polys->GetCurrentCell(size, ids);
    for (vtkIdType k = 1; k + 1 < size; ++k)
    {
      in.triangles.push_back({ static_cast<int>(ids[0]), static_cast<int>(ids[k]), static_cast<int>(ids[k + 1]) });
    }
  }
}

/// A one-component Region point array of `data`, or null.
vtkDataArray* RegionOf(vtkPolyData* data)
{
  vtkDataArray* region = data ? data->GetPointData()->GetArray(arrays::Region) : nullptr;
  return region && region->GetNumberOfComponents() == 1 ? region : nullptr;
}

/// Every point's Region when the surface or the veins have one (a point without one counts as blade); whether the
/// surface has one.
bool ReadRegions(vtkPolyData* input, vtkPolyData* veins, WiltingInput& in)
{
  const vtkIdType pointCount = input->GetNumberOfPoints();
  const vtkIdType veinCount = veins ? veins->GetNumberOfPoints() : 0;
  vtkDataArray* region = RegionOf(input);
  vtkDataArray* veinRegion = RegionOf(veins);
  if (region || veinRegion)
  {
    in.regions.assign(in.points.size(), RegionBlade);
    for (vtkIdType i = 0; region && i < pointCount; ++i)
    {
      in.regions[static_cast<std::size_t>(i)] = static_cast<int>(region->GetComponent(i, 0));
    }
    for (vtkIdType i = 0; veinRegion && i < veinCount; ++i)
    {
      in.regions[static_cast<std::size_t>(pointCount + i)] = static_cast<int>(veinRegion->GetComponent(i, 0));
    }
  }
  return region != nullptr;
}

/// LeafUV picks the base and the tip among the surface's points; vein points get NaN (never picked).
void ReadLeafUV(vtkPolyData* input, WiltingInput& in)
{
  vtkDataArray* uv = input->GetPointData()->GetArray(arrays::LeafUV);
  if (uv && uv->GetNumberOfComponents() == 2)
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    in.leafUV.assign(in.points.size(), Eigen::Vector2d(nan, nan));
    for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
    {
      in.leafUV[static_cast<std::size_t>(i)] = Eigen::Vector2d(uv->GetComponent(i, 0), uv->GetComponent(i, 1));
    }
  }
}

vtkSmartPointer<vtkDoubleArray> Vector3Array(const char* name, vtkIdType count)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->SetNumberOfTuples(count);
  return a;
}

/// The displacement of the simulation's `count` input points (the leaf's, then the veins'), embedded in the voxels.
std::vector<double> PointDisplacements(
  const WiltingSimulation& simulation, const WiltingNodeState& state, vtkIdType count)
{
  std::vector<double> d(3 * static_cast<std::size_t>(count));
  simulation.Embedding().Interpolate(state.q.data(), d.data());
  return d;
}

/// `count` points from `first` of the simulation's input points, moved by `d`, and their Displacement array.
void MovedPoints(const WiltingSimulation& simulation, const std::vector<double>& d, std::size_t first, vtkIdType count,
  vtkPoints* points, vtkDoubleArray* displacement)
{
  const std::vector<Eigen::Vector3d>& rest = simulation.InputPoints();
  points->SetNumberOfPoints(count);
  for (vtkIdType i = 0; i < count; ++i)
  {
    const std::size_t k = first + static_cast<std::size_t>(i);
    const double* di = d.data() + 3 * k;
    const Eigen::Vector3d& x = rest[k];
    // At t = 0 the displacement is exactly 0, so the points are the input's.
    points->SetPoint(i, x[0] + di[0], x[1] + di[1], x[2] + di[2]);
    displacement->SetTuple(i, di);
  }
}

/// Port 0: the moved input (the first of the simulation's points; the veins' follow), every array kept.
void WriteMovedLeaf(const WiltingSimulation& simulation, vtkPolyData* input, const std::vector<double>& d,
  double frameTime, vtkPolyData* output)
{
  const vtkIdType pointCount = input->GetNumberOfPoints();
  output->ShallowCopy(input);
  vtkNew<vtkPoints> points;
  points->SetDataType(input->GetPoints()->GetDataType());
  auto displacement = Vector3Array("Displacement", pointCount);
  MovedPoints(simulation, d, 0, pointCount, points, displacement);
  output->SetPoints(points);
  output->GetPointData()->AddArray(displacement);
  output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), frameTime);
}

/// Port 3: the moved veins, every array kept, plus Displacement.
void WriteMovedVeins(const WiltingSimulation& simulation, vtkIdType pointCount, vtkPolyData* veins,
  const std::vector<double>& d, double frameTime, vtkPolyData* movedVeins)
{
  const vtkIdType veinCount = veins ? veins->GetNumberOfPoints() : 0;
  if (veins && veinCount > 0)
  {
    movedVeins->ShallowCopy(veins);
    vtkNew<vtkPoints> veinPoints;
    veinPoints->SetDataType(veins->GetPoints()->GetDataType());
    auto veinDisplacement = Vector3Array("Displacement", veinCount);
    MovedPoints(simulation, d, static_cast<std::size_t>(pointCount), veinCount, veinPoints, veinDisplacement);
    movedVeins->SetPoints(veinPoints);
    movedVeins->GetPointData()->AddArray(veinDisplacement);
  }
  movedVeins->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), frameTime);
}

/// Port 1's points: the voxel model's nodes, moved, with each node's displacement, velocity, fixedness and mass.
void WriteVoxelNodes(const WiltingSimulation& simulation, const WiltingNodeState& state, vtkUnstructuredGrid* voxels)
{
  const VoxelGrid& grid = simulation.Grid();
  const std::size_t nodeCount = simulation.System().NodeCount();
  const std::vector<double>& q = state.q;
  vtkNew<vtkPoints> nodes;
  nodes->SetDataType(VTK_DOUBLE);
  nodes->SetNumberOfPoints(static_cast<vtkIdType>(nodeCount));
  auto nodeDisplacement = Vector3Array("Displacement", static_cast<vtkIdType>(nodeCount));
  auto nodeVelocity = Vector3Array("Velocity", static_cast<vtkIdType>(nodeCount));
  vtkNew<vtkUnsignedCharArray> fixed;
  fixed->SetName("Fixed");
  fixed->SetNumberOfTuples(static_cast<vtkIdType>(nodeCount));
  vtkNew<vtkDoubleArray> mass;
  mass->SetName("Mass");
  mass->SetNumberOfTuples(static_cast<vtkIdType>(nodeCount));
  for (std::size_t n = 0; n < nodeCount; ++n)
  {
    const Eigen::Vector3d& x = grid.nodes[n];
    nodes->SetPoint(static_cast<vtkIdType>(n), x[0] + q[3 * n], x[1] + q[3 * n + 1], x[2] + q[3 * n + 2]);
    nodeDisplacement->SetTuple(static_cast<vtkIdType>(n), q.data() + 3 * n);
    nodeVelocity->SetTuple(static_cast<vtkIdType>(n), state.v.data() + 3 * n);
    fixed->SetValue(static_cast<vtkIdType>(n), simulation.System().IsFixed(n) ? 1 : 0);
    mass->SetValue(static_cast<vtkIdType>(n), simulation.System().Masses()[n]);
  }
  voxels->SetPoints(nodes);
  voxels->GetPointData()->AddArray(nodeDisplacement);
  voxels->GetPointData()->AddArray(nodeVelocity);
  voxels->GetPointData()->AddArray(fixed);
  voxels->GetPointData()->AddArray(mass);
}

/// Port 1: the voxel model, hexahedra with their Region, at the state's time.
void WriteVoxels(const WiltingSimulation& simulation, const WiltingNodeState& state, vtkUnstructuredGrid* voxels)
{
  const VoxelGrid& grid = simulation.Grid();
  WriteVoxelNodes(simulation, state, voxels);
  voxels->Allocate(static_cast<vtkIdType>(grid.corners.size()));
  vtkNew<vtkIntArray> cellRegion;
  cellRegion->SetName(arrays::Region);
  for (std::size_t c = 0; c < grid.corners.size(); ++c)
  {
    vtkIdType ids[8];
    for (int k = 0; k < 8; ++k)
    {
      ids[k] = grid.corners[c][static_cast<std::size_t>(k)];
    }
    voxels->InsertNextCell(VTK_HEXAHEDRON, 8, ids);
    cellRegion->InsertNextValue(grid.regions[c]);
  }
  voxels->GetCellData()->AddArray(cellRegion);
  voxels->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), state.time);
}

/// Port 2: every frame's tip and energies.
void WriteFrameTable(const std::vector<WiltingFrame>& frames, vtkTable* table)
{
  const char* names[7] = { "Time", "TipX", "TipY", "TipZ", "Kinetic", "Spring", "Gravity" };
  for (const char* name : names)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name);
    column->SetNumberOfTuples(static_cast<vtkIdType>(frames.size()));
    table->AddColumn(column);
  }
  for (std::size_t f = 0; f < frames.size(); ++f)
  {
    const WiltingFrame& frame = frames[f];
    const double row[7] = { frame.time, frame.tip[0], frame.tip[1], frame.tip[2], frame.kinetic, frame.spring,
      frame.gravity };
    for (int c = 0; c < 7; ++c)
    {
      vtkDoubleArray::SafeDownCast(table->GetColumn(c))->SetValue(static_cast<vtkIdType>(f), row[c]);
    }
  }
}
/// The loads, shrinkage, curl and their time profiles.
void ReadLoads(vtkWiltingSimulator* f, WiltingParameters& p)
{
  p.gravity = f->GetGravity();
  p.droopForce = f->GetDroopForce();
  p.contractionForce = f->GetContractionForce();
  p.droopAsymmetry = f->GetDroopAsymmetry();
  p.contractionAsymmetry = f->GetContractionAsymmetry();
  p.shrinkageStrain = f->GetShrinkageStrain();
  p.shrinkageAsymmetry = f->GetShrinkageAsymmetry();
  p.curlStrain = f->GetCurlStrain();
  p.curlAsymmetry = f->GetCurlAsymmetry();
  p.curlRelaxation = f->GetCurlRelaxation();
  p.curlRelaxationTime = f->GetCurlRelaxationTime();
  p.curlTime = f->GetCurlTime();
  p.shrinkageTime = f->GetShrinkageTime();
  p.curlDirection = f->GetCurlDirection() == 1 ? WiltingCurlDirection::Radial : WiltingCurlDirection::Isotropic;
  p.contractionSide = f->GetContractionSide() == vtkWiltingSimulator::SIDE_TOP ? WiltingContractionSide::Top
                                                                               : WiltingContractionSide::Bottom;
  p.contractionTarget = f->GetContractionTarget() == vtkWiltingSimulator::TARGET_BASE
    ? WiltingContractionTarget::Base
    : WiltingContractionTarget::Midvein;
  p.loadProfile = static_cast<WiltingLoadProfile>(std::clamp(f->GetLoadProfile(), 0, 2));
  p.loadTime = f->GetLoadTime();
  p.contractionTime = f->GetContractionTime();
}

/// The time stepping: run length, frames, the Newmark integrator and its solver.
void ReadTimeStepping(vtkWiltingSimulator* f, WiltingParameters& p)
{
  p.duration = f->GetDuration();
  p.frameInterval = f->GetFrameInterval();
  p.tricubic = f->GetTricubic();
  p.newmark.timeStep = f->GetTimeStep();
  p.newmark.rayleighMass = f->GetRayleighAlpha();
  p.newmark.rayleighStiffness = f->GetRayleighBeta();
  p.newmark.maxIterations = f->GetNewtonIterations();
  p.newmark.compressionClamp = f->GetCompressionClamp();
  p.newmark.solver = static_cast<NewmarkSolver>(std::clamp(f->GetSolver(), 0, 2));
  p.newmark.threads = f->GetThreads();
  p.newmark.newtonTolerance = 1e-8;
  p.newmark.cgTolerance = 1e-8;
}

} // namespace

WiltingParameters WiltingParametersOf(vtkWiltingSimulator* f)
{
  WiltingParameters p;
  p.voxelSize = f->GetVoxelSize();
  p.resolution = f->GetResolution();
  p.units = f->GetUnits() == 1 ? WiltingUnits::Lattice : WiltingUnits::Physical;
  p.bladeThickness = f->GetBladeThickness();
  p.maxVoxels = static_cast<std::size_t>(std::max(1, f->GetMaximumVoxels()));
  const double* materials[4] = { f->GetBladeMaterial(), f->GetVeinMaterial(), f->GetMarginMaterial(),
    f->GetPetioleMaterial() };
  for (std::size_t m = 0; m < 4; ++m)
  {
    p.materials[m] = { materials[m][0], materials[m][1], materials[m][2] };
  }
  ReadLoads(f, p);
  p.anchorRadius = f->GetAnchorRadius();
  p.petioleLength = f->GetPetioleLength();
  ReadTimeStepping(f, p);
  if (f->GetPreset() >= 1 && f->GetPreset() < WiltingPresetCount)
  {
    ApplyWiltingPreset(static_cast<WiltingPreset>(f->GetPreset()), p);
  }
  return p;
}

std::string ValidateWiltingChoices(vtkWiltingSimulator* f)
{
  if (f->GetPreset() < 0 || f->GetPreset() >= WiltingPresetCount)
  {
    return OutOfRange("Preset", f->GetPreset(), "{0, 1, 2, 3}", "0 Custom, 1 Cucumber, 2 Tomato, 3 Watermelon");
  }
  if (f->GetLoadProfile() < 0 || f->GetLoadProfile() > 2)
  {
    return OutOfRange("LoadProfile", f->GetLoadProfile(), "{0, 1, 2}", "0 Constant, 1 Ramp, 2 Sigmoid");
  }
  if (f->GetContractionSide() < 0 || f->GetContractionSide() > 1)
  {
    return OutOfRange("ContractionSide", f->GetContractionSide(), "{0, 1}", "0 Bottom, 1 Top");
  }
  if (f->GetContractionTarget() < 0 || f->GetContractionTarget() > 1)
  {
    return OutOfRange("ContractionTarget", f->GetContractionTarget(), "{0, 1}", "0 Midvein, 1 Base");
  }
  if (f->GetCurlDirection() < 0 || f->GetCurlDirection() > 1)
  {
    return OutOfRange("CurlDirection", f->GetCurlDirection(), "{0, 1}", "0 Isotropic, 1 Radial");
  }
  if (f->GetUnits() < 0 || f->GetUnits() > 1)
  {
    return OutOfRange("Units", f->GetUnits(), "{0, 1}", "0 Physical, 1 Lattice");
  }
  if (f->GetSolver() < 0 || f->GetSolver() > 2)
  {
    return OutOfRange("Solver", f->GetSolver(), "{0, 1, 2}", "0 Auto, 1 Cholesky, 2 CG");
  }
  if (f->GetThreads() < 0 || f->GetThreads() > 256)
  {
    return OutOfRange("Threads", f->GetThreads(), "[0, 256]", "0: all cores");
  }
  if (f->GetMaximumVoxels() < 1)
  {
    return OutOfRange("MaximumVoxels", f->GetMaximumVoxels(), "[1, inf)");
  }
  return std::string();
}

std::string CheckedWiltingParameters(vtkWiltingSimulator* f, WiltingParameters& parameters)
{
  std::string error = ValidateWiltingChoices(f);
  parameters = WiltingParametersOf(f);
  return error.empty() ? ValidateWilting(parameters) : error;
}

std::string WiltingInputOf(vtkPolyData* input, vtkPolyData* veins, WiltingInput& in)
{
  ReadPoints(input, veins, in);
  ReadTriangles(input, in);
  const bool surfaceHasRegion = ReadRegions(input, veins, in);
  ReadLeafUV(input, in);
  vtkFieldData* field = input->GetFieldData();
  for (int a = 0; field && a < field->GetNumberOfArrays() && !in.fitted; ++a)
  {
    const char* name = field->GetAbstractArray(a) ? field->GetAbstractArray(a)->GetName() : nullptr;
    in.fitted = name && std::string(name).rfind("PlantMorph.FitModel.", 0) == 0;
  }
  return WiltingInputAssumptions(in, surfaceHasRegion);
}

void WriteSimulationFieldData(int simulationCount, double frameTime, vtkPolyData* output)
{
  vtkNew<vtkIntArray> runs;
  runs->SetName("WiltingSimulator.SimulationCount");
  runs->InsertNextValue(simulationCount);
  output->GetFieldData()->AddArray(runs);
  vtkNew<vtkDoubleArray> served;
  served->SetName("WiltingSimulator.FrameTime");
  served->InsertNextValue(frameTime);
  output->GetFieldData()->AddArray(served);
}

double WriteWiltedLeaf(const WiltingSimulation& simulation, vtkPolyData* leaf, vtkPolyData* veins, double time,
  const WiltingLeafOutputs& out)
{
  const WiltingNodeState state = InterpolateWiltingFrames(simulation.Frames(), time, simulation.System().NodeCount());
  const vtkIdType pointCount = leaf->GetNumberOfPoints();
  const vtkIdType veinCount = veins ? veins->GetNumberOfPoints() : 0;
  const std::vector<double> d = PointDisplacements(simulation, state, pointCount + veinCount);
  WriteMovedLeaf(simulation, leaf, d, state.time, out.leaf);
  WriteMovedVeins(simulation, pointCount, veins, d, state.time, out.veins);
  WriteVoxels(simulation, state, out.voxels);
  WriteFrameTable(simulation.Frames(), out.frames);
  return state.time;
}

void AppendedWiltedLeaves::Add(
  const WiltingSimulation& simulation, vtkPolyData* leaf, vtkPolyData* leafVeins, vtkTypeInt64 leafId, double time)
{
  vtkNew<vtkPolyData> moved, movedVeins;
  vtkNew<vtkUnstructuredGrid> leafVoxels;
  vtkNew<vtkTable> frames;
  this->served = WriteWiltedLeaf(simulation, leaf, leafVeins, time, { moved, leafVoxels, frames, movedVeins });
  for (vtkDataSet* part :
    { static_cast<vtkDataSet*>(moved), static_cast<vtkDataSet*>(movedVeins), static_cast<vtkDataSet*>(leafVoxels) })
  {
    MarkLeaf(part, leafId, this->wide);
  }
  this->leaves->AddInputData(moved);
  if (leafVeins && leafVeins->GetNumberOfPoints() > 0)
  {
    this->veins->AddInputData(movedVeins);
  }
  this->voxels->AddInputData(leafVoxels);
  AppendRows(this->rows, WithLeafColumn(frames, leafId, this->wide));
}

void AppendedWiltedLeaves::Write(int simulationCount, const WiltingLeafOutputs& out)
{
  vtkPolyData* output = out.leaf;
  vtkUnstructuredGrid* voxelOutput = out.voxels;
  vtkPolyData* movedVeins = out.veins;
  if (this->leaves->GetNumberOfInputConnections(0) > 0)
  {
    this->leaves->Update();
    this->voxels->Update();
    output->ShallowCopy(this->leaves->GetOutput());
    voxelOutput->ShallowCopy(this->voxels->GetOutput());
    WriteSimulationFieldData(simulationCount, this->served, output);
    output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), this->served);
    voxelOutput->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), this->served);
  }
  if (this->veins->GetNumberOfInputConnections(0) > 0)
  {
    this->veins->Update();
    movedVeins->ShallowCopy(this->veins->GetOutput());
    movedVeins->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), this->served);
  }
}

double RequestedTime(vtkInformation* request, const Run& run)
{
  int port = request && request->Has(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT())
    ? request->Get(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT())
    : 0;
  if (port < 0 || port >= run.NumberOfOutputs())
  {
    port = 0;
  }
  vtkInformation* outInfo = run.OutputInformation(port);
  if (!outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    outInfo = run.OutputInformation(0);
  }
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    return outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  }
  return 0.0;
}

WiltingLeafOutputs WiltingOutputsOf(const Run& run)
{
  return { run.Output<vtkPolyData>(0), run.Output<vtkUnstructuredGrid>(1), run.Output<vtkTable>(2),
    run.Output<vtkPolyData>(3) };
}

} // namespace plantmorph
