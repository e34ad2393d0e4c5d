#include "model/bearing/geometry.hpp"

#include <cmath>

namespace amb::model::bearing {

double BearingGeometry::gamma() const {
  return ball_diameter_m * std::cos(contact_angle_rad) / pitch_diameter_m;
}

bool BearingGeometry::valid() const {
  return ball_count >= 3 && ball_diameter_m > 0.0 && pitch_diameter_m > ball_diameter_m &&
         std::abs(contact_angle_rad) < 0.5 * M_PI;
}

DefectOrders defect_orders(const BearingGeometry& g) {
  const double gm = g.gamma();
  const double z = static_cast<double>(g.ball_count);
  DefectOrders o;
  o.ftf = 0.5 * (1.0 - gm);
  o.bpfo = 0.5 * z * (1.0 - gm);
  o.bpfi = 0.5 * z * (1.0 + gm);
  o.bsf = g.pitch_diameter_m / (2.0 * g.ball_diameter_m) * (1.0 - gm * gm);
  return o;
}

DefectFrequencies defect_frequencies(const BearingGeometry& g, double shaft_speed_hz) {
  const DefectOrders o = defect_orders(g);
  DefectFrequencies f;
  f.shaft_hz = shaft_speed_hz;
  f.ftf_hz = o.ftf * shaft_speed_hz;
  f.bpfo_hz = o.bpfo * shaft_speed_hz;
  f.bpfi_hz = o.bpfi * shaft_speed_hz;
  f.bsf_hz = o.bsf * shaft_speed_hz;
  return f;
}

double cage_speed(const BearingGeometry& g, double inner_speed, double outer_speed) {
  const double gm = g.gamma();
  return 0.5 * ((1.0 - gm) * inner_speed + (1.0 + gm) * outer_speed);
}

double ball_spin_speed(const BearingGeometry& g, double inner_speed, double outer_speed) {
  const double gm = g.gamma();
  return g.pitch_diameter_m / (2.0 * g.ball_diameter_m) * (outer_speed - inner_speed) *
         (1.0 - gm) * (1.0 + gm);
}

}  // namespace amb::model::bearing
