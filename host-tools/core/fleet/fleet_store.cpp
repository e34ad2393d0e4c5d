#include "host-tools/core/fleet/fleet_store.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <tuple>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "firmware/events/event_codec.hpp"
#include "firmware/wear/wear_record.hpp"
#include "host-tools/core/fleet/fleet_schema.hpp"
#include "host-tools/core/fit/fit_result_json.hpp"
#include "host-tools/core/fleet/sha256.hpp"

namespace amb::host::fleet {
namespace {

constexpr std::uintmax_t k_max_file_bytes = 1ull << 30;  // larger than any event the board writes

std::vector<std::uint8_t> read_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) throw std::invalid_argument(path + ": cannot be read");
  const std::streamoff n = f.tellg();
  if (n < 0 || static_cast<std::uintmax_t>(n) > k_max_file_bytes) throw std::invalid_argument(path + ": too large or unreadable");
  std::vector<std::uint8_t> b(static_cast<size_t>(n));
  f.seekg(0);
  f.read(reinterpret_cast<char*>(b.data()), n);
  if (!f) throw std::invalid_argument(path + ": read failed");
  return b;
}

bool starts_with(const std::vector<std::uint8_t>& b, const char* magic) {
  return b.size() >= 4 && std::equal(magic, magic + 4, b.begin());
}

Value number_or_null(double v) { return std::isfinite(v) ? Value{v} : Value{}; }

std::optional<double> json_number(const nlohmann::json& j, const char* k) {
  if (j.contains(k) && j[k].is_number()) return j[k].get<double>();
  return std::nullopt;
}

Value opt(const std::optional<double>& v) { return v && std::isfinite(*v) ? Value{*v} : Value{}; }

}  // namespace

FleetStore::FleetStore(const std::string& url) : FleetStore(open_database(url)) {}

FleetStore::FleetStore(std::unique_ptr<Database> db) : db_(std::move(db)) { migrate(*db_); }

std::int64_t FleetStore::machine_id(const std::string& name, const std::string& rig) {
  db_->query("INSERT INTO machines (name, rig) VALUES (?, ?) ON CONFLICT (name) DO NOTHING", {name, rig});
  return as_int(db_->query("SELECT id FROM machines WHERE name = ?", {name}).at(0).at(0));
}

