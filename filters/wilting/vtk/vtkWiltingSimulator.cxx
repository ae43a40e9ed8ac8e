// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkWiltingSimulator.h"
#include "PlantMorphAlgorithmHooks.h"

#include "PlantMorphLeafExchange.h"
#include "PlantMorphWholeInput.h"
#include "WiltingPresets.h"
#include "WiltingSimulation.h"

#include <plantmorph/DataContract.h>
#include <plantmorph/RangeError.h>

#include "vtkAppendFilter.h"
#include "vtkAppendPolyData.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkWiltingSimulator);

struct vtkWiltingSimulator::Cache
{
  plantmorph::WiltingSimulation simulation;
  vtkMTimeType inputTime = 0;
  vtkMTimeType veinsTime = 0;
  vtkIdType veinPoints = 0;
  vtkMTimeType selfTime = 0;
  bool valid = false;
  // Several leaves: one simulation per leaf this rank owns (LeafIds `leafIds`), keyed like the single one.
  std::vector<std::unique_ptr<plantmorph::WiltingSimulation>> leaves;
  std::vector<int> leafIds;
  std::vector<vtkIdType> leafVeinPoints;
  vtkMTimeType leavesInputTime = 0;
  vtkMTimeType leavesVeinsTime = 0;
  vtkMTimeType leavesSelfTime = 0;
  bool leavesValid = false;
};

namespace
{
plantmorph::WiltingParameters ParametersOf(vtkWiltingSimulator* f)
{
  plantmorph::WiltingParameters p;
  p.voxelSize = f->GetVoxelSize();
  p.resolution = f->GetResolution();
  p.units = f->GetUnits() == 1 ? plantmorph::WiltingUnits::Lattice : plantmorph::WiltingUnits::Physical;
  p.bladeThickness = f->GetBladeThickness();
  p.maxVoxels = static_cast<std::size_t>(std::max(1, f->GetMaximumVoxels()));
  const double* materials[4] = { f->GetBladeMaterial(), f->GetVeinMaterial(), f->GetMarginMaterial(),
    f->GetPetioleMaterial() };
  for (std::size_t m = 0; m < 4; ++m)
  {
    p.materials[m] = { materials[m][0], materials[m][1], materials[m][2] };
  }
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
  p.curlDirection =
    f->GetCurlDirection() == 1 ? plantmorph::WiltingCurlDirection::Radial : plantmorph::WiltingCurlDirection::Isotropic;
  p.contractionSide = f->GetContractionSide() == vtkWiltingSimulator::SIDE_TOP
    ? plantmorph::WiltingContractionSide::Top
    : plantmorph::WiltingContractionSide::Bottom;
  p.contractionTarget = f->GetContractionTarget() == vtkWiltingSimulator::TARGET_BASE
    ? plantmorph::WiltingContractionTarget::Base
    : plantmorph::WiltingContractionTarget::Midvein;
  p.loadProfile = static_cast<plantmorph::WiltingLoadProfile>(std::clamp(f->GetLoadProfile(), 0, 2));
  p.loadTime = f->GetLoadTime();
  p.contractionTime = f->GetContractionTime();
  p.anchorRadius = f->GetAnchorRadius();
  p.petioleLength = f->GetPetioleLength();
  p.duration = f->GetDuration();
  p.frameInterval = f->GetFrameInterval();
  p.tricubic = f->GetTricubic();
  p.newmark.timeStep = f->GetTimeStep();
  p.newmark.rayleighMass = f->GetRayleighAlpha();
  p.newmark.rayleighStiffness = f->GetRayleighBeta();
  p.newmark.maxIterations = f->GetNewtonIterations();
  p.newmark.compressionClamp = f->GetCompressionClamp();
  p.newmark.solver = static_cast<plantmorph::NewmarkSolver>(std::clamp(f->GetSolver(), 0, 2));
  p.newmark.threads = f->GetThreads();
  p.newmark.newtonTolerance = 1e-8;
  p.newmark.cgTolerance = 1e-8;
  if (f->GetPreset() >= 1 && f->GetPreset() < plantmorph::WiltingPresetCount)
  {
    plantmorph::ApplyWiltingPreset(static_cast<plantmorph::WiltingPreset>(f->GetPreset()), p);
  }
  return p;
}

/// The simulation's input from the leaf surface and the veins. Returns what had to be assumed (the Input lacks
/// LeafUV or Region, or is not a manifold surface), for a warning, or "".
std::string WiltingInputOf(vtkPolyData* input, vtkPolyData* veins, plantmorph::WiltingInput& in)
{
  const vtkIdType pointCount = input->GetNumberOfPoints();
  const vtkIdType veinCount = veins ? veins->GetNumberOfPoints() : 0;
  // The simulation's points: the surface's, then the veins' (they mark vein voxels through their Region and
  // follow the voxels like every surface point; they are not voxelised themselves).
  const std::size_t total = static_cast<std::size_t>(pointCount + veinCount);
  in.points.resize(total);
  for (vtkIdType i = 0; i < pointCount; ++i)
  {
    input->GetPoint(i, in.points[static_cast<std::size_t>(i)].data());
  }
  for (vtkIdType i = 0; i < veinCount; ++i)
  {
    veins->GetPoint(i, in.points[static_cast<std::size_t>(pointCount + i)].data());
  }
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
  // Region: a point without one (either dataset may lack the array) counts as blade.
  vtkDataArray* region = input->GetPointData()->GetArray(plantmorph::arrays::Region);
  vtkDataArray* veinRegion = veins ? veins->GetPointData()->GetArray(plantmorph::arrays::Region) : nullptr;
  region = region && region->GetNumberOfComponents() == 1 ? region : nullptr;
  veinRegion = veinRegion && veinRegion->GetNumberOfComponents() == 1 ? veinRegion : nullptr;
  if (region || veinRegion)
  {
    in.regions.assign(total, plantmorph::RegionBlade);
    for (vtkIdType i = 0; region && i < pointCount; ++i)
    {
      in.regions[static_cast<std::size_t>(i)] = static_cast<int>(region->GetComponent(i, 0));
    }
    for (vtkIdType i = 0; veinRegion && i < veinCount; ++i)
    {
      in.regions[static_cast<std::size_t>(pointCount + i)] = static_cast<int>(veinRegion->GetComponent(i, 0));
    }
  }
  // LeafUV picks the base and the tip among the surface's points; vein points get NaN (never picked).
  vtkDataArray* uv = input->GetPointData()->GetArray(plantmorph::arrays::LeafUV);
  if (uv && uv->GetNumberOfComponents() == 2)
  {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    in.leafUV.assign(total, Eigen::Vector2d(nan, nan));
    for (vtkIdType i = 0; i < pointCount; ++i)
    {
      in.leafUV[static_cast<std::size_t>(i)] = Eigen::Vector2d(uv->GetComponent(i, 0), uv->GetComponent(i, 1));
    }
  }
  std::ostringstream assumed;
  if (in.leafUV.empty())
  {
    assumed << "the Input has no LeafUV point array (2 components), so its base is taken as its lowest point (least "
               "y) and its tip as its point farthest from the base. ";
  }
  if (!region)
  {
    assumed << "the Input has no Region point array, so every point of it counts as blade (no margin or midvein "
               "material). ";
  }
  std::map<std::pair<int, int>, int> edgeUse;
  for (const auto& t : in.triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      const int a = t[k], b = t[(k + 1) % 3];
      ++edgeUse[{ std::min(a, b), std::max(a, b) }];
    }
  }
  const auto shared = std::count_if(edgeUse.begin(), edgeUse.end(), [](const auto& e) { return e.second > 2; });
  if (shared > 0)
  {
    assumed << "the Input is not a manifold surface (" << shared << " edge(s) shared by more than two triangles): it "
            << "is voxelised as it is, each triangle on its own. ";
  }
  std::string text = assumed.str();
  return text.empty() ? text : text.substr(0, text.size() - 1);
}

