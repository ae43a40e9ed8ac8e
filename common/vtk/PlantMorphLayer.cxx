// SPDX-License-Identifier: GPL-3.0-or-later
#include "PlantMorphLayer.h"

#include "PlantMorphAlgorithmHooks.h"
#include "PlantMorphFieldData.h"
#include "PlantMorphWholeInput.h"

#include "vtkAlgorithm.h"
#include "vtkCommunicator.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkExecutive.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObject.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"

#include <new>
#include <sstream>
#include <vector>

namespace plantmorph
{

namespace
{
const std::string Prefix = "PlantMorph.";

std::string Prefixed(const std::string& name)
{
  return name.compare(0, Prefix.size(), Prefix) == 0 ? name : Prefix + name;
}

/// The global controller when this process is one of several MPI ranks, else null.
vtkMultiProcessController* SeveralRanks()
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  return controller && controller->GetNumberOfProcesses() > 1 ? controller : nullptr;
}

/// A source, for the policies: no input port, or an optional first one (LeafOutlineSource's control points).
bool IsSource(vtkAlgorithm* algorithm)
{
  if (algorithm->GetNumberOfInputPorts() == 0)
  {
    return true;
  }
  vtkInformation* info = algorithm->GetInputPortInformation(0);
  return info && info->Has(vtkAlgorithm::INPUT_IS_OPTIONAL()) && info->Get(vtkAlgorithm::INPUT_IS_OPTIONAL()) != 0;
}

/// The output information holding the piece request of this update: the requested port's, else the first port's
/// that has one (null when none has). A source's port other than 0 counts only when it says it can make pieces
/// (CAN_HANDLE_PIECE_REQUEST): LeafCloudReader's table port, asked for piece k of N, is still the whole file on
/// every rank.
vtkInformation* PieceRequest(vtkAlgorithm* algorithm, vtkInformation* request, vtkInformationVector* outputs)
{
  const int ports = outputs->GetNumberOfInformationObjects();
  const bool source = IsSource(algorithm);
  const auto asks = [&](int port) -> vtkInformation* {
    vtkInformation* info = port >= 0 && port < ports ? outputs->GetInformationObject(port) : nullptr;
    if (!info || !info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()))
    {
      return nullptr;
    }
    const bool splits = port == 0 || !source ||
      (info->Has(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST()) && info->Get(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST()));
    return splits ? info : nullptr;
  };
  if (request && request->Has(vtkExecutive::FROM_OUTPUT_PORT()))
  {
    if (vtkInformation* info = asks(request->Get(vtkExecutive::FROM_OUTPUT_PORT())))
    {
      return info;
    }
  }
  for (int port = 0; port < ports; ++port)
  {
    if (vtkInformation* info = asks(port))
    {
      return info;
    }
  }
  return nullptr;
}

/// The whole of `piece` on rank 0 (collective; the piece itself serially): point sets and tables.
vtkSmartPointer<vtkDataObject> GatherWhole(vtkDataObject* piece)
{
  if (auto* points = vtkPointSet::SafeDownCast(piece))
  {
    return GatherOnFirstRank(points);
  }
  if (auto* table = vtkTable::SafeDownCast(piece))
  {
    return GatherRowsOnFirstRank(table);
  }
  return piece;
}
} // namespace

//------------------------------------------------------------------------------
const char* PolicyName(MPIPolicy policy)
{
  switch (policy)
  {
    case MPIPolicy::WholeOnFirstRank:
      return "WholeOnFirstRank";
    case MPIPolicy::LeafPerRank:
      return "LeafPerRank";
    case MPIPolicy::DataParallel:
      return "DataParallel";
  }
  return "?";
}

//------------------------------------------------------------------------------
RunFailure::RunFailure(const std::string& message, bool everyRank)
  : std::runtime_error(message)
  , AllRanks(everyRank)
{
}

void Fail(const std::string& message)
{
  throw RunFailure(message, true);
}

void Check(const std::string& error)
{
  if (!error.empty())
  {
    Fail(error);
  }
}

