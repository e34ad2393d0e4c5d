#include "host-tools/core/ui/progress_bar.hpp"

#include <algorithm>
#include <cmath>
#include <unistd.h>

namespace amb::host::ui {

namespace {
constexpr int k_width = 30;  // bar cells
constexpr auto k_min_redraw = std::chrono::milliseconds(50);
}  // namespace

bool ProgressBar::is_terminal(std::FILE* f) { return f != nullptr && ::isatty(::fileno(f)) == 1; }

ProgressBar::ProgressBar(std::string label, bool force, std::FILE* out)
    : label_(std::move(label)), out_(out), start_(std::chrono::steady_clock::now()) {
  tty_ = is_terminal(out_);
  enabled_ = out_ != nullptr && (tty_ || force);
  last_draw_ = start_ - k_min_redraw;
}

ProgressBar::~ProgressBar() {
  if (!finished_) finish();
}

void ProgressBar::update(double fraction) {
  if (!enabled_ || finished_) return;
  fraction = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
  if (tty_) {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_draw_ < k_min_redraw) return;
    last_draw_ = now;
    draw(fraction, false, {});
  } else {
    const int decile = static_cast<int>(fraction * 10.0);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    draw(fraction, false, {});
  }
}

void ProgressBar::finish(const std::string& note) {
  if (finished_) return;
  finished_ = true;
  if (enabled_) draw(1.0, true, note);
}

void ProgressBar::draw(double fraction, bool final_line, const std::string& note) {
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const int pct = static_cast<int>(std::floor(fraction * 100.0 + 1e-9));
  if (tty_) {
    const int full = static_cast<int>(fraction * k_width);
    std::string bar(static_cast<size_t>(full), '#');
    bar.resize(k_width, '.');
    std::fprintf(out_, "\r\033[2K%s [%s] %3d%% %6.1f s%s%s", label_.c_str(), bar.c_str(), pct, elapsed_s,
                 note.empty() ? "" : "  ", note.c_str());
    if (final_line) std::fputc('\n', out_);
  } else {
    std::fprintf(out_, "%s: %3d%% %.1f s%s%s\n", label_.c_str(), pct, elapsed_s, note.empty() ? "" : "  ", note.c_str());
  }
  std::fflush(out_);
}

}  // namespace amb::host::ui
