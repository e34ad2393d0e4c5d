#include "host-tools/core/wearid/rig_response.hpp"

#include <Eigen/Dense>
#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/amb/amb_force.hpp"
#include "model/journal/journal_rig.hpp"

namespace amb::host::wearid {
namespace {
constexpr double k_two_pi = 2.0 * M_PI;
}

RigResponse::RigResponse(const board::BoardConfig& board, double speed_hz, std::array<double, 2> static_force_n)
    : b_(board), speed_hz_(speed_hz) {
  if (!board.journal.present) throw std::invalid_argument("wear-id: board '" + board.name + "' has no [journal_bearing]");
  if (!(speed_hz > 0.0)) throw std::invalid_argument("wear-id: speed must be > 0 Hz");
  const model::PlantParams& p = board.plant;
  const model::RigModel rig(p);  // one FE build and eigen solve for the response and its statics
  fe_ = rig.rotor();
  red_ = rig.board_reduction().reduced;
  m_ = red_.modes;
  for (size_t b = 0; b < 2; ++b) {
    b_amb_[b] = model::rotor::modal_interpolation(fe_, red_, p.amb[b].axial_m);
    b_sensor_[b] = model::rotor::modal_interpolation(fe_, red_, p.sensor[2 * b].axial_m);
  }
  b_journal_ = model::rotor::modal_interpolation(fe_, red_, board.journal.axial_m);
  unb_s_ = Eigen::VectorXd::Zero(m_);
  unb_c_ = Eigen::VectorXd::Zero(m_);
  for (const auto& d : p.rotor.disks) {
    const Eigen::VectorXd bd = model::rotor::modal_interpolation(fe_, red_, d.axial_m).transpose();
    const double ph = d.unbalance_phase_deg * M_PI / 180.0;
    unb_s_ += d.unbalance_kg_m * std::sin(ph) * bd;
    unb_c_ += d.unbalance_kg_m * std::cos(ph) * bd;
  }
  // AMB operating point: static AMB forces and positions are affine in the film force.
  for (int k = 0; k < 3; ++k) {
    const model::journal::RigStatics st = model::journal::static_state(
        rig, board.journal.axial_m, board.journal.axial_m, k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0);
    amb_force_basis_[static_cast<size_t>(k)] = st.amb_force_n;
    amb_disp_basis_[static_cast<size_t>(k)] = st.amb_displacement_m;
  }
  for (size_t k = 1; k < 3; ++k)
    for (size_t b = 0; b < 2; ++b)
      for (size_t i = 0; i < 2; ++i) {
        amb_force_basis_[k][b][i] -= amb_force_basis_[0][b][i];
        amb_disp_basis_[k][b][i] -= amb_disp_basis_[0][b][i];
      }
  set_static_film_force(static_force_n);
  for (size_t k = 0; k < 2; ++k) probe_dir_[k] = model::magnet::axis_direction(board.journal.probe_angle_deg[k]);
  for (size_t k = 0; k < 4; ++k) sensor_dir_[k] = model::magnet::axis_direction(p.sensor[k].angle_deg);
}

void RigResponse::set_static_film_force(std::array<double, 2> f) {
  const model::PlantParams& p = b_.plant;
  for (size_t b = 0; b < 2; ++b) {
    const model::magnet::AxisLaw law = model::magnet::make_axis_law(p.amb[b]);
    ks_xy_[b] = Eigen::Matrix2d::Zero();
    ki_xy_[b] = Eigen::Matrix2d::Zero();
    for (size_t a = 0; a < 2; ++a) {
      const auto d = model::magnet::axis_direction(p.amb[b].actuator_angle_deg[a]);
      double f_axis = 0.0, z_axis = 0.0;
      for (size_t i = 0; i < 2; ++i) {
        const double fi = amb_force_basis_[0][b][i] + f[0] * amb_force_basis_[1][b][i] + f[1] * amb_force_basis_[2][b][i];
        const double zi = amb_disp_basis_[0][b][i] + f[0] * amb_disp_basis_[1][b][i] + f[1] * amb_disp_basis_[2][b][i];
        f_axis += d[i] * fi;
        z_axis += d[i] * zi;
      }
      const double ic = f_axis / p.amb[b].ki_n_per_a;
      const model::magnet::Linearisation lin = model::magnet::linearise(law, z_axis, ic);
      axis_z0_m_[b][a] = z_axis;
      axis_ic0_a_[b][a] = ic;
      axis_ks_[b][a] = lin.ks_n_per_m;
      axis_ki_[b][a] = lin.ki_n_per_a;
      const Eigen::Vector2d dv(d[0], d[1]);
      ks_xy_[b] += lin.ks_n_per_m * dv * dv.transpose();
      // The firmware divides its force demand by the board's ki; the coil pair delivers the
      // local dF/dic at the static gap and current, which differs from ki when the actuator
      // plane is not at zero (the sensors hold their own plane at zero) and the pair carries a
      // static load: 2 k ((i0 + ic)/(g0 - z)^2 + (i0 - ic)/(g0 + z)^2).
      ki_xy_[b] += lin.ki_n_per_a / p.amb[b].ki_n_per_a * dv * dv.transpose();
    }
  }
}

Eigen::VectorXcd RigResponse::modal_response(double speed_hz, const Eigen::Matrix2d& kj,
                                             const Eigen::Matrix2d& cj) const {
  const double w = k_two_pi * speed_hz;  // excitation = spin
  const cplx j(0.0, 1.0);
  const int m = m_;
  const Eigen::MatrixXcd a = dynamic_matrix(speed_hz, speed_hz, kj, cj);
  // Unbalance: fx = W^2 (S cos - C sin), fy = W^2 (S sin + C cos) -> X = W^2 (S + j C), Y = -j X.
  Eigen::VectorXcd f(2 * m);
  for (int i = 0; i < m; ++i) {
    const cplx fx = w * w * cplx(unb_s_(i), unb_c_(i));
    f(i) = fx;
    f(m + i) = -j * fx;
  }
  return a.partialPivLu().solve(f);
}

Eigen::Matrix2cd RigResponse::journal_receptance(double spin_hz, double excitation_hz, const Eigen::Matrix2d& kj,
                                                 const Eigen::Matrix2d& cj) const {
  const int m = m_;
  const Eigen::MatrixXcd a = dynamic_matrix(spin_hz, excitation_hz, kj, cj);
  Eigen::MatrixXcd f = Eigen::MatrixXcd::Zero(2 * m, 2);
  for (int i = 0; i < m; ++i) {
    f(i, 0) = b_journal_(i);
    f(m + i, 1) = b_journal_(i);
  }
  const Eigen::MatrixXcd e = a.partialPivLu().solve(f);
  Eigen::Matrix2cd h = Eigen::Matrix2cd::Zero();
  for (int c = 0; c < 2; ++c)
    for (int i = 0; i < m; ++i) {
      h(0, c) += b_journal_(i) * e(i, c);
      h(1, c) += b_journal_(i) * e(m + i, c);
    }
  return h;
}

Eigen::MatrixXcd RigResponse::dynamic_matrix(double spin_hz, double excitation_hz, const Eigen::Matrix2d& kj,
                                             const Eigen::Matrix2d& cj) const {
  const double w = k_two_pi * excitation_hz, spin = k_two_pi * spin_hz;
  const cplx j(0.0, 1.0);
  const int m = m_;
  Eigen::MatrixXcd a = Eigen::MatrixXcd::Zero(2 * m, 2 * m);
  for (int i = 0; i < m; ++i) {
    const cplx zi = red_.omega2(i) - w * w + j * w * red_.damping(i);
    a(i, i) = zi;
    a(m + i, m + i) = zi;
  }
  // Gyroscopic coupling as in the plant: x'' + W P y' ..., y'' - W P x' ...
  a.block(0, m, m, m) += (j * w * spin) * red_.polar.cast<cplx>();
  a.block(m, 0, m, m) -= (j * w * spin) * red_.polar.cast<cplx>();

  for (size_t b = 0; b < 2; ++b) {
    const cplx loop = loop_gain(b, w);
    const Eigen::MatrixXd aa = b_amb_[b].transpose() * b_amb_[b];
    const Eigen::MatrixXd as = b_amb_[b].transpose() * b_sensor_[b];
    for (int r = 0; r < 2; ++r)
      for (int q = 0; q < 2; ++q) {
        a.block(r * m, q * m, m, m) -= ks_xy_[b](r, q) * aa.cast<cplx>();
        a.block(r * m, q * m, m, m) += ki_xy_[b](r, q) * loop * as.cast<cplx>();
      }
  }
  // Film.
  const Eigen::MatrixXd jj = b_journal_.transpose() * b_journal_;
  for (int r = 0; r < 2; ++r)
    for (int q = 0; q < 2; ++q) a.block(r * m, q * m, m, m) += (kj(r, q) + j * w * cj(r, q)) * jj.cast<cplx>();
  return a;
}

cplx RigResponse::loop_gain(size_t b, double w) const {
  const model::PlantParams& p = b_.plant;
  const cplx j(0.0, 1.0);
  // Controller, discrete (see header), per direction in force units.
  const double dt = 1.0 / b_.rate_hz;
  const cplx zinv = std::exp(-j * w * dt);
  const auto& c = b_.controller;
  const double alpha = std::exp(-k_two_pi * c.derivative_filter_hz * dt);
  const cplx deriv = (1.0 - alpha) * (1.0 - zinv) / (dt * (1.0 - alpha * zinv));
  const cplx integ = c.ki_n_per_m_s * dt * zinv / (1.0 - zinv);
  cplx pid = c.kp_n_per_m + integ + c.kd_n_s_per_m * deriv;
  for (int n = 0; n < c.notch_count; ++n) {
    const auto& nt = c.notches[static_cast<size_t>(n)];
    const double w0 = k_two_pi * nt.centre_hz, bw = k_two_pi * nt.width_hz;
    const cplx s = j * w;
    pid *= (s * s + nt.depth * bw * s + w0 * w0) / (s * s + bw * s + w0 * w0);
  }
  const cplx hold = std::exp(-j * w * 0.5 * dt);
  const double fa = p.amb[b].amplifier_bandwidth_hz, fs = p.sensor[2 * b].bandwidth_hz;
  const cplx amp = fa > 0.0 ? 1.0 / (1.0 + j * w / (k_two_pi * fa)) : cplx(1.0);
  const cplx sen = fs > 0.0 ? 1.0 / (1.0 + j * w / (k_two_pi * fs)) : cplx(1.0);
  return amp * hold * pid * sen;
}

std::vector<Eigen::VectorXcd> RigResponse::amb_remainder(const std::vector<Eigen::VectorXcd>& e, double w, int samples) const {
  const model::PlantParams& p = b_.plant;
  const int m = m_;
  const size_t nh = e.size();
  std::vector<Eigen::VectorXcd> f(nh, Eigen::VectorXcd::Zero(2 * m));
  const auto at = [&](const Eigen::RowVectorXd& row, const Eigen::VectorXcd& v) {
    cplx x = 0.0, y = 0.0;
    for (int i = 0; i < m; ++i) {
      x += row(i) * v(i);
      y += row(i) * v(m + i);
    }
    return std::array<cplx, 2>{x, y};
  };
  const int n = std::max(8, samples);
  for (size_t b = 0; b < 2; ++b) {
    const model::magnet::AxisLaw law = model::magnet::make_axis_law(p.amb[b]);
    std::vector<std::array<cplx, 2>> xa(nh), xs(nh);
    std::vector<cplx> loop(nh);
    for (size_t k = 0; k < nh; ++k) {
      xa[k] = at(b_amb_[b], e[k]);
      xs[k] = at(b_sensor_[b], e[k]);
      loop[k] = loop_gain(b, static_cast<double>(k + 1) * w);
    }
    std::vector<std::array<cplx, 2>> fxy(nh, std::array<cplx, 2>{});
    for (size_t a = 0; a < 2; ++a) {
      const auto d = model::magnet::axis_direction(p.amb[b].actuator_angle_deg[a]);
      // Actuator-plane displacement along the axis and the control current the loop commands
      // (force demand -loop x_sensor along the axis, divided by the board's ki), per harmonic.
      std::vector<cplx> z(nh), ic(nh), r(nh, 0.0);
      for (size_t k = 0; k < nh; ++k) {
        z[k] = d[0] * xa[k][0] + d[1] * xa[k][1];
        ic[k] = -loop[k] * (d[0] * xs[k][0] + d[1] * xs[k][1]) / p.amb[b].ki_n_per_a;
      }
      const double z0 = axis_z0_m_[b][a], i0 = axis_ic0_a_[b][a];
      const double f0 = model::magnet::axis_force_n(law, z0, i0);
      for (int s = 0; s < n; ++s) {
        const cplx e1 = std::polar(1.0, k_two_pi * s / n);
        cplx ek = 1.0;
        double zt = 0.0, it = 0.0;
        for (size_t k = 0; k < nh; ++k) {
          ek *= e1;
          zt += (z[k] * ek).real();
          it += (ic[k] * ek).real();
        }
        const double rem = model::magnet::axis_force_n(law, z0 + zt, i0 + it) - f0 - axis_ks_[b][a] * zt - axis_ki_[b][a] * it;
        ek = 1.0;
        for (size_t k = 0; k < nh; ++k) {
          ek *= e1;
          r[k] += rem * std::conj(ek);
        }
      }
      for (size_t k = 0; k < nh; ++k)
        for (size_t c = 0; c < 2; ++c) fxy[k][c] += d[c] * r[k] * (2.0 / n);
    }
    for (size_t k = 0; k < nh; ++k)
      for (int i = 0; i < m; ++i) {
        f[k](i) += b_amb_[b](i) * fxy[k][0];
        f[k](m + i) += b_amb_[b](i) * fxy[k][1];
      }
  }
  return f;
}

namespace {
FullSpectrum pair_spectrum(const Eigen::RowVectorXd& b, const Eigen::VectorXcd& e, int m, const std::array<double, 2>& d0,
                           const std::array<double, 2>& d1) {
  cplx x = 0.0, y = 0.0;
  for (int i = 0; i < m; ++i) {
    x += b(i) * e(i);
    y += b(i) * e(m + i);
  }
  const cplx xp = d0[0] * x + d0[1] * y, yp = d1[0] * x + d1[1] * y;
  const cplx j(0.0, 1.0);
  return {0.5 * (xp + j * yp), 0.5 * std::conj(xp - j * yp)};
}
}  // namespace

std::array<FullSpectrum, 3> RigResponse::all_probes(const Eigen::Matrix2d& kj, const Eigen::Matrix2d& cj) const {
  const Eigen::VectorXcd e = modal_response(speed_hz_, kj, cj);
  // The AMB sensors' readings pass their first-order roll-off (the plant's sensor model);
  // the journal probes read the shaft directly. A common complex gain s on x' and y' scales
  // Z+ by s and Z- by conj(s).
  std::array<FullSpectrum, 3> z = {pair_spectrum(b_journal_, e, m_, probe_dir_[0], probe_dir_[1]),
                                   pair_spectrum(b_sensor_[0], e, m_, sensor_dir_[0], sensor_dir_[1]),
                                   pair_spectrum(b_sensor_[1], e, m_, sensor_dir_[2], sensor_dir_[3])};
  const double w = k_two_pi * speed_hz_;
  for (size_t b = 0; b < 2; ++b) {
    const double fs = b_.plant.sensor[2 * b].bandwidth_hz;
    if (!(fs > 0.0)) continue;
    const cplx sen = 1.0 / (1.0 + cplx(0.0, w / (k_two_pi * fs)));
    z[b + 1].forward_m *= sen;
    z[b + 1].backward_m *= std::conj(sen);
  }
  return z;
}

std::array<cplx, 2> RigResponse::journal_xy_at(double speed_hz, const Eigen::Matrix2d& kj,
                                               const Eigen::Matrix2d& cj) const {
  const Eigen::VectorXcd e = modal_response(speed_hz, kj, cj);
  const int m = m_;
  cplx x = 0.0, y = 0.0;
  for (int i = 0; i < m; ++i) {
    x += b_journal_(i) * e(i);
    y += b_journal_(i) * e(m + i);
  }
  return {x, y};
}

FullSpectrum RigResponse::journal_probes_at(double speed_hz, const Eigen::Matrix2d& kj, const Eigen::Matrix2d& cj) const {
  const auto xy = journal_xy_at(speed_hz, kj, cj);
  const cplx xp = probe_dir_[0][0] * xy[0] + probe_dir_[0][1] * xy[1];
  const cplx yp = probe_dir_[1][0] * xy[0] + probe_dir_[1][1] * xy[1];
  const cplx j(0.0, 1.0);
  return {0.5 * (xp + j * yp), 0.5 * std::conj(xp - j * yp)};
}

FullFilmSpectrum RigResponse::journal_probes_full_film(model::journal::ReynoldsSolver& solver,
                                                        const model::journal::JournalState& mean,
                                                        const model::journal::DynamicCoefficients& lin,
                                                        const HarmonicBalanceOptions& o) const {
  if (o.max_iterations < 1) throw std::invalid_argument("full film: max_iterations must be >= 1");
  if (o.harmonics < 2 || o.harmonics > k_max_harmonics)
    throw std::invalid_argument("full film: harmonics must be 2.." + std::to_string(k_max_harmonics));
  if (o.samples < 8 || 2 * o.harmonics >= o.samples)
    throw std::invalid_argument("full film: samples must be >= 8 and more than twice the harmonics");
  const Eigen::Matrix2d& k = lin.stiffness_n_per_m;
  const Eigen::Matrix2d& c = lin.damping_n_s_per_m;
  const double w = k_two_pi * speed_hz_;
  const cplx j(0.0, 1.0);
  const int m = m_;
  const size_t nh = static_cast<size_t>(o.harmonics);
  // Per harmonic h (h + 1 times the spin): the closed loop's dynamic matrix and the film's
  // linearisation at that frequency.
  std::vector<Eigen::PartialPivLU<Eigen::MatrixXcd>> a;
  std::vector<Eigen::Matrix2cd> dk;
  for (size_t h = 0; h < nh; ++h) {
    const double order = static_cast<double>(h + 1);
    a.emplace_back(dynamic_matrix(speed_hz_, order * speed_hz_, k, c));
    dk.push_back(k.cast<cplx>() + order * j * w * c.cast<cplx>());
  }
  Eigen::VectorXcd f_unb(2 * m);
  for (int i = 0; i < m; ++i) {
    const cplx fx = w * w * cplx(unb_s_(i), unb_c_(i));
    f_unb(i) = fx;
    f_unb(m + i) = -j * fx;
  }
  const Eigen::VectorXcd e1_lin = a[0].solve(f_unb);
  const auto journal_xy = [&](const Eigen::VectorXcd& e) {
    Eigen::Vector2cd x = Eigen::Vector2cd::Zero();
    for (int i = 0; i < m; ++i) {
      x(0) += b_journal_(i) * e(i);
      x(1) += b_journal_(i) * e(m + i);
    }
    return x;
  };
  const auto journal_force = [&](const Eigen::Vector2cd& f) {
    Eigen::VectorXcd v(2 * m);
    for (int i = 0; i < m; ++i) {
      v(i) = b_journal_(i) * f(0);
      v(m + i) = b_journal_(i) * f(1);
    }
    return v;
  };
  const double scale = std::max(journal_xy(e1_lin).norm(), 1e-12);
  // Unknowns: the modal responses E_1..E_H as reals (re, im per entry), in units of the
  // linear journal orbit; harmonic h occupies entries [4 m h, 4 m (h + 1)).
  const int block = 4 * m;
  const int nv = block * o.harmonics;
  auto pack = [&](const std::vector<Eigen::VectorXcd>& e) {
    Eigen::VectorXd v(nv);
    for (size_t h = 0; h < nh; ++h)
      for (int i = 0; i < 2 * m; ++i) {
        v(block * static_cast<int>(h) + 2 * i) = e[h](i).real() / scale;
        v(block * static_cast<int>(h) + 2 * i + 1) = e[h](i).imag() / scale;
      }
    return v;
  };
  auto unpack = [&](const Eigen::VectorXd& v) {
    std::vector<Eigen::VectorXcd> e(nh, Eigen::VectorXcd(2 * m));
    for (size_t h = 0; h < nh; ++h)
      for (int i = 0; i < 2 * m; ++i)
        e[h](i) = cplx(v(block * static_cast<int>(h) + 2 * i), v(block * static_cast<int>(h) + 2 * i + 1)) * scale;
    return e;
  };
  FullFilmSpectrum r;
  r.harmonics = o.harmonics;
  model::journal::FilmHarmonics fh;
  auto map = [&](const Eigen::VectorXd& v) {
    const std::vector<Eigen::VectorXcd> e = unpack(v);
    std::vector<Eigen::Vector2cd> x(nh);
    std::vector<std::array<cplx, 2>> q(nh);
    for (size_t h = 0; h < nh; ++h) {
      x[h] = journal_xy(e[h]);
      q[h] = {x[h](0), x[h](1)};
    }
    std::vector<Eigen::VectorXcd> g(nh, Eigen::VectorXcd::Zero(2 * m));
    g[0] = f_unb;
    if (o.film_nonlinear) {
      fh = model::journal::film_harmonics(solver, mean, q, w, o.samples);
      for (size_t h = 0; h < nh; ++h)
        g[h] += journal_force(Eigen::Vector2cd(fh.harmonic_n[h][0], fh.harmonic_n[h][1]) + dk[h] * x[h]);
    }
    if (o.amb_nonlinear) {
      const std::vector<Eigen::VectorXcd> ra = amb_remainder(e, w, o.samples);
      for (size_t h = 0; h < nh; ++h) g[h] += ra[h];
    }
    for (size_t h = 0; h < nh; ++h) g[h] = a[h].solve(g[h]);
    return pack(g);
  };
  Eigen::VectorXd x;
  std::vector<Eigen::VectorXcd> e0(nh, Eigen::VectorXcd::Zero(2 * m));
  e0[0] = e1_lin;
  if (o.start) {
    // The previous orbit's journal motion as a start: least-norm modal corrections that move
    // the journal to it, through the journal receptance of the linear system at each harmonic.
    for (size_t h = 0; h < nh; ++h) {
      const std::array<cplx, 2> s = h < o.start->journal_m.size() ? o.start->journal_m[h] : std::array<cplx, 2>{};
      Eigen::Vector2cd target(s[0], s[1]);
      if (h == 0) target -= journal_xy(e1_lin);
      const double order = static_cast<double>(h + 1);
      const Eigen::Matrix2cd rec = journal_receptance(speed_hz_, order * speed_hz_, k, c);
      e0[h] += a[h].solve(journal_force(rec.partialPivLu().solve(target)));
    }
  }
  x = pack(e0);
  // Anderson acceleration (depth 3) of the fixed-point map x -> g(x): the plain iteration
  // contracts by only ~0.45 per step at e = 0.7 (the film's describing-function stiffness
  // differs from its tangent stiffness by ~10 % there).
  constexpr int depth = 3;
  std::vector<Eigen::VectorXd> gs, fs;
  for (r.iterations = 1; r.iterations <= o.max_iterations; ++r.iterations) {
    const Eigen::VectorXd g = map(x);
    const Eigen::VectorXd f = g - x;
    if (f.norm() < o.tolerance) {
      x = g;
      r.converged = true;
      break;
    }
    gs.push_back(g);
    fs.push_back(f);
    if (static_cast<int>(gs.size()) > depth + 1) {
      gs.erase(gs.begin());
      fs.erase(fs.begin());
    }
    const int mk = static_cast<int>(gs.size()) - 1;
    if (mk == 0) {
      x = g;
      continue;
    }
    Eigen::MatrixXd df(nv, mk), dg(nv, mk);
    for (int i = 0; i < mk; ++i) {
      df.col(i) = fs[static_cast<size_t>(i + 1)] - fs[static_cast<size_t>(i)];
      dg.col(i) = gs[static_cast<size_t>(i + 1)] - gs[static_cast<size_t>(i)];
    }
    const Eigen::VectorXd gamma = df.completeOrthogonalDecomposition().solve(f);
    x = g - dg * gamma;
  }
  r.iterations = std::min(r.iterations, o.max_iterations);
  const std::vector<Eigen::VectorXcd> e = unpack(x);
  auto probes = [&](const Eigen::Vector2cd& v) {
    const cplx xp = probe_dir_[0][0] * v(0) + probe_dir_[0][1] * v(1);
    const cplx yp = probe_dir_[1][0] * v(0) + probe_dir_[1][1] * v(1);
    return FullSpectrum{0.5 * (xp + j * yp), 0.5 * std::conj(xp - j * yp)};
  };
  r.mean_force_n = {fh.fx_mean_n, fh.fy_mean_n};
  const std::array<FullSpectrum*, 3> zp{&r.first, &r.second, &r.third};
  r.journal_m.resize(nh);
  for (size_t h = 0; h < nh; ++h) {
    const Eigen::Vector2cd v = journal_xy(e[h]);
    r.journal_m[h] = {v(0), v(1)};
    if (h < zp.size()) *zp[h] = probes(v);
  }
  return r;
}

FullSpectrum RigResponse::journal_probes(const Eigen::Matrix2d& kj, const Eigen::Matrix2d& cj) const {
  return journal_probes_at(speed_hz_, kj, cj);
}

}  // namespace amb::host::wearid
