// The wear record's file and the one drop -> wear record path (host-tools/core/wear):
// written whole, read back equal, bad files named; account_drop is event_load +
// update_wear_record.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "firmware/wear/wear_record.hpp"
#include "host-tools/core/wear/load_map.hpp"
#include "host-tools/core/wear/wear_record_file.hpp"
#include "host-tools/core/wear/wear_update.hpp"

namespace hw = amb::host::wear;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("amb_wear_file_test_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::string error_of(const std::string& path, const std::string& board = {}) {
  try {
    hw::read_wear_record_file(path, board);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

/// Two contact steps at the bottom of bearing 0 (the drop model's step record).
std::vector<amb::model::drop::StepContact> steps() {
  std::vector<amb::model::drop::StepContact> s(2);
  for (size_t i = 0; i < s.size(); ++i) {
    s[i].t_s = 1e-4 * static_cast<double>(i + 1);
    s[i].h_s = 1e-4;
    s[i].active[0] = true;
    s[i].angle_deg[0] = 180.0 + static_cast<double>(i);
    s[i].normal_n[0] = 1000.0;
    s[i].friction_n[0] = 150.0;
    s[i].slip_m_s[0] = 2.0;
    s[i].friction_power_w[0] = 300.0;
  }
  return s;
}

}  // namespace

TEST(WearRecordFile, WrittenWholeAndReadBackEqual) {
  const fs::path d = temp_dir();
  amb::fw::WearRecord r;
  r.board_name = "bath-amb-rig";
  r.sequence = 3;
  r.bearing[1].cumulative_load_n[200] = 42.5f;
  const std::string p = (d / "w.ambw").string();
  hw::write_wear_record_file(p, r);
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  const amb::fw::WearRecord back = hw::read_wear_record_file(p, "bath-amb-rig");
  EXPECT_EQ(amb::fw::encode_wear_record(back), amb::fw::encode_wear_record(r));
  EXPECT_NE(error_of(p, "other-board").find("is the wear record of board 'bath-amb-rig', not of 'other-board'"), std::string::npos);
  EXPECT_NE(error_of((d / "missing.ambw").string()).find("cannot open wear record"), std::string::npos);
  std::ofstream((d / "short.ambw").string(), std::ios::binary) << "AMBW";
  EXPECT_NE(error_of((d / "short.ambw").string()).find("is not a usable wear record (AMBW v1)"), std::string::npos);
  {
    std::ofstream big((d / "big.ambw").string(), std::ios::binary);
    big << std::string(5 * amb::fw::wear_record_size(), 'A');
  }
  EXPECT_NE(error_of((d / "big.ambw").string()).find("larger than"), std::string::npos);
  EXPECT_NE(hw::wear_record_path_problem((d / "no-such-folder" / "w.ambw").string()).find("does not exist"), std::string::npos);
  EXPECT_EQ(hw::wear_record_path_problem(p), "");
  EXPECT_THROW(hw::write_wear_record_file((d / "no-such-folder" / "w.ambw").string(), r), std::runtime_error);
  fs::remove_all(d);
}

TEST(WearRecordFile, AccountDropIsEventLoadThenUpdate) {
  amb::fw::WearRecord prev;
  prev.board_name = "bath-amb-rig";
  std::array<amb::model::drop::RubbingDurations, 2> rub{};
  rub[0].forward_s = 0.125;
  const auto a = hw::account_drop(prev, steps(), rub, 0.15, "bath-amb-rig", 1234, hw::WearOptions{});
  hw::WearEvent ev;
  ev.load = hw::event_load(steps());
  ev.rubbing = rub;
  ev.friction_coefficient = 0.15;
  const auto direct = hw::update_wear_record(prev, ev, "bath-amb-rig", 1234, hw::WearOptions{});
  EXPECT_EQ(amb::fw::encode_wear_record(a.record), amb::fw::encode_wear_record(direct));
  EXPECT_GT(a.record.bearing[0].event_load_n[180], 0.0f);
  EXPECT_EQ(a.record.bearing[0].forward_rub_s, 0.125f);
  EXPECT_EQ(a.event.load[0].peak_force_n, ev.load[0].peak_force_n);
  EXPECT_THROW(hw::account_drop(prev, steps(), rub, 0.15, "other-board", 1, hw::WearOptions{}), std::invalid_argument);
}
