#pragma once
// Running a drop-envelope study on a Slurm cluster as a job array: task K of N runs
// `amb-host envelope SPEC --shard K/N --out DIR` (the cases with index % N == K) on the
// cluster, writing the same case files a local run writes into the shared DIR; the
// submitting host waits for the array (sbatch --wait) and then collects (a local run that
// finds every finished case and simulates only what is missing). Restartable like a local run.
#include <string>

namespace amb::host::envelope {

struct SlurmOptions {
  std::string amb_host;          ///< absolute path of the amb-host executable the tasks run
  std::string spec;              ///< absolute path of the study spec
  std::string out_dir;           ///< absolute output directory (shared with the nodes)
  int tasks = 4;                 ///< array tasks (shards), >= 1
  int threads_per_task = 1;      ///< --threads of each task (and --cpus-per-task)
  std::string partition;         ///< empty: the cluster's default
  std::string sbatch = "sbatch"; ///< the sbatch command
  std::string check() const;     ///< empty when usable
};

/// The batch script (text) of the array.
std::string array_script(const SlurmOptions& o);

/// Write DIR/slurm/envelope.sbatch, submit it with `sbatch --wait` and wait for the array to
/// end. Returns the script path. Throws std::runtime_error naming what failed (sbatch's
/// output is in DIR/slurm/sbatch.log; each task's in DIR/slurm/task-JOB_K.out).
std::string submit_array_and_wait(const SlurmOptions& o);

}  // namespace amb::host::envelope
