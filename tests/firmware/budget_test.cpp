// The board budget (firmware/budget): every table entry against what the code really
// allocates or writes, measured independently (operator new's byte count, the encoder's output
// length, the SPSC ring's own size), the storage budget's arithmetic, the CPU-share window,
// and the register block that serves them.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "firmware/analysis/analysis_task.hpp"
#include "firmware/board/board.hpp"
#include "firmware/budget/board_budget.hpp"
#include "firmware/budget/runtime_budget.hpp"
#include "firmware/capture/floating_capture.hpp"
#include "firmware/events/event_codec.hpp"
#include "firmware/events/event_record.hpp"
#include "firmware/supervisory/register_map.hpp"
#include "tests/firmware/alloc_counter.hpp"

using namespace amb;

namespace {
const fw::BufferBudget& entry(const std::vector<fw::BufferBudget>& t, const std::string& name) {
  for (const fw::BufferBudget& e : t)
    if (e.name == name) return e;
  ADD_FAILURE() << "no entry " << name;
  static fw::BufferBudget none;
  return none;
}
}  // namespace

TEST(BoardBudget, CaptureEntriesAreWhatTheCaptureAllocates) {
  for (const char* name : {"bath-amb-rig", "arm-virt-hil"}) {
    const board::BoardConfig b = board::load_board(name);
    const auto table = fw::buffer_budget(b);
    fw::FloatingCapture c;
    const long long before = test::bytes_requested();
    fw::configure_capture(c, b);
    const long long allocated = test::bytes_requested() - before;
    // Besides the ring and the sample buffers: the vector of event headers and the two index rings.
    const long long bookkeeping = static_cast<long long>(b.capture.event_buffers * sizeof(fw::FrozenEvent) +
                                                         2 * sizeof(fw::SpscRing<uint32_t, fw::FloatingCapture::k_max_buffers>));
    EXPECT_EQ(allocated - bookkeeping,
              static_cast<long long>(entry(table, "capture ring").bytes + entry(table, "frozen-event buffers").bytes))
        << name;
    EXPECT_EQ(entry(table, "capture ring").bytes, c.ring_samples() * sizeof(fw::LoopSample)) << name;
  }
}

TEST(BoardBudget, TrackerEntriesAreWhatTheAnalysisTaskHolds) {
  const board::BoardConfig b = board::load_board("bath-amb-rig");
  const auto table = fw::buffer_budget(b);
  // The hand-off ring lives inside the task object: its share of sizeof(AnalysisTask).
  EXPECT_GE(sizeof(fw::AnalysisTask), entry(table, "tracker hand-off ring").bytes);
  EXPECT_LT(sizeof(fw::AnalysisTask), entry(table, "tracker hand-off ring").bytes + 64 * 1024);
  auto task = std::make_unique<fw::AnalysisTask>();
  const long long before = test::bytes_requested();
  ASSERT_EQ(task->configure(b, nullptr), "");
  const long long allocated = test::bytes_requested() - before;
  // operator new sees the vectors; FFTW's own buffers (fftw_malloc: nfft doubles in, nfft/2+1
  // complex out) are not counted by it but are in the table.
  const size_t n = b.tracker.options.stft.nfft;
  const long long fftw = static_cast<long long>(8 * n + 16 * (n / 2 + 1));
  const long long table_bytes = static_cast<long long>(entry(table, "tracker STFT and ridge search").bytes);
  std::printf("[ NOTE ] tracker: table %lld B, operator new %lld B + FFTW buffers %lld B\n", table_bytes, allocated, fftw);
  EXPECT_GE(allocated + fftw, table_bytes);             // the table misses nothing the tracker keeps ...
  EXPECT_LE(allocated + fftw, table_bytes + 64 * 1024); // ... beyond configure-time temporaries
  // Without the analysis thread these buffers do not exist.
  fw::BudgetOptions off;
  off.analysis_thread = false;
  const auto t_off = fw::buffer_budget(b, off);
  EXPECT_EQ(entry(t_off, "tracker hand-off ring").bytes, 0u);
  EXPECT_EQ(entry(t_off, "tracker STFT and ridge search").bytes, 0u);
  EXPECT_EQ(entry(t_off, "thread stacks").bytes, 3u * off.thread_stack_bytes);
}

