#include "host-tools/core/sweep/sweep_model.hpp"

#include <cmath>
#include <stdexcept>

#include "model/amb/amb_force.hpp"
#include "model/effects/effect_loop_model.hpp"

namespace amb::host::sweep {
namespace {

using cd = std::complex<double>;

}  // namespace

template <class T>
T axis_position(const model::PlantParams& rig, int axis, const std::array<T, 4>& s) {
  const int p = axis / 2;
  const double a1 = rig.sensor[static_cast<size_t>(2 * p)].angle_deg * M_PI / 180.0;
  const double a2 = rig.sensor[static_cast<size_t>(2 * p + 1)].angle_deg * M_PI / 180.0;
  // s_k = x sin(a_k) + y cos(a_k): invert the 2 x 2.
  const double m00 = std::sin(a1), m01 = std::cos(a1), m10 = std::sin(a2), m11 = std::cos(a2);
  const double det = m00 * m11 - m01 * m10;
  const T s1 = s[static_cast<size_t>(2 * p)], s2 = s[static_cast<size_t>(2 * p + 1)];
  const T x = (m11 * s1 - m01 * s2) / det, y = (-m10 * s1 + m00 * s2) / det;
  const double b = rig.amb[static_cast<size_t>(p)].actuator_angle_deg[static_cast<size_t>(axis % 2)] * M_PI / 180.0;
  return std::sin(b) * x + std::cos(b) * y;
}

template double axis_position<double>(const model::PlantParams&, int, const std::array<double, 4>&);
template cd axis_position<cd>(const model::PlantParams&, int, const std::array<cd, 4>&);

SweepLoopModel::SweepLoopModel(const board::BoardConfig& b, double speed_hz, std::vector<int> axes, std::vector<double> f_hz)
    : b_(b), speed_hz_(speed_hz), axes_(std::move(axes)), f_(std::move(f_hz)) {
  for (int a : axes_)
    if (a < 0 || a > 3) throw std::invalid_argument("sweep model: axis " + std::to_string(a) + " is not a control axis 0..3");
  for (double f : f_)
    if (!(f > 0.0) || !std::isfinite(f)) throw std::invalid_argument("sweep model: line frequencies must be > 0");
  rig_ = model::RigModel::make(b_.plant);
  {
    // Linearised at the operating point: the coils carry the static control currents that hold
    // the rotor's weight, and the negative stiffness grows with them (amb_force.hpp:
    // ks(ic) = 4 k (i0^2 + ic^2) / g0^3; ki does not change at z = 0). The board's ks is the one
    // at ic = 0; the loop runs at the static currents.
    const model::effects::EffectLoopModel stat(rig_, b_.plant, b_.controller, b_.rate_hz, speed_hz_, {});
    const auto sp = stat.static_levitated();
    for (size_t p = 0; p < b_.plant.amb.size() && p < 2; ++p) {
      const auto law = model::magnet::make_axis_law(b_.plant.amb[p]);
      double ks = 0.0;
      for (size_t a = 0; a < 2; ++a) ks += 0.5 * model::magnet::linearise(law, 0.0, sp.current_a[2 * p + a]).ks_n_per_m;
      operating_ks_ratio_[p] = ks / b_.plant.amb[p].ks_n_per_m;
      b_.plant.amb[p].ks_n_per_m = ks;
    }
  }
  model::analysis::ClosedLoopOptions o;
  o.sample_rate_hz = b_.rate_hz;
  o.loop_delay_periods = b_.loop_delay_periods;
  o.spin_hz = speed_hz_;
  exact_ = std::make_unique<model::analysis::ClosedLoopModel>(*rig_, b_.plant, b_.controller, o);
  eff0_ = effect_lines({}, f_);
  board_.assign(axes_.size(), {});
  for (size_t a = 0; a < axes_.size(); ++a)
    for (double f : f_) board_[a].push_back(exact(a, f));
}

ModelResponse SweepLoopModel::exact(size_t a, double f) const {
  const auto r = exact_->injection_response(axes_[a], f);
  ModelResponse m;
  m.s = r.demand;
  m.t = 1.0 - r.demand;
  m.g = axis_position<cd>(b_.plant, axes_[a], r.sensor_m_per_a) / r.demand;
  return m;
}

std::vector<std::vector<ModelResponse>> SweepLoopModel::effect_lines(const model::effects::EffectSet& fx_in,
                                                                     const std::vector<double>& f) const {
  model::effects::EffectSet fx = fx_in;
  fx.update.loop_delay_s += b_.loop_delay_periods / b_.rate_hz;
  const model::effects::EffectLoopModel m(rig_, b_.plant, b_.controller, b_.rate_hz, speed_hz_, fx);
  std::vector<std::vector<ModelResponse>> out(axes_.size());
  for (double fh : f) {
    const auto r = m.at(fh);
    for (size_t a = 0; a < axes_.size(); ++a) {
      const int j = axes_[a];
      // Injection e before the amplifier = injection A_j e after it: the coil currents are
      // minv A_j e, the demand u_j = i_j / A_j = minv(j, j) e, the readings T minv A_j e.
      const cd amp = m.amplifier_response(j, fh);
      std::array<cd, 4> y{};
      for (int k = 0; k < 4; ++k) y[static_cast<size_t>(k)] = r.injection(k, j) * amp;
      ModelResponse q;
      q.s = r.injection(4 + j, j);
      q.t = 1.0 - q.s;
      q.g = axis_position<cd>(b_.plant, j, y) / q.s;
      out[a].push_back(q);
    }
  }
  return out;
}

std::vector<std::vector<ModelResponse>> SweepLoopModel::with(const model::effects::EffectSet& fx) const {
  if (fx.names().empty() && fx.update.loop_delay_s == 0.0 && fx.update.force_scale == 1.0) return board_;
  const auto e = effect_lines(fx, f_);
  auto out = board_;
  for (size_t a = 0; a < out.size(); ++a)
    for (size_t l = 0; l < f_.size(); ++l) {
      auto& q = out[a][l];
      q.s *= e[a][l].s / eff0_[a][l].s;
      q.g *= e[a][l].g / eff0_[a][l].g;
      q.t = 1.0 - q.s;
    }
  return out;
}

model::analysis::SensitivityPeak SweepLoopModel::peak(size_t a, double lo, double hi, const model::effects::EffectSet& fx) const {
  const bool none = fx.names().empty() && fx.update.loop_delay_s == 0.0 && fx.update.force_scale == 1.0;
  std::unique_ptr<model::effects::EffectLoopModel> em, e0;
  if (!none) {
    model::effects::EffectSet f1 = fx, f0;
    f1.update.loop_delay_s += b_.loop_delay_periods / b_.rate_hz;
    f0.update.loop_delay_s = b_.loop_delay_periods / b_.rate_hz;
    em = std::make_unique<model::effects::EffectLoopModel>(rig_, b_.plant, b_.controller, b_.rate_hz, speed_hz_, f1);
    e0 = std::make_unique<model::effects::EffectLoopModel>(rig_, b_.plant, b_.controller, b_.rate_hz, speed_hz_, f0);
  }
  const int j = axes_[a];
  auto mag = [&](double f) {
    cd s = exact_->injection_response(j, f).demand;
    if (!none) s *= em->at(f).injection(4 + j, j) / e0->at(f).injection(4 + j, j);
    return std::abs(s);
  };
  const int n = 400;
  double best = -1.0, fb = lo;
  int ib = 0;
  std::vector<double> g(n);
  for (int i = 0; i < n; ++i) {
    g[static_cast<size_t>(i)] = lo * std::pow(hi / lo, i / (n - 1.0));
    const double m = mag(g[static_cast<size_t>(i)]);
    if (m > best) { best = m; fb = g[static_cast<size_t>(i)]; ib = i; }
  }
  double l = g[static_cast<size_t>(std::max(0, ib - 1))], h = g[static_cast<size_t>(std::min(n - 1, ib + 1))];
  const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = h - gr * (h - l), x2 = l + gr * (h - l), m1 = mag(x1), m2 = mag(x2);
  for (int it = 0; it < 30; ++it) {
    if (m1 > m2) { h = x2; x2 = x1; m2 = m1; x1 = h - gr * (h - l); m1 = mag(x1); }
    else { l = x1; x1 = x2; m1 = m2; x2 = l + gr * (h - l); m2 = mag(x2); }
  }
  if (std::max(m1, m2) > best) { best = std::max(m1, m2); fb = m1 > m2 ? x1 : x2; }
  model::analysis::SensitivityPeak p;
  p.peak = best;
  p.peak_db = 20.0 * std::log10(best);
  p.frequency_hz = fb;
  p.zone = model::analysis::iso14839_zone(best);
  return p;
}

}  // namespace amb::host::sweep
