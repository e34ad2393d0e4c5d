#include "firmware/board/parse_bearing.hpp"

#include "model/bearing/catalogue.hpp"

namespace amb::board {

void parse_bearing(TableReader r, fw::BearingParams& b) {
  b.present = true;
  b.monitored = r.string("monitored");
  if (!model::bearing::find_bearing(b.monitored)) {
    std::string known;
    for (const auto& g : model::bearing::bearing_catalogue()) known += (known.empty() ? "" : ", ") + std::string(g.name);
    r.fail("monitored", "not in the bearing catalogue (known: " + known + ")");
  }
  b.radial_clearance_m = r.number_or("radial_clearance_m", b.radial_clearance_m, 0.0, 1e-3);
  b.min_speed_hz = r.number_or("min_speed_hz", b.min_speed_hz, 0.01, 5000.0);
  b.max_speed_hz = r.number_or("max_speed_hz", b.max_speed_hz, b.min_speed_hz, 20000.0);
  if (!(b.max_speed_hz > b.min_speed_hz)) r.fail("max_speed_hz", "must be greater than min_speed_hz");
  b.aux_contact_constant_n_per_m1p5 = r.number("aux_contact_constant_n_per_m1p5", 1e3, 1e14);
  b.aux_dynamic_load_rating_n = r.number_or("aux_dynamic_load_rating_n", 0.0, 0.0, 1e8);
  b.aux_spin_speed_hz = r.number_or("aux_spin_speed_hz", 0.0, 0.0, 5000.0);
  r.finish();
}

}  // namespace amb::board
