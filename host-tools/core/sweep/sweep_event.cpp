#include "host-tools/core/sweep/sweep_event.hpp"

#include "firmware/events/event_codec.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <vector>

namespace amb::host::sweep {

SweepRecord to_sweep_record(const fw::SweepEvent& e) {
  SweepRecord r;
  r.board_name = e.meta.board_name;
  r.rig_name = e.meta.rig_name;
  r.rate_hz = e.meta.rate_hz;
  r.speed_hz = e.speed_hz;
  r.bias_current_a = e.bias_current_a;
  r.loop_delay_periods = e.loop_delay_periods;
  r.injection = e.injection == 0 ? InjectionPoint::controller_output : InjectionPoint::sensor;
  ExcitationPlan& p = r.plan;
  p.kind = e.excitation == 0 ? ExcitationKind::multisine : ExcitationKind::stepped_sine;
  p.samples_per_period = e.samples_per_period;
  p.settle_periods = e.settle_periods;
  p.recorded_periods = e.recorded_periods;
  p.amplitude_a = e.amplitude_a;
  p.crest_factor = e.crest_factor;
  const double df = e.samples_per_period > 0 ? e.meta.rate_hz / static_cast<double>(e.samples_per_period) : 0.0;
  for (uint32_t k : e.bins) p.frequencies_hz.push_back(static_cast<double>(k) * df);
  auto widen = [](const std::vector<float>& v) { return std::vector<double>(v.begin(), v.end()); };
  for (const fw::SweepAxisData& a : e.axes) {
    SweepAxisRecord x;
    x.axis = a.axis;
    x.excitation_a = widen(a.excitation_a);
    x.controller_output_a = widen(a.controller_output_a);
    x.summing_point_a = widen(a.summing_point_a);
    x.sensor_m = widen(a.sensor_m);
    r.axes.push_back(std::move(x));
  }
  r.aborted = e.aborted;
  r.abort_reason = e.aborted ? fw::to_string(e.abort_reason) : "";
  return r;
}

bool decode_sweep_record(std::span<const uint8_t> bytes, SweepRecord& out, std::string& error) {
  fw::SweepEvent e;
  std::string why;
  if (!fw::decode_sweep_event(bytes, e, why)) {
    error = "sweep event: " + why;
    return false;
  }
  if (!(e.meta.rate_hz > 0.0) || !std::isfinite(e.meta.rate_hz)) {
    error = "sweep event: loop rate " + std::to_string(e.meta.rate_hz) + " Hz is not a positive number";
    return false;
  }
  out = to_sweep_record(e);
  return true;
}

bool is_sweep_event_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::vector<uint8_t> head(16);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  fw::EventKind kind = fw::EventKind::drop;
  uint16_t version = 0;
  std::string error;
  return fw::peek_event_kind(head, kind, version, error) && kind == fw::EventKind::sweep;
}

SweepRecord read_sweep_event_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot be read");
  const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  SweepRecord r;
  std::string err;
  if (!decode_sweep_record(bytes, r, err)) throw std::invalid_argument(path + ": " + err);
  return r;
}

}  // namespace amb::host::sweep
