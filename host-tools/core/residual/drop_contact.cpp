#include "host-tools/core/residual/drop_contact.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "model/amb/amb_force.hpp"
#include "model/drop/drop_options.hpp"
#include "model/drop/sensor_orbit.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::host::residual {
namespace {

using cd = std::complex<double>;
using Readings = std::vector<std::array<double, 4>>;
constexpr int k_orders = model::effects::k_runout_orders;
constexpr int k_runout_params = 4 * k_orders;  // 2 planes x orders x (re, im)

// Weight of sensor plane p in the straight-line view at aux plane k (SensorOrbit's extrapolation).
std::array<std::array<double, 2>, 2> aux_weights(const model::PlantParams& rig) {
  const double za = rig.sensor[0].axial_m, zb = rig.sensor[2].axial_m;
  std::array<std::array<double, 2>, 2> a{};
  for (size_t k = 0; k < 2; ++k) {
    const double s = (rig.aux[k].axial_m - za) / (zb - za);
    a[k] = {1.0 - s, s};
  }
  return a;
}

// K of the board's Hertz law F = K d^1.5 from its contact stiffness (dF/dd at the drop
// model's reference penetration), as model/drop does.
double hertz_coefficient(double contact_stiffness_n_per_m) {
  return model::drop::contact_law_coefficient(contact_stiffness_n_per_m, 1.5, model::drop::DropOptions{}.hertz_reference_penetration_m);
}

cd aux_point(const model::drop::SensorOrbit& view, const std::array<double, 4>& r, int k) {
  const auto p = view.at_aux_plane(r, k);
  return {p[0], p[1]};
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Joint least squares of both contact circles and (optionally) the runout phasors on given
// contact samples: unknowns [c0x, c0y, R0, c1x, c1y, R1, (re, im) per plane and order].
struct CircleFit {
  Eigen::VectorXd beta;
  Eigen::MatrixXd jtj;
  double ssr = 0.0;
  std::array<double, 2> ssr_k{};
  bool ok = false;
};

struct Sample {
  cd p;          // aux-plane point
  double theta;  // rotor angle
  int k;         // bearing
  size_t i;      // sample index
};

// Columns of the free phasors: (plane, order) -> first column, -1 when held at zero.
struct Layout {
  std::array<std::array<int, k_orders>, 2> col{};
  int params = 6;
};

Layout layout(bool runout, const RunoutMask& free) {
  Layout l;
  for (size_t p = 0; p < 2; ++p)
    for (size_t h = 0; h < static_cast<size_t>(k_orders); ++h) {
      l.col[p][h] = runout && free[p][h] ? l.params : -1;
      if (l.col[p][h] >= 0) l.params += 2;
    }
  return l;
}

cd runout_at(const Sample& x, const std::array<std::array<double, 2>, 2>& a, const Layout& l, const Eigen::VectorXd& beta) {
  cd w = 0.0;
  for (size_t p = 0; p < 2; ++p)
    for (size_t h = 0; h < static_cast<size_t>(k_orders); ++h)
      if (const int c = l.col[p][h]; c >= 0)
        w += a[static_cast<size_t>(x.k)][p] * cd(beta(c), beta(c + 1)) * std::exp(cd(0.0, static_cast<double>(h + 1) * x.theta));
  return w;
}

CircleFit fit_circles(const std::vector<Sample>& s, const std::array<std::array<double, 2>, 2>& a, const Layout& l,
                      const Eigen::VectorXd& start6) {
  const int np = l.params;
  CircleFit f;
  f.beta = Eigen::VectorXd::Zero(np);
  f.beta.head(6) = start6.head(6);
  for (int it = 0; it < 30; ++it) {
    Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(np, np);
    Eigen::VectorXd jtr = Eigen::VectorXd::Zero(np);
    double ssr = 0.0;
    std::array<double, 2> ssr_k{};
    Eigen::VectorXd j(np);
    for (const auto& x : s) {
      const cd d = x.p - runout_at(x, a, l, f.beta) - cd(f.beta(3 * x.k), f.beta(3 * x.k + 1));
      const double rad = std::abs(d);
      if (!(rad > 0.0)) continue;
      const cd u = d / rad;
      const double r = rad - f.beta(3 * x.k + 2);
      j.setZero();
      j(3 * x.k) = -u.real();
      j(3 * x.k + 1) = -u.imag();
      j(3 * x.k + 2) = -1.0;
      for (size_t p = 0; p < 2; ++p)
        for (size_t h = 0; h < static_cast<size_t>(k_orders); ++h)
          if (const int c = l.col[p][h]; c >= 0) {
            const cd ue = std::conj(u) * a[static_cast<size_t>(x.k)][p] * std::exp(cd(0.0, static_cast<double>(h + 1) * x.theta));
            j(c) = -ue.real();
            j(c + 1) = ue.imag();
          }
      jtj.noalias() += j * j.transpose();
      jtr.noalias() += j * r;
      ssr += r * r;
      ssr_k[static_cast<size_t>(x.k)] += r * r;
    }
    f.jtj = jtj;
    f.ssr = ssr;
    f.ssr_k = ssr_k;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(jtj);
    if (ldlt.info() != Eigen::Success) return f;
    const Eigen::VectorXd step = -ldlt.solve(jtr);
    if (!step.allFinite()) return f;
    f.beta += step;
    f.ok = true;
    if (step.norm() < 1e-11) break;
  }
  return f;
}

// Radial residuals of every sample under a fit.
std::vector<double> radial_residuals(const std::vector<Sample>& s, const std::array<std::array<double, 2>, 2>& a,
                                     const Layout& l, const Eigen::VectorXd& beta) {
  std::vector<double> r;
  r.reserve(s.size());
  for (const auto& x : s)
    r.push_back(std::abs(x.p - runout_at(x, a, l, beta) - cd(beta(3 * x.k), beta(3 * x.k + 1))) - beta(3 * x.k + 2));
  return r;
}

// Integrated autocorrelation time (samples) of a residual series taken at sample indices
// `idx` (gaps allowed): 1 + 2 sum rho(L) up to the first lag where rho < 0.05.
double correlation_samples(const std::vector<double>& r, const std::vector<size_t>& idx) {
  const size_t n = r.size();
  if (n < 10) return 1.0;
  double m = 0.0;
  for (double v : r) m += v;
  m /= static_cast<double>(n);
  double c0 = 0.0;
  for (double v : r) c0 += (v - m) * (v - m);
  c0 /= static_cast<double>(n);
  if (!(c0 > 0.0)) return 1.0;
  double tau = 1.0;
  for (size_t lag = 1; lag < 400 && lag < n / 4; ++lag) {
    double c = 0.0;
    size_t cnt = 0;
    // idx is increasing: walk a second pointer to the sample `lag` later.
    size_t j = 0;
    for (size_t i = 0; i < n; ++i) {
      while (j < n && idx[j] < idx[i] + lag) ++j;
      if (j < n && idx[j] == idx[i] + lag) {
        c += (r[i] - m) * (r[j] - m);
        ++cnt;
      }
    }
    if (cnt < 10) break;
    const double rho = c / static_cast<double>(cnt) / c0;
    if (rho < 0.05) break;
    tau += 2.0 * rho;
  }
  return tau;
}

// Contact samples among `cand` (each with a bearing index `k`) whose radial residual `r`
// lies within trim_sigma robust scales (1.4826 MAD) of its bearing's median: flight samples
// inside the contact band fall out.
template <class S>
std::vector<S> trimmed_contacts(const std::vector<S>& cand, const std::vector<double>& r, double trim_sigma) {
  std::array<std::vector<double>, 2> rk;
  for (size_t i = 0; i < cand.size(); ++i) rk[static_cast<size_t>(cand[i].k)].push_back(r[i]);
  std::array<double, 2> med{}, scale{};
  for (size_t k = 0; k < 2; ++k) {
    med[k] = median(rk[k]);
    std::vector<double> dev;
    for (double v : rk[k]) dev.push_back(std::abs(v - med[k]));
    scale[k] = 1.4826 * median(dev);
  }
  std::vector<S> next;
  for (size_t i = 0; i < cand.size(); ++i) {
    const auto k = static_cast<size_t>(cand[i].k);
    if (std::abs(r[i] - med[k]) <= trim_sigma * scale[k]) next.push_back(cand[i]);
  }
  return next;
}

// Correlation time (samples) of the residuals `res` of the samples `sel`, per bearing in time
// order, the longer one, at least `min_corr`.
template <class S>
double contact_correlation_samples(const std::vector<S>& sel, const std::vector<double>& res, double min_corr) {
  double tau = min_corr;
  for (int k = 0; k < 2; ++k) {
    std::vector<double> r;
    std::vector<size_t> idx;
    for (size_t i = 0; i < sel.size(); ++i)
      if (sel[i].k == k) {
        r.push_back(res[i]);
        idx.push_back(sel[i].i);
      }
    tau = std::max(tau, correlation_samples(r, idx));
  }
  return tau;
}

}  // namespace

double ContactRunout::largest_z() const {
  double z = 0.0;
  for (size_t p = 0; p < 2; ++p)
    for (size_t h = 0; h < static_cast<size_t>(k_orders); ++h)
      if (sigma_m[p][h] > 0.0) z = std::max(z, std::abs(runout.r_m[p][h]) / sigma_m[p][h]);
  return z;
}

ContactRunout estimate_contact_runout(const Readings& sensor_m, const SpinAngle& angle, const model::PlantParams& rig,
                                      double fs_hz, const ContactGeometryOptions& o, const RunoutMask& free) {
  ContactRunout out;
  const size_t n = std::min({sensor_m.size(), angle.theta_rad.size(), angle.known.size()});
  const model::drop::SensorOrbit view(rig);
  const auto a = aux_weights(rig);
  const double min_corr = std::max(1.0, fs_hz * o.decorrelation_s);  // samples per independent point, at least
  // Candidate contact samples: angle known, radius about the board's centre near the clearance.
  std::vector<Sample> cand;
  for (size_t i = 0; i < n; ++i) {
    if (!angle.known[i]) continue;
    for (int k = 0; k < 2; ++k) {
      const auto& ab = rig.aux[static_cast<size_t>(k)];
      const cd p = aux_point(view, sensor_m[i], k);
      if (std::abs(p - cd(ab.centre_offset_x_m, ab.centre_offset_y_m)) >= o.contact_band * ab.clearance_m)
        cand.push_back({p, angle.theta_rad[i], k, i});
    }
  }
  Eigen::VectorXd start = Eigen::VectorXd::Zero(6);
  for (int k = 0; k < 2; ++k) {
    start(3 * k) = rig.aux[static_cast<size_t>(k)].centre_offset_x_m;
    start(3 * k + 1) = rig.aux[static_cast<size_t>(k)].centre_offset_y_m;
    start(3 * k + 2) = rig.aux[static_cast<size_t>(k)].clearance_m;
  }
  auto count = [&](const std::vector<Sample>& s) {
    std::array<int, 2> c{};
    for (const auto& x : s) ++c[static_cast<size_t>(x.k)];
    return c;
  };
  auto enough = [&](const std::array<int, 2>& c) { return c[0] >= o.min_points * min_corr && c[1] >= o.min_points * min_corr; };
  if (!enough(count(cand))) {
    out.why_not = "too few contact samples with a known rotor angle (a spin-speed record after the trigger is needed)";
    return out;
  }
  // Contact samples: the circle fit's radial residual within trim_sigma robust scales of its
  // median (flight samples inside the band fall out), twice.
  const Layout circles_only = layout(false, free), with_runout = layout(true, free);
  std::vector<Sample> sel = cand;
  CircleFit c0 = fit_circles(sel, a, circles_only, start);
  for (int pass = 0; pass < 2 && c0.ok; ++pass) {
    std::vector<Sample> next = trimmed_contacts(cand, radial_residuals(cand, a, circles_only, c0.beta), o.trim_sigma);
    if (!enough(count(next))) break;
    sel = std::move(next);
    c0 = fit_circles(sel, a, circles_only, c0.beta);
  }
  const auto pts = count(sel);
  if (!c0.ok || !enough(pts)) {
    out.why_not = "too few contact points on the clearance circles";
    return out;
  }
  const CircleFit c1 = fit_circles(sel, a, with_runout, c0.beta);
  if (!c1.ok) {
    out.why_not = "the runout phasors are not resolved by the contact points";
    return out;
  }
  // Resolution (the rotor angle must sweep the contact directions).
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(c1.jtj);
  if (es.eigenvalues()(0) <= 1e-9 * es.eigenvalues()(es.eigenvalues().size() - 1)) {
    out.why_not = "the runout phasors are not resolved (rotor angle and contact direction do not vary independently)";
    return out;
  }
  // Correlation time of the residual (per bearing, in time order; the longer one).
  const double tau = contact_correlation_samples(sel, radial_residuals(sel, a, with_runout, c1.beta), min_corr);
  const double per_point = 1.0 / tau;
  const int np = with_runout.params;
  const int npts = pts[0] + pts[1];
  out.testable = true;
  out.points = pts;
  out.n_eff = std::max(1.0, npts * per_point);
  out.ssr_without_m2 = c0.ssr;
  out.ssr_with_m2 = c1.ssr;
  out.delta_bic = out.n_eff * std::log(c0.ssr / std::max(c1.ssr, 1e-300)) - (np - 6) * std::log(out.n_eff);
  const double s2 = c1.ssr / std::max(1, npts - np);
  const Eigen::MatrixXd cov = s2 * c1.jtj.inverse() / per_point;
  for (int k = 0; k < 2; ++k) {
    out.centre_m[static_cast<size_t>(k)] = {c1.beta(3 * k), c1.beta(3 * k + 1)};
    out.radius_m[static_cast<size_t>(k)] = c1.beta(3 * k + 2);
  }
  for (size_t p = 0; p < 2; ++p)
    for (size_t h = 0; h < static_cast<size_t>(k_orders); ++h)
      if (const int c = with_runout.col[p][h]; c >= 0) {
        out.runout.r_m[p][h] = cd(c1.beta(c), c1.beta(c + 1));
        out.sigma_m[p][h] = std::sqrt(0.5 * (cov(c, c) + cov(c + 1, c + 1)));
      }
  // Spin range over the points used.
  double wmin = 1e300, wmax = 0.0;
  for (const auto& x : sel)
    if (x.i > 0 && angle.known[x.i - 1]) {
      const double w = (angle.theta_rad[x.i] - angle.theta_rad[x.i - 1]) * fs_hz / (2.0 * M_PI);
      wmin = std::min(wmin, w);
      wmax = std::max(wmax, w);
    }
  out.spin_min_hz = wmax > 0.0 ? wmin : 0.0;
  out.spin_max_hz = wmax;
  return out;
}

std::array<double, 2> unbalance_contact_signature_m(const model::PlantParams& rig, const model::RigModel& rig_model,
                                                     const std::array<double, 2>& force_n,
                                                     const std::array<double, 2>& axial_m, double spin_hz) {
  rig_model.check_same_rig(rig, "drop contact");
  const model::rotor::RotorModel& rm = rig_model.rotor();
  const Eigen::Index nd = rm.planar_stiffness.rows();
  const double w = 2.0 * M_PI * spin_hz;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(nd + 2, nd + 2);
  a.topLeftCorner(nd, nd) = rm.planar_stiffness - w * w * rm.planar_mass;
  for (int k = 0; k < 2; ++k) {
    const Eigen::RowVectorXd c = model::rotor::planar_interpolation(rm, rig.aux[static_cast<size_t>(k)].axial_m);
    a.block(nd + k, 0, 1, nd) = c;
    a.block(0, nd + k, nd, 1) = c.transpose();
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
  std::array<double, 2> out{};
  double fsum = 0.0;
  for (size_t j = 0; j < 2; ++j) {
    if (!(std::abs(force_n[j]) > 0.0)) continue;
    fsum += std::abs(force_n[j]);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nd + 2);
    rhs.head(nd) = model::rotor::planar_interpolation(rm, axial_m[j]).transpose();
    const Eigen::VectorXd u = lu.solve(rhs);
    for (size_t p = 0; p < 2; ++p)
      out[p] += std::abs((model::rotor::planar_interpolation(rm, rig.sensor[2 * p].axial_m) * u.head(nd))(0)) * std::abs(force_n[j]);
  }
  // Contact-deflection modulation at the weight share (board's contact law).
  const double share = 0.5 * rm.mass_kg * rig.gravity_m_s2;
  for (size_t p = 0; p < 2; ++p) {
    const auto& ab = rig.aux[p];
    const double kc = ab.contact_stiffness_n_per_m;
    double compliance = kc > 0.0 ? 1.0 / kc : 0.0;
    if (ab.contact_law == model::AuxContactLaw::hertz && kc > 0.0) {
      const double d = std::pow(share / hertz_coefficient(kc), 2.0 / 3.0);
      compliance = 2.0 / 3.0 * d / share;
    }
    out[p] += compliance * fsum;
  }
  return out;
}

SagViewShift gravity_sag_view_shift_m(const model::PlantParams& rig, const model::RigModel& rig_model) {
  rig_model.check_same_rig(rig, "drop contact");
  const model::rotor::RotorModel& rm = rig_model.rotor();
  const Eigen::Index nd = rm.planar_stiffness.rows();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(nd + 2, nd + 2);
  a.topLeftCorner(nd, nd) = rm.planar_stiffness;
  for (int k = 0; k < 2; ++k) {
    const Eigen::RowVectorXd c = model::rotor::planar_interpolation(rm, rig.aux[static_cast<size_t>(k)].axial_m);
    a.block(nd + k, 0, 1, nd) = c;
    a.block(0, nd + k, nd, 1) = c.transpose();
  }
  // Gravity on every node's translation (y down).
  Eigen::VectorXd unit_w = Eigen::VectorXd::Zero(nd);
  for (Eigen::Index i = 0; i < nd; i += 2) unit_w(i) = 1.0;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nd + 2);
  rhs.head(nd) = -rig.gravity_m_s2 * (rm.planar_mass * unit_w);
  const Eigen::VectorXd u = a.partialPivLu().solve(rhs);
  if (!u.allFinite()) return {};
  const double ya = (model::rotor::planar_interpolation(rm, rig.sensor[0].axial_m) * u.head(nd))(0);
  const double yb = (model::rotor::planar_interpolation(rm, rig.sensor[2].axial_m) * u.head(nd))(0);
  const double za = rig.sensor[0].axial_m, zb = rig.sensor[2].axial_m;
  SagViewShift out;
  out.weight_n = rm.mass_kg * rig.gravity_m_s2;
  for (size_t k = 0; k < 2; ++k) {
    const double s = (rig.aux[k].axial_m - za) / (zb - za);
    out.shift_m[k] = ya + s * (yb - ya);  // the contact point itself is pinned at 0
  }
  return out;
}

