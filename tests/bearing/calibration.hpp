#pragma once
// The healthy records bearing-check's null is measured on, and the measurement itself
// (tests/bearing/null_calibration.cpp prints it; leave_one_out.cpp repeats it without the
// held-out record). Records: CWRU 1797_Normal (drive end DE_time on the 6205 at 48 kHz and
// decimated to 12 kHz, fan end FE_time on the 6203) and healthy records of the 4-DOF and 8-DOF
// models. Draws: each family's template at surrogate bases in every analysis band.
#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "host-tools/core/bearing/bearing_check.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "model/bearing/catalogue.hpp"
#include "tests/bearing/model_records.hpp"
#include "tests/support/test_paths.hpp"

namespace amb::test::bearing {

namespace hb = amb::host::bearing;

struct HealthyRecord {
  std::string name;
  std::vector<double> x;
  double fs_hz = 0.0;
  double speed_hz = 0.0;
  mb::BearingGeometry geometry;
};

/// Low-pass (windowed sinc, 127 taps, cut-off 0.8 x the new Nyquist) and keep every m-th sample.
inline std::vector<double> decimate(const std::vector<double>& x, int m) {
  const int taps = 127, half = taps / 2;
  const double fc = 0.8 * 0.5 / m;  // cycles per input sample
  std::vector<double> h(taps);
  double sum = 0;
  for (int i = 0; i < taps; ++i) {
    const double k = i - half;
    const double sinc = k == 0 ? 2 * fc : std::sin(2 * M_PI * fc * k) / (M_PI * k);
    h[static_cast<size_t>(i)] = sinc * (0.54 - 0.46 * std::cos(2 * M_PI * i / (taps - 1)));
    sum += h[static_cast<size_t>(i)];
  }
  std::vector<double> y;
  for (size_t n = half; n + half < x.size(); n += static_cast<size_t>(m)) {
    double v = 0;
    for (int i = 0; i < taps; ++i) v += h[static_cast<size_t>(i)] * x[n + static_cast<size_t>(i) - half];
    y.push_back(v / sum);
  }
  return y;
}

inline std::string cwru_path(const std::string& f) {
  return std::string(amb::test::shared_dir()) + "/data/measured/cwru/" + f + ".mat";
}

/// Calibration records. include_cwru: the CWRU healthy record's channels (left out when that
/// record is held out).
inline std::vector<HealthyRecord> calibration_records(bool include_cwru) {
  std::vector<HealthyRecord> out;
  const std::string normal = cwru_path("1797_Normal");
  if (include_cwru && std::filesystem::exists(normal)) {
    const double fs = amb::host::read_mat_scalar(normal, "fs"), rpm = amb::host::read_mat_scalar(normal, "RPM");
    const auto de = amb::host::read_mat_vector(normal, "DE_time");
    const auto fe = amb::host::read_mat_vector(normal, "FE_time");
    out.push_back({"1797_Normal DE 48k", de, fs, rpm / 60, *mb::find_bearing("6205")});
    out.push_back({"1797_Normal DE 12k", decimate(de, 4), fs / 4, rpm / 60, *mb::find_bearing("6205")});
    out.push_back({"1797_Normal FE 48k", fe, fs, rpm / 60, *mb::find_bearing("6203")});
  }
  // Model-made healthy records (settings disjoint from the validation tables' healthy ones).
  struct M {
    const char* model;
    const char* bearing;
    double speed_hz, fs_hz, duration_s, noise;
    int path;
  };
  for (const M& m : {M{"4dof", "6206", 25.0, 12000, 10, 0.5, 0}, M{"4dof", "6206", 40.0, 20000, 10, 1.0, 1},
                     M{"4dof", "6205", 29.0, 12000, 10, 0.3, 1}, M{"4dof", "6203", 45.0, 48000, 5, 2.0, 0},
                     M{"8dof", "6200", 33.3, 20000, 4, 0.5, 0}, M{"8dof", "6200", 20.0, 12000, 6, 1.0, 1}}) {
    RecordSpec s;
    s.model = m.model;
    s.bearing = m.bearing;
    s.speed_hz = m.speed_hz;
    s.fs_hz = m.fs_hz;
    s.duration_s = m.duration_s;
    s.noise_rel = m.noise;
    s.path = m.path;
    s.seed = 101;
    out.push_back({std::string(m.model) + " " + m.bearing + " healthy", make_record(s), s.fs_hz, s.speed_hz,
                   *mb::find_bearing(m.bearing)});
  }
  return out;
}

/// Draws of every family's score at surrogate bases on `records`, and the fitted nulls.
inline std::array<hb::NullFit, 4> calibrate(const std::vector<HealthyRecord>& records, hb::BearingCheckOptions o,
                                            std::array<std::vector<double>, 4>* draws_out = nullptr) {
  std::array<std::vector<double>, 4> draws;
  o.collect_surrogates = true;
  for (const auto& r : records) {
    const auto res = hb::check_bearing(r.x, r.fs_hz, r.speed_hz, r.geometry, o);
    for (size_t f = 0; f < 4; ++f)
      draws[f].insert(draws[f].end(), res.families[f].surrogates.begin(), res.families[f].surrogates.end());
  }
  std::array<hb::NullFit, 4> fits;
  for (size_t f = 0; f < 4; ++f) fits[f] = hb::fit_null(draws[f]);
  if (draws_out) *draws_out = draws;
  return fits;
}

}  // namespace amb::test::bearing
