#include "io/csv_writer.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace camdyn {
namespace {

// The shortest round-trip form of a double needs at most 24 characters
// ("-2.2250738585072014e-308"); a little more is reserved per number.
constexpr std::size_t kMaxNumberChars = 32;
// Written to the file once this much has been formatted.
constexpr std::size_t kBufferBytes = std::size_t{1} << 20;

char* put_double(char* p, double v) { return std::to_chars(p, p + kMaxNumberChars, v).ptr; }

void append_text(std::string& out, std::string_view s) {
  const bool needs_quotes =
      s.find_first_of(",\"\r\n") != std::string_view::npos || (!s.empty() && (s.front() == ' ' || s.back() == ' '));
  if (!needs_quotes) {
    out.append(s);
    return;
  }
  out.push_back('"');
  for (char c : s) {
    if (c == '"') out.push_back('"');  // RFC 4180: a quote inside quotes is doubled
    out.push_back(c);
  }
  out.push_back('"');
}

}  // namespace

std::string format_double(double v) {
  char buf[kMaxNumberChars];
  return std::string(buf, put_double(buf, v));
}

CsvWriter::CsvWriter(std::filesystem::path path, std::vector<std::string> columns)
    : file_(std::move(path)), columns_(std::move(columns)) {
  if (columns_.empty()) throw std::logic_error("CSV " + file_.path().string() + ": no columns");
  std::string header;
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (i > 0) header.push_back(',');
    append_text(header, columns_[i]);
  }
  header.push_back('\n');
  std::memcpy(reserve(header.size()), header.data(), header.size());
  used_ += header.size();
}

char* CsvWriter::reserve(std::size_t n) {
  if (used_ + n > buffer_.size()) {
    flush();
    if (n > buffer_.size()) buffer_.resize(std::max(n, kBufferBytes));
  }
  return buffer_.data() + used_;
}

void CsvWriter::flush() {
  if (used_ == 0) return;
  // One write of the whole buffer: the stream passes a block larger than its
  // own buffer straight to the file.
  file_.stream().write(buffer_.data(), static_cast<std::streamsize>(used_));
  used_ = 0;
}

void CsvWriter::commit() {
  flush();
  file_.commit();
}

void CsvWriter::check_count(std::size_t n) const {
  if (n != columns_.size()) {
    throw std::logic_error("CSV " + file_.path().string() + " row " + std::to_string(rows_ + 1) + ": " +
                           std::to_string(n) + " cells for " + std::to_string(columns_.size()) + " columns");
  }
}

void CsvWriter::non_finite(double v, std::size_t column) const {
  throw std::logic_error("CSV " + file_.path().string() + ": non-finite value " + format_double(v) + " in column '" +
                         columns_[column] + "', row " + std::to_string(rows_ + 1));
}

void CsvWriter::row(std::span<const double> values) {
  check_count(values.size());
  char* const start = reserve(values.size() * (kMaxNumberChars + 1) + 1);
  char* p = start;
  for (std::size_t i = 0; i < values.size(); ++i) {
    // A refused row leaves nothing behind: used_ only moves once the row is complete.
    if (!std::isfinite(values[i])) non_finite(values[i], i);
    if (i > 0) *p++ = ',';
    p = put_double(p, values[i]);
  }
  *p++ = '\n';
  used_ += static_cast<std::size_t>(p - start);
  ++rows_;
}

void CsvWriter::rows_from_columns(std::span<const std::vector<double>* const> columns) {
  check_count(columns.size());
  const std::size_t n = columns.front()->size();
  for (std::size_t c = 1; c < columns.size(); ++c) {
    if (columns[c]->size() != n) {
      throw std::logic_error("CSV " + file_.path().string() + ": column '" + columns_[c] + "' has " +
                             std::to_string(columns[c]->size()) + " values, column '" + columns_[0] + "' " +
                             std::to_string(n));
    }
  }
  const std::size_t row_chars = columns.size() * (kMaxNumberChars + 1) + 1;
  for (std::size_t r = 0; r < n; ++r) {
    char* const start = reserve(row_chars);
    char* p = start;
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const double v = (*columns[c])[r];
      if (!std::isfinite(v)) non_finite(v, c);
      if (c > 0) *p++ = ',';
      p = put_double(p, v);
    }
    *p++ = '\n';
    used_ += static_cast<std::size_t>(p - start);
    ++rows_;
  }
}

void CsvWriter::row(const std::vector<CsvCell>& cells) {
  check_count(cells.size());
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) line.push_back(',');
    const auto& v = cells[i].value();
    if (const double* d = std::get_if<double>(&v)) {
      if (!std::isfinite(*d)) non_finite(*d, i);
      char buf[kMaxNumberChars];
      line.append(buf, put_double(buf, *d));
    } else if (const long long* n = std::get_if<long long>(&v)) {
      line.append(std::to_string(*n));
    } else {
      append_text(line, std::get<std::string>(v));
    }
  }
  line.push_back('\n');
  std::memcpy(reserve(line.size()), line.data(), line.size());
  used_ += line.size();
  ++rows_;
}

}  // namespace camdyn
