#pragma once
// Nonlinear force of one AMB actuator axis (an opposed coil pair), seed 002 eq. 14 with the
// iron path l_i / mu_r neglected against the air gap and the pole angle folded into k:
//   F = k [ (i0 + ic)^2 / (g0 - z)^2 - (i0 - ic)^2 / (g0 + z)^2 ]      (N)
// z: rotor displacement along the axis towards the "+" coil (m), ic: control current (A).
// Linearised at z = 0, ic = 0:  F = ks z + ki ic,  ks = 4 k i0^2 / g0^3,  ki = 4 k i0 / g0^2.
// The law is built from (ks, ki, g0): i0 = ks g0 / ki and k = ki g0^2 / (4 i0), so that the
// linearisation is exactly the board's ks and ki. Flux saturation caps the pull of each coil
// at max_force_n (so |F| <= max_force_n); coil currents cannot go negative.
#include <array>

#include "model/plant/plant_params.hpp"

namespace amb::model::magnet {

struct AxisLaw {
  double k_n_m2_per_a2 = 0.0;    ///< force constant k, N m^2 / A^2
  double bias_a = 0.0;           ///< bias current i0, A
  double gap_m = 0.0;            ///< nominal air gap g0, m
  double max_coil_force_n = 0.0; ///< saturation pull of one coil, N
  double min_gap_m = 0.0;        ///< the gap used in the law never drops below this, m
};

/// The law of one AMB (both axes share it).
AxisLaw make_axis_law(const AmbParams& p);

/// Force along the axis, N (see file comment). No allocation; real-time safe.
double axis_force_n(const AxisLaw& law, double z_m, double ic_a);

/// Analytic partial derivatives at (z, ic): dF/dz (N/m) and dF/dic (N/A), without saturation.
struct Linearisation {
  double ks_n_per_m = 0.0;
  double ki_n_per_a = 0.0;
};
Linearisation linearise(const AxisLaw& law, double z_m, double ic_a);

/// Control current (A) at which the pair pulls with zero force with the rotor at `z_m` along
/// the axis: (i0 + ic) / (g0 - z) = (i0 - ic) / (g0 + z), i.e. ic = -i0 z / g0, with z held
/// inside the gap (|z| <= g0 - min_gap). A set-point feed-forward: with it the bias flux does
/// not pull a rotor held off-centre towards the nearer pole. No allocation; real-time safe.
double zero_force_current_a(const AxisLaw& law, double z_m);

/// Unit vector (x, y) of an axis at `angle_deg` from the upward vertical, positive towards +x.
std::array<double, 2> axis_direction(double angle_deg);

}  // namespace amb::model::magnet