//------------------------------------------------------------------------------
void RunThreaded(int threads, const std::function<void()>& body)
{
  const std::string current = vtkSMPTools::GetBackend() ? vtkSMPTools::GetBackend() : "Sequential";
  const std::string backend = threads == 1 ? "Sequential" : (current == "Sequential" ? "STDThread" : current);
  vtkSMPTools::LocalScope(vtkSMPTools::Config{ threads, backend, false }, body);
}

//------------------------------------------------------------------------------
FieldRecord::FieldRecord()
  : Fields(vtkSmartPointer<vtkFieldData>::New())
{
}

FieldRecord::~FieldRecord() = default;

void FieldRecord::Add(const std::string& name, double value)
{
  AddFieldValue(this->Fields, Prefixed(name).c_str(), value);
}

void FieldRecord::Add(const std::string& name, const std::string& value)
{
  AddFieldString(this->Fields, Prefixed(name).c_str(), value);
}

void FieldRecord::AddTuple(
  const std::string& name, const std::vector<std::string>& components, const std::vector<double>& values)
{
  this->AddRows(name, static_cast<int>(values.size()), values, components);
}

void FieldRecord::AddRows(
  const std::string& name, int components, const std::vector<double>& values, const std::vector<std::string>& names)
{
  vtkNew<vtkDoubleArray> array;
  array->SetName(Prefixed(name).c_str());
  array->SetNumberOfComponents(components > 0 ? components : 1);
  for (std::size_t c = 0; c < names.size() && static_cast<int>(c) < array->GetNumberOfComponents(); ++c)
  {
    array->SetComponentName(static_cast<vtkIdType>(c), names[c].c_str());
  }
  const std::size_t width = static_cast<std::size_t>(array->GetNumberOfComponents());
  for (std::size_t r = 0; r + width <= values.size(); r += width)
  {
    array->InsertNextTuple(values.data() + r);
  }
  this->Fields->AddArray(array);
}

void FieldRecord::AddArray(vtkAbstractArray* array)
{
  const std::string name = array->GetName() ? array->GetName() : "";
  if (Prefixed(name) != name)
  {
    array->SetName(Prefixed(name).c_str());
  }
  this->Fields->AddArray(array);
}

void FieldRecord::WriteTo(vtkDataObject* output) const
{
  for (int a = 0; a < this->Fields->GetNumberOfArrays(); ++a)
  {
    output->GetFieldData()->AddArray(this->Fields->GetAbstractArray(a));
  }
}

std::string FieldRecord::Text() const
{
  return FormatParameters(this->Fields);
}

//------------------------------------------------------------------------------
PresetOverrides::PresetOverrides(std::string presetProperty)
  : Preset(std::move(presetProperty))
{
}

std::string PresetOverrides::Message() const
{
  if (this->Changed.empty())
  {
    return {};
  }
  std::ostringstream text;
  text << "these properties are changed from their defaults but not used, because " << this->Preset
       << " is a named preset that sets them itself: ";
  for (std::size_t k = 0; k < this->Changed.size(); ++k)
  {
    text << (k ? ", " : "") << this->Changed[k];
  }
  text << ". Set " << this->Preset << " to Custom (0) to use them.";
  return text.str();
}

void PresetOverrides::Warn(vtkObject* object) const
{
  if (!this->Changed.empty())
  {
    vtkWarningWithObjectMacro(object, << this->Message());
  }
}

