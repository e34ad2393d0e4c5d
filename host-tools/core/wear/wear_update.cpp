#include "host-tools/core/wear/wear_update.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>

namespace amb::host::wear {

std::string WearOptions::check() const {
  if (!(friction_energy_budget_j > 0.0)) return "friction_energy_budget_j must be > 0";
  return {};
}

std::string life_model_name(const WearOptions& o) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "friction-energy budget (Archard) %.0f J", o.friction_energy_budget_j);
  return buf;
}

fw::WearRecord update_wear_record(const fw::WearRecord& previous, const WearEvent& event, const std::string& board_name,
                                  std::int64_t now_unix_s, const WearOptions& o) {
  if (const std::string e = o.check(); !e.empty()) throw std::invalid_argument("wear options: " + e);
  if (!previous.board_name.empty() && previous.board_name != board_name)
    throw std::invalid_argument("wear record belongs to board '" + previous.board_name + "', not '" + board_name + "'");
  fw::WearRecord r = previous;
  r.sequence = previous.sequence + 1;
  r.board_name = board_name.substr(0, 31);
  r.life_model = life_model_name(o).substr(0, 63);
  r.event_count = previous.event_count + 1;
  r.last_friction_coefficient = static_cast<float>(event.friction_coefficient);
  r.updated_unix_s = now_unix_s;
  for (size_t b = 0; b < 2; ++b) {
    auto& w = r.bearing[b];
    const auto& e = event.load[b];
    for (size_t k = 0; k < static_cast<size_t>(fw::k_load_bins); ++k) {
      w.event_load_n[k] = static_cast<float>(e.load_n[k]);
      w.cumulative_load_n[k] += static_cast<float>(e.load_n[k]);
    }
    w.swing_s += static_cast<float>(event.rubbing[b].swing_s);
    w.forward_rub_s += static_cast<float>(event.rubbing[b].forward_s);
    w.backward_rub_s += static_cast<float>(event.rubbing[b].backward_s);
    w.friction_energy_j += static_cast<float>(e.friction_energy_j);
    w.peak_force_n = std::max(w.peak_force_n, static_cast<float>(e.peak_force_n));
    w.life_used_fraction = static_cast<float>(static_cast<double>(w.friction_energy_j) / o.friction_energy_budget_j);
  }
  return r;
}

WearAccounting account_drop(const fw::WearRecord& previous, const std::vector<model::drop::StepContact>& contact_steps,
                            const std::array<model::drop::RubbingDurations, 2>& rubbing, double friction_coefficient,
                            const std::string& board_name, std::int64_t now_unix_s, const WearOptions& o) {
  WearAccounting a;
  a.event.load = event_load(contact_steps);
  a.event.rubbing = rubbing;
  a.event.friction_coefficient = friction_coefficient;
  a.record = update_wear_record(previous, a.event, board_name, now_unix_s, o);
  return a;
}

std::int64_t wall_clock_unix_s() {
  return std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace amb::host::wear