Readings remove_runout(const Readings& sensor_m, const SpinAngle& angle, const model::effects::SensorRunout& r,
                       const model::PlantParams& rig) {
  Readings out = sensor_m;
  const size_t n = std::min({sensor_m.size(), angle.theta_rad.size(), angle.known.size()});
  for (size_t i = 0; i < n; ++i) {
    if (!angle.known[i]) continue;
    for (int k = 0; k < 4; ++k) {
      const auto dir = model::magnet::axis_direction(rig.sensor[static_cast<size_t>(k)].angle_deg);
      double v = 0.0;
      for (int h = 1; h <= k_orders; ++h)
        v += (r.r_m[static_cast<size_t>(k / 2)][static_cast<size_t>(h - 1)] * cd(dir[0], -dir[1]) *
              std::exp(cd(0.0, h * angle.theta_rad[i])))
                 .real();
      out[i][static_cast<size_t>(k)] -= v;
    }
  }
  return out;
}

ContactCompliance estimate_contact_compliance(const Readings& sensor_m, const model::PlantParams& rig,
                                              const model::RigModel& rig_model, double fs_hz,
                                              const std::array<std::array<double, 2>, 2>& centre_m,
                                              const ContactGeometryOptions& o) {
  ContactCompliance out;
  const size_t n = sensor_m.size();
  rig_model.check_same_rig(rig, "drop contact");
  const model::rotor::RotorModel& rm = rig_model.rotor();
  struct {
    double mass_kg, z_cm_m, jt_kg_m2;
  } rr{rm.mass_kg, rm.centre_of_mass_m, rm.transverse_inertia_kg_m2};
  const double dt = 1.0 / fs_hz;
  // Second derivative: quadratic least squares over +-w samples (about +-0.5 ms).
  const int w = std::max(2, static_cast<int>(std::lround(0.5e-3 * fs_hz)));
  if (n < static_cast<size_t>(4 * w + 10) || !(rr.mass_kg > 0.0)) {
    out.why_not = "record too short";
    return out;
  }
  double m2 = 0.0;
  for (int k = -w; k <= w; ++k) m2 += k * k;
  m2 /= (2 * w + 1);
  double den = 0.0;
  for (int k = -w; k <= w; ++k) den += (k * k - m2) * (k * k - m2);
  const model::drop::SensorOrbit view(rig);
  const double za = rig.sensor[0].axial_m, zb = rig.sensor[2].axial_m;
  std::vector<cd> pa(n), pb(n);
  for (size_t i = 0; i < n; ++i) {
    const auto x = view.at_sensor_plane(sensor_m[i], 0), y = view.at_sensor_plane(sensor_m[i], 1);
    pa[i] = {x[0], x[1]};
    pb[i] = {y[0], y[1]};
  }
  auto acc = [&](const std::vector<cd>& v, size_t i) {
    cd s = 0.0;
    for (int k = -w; k <= w; ++k) s += (k * k - m2) * v[static_cast<size_t>(static_cast<long>(i) + k)];
    return 2.0 * s / (den * dt * dt);
  };
  const double l0 = rig.aux[0].axial_m - rr.z_cm_m, l1 = rig.aux[1].axial_m - rr.z_cm_m;
  const double g = rig.gravity_m_s2;
  std::array<std::vector<double>, 2> force, defl;
  std::array<std::vector<size_t>, 2> at;
  for (size_t i = static_cast<size_t>(w); i + static_cast<size_t>(w) < n; ++i) {
    const cd aa = acc(pa, i), ab = acc(pb, i);
    const cd acm = aa + (rr.z_cm_m - za) / (zb - za) * (ab - aa);
    const cd atilt = (ab - aa) / (zb - za);
    const cd sum = rr.mass_kg * acm + cd(0.0, rr.mass_kg * g);   // F_A + F_B
    const cd mom = rr.jt_kg_m2 * atilt;                           // l0 F_A + l1 F_B
    const cd fa = (mom - l1 * sum) / (l0 - l1), fb = sum - fa;
    for (int k = 0; k < 2; ++k) {
      const auto& ab_ = rig.aux[static_cast<size_t>(k)];
      const cd p = aux_point(view, sensor_m[i], k) - cd(centre_m[static_cast<size_t>(k)][0], centre_m[static_cast<size_t>(k)][1]);
      const double rad = std::abs(p);
      if (rad < o.contact_band * ab_.clearance_m) continue;
      const cd u = p / rad;
      const double nf = -(std::conj(u) * (k == 0 ? fa : fb)).real();  // normal force pushing the rotor inwards
      force[static_cast<size_t>(k)].push_back(nf);
      defl[static_cast<size_t>(k)].push_back(rad - ab_.clearance_m);
      at[static_cast<size_t>(k)].push_back(i);
    }
  }
  const double min_corr = std::max(1.0, fs_hz * o.decorrelation_s);
  const double weight_share = 0.5 * rr.mass_kg * g;
  bool all = true;
  for (size_t k = 0; k < 2; ++k) {
    // Contact samples: the normal force clearly positive (a tenth of the weight share).
    std::vector<double> f, d;
    std::vector<size_t> idx;
    for (size_t i = 0; i < force[k].size(); ++i)
      if (force[k][i] > 0.1 * weight_share) {
        f.push_back(force[k][i]);
        d.push_back(defl[k][i]);
        idx.push_back(at[k][i]);
      }
    out.points[k] = static_cast<int>(f.size());
    if (static_cast<double>(f.size()) < o.min_points * min_corr) {
      all = false;
      continue;
    }
    // The board's contact law: Hertz K d^1.5 (K from the contact stiffness dF/dd at 10 um) or linear.
    const auto& ab = rig.aux[k];
    const double kc = ab.contact_stiffness_n_per_m;
    auto law = [&](double fn) {
      if (ab.contact_law == model::AuxContactLaw::hertz) return std::pow(fn / hertz_coefficient(kc), 2.0 / 3.0);
      return fn / kc;
    };
    // deflection - law(F) = d0 + C F
    const size_t m = f.size();
    double sf = 0, sy = 0, sff = 0, sfy = 0, syy = 0;
    for (size_t i = 0; i < m; ++i) {
      const double y = d[i] - law(f[i]);
      sf += f[i];
      sy += y;
      sff += f[i] * f[i];
      sfy += f[i] * y;
      syy += y * y;
    }
    const double md = static_cast<double>(m);
    const double vf = sff - sf * sf / md, cfy = sfy - sf * sy / md, vy = syy - sy * sy / md;
    if (!(vf > 0.0)) {
      all = false;
      continue;
    }
    const double c = cfy / vf;
    const double ssr1 = std::max(vy - c * cfy, 1e-300);
    std::vector<double> res(m);
    const double d0 = (sy - c * sf) / md;
    for (size_t i = 0; i < m; ++i) res[i] = d[i] - law(f[i]) - d0 - c * f[i];
    const double per_point = 1.0 / std::max(min_corr, correlation_samples(res, idx));
    const double neff = std::max(2.0, md * per_point);
    out.compliance_m_per_n[k] = c;
    out.sigma_m_per_n[k] = std::sqrt(ssr1 / (md - 2.0) / vf / per_point);
    out.mean_force_n[k] = sf / md;
    std::vector<double> fs_sorted = f;
    std::sort(fs_sorted.begin(), fs_sorted.end());
    out.force_span_n[k] = fs_sorted[static_cast<size_t>(0.9 * (md - 1))] - fs_sorted[static_cast<size_t>(0.1 * (md - 1))];
    out.deflection_change_m[k] = c * out.force_span_n[k];
    out.noise_m[k] = std::sqrt(ssr1 / md);
    out.delta_bic[k] = neff * std::log(std::max(vy, 1e-300) / ssr1) - std::log(neff);
  }
  out.testable = all;
  if (!all) out.why_not = "too few contact samples with a resolved contact force";
  return out;
}

}  // namespace amb::host::residual

