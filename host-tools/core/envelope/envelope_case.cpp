#include "host-tools/core/envelope/envelope_case.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "host-tools/core/fit/drop_cost.hpp"
#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/wear/load_map.hpp"
#include "host-tools/core/wear/wear_update.hpp"
#include "model/drop/drop_simulation.hpp"
#include "model/drop/rubbing_states.hpp"

namespace amb::host::envelope {
namespace {

namespace md = amb::model::drop;

md::ContactLawChoice law_choice(const std::string& s) {
  if (s == "rigid") return md::ContactLawChoice::rigid;
  if (s == "hertz") return md::ContactLawChoice::hertz;
  if (s == "linear") return md::ContactLawChoice::linear;
  return md::ContactLawChoice::board;
}

template <typename T>
T field(const nlohmann::json& j, const char* k) {
  if (!j.contains(k)) throw std::invalid_argument(std::string("case file: missing '") + k + "'");
  try {
    return j.at(k).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw std::invalid_argument(std::string("case file: '") + k + "' has the wrong type");
  }
}

}  // namespace

int whirl_rank(const std::string& w) {
  if (w == "backward") return 3;
  if (w == "forward") return 2;
  if (w == "bouncing") return 1;
  return 0;
}

std::string CaseResult::whirl_worst() const { return whirl_rank(whirl[1]) > whirl_rank(whirl[0]) ? whirl[1] : whirl[0]; }

std::string case_key(const StudySettings& s, const CaseParams& c) {
  // Version tag first: a change of what a case computes must change every hash.
  return "envelope-case/1;board=" + s.board + ";law=" + s.contact_law + ";settle_s=" + io::exact_text(s.settle_s) +
         ";window_s=" + io::exact_text(s.window_s) + ";rate_hz=" + io::exact_text(s.sample_rate_hz) + ";step_s=" + io::exact_text(s.step_s) +
         ";budget_j=" + io::exact_text(s.friction_energy_budget_j) + ";speed_hz=" + io::exact_text(c.speed_hz) + ";friction=" + io::exact_text(c.friction) +
         ";unbalance_factor=" + io::exact_text(c.unbalance_factor) + ";clearance_m=" + io::exact_text(c.clearance_m) +
         ";offset_x_m=" + io::exact_text(c.offset_x_m) + ";offset_y_m=" + io::exact_text(c.offset_y_m) +
         ";failed=" + channels_name(c.failed_channels);
}

std::string case_hash(const StudySettings& s, const CaseParams& c) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char ch : case_key(s, c)) {
    h ^= ch;
    h *= 0x100000001b3ull;
  }
  char b[17];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h));
  return b;
}

CaseResult run_case(const board::BoardConfig& board, const StudySettings& s, const CaseParams& c) {
  return run_case(board, model::RigModel::make(board.plant), s, c);
}