AddResult FleetStore::add_file(const std::string& path, const std::string& machine_override) {
  const std::vector<std::uint8_t> bytes = read_file(path);
  AddResult r;
  r.path = path;
  r.content_hash = sha256_hex(bytes);

  if (starts_with(bytes, "AMBE")) {
    fw::EventRecord ev;
    std::string err;
    fw::EventKind kind = fw::EventKind::drop;
    uint16_t version = 0;
    if (fw::peek_event_kind(bytes, kind, version, err) && kind == fw::EventKind::sweep)
      throw std::invalid_argument(path + ": a loop-sweep event (AMBE v4): the fleet store keeps drop events; rate it with amb-host sweep --event");
    if (!fw::decode_event(bytes, ev, err)) throw std::invalid_argument(path + ": " + err);
    r.kind = "event";
    r.machine = machine_override.empty() ? ev.meta.board_name : machine_override;
    if (r.machine.empty()) throw std::invalid_argument(path + ": the event names no board; give --machine");
    Transaction t(*db_);
    const std::int64_t mid = machine_id(r.machine, ev.meta.rig_name);
    const auto ins = db_->query(
        "INSERT INTO events (content_hash, machine_id, event_number, trigger_t_ns, cause, speed_at_trigger_hz, samples, rate_hz,"
        " phase_b_fault, source, bytes) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?) ON CONFLICT (content_hash) DO NOTHING RETURNING id",
        {r.content_hash, mid, static_cast<std::int64_t>(ev.meta.event_number), static_cast<std::int64_t>(ev.meta.trigger_t_ns),
         std::string(fw::to_string(ev.meta.cause)), number_or_null(ev.meta.speed_at_trigger_hz),
         static_cast<std::int64_t>(ev.samples.size()), ev.meta.rate_hz,
         std::string(ev.has_diagnosis ? fw::diag::to_string(ev.diagnosis.type) : ""), path, Blob{bytes}});
    if (ins.empty()) return r;  // already stored (the machine row, if new, is rolled back)
    const std::int64_t id = as_int(ins[0][0]);
    for (int b = 0; b < 2; ++b) {
      const fw::AuxQuickLook& q = ev.analysis.aux[static_cast<size_t>(b)];
      const bool valid = ev.has_analysis && ev.analysis.quick_look_valid && q.valid;
      db_->query("INSERT INTO event_bearings (event_id, position, quick_look_valid, peak_force_n, life_fraction, contact_time_s)"
                 " VALUES (?, ?, ?, ?, ?, ?)",
                 {id, std::int64_t{b}, std::int64_t{valid}, valid ? q.peak_force_n : 0.0, valid ? q.life_fraction : 0.0,
                  valid ? q.contact_time_s : 0.0});
    }
    t.commit();
    r.added = true;
    return r;
  }

  if (starts_with(bytes, "AMBW")) {
    fw::WearRecord w;
    std::string err;
    if (!fw::decode_wear_record(bytes, w, err)) throw std::invalid_argument(path + ": " + err);
    r.kind = "wear";
    r.machine = machine_override.empty() ? w.board_name : machine_override;
    if (r.machine.empty()) throw std::invalid_argument(path + ": the wear record names no board; give --machine");
    Transaction t(*db_);
    const std::int64_t mid = machine_id(r.machine, "");
    const auto ins = db_->query(
        "INSERT INTO wear_records (content_hash, machine_id, sequence, updated_unix_s, event_count, life_model,"
        " friction_coefficient, source) VALUES (?, ?, ?, ?, ?, ?, ?, ?) ON CONFLICT (content_hash) DO NOTHING RETURNING id",
        {r.content_hash, mid, static_cast<std::int64_t>(w.sequence), static_cast<std::int64_t>(w.updated_unix_s),
         static_cast<std::int64_t>(w.event_count), w.life_model, static_cast<double>(w.last_friction_coefficient), path});
    if (ins.empty()) return r;
    const std::int64_t id = as_int(ins[0][0]);
    for (int b = 0; b < 2; ++b) {
      const fw::AuxBearingWear& a = w.bearing[static_cast<size_t>(b)];
      db_->query("INSERT INTO wear_bearings (wear_id, position, life_used_fraction, friction_energy_j, peak_force_n, swing_s,"
                 " forward_rub_s, backward_rub_s) VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                 {id, std::int64_t{b}, static_cast<double>(a.life_used_fraction), static_cast<double>(a.friction_energy_j),
                  static_cast<double>(a.peak_force_n), static_cast<double>(a.swing_s), static_cast<double>(a.forward_rub_s),
                  static_cast<double>(a.backward_rub_s)});
    }
    t.commit();
    r.added = true;
    return r;
  }

  nlohmann::json j;
  try {
    j = nlohmann::json::parse(bytes.begin(), bytes.end());
  } catch (const nlohmann::json::exception&) {
    throw std::invalid_argument(path + ": neither a board event (AMBE), a wear record (AMBW) nor JSON");
  }
  if (!j.is_object()) throw std::invalid_argument(path + ": JSON is not an object");
  if (j.contains("effects_added")) r.kind = "residual";
  else if (fit::is_fit_result_json(j)) r.kind = "fit";
  else throw std::invalid_argument(path + ": JSON is neither a fit (" + fit::k_fit_result_format +
                                   ", or friction_coefficient) nor a residual result (effects_added)");
  std::string board, whirl, verdict, event_ref;
  std::optional<double> converged, friction, cost;
  std::optional<double> rms_before, rms_after;
  if (r.kind == "fit") {
    // The fit's JSON is read by its own module (host-tools/core/fit/fit_result_json.hpp).
    fit::FitResultDocument doc;
    try {
      doc = fit::read_fit_result_json(j);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(path + ": " + e.what());
    }
    board = doc.board;
    event_ref = doc.event;
    friction = doc.result.friction_coefficient;
    if (j.contains("cost")) cost = doc.result.cost.total;
    if (j.contains("converged")) converged = doc.result.converged ? 1.0 : 0.0;
    if (j.contains("whirl"))
      for (const auto& w : doc.result.whirl) whirl += (whirl.empty() ? "" : ",") + w.direction;
  } else {
    if (j.contains("board") && j["board"].is_string()) board = j["board"].get<std::string>();
    if (j.contains("verdict") && j["verdict"].is_string()) verdict = j["verdict"].get<std::string>();
    if (j.contains("event") && j["event"].is_string()) event_ref = j["event"].get<std::string>();
    if (j.contains("converged") && j["converged"].is_boolean()) converged = j["converged"].get<bool>() ? 1.0 : 0.0;
    friction = json_number(j, "friction_coefficient");
    cost = json_number(j, "cost");
    if (j.contains("error_before") && j["error_before"].is_object()) rms_before = json_number(j["error_before"], "rms");
    if (j.contains("error_after") && j["error_after"].is_object()) rms_after = json_number(j["error_after"], "rms");
  }
  r.machine = machine_override.empty() ? board : machine_override;
  if (r.machine.empty()) throw std::invalid_argument(path + ": a " + r.kind + " result names no board; give --machine");
  Transaction t(*db_);
  const std::int64_t mid = machine_id(r.machine, "");
  const auto ins = db_->query(
      "INSERT INTO results (content_hash, machine_id, kind, event_ref, friction_coefficient, cost, converged, whirl, verdict,"
      " rms_before, rms_after, document, source) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"
      " ON CONFLICT (content_hash) DO NOTHING RETURNING id",
      {r.content_hash, mid, r.kind, event_ref, opt(friction), opt(cost),
       converged ? Value{static_cast<std::int64_t>(*converged)} : Value{}, whirl, verdict, opt(rms_before), opt(rms_after),
       j.dump(), path});
  if (ins.empty()) return r;
  t.commit();
  r.added = true;
  return r;
}

