// SPDX-License-Identifier: GPL-3.0-or-later
// vtkWiltingSimulator's conversions between VTK and the wilting core (filters/wilting/core): its properties into
// plantmorph::WiltingParameters, the leaf and its veins into a plantmorph::WiltingInput, and a simulation's state at
// a time into the filter's four outputs (port 0 the moved leaf, 1 the voxel model, 2 the frame table, 3 the moved
// veins), one leaf or several appended. Private to the module.
#pragma once

#include "WiltingSimulation.h"

#include "vtkAppendFilter.h"
#include "vtkAppendPolyData.h"
#include "vtkNew.h"
#include "vtkTable.h"

#include <string>

class vtkInformation;
class vtkPolyData;
class vtkUnstructuredGrid;
class vtkWiltingSimulator;

namespace plantmorph
{
class Run;

/// The time asked of the port that asked (a request through the veins' or the voxels' port leaves port 0's time
/// stale), else port 0's; 0 when no time is asked. (Run does not give the requesting port: `request` does.)
double RequestedTime(vtkInformation* request, const Run& run);

/// The properties as the simulation's parameters, a named Preset's values in place of the ones it sets (the
/// enumerations clamped to their ranges).
WiltingParameters WiltingParametersOf(vtkWiltingSimulator* filter);
/// "" when every enumeration property (and Threads, MaximumVoxels) is in its range, else a message naming it.
std::string ValidateWiltingChoices(vtkWiltingSimulator* filter);
/// `parameters` from the properties, and "" or a message naming the property out of range.
std::string CheckedWiltingParameters(vtkWiltingSimulator* filter, WiltingParameters& parameters);

/// The simulation's input from the leaf surface and the veins (may be null). Returns what had to be assumed (the
/// Input lacks LeafUV or Region, or is not a manifold surface), for a warning, or "".
std::string WiltingInputOf(vtkPolyData* input, vtkPolyData* veins, WiltingInput& in);

/// Port 0's field data: how many simulations the filter has run (scrubbing must not raise it) and the frame time.
void WriteSimulationFieldData(int simulationCount, double frameTime, vtkPolyData* output);

/// One leaf's four outputs.
struct WiltingLeafOutputs
{
  vtkPolyData* leaf;
  vtkUnstructuredGrid* voxels;
  vtkTable* frames;
  vtkPolyData* veins;
};

/// The run's four outputs.
WiltingLeafOutputs WiltingOutputsOf(const Run& run);

/// One leaf's outputs at `time` (linear between frames) from its simulation of `leaf` and `veins` (may be null);
/// the simulation has frames. Returns the time served.
double WriteWiltedLeaf(const WiltingSimulation& simulation, vtkPolyData* leaf, vtkPolyData* veins, double time,
  const WiltingLeafOutputs& out);

/// The outputs of several leaves, appended in LeafId order, each point and cell marked with its LeafId.
class AppendedWiltedLeaves
{
public:
  /// `wide`: the LeafId arrays 64-bit (LeafPlan::WideIds), else int.
  explicit AppendedWiltedLeaves(bool wide = false)
    : wide(wide)
  {
  }
  /// A leaf's outputs at `time`, marked `leafId` (its veins may be null).
  void Add(
    const WiltingSimulation& simulation, vtkPolyData* leaf, vtkPolyData* leafVeins, vtkTypeInt64 leafId, double time);
  /// Ports 0, 1 and 3 of `out` (port 0's field data with `simulationCount`), when any leaf was added; `out.frames`
  /// is not used (the rows are gathered by the caller).
  void Write(int simulationCount, const WiltingLeafOutputs& out);
  /// The frame tables' rows, a first column LeafId (port 2, to gather).
  vtkTable* Rows() { return this->rows; }

private:
  vtkNew<vtkAppendPolyData> leaves, veins;
  vtkNew<vtkAppendFilter> voxels;
  vtkNew<vtkTable> rows;
  double served = 0.0;
  bool wide = false;
};

} // namespace plantmorph
