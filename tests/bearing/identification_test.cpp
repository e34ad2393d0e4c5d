// Contact-stiffness scale identification (seed 003 section 4) on model-generated data.
#include <gtest/gtest.h>

#include <cmath>

#include "model/bearing/stiffness_identification.hpp"

namespace mb = amb::model::bearing;

namespace {
mb::Hertz4DofParams rig() {
  mb::Hertz4DofParams p;
  p.defect.location = mb::DefectLocation::outer_race;
  p.defect.width_m = 0.5e-3;
  p.defect.depth_m = 0.3e-3;
  p.defect.angle_rad = M_PI / 2;
  return p;
}
}  // namespace

TEST(StiffnessId, FastMethodRecoversKnownScaleWithNoise) {
  auto speed = [](double) { return 5000.0 / 60.0; };
  for (double eta_true : {1.3, 0.8}) {
    auto p = rig();
    p.stiffness_scale = eta_true;
    const auto measured = mb::simulate_housing_acceleration(p, speed, 20000.0, 0.5, 0.05, 11);
    mb::StiffnessIdOptions o;
    o.fs_hz = 20000.0;
    p.stiffness_scale = 1.0;  // the identification must not see the truth
    const auto s = mb::identify_stiffness_scale(p, speed, measured, o);
    EXPECT_TRUE(s.converged) << s.termination;
    EXPECT_NEAR(s.eta, eta_true, 0.02 * eta_true) << "evaluations " << s.evaluations;
    EXPECT_LE(s.evaluations, o.max_evaluations + 1);
  }
}

TEST(StiffnessId, AfsaReferenceRecoversKnownScale) {
  // Seed 003 AFSA settings, shorter record to keep the test quick.
  auto speed = [](double) { return 5000.0 / 60.0; };
  auto p = rig();
  p.stiffness_scale = 1.3;
  p.settle_s = 0.04;  // ~4 housing time constants; AFSA runs ~1000 simulations
  const auto measured = mb::simulate_housing_acceleration(p, speed, 20000.0, 0.1, 0.05, 5);
  mb::StiffnessIdOptions o;
  o.fs_hz = 20000.0;
  o.method = mb::EtaMethod::afsa;
  p.stiffness_scale = 1.0;
  const auto s = mb::identify_stiffness_scale(p, speed, measured, o);
  EXPECT_NEAR(s.eta, 1.3, 0.02 * 1.3) << s.termination;
  EXPECT_GT(s.evaluations, o.swarm_size);
}

TEST(StiffnessId, InvalidOptionsRefused) {
  mb::StiffnessIdOptions o;
  o.eta_min = 2.0;
  o.eta_max = 1.0;
  EXPECT_FALSE(o.valid());
  EXPECT_THROW(mb::identify_stiffness_scale(rig(), [](double) { return 50.0; }, std::vector<double>(1000, 0.0), o),
               std::invalid_argument);
}
