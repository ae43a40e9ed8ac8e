// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkWiltingSimulator.h"
#include "PlantMorphAlgorithmHooks.h"
#include "PlantMorphLayer.h"

#include "PlantMorphLeafExchange.h"
#include "PlantMorphWholeInput.h"
#include "WiltingConversion.h"
#include "WiltingFrames.h"
#include "WiltingPresets.h"
#include "WiltingSimulation.h"

#include <plantmorph/DataContract.h>

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTable.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkWiltingSimulator);

struct vtkWiltingSimulator::Cache
{
  /// What frames were simulated from: the inputs' and the filter's modification times, the leaves (LeafIds, none
  /// for one leaf) and each leaf's number of vein points.
  struct Key
  {
    vtkMTimeType input = 0, veins = 0, self = 0;
    std::vector<plantmorph::LeafIdType> leafIds;
    std::vector<vtkIdType> veinPoints;
    bool operator==(const Key& o) const
    {
      return input == o.input && veins == o.veins && self == o.self && leafIds == o.leafIds &&
        veinPoints == o.veinPoints;
    }
  };
  // One leaf.
  plantmorph::WiltingSimulation simulation;
  Key key;
  bool valid = false;
  // Several leaves: one simulation per leaf this rank owns, in the order of key.leafIds.
  std::vector<std::unique_ptr<plantmorph::WiltingSimulation>> leaves;
  Key leavesKey;
  bool leavesValid = false;
};

namespace
{
/// Under MPI each leaf wilts whole on one rank (PlantMorphLeafExchange.h), one leaf on rank 0: the voxel model needs
/// the whole blade.
constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::LeafPerRank;

/// A material property's three values, comparable.
std::array<double, 3> Triple(const double values[3])
{
  return { values[0], values[1], values[2] };
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
  const std::vector<double> times = plantmorph::ValidateWiltingChoices(this).empty()
    ? plantmorph::WiltingFrameTimes(plantmorph::WiltingParametersOf(this))
    : std::vector<double>();
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
  plantmorph::PresetOverrides overrides("Preset");
  overrides.Check("BladeMaterial", Triple(this->BladeMaterial), Triple(defaults->BladeMaterial));
  overrides.Check("VeinMaterial", Triple(this->VeinMaterial), Triple(defaults->VeinMaterial));
  overrides.Check("MarginMaterial", Triple(this->MarginMaterial), Triple(defaults->MarginMaterial));
  overrides.Check("PetioleMaterial", Triple(this->PetioleMaterial), Triple(defaults->PetioleMaterial));
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, Gravity);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, DroopForce);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ContractionForce);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, DroopAsymmetry);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ContractionAsymmetry);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ShrinkageStrain);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ShrinkageAsymmetry);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ShrinkageTime);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, CurlStrain);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, CurlAsymmetry);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, CurlRelaxation);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, CurlRelaxationTime);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, CurlTime);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, CurlDirection);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ContractionSide);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ContractionTarget);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, LoadProfile);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, LoadTime);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, ContractionTime);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, RayleighAlpha);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, RayleighBeta);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, Units);
  PLANTMORPH_PRESET_CHECK(overrides, this, defaults, AnchorRadius);
  overrides.Warn(this);
}

