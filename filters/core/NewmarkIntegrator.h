// Implicit Newmark time integration with Newton-Raphson for a MassSpringSystem (spec 04 "Integrator"; paper 001
// sec. 2). Plain C++17 + Eigen, no VTK.
//
// The equations of motion M a + C v + R(q) = f(t), q the displacements, with Rayleigh damping
// C = alpha M + beta K(q) + D (K the tangent stiffness at the current Newton iterate, D the springs' dashpots), are
// stepped exactly as VegaFEM's ImplicitNewmarkSparse does (so that benchmarks/wilting_plate can be checked
// against it):
//
//   a1 = 1/(b dt^2), a2 = 1/(b dt), a3 = (1 - 2b)/(2b), a4 = g/(b dt), a5 = 1 - g/b, a6 = (1 - g/(2b)) dt
//   (b = NewmarkBeta, g = NewmarkGamma)
//   q_s, v_s, a_s: the state at the start of the step; the iterate q starts at q_s, and for the iterate
//       accel(q) = a1 (q - q_s) - a2 v_s - a3 a_s,   vel(q) = a4 (q - q_s) + a5 v_s + a6 a_s
//   Newton iteration: K = K(q), C = alpha M + beta K + D,
//       r = M accel(q) + C vel(q) + R(q) - f(t_{s+1}),
//       stop if |r|^2 <= NewtonTolerance^2 |r_0|^2 (r_0 the first residual of the step; VegaFEM's test),
//       solve (a1 M + a4 C + K) dq = -r on the free degrees of freedom, q += dq.
//   The step ends with v_{s+1} = vel(q), a_{s+1} = accel(q). Fixed nodes stay at zero.
//
// With MaxIterations = 1 (the paper's and VegaFEM's choice) this is one linearised implicit step per time step;
// more iterations converge to the fully implicit average-acceleration step, which conserves the energy of a linear
// system exactly.
//
// The system matrix is kept in the springs' own layout: per spring s I + t n n^T (the (a, b) off-diagonal block is
// minus it) and a 3x3 diagonal block per node. Springs are cut into 16 fixed spatial slabs; the slabs' springs are
// assembled (and multiplied) in parallel, touching disjoint nodes, then the springs joining two slabs serially:
// every sum is taken in the same order on any thread count (bit-identical results), no atomics.
// Two linear solvers:
//   - ConjugateGradient: block-Jacobi (3x3 per node) preconditioned CG, warm-started from the previous step's
//     increment, stopped when r^T P^-1 r <= CGTolerance^2 b^T P^-1 b (VegaFEM's Jacobi CG test with x0 = 0),
//     matrix-vector products and reductions threaded (MassSpringThreads, fixed partitions);
//   - Cholesky: Eigen's SimplicialLDLT on the free degrees of freedom, the sparsity pattern analysed once (AMD
//     ordering), factorised every Newton iteration (exact to round-off).
//   - Auto picks Cholesky below AutoCholeskyMaxNodes free nodes and CG above (benchmarks/README.md, "wilting").
#pragma once

#include "MassSpringSystem.h"
#include "MassSpringThreads.h"

#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

