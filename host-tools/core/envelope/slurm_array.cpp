#include "host-tools/core/envelope/slurm_array.hpp"

#include <sys/wait.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace amb::host::envelope {
namespace {

namespace fs = std::filesystem;

/// Single-quoted for sh.
std::string q(const std::string& s) {
  std::string o = "'";
  for (char c : s) o += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return o + "'";
}

}  // namespace

std::string SlurmOptions::check() const {
  if (tasks < 1 || tasks > 100000) return "--slurm-tasks must be in [1, 100000]";
  if (threads_per_task < 1 || threads_per_task > 1024) return "threads per task must be in [1, 1024]";
  for (const std::string* p : {&amb_host, &spec, &out_dir})
    if (p->empty() || !fs::path(*p).is_absolute()) return "amb-host, spec and output paths must be absolute (the nodes run them)";
  for (char c : partition)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == ','))
      return "partition name '" + partition + "' has characters other than letters, digits, _ - ,";
  return {};
}

std::string array_script(const SlurmOptions& o) {
  const std::string dir = (fs::path(o.out_dir) / "slurm").string();
  std::ostringstream s;
  s << "#!/bin/sh\n"
    << "# amb-host envelope as a Slurm job array: task K of " << o.tasks << " runs the cases with index % " << o.tasks
    << " == K.\n"
    << "#SBATCH --job-name=amb-envelope\n"
    << "#SBATCH --array=0-" << (o.tasks - 1) << "\n"
    << "#SBATCH --ntasks=1\n"
    << "#SBATCH --cpus-per-task=" << o.threads_per_task << "\n"
    << "#SBATCH --output=" << dir << "/task-%A_%a.out\n";
  if (!o.partition.empty()) s << "#SBATCH --partition=" << o.partition << "\n";
  s << "exec " << q(o.amb_host) << " envelope " << q(o.spec) << " --out " << q(o.out_dir) << " --shard \"$SLURM_ARRAY_TASK_ID/"
    << o.tasks << "\" --threads " << o.threads_per_task << " --quiet\n";
  return s.str();
}

std::string submit_array_and_wait(const SlurmOptions& o) {
  if (const std::string e = o.check(); !e.empty()) throw std::invalid_argument(e);
  const fs::path dir = fs::path(o.out_dir) / "slurm";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot be created: " + ec.message());
  const fs::path script = dir / "envelope.sbatch", log = dir / "sbatch.log";
  {
    std::ofstream f(script, std::ios::trunc);
    f << array_script(o);
    if (!f) throw std::runtime_error(script.string() + ": cannot be written");
  }
  // --wait: sbatch returns when every task of the array has ended (non-zero if any failed).
  const std::string cmd = o.sbatch + " --wait " + q(script.string()) + " > " + q(log.string()) + " 2>&1";
  const int rc = std::system(cmd.c_str());
  if (rc == -1 || !WIFEXITED(rc) || WEXITSTATUS(rc) != 0) {
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    throw std::runtime_error("sbatch --wait " + script.string() + " failed (exit " +
                             std::to_string(WIFEXITED(rc) ? WEXITSTATUS(rc) : -1) + "): " + ss.str());
  }
  return script.string();
}

}  // namespace amb::host::envelope
