#pragma once
// A progress bar for long host work (replays, fits, reports). It writes to stderr only —
// never to stdout, which may carry JSON — and only when stderr is a terminal or when the user
// asked for it (--progress). On a terminal it redraws one line in place (at most every 50 ms);
// when forced onto a file or pipe it prints a plain line every 10 % instead.
//
// Usage:
//   ui::ProgressBar bar("replay", show_progress);
//   for (...) bar.update(done / total);
//   bar.finish("25000 samples");
#include <chrono>
#include <cstdio>
#include <string>

namespace amb::host::ui {

class ProgressBar {
 public:
  /// `label`: shown before the bar. `force`: draw even when `out` is not a terminal (the
  /// --progress option). `out`: stderr unless a test passes another stream.
  explicit ProgressBar(std::string label, bool force = false, std::FILE* out = stderr);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Report the fraction done, 0..1 (clamped). Cheap when nothing needs drawing.
  void update(double fraction);
  /// Close the bar (100 %, elapsed time, optional note). Called by the destructor if needed.
  void finish(const std::string& note = {});
  /// True when this bar draws anything.
  bool enabled() const { return enabled_; }

  /// True when `f` is a terminal.
  static bool is_terminal(std::FILE* f);

 private:
  void draw(double fraction, bool final_line, const std::string& note);

  std::string label_;
  std::FILE* out_;
  bool enabled_ = false;
  bool tty_ = false;
  bool finished_ = false;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace amb::host::ui
