#include "firmware/board/parse_journal.hpp"

namespace amb::board {

void parse_journal_bearing(TableReader r, model::journal::JournalBearingParams& j, double rotor_length_m) {
  j.present = true;
  j.axial_m = r.number("axial_m", 0.0, rotor_length_m);
  j.geometry.bore_radius_m = 0.5 * r.number("bore_diameter_m", 1e-3, 2.0);
  j.geometry.length_m = r.number("width_m", 1e-3, 2.0);
  j.geometry.clearance_m = r.number("radial_clearance_m", 1e-6, 0.05 * j.geometry.bore_radius_m);
  j.geometry.viscosity_pa_s = r.number("viscosity_pa_s", 1e-4, 10.0);
  j.static_eccentricity = r.number("static_eccentricity", 0.0, 0.95);
  j.static_direction_deg = r.number_or("static_direction_deg", 180.0, -180.0, 180.0);
  j.grid.cells_theta = static_cast<int>(r.integer_or("cells_theta", 72, 12, 2000));
  j.grid.cells_axial = static_cast<int>(r.integer_or("cells_axial", 12, 2, 400));
  const auto ang = r.numbers("probe_angle_deg", 2, -180.0, 180.0);
  j.probe_angle_deg = {ang[0], ang[1]};
  j.probe_noise_rms_m = r.number_or("probe_noise_rms_m", 0.0, 0.0, 1e-4);
  r.finish();
}

}  // namespace amb::board
