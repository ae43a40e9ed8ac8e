// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkMtgWriter
 * @brief   Writes a tree skeleton (TreeFromSketchSource's Skeleton output: polylines with cell arrays BranchId and
 *          ParentId, point array Radius) as an MTG file that openalea.mtg reads (docs/formats/mtg.md).
 *
 * FORM-A with three scales below the root: plant P (1), axis A (2), segment S (3). Each polyline is one axis
 * A<BranchId>, each of its points one segment S<k> (k from 1) with features XX, YY, ZZ (the point) and diam (twice
 * Radius; left empty without a Radius point array or where it is not finite). Segments follow one another ('<'); a
 * branch's first segment branches ('+') on its parent's segment nearest to its first point; a polyline whose ParentId
 * is no other polyline's BranchId starts a plant. Numbers are written in their shortest exact form, so the
 * coordinates read back bit for bit (vtkMtgReader with ConnectBranches off gives the same polylines).
 *
 * Errors (an error naming what is wrong, and no file written): no FileName, an input without lines or without the
 * cell arrays BranchId and ParentId, a negative or repeated BranchId, ParentIds that form a cycle, a file that cannot
 * be written. Under MPI the input is gathered on the first rank, which writes the file.
 */
#ifndef vtkMtgWriter_h
#define vtkMtgWriter_h

#include "PlantMorphFormatsVTKModule.h" // for export macro
#include "vtkWriter.h"

namespace plantmorph
{
class Run;
}

class PLANTMORPHFORMATSVTK_EXPORT vtkMtgWriter : public vtkWriter
{
public:
  static vtkMtgWriter* New();
  vtkTypeMacro(vtkMtgWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The MTG file to write. */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

protected:
  vtkMtgWriter();
  ~vtkMtgWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  /// Under MPI asks the input for this rank's piece (WriterPieces.h), then as vtkWriter.
  vtkTypeBool ProcessRequest(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  void WriteData() override {} // RequestData writes (through plantmorph::RunRequestData)

  char* FileName = nullptr;

private:
  void Execute(plantmorph::Run& run);

  vtkMtgWriter(const vtkMtgWriter&) = delete;
  void operator=(const vtkMtgWriter&) = delete;
};

#endif
