// Compliant contact laws of the drop model (model/drop/compliant_contact.hpp) against the
// project's penalty plant (model/plant RotorAmbPlant, written independently of the drop
// model: explicit sub-stepping, Kelvin-Voigt contact, sqrt-regularised friction): same rig,
// same initial state (levitated centre, amplifiers off, spin), same contact law ("linear").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "drop_test_util.hpp"
#include "model/plant/rotor_amb_plant.hpp"
#include "tests/support/test_paths.hpp"

namespace md = amb::model::drop;

namespace {

struct Trace {
  std::vector<double> x, y, fn, spin_hz;
};

template <class P>
Trace free_drop(P& plant, double spin_hz, double duration_s, double dt_s = 1e-4) {
  plant.reset(true, spin_hz);
  amb::model::PlantInputs in;
  in.amplifiers_enabled = false;
  Trace r;
  const int n = static_cast<int>(std::lround(duration_s / dt_s));
  for (int i = 0; i < n; ++i) {
    plant.step(dt_s, in);
    const auto tr = plant.truth();
    r.x.push_back(tr.aux_x_m[0]);
    r.y.push_back(tr.aux_y_m[0]);
    r.fn.push_back(tr.contact_force_n[0]);
    r.spin_hz.push_back(plant.outputs().spin_speed_hz);
  }
  return r;
}

int first_contact(const Trace& t) {
  for (size_t i = 0; i < t.fn.size(); ++i)
    if (t.fn[i] > 0.0) return static_cast<int>(i);
  return -1;
}

// Mean whirl rate of the contact point (rad/s, counter-clockwise positive) from sample i0 on.
double whirl_rate(const Trace& t, size_t i0, double dt_s) {
  double ang = 0.0, prev = std::atan2(t.y[i0], t.x[i0]);
  for (size_t i = i0 + 1; i < t.x.size(); ++i) {
    const double a = std::atan2(t.y[i], t.x[i]);
    ang += std::remainder(a - prev, 2.0 * M_PI);
    prev = a;
  }
  return ang / (dt_s * static_cast<double>(t.x.size() - 1 - i0));
}

md::DropOptions plant_like(const amb::model::PlantParams& p, md::ContactLawChoice law) {
  md::DropOptions o;
  o.internal_controller = false;
  o.sensor_noise = false;
  o.modes_per_plane = p.rotor.modes_kept;
  o.contact_law = law;
  return o;
}

}  // namespace

TEST(CompliantContact, LinearLawAgreesWithPenaltyPlantThroughImpactsAndRub) {
  // Board rotor and friction 0.15 at 2700 rpm: bouncing, then rubbing at the bottom.
  const auto p = amb::test::bath_board().plant;
  amb::model::RotorAmbPlant plant(p);
  const double dt = 1e-4, dur = 0.4;
  const Trace a = free_drop(plant, 45.0, dur, dt);
  auto m = amb::test::make_drop_model(p, plant_like(p, md::ContactLawChoice::linear));
  const Trace b = free_drop(*m, 45.0, dur, dt);
  const int ia = first_contact(a), ib = first_contact(b);
  ASSERT_GT(ia, 0);
  EXPECT_NEAR(ib, ia, 1);  // first impact within one sample (0.1 ms)
  // First impact's peak force within 5 %, and the second impact at the same sample +- 2.
  const auto peak = [](const Trace& t, int i0) { return *std::max_element(t.fn.begin() + i0, t.fn.begin() + i0 + 30); };
  EXPECT_NEAR(peak(b, ib), peak(a, ia), 0.05 * peak(a, ia));
  // Spin-down over the window: within 1 % of the plant's.
  const double da = a.spin_hz.front() - a.spin_hz.back(), db = b.spin_hz.front() - b.spin_hz.back();
  EXPECT_GT(da, 1.0);
  EXPECT_NEAR(db, da, 0.01 * da);
  // The model never ends an impact with a deep penetration (< 5 % of the clearance).
  EXPECT_LT(m->counters().max_penetration_m, 0.05 * p.aux[0].clearance_m);
  EXPECT_EQ(m->counters().solver_unconverged, 0u);
}

