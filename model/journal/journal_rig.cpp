#include "model/journal/journal_rig.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

#include "model/rotor/modal_reduction.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::model::journal {

JournalState static_journal_state(const JournalBearingParams& jb) {
  const double a = jb.static_direction_deg * M_PI / 180.0;
  const double e = jb.static_eccentricity * jb.geometry.clearance_m;
  return {e * std::sin(a), e * std::cos(a), 0.0, 0.0};
}

RigStatics static_state(const PlantParams& rig, double at_axial_m, double force_axial_m, double fx_n, double fy_n) {
  return static_state(RigModel(rig), at_axial_m, force_axial_m, fx_n, fy_n);
}

RigStatics static_state(const RigModel& rig_model, double at_axial_m, double force_axial_m, double fx_n, double fy_n) {
  const PlantParams& rig = rig_model.params();
  const rotor::RotorModel& fe = rig_model.rotor();
  const rotor::ReducedRotor& red = rig_model.board_reduction().reduced;
  const int m = red.modes;
  // Unknowns: modal displacements and the two AMB forces; rows: modal equilibrium and the
  // two sensor planes at zero. x and y planes decouple at rest.
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m + 2, m + 2);
  a.topLeftCorner(m, m) = red.omega2.asDiagonal();
  for (int b = 0; b < 2; ++b) {
    a.block(0, m + b, m, 1) = -rotor::modal_interpolation(fe, red, rig.amb[static_cast<size_t>(b)].axial_m).transpose();
    // Sensor planes of AMB b: the sensors of channels 2b, 2b+1 share a plane.
    a.block(m + b, 0, 1, m) = rotor::modal_interpolation(fe, red, rig.sensor[static_cast<size_t>(2 * b)].axial_m);
  }
  const Eigen::RowVectorXd bf = rotor::modal_interpolation(fe, red, force_axial_m);
  const Eigen::RowVectorXd bat = rotor::modal_interpolation(fe, red, at_axial_m);
  Eigen::VectorXd rx = Eigen::VectorXd::Zero(m + 2), ry = Eigen::VectorXd::Zero(m + 2);
  rx.head(m) = fx_n * bf.transpose();
  ry.head(m) = fy_n * bf.transpose() + rotor::modal_gravity_load(fe, red, rig.gravity_m_s2);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  if (lu.rank() < m + 2) throw std::invalid_argument("journal placement: the sensor planes do not hold the rotor");
  const Eigen::VectorXd sx = lu.solve(rx), sy = lu.solve(ry);
  RigStatics st;
  st.at_m = {bat.dot(sx.head(m)), bat.dot(sy.head(m))};
  for (int b = 0; b < 2; ++b) {
    const Eigen::RowVectorXd ba = rotor::modal_interpolation(fe, red, rig.amb[static_cast<size_t>(b)].axial_m);
    st.amb_force_n[static_cast<size_t>(b)] = {sx(m + b), sy(m + b)};
    st.amb_displacement_m[static_cast<size_t>(b)] = {ba.dot(sx.head(m)), ba.dot(sy.head(m))};
  }
  return st;
}

std::array<double, 2> static_displacement_m(const PlantParams& rig, double at_axial_m, double force_axial_m,
                                            double fx_n, double fy_n) {
  return static_state(rig, at_axial_m, force_axial_m, fx_n, fy_n).at_m;
}

LinearJournal place_journal(const PlantParams& rig, const JournalBearingParams& jb, double spin_rad_s) {
  return place_journal(rig, jb, spin_rad_s, FilmCoefficientsFn{});
}

LinearJournal place_journal(const PlantParams& rig, const JournalBearingParams& jb, double spin_rad_s,
                            const FilmCoefficientsFn& film) {
  if (!jb.present) return {};
  if (!(jb.static_eccentricity >= 0.0 && jb.static_eccentricity <= 0.95))
    throw std::invalid_argument("journal placement: static_eccentricity must be in [0, 0.95]");
  if (!(spin_rad_s > 0.0)) throw std::invalid_argument("journal placement: linearisation speed must be > 0");
  const JournalState s = static_journal_state(jb);
  LinearJournal j;
  j.enabled = true;
  j.axial_m = jb.axial_m;
  j.lin_x_m = s.x_m;
  j.lin_y_m = s.y_m;
  j.ref_spin_rad_s = spin_rad_s;
  if (film) {
    j.coeff = film(s, spin_rad_s);
  } else {
    ReynoldsSolver solver(jb.geometry, jb.wear, jb.grid);
    j.coeff = perturbation_coefficients(solver, s, spin_rad_s);
  }
  j.probe_angle_deg = jb.probe_angle_deg;
  j.probe_noise_rms_m = jb.probe_noise_rms_m;
  j.clearance_m = jb.geometry.clearance_m;
  const auto q = static_displacement_m(rig, jb.axial_m, jb.axial_m, j.coeff.fx0_n, j.coeff.fy0_n);
  j.bore_x_m = q[0] - s.x_m;
  j.bore_y_m = q[1] - s.y_m;
  return j;
}

LinearJournal relinearise_journal(const LinearJournal& j, const JournalBearingParams& jb, double x_m, double y_m) {
  return relinearise_journal(j, jb, x_m, y_m, FilmCoefficientsFn{});
}

LinearJournal relinearise_journal(const LinearJournal& j, const JournalBearingParams& jb, double x_m, double y_m,
                                  const FilmCoefficientsFn& film) {
  if (!j.enabled) throw std::invalid_argument("journal re-linearisation: the element is not enabled");
  if (!(std::hypot(x_m, y_m) < 0.98 * jb.geometry.clearance_m))
    throw std::invalid_argument("journal re-linearisation: position outside 0.98 of the clearance");
  LinearJournal r = j;
  r.lin_x_m = x_m;
  r.lin_y_m = y_m;
  if (film) {
    r.coeff = film({x_m, y_m, 0.0, 0.0}, j.ref_spin_rad_s);
  } else {
    ReynoldsSolver solver(jb.geometry, jb.wear, jb.grid);
    r.coeff = perturbation_coefficients(solver, {x_m, y_m, 0.0, 0.0}, j.ref_spin_rad_s);
  }
  return r;
}

}  // namespace amb::model::journal
