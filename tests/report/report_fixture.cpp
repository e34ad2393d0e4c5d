#include "tests/report/report_fixture.hpp"

#include "firmware/events/event_codec.hpp"
#include "host-tools/core/fit/drop_fit.hpp"
#include "host-tools/core/replay/event_board.hpp"
#include "host-tools/core/replay/event_replay.hpp"
#include "host-tools/core/report/report_builder.hpp"
#include "host-tools/core/wear/load_map.hpp"
#include "host-tools/core/wear/wear_update.hpp"
#include "model/drop/drop_model.hpp"
#include "model/drop/drop_simulation.hpp"
#include "tests/replay/sil_capture_run.hpp"

namespace amb::test {

namespace {
host::report::ReportData build() {
  namespace hr = host::report;
  const CaptureRunResult& run = sil_capture();
  fw::EventRecord ev;
  std::string err;
  if (!fw::decode_event(run.event_default, ev, err)) throw std::runtime_error(err);
  const board::BoardConfig board = host::replay::board_for_event(ev);
  hr::ReportData d = hr::new_report_data("Drop event report: event_00000001.ambe (SIL)");
  hr::add_event(d, ev, board, "event_00000001.ambe");
  hr::add_replay(d, host::replay::replay_event(ev, board));

  // Phase C: a short fit of a drop-model "measurement" (sensor view, noise on).
  model::drop::DropOptions mo;
  mo.noise_seed = 77;
  model::drop::DropModel gen(board.plant, board.controller, board.rate_hz, mo);
  gen.set_friction_coefficient(0.15);
  model::drop::DropScenario sc;
  sc.window_s = 0.2;
  sc.pre_trigger_s = 0.02;
  const model::drop::DropTrace truth = model::drop::simulate_drop(gen, sc, false);
  const host::fit::DropMeasurement meas =
      host::fit::drop_measurement_from_trace(truth, sc, "drop model, mu 0.15 (report test)", board.name);
  host::fit::DropFitOptions fo;
  fo.max_window_s = 0.2;
  fo.optimiser.max_evaluations = 16;
  fo.optimiser.doe_points = 5;
  const host::fit::DropFitResult fit = host::fit::fit_drop(meas, board, fo);
  hr::add_fit(d, fit, "host-tools/core/fit on a drop-model measurement (mu 0.15), not on this SIL event: the fit "
                       "reads measured-event files; 16 evaluations (report test budget)");

  // Phase E: the fitted event folded into a fresh wear record.
  fw::WearRecord previous;
  previous.board_name = board.name;
  host::wear::WearEvent we;
  we.load = host::wear::event_load(fit.trace.contact_steps);
  we.rubbing = fit.rubbing;
  we.friction_coefficient = fit.friction_coefficient;
  const fw::WearRecord wear = host::wear::update_wear_record(previous, we, board.name, 1'800'000'000, {});
  hr::add_wear_record(d, wear, "host-tools/core/wear: update_wear_record (report test)");
  return d;
}
}  // namespace

const host::report::ReportData& full_report() {
  static const host::report::ReportData d = build();
  return d;
}

}  // namespace amb::test
