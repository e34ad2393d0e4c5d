#pragma once
// Storage in one directory of a POSIX file system, power-loss safe per item:
// write_atomic = write a temporary file, fsync it, rename it over the item, fsync the directory.
// Temporary files left by a power loss during a write are removed when the store is opened.
// Not real-time; safe to use from several threads on different names.
//
// Fault seam (no LD_PRELOAD): an optional FsFaultHook is asked before every file-system call
// and may fail it with an errno (ENOSPC, EIO, EROFS, ...) or delay it (a slow fsync). Tests and
// the fault rig (tests/sil/fault_rig.cpp) use it to prove that a failing storage never leaves
// a torn item and that every failure is reported.
#include <atomic>
#include <cstdint>
#include <string>
#include <string_view>

#include "hal/interfaces.hpp"

namespace amb::hal::linux_hw {

/// File-system calls FileStorage makes, as the fault hook sees them.
enum class FsOp : uint8_t { create = 0, write, fsync, rename, fsync_dir, read, unlink };

class FsFaultHook {
 public:
  virtual ~FsFaultHook() = default;
  /// Called before `op` on `path` (`bytes`: the size written, or of the file removed). Return an
  /// errno to make the call fail with it (a failed write has written its first half: a short
  /// write), 0 to let it run. May sleep (a slow device). Called from the storage's caller thread.
  virtual int before(FsOp op, std::string_view path, uint64_t bytes) = 0;
  /// Free bytes to report instead of statvfs; negative: ask statvfs.
  virtual int64_t free_bytes(std::string_view dir) { (void)dir; return -1; }
};

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

  /// Install (or remove, nullptr) the fault hook; it must outlive its use. Any thread.
  void set_fault_hook(FsFaultHook* hook) { hook_.store(hook, std::memory_order_release); }

 private:
  std::string path_of(std::string_view name) const;
  /// errno the hook injects for `op` (0: none / no hook).
  int inject(FsOp op, const std::string& path, uint64_t bytes) const;
  std::string dir_;
  std::atomic<FsFaultHook*> hook_{nullptr};
  int stale_removed_ = 0;
  std::atomic<uint64_t> temp_counter_{0};
};

}  // namespace amb::hal::linux_hw
