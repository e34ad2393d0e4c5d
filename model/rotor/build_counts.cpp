// Process-wide counts of FE assemblies and modal eigen solves (see modal_reduction.hpp).
#include <atomic>

#include "model/rotor/modal_reduction.hpp"

namespace amb::model::rotor {
namespace {
std::atomic<long> g_fe_builds{0};
std::atomic<long> g_eigen_solves{0};
}  // namespace

namespace detail {
void count_fe_build() { g_fe_builds.fetch_add(1, std::memory_order_relaxed); }
void count_eigen_solve() { g_eigen_solves.fetch_add(1, std::memory_order_relaxed); }
}  // namespace detail

BuildCounts build_counts() {
  return {g_fe_builds.load(std::memory_order_relaxed), g_eigen_solves.load(std::memory_order_relaxed)};
}

}  // namespace amb::model::rotor
