#pragma once
// Physical description of a rotor-AMB rig, as the board file gives it. Pure data, SI units.
#include <array>
#include <string>
#include <vector>

namespace amb::model {

/// One Timoshenko beam element of the rotor, left to right.
struct BeamElement {
  double length_m = 0.0;            ///< element length, m
  double outer_diameter_m = 0.0;    ///< outer diameter, m
  double inner_diameter_m = 0.0;    ///< bore, m (0 for solid)
  double density_kg_m3 = 7800.0;    ///< mass density, kg/m^3
  double youngs_modulus_pa = 2.1e11;///< Young's modulus, Pa
  double poisson_ratio = 0.3;       ///< for the shear modulus G = E / (2 (1 + nu))
  bool structural = true;           ///< false: adds mass/inertia but no stiffness (e.g. laminations)
};

/// A rigid disk attached at an axial position.
struct RigidDisk {
  double axial_m = 0.0;             ///< position from the rotor's left end, m (must be a node)
  double mass_kg = 0.0;             ///< mass, kg
  double polar_inertia_kg_m2 = 0.0; ///< about the spin axis, kg m^2
  double transverse_inertia_kg_m2 = 0.0; ///< about a diameter, kg m^2
  double unbalance_kg_m = 0.0;      ///< mass times eccentricity, kg m
  double unbalance_phase_deg = 0.0; ///< angle of the unbalance at spin angle 0, deg
};

struct RotorParams {
  std::vector<BeamElement> elements;///< left to right; nodes are at element ends
  std::vector<RigidDisk> disks;
  double rayleigh_alpha_1_per_s = 0.0; ///< mass-proportional damping, 1/s
  double rayleigh_beta_s = 0.0;        ///< stiffness-proportional damping, s
  int modes_kept = 0;               ///< modal reduction: lowest modes kept (0: keep all DOF)
};

/// One radial AMB: two opposed coil pairs on actuator axes (usually +-45 deg from vertical).
/// Force per actuator axis (seed 002 eq. 14 with l_i/mu_r neglected against the gap):
///   F = k [ (i0 + ic)^2 / (g0 - z)^2 - (i0 - ic)^2 / (g0 + z)^2 ],
/// whose linearisation is F = ks z + ki ic with ks = 4 k i0^2 / g0^3, ki = 4 k i0 / g0^2.
struct AmbParams {
  double axial_m = 0.0;             ///< actuator plane from the rotor's left end, m
  double gap_m = 0.0;               ///< nominal air gap g0, m
  double bias_current_a = 0.0;      ///< bias current i0, A
  double ks_n_per_m = 0.0;          ///< negative (destabilising) stiffness at the centre, N/m
  double ki_n_per_a = 0.0;          ///< current gain at the centre, N/A
  double max_force_n = 0.0;         ///< force capacity of one actuator axis, N (flux saturation)
  double coil_current_limit_a = 0.0;///< amplifier limit on |ic|, A
  double amplifier_bandwidth_hz = 0.0; ///< current-loop bandwidth (first-order), Hz
  std::array<double, 2> actuator_angle_deg{45.0, -45.0}; ///< axis directions from upward vertical, deg
};

/// One displacement sensor (non-collocated: its own axial plane).
struct SensorParams {
  double axial_m = 0.0;             ///< sensor plane, m
  double angle_deg = 0.0;           ///< measuring direction from upward vertical, deg
  double noise_rms_m = 0.0;         ///< white measurement noise, m rms
  double bandwidth_hz = 0.0;        ///< first-order sensor/anti-alias roll-off, Hz (0: none)
};

/// An auxiliary (touchdown) bearing.
/// Contact law of the drop model (model/drop) at an auxiliary bearing, chosen per board
/// (`[[rig.aux_bearing]] contact_law`). The SIL plant (rotor_amb_plant) keeps its own penalty law.
///  rigid:  unilateral rigid contact, Newton restitution (Moreau-Jean);
///  hertz:  compliant, F = K d^1.5 + damping, never pulling (K from contact_stiffness_n_per_m);
///  linear: compliant, F = k d + damping (Kelvin-Voigt penalty), never pulling.
enum class AuxContactLaw : int { rigid = 0, hertz = 1, linear = 2 };

struct AuxBearingParams {
  double axial_m = 0.0;             ///< bearing plane, m
  double clearance_m = 0.0;         ///< radial clearance to the rotor collar, m
  double contact_stiffness_n_per_m = 0.0; ///< penalty/contact stiffness, N/m
  double contact_damping_n_s_per_m = 0.0; ///< contact damping, N s/m
  double friction_coefficient = 0.0;///< Coulomb friction rotor collar / inner ring
  double collar_radius_m = 0.0;     ///< rotor collar radius at the contact, m
  double ring_inertia_kg_m2 = 0.0;  ///< inner ring polar inertia, kg m^2
  double ring_friction_torque_n_m = 0.0; ///< bearing drag torque on the inner ring, N m
  double centre_offset_x_m = 0.0;   ///< bearing centre relative to the sensor zero, m
  double centre_offset_y_m = 0.0;
  AuxContactLaw contact_law = AuxContactLaw::rigid; ///< drop-model contact law (board key contact_law)
};

struct PlantParams {
  std::string rig_name;
  RotorParams rotor;
  std::array<AmbParams, 2> amb{};
  std::array<SensorParams, 4> sensor{};   ///< channel order [A1, A2, B1, B2] as the HAL
  std::array<AuxBearingParams, 2> aux{};
  double gravity_m_s2 = 9.81;             ///< along -y (downwards)
  double drive_torque_limit_n_m = 0.0;    ///< motor drive torque limit, N m
  double drive_speed_gain_n_m_s = 0.0;    ///< speed-loop gain of the drive, N m per rad/s
  double integration_step_s = 0.0;        ///< plant integrator step, s (sub-steps of the loop period)
};

/// Faults the plant can be told to exhibit (SIL fault injection). The firmware never sees this.
struct PlantFaults {
  std::array<double, 4> current_factor{1.0, 1.0, 1.0, 1.0}; ///< amplifier output scale per axis (0: cut-off)
  std::array<double, 4> disturbance_amplitude_a{};          ///< additive sinusoid on each coil current, A
  double disturbance_frequency_hz = 0.0;
  double disturbance_start_s = 1e30;                        ///< time the disturbance starts, s
  double unbalance_growth_kg_m_per_s = 0.0;                 ///< added unbalance rate at the mid disk, kg m/s
  double unbalance_growth_start_s = 1e30;
  double misalignment_rate_m_per_s = 0.0;                   ///< drift of a coupling-side static force point, m/s
  double misalignment_direction_deg = 0.0;                  ///< direction of that drift, deg from vertical
  double misalignment_start_s = 1e30;
  double misalignment_stiffness_n_per_m = 0.0;              ///< coupling stiffness that converts drift to force
};

}  // namespace amb::model
