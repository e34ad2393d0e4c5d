#include "firmware/board/board.hpp"
#include "firmware/board/board_text.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "boards/embedded_boards.hpp"
#include "firmware/board/parse_bearing.hpp"
#include "firmware/board/parse_comms.hpp"
#include "firmware/board/parse_sweep.hpp"
#include "firmware/board/parse_journal.hpp"
#include "firmware/board/parse_capture.hpp"
#include "firmware/board/parse_tracker.hpp"
#include "firmware/board/toml_reader.hpp"

namespace amb::board {

BoardError::BoardError(const std::string& source, const std::string& key, const std::string& message)
    : std::runtime_error("board " + source + ": " + (key.empty() ? "" : "key '" + key + "': ") + message),
      key_(key) {}

namespace {

constexpr double k_big = 1e12;

void parse_rotor(TableReader r, model::RotorParams& rotor) {
  rotor.rayleigh_alpha_1_per_s = r.number_or("rayleigh_alpha_1_per_s", 0.0, 0.0, 1e4);
  rotor.rayleigh_beta_s = r.number_or("rayleigh_beta_s", 0.0, 0.0, 1e-2);
  rotor.modes_kept = static_cast<int>(r.integer_or("modes_kept", 0, 0, 400));
  for (TableReader e : r.tables("elements", 1, 400)) {
    model::BeamElement el;
    el.length_m = e.number("length_m", 1e-4, 10.0);
    el.outer_diameter_m = e.number("outer_diameter_m", 1e-4, 5.0);
    el.inner_diameter_m = e.number_or("inner_diameter_m", 0.0, 0.0, 5.0);
    if (el.inner_diameter_m >= el.outer_diameter_m)
      e.fail("inner_diameter_m", "must be smaller than outer_diameter_m");
    el.density_kg_m3 = e.number_or("density_kg_m3", 7800.0, 100.0, 30000.0);
    el.youngs_modulus_pa = e.number_or("youngs_modulus_pa", 2.1e11, 1e8, 1e13);
    el.poisson_ratio = e.number_or("poisson_ratio", 0.3, 0.0, 0.5);
    el.structural = e.boolean_or("structural", true);
    const long long repeat = e.integer_or("repeat", 1, 1, 400);
    e.finish();
    for (long long i = 0; i < repeat; ++i) rotor.elements.push_back(el);
  }
  for (TableReader d : r.tables("disks", 0, 64)) {
    model::RigidDisk disk;
    disk.axial_m = d.number("axial_m", 0.0, 100.0);
    disk.mass_kg = d.number("mass_kg", 0.0, 1e5);
    disk.polar_inertia_kg_m2 = d.number("polar_inertia_kg_m2", 0.0, 1e5);
    disk.transverse_inertia_kg_m2 = d.number("transverse_inertia_kg_m2", 0.0, 1e5);
    disk.unbalance_kg_m = d.number_or("unbalance_kg_m", 0.0, 0.0, 1.0);
    disk.unbalance_phase_deg = d.number_or("unbalance_phase_deg", 0.0, -360.0, 360.0);
    d.finish();
    rotor.disks.push_back(disk);
  }
  r.finish();
}

double rotor_length_m(const model::RotorParams& rotor) {
  double l = 0.0;
  for (const auto& e : rotor.elements) l += e.length_m;
  return l;
}

bool on_node(const model::RotorParams& rotor, double x_m) {
  double at = 0.0;
  if (std::abs(x_m) < 1e-6) return true;
  for (const auto& e : rotor.elements) {
    at += e.length_m;
    if (std::abs(at - x_m) < 1e-6) return true;
  }
  return false;
}

void parse_rig(TableReader r, model::PlantParams& p) {
  p.rig_name = r.string("name");
  p.gravity_m_s2 = r.number_or("gravity_m_s2", 9.81, 0.0, 20.0);
  p.integration_step_s = r.number_or("integration_step_s", 1e-5, 1e-7, 1e-3);
  parse_rotor(r.table("rotor"), p.rotor);
  const double length = rotor_length_m(p.rotor);
  for (size_t i = 0; i < p.rotor.disks.size(); ++i)
    if (!on_node(p.rotor, p.rotor.disks[i].axial_m))
      r.fail("rotor.disks[" + std::to_string(i) + "].axial_m",
             "must coincide with an element end (a node) of the rotor mesh");

  auto ambs = r.tables("amb", 2, 2);
  for (size_t i = 0; i < 2; ++i) {
    TableReader& a = ambs[i];
    model::AmbParams& amb = p.amb[i];
    amb.axial_m = a.number("axial_m", 0.0, length);
    amb.gap_m = a.number("gap_m", 1e-5, 1e-2);
    amb.bias_current_a = a.number("bias_current_a", 1e-3, 100.0);
    amb.ks_n_per_m = a.number("ks_n_per_m", 0.0, 1e10);
    amb.ki_n_per_a = a.number("ki_n_per_a", 1e-3, 1e6);
    amb.max_force_n = a.number("max_force_n", 1.0, 1e7);
    amb.coil_current_limit_a = a.number("coil_current_limit_a", 1e-3, 200.0);
    amb.amplifier_bandwidth_hz = a.number("amplifier_bandwidth_hz", 1.0, 1e5);
    const auto ang = a.numbers("actuator_angle_deg", 2, -180.0, 180.0);
    amb.actuator_angle_deg = {ang[0], ang[1]};
    if (std::abs(std::sin((ang[0] - ang[1]) * M_PI / 180.0)) < 0.5)
      a.fail("actuator_angle_deg", "the two actuator axes must be at least 30 deg apart");
    // The force law ties bias, gap and the two gains: ks / ki = i0 / g0 (see AmbParams).
    const double i0_implied = amb.ks_n_per_m * amb.gap_m / amb.ki_n_per_a;
    if (std::abs(i0_implied - amb.bias_current_a) > 0.25 * amb.bias_current_a)
      a.fail("bias_current_a", "inconsistent with ks*gap/ki = " + std::to_string(i0_implied) +
                                   " A (allowed within 25 %)");
    a.finish();
  }
  auto sensors = r.tables("sensor", 4, 4);
  for (size_t i = 0; i < 4; ++i) {
    TableReader& s = sensors[i];
    p.sensor[i].axial_m = s.number("axial_m", 0.0, length);
    p.sensor[i].angle_deg = s.number("angle_deg", -180.0, 180.0);
    p.sensor[i].noise_rms_m = s.number_or("noise_rms_m", 0.0, 0.0, 1e-3);
    p.sensor[i].bandwidth_hz = s.number_or("bandwidth_hz", 0.0, 0.0, 1e6);
    s.finish();
  }
  auto aux = r.tables("aux_bearing", 2, 2);
  for (size_t i = 0; i < 2; ++i) {
    TableReader& a = aux[i];
    model::AuxBearingParams& b = p.aux[i];
    b.axial_m = a.number("axial_m", 0.0, length);
    b.clearance_m = a.number("clearance_m", 1e-6, 1e-2);
    b.contact_stiffness_n_per_m = a.number("contact_stiffness_n_per_m", 1e3, 1e12);
    b.contact_damping_n_s_per_m = a.number_or("contact_damping_n_s_per_m", 0.0, 0.0, 1e7);
    b.friction_coefficient = a.number("friction_coefficient", 0.0, 2.0);
    b.collar_radius_m = a.number("collar_radius_m", 1e-3, 2.0);
    b.ring_inertia_kg_m2 = a.number("ring_inertia_kg_m2", 1e-9, 100.0);
    b.ring_friction_torque_n_m = a.number_or("ring_friction_torque_n_m", 0.0, 0.0, 1e3);
    b.centre_offset_x_m = a.number_or("centre_offset_x_m", 0.0, -1e-2, 1e-2);
    b.centre_offset_y_m = a.number_or("centre_offset_y_m", 0.0, -1e-2, 1e-2);
    {
      // Drop-model contact law (model/drop): "rigid" (default, Moreau-Jean with restitution),
      // "hertz" (K d^1.5, K from contact_stiffness_n_per_m at 10 um) or "linear" (k d).
      const std::string law = a.string_or("contact_law", "rigid");
      if (law == "rigid") b.contact_law = model::AuxContactLaw::rigid;
      else if (law == "hertz") b.contact_law = model::AuxContactLaw::hertz;
      else if (law == "linear") b.contact_law = model::AuxContactLaw::linear;
      else a.fail("contact_law", "must be \"rigid\", \"hertz\" or \"linear\", got \"" + law + "\"");
    }
    a.finish();
  }
  {
    TableReader d = r.table("drive");
    p.drive_torque_limit_n_m = d.number("torque_limit_n_m", 0.0, 1e5);
    p.drive_speed_gain_n_m_s = d.number("speed_gain_n_m_s", 0.0, 1e5);
    d.finish();
  }
  r.finish();
}

void parse_controller(TableReader r, BoardConfig& b) {
  b.rate_hz = r.number("rate_hz", 100.0, 40000.0);  // 100 Hz: slow emulated boards (tests/target)
  // Sample instant -> demand at the amplifiers, periods. Above 2 the sampled PID of these
  // rigs is unstable anyway (docs/plant.md), and the sim backend's demand queue is bounded.
  b.loop_delay_periods = r.number_or("loop_delay_periods", 0.0, 0.0, 2.0);
  model::PidParams& c = b.controller;
  c.kp_n_per_m = r.number("kp_n_per_m", 0.0, k_big);
  c.ki_n_per_m_s = r.number("ki_n_per_m_s", 0.0, k_big);
  c.kd_n_s_per_m = r.number("kd_n_s_per_m", 0.0, k_big);
  c.derivative_filter_hz = r.number("derivative_filter_hz", 1.0, 0.45 * b.rate_hz);
  c.integrator_limit_n = r.number("integrator_limit_n", 0.0, 1e7);
  c.current_limit_a = r.number("current_limit_a", 1e-3, 200.0);
  // Optional lead: both keys or neither; the pole above the zero, both below Nyquist.
  if (r.has("lead_zero_hz") || r.has("lead_pole_hz")) {
    c.lead_zero_hz = r.number("lead_zero_hz", 1.0, 0.45 * b.rate_hz);
    c.lead_pole_hz = r.number("lead_pole_hz", c.lead_zero_hz * 1.01, 0.45 * b.rate_hz);
  }
  auto notches = r.inline_tables("notches", 0, model::k_max_notches);
  c.notch_count = static_cast<int>(notches.size());
  for (size_t i = 0; i < notches.size(); ++i) {
    TableReader& n = notches[i];
    c.notches[i].centre_hz = n.number("centre_hz", 1.0, 0.45 * b.rate_hz);
    c.notches[i].width_hz = n.number("width_hz", 0.1, 0.45 * b.rate_hz);
    c.notches[i].depth = n.number("depth", 0.0, 1.0);
    n.finish();
  }
  r.finish();
}

void parse_lifecycle(TableReader r, BoardConfig& b) {
  LifecycleParams& l = b.lifecycle;
  l.liftoff_ramp_s = r.number("liftoff_ramp_s", 0.0, 60.0);
  l.settle_s = r.number("settle_s", 0.0, 60.0);
  l.operating_speed_hz = r.number("operating_speed_hz", 0.0, 2000.0);
  l.spin_accel_hz_per_s = r.number("spin_accel_hz_per_s", 0.01, 1000.0);
  l.landing_ramp_s = r.number("landing_ramp_s", 0.0, 60.0);
  l.max_orbit_fault_m = r.number("max_orbit_fault_m", 1e-6, 1e-2);
  l.settle_tolerance_m = r.number_or("settle_tolerance_m", 0.1 * l.max_orbit_fault_m, 1e-7, l.max_orbit_fault_m);
  l.max_missed_samples = static_cast<uint32_t>(r.integer_or("max_missed_samples", l.max_missed_samples, 1, 100000));
  r.finish();
}

void parse_assumed(TableReader r, const toml::table& root, BoardConfig& b) {
  for (auto& [key, reason] : r.string_entries()) {
    // The key must name something the file sets (array indices are not needed).
    if (!root.at_path(key)) r.fail(key, "names no key of this board file");
    if (reason.empty()) r.fail(key, "needs a reason");
    b.assumed[key] = reason;
  }
  r.finish();
}

}  // namespace

BoardConfig parse_board(std::string_view toml_text, const std::string& source) {
  toml::table root;
  std::string screened;
  try {
    screened = screen_toml_text(toml_text);
  } catch (const std::invalid_argument& e) {
    throw BoardError(source, "", e.what());
  }
  try {
    root = toml::parse(screened, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << "not valid TOML at line " << e.source().begin.line << ", column "
       << e.source().begin.column << ": " << e.description();
    throw BoardError(source, "", os.str());
  }
  BoardConfig b;
  b.source = source;
  TableReader top(root, "", source);
  const std::string schema = top.string("schema");
  if (schema != "amb-board/1") top.fail("schema", "must be \"amb-board/1\", got \"" + schema + "\"");
  {
    TableReader t = top.table("board");
    b.name = t.string("name");
    b.description = t.string_or("description", "");
    b.backend = t.string_or("backend", "sim");
    if (b.backend != "sim" && b.backend != "linux" && b.backend != "replay")
      t.fail("backend", "must be one of \"sim\", \"linux\", \"replay\"");
    t.finish();
  }
  parse_rig(top.table("rig"), b.plant);
  parse_controller(top.table("controller"), b);
  parse_lifecycle(top.table("lifecycle"), b);
  if (top.has("capture")) parse_capture(top.table("capture"), b.capture, b.rate_hz);
  if (top.has("triggers")) parse_triggers(top.table("triggers"), b.capture.triggers);
  if (top.has("tracker")) parse_tracker(top.table("tracker"), b.tracker, b.rate_hz);
  if (top.has("bearing")) parse_bearing(top.table("bearing"), b.bearing);
  if (top.has("comms")) parse_comms(top.table("comms"), b.comms);
  if (top.has("journal_bearing"))
    parse_journal_bearing(top.table("journal_bearing"), b.journal, rotor_length_m(b.plant.rotor));
  {
    const double clearance = std::min(b.plant.aux[0].clearance_m, b.plant.aux[1].clearance_m);
    b.sweep = sweep_defaults(b.rate_hz, clearance, b.lifecycle.max_orbit_fault_m);
    if (top.has("sweep")) parse_sweep(top.table("sweep"), b.sweep, b.rate_hz);
    check_sweep(b.sweep, b.rate_hz, clearance, b.lifecycle.max_orbit_fault_m, source);
  }
  if (top.has("assumed")) parse_assumed(top.table("assumed"), root, b);
  top.finish();
  return b;
}

std::vector<std::string> embedded_board_names() {
  std::vector<std::string> names;
  for (const boards::EmbeddedBoard* e = boards::embedded_boards(); e->name; ++e) names.emplace_back(e->name);
  return names;
}

BoardConfig load_board(const std::string& name_or_path) {
  for (const boards::EmbeddedBoard* e = boards::embedded_boards(); e->name; ++e)
    if (name_or_path == e->name) return parse_board(e->toml, std::string("embedded:") + e->name);
  std::ifstream in(name_or_path, std::ios::binary);
  if (!in) {
    std::string known;
    for (const auto& n : embedded_board_names()) known += (known.empty() ? "" : ", ") + n;
    throw BoardError(name_or_path, "", "no such file, and not an embedded board (known: " + known + ")");
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_board(ss.str(), name_or_path);
}

}  // namespace amb::board
