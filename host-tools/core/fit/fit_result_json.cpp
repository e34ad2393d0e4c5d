#include "host-tools/core/fit/fit_result_json.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace amb::host::fit {
namespace {

using nlohmann::json;

// The document's fields are listed once (result_fields below), as a template over the coder:
// JsonOut writes them, JsonIn reads them back with the same calls (the JSON twin of the
// AMBE/AMBW codecs' ByteWriter/ByteReader).

class JsonOut {
 public:
  static constexpr bool k_reads = false;
  explicit JsonOut(json& j) : j_(j) {}
  template <class T>
  void field(const char* key, const T& v) { j_[key] = v; }
  template <class F>
  void object(const char* key, F&& f) {
    json o = json::object();
    JsonOut c(o);
    f(c);
    j_[key] = std::move(o);
  }
  /// An array of objects, one per element of `items` (a vector, or a fixed-size array).
  template <class Items, class F>
  void objects(const char* key, const Items& items, F&& f) {
    json a = json::array();
    for (const auto& x : items) {
      json o = json::object();
      JsonOut c(o);
      f(c, x);
      a.push_back(std::move(o));
    }
    j_[key] = std::move(a);
  }

 private:
  json& j_;
};

// Reading: a key absent keeps the default; present, it must have the written type. A number
// written as null is a NaN or infinity (JSON has neither): read back as NaN.
[[noreturn]] void wrong(const std::string& key, const char* what) {
  throw std::invalid_argument("fit result: key '" + key + "': expected " + what);
}

double number_or_nan(const json& x, const char* key) {
  if (x.is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!x.is_number()) wrong(key, "a number");
  return x.get<double>();
}

class JsonIn {
 public:
  static constexpr bool k_reads = true;
  explicit JsonIn(const json& j) : j_(j) {}
  void field(const char* key, double& v) {
    if (const json* x = find(key)) v = number_or_nan(*x, key);
  }
  void field(const char* key, int& v) {
    if (const json* x = find(key)) {
      if (!x->is_number_integer()) wrong(key, "an integer");
      v = x->get<int>();
    }
  }
  void field(const char* key, bool& v) {
    if (const json* x = find(key)) {
      if (!x->is_boolean()) wrong(key, "true or false");
      v = x->get<bool>();
    }
  }
  void field(const char* key, std::string& v) {
    if (const json* x = find(key)) {
      if (!x->is_string()) wrong(key, "a string");
      v = x->get<std::string>();
    }
  }
  void field(const char* key, std::vector<double>& v) {
    if (const json* x = find(key)) {
      if (!x->is_array()) wrong(key, "an array of numbers");
      v.clear();
      for (const json& e : *x) v.push_back(number_or_nan(e, key));
    }
  }
  void field(const char* key, std::array<double, 2>& v) {
    if (const json* x = find(key)) {
      if (!x->is_array() || x->size() != 2) wrong(key, "two numbers");
      for (size_t i = 0; i < 2; ++i) v[i] = number_or_nan((*x)[i], key);
    }
  }
  void field(const char* key, std::array<bool, 2>& v) {
    if (const json* x = find(key)) {
      if (!x->is_array() || x->size() != 2 || !(*x)[0].is_boolean() || !(*x)[1].is_boolean()) wrong(key, "two booleans");
      v = {(*x)[0].get<bool>(), (*x)[1].get<bool>()};
    }
  }
  template <class F>
  void object(const char* key, F&& f) {
    if (const json* x = find(key)) {
      if (!x->is_object()) wrong(key, "an object");
      JsonIn c(*x);
      f(c);
    }
  }
  template <class T, class F>
  void objects(const char* key, std::vector<T>& items, F&& f) {
    if (const json* x = find(key)) {
      items.assign(check_objects(*x, key, x->size()), T{});
      for (size_t i = 0; i < items.size(); ++i) {
        JsonIn c((*x)[i]);
        f(c, items[i]);
      }
    }
  }
  template <class T, size_t N, class F>
  void objects(const char* key, std::array<T, N>& items, F&& f) {
    if (const json* x = find(key)) {
      check_objects(*x, key, N);
      for (size_t i = 0; i < N; ++i) {
        JsonIn c((*x)[i]);
        f(c, items[i]);
      }
    }
  }

