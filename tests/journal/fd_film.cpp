#include "fd_film.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace amb::test::journal {
namespace mj = amb::model::journal;

FdFilm::FdFilm(const mj::BearingGeometry& g, const mj::WearParams& w, int nodes_theta, int intervals_axial)
    : g_(g), wear_(w, g.bore_radius_m, g.clearance_m), nt_(nodes_theta), nz_(intervals_axial) {
  if (nt_ < 12 || nz_ < 2) throw std::invalid_argument("FdFilm: need >= 12 nodes and >= 2 axial intervals");
  p_.assign(static_cast<size_t>(nt_ * (nz_ + 1)), 0.0);
}

std::array<double, 2> FdFilm::force_n(const mj::JournalState& s, double spin_rad_s) {
  const double dth = 2.0 * M_PI / nt_, dz = g_.length_m / nz_, r = g_.bore_radius_m, mu = g_.viscosity_pa_s;
  auto h = [&](double th) {
    return g_.clearance_m - s.x_m * std::cos(th) - s.y_m * std::sin(th) + wear_.extra_film_m(th);
  };
  std::vector<double> ae(static_cast<size_t>(nt_)), aw(ae), az(ae), rhs(ae);
  for (int i = 0; i < nt_; ++i) {
    const double th = i * dth, hp = h(th + 0.5 * dth), hm = h(th - 0.5 * dth), hi = h(th);
    if (!(hp > 0.0 && hm > 0.0 && hi > 0.0)) throw std::invalid_argument("FdFilm: the journal touches the bore");
    ae[static_cast<size_t>(i)] = hp * hp * hp / (r * r * dth * dth);
    aw[static_cast<size_t>(i)] = hm * hm * hm / (r * r * dth * dth);
    az[static_cast<size_t>(i)] = hi * hi * hi / (dz * dz);
    const double dhdt = -(s.vx_m_s * std::cos(th) + s.vy_m_s * std::sin(th));
    rhs[static_cast<size_t>(i)] = 6.0 * mu * spin_rad_s * (hp - hm) / dth + 12.0 * mu * dhdt;
  }
  const int stride = nz_ + 1;
  const double omega = 2.0 / (1.0 + std::sin(M_PI / std::max(0.5 * nt_, static_cast<double>(nz_))));
  if (zero_node_ >= 0 && zero_node_ < nt_)
    for (int j = 0; j <= nz_; ++j) p_[static_cast<size_t>(zero_node_ * stride + j)] = 0.0;
  sweeps_ = 0;
  for (;;) {
    double change = 0.0, pmax = 0.0;
    for (int i = 0; i < nt_; ++i) {
      if (i == zero_node_) continue;  // p stays 0 on the inlet line
      const int ip = (i + 1) % nt_, im = (i + nt_ - 1) % nt_;
      const size_t ii = static_cast<size_t>(i);
      const double diag = ae[ii] + aw[ii] + 2.0 * az[ii];
      for (int j = 1; j < nz_; ++j) {
        double& p = p_[static_cast<size_t>(i * stride + j)];
        const double gs = (ae[ii] * p_[static_cast<size_t>(ip * stride + j)] + aw[ii] * p_[static_cast<size_t>(im * stride + j)] +
                           az[ii] * (p_[static_cast<size_t>(i * stride + j + 1)] + p_[static_cast<size_t>(i * stride + j - 1)]) -
                           rhs[ii]) /
                          diag;
        const double next = std::max(0.0, p + omega * (gs - p));
        change = std::max(change, std::abs(next - p));
        p = next;
        pmax = std::max(pmax, p);
      }
    }
    ++sweeps_;
    if (change <= 1e-11 * pmax) break;
    if (sweeps_ > 400000) throw std::runtime_error("FdFilm: projected SOR did not converge");
  }
  double fx = 0.0, fy = 0.0;
  for (int i = 0; i < nt_; ++i) {
    double col = 0.0;
    for (int j = 1; j < nz_; ++j) col += p_[static_cast<size_t>(i * stride + j)];
    fx -= col * std::cos(i * dth);
    fy -= col * std::sin(i * dth);
  }
  return {fx * r * dth * dz, fy * r * dth * dz};
}

mj::DynamicCoefficients FdFilm::coefficients(const mj::JournalState& s, double spin_rad_s, double relative_step) {
  mj::DynamicCoefficients d;
  const auto f0 = force_n(s, spin_rad_s);
  d.fx0_n = f0[0];
  d.fy0_n = f0[1];
  const double dq = relative_step * g_.clearance_m, dv = dq * spin_rad_s;
  for (int k = 0; k < 4; ++k) {
    mj::JournalState sp = s, sm = s;
    const double step = k < 2 ? dq : dv;
    double* ap[4] = {&sp.x_m, &sp.y_m, &sp.vx_m_s, &sp.vy_m_s};
    double* am[4] = {&sm.x_m, &sm.y_m, &sm.vx_m_s, &sm.vy_m_s};
    *ap[k] += step;
    *am[k] -= step;
    const auto fp = force_n(sp, spin_rad_s), fm = force_n(sm, spin_rad_s);
    for (int row = 0; row < 2; ++row) {
      const double v = -(fp[static_cast<size_t>(row)] - fm[static_cast<size_t>(row)]) / (2.0 * step);
      if (k < 2) d.stiffness_n_per_m(row, k) = v;
      else d.damping_n_s_per_m(row, k - 2) = v;
    }
  }
  return d;
}

}  // namespace amb::test::journal