//------------------------------------------------------------------------------
Run::Run(vtkAlgorithm* algorithm, MPIPolicy policy, std::string building, vtkInformation* request,
  vtkInformationVector** inputs, vtkInformationVector* outputs)
  : Self(algorithm)
  , Mode(policy)
  , What(std::move(building))
  , Inputs(inputs)
  , Outputs(outputs)
{
  // The piece asked of the port this update is for (vtkExecutive::FROM_OUTPUT_PORT); without one, of the first
  // port that has a piece request (PieceRequest). A request through another port than 0 (a fetch or view of a later
  // port alone) leaves port 0 without pieces or with a stale one, and the MPI controller would be lost.
  this->Request = request;
  vtkInformation* info = PieceRequest(algorithm, request, outputs);
  if (info)
  {
    this->PieceNumber = info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
  }
  if (info && info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()))
  {
    this->PieceCount = info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES());
  }
  if (this->PieceCount < 1)
  {
    this->PieceNumber = 0;
    this->PieceCount = 1;
  }
  vtkMultiProcessController* controller = SeveralRanks();
  if (controller && controller->GetNumberOfProcesses() == this->PieceCount &&
    controller->GetLocalProcessId() == this->PieceNumber)
  {
    this->Parallel = controller;
  }
}

Run::~Run() = default;

vtkDataObject* Run::Input(int port) const
{
  if (this->GatheredInputs)
  {
    return port >= 0 && static_cast<std::size_t>(port) < this->Gathered.size() ? this->Gathered[port].Get() : nullptr;
  }
  if (port < 0 || port >= this->Self->GetNumberOfInputPorts() || !this->Inputs[port] ||
    this->Inputs[port]->GetNumberOfInformationObjects() == 0)
  {
    return nullptr;
  }
  return vtkDataObject::GetData(this->Inputs[port], 0);
}

vtkDataObject* Run::Output(int port) const
{
  return port >= 0 && port < this->NumberOfOutputs() ? vtkDataObject::GetData(this->Outputs, port) : nullptr;
}

int Run::NumberOfOutputs() const
{
  return this->Outputs->GetNumberOfInformationObjects();
}

vtkInformation* Run::OutputInformation(int port) const
{
  return port >= 0 && port < this->NumberOfOutputs() ? this->Outputs->GetInformationObject(port) : nullptr;
}

int Run::Rank() const
{
  return this->Parallel ? this->Parallel->GetLocalProcessId() : 0;
}

int Run::Ranks() const
{
  return this->Parallel ? this->Parallel->GetNumberOfProcesses() : 1;
}

bool Run::IsFirstRank() const
{
  if (this->Mode == MPIPolicy::WholeOnFirstRank)
  {
    return this->RunsBody();
  }
  return plantmorph::IsFirstRank();
}

bool AnyRank(vtkMultiProcessController* controller, bool failed)
{
  const int mine = failed ? 1 : 0;
  int any = mine;
  if (controller)
  {
    controller->AllReduce(&mine, &any, 1, vtkCommunicator::MAX_OP);
  }
  return any != 0;
}

double SumOverRanks(vtkMultiProcessController* controller, double value)
{
  if (!controller || controller->GetNumberOfProcesses() < 2)
  {
    return value;
  }
  std::vector<double> values(static_cast<std::size_t>(controller->GetNumberOfProcesses()));
  controller->AllGather(&value, values.data(), 1);
  double sum = 0.0;
  for (double v : values)
  {
    sum += v;
  }
  return sum;
}

bool Run::AnyRank(bool failed) const
{
  return plantmorph::AnyRank(this->Parallel, failed);
}

vtkSmartPointer<vtkPolyData> Run::Replicated(vtkPolyData* piece) const
{
  vtkMultiProcessController* controller = SeveralRanks(); // every rank, as GatherOnFirstRank
  if (!controller)
  {
    return piece;
  }
  const vtkSmartPointer<vtkPolyData> whole = AppendOnFirstRank(piece);
  auto replica = vtkSmartPointer<vtkPolyData>::New();
  if (controller->GetLocalProcessId() == 0)
  {
    replica->ShallowCopy(whole);
  }
  controller->Broadcast(replica, 0);
  return replica;
}

//------------------------------------------------------------------------------
void Run::Fail(const std::string& message) const
{
  throw RunFailure(message, true);
}

void Run::FailHere(const std::string& message) const
{
  throw RunFailure(message, false);
}

void Run::Stop() const
{
  throw RunFailure(std::string(), false);
}

