// amb-host fleet add|list|trend|report: the fleet store of events, wear records, fits and
// residual results (SQLite file by default, PostgreSQL with --store postgresql://...).
// Logic: host-tools/core/fleet.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host-tools/core/sweep/sweep_event.hpp"
#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/fit/fit_result_json.hpp"
#include "host-tools/core/fleet/fleet_report.hpp"
#include "host-tools/core/fleet/fleet_schema.hpp"
#include "host-tools/core/fleet/fleet_store.hpp"

namespace {

namespace fl = amb::host::fleet;
namespace fs = std::filesystem;

struct Args {
  std::string store;
  std::vector<std::string> files;
  std::string machine;
  std::string out = "amb-out/fleet.html";
  bool json = false;
  bool create = false;
  CLI::App* add = nullptr;
  CLI::App* list = nullptr;
  CLI::App* trend = nullptr;
  CLI::App* report = nullptr;
};

std::string default_store() {
  const char* env = std::getenv("AMB_FLEET_STORE");
  return env && *env ? env : "amb-out/fleet.sqlite";
}

/// A JSON file found in a directory that is not a fit or residual result (e.g. a measured-event
/// sidecar or a scenario summary next to the events): skipped, not an error.
bool other_json(const std::string& path) {
  std::ifstream f(path);
  const nlohmann::json j = nlohmann::json::parse(f, nullptr, false);
  return j.is_discarded() || !j.is_object() || (!amb::host::fit::is_fit_result_json(j) && !j.contains("effects_added"));
}

/// Files to import: each file given, and the .ambe/.ambw/.json files in each directory given
/// (sorted; JSON other than fit/residual results skipped, and loop-sweep events: the store keeps
/// drop events, and a sweep's figures are amb-host sweep's).
std::vector<std::string> expand(const std::vector<std::string>& in, size_t& skipped) {
  std::vector<std::string> out;
  for (const std::string& p : in) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<std::string> found;
      for (const auto& e : fs::recursive_directory_iterator(p, ec)) {
        const std::string ext = e.path().extension().string();
        if (!e.is_regular_file()) continue;
        if (ext == ".ambe" && amb::host::sweep::is_sweep_event_file(e.path().string())) ++skipped;
        else if (ext == ".ambe" || ext == ".ambw") found.push_back(e.path().string());
        else if (ext == ".json" && other_json(e.path().string())) ++skipped;
        else if (ext == ".json") found.push_back(e.path().string());
      }
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
    } else {
      out.push_back(p);
    }
  }
  return out;
}

/// The store as shown on the page: a password in a URL or conninfo is replaced by ***.
std::string redacted(std::string url) {
  if (const auto at = url.find('@'), scheme = url.find("://"); scheme != std::string::npos && at != std::string::npos) {
    const auto colon = url.find(':', scheme + 3);
    if (colon != std::string::npos && colon < at) url.replace(colon + 1, at - colon - 1, "***");
  }
  for (auto p = url.find("password="); p != std::string::npos; p = url.find("password=", p + 1)) {
    const auto end = url.find_first_of(" &", p);
    url.replace(p + 9, (end == std::string::npos ? url.size() : end) - p - 9, "***");
  }
  return url;
}

nlohmann::json status_json(const fl::BearingStatus& s) {
  return {{"machine", s.machine}, {"bearing", s.bearing}, {"source", s.source}, {"life_used_fraction", s.life_used_fraction},
          {"peak_force_n", s.peak_force_n}, {"events", s.events}};
}

