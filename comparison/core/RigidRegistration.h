// CloudComparisonFilter's optional registration (docs/methods/comparison.md): iterative closest point (ICP)
// that moves the measured points onto the reference, rigidly or rigidly with one uniform scale. Plain C++17 + Eigen.
//
// Each iteration finds, for every landmark (the measured points, or a seeded random subset of them when there are
// more than maximumLandmarks), its exact closest point on the reference with PointSurfaceDistance, then:
// - reference surface: point-to-plane ICP (Chen and Medioni 1992): the least-squares motion that moves each landmark
//   onto the tangent plane of its closest triangle, linearised about the landmarks' centroid (rotation vector,
//   translation, and the scale change when asked), solved as a 6x6 (7x7) normal system, applied as an exact
//   rotation and composed with the transform so far. It converges in a few iterations where point-to-point ICP
//   crawls along the surface, and a cloud sampled exactly from a moved copy of the reference is put back to
//   rounding. A tiny ridge term leaves directions the surface does not fix (sliding along a plane) unchanged.
// - reference point cloud: point-to-point ICP, the closed-form similarity between the ORIGINAL landmarks and their
//   nearest reference points (Umeyama 1991, Eigen::umeyama; rotation from the SVD of the cross-covariance with the
//   reflection fix, scale from the variance when asked).
// Pairs farther apart than rejectDistance (when >= 0) are left out of the fit (outliers, e.g. a petiole the model
// lacks). In rigid mode the final rotation is re-orthonormalised.
//
// It stops when the transform moves no landmark by more than tolerance times the landmarks' bounding-box diagonal
// between two iterations (converged), or after maximumIterations. ICP finds a local minimum: put the two roughly in
// place first (same units: apply the unit scale before; a rough translation or rotation with ParaView's Transform
// filter when they are far apart). The landmark subset is drawn with RandomStream(seed), so results are
// reproducible.
#pragma once

#include "PointSurfaceDistance.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace plantmorph
{

struct RegistrationSettings
{
  bool withScale = false;          ///< rigid + one uniform scale instead of rigid
  int maximumIterations = 100;     ///< [1, 10000]
  double tolerance = 1e-7;         ///< relative to the landmarks' bounding-box diagonal, (0, 1)
  std::size_t maximumLandmarks = 20000; ///< >= 3; more measured points than this: a random subset
  double rejectDistance = -1.0;    ///< < 0: no rejection
  std::uint64_t seed = 0;
};

struct RegistrationResult
{
  /// Row-major 4x4 homogeneous matrix taking a measured point x to s R x + t (last row 0 0 0 1).
  double matrix[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  double scale = 1.0;
  int iterations = 0;
  bool converged = false;
  double rms = 0.0;           ///< RMS distance of the fitted landmark pairs after the final transform
  std::size_t landmarks = 0;  ///< landmarks used
  std::string error;          ///< empty on success
};

/// Validates settings; empty string when fine.
std::string ValidateRegistrationSettings(const RegistrationSettings& settings);

/// Least-squares similarity (or rigid motion) taking source[i] to target[i] (x,y,z triples), Umeyama's closed form.
/// Returns false (matrix untouched) if fewer than 3 pairs or the problem is degenerate (all points coincide).
bool FitSimilarity(const double* source, const double* target, std::size_t count, bool withScale, double matrix[16]);

/// Applies a row-major 4x4 matrix to count x,y,z triples (in may equal out).
void ApplyTransform(const double matrix[16], const double* in, double* out, std::size_t count);

/// ICP of `count` points (x,y,z triples) onto `reference` (built). Threads the closest-point queries with
/// `parallelFor`.
RegistrationResult RegisterPoints(const double* points, std::size_t count, const PointSurfaceDistance& reference,
  const RegistrationSettings& settings, const ParallelFor& parallelFor = SerialFor);

} // namespace plantmorph