std::string ValidateEnumerations(vtkWiltingSimulator* f)
{
  if (f->GetPreset() < 0 || f->GetPreset() >= plantmorph::WiltingPresetCount)
  {
    return plantmorph::OutOfRange(
      "Preset", f->GetPreset(), "{0, 1, 2, 3}", "0 Custom, 1 Cucumber, 2 Tomato, 3 Watermelon");
  }
  if (f->GetLoadProfile() < 0 || f->GetLoadProfile() > 2)
  {
    return plantmorph::OutOfRange("LoadProfile", f->GetLoadProfile(), "{0, 1, 2}", "0 Constant, 1 Ramp, 2 Sigmoid");
  }
  if (f->GetContractionSide() < 0 || f->GetContractionSide() > 1)
  {
    return plantmorph::OutOfRange("ContractionSide", f->GetContractionSide(), "{0, 1}", "0 Bottom, 1 Top");
  }
  if (f->GetContractionTarget() < 0 || f->GetContractionTarget() > 1)
  {
    return plantmorph::OutOfRange("ContractionTarget", f->GetContractionTarget(), "{0, 1}", "0 Midvein, 1 Base");
  }
  if (f->GetCurlDirection() < 0 || f->GetCurlDirection() > 1)
  {
    return plantmorph::OutOfRange("CurlDirection", f->GetCurlDirection(), "{0, 1}", "0 Isotropic, 1 Radial");
  }
  if (f->GetUnits() < 0 || f->GetUnits() > 1)
  {
    return plantmorph::OutOfRange("Units", f->GetUnits(), "{0, 1}", "0 Physical, 1 Lattice");
  }
  if (f->GetSolver() < 0 || f->GetSolver() > 2)
  {
    return plantmorph::OutOfRange("Solver", f->GetSolver(), "{0, 1, 2}", "0 Auto, 1 Cholesky, 2 CG");
  }
  if (f->GetThreads() < 0 || f->GetThreads() > 256)
  {
    return plantmorph::OutOfRange("Threads", f->GetThreads(), "[0, 256]", "0: all cores");
  }
  if (f->GetMaximumVoxels() < 1)
  {
    return plantmorph::OutOfRange("MaximumVoxels", f->GetMaximumVoxels(), "[1, inf)");
  }
  return std::string();
}

