// The journal of a study with many independent runs (compare): one JSON line
// per finished run, appended and fsynced as each run finishes, so that a
// killed study loses no finished run and a rerun with the same output folder
// resumes where it stopped.
//
// File format (`<out>/journal.jsonl`, JSON Lines):
//   line 1:  {"camdyn_journal": 1, "study": "compare", "hash": "<16 hex>", "runs": M}
//   then:    one object per finished run, with at least "index" (0 ≤ index < M)
// The hash identifies the study (every run's resolved input); a journal of a
// different study is refused (InputError, exit 2) rather than mixed in. A
// last line without its newline (the process was killed while writing it) is
// cut off when the journal is opened; a line that does not parse is skipped
// with a warning, so that run is simply done again.
//
// Each record carries "checksum": the FNV-1a fingerprint of the study's hash
// and the record's compact JSON without it. A record that fails it (changed
// by hand or by a disk, copied from another study's journal) or has none (a
// journal of an earlier camdyn) is not trusted: a warning, and that run is
// done again. The journal must be a regular file: a FIFO, device or
// directory at its path is refused (InputError, exit 2).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>

#include "io/config.h"

namespace camdyn {

/// 64-bit FNV-1a hash of `text` as 16 lower-case hex digits (a fingerprint, not cryptographic).
std::string fingerprint(std::string_view text);

/// record[key] if it is a string, else `fallback`: a journal read back may
/// have been edited (its checksum recomputed, or its header changed by hand),
/// so a field is compared, never converted (tests/fuzz/journal_fuzzer.cc).
std::string string_or(const Json& record, const char* key, const std::string& fallback);

class Journal {
 public:
  /// Opens (or creates) the journal at `path` for a study `study` of `runs`
  /// runs with fingerprint `hash`, reading the runs already done. Throws
  /// InputError(path, "hash", ...) if it belongs to another study,
  /// InputError(path, "", ...) if it is not a regular file, and
  /// std::runtime_error if the file cannot be read or written.
  Journal(std::filesystem::path path, const std::string& study, std::string hash, std::size_t runs);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  /// Records of the runs already done when the journal was opened, by index
  /// (the first record of an index wins).
  const std::map<std::size_t, Json>& done() const { return done_; }

  /// Appends `record` (an object with an "index") as one line, then fsyncs.
  /// Not thread-safe: callers serialise. Throws std::runtime_error on I/O errors.
  void append(const Json& record);

  const std::filesystem::path& path() const { return path_; }

 private:
  void write_line(const std::string& line);

  std::filesystem::path path_;
  std::string hash_;  ///< the study's fingerprint, part of every record's checksum
  int fd_ = -1;
  std::map<std::size_t, Json> done_;
};

}  // namespace camdyn