TEST(BoardBudget, WorstCaseEventIsTheEncodedSizeOfAFullWindow) {
  for (const char* name : {"bath-amb-rig", "arm-virt-hil"}) {
    const board::BoardConfig b = board::load_board(name);
    const fw::StorageBudget s = fw::storage_budget(b);
    fw::FloatingCapture c;
    fw::configure_capture(c, b);
    fw::FrozenEvent e;
    e.samples.assign(c.pre_samples() + c.post_samples(), fw::LoopSample{});
    e.header.sample_count = static_cast<uint32_t>(e.samples.size());
    e.header.trigger_index = c.pre_samples();
    fw::EventRecord r = fw::make_event_record(e, b, 1);
    r.has_diagnosis = true;
    r.has_analysis = true;
    const std::vector<uint8_t> file = fw::encode_event(r);
    EXPECT_EQ(file.size(), s.event_bytes_worst) << name;
    EXPECT_EQ(entry(fw::buffer_budget(b), "event file image").bytes, file.size()) << name;
    EXPECT_EQ(s.window_samples, e.samples.size()) << name;
    EXPECT_EQ(s.events_kept, std::min<uint64_t>(s.max_events, s.capacity_bytes / file.size())) << name;
  }
  // The bath board: 0.5 + 2.0 s at 10 kHz = 25000 samples of 84 B + 1164 B; 256 MiB / that = 127
  // events, max_events 100: the count binds.
  const fw::StorageBudget bath = fw::storage_budget(board::load_board("bath-amb-rig"));
  EXPECT_EQ(bath.event_bytes_worst, 1164u + 25000u * 84u);
  EXPECT_EQ(bath.events_kept, 100u);
}

TEST(BoardBudget, CpuShareWindowSlides) {
  fw::CpuShareWindow<3> w;
  EXPECT_LT(w.share(), 0.0);
  w.add(0, 0);
  EXPECT_LT(w.share(), 0.0);
  w.add(1'000'000'000, 250'000'000);  // 25 % in the first second
  EXPECT_DOUBLE_EQ(w.share(), 0.25);
  w.add(2'000'000'000, 1'250'000'000);  // 100 % in the second
  EXPECT_DOUBLE_EQ(w.share(), 0.625);
  w.add(3'000'000'000, 1'250'000'000);  // idle in the third; the first second leaves the window
  EXPECT_DOUBLE_EQ(w.share(), 0.5);
  EXPECT_DOUBLE_EQ(w.window_s(), 2.0);
}

TEST(BoardBudget, RegistersServeTheTableAndTheMeasuredFigures) {
  const board::BoardConfig b = board::load_board("bath-amb-rig");
  const auto table = fw::buffer_budget(b);
  ASSERT_LE(table.size(), fw::regs::k_max_buffer_entries);
  fw::RegisterSources src;
  for (const fw::BufferBudget& e : table) src.buffer_bytes.push_back(e.bytes);
  src.storage_budget = fw::storage_budget(b);
  fw::RuntimeBudget rb;
  rb.locked_kb = 12345;
  rb.resident_kb = 23456;
  rb.peak_resident_kb = 70000;
  rb.loop_cpu_share = 0.1234;
  rb.analysis_cpu_share = -1.0;
  rb.window_s = 20.0;
  rb.start_to_ready_ns = 1'500'000'000;
  src.runtime_budget = [rb] { return rb; };
  fw::RegisterMap map(src);
  std::vector<uint16_t> r(fw::regs::buffers_end - fw::regs::buffers);
  ASSERT_EQ(map.read_registers(fw::regs::buffers, r), hal::RegisterHandler::Status::ok);
  ASSERT_EQ(r[0], table.size());
  for (size_t i = 0; i < table.size(); ++i)
    EXPECT_EQ((uint64_t{r[1 + 2 * i]} << 16) | r[2 + 2 * i], table[i].bytes) << table[i].name;
  std::vector<uint16_t> m(fw::regs::budget_end - fw::regs::budget);
  ASSERT_EQ(map.read_registers(fw::regs::budget, m), hal::RegisterHandler::Status::ok);
  EXPECT_EQ((uint32_t{m[0]} << 16) | m[1], 12345u);
  EXPECT_EQ((uint32_t{m[2]} << 16) | m[3], 23456u);
  EXPECT_EQ(m[6], 1234);    // 1/10000 of one CPU
  EXPECT_EQ(m[7], 0xFFFF);  // analysis not running
  EXPECT_EQ(m[8], 20);
  EXPECT_EQ((uint32_t{m[9]} << 16) | m[10], 1500u);
  EXPECT_EQ((uint32_t{m[11]} << 16) | m[12], 1164u + 25000u * 84u);
  EXPECT_EQ(m[15], 100);
  EXPECT_EQ(m[16], 100);
  // The hole between the blocks is not readable.
  std::vector<uint16_t> hole(1);
  EXPECT_NE(map.read_registers(fw::regs::budget_end, hole), hal::RegisterHandler::Status::ok);
}
