#include "tests/support/firmware_control_law.hpp"
#include "tests/sweep_analysis/sweep_sil.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "firmware/control/axis_transform.hpp"
#include "firmware/control/pid_axis.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "hal/sim/sim_rig.hpp"
#include "host-tools/core/sweep/sweep_model.hpp"
#include "model/effects/effect_plant.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::test {

std::vector<double> multisine(int n, const std::vector<int>& bins, double amplitude_a, double& crest) {
  std::vector<double> x(static_cast<size_t>(n), 0.0);
  const double l = static_cast<double>(bins.size());
  for (size_t i = 0; i < bins.size(); ++i) {
    const double ph = -M_PI * static_cast<double>(i) * static_cast<double>(i + 1) / l;  // Schroeder
    for (int k = 0; k < n; ++k) x[static_cast<size_t>(k)] += std::cos(2.0 * M_PI * bins[i] * k / n + ph);
  }
  double peak = 0.0, ss = 0.0;
  for (double v : x) {
    peak = std::max(peak, std::abs(v));
    ss += v * v;
  }
  crest = peak / std::sqrt(ss / n);
  for (double& v : x) v *= amplitude_a / peak;
  return x;
}

host::sweep::SweepRecord run_sil_sweep(const board::BoardConfig& b, const SilSweepOptions& o) {
  board::BoardConfig truth = b;
  model::effects::apply_to_params(o.effects, truth.plant);
  for (auto& s : truth.plant.sensor) s.noise_rms_m *= o.noise_scale;
  model::RotorAmbPlant::Options po;
  po.noise_seed = o.seed;
  auto plant = std::make_unique<model::effects::EffectPlant>(sil::make_board_plant(truth, po), truth.plant, o.effects);
  plant->reset(true, 0.0);
  hal::sim::SimRig rig(std::move(plant));
  const int64_t period_ns = std::llround(1e9 / b.rate_hz);
  rig.set_demand_delay_ns(std::llround(b.loop_delay_periods * period_ns));
  // The firmware's controller, configured from the board (not from the simulated truth).
  const auto& bp = b.plant;
  test::FirmwareControlLaw law(b, bp);
  {
    // The y integrators start at each plane's weight share (rigid-rotor lever rule), as the
    // firmware's supervisor does at lift-off.
    const model::rotor::RotorModel rotor = model::rotor::build_rotor_model(bp.rotor);
    const double w = rotor.mass_kg * bp.gravity_m_s2;
    const double a = bp.amb[0].axial_m, c = bp.amb[1].axial_m;
    const double share_b = (c != a) ? w * (rotor.centre_of_mass_m - a) / (c - a) : 0.5 * w;
    law.pid(1).preload_force(w - share_b);
    law.pid(3).preload_force(share_b);
  }
  const int n = o.samples_per_period;
  std::vector<int> bins;
  for (int i = 0; i < o.lines; ++i) {
    const double f = o.f_lo_hz * std::pow(o.f_hi_hz / o.f_lo_hz, o.lines > 1 ? i / (o.lines - 1.0) : 0.0);
    const int k = std::max(1, static_cast<int>(std::lround(f * n / b.rate_hz)));
    if (bins.empty() || k > bins.back()) bins.push_back(k);
  }
  host::sweep::SweepRecord r;
  r.board_name = b.name;
  r.rig_name = b.name;
  r.rate_hz = b.rate_hz;
  r.bias_current_a = bp.amb[0].bias_current_a;
  r.loop_delay_periods = b.loop_delay_periods;
  auto& pl = r.plan;
  pl.kind = o.stepped ? host::sweep::ExcitationKind::stepped_sine : host::sweep::ExcitationKind::multisine;
  for (int k : bins) pl.frequencies_hz.push_back(k * b.rate_hz / n);
  pl.samples_per_period = static_cast<uint32_t>(n);
  pl.settle_periods = static_cast<uint32_t>(o.settle_periods);
  pl.recorded_periods = static_cast<uint32_t>(o.recorded_periods);
  pl.amplitude_a = o.amplitude_fraction * r.bias_current_a;
  // The excitation of one axis: blocks of (settle + recorded) periods, one block per step
  // (multisine: one block).
  std::vector<std::vector<double>> blocks;
  if (o.stepped) {
    for (int k : bins) {
      double cf = 0.0;
      blocks.push_back(multisine(n, {k}, pl.amplitude_a, cf));
      pl.crest_factor = cf;
    }
  } else {
    blocks.push_back(multisine(n, bins, pl.amplitude_a, pl.crest_factor));
  }
  const double clearance = std::min(bp.aux[0].clearance_m, bp.aux[1].clearance_m);
  int64_t k_abs = 0;
  auto step = [&](int axis, double e, host::sweep::SweepAxisRecord* rec) {
    hal::AnalogInputs in;
    rig.analog().read(in);
    hal::AnalogOutputs out{};
    out.amplifiers_enabled = true;
    out.current_demand_a = law.demands_a(in.displacement_m);
    for (double v : in.displacement_m)
      if (std::abs(v) > 0.5 * clearance) throw std::runtime_error("sil sweep: the rotor left the levitated range");
    if (axis >= 0) {
      const double uc = out.current_demand_a[static_cast<size_t>(axis)];
      out.current_demand_a[static_cast<size_t>(axis)] = uc + e;
      if (rec) {
        rec->excitation_a.push_back(e);
        rec->controller_output_a.push_back(uc);
        rec->summing_point_a.push_back(uc + e);
        rec->sensor_m.push_back(host::sweep::axis_position<double>(
            bp, axis, {in.displacement_m[0], in.displacement_m[1], in.displacement_m[2], in.displacement_m[3]}));
      }
    }
    rig.analog().write(out);
    rig.clock().wait_until_ns(++k_abs * period_ns);
  };
  for (int k = 0; k < static_cast<int>(0.5 * b.rate_hz); ++k) step(-1, 0.0, nullptr);
  for (int axis : o.axes) {
    host::sweep::SweepAxisRecord rec;
    rec.axis = axis;
    for (const auto& blk : blocks) {
      for (int q = 0; q < o.settle_periods; ++q)
        for (int i = 0; i < n; ++i) step(axis, blk[static_cast<size_t>(i)], nullptr);
      for (int q = 0; q < o.recorded_periods; ++q)
        for (int i = 0; i < n; ++i) step(axis, blk[static_cast<size_t>(i)], &rec);
    }
    r.axes.push_back(std::move(rec));
  }
  return r;
}

}  // namespace amb::test
