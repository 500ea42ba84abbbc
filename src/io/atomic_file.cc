#include "io/atomic_file.h"

#include <fcntl.h>
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
  const int err = errno != 0 ? errno : EIO;
  out_.close();
  // On failure the destructor removes the temporary file (committed_ stays false).
  if (!ok || out_.fail()) fail("cannot write", temp_, err);
  fsync_path(temp_);
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
    fail("cannot rename temporary file to", path_, errno);
  }
  committed_ = true;
}

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  AtomicFile file(path);
  file.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  file.commit();
}

}  // namespace camdyn
