// The board's file codecs (AMBE events, AMBW wear records): encode and decode throughput of
// a main-job-sized event (25 000 samples of 84 bytes, with diagnosis and analysis sections)
// and of a wear record. The field lists are templates over ByteWriter/ByteReader
// (firmware/common/byte_codec.hpp); these figures say what that costs against the mirrored
// hand-written lists before it (docs/event-format.md).
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "firmware/events/event_codec.hpp"
#include "firmware/wear/wear_record.hpp"

namespace {

namespace fw = amb::fw;

fw::EventRecord bench_event(size_t samples) {
  fw::EventRecord r;
  r.meta.board_name = "bath-amb-rig";
  r.meta.rig_name = "bath";
  r.meta.rate_hz = 10000.0;
  r.meta.trigger_index = static_cast<uint32_t>(samples / 2);
  r.samples.resize(samples);
  for (size_t i = 0; i < samples; ++i) {
    fw::LoopSample& s = r.samples[i];
    s.seq = i;
    s.t_ns = static_cast<int64_t>(i) * 100000;
    for (size_t k = 0; k < 4; ++k) {
      s.displacement_m[k] = 1e-6f * static_cast<float>((i + k) % 97);
      s.coil_current_a[k] = 0.01f * static_cast<float>((i * 3 + k) % 89);
      s.current_demand_a[k] = 0.01f * static_cast<float>((i * 5 + k) % 83);
    }
    s.speed_hz = 45.0f;
    s.tach_hz = 44.9f;
    s.flags = static_cast<uint32_t>(i & 7u);
  }
  r.has_diagnosis = true;
  r.diagnosis.summary = "channel cut-off on all four channels";
  r.has_analysis = true;
  return r;
}

void BM_EventEncode(benchmark::State& state) {
  const fw::EventRecord r = bench_event(static_cast<size_t>(state.range(0)));
  size_t bytes = 0;
  for (auto _ : state) {
    const std::vector<uint8_t> b = fw::encode_event(r);
    bytes = b.size();
    benchmark::DoNotOptimize(b.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(bytes));
}
BENCHMARK(BM_EventEncode)->ArgName("samples")->Arg(25000)->Unit(benchmark::kMillisecond);

void BM_EventDecode(benchmark::State& state) {
  const std::vector<uint8_t> b = fw::encode_event(bench_event(static_cast<size_t>(state.range(0))));
  for (auto _ : state) {
    fw::EventRecord r;
    std::string err;
    if (!fw::decode_event(b, r, err)) state.SkipWithError(err.c_str());
    benchmark::DoNotOptimize(r.samples.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(b.size()));
}
BENCHMARK(BM_EventDecode)->ArgName("samples")->Arg(25000)->Unit(benchmark::kMillisecond);

void BM_WearRecordRoundTrip(benchmark::State& state) {
  fw::WearRecord w;
  w.board_name = "bath-amb-rig";
  w.life_model = "friction-energy budget (Archard) 20000 J";
  for (auto& b : w.bearing)
    for (size_t i = 0; i < b.event_load_n.size(); ++i) b.event_load_n[i] = static_cast<float>(i);
  for (auto _ : state) {
    const std::vector<uint8_t> b = fw::encode_wear_record(w);
    fw::WearRecord back;
    std::string err;
    if (!fw::decode_wear_record(b, back, err)) state.SkipWithError(err.c_str());
    benchmark::DoNotOptimize(back.bearing.data());
  }
}
BENCHMARK(BM_WearRecordRoundTrip)->Unit(benchmark::kMicrosecond);

}  // namespace
