// Writes the seed corpora of the fuzz targets from the project's own encoders, so the seeds
// stay valid when a format version changes: `fuzz_make_seeds DIR` fills DIR/<target>/.
// (Board-file seeds are the boards/ folder itself; scripts/fuzz.sh passes it.)
#include <matio.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "firmware/events/event_codec.hpp"
#include "firmware/events/sweep_event.hpp"
#include "firmware/fieldbus/protocol.hpp"
#include "firmware/persistence/generation_store.hpp"
#include "firmware/supervisory/register_addresses.hpp"
#include "firmware/wear/wear_record.hpp"

namespace fs = std::filesystem;

namespace {

void write(const fs::path& dir, const std::string& name, const std::vector<uint8_t>& bytes) {
  fs::create_directories(dir);
  std::ofstream f(dir / name, std::ios::binary);
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

std::vector<uint8_t> text(const std::string& s) { return {s.begin(), s.end()}; }

void append_frame(std::vector<uint8_t>& out, const amb::hal::CanFrame& f) {
  out.push_back(static_cast<uint8_t>((f.extended ? 1 : 0) | (f.fd ? 2 : 0) | (f.error ? 4 : 0)));
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(f.id >> (8 * i)));
  out.push_back(f.len);
  out.insert(out.end(), f.data.begin(), f.data.begin() + f.len);
}

void append_request(std::vector<uint8_t>& out, bool write, uint16_t address, const std::vector<uint16_t>& values,
                    uint8_t count) {
  out.push_back(write ? 1 : 0);
  out.push_back(static_cast<uint8_t>(address >> 8));
  out.push_back(static_cast<uint8_t>(address & 0xFF));
  if (!write) {
    out.push_back(static_cast<uint8_t>(count - 1));
    return;
  }
  out.push_back(static_cast<uint8_t>(values.size() - 1));
  for (uint16_t v : values) {
    out.push_back(static_cast<uint8_t>(v >> 8));
    out.push_back(static_cast<uint8_t>(v & 0xFF));
  }
}

void write_mat(const fs::path& file) {
  mat_t* m = Mat_CreateVer(file.c_str(), nullptr, MAT_FT_MAT5);
  if (!m) return;
  double x[16];
  for (int i = 0; i < 16; ++i) x[i] = 0.01 * i;
  size_t dims[2] = {16, 1};
  if (matvar_t* v = Mat_VarCreate("DE_time", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, x, 0)) {
    Mat_VarWrite(m, v, MAT_COMPRESSION_NONE);
    Mat_VarFree(v);
  }
  double rpm = 1797.0;
  size_t one[2] = {1, 1};
  if (matvar_t* v = Mat_VarCreate("RPM", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &rpm, 0)) {
    Mat_VarWrite(m, v, MAT_COMPRESSION_ZLIB);
    Mat_VarFree(v);
  }
  Mat_Close(m);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_make_seeds DIR\n");
    return 1;
  }
  const fs::path root = argv[1];
  const auto board = amb::board::load_board("bath-amb-rig");

  // AMBE: a short event with the board's metadata.
  amb::fw::EventRecord ev;
  ev.meta.board_name = board.name;
  ev.meta.rig_name = board.name;
  ev.meta.firmware_version = amb::fw::k_firmware_version;
  ev.meta.board_source = "embedded:bath-amb-rig";
  ev.meta.rate_hz = board.rate_hz;
  ev.samples.resize(8);
  for (size_t i = 0; i < ev.samples.size(); ++i) ev.samples[i].seq = i;
  ev.meta.trigger_index = 4;
  write(root / "fuzz_event_ambe", "short_v_current", amb::fw::encode_event(ev));
  write(root / "fuzz_event_ambe", "short_v1", amb::fw::encode_event_v1(ev));
  {
    // A sweep event (AMBE v4, record kind sweep): two lines, one axis of one 8-sample period.
    amb::fw::SweepEvent sw;
    sw.meta = ev.meta;
    sw.samples_per_period = 8;
    sw.settle_periods = 1;
    sw.recorded_periods = 1;
    sw.amplitude_a = 0.25;
    sw.bins = {1, 3};
    amb::fw::SweepAxisData a;
    a.axis = 2;
    for (int k = 0; k < 8; ++k) {
      a.excitation_a.push_back(0.1f * static_cast<float>(k));
      a.controller_output_a.push_back(0.2f);
      a.summing_point_a.push_back(0.2f + 0.1f * static_cast<float>(k));
      a.sensor_m.push_back(1e-6f);
    }
    sw.axes.push_back(a);
    write(root / "fuzz_event_ambe", "short_sweep_v4", amb::fw::encode_sweep_event(sw));
  }

