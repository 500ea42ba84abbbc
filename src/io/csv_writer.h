// CSV output (timeseries.csv, history.csv, comparison.csv, ...): a header row
// then one row per record, written through AtomicFile. Numbers are printed in
// the shortest form that reads back to the same double (std::to_chars), and a
// NaN or infinity is refused (std::logic_error naming the column), because
// the interface promises that no NaN ever reaches an output file. Rows are
// formatted straight into a buffer of about a megabyte that goes to the file
// in one write when full, so a long time series costs little more than its
// number formatting and the disk.
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
  /// Row i holds element i of every column, for i below the columns' common
  /// length (one column per CSV column, in order; throws std::logic_error on a
  /// wrong count, unequal lengths or a non-finite value). The same text as
  /// row() for each i, without gathering the rows first.
  void rows_from_columns(std::span<const std::vector<double>* const> columns);

  /// Flushes, fsyncs and renames over `path`. Without it the file is discarded.
  void commit();

  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t rows_written() const { return rows_; }

 private:
  void check_count(std::size_t n) const;
  [[noreturn]] void non_finite(double v, std::size_t column) const;
  /// Room for `n` more characters at the end of the buffer (writes it out first if full).
  char* reserve(std::size_t n);
  void flush();

  AtomicFile file_;
  std::vector<std::string> columns_;
  std::size_t rows_ = 0;
  std::vector<char> buffer_;  // buffer_[0, used_) is waiting for the file
  std::size_t used_ = 0;
};

}  // namespace camdyn
