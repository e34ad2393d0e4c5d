#pragma once
// Finite-length hydrodynamic journal bearing: the Reynolds equation (seed 002 eq. 1)
//   (1/R^2) d/dtheta (h^3 dp/dtheta) + d/dx (h^3 dp/dx) = 6 mu Omega dh/dtheta + 12 mu dh/dt
// solved by finite volumes on (theta, x), and the film forces (seed 002 eq. 3).
//
// Frame and film. Rig frame x right, y up; theta is the bore-wall angle counter-clockwise
// from +x, the direction of spin (see wear_geometry.hpp). The journal centre sits at
// (x, y) from the bore centre, so the film is h = C - x cos(theta) - y sin(theta) + delta_h(theta)
// (seed 002 eq. 2 and 4 written in this frame) and dh/dt = -(vx cos + vy sin). The force
// of the film on the journal is F = -int p (cos theta, sin theta) R dtheta dx.
//
// Discretisation. Cells of equal size, centres at theta_i = (i + 1/2) 2 pi / N_theta
// (periodic) and x_j in (-L/2, L/2) with p = 0 (ambient, gauge) at both ends; the oil
// supply pressure is neglected. The circumferential flux between two cell centres is the
// exact one-dimensional one for a film that varies between them: with
// q = -h^3/(12 mu) dp/ds + U h / 2 constant from centre to centre,
//   p_{i+1} - p_i = 6 mu U I2 - 12 mu q I3,   I2 = int ds / h^2,  I3 = int ds / h^3,
// and the two integrals are taken piecewise by Gauss quadrature, split at the edges of the
// wear. A jump of h or of dh/dtheta (the edges of the worn span) therefore costs no accuracy
// and needs no smoothing: this is the flux-continuity treatment of film discontinuities
// (Arghir et al.; the 2D extension of seed 002 ref. [13]) in finite-volume form.
//
// Film rupture (selectable):
//  reynolds (default): Swift-Stieber / Reynolds condition, p >= 0 with zero flux out of the
//    cavitated zone, as the linear complementarity problem p >= 0, A p - b >= 0,
//    p (A p - b) = 0, solved exactly by a primal-dual active-set method (A is an M-matrix, so
//    the iteration is monotone and finite). Not mass-conserving (no Elrod/JFO reformation).
//  gumbel: half-Sommerfeld: the full solution with negative pressures discarded.
//  none: full Sommerfeld (negative pressures kept).
//
// Allocation happens in the constructor; solve() reuses the working memory (host side, not
// a real-time path).
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <array>
#include <complex>
#include <vector>

#include "model/journal/wear_geometry.hpp"

