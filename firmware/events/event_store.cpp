#include "firmware/events/event_store.hpp"

#include <algorithm>
#include <cstdio>

namespace amb::fw {

std::string EventStore::name_of(uint64_t number) {
  char b[40];
  std::snprintf(b, sizeof b, "event_%08llu.ambe", static_cast<unsigned long long>(number));
  return b;
}

bool EventStore::parse_name(const std::string& name, uint64_t& number) {
  constexpr std::string_view prefix = "event_", suffix = ".ambe";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return false;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (digits.empty() || digits.size() > 18) return false;
  uint64_t v = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + static_cast<uint64_t>(c - '0');
  }
  number = v;
  return true;
}

EventStore::EventStore(hal::Storage& storage, const CaptureParams& params) : storage_(storage), p_(params) {
  std::vector<uint8_t> bytes;
  std::string error;
  for (const std::string& name : storage_.list()) {
    uint64_t n = 0;
    if (!parse_name(name, n)) continue;
    if (!storage_.read(name, bytes, error)) continue;
    sizes_[n] = bytes.size();
    if (n >= next_) next_ = n + 1;
  }
}

void EventStore::set_protected(uint64_t number, bool is_protected) {
  if (is_protected) protected_.insert(number);
  else protected_.erase(number);
}

std::vector<uint64_t> EventStore::numbers() const {
  std::vector<uint64_t> v;
  for (const auto& [n, sz] : sizes_) v.push_back(n);
  return v;
}

uint64_t EventStore::bytes_used() const {
  uint64_t u = 0;
  for (const auto& [n, sz] : sizes_) u += sz;
  return u;
}

StoreResult EventStore::put(uint64_t number, std::span<const uint8_t> bytes, std::string& error) {
  const uint64_t size = bytes.size();
  auto in_budget = [&] {
    return sizes_.size() + 1 <= static_cast<size_t>(p_.max_events) && bytes_used() + size <= p_.storage_capacity_bytes;
  };
  auto droppable = [&](uint64_t n) { return !protected_.count(n) && n != number; };
  // 1. The budget (count, bytes): the policy decides.
  if (!in_budget() && p_.storage_policy == StoragePolicy::drop_oldest) {
    for (auto it = sizes_.begin(); it != sizes_.end() && !in_budget();) {
      if (!droppable(it->first)) { ++it; continue; }
      storage_.remove(name_of(it->first));
      it = sizes_.erase(it);
      ++counters_.dropped_oldest;
    }
  }
  if (!in_budget()) {
    ++counters_.refused;
    error = "event " + std::to_string(number) + " refused (" +
            (p_.storage_policy == StoragePolicy::refuse_new ? "policy refuse_new" : "only protected events left") +
            "): " + std::to_string(sizes_.size()) + " events, " + std::to_string(bytes_used()) + " of " +
            std::to_string(p_.storage_capacity_bytes) + " bytes used, " + std::to_string(size) + " needed";
    return StoreResult::refused;
  }
  // 2. The file system's free space. drop_oldest makes room by dropping older events, but only
  // if dropping all it may drop would make room, and only while that helps: if a removal does not give space back (the file system is being filled by
  // something else), nothing more is dropped until the storage has room again. An event that
  // does not fit is a storage fault, not a policy refusal: `failed`, the caller retries.
  uint64_t free_now = storage_.free_bytes();
  if (size <= free_now) drops_ineffective_ = false;
  uint64_t could_free = 0;
  for (const auto& [n, sz] : sizes_)
    if (droppable(n)) could_free += sz;
  if (size > free_now && size <= free_now + could_free && p_.storage_policy == StoragePolicy::drop_oldest &&
      !drops_ineffective_) {
    for (auto it = sizes_.begin(); it != sizes_.end() && size > free_now;) {
      if (!droppable(it->first)) { ++it; continue; }
      const uint64_t dropped = it->second;
      storage_.remove(name_of(it->first));
      it = sizes_.erase(it);
      ++counters_.dropped_oldest;
      const uint64_t after = storage_.free_bytes();
      if (after < free_now + dropped / 2) {
        drops_ineffective_ = true;
        break;
      }
      free_now = after;
    }
  }
  if (size > free_now) {
    ++counters_.no_space;
    error = "event " + std::to_string(number) + ": storage full (" + std::to_string(free_now) + " bytes free, " +
            std::to_string(size) + " needed)";
    return StoreResult::failed;
  }
  std::string e;
  if (!storage_.write_atomic(name_of(number), bytes, e)) {
    ++counters_.write_errors;
    error = "event " + std::to_string(number) + ": write failed: " + e;
    return StoreResult::failed;
  }
  sizes_[number] = size;
  if (number >= next_) next_ = number + 1;
  ++counters_.written;
  return StoreResult::stored;
}

}  // namespace amb::fw
