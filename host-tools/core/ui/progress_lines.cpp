#include "host-tools/core/ui/progress_lines.hpp"

#include <chrono>
#include <cstdio>
#include <memory>

namespace amb::host::ui {

std::function<void(const std::string&)> periodic_lines(const std::string& label, double period_s) {
  struct State {
    bool any = false;
    std::chrono::steady_clock::time_point last;
  };
  auto st = std::make_shared<State>();
  return [st, label, period_s](const std::string& line) {
    const auto now = std::chrono::steady_clock::now();
    if (st->any && std::chrono::duration<double>(now - st->last).count() < period_s) return;
    st->any = true;
    st->last = now;
    std::fprintf(stderr, "%s: %s\n", label.c_str(), line.c_str());
  };
}

}  // namespace amb::host::ui
