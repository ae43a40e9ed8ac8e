// SPDX-License-Identifier: GPL-3.0-or-later
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

struct RegistrationParameters
{
  bool withScale = false;               ///< rigid + one uniform scale instead of rigid
  int maximumIterations = 100;          ///< [1, 10000]
  double tolerance = 1e-7;              ///< relative to the landmarks' bounding-box diagonal, (0, 1)
  std::size_t maximumLandmarks = 20000; ///< >= 3; more measured points than this: a random subset
  double rejectDistance = -1.0;         ///< < 0: no rejection
  std::uint64_t seed = 0;
  /// The reference's points (x,y,z triples), optional. Given, the registration is symmetric (see SymmetricICP
  /// below) and guarded: it cannot shrink the measured cloud to a point, it sees sliding within a flat leaf's plane
  /// through the outline, and a result that fits worse than no registration is not used.
  const double* referencePoints = nullptr;
  std::size_t referenceCount = 0;
};

struct RegistrationResult
{
  // iterations never exceed maximumIterations (the symmetric stage and its polish share them); converged is true
  // only when the stage whose transform is returned met the tolerance. Measured points that cannot determine a
  // transform (UndeterminedRegistration) give the identity, 0 iterations, converged false and `warning`.
  /// Row-major 4x4 homogeneous matrix taking a measured point x to s R x + t (last row 0 0 0 1).
  double matrix[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
  double scale = 1.0;
  int iterations = 0;
  bool converged = false;
  double rms = 0.0;          ///< RMS distance of the fitted landmark pairs after the final transform
  std::size_t landmarks = 0; ///< landmarks used
  std::string error;         ///< empty on success
  /// Symmetric mode: the symmetric mean distance (half the mean measured-to-reference distance plus half the mean
  /// reference-point-to-measured distance) without registration and with the transform found. When the transform
  /// is worse, `worse` is set, `warning` says so, and matrix and scale are the identity (the unregistered result).
  double symmetricBefore = 0.0;
  double symmetricAfter = 0.0;
  bool worse = false;
  std::string warning;
};

/// Validates settings; empty string when fine.
std::string ValidateRegistrationParameters(const RegistrationParameters& settings);

/// Least-squares similarity (or rigid motion) taking source[i] to target[i] (x,y,z triples), Umeyama's closed form.
/// Returns false (matrix untouched) if fewer than 3 pairs or the problem is degenerate (all points coincide).
bool FitSimilarity(const double* source, const double* target, std::size_t count, bool withScale, double matrix[16]);

/// Empty when `count` measured points (x,y,z triples) can determine a registration; else the warning saying why
/// not: all the same point, all on one line, or fewer distinct points than the transform's unknowns (6 rigid, 7
/// with scale). RegisterPoints then keeps the identity with that warning and converged false.
std::string UndeterminedRegistration(const double* points, std::size_t count, bool withScale);

/// Applies a row-major 4x4 matrix to count x,y,z triples (in may equal out).
void ApplyTransform(const double matrix[16], const double* in, double* out, std::size_t count);

/// ICP of `count` points (x,y,z triples) onto `reference` (built). Threads the closest-point queries with
/// `parallelFor`.
///
/// With settings.referencePoints (symmetric mode): ICP whose pairs go both ways, each measured landmark to its
/// closest point on the reference AND each reference point (a strided subset of at most maximumLandmarks) to its
/// nearest moved landmark. The second half of the pairs makes the measured cloud cover the whole reference: scale
/// cannot collapse (a shrunken cloud leaves the reference's far points far away), and a flat leaf turned or scaled
/// within its plane is brought back by its outline (one-sided point-to-plane terms cannot see that). On a surface
/// each iteration is a Gauss-Newton step with the surface's tangent planes (the offsets along the surface of
/// reference points within the landmarks' cover in the gradient only), taken back and halved when it does not lower
/// the symmetric mean distance, and the stage ends with the best transform after three iterations without a 0.1 %
/// gain (or a step below the tolerance); on a point cloud, Umeyama's similarity of the pairs, then a one-sided
/// polish. Then the guard: the symmetric mean distance with and without the transform; if registration made it
/// worse, the identity is returned with `worse` and a warning.
RegistrationResult RegisterPoints(const double* points, std::size_t count, const PointSurfaceDistance& reference,
  const RegistrationParameters& settings, const ParallelFor& parallelFor = SerialFor);

} // namespace plantmorph
