// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkTrajectoryComparisonFilter
 * @brief   Compares a measured trajectory (a leaf tip's positions over time) with a simulated one: matched samples,
 *          distances and their components, mean and maximum, and the angle between the motion directions
 *          (docs/methods/comparison.md; paper 001 sec. 3, Table 1).
 *
 * Related publication: [P001] Miao Teng, Guo Xinyu, Wen Weiliang, Lu Shenglian, "A physically based representation
 * of leaf wilting" (in Chinese), Transactions of the Chinese Society for Agricultural Machinery 45(5), 2014: sec. 3,
 * Table 1.
 * Full references: docs/references.md. What the code does, and where and why it departs from the paper:
 * docs/methods/comparison.md.
 *
 * Input port 0, **Measured**, and input port 1, **Simulated**: each a vtkTable (e.g. a CSV file read by ParaView's
 * CSV reader, such as data/cucumber-wilting-tip.csv, or WiltingSimulator's Trajectory port) or a vtkPointSet (e.g.
 * Table To Points' output). From a table the x, y, z columns named by MeasuredColumns / SimulatedColumns are read
 * (any numeric type). Their default, "auto" (or empty), recognises the known layouts, the first found in this order:
 * Measured: measured_x/y/z (the tip CSV), x/y/z, X/Y/Z, TipX/TipY/TipZ (WiltingSimulator's Trajectory port),
 * paper_sim_x/y/z, Points_0/1/2; Simulated: TipX/TipY/TipZ, paper_sim_x/y/z, x/y/z, X/Y/Z, Points_0/1/2,
 * measured_x/y/z. So the defaults chain: a simulated trajectory compared with itself or with the tip CSV needs no
 * column typed; a table with none of them is refused with an error listing them and its columns. From a point set,
 * its points. Samples are taken in row (point) order, which must be time order. An optional time column or point
 * array named TimeColumn (default "auto": time, Time or t, whichever is present) is carried into the output (it
 * does not enter the matching).
 *
 * Matchings (plantmorph::CompareTrajectories, filters/comparison/core/TrajectoryMatching.h):
 * - Closest sample (paper 001's): each measured sample to the nearest simulated sample, independently.
 * - Time-monotone: strictly increasing simulated indices minimising the summed distance (dynamic programming). It
 *   needs at least as many simulated as measured samples and at most 2*10^7 measured x simulated pairs; otherwise
 *   only the closest-sample columns are written, with a warning.
 *
 * Output port 0, one row per measured sample: `Sample`, `MeasuredX/Y/Z`, (`MeasuredTime`), then for each matching
 * (prefix `Closest` and `Monotone`): `...Index` (the simulated row), (`...Time`), `...X/Y/Z` (the simulated
 * position), `...Distance`, `...DX/DY/DZ` (simulated minus measured; paper 001 prints their absolute values).
 * Output port 1, one summary row: `MeasuredSamples`, `SimulatedSamples`, and per matching `...MeanDistance`,
 * `...MaxDistance`, `...DirectionAngle` (degrees between the measured last-minus-first direction and the matched
 * simulated last-minus-first direction; on paper 001's Table 1, 6.1 degrees, where the paper prints 19.1 which its
 * own unit vectors do not give). The summary is also written to port 0's field data.
 *
 * Errors (vtkErrorMacro naming the input, column or property, and EMPTY outputs, never a crash): a missing input,
 * a table without the named column (the available ones are listed) or with a non-numeric one, "auto" columns that
 * match no known layout, fewer than 2 samples in either input (the direction angle needs two; one sample used to
 * give a NaN angle), a non-finite coordinate. Both inputs empty: a warning naming them and empty outputs (on MPI
 * ranks other than 0 an empty share is expected and silent).
 */
#ifndef vtkTrajectoryComparisonFilter_h
#define vtkTrajectoryComparisonFilter_h

#include "PlantMorphComparisonVTKModule.h" // for export macro
#include "vtkTableAlgorithm.h"

#include <string>

namespace plantmorph
{
class Run;
}

class PLANTMORPHCOMPARISONVTK_EXPORT vtkTrajectoryComparisonFilter : public vtkTableAlgorithm
{
public:
  static vtkTrajectoryComparisonFilter* New();
  vtkTypeMacro(vtkTrajectoryComparisonFilter, vtkTableAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The simulated trajectory, input port 1.
  void SetSimulatedConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetSimulatedData(vtkDataObject* data) { this->SetInputData(1, data); }

  ///@{
  /**
   * The measured table's x, y and z columns, one name each (the panel's MeasuredX/Y/Z column menus). Default
   * "auto" (or empty): the recognised layouts above. Ignored for a point set. GetMeasuredColumn(i) is the name in
   * use: the column's own setting, else SetMeasuredColumns's (the three-name property of scripts and states
   * written before the menus), else "auto".
   */
  void SetMeasuredX(const char* name) { this->SetColumn(this->MeasuredColumn[0], name); }
  void SetMeasuredY(const char* name) { this->SetColumn(this->MeasuredColumn[1], name); }
  void SetMeasuredZ(const char* name) { this->SetColumn(this->MeasuredColumn[2], name); }
  void SetMeasuredColumns(const char* x, const char* y, const char* z);
  std::string GetMeasuredColumn(int i) const { return Chosen(this->MeasuredColumn[i], this->MeasuredColumns[i]); }
  ///@}

  ///@{
  /** The simulated table's x, y and z columns, likewise (SimulatedX/Y/Z; SimulatedColumns in older scripts). */
  void SetSimulatedX(const char* name) { this->SetColumn(this->SimulatedColumn[0], name); }
  void SetSimulatedY(const char* name) { this->SetColumn(this->SimulatedColumn[1], name); }
  void SetSimulatedZ(const char* name) { this->SetColumn(this->SimulatedColumn[2], name); }
  void SetSimulatedColumns(const char* x, const char* y, const char* z);
  std::string GetSimulatedColumn(int i) const { return Chosen(this->SimulatedColumn[i], this->SimulatedColumns[i]); }
  ///@}

  ///@{
  /** Optional time column (table) or point array (point set), looked up in both inputs; empty or absent: none.
   * Default "time". */
  void SetTimeColumn(const char* name);
  const char* GetTimeColumn() const { return this->TimeColumn.c_str(); }
  ///@}

protected:
  vtkTrajectoryComparisonFilter();
  ~vtkTrajectoryComparisonFilter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  /// The per-column settings (the panel's menus) and the three-name settings (older scripts and states): a column's
  /// own setting wins unless it is "auto" or empty, so the two properties never depend on the order ParaView pushes
  /// them in.
  std::string MeasuredColumn[3] = { "auto", "auto", "auto" };
  std::string SimulatedColumn[3] = { "auto", "auto", "auto" };
  std::string MeasuredColumns[3] = { "auto", "auto", "auto" };
  std::string SimulatedColumns[3] = { "auto", "auto", "auto" };

  void SetColumn(std::string& column, const char* name);
  static std::string Chosen(const std::string& own, const std::string& legacy)
  {
    return own.empty() || own == "auto" ? (legacy.empty() ? std::string("auto") : legacy) : own;
  }
  std::string TimeColumn = "auto";

private:
  /// RequestData's body (plantmorph::RunRequestData): reads both trajectories, compares them, writes both ports.
  void Execute(plantmorph::Run& run);
  vtkTrajectoryComparisonFilter(const vtkTrajectoryComparisonFilter&) = delete;
  void operator=(const vtkTrajectoryComparisonFilter&) = delete;
};

#endif
