#include "host-tools/core/fit/fit_result_json.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace amb::host::fit {
namespace {

using nlohmann::json;

// Reading: a key absent keeps the default; present, it must have the written type. A number
// written as null is a NaN or infinity (JSON has neither): read back as NaN.
[[noreturn]] void wrong(const std::string& key, const char* what) {
  throw std::invalid_argument("fit result: key '" + key + "': expected " + what);
}

void get(const json& j, const char* key, double& v) {
  if (!j.contains(key)) return;
  const json& x = j[key];
  if (x.is_null()) v = std::numeric_limits<double>::quiet_NaN();
  else if (x.is_number()) v = x.get<double>();
  else wrong(key, "a number");
}
void get(const json& j, const char* key, int& v) {
  if (!j.contains(key)) return;
  if (!j[key].is_number_integer()) wrong(key, "an integer");
  v = j[key].get<int>();
}
void get(const json& j, const char* key, bool& v) {
  if (!j.contains(key)) return;
  if (!j[key].is_boolean()) wrong(key, "true or false");
  v = j[key].get<bool>();
}
void get(const json& j, const char* key, std::string& v) {
  if (!j.contains(key)) return;
  if (!j[key].is_string()) wrong(key, "a string");
  v = j[key].get<std::string>();
}
void get(const json& j, const char* key, std::vector<double>& v) {
  if (!j.contains(key)) return;
  if (!j[key].is_array()) wrong(key, "an array");
  v.clear();
  for (const json& x : j[key]) {
    if (x.is_null()) v.push_back(std::numeric_limits<double>::quiet_NaN());
    else if (x.is_number()) v.push_back(x.get<double>());
    else wrong(key, "an array of numbers");
  }
}
/// An object (or array) member to descend into: nullptr when absent.
const json* member(const json& j, const char* key, bool array) {
  if (!j.contains(key)) return nullptr;
  const json& x = j[key];
  if (array ? !x.is_array() : !x.is_object()) wrong(key, array ? "an array" : "an object");
  return &x;
}
void get2(const json& j, const char* key, std::array<double, 2>& v) {
  const json* a = member(j, key, true);
  if (!a) return;
  if (a->size() != 2) wrong(key, "two numbers");
  for (size_t i = 0; i < 2; ++i) {
    if (!(*a)[i].is_number()) wrong(key, "two numbers");
    v[i] = (*a)[i].get<double>();
  }
}

json durations_json(const model::drop::RubbingDurations& d) {
  return {{"swing", d.swing_s}, {"forward", d.forward_s}, {"backward", d.backward_s}};
}
void read_durations(const json& j, model::drop::RubbingDurations& d) {
  get(j, "swing", d.swing_s);
  get(j, "forward", d.forward_s);
  get(j, "backward", d.backward_s);
}
json durations_pair_json(const std::array<model::drop::RubbingDurations, 2>& d) {
  return {durations_json(d[0]), durations_json(d[1])};
}
void read_durations_pair(const json& j, const char* key, std::array<model::drop::RubbingDurations, 2>& d) {
  const json* a = member(j, key, true);
  if (!a) return;
  if (a->size() != 2) wrong(key, "two objects");
  for (size_t b = 0; b < 2; ++b) {
    if (!(*a)[b].is_object()) wrong(key, "two objects");
    read_durations((*a)[b], d[b]);
  }
}

json cost_json(const CostBreakdown& c) {
  return {{"rubbing", c.rubbing}, {"orbit", c.orbit},     {"speed", c.speed}, {"spin_down", c.spin_down},
          {"contact", c.contact}, {"whirl", c.whirl}, {"bounce", c.bounce}};
}
void read_cost(const json& j, CostBreakdown& c) {
  get(j, "rubbing", c.rubbing);
  get(j, "orbit", c.orbit);
  get(j, "speed", c.speed);
  get(j, "spin_down", c.spin_down);
  get(j, "contact", c.contact);
  get(j, "whirl", c.whirl);
  get(j, "bounce", c.bounce);
}

json windows_json(const std::vector<FrictionWindow>& ws) {
  json a = json::array();
  for (const auto& w : ws)
    a.push_back({{"bearing", w.bearing}, {"start_s", w.start_s}, {"normal_impulse_n_s", w.normal_impulse_n_s},
                 {"friction_impulse_n_s", w.friction_impulse_n_s}, {"ratio", w.ratio}, {"sliding", w.sliding},
                 {"next_to_rolling", w.next_to_rolling}});
  return a;
}
void read_windows(const json& j, std::vector<FrictionWindow>& ws) {
  const json* a = member(j, "windows", true);
  if (!a) return;
  ws.clear();
  for (const json& x : *a) {
    if (!x.is_object()) wrong("windows", "an array of objects");
    FrictionWindow w;
    get(x, "bearing", w.bearing);
    get(x, "start_s", w.start_s);
    get(x, "normal_impulse_n_s", w.normal_impulse_n_s);
    get(x, "friction_impulse_n_s", w.friction_impulse_n_s);
    get(x, "ratio", w.ratio);
    get(x, "sliding", w.sliding);
    get(x, "next_to_rolling", w.next_to_rolling);
    ws.push_back(w);
  }
}

json rigid_bent_json(const std::array<double, 2>& v) { return {{"rigid", v[0]}, {"bent", v[1]}}; }
void read_rigid_bent(const json& j, const char* key, std::array<double, 2>& v) {
  const json* o = member(j, key, false);
  if (!o) return;
  get(*o, "rigid", v[0]);
  get(*o, "bent", v[1]);
}

json friction_estimate_json(const FrictionEstimate& fe) {
  return {{"valid", fe.valid},
          {"friction", fe.friction},
          {"uncertainty", fe.uncertainty},
          {"standard_error", fe.standard_error},
          {"smoothing_change", fe.smoothing_change},
          {"windows_used", fe.windows_used},
          {"windows_total", fe.windows_total},
          {"window_s", fe.window_s},
          {"sliding_time_s", fe.sliding_time_s},
          {"measured_spin_down_rad_s2", fe.measured_spin_down_rad_s2},
          {"force_spin_down_rad_s2", fe.force_spin_down_rad_s2},
          {"force_spin_down_scatter_rad_s2", fe.force_spin_down_scatter_rad_s2},
          {"synchronous_removed", fe.synchronous_removed},
          {"synchronous_force_n", fe.synchronous_force_n},
          {"synchronous_moment_n_m", fe.synchronous_moment_n_m},
          {"bending_modes", fe.bending_modes},
          {"rotor_choice", fe.rotor_choice},
          {"free_flight_samples", fe.free_flight_samples},
          {"free_flight_force_rms_n", rigid_bent_json(fe.free_flight_force_rms_n)},
          {"free_flight_noise_rms_n", rigid_bent_json(fe.free_flight_noise_rms_n)},
          {"note", fe.note},
          {"windows", windows_json(fe.windows)}};
}
void read_friction_estimate(const json& j, FrictionEstimate& fe) {
  get(j, "valid", fe.valid);
  get(j, "friction", fe.friction);
  get(j, "uncertainty", fe.uncertainty);
  get(j, "standard_error", fe.standard_error);
  get(j, "smoothing_change", fe.smoothing_change);
  get(j, "windows_used", fe.windows_used);
  get(j, "windows_total", fe.windows_total);
  get(j, "window_s", fe.window_s);
  get(j, "sliding_time_s", fe.sliding_time_s);
  get(j, "measured_spin_down_rad_s2", fe.measured_spin_down_rad_s2);
  get(j, "force_spin_down_rad_s2", fe.force_spin_down_rad_s2);
  get(j, "force_spin_down_scatter_rad_s2", fe.force_spin_down_scatter_rad_s2);
  get(j, "synchronous_removed", fe.synchronous_removed);
  get(j, "synchronous_force_n", fe.synchronous_force_n);
  get(j, "synchronous_moment_n_m", fe.synchronous_moment_n_m);
  get(j, "bending_modes", fe.bending_modes);
  get(j, "rotor_choice", fe.rotor_choice);
  get(j, "free_flight_samples", fe.free_flight_samples);
  read_rigid_bent(j, "free_flight_force_rms_n", fe.free_flight_force_rms_n);
  read_rigid_bent(j, "free_flight_noise_rms_n", fe.free_flight_noise_rms_n);
  get(j, "note", fe.note);
  read_windows(j, fe.windows);
}

json whirl_json(const std::array<WhirlSummary, 2>& w) {
  json list = json::array();
  for (const auto& x : w)
    list.push_back({{"direction", x.direction}, {"frequency_hz", x.frequency_hz}, {"onset_s", x.onset_s},
                    {"contact_share", x.contact_share}, {"whirl_rate_rad_s", x.whirl_rate_rad_s},
                    {"bounce_rate_per_s", x.bounce_rate_per_s}});
  return list;
}
void read_whirl(const json& j, const char* key, std::array<WhirlSummary, 2>& w) {
  const json* a = member(j, key, true);
  if (!a) return;
  if (a->size() != 2) wrong(key, "two objects");
  for (size_t b = 0; b < 2; ++b) {
    const json& x = (*a)[b];
    if (!x.is_object()) wrong(key, "two objects");
    get(x, "direction", w[b].direction);
    get(x, "frequency_hz", w[b].frequency_hz);
    get(x, "onset_s", w[b].onset_s);
    get(x, "contact_share", w[b].contact_share);
    get(x, "whirl_rate_rad_s", w[b].whirl_rate_rad_s);
    get(x, "bounce_rate_per_s", w[b].bounce_rate_per_s);
  }
}

json lock_in_json(const LockInFeatures& f) {
  return {{"valid", f.valid},
          {"own", f.own},
          {"start_s", f.start_s},
          {"speed_level_rad_s", f.speed_level_rad_s},
          {"spin_down_rad_s2", f.spin_down_rad_s2},
          {"whirling", {f.whirling[0], f.whirling[1]}},
          {"centripetal_m_s2", {f.centripetal_m_s2[0], f.centripetal_m_s2[1]}},
          {"penetration_m", {f.penetration_m[0], f.penetration_m[1]}}};
}
void read_lock_in(const json& j, const char* key, LockInFeatures& f) {
  const json* o = member(j, key, false);
  if (!o) return;
  get(*o, "valid", f.valid);
  get(*o, "own", f.own);
  get(*o, "start_s", f.start_s);
  get(*o, "speed_level_rad_s", f.speed_level_rad_s);
  get(*o, "spin_down_rad_s2", f.spin_down_rad_s2);
  if (const json* a = member(*o, "whirling", true)) {
    if (a->size() != 2 || !(*a)[0].is_boolean() || !(*a)[1].is_boolean()) wrong("whirling", "two booleans");
    f.whirling = {(*a)[0].get<bool>(), (*a)[1].get<bool>()};
  }
  get2(*o, "centripetal_m_s2", f.centripetal_m_s2);
  get2(*o, "penetration_m", f.penetration_m);
}

}  // namespace

