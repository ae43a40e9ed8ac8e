// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkLeafCloudReader
 * @brief   Reads a measured leaf point cloud from a delimited text file (x, y, z [, nx, ny, nz [, r, g, b
 *          [, scalar ...]]]) as vtkPolyData, keeping its normals and colours (docs/methods/comparison.md).
 *
 * Related publication: the scans' format and data: R. Ando, Y. Ozasa, W. Guo, "Robust surface reconstruction of
 * plant leaves from 3D point clouds", Plant Phenomics, 2021 (data/leaf-clouds, MIT licence).
 * Full references: docs/references.md. What the code does, and where and why it departs from the paper:
 * docs/methods/comparison.md.
 *
 * The format is the one of the leaf scans in data/leaf-clouds (Ando, Ozasa, Guo 2021; docs/references.md): one point
 * per line, numbers separated by commas, semicolons, spaces or tabs. Blank lines and lines starting with '#' or '//'
 * are skipped; so is a first line that is not numeric (a header). Every data line must have the same number of columns,
 * at least 3. Columns by position:
 * - 0-2: x, y, z, stored as double precision points (the file's values exactly, no float rounding);
 * - 3-5: the normal, point array `Normals` (double x3, set as the active normals, as in the file: not re-normalised);
 * - 6-8: the colour, point array `Colors` (unsigned char x3, set as the active scalars so ParaView shows the scan's
 *   own colours with Map Scalars off): values all within [0, 1] in the file are taken as fractions and scaled by
 *   255 and rounded, otherwise as 0-255 values (clamped); the file's values are also kept as `RGB` (double x3);
 * - 9: `Scalar` (double), the files' unnamed tenth column;
 * - further columns: `Column10`, `Column11`, ... (double).
 * Files with 4 or 5 columns keep the columns after z as `Column3`, `Column4`; 7 or 8 columns keep 6, 7 the same way.
 *
 * A header naming every column (comma-, semicolon- or tab-separated, else space-separated; a UTF-8 byte order mark
 * and quotes are dropped) names them, and then no column is taken by position: the coordinates are `x`, `y`, `z`
 * (any case, any order) or `P_x`, `P_y`, `P_z` for a prefix P (the first found, not normal_; e.g. measured_x,
 * measured_y, measured_z of data/cucumber-wilting-tip.csv); `r`, `g`, `b` or `red`, `green`, `blue` are the colour
 * (`Colors` and `RGB` as above); `nx`, `ny`, `nz`, `normal_x`, `normal_y`, `normal_z` (or normalx.., n_x..) the
 * normal (`Normals`); every other column (intensity, classification, LeafId, ...) a point array named by the header.
 * A header naming no coordinates is refused (an error listing the names, and an empty port 0; port 1 still has the
 * table): reading (sample, measured_x, measured_y) as x, y, z would be silently wrong.
 *
 * Refused with the reason rather than misread: decimal commas (a data line that, split at blanks and semicolons, has
 * two or more fields, none with '.' or an exponent, one of the form digits,digits: `1,5 2,5 3,5`, `1,5;2,5;3,5`),
 * lines ending in a carriage return alone (old Mac line ends), and a FileName that is a directory.
 *
 * Each point gets one vertex cell (so ParaView draws it). Units are the file's (the soybean scans are in mm: set
 * CloudComparisonFilter's Scale to 0.1 to compare them with a model in cm). Field data `PlantMorph.SourceFile`
 * holds the file name.
 *
 * Output port 1 is the same file as a vtkTable, every column a double array named by the header line (a first
 * non-numeric line with one comma-, semicolon- or tab-separated name per column) or Column0, Column1, ... This reads
 * comma-separated tables with '#' comment lines, which ParaView 5.11's CSV reader cannot skip, such as
 * data/cucumber-wilting-tip.csv (columns sample, measured_x, ..., paper_sim_z), for
 * TrajectoryComparisonFilter.
 *
 * Pieces (MPI: one per rank): piece p of N parses its own byte range of the file, cut at line ends (the lines whose
 * preceding newline lies in bytes [p S/N, (p+1) S/N), piece 0 also the first line), after reading the file's head
 * up to its first data line (header, column count). The pieces in rank order hold the serial points and rows in
 * file order; under MPI the ranks agree on errors, line numbers and the colour scale (docs/methods/comparison.md
 * "Under MPI"). One piece: the whole file, as before.
 *
 * Errors (vtkErrorMacro naming FileName and the line, and an empty output): no FileName, a file that cannot be
 * opened, no data line, a non-numeric or non-finite value, a line with a different number of columns than the first.
 * Hostile files are refused the same way, in one linear pass (the parser is sources/leaf_cloud/core/PointCloudText.h): a line
 * of more than 2^20 characters or 1000 columns, a number of more than 512 characters or beyond a double's range,
 * binary junk. Progress is reported while reading (by bytes), and Abort stops the read with an error.
 */
#ifndef vtkLeafCloudReader_h
#define vtkLeafCloudReader_h

#include "PlantMorphLeafCloudVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string>

namespace plantmorph
{
class Run;
}

class PLANTMORPHLEAFCLOUDVTK_EXPORT vtkLeafCloudReader : public vtkPolyDataAlgorithm
{
public:
  static vtkLeafCloudReader* New();
  vtkTypeMacro(vtkLeafCloudReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The text file to read. */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  /** 1 if the file's first data line has 3 or more numeric columns (for ParaView's reader choice). */
  int CanReadFile(const char* name);

protected:
  vtkLeafCloudReader();
  ~vtkLeafCloudReader() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;

private:
  /// RequestData's body (plantmorph::RunRequestData): reads this piece, writes the points and the table.
  void Execute(plantmorph::Run& run);

  vtkLeafCloudReader(const vtkLeafCloudReader&) = delete;
  void operator=(const vtkLeafCloudReader&) = delete;
};

#endif
