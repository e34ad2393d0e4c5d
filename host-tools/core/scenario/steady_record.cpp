#include "host-tools/core/scenario/steady_record.hpp"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include "firmware/sil/sil_rig.hpp"
#include "host-tools/core/events/measured_event.hpp"
#include "model/effects/effect_plant.hpp"

namespace amb::host {
namespace {

class Collector final : public fw::SampleSink {
 public:
  void on_sample(const fw::LoopSample& s) override { samples.push_back(s); }
  std::vector<fw::LoopSample> samples;
};

}  // namespace

std::string generate_steady_record(const std::string& dir, const std::string& stem,
                                   const model::effects::EffectSet& effects, const SteadyRecordOptions& o) {
  board::BoardConfig b = board::load_board(o.board);
  // The generator's rig: the board's, changed by the effect; the firmware keeps the board.
  board::BoardConfig truth = b;
  model::effects::apply_to_params(effects, truth.plant);
  for (auto& disk : truth.plant.rotor.disks) disk.unbalance_kg_m *= o.unbalance_scale;
  for (auto& a : truth.plant.aux) {
    if (o.friction_coefficient >= 0.0) a.friction_coefficient = o.friction_coefficient;
    a.ring_inertia_kg_m2 *= o.ring_inertia_scale;
  }
  for (auto& a : truth.plant.amb) a.amplifier_bandwidth_hz *= o.amplifier_bandwidth_scale;
  if (o.rigid_rotor) truth.plant.rotor.modes_kept = 2;  // per lateral plane: the two rigid-body modes
  model::RotorAmbPlant::Options po;
  po.noise_seed = o.seed;
  po.contact_exponent = o.contact_exponent;
  auto plant = std::make_unique<model::effects::EffectPlant>(sil::make_board_plant(truth, po), truth.plant, effects);
  b.lifecycle.spin_accel_hz_per_s = o.spin_accel_hz_per_s;
  if (o.speed_hz > 0.0) b.lifecycle.operating_speed_hz = o.speed_hz;
  if (o.settle_tolerance_m > 0.0) b.lifecycle.settle_tolerance_m = std::min(o.settle_tolerance_m, b.lifecycle.max_orbit_fault_m);
  sil::SilOptions so;
  so.noise_seed = o.seed;
  so.tachometer = o.tachometer;
  sil::SilRig rig(b, std::move(plant), so);
  Collector sink;
  sink.samples.reserve(static_cast<size_t>((o.rest_s + o.steady_s + 3.0) * b.rate_hz));
  rig.set_sink(&sink);
  fw::Supervisor& sup = rig.supervisor();
  rig.run_for(o.rest_s);
  sup.post(fw::Command::levitate);
  auto at = [](fw::Phase p) { return [p](const fw::Status& s) { return s.phase == p || s.state == fw::State::fault; }; };
  if (!rig.run_until(at(fw::Phase::levitated), 5.0) || sup.state() == fw::State::fault)
    throw std::runtime_error("generator: no lift-off for " + stem + " (state " + fw::to_string(sup.state()) + ", phase " +
                             fw::to_string(sup.status().phase) + ", fault " + fw::to_string(sup.status().fault) +
                             ", orbit radius " + std::to_string(sup.status().orbit_radius_m[0] * 1e6) + " / " +
                             std::to_string(sup.status().orbit_radius_m[1] * 1e6) + " um against the settle tolerance " +
                             std::to_string(b.lifecycle.settle_tolerance_m * 1e6) + " um; rotor speed " +
                             std::to_string(rig.plant().outputs().spin_speed_hz) + " Hz)");
  sup.post(fw::Command::run);
  if (!rig.run_until(at(fw::Phase::at_speed), 10.0) || sup.state() == fw::State::fault)
    throw std::runtime_error("generator: did not reach speed for " + stem);
  rig.run_for(o.settle_s + o.steady_s);
  if (sup.state() == fw::State::fault) throw std::runtime_error("generator: fault while steady for " + stem);
  size_t first = 0, trigger = 0;
  if (o.drop_s > 0) {
    trigger = sink.samples.size();
    const auto keep = static_cast<size_t>(o.steady_s * b.rate_hz);
    first = trigger > keep ? trigger - keep : 0;
    model::PlantFaults cut;
    cut.current_factor = {0.0, 0.0, 0.0, 0.0};
    rig.plant().set_faults(cut);
    rig.run_for(o.drop_s);
  }
  rig.set_sink(nullptr);

  MeasuredEventOut r;
  r.rig = o.board;
  r.sample_rate_hz = b.rate_hz;
  r.trigger_index = trigger - first;
  r.notes = o.drop_s > 0 ? "generated drop event (all amplifier channels cut at the trigger)" : "generated steady-state run";
  const size_t rows = sink.samples.size() > first ? sink.samples.size() - first : 0;
  std::vector<std::vector<double>> v(10, std::vector<double>(rows));
  const int64_t t0 = sink.samples.size() > first ? sink.samples[first].t_ns : 0;
  for (size_t i = first; i < sink.samples.size(); ++i) {
    const auto& s = sink.samples[i];
    v[0][i - first] = static_cast<double>(s.t_ns - t0) * 1e-9;
    for (size_t k = 0; k < 4; ++k) v[1 + k][i - first] = s.displacement_m[k];
    for (size_t j = 0; j < 4; ++j) v[5 + j][i - first] = s.coil_current_a[j];
    v[9][i - first] = s.speed_hz;
  }
  r.columns.push_back({"t_s", "time", "s", false, 0.0, 0.0, &v[0], true});
  const char* dn[4] = {"xa1", "xa2", "xb1", "xb2"};
  const char* in[4] = {"ia1", "ia2", "ib1", "ib2"};
  for (size_t k = 0; k < 4; ++k)
    r.columns.push_back({dn[k], "displacement", "m", true, b.plant.sensor[k].axial_m, b.plant.sensor[k].angle_deg, &v[1 + k], true});
  for (size_t j = 0; j < 4; ++j)
    r.columns.push_back({in[j], "current", "A", true, b.plant.amb[j / 2].axial_m, b.plant.amb[j / 2].actuator_angle_deg[j % 2], &v[5 + j], true});
  r.columns.push_back({"n", "speed", "Hz", false, 0.0, 0.0, &v[9], true});
  std::filesystem::create_directories(dir);
  const std::string path = (std::filesystem::path(dir) / (stem + ".json")).string();
  write_measured_event((std::filesystem::path(dir) / stem).string(), r);
  return path;
}

}  // namespace amb::host