std::vector<double> FrameTimes(const plantmorph::WiltingParameters& p)
{
  std::vector<double> times;
  if (!plantmorph::ValidateWilting(p).empty())
  {
    return times;
  }
  const int spf = std::max(1, static_cast<int>(std::lround(p.frameInterval / p.newmark.timeStep)));
  const double frame = spf * p.newmark.timeStep;
  const int count = 1 + static_cast<int>(std::floor(p.duration / frame + 1e-9));
  for (int k = 0; k < count; ++k)
  {
    times.push_back(k * spf * p.newmark.timeStep);
  }
  return times;
}

vtkSmartPointer<vtkDoubleArray> Vector3Array(const char* name, vtkIdType count)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->SetNumberOfTuples(count);
  return a;
}

/// The time asked of the port that asked (a request through the veins' or the voxels' port leaves port 0's time
/// stale), else port 0's; 0 when no time is asked.
double RequestedTime(vtkInformation* request, vtkInformationVector* outputVector)
{
  int port = request && request->Has(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT())
    ? request->Get(vtkDemandDrivenPipeline::FROM_OUTPUT_PORT())
    : 0;
  if (port < 0 || port >= outputVector->GetNumberOfInformationObjects())
  {
    port = 0;
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(port);
  if (!outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    outInfo = outputVector->GetInformationObject(0);
  }
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP()))
  {
    return outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
  }
  return 0.0;
}

/// The nodes' displacements and velocities at one time, between two frames.
struct NodeState
{
  std::vector<double> q, v;
  double time = 0.0;
};

/// The state at `time`, linear between the frames around it (clamped to the first and the last).
NodeState InterpolateFrames(const std::vector<plantmorph::WiltingFrame>& frames, double time, std::size_t nodeCount)
{
  std::size_t lower = 0;
  while (lower + 1 < frames.size() && frames[lower + 1].time <= time)
  {
    ++lower;
  }
  const std::size_t upper = std::min(lower + 1, frames.size() - 1);
  double w = 0.0;
  if (upper != lower && frames[upper].time > frames[lower].time)
  {
    w = std::clamp((time - frames[lower].time) / (frames[upper].time - frames[lower].time), 0.0, 1.0);
  }
  NodeState state;
  state.q.resize(3 * nodeCount);
  state.v.resize(3 * nodeCount);
  for (std::size_t k = 0; k < state.q.size(); ++k)
  {
    state.q[k] = (1.0 - w) * frames[lower].q[k] + w * frames[upper].q[k];
    state.v[k] = (1.0 - w) * frames[lower].v[k] + w * frames[upper].v[k];
  }
  state.time = (1.0 - w) * frames[lower].time + w * frames[upper].time;
  return state;
}

/// The displacement of the simulation's `count` input points (the leaf's, then the veins'), embedded in the voxels.
std::vector<double> PointDisplacements(
  const plantmorph::WiltingSimulation& simulation, const NodeState& state, vtkIdType count)
{
  std::vector<double> d(3 * static_cast<std::size_t>(count));
  simulation.Embedding().Interpolate(state.q.data(), d.data());
  return d;
}