namespace amb::model::journal {

struct BearingGeometry {
  double bore_radius_m = 0.0;   ///< R: bearing radius (bore diameter / 2), m
  double length_m = 0.0;        ///< L: axial width, m
  double clearance_m = 0.0;     ///< C: radial clearance of the unworn bore, m
  double viscosity_pa_s = 0.0;  ///< mu: dynamic viscosity of the oil, Pa s
};

enum class Cavitation : int { reynolds = 0, gumbel = 1, none = 2 };

struct ReynoldsOptions {
  int cells_theta = 72;               ///< circumferential cells (>= 12)
  int cells_axial = 12;               ///< axial cells over the full width (>= 2)
  Cavitation cavitation = Cavitation::reynolds;
  int max_active_set_iterations = 100;///< reynolds only
  int gauss_points = 3;               ///< per smooth piece of each centre-to-centre interval (1..4)
  /// Raimondi & Boyd's (1958) inlet condition: p = 0 on the axial line of cells whose centre
  /// has the largest film (the full film starts at the maximum film thickness), Reynolds
  /// condition at the trailing edge. false (default): the complementarity problem alone
  /// decides where the full film starts. For the comparison with their tables
  /// (tests/journal/raimondi_boyd_test.cpp); the journal should then sit so that the maximum
  /// film falls on a cell centre.
  bool zero_pressure_at_max_film = false;
  /// Solve only the half width x < 0 when cells_axial is even (zero axial flux through the
  /// mid-plane): the film of an untilted journal is symmetric, so the discrete solution is the
  /// full grid's at half the unknowns (2-4x faster). false: the full width (for the check).
  bool midplane_symmetry = true;
  /// Speed (reynolds cavitation only; the result does not change, tests/journal/
  /// reynolds_reuse_test.cpp):
  ///  - after an active-set iteration that changed the set, the next set is guessed by
  ///    projected Gauss-Seidel sweeps from the latest iterate (up to 100, alternately along
  ///    and against the spin, until two sweeps move no cell across p = 0): the full film
  ///    grows by one cell per plain iteration, a sweep carries it along the circumference
  ///    (the first 8 iterations of a solve; then the plain update, which terminates);
  ///  - an iteration whose set and journal position are those of the latest factorisation
  ///    solves with it instead of factorising the same matrix again;
  ///  - perturbation_coefficients takes the velocity steps first, each step from the
  ///    linearisation point's active set, and restores the solver's state at the end
  ///    instead of solving the point again.
  /// Every solve still ends with an exact factorisation whose set is self-consistent; the
  /// matrix is a function of the position and the active set, the factorisation of the
  /// matrix, and the complementarity problem's solution is unique: the result is that of
  /// false bit for bit. false: every iteration factorises, plain order (the reference).
  bool reuse_factorisation = true;
  /// Empty when valid, else the reason.
  const char* check() const;
};

/// Journal centre relative to the bore centre and its velocity.
struct JournalState {
  double x_m = 0.0, y_m = 0.0;        ///< m
  double vx_m_s = 0.0, vy_m_s = 0.0;  ///< m/s
};

struct FilmForces {
  double fx_n = 0.0, fy_n = 0.0;      ///< force of the film on the journal, N
  double max_pressure_pa = 0.0;
  double min_film_m = 0.0;
  int active_set_iterations = 0;
  bool converged = true;              ///< false: active-set iteration limit hit
};

struct DynamicCoefficients;

class ReynoldsSolver {
 public:
  /// Throws std::invalid_argument naming what is wrong (geometry, wear, options).
  ReynoldsSolver(const BearingGeometry& g, const WearParams& wear, const ReynoldsOptions& o = {});

  /// Film forces at a journal state and spin speed (rad/s, > 0). Throws std::invalid_argument
  /// if the journal touches the bore (film <= 0 somewhere) or the speed is not positive.
  /// The active set of the previous call is the starting guess (warm start).
  FilmForces solve(const JournalState& s, double spin_rad_s);

  /// Another wear of the same bore (geometry and grid unchanged): the next solve starts from
  /// this solver's active set (warm start; the result does not depend on the start) and
  /// reuses the symbolic analysis of the grid. Throws std::invalid_argument as the
  /// constructor for an invalid wear (the solver is then unchanged).
  void set_wear(const WearParams& wear);

  /// Work counters since construction (speed measurements; tests/bench).
  struct Counters {
    long solves = 0;            ///< solve() calls
    long iterations = 0;        ///< active-set iterations
    long factorisations = 0;    ///< sparse LDL^T factorisations
  };
  const Counters& counters() const { return counters_; }

  /// Pressure of the last solve, Pa, N_theta x N_axial (rows: theta cells).
  Eigen::MatrixXd pressure_pa() const;
  /// Cell-centre angle of row i, rad.
  double theta_rad(int i) const;
  const BearingGeometry& geometry() const { return g_; }
  const WearShape& wear() const { return wear_; }
  const ReynoldsOptions& options() const { return o_; }
  /// Film thickness at a wall angle for a journal position, m.
  double film_m(double theta_rad, double x_m, double y_m) const;

 private:
  void assemble(const JournalState& s, double spin_rad_s);
  // Fill a_ for the current active set (rows/columns of active cells become identity).
  void fill_matrix();
  // Guess the next active set from projected Gauss-Seidel sweeps (reuse_factorisation).
  void predict_active_set(int pinned_row);
  // (A p) with the unconstrained matrix (used for the multiplier w = A p - b).
  void base_matvec(const Eigen::VectorXd& p, Eigen::VectorXd& out) const;
  double axial(int i) const;
  friend DynamicCoefficients perturbation_coefficients(ReynoldsSolver&, const JournalState&, double, double);