//------------------------------------------------------------------------------
bool vtkWiltingSimulator::SetUpSimulation(plantmorph::WiltingSimulation& simulation, vtkPolyData* leaf,
  vtkPolyData* veins, const plantmorph::WiltingParameters& parameters, const std::string& label)
{
  plantmorph::WiltingInput in;
  const std::string assumed = plantmorph::WiltingInputOf(leaf, veins, in);
  if (!assumed.empty())
  {
    vtkWarningMacro(<< label << assumed);
  }
  const std::string fitted = plantmorph::FittedBladeWarning(in, parameters);
  if (!fitted.empty())
  {
    vtkWarningMacro(<< label << fitted);
  }
  const std::string error = simulation.Setup(in, parameters);
  if (!error.empty())
  {
    vtkErrorMacro(<< label << error);
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkWiltingSimulator::RunSimulation(
  plantmorph::WiltingSimulation& simulation, const std::string& label, double progressBegin, double progressEnd)
{
  const std::string error = simulation.Run(plantmorph::Progress(this, progressBegin, progressEnd));
  if (simulation.Aborted())
  {
    return false; // the cache stays invalid: the next request simulates again
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< label << error << " (the frames before it are kept)");
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkWiltingSimulator::Simulate(vtkPolyData* input, vtkPolyData* veins,
  const plantmorph::WiltingParameters& parameters, vtkMTimeType pieceTime, vtkMTimeType veinsTime)
{
  Cache& cache = *this->Cached;
  const Cache::Key key{ pieceTime, veinsTime, this->GetMTime(), {}, { veins ? veins->GetNumberOfPoints() : 0 } };
  if (cache.valid && cache.key == key)
  {
    return true;
  }
  cache.valid = false;
  if (!this->SetUpSimulation(cache.simulation, input, veins, parameters, std::string()))
  {
    return false;
  }
  ++this->SimulationCount;
  this->WarnAboutPresetOverrides();
  if (!this->RunSimulation(cache.simulation, std::string(), 0.0, 1.0))
  {
    return false;
  }
  cache.valid = true;
  cache.key = key;
  return true;
}

//------------------------------------------------------------------------------
int vtkWiltingSimulator::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return plantmorph::RunRequestData(this, Policy, "the wilting simulation", request, inputVector, outputVector,
    [this, request](plantmorph::Run& run) { this->Execute(run, plantmorph::RequestedTime(request, run)); });
}

//------------------------------------------------------------------------------
void vtkWiltingSimulator::Execute(plantmorph::Run& run, double time)
{
  vtkPolyData* input = run.Input<vtkPolyData>(0);
  vtkPolyData* veins = run.Input<vtkPolyData>(1);
  if (!input)
  {
    return;
  }
  // Several leaves (PlantMorphLeafExchange.h: a LeafId array, or connected blades): each wilts alone, on one rank.
  const plantmorph::LeafPlan plan(input);
  run.StopIfAnyRankFailed(plan.AnyRank(!plan.Error().empty()), plan.Error());
  if (plan.LeafIds().size() > 1)
  {
    this->WiltLeaves(run, plan, time, input, veins);
    return;
  }
  this->WiltLeaf(run, time, input, veins);
}

//------------------------------------------------------------------------------
void vtkWiltingSimulator::WiltLeaf(plantmorph::Run& run, double time, vtkPolyData* input, vtkPolyData* veins)
{
  // Under MPI the leaf wilts once, on rank 0, whole (blade and veins gathered there if they were split over ranks).
  // The cache stays keyed on this rank's own inputs' times, so scrubbing a gathered leaf does not re-simulate.
  const vtkMTimeType pieceTime = input->GetMTime();
  const vtkMTimeType veinsPieceTime = veins ? veins->GetMTime() : 0;
  const vtkSmartPointer<vtkPolyData> wholeLeaf = plantmorph::GatherOnFirstRank(input);
  const vtkSmartPointer<vtkPolyData> wholeVeins = veins ? plantmorph::GatherOnFirstRank(veins) : nullptr;
  if (wholeLeaf->GetNumberOfPoints() == 0)
  {
    // An empty piece on another rank is expected; on rank 0 the whole leaf is empty.
    run.Warn("the Input (the leaf) is empty (no points): nothing to wilt, the outputs are empty");
    return;
  }
  plantmorph::WiltingParameters parameters;
  const std::string error = plantmorph::CheckedWiltingParameters(this, parameters);
  if (!error.empty())
  {
    this->Cached->valid = false;
    run.FailHere(error);
  }
  // Simulate (or reuse the cached frames), then serve the requested time.
  if (!this->Simulate(wholeLeaf, wholeVeins, parameters, pieceTime, veinsPieceTime))
  {
    run.Stop(); // the error, if any, is said
  }
  if (this->Cached->simulation.Frames().empty())
  {
    return;
  }
  const plantmorph::WiltingLeafOutputs out = plantmorph::WiltingOutputsOf(run);
  const double served = plantmorph::WriteWiltedLeaf(this->Cached->simulation, wholeLeaf, wholeVeins, time, out);
  plantmorph::WriteSimulationFieldData(this->SimulationCount, served, out.leaf);
  run.UpdateProgress(1.0);
}

//------------------------------------------------------------------------------
bool vtkWiltingSimulator::SimulateLeaves(const std::vector<vtkSmartPointer<vtkPolyData>>& leaves,
  const std::vector<vtkSmartPointer<vtkPolyData>>& veins, const std::vector<plantmorph::LeafIdType>& leafIds,
  const plantmorph::WiltingParameters& parameters, vtkMTimeType pieceTime, vtkMTimeType veinsTime)
{
  Cache& cache = *this->Cached;
  Cache::Key key{ pieceTime, veinsTime, this->GetMTime(), leafIds, {} };
  for (const auto& v : veins)
  {
    key.veinPoints.push_back(v->GetNumberOfPoints());
  }
  if (cache.leavesValid && cache.leavesKey == key)
  {
    return true;
  }
  cache.leavesValid = false;
  cache.leaves.clear();
  const double share = 1.0 / static_cast<double>(leaves.size());
  for (std::size_t k = 0; k < leaves.size(); ++k)
  {
    vtkPolyData* leafVeins = key.veinPoints[k] > 0 ? veins[k].Get() : nullptr;
    const std::string label = "leaf " + std::to_string(leafIds[k]) + ": ";
    cache.leaves.push_back(std::make_unique<plantmorph::WiltingSimulation>());
    if (!this->SetUpSimulation(*cache.leaves.back(), leaves[k], leafVeins, parameters, label))
    {
      return false;
    }
    if (k == 0)
    {
      this->WarnAboutPresetOverrides();
    }
    if (!this->RunSimulation(*cache.leaves.back(), label, k * share, (k + 1) * share))
    {
      return false;
    }
  }
  ++this->SimulationCount;
  cache.leavesValid = true;
  cache.leavesKey = key;
  return true;
}

//------------------------------------------------------------------------------
void vtkWiltingSimulator::WiltLeaves(
  plantmorph::Run& run, const plantmorph::LeafPlan& plan, double time, vtkPolyData* input, vtkPolyData* veins)
{
  // Collective: the veins split by their LeafId point array; each leaf and its veins sent to the leaf's owner.
  std::vector<plantmorph::LeafIdType> veinLeafOf;
  const bool veinsKnown = plantmorph::LeafIdsOfPoints(veins, veinLeafOf);
  if (plan.AnyRank(!veinsKnown))
  {
    run.CheckHere(veinsKnown ? std::string()
                             : "Veins: with several leaves the veins need a one-component point array LeafId naming "
                               "the leaf of each vein point (VenationFilter's veins of several leaves have it)");
    run.Stop();
  }
  vtkNew<vtkPolyData> noVeins;
  const std::vector<vtkSmartPointer<vtkPolyData>> leaves = plan.Leaves();
  const std::vector<vtkSmartPointer<vtkPolyData>> leafVeins =
    plan.Distribute(veins ? veins : noVeins.Get(), veinLeafOf);
  const std::vector<plantmorph::LeafIdType> owned = plan.Owned();
  // Properties -> parameters, checked where leaves wilt; then every owned leaf wilts alone (or comes from the cache).
  plantmorph::WiltingParameters parameters;
  std::string error = plantmorph::CheckedWiltingParameters(this, parameters);
  error = owned.empty() ? std::string() : error;
  if (plan.AnyRank(!error.empty()))
  {
    this->Cached->leavesValid = this->Cached->leavesValid && error.empty();
    run.CheckHere(error);
    run.Stop();
  }
  const bool simulated = owned.empty() ||
    this->SimulateLeaves(leaves, leafVeins, owned, parameters, input->GetMTime(), veins ? veins->GetMTime() : 0);
  if (plan.AnyRank(!simulated))
  {
    run.Stop(); // the error, if any, is said where it happened
  }
  // Every owned leaf at the requested time, appended in LeafId order and marked with LeafId.
  plantmorph::AppendedWiltedLeaves appended(plan.WideIds());
  for (std::size_t k = 0; k < owned.size(); ++k)
  {
    const plantmorph::WiltingSimulation& simulation = *this->Cached->leaves[k];
    if (!simulation.Frames().empty())
    {
      appended.Add(
        simulation, leaves[k], leafVeins[k]->GetNumberOfPoints() > 0 ? leafVeins[k].Get() : nullptr, owned[k], time);
    }
  }
  appended.Write(this->SimulationCount, plantmorph::WiltingOutputsOf(run));
  // Collective: the frame tables' rows on rank 0, in LeafId order (each leaf's frames in time order).
  run.Output(2)->ShallowCopy(plan.GatherRows(appended.Rows()));
  run.UpdateProgress(1.0);
}

//------------------------------------------------------------------------------
const char* vtkWiltingSimulator::GetPresetValues()
{
  if (this->Preset <= PRESET_CUSTOM || this->Preset >= plantmorph::WiltingPresetCount)
  {
    this->PresetValues = this->Preset == PRESET_CUSTOM ? "Custom: the properties are used as set."
                                                       : "Preset is outside the accepted range.";
  }
  else
  {
    this->PresetValues = plantmorph::DescribeWiltingPreset(static_cast<plantmorph::WiltingPreset>(this->Preset));
  }
  return this->PresetValues.c_str();
}
