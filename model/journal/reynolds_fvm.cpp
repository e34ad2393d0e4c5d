#include "model/journal/reynolds_fvm.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>
#include <string>

namespace amb::model::journal {
namespace {
constexpr double k_two_pi = 2.0 * M_PI;
constexpr int k_predicted_iterations = 8;  // active-set iterations that take the sweeps' guess

void gauss_legendre_01(int n, std::vector<double>& x, std::vector<double>& w) {
  // Nodes and weights on [0, 1].
  switch (n) {
    case 1: x = {0.5}; w = {1.0}; break;
    case 2: x = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)}; w = {0.5, 0.5}; break;
    case 3: {
      const double d = 0.5 * std::sqrt(0.6);
      x = {0.5 - d, 0.5, 0.5 + d};
      w = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
      break;
    }
    default: {
      const double a = std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * std::sqrt(1.2));
      const double b = std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * std::sqrt(1.2));
      const double wa = (18.0 + std::sqrt(30.0)) / 36.0, wb = (18.0 - std::sqrt(30.0)) / 36.0;
      x = {0.5 - 0.5 * b, 0.5 - 0.5 * a, 0.5 + 0.5 * a, 0.5 + 0.5 * b};
      w = {0.5 * wb, 0.5 * wa, 0.5 * wa, 0.5 * wb};
    }
  }
}
}  // namespace

const char* ReynoldsOptions::check() const {
  if (cells_theta < 12) return "cells_theta must be >= 12";
  if (cells_axial < 2) return "cells_axial must be >= 2";
  if (max_active_set_iterations < 1) return "max_active_set_iterations must be >= 1";
  if (gauss_points < 1 || gauss_points > 4) return "gauss_points must be 1..4";
  return "";
}

ReynoldsSolver::ReynoldsSolver(const BearingGeometry& g, const WearParams& wear, const ReynoldsOptions& o)
    : g_(g), o_(o) {
  if (!(g.bore_radius_m > 0.0)) throw std::invalid_argument("journal bearing: bore_radius_m must be > 0");
  if (!(g.length_m > 0.0)) throw std::invalid_argument("journal bearing: length_m must be > 0");
  if (!(g.clearance_m > 0.0) || !(g.clearance_m < 0.1 * g.bore_radius_m))
    throw std::invalid_argument("journal bearing: clearance_m must be > 0 and below 10 % of the radius");
  if (!(g.viscosity_pa_s > 0.0)) throw std::invalid_argument("journal bearing: viscosity_pa_s must be > 0");
  if (const std::string why = o.check(); !why.empty()) throw std::invalid_argument("journal bearing: " + why);
  wear_ = WearShape(wear, g.bore_radius_m, g.clearance_m);

  nt_ = o.cells_theta;
  // The film is symmetric about the mid-plane (the journal state has no tilt): with an even
  // number of axial cells only the half x < 0 is solved, with zero axial flux through the
  // mid-plane. The discrete solution is the full grid's, at half the unknowns.
  half_ = o.midplane_symmetry && o.cells_axial % 2 == 0;
  nz_ = half_ ? o.cells_axial / 2 : o.cells_axial;
  dtheta_ = k_two_pi / nt_;
  dzeta_ = 1.0 / o.cells_axial;
  gauss_legendre_01(o.gauss_points, gauss_x_, gauss_w_);
  cos_int_.resize(static_cast<size_t>(nt_));
  sin_int_.resize(static_cast<size_t>(nt_));
  for (int i = 0; i < nt_; ++i) {
    const double a = i * dtheta_, b = (i + 1) * dtheta_;
    cos_int_[static_cast<size_t>(i)] = std::sin(b) - std::sin(a);
    sin_int_[static_cast<size_t>(i)] = std::cos(a) - std::cos(b);
  }
  const int n = nt_ * nz_;
  cond_theta_.resize(nt_);
  couette_.resize(nt_);
  h_cell_.resize(nt_);
  rhs_ = Eigen::VectorXd::Zero(n);
  p_ = Eigen::VectorXd::Zero(n);
  w_ = Eigen::VectorXd::Zero(n);
  b_ = Eigen::VectorXd::Zero(n);
  active_.assign(static_cast<size_t>(n), 0);

  // Five-point pattern, periodic in theta: row k = i * nz + j.
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(5 * n));
  for (int i = 0; i < nt_; ++i)
    for (int j = 0; j < nz_; ++j) {
      const int k = i * nz_ + j;
      t.emplace_back(k, k, 1.0);
      t.emplace_back(k, ((i + nt_ - 1) % nt_) * nz_ + j, 0.0);
      t.emplace_back(k, ((i + 1) % nt_) * nz_ + j, 0.0);
      if (j > 0) t.emplace_back(k, k - 1, 0.0);
      if (j + 1 < nz_) t.emplace_back(k, k + 1, 0.0);
    }
  a_.resize(n, n);
  a_.setFromTriplets(t.begin(), t.end());
  a_.makeCompressed();
}

