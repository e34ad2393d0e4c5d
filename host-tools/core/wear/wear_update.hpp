#pragma once
// Phase D/E bookkeeping: fold one fitted drop event into the board's wear record
// (firmware/wear/wear_record.hpp, format AMBW v1, unchanged).
//
// Life model: friction-energy budget (Archard). Touchdown bearings fail by surface wear
// and heating of the inner ring and collar during rubbing, not by rolling-contact fatigue
// (a few hundred drops, not 1e6 revolutions under a steady load), and Archard's law makes
// the worn volume proportional to the friction work: V = k W_f / H. The consumed life is
// therefore the cumulative friction energy over a per-bearing budget,
//   life_used_fraction = sum_events W_f / budget_j,
// and the load map says where on the circumference it goes. The budget is a parameter to
// calibrate against the bearing maker's permitted drops (the default is an assumption: no
// seed paper gives one).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "firmware/wear/wear_record.hpp"
#include "host-tools/core/wear/load_map.hpp"
#include "model/drop/rubbing_states.hpp"

namespace amb::host::wear {

struct WearOptions {
  double friction_energy_budget_j = 20000.0;  ///< friction work one aux bearing may take, J (assumed)
  std::string check() const;                  ///< empty when usable
};

/// One accounted event.
struct WearEvent {
  std::array<BearingEventLoad, 2> load;                        ///< event_load() of the fitted simulation
  std::array<model::drop::RubbingDurations, 2> rubbing{};      ///< per bearing, s
  double friction_coefficient = 0.0;                           ///< from the fit
};

/// The life model's name as stored in the record.
std::string life_model_name(const WearOptions& o);

/// `previous` with `event` added: sequence + 1, event_count + 1, event load replaced,
/// cumulative load / durations / energy summed, peak force max, life fraction recomputed.
/// `board_name` must match a non-empty previous board name (else std::invalid_argument).
fw::WearRecord update_wear_record(const fw::WearRecord& previous, const WearEvent& event, const std::string& board_name,
                                  std::int64_t now_unix_s, const WearOptions& o);

/// One drop accounted: the event and the record it made.
struct WearAccounting {
  WearEvent event;        ///< load maps, rubbing and friction of the drop
  fw::WearRecord record;  ///< `previous` with the event added
};

/// The one path from a simulated drop (a fit's trace, or an envelope case's) to the wear
/// record: the load maps from `contact_steps` (event_load), then update_wear_record.
/// `rubbing`: per bearing, s (zeros when not classified); `friction_coefficient`: the drop's, 1.
/// Throws std::invalid_argument as update_wear_record.
WearAccounting account_drop(const fw::WearRecord& previous, const std::vector<model::drop::StepContact>& contact_steps,
                            const std::array<model::drop::RubbingDurations, 2>& rubbing, double friction_coefficient,
                            const std::string& board_name, std::int64_t now_unix_s, const WearOptions& o);

/// The host's wall clock as stored in updated_unix_s, s since 1970.
std::int64_t wall_clock_unix_s();

}  // namespace amb::host::wear
