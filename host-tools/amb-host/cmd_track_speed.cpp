// amb-host track-speed: tachless shaft speed of a recorded channel (STFT speed-ridge tracker).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "host-tools/core/tracking/track_speed.hpp"
#include "model/signal/window_function.hpp"

namespace {

struct Args {
  std::string mat, var, window = "hamming", orders, profile;
  bool fixed = false;  // a tracker flag was given: legacy per-run settings, no profile
  double fs_hz = 0.0;
  bool json = false;
  amb::host::TrackSpeedOptions opt{};
};

// Parses "1,2,3" into the tracker's order comb (weights 1 - 0.1 k). Empty: keep defaults.
bool parse_orders(const std::string& text, amb::model::signal::SpeedTrackerOptions& t, std::string& err) {
  if (text.empty()) return true;
  size_t n = 0, pos = 0;
  while (pos <= text.size()) {
    const size_t comma = text.find(',', pos);
    const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    if (n >= amb::model::signal::k_max_orders) {
      err = "--orders takes at most " + std::to_string(amb::model::signal::k_max_orders) + " values";
      return false;
    }
    try {
      size_t used = 0;
      t.orders[n] = std::stod(item, &used);
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      err = "--orders: '" + item + "' is not a number (expected e.g. 1,2,3)";
      return false;
    }
    t.order_weights[n] = 1.0 - 0.1 * static_cast<double>(n);
    ++n;
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  t.n_orders = n;
  return true;
}

int run(Args& a) {
  std::string err;
  if (!amb::model::signal::parse_window(a.window, a.opt.tracker.stft.window)) {
    std::fprintf(stderr, "amb-host track-speed: error: --window must be one of rectangular, hann, hamming, blackman; got '%s'\n",
                 a.window.c_str());
    return 1;
  }
  // Keep the chirp-rate step inside the acceleration limit when only the limit was lowered.
  a.opt.tracker.rate_step_hz_per_s = std::min(a.opt.tracker.rate_step_hz_per_s, a.opt.tracker.max_accel_hz_per_s);
  if (!a.profile.empty() && a.fixed) {
    std::fprintf(stderr, "amb-host track-speed: error: --profile replaces the per-run tracker flags; give one or the other\n");
    return 1;
  }
  if (!parse_orders(a.orders, a.opt.tracker, err)) {
    std::fprintf(stderr, "amb-host track-speed: error: %s\n", err.c_str());
    return 1;
  }
  if (std::string v = a.opt.validate(a.fs_hz); !v.empty()) {
    v = amb::host::cli::in_option_names(v, {{"stft.window_s * sample_rate_hz", "--window-s x the tracker rate"}, {"stft.sample_rate_hz", "the tracker rate"},
                                 {"stft.nfft", "--nfft"}, {"stft.window_s", "--window-s"}, {"stft.overlap", "--overlap"},
                                 {"min_speed_hz", "--min-hz"}, {"max_speed_hz", "--max-hz"}, {"initial_speed_hz", "--predict-hz"},
                                 {"search_half_band_hz", "--band-hz"}, {"max_accel_hz_per_s", "--max-accel"},
                                 {"n_orders", "the number of --orders"}, {"orders", "--orders"}, {"decimate", "--decimate"},
                                 {"fs", "--fs"}});
    std::fprintf(stderr, "amb-host track-speed: error: %s\n", v.c_str());
    return 1;
  }
  // The profile before the record: every input is checked before any work.
  amb::host::MachineProfile prof;
  const bool profiled = !a.fixed || !a.profile.empty();
  if (profiled) {
    try {
      prof = a.profile.empty() ? amb::host::default_machine_profile() : amb::host::load_machine_profile(a.profile);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "amb-host track-speed: error: --profile '%s': %s\n", a.profile.c_str(), e.what());
      return 1;
    }
  }
  std::vector<double> x;
  try {
    x = amb::host::read_mat_vector(a.mat, a.var);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "amb-host track-speed: error: --mat '%s' --var '%s': %s\n", a.mat.c_str(), a.var.c_str(), e.what());
    return 1;
  }
  amb::host::TrackSpeedResult r;
  try {
    if (profiled) {
      r = amb::host::track_speed_with_profile(x, a.fs_hz, prof);
    } else {
      r = amb::host::track_speed(x, a.fs_hz, a.opt);
    }
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "amb-host track-speed: error: %s\n", amb::host::cli::in_option_names(e.what(), {{"stft.window_s * sample_rate_hz", "--window-s x the tracker rate"}, {"stft.sample_rate_hz", "the tracker rate"},
                                 {"stft.nfft", "--nfft"}, {"stft.window_s", "--window-s"}, {"stft.overlap", "--overlap"},
                                 {"min_speed_hz", "--min-hz"}, {"max_speed_hz", "--max-hz"}, {"initial_speed_hz", "--predict-hz"},
                                 {"search_half_band_hz", "--band-hz"}, {"max_accel_hz_per_s", "--max-accel"},
                                 {"n_orders", "the number of --orders"}, {"orders", "--orders"}, {"decimate", "--decimate"},
                                 {"fs", "--fs"}}).c_str());
    return 1;
  }
  if (a.json) {
    std::printf("%s\n", amb::host::to_json(r).dump(1).c_str());
    return 0;
  }
  const double med = amb::host::median_speed_hz(r);
  std::printf("track-speed %s:%s  (%zu samples at %.1f Hz, decimated by %zu to %.1f Hz)\n", a.mat.c_str(),
              a.var.c_str(), x.size(), a.fs_hz, r.decimation, r.tracker_rate_hz);
  std::printf("  updates        %zu at %.1f per second (window %.3f s, latency %.3f s)\n", r.t_s.size(),
              r.summary.update_rate_hz, r.window_s, r.summary.latency_s);
  if (std::isfinite(med))
    std::printf("  median speed   %.3f Hz = %.1f rpm\n", med, 60.0 * med);
  else
    std::printf("  median speed   none (no valid update)\n");
  if (r.profiled)
    std::printf("  status         %s (%s)\n", r.status.c_str(), r.discovery.reason.c_str());
  std::printf("  lost           %.1f %% of updates (stated minimum %.2f Hz; %llu acquisitions, %llu losses)\n",
              100.0 * amb::host::lost_fraction(r), r.summary.stated_min_speed_hz,
              static_cast<unsigned long long>(r.summary.acquisitions), static_cast<unsigned long long>(r.summary.losses));
  return 0;
}