std::vector<MachineSummary> FleetStore::machines() {
  std::vector<MachineSummary> out;
  const auto rows = db_->query(
      "SELECT m.name, m.rig,"
      " (SELECT COUNT(*) FROM events e WHERE e.machine_id = m.id),"
      " (SELECT COUNT(*) FROM wear_records w WHERE w.machine_id = m.id),"
      " (SELECT COUNT(*) FROM results r WHERE r.machine_id = m.id AND r.kind = 'fit'),"
      " (SELECT COUNT(*) FROM results r WHERE r.machine_id = m.id AND r.kind = 'residual'),"
      " (SELECT MAX(e.event_number) FROM events e WHERE e.machine_id = m.id)"
      " FROM machines m ORDER BY m.name");
  for (const Row& r : rows) {
    MachineSummary m;
    m.name = as_text(r[0]);
    m.rig = as_text(r[1]);
    m.events = as_int(r[2]);
    m.wear_records = as_int(r[3]);
    m.fits = as_int(r[4]);
    m.residuals = as_int(r[5]);
    m.last_event_number = is_null(r[6]) ? -1 : as_int(r[6]);
    out.push_back(m);
  }
  return out;
}

std::vector<TrendPoint> FleetStore::trend(const std::string& machine) {
  std::vector<TrendPoint> out;
  const std::string where = machine.empty() ? "" : " AND m.name = ?";
  std::vector<Value> p;
  if (!machine.empty()) p.push_back(machine);
  for (const Row& r : db_->query("SELECT m.name, b.position, w.sequence, w.updated_unix_s, b.life_used_fraction"
                                 " FROM wear_bearings b JOIN wear_records w ON w.id = b.wear_id JOIN machines m ON m.id = w.machine_id"
                                 " WHERE 1 = 1" + where +
                                     " ORDER BY m.name, b.position, w.sequence, w.updated_unix_s, w.content_hash",
                                 p))
    out.push_back({as_text(r[0]), static_cast<int>(as_int(r[1])), "wear", as_int(r[2]), as_int(r[3]), as_double(r[4])});
  // Quick-look curves: running sums in one fixed order (the same on every engine).
  std::map<std::pair<std::string, int>, double> sum;
  for (const Row& r : db_->query("SELECT m.name, b.position, e.event_number, b.life_fraction"
                                 " FROM event_bearings b JOIN events e ON e.id = b.event_id JOIN machines m ON m.id = e.machine_id"
                                 " WHERE b.quick_look_valid = 1" + where +
                                     " ORDER BY m.name, b.position, e.event_number, e.content_hash",
                                 p)) {
    const auto key = std::make_pair(as_text(r[0]), static_cast<int>(as_int(r[1])));
    sum[key] += as_double(r[3]);
    out.push_back({key.first, key.second, "quick_look", as_int(r[2]), 0, sum[key]});
  }
  std::stable_sort(out.begin(), out.end(), [](const TrendPoint& a, const TrendPoint& b) {
    return std::tie(a.machine, a.bearing, a.source, a.order) < std::tie(b.machine, b.bearing, b.source, b.order);
  });
  return out;
}

