// A small reader for numeric CSV files (lift tables, measured signals): a
// header row naming the columns, then one row per sample. Only the requested
// columns have to be numeric. Lines starting with '#' and blank lines are
// skipped. Every problem is an InputError naming the file and the CSV line or
// column, so a user can fix the data without reading code.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace camdyn {

/// The requested columns of a CSV file.
struct CsvColumns {
  std::string file;                         ///< as given to read_csv
  std::vector<std::string> names;           ///< requested column names, in request order
  std::vector<std::vector<double>> values;  ///< values[k]: column names[k], one entry per data row
  std::vector<int> lines;                   ///< 1-based file line of each data row (for error messages)

  /// The values of a requested column; throws std::out_of_range for a name not requested.
  const std::vector<double>& operator[](const std::string& name) const;
  std::size_t rows() const { return lines.size(); }
};

/// Reads `columns` from the CSV file `file` (comma-separated, first non-comment
/// line is the header, optional double quotes around header names). Throws
/// InputError(file, where, reason) for: a file that cannot be opened, a
/// missing header, a requested column not in the header or named twice
/// ("column NAME"), a row with the wrong number of fields, an empty,
/// non-numeric, NaN or infinite value ("line N"), or fewer than `min_rows`
/// data rows.
/// The file itself must be a regular file within the memory budget
/// (io/input_file.h); when it is not, the InputError names `config_field`, the
/// dotted config path that gave the file.
CsvColumns read_csv(const std::string& file, const std::vector<std::string>& columns, std::size_t min_rows = 1,
                    const std::string& config_field = "");

}  // namespace camdyn