namespace plantmorph
{

enum class NewmarkSolver : int
{
  Auto = 0,
  Cholesky = 1,
  ConjugateGradient = 2
};

struct NewmarkParameters
{
  double timeStep = 1.0 / 240.0;
  double newmarkBeta = 0.25;
  double newmarkGamma = 0.5;
  double rayleighMass = 0.0;      ///< alpha of C = alpha M + beta K
  double rayleighStiffness = 0.0; ///< beta
  int maxIterations = 1;          ///< Newton iterations per step
  double newtonTolerance = 1e-6;  ///< relative residual norm that ends the Newton iterations early
  bool compressionClamp = true;   ///< clamp (1 - L/l) at 0 in the tangent stiffness
  NewmarkSolver solver = NewmarkSolver::Auto;
  double cgTolerance = 1e-6;      ///< relative (preconditioned) residual of the CG solve
  int cgMaxIterations = 10000;
  int threads = 1;                ///< <= 0: all hardware threads
};

/// Free nodes up to this count use Cholesky under NewmarkSolver::Auto: CG won at every measured size (1k, 10k, 100k
/// nodes, benchmarks/README.md "wilting"); only tiny models keep the exact direct solve.
inline constexpr std::size_t AutoCholeskyMaxNodes = 200;

/// Empty when the parameters are usable; otherwise a message naming the parameter and its range.
std::string ValidateNewmark(const NewmarkParameters& parameters);

/// Accumulated wall-clock seconds of the two halves of a step, and counters.
struct NewmarkTimings
{
  double assemblySeconds = 0.0; ///< springs, forces, residual, system matrix (and Eigen's value fill)
  double solveSeconds = 0.0;    ///< factorisation + solve, or CG
  long long steps = 0;
  long long newtonIterations = 0;
  long long cgIterations = 0;
};

class NewmarkIntegrator
{
public:
  NewmarkIntegrator();
  ~NewmarkIntegrator();

  /// Binds a finalized system (kept by reference: it must outlive the integrator) and resets to rest. Empty on
  /// success, else a message.
  std::string Setup(const MassSpringSystem& system, const NewmarkParameters& parameters);

  /// Rest: q = v = a = 0, time 0.
  void Reset();
  /// Any state (3 per node each; fixed nodes are zeroed) at `time`.
  void SetState(const std::vector<double>& q, const std::vector<double>& v, const std::vector<double>& a, double time);

  /// One step to time + dt under the external force `force` (3 per node) at the step's end. Empty on success;
  /// else a message (the solver failed, a non-finite value appeared) and the state is that of the step's start.
  std::string Step(const std::vector<double>& force);

  const std::vector<double>& Displacement() const { return this->Q; }
  const std::vector<double>& Velocity() const { return this->V; }
  const std::vector<double>& Acceleration() const { return this->A; }
  double Time() const { return this->CurrentTime; }
  const NewmarkTimings& Timings() const { return this->Timing; }
  NewmarkSolver ActiveSolver() const { return this->Solver; }
  const NewmarkParameters& Parameters() const { return this->Params; }

private:
  void Assemble(const std::vector<double>& force, double& residualNorm2);
  bool SolveCG();
  bool SolveCholesky();
  double MultiplySystem(const double* x, double* y) const;

  const MassSpringSystem* System = nullptr;
  NewmarkParameters Params;
  NewmarkSolver Solver = NewmarkSolver::ConjugateGradient;
  std::unique_ptr<MassSpringThreads> Threads;
  double Alpha[7] = { 0, 0, 0, 0, 0, 0, 0 };
  double CurrentTime = 0.0;
  std::vector<double> Q, V, A;    // state
  std::vector<double> Q1, V1, A1; // start of the step
  // The springs in part order: those of part p (both ends in it) in [PartOffsets[p], PartOffsets[p + 1]), the
  // springs joining two parts after PartOffsets[Parts]. The system's block of a spring is s I + t n n^T.
  struct CompactSpring
  {
    int a, b;
    double s, t, n[3];
  };
  struct SpringMaterial
  {
    double stiffness, damping, restLength;
  };
  std::vector<CompactSpring> Compact;
  std::vector<SpringMaterial> Material;
  std::vector<std::size_t> PartOffsets;
  std::vector<double> NodeBlock;     // 6 per node: the system's diagonal block
  std::vector<double> Rhs;           // -r, 3 per node (0 on fixed nodes)
  std::vector<double> Delta;         // the increment, 3 per node
  std::vector<double> PreviousDelta; // warm start
  std::vector<double> CGr, CGz, CGd, CGq, Precond; // CG work (Precond: inverse diagonal blocks, 6 per node)
  struct CholeskyData;
  std::unique_ptr<CholeskyData> Chol;
  NewmarkTimings Timing;
};

} // namespace plantmorph