CaseResult run_case(const board::BoardConfig& board, const std::shared_ptr<const model::RigModel>& rig_model,
                    const StudySettings& s, const CaseParams& c) {
  const auto t0 = std::chrono::steady_clock::now();
  model::PlantParams rig = board.plant;
  for (auto& disk : rig.rotor.disks) disk.unbalance_kg_m *= c.unbalance_factor;
  for (auto& a : rig.aux) {
    if (c.clearance_m > 0.0) a.clearance_m = c.clearance_m;
    a.friction_coefficient = c.friction;
    a.centre_offset_x_m = c.offset_x_m;
    a.centre_offset_y_m = c.offset_y_m;
    if (std::hypot(a.centre_offset_x_m, a.centre_offset_y_m) >= a.clearance_m)
      throw std::invalid_argument("centre offset (" + io::exact_text(c.offset_x_m) + ", " + io::exact_text(c.offset_y_m) + ") m reaches the clearance " +
                                  io::exact_text(a.clearance_m) + " m");
  }
  md::DropOptions mo;
  mo.step_s = s.step_s;
  mo.contact_law = law_choice(s.contact_law);
  mo.internal_controller = true;
  mo.sensor_noise = false;
  if (const std::string e = mo.check(); !e.empty()) throw std::invalid_argument("drop options: " + e);
  md::DropModel model(rig_model, rig, board.controller, board.rate_hz, mo);

  md::DropScenario sc;
  sc.speed_hz = c.speed_hz;
  sc.settle_s = s.settle_s;
  sc.pre_trigger_s = 0.0;
  sc.window_s = s.window_s;
  sc.sample_rate_hz = s.sample_rate_hz;
  // All channels cut: the amplifiers are switched off (the classic drop). Some channels:
  // those amplifier outputs fail (factor 0) while the controller keeps the others.
  sc.amplifiers_off = (c.failed_channels & k_all_channels) == k_all_channels;
  if (!sc.amplifiers_off)
    for (int i = 0; i < 4; ++i)
      if (c.failed_channels & (1u << i)) sc.faults.current_factor[static_cast<size_t>(i)] = 0.0;
  const md::DropTrace trace = md::simulate_drop(model, sc, true);

  CaseResult r;
  wear::WearOptions wo;
  wo.friction_energy_budget_j = s.friction_energy_budget_j;
  // The life fraction of this one drop, computed by the wear record's own update.
  const wear::WearAccounting acc = wear::account_drop(fw::WearRecord{}, trace.contact_steps, {}, c.friction, board.name, 0, wo);
  const auto& load = acc.event.load;
  const fw::WearRecord& one = acc.record;

  const double period = trace.sample_period_s;
  const double spin_sign = c.speed_hz >= 0.0 ? 1.0 : -1.0;
  for (size_t b = 0; b < 2; ++b) {
    std::vector<double> x, y;
    x.reserve(trace.samples.size());
    y.reserve(trace.samples.size());
    for (size_t i = static_cast<size_t>(trace.trigger_index); i < trace.samples.size(); ++i) {
      x.push_back(trace.samples[i].aux_x_m[b] - rig.aux[b].centre_offset_x_m);
      y.push_back(trace.samples[i].aux_y_m[b] - rig.aux[b].centre_offset_y_m);
    }
    const auto rub = md::classify_rubbing(x, y, period, rig.aux[b].clearance_m, spin_sign, 0, md::RubbingOptions{});
    const auto w = fit::whirl_summary(rub, period, spin_sign);
    r.peak_force_n[b] = load[b].peak_force_n;
    r.friction_energy_j[b] = load[b].friction_energy_j;
    r.contact_time_s[b] = load[b].contact_time_s;
    r.life_fraction[b] = static_cast<double>(one.bearing[b].life_used_fraction);
    r.whirl[b] = w.direction;
    r.whirl_hz[b] = w.frequency_hz;
  }
  r.speed_end_hz = trace.samples.empty() ? 0.0 : trace.samples.back().spin_rad_s / (2.0 * M_PI);
  r.solver_unconverged = trace.counters.solver_unconverged;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

nlohmann::json params_json(const CaseParams& c) {
  return {{"speed_hz", c.speed_hz},       {"friction", c.friction},     {"unbalance_factor", c.unbalance_factor},
          {"clearance_m", c.clearance_m}, {"offset_x_m", c.offset_x_m}, {"offset_y_m", c.offset_y_m},
          {"failed_channels", channels_name(c.failed_channels)}};
}

nlohmann::json to_case_json(const StudySettings& s, const CaseParams& c, const CaseResult& r) {
  return {{"key", case_key(s, c)},
          {"hash", case_hash(s, c)},
          {"parameters", params_json(c)},
          {"result",
           {{"peak_force_n", r.peak_force_n},
            {"whirl", r.whirl},
            {"whirl_hz", r.whirl_hz},
            {"friction_energy_j", r.friction_energy_j},
            {"life_fraction", r.life_fraction},
            {"contact_time_s", r.contact_time_s},
            {"speed_end_hz", r.speed_end_hz},
            {"solver_unconverged", r.solver_unconverged},
            {"wall_s", r.wall_s}}}};
}

CaseResult from_case_json(const nlohmann::json& j) {
  if (!j.is_object() || !j.contains("result") || !j["result"].is_object())
    throw std::invalid_argument("case file: missing 'result'");
  const nlohmann::json& x = j["result"];
  CaseResult r;
  r.peak_force_n = field<std::array<double, 2>>(x, "peak_force_n");
  r.whirl = field<std::array<std::string, 2>>(x, "whirl");
  r.whirl_hz = field<std::array<double, 2>>(x, "whirl_hz");
  r.friction_energy_j = field<std::array<double, 2>>(x, "friction_energy_j");
  r.life_fraction = field<std::array<double, 2>>(x, "life_fraction");
  r.contact_time_s = field<std::array<double, 2>>(x, "contact_time_s");
  r.speed_end_hz = field<double>(x, "speed_end_hz");
  r.solver_unconverged = field<std::uint64_t>(x, "solver_unconverged");
  r.wall_s = field<double>(x, "wall_s");
  return r;
}

}  // namespace amb::host::envelope