 private:
  const json* find(const char* key) const { return j_.contains(key) ? &j_[key] : nullptr; }
  /// `x` is an array of `n` objects; returns n.
  static size_t check_objects(const json& x, const char* key, size_t n) {
    if (!x.is_array() || x.size() != n) wrong(key, "an array of objects");
    for (const json& e : x)
      if (!e.is_object()) wrong(key, "an array of objects");
    return n;
  }
  const json& j_;
};

template <class C, class D>
void durations_fields(C& c, D& d) {
  c.field("swing", d.swing_s);
  c.field("forward", d.forward_s);
  c.field("backward", d.backward_s);
}

template <class C, class A>
void rigid_bent(C& c, const char* key, A& v) {
  c.object(key, [&](auto& o) {
    o.field("rigid", v[0]);
    o.field("bent", v[1]);
  });
}

template <class C, class E>
void friction_estimate_fields(C& c, E& fe) {
  c.field("valid", fe.valid);
  c.field("friction", fe.friction);
  c.field("uncertainty", fe.uncertainty);
  c.field("standard_error", fe.standard_error);
  c.field("smoothing_change", fe.smoothing_change);
  c.field("windows_used", fe.windows_used);
  c.field("windows_total", fe.windows_total);
  c.field("window_s", fe.window_s);
  c.field("sliding_time_s", fe.sliding_time_s);
  c.field("measured_spin_down_rad_s2", fe.measured_spin_down_rad_s2);
  c.field("force_spin_down_rad_s2", fe.force_spin_down_rad_s2);
  c.field("force_spin_down_scatter_rad_s2", fe.force_spin_down_scatter_rad_s2);
  c.field("synchronous_removed", fe.synchronous_removed);
  c.field("synchronous_force_n", fe.synchronous_force_n);
  c.field("synchronous_moment_n_m", fe.synchronous_moment_n_m);
  c.field("bending_modes", fe.bending_modes);
  c.field("rotor_choice", fe.rotor_choice);
  c.field("free_flight_samples", fe.free_flight_samples);
  rigid_bent(c, "free_flight_force_rms_n", fe.free_flight_force_rms_n);
  rigid_bent(c, "free_flight_noise_rms_n", fe.free_flight_noise_rms_n);
  c.field("note", fe.note);
  c.objects("windows", fe.windows, [](auto& o, auto& w) {
    o.field("bearing", w.bearing);
    o.field("start_s", w.start_s);
    o.field("normal_impulse_n_s", w.normal_impulse_n_s);
    o.field("friction_impulse_n_s", w.friction_impulse_n_s);
    o.field("ratio", w.ratio);
    o.field("sliding", w.sliding);
    o.field("next_to_rolling", w.next_to_rolling);
  });
}

template <class C, class W>
void whirl_fields(C& c, const char* key, W& whirl) {
  c.objects(key, whirl, [](auto& o, auto& w) {
    o.field("direction", w.direction);
    o.field("frequency_hz", w.frequency_hz);
    o.field("onset_s", w.onset_s);
    o.field("contact_share", w.contact_share);
    o.field("whirl_rate_rad_s", w.whirl_rate_rad_s);
    o.field("bounce_rate_per_s", w.bounce_rate_per_s);
  });
}

template <class C, class L>
void lock_in_fields(C& c, const char* key, L& f) {
  c.object(key, [&](auto& o) {
    o.field("valid", f.valid);
    o.field("own", f.own);
    o.field("start_s", f.start_s);
    o.field("speed_level_rad_s", f.speed_level_rad_s);
    o.field("spin_down_rad_s2", f.spin_down_rad_s2);
    o.field("whirling", f.whirling);
    o.field("centripetal_m_s2", f.centripetal_m_s2);
    o.field("penetration_m", f.penetration_m);
  });
}

/// Every field of DropFitResult the document carries.
template <class C, class R>
void result_fields(C& c, R& r) {
  c.field("friction_coefficient", r.friction_coefficient);
  c.objects("rubbing_s_per_bearing", r.rubbing, [](auto& o, auto& d) { durations_fields(o, d); });
  c.objects("measured_rubbing_s_per_bearing", r.measured_rubbing, [](auto& o, auto& d) { durations_fields(o, d); });
  c.field("cost", r.cost.total);
  c.object("cost_terms", [&](auto& o) {
    o.field("rubbing", r.cost.rubbing);
    o.field("orbit", r.cost.orbit);
    o.field("speed", r.cost.speed);
    o.field("spin_down", r.cost.spin_down);
    o.field("contact", r.cost.contact);
    o.field("whirl", r.cost.whirl);
    o.field("bounce", r.cost.bounce);
  });
  c.field("cost_lock_in", r.cost.lock_in);
  c.field("friction_uncertainty", r.friction_uncertainty);
  c.field("friction_method", r.friction_method);
  c.object("friction_estimate", [&](auto& o) { friction_estimate_fields(o, r.friction_estimate); });
  c.field("bound_active", r.bound_active);
  c.field("contact_law", r.contact_law);
  c.field("contact_stiffness_n_per_m", r.contact_stiffness_n_per_m);
  c.field("contact_damping_n_s_per_m", r.contact_damping_n_s_per_m);
  c.field("ring_drag_n_m", r.ring_drag_n_m);
  c.field("spin_down_rad_s2", r.spin_down_rad_s2);
  c.field("fitted_spin_down_rad_s2", r.fitted_spin_down_rad_s2);
  c.field("polish_evaluations", r.polish_evaluations);
  c.objects("unknowns", r.unknowns, [](auto& o, auto& u) {
    o.field("name", u.name);
    o.field("value", u.value);
    o.field("uncertainty", u.uncertainty);
    o.field("lower", u.lower);
    o.field("upper", u.upper);
    o.field("bound_active", u.bound_active);
  });
  whirl_fields(c, "whirl", r.whirl);
  whirl_fields(c, "fitted_whirl", r.fitted_whirl);
  lock_in_fields(c, "lock_in", r.lock_in);
  lock_in_fields(c, "fitted_lock_in", r.fitted_lock_in);
  c.object("rotor_structure", [&](auto& o) {
    o.field("modes_per_plane", r.rotor_modes_per_plane);
    if constexpr (!C::k_reads) o.field("model", std::string(r.rotor_modes_per_plane == 2 ? "rigid" : "flexible"));
    o.objects("trials", r.structure_trials, [](auto& t, auto& s) {
      t.field("modes_per_plane", s.modes_per_plane);
      t.field("cost", s.cost);
      t.field("converged", s.converged);
      t.field("bound_active", s.bound_active);
    });
  });
  c.field("evaluations", r.evaluations);
  c.field("wall_s", r.wall_s);
  c.field("converged", r.converged);
  c.field("stop_reason", r.stop_reason);
  c.field("restitution", r.restitution);
  c.field("centre_offset_m", r.centre_offset_m);
  c.field("cost_history", r.cost_history);
}

}  // namespace

json fit_result_json(const FitResultDocument& doc) {
  json j = json::object();
  JsonOut c(j);
  c.field("format", std::string(k_fit_result_format));
  if (!doc.board.empty()) c.field("board", doc.board);
  if (!doc.event.empty()) c.field("event", doc.event);
  result_fields(c, doc.result);
  // Bearing 1 alone: kept for readers of the first documents (before the per-bearing list).
  c.object("rubbing_s", [&](auto& o) { durations_fields(o, doc.result.rubbing[0]); });
  if (!doc.wear_note.empty()) c.field("wear", doc.wear_note);
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
  JsonIn c(j);
  c.field("board", doc.board);
  c.field("event", doc.event);
  c.field("wear", doc.wear_note);
  result_fields(c, doc.result);
  if (!j.contains("rubbing_s_per_bearing"))
    c.object("rubbing_s", [&](auto& o) { durations_fields(o, doc.result.rubbing[0]); });
  return doc;
}

}  // namespace amb::host::fit