/// `count` points from `first` of the simulation's input points, moved by `d`, and their Displacement array.
void MovedPoints(const plantmorph::WiltingSimulation& simulation, const std::vector<double>& d, std::size_t first,
  vtkIdType count, vtkPoints* points, vtkDoubleArray* displacement)
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
void WriteMovedLeaf(const plantmorph::WiltingSimulation& simulation, vtkPolyData* input, const std::vector<double>& d,
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
void WriteMovedVeins(const plantmorph::WiltingSimulation& simulation, vtkIdType pointCount, vtkPolyData* veins,
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

/// Port 0's field data: how many simulations this filter has run (scrubbing must not raise it) and the frame time.
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

/// Port 1: the voxel model, moved, with each node's displacement, velocity, fixedness and mass.
void WriteVoxels(const plantmorph::WiltingSimulation& simulation, const NodeState& state, vtkUnstructuredGrid* voxels)
{
  const plantmorph::VoxelGrid& grid = simulation.Grid();
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
  voxels->Allocate(static_cast<vtkIdType>(grid.corners.size()));
  vtkNew<vtkIntArray> cellRegion;
  cellRegion->SetName(plantmorph::arrays::Region);
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
  voxels->GetPointData()->AddArray(nodeDisplacement);
  voxels->GetPointData()->AddArray(nodeVelocity);
  voxels->GetPointData()->AddArray(fixed);
  voxels->GetPointData()->AddArray(mass);
  voxels->GetCellData()->AddArray(cellRegion);
  voxels->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), state.time);
}

/// Port 2: every frame's tip and energies.
void WriteFrameTable(const std::vector<plantmorph::WiltingFrame>& frames, vtkTable* table)
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
    const plantmorph::WiltingFrame& frame = frames[f];
    const double row[7] = { frame.time, frame.tip[0], frame.tip[1], frame.tip[2], frame.kinetic, frame.spring,
      frame.gravity };
    for (int c = 0; c < 7; ++c)
    {
      vtkDoubleArray::SafeDownCast(table->GetColumn(c))->SetValue(static_cast<vtkIdType>(f), row[c]);
    }
  }
}
} // namespace

//------------------------------------------------------------------------------
vtkWiltingSimulator::vtkWiltingSimulator()
  : Cached(new Cache)
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(4);
}

vtkWiltingSimulator::~vtkWiltingSimulator() = default;

//------------------------------------------------------------------------------
void vtkWiltingSimulator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Preset: " << this->Preset << "\n";
  os << indent << "VoxelSize: " << this->VoxelSize << "\n";
  os << indent << "Resolution: " << this->Resolution << "\n";
  os << indent << "Units: " << this->Units << "\n";
  os << indent << "BladeThickness: " << this->BladeThickness << "\n";
  os << indent << "Duration: " << this->Duration << "\n";
  os << indent << "TimeStep: " << this->TimeStep << "\n";
  os << indent << "FrameInterval: " << this->FrameInterval << "\n";
  os << indent << "DroopForce: " << this->DroopForce << "\n";
  os << indent << "ContractionForce: " << this->ContractionForce << "\n";
  os << indent << "DroopAsymmetry: " << this->DroopAsymmetry << "\n";
  os << indent << "ContractionAsymmetry: " << this->ContractionAsymmetry << "\n";
  os << indent << "ShrinkageStrain: " << this->ShrinkageStrain << "\n";
  os << indent << "ShrinkageAsymmetry: " << this->ShrinkageAsymmetry << "\n";
  os << indent << "CurlStrain: " << this->CurlStrain << "\n";
  os << indent << "CurlAsymmetry: " << this->CurlAsymmetry << "\n";
  os << indent << "CurlRelaxation: " << this->CurlRelaxation << "\n";
  os << indent << "CurlRelaxationTime: " << this->CurlRelaxationTime << "\n";
  os << indent << "CurlTime: " << this->CurlTime << "\n";
  os << indent << "ShrinkageTime: " << this->ShrinkageTime << "\n";
  os << indent << "PetioleLength: " << this->PetioleLength << "\n";
  os << indent << "CurlDirection: " << this->CurlDirection << "\n";
  os << indent << "Solver: " << this->Solver << "\n";
}

//------------------------------------------------------------------------------
int vtkWiltingSimulator::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    return 1;
  }
  return this->Superclass::FillInputPortInformation(port, info);
}

//------------------------------------------------------------------------------
void vtkWiltingSimulator::SetVeinsConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

//------------------------------------------------------------------------------
void vtkWiltingSimulator::SetVeinsData(vtkPolyData* veins)
{
  this->SetInputData(1, veins);
}

//------------------------------------------------------------------------------
int vtkWiltingSimulator::FillOutputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkUnstructuredGrid");
    return 1;
  }
  if (port == 2)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

