#include "host-tools/core/hybrid/record_spec.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace amb::host::hybrid {

Record parse_record_spec(const std::string& spec, bool need_condition) {
  Record r;
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
      r.state = parse_state(val);
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

void write_prediction_csv(const Prediction& p, const std::string& path) {
  std::ostringstream f;
  f.precision(9);
  f << "# spectrum,f_hz,hybrid,hybrid_lo,hybrid_hi,physics,data_only,nearest_transport,interpolated_transport"
       " (log_psd: log10 g^2/Hz; envelope: g^2)\n";
  auto cell = [&](const std::vector<double>& v, size_t k) {
    f << ',';
    if (k < v.size()) f << v[k];
  };
  for (size_t k = 0; k < p.psd_hz.size(); ++k) {
    f << "log_psd," << p.psd_hz[k];
    for (const auto* v : {&p.log_psd_hybrid, &p.log_psd_hybrid_lo, &p.log_psd_hybrid_hi, &p.log_psd_physics,
                          &p.log_psd_data_only, &p.log_psd_transport, &p.log_psd_interp})
      cell(*v, k);
    f << '\n';
  }
  for (size_t k = 0; k < p.env_hz.size(); ++k) {
    f << "envelope," << p.env_hz[k];
    for (const auto* v : {&p.env_hybrid, &p.env_hybrid_lo, &p.env_hybrid_hi, &p.env_physics, &p.env_data_only,
                          &p.env_transport, &p.env_interp})
      cell(*v, k);
    f << '\n';
  }
  // Written whole or not at all: a temporary file renamed into place.
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error("cannot write '" + path + "'");
    out << f.str();
    if (!out) throw std::runtime_error("error writing '" + path + "'");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("cannot write '" + path + "': " + ec.message());
}

}  // namespace amb::host::hybrid