TEST(CompliantContact, BackwardWhirlLikeThePenaltyPlant) {
  // High friction against a heavy ring with unbalance: dry-friction backward whirl in the
  // plant; the compliant model must whirl the same way at a comparable rate, the rigid model
  // is shown for contrast (not asserted beyond running).
  auto p = amb::test::bath_board().plant;
  for (auto& a : p.aux) {
    a.friction_coefficient = 0.4;
    a.ring_inertia_kg_m2 = 2e-3;
  }
  for (auto& d : p.rotor.disks) d.unbalance_kg_m = 1e-4;
  amb::model::RotorAmbPlant plant(p);
  const double dt = 1e-4, dur = 0.3;
  const Trace a = free_drop(plant, 45.0, dur, dt);
  auto m = amb::test::make_drop_model(p, plant_like(p, md::ContactLawChoice::linear));
  const Trace b = free_drop(*m, 45.0, dur, dt);
  const double wa = whirl_rate(a, 1000, dt), wb = whirl_rate(b, 1000, dt);
  RecordProperty("plant_whirl_rad_s", std::to_string(wa));
  RecordProperty("model_whirl_rad_s", std::to_string(wb));
  std::printf("whirl rate plant %.1f rad/s, compliant model %.1f rad/s; spin end %.2f / %.2f Hz\n", wa, wb,
              a.spin_hz.back(), b.spin_hz.back());
  ASSERT_LT(wa, -2.0 * M_PI * 20.0);  // the plant whirls backward (against the +z spin)
  EXPECT_LT(wb, -2.0 * M_PI * 20.0);
  EXPECT_NEAR(wb, wa, 0.15 * std::abs(wa));
  EXPECT_NEAR(b.spin_hz.back(), a.spin_hz.back(), 0.03 * a.spin_hz.front());
}

// The board's contact_stiffness_n_per_m is the contact stiffness dF/dd at the reference
// penetration (10 um): K = k / (1.5 sqrt(d_ref)) for the Hertz law, K = k for the linear one.
// Checked on the helper and on the model: the rigid rotor resting on both rings (spin 0,
// amplifiers off, the bounce damped out) sinks in by (W / 2 / K)^(2/3) at each bearing, where
// the secant definition (K 1.5 x larger) would give 24 % less.
TEST(CompliantContact, HertzCoefficientFromTheTangentStiffness) {
  namespace md = amb::model::drop;
  const double k = 1e8, dref = 1e-5, kh = md::contact_law_coefficient(k, 1.5, dref);
  const double dd = 1e-9;
  EXPECT_NEAR((kh * std::pow(dref + dd, 1.5) - kh * std::pow(dref - dd, 1.5)) / (2.0 * dd), k, 1e-6 * k);
  EXPECT_DOUBLE_EQ(md::contact_law_coefficient(k, 1.0, dref), k);
  EXPECT_NEAR(md::contact_law_stiffness(kh, 1.5, dref), k, 1e-9 * k);

  auto p = amb::test::bath_board().plant;
  for (auto& d : p.rotor.disks) d.unbalance_kg_m = 0.0;
  md::DropOptions o;
  o.modes_per_plane = 2;
  o.sensor_noise = false;
  auto model = amb::test::make_drop_model(p, o);
  ASSERT_TRUE(model->compliant());
  model->reset(false, 0.0);
  amb::model::PlantInputs in;
  in.amplifiers_enabled = false;
  for (int i = 0; i < 3000; ++i) model->step(1e-4, in);
  const auto t = model->truth();
  const double w_share = 0.5 * model->rotor_mass_kg() * p.gravity_m_s2;
  const double expected = std::pow(w_share / md::contact_law_coefficient(p.aux[0].contact_stiffness_n_per_m, 1.5, dref), 2.0 / 3.0);
  for (int b = 0; b < 2; ++b) {
    const double pen = std::hypot(t.aux_x_m[static_cast<size_t>(b)], t.aux_y_m[static_cast<size_t>(b)]) - p.aux[static_cast<size_t>(b)].clearance_m;
    EXPECT_NEAR(pen, expected, 0.03 * expected) << "bearing " << b;
  }
}