std::vector<BearingStatus> FleetStore::nearest_budget() {
  std::map<std::pair<std::string, int>, BearingStatus> st;
  // Latest wear record per bearing (rows in order: the last one wins).
  for (const Row& r : db_->query("SELECT m.name, b.position, b.life_used_fraction, b.peak_force_n, w.event_count"
                                 " FROM wear_bearings b JOIN wear_records w ON w.id = b.wear_id JOIN machines m ON m.id = w.machine_id"
                                 " ORDER BY m.name, b.position, w.sequence, w.updated_unix_s, w.content_hash")) {
    BearingStatus s{as_text(r[0]), static_cast<int>(as_int(r[1])), "wear", as_double(r[2]), as_double(r[3]), as_int(r[4])};
    st[{s.machine, s.bearing}] = s;
  }
  std::map<std::pair<std::string, int>, BearingStatus> ql;
  for (const Row& r : db_->query("SELECT m.name, b.position, b.life_fraction, b.peak_force_n, b.quick_look_valid"
                                 " FROM event_bearings b JOIN events e ON e.id = b.event_id JOIN machines m ON m.id = e.machine_id"
                                 " ORDER BY m.name, b.position, e.event_number, e.content_hash")) {
    const auto key = std::make_pair(as_text(r[0]), static_cast<int>(as_int(r[1])));
    BearingStatus& s = ql[key];
    s.machine = key.first, s.bearing = key.second, s.source = "quick_look";
    ++s.events;
    if (as_int(r[4]) == 1) {
      s.life_used_fraction += as_double(r[2]);
      s.peak_force_n = std::max(s.peak_force_n, as_double(r[3]));
    }
  }
  for (const auto& [k, s] : ql)
    if (!st.count(k)) st[k] = s;
  std::vector<BearingStatus> out;
  for (const auto& [k, s] : st) out.push_back(s);
  std::stable_sort(out.begin(), out.end(), [](const BearingStatus& a, const BearingStatus& b) { return a.life_used_fraction > b.life_used_fraction; });
  return out;
}

std::int64_t FleetStore::count(const std::string& table) {
  static const char* const allowed[] = {"events", "event_bearings", "wear_records", "wear_bearings", "results", "machines"};
  if (std::find(std::begin(allowed), std::end(allowed), table) == std::end(allowed))
    throw std::invalid_argument("no fleet table '" + table + "'");
  return as_int(db_->query("SELECT COUNT(*) FROM " + table).at(0).at(0));
}

}  // namespace amb::host::fleet
