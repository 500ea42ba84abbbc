// Atomic output files: everything camdyn writes goes to a temporary name in the
// same directory and is renamed over the final name only once complete, so a
// killed run never leaves a truncated file that looks finished
// (docs/outputs-and-resume.md).
#pragma once

#include <filesystem>
#include <fstream>
#include <string_view>

namespace camdyn {

/// Writes `content` to `path` atomically (parent directories are created).
/// Throws std::runtime_error naming the path and the OS error.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// Removes the temporary files `<name>.tmp.<pid>` that killed runs left in
/// `dir` and its subfolders (one level): those whose process is gone. A run
/// that holds the folder's lock (output/output_folder.h) calls it at its start,
/// so a file the new run never writes again leaves no temporary behind either.
void remove_stale_temporary_files(const std::filesystem::path& dir);

/// A streaming atomic file. Writes go to `<path>.tmp.<pid>`; commit() flushes,
/// checks the stream, fsyncs and renames it over `path`. Destroying an
/// uncommitted AtomicFile removes the temporary file, leaving `path` untouched.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// The stream to write to; valid until commit().
  std::ostream& stream() { return out_; }
  void commit();

  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& temp_path() const { return temp_; }

 private:
  std::filesystem::path path_, temp_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace camdyn
