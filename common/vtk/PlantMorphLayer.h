// SPDX-License-Identifier: GPL-3.0-or-later
// The VTK layer every PlantMorph wrapper composes (module PlantMorph::VTKCommon, docs/architecture.md "The VTK
// layer"). A wrapper stays a plain vtkPolyDataAlgorithm (or vtkTableAlgorithm, ...) and hands its RequestData to
// plantmorph::RunRequestData with the MPI policy it declared once:
//
//     namespace { constexpr plantmorph::MPIPolicy Policy = plantmorph::MPIPolicy::WholeOnFirstRank; }
//
//     int vtkMyFilter::RequestData(vtkInformation* request, vtkInformationVector** in, vtkInformationVector* out)
//     {
//       return plantmorph::RunRequestData(this, Policy, "the blade", request, in, out,
//         [this](plantmorph::Run& run) { this->Execute(run); });
//     }
//
// RunRequestData empties every output port, applies the policy, runs the body and catches what it throws: a
// plantmorph::RunFailure (run.Fail, run.FailHere, run.Check, plantmorph::Fail), std::bad_alloc ("ran out of memory
// building <what>") or any other exception. On any failure the error is reported once and every output port is left
// empty: never half an output. (Under MPI the ranks that must fail together agree first: run.AnyRank.)
#pragma once

#include "PlantMorphVTKCommonModule.h" // for export macro

#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

class vtkAbstractArray;
class vtkAlgorithm;
class vtkDataObject;
class vtkFieldData;
class vtkInformation;
class vtkInformationVector;
class vtkMultiProcessController;
class vtkObject;
class vtkPolyData;

