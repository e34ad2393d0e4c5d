// amb-firmware --backend linux: the supervisor on real I/O. The field bus (SocketCAN) carries
// samples and demands to the sensor and amplifier nodes, the discrete lines are on a GPIO chip
// (libgpiod), the supervisory link is Modbus TCP (libmodbus, own thread), storage is a
// directory with power-loss-safe replace. Wiring comes from the board file's [comms] table.
//
// Threads: the loop (SCHED_FIFO if permitted, memory locked) runs read -> step -> write; the
// Modbus server thread, the event-writer thread and the analysis thread (speed tracker,
// bearing task, CAN board-status frame) exchange data with it only through lock-free
// snapshots, one atomic word (the tracked speed) and SPSC rings.
#ifdef AMB_HAVE_LINUX_HAL
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/mman.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <thread>

#include "firmware/analysis/analysis_thread.hpp"
#include "firmware/app/loop_runner.hpp"
#include "firmware/app/sample_fanout.hpp"
#include "firmware/budget/board_budget.hpp"
#include "firmware/budget/print_budget.hpp"
#include "firmware/budget/runtime_budget.hpp"
#include "firmware/capture/floating_capture.hpp"
#include "firmware/events/event_writer.hpp"
#include "firmware/fieldbus/field_bus_front_end.hpp"
#include "firmware/main/run_modes.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "firmware/supervisory/register_map.hpp"
#include "hal/linux/file_storage.hpp"
#include "hal/linux/gpiod_discrete_io.hpp"
#include "hal/linux/linux_clock.hpp"
#include "hal/linux/modbus_tcp_server.hpp"
#include "hal/linux/process_memory.hpp"
#include "hal/linux/rt_thread.hpp"
#include "hal/linux/thread_scheduling.hpp"
#include "hal/linux/service_notify.hpp"
#include "hal/linux/socketcan_bus.hpp"

namespace amb::fwmain {

namespace {

namespace lx = hal::linux_hw;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }

/// Tells the service manager (systemd, Type=notify) something; a no-op when not started by
/// one (no NOTIFY_SOCKET). Called from the main thread only, never from the loop: a system call.
void notify_service_manager(const char* state) { (void)lx::notify_service_manager(state); }
using lx::service_watchdog_ns;

/// Discrete inputs from the GPIO lines, with the amplifier node's fault report (field bus)
/// OR-ed into the amplifier fault. [RT]
class BoardDiscreteIo final : public hal::DiscreteIo {
 public:
  BoardDiscreteIo(lx::GpiodDiscreteIo* gpio, const fieldbus::FieldBusFrontEnd& fe) : gpio_(gpio), fe_(fe) {}
  hal::DiscreteInputs read() override {
    hal::DiscreteInputs d = gpio_ ? gpio_->read() : hal::DiscreteInputs{};
    d.amplifier_fault = d.amplifier_fault || fe_.amplifier_fault();
    return d;
  }
  void write(const hal::DiscreteOutputs& out) override {
    if (gpio_) gpio_->write(out);
  }

 private:
  lx::GpiodDiscreteIo* gpio_;
  const fieldbus::FieldBusFrontEnd& fe_;
};

/// The process's memory set-up (before any thread exists): one malloc arena, fixed mmap and
/// trim thresholds, and every thread's stack (std::thread included) sized here.
const lx::ProcessMemoryOptions k_memory{};

/// Real-time setup of the loop thread, called in it once every other thread runs and every
/// buffer is allocated: its stack pre-faulted, then mlockall(MCL_CURRENT) -- all the loop
/// touches exists by then, so MCL_FUTURE (which would lock and populate every later mapping
/// of the non-real-time threads too) is not needed; SCHED_FIFO 80; the highest CPU of the
/// service's set (CPUAffinity= or taskset; the other threads share the rest). Failures are
/// reported, not fatal, so the firmware also runs unprivileged (tests, emulation).
lx::RtOptions loop_rt_options() {
  lx::RtOptions o;
  o.fifo_priority = 80;
  o.pin_highest_allowed = true;
  o.lock_memory = true;
  o.lock_future = false;
  o.prefault_stack_bytes = k_memory.thread_stack_bytes / 2;
  return o;
}

std::vector<lx::CanFilter> board_filters(const comms::CanParams& c) {
  std::vector<lx::CanFilter> f;
  for (uint32_t fn : {fieldbus::k_position, fieldbus::k_sample_fd, fieldbus::k_heartbeat})
    f.push_back({fn + c.sensor_node_id, 0x7FF, false});
  for (uint32_t fn : {fieldbus::k_current, fieldbus::k_amp_status, fieldbus::k_heartbeat})
    f.push_back({fn + c.amplifier_node_id, 0x7FF, false});
  return f;
}

}  // namespace

