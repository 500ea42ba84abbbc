#include "output/output_folder.h"

#include <camdyn/version.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "common/errors.h"
#include "io/atomic_file.h"
#include "io/config.h"
#include "io/json_writer.h"

namespace camdyn {

namespace {

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& path, int err) {
  throw std::runtime_error(what + " '" + path.string() + "': " + std::strerror(err));
}

/// The process id the holder wrote into the lock file ("" if it has not yet).
std::string holder_of(int fd) {
  char buf[32] = {};
  const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  if (n <= 0) return "";
  std::string pid(buf, static_cast<std::size_t>(n));
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid.find_first_not_of("0123456789") == std::string::npos ? pid : "";
}

/// `fd` (locked) is still the file at `path`: a holder that was releasing
/// may have unlinked it between our open() and flock().
bool same_file(int fd, const std::filesystem::path& path) {
  struct stat by_fd {};
  struct stat by_name {};
  if (::fstat(fd, &by_fd) != 0 || ::lstat(path.c_str(), &by_name) != 0) return false;
  return by_fd.st_dev == by_name.st_dev && by_fd.st_ino == by_name.st_ino;
}

/// Opens the lock file, never through a link planted in its place (it would
/// truncate the file the link names): a regular file of one name only.
int open_lock_file(const std::filesystem::path& file) {
  const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0644);
  if (fd < 0 && errno == ELOOP) check_output_path(file);  // names the symbolic link (exit 2)
  if (fd < 0) fail("cannot create the lock file", file, errno);
  struct stat info {};
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode) || info.st_nlink > 1) {
    ::close(fd);
    check_output_path(file);  // a FIFO, a device: named (exit 2)
    throw InputError(file.string(), "",
                     "has another name (a hard link) or is not a regular file: camdyn never writes through one; "
                     "remove it or choose another --out");
  }
  return fd;
}

}  // namespace

OutputLock::OutputLock(std::filesystem::path dir) : dir_(std::move(dir)), file_(dir_ / kLockFile) {
  std::error_code ec;
  created_dir_ = !std::filesystem::exists(dir_, ec);
  std::filesystem::create_directories(dir_, ec);
  // A file in the way, no permission: the --out the user gave cannot be used (exit 2).
  if (ec)
    throw InputError(dir_.string(), "", "cannot create the output folder: " + ec.message() + "; choose another --out");
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    const int fd = open_lock_file(file_);
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      if (err != EWOULDBLOCK) {
        ::close(fd);
        std::cerr << "camdyn: warning: cannot lock the output folder " << dir_.string() << " (" << std::strerror(err)
                  << "); another run into it at the same time would mix its files with this one's\n";
        return;
      }
      const std::string pid = holder_of(fd);
      ::close(fd);
      throw InputError(dir_.string(), "",
                       "the output folder is in use by " +
                           (pid.empty() ? std::string("another camdyn process") : "camdyn process " + pid) +
                           " (it holds " + file_.string() + "); wait for that run to finish or choose another --out");
    }
    if (same_file(fd, file_)) {
      fd_ = fd;
    } else {
      ::close(fd);  // unlinked by its last holder: lock the new one
    }
  }
  if (fd_ < 0)
    throw std::runtime_error("cannot lock the output folder '" + dir_.string() + "': the lock file keeps changing");
  root_ = std::make_unique<OutputFolderRoot>(dir_);  // its subfolders must be real folders
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    const int err = errno;
    ::close(fd_);
    fail("cannot write the lock file", file_, err);
  }
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  // Unlink while still holding the lock, so the next run locks a fresh file.
  ::unlink(file_.c_str());
  ::close(fd_);
  std::error_code ec;
  if (created_dir_ && std::filesystem::is_empty(dir_, ec) && !ec) std::filesystem::remove(dir_, ec);
}

void remove_completion_marker(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::remove(dir / kCompleteFile, ec);
  if (ec) fail("cannot remove the completion marker", dir / kCompleteFile, ec.value());
}

void write_completion_marker(const std::filesystem::path& dir, const std::string& study,
                             const std::string& main_output) {
  Json marker = Json::object();
  marker["complete"] = true;
  marker["study"] = study;
  marker["main_output"] = main_output;
  marker["camdyn_version"] = CAMDYN_VERSION;
  write_json_atomic(dir / kCompleteFile, marker);
}

}  // namespace camdyn
