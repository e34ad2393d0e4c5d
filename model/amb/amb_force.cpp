#include "model/amb/amb_force.hpp"

#include <algorithm>
#include <cmath>

namespace amb::model::magnet {

AxisLaw make_axis_law(const AmbParams& p) {
  AxisLaw law;
  law.gap_m = p.gap_m;
  // ks / ki = i0 / g0 ties the bias to the two measured gains; the board's bias_current_a
  // is checked against this by the loader, the gains are what was measured.
  law.bias_a = p.ki_n_per_a > 0.0 ? p.ks_n_per_m * p.gap_m / p.ki_n_per_a : 0.0;
  law.k_n_m2_per_a2 = law.bias_a > 0.0 ? p.ki_n_per_a * p.gap_m * p.gap_m / (4.0 * law.bias_a) : 0.0;
  law.max_coil_force_n = p.max_force_n;
  // Keeps the law finite should the rotor ever reach the stator (the touchdown bearings
  // normally stop it well before).
  law.min_gap_m = 0.02 * p.gap_m;
  return law;
}

double axis_force_n(const AxisLaw& law, double z_m, double ic_a) {
  const double i_plus = std::max(0.0, law.bias_a + ic_a);
  const double i_minus = std::max(0.0, law.bias_a - ic_a);
  const double g_plus = std::max(law.min_gap_m, law.gap_m - z_m);
  const double g_minus = std::max(law.min_gap_m, law.gap_m + z_m);
  const double f_plus = std::min(law.max_coil_force_n, law.k_n_m2_per_a2 * i_plus * i_plus / (g_plus * g_plus));
  const double f_minus = std::min(law.max_coil_force_n, law.k_n_m2_per_a2 * i_minus * i_minus / (g_minus * g_minus));
  return f_plus - f_minus;
}

double zero_force_current_a(const AxisLaw& law, double z_m) {
  if (!(law.gap_m > 0.0)) return 0.0;
  const double reach = std::max(0.0, law.gap_m - law.min_gap_m);
  return -law.bias_a * std::clamp(z_m, -reach, reach) / law.gap_m;
}

Linearisation linearise(const AxisLaw& law, double z, double ic) {
  const double k = law.k_n_m2_per_a2, ip = law.bias_a + ic, im = law.bias_a - ic;
  const double gp = law.gap_m - z, gm = law.gap_m + z;
  Linearisation l;
  l.ks_n_per_m = 2.0 * k * (ip * ip / (gp * gp * gp) + im * im / (gm * gm * gm));
  l.ki_n_per_a = 2.0 * k * (ip / (gp * gp) + im / (gm * gm));
  return l;
}

std::array<double, 2> axis_direction(double angle_deg) {
  const double a = angle_deg * M_PI / 180.0;
  return {std::sin(a), std::cos(a)};
}

}  // namespace amb::model::magnet
