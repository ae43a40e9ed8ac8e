// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkVirtualScanner
 * @brief   Simulated scans of any surface: a terrestrial laser scanner, a line (profile) scanner on a path or a
 *          turntable, or a depth camera, with occlusion, range noise, jitter and dropout
 *          (docs/methods/virtual-scanner.md).
 *
 * Input: a vtkPolyData surface (polygons and triangle strips; vertices and lines are not scanned), e.g. a leaf, a
 * wilting frame, a tree with leaves, several plants appended. Every beam of the scanner's pattern is cast through
 * an Embree 3 hierarchy of the surface (filters/scanner/core/RayCaster.h: Embree's robust single-precision triangles find
 * the candidates, each re-tested with its neighbours by a double-precision watertight test, so no beam slips between
 * two triangles of a surface whose triangles share their points, and the hit point lies on its triangle in double
 * precision) and returns the nearest hit within MaximumRange. The triangulated surface and its hierarchy are kept
 * between runs while the input is unchanged (serial runs; under MPI they are rebuilt every run), so changing the
 * scanner's properties does not rebuild them; they are released with the filter or when the input changes.
 *
 * Output port 0, the cloud: one vertex per point, in beam order, with point arrays `Normals` (the unit normal of
 * the polygon hit, turned to face the scanner), `Range` (measured, model units), `Intensity` (cos of the incidence
 * angle, over the true range squared when IntensityFalloff is on), `ScanPosition` (the scanner pose: position
 * index for Terrestrial and Depth camera, fan index along the path for Line, position * TurntableSteps + step on a
 * turntable), `HitCellId` (the input cell hit), `BeamId` (the beam's index in the pattern), and every cell array of
 * the input carried from the hit cell as a point array of the same name (`Region`, `BranchId`, `LeafId`, ...; a
 * cell array named like one of ours is not carried). The input's point arrays follow, unless a cell array or one
 * of ours has the name: floating-point ones (`LeafUV`, `TCoords`) interpolated at the hit with its barycentric
 * weights, integer ones (labels) from the hit triangle's vertex nearest the hit. Field data: PlantMorph.Beams, PlantMorph.Returns,
 * PlantMorph.Dropped, PlantMorph.Seed, PlantMorph.ScannerType. Output port 1, the set-up: per pose (at most 200
 * shown) its central beam and the beams at the corners of its field as lines as long as the distance from the
 * first position to LookAt, and a line scanner's path, with the cell array `ScanPosition` (-1 on the path).
 *
 * Same input, properties and Seed: the same cloud bit for bit, whatever the number of threads. Under MPI the
 * surface is gathered on rank 0 (if it was split) and replicated on every rank, and each rank casts its consecutive
 * share of the beams (every random number depends on the beam alone), so the ranks' pieces in rank order are the
 * serial cloud; the set-up lines are on rank 0, the field data's totals on every rank.
 *
 * Errors (vtkErrorMacro naming the property and its accepted range, and empty outputs): out-of-range or non-finite
 * properties, no position, LookAt on a position, a surface without polygons or with non-finite points, a beam count
 * over MaximumBeams (refused before anything is built or cast).
 */
#ifndef vtkVirtualScanner_h
#define vtkVirtualScanner_h

#include "PlantMorphScannerVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for the prepared surface
#include <string> // for error messages
#include <vector> // for the positions

namespace plantmorph
{
class Run;
struct ScannerParameters;
}

class PLANTMORPHSCANNERVTK_EXPORT vtkVirtualScanner : public vtkPolyDataAlgorithm
{
public:
  static vtkVirtualScanner* New();
  vtkTypeMacro(vtkVirtualScanner, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  // Setters do not clamp: an out-of-range value is reported when the filter runs (and the outputs are empty).

  ///@{
  /** 0 Terrestrial (default), 1 Line (path or turntable), 2 Depth camera. */
  vtkSetMacro(ScannerType, int);
  vtkGetMacro(ScannerType, int);
  ///@}

  ///@{
  /**
   * Scanner positions (x, y, z), model units. Terrestrial and Depth camera: one scan per position, merged. Line on
   * a path: the path's vertices. Line on a turntable: one scanner per position. Default one position (0, -5, 1).
   */
  void ClearPositions();
  void AddPosition(double x, double y, double z);
  int GetNumberOfPositions() const { return static_cast<int>(this->Positions.size() / 3); }
  /// The number of values the Positions property held (its server-side helper, vtkSICountedDoubleVectorProperty,
  /// sets it after the rows): a count that is not a multiple of three is refused when the filter runs. -1 (set by
  /// ClearPositions): not given, the rows added are all there is.
  void SetPositionsElementCount(int count);
  ///@}

  ///@{
  /**
   * The point the scanners look at. A line scanner on a path looks at it from the middle of the path and keeps that
   * direction, so the middle fan looks at LookAt and the fans sweep a strip centred on it side by side (looking at
   * the one point from every position would put every fan, which spans Up, through the same line of the surface).
   */
  vtkSetVector3Macro(LookAt, double);
  vtkGetVector3Macro(LookAt, double);
  ///@}

  ///@{
  /** Up: the vertical of the Terrestrial grid's azimuth and elevation, the camera's and the fan's up. Default z. */
  vtkSetVector3Macro(Up, double);
  vtkGetVector3Macro(Up, double);
  ///@}

  ///@{
  /**
   * Fields of view, degrees: horizontal (0, 360] and vertical (0, 180] for Terrestrial, both (0, 180) for the
   * Depth camera; a line scanner's fan opens over VerticalFieldOfView. Defaults 60 and 40.
   */
  vtkSetMacro(HorizontalFieldOfView, double);
  vtkGetMacro(HorizontalFieldOfView, double);
  vtkSetMacro(VerticalFieldOfView, double);
  vtkGetMacro(VerticalFieldOfView, double);
  ///@}

  ///@{
  /** Angle between neighbouring beams (Terrestrial grid, Line fan), degrees [1e-4, 90]. Default 0.2. */
  vtkSetMacro(AngularStep, double);
  vtkGetMacro(AngularStep, double);
  ///@}

  ///@{
  /** Depth camera: pixels across and down, each [1, 100000]. Default 640 x 480. */
  vtkSetVector2Macro(Resolution, int);
  vtkGetVector2Macro(Resolution, int);
  ///@}

  ///@{
  /**
   * Line scanner: 0 along the path through Positions, a fan every LineSpacing (model units, > 0; default 0.01);
   * 1 on a turntable turning about TurntableAxis through LookAt, TurntableSteps fans per turn [1, 1e6] (360).
   */
  vtkSetMacro(LineMotion, int);
  vtkGetMacro(LineMotion, int);
  vtkSetMacro(LineSpacing, double);
  vtkGetMacro(LineSpacing, double);
  vtkSetMacro(TurntableSteps, int);
  vtkGetMacro(TurntableSteps, int);
  vtkSetVector3Macro(TurntableAxis, double);
  vtkGetVector3Macro(TurntableAxis, double);
  ///@}

  ///@{
  /**
   * Noise: RangeNoise, the standard deviation of the range (model units, [0, 1e6]); AngularJitter, of each beam's
   * direction (degrees, [0, 10]); DropoutProbability, of a hit returning nothing ([0, 1]). All from Seed
   * ([0, 1000000]; outside it the filter refuses to run, naming Seed).
   */
  vtkSetMacro(RangeNoise, double);
  vtkGetMacro(RangeNoise, double);
  vtkSetMacro(AngularJitter, double);
  vtkGetMacro(AngularJitter, double);
  vtkSetMacro(DropoutProbability, double);
  vtkGetMacro(DropoutProbability, double);
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /** Hits farther than this return nothing, model units (0, 1e30]. Default 1000. */
  vtkSetMacro(MaximumRange, double);
  vtkGetMacro(MaximumRange, double);
  ///@}

  ///@{
  /** Intensity = cos(incidence) / range^2 when on (default), cos(incidence) alone when off. */
  vtkSetMacro(IntensityFalloff, bool);
  vtkGetMacro(IntensityFalloff, bool);
  vtkBooleanMacro(IntensityFalloff, bool);
  ///@}

  ///@{
  /** The most beams a run may cast [1, 4e9] (default 5e7); more is refused before any work, with a message. */
  vtkSetMacro(MaximumBeams, double);
  vtkGetMacro(MaximumBeams, double);
  ///@}

protected:
  vtkVirtualScanner();
  ~vtkVirtualScanner() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int ScannerType = 0;
  std::vector<double> Positions{ 0.0, -5.0, 1.0 };
  int PositionsElementCount = -1;
  double LookAt[3] = { 0.0, 0.0, 0.0 };
  double Up[3] = { 0.0, 0.0, 1.0 };
  double HorizontalFieldOfView = 60.0;
  double VerticalFieldOfView = 40.0;
  double AngularStep = 0.2;
  int Resolution[2] = { 640, 480 };
  int LineMotion = 0;
  double LineSpacing = 0.01;
  int TurntableSteps = 360;
  double TurntableAxis[3] = { 0.0, 0.0, 1.0 };
  double RangeNoise = 0.0;
  double AngularJitter = 0.0;
  double DropoutProbability = 0.0;
  int Seed = 0;
  double MaximumRange = 1000.0;
  bool IntensityFalloff = true;
  double MaximumBeams = 5e7;

public:
  struct PreparedSurface; // the triangulated input and its caster, kept while the input is unchanged (internal)

private:
  /// RequestData's body (plantmorph::RunRequestData): the parameters, the prepared surface, the cast, both ports.
  void Execute(plantmorph::Run& run);
  /// The scanner parameters from the properties; "" or the message naming the first bad one.
  std::string ReadParameters(plantmorph::ScannerParameters& p) const;
  /// Triangulates `input` (the replicated `original`) and builds its ray caster, unless the last run prepared the
  /// same unchanged input (serial runs only).
  void Prepare(plantmorph::Run& run, vtkPolyData* original, vtkPolyData* input, int ranks);

  std::shared_ptr<PreparedSurface> Prepared;

  vtkVirtualScanner(const vtkVirtualScanner&) = delete;
  void operator=(const vtkVirtualScanner&) = delete;
};

#endif
