// CSV output (timeseries.csv, history.csv, comparison.csv, ...): a header row
// then one row per record, written through AtomicFile. Numbers are printed in
// the shortest form that reads back to the same double, and a NaN or infinity
// is refused (std::logic_error naming the column), because the interface
// promises that no NaN ever reaches an output file.
#pragma once

#include <concepts>
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "io/atomic_file.h"

namespace camdyn {

/// One CSV cell: a number (double or integer) or a text.
class CsvCell {
 public:
  CsvCell(double v) : value_(v) {}  // NOLINT(google-explicit-constructor): cells read like literals
  template <std::integral T>
  CsvCell(T v) : value_(static_cast<long long>(v)) {}      // NOLINT(google-explicit-constructor)
  CsvCell(std::string s) : value_(std::move(s)) {}         // NOLINT(google-explicit-constructor)
  CsvCell(const char* s) : value_(std::string(s)) {}       // NOLINT(google-explicit-constructor)
  CsvCell(std::string_view s) : value_(std::string(s)) {}  // NOLINT(google-explicit-constructor)

  const std::variant<double, long long, std::string>& value() const { return value_; }

 private:
  std::variant<double, long long, std::string> value_;
};

/// Shortest text that parses back to exactly `v` (std::to_chars); `v` must be finite.
std::string format_double(double v);

/// Writes `path` atomically: nothing appears under `path` until commit().
class CsvWriter {
 public:
  /// Throws std::runtime_error if the temporary file cannot be created.
  CsvWriter(std::filesystem::path path, std::vector<std::string> columns);

  /// A row of numbers, one per column. Throws std::logic_error on a wrong
  /// count or a non-finite value (naming the column and the row).
  void row(std::span<const double> values);
  void row(std::initializer_list<double> values) { row(std::span<const double>(values)); }
  /// A row of mixed cells; text is quoted when it needs to be (RFC 4180).
  void row(const std::vector<CsvCell>& cells);

  /// Flushes, fsyncs and renames over `path`. Without it the file is discarded.
  void commit() { file_.commit(); }

  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t rows_written() const { return rows_; }

 private:
  void check_count(std::size_t n) const;
  void check_finite(double v, std::size_t column) const;

  AtomicFile file_;
  std::vector<std::string> columns_;
  std::size_t rows_ = 0;
  std::string line_;  // reused so a long time series does not allocate per row
};

}  // namespace camdyn
