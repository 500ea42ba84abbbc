// Data paths are what they claim (docs/config.md, "Data files"): every file
// camdyn reads because a config or a command line names it (a config and
// what it extends, a lift table, a contour, a measured record, a compare
// case config, a journal) is opened here. It must be a regular file (a
// symbolic link to one is fine) outside /proc, /sys and /dev, and no larger
// than the memory budget (--max-memory, common/study_budget.h); a device, a
// FIFO, a directory or a file too large is refused, naming the file and the
// field that named it, before anything is read.
#pragma once

#include <cstdint>
#include <string>

namespace camdyn {

/// Checks that `file` can be read as a data file: a regular file outside
/// /proc, /sys and /dev of at most `max_bytes`. Returns its size [bytes].
/// Throws InputError(file, field, reason) otherwise, or when it cannot be
/// opened. Opening never blocks (a FIFO is refused, not waited for).
std::uint64_t check_input_file(const std::string& file, const std::string& field, double max_bytes);
/// The same against the memory budget (memory_budget_bytes()).
std::uint64_t check_input_file(const std::string& file, const std::string& field = "");

/// Reads `file` whole, after check_input_file(file, field, max_bytes). Stops
/// at `max_bytes` even if the file grows while it is read (InputError).
std::string read_input_file(const std::string& file, const std::string& field, double max_bytes);
/// The same against the memory budget (memory_budget_bytes()).
std::string read_input_file(const std::string& file, const std::string& field = "");

}  // namespace camdyn
