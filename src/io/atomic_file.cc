#include "io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>

#include "common/errors.h"

namespace camdyn {
namespace {

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& path, int err) {
  throw std::runtime_error(what + " '" + path.string() + "': " + std::strerror(err));
}

/// The output folders of OutputFolderRoot (absolute, normal), and their guard.
std::mutex g_roots_mutex;
std::vector<std::filesystem::path> g_roots;

std::filesystem::path absolute_normal(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(path, ec);
  return (ec ? path : absolute).lexically_normal();
}

/// What is at `path` instead of a regular file ("": a regular file, or nothing).
std::string what_is_in_the_way(const std::filesystem::path& path) {
  struct stat info {};
  if (::lstat(path.c_str(), &info) != 0 || S_ISREG(info.st_mode)) return "";
  if (S_ISLNK(info.st_mode)) return "a symbolic link";
  if (S_ISDIR(info.st_mode)) return "a folder";
  if (S_ISFIFO(info.st_mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(info.st_mode) || S_ISBLK(info.st_mode)) return "a device";
  return "not a regular file";
}

[[noreturn]] void refuse(const std::filesystem::path& path, const std::string& what) {
  throw InputError(path.string(), "",
                   "is " + what +
                       " where camdyn writes an output: camdyn never writes through one; remove it or choose "
                       "another --out");
}

/// The folders between a registered output folder and `path` (exclusive) are real folders.
void check_subfolders(const std::filesystem::path& path) {
  const std::filesystem::path target = absolute_normal(path);
  const std::lock_guard<std::mutex> lock(g_roots_mutex);
  for (const std::filesystem::path& root : g_roots) {
    const std::filesystem::path relative = target.lexically_relative(root);
    if (relative.empty() || *relative.begin() == "..") continue;
    std::filesystem::path folder = root;
    for (auto part = relative.begin(); part != relative.end() && std::next(part) != relative.end(); ++part) {
      folder /= *part;
      struct stat info {};
      if (::lstat(folder.c_str(), &info) == 0 && S_ISLNK(info.st_mode)) refuse(folder, "a symbolic link to a folder");
    }
  }
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

DescriptorBuffer::DescriptorBuffer() : buffer_(std::size_t{1} << 16) {
  setp(buffer_.data(), buffer_.data() + buffer_.size());
}

bool DescriptorBuffer::drain() {
  const char* from = pbase();
  while (from < pptr() && error_ == 0) {
    const ssize_t n = ::write(fd_, from, static_cast<std::size_t>(pptr() - from));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) error_ = n < 0 ? errno : EIO;
    if (n > 0) from += n;
  }
  setp(buffer_.data(), buffer_.data() + buffer_.size());
  return error_ == 0;
}

DescriptorBuffer::int_type DescriptorBuffer::overflow(int_type ch) {
  if (!drain()) return traits_type::eof();
  if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
  *pptr() = traits_type::to_char_type(ch);
  pbump(1);
  return ch;
}

int DescriptorBuffer::sync() { return drain() ? 0 : -1; }

void check_output_path(const std::filesystem::path& path) {
  check_subfolders(path);
  const std::string what = what_is_in_the_way(path);
  if (!what.empty()) refuse(path, what);
}

OutputFolderRoot::OutputFolderRoot(const std::filesystem::path& dir) : dir_(absolute_normal(dir)) {
  const std::lock_guard<std::mutex> lock(g_roots_mutex);
  g_roots.push_back(dir_);
}

OutputFolderRoot::~OutputFolderRoot() {
  const std::lock_guard<std::mutex> lock(g_roots_mutex);
  const auto it = std::find(g_roots.begin(), g_roots.end(), dir_);
  if (it != g_roots.end()) g_roots.erase(it);
}

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)) {
  if (path_.empty() || !path_.has_filename()) {
    throw std::runtime_error("cannot write '" + path_.string() + "': not a file name");
  }
  check_subfolders(path_);  // before creating anything through a planted link
  if (path_.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path_.parent_path(), ec);
    if (ec) {
      throw std::runtime_error("cannot create directory '" + path_.parent_path().string() + "': " + ec.message());
    }
  }
  check_output_path(path_);
  remove_stale_temporaries(path_);
  // Same directory as the target, so rename() stays on one file system and is atomic.
  temp_ = path_;
  temp_ += ".tmp." + std::to_string(::getpid());
  for (int attempt = 0; attempt < 2 && fd_ < 0; ++attempt) {
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd_ >= 0 || errno != EEXIST) break;
    // Ours from an earlier AtomicFile that could not remove it: a regular file is replaced, anything else refused.
    const std::string what = what_is_in_the_way(temp_);
    if (!what.empty()) refuse(temp_, what);
    ::unlink(temp_.c_str());
  }
  if (fd_ < 0) fail("cannot create", temp_, errno);
  buffer_.attach(fd_);
  out_.rdbuf(&buffer_);
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_) ::unlink(temp_.c_str());  // best effort: a destructor must not throw
}

void AtomicFile::commit() {
  if (committed_) throw std::logic_error("AtomicFile::commit called twice for " + path_.string());
  out_.flush();
  // On failure the destructor removes the temporary file (committed_ stays false).
  if (!out_ || buffer_.error() != 0) fail("cannot write", temp_, buffer_.error() != 0 ? buffer_.error() : EIO);
  // Without the fsync a crash after rename could leave an empty file under the final name.
  if (::fsync(fd_) != 0) fail("cannot fsync", temp_, errno);
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0) fail("cannot write", temp_, errno);
  check_output_path(path_);  // planted while we wrote: refused, not replaced
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
