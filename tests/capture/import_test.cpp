// Host side: board event files and the measured-event exchange format through the common
// loader: SI conversion, channel matching to the rig, export/import round trip, and refusal
// of malformed files with a message naming the file and the row or field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "firmware/board/board.hpp"
#include "firmware/events/event_codec.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/events/measured_event.hpp"
#include "tests/capture/synthetic_samples.hpp"

namespace {
namespace fs = std::filesystem;
using namespace amb;

class Import : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("amb_import_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::string& text) const { std::ofstream(path(name)) << text; }

  /// `tach`: the samples carry a tachometer channel (the rotor slowing from 45 Hz) while the
  /// board's own estimate (the tracker's) is lost (NaN) after the trigger.
  std::string board_event_file(bool corrupt = false, bool tach = false, bool v2 = false) const {
    const auto board = board::load_board("bath-amb-rig");
    fw::FrozenEvent e;
    e.samples.resize(400);
    for (size_t i = 0; i < 400; ++i) {
      e.samples[i] = test::synthetic_sample(5000 + i);
      if (tach) {
        e.samples[i].tach_hz = 45.0f - (i > 150 ? 0.02f * static_cast<float>(i - 150) : 0.0f);
        if (i > 150) {
          e.samples[i].speed_hz = std::numeric_limits<float>::quiet_NaN();
          e.samples[i].speed_quality = fw::pack_speed_quality(0.0, true);
        }
      }
    }
    e.header.sample_count = 400;
    e.header.trigger_index = 150;
    e.header.cause = fw::TriggerCause::channel_cutoff;
    e.header.speed_at_trigger_hz = 45.0f;
    fw::EventRecord r = fw::make_event_record(e, board, 3);
    r.has_diagnosis = true;
    r.diagnosis.type = fw::diag::FaultType::channel_cutoff;
    r.diagnosis.cutoff_channels = 0x2;
    r.diagnosis.current_factor = {1, 0, 1, 1};
    r.diagnosis.confidence = 0.9;
    r.diagnosis.summary = "cut-off";
    auto bytes = v2 ? fw::encode_event_v2(r) : fw::encode_event(r);
    if (corrupt) bytes[1000] ^= 1;
    const std::string p = path(corrupt ? "bad.ambe" : (tach ? (v2 ? "tach_v2.ambe" : "tach.ambe") : "event_00000003.ambe"));
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<long>(bytes.size()));
    return p;
  }

  /// A small valid measured event in mixed units; `edit` may change the sidecar/CSV text.
  std::string measured(const std::string& sidecar_extra = "", const std::string& csv = "") const {
    // Positions from the rig's board: A1 sensor, A2 sensor 1 mm off (within the tolerance) and
    // pointing the other way, AMB A actuator axis 2, an accelerometer on nothing of the rig.
    const auto b = board::load_board("bath-amb-rig");
    auto num = [](double v) { char t[32]; std::snprintf(t, sizeof t, "%.4f", v); return std::string(t); };
    std::string text = R"({
  "format": "amb-measured-event/1",
  "rig": "bath-amb-rig",
  "sample_rate_hz": 1000.0,
  "trigger_index": 2,
  "speed_rpm": 2700.0,
  "channels": [
    {"column": "t",   "quantity": "time",         "unit": "s"},
    {"column": "ax1", "quantity": "displacement", "unit": "mm", "axial_m": 0.100, "angle_deg": 45.0},
    {"column": "ay1", "quantity": "displacement", "unit": "um", "axial_m": 0.101, "angle_deg": 135.0},
    {"column": "ic1", "quantity": "current",      "unit": "A",  "axial_m": 0.150, "angle_deg": -45.0},
    {"column": "acc", "quantity": "acceleration", "unit": "g",  "axial_m": 0.300, "angle_deg": 0.0},
    {"column": "n",   "quantity": "speed",        "unit": "rpm"}
  ],
  "declared_faults": ["amb_cutoff_all"],
  "notes": "lab rig, run 7")" + sidecar_extra + "\n}\n";
    auto put = [&](const std::string& from, const std::string& to) { text.replace(text.find(from), from.size(), to); };
    put("\"axial_m\": 0.100", "\"axial_m\": " + num(b.plant.sensor[0].axial_m));
    put("\"axial_m\": 0.101", "\"axial_m\": " + num(b.plant.sensor[1].axial_m + 0.001));
    put("\"axial_m\": 0.150", "\"axial_m\": " + num(b.plant.amb[0].axial_m));
    write("m.json", text);
    write("m.csv", csv.empty() ? "t,ax1,ay1,ic1,acc,n,ignored\n"
                                 "0.000,0.010,-5,0.5,1.0,2700,x\n"
                                 "0.001,0.020,-6,0.6,0.5,2700,y\n"
                                 "0.002,0.030,-7,0.7,0.0,2640,z\n"
                                 "0.003,0.040,-8,0.8,-0.5,2580,w\n"
                               : csv);
    return path("m.json");
  }

  fs::path dir_;
};

