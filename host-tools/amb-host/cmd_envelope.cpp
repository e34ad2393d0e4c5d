// amb-host envelope SPEC.toml: a parameter study of rotor drops (design envelope) on the
// board's drop model. Logic: host-tools/core/envelope (spec, case, study, report).
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/envelope/envelope_study.hpp"
#include "host-tools/core/envelope/slurm_array.hpp"
#include "host-tools/core/ui/progress_bar.hpp"

namespace {

namespace ev = amb::host::envelope;

struct Args {
  std::string spec;
  std::string out_dir = "amb-out/envelope";
  int threads = 2;
  std::string shard;  // "K/N"
  bool json = false;
  bool quiet = false;
  bool slurm = false;
  int slurm_tasks = 4;
  std::string slurm_partition;
};

int run(const Args& a) {
  ev::StudySpec spec;
  ev::StudyOptions o;
  o.out_dir = a.out_dir;
  o.threads = a.threads;
  if (!a.shard.empty()) {
    int k = -1, n = 0;
    char tail = 0;
    if (std::sscanf(a.shard.c_str(), "%d/%d%c", &k, &n, &tail) != 2) {
      std::fprintf(stderr, "amb-host envelope: error: --shard must be K/N (got '%s')\n", a.shard.c_str());
      return 1;
    }
    o.shard_index = k;
    o.shard_count = n;
    o.write_outputs = false;
  }
  if (const std::string e = o.check(); !e.empty()) {
    std::fprintf(stderr, "amb-host envelope: error: %s\n", e.c_str());
    return 1;
  }
  try {
    spec = ev::load_spec(a.spec);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "amb-host envelope: error: %s\n", e.what());
    return 1;
  }
  // On a Slurm cluster: the array computes the case files, then the local run below collects
  // them (and simulates only what the array did not finish).
  double slurm_wall_s = 0.0;
  if (a.slurm) {
    if (!a.shard.empty()) {
      std::fprintf(stderr, "amb-host envelope: error: --slurm and --shard do not go together (the array sets the shards)\n");
      return 1;
    }
    ev::SlurmOptions so;
    std::error_code ec;
    so.amb_host = std::filesystem::read_symlink("/proc/self/exe", ec).string();
    so.spec = std::filesystem::absolute(a.spec).string();
    so.out_dir = std::filesystem::absolute(a.out_dir).string();
    so.tasks = a.slurm_tasks;
    so.threads_per_task = a.threads;
    so.partition = a.slurm_partition;
    if (const std::string e = so.check(); !e.empty()) {
      std::fprintf(stderr, "amb-host envelope: error: %s\n", e.c_str());
      return 1;
    }
    const auto t0 = std::chrono::steady_clock::now();
    try {
      std::fprintf(stderr, "envelope: submitting a %d-task job array (sbatch --wait)\n", so.tasks);
      const std::string script = ev::submit_array_and_wait(so);
      slurm_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::fprintf(stderr, "envelope: array %s done in %.1f s; collecting\n", script.c_str(), slurm_wall_s);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "amb-host envelope: error: %s\n", e.what());
      return 2;
    }
  }
  // Progress on stderr (stdout may carry the JSON): a line every 10 % off a terminal.
  auto bar = std::make_shared<amb::host::ui::ProgressBar>("envelope", !a.quiet);
  o.progress = [bar](std::size_t done, std::size_t total) { bar->update(total ? static_cast<double>(done) / total : 1.0); };
  ev::StudySummary s;
  try {
    s = ev::run_study(spec, o);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "amb-host envelope: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "amb-host envelope: error: %s\n", e.what());
    return 2;
  }
  bar->finish(std::to_string(s.cases) + " cases");
  if (a.json) {
    nlohmann::json j = ev::summary_json(spec, s);
    if (a.slurm) j["slurm"] = {{"tasks", a.slurm_tasks}, {"array_wall_s", slurm_wall_s}};
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%zu cases: %zu simulated, %zu reused, %zu failed; %.2f s wall, %.2f cases/s on %d threads\n", s.cases,
                s.cases_run, s.cases_reused, s.cases_failed, s.wall_s, s.cases_per_s, s.threads);
    for (std::size_t k : s.worst_force) {
      const auto& c = s.outcomes[k];
      std::printf("  case %zu: %.1f Hz, mu %.3g, unbalance x%.3g, failed %s: peak %.1f N, whirl %s, life %.3e\n", c.index,
                  c.params.speed_hz, c.params.friction, c.params.unbalance_factor,
                  ev::channels_name(c.params.failed_channels).c_str(), c.result.peak_force_max_n(),
                  c.result.whirl_worst().c_str(), c.result.life_fraction_max());
    }
    if (!s.report_path.empty()) std::printf("results: %s, report: %s\n", s.csv_path.c_str(), s.report_path.c_str());
  }
  if (s.cases_failed > 0) std::fprintf(stderr, "amb-host envelope: %zu cases failed (see results)\n", s.cases_failed);
  return s.cases_failed > 0 ? 2 : 0;
}

void declare(CLI::App& sub, Args& args) {
  namespace hc = amb::host::cli;
  hc::input_file(sub.add_option("spec", args.spec, "study spec (TOML; docs/envelope.md)")->required(), "envelope-spec");
  hc::output_path(sub.add_option("--out", args.out_dir, "output directory: case files, results.csv/json, report.html"));
  hc::whole(sub.add_option("--threads", args.threads, "worker threads"), 1, 256);
  sub.add_option("--shard", args.shard, "run only cases with index % N == K (K/N; a job-array task; no results written)");
  sub.add_flag("--slurm", args.slurm,
               "run the cases as a Slurm job array (sbatch --wait; --out must be on storage the nodes share), then collect");
  hc::whole(sub.add_option("--slurm-tasks", args.slurm_tasks, "array tasks with --slurm; each uses --threads threads"), 1, 100000);
  sub.add_option("--slurm-partition", args.slurm_partition, "partition with --slurm (default: the cluster's)");
  sub.add_flag("--json", args.json, "print the summary as JSON");
  sub.add_flag("--quiet", args.quiet, "no progress lines on stderr");
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "envelope", "drop-envelope study: many drops over speed, friction, unbalance, clearance, offsets, failed channels", declare, run);

}  // namespace