json fit_result_json(const FitResultDocument& doc) {
  const DropFitResult& r = doc.result;
  json j;
  j["format"] = k_fit_result_format;
  if (!doc.board.empty()) j["board"] = doc.board;
  if (!doc.event.empty()) j["event"] = doc.event;
  j["friction_coefficient"] = r.friction_coefficient;
  j["rubbing_s"] = durations_json(r.rubbing[0]);  // bearing 1 alone: kept for readers of the first format
  j["rubbing_s_per_bearing"] = durations_pair_json(r.rubbing);
  j["measured_rubbing_s_per_bearing"] = durations_pair_json(r.measured_rubbing);
  j["cost"] = r.cost.total;
  j["cost_terms"] = cost_json(r.cost);
  j["friction_uncertainty"] = r.friction_uncertainty;
  j["friction_method"] = r.friction_method;
  j["friction_estimate"] = friction_estimate_json(r.friction_estimate);
  j["bound_active"] = r.bound_active;
  j["contact_law"] = r.contact_law;
  j["contact_stiffness_n_per_m"] = r.contact_stiffness_n_per_m;
  j["contact_damping_n_s_per_m"] = r.contact_damping_n_s_per_m;
  j["ring_drag_n_m"] = r.ring_drag_n_m;
  j["spin_down_rad_s2"] = r.spin_down_rad_s2;
  j["fitted_spin_down_rad_s2"] = r.fitted_spin_down_rad_s2;
  j["polish_evaluations"] = r.polish_evaluations;
  json unknowns = json::array();
  for (const auto& u : r.unknowns)
    unknowns.push_back({{"name", u.name}, {"value", u.value}, {"uncertainty", u.uncertainty}, {"lower", u.lower},
                        {"upper", u.upper}, {"bound_active", u.bound_active}});
  j["unknowns"] = unknowns;
  j["whirl"] = whirl_json(r.whirl);
  j["fitted_whirl"] = whirl_json(r.fitted_whirl);
  j["cost_lock_in"] = r.cost.lock_in;
  j["lock_in"] = lock_in_json(r.lock_in);
  j["fitted_lock_in"] = lock_in_json(r.fitted_lock_in);
  json trials = json::array();
  for (const auto& t : r.structure_trials)
    trials.push_back({{"modes_per_plane", t.modes_per_plane}, {"cost", t.cost}, {"converged", t.converged}, {"bound_active", t.bound_active}});
  j["rotor_structure"] = {{"modes_per_plane", r.rotor_modes_per_plane},
                          {"model", r.rotor_modes_per_plane == 2 ? "rigid" : "flexible"},
                          {"trials", trials}};
  j["evaluations"] = r.evaluations;
  j["wall_s"] = r.wall_s;
  j["converged"] = r.converged;
  j["stop_reason"] = r.stop_reason;
  j["restitution"] = r.restitution;
  j["centre_offset_m"] = {r.centre_offset_m[0], r.centre_offset_m[1]};
  j["cost_history"] = r.cost_history;
  if (!doc.wear_note.empty()) j["wear"] = doc.wear_note;
  return j;
}