void ReynoldsSolver::set_wear(const WearParams& wear) {
  wear_ = WearShape(wear, g_.bore_radius_m, g_.clearance_m);
  factored_valid_ = false;  // the matrix depends on the film, so on the wear
}

double ReynoldsSolver::theta_rad(int i) const { return (i + 0.5) * dtheta_; }

double ReynoldsSolver::film_m(double theta, double x_m, double y_m) const {
  return g_.clearance_m - x_m * std::cos(theta) - y_m * std::sin(theta) + wear_.extra_film_m(theta);
}

void ReynoldsSolver::assemble(const JournalState& s, double spin_rad_s) {
  const double c = g_.clearance_m;
  const double xb = s.x_m / c, yb = s.y_m / c;
  auto h_of = [&](double th) { return 1.0 - xb * std::cos(th) - yb * std::sin(th) + wear_.extra_film_m(th) / c; };
  const auto edges = wear_.edges_rad();
  const bool worn = wear_.span_rad() > 0.0;

  // Circumferential faces: exact 1D flux between centres i and i+1 (see header).
  for (int i = 0; i < nt_; ++i) {
    const double t0 = theta_rad(i);
    double cuts[4] = {0.0, 0.0, 0.0, 0.0};
    int nc = 0;
    cuts[nc++] = 0.0;
    if (worn) {
      double e0 = wrap_2pi(edges[0] - t0), e1 = wrap_2pi(edges[1] - t0);
      if (e0 > e1) std::swap(e0, e1);
      if (e0 > 0.0 && e0 < dtheta_) cuts[nc++] = e0;
      if (e1 > 0.0 && e1 < dtheta_) cuts[nc++] = e1;
    }
    cuts[nc++] = dtheta_;
    double i2 = 0.0, i3 = 0.0;
    for (int p = 0; p + 1 < nc; ++p) {
      const double len = cuts[p + 1] - cuts[p];
      for (size_t q = 0; q < gauss_x_.size(); ++q) {
        const double h = h_of(t0 + cuts[p] + gauss_x_[q] * len);
        if (!(h > 0.0)) throw std::invalid_argument("journal bearing: the journal touches the bore (film <= 0)");
        const double ih2 = 1.0 / (h * h);
        i2 += gauss_w_[q] * len * ih2;
        i3 += gauss_w_[q] * len * ih2 / h;
      }
    }
    cond_theta_(i) = dzeta_ / i3;
    couette_(i) = i2 / i3;
    h_cell_(i) = h_of(t0);
    if (!(h_cell_(i) > 0.0)) throw std::invalid_argument("journal bearing: the journal touches the bore (film <= 0)");
  }

  // Right-hand side: Couette flux difference and squeeze term 2 (dH/dt) / Omega.
  const double vx = s.vx_m_s / (c * spin_rad_s), vy = s.vy_m_s / (c * spin_rad_s);
  for (int i = 0; i < nt_; ++i) {
    const int im = (i + nt_ - 1) % nt_;
    const double src = dzeta_ * (couette_(i) - couette_(im)) -
                       2.0 * dzeta_ * (vx * cos_int_[static_cast<size_t>(i)] + vy * sin_int_[static_cast<size_t>(i)]);
    for (int j = 0; j < nz_; ++j) rhs_(i * nz_ + j) = -src;
  }
}

double ReynoldsSolver::axial(int i) const {
  const double rl2 = (g_.bore_radius_m / g_.length_m) * (g_.bore_radius_m / g_.length_m);
  return rl2 * h_cell_(i) * h_cell_(i) * h_cell_(i) * dtheta_ / dzeta_;
}

void ReynoldsSolver::base_matvec(const Eigen::VectorXd& p, Eigen::VectorXd& out) const {
  for (int i = 0; i < nt_; ++i) {
    const int im = (i + nt_ - 1) % nt_, ip = (i + 1) % nt_;
    const double az = axial(i);
    const double upper_end = half_ ? 0.0 : 2.0 * az;
    for (int j = 0; j < nz_; ++j) {
      const int k = i * nz_ + j;
      double d = cond_theta_(i) + cond_theta_(im);
      double v = -cond_theta_(im) * p(im * nz_ + j) - cond_theta_(i) * p(ip * nz_ + j);
      d += (j > 0 ? az : 2.0 * az) + (j + 1 < nz_ ? az : upper_end);
      if (j > 0) v -= az * p(k - 1);
      if (j + 1 < nz_) v -= az * p(k + 1);
      out(k) = d * p(k) + v;
    }
  }
}

