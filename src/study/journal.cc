#include "study/journal.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <iterator>
#include <stdexcept>
#include <utility>

#include "common/errors.h"
#include "io/atomic_file.h"
#include "io/input_file.h"

namespace camdyn {

namespace {

constexpr int kJournalVersion = 1;

std::runtime_error io_error(const std::string& what, const std::filesystem::path& path) {
  return std::runtime_error(what + " " + path.string() + ": " + std::strerror(errno));
}

// Makes the journal's directory entry durable (after creating the file).
void sync_directory(const std::filesystem::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // best effort: the data itself is fsynced
  (void)::fsync(fd);
  ::close(fd);
}

/// The key of a record's checksum.
constexpr const char* kChecksumKey = "checksum";

/// A record's text as journaled: compact, invalid UTF-8 replaced (say, in an
/// error message) so that the record is always writable.
std::string record_text(const Json& record) { return record.dump(-1, ' ', false, Json::error_handler_t::replace); }

/// The checksum of `record` (without its "checksum") in the journal of the
/// study with fingerprint `hash`: FNV-1a of both, so a record changed by hand
/// or by a disk, or copied from another study's journal, fails it.
std::string record_checksum(Json record, const std::string& hash) {
  record.erase(kChecksumKey);
  return fingerprint(hash + "\n" + record_text(record));
}

/// Refuses a journal that is not a regular file (a FIFO would block the
/// read, a device never end, a directory fail with a raw error): exit 2.
void require_regular_file(const std::filesystem::path& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (error || status.type() == std::filesystem::file_type::not_found ||
      status.type() == std::filesystem::file_type::regular)
    return;
  const char* kind =
      status.type() == std::filesystem::file_type::directory ? "a directory"
      : status.type() == std::filesystem::file_type::fifo    ? "a FIFO (named pipe)"
      : status.type() == std::filesystem::file_type::character || status.type() == std::filesystem::file_type::block
          ? "a device"
          : "not a regular file";
  throw InputError(path.string(), "",
                   std::string("the study's journal is ") + kind +
                       ", not a regular file: remove it or choose another --out (camdyn writes its journal there)");
}

}  // namespace

std::string fingerprint(std::string_view text) {
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a offset basis
  for (const char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;  // FNV prime
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string string_or(const Json& record, const char* key, const std::string& fallback) {
  const auto it = record.find(key);
  return it != record.end() && it->is_string() ? it->get<std::string>() : fallback;
}

Journal::Journal(std::filesystem::path path, const std::string& study, std::string hash, std::size_t runs)
    : path_(std::move(path)), hash_(std::move(hash)) {
  require_regular_file(path_);
  // An output and an input: never through a planted link (io/atomic_file.h), within the memory budget.
  check_output_path(path_);
  std::string content;
  const bool existed = std::filesystem::exists(path_);
  if (existed) content = read_input_file(path_.string());
  // Only newline-terminated lines are complete; the rest was cut by a kill.
  const std::size_t complete = content.rfind('\n') == std::string::npos ? 0 : content.rfind('\n') + 1;
  bool fresh = complete == 0;
  for (std::size_t begin = 0, line_no = 1; begin < complete; ++line_no) {
    const std::size_t end = content.find('\n', begin);
    const std::string line = content.substr(begin, end - begin);
    begin = end + 1;
    const Json j = Json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (line_no == 1) {
      if (j.is_discarded() || !j.is_object() || !j.contains("camdyn_journal"))
        throw InputError(path_.string(), "", "is not a camdyn journal; delete it or choose another --out");
      // A header edited by hand may hold any type: compare what is there, never convert it.
      const bool runs_match =
          j.contains("runs") && j["runs"].is_number_unsigned() && j["runs"].get<std::size_t>() == runs;
      const bool same = string_or(j, "study", "?") == study && string_or(j, "hash", "?") == hash_ && runs_match;
      if (!same)
        throw InputError(path_.string(), "hash",
                         "this output folder holds the journal of a different " + study +
                             " study (the study, a case config or an override changed since; journal "
                             "fingerprint " +
                             string_or(j, "hash", "?") + ", now " + hash_ +
                             "): delete the journal or choose another --out to start afresh");
      continue;
    }
    const bool valid = !j.is_discarded() && j.is_object() && j.contains("index") && j["index"].is_number_unsigned() &&
                       j["index"].get<std::size_t>() < runs;
    if (!valid) {
      std::cerr << "camdyn: warning: " << path_.string() << " line " << line_no
                << " is not a run record; that run is done again\n";
      continue;
    }
    if (!j.contains(kChecksumKey) || !j[kChecksumKey].is_string()) {
      std::cerr << "camdyn: warning: " << path_.string() << " line " << line_no
                << " has no checksum (a journal of an earlier camdyn): unverified, so that run is done again\n";
      continue;
    }
    if (j[kChecksumKey].get<std::string>() != record_checksum(j, hash_)) {
      std::cerr << "camdyn: warning: " << path_.string() << " line " << line_no
                << " fails its checksum (the record was changed after it was written): that run is done again\n";
      continue;
    }
    done_.emplace(j["index"].get<std::size_t>(), j);
  }

  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0644);
  if (fd_ < 0) throw io_error("cannot open", path_);
  // Cut the partial last line (or everything, for a fresh start) so the next
  // line starts at a line boundary.
  if (complete != content.size() || fresh) {
    if (::ftruncate(fd_, static_cast<off_t>(fresh ? 0 : complete)) != 0) {
      const auto error = io_error("cannot truncate", path_);
      ::close(fd_);
      throw error;
    }
  }
  if (fresh) {
    Json header = Json::object();
    header["camdyn_journal"] = kJournalVersion;
    header["study"] = study;
    header["hash"] = hash_;
    header["runs"] = runs;
    write_line(header.dump());
  }
  if (!existed) sync_directory(path_.parent_path().empty() ? "." : path_.parent_path());
}

Journal::~Journal() {
  if (fd_ >= 0) ::close(fd_);
}

void Journal::append(const Json& record) {
  Json checked = record;
  checked.erase(kChecksumKey);
  // The checksum of the text as written: invalid UTF-8 already replaced, as a re-read sees it.
  checked = Json::parse(record_text(checked));
  checked[kChecksumKey] = record_checksum(checked, hash_);
  write_line(record_text(checked));
}

void Journal::write_line(const std::string& text) {
  const std::string line = text + "\n";
  std::size_t written = 0;
  while (written < line.size()) {
    const ssize_t n = ::write(fd_, line.data() + written, line.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw io_error("cannot write", path_);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd_) != 0) throw io_error("cannot fsync", path_);
}

}  // namespace camdyn