void Run::Check(const std::string& error) const
{
  if (!error.empty())
  {
    this->Fail(error);
  }
}

void Run::CheckHere(const std::string& error) const
{
  if (!error.empty())
  {
    this->FailHere(error);
  }
}

void Run::StopIfAnyRankFailed(bool anyRankFailed, const std::string& error) const
{
  if (anyRankFailed)
  {
    this->CheckHere(error);
    this->Stop();
  }
}

void Run::StopIfAborted() const
{
  if (this->Self->GetAbortExecute())
  {
    this->Stop();
  }
}

void Run::Error(const std::string& message) const
{
  this->Report(message, true);
}

void Run::Warn(const std::string& message) const
{
  if (!this->Parallel || this->Parallel->GetLocalProcessId() == 0)
  {
    this->WarnHere(message);
  }
}

void Run::WarnHere(const std::string& message) const
{
  vtkWarningWithObjectMacro(this->Self, << message);
}

std::function<bool(double)> Run::Progress(double begin, double end) const
{
  return plantmorph::Progress(this->Self, begin, end);
}

void Run::UpdateProgress(double fraction) const
{
  this->Self->UpdateProgress(fraction);
}

void Run::WriteToEveryOutput(const FieldRecord& record) const
{
  for (int port = 0; port < this->NumberOfOutputs(); ++port)
  {
    if (vtkDataObject* output = this->Output(port))
    {
      record.WriteTo(output);
    }
  }
}

void Run::ClearOutputs() const
{
  for (int port = 0; port < this->NumberOfOutputs(); ++port)
  {
    if (vtkDataObject* output = this->Output(port))
    {
      output->Initialize();
    }
  }
}

//------------------------------------------------------------------------------
bool Run::RunsBody() const
{
  if (this->Mode != MPIPolicy::WholeOnFirstRank)
  {
    return true;
  }
  return IsSource(this->Self) ? this->PieceNumber == 0 : plantmorph::IsFirstRank();
}

void Run::GatherInputs()
{
  // Collective: every rank gathers every connected input port's data (the same ports on every rank).
  this->Gathered.clear();
  for (int port = 0; port < this->Self->GetNumberOfInputPorts(); ++port)
  {
    vtkDataObject* piece = this->Input(port);
    this->Gathered.push_back(piece ? GatherWhole(piece) : nullptr);
  }
  this->GatheredInputs = true;
}

void Run::Report(const std::string& message, bool everyRank) const
{
  if (message.empty() || (everyRank && this->Parallel && this->Parallel->GetLocalProcessId() != 0))
  {
    return;
  }
  vtkErrorWithObjectMacro(this->Self, << message);
}

//------------------------------------------------------------------------------
int RunRequestData(vtkAlgorithm* algorithm, MPIPolicy policy, const std::string& building, vtkInformation* request,
  vtkInformationVector** inputs, vtkInformationVector* outputs, const std::function<void(Run&)>& execute)
{
  KeepFreedMemory(); // before the first update's arrays are allocated
  Run run(algorithm, policy, building, request, inputs, outputs);
  run.ClearOutputs();
  bool failed = false;
  try
  {
    if (policy == MPIPolicy::WholeOnFirstRank && SeveralRanks() && !IsSource(algorithm))
    {
      run.GatherInputs();
    }
    if (run.RunsBody())
    {
      execute(run);
    }
  }
  catch (const RunFailure& failure)
  {
    failed = true;
    run.Report(failure.what(), failure.EveryRank());
  }
  catch (const std::bad_alloc&)
  {
    failed = true;
    run.Report("ran out of memory building " + run.Building() + ": the outputs are empty", false);
  }
  catch (const std::exception& e)
  {
    failed = true;
    run.Report("failed building " + run.Building() + ": " + e.what(), false);
  }
  catch (...)
  {
    failed = true;
    run.Report("failed building " + run.Building() + " (an unknown exception)", false);
  }
  if (failed)
  {
    run.ClearOutputs();
  }
  return 1;
}

} // namespace plantmorph
