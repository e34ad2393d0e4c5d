#include "host-tools/core/residual/contact_view.hpp"

#include <stdexcept>

#include "model/amb/amb_force.hpp"

namespace amb::host::residual {

ContactView::ContactView(const model::PlantParams& rig, const model::RigModel& rig_model, bool use_bending) : straight_(rig) {
  rig_model.check_same_rig(rig, "contact view");
  for (size_t k = 0; k < 2; ++k) {
    sensor_z_m_[k] = rig.sensor[2 * k].axial_m;
    aux_z_m_[k] = rig.aux[k].axial_m;
  }
  for (size_t s = 0; s < 4; ++s) sensor_dir_[s] = model::magnet::axis_direction(rig.sensor[s].angle_deg);
  if (!use_bending || rig.rotor.modes_kept <= 2) return;
  try {
    auto f = std::make_unique<model::drop::FlexibleOrbit>(rig_model, sensor_z_m_, aux_z_m_, 1);
    if (f->usable()) flex_ = std::move(f);
  } catch (const std::invalid_argument&) {
    // No bending mode above the rigid-body ones, or coinciding planes: the straight view.
  }
}

ContactView::~ContactView() = default;

double ContactView::bending_hz() const {
  return flex_ && !flex_->bending_frequencies_hz().empty() ? flex_->bending_frequencies_hz()[0] : 0.0;
}

std::vector<std::array<double, 4>> ContactView::from_aux_planes(const std::vector<std::array<double, 4>>& aux_m) const {
  std::vector<std::array<double, 4>> out(aux_m.size());
  const double span = aux_z_m_[1] - aux_z_m_[0];
  for (size_t i = 0; i < aux_m.size(); ++i) {
    const auto& a = aux_m[i];
    for (size_t p = 0; p < 2; ++p) {
      const double s = (sensor_z_m_[p] - aux_z_m_[0]) / span;
      const double x = a[0] + s * (a[2] - a[0]), y = a[1] + s * (a[3] - a[1]);
      for (size_t j = 0; j < 2; ++j) {
        const auto& d = sensor_dir_[2 * p + j];
        out[i][2 * p + j] = d[0] * x + d[1] * y;
      }
    }
  }
  return out;
}

std::vector<std::array<double, 4>> ContactView::contact_readings(const std::vector<std::array<double, 4>>& sensor_m, double fs_hz) const {
  if (!flex_ || sensor_m.size() < 2 || !(fs_hz > 0.0)) return sensor_m;
  std::vector<std::array<double, 4>> planes(sensor_m.size());
  for (size_t i = 0; i < sensor_m.size(); ++i) {
    const auto p0 = straight_.at_sensor_plane(sensor_m[i], 0), p1 = straight_.at_sensor_plane(sensor_m[i], 1);
    planes[i] = {p0[0], p0[1], p1[0], p1[1]};
  }
  return from_aux_planes(flex_->aux_planes(planes, 1.0 / fs_hz));
}

}  // namespace amb::host::residual
