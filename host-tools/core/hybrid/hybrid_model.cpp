#include "host-tools/core/hybrid/hybrid_model.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <tuple>

#include <nlohmann/json.hpp>

#include "host-tools/core/io/mat_file.hpp"

namespace amb::host::hybrid {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Run f(i) for i in [0, n) on `threads` workers (deterministic results: each i writes its own slot).
void parallel_for(size_t n, int threads, const std::function<void(size_t)>& f) {
  const auto workers = static_cast<size_t>(std::max(1, std::min<int>(threads, static_cast<int>(n))));
  if (workers <= 1) {
    for (size_t i = 0; i < n; ++i) f(i);
    return;
  }
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  std::vector<std::thread> pool;
  for (size_t w = 0; w < workers; ++w)
    pool.emplace_back([&] {
      for (size_t i = next++; i < n; i = next++) {
        try {
          f(i);
        } catch (...) {
          std::lock_guard<std::mutex> lock(error_mutex);
          if (!error) error = std::current_exception();
        }
      }
    });
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

// Seed of the simulated sensor noise of one (state, operating point): a fixed function of the
// model seed and the case, so a prediction repeats the training simulation of the same case.
uint64_t case_seed(uint64_t seed, BearingState s, const OperatingPoint& op) {
  uint64_t h = seed * 0x9E3779B97F4A7C15ULL;
  h ^= static_cast<uint64_t>(s) + 0x632BE59BD9B4E019ULL + (h << 6) + (h >> 2);
  h ^= static_cast<uint64_t>(std::llround(op.speed_rpm * 1000.0)) + (h << 6) + (h >> 2);
  h ^= static_cast<uint64_t>(std::llround(op.load * 1000.0)) + (h << 6) + (h >> 2);
  return h;
}

Spectra physics_spectra(const TrainOptions& o, BearingState s, const OperatingPoint& op) {
  const auto x = simulate_drive_end(o.rig, s, op, o.sim_fs_hz, o.sim_duration_s, case_seed(o.seed, s, op));
  return compute_spectra(x, o.sim_fs_hz, o.spectra, speed_scales(o.speed_uncertainty, o.speed_points));
}

std::vector<double> power(const std::vector<double>& amp, double scale) {
  std::vector<double> p(amp.size());
  for (size_t i = 0; i < amp.size(); ++i) p[i] = amp[i] * amp[i] / scale;
  return p;
}

// Envelope amplitudes of the correction's domain (normalised power -> amplitude).
std::vector<double> amplitude(const std::vector<double>& pw) {
  std::vector<double> a(pw.size());
  for (size_t i = 0; i < pw.size(); ++i) a[i] = std::sqrt(std::max(0.0, pw[i]));
  return a;
}


}  // namespace

// The model file's option blocks, one field list each (nlohmann: to_json and from_json; a
// missing key throws).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SpectralOptions, psd_df_hz, psd_min_hz, psd_max_hz, psd_bin_min_hz, env_band_low_hz, env_band_high_hz, env_df_hz, env_min_hz, env_max_hz, env_bin_min_hz, rel_bin_width, psd_floor_rel)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(RigParams, drive_end_bearing, fan_end_bearing, drive_end_contact_angle_rad, bearing_mass_kg, disc_mass_kg, shaft_stiffness_n_per_m, bearing_damping_n_s_per_m, disc_damping_n_s_per_m, radial_clearance_m, defect_width_m, unbalance_eccentricity_m, housing_mass_kg, sensor_angle_rad, outer_defect_angle_rad, sensor_noise_rel, settle_s, steps_per_sample)

TrainOptions::TrainOptions() {
  // Log PSD: narrow transfer hats (6 grid bins = 6 % above 400 Hz: the width of a damped
  // housing resonance), physics split into broadband level and lines.
  psd_map.transfer_spacing_bins = 6;
  psd_map.split_local = true;
  psd_map.lambda_transfer = 0.01;
  psd_map.lambda_physics = 0.1;
  // Envelope: almost all of it is speed-locked lines, so the transfer part is kept coarse
  // (32 bins) so that it cannot memorise the training lines; the physics spectrum itself is
  // the feature (power domain: a line's measured power ~ gain x its simulated power).
  env_map.transfer_spacing_bins = 32;
  env_map.split_local = false;
  env_map.lambda_transfer = 0.01;
  env_map.lambda_physics = 0.1;
}

bool TrainOptions::valid(std::string* why) const {
  auto fail = [&](const std::string& m) {
    if (why) *why = m;
    return false;
  };
  std::string w;
  if (!spectra.valid(&w)) return fail("spectra: " + w);
  if (!psd_map.valid(&w)) return fail("psd map: " + w);
  if (!env_map.valid(&w)) return fail("envelope map: " + w);
  if (!rig.valid(&w)) return fail("rig: " + w);
  if (!(segment_s >= spectra.min_record_s())) return fail("segment_s must be >= " + std::to_string(spectra.min_record_s()) + " s");
  if (!(sim_duration_s >= spectra.min_record_s()) || sim_duration_s > 60) return fail("sim_duration_s out of range");
  if (!(sim_fs_hz / 2 > std::max(spectra.psd_max_hz, spectra.env_band_high_hz))) return fail("sim_fs_hz too low for the grids");
  if (!(speed_uncertainty >= 0) || !(speed_uncertainty < 0.1)) return fail("speed_uncertainty in [0, 0.1)");
  if (speed_points < 1 || speed_points > 101) return fail("speed_points in [1, 101]");
  if (threads < 1 || threads > 64) return fail("threads in [1, 64]");
  if (ensemble_members < 0 || ensemble_members > 256) return fail("ensemble_members in [0, 256]");
  return true;
}

void load_record(Record& r) {
  r.signal = read_mat_vector(r.path, r.var);
  if (!(r.fs_hz > 0)) {
    try {
      r.fs_hz = read_mat_scalar(r.path, "fs");
    } catch (const std::exception&) {
      throw std::invalid_argument(r.path + ": no sample rate given and no 'fs' variable in the file");
    }
  }
  if (!(r.fs_hz > 0)) throw std::invalid_argument(r.path + ": sample rate must be > 0");
  for (double v : r.signal)
    if (!std::isfinite(v)) throw std::invalid_argument(r.path + ": signal holds a non-finite value");
}

HybridModel train_hybrid(const std::vector<Record>& records, const TrainOptions& o_in,
                         const std::function<void(const std::string&)>& progress) {
  const auto t0 = Clock::now();
  auto step = [&](const std::string& what) {
    if (progress) {
      char b[48];
      std::snprintf(b, sizeof b, "[%6.2f s] ", seconds_since(t0));
      progress(b + what);
    }
  };
  std::string why;
  if (!o_in.valid(&why)) throw std::invalid_argument("train options: " + why);
  if (records.empty()) throw std::invalid_argument("no training record");
  HybridModel m;
  m.options = o_in;
  TrainOptions& o = m.options;
  for (const auto& r : records) {
    if (r.signal.empty()) throw std::invalid_argument(r.path + ": signal not loaded");
    if (!(r.op.speed_rpm > 0) || !(r.op.load >= 0)) throw std::invalid_argument(r.path + ": speed must be > 0 and load >= 0");
    if (static_cast<double>(r.signal.size()) / r.fs_hz < o.segment_s)
      throw std::invalid_argument(r.path + ": shorter than one training segment");
  }

  // 1. Kinematic calibration from the training records only.
  step("kinematic calibration of the drive-end bearing");
  if (o.calibrate_kinematics) {
    std::vector<CalibrationRecord> cal;
    for (const auto& r : records) cal.push_back({&r.signal, r.fs_hz, r.state, r.op.speed_rpm});
    m.calibration = calibrate_kinematics(cal, o.spectra.env_band_low_hz, o.spectra.env_band_high_hz, o.rig);
  } else {
    m.calibration.note = "kinematic calibration off: catalogue geometry";
  }

  // 2. Physics at every distinct (state, operating point) of the training set.
  using Key = std::tuple<int, double, double>;
  std::map<Key, size_t> case_index;
  std::vector<std::pair<BearingState, OperatingPoint>> cases;
  for (const auto& r : records) {
    const Key k{static_cast<int>(r.state), r.op.speed_rpm, r.op.load};
    if (case_index.emplace(k, cases.size()).second) cases.emplace_back(r.state, r.op);
  }
  std::vector<Spectra> phys(cases.size());
  step("physics: " + std::to_string(cases.size()) + " simulated case(s); spectra of the training segments");
  // 3. Measured spectra of every segment.
  std::vector<std::pair<size_t, std::vector<double>>> segments;  // (record, samples)
  for (size_t i = 0; i < records.size(); ++i)
    for (auto& s : split_segments(records[i].signal, records[i].fs_hz, o.segment_s)) segments.emplace_back(i, std::move(s));
  std::vector<Spectra> meas(segments.size());
  parallel_for(cases.size() + segments.size(), o.threads, [&](size_t i) {
    if (i < cases.size()) {
      phys[i] = physics_spectra(o, cases[i].first, cases[i].second);
    } else {
      const auto& [ri, x] = segments[i - cases.size()];
      meas[i - cases.size()] = compute_spectra(x, records[ri].fs_hz, o.spectra);
    }
  });

  // Envelope power normalisations (training means), so the map's numbers are O(1).
  auto mean_power = [](const std::vector<Spectra>& v) {
    double s = 0;
    size_t n = 0;
    for (const auto& sp : v)
      for (double a : sp.env) {
        s += a * a;
        ++n;
      }
    return n > 0 && s > 0 ? s / static_cast<double>(n) : 1.0;
  };
  m.physics_env_scale = mean_power(phys);
  m.measured_env_scale = mean_power(meas);

  // 4. Reference spectra per training case (mean over its segments) and, for every training
  // segment, the reference of its case without that segment (leave-one-segment-out: the map
  // learns how far the transported reference predicts a segment it has not seen; a case with
  // one segment uses its own).
  const auto psd_c = centres(psd_grid(o.spectra));
  const auto env_c = centres(env_grid(o.spectra));
  const auto scales = speed_scales(o.speed_uncertainty, o.speed_points);
  std::vector<size_t> seg_case(segments.size());
  std::vector<std::vector<double>> y_psd(segments.size()), y_env(segments.size());
  std::vector<std::vector<double>> sum_psd(cases.size(), std::vector<double>(psd_c.size(), 0.0)),
      sum_env(cases.size(), std::vector<double>(env_c.size(), 0.0));
  std::vector<int> case_segments(cases.size(), 0);
  for (size_t i = 0; i < segments.size(); ++i) {
    const Record& r = records[segments[i].first];
    seg_case[i] = case_index.at(Key{static_cast<int>(r.state), r.op.speed_rpm, r.op.load});
    y_psd[i] = meas[i].log_psd;
    y_env[i] = power(meas[i].env, m.measured_env_scale);
    for (size_t k = 0; k < psd_c.size(); ++k) sum_psd[seg_case[i]][k] += y_psd[i][k];
    for (size_t k = 0; k < env_c.size(); ++k) sum_env[seg_case[i]][k] += y_env[i][k];
    ++case_segments[seg_case[i]];
  }
  for (size_t c = 0; c < cases.size(); ++c) {
    ReferenceSpectra ref;
    ref.state = cases[c].first;
    ref.op = cases[c].second;
    ref.segments = case_segments[c];
    ref.log_psd = sum_psd[c];
    ref.env_power = sum_env[c];
    for (double& v : ref.log_psd) v /= std::max(1, ref.segments);
    for (double& v : ref.env_power) v /= std::max(1, ref.segments);
    m.references.push_back(std::move(ref));
  }
  const int h = o.psd_map.local_halfwidth_bins;

  // 5. The maps.
  step("learned maps (hybrid, 8-DOF only, data only)");
  std::vector<MapInput> in_psd, in_env, in_psd_sim, in_env_sim, in_data;
  std::vector<size_t> seg_count(records.size(), 0);
  for (size_t i = 0; i < segments.size(); ++i) {
    const Record& r = records[segments[i].first];
    ++seg_count[segments[i].first];
    const size_t c = seg_case[i];
    const Spectra& p = phys[c];
    const int n = case_segments[c];
    std::vector<double> loo_psd = sum_psd[c], loo_env = sum_env[c];
    for (size_t k = 0; k < loo_psd.size(); ++k) loo_psd[k] = n > 1 ? (loo_psd[k] - y_psd[i][k]) / (n - 1) : y_psd[i][k];
    for (size_t k = 0; k < loo_env.size(); ++k) loo_env[k] = n > 1 ? (loo_env[k] - y_env[i][k]) / (n - 1) : y_env[i][k];
    MapInput d;
    d.state = static_cast<int>(r.state);
    d.op = {r.op.speed_rpm, r.op.load};
    MapInput hp = d, he = d, hps = d, hes = d;
    hps.physics = {p.log_psd};
    hes.physics = {power(p.env, m.physics_env_scale)};
    hp.physics = hps.physics;
    he.physics = hes.physics;
    // Cross-fitting across operating points: if the state was also trained at another speed,
    // the segment's transport input is the nearest such case moved to the segment's speed, so
    // the map learns from real speed changes how far to trust the transported spectrum.
    // Otherwise its own case without it (ratio 1).
    const ReferenceSpectra* other = nullptr;
    double best = 0.0;
    for (const auto& ref : m.references) {
      if (ref.state != r.state || std::abs(ref.op.speed_rpm - r.op.speed_rpm) <= 1e-9 * r.op.speed_rpm) continue;
      const double dist = std::abs(std::log(r.op.speed_rpm / ref.op.speed_rpm)) + 1e-6 * std::abs(r.op.load - ref.op.load);
      if (other == nullptr || dist < best) {
        other = &ref;
        best = dist;
      }
    }
    const double ratio = other ? r.op.speed_rpm / other->op.speed_rpm : 1.0;
    if (o.transport_log_psd)
      hp.physics.push_back(transport_log_psd(other ? other->log_psd : loo_psd, psd_c, ratio, scales, h));
    if (o.transport_env) he.physics.push_back(transport_env(other ? other->env_power : loo_env, env_c, ratio, scales));
    in_data.push_back(d);
    in_psd.push_back(std::move(hp));
    in_env.push_back(std::move(he));
    in_psd_sim.push_back(std::move(hps));
    in_env_sim.push_back(std::move(hes));
  }
  SpectralMapOptions po = o.psd_map, eo = o.env_map;
  po.use_physics = eo.use_physics = true;
  po.physics_channels = o.transport_log_psd ? 2 : 1;
  eo.physics_channels = o.transport_env ? 2 : 1;
  SpectralMapOptions ps = po, es = eo;
  ps.physics_channels = es.physics_channels = 1;
  SpectralMapOptions pd = po, ed = eo;
  pd.use_physics = ed.use_physics = false;
  pd.physics_channels = ed.physics_channels = 1;
  o.psd_map = po;
  o.env_map = eo;
  m.psd_hybrid.train(in_psd, y_psd, psd_c, po);
  m.psd_hybrid_sim.train(in_psd_sim, y_psd, psd_c, ps);
  m.psd_data_only.train(in_data, y_psd, psd_c, pd);
  m.env_hybrid.train(in_env, y_env, env_c, eo);
  m.env_hybrid_sim.train(in_env_sim, y_env, env_c, es);
  m.env_data_only.train(in_data, y_env, env_c, ed);

  // 6. The correction of the interpolated transport (issue 34), when some state was trained at
  // two or more operating points. Each training case's inputs come from the OTHER operating
  // points of its state (cross-fitted: its own records never enter its inputs); its targets are
  // its segments. Cases whose state has no other operating point carry no information on a
  // speed change and are left out.
  if (o.correction) {
    std::vector<OperatingPoint> points;
    auto point_index = [&](const OperatingPoint& op) {
      for (size_t i = 0; i < points.size(); ++i)
        if (points[i].speed_rpm == op.speed_rpm && points[i].load == op.load) return static_cast<int>(i);
      points.push_back(op);
      return static_cast<int>(points.size() - 1);
    };
    std::vector<CorrectionCase> cp, ce;
    for (size_t c = 0; c < cases.size(); ++c) {
      const auto& [st, op] = cases[c];
      // One correction case per other operating point of the state: its training spectrum
      // moved to this case's speed (single-source transports; prediction corrects each source
      // of the interpolation and then interpolates).
      const int g = point_index(op);
      for (const auto& src : all_sources(m.references, st, op, psd_c, env_c, scales, h, op)) {
        CorrectionCase a, e;
        a.group = e.group = g;
        a.speed_change = e.speed_change = std::abs(std::log(op.speed_rpm / src.speed_rpm));
        a.base = src.moved_log_psd;
        a.fixed = src.log_psd;
        a.sim = phys[c].log_psd;
        e.base = amplitude(src.moved_env_power);
        e.fixed = amplitude(src.env_power);
        e.sim = amplitude(power(phys[c].env, m.physics_env_scale));
        for (size_t i = 0; i < segments.size(); ++i)
          if (seg_case[i] == c) {
            a.segments.push_back(y_psd[i]);
            e.segments.push_back(amplitude(y_env[i]));
          }
        cp.push_back(std::move(a));
        ce.push_back(std::move(e));
      }
    }
    std::vector<int> groups;
    for (const auto& c : cp)
      if (std::find(groups.begin(), groups.end(), c.group) == groups.end()) groups.push_back(c.group);
    if (groups.size() >= 2) {
      step("correction: inner cross-validation over " + std::to_string(groups.size()) + " training operating points, " +
           std::to_string(cp.size()) + " case(s), then the ensemble");
      const auto cand = correction_candidates(h, o.psd_map.transfer_spacing_bins * 4, o.correction_sim_features);
      m.psd_correction.train(cp, cand, o.ensemble_members, o.seed);
      m.env_correction.relative_residuals = true;
      m.env_correction.train(ce, correction_candidates(h, o.env_map.transfer_spacing_bins, o.correction_sim_features), o.ensemble_members,
                             o.seed + 1);
    }
  }

  for (size_t i = 0; i < records.size(); ++i) {
    const auto& r = records[i];
    m.records.push_back({{"path", r.path},
                         {"var", r.var},
                         {"fs_hz", r.fs_hz},
                         {"state", state_name(r.state)},
                         {"speed_rpm", r.op.speed_rpm},
                         {"load", r.op.load},
                         {"segments", seg_count[i]}});
  }
  m.train_wall_s = seconds_since(t0);
  step("done");
  return m;
}

Prediction predict_hybrid(const HybridModel& m, BearingState state, const OperatingPoint& op) {
  if (!(op.speed_rpm > 0) || !(op.load >= 0)) throw std::invalid_argument("speed must be > 0 rpm and load >= 0");
  Prediction p;
  const auto t0 = Clock::now();
  const Spectra phys = physics_spectra(m.options, state, op);
  p.physics_s = seconds_since(t0);
  p.psd_hz = centres(psd_grid(m.options.spectra));
  p.env_hz = centres(env_grid(m.options.spectra));
  MapInput d;
  d.state = static_cast<int>(state);
  d.op = {op.speed_rpm, op.load};
  MapInput hp = d, he = d;
  hp.physics = {phys.log_psd};
  he.physics = {power(phys.env, m.physics_env_scale)};
  p.log_psd_physics = phys.log_psd;
  p.log_psd_hybrid_sim = m.psd_hybrid_sim.predict(hp);
  p.log_psd_data_only = m.psd_data_only.predict(d);
  p.env_physics = phys.env;
  auto amp = [&](const std::vector<double>& pw) {
    std::vector<double> a(pw.size());
    for (size_t i = 0; i < pw.size(); ++i) a[i] = std::sqrt(std::max(0.0, pw[i]) * m.measured_env_scale);
    return a;
  };
  p.env_hybrid_sim = amp(m.env_hybrid_sim.predict(he));
  p.env_data_only = amp(m.env_data_only.predict(d));
  // Baselines 3 and 4: the training spectra of the state moved to the queried speed.
  const auto scales = speed_scales(m.options.speed_uncertainty, m.options.speed_points);
  const int h = m.options.psd_map.local_halfwidth_bins;
  const auto b = transported_base(m.references, state, op, p.psd_hz, p.env_hz, scales, h);
  auto band_is_point = [&p] {
    p.log_psd_hybrid_lo = p.log_psd_hybrid_hi = p.log_psd_hybrid;
    p.env_hybrid_lo = p.env_hybrid_hi = p.env_hybrid;
  };
  if (!b.found) {  // state not trained: no measured reference to transport (the maps with
                   // a transport input fall back to their 8-DOF-only twins)
    p.log_psd_hybrid = p.log_psd_hybrid_sim;
    p.env_hybrid = p.env_hybrid_sim;
    p.hybrid_kind = "map_sim";
    band_is_point();
    return p;
  }
  p.reference = b.nearest_case;
  p.interp_cases = b.interp_cases;
  const auto& tp = b.nearest_log_psd;
  const auto& te = b.nearest_env_power;
  p.log_psd_transport = tp;
  p.env_transport = amp(te);
  p.log_psd_interp = b.interp_log_psd;
  p.env_interp = amp(b.interp_env_power);
  if (m.psd_correction.trained() && m.env_correction.trained()) {
    std::vector<CorrectionCase> a(b.sources.size()), e(b.sources.size());
    std::vector<double> w;
    for (size_t i = 0; i < b.sources.size(); ++i) {
      const auto& src = b.sources[i];
      a[i].base = src.moved_log_psd;
      a[i].fixed = src.log_psd;
      a[i].sim = phys.log_psd;
      e[i].base = amplitude(src.moved_env_power);
      e[i].fixed = amplitude(src.env_power);
      e[i].sim = amplitude(power(phys.env, m.physics_env_scale));
      a[i].speed_change = e[i].speed_change = std::abs(std::log(op.speed_rpm / src.speed_rpm));
      w.push_back(src.weight);
    }
    m.psd_correction.predict(a, w, p.log_psd_hybrid, p.log_psd_hybrid_lo, p.log_psd_hybrid_hi);
    m.env_correction.predict(e, w, p.env_hybrid, p.env_hybrid_lo, p.env_hybrid_hi);
    const double g = std::sqrt(m.measured_env_scale);
    for (auto* v : {&p.env_hybrid, &p.env_hybrid_lo, &p.env_hybrid_hi})
      for (double& x : *v) x = std::max(0.0, x) * g;
    p.hybrid_kind = "correction";
    return p;
  }
  if (m.psd_hybrid.options().physics_channels == 2) hp.physics.push_back(tp);
  if (m.env_hybrid.options().physics_channels == 2) he.physics.push_back(te);
  p.log_psd_hybrid = m.psd_hybrid.predict(hp);
  p.env_hybrid = amp(m.env_hybrid.predict(he));
  p.hybrid_kind = "map";
  band_is_point();
  return p;
}

Spectra measured_spectra(const HybridModel& m, const Record& r) {
  return compute_spectra(r.signal, r.fs_hz, m.options.spectra);
}

Scores score(const Prediction& p, const Spectra& s) {
  Scores c;
  c.log_psd_hybrid = pearson(p.log_psd_hybrid, s.log_psd);
  c.log_psd_physics = pearson(p.log_psd_physics, s.log_psd);
  c.log_psd_data_only = pearson(p.log_psd_data_only, s.log_psd);
  c.env_hybrid = pearson(p.env_hybrid, s.env);
  c.env_physics = pearson(p.env_physics, s.env);
  c.env_data_only = pearson(p.env_data_only, s.env);
  c.log_psd_hybrid_sim = pearson(p.log_psd_hybrid_sim, s.log_psd);
  c.env_hybrid_sim = pearson(p.env_hybrid_sim, s.env);
  if (!p.log_psd_transport.empty()) {
    c.log_psd_transport = pearson(p.log_psd_transport, s.log_psd);
    c.env_transport = pearson(p.env_transport, s.env);
  }
  return c;
}

double band_coverage(const std::vector<double>& y, const std::vector<double>& lo, const std::vector<double>& hi) {
  if (lo.size() != y.size() || hi.size() != y.size()) throw std::invalid_argument("band_coverage: sizes differ");
  size_t in = 0;
  for (size_t k = 0; k < y.size(); ++k) in += (y[k] >= lo[k] && y[k] <= hi[k]) ? 1 : 0;
  return y.empty() ? 0.0 : static_cast<double>(in) / static_cast<double>(y.size());
}

double mse(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.empty()) throw std::invalid_argument("mse: sizes differ or are empty");
  double s = 0.0;
  for (size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return s / static_cast<double>(a.size());
}

std::vector<ModelScore> score_table(const Prediction& p, const Spectra& s) {
  auto one = [&](const char* name, const std::vector<double>& lp, const std::vector<double>& env) {
    ModelScore r;
    r.model = name;
    r.available = !lp.empty() && !env.empty();
    if (!r.available) return r;
    r.log_pearson = pearson(lp, s.log_psd);
    r.log_mse = mse(lp, s.log_psd);
    r.env_pearson = pearson(env, s.env);
    r.env_mse = mse(env, s.env);
    return r;
  };
  return {one("physics", p.log_psd_physics, p.env_physics), one("data_only", p.log_psd_data_only, p.env_data_only),
          one("nearest_transport", p.log_psd_transport, p.env_transport),
          one("interpolated_transport", p.log_psd_interp, p.env_interp), one("hybrid", p.log_psd_hybrid, p.env_hybrid)};
}

nlohmann::json HybridModel::training_summary() const {
  nlohmann::json j;
  j["records"] = records;
  j["calibration"] = {{"lines_used", calibration.lines_used},
                      {"gamma_catalogue", calibration.gamma_catalogue},
                      {"gamma_effective", calibration.gamma_effective},
                      {"contact_angle_deg", calibration.contact_angle_rad * 180.0 / M_PI},
                      {"note", calibration.note}};
  j["training_rms"] = {{"log_psd_hybrid", psd_hybrid.training_rms()},
                       {"log_psd_data_only", psd_data_only.training_rms()},
                       {"log_psd_hybrid_sim", psd_hybrid_sim.training_rms()},
                       {"env_power_hybrid", env_hybrid.training_rms()},
                       {"env_power_hybrid_sim", env_hybrid_sim.training_rms()},
                       {"env_power_data_only", env_data_only.training_rms()}};
  j["train_wall_s"] = train_wall_s;
  if (psd_correction.trained()) {
    auto cv = [](const CorrectionEnsemble& e) {
      return nlohmann::json{{"chosen", e.cv.chosen.describe()},
                            {"inner_cv_pearson", e.cv.chosen_pearson},
                            {"inner_cv_pearson_baseline", e.cv.baseline_pearson},
                            {"ensemble_members", e.members.size()}};
    };
    j["correction"] = {{"log_spectrum", cv(psd_correction)}, {"envelope_spectrum", cv(env_correction)}};
  } else {
    j["correction"] = nullptr;
  }
  return j;
}

void save_model(const HybridModel& m, const std::string& path) {
  const auto& o = m.options;
  nlohmann::json j;
  j["format"] = k_model_format;
  j["version"] = k_model_version;
  j["options"] = {{"spectra", o.spectra},
                  {"rig", o.rig},
                  {"segment_s", o.segment_s},
                  {"sim_duration_s", o.sim_duration_s},
                  {"sim_fs_hz", o.sim_fs_hz},
                  {"speed_uncertainty", o.speed_uncertainty},
                  {"speed_points", o.speed_points},
                  {"calibrate_kinematics", o.calibrate_kinematics},
                  {"transport_env", o.transport_env},
                  {"transport_log_psd", o.transport_log_psd},
                  {"correction", o.correction},
                  {"ensemble_members", o.ensemble_members},
                  {"correction_sim_features", o.correction_sim_features},
                  {"seed", o.seed},
                  {"threads", o.threads}};
  j["training"] = m.training_summary();
  j["training"].erase("train_wall_s");  // a timing: the file is the same bit for bit for one seed
  j["physics_env_scale"] = m.physics_env_scale;
  j["measured_env_scale"] = m.measured_env_scale;
  j["maps"] = {{"psd_hybrid", m.psd_hybrid.to_json()},
               {"psd_hybrid_sim", m.psd_hybrid_sim.to_json()},
               {"psd_data_only", m.psd_data_only.to_json()},
               {"env_hybrid", m.env_hybrid.to_json()},
               {"env_hybrid_sim", m.env_hybrid_sim.to_json()},
               {"env_data_only", m.env_data_only.to_json()}};
  nlohmann::json refs = nlohmann::json::array();
  for (const auto& r : m.references)
    refs.push_back({{"state", state_name(r.state)},
                    {"speed_rpm", r.op.speed_rpm},
                    {"load", r.op.load},
                    {"segments", r.segments},
                    {"log_psd", r.log_psd},
                    {"env_power", r.env_power}});
  j["references"] = refs;
  j["corrections"] = m.psd_correction.trained()
                         ? nlohmann::json{{"log_psd", m.psd_correction.to_json()}, {"envelope", m.env_correction.to_json()}}
                         : nlohmann::json(nullptr);
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write model file '" + path + "'");
  f << j.dump(1) << '\n';
  if (!f) throw std::runtime_error("error writing model file '" + path + "'");
}

HybridModel load_model(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot open model file '" + path + "'");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(f);
  } catch (const std::exception& e) {
    throw std::invalid_argument("model file '" + path + "': not JSON (" + e.what() + ")");
  }
  if (!j.is_object() || j.value("format", std::string()) != k_model_format)
    throw std::invalid_argument("model file '" + path + "': not an " + std::string(k_model_format) + " file");
  const int v = j.value("version", -1);
  if (v != k_model_version)
    throw std::invalid_argument("model file '" + path + "': version " + std::to_string(v) + " (this amb-host reads " +
                                std::to_string(k_model_version) + ")");
  HybridModel m;
  try {
    const auto& o = j.at("options");
    m.options.spectra = o.at("spectra").get<SpectralOptions>();
    m.options.rig = o.at("rig").get<RigParams>();
    m.options.segment_s = o.at("segment_s");
    m.options.sim_duration_s = o.at("sim_duration_s");
    m.options.sim_fs_hz = o.at("sim_fs_hz");
    m.options.speed_uncertainty = o.at("speed_uncertainty");
    m.options.speed_points = o.at("speed_points");
    m.options.calibrate_kinematics = o.at("calibrate_kinematics");
    m.options.transport_env = o.at("transport_env");
    m.options.transport_log_psd = o.at("transport_log_psd");
    m.options.correction = o.at("correction");
    m.options.ensemble_members = o.at("ensemble_members");
    m.options.correction_sim_features = o.at("correction_sim_features");
    m.options.seed = o.at("seed");
    m.options.threads = o.at("threads");
    m.physics_env_scale = j.at("physics_env_scale");
    m.measured_env_scale = j.at("measured_env_scale");
    const auto& maps = j.at("maps");
    m.psd_hybrid = SpectralMap::from_json(maps.at("psd_hybrid"));
    m.psd_data_only = SpectralMap::from_json(maps.at("psd_data_only"));
    m.env_hybrid = SpectralMap::from_json(maps.at("env_hybrid"));
    m.env_data_only = SpectralMap::from_json(maps.at("env_data_only"));
    m.psd_hybrid_sim = SpectralMap::from_json(maps.at("psd_hybrid_sim"));
    m.env_hybrid_sim = SpectralMap::from_json(maps.at("env_hybrid_sim"));
    for (const auto& r : j.at("references")) {
      ReferenceSpectra ref;
      ref.state = parse_state(r.at("state").get<std::string>());
      ref.op = {r.at("speed_rpm").get<double>(), r.at("load").get<double>()};
      ref.segments = r.at("segments").get<int>();
      ref.log_psd = r.at("log_psd").get<std::vector<double>>();
      ref.env_power = r.at("env_power").get<std::vector<double>>();
      if (!(ref.op.speed_rpm > 0) || ref.log_psd.size() != m.psd_hybrid.bins() || ref.env_power.size() != m.env_hybrid.bins())
        throw std::invalid_argument("model file '" + path + "': reference spectrum " + state_name(ref.state) +
                                    " does not match the grids or has no speed");
      m.references.push_back(std::move(ref));
    }
    if (const auto& c = j.at("corrections"); !c.is_null()) {
      m.psd_correction = CorrectionEnsemble::from_json(c.at("log_psd"));
      m.env_correction = CorrectionEnsemble::from_json(c.at("envelope"));
    }
    m.options.psd_map = m.psd_hybrid.options();
    m.options.env_map = m.env_hybrid.options();
    const auto& t = j.at("training");
    for (const auto& r : t.at("records")) m.records.push_back(r);
    const auto& c = t.at("calibration");
    m.calibration.lines_used = c.at("lines_used");
    m.calibration.gamma_catalogue = c.at("gamma_catalogue");
    m.calibration.gamma_effective = c.at("gamma_effective");
    m.calibration.contact_angle_rad = c.at("contact_angle_deg").get<double>() * M_PI / 180.0;
    m.calibration.note = c.at("note");
    m.train_wall_s = t.value("train_wall_s", 0.0);
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument("model file '" + path + "': " + e.what());
  }
  std::string why;
  if (!m.options.valid(&why)) throw std::invalid_argument("model file '" + path + "': " + why);
  if (m.psd_hybrid.bins() != psd_grid(m.options.spectra).bins() || m.env_hybrid.bins() != env_grid(m.options.spectra).bins() ||
      m.psd_data_only.bins() != m.psd_hybrid.bins() || m.env_data_only.bins() != m.env_hybrid.bins() ||
      m.psd_hybrid_sim.bins() != m.psd_hybrid.bins() || m.env_hybrid_sim.bins() != m.env_hybrid.bins())
    throw std::invalid_argument("model file '" + path + "': map grids do not match the spectral options");
  if (m.psd_correction.trained() &&
      (m.psd_correction.main.bins() != m.psd_hybrid.bins() || m.env_correction.main.bins() != m.env_hybrid.bins()))
    throw std::invalid_argument("model file '" + path + "': correction grids do not match the spectral options");
  if (!(m.physics_env_scale > 0) || !(m.measured_env_scale > 0))
    throw std::invalid_argument("model file '" + path + "': envelope scales must be > 0");
  return m;
}

}  // namespace amb::host::hybrid
