#include "host-tools/core/hybrid/leave_one_out.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace amb::host::hybrid {

const ModelScore& LooRow::model(const std::string& name) const {
  for (const auto& m : models)
    if (m.model == name) return m;
  throw std::invalid_argument("no model '" + name + "' in the table");
}

namespace {

double mean_width(const std::vector<double>& lo, const std::vector<double>& hi) {
  double s = 0;
  for (size_t k = 0; k < lo.size(); ++k) s += hi[k] - lo[k];
  return lo.empty() ? 0.0 : s / static_cast<double>(lo.size());
}

}  // namespace

LooResult leave_one_point_out(const std::vector<Record>& records, const TrainOptions& o,
                              const std::function<void(const std::string&)>& progress) {
  std::vector<OperatingPoint> points;
  for (const auto& r : records)
    if (std::none_of(points.begin(), points.end(), [&](const OperatingPoint& p) {
          return p.speed_rpm == r.op.speed_rpm && p.load == r.op.load;
        }))
      points.push_back(r.op);
  if (points.size() < 2) throw std::invalid_argument("leave-one-out needs records at two or more operating points");
  LooResult res;
  for (const auto& p : points) {
    std::vector<Record> train, test;
    for (const auto& r : records) (r.op.speed_rpm == p.speed_rpm && r.op.load == p.load ? test : train).push_back(r);
    char line[160];
    std::snprintf(line, sizeof line, "leave-one-out: holding out %g rpm / load %g, training on %zu record(s)", p.speed_rpm,
                  p.load, train.size());
    if (progress) progress(line);
    const HybridModel m = train_hybrid(train, o);
    res.train_wall_s.push_back(m.train_wall_s);
    for (const auto& r : test) {
      const Prediction pr = predict_hybrid(m, r.state, r.op);
      const Spectra meas = measured_spectra(m, r);
      LooRow row;
      row.held_out = p;
      row.state = r.state;
      row.record = r.path;
      row.models = score_table(pr, meas);
      row.hybrid_kind = pr.hybrid_kind;
      if (m.psd_correction.trained()) {
        row.chosen_log = m.psd_correction.cv.chosen.describe();
        row.chosen_env = m.env_correction.cv.chosen.describe();
        row.cv_log = m.psd_correction.cv.chosen_pearson;
        row.cv_log_baseline = m.psd_correction.cv.baseline_pearson;
        row.cv_env = m.env_correction.cv.chosen_pearson;
        row.cv_env_baseline = m.env_correction.cv.baseline_pearson;
      }
      row.band_coverage_log = band_coverage(meas.log_psd, pr.log_psd_hybrid_lo, pr.log_psd_hybrid_hi);
      row.band_coverage_env = band_coverage(meas.env, pr.env_hybrid_lo, pr.env_hybrid_hi);
      row.band_width_log = mean_width(pr.log_psd_hybrid_lo, pr.log_psd_hybrid_hi);
      double mean_env = 0;
      for (double v : meas.env) mean_env += v / static_cast<double>(meas.env.size());
      row.band_width_env_rel = mean_env > 0 ? mean_width(pr.env_hybrid_lo, pr.env_hybrid_hi) / mean_env : 0.0;
      res.rows.push_back(std::move(row));
    }
  }
  return res;
}

nlohmann::json loo_json(const LooResult& r) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& row : r.rows) {
    nlohmann::json models = nlohmann::json::object();
    for (const auto& m : row.models)
      models[m.model] = m.available ? nlohmann::json{{"log_spectrum", {{"pearson", m.log_pearson}, {"mse", m.log_mse}}},
                                                     {"envelope_spectrum", {{"pearson", m.env_pearson}, {"mse", m.env_mse}}}}
                                    : nlohmann::json(nullptr);
    rows.push_back({{"held_out_rpm", row.held_out.speed_rpm},
                    {"held_out_load", row.held_out.load},
                    {"state", state_name(row.state)},
                    {"record", row.record},
                    {"hybrid_kind", row.hybrid_kind},
                    {"chosen", {{"log_spectrum", row.chosen_log}, {"envelope_spectrum", row.chosen_env}}},
                    {"inner_cv", {{"log_spectrum", {{"chosen", row.cv_log}, {"transport", row.cv_log_baseline}}},
                                  {"envelope_spectrum", {{"chosen", row.cv_env}, {"transport", row.cv_env_baseline}}}}},
                    {"band_coverage", {{"log_spectrum", row.band_coverage_log}, {"envelope_spectrum", row.band_coverage_env}}},
                    {"band_width", {{"log_spectrum_log10", row.band_width_log}, {"envelope_rel", row.band_width_env_rel}}},
                    {"models", models}});
  }
  return {{"rows", rows}, {"train_wall_s", r.train_wall_s}};
}

}  // namespace amb::host::hybrid
