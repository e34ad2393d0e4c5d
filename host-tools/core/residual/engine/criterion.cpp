#include "host-tools/core/residual/engine/criterion.hpp"

#include <cmath>
#include <cstdio>

namespace amb::host::residual::engine {
namespace {

std::string num(double x, int digits = 3) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, x);
  return b;
}

}  // namespace

std::string Criterion::check() const {
  auto finite_pos = [](double x) { return std::isfinite(x) && x >= 0.0; };
  if (!std::isfinite(min_delta_ic)) return "criterion: min_delta_ic must be finite";
  if (!finite_pos(min_effect_sigma)) return "criterion: min_effect_sigma must be finite and >= 0";
  if (!(min_relative_improvement >= 0.0 && min_relative_improvement < 1.0))
    return "criterion: min_relative_improvement must lie in [0, 1)";
  if (!finite_pos(strong_delta_ic)) return "criterion: strong_delta_ic must be finite and >= 0";
  if (!(feature_tolerance >= 0.0 && feature_tolerance < 1.0)) return "criterion: feature_tolerance must lie in [0, 1)";
  return {};
}

double relative_change(const Feature& f) {
  const double scale = std::abs(f.before) > 0.0 ? std::abs(f.before) : 1.0;
  const double d = (f.after - f.before) / scale;
  return f.higher_is_better ? -d : d;
}

Decision decide(const CandidateEvidence& c, const Criterion& k) {
  Decision d;
  d.value = c.delta_ic;
  d.threshold = k.min_delta_ic;
  if (!c.testable) {
    d.reason = "not testable on this record";
    return d;
  }
  std::string why;
  auto fail = [&](const std::string& s) { why += (why.empty() ? "" : "; ") + s; };
  if (!(c.delta_ic > k.min_delta_ic)) fail("information-criterion decrease " + num(c.delta_ic) + " <= threshold " + num(k.min_delta_ic));
  if (!(c.effect_sigma >= k.min_effect_sigma))
    fail("predicted change " + num(c.effect_sigma) + " sigma < " + num(k.min_effect_sigma) + " (no effect beyond the noise)");
  if (!c.identified) fail("not identified" + (c.not_identified.empty() ? std::string() : " (" + c.not_identified + ")"));
  const double need = c.delta_ic >= k.strong_delta_ic ? 0.5 * k.min_relative_improvement : k.min_relative_improvement;
  bool one_falls = c.decision.empty();
  std::string best;
  double best_change = 0.0;
  for (const auto& f : c.decision) {
    const double r = relative_change(f);
    if (r > k.feature_tolerance && !(f.rises_above > 0.0 && std::abs(f.after) <= f.rises_above))
      fail(f.name + " rises (" + num(f.before) + " -> " + num(f.after) + " " + f.unit + ")");
    const bool counts = std::abs(f.before) > f.counts_above;
    if (counts && r <= -need) one_falls = true;
    if (counts && r < best_change) {
      best_change = r;
      best = f.name + " " + num(f.before) + " -> " + num(f.after) + " " + f.unit;
    }
  }
  if (!one_falls)
    fail("no decision feature falls by " + num(100.0 * need, 2) + " %" +
         (best.empty() ? std::string() : " (best: " + best + ", " + num(-100.0 * best_change, 2) + " %)"));
  d.kept = why.empty();
  d.reason = d.kept ? "kept: information-criterion decrease " + num(c.delta_ic) + " > " + num(k.min_delta_ic) +
                          (best.empty() ? std::string() : "; " + best)
                    : "rejected: " + why;
  return d;
}

}  // namespace amb::host::residual::engine