int run_linux(const board::BoardConfig& board, const RunOptions& opt) {
  const comms::CommsParams& cm = board.comms;
  if (!cm.present) {
    std::fprintf(stderr, "amb-firmware: board %s has no [comms] table: the linux backend needs one\n",
                 board.name.c_str());
    return 1;
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // a service log: one line at a time
  if (const lx::ProcessMemoryReport pm = lx::configure_process_memory(k_memory); !pm.warnings.empty())
    std::printf("amb-firmware: memory set-up: %s\n", pm.warnings.c_str());
  const char* env_dir = std::getenv("AMB_DATA_DIR");
  const std::string data_dir = env_dir && *env_dir ? env_dir : cm.data_dir;
  std::string err;

  // ---- configure: open every device, allocate everything ------------------------------
  lx::SocketCanBus can;
  lx::SocketCanOptions co;
  co.interface = cm.can.interface;
  co.fd = cm.can.fd;
  co.filters = board_filters(cm.can);
  co.bus_off_restart_ns = static_cast<int64_t>(cm.can.bus_off_restart_ms) * 1'000'000;
  if (!can.open(co, err)) {
    std::fprintf(stderr, "amb-firmware: %s\n", err.c_str());
    return 1;
  }
  std::unique_ptr<lx::GpiodDiscreteIo> gpio;
  if (cm.gpio.enabled) {
    gpio = std::make_unique<lx::GpiodDiscreteIo>();
    lx::GpioLineMap lines;
    lines.chip = cm.gpio.chip;
    lines.amplifier_enable = static_cast<unsigned>(cm.gpio.amplifier_enable_line);
    lines.watchdog = static_cast<unsigned>(cm.gpio.watchdog_line);
    lines.status = static_cast<unsigned>(cm.gpio.status_line);
    lines.amplifier_fault = static_cast<unsigned>(cm.gpio.amplifier_fault_line);
    lines.landing_request = static_cast<unsigned>(cm.gpio.landing_request_line);
    if (!gpio->open(lines, "amb-firmware", err)) {
      std::fprintf(stderr, "amb-firmware: %s\n", err.c_str());
      return 1;
    }
  }
  std::unique_ptr<lx::FileStorage> events_fs, wear_fs;
  try {
    lx::FileStorage root(data_dir);  // creates the root if needed
    events_fs = std::make_unique<lx::FileStorage>(data_dir + "/events");
    wear_fs = std::make_unique<lx::FileStorage>(data_dir + "/wear");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "amb-firmware: %s\n", e.what());
    return 1;
  }
  fw::WearStore wear(*wear_fs, board.name);
  const fw::GenerationReport wear_report = wear.open();
  std::printf("amb-firmware: storage %s: %zu event(s), wear record %s (generation %llu; %s), %d interrupted write(s) cleaned\n",
              data_dir.c_str(), events_fs->list().size(),
              wear.has_record() ? ("sequence " + std::to_string(wear.record().sequence)).c_str() : "absent",
              static_cast<unsigned long long>(wear_report.generation), wear_report.detail.c_str(),
              events_fs->stale_temporaries_removed() + wear_fs->stale_temporaries_removed());

  std::printf("amb-firmware: configuring the supervisor, capture and event writer\n");
  fw::Supervisor sup;
  sup.configure(board);
  lx::LinuxClock clock;
  fieldbus::FieldBusFrontEnd fe(can, clock, cm.can, &sup);
  BoardDiscreteIo dio(gpio.get(), fe);
  fw::FloatingCapture capture;
  fw::configure_capture(capture, board);
  fw::EventWriter writer(capture, *events_fs, board);
  writer.on_event = [](const fw::EventRecord&, const std::string& name, bool stored) {
    std::printf("amb-firmware: drop event %s %s\n", name.c_str(), stored ? "stored" : "NOT stored");
    std::fflush(stdout);
  };
  // The loop-sensitivity sweep: its finished record is stored by the same writer (AMBE v4, kind sweep).
  writer.set_sweep_source(&sup.sweep());
  writer.on_sweep = [](const fw::SweepEvent& e, const std::string& name, bool stored) {
    std::printf("amb-firmware: sweep event %s %s (%zu axes, %zu lines, amplitude %.4g A, crest %.2f%s%s)\n", name.c_str(),
                stored ? "stored" : "NOT stored", e.axes.size(), e.bins.size(), e.amplitude_a, e.crest_factor,
                e.aborted ? ", aborted: " : "", e.aborted ? fw::to_string(e.abort_reason) : "");
    std::fflush(stdout);
  };
  if (!sup.sweep_config_error().empty())
    std::printf("amb-firmware: sweep: starts will be refused: %s\n", sup.sweep_config_error().c_str());
  // Analysis task (tracker on the [tracker] channel, bearing task): fed from the loop through
  // its SPSC ring, polled by the analysis thread.
  auto analysis = std::make_unique<fw::AnalysisTask>();
  if (std::string aerr = analysis->configure(board, &sup); !aerr.empty()) {
    std::fprintf(stderr, "amb-firmware: board %s: %s\n", board.name.c_str(), aerr.c_str());
    return 1;
  }
  const bool run_analysis = opt.analysis && analysis->enabled();
  fw::BudgetOptions bo;
  bo.analysis_thread = run_analysis;
  bo.thread_stack_bytes = k_memory.thread_stack_bytes;
  const std::vector<fw::BufferBudget> buffer_table = fw::buffer_budget(board, bo);
  const fw::StorageBudget storage_budget = fw::storage_budget(board);
  fw::print_budget(stdout, buffer_table, storage_budget);
  fw::SeqLock<fw::RuntimeBudget> runtime_budget;
  runtime_budget.store(fw::RuntimeBudget{});
  fw::SampleFanout sinks;
  sinks.add(&capture);
  if (run_analysis) sinks.add(analysis.get());
  // The board-status frame goes out on its own socket from the analysis thread (the loop's
  // socket stays the loop's); it receives nothing (filter on its own identifier).
  lx::SocketCanBus status_can;
  if (run_analysis) {
    lx::SocketCanOptions so = co;
    so.filters = {{static_cast<uint32_t>(fieldbus::k_board_status + cm.can.board_node_id), 0x7FF, false}};
    if (!status_can.open(so, err)) {
      std::fprintf(stderr, "amb-firmware: board-status socket: %s\n", err.c_str());
      return 1;
    }
  }
  // The sweep-status frame goes out from the supervision thread below, on its own socket.
  lx::SocketCanBus sweep_can;
  {
    lx::SocketCanOptions so = co;
    so.filters = {{static_cast<uint32_t>(fieldbus::k_sweep_status + cm.can.board_node_id), 0x7FF, false}};
    if (!sweep_can.open(so, err)) {
      std::fprintf(stderr, "amb-firmware: sweep-status socket: %s\n", err.c_str());
      return 1;
    }
  }
  fw::LoopRunner loop(clock, fe, dio, sup, &sinks);
  fw::SeqLock<fw::LoopStats> loop_stats;
  loop_stats.store(fw::LoopStats{});

  lx::ModbusTcpOptions mo;
  mo.bind_address = cm.modbus.bind_address;
  mo.port = cm.modbus.port;
  mo.unit_id = cm.modbus.unit_id;
  mo.max_clients = cm.modbus.max_clients;
  lx::ModbusTcpServer server(mo);
  fw::RegisterSources src;
  src.supervisor = &sup;
  src.loop_stats = [&] { return loop_stats.load(); };
  src.can_stats = [&] { return can.stats(); };
  src.fieldbus = [&] { return fe.counters(); };
  src.link = [&] {
    const auto s = server.stats();
    return fw::LinkCounters{s.requests, s.exceptions, s.bad_frames, s.wrong_unit, s.connections, s.refused_connections};
  };
  src.storage = [&] { return writer.store_counters(); };
  src.sweep_store = [&] { return fw::SweepStoreInfo{writer.sweeps_stored(), writer.last_sweep_number()}; };
  src.runtime_budget = [&] { return runtime_budget.load(); };
  for (const fw::BufferBudget& e : buffer_table) src.buffer_bytes.push_back(e.bytes);
  src.storage_budget = storage_budget;
  src.manual_capture = [&] { return capture.request_manual_trigger(); };
  src.now_ns = [] { return lx::monotonic_ns(); };
  src.arm_key = cm.modbus.arm_key;
  src.arm_window_ns = static_cast<int64_t>(cm.modbus.arm_window_ms) * 1'000'000;
  src.nodes_alive = [&] { return fe.nodes_alive(); };
  if (run_analysis) src.analysis = [&] { return analysis->status(); };
  src.speed_source = static_cast<uint8_t>(board.tracker.speed_source);
  src.events = events_fs.get();
  src.wear = &wear;
  src.wear_corrupt_at_start = wear_report.corrupt_slots;
  src.board_name = board.name;
  src.unit_id = cm.modbus.unit_id;
  src.rate_hz = board.rate_hz;
  fw::RegisterMap map(src);
  if (!server.start(map, err)) {
    std::fprintf(stderr, "amb-firmware: %s\n", err.c_str());
    return 1;
  }
  writer.start();
  lx::LinuxThreadScheduling thread_scheduling;
  fw::AnalysisThread analysis_thread(&thread_scheduling);
  std::atomic<uint64_t> status_frames{0};
  if (run_analysis) {
    uint64_t last_disagreements = 0;
    uint8_t status_seq = 0;
    analysis_thread.start(
        *analysis, board.tracker.poll_period_s,
        [&, last_disagreements, status_seq](const fw::AnalysisStatus& a) mutable {
          const fw::Status st = sup.status();
          fieldbus::BoardStatus bs;
          bs.speed_hz = st.speed_lost ? std::nan("") : st.speed_estimate_hz;
          bs.confidence = st.speed_confidence;
          bs.flags = static_cast<uint8_t>((st.speed_lost ? fieldbus::status_speed_lost : 0) |
                                          (st.tracked.stale ? fieldbus::status_tracker_stale : 0) |
                                          (a.below_min ? fieldbus::status_below_min : 0) |
                                          (static_cast<unsigned>(board.tracker.speed_source) << 3) |
                                          (a.defects_valid ? fieldbus::status_defects_valid : 0) |
                                          (st.counters.speed_disagreements != last_disagreements ? fieldbus::status_disagreement : 0));
          last_disagreements = st.counters.speed_disagreements;
          bs.sequence = status_seq++;
          bs.tracker_mode = a.mode;
          if (status_can.send(fieldbus::encode_board_status(cm.can.board_node_id, bs))) status_frames.fetch_add(1);
        },
        board.tracker.status_frame_period_s);
  }

  struct sigaction sa{};
  sa.sa_handler = on_signal;
  ::sigaction(SIGTERM, &sa, nullptr);
  ::sigaction(SIGINT, &sa, nullptr);
  ::signal(SIGPIPE, SIG_IGN);

  // ---- active: the loop ---------------------------------------------------------------
  lx::RtReport rt;
  std::atomic<bool> loop_done{false};
  std::thread loop_thread([&] {
    rt = lx::configure_realtime_thread(loop_rt_options());
    const int64_t stop_ns = opt.duration_s > 0 ? static_cast<int64_t>(opt.duration_s * 1e9) : -1;
    int64_t deadline = clock.now_ns() + loop.period_ns();
    uint64_t n = 0;
    while (!g_stop.load(std::memory_order_relaxed)) {
      deadline = loop.run_one(deadline);
      if ((++n & 15u) == 0) loop_stats.store(loop.stats());
      if (stop_ns > 0 && deadline >= stop_ns) break;
    }
    loop_stats.store(loop.stats());
    // Leave the plant safe: amplifiers off, drive off, lines low.
    sup.enter_safe_state(fw::FaultReason::emergency_stop);
    fe.write(hal::AnalogOutputs{});
    dio.write(hal::DiscreteOutputs{});
    loop_done.store(true);
  });
  std::printf("amb-firmware: ready: board %s, %.0f Hz loop, CAN %s%s, GPIO %s, Modbus TCP %s:%u unit %u, "
              "analysis thread %s (speed source %s), Modbus commands %s\n",
              board.name.c_str(), board.rate_hz, cm.can.interface.c_str(), cm.can.fd ? " (FD)" : "",
              gpio ? cm.gpio.chip.c_str() : "none", cm.modbus.bind_address.c_str(), server.bound_port(),
              cm.modbus.unit_id, run_analysis ? "on" : "off", fw::to_string(board.tracker.speed_source),
              cm.modbus.arm_key != 0 ? "armed by key ([comms.modbus] arm_key)" : "disabled (no arm_key)");
  std::fflush(stdout);

  // ---- service supervision (this non-RT thread): READY=1 once the loop has run its first
  // periods; then WATCHDOG=1 every half watchdog interval, but only while the loop's period
  // count (its heartbeat, published through the SeqLock every 16 periods) advances: a hung
  // loop stops the petting and systemd restarts the service (Restart=on-failure).
  const int64_t watchdog_ns = service_watchdog_ns();
  const int64_t pet_ns = watchdog_ns > 0 ? watchdog_ns / 2 : 0;
  bool ready_sent = false;
  uint64_t last_periods = 0, missed_pets = 0;
  int64_t next_pet = lx::monotonic_ns() + pet_ns;
  // The budget as measured: memory from /proc and the CPU clocks of the loop and analysis
  // threads, once a second here (never in the loop), shares over the last 20 s.
  fw::CpuShareWindow<21> loop_cpu, analysis_cpu;
  fw::RuntimeBudget rb;
  int64_t next_measure = lx::monotonic_ns();
  auto measure = [&] {
    const int64_t now = lx::monotonic_ns();
    const lx::ProcessMemory pm = lx::read_process_memory();
    rb.locked_kb = pm.locked_kb;
    rb.resident_kb = pm.resident_kb;
    rb.peak_resident_kb = pm.peak_resident_kb;
    if (const int64_t c = lx::thread_cpu_ns(loop_thread.native_handle()); c >= 0) loop_cpu.add(now, c);
    if (run_analysis)
      if (const int64_t c = lx::thread_cpu_ns(analysis_thread.native_handle()); c >= 0) analysis_cpu.add(now, c);
    rb.loop_cpu_share = loop_cpu.share();
    rb.analysis_cpu_share = run_analysis ? analysis_cpu.share() : -1.0;
    rb.window_s = loop_cpu.window_s();
    runtime_budget.store(rb);
  };
  int64_t next_sweep_frame = 0;
  bool sweep_was_running = false;
  uint64_t sweep_frames = 0;
  while (!loop_done.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const uint64_t periods = loop_stats.load().periods;
    // Sweep status on CAN every 100 ms while a sweep runs, and once when it has ended.
    if (const fw::SweepStatus sw = sup.status().sweep; sw.state != fw::SweepState::idle || sweep_was_running) {
      const int64_t now = lx::monotonic_ns();
      if (now >= next_sweep_frame || sw.state == fw::SweepState::idle) {
        fieldbus::SweepStatusFrame f;
        f.state = static_cast<uint8_t>(sw.state);
        f.axis = sw.axis;
        f.axes_done = sw.axes_done;
        f.axes_total = sw.axes_total;
        f.period = static_cast<uint16_t>(std::min<uint32_t>(sw.period, 0xFFFF));
        f.aborts = static_cast<uint8_t>(std::min<uint32_t>(sw.aborts, 255));
        f.refusals = static_cast<uint8_t>(std::min<uint32_t>(sw.refusals, 255));
        f.last_abort = static_cast<uint8_t>(sw.last_abort);
        f.last_refusal = static_cast<uint8_t>(sw.last_refusal);
        if (sweep_can.send(fieldbus::encode_sweep_status(cm.can.board_node_id, f))) ++sweep_frames;
        next_sweep_frame = now + 100'000'000;
      }
      sweep_was_running = sw.state != fw::SweepState::idle;
    }
    if (!ready_sent && periods > 0) {
      rb.start_to_ready_ns = lx::ns_since_process_start();
      notify_service_manager("READY=1\nSTATUS=loop running");
      std::printf("amb-firmware: service: READY=1 sent (loop running) %.2f s after the process started%s\n",
                  static_cast<double>(rb.start_to_ready_ns) * 1e-9,
                  watchdog_ns > 0 ? ", watchdog petted while the loop's period count advances" : "");
      std::fflush(stdout);
      ready_sent = true;
    }
    if (lx::monotonic_ns() >= next_measure) {
      measure();
      next_measure += 1'000'000'000;
    }
    if (pet_ns <= 0 || lx::monotonic_ns() < next_pet) continue;
    next_pet += pet_ns;
    if (periods != last_periods) {
      notify_service_manager("WATCHDOG=1");
      last_periods = periods;
    } else if (missed_pets++ == 0) {
      std::printf("amb-firmware: service: loop heartbeat stalled at %llu periods: watchdog not petted\n",
                  static_cast<unsigned long long>(periods));
      std::fflush(stdout);
    }
  }
  notify_service_manager("STOPPING=1");
  measure();
  loop_thread.join();
  std::printf("amb-firmware: budget: VmLck %llu kB, VmRSS %llu kB (peak %llu kB); CPU over the last %.0f s: loop thread %.2f %%, "
              "analysis thread %s\n",
              static_cast<unsigned long long>(rb.locked_kb), static_cast<unsigned long long>(rb.resident_kb),
              static_cast<unsigned long long>(rb.peak_resident_kb), rb.window_s, 100.0 * rb.loop_cpu_share,
              run_analysis ? (std::to_string(100.0 * rb.analysis_cpu_share).substr(0, 5) + " %").c_str() : "off");
  analysis_thread.stop();
  writer.stop();
  server.stop();

  const fw::LoopStats ls = loop.stats();
  const hal::CanStats cs = can.stats();
  const fieldbus::FieldBusCounters fc = fe.counters();
  const fw::Status st = sup.status();
  std::printf("amb-firmware: stopped: %llu periods, %llu overruns, latency mean %.0f us p99 %.0f us max %.0f us, "
              "memory %s, SCHED_FIFO %s\n",
              static_cast<unsigned long long>(ls.periods), static_cast<unsigned long long>(ls.overruns),
              ls.mean_latency_ns() * 1e-3, static_cast<double>(ls.latency_quantile_ns(0.99)) * 1e-3,
              static_cast<double>(ls.max_latency_ns) * 1e-3, rt.memory_locked ? "locked" : "not locked",
              rt.fifo ? "yes" : "no (not permitted)");
  std::printf("amb-firmware: loop delay (sample instant -> demand written) p50 %.0f us p99 %.0f us p99.9 %.0f us "
              "max %.0f us (%.2f / %.2f periods at p50 / p99; board key loop_delay_periods %.2f)\n",
              static_cast<double>(ls.delay_quantile_ns(0.5)) * 1e-3, static_cast<double>(ls.delay_quantile_ns(0.99)) * 1e-3,
              static_cast<double>(ls.delay_quantile_ns(0.999)) * 1e-3, static_cast<double>(ls.max_delay_ns) * 1e-3,
              static_cast<double>(ls.delay_quantile_ns(0.5)) * 1e-9 * board.rate_hz,
              static_cast<double>(ls.delay_quantile_ns(0.99)) * 1e-9 * board.rate_hz, board.loop_delay_periods);
  std::printf("amb-firmware: CAN tx %llu rx %llu tx_dropped %llu rx_dropped %llu error_frames %llu bus_off %llu; "
              "field bus samples %llu malformed %llu node_timeouts %llu; state %s, fault %s\n",
              static_cast<unsigned long long>(cs.tx_frames), static_cast<unsigned long long>(cs.rx_frames),
              static_cast<unsigned long long>(cs.tx_dropped), static_cast<unsigned long long>(cs.rx_dropped),
              static_cast<unsigned long long>(cs.error_frames), static_cast<unsigned long long>(cs.bus_off_events),
              static_cast<unsigned long long>(fc.samples), static_cast<unsigned long long>(fc.malformed),
              static_cast<unsigned long long>(fc.node_timeouts), fw::to_string(st.state), fw::to_string(st.fault));
  std::printf("amb-firmware: sweep: %u started, %u completed, %u aborted (last: %s), %u refused (last: %s); "
              "%llu sweep events stored, %llu sweep-status frames\n",
              st.sweep.started, st.sweep.completed, st.sweep.aborts, fw::to_string(st.sweep.last_abort), st.sweep.refusals,
              fw::to_string(st.sweep.last_refusal), static_cast<unsigned long long>(writer.sweeps_stored()),
              static_cast<unsigned long long>(sweep_frames));
  const fw::StoreCounters sc = writer.store_counters();
  std::printf("amb-firmware: storage: events written %llu, refused %llu, dropped oldest %llu, write errors %llu, "
              "retries %llu, lost %llu; wear-record commits failed in storage %llu\n",
              static_cast<unsigned long long>(sc.written), static_cast<unsigned long long>(sc.refused),
              static_cast<unsigned long long>(sc.dropped_oldest), static_cast<unsigned long long>(sc.write_errors),
              static_cast<unsigned long long>(sc.retries), static_cast<unsigned long long>(sc.lost),
              static_cast<unsigned long long>(map.wear_store_failures()));
  if (run_analysis) {
    const fw::AnalysisStatus a = analysis->status();
    std::printf("amb-firmware: analysis: %llu tracker updates, %llu samples, %llu gaps, %llu resets, %llu ring drops, "
                "%llu status frames; last tracked %.3f Hz (confidence %.2f%s); %llu tach disagreements, %llu lost periods\n",
                static_cast<unsigned long long>(a.tracker_updates), static_cast<unsigned long long>(a.samples),
                static_cast<unsigned long long>(a.gaps), static_cast<unsigned long long>(a.resets),
                static_cast<unsigned long long>(a.ring_drops), static_cast<unsigned long long>(status_frames.load()),
                a.tracked_speed_hz, a.confidence, a.lost ? ", lost" : "",
                static_cast<unsigned long long>(st.counters.speed_disagreements),
                static_cast<unsigned long long>(st.counters.speed_lost_periods));
  }
  return 0;
}

}  // namespace amb::fwmain
#endif  // AMB_HAVE_LINUX_HAL
