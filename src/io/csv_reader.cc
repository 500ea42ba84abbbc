#include "io/csv_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include "common/errors.h"
#include "common/study_budget.h"
#include "io/input_file.h"

namespace camdyn {

namespace {

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t");
  return s.substr(first, last - first + 1);
}

/// Trimmed fields of one line; a pair of surrounding double quotes is removed.
/// (No embedded commas or escaped quotes: these files are numeric.)
std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    std::string_view field = trim(line.substr(begin, comma - begin));
    if (field.size() >= 2 && field.front() == '"' && field.back() == '"')
      field = trim(field.substr(1, field.size() - 2));
    fields.push_back(field);
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return fields;
}

/// Parses the whole field as a double; false if it is not a number.
bool parse_double(std::string_view field, double& value) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);  // from_chars rejects '+'
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, value);
  return ec == std::errc() && ptr == end;
}

/// Memory of what is built from one data row (a table's spline piece, a record's residual) [bytes].
constexpr double kBuiltBytesPerRow = 128.0;

/// The error for a file with more data rows than the memory budget holds.
InputError too_many_rows(const std::string& file, const std::string& where, std::size_t rows, double row_bytes) {
  const double mb = static_cast<double>(rows) * row_bytes / kBytesPerMb;
  return InputError(file, where,
                    "the file has more than " + std::to_string(rows) + " data rows, which would need about " +
                        std::to_string(static_cast<long long>(std::ceil(mb))) + " MB: " + memory_budget_text() +
                        ": decimate the data (keep every k-th row) or raise --max-memory");
}

std::string join(const std::vector<std::string_view>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + std::string(n);
  return out;
}

}  // namespace

const std::vector<double>& CsvColumns::operator[](const std::string& name) const {
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == name) return values[k];
  throw std::out_of_range("column '" + name + "' was not read from " + file);
}

CsvColumns read_csv(const std::string& file, const std::vector<std::string>& columns, std::size_t min_rows,
                    const std::string& config_field) {
  // A regular file within the memory budget, or refused before it is read (io/input_file.h).
  const std::string text = read_input_file(file, config_field);

  CsvColumns out;
  out.file = file;
  out.names = columns;
  out.values.resize(columns.size());
  std::vector<std::size_t> index(columns.size());  // field index of each requested column
  std::size_t header_fields = 0;
  bool have_header = false;

  // What each data row will hold in memory [bytes]: its values and line
  // number (twice, for the vectors' growth), and what is built from it.
  const double row_bytes = 2.0 * static_cast<double>(columns.size() * sizeof(double) + sizeof(int)) + kBuiltBytesPerRow;
  const double max_rows = memory_budget_bytes() / row_bytes;

  int line_no = 0;
  for (std::size_t begin = 0; begin < text.size();) {
    const std::size_t newline = std::min(text.find('\n', begin), text.size());
    std::string_view line = std::string_view(text).substr(begin, newline - begin);
    begin = newline + 1;
    ++line_no;
    if (line_no == 1 && line.starts_with("\xEF\xBB\xBF")) line.remove_prefix(3);  // UTF-8 BOM
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    line = trim(line);
    if (line.empty() || line.front() == '#') continue;
    const std::vector<std::string_view> fields = split_fields(line);

    if (!have_header) {
      have_header = true;
      header_fields = fields.size();
      for (std::size_t k = 0; k < columns.size(); ++k) {
        std::size_t found = 0, count = 0;
        for (std::size_t f = 0; f < fields.size(); ++f) {
          if (fields[f] == columns[k]) {
            found = f;
            ++count;
          }
        }
        if (count == 0)
          throw InputError(file, "column " + columns[k],
                           "not in the header (line " + std::to_string(line_no) + " has: " + join(fields) + ")");
        if (count > 1) throw InputError(file, "column " + columns[k], "appears more than once in the header");
        index[k] = found;
      }
      continue;
    }

    const std::string where = "line " + std::to_string(line_no);
    if (static_cast<double>(out.rows()) >= max_rows) throw too_many_rows(file, where, out.rows(), row_bytes);
    if (fields.size() != header_fields)
      throw InputError(
          file, where,
          "has " + std::to_string(fields.size()) + " fields, the header has " + std::to_string(header_fields));
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const std::string_view field = fields[index[k]];
      double value = 0.0;
      if (field.empty()) throw InputError(file, where, "column " + columns[k] + " is empty");
      if (!parse_double(field, value))
        throw InputError(file, where, "column " + columns[k] + ": '" + std::string(field) + "' is not a number");
      if (!std::isfinite(value))
        throw InputError(file, where,
                         "column " + columns[k] + ": '" + std::string(field) + "' is not finite (NaN or infinity)");
      out.values[k].push_back(value);
    }
    out.lines.push_back(line_no);
  }
  if (!have_header) throw InputError(file, "", "no header row (the file is empty or all comments)");
  if (out.rows() < min_rows)
    throw InputError(
        file, "",
        "has " + std::to_string(out.rows()) + " data rows, at least " + std::to_string(min_rows) + " are needed");
  return out;
}

}  // namespace camdyn
