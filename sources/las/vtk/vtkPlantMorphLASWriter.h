// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPlantMorphLASWriter
 * @brief   Writes the points of a point set and their numeric point arrays as a LAS 1.2 or 1.4 file
 *          (docs/formats/las.md); File > Save Data offers it for point data as "LAS point cloud (PlantMorph)".
 *
 * Point arrays named like a LAS attribute of the point format (Intensity, ReturnNumber, NumberOfReturns,
 * Classification, ClassificationFlags, ScanDirectionFlag, EdgeOfFlightLine, ScannerChannel, ScanAngleRank or
 * ScanAngle, UserData, PointSourceId, GpsTime, RGB, NIR; see vtkPlantMorphLASReader) with integer values in its
 * range go there; RGB may also come from Colors (unsigned char, x 257) when there is no RGB array. Every other
 * numeric point array (PlantMorph's labels LeafId, Organ, BranchId, BeamId, ScanPosition, VirtualScanner's Range
 * and Intensity, Normals as Normals_X, _Y, _Z, ...) is an extra-bytes dimension of its own type, described in the
 * Extra Bytes VLR so that other tools (CloudCompare, PDAL, lasinfo) see it, in the order of their names (so the
 * file does not depend on the order of the arrays, which gathering the pieces under MPI changes). Arrays whose names start with "vtk" and
 * string arrays are not written. Cells, cell data and field data other than the scale and offset are not written.
 *
 * Version 1.4 (default) or 1.2; PointFormat -1 (default) picks the smallest format of the version that holds the
 * cloud's GpsTime, RGB and NIR (6, 7, 8; or 0-3). Scale 0 (default): the scale and offset the input's field data
 * PlantMorph.LASScale / LASOffset give (a cloud read by LASReader) when every point fits them, else per axis the
 * finest power of ten whose 32-bit integers reach the points from the offset (the middle of the extent), so every
 * coordinate comes back within half the scale. The file is written to FileName.partial and renamed when complete:
 * a failed write leaves no file.
 */
#ifndef vtkPlantMorphLASWriter_h
#define vtkPlantMorphLASWriter_h

#include "PlantMorphLasVTKModule.h" // for export macro
#include "vtkWriter.h"

#include <string>

class PLANTMORPHLASVTK_EXPORT vtkPlantMorphLASWriter : public vtkWriter
{
public:
  static vtkPlantMorphLASWriter* New();
  vtkTypeMacro(vtkPlantMorphLASWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The LAS file to write. */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /** The LAS minor version: 4 (LAS 1.4, default) or 2 (LAS 1.2). */
  vtkSetMacro(Version, int);
  vtkGetMacro(Version, int);
  ///@}

  ///@{
  /** The point data record format: -1 (default) chosen from the arrays, or 0-3 (and 6-8 with LAS 1.4). */
  vtkSetMacro(PointFormat, int);
  vtkGetMacro(PointFormat, int);
  ///@}

  ///@{
  /** The coordinates' scale (every axis): 0 (default) chosen, else this (the offset is then chosen). */
  vtkSetMacro(Scale, double);
  vtkGetMacro(Scale, double);
  ///@}

  /** The last write's attributes: "standard: ...; extra bytes: ...; scale: ...". */
  const char* GetLastWriteSummary() { return this->Summary.c_str(); }

protected:
  vtkPlantMorphLASWriter();
  ~vtkPlantMorphLASWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  void WriteData() override;

  char* FileName = nullptr;
  int Version = 4;
  int PointFormat = -1;
  double Scale = 0.0;
  std::string Summary;

private:
  vtkPlantMorphLASWriter(const vtkPlantMorphLASWriter&) = delete;
  void operator=(const vtkPlantMorphLASWriter&) = delete;
};

#endif
