#include "tests/fleet/fleet_fixture.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "firmware/events/event_codec.hpp"
#include "firmware/wear/wear_record.hpp"
#include "host-tools/core/fleet/fleet_db.hpp"

namespace amb::test::fleet {
namespace {

void write(const std::filesystem::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream f(p, std::ios::binary);
  f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

std::string g17(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

}  // namespace

std::vector<std::string> FleetFiles::all() const {
  std::vector<std::string> v = events;
  v.insert(v.end(), wear.begin(), wear.end());
  v.insert(v.end(), results.begin(), results.end());
  return v;
}

std::filesystem::path fresh_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("amb-fleet-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

FleetFiles make_fleet_files(const std::filesystem::path& dir, int samples_per_event) {
  std::filesystem::create_directories(dir);
  FleetFiles f;
  const int machines = 5;
  // 100 events: 20 per board, each board's drops a little harder than the last board's.
  for (int k = 0; k < 100; ++k) {
    const int m = k % machines, n = k / machines;
    fw::EventRecord r;
    r.meta.board_name = "board-" + std::to_string(m + 1);
    r.meta.rig_name = m < 3 ? "bath-amb-rig" : "tum-mlps-rig";
    r.meta.firmware_version = fw::k_firmware_version;
    r.meta.board_source = "embedded:" + r.meta.rig_name;
    r.meta.event_number = static_cast<std::uint64_t>(n + 1);
    r.meta.capture_number = r.meta.event_number;
    r.meta.rate_hz = 10000.0;
    r.meta.pre_trigger_s = 0.05;
    r.meta.post_trigger_s = 0.15;
    r.meta.cause = n % 3 == 0 ? fw::TriggerCause::channel_cutoff : fw::TriggerCause::orbit_radius;
    r.meta.trigger_index = static_cast<std::uint32_t>(samples_per_event / 4);
    r.meta.speed_at_trigger_hz = n % 7 == 3 ? std::nan("") : 30.0 + m + 0.5 * n;
    r.samples.resize(static_cast<size_t>(samples_per_event));
    for (size_t i = 0; i < r.samples.size(); ++i) {
      auto& s = r.samples[i];
      s.seq = i;
      s.t_ns = static_cast<std::int64_t>(i) * 100000 + static_cast<std::int64_t>(k) * 1000000000;
      s.displacement_m = {static_cast<float>(1e-5 * std::sin(0.01 * static_cast<double>(i + k))), 0.0f, 0.0f, 0.0f};
      s.speed_hz = static_cast<float>(30.0 + m);
    }
    r.meta.trigger_seq = r.meta.trigger_index;
    r.meta.first_t_ns = r.samples.front().t_ns;
    r.meta.last_t_ns = r.samples.back().t_ns;
    r.meta.trigger_t_ns = r.samples[r.meta.trigger_index].t_ns;
    r.has_analysis = true;
    r.analysis.quick_look_valid = n % 9 != 4;  // some events without a quick-look
    for (int b = 0; b < 2; ++b) {
      auto& q = r.analysis.aux[static_cast<size_t>(b)];
      q.valid = true;
      q.samples_in_contact = static_cast<std::uint32_t>(100 + n);
      q.peak_force_n = 1000.0 * (m + 1) + 10.0 * n + 100.0 * b;
      q.life_fraction = 0.001 * (m + 1) * (1.0 + 0.5 * b) * (1.0 + 0.1 * std::sin(static_cast<double>(n)));
      q.contact_time_s = 0.01 * (n + 1);
    }
    char name[64];
    std::snprintf(name, sizeof name, "board-%d_event_%08d.ambe", m + 1, n + 1);
    write(dir / name, fw::encode_event(r));
    f.events.push_back((dir / name).string());
  }
  // Wear records of boards 1..3 (the host fitted their drops), sequences 1..4.
  for (int m = 0; m < 3; ++m) {
    for (int s = 1; s <= 4; ++s) {
      fw::WearRecord w;
      w.sequence = static_cast<std::uint32_t>(s);
      w.board_name = "board-" + std::to_string(m + 1);
      w.life_model = "friction-energy budget (Archard) 20000 J";
      w.event_count = static_cast<std::uint32_t>(5 * s);
      w.last_friction_coefficient = 0.15f + 0.01f * static_cast<float>(m);
      w.updated_unix_s = 1700000000 + 86400 * (7 * s + m);
      for (int b = 0; b < 2; ++b) {
        auto& a = w.bearing[static_cast<size_t>(b)];
        a.friction_energy_j = static_cast<float>(1500.0 * s * (m + 1) * (1 + b));
        a.life_used_fraction = a.friction_energy_j / 20000.0f;
        a.peak_force_n = static_cast<float>(4000 + 100 * s + 500 * m);
        a.swing_s = 0.1f * static_cast<float>(s);
      }
      const auto p = dir / ("board-" + std::to_string(m + 1) + "_wear_" + std::to_string(s) + ".ambw");
      write(p, fw::encode_wear_record(w));
      f.wear.push_back(p.string());
    }
  }
  // A fit and a residual result per board 1..2 (the shape of amb-host fit / residual --json).
  for (int m = 0; m < 2; ++m) {
    nlohmann::json fit = {{"board", "board-" + std::to_string(m + 1)},
                          {"event", "board-" + std::to_string(m + 1) + "_event_00000001.ambe"},
                          {"friction_coefficient", 0.15 + 0.01 * m},
                          {"cost", 0.42 + m},
                          {"converged", m == 0},
                          {"whirl", {{{"direction", "bouncing"}, {"frequency_hz", 3.0}}, {{"direction", "backward"}, {"frequency_hz", 80.0}}}}};
    nlohmann::json res = {{"board", "board-" + std::to_string(m + 1)},
                          {"effects_added", nlohmann::json::array({{{"name", "aux_bearing_offset"}}})},
                          {"error_before", {{"rms", 1.5e-5}, {"spectral", 3.0}, {"pearson", 0.8}}},
                          {"error_after", {{"rms", 4.0e-6}, {"spectral", 1.0}, {"pearson", 0.97}}},
                          {"verdict", "aux_bearing_offset"}};
    const auto pf = dir / ("board-" + std::to_string(m + 1) + "_fit.json");
    const auto pr = dir / ("board-" + std::to_string(m + 1) + "_residual.json");
    std::ofstream(pf) << fit.dump(1);
    std::ofstream(pr) << res.dump(1);
    f.results.push_back(pf.string());
    f.results.push_back(pr.string());
  }
  return f;
}

std::string query_dump(host::fleet::FleetStore& store) {
  std::string t;
  for (const auto& m : store.machines())
    t += "machine " + m.name + " " + m.rig + " " + std::to_string(m.events) + " " + std::to_string(m.wear_records) + " " +
         std::to_string(m.fits) + " " + std::to_string(m.residuals) + " " + std::to_string(m.last_event_number) + "\n";
  for (const auto& p : store.trend())
    t += "trend " + p.machine + " " + std::to_string(p.bearing) + " " + p.source + " " + std::to_string(p.order) + " " +
         std::to_string(p.time_unix_s) + " " + g17(p.life_used_fraction) + "\n";
  for (const auto& s : store.nearest_budget())
    t += "nearest " + s.machine + " " + std::to_string(s.bearing) + " " + s.source + " " + g17(s.life_used_fraction) + " " +
         g17(s.peak_force_n) + " " + std::to_string(s.events) + "\n";
  for (const auto& r : store.db().query(
           "SELECT e.content_hash, m.name, e.event_number, e.trigger_t_ns, e.cause, e.speed_at_trigger_hz, e.samples, e.rate_hz,"
           " b.position, b.quick_look_valid, b.peak_force_n, b.life_fraction, b.contact_time_s"
           " FROM events e JOIN machines m ON m.id = e.machine_id JOIN event_bearings b ON b.event_id = e.id"
           " ORDER BY e.content_hash, b.position")) {
    t += "event";
    for (const auto& v : r) t += " " + host::fleet::canonical(v);
    t += "\n";
  }
  for (const auto& r : store.db().query(
           "SELECT r.content_hash, m.name, r.kind, r.event_ref, r.friction_coefficient, r.cost, r.converged, r.whirl, r.verdict,"
           " r.rms_before, r.rms_after FROM results r JOIN machines m ON m.id = r.machine_id ORDER BY r.content_hash")) {
    t += "result";
    for (const auto& v : r) t += " " + host::fleet::canonical(v);
    t += "\n";
  }
  return t;
}

}  // namespace amb::test::fleet
