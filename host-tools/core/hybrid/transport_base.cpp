#include "host-tools/core/hybrid/transport_base.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "host-tools/core/hybrid/spectra.hpp"

namespace amb::host::hybrid {

std::string case_name(BearingState s, const OperatingPoint& op) {
  char b[96];
  std::snprintf(b, sizeof b, "%s@%grpm/%g", state_name(s), op.speed_rpm, op.load);
  return b;
}

namespace {

bool same_point(const OperatingPoint& a, const OperatingPoint& b) {
  return std::abs(a.speed_rpm - b.speed_rpm) <= 1e-9 * std::max(a.speed_rpm, b.speed_rpm) &&
         std::abs(a.load - b.load) <= 1e-9 * std::max(1.0, std::max(a.load, b.load));
}

std::vector<double> mix(const std::vector<double>& lo, const std::vector<double>& hi, double w_hi) {
  std::vector<double> out(lo.size());
  for (size_t k = 0; k < lo.size(); ++k) out[k] = (1.0 - w_hi) * lo[k] + w_hi * hi[k];
  return out;
}

}  // namespace

TransportedBase transported_base(const std::vector<ReferenceSpectra>& refs, BearingState state, const OperatingPoint& op,
                                 const std::vector<double>& psd_hz, const std::vector<double>& env_hz,
                                 const std::vector<double>& scales, int halfwidth_bins, const OperatingPoint* exclude) {
  TransportedBase b;
  const ReferenceSpectra *nearest = nullptr, *below = nullptr, *above = nullptr;
  double best = 0.0;
  for (const auto& r : refs) {
    if (r.state != state || (exclude != nullptr && same_point(r.op, *exclude))) continue;
    // Nearest in speed (log ratio), then in load.
    const double dist = std::abs(std::log(op.speed_rpm / r.op.speed_rpm)) + 1e-6 * std::abs(op.load - r.op.load);
    if (nearest == nullptr || dist < best) {
      nearest = &r;
      best = dist;
    }
    if (r.op.speed_rpm <= op.speed_rpm && (below == nullptr || r.op.speed_rpm > below->op.speed_rpm)) below = &r;
    if (r.op.speed_rpm >= op.speed_rpm && (above == nullptr || r.op.speed_rpm < above->op.speed_rpm)) above = &r;
  }
  if (nearest == nullptr) return b;
  b.found = true;
  b.nearest_case = case_name(nearest->state, nearest->op);
  auto moved_log = [&](const ReferenceSpectra& r) {
    return transport_log_psd(r.log_psd, psd_hz, op.speed_rpm / r.op.speed_rpm, scales, halfwidth_bins);
  };
  auto moved_env = [&](const ReferenceSpectra& r) { return transport_env(r.env_power, env_hz, op.speed_rpm / r.op.speed_rpm, scales); };
  auto source = [&](const ReferenceSpectra& r, double w) {
    TransportSource t;
    t.case_name = case_name(r.state, r.op);
    t.weight = w;
    t.speed_rpm = r.op.speed_rpm;
    t.moved_log_psd = moved_log(r);
    t.moved_env_power = moved_env(r);
    t.log_psd = r.log_psd;
    t.env_power = r.env_power;
    return t;
  };
  b.nearest_log_psd = moved_log(*nearest);
  b.nearest_env_power = moved_env(*nearest);
  if (below != nullptr && above != nullptr && below != above && above->op.speed_rpm > below->op.speed_rpm) {
    b.upper_weight = (op.speed_rpm - below->op.speed_rpm) / (above->op.speed_rpm - below->op.speed_rpm);
    b.interp_cases = case_name(below->state, below->op) + " + " + case_name(above->state, above->op);
    b.interp_log_psd = mix(moved_log(*below), moved_log(*above), b.upper_weight);
    b.interp_env_power = mix(moved_env(*below), moved_env(*above), b.upper_weight);
    b.fixed_log_psd = mix(below->log_psd, above->log_psd, b.upper_weight);
    b.fixed_env_power = mix(below->env_power, above->env_power, b.upper_weight);
    b.sources = {source(*below, 1.0 - b.upper_weight), source(*above, b.upper_weight)};
  } else {  // no bracket (outside the trained range, or one case): clamped to the nearest
    b.interp_cases = b.nearest_case;
    b.interp_log_psd = b.nearest_log_psd;
    b.interp_env_power = b.nearest_env_power;
    b.fixed_log_psd = nearest->log_psd;
    b.fixed_env_power = nearest->env_power;
    b.sources = {source(*nearest, 1.0)};
  }
  return b;
}

std::vector<TransportSource> all_sources(const std::vector<ReferenceSpectra>& refs, BearingState state, const OperatingPoint& op,
                                         const std::vector<double>& psd_hz, const std::vector<double>& env_hz,
                                         const std::vector<double>& scales, int halfwidth_bins, const OperatingPoint& exclude) {
  std::vector<TransportSource> out;
  for (const auto& r : refs) {
    if (r.state != state || same_point(r.op, exclude)) continue;
    TransportSource t;
    t.case_name = case_name(r.state, r.op);
    t.speed_rpm = r.op.speed_rpm;
    t.moved_log_psd = transport_log_psd(r.log_psd, psd_hz, op.speed_rpm / r.op.speed_rpm, scales, halfwidth_bins);
    t.moved_env_power = transport_env(r.env_power, env_hz, op.speed_rpm / r.op.speed_rpm, scales);
    t.log_psd = r.log_psd;
    t.env_power = r.env_power;
    out.push_back(std::move(t));
  }
  return out;
}

}  // namespace amb::host::hybrid