  // AMBW: an empty and a filled record.
  amb::fw::WearRecord w;
  w.board_name = board.name;
  w.life_model = "friction-energy";
  write(root / "fuzz_wear_ambw", "empty", amb::fw::encode_wear_record(w));
  w.sequence = 7;
  w.event_count = 3;
  w.bearing[0].event_load_n[10] = 120.0f;
  w.bearing[1].life_used_fraction = 0.01f;
  const auto wear_bytes = amb::fw::encode_wear_record(w);
  write(root / "fuzz_wear_ambw", "filled", wear_bytes);

  // Generation store: first byte places the cut between slot A and slot B.
  {
    auto a = amb::fw::GenerationStore::encode(3, wear_bytes);
    auto b = amb::fw::GenerationStore::encode(2, wear_bytes);
    std::vector<uint8_t> in{static_cast<uint8_t>(255 * (a.size() + 1) / (a.size() + b.size() + 1))};
    in.insert(in.end(), a.begin(), a.end());
    in.insert(in.end(), b.begin(), b.end());
    write(root / "fuzz_generation_store", "two_generations", in);
  }

  // CAN: one of every frame kind of the protocol.
  {
    namespace fb = amb::fieldbus;
    std::vector<uint8_t> in;
    append_frame(in, fb::encode_position(2, {1e-5, -2e-5, 3e-6, 0.0}, 0));
    append_frame(in, fb::encode_current(3, {0.5, -0.2, 1.0, 0.0}, 0));
    append_frame(in, fb::encode_demand(3, {0.1, 0.2, 0.3, 0.4}));
    append_frame(in, fb::encode_drive(3, 1, true, 45.0));
    append_frame(in, fb::encode_sample_fd(2, 2, {1e-5, 0.0, 0.0, 0.0}, {0.1, 0.0, 0.0, 0.0}, 45.0, 0));
    append_frame(in, fb::encode_heartbeat(2, 5, 0));
    write(root / "fuzz_can_frame", "every_kind", in);
  }

  // Modbus: read the identity block, the status block, post a command, browse the events.
  {
    namespace regs = amb::fw::regs;
    std::vector<uint8_t> in;
    append_request(in, false, regs::identity, {}, regs::identity_end - regs::identity);
    append_request(in, false, regs::state, {}, regs::state_end - regs::state);
    append_request(in, true, regs::command, {1}, 0);
    append_request(in, false, regs::speed_estimate_mhz, {}, 16);
    append_request(in, true, regs::event_browse_index, {0}, 0);
    append_request(in, false, regs::event_count, {}, 24);
    append_request(in, true, regs::dl_select, {0, 0, 0, 0, 0}, 0);
    append_request(in, false, regs::dl_valid_bytes, {}, 100);
    append_request(in, true, regs::wb_control, {1, 0, 200, 0x1234, 0x5678}, 0);
    append_request(in, true, regs::wb_control, {3}, 0);
    write(root / "fuzz_modbus_registers", "session", in);
  }

  // Measured event: sidecar, NUL, CSV.
  {
    const std::string json =
        R"({"format":"amb-measured-event/1","rig":"bath-amb-rig","sample_rate_hz":10000.0,"trigger_index":2,)"
        R"("speed_rpm":2700.0,"channels":[{"column":"t_s","quantity":"time","unit":"s"},)"
        R"({"column":"xa1","quantity":"displacement","unit":"um","axial_m":0.135,"angle_deg":45.0},)"
        R"({"column":"xa2","quantity":"displacement","unit":"m","axial_m":0.135,"angle_deg":-45.0},)"
        R"({"column":"xb1","quantity":"displacement","unit":"m","axial_m":0.465,"angle_deg":45.0},)"
        R"({"column":"xb2","quantity":"displacement","unit":"m","axial_m":0.465,"angle_deg":-45.0},)"
        R"({"column":"ia1","quantity":"current","unit":"A","axial_m":0.115,"angle_deg":45.0},)"
        R"({"column":"n","quantity":"speed","unit":"rpm"}],"declared_faults":["amb_cutoff_all"],"notes":"seed"})";
    const std::string csv =
        "t_s,xa1,xa2,xb1,xb2,ia1,n\n"
        "0,1.5,2e-6,-1e-6,0,0.1,2700\n"
        "0.0001,1.4,2.1e-6,-1e-6,1e-7,0.1,2700\n"
        "0.0002,1.2,2.2e-6,-0.9e-6,2e-7,0.0,2699.5\n"
        "0.0003,0.9,2.4e-6,-0.5e-6,3e-7,0.0,2699\n";
    auto in = text(json);
    in.push_back(0);
    const auto c = text(csv);
    in.insert(in.end(), c.begin(), c.end());
    write(root / "fuzz_measured_event", "bath_small", in);
  }

  // MATLAB v5: a vector and a compressed scalar.
  fs::create_directories(root / "fuzz_mat_file");
  write_mat(root / "fuzz_mat_file" / "small.mat");
  return 0;
}
