#include "host-tools/core/replay/replay_compare.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace amb::host::replay {

namespace {
constexpr int k_channels = 10;
const char* const k_names[k_channels] = {"current_demand_a[0]", "current_demand_a[1]", "current_demand_a[2]",
                                         "current_demand_a[3]", "speed_command_hz",    "state",
                                         "phase",               "fault",               "flags",
                                         "t_ns"};

int64_t ulp_distance(float a, float b) {
  // Map the float bit patterns onto a monotonic integer line.
  auto key = [](float f) {
    const auto u = std::bit_cast<int32_t>(f);
    return u < 0 ? static_cast<int64_t>(std::numeric_limits<int32_t>::min()) - u : static_cast<int64_t>(u);
  };
  return std::llabs(key(a) - key(b));
}

bool same_bits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

/// Fill `d` for channel `c` if it differs; returns true when it differs.
bool differs(const fw::LoopSample& r, const fw::LoopSample& p, int c, SampleDifference& d) {
  auto set = [&](double rv, double pv, double diff, int64_t ulps) {
    d.recorded = rv;
    d.replayed = pv;
    d.difference = diff;
    d.ulps = ulps;
    d.channel = k_names[c];
    return true;
  };
  if (c < 4) {
    const float a = r.current_demand_a[static_cast<size_t>(c)], b = p.current_demand_a[static_cast<size_t>(c)];
    return !same_bits(a, b) && set(a, b, static_cast<double>(b) - a, ulp_distance(a, b));
  }
  switch (c) {
    case 4:
      return !same_bits(r.speed_command_hz, p.speed_command_hz) &&
             set(r.speed_command_hz, p.speed_command_hz, static_cast<double>(p.speed_command_hz) - r.speed_command_hz,
                 ulp_distance(r.speed_command_hz, p.speed_command_hz));
    case 5: return r.state != p.state && set(r.state, p.state, p.state - r.state, 0);
    case 6: return r.phase != p.phase && set(r.phase, p.phase, p.phase - r.phase, 0);
    case 7: return r.fault != p.fault && set(r.fault, p.fault, p.fault - r.fault, 0);
    case 8: return r.flags != p.flags && set(r.flags, p.flags, r.flags ^ p.flags, 0);
    case 9:
      return r.t_ns != p.t_ns &&
             set(static_cast<double>(r.t_ns), static_cast<double>(p.t_ns), static_cast<double>(p.t_ns - r.t_ns), 0);
    default: return false;
  }
}
}  // namespace

ReplayComparison compare_samples(std::span<const fw::LoopSample> recorded, std::span<const fw::LoopSample> replayed,
                                 size_t compare_from, size_t trigger_index, size_t max_listed) {
  ReplayComparison c;
  c.compare_from = compare_from;
  c.channels.resize(k_channels);
  for (int k = 0; k < k_channels; ++k) c.channels[static_cast<size_t>(k)].channel = k_names[k];
  const size_t n = std::min(recorded.size(), replayed.size());
  const double period_s = n > 1 ? static_cast<double>(recorded[n - 1].t_ns - recorded[0].t_ns) * 1e-9 / static_cast<double>(n - 1) : 0.0;
  SampleDifference d;
  for (size_t i = 0; i < n; ++i) {
    const bool counted = compare_from != k_no_index && i >= compare_from;
    bool any = false;
    for (int k = 0; k < k_channels; ++k) {
      if (!differs(recorded[i], replayed[i], k, d)) continue;
      any = true;
      if (!counted) {
        if (k < 4) c.warm_up_max_demand_difference_a = std::max(c.warm_up_max_demand_difference_a, std::abs(d.difference));
        continue;
      }
      ChannelSummary& ch = c.channels[static_cast<size_t>(k)];
      ++ch.mismatches;
      if (ch.first_index == k_no_index) ch.first_index = i;
      if (k != 8) ch.max_abs_difference = std::max(ch.max_abs_difference, std::abs(d.difference));
      if (c.differences.size() < max_listed) {
        d.index = i;
        d.t_ns = recorded[i].t_ns;
        d.t_from_trigger_s = (static_cast<double>(i) - static_cast<double>(trigger_index)) * period_s;
        c.differences.push_back(d);
      }
    }
    if (counted) {
      ++c.compared_samples;
      if (any) ++c.mismatched_samples;
    } else {
      ++c.warm_up_samples;
      if (any) ++c.warm_up_differing_samples;
    }
  }
  // A length mismatch is a difference of every missing sample.
  if (recorded.size() != replayed.size() && compare_from != k_no_index) {
    c.mismatched_samples += std::max(recorded.size(), replayed.size()) - n;
  }
  c.bit_exact = c.compared_samples > 0 && c.mismatched_samples == 0;
  return c;
}

std::string format_comparison(const ReplayComparison& c) {
  std::string s;
  char buf[256];
  if (c.compare_from == k_no_index) {
    s += "  no sample compared bit for bit: the controller state is never provably reproduced in this window\n";
  } else {
    std::snprintf(buf, sizeof buf, "  compared bit for bit from sample %zu: %llu samples, %llu mismatched -> %s\n",
                  c.compare_from, static_cast<unsigned long long>(c.compared_samples),
                  static_cast<unsigned long long>(c.mismatched_samples), c.bit_exact ? "BIT-EXACT" : "DIFFERENT");
    s += buf;
  }
  if (c.warm_up_samples > 0) {
    std::snprintf(buf, sizeof buf, "  warm-up part (not counted): %llu samples, %llu differ, max |demand difference| %.3g A\n",
                  static_cast<unsigned long long>(c.warm_up_samples),
                  static_cast<unsigned long long>(c.warm_up_differing_samples), c.warm_up_max_demand_difference_a);
    s += buf;
  }
  for (const ChannelSummary& ch : c.channels) {
    if (ch.mismatches == 0) continue;
    std::snprintf(buf, sizeof buf, "  %-20s %llu mismatches, first at sample %zu, max |difference| %.6g\n",
                  ch.channel.c_str(), static_cast<unsigned long long>(ch.mismatches), ch.first_index, ch.max_abs_difference);
    s += buf;
  }
  for (const SampleDifference& d : c.differences) {
    std::snprintf(buf, sizeof buf, "    sample %zu (t %+.4f s from trigger) %-20s recorded %.9g replayed %.9g difference %.3g%s\n",
                  d.index, d.t_from_trigger_s, d.channel.c_str(), d.recorded, d.replayed, d.difference,
                  d.ulps ? (" (" + std::to_string(d.ulps) + " ulp)").c_str() : "");
    s += buf;
  }
  return s;
}

}  // namespace amb::host::replay
