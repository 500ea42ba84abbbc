// comparison.csv / comparison.json and the summary line of a compare study.
#include "study/compare_output.h"

#include <camdyn/version.h>

#include <cmath>
#include <cstdio>

#include "io/csv_writer.h"
#include "io/json_writer.h"

namespace camdyn {

std::string cell_text(const Json& value) { return value.is_string() ? value.get<std::string>() : value.dump(); }

namespace {

/// The CSV cells and the JSON row of run `i`.
Json write_row(const CompareResult& result, std::size_t i, CsvWriter& csv) {
  const std::vector<std::string>& metric_names = compare_metric_names();
  const ComparePoint& p = result.points[i];
  const CompareOutcome& o = result.outcomes[i];
  std::vector<CsvCell> cells = {CsvCell(result.case_name(i))};
  Json row{{"case", result.case_name(i)}};
  for (std::size_t k = 0; k < result.keys.size(); ++k) {
    cells.push_back(CsvCell(cell_text(p.values[k])));
    row[result.keys[k]] = p.values[k];
  }
  Json metrics_json = Json::object();
  for (std::size_t m = 0; m < metric_names.size(); ++m) {
    const bool have = o.ok && std::isfinite(o.metrics[m]);
    cells.push_back(have ? CsvCell(o.metrics[m]) : CsvCell(""));
    metrics_json[metric_names[m]] = have ? Json(o.metrics[m]) : Json(nullptr);
  }
  cells.emplace_back(o.ok ? "ok" : "failed");
  cells.emplace_back(o.error);
  cells.emplace_back(o.run_time_s);
  csv.row(cells);
  row["metrics"] = metrics_json;
  row["status"] = o.ok ? "ok" : "failed";
  row["error"] = o.error;
  row["run_time_s"] = o.run_time_s;
  return row;
}

}  // namespace

void write_comparison(const CompareResult& result, const std::filesystem::path& out_dir) {
  std::vector<std::string> columns = {"case"};
  columns.insert(columns.end(), result.keys.begin(), result.keys.end());
  for (const std::string& m : compare_metric_names()) columns.push_back(m);
  columns.insert(columns.end(), {"status", "error", "run_time_s"});
  CsvWriter csv(out_dir / "comparison.csv", columns);
  Json rows = Json::array();
  for (std::size_t i = 0; i < result.points.size(); ++i) rows.push_back(write_row(result, i, csv));
  csv.commit();
  write_json_atomic(out_dir / "comparison.json", Json{{"name", result.name},
                                                      {"study", "compare"},
                                                      {"camdyn_version", CAMDYN_VERSION},
                                                      {"runs", result.points.size()},
                                                      {"failed", result.failed},
                                                      {"resumed_runs", result.resumed},
                                                      {"run_time_s", result.wall_time_s},
                                                      {"results", rows}});
}

void print_compare_summary(const CompareResult& result, const std::filesystem::path& out_dir) {
  const std::string resumed_text =
      result.resumed > 0 ? std::string(" (") + std::to_string(result.resumed) + " resumed)" : "";
  std::printf("%s: %zu runs, %zu failed, %.3g s%s\n  comparison.csv and report: %s\n", result.name.c_str(),
              result.points.size(), result.failed, result.wall_time_s, resumed_text.c_str(),
              std::filesystem::absolute(out_dir / "report.html").lexically_normal().c_str());
}

}  // namespace camdyn
