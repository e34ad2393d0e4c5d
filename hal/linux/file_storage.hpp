#pragma once
// Storage in one directory of a POSIX file system, power-loss safe per item:
// write_atomic = write a temporary file, fsync it, rename it over the item, fsync the directory.
// Temporary files left by a power loss during a write are removed when the store is opened.
// Not real-time; safe to use from several threads on different names.
#include <atomic>
#include <string>

#include "hal/interfaces.hpp"

namespace amb::hal::linux_hw {

class FileStorage final : public Storage {
 public:
  /// Use (and create if missing, mode 0755) the directory `dir`. Removes stale temporaries.
  /// Throws std::runtime_error if the directory cannot be created or opened.
  explicit FileStorage(std::string dir);

  /// `name`: 1..64 characters from [A-Za-z0-9._-], not starting with '.'.
  bool write_atomic(std::string_view name, std::span<const uint8_t> bytes, std::string& error) override;
  bool read(std::string_view name, std::vector<uint8_t>& bytes, std::string& error) override;
  std::vector<std::string> list() override;
  bool remove(std::string_view name) override;
  uint64_t free_bytes() override;

  const std::string& dir() const { return dir_; }
  /// Temporaries found (and removed) at open: each one is an interrupted write.
  int stale_temporaries_removed() const { return stale_removed_; }

  /// Whether `name` is acceptable as an item name.
  static bool valid_name(std::string_view name);

 private:
  std::string path_of(std::string_view name) const;
  std::string dir_;
  int stale_removed_ = 0;
  std::atomic<uint64_t> temp_counter_{0};
};

}  // namespace amb::hal::linux_hw