//------------------------------------------------------------------------------
int vtkWiltingSimulator::RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  const std::vector<double> times =
    ValidateEnumerations(this).empty() ? FrameTimes(ParametersOf(this)) : std::vector<double>();
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    vtkInformation* info = outputVector->GetInformationObject(port);
    if (times.empty())
    {
      info->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
      info->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
      continue;
    }
    info->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), times.data(), static_cast<int>(times.size()));
    const double range[2] = { times.front(), times.back() };
    info->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkWiltingSimulator::RequestUpdateExtent(vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // The whole simulation starts from the inputs' one state: do not pass our time upstream.
  for (int port = 0; port < 2; ++port)
  {
    vtkInformation* inInfo = inputVector[port]->GetInformationObject(0);
    if (inInfo)
    {
      inInfo->Remove(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    }
  }
  return 1;
}

//------------------------------------------------------------------------------
void vtkWiltingSimulator::WarnAboutPresetOverrides()
{
  if (this->Preset == PRESET_CUSTOM)
  {
    return;
  }
  vtkNew<vtkWiltingSimulator> defaults;
  std::ostringstream ignored;
  const auto check = [&](const char* name, bool changed) {
    if (changed)
    {
      ignored << (ignored.tellp() > 0 ? ", " : "") << name;
    }
  };
  const auto differ = [](const double a[3], const double b[3]) { return !std::equal(a, a + 3, b); };
#define PLANTMORPH_CHECK(name) check(#name, this->name != defaults->name)
  check("BladeMaterial", differ(this->BladeMaterial, defaults->BladeMaterial));
  check("VeinMaterial", differ(this->VeinMaterial, defaults->VeinMaterial));
  check("MarginMaterial", differ(this->MarginMaterial, defaults->MarginMaterial));
  check("PetioleMaterial", differ(this->PetioleMaterial, defaults->PetioleMaterial));
  PLANTMORPH_CHECK(Gravity);
  PLANTMORPH_CHECK(DroopForce);
  PLANTMORPH_CHECK(ContractionForce);
  PLANTMORPH_CHECK(DroopAsymmetry);
  PLANTMORPH_CHECK(ContractionAsymmetry);
  PLANTMORPH_CHECK(ShrinkageStrain);
  PLANTMORPH_CHECK(ShrinkageAsymmetry);
  PLANTMORPH_CHECK(ShrinkageTime);
  PLANTMORPH_CHECK(CurlStrain);
  PLANTMORPH_CHECK(CurlAsymmetry);
  PLANTMORPH_CHECK(CurlRelaxation);
  PLANTMORPH_CHECK(CurlRelaxationTime);
  PLANTMORPH_CHECK(CurlTime);
  PLANTMORPH_CHECK(CurlDirection);
  PLANTMORPH_CHECK(ContractionSide);
  PLANTMORPH_CHECK(ContractionTarget);
  PLANTMORPH_CHECK(LoadProfile);
  PLANTMORPH_CHECK(LoadTime);
  PLANTMORPH_CHECK(ContractionTime);
  PLANTMORPH_CHECK(RayleighAlpha);
  PLANTMORPH_CHECK(RayleighBeta);
  PLANTMORPH_CHECK(Units);
#undef PLANTMORPH_CHECK
  if (ignored.tellp() > 0)
  {
    vtkWarningMacro(<< "these properties are changed from their defaults but not used, because Preset is a named "
                       "preset that sets them itself: "
                    << ignored.str() << ". Set Preset to Custom (0) to use them.");
  }
}

//------------------------------------------------------------------------------
bool vtkWiltingSimulator::Simulate(vtkPolyData* input, vtkPolyData* veins,
  const plantmorph::WiltingParameters& parameters, vtkMTimeType pieceTime, vtkMTimeType veinsTime)
{
  Cache& cache = *this->Cached;
  const vtkIdType veinCount = veins ? veins->GetNumberOfPoints() : 0;
  if (cache.valid && cache.inputTime == pieceTime && cache.selfTime == this->GetMTime() &&
    cache.veinsTime == veinsTime && cache.veinPoints == veinCount)
  {
    return true;
  }
  plantmorph::WiltingInput in;
  const std::string assumed = WiltingInputOf(input, veins, in);
  if (!assumed.empty())
  {
    vtkWarningMacro(<< assumed);
  }
  cache.valid = false;
  std::string error = cache.simulation.Setup(in, parameters);
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return false;
  }
  ++this->SimulationCount;
  this->WarnAboutPresetOverrides();
  error = cache.simulation.Run(plantmorph::Progress(this));
  if (cache.simulation.Aborted())
  {
    return false; // the cache stays invalid: the next request simulates again
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error << " (the frames before it are kept)");
  }
  cache.valid = true;
  cache.inputTime = pieceTime;
  cache.veinsTime = veinsTime;
  cache.veinPoints = veinCount;
  cache.selfTime = this->GetMTime();
  return true;
}

//------------------------------------------------------------------------------
namespace
{
/// The shortest text that reads back as exactly `value`, so the box shows what the preset uses, digit for digit.
std::string Exact(double value)
{
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof(buffer), value).ptr;
  return std::string(buffer, end);
}
} // namespace

