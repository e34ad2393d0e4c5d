#pragma once
// Identification of the contact-stiffness scale eta (seed 003 section 4): k_b = eta k_b,nom is
// chosen so that the 4-DOF model's housing acceleration matches a measured record in the
// frequency domain (eq. 9):
//   f(eta) = sqrt( 1/N sum_i ( |G_meas,i| - |G_sim,i(eta)| )^2 )   over the bins of a band.
// Magnitudes are compared, not complex values: the measured record's phase depends on the
// unknown start angle of the cage, which the model cannot know. (Eq. 9 writes |g_meas - g_sim|
// with g the DFT values; the extracted text does not say whether g is complex or a magnitude.)
//
// Two optimisers: seed 003's artificial fish swarm (AFSA, chaotic logistic initialisation,
// eq. 10-11, swarm 20, 15 iterations, visual 0.5, step 0.01, crowding 1.68) as the reference,
// and a fast one: a log-grid scan, zoomed around the best point until its spacing is 1.5 %,
// then Brent's parabolic / golden-section search inside the final bracket.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "model/bearing/hertz_4dof.hpp"

namespace amb::model::bearing {

enum class EtaMethod { afsa, brent };

/// Options (Ceres style: defaults, validity check).
struct StiffnessIdOptions {
  EtaMethod method = EtaMethod::brent;
  double eta_min = 0.5;         ///< lower bound of the search, dimensionless (> 0)
  double eta_max = 2.0;         ///< upper bound, dimensionless (> eta_min)
  double fs_hz = 20000.0;       ///< sample rate of the measured record, Hz
  double band_low_hz = 0.0;     ///< cost band lower edge, Hz
  double band_high_hz = 0.0;    ///< cost band upper edge, Hz (0: Nyquist)
  /// Width of a moving-average smoothing of both magnitude spectra before eq. 9, Hz (0: none).
  /// Default off: smoothing averages the measurement noise floor into the magnitudes, which
  /// biases eta (measured +7 % at eta 1.3 with 200 Hz); the fast method instead zooms its grid.
  double smoothing_hz = 0.0;
  // Brent (fast method)
  int grid_points = 7;           ///< log-spaced bracketing scan points per zoom level (>= 5)
  double zoom_spacing = 0.015;   ///< zoom until the grid spacing is below this relative step
                                 ///< (f(eta) has side minima ~4 % apart where a resonance flank
                                 ///< crosses a defect harmonic; the grid must resolve them)
  double eta_tolerance = 1e-3;   ///< relative tolerance on eta for Brent, dimensionless
  int max_evaluations = 60;      ///< cost evaluations budget (both methods stop at it)
  // AFSA (seed 003 section 4.2). Positions live in u in [0, 1], eta = eta_min (eta_max/eta_min)^u.
  int swarm_size = 20;           ///< fish, seed 003: 20
  int max_iterations = 15;       ///< seed 003: 15
  double visual = 0.5;           ///< visual distance in u, seed 003: 0.5
  double step = 0.01;            ///< step in u, seed 003: 0.01
  double crowding = 1.68;        ///< crowding factor delta, seed 003: 1.68
  int prey_tries = 3;            ///< random probes in the prey behaviour (not given by seed 003: ASSUMED)
  double logistic_mu = 4.0;      ///< logistic map parameter (chaotic for 3.5699 <= mu <= 4)
  double logistic_x0 = 0.3141;   ///< logistic map start, not a fixed point (0, 0.25, 0.5, 0.75, 1 are bad)
  uint64_t seed = 1;             ///< random stream of AFSA's prey/step draws
  int afsa_max_evaluations = 2000;  ///< AFSA's own budget (it needs many more than Brent)
  bool valid() const;
};

/// Summary: why it stopped and how good the result is.
struct StiffnessIdSummary {
  double eta = 0.0;             ///< identified scale, dimensionless
  double cost = 0.0;            ///< eq. 9 at eta, spectrum units (m/s^2 per bin)
  int evaluations = 0;          ///< model simulations run
  double wall_s = 0.0;          ///< wall time of the identification, s
  bool converged = false;       ///< tolerance met (Brent) / iterations completed (AFSA)
  std::string termination;      ///< why it stopped
  double effective_stiffness_n_per_m = 0.0;  ///< eq. 8 at the static state with the identified eta
};

/// Identify eta for the model `base` (its stiffness_scale is ignored) driven by `shaft_speed_hz`,
/// from `measured` (housing acceleration, m/s^2, sampled at o.fs_hz, starting at t = 0).
/// Throws std::invalid_argument if the options or parameters are invalid.
StiffnessIdSummary identify_stiffness_scale(const Hertz4DofParams& base,
                                            const std::function<double(double t_s)>& shaft_speed_hz,
                                            const std::vector<double>& measured,
                                            const StiffnessIdOptions& o);

/// The eq. 9 cost, exposed for tests and plots: evaluates f(eta) for one eta.
class SpectralCost {
 public:
  SpectralCost(const Hertz4DofParams& base, std::function<double(double t_s)> shaft_speed_hz,
               const std::vector<double>& measured, double fs_hz, double band_low_hz, double band_high_hz,
               double smoothing_hz = 0.0);
  ~SpectralCost();
  SpectralCost(const SpectralCost&) = delete;
  SpectralCost& operator=(const SpectralCost&) = delete;
  /// f(eta); throws std::invalid_argument if eta <= 0.
  double operator()(double eta);
  int evaluations() const { return evaluations_; }

 private:
  void magnitude(const std::vector<double>& x, std::vector<double>& mag);
  Hertz4DofParams base_;
  std::function<double(double)> speed_;
  double fs_hz_;
  size_t n_;
  size_t k0_, k1_;
  size_t smooth_bins_ = 1;
  std::vector<double> meas_mag_, sim_mag_, sim_, fft_in_, raw_mag_;
  std::vector<double> fft_out_;  // interleaved complex
  void* plan_ = nullptr;         // fftw_plan, created once
  int evaluations_ = 0;
};

}  // namespace amb::model::bearing