  BearingGeometry g_;
  WearShape wear_;
  ReynoldsOptions o_;
  int nt_ = 0, nz_ = 0;                        // nz_: axial rows solved (half the cells when even)
  bool half_ = false;
  double dtheta_ = 0.0, dzeta_ = 0.0, pressure_scale_pa_ = 0.0;
  std::vector<double> cos_int_, sin_int_;      // per theta cell: int cos, int sin over the cell
  std::vector<double> gauss_x_, gauss_w_;      // on [0, 1]
  Eigen::VectorXd cond_theta_, couette_;       // per theta face i+1/2: Delta zeta / I3, I2 / I3
  Eigen::VectorXd h_cell_;                     // per theta cell, dimensionless
  Eigen::VectorXd rhs_, p_, w_;
  std::vector<char> active_;                   // 1: cell held at p = 0
  Eigen::SparseMatrix<double> a_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  bool pattern_analysed_ = false;
  // The latest factorisation: its active set and journal position (the matrix depends on the
  // position and the active set only); valid = false before the first one.
  bool factored_valid_ = false;
  double factored_x_m_ = 0.0, factored_y_m_ = 0.0;
  std::vector<char> factored_active_;
  Eigen::VectorXd b_;                          // right-hand side of the current active set
  Counters counters_;
};

/// Linearised film force about a journal state (seed 002 eq. 22-23), rotordynamic sign
/// convention: F = F0 - K dq - C dq', so K_ij = -dF_i/dq_j and C_ij = -dF_i/dq'_j (q = x, y).
struct DynamicCoefficients {
  double fx0_n = 0.0, fy0_n = 0.0;  ///< static force at the state, N
  Eigen::Matrix2d stiffness_n_per_m = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d damping_n_s_per_m = Eigen::Matrix2d::Zero();
};

/// Coefficients by central differences of the Reynolds solution: displacement steps of
/// `relative_step` * C and velocity steps of `relative_step` * C * spin.
/// Step: the film force is piecewise smooth, with a kink each time a cell joins or leaves the
/// cavitated set (the free boundary moves cell by cell). Steps of 1e-3 C (0.19 um here)
/// resolve single kinks, so K and C jittered by 0.5-2 % as a wear parameter moved by a
/// fraction of a degree (wear 3, beta 100-104 deg: Kyy -1.148, -1.125, -1.114, -1.126,
/// -1.138e5 N/m), which made the identification's cost rough. 1e-2 C (1.85 um, a tenth of
/// the smallest orbits on the rig) spans several switches: the same scan is monotone
/// (-1.133 ... -1.280e5) and the central-difference bias (step / minimum film)^2 stays
/// < 0.1 % at e = 0.7. The SIL plant and the identification both use this default.
DynamicCoefficients perturbation_coefficients(ReynoldsSolver& solver, const JournalState& s, double spin_rad_s,
                                              double relative_step = 1e-2);

/// Film force along a periodic journal orbit, as Fourier components over the spin angle phi:
/// the journal at q(phi) = q_mean + Re(sum_k Q_k e^{j k phi}), k = 1..N, N = q_m.size() (x, y;
/// m) with the velocity that orbit has at spin speed W (dq/dt = W dq/dphi), and the film force
/// F(phi) = F_mean + Re(sum_k F_k e^{j k phi} + ...). For the harmonic balance of a steady
/// unbalance response with the full (nonlinear) film: the linear coefficients give
/// F_k = -(K + j k W C) Q_k only to first order in the orbit.
struct FilmHarmonics {
  double fx_mean_n = 0.0, fy_mean_n = 0.0;                    ///< mean force over the orbit, N
  std::vector<std::array<std::complex<double>, 2>> harmonic_n;  ///< F_k (x, y), k = 1..N, N
  double min_film_m = 0.0;                                    ///< smallest film met along the orbit, m
};

/// `samples` equally spaced spin angles; one Reynolds solve each (warm-started). Throws
/// std::invalid_argument when the orbit touches the bore, `samples` < 8, N < 1 or
/// 2 N >= `samples`.
FilmHarmonics film_harmonics(ReynoldsSolver& solver, const JournalState& mean,
                             const std::vector<std::array<std::complex<double>, 2>>& q_m, double spin_rad_s,
                             int samples = 32);

}  // namespace amb::model::journal