void ReynoldsSolver::predict_active_set(int pinned_row) {
  // Projected Gauss-Seidel sweeps on the complementarity problem from the latest iterate,
  // alternately along and against the spin: the full film grows by one cell per active-set
  // iteration (a cavitated cell's multiplier changes sign only next to the full film), but
  // a sweep carries it along the circumference in one pass. The next iteration starts from
  // the cells the sweeps leave at p = 0: a guess only; the iteration still ends with an
  // exact solve whose set is self-consistent.
  const int n = nt_ * nz_;
  for (int k = 0; k < n; ++k) w_(k) = active_[static_cast<size_t>(k)] ? 0.0 : std::max(0.0, p_(k));
  int quiet = 0;  // consecutive sweeps that moved no cell across p = 0
  constexpr int max_sweeps = 100;
  for (int sweep = 0; sweep < max_sweeps && quiet < 2; ++sweep) {
    const bool forward = sweep % 2 == 0;
    int moved = 0;
    for (int ii = 0; ii < nt_; ++ii) {
      const int i = forward ? ii : nt_ - 1 - ii;
      if (i == pinned_row) continue;
      const int im = (i + nt_ - 1) % nt_, ip = (i + 1) % nt_;
      const double az = axial(i);
      const double upper_end = half_ ? 0.0 : 2.0 * az;
      for (int j = 0; j < nz_; ++j) {
        const int k = i * nz_ + j;
        const double d = cond_theta_(i) + cond_theta_(im) + (j > 0 ? az : 2.0 * az) + (j + 1 < nz_ ? az : upper_end);
        double v = rhs_(k) + cond_theta_(im) * w_(im * nz_ + j) + cond_theta_(i) * w_(ip * nz_ + j);
        if (j > 0) v += az * w_(k - 1);
        if (j + 1 < nz_) v += az * w_(k + 1);
        const double pk = std::max(0.0, v / d);
        moved += (pk > 0.0) != (w_(k) > 0.0);
        w_(k) = pk;
      }
    }
    quiet = moved == 0 ? quiet + 1 : 0;
  }
  for (int k = 0; k < n; ++k)
    if (k / nz_ != pinned_row) active_[static_cast<size_t>(k)] = w_(k) > 0.0 ? 0 : 1;
}

void ReynoldsSolver::fill_matrix() {
  const int n = nt_ * nz_;
  for (int col = 0; col < n; ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator e(a_, col); e; ++e) {
      const int row = static_cast<int>(e.row());
      const bool act = active_[static_cast<size_t>(row)] || active_[static_cast<size_t>(col)];
      const int i = row / nz_, j = row % nz_;
      if (row == col) {
        if (active_[static_cast<size_t>(row)]) {
          e.valueRef() = 1.0;
        } else {
          const double az = axial(i);
          e.valueRef() = cond_theta_(i) + cond_theta_((i + nt_ - 1) % nt_) + (j > 0 ? az : 2.0 * az) +
                         (j + 1 < nz_ ? az : (half_ ? 0.0 : 2.0 * az));
        }
        continue;
      }
      if (act) {
        e.valueRef() = 0.0;
        continue;
      }
      const int ic = col / nz_;
      if (ic == i) {
        e.valueRef() = -axial(i);
      } else if (ic == (i + 1) % nt_) {
        e.valueRef() = -cond_theta_(i);
      } else {
        e.valueRef() = -cond_theta_(ic);
      }
    }
  }
}

