// amb-host hybrid train | predict: the physics-informed hybrid model of seed 001 (issue 18).
// Logic: host-tools/core/hybrid/hybrid_model.hpp; method and figures: docs/hybrid.md.
#include <chrono>
#include <cmath>
#include <memory>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/hybrid/hybrid_model.hpp"
#include "host-tools/core/hybrid/hybrid_page.hpp"
#include "host-tools/core/hybrid/record_spec.hpp"

namespace {
namespace hy = amb::host::hybrid;

int bad_input(const char* sub, const std::string& what) {
  std::fprintf(stderr, "amb-host hybrid %s: error: %s\n", sub, what.c_str());
  return 1;
}

struct TrainArgs {
  std::vector<std::string> records;
  std::string out;
  uint64_t seed = 1;
  int threads = 2;
  double segment_s = 2.0;
  double sim_s = 4.0;
  double speed_uncertainty = 0.005;
  bool no_calibration = false;
  bool transport_env = false;
  bool transport_log_psd = false;
  bool json = false;
};

int run_train(const TrainArgs& a) {
  hy::TrainOptions o;
  o.seed = a.seed;
  o.threads = a.threads;
  o.segment_s = a.segment_s;
  o.sim_duration_s = a.sim_s;
  o.speed_uncertainty = a.speed_uncertainty;
  o.calibrate_kinematics = !a.no_calibration;
  o.transport_env = a.transport_env;
  o.transport_log_psd = a.transport_log_psd;
  std::string why;
  if (!o.valid(&why))
    return bad_input("train", amb::host::cli::in_option_names(why, {{"segment_s", "--segment-s"}, {"sim_duration_s", "--sim-s"}}));
  std::vector<hy::Record> recs;
  try {
    for (const auto& s : a.records) {
      recs.push_back(hy::parse_record_spec(s, true));
      hy::load_record(recs.back());
    }
  } catch (const std::exception& e) {
    return bad_input("train", e.what());
  }
  std::fprintf(stderr, "amb-host hybrid train: %zu record(s), %d thread(s), seed %llu\n", recs.size(), o.threads,
               static_cast<unsigned long long>(o.seed));
  hy::HybridModel m;
  try {
    m = hy::train_hybrid(recs, o, [](const std::string& line) { std::fprintf(stderr, "amb-host hybrid train: %s\n", line.c_str()); });
  } catch (const std::invalid_argument& e) {
    return bad_input("train", e.what());
  }
  hy::save_model(m, a.out);
  nlohmann::json j = m.training_summary();
  j["model"] = a.out;
  j["format"] = hy::k_model_format;
  j["version"] = hy::k_model_version;
  j["seed"] = a.seed;
  j["threads"] = a.threads;
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("hybrid model (%s v%d) written to %s\n", hy::k_model_format, hy::k_model_version, a.out.c_str());
  for (const auto& r : m.records)
    std::printf("  trained on %-40s %-10s %7.1f rpm  load %.2f  %d segment(s)\n",
                std::filesystem::path(r.at("path").get<std::string>()).filename().c_str(),
                r.at("state").get<std::string>().c_str(), r.at("speed_rpm").get<double>(), r.at("load").get<double>(),
                r.at("segments").get<int>());
  std::printf("  kinematic calibration: %s\n", m.calibration.note.c_str());
  if (m.psd_correction.trained()) {
    std::printf("  correction (inner cross-validation over the training operating points):\n");
    std::printf("    log spectrum: %s (inner CV Pearson %.3f, transport alone %.3f)\n", m.psd_correction.cv.chosen.describe().c_str(),
                m.psd_correction.cv.chosen_pearson, m.psd_correction.cv.baseline_pearson);
    std::printf("    envelope:     %s (inner CV Pearson %.3f, transport alone %.3f)\n", m.env_correction.cv.chosen.describe().c_str(),
                m.env_correction.cv.chosen_pearson, m.env_correction.cv.baseline_pearson);
  } else {
    std::printf("  no correction: no state was trained at two operating points (the hybrid is the learned map)\n");
  }
  std::printf("  training wall time %.2f s (%d thread(s))\n", m.train_wall_s, a.threads);
  return 0;
}

struct PredictArgs {
  std::string model;
  std::string state;
  double rpm = 0.0;
  double load = -1.0;
  std::string measured;
  std::string out_csv;
  std::string report;
  std::string html;
  bool json = false;
};

nlohmann::json pair_json(double psd, double env) { return {{"log_spectrum", psd}, {"envelope_spectrum", env}}; }

int run_predict(const PredictArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  hy::HybridModel m;
  hy::BearingState state{};
  hy::Record meas;
  const bool have_meas = !a.measured.empty();
  try {
    state = hy::parse_state(a.state);
    if (!(a.rpm > 0)) throw std::invalid_argument("--rpm must be > 0");
    if (!(a.load >= 0)) throw std::invalid_argument("--load must be >= 0");
    m = hy::load_model(a.model);
    if (have_meas) {
      meas = hy::parse_record_spec(a.measured, false);
      hy::load_record(meas);
    }
  } catch (const std::exception& e) {
    return bad_input("predict", e.what());
  }
  const hy::OperatingPoint op{a.rpm, a.load};
  hy::Prediction p;
  hy::Scores s;
  std::vector<hy::ModelScore> table;
  hy::Spectra meas_spectra;
  try {
    p = hy::predict_hybrid(m, state, op);
    if (have_meas) {
      meas_spectra = hy::measured_spectra(m, meas);
      s = hy::score(p, meas_spectra);
      table = hy::score_table(p, meas_spectra);
    }
  } catch (const std::invalid_argument& e) {
    return bad_input("predict", e.what());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!a.out_csv.empty()) {
    try {
      hy::write_prediction_csv(p, a.out_csv);
    } catch (const std::exception& e) {
      return bad_input("predict", e.what());
    }
  }
  // Above every baseline (that has a prediction here), both spectra, Pearson.
  bool above = have_meas;
  for (const auto& r : table) {
    if (r.model == "hybrid" || !r.available) continue;
    above = above && table.back().log_pearson > r.log_pearson && table.back().env_pearson > r.env_pearson;
  }
  nlohmann::json j;
  j["state"] = hy::state_name(state);
  j["speed_rpm"] = a.rpm;
  j["load"] = a.load;
  j["model"] = a.model;
  j["contact_angle_deg"] = m.options.rig.drive_end_contact_angle_rad * 180.0 / M_PI;
  j["trained_at"] = m.records;
  if (have_meas) {
    j["measured"] = meas.path;
    // Every model of issue 34: physics, data_only, nearest_transport, interpolated_transport,
    // hybrid (null: no prediction, e.g. a transported baseline without a record of the state).
    nlohmann::json pj = nlohmann::json::object(), mj = nlohmann::json::object();
    for (const auto& r : table) {
      pj[r.model] = r.available ? pair_json(r.log_pearson, r.env_pearson) : nlohmann::json(nullptr);
      mj[r.model] = r.available ? pair_json(r.log_mse, r.env_mse) : nlohmann::json(nullptr);
    }
    j["pearson"] = pj;
    j["mse"] = mj;
    // Ablations: the map on the 8-DOF physics alone, and the transported training spectrum
    // alone (null when the model has no reference case of this state).
    j["ablations"] = {{"hybrid_sim", pair_json(s.log_psd_hybrid_sim, s.env_hybrid_sim)},
                      {"transport", p.log_psd_transport.empty() ? nlohmann::json(nullptr)
                                                                 : pair_json(s.log_psd_transport, s.env_transport)}};
    j["hybrid_above_baselines"] = above;
  } else {
    j["pearson"] = nullptr;
    j["mse"] = nullptr;
  }
  j["hybrid_kind"] = p.hybrid_kind;
  j["reference"] = p.reference.empty() ? nlohmann::json(nullptr) : nlohmann::json(p.reference);
  j["interpolated_from"] = p.interp_cases.empty() ? nlohmann::json(nullptr) : nlohmann::json(p.interp_cases);
  {
    // The band (docs/hybrid.md, "Band"): per spectrum the grid, the hybrid and its bounds.
    auto spectrum = [](const std::vector<double>& f, const std::vector<double>& y, const std::vector<double>& lo,
                       const std::vector<double>& hi) { return nlohmann::json{{"f_hz", f}, {"hybrid", y}, {"lo", lo}, {"hi", hi}}; };
    const bool ens = p.hybrid_kind == "correction";
    nlohmann::json b = {{"kind", ens ? "ensemble range + inner-CV residual quantiles" : "none (a map without ensemble: lo = hi)"},
                        {"nominal_coverage", ens ? nlohmann::json(hy::k_band_coverage) : nlohmann::json(nullptr)},
                        {"ensemble_members", ens ? nlohmann::json(m.psd_correction.members.size() + 1) : nlohmann::json(1)},
                        {"log_spectrum", spectrum(p.psd_hz, p.log_psd_hybrid, p.log_psd_hybrid_lo, p.log_psd_hybrid_hi)},
                        {"envelope_spectrum", spectrum(p.env_hz, p.env_hybrid, p.env_hybrid_lo, p.env_hybrid_hi)}};
    if (have_meas) {
      b["measured_coverage"] = pair_json(hy::band_coverage(meas_spectra.log_psd, p.log_psd_hybrid_lo, p.log_psd_hybrid_hi),
                                         hy::band_coverage(meas_spectra.env, p.env_hybrid_lo, p.env_hybrid_hi));
    }
    j["band"] = b;
  }
  if (!a.html.empty()) {
    hy::HybridPageData d;
    d.state = state;
    d.op = op;
    d.model_path = a.model;
    for (const auto& r : m.records) {
      char t[96];
      std::snprintf(t, sizeof t, "%s@%grpm/%g", r.at("state").get<std::string>().c_str(), r.at("speed_rpm").get<double>(),
                    r.at("load").get<double>());
      d.trained_at.push_back(t);
    }
    d.prediction = p;
    if (have_meas) {
      d.measured_path = meas.path;
      d.measured = meas_spectra;
      d.scores = table;
    }
    try {
      hy::write_hybrid_page(d, a.html);
    } catch (const std::exception& e) {
      return bad_input("predict", e.what());
    }
  }
  j["predict_wall_s"] = wall;
  j["physics_s"] = p.physics_s;
  if (!a.report.empty()) {
    std::ofstream f(a.report);
    if (!f) return bad_input("predict", "cannot write '" + a.report + "'");
    f << "## Hybrid model prediction (seed 001)\n\n";
    f << "State `" << hy::state_name(state) << "` at " << a.rpm << " rpm, load " << a.load << "; model `" << a.model
      << "` (trained at:";
    for (const auto& r : m.records)
      f << ' ' << r.at("state").get<std::string>() << '@' << r.at("speed_rpm").get<double>() << "rpm/"
        << r.at("load").get<double>();
    f << "). Kinematic calibration: " << m.calibration.note << ".\n\n";
    if (have_meas) {
      char line[256];
      f << "Against `" << meas.path << "`:\n\n| model | log spectrum Pearson | log spectrum MSE | envelope Pearson | envelope MSE |\n"
        << "| --- | --- | --- | --- | --- |\n";
      for (const auto& r : table) {
        if (!r.available) {
          f << "| " << r.model << " | n/a | n/a | n/a | n/a |\n";
          continue;
        }
        std::snprintf(line, sizeof line, "| %s | %.3f | %.4g | %.3f | %.4g |\n", r.model.c_str(), r.log_pearson, r.log_mse,
                      r.env_pearson, r.env_mse);
        f << line;
      }
      f << "\nHybrid above every baseline on both spectra (Pearson): " << (above ? "yes" : "no") << ".\n";
    }
    f << "\nPrediction wall time " << wall << " s (physics " << p.physics_s << " s).\n";
  }
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("hybrid predict: %s at %.1f rpm, load %.2f (model %s)\n", hy::state_name(state), a.rpm, a.load,
              a.model.c_str());
  if (have_meas) {
    std::printf("  against %s\n  %-23s %12s %12s %12s %12s\n", meas.path.c_str(), "model", "log Pearson", "log MSE",
                "env Pearson", "env MSE");
    for (const auto& r : table) {
      if (r.available)
        std::printf("  %-23s %12.3f %12.4g %12.3f %12.4g\n", r.model.c_str(), r.log_pearson, r.log_mse, r.env_pearson, r.env_mse);
      else
        std::printf("  %-23s %12s\n", r.model.c_str(), "n/a (no training record of the state)");
    }
    std::printf("  hybrid above every baseline: %s\n", above ? "yes" : "no");
  }
  std::printf("  wall time %.2f s (physics %.2f s)\n", wall, p.physics_s);
  return 0;
}

const amb::host::Registration reg{
    "hybrid", "physics-informed hybrid model (seed 001): train on measured records, predict spectra at another speed",
    [](CLI::App& sub, std::function<int()>& run) {
      auto ta = std::make_shared<TrainArgs>();
      auto pa = std::make_shared<PredictArgs>();
      sub.require_subcommand(1, 1);
      CLI::App* t = sub.add_subcommand("train", "train the hybrid map and its baselines; writes a versioned model file");
      t->add_option("--record", ta->records,
                    "training record 'FILE.mat,state=S,rpm=R,load=L[,fs=HZ][,var=NAME]' (repeat; S: healthy, "
                    "inner_race, outer_race, ball; fs defaults to the file's 'fs', var to DE_time)")
          ->required();
      namespace hc = amb::host::cli;
      hc::output_file(t->add_option("--out", ta->out, "model file to write (JSON)")->required());
      hc::whole(t->add_option("--seed", ta->seed, "seed of the simulated sensor noise (training is deterministic for a seed)"), 0, 9.0e15);
      hc::whole(t->add_option("--threads", ta->threads, "worker threads"), 1, 64);
      hc::positive(t->add_option("--segment-s", ta->segment_s, "training segment length, s"), 60.0, "s");
      hc::positive(t->add_option("--sim-s", ta->sim_s, "simulated duration per case, s"), 60.0, "s");
      hc::real(t->add_option("--speed-uncertainty", ta->speed_uncertainty, "relative uncertainty of a nominal speed"), 0.0, 0.5);
      t->add_flag("--no-calibration", ta->no_calibration, "keep the catalogue kinematics of the drive-end bearing");
      t->add_flag("--transport-env", ta->transport_env,
                  "envelope map: also take the kinematically transported training spectrum of the state as an input (docs/hybrid.md)");
      t->add_flag("--transport-log-psd", ta->transport_log_psd,
                  "log-spectrum map: also take the kinematically transported training spectrum as an input");
      t->add_flag("--json", ta->json, "print the training summary as JSON");
      CLI::App* p = sub.add_subcommand("predict", "predict the spectra of a state at an operating point (and score them)");
      hc::input_file(p->add_option("--model", pa->model, "model file written by 'hybrid train'")->required(), "hybrid-model");
      p->add_option("--state", pa->state, "bearing state: healthy, inner_race, outer_race, ball")
          ->required()
          ->check(CLI::IsMember({"healthy", "inner_race", "outer_race", "ball"}));
      hc::positive(p->add_option("--rpm", pa->rpm, "shaft speed, rpm")->required(), 1e5, "rpm");
      hc::real(p->add_option("--load", pa->load, "motor load (the unit used in training, CWRU: hp)")->required(), 0.0, 1000.0);
      p->add_option("--measured", pa->measured, "measured record to score against 'FILE.mat[,fs=HZ][,var=NAME]'");
      hc::output_file(p->add_option("--out", pa->out_csv, "write the predicted spectra (CSV)"));
      hc::output_file(p->add_option("--report", pa->report, "write a report section (Markdown)"));
      hc::output_file(p->add_option("--html", pa->html, "write the prediction as an HTML page (plots with the band and the baselines)"));
      p->add_flag("--json", pa->json, "print the figures as JSON");
      run = [&sub, t, p, ta, pa]() -> int {
        (void)sub;
        if (t->parsed()) return run_train(*ta);
        if (p->parsed()) return run_predict(*pa);
        return 1;
      };
    }};

}  // namespace
