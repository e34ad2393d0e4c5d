#include "host-tools/core/envelope/envelope_study.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "host-tools/core/envelope/envelope_report.hpp"

namespace amb::host::envelope {
namespace {

namespace fs = std::filesystem;

/// Write `text` to `path` whole: a temporary file in the same directory, then rename (a
/// reader sees the old file or the new one, never half of it).
void write_whole(const fs::path& path, const std::string& text) {
  std::ostringstream tmp_name;
  tmp_name << path.filename().string() << ".tmp." << ::getpid() << "." << std::this_thread::get_id();
  const fs::path tmp = path.parent_path() / tmp_name.str();
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error(tmp.string() + ": cannot be written");
    f << text;
    f.flush();
    if (!f) throw std::runtime_error(tmp.string() + ": write failed");
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot be written (rename failed)");
  }
}

/// A finished case file for exactly this key, or false.
bool read_case(const fs::path& path, const std::string& key, CaseResult& out) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return false;
  try {
    const nlohmann::json j = nlohmann::json::parse(f);
    if (!j.contains("key") || j["key"] != key) return false;  // hash collision or foreign file: run again
    out = from_case_json(j);
    return true;
  } catch (const std::exception&) {
    return false;  // unreadable or torn (cannot happen with write_whole, but a user may edit): run again
  }
}

std::string csv_number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

nlohmann::json case_entry(const CaseOutcome& o) {
  nlohmann::json j = {{"index", o.index}, {"hash", o.hash}, {"parameters", params_json(o.params)}};
  if (o.done) {
    j["peak_force_n"] = o.result.peak_force_max_n();
    j["whirl"] = o.result.whirl_worst();
    j["friction_energy_j"] = o.result.friction_energy_total_j();
    j["life_fraction"] = o.result.life_fraction_max();
    j["per_bearing"] = {{"peak_force_n", o.result.peak_force_n},
                        {"whirl", o.result.whirl},
                        {"whirl_hz", o.result.whirl_hz},
                        {"friction_energy_j", o.result.friction_energy_j},
                        {"life_fraction", o.result.life_fraction},
                        {"contact_time_s", o.result.contact_time_s}};
    j["speed_end_hz"] = o.result.speed_end_hz;
    j["solver_unconverged"] = o.result.solver_unconverged;
  } else {
    j["error"] = o.error;
  }
  return j;
}

std::string results_csv(const StudySummary& s) {
  std::string t =
      "index,hash,speed_hz,friction,unbalance_factor,clearance_m,offset_x_m,offset_y_m,failed_channels,"
      "peak_force_n,whirl,friction_energy_j,life_fraction,peak_force_a_n,peak_force_b_n,whirl_a,whirl_b,"
      "whirl_a_hz,whirl_b_hz,friction_energy_a_j,friction_energy_b_j,life_fraction_a,life_fraction_b,"
      "contact_time_a_s,contact_time_b_s,speed_end_hz,error\n";
  for (const CaseOutcome& o : s.outcomes) {
    const CaseParams& c = o.params;
    const CaseResult& r = o.result;
    t += std::to_string(o.index) + "," + o.hash + "," + csv_number(c.speed_hz) + "," + csv_number(c.friction) + "," +
         csv_number(c.unbalance_factor) + "," + csv_number(c.clearance_m) + "," + csv_number(c.offset_x_m) + "," +
         csv_number(c.offset_y_m) + "," + channels_name(c.failed_channels) + ",";
    if (o.done) {
      t += csv_number(r.peak_force_max_n()) + "," + r.whirl_worst() + "," + csv_number(r.friction_energy_total_j()) + "," +
           csv_number(r.life_fraction_max()) + "," + csv_number(r.peak_force_n[0]) + "," + csv_number(r.peak_force_n[1]) + "," +
           r.whirl[0] + "," + r.whirl[1] + "," + csv_number(r.whirl_hz[0]) + "," + csv_number(r.whirl_hz[1]) + "," +
           csv_number(r.friction_energy_j[0]) + "," + csv_number(r.friction_energy_j[1]) + "," +
           csv_number(r.life_fraction[0]) + "," + csv_number(r.life_fraction[1]) + "," + csv_number(r.contact_time_s[0]) +
           "," + csv_number(r.contact_time_s[1]) + "," + csv_number(r.speed_end_hz) + ",\n";
    } else {
      std::string e = o.error;
      std::replace(e.begin(), e.end(), ',', ';');
      std::replace(e.begin(), e.end(), '\n', ' ');
      t += ",,,,,,,,,,,,,,,," + e + "\n";
    }
  }
  return t;
}

}  // namespace

std::string StudyOptions::check() const {
  if (threads < 1 || threads > 1024) return "threads must be in [1, 1024]";
  if (shard_count < 1) return "shard count must be >= 1";
  if (shard_index < 0 || shard_index >= shard_count) return "shard index must be in [0, shard count)";
  if (out_dir.empty()) return "output directory must not be empty";
  return {};
}

std::string case_file_path(const std::string& out_dir, const std::string& hash) {
  return (fs::path(out_dir) / "cases" / (hash + ".json")).string();
}