namespace amb::host::residual {
namespace {

// Gauss-Newton on [c0x, c0y, R0, c1x, c1y, R1, aA, aB] (ratios held at 0 where not free).
struct GainFit {
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(8);
  Eigen::MatrixXd jtj;
  double ssr = 0.0;
  bool ok = false;
};

struct GainSample {
  std::array<double, 4> r;  // readings
  int k;                    // bearing
  size_t i;                 // sample index
};

// Aux-plane point of bearing k from readings divided by the gains of ratios a (complex, m),
// and its derivatives with respect to a_A and a_B.
void gain_point(const std::array<std::array<cd, 4>, 2>& m, const GainSample& x, const Eigen::VectorXd& beta, cd& p,
                std::array<cd, 2>& dp) {
  p = 0.0;
  dp = {cd(0.0), cd(0.0)};
  for (size_t j = 0; j < 4; ++j) {
    const size_t plane = j / 2;
    const double sign = j % 2 == 0 ? 1.0 : -1.0;
    const double inv_g = std::exp(-0.5 * sign * beta(6 + static_cast<int>(plane)));
    const cd term = m[static_cast<size_t>(x.k)][j] * x.r[j] * inv_g;
    p += term;
    dp[plane] += -0.5 * sign * term;
  }
}

GainFit fit_gain(const std::vector<GainSample>& s, const std::array<std::array<cd, 4>, 2>& m, const std::array<bool, 2>& free,
                 const Eigen::VectorXd& start) {
  GainFit f;
  f.beta = start;
  for (int p = 0; p < 2; ++p)
    if (!free[static_cast<size_t>(p)]) f.beta(6 + p) = 0.0;
  for (int it = 0; it < 40; ++it) {
    Eigen::MatrixXd jtj = Eigen::MatrixXd::Zero(8, 8);
    Eigen::VectorXd jtr = Eigen::VectorXd::Zero(8);
    double ssr = 0.0;
    Eigen::VectorXd j(8);
    for (const auto& x : s) {
      cd p;
      std::array<cd, 2> dp;
      gain_point(m, x, f.beta, p, dp);
      const cd d = p - cd(f.beta(3 * x.k), f.beta(3 * x.k + 1));
      const double rad = std::abs(d);
      if (!(rad > 0.0)) continue;
      const cd u = d / rad;
      const double r = rad - f.beta(3 * x.k + 2);
      j.setZero();
      j(3 * x.k) = -u.real();
      j(3 * x.k + 1) = -u.imag();
      j(3 * x.k + 2) = -1.0;
      for (int q = 0; q < 2; ++q)
        if (free[static_cast<size_t>(q)]) j(6 + q) = (std::conj(u) * dp[static_cast<size_t>(q)]).real();
      jtj.noalias() += j * j.transpose();
      jtr.noalias() += j * r;
      ssr += r * r;
    }
    for (int q = 0; q < 2; ++q)
      if (!free[static_cast<size_t>(q)]) jtj(6 + q, 6 + q) = 1.0;  // held: a unit pivot, zero step
    f.jtj = jtj;
    f.ssr = ssr;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(jtj);
    if (ldlt.info() != Eigen::Success) return f;
    const Eigen::VectorXd step = -ldlt.solve(jtr);
    if (!step.allFinite()) return f;
    f.beta += step;
    f.ok = true;
    if (step.head(6).norm() < 1e-11 && step.tail(2).norm() < 1e-9) break;
  }
  return f;
}

}  // namespace

ContactGain estimate_contact_gain(const Readings& sensor_m, const model::PlantParams& rig, double fs_hz, const ContactGeometryOptions& o,
                                  const std::array<bool, 2>& free) {
  ContactGain out;
  const model::drop::SensorOrbit view(rig);
  // The straight-line view is linear in the readings: its column per probe.
  std::array<std::array<cd, 4>, 2> m{};
  for (int k = 0; k < 2; ++k)
    for (size_t j = 0; j < 4; ++j) {
      std::array<double, 4> e{};
      e[j] = 1.0;
      m[static_cast<size_t>(k)][j] = aux_point(view, e, k);
    }
  const double min_corr = std::max(1.0, fs_hz * o.decorrelation_s);
  std::vector<GainSample> cand;
  for (size_t i = 0; i < sensor_m.size(); ++i)
    for (int k = 0; k < 2; ++k) {
      const auto& ab = rig.aux[static_cast<size_t>(k)];
      if (std::abs(aux_point(view, sensor_m[i], k) - cd(ab.centre_offset_x_m, ab.centre_offset_y_m)) >= o.contact_band * ab.clearance_m)
        cand.push_back({sensor_m[i], k, i});
    }
  auto count = [&](const std::vector<GainSample>& s) {
    std::array<int, 2> c{};
    for (const auto& x : s) ++c[static_cast<size_t>(x.k)];
    return c;
  };
  auto enough = [&](const std::array<int, 2>& c) { return c[0] >= o.min_points * min_corr && c[1] >= o.min_points * min_corr; };
  if (!enough(count(cand))) {
    out.why_not = "too few contact samples";
    return out;
  }
  Eigen::VectorXd start = Eigen::VectorXd::Zero(8);
  for (int k = 0; k < 2; ++k) {
    start(3 * k) = rig.aux[static_cast<size_t>(k)].centre_offset_x_m;
    start(3 * k + 1) = rig.aux[static_cast<size_t>(k)].centre_offset_y_m;
    start(3 * k + 2) = rig.aux[static_cast<size_t>(k)].clearance_m;
  }
  const std::array<bool, 2> none{false, false};
  auto residuals = [&](const std::vector<GainSample>& s, const Eigen::VectorXd& beta) {
    std::vector<double> r;
    r.reserve(s.size());
    for (const auto& x : s) {
      cd p;
      std::array<cd, 2> dp;
      gain_point(m, x, beta, p, dp);
      r.push_back(std::abs(p - cd(beta(3 * x.k), beta(3 * x.k + 1))) - beta(3 * x.k + 2));
    }
    return r;
  };
  // Contact samples: within trim_sigma robust scales of the circle fit's median residual, twice.
  std::vector<GainSample> sel = cand;
  GainFit c0 = fit_gain(sel, m, none, start);
  for (int pass = 0; pass < 2 && c0.ok; ++pass) {
    std::vector<GainSample> next = trimmed_contacts(cand, residuals(cand, c0.beta), o.trim_sigma);
    if (!enough(count(next))) break;
    sel = std::move(next);
    c0 = fit_gain(sel, m, none, c0.beta);
  }
  const auto pts = count(sel);
  if (!c0.ok || !enough(pts)) {
    out.why_not = "too few contact points on the clearance circles";
    return out;
  }
  const GainFit c1 = fit_gain(sel, m, free, c0.beta);
  const int nfree = static_cast<int>(free[0]) + static_cast<int>(free[1]);
  if (!c1.ok || nfree == 0) {
    out.why_not = nfree == 0 ? "no gain ratio free" : "the gain ratios are not resolved by the contact points";
    return out;
  }
  // Resolution: the contact directions must spread round the circle (an arc at the bottom
  // alone cannot tell an ellipse from a circle of another centre).
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(c1.jtj);
  if (es.eigenvalues()(0) <= 1e-9 * es.eigenvalues()(7)) {
    out.why_not = "the gain ratios are not resolved (the contact points do not spread round the circles)";
    return out;
  }
  const double tau = contact_correlation_samples(sel, residuals(sel, c1.beta), min_corr);
  const double per_point = 1.0 / tau;
  const int npts = pts[0] + pts[1];
  out.testable = true;
  out.points = pts;
  out.n_eff = std::max(1.0, npts * per_point);
  out.ssr_without_m2 = c0.ssr;
  out.ssr_with_m2 = c1.ssr;
  out.delta_bic = out.n_eff * std::log(c0.ssr / std::max(c1.ssr, 1e-300)) - nfree * std::log(out.n_eff);
  const double s2 = c1.ssr / std::max(1, npts - 6 - nfree);
  const Eigen::MatrixXd cov = s2 * c1.jtj.inverse() / per_point;
  for (int p = 0; p < 2; ++p)
    if (free[static_cast<size_t>(p)]) {
      out.log_ratio[static_cast<size_t>(p)] = c1.beta(6 + p);
      out.sigma[static_cast<size_t>(p)] = std::sqrt(std::max(0.0, cov(6 + p, 6 + p)));
    }
  return out;
}

Readings remove_gain_ratio(const Readings& sensor_m, const std::array<double, 2>& log_ratio) {
  Readings out = sensor_m;
  for (auto& r : out)
    for (size_t j = 0; j < 4; ++j) r[j] *= std::exp(-0.5 * (j % 2 == 0 ? 1.0 : -1.0) * log_ratio[j / 2]);
  return out;
}

}  // namespace amb::host::residual
