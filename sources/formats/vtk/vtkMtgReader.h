// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkMtgReader
 * @brief   Reads an MTG file (multiscale tree graph, FORM-A text of OpenAlea's openalea.mtg, AMAPmod, XploRer,
 *          MultiScaleTreeGraph.jl) as polylines, one per axis, with every feature (docs/formats/mtg.md).
 *
 * The axes are those of the finest scale where some entity has XX, YY, ZZ (each entity's point, as openalea.mtg's
 * PlantFrame takes them): entities joined by '<' form an axis, '+' starts one. Without coordinates anywhere the
 * finest scale is laid out by default in the XY plane (y up; each entity one Length, else 1, further; a branch at 45
 * degrees to its bearer's axis, alternately left and right) and a warning says so. An entity of the geometry scale
 * without coordinates is placed on its axis between the measured ones around it, linearly by rank (a warning counts
 * them).
 *
 * Output: one polyline per axis, in file order (a bearer's axis before its branches). With ConnectBranches (default
 * on) a branch's polyline starts at its bearer's point, so it touches its parent: the form TreeFromSketchSource's
 * Strokes input takes (its first line the trunk, each later one starting on its parent; strokes are read in the XY
 * plane, so rotate a Z-up plant to Y up first) and its MergeTree input (BranchId, ParentId, Radius).
 * Cell data: `BranchId` (the axis' number in file order), `ParentId` (its bearer's axis, -1 for none), `BranchOrder`.
 * Point data: `EntityId` (the entity the point stands for, numbered in file order from 1; the bearer's for a
 * branch's first point), `Label` (its code label, e.g. E3), `Scale<s>Id` and `Scale<s>Label` for every coarser scale s
 * >= 1 (the entity it is a component of at that scale), every feature under its own name (INT and REAL as doubles,
 * NaN where missing; STRING, ALPHA and dates as strings, "" where missing), and `Radius` (half the first of diam,
 * Diameter, diameter, TopDia, TopDiameter the file has). Field data: PlantMorph.SourceFile, PlantMorph.MtgScale,
 * PlantMorph.ExplicitCoordinates.
 *
 * Errors (an error naming FileName and the line, and an empty output): no FileName, a file that cannot be opened,
 * anything the grammar does not allow (an undeclared symbol or feature, '^' with no line above in its column, a value
 * that is not of its feature's type, a '<' or '+' to a finer scale, a line of more than 65536 characters, a NUL byte).
 * One linear pass over the file (the parser is sources/formats/core/MtgText.h). The tree is made on the first rank.
 */
#ifndef vtkMtgReader_h
#define vtkMtgReader_h

#include "PlantMorphFormatsVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

namespace plantmorph
{
class Run;
}

class PLANTMORPHFORMATSVTK_EXPORT vtkMtgReader : public vtkPolyDataAlgorithm
{
public:
  static vtkMtgReader* New();
  vtkTypeMacro(vtkMtgReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /** The MTG file to read. */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /** 1 (default): a branch's polyline starts at its bearer's point; 0: only the branch's own entities. */
  vtkSetClampMacro(ConnectBranches, int, 0, 1);
  vtkGetMacro(ConnectBranches, int);
  vtkBooleanMacro(ConnectBranches, int);
  ///@}

  /** 1 if one of the file's first lines opens a FORM-A section (CODE:, CLASSES:, MTG:). */
  int CanReadFile(const char* name);

protected:
  vtkMtgReader();
  ~vtkMtgReader() override;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  int ConnectBranches = 1;

private:
  /// RequestData's body (plantmorph::RunRequestData): reads the file, writes the polylines.
  void Execute(plantmorph::Run& run);

  vtkMtgReader(const vtkMtgReader&) = delete;
  void operator=(const vtkMtgReader&) = delete;
};

#endif