const char* vtkWiltingSimulator::GetPresetValues()
{
  if (this->Preset <= PRESET_CUSTOM || this->Preset >= plantmorph::WiltingPresetCount)
  {
    this->PresetValues = this->Preset == PRESET_CUSTOM ? "Custom: the properties are used as set."
                                                       : "Preset is outside the accepted range.";
    return this->PresetValues.c_str();
  }
  const auto preset = static_cast<plantmorph::WiltingPreset>(this->Preset);
  plantmorph::WiltingParameters p;
  plantmorph::ApplyWiltingPreset(preset, p);
  std::ostringstream text;
  const auto line = [&](const char* name, double value) { text << "\n" << name << " = " << Exact(value); };
  const auto material = [&](const char* name, const plantmorph::WiltingMaterial& m) {
    text << "\n" << name << " = " << Exact(m.density) << ", " << Exact(m.stiffness) << ", " << Exact(m.damping);
  };
  text << plantmorph::WiltingPresetName(preset) << " sets (the greyed properties are not used):";
  material("BladeMaterial", p.materials[plantmorph::WiltingBlade]);
  material("VeinMaterial", p.materials[plantmorph::WiltingVein]);
  material("MarginMaterial", p.materials[plantmorph::WiltingMargin]);
  material("PetioleMaterial", p.materials[plantmorph::WiltingPetiole]);
  line("Gravity", p.gravity);
  line("DroopForce", p.droopForce);
  line("ContractionForce", p.contractionForce);
  line("DroopAsymmetry", p.droopAsymmetry);
  line("ContractionAsymmetry", p.contractionAsymmetry);
  line("ShrinkageStrain", p.shrinkageStrain);
  line("ShrinkageAsymmetry", p.shrinkageAsymmetry);
  line("ShrinkageTime", p.shrinkageTime);
  line("CurlStrain", p.curlStrain);
  line("CurlAsymmetry", p.curlAsymmetry);
  line("CurlRelaxation", p.curlRelaxation);
  line("CurlRelaxationTime", p.curlRelaxationTime);
  line("CurlTime", p.curlTime);
  line("CurlDirection", static_cast<int>(p.curlDirection));
  line("ContractionSide", static_cast<int>(p.contractionSide));
  line("ContractionTarget", static_cast<int>(p.contractionTarget));
  line("LoadProfile", static_cast<int>(p.loadProfile));
  line("LoadTime", p.loadTime);
  line("ContractionTime", p.contractionTime);
  line("RayleighAlpha", p.newmark.rayleighMass);
  line("RayleighBeta", p.newmark.rayleighStiffness);
  line("Units", static_cast<int>(p.units));
  text << "\n(Physical units: Young's moduli and pressures in dyn/cm^2, densities in g/cm^3, for a blade of "
          "BladeThickness, 0: the leaf's longest side / 14)";
  this->PresetValues = text.str();
  return this->PresetValues.c_str();
}

