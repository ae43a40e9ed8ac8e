// SPDX-License-Identifier: GPL-3.0-or-later
// Implicit Newmark time integration with Newton-Raphson for a MassSpringSystem (docs/methods/wilting.md; paper 001
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
// The system matrix is kept in the springs' own layout: per spring s I + m m^T (m = sqrt(t) n; the (a, b)
// off-diagonal block is minus it) and a 3x3 diagonal block per node. The solver numbers the nodes by their rest
// positions (sorted along the longest axis, then the middle, then the shortest: neighbours end up close in memory)
// and every per-node quantity (residual, diagonal block, A x) is a gather over the node's row of springs in a fixed
// order; reductions are cut into fixed chunks added in order. So the results are bit-identical on any thread count
// and for any numbering of the same geometry, with no atomics, no partition and no serial part.
// Two linear solvers:
//   - ConjugateGradient: block-Jacobi (3x3 per node) preconditioned CG in Chronopoulos and Gear's form (two passes
//     over the nodes per iteration: one gathering A u, one local), warm-started from the linear extrapolation
//     2 d_{s-1} - d_{s-2} of the last two steps' increments, stopped when r^T P^-1 r <= CGTolerance^2 b^T P^-1 b
//     (VegaFEM's Jacobi CG test with x0 = 0), every pass threaded (MassSpringThreads, fixed chunks);
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
  double cgTolerance = 1e-6; ///< relative (preconditioned) residual of the CG solve
  int cgMaxIterations = 10000;
  bool extrapolateWarmStart = true; ///< CG starts from 2 d_{s-1} - d_{s-2} (else from d_{s-1})
  int threads = 1;                  ///< <= 0: all hardware threads
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
  /// Replaces the springs' rest lengths for the following steps (one per spring of the bound system, in its
  /// order, each > 0): a material whose rest shape changes in time (WiltingSimulation's shrinkage). Setup takes the
  /// system's own.
  void SetRestLengths(const std::vector<double>& restLengths);

  const std::vector<double>& Displacement() const { return this->Q; }
  const std::vector<double>& Velocity() const { return this->V; }
  const std::vector<double>& Acceleration() const { return this->A; }
  double Time() const { return this->CurrentTime; }
  const NewmarkTimings& Timings() const { return this->Timing; }
  NewmarkSolver ActiveSolver() const { return this->Solver; }
  const NewmarkParameters& Parameters() const { return this->Params; }

private:
  /// Setup's steps: the solver's node order (and each node's mass, fixedness, rest position in it), the springs in
  /// the order of their ends, each node's row of springs, and the work arrays.
  void OrderNodes(const MassSpringSystem& system);
  void OrderSprings(const MassSpringSystem& system);
  void BuildRows();
  void ResetWorkspace();
  void Assemble(const std::vector<double>& force, double& residualNorm2);
  bool SolveCG();
  bool SolveCholesky();
  double MultiplySystem(const double* x, double* y) const;
  void WarmStart();
  void MultiplyRow(std::size_t node, const double* x, double* y) const;

  const MassSpringSystem* System = nullptr;
  NewmarkParameters Params;
  NewmarkSolver Solver = NewmarkSolver::ConjugateGradient;
  std::unique_ptr<MassSpringThreads> Threads;
  double Alpha[7] = { 0, 0, 0, 0, 0, 0, 0 };
  double CurrentTime = 0.0;
  std::vector<double> Q, V, A;                   // state
  std::vector<double> Q1, V1, A1;                // start of the step, in the solver's node order
  std::vector<double> SolverQ, SolverV, SolverA; // the state in the solver's node order
  // Per spring (in the system's order): the ends, the system's block s I + m m^T, the material, and g_e, the
  // spring's term of the residual (-R on a, +R on b). Per node: its springs as a row (the other end and the
  // spring), so every per-node sum is a gather in a fixed order: no scatter, no atomics, no partition.
  struct SpringEnds
  {
    int a, b;
  };
  struct SpringBlock // s I + m m^T
  {
    double s, m[3];
  };
  struct SpringMaterial
  {
    double stiffness, damping, restLength;
  };
  struct RowEntry
  {
    int node, spring;
  };
  std::vector<int> Order;                  // solver position -> system node
  std::vector<int> Position;               // system node -> solver position
  std::vector<double> NodeMass;            // by solver position
  std::vector<char> NodeFixed;             // by solver position
  std::vector<Eigen::Vector3d> RestSolver; // by solver position
  std::vector<SpringEnds> Ends;            // solver positions of the spring's a and b ends
  std::vector<SpringBlock> Blocks;
  std::vector<SpringMaterial> Material;
  std::vector<int> SystemSpring;     // the system's index of each spring in the solver's order
  std::vector<double> SpringTerm;    // g_e, 3 per spring
  std::vector<int> RowOffsets;       // NodeCount() + 1
  std::vector<RowEntry> Rows;        // 2 per spring, solver positions
  std::vector<signed char> RowSign;  // -1 where the row's node is the spring's a end, else +1
  std::vector<double> NodeBlock;     // 6 per node: the system's diagonal block
  std::vector<double> Rhs;           // -r, 3 per node (0 on fixed nodes)
  std::vector<double> Delta;         // the increment, 3 per node
  std::vector<double> PreviousDelta; // warm start: the last step's first increment
  std::vector<double> OlderDelta;    // and the one before
  int WarmSteps = 0;                 // how many of the two are known
  // CG work (Chronopoulos-Gear form): residual r, preconditioned residual u = P r, w = A u, direction p, s = A p;
  // Precond: the inverse diagonal blocks, 6 per node.
  std::vector<double> CGr, CGz, CGd, CGq, CGw, Precond;
  struct CholeskyData;
  std::unique_ptr<CholeskyData> Chol;
  NewmarkTimings Timing;
};

} // namespace plantmorph
