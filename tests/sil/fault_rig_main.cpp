// amb-fault-rig: faults and load while the loop runs, on this machine (tests/sil/fault_rig.hpp).
//   amb-fault-rig [--fault NAME|all] [--seconds S] [--recovery S] [--json] [--keep DIR]
// Prints one line per scenario (or the JSON of each); the table in docs/hardening.md comes
// from `amb-fault-rig --fault all --seconds 5 --json`.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "tests/sil/fault_rig.hpp"

namespace f = amb::sil::faults;

int main(int argc, char** argv) {
  f::RigOptions o;
  std::vector<f::Fault> faults;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "amb-fault-rig: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--fault") {
      const std::string v = value();
      f::Fault x;
      if (v == "all") faults = f::all_faults();
      else if (f::parse_fault(v, x)) faults.push_back(x);
      else {
        std::fprintf(stderr, "amb-fault-rig: unknown fault '%s'; one of:", v.c_str());
        for (f::Fault k : f::all_faults()) std::fprintf(stderr, " %s", f::to_string(k));
        std::fprintf(stderr, " all\n");
        return 2;
      }
    } else if (a == "--seconds") o.window_s = std::atof(value().c_str());
    else if (a == "--recovery") o.recovery_s = std::atof(value().c_str());
    else if (a == "--json") json = true;
    else if (a == "--keep") {
      o.dir = value();
      o.keep_dir = true;
    } else {
      std::printf("usage: amb-fault-rig [--fault NAME|all] [--seconds S] [--recovery S] [--json] [--keep DIR]\n");
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (faults.empty()) faults.push_back(f::Fault::none);
  int bad = 0;
  if (json) std::printf("[\n");
  for (size_t k = 0; k < faults.size(); ++k) {
    o.fault = faults[k];
    try {
      const f::RigResult r = f::run_fault_rig(o);
      if (json) std::printf("%s%s\n", r.json().c_str(), k + 1 < faults.size() ? "," : "");
      else
        std::printf("%-20s p99 quiet %6.1f us fault %6.1f us | overruns %llu / %llu | events frozen %llu written %llu "
                    "refused %llu dropped %llu lost %llu torn %llu wear-torn %d | %s -> %s (%s)\n",
                    f::to_string(r.fault), r.quiet.p99_us, r.faulted.p99_us,
                    static_cast<unsigned long long>(r.quiet.overruns), static_cast<unsigned long long>(r.faulted.overruns),
                    static_cast<unsigned long long>(r.events_frozen), static_cast<unsigned long long>(r.written),
                    static_cast<unsigned long long>(r.refused), static_cast<unsigned long long>(r.dropped_oldest),
                    static_cast<unsigned long long>(r.events_lost), static_cast<unsigned long long>(r.events_torn),
                    r.wear_corrupt_slots, r.state_after_fault.c_str(), r.state_at_end.c_str(), r.fault_counter.c_str());
      std::fflush(stdout);
      if (r.events_lost != 0 || r.events_torn != 0 || r.wear_corrupt_slots != 0) ++bad;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "amb-fault-rig: %s: %s\n", f::to_string(o.fault), e.what());
      ++bad;
    }
  }
  if (json) std::printf("]\n");
  return bad == 0 ? 0 : 1;
}