//------------------------------------------------------------------------------
int vtkWiltingSimulator::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
  vtkPolyData* veins = vtkPolyData::GetData(inputVector[1], 0);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkUnstructuredGrid* voxels = vtkUnstructuredGrid::GetData(outputVector, 1);
  vtkTable* table = vtkTable::GetData(outputVector, 2);
  vtkPolyData* movedVeins = vtkPolyData::GetData(outputVector, 3);
  output->Initialize();
  voxels->Initialize();
  table->Initialize();
  movedVeins->Initialize();
  if (!input)
  {
    return 1;
  }
  // Several leaves (PlantMorphLeafExchange.h: a LeafId array, or connected blades): each wilts alone, on one rank.
  const plantmorph::LeafPlan plan(input);
  if (plan.AnyRank(!plan.Error().empty()))
  {
    if (!plan.Error().empty())
    {
      vtkErrorMacro(<< plan.Error());
    }
    return 1;
  }
  if (plan.LeafIds().size() > 1)
  {
    return this->WiltLeaves(plan, request, input, veins, outputVector);
  }
  // One leaf: under MPI the leaf wilts once, on rank 0, whole (blade and veins gathered there if they were split over ranks).
  // The cache stays keyed on this rank's own inputs' times, so scrubbing a gathered leaf does not re-simulate.
  const vtkMTimeType pieceTime = input->GetMTime();
  const vtkMTimeType veinsPieceTime = veins ? veins->GetMTime() : 0;
  const vtkSmartPointer<vtkPolyData> wholeLeaf = plantmorph::GatherOnFirstRank(input);
  const vtkSmartPointer<vtkPolyData> wholeVeins = veins ? plantmorph::GatherOnFirstRank(veins) : nullptr;
  input = wholeLeaf.Get();
  veins = wholeVeins.Get();
  if (input->GetNumberOfPoints() == 0)
  {
    // An empty piece on another rank is expected; on rank 0 the whole leaf is empty.
    if (plantmorph::IsFirstRank())
    {
      vtkWarningMacro(<< "the Input (the leaf) is empty (no points): nothing to wilt, the outputs are empty");
    }
    return 1;
  }
  // Properties -> parameters.
  std::string error = ValidateEnumerations(this);
  const plantmorph::WiltingParameters parameters = ParametersOf(this);
  if (error.empty())
  {
    error = plantmorph::ValidateWilting(parameters);
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    this->Cached->valid = false;
    return 1;
  }
  // Simulate (or reuse the cached frames), then serve the requested time.
  if (!this->Simulate(input, veins, parameters, pieceTime, veinsPieceTime))
  {
    return 1;
  }
  const plantmorph::WiltingSimulation& simulation = this->Cached->simulation;
  const std::vector<plantmorph::WiltingFrame>& frames = simulation.Frames();
  if (frames.empty())
  {
    return 1;
  }
  const NodeState state =
    InterpolateFrames(frames, RequestedTime(request, outputVector), simulation.System().NodeCount());
  const vtkIdType pointCount = input->GetNumberOfPoints();
  const vtkIdType veinCount = veins ? veins->GetNumberOfPoints() : 0;
  const std::vector<double> d = PointDisplacements(simulation, state, pointCount + veinCount);
  WriteMovedLeaf(simulation, input, d, state.time, output);
  WriteMovedVeins(simulation, pointCount, veins, d, state.time, movedVeins);
  WriteSimulationFieldData(this->SimulationCount, state.time, output);
  WriteVoxels(simulation, state, voxels);
  WriteFrameTable(frames, table);
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
bool vtkWiltingSimulator::SimulateLeaves(const std::vector<vtkSmartPointer<vtkPolyData>>& leaves,
  const std::vector<vtkSmartPointer<vtkPolyData>>& veins, const std::vector<int>& leafIds,
  const plantmorph::WiltingParameters& parameters, vtkMTimeType pieceTime, vtkMTimeType veinsTime)
{
  Cache& cache = *this->Cached;
  std::vector<vtkIdType> veinPoints;
  for (const auto& v : veins)
  {
    veinPoints.push_back(v->GetNumberOfPoints());
  }
  if (cache.leavesValid && cache.leavesInputTime == pieceTime && cache.leavesSelfTime == this->GetMTime() &&
    cache.leavesVeinsTime == veinsTime && cache.leafIds == leafIds && cache.leafVeinPoints == veinPoints)
  {
    return true;
  }
  cache.leavesValid = false;
  cache.leaves.clear();
  bool warned = false;
  for (std::size_t k = 0; k < leaves.size(); ++k)
  {
    plantmorph::WiltingInput in;
    vtkPolyData* leafVeins = veinPoints[k] > 0 ? veins[k].Get() : nullptr;
    const std::string assumed = WiltingInputOf(leaves[k], leafVeins, in);
    const std::string leaf = "leaf " + std::to_string(leafIds[k]) + ": ";
    if (!assumed.empty())
    {
      vtkWarningMacro(<< leaf << assumed);
    }
    cache.leaves.push_back(std::make_unique<plantmorph::WiltingSimulation>());
    plantmorph::WiltingSimulation& simulation = *cache.leaves.back();
    const std::string error = simulation.Setup(in, parameters);
    if (!error.empty())
    {
      vtkErrorMacro(<< leaf << error);
      return false;
    }
    if (!warned)
    {
      this->WarnAboutPresetOverrides();
      warned = true;
    }
    const double share = 1.0 / static_cast<double>(leaves.size());
    const std::string runError = simulation.Run(plantmorph::Progress(this, k * share, (k + 1) * share));
    if (simulation.Aborted())
    {
      return false;
    }
    if (!runError.empty())
    {
      vtkErrorMacro(<< leaf << runError << " (the frames before it are kept)");
    }
  }
  ++this->SimulationCount;
  cache.leavesValid = true;
  cache.leafIds = leafIds;
  cache.leafVeinPoints = veinPoints;
  cache.leavesInputTime = pieceTime;
  cache.leavesVeinsTime = veinsTime;
  cache.leavesSelfTime = this->GetMTime();
  return true;
}

