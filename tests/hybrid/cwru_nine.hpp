#pragma once
// The nine CWRU fault records of issue 34 (inner race, outer race, ball; 7 mil, drive end,
// 12 kHz) at 1797 rpm / 0 hp, 1750 rpm / 2 hp and 1730 rpm / 3 hp, loaded.
#include <string>
#include <vector>

#include "host-tools/core/hybrid/hybrid_model.hpp"
#include "tests/support/test_paths.hpp"

namespace amb::test::hybrid {

inline std::vector<amb::host::hybrid::Record> cwru_nine_records() {
  namespace hy = amb::host::hybrid;
  std::vector<hy::Record> v;
  const struct {
    const char* tag;
    double rpm, load;
  } pts[] = {{"1797", 1797, 0}, {"1750", 1750, 2}, {"1730", 1730, 3}};
  const struct {
    const char* file;
    hy::BearingState state;
  } states[] = {{"_IR_7_DE12", hy::BearingState::inner_race},
                {"_ORat6_7_DE12", hy::BearingState::outer_race},
                {"_B_7_DE12", hy::BearingState::ball}};
  for (const auto& p : pts)
    for (const auto& s : states) {
      hy::Record r;
      r.path = std::string(amb::test::shared_dir()) + "/data/measured/cwru/" + p.tag + s.file + ".mat";
      r.state = s.state;
      r.op = {p.rpm, p.load};
      hy::load_record(r);
      v.push_back(std::move(r));
    }
  return v;
}

/// The five models of score_table(), in its order.
inline const char* const k_models[] = {"physics", "data_only", "nearest_transport", "interpolated_transport", "hybrid"};

}  // namespace amb::test::hybrid