TEST(CompliantContact, BoardSelectsTheLawAndRefusesUnknownOnes) {
  std::ifstream f(std::string(amb::test::source_dir()) + "/boards/bath-amb-rig.toml");
  ASSERT_TRUE(f.good());
  std::stringstream ss;
  ss << f.rdbuf();
  std::string text = ss.str();
  const auto with_law = [&](const std::string& law) {
    std::string t = text;
    size_t pos = 0;
    while ((pos = t.find("[[rig.aux_bearing]]\n", pos)) != std::string::npos) {
      pos += 20;
      // Drop any contact_law line of the board, then state the one under test.
      const size_t end = t.find("\n\n", pos);
      const size_t old = t.find("contact_law", pos);
      if (old != std::string::npos && old < end) t.erase(old, t.find('\n', old) + 1 - old);
      t.insert(pos, "contact_law = \"" + law + "\"\n");
    }
    return t;
  };
  EXPECT_EQ(amb::board::parse_board(with_law("hertz"), "test").plant.aux[1].contact_law, amb::model::AuxContactLaw::hertz);
  EXPECT_EQ(amb::board::parse_board(with_law("rigid"), "test").plant.aux[0].contact_law, amb::model::AuxContactLaw::rigid);
  const auto b = amb::board::parse_board(with_law("linear"), "test");
  EXPECT_EQ(b.plant.aux[0].contact_law, amb::model::AuxContactLaw::linear);
  md::DropOptions o;
  EXPECT_EQ(amb::test::make_drop_model(b.plant, o)->contact_law(), amb::model::AuxContactLaw::linear);
  try {
    amb::board::parse_board(with_law("soft"), "test");
    FAIL() << "an unknown contact law was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("contact_law"), std::string::npos) << e.what();
  }
}

namespace {

// Figures of one board-law (Hertz) drop that a sub-step error would move: first impact time
// and its peak force, spin-down, time in contact and the whirl rate of the contact point.
struct DropFigures {
  double first_impact_s = -1.0, first_peak_n = 0.0, spin_end_hz = 0.0, contact_share = 0.0, whirl_rad_s = 0.0;
  double peak_n = 0.0;          ///< largest sample-mean normal force of the record, N
  double late_mean_n = 0.0;     ///< mean normal force over the record's second half, N
  double late_p99_n = 0.0;      ///< its 99th percentile, N
  std::vector<double> fn;       ///< sample-mean normal force at bearing 0, N
};

// rms difference of two force records over `n` samples from i0, relative to the reference's rms.
double relative_rms_difference(const std::vector<double>& ref, const std::vector<double>& f, size_t i0, size_t n) {
  double d2 = 0.0, r2 = 0.0;
  for (size_t i = i0; i < i0 + n && i < ref.size() && i < f.size(); ++i) {
    d2 += (f[i] - ref[i]) * (f[i] - ref[i]);
    r2 += ref[i] * ref[i];
  }
  return r2 > 0.0 ? std::sqrt(d2 / r2) : 0.0;
}

DropFigures board_law_drop(const amb::model::PlantParams& p, double contact_step_s, double quiet_share,
                           double duration_s) {
  md::DropOptions o = plant_like(p, md::ContactLawChoice::board);
  o.contact_step_s = contact_step_s;
  o.quiet_contact_share = quiet_share;
  auto m = amb::test::make_drop_model(p, o);
  const double dt = 1e-4;
  const Trace t = free_drop(*m, 45.0, duration_s, dt);
  DropFigures f;
  const int i0 = first_contact(t);
  if (i0 < 0) return f;
  f.first_impact_s = dt * (i0 + 1);
  for (int i = i0; i < i0 + 30 && static_cast<size_t>(i) < t.fn.size(); ++i) f.first_peak_n = std::max(f.first_peak_n, t.fn[static_cast<size_t>(i)]);
  f.spin_end_hz = t.spin_hz.back();
  f.contact_share = static_cast<double>(std::count_if(t.fn.begin(), t.fn.end(), [](double v) { return v > 0.0; })) /
                    static_cast<double>(t.fn.size());
  f.whirl_rad_s = whirl_rate(t, t.x.size() / 2, dt);
  f.peak_n = *std::max_element(t.fn.begin(), t.fn.end());
  f.fn = t.fn;
  std::vector<double> late(t.fn.begin() + static_cast<long>(t.fn.size() / 2), t.fn.end());
  for (double v : late) f.late_mean_n += v / static_cast<double>(late.size());
  std::sort(late.begin(), late.end());
  f.late_p99_n = late[static_cast<size_t>(0.99 * static_cast<double>(late.size() - 1))];
  return f;
}

}  // namespace

