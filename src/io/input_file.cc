#include "io/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string_view>
#include <utility>

#include "common/errors.h"
#include "common/study_budget.h"

namespace camdyn {
namespace {

/// The kernel's pseudo file systems: their "files" are devices, process
/// memory or settings, never data (and /proc's report a size of 0).
bool in_pseudo_file_system(const std::string& file) {
  std::error_code ec;
  const std::string canonical = std::filesystem::weakly_canonical(std::filesystem::absolute(file), ec).string();
  if (ec) return false;
  for (const std::string_view root : {"/proc", "/sys", "/dev"})
    if (canonical == root || (canonical.starts_with(root) && canonical[root.size()] == '/')) return true;
  return false;
}

std::string what_it_is(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string megabytes(double bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", bytes / kBytesPerMb);
  return buf;
}

/// A descriptor closed on scope exit.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

/// Opens `file` for reading, checked; the descriptor and the file's size [bytes].
std::pair<int, std::uint64_t> open_checked(const std::string& file, const std::string& field, double max_bytes) {
  if (in_pseudo_file_system(file))
    throw InputError(file, field, "is in /proc, /sys or /dev: a data path must name a regular file");
  // O_NONBLOCK: opening a FIFO without a writer would otherwise wait for ever.
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) {
    const int err = errno;
    throw InputError(file, field,
                     std::string("cannot open (") + (err == ENOENT ? "no such file" : std::strerror(err)) + ")");
  }
  struct stat info {};
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode)) {
    const std::string what = what_it_is(info.st_mode);
    ::close(fd);
    throw InputError(file, field, "is " + what + ": a data path must name a regular file");
  }
  const auto size = static_cast<std::uint64_t>(info.st_size);
  if (static_cast<double>(size) > max_bytes) {
    ::close(fd);
    throw InputError(file, field,
                     "the file is " + megabytes(static_cast<double>(size)) + " MB, " +
                         (std::isfinite(max_bytes) && max_bytes == memory_budget_bytes()
                              ? memory_budget_text()
                              : "more than the " + megabytes(max_bytes) + " MB it may hold") +
                         ": it is not read");
  }
  return {fd, size};
}

}  // namespace

std::uint64_t check_input_file(const std::string& file, const std::string& field, double max_bytes) {
  const auto [fd, size] = open_checked(file, field, max_bytes);
  ::close(fd);
  return size;
}

std::uint64_t check_input_file(const std::string& file, const std::string& field) {
  return check_input_file(file, field, memory_budget_bytes());
}

std::string read_input_file(const std::string& file, const std::string& field, double max_bytes) {
  const auto [raw_fd, size] = open_checked(file, field, max_bytes);
  const Descriptor fd(raw_fd);
  std::string content;
  content.reserve(static_cast<std::size_t>(size));
  std::array<char, 1 << 16> buffer{};
  for (;;) {
    const ssize_t n = ::read(fd.get(), buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputError(file, field, std::string("cannot read: ") + std::strerror(errno));
    if (n == 0) break;
    if (static_cast<double>(content.size() + static_cast<std::size_t>(n)) > max_bytes)
      throw InputError(file, field, "the file grew past " + megabytes(max_bytes) + " MB while it was read");
    content.append(buffer.data(), static_cast<std::size_t>(n));
  }
  return content;
}

std::string read_input_file(const std::string& file, const std::string& field) {
  return read_input_file(file, field, memory_budget_bytes());
}

}  // namespace camdyn