int run(const Args& a) {
  const std::string url = a.store.empty() ? default_store() : a.store;
  std::unique_ptr<fl::FleetStore> store;
  std::string created_store;  // a SQLite file this run creates (removed again when `add` refuses every file)
  try {
    if (url.find("://") == std::string::npos && url.rfind("postgres:", 0) != 0) {
      const std::string path = url.rfind("sqlite:", 0) == 0 ? url.substr(7) : url;
      // A store is made only when asked: a typo must not leave an empty store and an empty
      // listing behind. `add` may create it (it is about to fill it); the others need --create.
      if (!fs::exists(path) && !a.create && !a.add->parsed()) {
        std::fprintf(stderr,
                     "amb-host fleet: error: --store '%s' does not exist; check the name, or pass --create to start an "
                     "empty store there\n",
                     path.c_str());
        return 1;
      }
      if (fs::is_directory(path)) {
        std::fprintf(stderr, "amb-host fleet: error: --store '%s' is a directory, not a store file\n", path.c_str());
        return 1;
      }
      if (fs::path(path).has_parent_path()) fs::create_directories(fs::path(path).parent_path());
      if (!fs::exists(path) && !a.create) created_store = path;
    }
    store = std::make_unique<fl::FleetStore>(url);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "amb-host fleet: error: %s\n", e.what());
    return 2;
  }
  try {
    if (a.add->parsed()) {
      int bad = 0;
      nlohmann::json list = nlohmann::json::array();
      size_t added = 0, present = 0, skipped = 0;
      for (const std::string& f : expand(a.files, skipped)) {
        try {
          const fl::AddResult r = store->add_file(f, a.machine);
          (r.added ? added : present)++;
          list.push_back({{"path", r.path}, {"kind", r.kind}, {"machine", r.machine}, {"content_hash", r.content_hash}, {"added", r.added}});
          if (!a.json) std::printf("%s %s: %s (%s)\n", r.added ? "added" : "already stored", r.kind.c_str(), f.c_str(), r.machine.c_str());
        } catch (const std::invalid_argument& e) {
          ++bad;
          std::fprintf(stderr, "amb-host fleet add: error: %s\n", e.what());
        }
      }
      if (bad && added == 0 && present == 0) {
        // Bad input only: no summary on stdout, and no empty store left behind by `add`.
        store.reset();
        if (!created_store.empty()) {
          std::error_code ec;
          for (const char* suffix : {"", "-journal", "-wal", "-shm"}) fs::remove(created_store + suffix, ec);
        }
        std::fprintf(stderr, "fleet add: nothing added, %d file(s) refused\n", bad);
        return 1;
      }
      if (a.json)
        std::printf("%s\n", nlohmann::json({{"added", added}, {"already_stored", present}, {"errors", bad}, {"skipped_json", skipped}, {"files", list}}).dump(2).c_str());
      else
        std::fprintf(stderr, "fleet add: %zu added, %zu already stored, %d refused, %zu other files skipped (JSON other than fit/residual results, sweep events)\n", added, present,
                     bad, skipped);
      return bad ? 1 : 0;
    }
    if (a.list->parsed()) {
      const auto ms = store->machines();
      if (a.json) {
        nlohmann::json j = nlohmann::json::array();
        for (const auto& m : ms)
          j.push_back({{"machine", m.name}, {"rig", m.rig}, {"events", m.events}, {"wear_records", m.wear_records},
                       {"fits", m.fits}, {"residuals", m.residuals}, {"last_event_number", m.last_event_number}});
        std::printf("%s\n", nlohmann::json({{"schema_version", fl::schema_version(store->db())}, {"machines", j}}).dump(2).c_str());
      } else {
        std::printf("%-24s %-20s %7s %6s %5s %9s\n", "machine", "rig", "events", "wear", "fits", "residuals");
        for (const auto& m : ms)
          std::printf("%-24s %-20s %7lld %6lld %5lld %9lld\n", m.name.c_str(), m.rig.c_str(), static_cast<long long>(m.events),
                      static_cast<long long>(m.wear_records), static_cast<long long>(m.fits), static_cast<long long>(m.residuals));
      }
      return 0;
    }
    if (a.trend->parsed()) {
      const auto t = store->trend(a.machine);
      if (a.json) {
        nlohmann::json j = nlohmann::json::array();
        for (const auto& p : t)
          j.push_back({{"machine", p.machine}, {"bearing", p.bearing}, {"source", p.source}, {"order", p.order},
                       {"time_unix_s", p.time_unix_s}, {"life_used_fraction", p.life_used_fraction}});
        std::printf("%s\n", nlohmann::json({{"trend", j}}).dump(2).c_str());
      } else {
        for (const auto& p : t)
          std::printf("%-24s aux %d %-10s %8lld %12lld %10.6f\n", p.machine.c_str(), p.bearing + 1, p.source.c_str(),
                      static_cast<long long>(p.order), static_cast<long long>(p.time_unix_s), p.life_used_fraction);
      }
      return 0;
    }
    if (a.report->parsed()) {
      fl::FleetPageData d;
      d.store = redacted(url);
      d.machines = store->machines();
      d.nearest = store->nearest_budget();
      d.trend = store->trend();
      if (fs::path(a.out).has_parent_path()) fs::create_directories(fs::path(a.out).parent_path());
      const std::string tmp = a.out + ".tmp";
      {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        f << fl::render_fleet_page(d);
        if (!f) throw std::runtime_error(a.out + ": cannot be written");
      }
      fs::rename(tmp, a.out);
      if (a.json) {
        nlohmann::json n = nlohmann::json::array();
        for (const auto& s : d.nearest) n.push_back(status_json(s));
        std::printf("%s\n", nlohmann::json({{"nearest", n}, {"report", fs::absolute(a.out).string()}}).dump(2).c_str());
      } else {
        for (size_t i = 0; i < d.nearest.size() && i < 10; ++i) {
          const auto& s = d.nearest[i];
          std::printf("%-24s aux %d: %6.2f %% of budget (%s, %lld events)\n", s.machine.c_str(), s.bearing + 1,
                      100.0 * s.life_used_fraction, s.source.c_str(), static_cast<long long>(s.events));
        }
        std::printf("fleet page: %s\n", a.out.c_str());
      }
      return 0;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "amb-host fleet: error: %s\n", e.what());
    return 2;
  }
  return 1;
}

void declare(CLI::App& sub, Args& a) {
  sub.add_option("--store", a.store,
                 "store: a SQLite file (default $AMB_FLEET_STORE or amb-out/fleet.sqlite) or postgresql://... / postgres:CONNINFO");
  sub.add_flag("--create", a.create, "create the SQLite store when it does not exist (add creates it anyway)");
  sub.require_subcommand(1);
  a.add = sub.add_subcommand("add", "import .ambe events, .ambw wear records, fit/residual --json files (or directories of them)");
  a.add->add_option("files", a.files, "files or directories")->required();
  a.add->add_option("--machine", a.machine, "machine name (default: the board name in the file)");
  a.add->add_flag("--json", a.json, "print what was imported as JSON");
  a.list = sub.add_subcommand("list", "machines and what is stored for each");
  a.list->add_flag("--json", a.json, "print as JSON");
  a.trend = sub.add_subcommand("trend", "life used per aux bearing over time");
  a.trend->add_option("--machine", a.machine, "only this machine");
  a.trend->add_flag("--json", a.json, "print as JSON");
  a.report = sub.add_subcommand("report", "bearings nearest their budget and the HTML fleet page");
  amb::host::cli::output_path(a.report->add_option("--out", a.out, "fleet page"));
  a.report->add_flag("--json", a.json, "print as JSON");
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "fleet", "fleet store: events, wear records, fits and residual results per machine (SQLite or PostgreSQL)", declare, run);

}  // namespace
