// A small drop-envelope study through a one-node Slurm cluster started by the test: munged
// with its own key and socket, slurmctld and slurmd with a generated slurm.conf, all in a
// temporary directory on ports of their own; `amb-host envelope --slurm` writes and submits
// the job array, waits and collects. The figures must be identical to a local run's for
// identical cases, and the collection must reuse every case the array computed.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "host-tools/core/envelope/envelope_study.hpp"
#include "host-tools/core/envelope/slurm_array.hpp"
#include "tests/support/read_text.hpp"

namespace ev = amb::host::envelope;
namespace fs = std::filesystem;

namespace {

int sh(const std::string& cmd) {
  const int rc = std::system(cmd.c_str());
  return rc != -1 && WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

bool have(const char* exe) { return sh(std::string("command -v ") + exe + " > /dev/null 2>&1") == 0; }

/// munged + slurmctld + slurmd of their own; stopped (by their pid files) in the destructor.
class OneNodeCluster {
 public:
  explicit OneNodeCluster(const fs::path& dir) : dir_(dir) {
    fs::create_directories(dir_ / "state");
    fs::create_directories(dir_ / "spool");
    fs::create_directories(dir_ / "munge");
    fs::permissions(dir_ / "munge", fs::perms::owner_all);
    const fs::path key = dir_ / "munge" / "munge.key";
    if (sh("dd if=/dev/urandom of='" + key.string() + "' bs=1024 count=1 2>/dev/null && chmod 400 '" + key.string() + "'") != 0) {
      why_ = "cannot write the munge key";
      return;
    }
    const fs::path sock = dir_ / "munge" / "munge.socket";
    if (sh("munged --force --socket='" + sock.string() + "' --key-file='" + key.string() + "' --pid-file='" +
           (dir_ / "munge" / "munged.pid").string() + "' --log-file='" + (dir_ / "munge" / "munged.log").string() +
           "' --seed-file='" + (dir_ / "munge" / "seed").string() + "'") != 0) {
      why_ = "munged did not start: " + amb::test::read_text(dir_ / "munge" / "munged.log");
      return;
    }
    char host[256] = {};
    ::gethostname(host, sizeof host - 1);
    const std::string user = ::geteuid() == 0 ? "root" : (std::getenv("USER") ? std::getenv("USER") : "");
    const int port = 30000 + static_cast<int>(::getpid() % 9000) * 2;  // apart from the PostgreSQL test's 50000-59999
    const unsigned cpus = std::max(1u, std::thread::hardware_concurrency());
    conf_ = dir_ / "slurm.conf";
    std::ofstream c(conf_);
    c << "ClusterName=ambtest\nSlurmctldHost=" << host << "(127.0.0.1)\n"
      << "SlurmUser=" << user << "\nSlurmdUser=" << user << "\n"
      << "AuthType=auth/munge\nCredType=cred/munge\nAuthInfo=socket=" << sock.string() << "\n"
      << "SlurmctldPort=" << port << "\nSlurmdPort=" << port + 1 << "\n"
      << "StateSaveLocation=" << (dir_ / "state").string() << "\nSlurmdSpoolDir=" << (dir_ / "spool").string() << "\n"
      << "SlurmctldPidFile=" << (dir_ / "slurmctld.pid").string() << "\nSlurmdPidFile=" << (dir_ / "slurmd.pid").string() << "\n"
      << "SlurmctldLogFile=" << (dir_ / "slurmctld.log").string() << "\nSlurmdLogFile=" << (dir_ / "slurmd.log").string() << "\n"
      << "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\nSchedulerType=sched/builtin\n"
      << "SelectType=select/cons_tres\nSelectTypeParameters=CR_Core\nReturnToService=2\nMpiDefault=none\n"
      << "JobAcctGatherType=jobacct_gather/none\nAccountingStorageType=accounting_storage/none\n"
      << "NodeName=" << host << " NodeAddr=127.0.0.1 CPUs=" << cpus << " State=UNKNOWN\n"
      << "PartitionName=amb Nodes=ALL Default=YES MaxTime=INFINITE State=UP\n";
    c.close();
    ::setenv("SLURM_CONF", conf_.c_str(), 1);
    if (sh("slurmctld -f '" + conf_.string() + "'") != 0 || sh(std::string("slurmd -f '") + conf_.string() + "' -N " + host) != 0) {
      why_ = "slurmctld/slurmd did not start: " + amb::test::read_text(dir_ / "slurmctld.log") + amb::test::read_text(dir_ / "slurmd.log");
      return;
    }
    // Up when the node is idle.
    for (int i = 0; i < 120; ++i) {
      if (sh("sinfo -h -o %t 2>/dev/null | grep -q idle") == 0) {
        up_ = true;
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
    why_ = "the node never became idle: " + amb::test::read_text(dir_ / "slurmctld.log") + amb::test::read_text(dir_ / "slurmd.log");
  }
  ~OneNodeCluster() {
    for (const char* pf : {"slurmd.pid", "slurmctld.pid", "munge/munged.pid"}) {
      const std::string pid = amb::test::read_text(dir_ / pf);
      if (!pid.empty()) ::kill(static_cast<pid_t>(std::atol(pid.c_str())), SIGTERM);
    }
    std::this_thread::sleep_for(std::chrono::seconds(1));
    ::unsetenv("SLURM_CONF");
  }
  bool up() const { return up_; }
  const std::string& why() const { return why_; }

 private:
  fs::path dir_, conf_;
  bool up_ = false;
  std::string why_;
};

const char* const k_spec = R"([study]
board = "bath-amb-rig"
method = "lhs"
cases = 6
seed = 5
settle_s = 0.01
window_s = 0.03
[parameters]
speed_hz = { min = 15.0, max = 60.0 }
friction = { min = 0.05, max = 0.35 }
failed_channels = ["all", "A1+A2"]
)";

}  // namespace

TEST(EnvelopeSlurm, ArrayOnOneNodeClusterGivesTheLocalFigures) {
  for (const char* exe : {"munged", "slurmctld", "slurmd", "sbatch", "sinfo"})
    if (!have(exe)) GTEST_SKIP() << exe << " is missing: install the Debian packages slurm-wlm and munge";
  const fs::path dir = fs::temp_directory_path() / ("amb-envelope-slurm-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path spec_path = dir / "study.toml";
  std::ofstream(spec_path) << k_spec;
  const ev::StudySpec spec = ev::load_spec(spec_path.string());

  // The local reference.
  ev::StudyOptions lo;
  lo.out_dir = (dir / "local").string();
  const ev::StudySummary local = ev::run_study(spec, lo);
  ASSERT_EQ(local.cases_failed, 0u);

  nlohmann::json j;
  {
    OneNodeCluster cluster(dir / "cluster");
    ASSERT_TRUE(cluster.up()) << cluster.why();
    const fs::path out = dir / "slurm-out", log = dir / "envelope.log";
    const std::string cmd = std::string(AMB_HOST_EXE) + " envelope '" + spec_path.string() + "' --slurm --slurm-tasks 3 --threads 1 --out '" +
                            out.string() + "' --json > '" + (dir / "envelope.json").string() + "' 2> '" + log.string() + "'";
    ASSERT_EQ(sh(cmd), 0) << amb::test::read_text(log);
    j = nlohmann::json::parse(amb::test::read_text(dir / "envelope.json"));
    // Every task wrote its own output: the array really ran.
    int task_logs = 0;
    for (const auto& e : fs::directory_iterator(out / "slurm")) task_logs += e.path().filename().string().rfind("task-", 0) == 0;
    EXPECT_EQ(task_logs, 3);
  }
  EXPECT_EQ(j["cases"], 6);
  EXPECT_EQ(j["cases_reused"], 6) << "the collection simulated cases the array should have";
  EXPECT_EQ(j["cases_run"], 0);
  EXPECT_EQ(j["slurm"]["tasks"], 3);
  // Identical case files (the same figures) for identical cases.
  for (const auto& c : local.outcomes) {
    const nlohmann::json a = nlohmann::json::parse(amb::test::read_text(ev::case_file_path(lo.out_dir, c.hash)));
    const nlohmann::json b = nlohmann::json::parse(amb::test::read_text(ev::case_file_path((dir / "slurm-out").string(), c.hash)));
    nlohmann::json ra = a["result"], rb = b["result"];
    ra.erase("wall_s");
    rb.erase("wall_s");
    EXPECT_EQ(ra, rb) << "case " << c.index;
    EXPECT_EQ(a["key"], b["key"]);
  }
  std::printf("[slurm] 6 cases in 3 array tasks: array %.1f s wall\n", j["slurm"]["array_wall_s"].get<double>());
  fs::remove_all(dir);
}