namespace plantmorph
{

/// How a wrapper shares its work over the MPI ranks of pvbatch or a parallel pvserver (every rank runs every
/// proxy). Declared once per class and given to RunRequestData.
enum class MPIPolicy
{
  /// The output is made whole in one place. A source (no required input) makes it on piece 0 and leaves the other
  /// pieces empty; a filter gets every input gathered whole on rank 0 first (collective, PlantMorphWholeInput.h) and
  /// runs there alone, the other ranks' outputs staying empty. Serially the body runs once on the input as it is.
  WholeOnFirstRank,
  /// Each leaf of the input is processed whole on one owner rank (PlantMorphLeafExchange.h's LeafPlan, or the
  /// fitters' OwnerExchange of PlantMorphOwnerExchange.h); the body runs on every rank and does the exchange itself.
  LeafPerRank,
  /// Every rank computes its own piece (a byte range of a file, its own measured points, its share of the beams or
  /// branches), small inputs replicated where needed (Run::Replicated); the body runs on every rank.
  DataParallel
};

/// "WholeOnFirstRank", "LeafPerRank" or "DataParallel".
PLANTMORPHVTKCOMMON_EXPORT const char* PolicyName(MPIPolicy policy);

/// Collective over `controller`'s ranks: true on every rank when `failed` is true on any (a maximum of flags, the same
/// on any number of ranks); `failed` itself when `controller` is null (serial). Run, LeafPlan, OwnerExchange and the
/// cloud comparison's exchange all ask through this.
PLANTMORPHVTKCOMMON_EXPORT bool AnyRank(vtkMultiProcessController* controller, bool failed);

/// Collective over `controller`'s ranks: the sum of every rank's `value`, added in rank order so that every rank and
/// every run get the same bits (exact for counts below 2^53, whatever the number of ranks); `value` itself when
/// `controller` is null or has one rank.
PLANTMORPHVTKCOMMON_EXPORT double SumOverRanks(vtkMultiProcessController* controller, double value);

/// What a run throws to stop: caught by RunRequestData, which reports `what()` (unless empty) and empties every
/// output. `everyRank`: every rank finds the same failure (a property, a replicated input), so only the first
/// rank reports it; otherwise the rank that found it does.
class PLANTMORPHVTKCOMMON_EXPORT RunFailure : public std::runtime_error
{
public:
  RunFailure(const std::string& message, bool everyRank);
  bool EveryRank() const { return this->AllRanks; }

private:
  bool AllRanks;
};

/// Throws a RunFailure every rank finds alike (reported once). For conversion helpers that have no Run at hand.
[[noreturn]] PLANTMORPHVTKCOMMON_EXPORT void Fail(const std::string& message);
/// Fail(error) unless `error` is empty: for the algorithm layers' "" or message results.
PLANTMORPHVTKCOMMON_EXPORT void Check(const std::string& error);

/// Runs `body` with vtkSMPTools set to `threads` threads (0: all cores) and a threaded backend: ParaView's own when
/// it has one, STDThread when it is Sequential (Debian's default); one thread runs Sequential. The algorithms give
/// the same results however the work is cut, so this is a speed setting only.
PLANTMORPHVTKCOMMON_EXPORT void RunThreaded(int threads, const std::function<void()>& body);

/// The PlantMorph.* field data of one run (docs/architecture.md, the data contract): the parameters and results a
/// later filter or a user reads back, as arrays named "PlantMorph.<name>" (the prefix is added when a name lacks
/// it). Written onto the outputs with WriteTo; Text() is what the panels' PresetValues boxes show.
class PLANTMORPHVTKCOMMON_EXPORT FieldRecord
{
public:
  FieldRecord();
  ~FieldRecord();
  /// A one-value double array.
  void Add(const std::string& name, double value);
  /// A one-value string array.
  void Add(const std::string& name, const std::string& value);
  void Add(const std::string& name, const char* value) { this->Add(name, std::string(value)); }
  /// One tuple with named components (PlantMorph.Curvature: Function, Mu, ...).
  void AddTuple(const std::string& name, const std::vector<std::string>& components, const std::vector<double>& values);
  /// Rows of `components` values each (`values` row after row; `names` the components' names, or none).
  void AddRows(const std::string& name, int components, const std::vector<double>& values,
    const std::vector<std::string>& names = {});
  /// An array made elsewhere (its name gets the prefix when it lacks it).
  void AddArray(vtkAbstractArray* array);
  /// Every array of the record added (shared, not copied) to the field data of `output`.
  void WriteTo(vtkDataObject* output) const;
  /// The record as "Name = value" lines (FormatParameters).
  std::string Text() const;
  vtkFieldData* Data() const { return this->Fields; }

private:
  vtkSmartPointer<vtkFieldData> Fields;
};

/// The one preset-override warning of the classes with named presets (LeafOutlineSource, VenationFilter,
/// WiltingSimulator): the properties a named preset sets itself are listed when the user changed them from their
/// defaults, in one warning. Usage, with `defaults` a default-constructed instance of the class:
///
///     plantmorph::PresetOverrides overrides("Preset");
///     PLANTMORPH_PRESET_CHECK(overrides, this, defaults, Width);
///     ...
///     overrides.Warn(this);
class PLANTMORPHVTKCOMMON_EXPORT PresetOverrides
{
public:
  /// `presetProperty`: the property that names the preset (Preset, SpaceCurvePreset, BSplinePreset).
  explicit PresetOverrides(std::string presetProperty);
  /// Notes `property` when `value` differs from `defaultValue`.
  template <class T>
  void Check(const char* property, const T& value, const T& defaultValue)
  {
    if (!(value == defaultValue))
    {
      this->Changed.emplace_back(property);
    }
  }
  const std::vector<std::string>& ChangedProperties() const { return this->Changed; }
  /// The warning's text; empty when no property was changed.
  std::string Message() const;
  /// Sends the warning as `object`'s (nothing when no property was changed).
  void Warn(vtkObject* object) const;

private:
  std::string Preset;
  std::vector<std::string> Changed;
};

/// PresetOverrides::Check of the member `name` of `self` against the same member of `defaults`.
#define PLANTMORPH_PRESET_CHECK(overrides, self, defaults, name)                                                       \
  (overrides).Check(#name, (self)->name, (defaults)->name)

/// One RequestData of a wrapper, as RunRequestData gives it to the body: where the run is (piece, rank), its inputs
/// (gathered whole under WholeOnFirstRank) and outputs, and the ways to stop.
class PLANTMORPHVTKCOMMON_EXPORT Run
{
public:
  Run(vtkAlgorithm* algorithm, MPIPolicy policy, std::string building, vtkInformation* request,
    vtkInformationVector** inputs, vtkInformationVector* outputs);
  ~Run();
  Run(const Run&) = delete;
  Run& operator=(const Run&) = delete;

  vtkAlgorithm* Algorithm() const { return this->Self; }
  MPIPolicy Policy() const { return this->Mode; }

  /// The first dataset of input port `port` (null when nothing is connected). Under WholeOnFirstRank the whole
  /// input gathered on rank 0 (point sets and tables; other data as it is).
  vtkDataObject* Input(int port) const;
  template <class T>
  T* Input(int port) const
  {
    return T::SafeDownCast(this->Input(port));
  }
  vtkDataObject* Output(int port) const;
  template <class T>
  T* Output(int port) const
  {
    return T::SafeDownCast(this->Output(port));
  }
  int NumberOfOutputs() const;
  /// The pipeline information of output port `port` (time requests, ...).
  vtkInformation* OutputInformation(int port) const;
  /// The pipeline request of this RequestData (which port it is for: vtkExecutive::FROM_OUTPUT_PORT).
  vtkInformation* RequestInformation() const { return this->Request; }

  /// The piece asked of the port this update is for (the first port with a piece request when the request names
  /// none; a source's port other than 0 only when it can make pieces), and of how many.
  int Piece() const { return this->PieceNumber; }
  int Pieces() const { return this->PieceCount; }
  /// The MPI controller when this process is one of several ranks and the pieces are the ranks (piece == rank);
  /// null serially or when one process makes several pieces. Collective calls go through it.
  vtkMultiProcessController* Controller() const { return this->Parallel; }
  int Rank() const;
  int Ranks() const;
  /// Serial, or rank 0 (and, for a source under WholeOnFirstRank, piece 0): where a once-only message is said.
  bool IsFirstRank() const;
  /// Collective under Controller(): true on every rank when `failed` is true on any (false serially if not failed).
  bool AnyRank(bool failed) const;
  /// Collective over every rank (the global controller, as GatherOnFirstRank): the whole of `piece` (gathered on
  /// rank 0, its pieces appended without merging points, AppendOnFirstRank, and broadcast) on every rank; `piece`
  /// itself serially. For the small inputs of data-parallel wrappers (a surface to scan).
  vtkSmartPointer<vtkPolyData> Replicated(vtkPolyData* piece) const;

  /// Stops the run: an error every rank finds alike (a property, a replicated input), reported by the first rank.
  [[noreturn]] void Fail(const std::string& message) const;
  /// Stops the run: an error of this rank's own data, reported here.
  [[noreturn]] void FailHere(const std::string& message) const;
  /// Stops the run without a message (the user pressed Abort; the error was already said).
  [[noreturn]] void Stop() const;
  /// Fail(error) / FailHere(error) unless `error` is empty.
  void Check(const std::string& error) const;
  void CheckHere(const std::string& error) const;
  /// After a collective that told every rank whether any failed (`anyRankFailed`: AnyRank here, or a LeafPlan's or
  /// exchange's own): the rank with an `error` reports it (FailHere), every rank stops; nothing when none failed. An
  /// error left to one rank would hang the others' next collective call.
  void StopIfAnyRankFailed(bool anyRankFailed, const std::string& error) const;
  /// Stop() when the user pressed Abort.
  void StopIfAborted() const;
  /// What the run is building now, for the out-of-memory message ("ran out of memory building <what>").
  void Building(const std::string& what) { this->What = what; }
  const std::string& Building() const { return this->What; }

  /// An error said once (by the first rank) that does not stop the run: only for an output port the class refuses
  /// and empties itself while its other ports stay valid (LeafCloudReader's points of a table without x, y, z
  /// columns; its table port is still the file). Anything else stops with Fail.
  void Error(const std::string& message) const;
  /// A warning said once (by the first rank).
  void Warn(const std::string& message) const;
  /// A warning said by this rank (about its own data).
  void WarnHere(const std::string& message) const;

  /// The progress callback of the algorithm layers: fraction f shows as begin + (end - begin) f; false once the
  /// user pressed Abort.
  std::function<bool(double)> Progress(double begin = 0.0, double end = 1.0) const;
  void UpdateProgress(double fraction) const;
  /// RunThreaded(threads, body).
  void Threaded(int threads, const std::function<void()>& body) const { RunThreaded(threads, body); }
  /// `record` onto every output port's field data.
  void WriteToEveryOutput(const FieldRecord& record) const;

  /// Empties every output port (RunRequestData does it before and after a failed body).
  void ClearOutputs() const;

private:
  friend PLANTMORPHVTKCOMMON_EXPORT int RunRequestData(vtkAlgorithm*, MPIPolicy, const std::string&, vtkInformation*,
    vtkInformationVector**, vtkInformationVector*, const std::function<void(Run&)>&);
  bool RunsBody() const;
  void GatherInputs();
  void Report(const std::string& message, bool everyRank) const;

  vtkAlgorithm* Self;
  MPIPolicy Mode;
  std::string What;
  vtkInformation* Request = nullptr;
  vtkInformationVector** Inputs;
  vtkInformationVector* Outputs;
  int PieceNumber = 0;
  int PieceCount = 1;
  vtkMultiProcessController* Parallel = nullptr;
  std::vector<vtkSmartPointer<vtkDataObject>> Gathered; // WholeOnFirstRank: each input port's whole input
  bool GatheredInputs = false;
};

/// RequestData's boundary (see the top of this file): empties every output port; under WholeOnFirstRank gathers
/// the inputs and runs `execute` only where the output is made; catches every failure, reports it once and empties
/// every output port of the rank that failed. It adds no collective call of its own after the body: under
/// LeafPerRank and DataParallel a body whose ranks may fail apart agrees first (run.AnyRank, LeafPlan::AnyRank) and
/// then fails on every rank, as the wrappers do. `building` names what the run makes ("the leaf blade"), for the
/// out-of-memory message. Returns 1 (the error, if any, is reported; the pipeline carries on).
PLANTMORPHVTKCOMMON_EXPORT int RunRequestData(vtkAlgorithm* algorithm, MPIPolicy policy, const std::string& building,
  vtkInformation* request, vtkInformationVector** inputs, vtkInformationVector* outputs,
  const std::function<void(Run&)>& execute);

} // namespace plantmorph