const amb::host::Registration reg{
    "track-speed", "tachless shaft speed from a vibration or 1x displacement channel (STFT speed ridge)",
    [](CLI::App& sub, std::function<int()>& run_fn) {
      auto a = std::make_shared<Args>();
      auto& t = a->opt.tracker;
      namespace hc = amb::host::cli;
      hc::input_file(sub.add_option("--mat", a->mat, "MATLAB .mat file")->required(), "mat");
      sub.add_option("--var", a->var, "variable name (struct fields with dots)")->required();
      hc::real(sub.add_option("--fs", a->fs_hz, "sample rate of the variable, Hz")->required(), 1.0, 1e7, "Hz");
      sub.add_flag("--json", a->json, "print t_s, speed_hz, confidence, lost (arrays) as JSON");
      sub.add_option("--window", a->window, "window: rectangular, hann, hamming (default), blackman");
      hc::positive(sub.add_option("--window-s", t.stft.window_s, "window length, s"), 60.0, "s");
      hc::real(sub.add_option("--overlap", t.stft.overlap, "overlap fraction"), 0.0, 0.99);
      hc::whole(sub.add_option("--nfft", t.stft.nfft, "FFT length, power of two"), 64, 1048576);
      hc::real(sub.add_option("--min-hz", t.min_speed_hz, "lowest shaft speed reported, Hz"), 0.0, 1e5, "Hz");
      hc::positive(sub.add_option("--max-hz", t.max_speed_hz, "highest shaft speed searched, Hz"), 1e5, "Hz");
      hc::real(sub.add_option("--predict-hz", t.initial_speed_hz, "initial speed guess, Hz (0: unknown, wide search)"), 0.0, 1e5, "Hz");
      hc::positive(sub.add_option("--band-hz", t.search_half_band_hz, "narrow-band half width around the prediction, Hz"), 1000.0, "Hz");
      hc::positive(sub.add_option("--max-accel", t.max_accel_hz_per_s, "largest |d speed/dt| followed, Hz/s"), 1e5, "Hz/s");
      sub.add_option("--orders", a->orders, "comb orders, e.g. 1,2,3,4 (default) or 3.568,7.136 for ball-pass lines");
      hc::whole(sub.add_option("--decimate", a->opt.decimate, "decimation factor: 0 auto, 1 none"), 0, 4096);
      hc::input_file(sub.add_option("--profile", a->profile,
                     "machine profile (TOML: speed range, acceleration limit, order comb or \"discover\"; "
                     "docs/tracking.md). Without it and without tracker flags the built-in default profile is used"),
                     "profile");
      run_fn = [a, &sub]() {
        for (const char* f : {"--window", "--window-s", "--overlap", "--nfft", "--min-hz", "--max-hz", "--predict-hz",
                              "--band-hz", "--max-accel", "--orders", "--decimate"})
          if (sub.count(f) > 0) a->fixed = true;
        return run(*a);
      };
    }};

}  // namespace