FilmForces ReynoldsSolver::solve(const JournalState& s, double spin_rad_s) {
  if (!(spin_rad_s > 0.0)) throw std::invalid_argument("journal bearing: spin speed must be > 0 rad/s");
  if (!std::isfinite(s.x_m) || !std::isfinite(s.y_m) || !std::isfinite(s.vx_m_s) || !std::isfinite(s.vy_m_s))
    throw std::invalid_argument("journal bearing: journal state is not finite");
  assemble(s, spin_rad_s);
  ++counters_.solves;
  const int n = nt_ * nz_;

  const bool lcp = o_.cavitation == Cavitation::reynolds;
  if (!lcp) std::fill(active_.begin(), active_.end(), 0);
  // Raimondi & Boyd's inlet: the row of cells with the largest film held at p = 0 for good.
  int pinned_row = -1;
  if (o_.zero_pressure_at_max_film) {
    Eigen::Index imax = 0;
    h_cell_.maxCoeff(&imax);
    pinned_row = static_cast<int>(imax);
    for (int j = 0; j < nz_; ++j) active_[static_cast<size_t>(pinned_row * nz_ + j)] = 1;
  }
  // With reuse_factorisation, an iteration whose active set and journal position are those
  // of the latest factorisation solves with it instead of factorising the same matrix again
  // (a velocity step from the linearisation point's active set: only the right-hand side
  // differs). The factorisation is a function of the matrix alone, so the result is the same.
  const bool reuse = lcp && o_.reuse_factorisation;
  FilmForces f;
  int it = 0;
  Eigen::VectorXd& b = b_;
  for (;;) {
    ++it;
    ++counters_.iterations;
    b = rhs_;
    for (int k = 0; k < n; ++k)
      if (active_[static_cast<size_t>(k)]) b(k) = 0.0;
    const bool have = reuse && factored_valid_ && factored_x_m_ == s.x_m && factored_y_m_ == s.y_m &&
                      factored_active_ == active_;
    if (!have) {
      fill_matrix();
      if (!pattern_analysed_) {
        ldlt_.analyzePattern(a_);
        pattern_analysed_ = true;
      }
      ldlt_.factorize(a_);
      ++counters_.factorisations;
      if (ldlt_.info() != Eigen::Success) throw std::runtime_error("journal bearing: factorisation failed");
      factored_valid_ = true;
      factored_x_m_ = s.x_m;
      factored_y_m_ = s.y_m;
      factored_active_ = active_;
    }
    p_ = ldlt_.solve(b);
    if (!lcp) break;
    // Primal-dual active set update with the multiplier w = A p - b.
    base_matvec(p_, w_);
    w_ -= rhs_;
    bool changed = false;
    for (int k = 0; k < n; ++k) {
      if (k / nz_ == pinned_row) continue;
      const bool now = active_[static_cast<size_t>(k)] ? (w_(k) > 0.0) : (p_(k) < 0.0);
      if (now != static_cast<bool>(active_[static_cast<size_t>(k)])) {
        active_[static_cast<size_t>(k)] = now ? 1 : 0;
        changed = true;
      }
    }
    if (!changed) break;
    if (it >= o_.max_active_set_iterations) {
      f.converged = false;
      break;
    }
    // The guess for the first iterations only: from there on the plain update, which
    // terminates from any start (A is an M-matrix).
    if (reuse && it < k_predicted_iterations) predict_active_set(pinned_row);
  }
  f.active_set_iterations = it;
  if (o_.cavitation != Cavitation::none)
    for (int k = 0; k < n; ++k) p_(k) = std::max(0.0, p_(k));

  // Forces: F = -int p (cos, sin) R dtheta dx with p = P p_bar, P = 6 mu Omega R^2 / C^2.
  pressure_scale_pa_ = 6.0 * g_.viscosity_pa_s * spin_rad_s * g_.bore_radius_m * g_.bore_radius_m /
                       (g_.clearance_m * g_.clearance_m);
  double sx = 0.0, sy = 0.0, pmax = 0.0;
  for (int i = 0; i < nt_; ++i) {
    double col = 0.0;
    for (int j = 0; j < nz_; ++j) {
      col += p_(i * nz_ + j);
      pmax = std::max(pmax, p_(i * nz_ + j));
    }
    sx += col * cos_int_[static_cast<size_t>(i)];
    sy += col * sin_int_[static_cast<size_t>(i)];
  }
  const double scale = -pressure_scale_pa_ * g_.bore_radius_m * g_.length_m * dzeta_ * (half_ ? 2.0 : 1.0);
  f.fx_n = scale * sx;
  f.fy_n = scale * sy;
  f.max_pressure_pa = pressure_scale_pa_ * pmax;
  f.min_film_m = g_.clearance_m * h_cell_.minCoeff();
  return f;
}

Eigen::MatrixXd ReynoldsSolver::pressure_pa() const {
  const int nz = o_.cells_axial;
  Eigen::MatrixXd m(nt_, nz);
  for (int i = 0; i < nt_; ++i)
    for (int j = 0; j < nz; ++j) m(i, j) = pressure_scale_pa_ * p_(i * nz_ + (j < nz_ ? j : nz - 1 - j));
  return m;
}

