#include "io/csv_writer.h"

#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>

namespace camdyn {
namespace {

void append_double(std::string& out, double v) {
  std::array<char, 32> buf{};  // the shortest round-trip form of a double needs at most 24
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  out.append(buf.data(), res.ptr);
}

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
  std::string s;
  append_double(s, v);
  return s;
}

CsvWriter::CsvWriter(std::filesystem::path path, std::vector<std::string> columns)
    : file_(std::move(path)), columns_(std::move(columns)) {
  if (columns_.empty()) throw std::logic_error("CSV " + file_.path().string() + ": no columns");
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (i > 0) line_.push_back(',');
    append_text(line_, columns_[i]);
  }
  line_.push_back('\n');
  file_.stream() << line_;
}

void CsvWriter::check_count(std::size_t n) const {
  if (n != columns_.size()) {
    throw std::logic_error("CSV " + file_.path().string() + " row " + std::to_string(rows_ + 1) + ": " +
                           std::to_string(n) + " cells for " + std::to_string(columns_.size()) + " columns");
  }
}

void CsvWriter::check_finite(double v, std::size_t column) const {
  if (!std::isfinite(v)) {
    throw std::logic_error("CSV " + file_.path().string() + ": non-finite value " + format_double(v) + " in column '" +
                           columns_[column] + "', row " + std::to_string(rows_ + 1));
  }
}

void CsvWriter::row(std::span<const double> values) {
  check_count(values.size());
  line_.clear();
  for (std::size_t i = 0; i < values.size(); ++i) {
    check_finite(values[i], i);
    if (i > 0) line_.push_back(',');
    append_double(line_, values[i]);
  }
  line_.push_back('\n');
  file_.stream() << line_;
  ++rows_;
}

void CsvWriter::row(const std::vector<CsvCell>& cells) {
  check_count(cells.size());
  line_.clear();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) line_.push_back(',');
    const auto& v = cells[i].value();
    if (const double* d = std::get_if<double>(&v)) {
      check_finite(*d, i);
      append_double(line_, *d);
    } else if (const long long* n = std::get_if<long long>(&v)) {
      line_.append(std::to_string(*n));
    } else {
      append_text(line_, std::get<std::string>(v));
    }
  }
  line_.push_back('\n');
  file_.stream() << line_;
  ++rows_;
}

}  // namespace camdyn
