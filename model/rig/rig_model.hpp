#pragma once
// One rig's structure, built once from its board's plant parameters and then only read
// (the Model half of a Model/Data split): the finite-element rotor, its complete free-free
// modal basis (one eigen solve), and, at any modal truncation, the reduced rotor with the
// modal rows at every plane the rig has (AMB actuators, sensors, aux bearings, disks, the
// coupling end), the modal gravity load and the AMB force laws with their linearisation.
//
// Every model of the rig takes it by `const&` (or shares it through
// `std::shared_ptr<const RigModel>` when it must outlive the caller) and keeps only its own
// state: the SIL plant (model/plant), the drop model (model/drop), the loop models of the
// residual engine (model/effects), the closed-loop analysis (model/analysis), the journal
// rig and the host's fits. The plant that makes a record and the model fitted to it therefore
// share one structure by construction.
//
// What belongs to the rig model: the rotor (elements, disks' mass and inertia, Rayleigh
// damping), the axial positions of the planes, gravity and the AMB laws. What does not:
// everything a fit or an effect varies (aux-bearing offsets, friction, clearances, contact
// law, unbalance, sensor gains and noise); users read those from their own PlantParams.
// `check_same_rig` refuses parameters that describe another rotor or other planes.
//
// Building allocates (configure time). Thread-safe once built: every member is const.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "model/amb/amb_force.hpp"
#include "model/plant/plant_params.hpp"
#include "model/rotor/modal_reduction.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::model {

/// The rig at one modal truncation. Rows map modal coordinates (one plane) to the lateral
/// displacement at a plane, m per unit modal coordinate; vectors are per kept mode.
struct RigReduction {
  rotor::ReducedRotor reduced;               ///< kept modes per plane, shapes, w^2, damping, polar
  Eigen::VectorXd gravity_y_n;               ///< modal gravity load along -y, N per mode (Phi^T M (-g t))
  std::array<Eigen::RowVectorXd, 2> amb;     ///< at the AMB planes [A, B]
  std::array<Eigen::RowVectorXd, 2> aux;     ///< at the aux-bearing planes [A, B]
  std::array<Eigen::RowVectorXd, 4> sensor;  ///< at the sensor planes, channel order [A1, A2, B1, B2]
  Eigen::RowVectorXd coupling;               ///< at the right end (z = rotor length): coupling
  std::vector<Eigen::RowVectorXd> disk;      ///< at each rigid disk, board order
  int mid_disk = -1;                         ///< index of the disk nearest mid-span (-1: no disks)
  Eigen::RowVectorXd mid_span;               ///< at mid-span (z = length / 2)
  int modes() const { return reduced.modes; }
};

/// The disks' unbalance of `rotor` (the user's own parameters: unbalance and phase) expanded on
/// the rows of `r` in cos/sin of the spin angle: a disk at angle a_d = phase_d - theta pulls
/// u (W^2 (sin a, cos a) + W' (cos a, -sin a)), whose sums are S = sum b_d u_d sin(phase_d) and
/// C = sum b_d u_d cos(phase_d) (kg m per mode). Also the row and phase of the disk nearest
/// mid-span (mid-span itself, phase 0, without disks).
struct UnbalanceExpansion {
  Eigen::VectorXd sin_sum, cos_sum;  ///< S and C, kg m per mode
  Eigen::RowVectorXd mid_row;        ///< modal row of the disk nearest mid-span
  double mid_phase_rad = 0.0;        ///< its unbalance phase, rad
};
UnbalanceExpansion unbalance_expansion(const RigReduction& r, const RotorParams& rotor);

class RigModel {
 public:
  /// Builds the FE rotor (once) and its complete modal basis (one eigen solve), then the
  /// reduction at the board's modes_kept. Throws std::invalid_argument for a rotor it cannot
  /// build (see rotor::build_rotor_model).
  explicit RigModel(const PlantParams& p);
  static std::shared_ptr<const RigModel> make(const PlantParams& p) { return std::make_shared<const RigModel>(p); }

  const PlantParams& params() const { return p_; }          ///< the parameters it was built from
  const rotor::RotorModel& rotor() const { return fe_; }    ///< full FE model
  const rotor::ReducedRotor& modal_basis() const { return basis_; } ///< every planar mode
  /// The reduction at the board's modes_kept (built once).
  const RigReduction& board_reduction() const { return board_; }
  /// The reduction at `modes_per_plane` modes (<= 0 or above the basis: all of them), cut
  /// from the basis: no FE build and no eigen solve. Bit-identical to rotor::reduce_rotor.
  RigReduction reduction(int modes_per_plane) const;
  /// Modal row of the displacement at any axial position, for the reduction `r`.
  Eigen::RowVectorXd modal_row(const RigReduction& r, double axial_m) const;

  double mass_kg() const { return fe_.mass_kg; }
  double weight_n() const { return fe_.mass_kg * p_.gravity_m_s2; }
  /// The force law of AMB `b` (0: A, 1: B) and its linearisation at the centre with zero
  /// control current: ks (N/m, positive = destabilising) and ki (N/A).
  const magnet::AxisLaw& amb_law(size_t b) const { return law_[b]; }
  magnet::Linearisation amb_linearisation(size_t b) const { return lin_[b]; }

  /// Empty when `p` describes the same rotor and planes as this model, else what differs
  /// (e.g. "aux bearing 1 axial_m 0.412 vs 0.420"). Parameters a fit varies are not compared.
  std::string differs_from(const PlantParams& p) const;
  /// Throws std::invalid_argument("<who>: the rig model was built for another rotor: ...").
  void check_same_rig(const PlantParams& p, const char* who) const;

 private:
  PlantParams p_;
  rotor::RotorModel fe_;
  rotor::ReducedRotor basis_;
  RigReduction board_;
  std::array<magnet::AxisLaw, 2> law_{};
  std::array<magnet::Linearisation, 2> lin_{};
};

}  // namespace amb::model
