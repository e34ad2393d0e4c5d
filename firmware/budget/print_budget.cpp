#include "firmware/budget/print_budget.hpp"

namespace amb::fw {

void print_budget(std::FILE* out, const std::vector<BufferBudget>& table, const StorageBudget& s) {
  std::fprintf(out, "amb-firmware: budget: buffers (resident %.1f KiB):\n",
               static_cast<double>(resident_buffer_bytes(table)) / 1024.0);
  for (const BufferBudget& e : table)
    std::fprintf(out, "amb-firmware: budget:   %-40s %10.1f KiB  %s; %s\n", e.name.c_str(),
                 static_cast<double>(e.bytes) / 1024.0, e.resident ? "resident" : "per event", e.basis.c_str());
  std::fprintf(out,
               "amb-firmware: budget: storage: %llu B per event (worst case, %llu samples), capacity %llu B, "
               "max_events %llu, policy %s: keeps %llu events; wear record %llu B\n",
               static_cast<unsigned long long>(s.event_bytes_worst), static_cast<unsigned long long>(s.window_samples),
               static_cast<unsigned long long>(s.capacity_bytes), static_cast<unsigned long long>(s.max_events), s.policy,
               static_cast<unsigned long long>(s.events_kept), static_cast<unsigned long long>(s.wear_record_bytes));
}

}  // namespace amb::fw
