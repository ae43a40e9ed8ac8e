// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPlantMorphLASReader
 * @brief   Reads a LAS 1.0-1.4 point cloud (the lidar exchange format) as vtkPolyData with every attribute and
 *          extra-bytes dimension as a point array (docs/formats/las.md). Proxy: LASReader.
 *
 * Point formats 0-10 (the waveform packets of 4, 5, 9 and 10 are not read), coordinates scaled and offset as the
 * header says, stored as double precision points, one vertex cell each. Point arrays, named as PDAL names the
 * dimensions: Intensity, ReturnNumber, NumberOfReturns, ScanDirectionFlag, EdgeOfFlightLine, Classification,
 * ClassificationFlags (bit 0 synthetic, 1 key-point, 2 withheld, 3 overlap), ScannerChannel (formats 6-10),
 * ScanAngleRank (degrees, formats 0-5) or ScanAngle (0.006 degree units, formats 6-10), UserData, PointSourceId,
 * GpsTime, RGB (unsigned short x3, the file's values) with Colors (unsigned char x3, RGB / 257 when any value
 * exceeds 255, the active scalars, unless an extra-bytes dimension is named Colors) and NIR, in the storage types of the format. Every dimension the Extra Bytes
 * VLR describes (user LASF_Spec, record 4; PlantMorph's labels LeafId, Organ, BranchId, BeamId, ScanPosition among
 * them) becomes an array of its type (double when it has a scale or offset); dimensions Name_X, Name_Y, Name_Z
 * (or Name_0, Name_1, ...) of one type become one array Name of several components, as the LAS writer splits them.
 * Field data: PlantMorph.SourceFile, PlantMorph.LASVersion, PlantMorph.LASPointFormat, PlantMorph.LASScale,
 * PlantMorph.LASOffset (x, y, z), PlantMorph.LASSystemIdentifier, PlantMorph.LASGeneratingSoftware,
 * PlantMorph.LASGlobalEncoding, PlantMorph.LASFileSourceId; the LAS writer takes the scale and offset back.
 *
 * Errors (naming FileName and the header field, VLR or point record at fault; the output empty): no FileName, a
 * file that cannot be opened, a wrong signature, a header, VLR or point count the file's size cannot hold (never
 * a huge allocation), a record shorter than its format, a LAZ (compressed) file. The file is read once, in blocks
 * (sources/las/core/LasFile.h). Pieces (MPI: one per rank): piece p of N reads the header and point records
 * [R p / N, R (p + 1) / N) of the file's R, so the pieces in rank order hold every point once, in file order; the
 * ranks agree on failures (a header's error is said once).
 */
#ifndef vtkPlantMorphLASReader_h
#define vtkPlantMorphLASReader_h

#include "PlantMorphLasVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

namespace plantmorph
{
class Run;
}

class PLANTMORPHLASVTK_EXPORT vtkPlantMorphLASReader : public vtkPolyDataAlgorithm
{
public:
  static vtkPlantMorphLASReader* New();
  vtkTypeMacro(vtkPlantMorphLASReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The LAS file to read. */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  /** 1 if the file starts with the LAS signature "LASF". */
  int CanReadFile(const char* name);

protected:
  vtkPlantMorphLASReader();
  ~vtkPlantMorphLASReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;

private:
  void Execute(plantmorph::Run& run);

  vtkPlantMorphLASReader(const vtkPlantMorphLASReader&) = delete;
  void operator=(const vtkPlantMorphLASReader&) = delete;
};

#endif
