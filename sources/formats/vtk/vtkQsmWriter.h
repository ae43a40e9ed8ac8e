// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkQsmWriter
 * @brief   Writes cylinders as a QSM table, the SimpleForest / rTwig CSV (docs/formats/qsm.md).
 *
 * Columns: ID, parentID, startX, startY, startZ, endX, endY, endZ, axisX, axisY, axisZ (the unit direction), radius,
 * length (|end - start|), branchID, branchOrder, then every other one-component numeric cell array under its own
 * name. Numbers are written in their shortest exact form (a table read by vtkQsmReader and written again is the same
 * numbers), NaN as NA.
 *
 * Two kinds of input (lines of a polydata):
 * - cylinders, as vtkQsmReader makes them (Tubes off): every line has two points, a cell array names the parent
 *   (parentID, parent), and one names the ID (id, ID, cylinder_id) or none is BranchId (TreeQSM's table: the row
 *   number is the ID). ID and parent are written as they are, the radius from the
 *   cell array radius (else the mean of the point array Radius at the two ends), branchID and branchOrder from the
 *   cell arrays branchID (or branch) and branchOrder (or branch_order), else 0;
 * - any other polylines with a point array Radius (TreeFromSketchSource's Skeleton, a Tube filter's input): each
 *   segment one cylinder, ids 1, 2, ... in order, the radius the mean of its two points', a segment's parent the one
 *   before it; with cell arrays BranchId and ParentId a polyline's first segment's parent is the parent polyline's
 *   segment ending at its point nearest to the first point, branchID is BranchId and branchOrder the cell array
 *   BranchOrder (or Depth), else the depth below the root polyline.
 *
 * Errors (and no file written): no FileName, an input without lines, polylines without a Radius point array, a file
 * that cannot be written. Under MPI the input is gathered on the first rank, which writes the file.
 */
#ifndef vtkQsmWriter_h
#define vtkQsmWriter_h

#include "PlantMorphFormatsVTKModule.h" // for export macro
#include "vtkWriter.h"

namespace plantmorph
{
class Run;
}

class PLANTMORPHFORMATSVTK_EXPORT vtkQsmWriter : public vtkWriter
{
public:
  static vtkQsmWriter* New();
  vtkTypeMacro(vtkQsmWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The CSV file to write. */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

protected:
  vtkQsmWriter();
  ~vtkQsmWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  /// Under MPI asks the input for this rank's piece (WriterPieces.h), then as vtkWriter.
  vtkTypeBool ProcessRequest(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  void WriteData() override {} // RequestData writes (through plantmorph::RunRequestData)

  char* FileName = nullptr;

private:
  void Execute(plantmorph::Run& run);

  vtkQsmWriter(const vtkQsmWriter&) = delete;
  void operator=(const vtkQsmWriter&) = delete;
};

#endif
