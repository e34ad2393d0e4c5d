#include "host-tools/core/residual/candidate_report.hpp"

#include <cmath>
#include <cstdio>

namespace amb::host::residual {
namespace {

nlohmann::json features_json(const std::vector<engine::Feature>& v) {
  nlohmann::json a = nlohmann::json::array();
  auto num = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  for (const auto& f : v) a.push_back({{"name", f.name}, {"unit", f.unit}, {"before", num(f.before)}, {"after", num(f.after)}});
  return a;
}

}  // namespace

CandidateScore scored(const engine::CandidateEvidence& c, const engine::Decision& d) {
  CandidateScore s;
  s.name = c.element;
  s.testable = c.testable;
  s.delta_bic = c.delta_ic;
  s.evidence = c.evidence;
  s.decided = true;
  s.kept = d.kept;
  s.threshold = d.threshold;
  s.reason = d.reason;
  s.decision_features = c.decision;
  s.information_features = c.information;
  return s;
}

nlohmann::json candidate_json(const CandidateScore& c) {
  nlohmann::json j{{"name", c.name},
                   {"testable", c.testable},
                   {"delta_bic", c.testable && std::isfinite(c.delta_bic) ? nlohmann::json(c.delta_bic) : nlohmann::json(nullptr)},
                   {"evidence", c.evidence},
                   {"decided", c.decided}};
  if (c.decided) {
    j["kept"] = c.kept;
    j["criterion"] = {{"value", std::isfinite(c.delta_bic) ? nlohmann::json(c.delta_bic) : nlohmann::json(nullptr)},
                      {"threshold", c.threshold},
                      {"what", "information-criterion (BIC) decrease on the decision features"}};
    j["reason"] = c.reason;
    j["decision_features"] = features_json(c.decision_features);
    j["information_features"] = features_json(c.information_features);
  }
  return j;
}

nlohmann::json candidates_json(const std::vector<CandidateScore>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& c : v) a.push_back(candidate_json(c));
  return a;
}

std::string candidate_text(const CandidateScore& c) {
  char b[96];
  std::string s = c.name + ": ";
  if (!c.testable) return s + "not testable; " + c.evidence;
  if (c.decided) {
    std::snprintf(b, sizeof b, "%s (dBIC %.1f vs threshold %.1f): ", c.kept ? "KEPT" : "rejected", c.delta_bic, c.threshold);
    s += b + c.reason;
    for (const auto& f : c.decision_features) {
      std::snprintf(b, sizeof b, "%.4g -> %.4g", f.before, f.after);
      s += "; [decides] " + f.name + " " + b + " " + f.unit;
    }
    for (const auto& f : c.information_features) {
      std::snprintf(b, sizeof b, "%.4g -> %.4g", f.before, f.after);
      s += "; [information] " + f.name + " " + b + " " + f.unit;
    }
    return s + "; evidence: " + c.evidence;
  }
  std::snprintf(b, sizeof b, "screened out (dBIC %.1f): ", c.delta_bic);
  return s + b + c.evidence;
}

}  // namespace amb::host::residual