TEST(CompliantContact, ContactSubStepConverges) {
  // The board's Hertz law through the first impacts and into sustained contact, with the
  // default contact sub-step and quiet-contact rule against a quarter of the sub-step cut on
  // every step near a contact: a bouncing drop (friction 0.15) and a dry-friction backward
  // whirl (0.4, heavy rings, unbalance).
  auto bounce = amb::test::bath_board().plant;
  auto whirl = bounce;
  for (auto& a : whirl.aux) {
    a.friction_coefficient = 0.4;
    a.ring_inertia_kg_m2 = 2e-3;
  }
  for (auto& d : whirl.rotor.disks) d.unbalance_kg_m = 1e-4;
  const md::DropOptions def;
  const double h = def.contact_step_s;
  for (const auto* p : {&bounce, &whirl}) {
    const DropFigures ref = board_law_drop(*p, 0.25 * h, 0.0, 0.3), f = board_law_drop(*p, h, def.quiet_contact_share, 0.3);
    std::printf("contact step %.2f / %.2f us: first impact %.4f / %.4f s, peak %.1f / %.1f N, spin at 0.3 s %.3f / %.3f Hz, "
                "in contact %.3f / %.3f, whirl %.1f / %.1f rad/s\n", 0.25 * h * 1e6, h * 1e6, ref.first_impact_s,
                f.first_impact_s, ref.first_peak_n, f.first_peak_n, ref.spin_end_hz, f.spin_end_hz, ref.contact_share,
                f.contact_share, ref.whirl_rad_s, f.whirl_rad_s);
    const size_t i0 = static_cast<size_t>(std::lround(ref.first_impact_s / 1e-4));
    const double rms_20ms = relative_rms_difference(ref.fn, f.fn, i0, 200);
    std::printf("  peak of the record %.1f / %.1f N, normal force over 20 ms from the first impact: rms difference %.3f;"
                " second half: mean %.1f / %.1f N, 99th percentile %.1f / %.1f N\n",
                ref.peak_n, f.peak_n, rms_20ms, ref.late_mean_n, f.late_mean_n, ref.late_p99_n, f.late_p99_n);
    ASSERT_GT(ref.first_impact_s, 0.0);
    EXPECT_NEAR(f.first_impact_s, ref.first_impact_s, 1e-4);
    // The impact's peak is what the load map and the wear record take: within 2 % (a sub-step
    // twice the default: -0.8 % / -3.0 %, four times: -0.9 % / -7.4 % on these drops).
    EXPECT_NEAR(f.first_peak_n, ref.first_peak_n, 0.02 * ref.first_peak_n);
    EXPECT_NEAR(f.spin_end_hz, ref.spin_end_hz, 0.01 * 45.0);
    EXPECT_NEAR(f.contact_share, ref.contact_share, 0.01);
    EXPECT_NEAR(f.whirl_rad_s, ref.whirl_rad_s, 0.02 * std::max(std::abs(ref.whirl_rad_s), 2.0 * M_PI * 20.0));
    // The force history through the bounces (20 ms from the first impact): cutting every
    // step near a contact leaves 0.049 of the reference's rms, the quiet rule 0.062; a rule
    // three times as permissive (0.3) 0.17, never cutting a closed contact (1.0) 0.20.
    EXPECT_LT(rms_20ms, 0.08);
    // Sustained contact: the mean force within 2 %, its 99th percentile within 6 % (cutting
    // every step: -4.9 %), the record's single largest sample within 15 % (cutting every
    // step -5.5 %, the quiet rule -10.5 %, never cutting a closed contact -18.9 %; one
    // sample of a chaotic whirl).
    EXPECT_NEAR(f.late_mean_n, ref.late_mean_n, 0.02 * ref.late_mean_n);
    EXPECT_NEAR(f.late_p99_n, ref.late_p99_n, 0.06 * ref.late_p99_n);
    EXPECT_NEAR(f.peak_n, ref.peak_n, 0.15 * ref.peak_n);
  }
}
