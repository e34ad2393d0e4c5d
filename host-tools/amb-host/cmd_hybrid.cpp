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

namespace {
namespace hy = amb::host::hybrid;

int bad_input(const char* sub, const std::string& what) {
  std::fprintf(stderr, "amb-host hybrid %s: error: %s\n", sub, what.c_str());
  return 1;
}

// "PATH[,key=value]..." with keys state, rpm, load, fs, var. `need_condition`: state, rpm and
// load are required (training records); else they are refused (a measured record to score).
hy::Record parse_record(const std::string& spec, bool need_condition) {
  hy::Record r;
  std::stringstream ss(spec);
  std::string item;
  bool first = true, has_state = false, has_rpm = false, has_load = false;
  while (std::getline(ss, item, ',')) {
    if (first) {
      r.path = item;
      first = false;
      continue;
    }
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw std::invalid_argument("record '" + spec + "': '" + item + "' is not key=value");
    const std::string key = item.substr(0, eq), val = item.substr(eq + 1);
    auto number = [&](const std::string& k) {
      size_t used = 0;
      double v = 0;
      try {
        v = std::stod(val, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != val.size() || !std::isfinite(v)) throw std::invalid_argument("record '" + spec + "': " + k + " is not a number");
      return v;
    };
    if (key == "fs") {
      r.fs_hz = number(key);
      if (!(r.fs_hz > 0)) throw std::invalid_argument("record '" + spec + "': fs must be > 0");
    } else if (key == "var") {
      r.var = val;
    } else if (need_condition && key == "state") {
      r.state = hy::parse_state(val);
      has_state = true;
    } else if (need_condition && key == "rpm") {
      r.op.speed_rpm = number(key);
      if (!(r.op.speed_rpm > 0)) throw std::invalid_argument("record '" + spec + "': rpm must be > 0");
      has_rpm = true;
    } else if (need_condition && key == "load") {
      r.op.load = number(key);
      if (!(r.op.load >= 0)) throw std::invalid_argument("record '" + spec + "': load must be >= 0");
      has_load = true;
    } else {
      throw std::invalid_argument("record '" + spec + "': unknown key '" + key + "' (allowed: " +
                                  (need_condition ? "state, rpm, load, " : "") + "fs, var)");
    }
  }
  if (r.path.empty()) throw std::invalid_argument("record '" + spec + "': no file");
  if (!std::filesystem::exists(r.path)) throw std::invalid_argument("record file '" + r.path + "' does not exist");
  if (need_condition && (!has_state || !has_rpm || !has_load))
    throw std::invalid_argument("record '" + spec + "': state=, rpm= and load= are required (the operating point is an input)");
  return r;
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
      recs.push_back(parse_record(s, true));
      hy::load_record(recs.back());
    }
  } catch (const std::exception& e) {
    return bad_input("train", e.what());
  }
  if (!a.json) std::fprintf(stderr, "amb-host hybrid train: %zu record(s), %d thread(s)...\n", recs.size(), o.threads);
  hy::HybridModel m;
  try {
    m = hy::train_hybrid(recs, o);
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
      meas = parse_record(a.measured, false);
      hy::load_record(meas);
    }
  } catch (const std::exception& e) {
    return bad_input("predict", e.what());
  }
  const hy::OperatingPoint op{a.rpm, a.load};
  hy::Prediction p;
  hy::Scores s;
  try {
    p = hy::predict_hybrid(m, state, op);
    if (have_meas) s = hy::score(p, hy::measured_spectra(m, meas));
  } catch (const std::invalid_argument& e) {
    return bad_input("predict", e.what());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!a.out_csv.empty()) {
    std::ofstream f(a.out_csv);
    if (!f) return bad_input("predict", "cannot write '" + a.out_csv + "'");
    f << "# spectrum,f_hz,hybrid,physics,data_only (log_psd: log10 g^2/Hz; envelope: g^2)\n";
    for (size_t k = 0; k < p.psd_hz.size(); ++k)
      f << "log_psd," << p.psd_hz[k] << ',' << p.log_psd_hybrid[k] << ',' << p.log_psd_physics[k] << ','
        << p.log_psd_data_only[k] << '\n';
    for (size_t k = 0; k < p.env_hz.size(); ++k)
      f << "envelope," << p.env_hz[k] << ',' << p.env_hybrid[k] << ',' << p.env_physics[k] << ',' << p.env_data_only[k]
        << '\n';
  }
  const bool above = have_meas && s.log_psd_hybrid > s.log_psd_physics && s.log_psd_hybrid > s.log_psd_data_only &&
                     s.env_hybrid > s.env_physics && s.env_hybrid > s.env_data_only;
  nlohmann::json j;
  j["state"] = hy::state_name(state);
  j["speed_rpm"] = a.rpm;
  j["load"] = a.load;
  j["model"] = a.model;
  j["contact_angle_deg"] = m.options.rig.drive_end_contact_angle_rad * 180.0 / M_PI;
  j["trained_at"] = m.records;
  if (have_meas) {
    j["measured"] = meas.path;
    j["pearson"] = {{"hybrid", pair_json(s.log_psd_hybrid, s.env_hybrid)},
                    {"physics", pair_json(s.log_psd_physics, s.env_physics)},
                    {"data_only", pair_json(s.log_psd_data_only, s.env_data_only)}};
    // Ablations: the map on the 8-DOF physics alone, and the transported training spectrum
    // alone (null when the model has no reference case of this state).
    j["ablations"] = {{"hybrid_sim", pair_json(s.log_psd_hybrid_sim, s.env_hybrid_sim)},
                      {"transport", p.log_psd_transport.empty() ? nlohmann::json(nullptr)
                                                                 : pair_json(s.log_psd_transport, s.env_transport)}};
    j["hybrid_above_baselines"] = above;
  } else {
    j["pearson"] = nullptr;
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
      f << "Pearson correlation with `" << meas.path << "`:\n\n| model | log spectrum | envelope spectrum |\n| --- | --- | --- |\n";
      std::snprintf(line, sizeof line, "| hybrid | %.3f | %.3f |\n| physics only | %.3f | %.3f |\n| data only | %.3f | %.3f |\n",
                    s.log_psd_hybrid, s.env_hybrid, s.log_psd_physics, s.env_physics, s.log_psd_data_only,
                    s.env_data_only);
      f << line << "\nHybrid above both baselines on both spectra: " << (above ? "yes" : "no") << ".\n";
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
    std::printf("  Pearson vs %s\n  %-13s %12s %18s\n", meas.path.c_str(), "model", "log spectrum", "envelope spectrum");
    std::printf("  %-13s %12.3f %18.3f\n", "hybrid", s.log_psd_hybrid, s.env_hybrid);
    std::printf("  %-13s %12.3f %18.3f\n", "physics only", s.log_psd_physics, s.env_physics);
    std::printf("  %-13s %12.3f %18.3f\n", "data only", s.log_psd_data_only, s.env_data_only);
    std::printf("  hybrid above both baselines: %s\n", above ? "yes" : "no");
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
      p->add_flag("--json", pa->json, "print the figures as JSON");
      run = [&sub, t, p, ta, pa]() -> int {
        (void)sub;
        if (t->parsed()) return run_train(*ta);
        if (p->parsed()) return run_predict(*pa);
        return 1;
      };
    }};

}  // namespace
