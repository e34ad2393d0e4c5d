#include "hal/linux/file_storage.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace amb::hal::linux_hw {

namespace {

std::string errno_text(const std::string& what) { return what + ": " + std::strerror(errno); }

bool write_all(int fd, const uint8_t* p, size_t n, int injected) {
  if (injected != 0) {  // a short write, then the error
    const size_t half = n / 2;
    if (half > 0 && ::write(fd, p, half) < 0) return false;
    errno = injected;
    return false;
  }
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += w;
    n -= static_cast<size_t>(w);
  }
  return true;
}

bool fsync_dir(const std::string& dir, int injected = 0) {
  if (injected != 0) {
    errno = injected;
    return false;
  }
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}

bool is_temporary(const std::string& n) { return n.size() > 5 && n[0] == '.' && n.ends_with(".tmp"); }

}  // namespace

bool FileStorage::valid_name(std::string_view name) {
  if (name.empty() || name.size() > 64 || name[0] == '.') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
           c == '-';
  });
}

FileStorage::FileStorage(std::string dir) : dir_(std::move(dir)) {
  if (::mkdir(dir_.c_str(), 0755) != 0 && errno != EEXIST)
    throw std::runtime_error(errno_text("cannot create storage directory " + dir_));
  DIR* d = ::opendir(dir_.c_str());
  if (!d) throw std::runtime_error(errno_text("cannot open storage directory " + dir_));
  std::vector<std::string> stale;
  while (dirent* e = ::readdir(d)) {
    const std::string n = e->d_name;
    if (is_temporary(n)) stale.push_back(n);
  }
  ::closedir(d);
  // A temporary is a write that never reached its rename: the item still holds the old content.
  for (const auto& n : stale)
    if (::unlink((dir_ + "/" + n).c_str()) == 0) ++stale_removed_;
  if (stale_removed_ > 0) fsync_dir(dir_);
}

std::string FileStorage::path_of(std::string_view name) const { return dir_ + "/" + std::string(name); }

int FileStorage::inject(FsOp op, const std::string& path, uint64_t bytes) const {
  FsFaultHook* h = hook_.load(std::memory_order_acquire);
  return h ? h->before(op, path, bytes) : 0;
}

bool FileStorage::write_atomic(std::string_view name, std::span<const uint8_t> bytes, std::string& error) {
  if (!valid_name(name)) {
    error = "invalid storage item name '" + std::string(name) + "'";
    return false;
  }
  const std::string tmp = dir_ + "/." + std::string(name) + "." + std::to_string(::getpid()) + "." +
                          std::to_string(temp_counter_.fetch_add(1)) + ".tmp";
  if (const int e = inject(FsOp::create, tmp, bytes.size()); e != 0) {
    errno = e;
    error = errno_text("cannot create " + tmp);
    return false;
  }
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    error = errno_text("cannot create " + tmp);
    return false;
  }
  // Any failure before the rename leaves the item as it was; the temporary is removed.
  auto fail = [&](const std::string& what) {
    error = errno_text(what + " " + tmp);
    ::close(fd);
    ::unlink(tmp.c_str());
    return false;
  };
  if (!write_all(fd, bytes.data(), bytes.size(), inject(FsOp::write, tmp, bytes.size()))) return fail("cannot write");
  if (const int e = inject(FsOp::fsync, tmp, bytes.size()); e != 0) {
    errno = e;
    return fail("cannot fsync");
  }
  if (::fsync(fd) != 0) return fail("cannot fsync");
  if (::close(fd) != 0) {
    error = errno_text("cannot close " + tmp);
    ::unlink(tmp.c_str());
    return false;
  }
  const int rename_error = inject(FsOp::rename, path_of(name), bytes.size());
  if (rename_error != 0 || ::rename(tmp.c_str(), path_of(name).c_str()) != 0) {
    if (rename_error != 0) errno = rename_error;
    error = errno_text("cannot rename " + tmp);
    ::unlink(tmp.c_str());
    return false;
  }
  // The rename is durable only once the directory entry is on disk. If that fails the item
  // holds the new content or (after a power loss) the old one, never a mix: reported as a
  // failure, the caller may write it again.
  if (!fsync_dir(dir_, inject(FsOp::fsync_dir, dir_, 0))) {
    error = errno_text("cannot fsync directory " + dir_);
    return false;
  }
  return true;
}

bool FileStorage::read(std::string_view name, std::vector<uint8_t>& bytes, std::string& error) {
  if (!valid_name(name)) {
    error = "invalid storage item name '" + std::string(name) + "'";
    return false;
  }
  const int injected = inject(FsOp::read, path_of(name), 0);
  const int fd = injected != 0 ? -1 : ::open(path_of(name).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (injected != 0) errno = injected;
    error = errno_text("cannot open " + path_of(name));
    return false;
  }
  struct stat st{};
  if (::fstat(fd, &st) != 0) {
    error = errno_text("cannot stat " + path_of(name));
    ::close(fd);
    return false;
  }
  bytes.resize(static_cast<size_t>(st.st_size));
  size_t at = 0;
  while (at < bytes.size()) {
    const ssize_t r = ::read(fd, bytes.data() + at, bytes.size() - at);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) break;
    at += static_cast<size_t>(r);
  }
  ::close(fd);
  if (at != bytes.size()) {
    error = "short read of " + path_of(name);
    return false;
  }
  return true;
}

std::vector<std::string> FileStorage::list() {
  std::vector<std::string> names;
  DIR* d = ::opendir(dir_.c_str());
  if (!d) return names;
  while (dirent* e = ::readdir(d)) {
    const std::string n = e->d_name;
    if (!valid_name(n)) continue;
    struct stat st{};
    if (::stat(path_of(n).c_str(), &st) == 0 && S_ISREG(st.st_mode)) names.push_back(n);
  }
  ::closedir(d);
  std::sort(names.begin(), names.end());
  return names;
}

bool FileStorage::remove(std::string_view name) {
  if (!valid_name(name)) return false;
  struct stat st{};
  const uint64_t size = ::stat(path_of(name).c_str(), &st) == 0 ? static_cast<uint64_t>(st.st_size) : 0;
  if (inject(FsOp::unlink, path_of(name), size) != 0) return false;
  if (::unlink(path_of(name).c_str()) != 0) return false;
  fsync_dir(dir_);
  return true;
}

uint64_t FileStorage::free_bytes() {
  if (FsFaultHook* h = hook_.load(std::memory_order_acquire)) {
    const int64_t f = h->free_bytes(dir_);
    if (f >= 0) return static_cast<uint64_t>(f);
  }
  struct statvfs s{};
  if (::statvfs(dir_.c_str(), &s) != 0) return 0;
  return static_cast<uint64_t>(s.f_bavail) * static_cast<uint64_t>(s.f_frsize);
}

}  // namespace amb::hal::linux_hw
