// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkQsmReader
 * @brief   Reads a QSM cylinder table (TreeQSM's text output, or a SimpleForest / rTwig CSV) as one line or one
 *          closed tube per cylinder, every column kept as a cell array (docs/formats/qsm.md).
 *
 * TreeQSM text: one cylinder per line, blank-separated, 14 or 17 columns by position (radius, length, start_x..z,
 * axis_x..z, parent, extension, branch, branch_order, position_in_branch, [mad, SurfCov,] added, [UnmodRadius]) or
 * under TreeQSM's own header (start_point and axis_direction name three columns each); a '#' line after the cylinders
 * ends the table. CSV: a header naming ID, parentID, startX, startY, startZ, endX, endY, endZ (or axisX, axisY, axisZ
 * and length) and radius, in any case, with or without '_' (start_x) and units in parentheses; any other column is
 * kept. Missing values (NA, NaN, empty) read as NaN, TRUE / FALSE as 1 / 0.
 *
 * Output: Tubes off (default), one line (start, end) per cylinder with point array `Radius` (for ParaView's Tube
 * filter, Vary Radius By Absolute Scalar); Tubes on, a closed tube of `Sides` sides per cylinder (`Radius` on its
 * points). Cell data: every column of the table as a double array under its header's name (TreeQSM's positional
 * columns under the names above); a repeated name gets a suffix _2, _3, ... Field data: PlantMorph.SourceFile.
 *
 * Errors (an error naming FileName and the line, and an empty output): no FileName, a file that cannot be opened, a
 * field that is not a number, a row with another number of columns, a table without radius, start or end columns, a
 * cylinder without start, end or radius, a line of more than 65536 characters or 1000 columns, a NUL byte. One linear
 * pass (sources/formats/core/QsmTable.h). The cylinders are made on the first rank.
 */
#ifndef vtkQsmReader_h
#define vtkQsmReader_h

#include "PlantMorphFormatsVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

namespace plantmorph
{
class Run;
}

class PLANTMORPHFORMATSVTK_EXPORT vtkQsmReader : public vtkPolyDataAlgorithm
{
public:
  static vtkQsmReader* New();
  vtkTypeMacro(vtkQsmReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The cylinder table to read (.txt TreeQSM text, .csv SimpleForest / rTwig). */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /** 0 (default): one line per cylinder; 1: one closed tube per cylinder. */
  vtkSetMacro(Tubes, int);
  vtkGetMacro(Tubes, int);
  vtkBooleanMacro(Tubes, int);
  ///@}

  ///@{
  /** Sides of each tube (3..256, default 12). */
  vtkSetMacro(Sides, int);
  vtkGetMacro(Sides, int);
  ///@}

  /** 1 if the file reads as a QSM cylinder table. */
  int CanReadFile(const char* name);

protected:
  vtkQsmReader();
  ~vtkQsmReader() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  int Tubes = 0;
  int Sides = 12;

private:
  void Execute(plantmorph::Run& run);

  vtkQsmReader(const vtkQsmReader&) = delete;
  void operator=(const vtkQsmReader&) = delete;
};

#endif
