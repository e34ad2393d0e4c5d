#pragma once
// Phase E (seed 000 section 2.5, Fig. 13): the load over each auxiliary bearing's
// circumference for one event: the sum of contact forces (superposition of normal and
// tangential: |F| = sqrt(N^2 + T^2)) per 1-degree bin of the contact point's polar angle
// (0 deg = upward vertical, positive towards +x; the bottom is 180 deg).
// "Sum of forces" depends on how often forces are sampled, so it is defined rate-free: each
// Moreau-Jean step adds |F| h / k_load_reference_period_s, i.e. the sum the forces would
// give sampled at 10 kHz (the board's capture rate).
#include <array>
#include <vector>

#include "firmware/wear/wear_record.hpp"
#include "model/drop/drop_model.hpp"

namespace amb::host::wear {

inline constexpr double k_load_reference_period_s = 1e-4;  ///< sampling the load sum refers to, s

struct BearingEventLoad {
  std::array<double, fw::k_load_bins> load_n{};  ///< sum of |F| per bin (see file comment), N
  double peak_force_n = 0.0;                     ///< largest step-mean |F|, N
  double friction_energy_j = 0.0;                ///< friction work dissipated at the contact, J
  double contact_time_s = 0.0;                   ///< time with the contact closed, s
  /// Mean whirl of the contact point while closed, from consecutive contact steps, Hz:
  /// positive with a positive (+z) spin (forward), negative against it (backward whirl).
  double whirl_hz = 0.0;
};

/// Load maps of one event from the drop model's contact steps (DropTrace::contact_steps).
std::array<BearingEventLoad, 2> event_load(const std::vector<model::drop::StepContact>& steps);

/// Bin of a polar angle (deg, any range) in [0, k_load_bins).
int load_bin(double angle_deg);

}  // namespace amb::host::wear
