#pragma once
// Running a drop-envelope study: the spec's cases on local threads (or one shard of them,
// for a Slurm array task), each case's figures kept in its own file DIR/cases/<hash>.json
// (written whole: temporary file + rename), so an interrupted study resumes where it stopped
// and a finished case is never simulated again. Then the table of all cases
// (DIR/results.csv, DIR/results.json), the worst cases and the HTML report with maps
// (DIR/report.html).
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host-tools/core/envelope/envelope_case.hpp"
#include "host-tools/core/envelope/envelope_spec.hpp"

namespace amb::host::envelope {

struct StudyOptions {
  std::string out_dir = "amb-out/envelope";  ///< where case files and results go
  int threads = 2;                           ///< worker threads, >= 1
  /// Run only the cases with index % shard_count == shard_index (a job-array task); the
  /// others are neither run nor required. 0 / 1: all cases.
  int shard_index = 0, shard_count = 1;
  /// Write results.csv, results.json and report.html (off for a shard).
  bool write_outputs = true;
  /// Called after each case (done, total of this run), from the worker threads but never
  /// concurrently. Optional.
  std::function<void(std::size_t, std::size_t)> progress;
  std::string check() const;  ///< empty when usable
};

struct CaseOutcome {
  std::size_t index = 0;    ///< position in expand_cases()
  CaseParams params;
  std::string hash;
  CaseResult result;
  bool done = false;        ///< result is valid (run now or reused)
  bool reused = false;      ///< read from its case file, not simulated
  std::string error;        ///< why the case failed (empty: it did not)
};

struct StudySummary {
  std::size_t cases = 0;            ///< cases of this run (the shard's, or all)
  std::size_t cases_run = 0;        ///< simulated now
  std::size_t cases_reused = 0;     ///< taken from existing case files
  std::size_t cases_failed = 0;
  double wall_s = 0.0;              ///< whole run, s
  double cases_per_s = 0.0;         ///< simulated cases / wall_s (0 when none was simulated)
  int threads = 0;
  std::vector<CaseOutcome> outcomes;       ///< this run's cases, by index
  std::vector<std::size_t> worst_force;    ///< positions in outcomes, largest peak force first
  std::vector<std::size_t> worst_life;     ///< positions in outcomes, largest life fraction first
  std::string csv_path, json_path, report_path;  ///< empty when not written
};

/// Run the study. Throws std::invalid_argument for bad options or a board that cannot be
/// loaded, std::runtime_error when the output directory cannot be written.
StudySummary run_study(const StudySpec& spec, const StudyOptions& options);

/// The summary as printed by `amb-host envelope --json` (keys: cases, cases_run,
/// cases_reused, cases_failed, wall_s, cases_per_s, threads, worst, worst_life, results_csv,
/// results_json, report).
nlohmann::json summary_json(const StudySpec& spec, const StudySummary& s);

/// Path of the case file of `hash` under `out_dir`.
std::string case_file_path(const std::string& out_dir, const std::string& hash);

}  // namespace amb::host::envelope