//------------------------------------------------------------------------------
int vtkWiltingSimulator::WiltLeaves(const plantmorph::LeafPlan& plan, vtkInformation* request, vtkPolyData* input,
  vtkPolyData* veins, vtkInformationVector* outputVector)
{
  // Collective: the veins split by their LeafId point array; each leaf and its veins sent to the leaf's owner.
  std::vector<int> veinLeafOf;
  const bool veinsKnown = plantmorph::LeafIdsOfPoints(veins, veinLeafOf);
  if (!veinsKnown)
  {
    vtkErrorMacro(<< "Veins: with several leaves the veins need a one-component point array LeafId naming the leaf of "
                     "each vein point (VenationFilter's veins of several leaves have it)");
  }
  if (plan.AnyRank(!veinsKnown))
  {
    return 1;
  }
  vtkNew<vtkPolyData> noVeins;
  const std::vector<vtkSmartPointer<vtkPolyData>> leaves = plan.Leaves();
  const std::vector<vtkSmartPointer<vtkPolyData>> leafVeins =
    plan.Distribute(veins ? veins : noVeins.Get(), veinLeafOf);
  const std::vector<int> owned = plan.Owned();
  // Properties -> parameters, checked where leaves wilt; then every owned leaf wilts alone (or comes from the cache).
  std::string error = owned.empty() ? std::string() : ValidateEnumerations(this);
  const plantmorph::WiltingParameters parameters = ParametersOf(this);
  if (!owned.empty() && error.empty())
  {
    error = plantmorph::ValidateWilting(parameters);
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    this->Cached->leavesValid = false;
  }
  if (plan.AnyRank(!error.empty()))
  {
    return 1;
  }
  const bool simulated = owned.empty() ||
    this->SimulateLeaves(leaves, leafVeins, owned, parameters, input->GetMTime(), veins ? veins->GetMTime() : 0);
  if (plan.AnyRank(!simulated))
  {
    return 1;
  }
  // Every owned leaf at the requested time, appended in LeafId order and marked with LeafId.
  const double time = RequestedTime(request, outputVector);
  vtkNew<vtkAppendPolyData> appendLeaves, appendVeins;
  vtkNew<vtkAppendFilter> appendVoxels;
  vtkNew<vtkTable> rows;
  double served = 0.0;
  for (std::size_t k = 0; k < owned.size(); ++k)
  {
    const plantmorph::WiltingSimulation& simulation = *this->Cached->leaves[k];
    if (simulation.Frames().empty())
    {
      continue;
    }
    const NodeState state = InterpolateFrames(simulation.Frames(), time, simulation.System().NodeCount());
    vtkPolyData* leafVeinsK = leafVeins[k]->GetNumberOfPoints() > 0 ? leafVeins[k].Get() : nullptr;
    const vtkIdType pointCount = leaves[k]->GetNumberOfPoints();
    const vtkIdType veinCount = leafVeinsK ? leafVeinsK->GetNumberOfPoints() : 0;
    const std::vector<double> d = PointDisplacements(simulation, state, pointCount + veinCount);
    vtkNew<vtkPolyData> moved, movedVeins;
    vtkNew<vtkUnstructuredGrid> voxels;
    vtkNew<vtkTable> frames;
    WriteMovedLeaf(simulation, leaves[k], d, state.time, moved);
    WriteMovedVeins(simulation, pointCount, leafVeinsK, d, state.time, movedVeins);
    WriteVoxels(simulation, state, voxels);
    WriteFrameTable(simulation.Frames(), frames);
    for (vtkDataSet* part :
      { static_cast<vtkDataSet*>(moved), static_cast<vtkDataSet*>(movedVeins), static_cast<vtkDataSet*>(voxels) })
    {
      plantmorph::MarkLeaf(part, owned[k]);
    }
    appendLeaves->AddInputData(moved);
    if (veinCount > 0)
    {
      appendVeins->AddInputData(movedVeins);
    }
    appendVoxels->AddInputData(voxels);
    plantmorph::AppendRows(rows, plantmorph::WithLeafColumn(frames, owned[k]));
    served = state.time;
  }
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* movedVeins = vtkPolyData::GetData(outputVector, 3);
  if (appendLeaves->GetNumberOfInputConnections(0) > 0)
  {
    appendLeaves->Update();
    appendVoxels->Update();
    output->ShallowCopy(appendLeaves->GetOutput());
    vtkUnstructuredGrid::GetData(outputVector, 1)->ShallowCopy(appendVoxels->GetOutput());
    WriteSimulationFieldData(this->SimulationCount, served, output);
    output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), served);
    vtkUnstructuredGrid::GetData(outputVector, 1)->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), served);
  }
  if (appendVeins->GetNumberOfInputConnections(0) > 0)
  {
    appendVeins->Update();
    movedVeins->ShallowCopy(appendVeins->GetOutput());
    movedVeins->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), served);
  }
  // Collective: the frame tables' rows on rank 0, in LeafId order (each leaf's frames in time order).
  vtkTable::GetData(outputVector, 2)->ShallowCopy(plan.GatherRows(rows));
  this->UpdateProgress(1.0);
  return 1;
}
