#pragma once
// Hands each loop sample to several sinks (the capture ring and the analysis task's ring).
// [RT]: a fixed array of pointers, no allocation.
#include <array>
#include <cstddef>

#include "firmware/app/loop_runner.hpp"

namespace amb::fw {

class SampleFanout final : public SampleSink {
 public:
  static constexpr size_t k_max_sinks = 4;
  /// Configure time: add a sink (nullptr ignored). False when full.
  bool add(SampleSink* sink) {
    if (!sink) return true;
    if (n_ == k_max_sinks) return false;
    sinks_[n_++] = sink;
    return true;
  }
  size_t size() const { return n_; }
  void on_sample(const LoopSample& s) override {
    for (size_t i = 0; i < n_; ++i) sinks_[i]->on_sample(s);
  }

 private:
  std::array<SampleSink*, k_max_sinks> sinks_{};
  size_t n_ = 0;
};

}  // namespace amb::fw