DynamicCoefficients perturbation_coefficients(ReynoldsSolver& solver, const JournalState& s, double spin_rad_s,
                                              double relative_step) {
  DynamicCoefficients d;
  const FilmForces f0 = solver.solve(s, spin_rad_s);
  d.fx0_n = f0.fx_n;
  d.fy0_n = f0.fy_n;
  const double dq = relative_step * solver.geometry().clearance_m;
  const double dv = dq * spin_rad_s;
  // With reuse_factorisation: the velocity steps first (the matrix is the linearisation
  // point's, only the right-hand side changes), each step started from the linearisation
  // point's active set, and the solver's state restored at the end instead of solved again.
  // The forces are the same as in the plain order (each solve's result does not depend on
  // its start).
  const bool reuse = solver.o_.reuse_factorisation && solver.o_.cavitation == Cavitation::reynolds;
  const std::vector<char> active0 = solver.active_;
  const Eigen::VectorXd p0 = solver.p_;
  const double scale0 = solver.pressure_scale_pa_;
  const std::array<int, 4> order = reuse ? std::array<int, 4>{2, 3, 0, 1} : std::array<int, 4>{0, 1, 2, 3};
  for (const int j : order) {
    JournalState sp = s, sm = s;
    double step = 0.0;
    switch (j) {
      case 0: sp.x_m += dq; sm.x_m -= dq; step = dq; break;
      case 1: sp.y_m += dq; sm.y_m -= dq; step = dq; break;
      case 2: sp.vx_m_s += dv; sm.vx_m_s -= dv; step = dv; break;
      default: sp.vy_m_s += dv; sm.vy_m_s -= dv; step = dv; break;
    }
    if (reuse) solver.active_ = active0;
    const FilmForces fp = solver.solve(sp, spin_rad_s);
    if (reuse) solver.active_ = active0;
    const FilmForces fm = solver.solve(sm, spin_rad_s);
    const double gx = -(fp.fx_n - fm.fx_n) / (2.0 * step), gy = -(fp.fy_n - fm.fy_n) / (2.0 * step);
    if (j < 2) {
      d.stiffness_n_per_m(0, j) = gx;
      d.stiffness_n_per_m(1, j) = gy;
    } else {
      d.damping_n_s_per_m(0, j - 2) = gx;
      d.damping_n_s_per_m(1, j - 2) = gy;
    }
  }
  if (reuse) {
    // Leave the solver at the linearisation point: its pressure and active set.
    solver.active_ = active0;
    solver.p_ = p0;
    solver.pressure_scale_pa_ = scale0;
  } else {
    solver.solve(s, spin_rad_s);  // leave the solver at the linearisation point
  }
  return d;
}

FilmHarmonics film_harmonics(ReynoldsSolver& solver, const JournalState& mean,
                             const std::vector<std::array<std::complex<double>, 2>>& q_m, double spin_rad_s, int samples) {
  using cplx = std::complex<double>;
  if (samples < 8) throw std::invalid_argument("film_harmonics: need at least 8 samples per revolution");
  const size_t n = q_m.size();
  if (n < 1 || 2 * n >= static_cast<size_t>(samples))
    throw std::invalid_argument("film_harmonics: need 1 <= harmonics < samples / 2");
  FilmHarmonics r;
  r.harmonic_n.assign(n, std::array<cplx, 2>{});
  r.min_film_m = 1e300;
  const cplx j(0.0, 1.0);
  const double inv = 1.0 / static_cast<double>(samples);
  std::vector<cplx> e(n);
  for (int k = 0; k < samples; ++k) {
    const cplx e1 = std::exp(j * (2.0 * M_PI * k * inv));
    e[0] = e1;
    for (size_t h = 1; h < n; ++h) e[h] = e[h - 1] * e1;
    JournalState s = mean;
    for (size_t h = 0; h < n; ++h) {
      const double order = static_cast<double>(h + 1);
      s.x_m += (q_m[h][0] * e[h]).real();
      s.y_m += (q_m[h][1] * e[h]).real();
      s.vx_m_s += spin_rad_s * order * (j * q_m[h][0] * e[h]).real();
      s.vy_m_s += spin_rad_s * order * (j * q_m[h][1] * e[h]).real();
    }
    const FilmForces f = solver.solve(s, spin_rad_s);
    r.min_film_m = std::min(r.min_film_m, f.min_film_m);
    r.fx_mean_n += inv * f.fx_n;
    r.fy_mean_n += inv * f.fy_n;
    for (size_t h = 0; h < n; ++h) {
      r.harmonic_n[h][0] += 2.0 * inv * f.fx_n * std::conj(e[h]);
      r.harmonic_n[h][1] += 2.0 * inv * f.fy_n * std::conj(e[h]);
    }
  }
  return r;
}

}  // namespace amb::model::journal
