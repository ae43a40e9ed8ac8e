// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkCloudComparisonFilter
 * @brief   Distances from measured points (a scan) to a reference surface or point cloud (a simulated leaf), with
 *          statistics, a histogram and optional ICP registration (docs/methods/comparison.md).
 *
 * Related publications:
 * - J. A. Baerentzen, H. Aanaes, "Signed distance computation using the angle weighted pseudonormal", IEEE TVCG
 *   11(3), 2005 (SignedDistance);
 * - Y. Chen, G. Medioni, "Object modelling by registration of multiple range images", Image and Vision Computing
 *   10(3), 1992 (point-to-plane ICP);
 * - S. Umeyama, "Least-squares estimation of transformation parameters between two point patterns", IEEE TPAMI
 *   13(4), 1991.
 * Full references: docs/references.md. What the code does, and where and why it departs from the paper:
 * docs/methods/comparison.md.
 *
 * vtkCloudComparisonFilter takes two inputs. Port 0, **Measured**: any vtkPointSet; only its points are compared,
 * whatever its cells (one poly-vertex, one vertex per point, no cells at all, or a mesh). Port 1, **Reference**:
 * a vtkPolyData with polygons or triangle strips (or any vtkPointSet with 2-D cells: triangles, quads, pixels,
 * polygons, strips) is a *surface*; a vtkPointSet without 2-D cells is a *point cloud* (its points).
 *
 * For every measured point, after multiplying its coordinates by Scale (unit mismatch, e.g. 0.1 for a scan in mm
 * against a model in cm) and applying the registration (if any):
 * - `Distance`: to a surface, the exact Euclidean distance to the nearest triangle (closed-form closest point on a
 *   triangle, Ericson 5.1.5; polygons are triangulated first, quads and pixels into two triangles, larger polygons
 *   by vtkPolygon's ear cutting); to a point cloud, the distance to the nearest reference point. The BVH only
 *   prunes the search: the result equals the brute-force minimum over all triangles (tested).
 * - `SignedDistance` (surfaces only): the distance signed by the angle-weighted pseudo-normal of the nearest
 *   feature (face, edge or vertex; Baerentzen and Aanaes 2005): positive on the side the triangles' normals point to
 *   (right-hand rule on their point order), so + is outside a closed, outward-wound surface and above a
 *   LeafOutlineSource blade (upper side +Z). On an open surface, points beyond the margin take the margin's side.
 * - `ClosestPoint`: the nearest point on the reference (double x3).
 * - `Outlier` (only with UseMaximumDistance): 1 where Distance > MaximumDistance. Outliers keep their distances
 *   but are left out of the statistics, the histogram and the registration fit; their number is reported.
 *
 * Output port 0: the measured points (transformed by Scale and registration, in double precision when transformed,
 * else the input's own points) with all their point arrays passed through plus the arrays above. The cells of a
 * vtkPolyData input are kept; any other input (or a vtkPolyData without cells) gets one vertex cell per point, so
 * ParaView draws it.
 *
 * Output port 1: a vtkTable histogram of the kept distances, HistogramBins equal bins over [min, max]:
 * `bin_extents` (bin centres; the name ParaView's Histogram filter uses, so the bar chart view picks it as x),
 * `bin_values` (counts), `BinStart`, `BinEnd`, `Fraction` (count / kept points).
 *
 * Output port 2: a one-row vtkTable of statistics (also written to port 0's field data under the same names):
 * `Count` (kept points), `Outliers`, `Minimum`, `Maximum`, `Mean`, `StandardDeviation` (population), `RMS`,
 * `Percentile50`, `Percentile68`, `Percentile75`, `Percentile95`, `Percentile99` (linear interpolation at rank
 * p/100 (n-1), numpy's default), `Hausdorff` (one-sided, measured to reference: the largest kept distance),
 * `ReferenceIsSurface`. With Symmetric on, the reverse comparison is made too: every reference point to the
 * measured data, *the forward computation with the inputs swapped* (measured taken as a surface if it is a
 * vtkPolyData with polygons, else as points); columns `ReverseCount`, `ReverseMean`, `ReverseHausdorff`,
 * `SymmetricHausdorff` (the larger one-sided one) and `Chamfer` (mean of the two mean distances). Defined this way,
 * both are exactly symmetric under swapping the inputs. A surface's reverse direction is sampled at its vertices
 * (the supremum over the continuous surface is not computed).
 *
 * Registration (docs/methods/comparison.md): None; Rigid (ICP: a rotation and translation); Rigid + scale (one uniform scale
 * too). Symmetric ICP (plantmorph::RegisterPoints with the reference's points, filters/comparison/core/RigidRegistration.h):
 * point-to-point pairs both ways, every measured landmark to its closest reference point and every reference point
 * to its nearest measured landmark (Umeyama each iteration), so the scale cannot collapse and a flat leaf's in-plane
 * turn or scale is seen by its outline; then a rigid point-to-plane polish against a surface, kept only if it does
 * not worsen the fit. On at most RegistrationLandmarks points per side (a strided subset), outliers
 * (UseMaximumDistance) left out. Guard: if the registered result's symmetric mean distance is larger than the
 * unregistered one, a warning says so and the unregistered result is output. ICP is local: bring the two roughly
 * into place first. Field data of port 0: `PlantMorph.MeasuredTransform` (16 components, row-major 4x4 from the
 * input's coordinates to the output's, Scale included; present in every mode), `PlantMorph.RegistrationScale`,
 * `PlantMorph.RegistrationIterations`, `PlantMorph.RegistrationConverged`, `PlantMorph.RegistrationRMS`,
 * `PlantMorph.RegistrationSymmetricBefore`, `PlantMorph.RegistrationSymmetricAfter`,
 * `PlantMorph.RegistrationRejected` (1 when the guard refused the registration).
 *
 * Errors (a vtkErrorMacro naming the input or property and the accepted range, and EMPTY outputs on all three
 * ports, never a crash): a missing or empty Reference, a reference with a non-finite coordinate, Scale not finite
 * or <= 0, MaximumDistance not finite or < 0 (when used), HistogramBins outside [1, 100000], registration
 * properties out of range, a measured point with a non-finite coordinate (its index is named), a registration
 * that finds fewer than 3 pairs. An empty Measured input gives empty outputs without an error (an MPI piece with
 * no points).
 *
 * Under MPI (pvbatch, pvserver) the filter is data-parallel (CloudComparisonExchange.h, docs/methods/comparison.md
 * "Under MPI"): Measured stays on its ranks, each comparing its own points; Reference is gathered and broadcast to
 * every rank (it is expected small: a leaf, a plant; it is replicated whatever its size). Per-point arrays equal the
 * serial ones bit for bit; statistics, exact percentiles, histogram and the registration's transform are reduced
 * over the ranks in a fixed order (equal to serial: counts, extremes, percentiles and the transform exactly, sums to
 * about one rounding). Ports 1 and 2 are on rank 0; the field data on every rank's piece.
 *
 * Queries run in parallel with vtkSMPTools (NumberOfThreads; the Sequential backend ParaView ships with is
 * replaced by STDThread for the filter's run) in blocks, with progress and abort between blocks.
 */
#ifndef vtkCloudComparisonFilter_h
#define vtkCloudComparisonFilter_h

#include "PlantMorphComparisonVTKModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

namespace plantmorph
{
class Run;
}

class PLANTMORPHCOMPARISONVTK_EXPORT vtkCloudComparisonFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkCloudComparisonFilter* New();
  vtkTypeMacro(vtkCloudComparisonFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum RegistrationModes
  {
    REGISTRATION_NONE = 0,
    REGISTRATION_RIGID = 1,
    REGISTRATION_RIGID_SCALE = 2,
  };

  /// The reference (surface or point set), input port 1.
  void SetReferenceConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetReferenceData(vtkDataObject* data) { this->SetInputData(1, data); }

  // The setters do not clamp: a value outside its range is an error when the filter runs (empty outputs).

  ///@{
  /** Factor applied to the measured coordinates before anything else (0.1: a scan in mm against a model in cm).
   * Range (0, inf). Default 1. */
  vtkSetMacro(Scale, double);
  vtkGetMacro(Scale, double);
  ///@}

  ///@{
  /** REGISTRATION_NONE (default), REGISTRATION_RIGID or REGISTRATION_RIGID_SCALE. */
  vtkSetMacro(Registration, int);
  vtkGetMacro(Registration, int);
  ///@}

  ///@{
  /** ICP iterations at most, [1, 10000]. Default 100. */
  vtkSetMacro(RegistrationIterations, int);
  vtkGetMacro(RegistrationIterations, int);
  ///@}

  ///@{
  /** ICP stops when no landmark moves more than this times the landmarks' bounding-box diagonal, (0, 1).
   * Default 1e-7. */
  vtkSetMacro(RegistrationTolerance, double);
  vtkGetMacro(RegistrationTolerance, double);
  ///@}

  ///@{
  /** Measured (and reference) points used by ICP at most (every k-th point above it), [3, 10^8]. Default 20000. */
  vtkSetMacro(RegistrationLandmarks, int);
  vtkGetMacro(RegistrationLandmarks, int);
  ///@}

  ///@{
  /**
   * Ignored (it was the seed of a random landmark subset; registration now takes every k-th point, see
   * RegistrationLandmarks). Kept, and hidden in the panel, so that state files saved with it still load.
   */
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /** Outlier cut-off: when on, distances above MaximumDistance are outliers. Default off, 1.0. */
  vtkSetMacro(UseMaximumDistance, vtkTypeBool);
  vtkGetMacro(UseMaximumDistance, vtkTypeBool);
  vtkBooleanMacro(UseMaximumDistance, vtkTypeBool);
  vtkSetMacro(MaximumDistance, double);
  vtkGetMacro(MaximumDistance, double);
  ///@}

  ///@{
  /** Also compare the reference's points to the measured data (reverse Hausdorff, symmetric Hausdorff, Chamfer).
   * Default off. */
  vtkSetMacro(Symmetric, vtkTypeBool);
  vtkGetMacro(Symmetric, vtkTypeBool);
  vtkBooleanMacro(Symmetric, vtkTypeBool);
  ///@}

  ///@{
  /** Histogram bins, [1, 100000]. Default 32. */
  vtkSetMacro(HistogramBins, int);
  vtkGetMacro(HistogramBins, int);
  ///@}

  ///@{
  /** Threads for the queries: 0 all cores, 1 serial, up to 256. Default 0. */
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

protected:
  vtkCloudComparisonFilter();
  ~vtkCloudComparisonFilter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Scale = 1.0;
  int Registration = REGISTRATION_NONE;
  int RegistrationIterations = 100;
  double RegistrationTolerance = 1e-7;
  int RegistrationLandmarks = 20000;
  int Seed = 0;
  vtkTypeBool UseMaximumDistance = 0;
  double MaximumDistance = 1.0;
  vtkTypeBool Symmetric = 0;
  int HistogramBins = 32;
  int NumberOfThreads = 0;

private:
  /// RequestData's body (plantmorph::RunRequestData): checks NumberOfThreads, replicates the reference and compares
  /// on the threads asked for.
  void Execute(plantmorph::Run& run);

  vtkCloudComparisonFilter(const vtkCloudComparisonFilter&) = delete;
  void operator=(const vtkCloudComparisonFilter&) = delete;
};

#endif
