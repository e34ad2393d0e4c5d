#pragma once
// The wind-turbine high-speed-shaft records of ../shared/data/measured/windturbine-hss for the
// track-speed tests: where they are, their sample rate, and the truth (tach pulse rate / 2).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/test_paths.hpp"

namespace amb::test::windturbine {

/// Sample rate of the vibration and tach channels, Hz.
inline constexpr double k_fs_hz = 97656.0;
/// Tach pulses per shaft revolution (windturbine_test.cpp: PulsesPerRevolutionEvidence).
inline constexpr double k_pulses_per_rev = 2.0;

/// Folder of the records.
inline std::string record_dir() { return std::string(amb::test::shared_dir()) + "/data/measured/windturbine-hss"; }

/// The records' .mat files, sorted (empty if the folder is missing).
inline std::vector<std::string> records() {
  std::vector<std::string> files;
  const std::string dir = record_dir();
  if (!std::filesystem::is_directory(dir)) return files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".mat") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

/// Mean pulse rate (pulses/s) over [t0_s, t1_s] from the sorted pulse times `tach_s`; NaN if
/// fewer than 3 pulses fall inside.
inline double pulse_rate(const std::vector<double>& tach_s, double t0_s, double t1_s) {
  auto lo = std::lower_bound(tach_s.begin(), tach_s.end(), t0_s);
  auto hi = std::upper_bound(tach_s.begin(), tach_s.end(), t1_s);
  if (hi - lo < 3) return std::nan("");
  return static_cast<double>(hi - lo - 1) / (*(hi - 1) - *lo);
}

/// True shaft speed (Hz) over a window [t0_s, t1_s].
inline double shaft_speed_hz(const std::vector<double>& tach_s, double t0_s, double t1_s) {
  return pulse_rate(tach_s, t0_s, t1_s) / k_pulses_per_rev;
}

}  // namespace amb::test::windturbine