std::string refusal(const std::string& file) {
  try {
    host::load_event(file);
  } catch (const host::EventLoadError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST_F(Import, BoardEventFileLoadsWithSiChannelsAndPhaseB) {
  const host::LoadedEvent e = host::load_event(board_event_file());
  EXPECT_EQ(e.format, "AMBE/3");  // written by the current firmware (v3: tachometer channel)
  EXPECT_EQ(e.speed_channel, "board speed estimate");  // no tachometer on these samples
  EXPECT_TRUE(e.speed_estimate_hz.empty());
  EXPECT_EQ(e.rig, "bath-amb-rig");
  EXPECT_EQ(e.sample_rate_hz, 10000.0);
  EXPECT_EQ(e.samples(), 400u);
  EXPECT_EQ(e.trigger_index, 150u);
  EXPECT_EQ(e.trigger_cause, "channel_cutoff");
  ASSERT_EQ(e.displacement.size(), 4u);
  ASSERT_EQ(e.current.size(), 4u);
  const auto b = board::load_board("bath-amb-rig");
  EXPECT_DOUBLE_EQ(e.displacement[2].axial_m, b.plant.sensor[2].axial_m);
  EXPECT_DOUBLE_EQ(e.displacement[1].angle_deg, b.plant.sensor[1].angle_deg);
  EXPECT_DOUBLE_EQ(e.current[3].axial_m, b.plant.amb[1].axial_m);
  EXPECT_EQ(e.displacement[0].values[7], static_cast<double>(test::synthetic_sample(5007).displacement_m[0]));
  EXPECT_NEAR(e.t_s[10], 1e-3, 1e-12);
  ASSERT_TRUE(e.phase_b.has_value());
  EXPECT_EQ(e.phase_b->type, fw::diag::FaultType::channel_cutoff);
  ASSERT_TRUE(e.speed_at_trigger_hz.has_value());
  EXPECT_DOUBLE_EQ(*e.speed_at_trigger_hz, 45.0);
}

// A rig with a tachometer, a board whose speed source is the tracker (lost once the rotor
// drops): the event's speed channel is the tachometer's (the spin-down during the drop), the
// board's estimate rides along; the export declares the tachometer as the speed channel.
TEST_F(Import, BoardEventWithTachometerGivesTheMeasuredSpeedChannel) {
  const host::LoadedEvent e = host::load_event(board_event_file(false, true));
  EXPECT_EQ(e.speed_channel, "tachometer");
  ASSERT_EQ(e.speed_hz.size(), 400u);
  EXPECT_EQ(e.speed_hz[100], 45.0);
  EXPECT_EQ(static_cast<float>(e.speed_hz[350]), 45.0f - 0.02f * 200.0f);
  ASSERT_EQ(e.speed_estimate_hz.size(), 400u);
  EXPECT_TRUE(std::isnan(e.speed_estimate_hz[350]));
  EXPECT_NE(e.notes.find("speed channel: tachometer"), std::string::npos) << e.notes;
  host::export_measured_event(e, path("tach_export"));
  const host::LoadedEvent b = host::load_event(path("tach_export.json"));
  ASSERT_EQ(b.speed_hz.size(), 400u);  // a declared speed channel (finite throughout)
  EXPECT_EQ(static_cast<float>(b.speed_hz[350]), static_cast<float>(e.speed_hz[350]));
  // The same samples in an AMBE v2 file (no tachometer channel): the board's estimate, NaN
  // after the trigger, which the export keeps as an undeclared column.
  const host::LoadedEvent old = host::load_event(board_event_file(false, true, true));
  EXPECT_EQ(old.format, "AMBE/2");
  EXPECT_EQ(old.speed_channel, "board speed estimate");
  EXPECT_TRUE(std::isnan(old.speed_hz[350]));
  host::export_measured_event(old, path("v2_export"));
  EXPECT_TRUE(host::load_event(path("v2_export.json")).speed_hz.empty());
}

TEST_F(Import, CorruptedBoardEventIsRefusedNamingTheFile) {
  const std::string p = board_event_file(true);
  const std::string msg = refusal(p);
  EXPECT_NE(msg.find(p), std::string::npos) << msg;
  EXPECT_NE(msg.find("bad checksum"), std::string::npos) << msg;
}

TEST_F(Import, ExportThenImportRoundTrips) {
  const host::LoadedEvent a = host::load_event(board_event_file());
  host::export_measured_event(a, path("exported"));
  const host::LoadedEvent b = host::load_event(path("exported.json"));
  EXPECT_EQ(b.format, "amb-measured-event/1");
  EXPECT_EQ(b.board, "bath-amb-rig");
  EXPECT_EQ(b.samples(), a.samples());
  EXPECT_EQ(b.trigger_index, a.trigger_index);
  EXPECT_TRUE(b.warnings.empty()) << b.warnings.front();
  ASSERT_EQ(b.displacement.size(), 4u);
  ASSERT_EQ(b.current.size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(b.displacement[k].rig_index, static_cast<int>(k));
    EXPECT_EQ(b.current[k].rig_index, static_cast<int>(k));
    for (size_t i = 0; i < a.samples(); ++i) {
      // The board records float32; %.9g in the CSV round-trips every float exactly.
      ASSERT_EQ(static_cast<float>(b.displacement[k].values[i]), static_cast<float>(a.displacement[k].values[i]));
      ASSERT_EQ(static_cast<float>(b.current[k].values[i]), static_cast<float>(a.current[k].values[i]));
    }
  }
  ASSERT_EQ(b.speed_hz.size(), a.samples());
  EXPECT_EQ(static_cast<float>(b.speed_hz[5]), static_cast<float>(a.speed_hz[5]));
  EXPECT_NE(b.notes.find("Phase B: channel_cutoff"), std::string::npos) << b.notes;
}

TEST_F(Import, MeasuredEventIsConvertedToSiAndMatchedToTheRig) {
  const host::LoadedEvent e = host::load_event(measured());
  EXPECT_EQ(e.samples(), 4u);
  EXPECT_EQ(e.trigger_index, 2u);
  EXPECT_EQ(e.board, "bath-amb-rig");
  ASSERT_EQ(e.displacement.size(), 2u);
  EXPECT_DOUBLE_EQ(e.displacement[0].values[1], 20e-6);           // mm -> m
  EXPECT_EQ(e.displacement[0].rig_index, 0);                       // sensor A1 (0.10 m, 45 deg)
  EXPECT_EQ(e.displacement[1].rig_index, 1);                       // A2 at -45 deg, measured at 135 deg: inverted
  EXPECT_TRUE(e.displacement[1].inverted);
  EXPECT_DOUBLE_EQ(e.displacement[1].values[0], 5e-6);             // um -> m, sign to the rig's direction
  EXPECT_EQ(e.current[0].rig_index, 1);                            // AMB A actuator axis 2 (-45 deg)
  ASSERT_EQ(e.other.size(), 1u);
  EXPECT_DOUBLE_EQ(e.other[0].values[0], 9.80665);                 // g -> m/s^2
  EXPECT_EQ(e.other[0].rig_index, -1);
  ASSERT_EQ(e.warnings.size(), 1u);                                // the accelerometer is reported unmatched
  EXPECT_NE(e.warnings[0].find("'acc'"), std::string::npos);
  EXPECT_DOUBLE_EQ(e.speed_hz[2], 44.0);                           // rpm -> Hz
  EXPECT_DOUBLE_EQ(*e.speed_at_trigger_hz, 45.0);                  // from speed_rpm
  EXPECT_EQ(e.declared_faults, std::vector<std::string>{"amb_cutoff_all"});
  EXPECT_EQ(e.notes, "lab rig, run 7");
}

TEST_F(Import, MalformedSidecarsAreRefusedNamingTheField) {
  struct Case {
    std::string extra, expect;
  };
  const std::vector<Case> cases = {
      {",\n  \"format2\": 1", "unknown field 'format2'"},
      {",\n  \"speed_rpm\": -5", "field 'speed_rpm'"},
  };
  for (const auto& c : cases) {
    const std::string msg = refusal(measured(c.extra));
    EXPECT_NE(msg.find(c.expect), std::string::npos) << msg;
    EXPECT_NE(msg.find("m.json"), std::string::npos) << msg;
  }
  auto edit = [&](const std::string& from, const std::string& to) {
    measured();
    std::ifstream in(path("m.json"));
    std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    s.replace(at, from.size(), to);
    write("m.json", s);
    return refusal(path("m.json"));
  };
  EXPECT_NE(edit("amb-measured-event/1", "amb-measured-event/2").find("field 'format'"), std::string::npos);
  EXPECT_NE(edit("\"sample_rate_hz\": 1000.0,", "").find("'sample_rate_hz' is missing"), std::string::npos);
  EXPECT_NE(edit("\"sample_rate_hz\": 1000.0", "\"sample_rate_hz\": 0").find("'sample_rate_hz' must be > 0"), std::string::npos);
  EXPECT_NE(edit("\"unit\": \"mm\"", "\"unit\": \"inch\"").find("channels[1].unit': 'inch' is not a unit of displacement"),
            std::string::npos);
  EXPECT_NE(edit("\"unit\": \"A\"", "\"unit\": \"mA\"").find("channels[3].unit"), std::string::npos);
  EXPECT_NE(edit("\"quantity\": \"acceleration\"", "\"quantity\": \"force\"").find("channels[4].quantity"), std::string::npos);
  EXPECT_NE(edit("\"unit\": \"mm\", \"axial_m\"", "\"unit\": \"mm\", \"axial\"").find("channels[1].axial' is unknown"),
            std::string::npos);
  EXPECT_NE(edit("\"rig\": \"bath-amb-rig\"", "\"rig\": \"no-such-rig\"").find("field 'rig'"), std::string::npos);
  EXPECT_NE(edit("\"trigger_index\": 2", "\"trigger_index\": 9").find("'trigger_index': 9 is beyond the 4 data rows"),
            std::string::npos);
  EXPECT_NE(edit("\"trigger_index\": 2", "\"trigger_index\": 1.5").find("'trigger_index' must be an integer"),
            std::string::npos);
  EXPECT_NE(edit("\"column\": \"ay1\"", "\"column\": \"ax1\"").find("'ax1' is named twice"), std::string::npos);
  write("m.json", "{ not json");
  EXPECT_NE(refusal(path("m.json")).find("not valid JSON"), std::string::npos);
}

TEST_F(Import, MalformedCsvIsRefusedNamingTheRow) {
  const std::string header = "t,ax1,ay1,ic1,acc,n\n";
  auto csv_refusal = [&](const std::string& body) { return refusal(measured("", header + body)); };
  std::string msg = csv_refusal("0,1,1,1,1,1\n0.001,1,abc,1,1,1\n0.002,1,1,1,1,1\n");
  EXPECT_NE(msg.find("m.csv: line 3, column 'ay1': 'abc' is not a finite number"), std::string::npos) << msg;
  msg = csv_refusal("0,1,1,1,1,1\n0.001,1,1,1,1\n0.002,1,1,1,1,1\n");
  EXPECT_NE(msg.find("line 3: 5 fields, the header has 6"), std::string::npos) << msg;
  msg = csv_refusal("0,1,1,1,1,1\n0.001,1,1,1,1,1\n0.0025,1,1,1,1,1\n");
  EXPECT_NE(msg.find("line 4, column 't': time step"), std::string::npos) << msg;
  msg = csv_refusal("0,1,1,1,1,1\n0.001,1,1,1,1,nan\n0.002,1,1,1,1,1\n");
  EXPECT_NE(msg.find("line 3, column 'n'"), std::string::npos) << msg;
  msg = refusal(measured("", "t,ax1,ic1,acc,n\n0,1,1,1,1\n0.001,1,1,1,1\n0.002,1,1,1,1\n"));
  EXPECT_NE(msg.find("m.csv: line 1: column 'ay1' named in the sidecar is not in the header"), std::string::npos) << msg;
  fs::remove(path("m.csv"));
  write("m.json", "{}");
  measured();
  fs::remove(path("m.csv"));
  msg = refusal(path("m.json"));
  EXPECT_NE(msg.find("m.csv: cannot open"), std::string::npos) << msg;
}

TEST_F(Import, UnknownFileIsRefused) {
  write("junk.bin", "hello");
  EXPECT_NE(refusal(path("junk.bin")).find("neither a board event file"), std::string::npos);
  EXPECT_NE(refusal(path("missing.ambe")).find("no such file"), std::string::npos);
}

}  // namespace
