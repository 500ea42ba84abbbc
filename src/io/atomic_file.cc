#include "io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

namespace camdyn {
namespace {

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& path, int err) {
  throw std::runtime_error(what + " '" + path.string() + "': " + std::strerror(err));
}

// std::ofstream cannot fsync; reopen the file by name. Without the fsync a
// crash after rename could leave an empty file under the final name.
void fsync_path(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail("cannot open for fsync", path, errno);
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) fail("cannot fsync", path, err);
}

// A failed write without errno (the stream does not always set it): a full
// file system is the usual cause, and is worth naming.
int write_error(const std::filesystem::path& path) {
  if (errno != 0) return errno;
  std::error_code ec;
  const std::filesystem::space_info space =
      std::filesystem::space(path.parent_path().empty() ? "." : path.parent_path(), ec);
  return !ec && space.available == 0 ? ENOSPC : EIO;
}

// `name` is `<prefix><pid>` (prefix ending in ".tmp.") of a process that is gone.
bool is_stale_temporary(const std::string& name, const std::string& prefix) {
  if (!name.starts_with(prefix)) return false;
  const std::string digits = name.substr(prefix.size());
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 9) return false;
  const auto pid = static_cast<pid_t>(std::stol(digits));
  return pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;  // alive, or not ours to judge: kept
}

// Temporary files `<name>.tmp.<pid>` of a run that was killed before it
// committed (its process is gone) are removed when the file is next written.
void remove_stale_temporaries(const std::filesystem::path& path) {
  const std::string prefix = path.filename().string() + ".tmp.";
  const std::filesystem::path dir = path.parent_path().empty() ? "." : path.parent_path();
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
    if (is_stale_temporary(entry.path().filename().string(), prefix)) std::filesystem::remove(entry.path(), ec);
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)) {
  if (path_.empty() || !path_.has_filename()) {
    throw std::runtime_error("cannot write '" + path_.string() + "': not a file name");
  }
  if (path_.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path_.parent_path(), ec);
    if (ec) {
      throw std::runtime_error("cannot create directory '" + path_.parent_path().string() + "': " + ec.message());
    }
  }
  remove_stale_temporaries(path_);
  // Same directory as the target, so rename() stays on one file system and is atomic.
  temp_ = path_;
  temp_ += ".tmp." + std::to_string(::getpid());
  errno = 0;
  out_.open(temp_, std::ios::binary | std::ios::trunc);
  if (!out_) fail("cannot create", temp_, errno != 0 ? errno : EIO);
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::error_code ec;  // best effort: a destructor must not throw
    std::filesystem::remove(temp_, ec);
  }
}

void AtomicFile::commit() {
  if (committed_) throw std::logic_error("AtomicFile::commit called twice for " + path_.string());
  errno = 0;
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  const int err = ok ? 0 : write_error(temp_);
  out_.close();
  // On failure the destructor removes the temporary file (committed_ stays false).
  if (!ok || out_.fail()) fail("cannot write", temp_, err != 0 ? err : write_error(temp_));
  fsync_path(temp_);
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
    fail("cannot rename temporary file to", path_, errno);
  }
  committed_ = true;
}

void remove_stale_temporary_files(const std::filesystem::path& dir) {
  std::error_code ec;
  auto it = std::filesystem::recursive_directory_iterator(dir, ec);
  for (; !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    if (it.depth() >= 1) it.disable_recursion_pending();  // the folder and its subfolders, no deeper
    const std::string name = it->path().filename().string();
    const std::size_t tmp = name.rfind(".tmp.");
    std::error_code ignored;  // best effort, like the removal on the next write
    if (tmp == std::string::npos || !it->is_regular_file(ignored)) continue;
    if (is_stale_temporary(name, name.substr(0, tmp + 5))) std::filesystem::remove(it->path(), ignored);
  }
}

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  AtomicFile file(path);
  file.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  file.commit();
}

}  // namespace camdyn