StudySummary run_study(const StudySpec& spec, const StudyOptions& o) {
  if (const std::string e = o.check(); !e.empty()) throw std::invalid_argument(e);
  const auto t0 = std::chrono::steady_clock::now();
  board::BoardConfig board;
  try {
    board = board::load_board(spec.settings.board);
  } catch (const std::exception& e) {
    throw std::invalid_argument(spec.source + ": study.board: " + e.what());
  }
  std::error_code ec;
  fs::create_directories(fs::path(o.out_dir) / "cases", ec);
  if (ec) throw std::runtime_error(o.out_dir + ": cannot create the output directory: " + ec.message());

  StudySummary s;
  s.threads = o.threads;
  const std::vector<CaseParams> all = expand_cases(spec);
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (static_cast<int>(i % static_cast<std::size_t>(o.shard_count)) != o.shard_index) continue;
    CaseOutcome c;
    c.index = i;
    c.params = all[i];
    c.hash = case_hash(spec.settings, all[i]);
    s.outcomes.push_back(std::move(c));
  }
  s.cases = s.outcomes.size();

  const std::shared_ptr<const model::RigModel> rig_model = model::RigModel::make(board.plant);  // once per study
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  std::mutex progress_mutex;
  auto worker = [&] {
    for (;;) {
      const std::size_t k = next.fetch_add(1);
      if (k >= s.outcomes.size()) return;
      CaseOutcome& c = s.outcomes[k];
      const std::string path = case_file_path(o.out_dir, c.hash);
      const std::string key = case_key(spec.settings, c.params);
      if (read_case(path, key, c.result)) {
        c.done = c.reused = true;
      } else {
        try {
          c.result = run_case(board, rig_model, spec.settings, c.params);
          write_whole(path, to_case_json(spec.settings, c.params, c.result).dump(1) + "\n");
          c.done = true;
        } catch (const std::exception& e) {
          c.error = e.what();
        }
      }
      std::lock_guard<std::mutex> lock(progress_mutex);
      ++done;
      if (o.progress) o.progress(done, s.outcomes.size());
    }
  };
  const int n_threads = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(o.threads), std::max<std::size_t>(1, s.outcomes.size())));
  std::vector<std::thread> pool;
  for (int t = 1; t < n_threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();

  for (const CaseOutcome& c : s.outcomes) {
    if (!c.done) ++s.cases_failed;
    else if (c.reused) ++s.cases_reused;
    else ++s.cases_run;
  }
  std::vector<std::size_t> ok;
  for (std::size_t k = 0; k < s.outcomes.size(); ++k)
    if (s.outcomes[k].done) ok.push_back(k);
  const std::size_t n_worst = std::min<std::size_t>(ok.size(), static_cast<std::size_t>(spec.worst_count));
  // Ties broken by case index, so the list does not depend on the thread schedule.
  s.worst_force = ok;
  std::stable_sort(s.worst_force.begin(), s.worst_force.end(), [&](std::size_t a, std::size_t b) {
    return s.outcomes[a].result.peak_force_max_n() > s.outcomes[b].result.peak_force_max_n();
  });
  s.worst_force.resize(n_worst);
  s.worst_life = ok;
  std::stable_sort(s.worst_life.begin(), s.worst_life.end(), [&](std::size_t a, std::size_t b) {
    return s.outcomes[a].result.life_fraction_max() > s.outcomes[b].result.life_fraction_max();
  });
  s.worst_life.resize(n_worst);

  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  s.cases_per_s = s.cases_run > 0 && s.wall_s > 0.0 ? static_cast<double>(s.cases_run) / s.wall_s : 0.0;

  if (o.write_outputs) {
    const fs::path dir(o.out_dir);
    s.csv_path = (dir / "results.csv").string();
    s.json_path = (dir / "results.json").string();
    s.report_path = (dir / "report.html").string();
    write_whole(s.csv_path, results_csv(s));
    nlohmann::json cases = nlohmann::json::array();
    for (const CaseOutcome& c : s.outcomes) cases.push_back(case_entry(c));
    nlohmann::json all_j = summary_json(spec, s);
    all_j["cases_table"] = std::move(cases);
    write_whole(s.json_path, all_j.dump(1) + "\n");
    write_whole(s.report_path, render_envelope_report(spec, s));
  }
  return s;
}

nlohmann::json summary_json(const StudySpec& spec, const StudySummary& s) {
  nlohmann::json worst = nlohmann::json::array(), worst_life = nlohmann::json::array();
  for (std::size_t k : s.worst_force) worst.push_back(case_entry(s.outcomes[k]));
  for (std::size_t k : s.worst_life) worst_life.push_back(case_entry(s.outcomes[k]));
  return {{"spec", spec.source},
          {"board", spec.settings.board},
          {"method", spec.method},
          {"cases", s.cases},
          {"cases_run", s.cases_run},
          {"cases_reused", s.cases_reused},
          {"cases_failed", s.cases_failed},
          {"wall_s", s.wall_s},
          {"cases_per_s", s.cases_per_s},
          {"threads", s.threads},
          {"worst", worst},
          {"worst_life", worst_life},
          {"results_csv", s.csv_path},
          {"results_json", s.json_path},
          {"report", s.report_path}};
}

}  // namespace amb::host::envelope
