// Atomic output files: everything camdyn writes goes to a temporary name in the
// same directory and is renamed over the final name only once complete, so a
// killed run never leaves a truncated file that looks finished
// (docs/outputs-and-resume.md).
#pragma once

#include <filesystem>
#include <ostream>
#include <streambuf>
#include <string_view>
#include <vector>

namespace camdyn {

/// Outputs cannot be redirected (docs/outputs-and-resume.md, "What may be in
/// the output folder"): throws InputError naming `path` when something other
/// than a regular file is where camdyn writes it (a symbolic link, a FIFO, a
/// device, a folder), or when a folder between a locked output folder (see
/// OutputFolderRoot) and `path` is a symbolic link. A missing `path` is fine.
void check_output_path(const std::filesystem::path& path);

/// Registers `dir` as an output folder for the object's lifetime: below it,
/// check_output_path refuses subfolders that are symbolic links (an `orbit/`
/// pointing elsewhere would send outputs outside --out). The folder itself
/// may be a symbolic link: the user named it. OutputLock holds one.
class OutputFolderRoot {
 public:
  explicit OutputFolderRoot(const std::filesystem::path& dir);
  ~OutputFolderRoot();
  OutputFolderRoot(const OutputFolderRoot&) = delete;
  OutputFolderRoot& operator=(const OutputFolderRoot&) = delete;

 private:
  std::filesystem::path dir_;
};

/// Writes `content` to `path` atomically (parent directories are created).
/// Throws std::runtime_error naming the path and the OS error.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// Removes the temporary files `<name>.tmp.<pid>` that killed runs left in
/// `dir` and its subfolders (one level): those whose process is gone. A run
/// that holds the folder's lock (output/output_folder.h) calls it at its start,
/// so a file the new run never writes again leaves no temporary behind either.
void remove_stale_temporary_files(const std::filesystem::path& dir);

/// A stream buffer that writes to a file descriptor (which it does not own).
class DescriptorBuffer : public std::streambuf {
 public:
  DescriptorBuffer();
  /// Writes from now on go to `fd`.
  void attach(int fd) { fd_ = fd; }
  /// The errno of the first failed write (0: none).
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override;
  int sync() override;

 private:
  bool drain();
  int fd_ = -1;
  int error_ = 0;
  std::vector<char> buffer_;
};

/// A streaming atomic file. Writes go to `<path>.tmp.<pid>`, created new
/// (O_EXCL | O_NOFOLLOW: never through a link planted there); commit()
/// flushes, checks the stream, fsyncs and renames it over `path`. Destroying
/// an uncommitted AtomicFile removes the temporary file, leaving `path`
/// untouched. Throws InputError (check_output_path) when `path` or the
/// temporary name holds something other than a regular file.
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
  int fd_ = -1;
  DescriptorBuffer buffer_;
  std::ostream out_{nullptr};
  bool committed_ = false;
};

}  // namespace camdyn