bool is_fit_result_json(const json& j) {
  if (!j.is_object()) return false;
  if (j.contains("format")) return j["format"].is_string() && j["format"].get<std::string>() == k_fit_result_format;
  return j.contains("friction_coefficient") && j["friction_coefficient"].is_number() && !j.contains("effects_added");
}

FitResultDocument read_fit_result_json(const json& j) {
  if (!j.is_object()) throw std::invalid_argument("fit result: not a JSON object");
  if (j.contains("format") && !(j["format"].is_string() && j["format"].get<std::string>() == k_fit_result_format))
    throw std::invalid_argument("fit result: key 'format': expected \"" + std::string(k_fit_result_format) + "\"");
  if (!j.contains("friction_coefficient")) throw std::invalid_argument("fit result: key 'friction_coefficient' missing");
  FitResultDocument doc;
  DropFitResult& r = doc.result;
  get(j, "board", doc.board);
  get(j, "event", doc.event);
  get(j, "wear", doc.wear_note);
  get(j, "friction_coefficient", r.friction_coefficient);
  read_durations_pair(j, "rubbing_s_per_bearing", r.rubbing);
  if (!j.contains("rubbing_s_per_bearing"))
    if (const json* o = member(j, "rubbing_s", false)) read_durations(*o, r.rubbing[0]);
  read_durations_pair(j, "measured_rubbing_s_per_bearing", r.measured_rubbing);
  get(j, "cost", r.cost.total);
  if (const json* o = member(j, "cost_terms", false)) read_cost(*o, r.cost);
  get(j, "cost_lock_in", r.cost.lock_in);
  get(j, "friction_uncertainty", r.friction_uncertainty);
  get(j, "friction_method", r.friction_method);
  if (const json* o = member(j, "friction_estimate", false)) read_friction_estimate(*o, r.friction_estimate);
  get(j, "bound_active", r.bound_active);
  get(j, "contact_law", r.contact_law);
  get(j, "contact_stiffness_n_per_m", r.contact_stiffness_n_per_m);
  get(j, "contact_damping_n_s_per_m", r.contact_damping_n_s_per_m);
  get(j, "ring_drag_n_m", r.ring_drag_n_m);
  get(j, "spin_down_rad_s2", r.spin_down_rad_s2);
  get(j, "fitted_spin_down_rad_s2", r.fitted_spin_down_rad_s2);
  get(j, "polish_evaluations", r.polish_evaluations);
  if (const json* a = member(j, "unknowns", true)) {
    for (const json& x : *a) {
      if (!x.is_object()) wrong("unknowns", "an array of objects");
      DropFitResult::Unknown u;
      get(x, "name", u.name);
      get(x, "value", u.value);
      get(x, "uncertainty", u.uncertainty);
      get(x, "lower", u.lower);
      get(x, "upper", u.upper);
      get(x, "bound_active", u.bound_active);
      r.unknowns.push_back(u);
    }
  }
  read_whirl(j, "whirl", r.whirl);
  read_whirl(j, "fitted_whirl", r.fitted_whirl);
  read_lock_in(j, "lock_in", r.lock_in);
  read_lock_in(j, "fitted_lock_in", r.fitted_lock_in);
  if (const json* o = member(j, "rotor_structure", false)) {
    get(*o, "modes_per_plane", r.rotor_modes_per_plane);
    if (const json* a = member(*o, "trials", true)) {
      for (const json& x : *a) {
        if (!x.is_object()) wrong("trials", "an array of objects");
        DropFitResult::StructureTrial t;
        get(x, "modes_per_plane", t.modes_per_plane);
        get(x, "cost", t.cost);
        get(x, "converged", t.converged);
        get(x, "bound_active", t.bound_active);
        r.structure_trials.push_back(t);
      }
    }
  }
  get(j, "evaluations", r.evaluations);
  get(j, "wall_s", r.wall_s);
  get(j, "converged", r.converged);
  get(j, "stop_reason", r.stop_reason);
  get(j, "restitution", r.restitution);
  get2(j, "centre_offset_m", r.centre_offset_m);
  get(j, "cost_history", r.cost_history);
  return doc;
}

}  // namespace amb::host::fit
