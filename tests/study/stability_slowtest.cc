// The stability sweep of studies/stability.json (360 stiff and extreme runs,
// several minutes: label `slow`). Every run ends ok with finite metrics and a
// closed energy balance, or failed with a stated reason; never a crash, a
// hang or NaN. "Closed": below 1e-2, where camdyn itself calls a balance
// open at any tolerance (plausibility.cc), and for the typical (median) run
// below its bound at the sweep's tolerance, 1e4 rtol = 1e-4. The balance is
// integrated independently of the state (docs/model.md §7), so it shows the
// integration error: the stiffest cases with friction mu = 1 (K = 1e13, a
// penetration at the level of atol near separation) reach 1e-3 at rtol 1e-8.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"

namespace {

TEST(StabilitySweep, EveryCaseIsOkOrFailsWithAReason) {
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / ("camdyn_stability_" + std::to_string(::getpid()));
  fs::create_directories(out);
  const camdyn::test::Outcome run = camdyn::test::run_camdyn(
      {"run", std::string(CAMDYN_SOURCE_DIR) + "/studies/stability.json", "--quiet", "--out", out.string()}, out);
  ASSERT_EQ(run.code, 0) << run.err;
  std::ifstream in(out / "comparison.csv");
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  std::vector<std::string> header;
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  auto column = [&](const std::string& name) {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return i;
    ADD_FAILURE() << "no column " << name;
    return size_t{0};
  };
  const size_t status_col = column("status"), error_col = column("error"), energy_col = column("energy_residual");
  int rows = 0, ok = 0;
  std::vector<double> residuals;
  while (std::getline(in, line)) {
    ++rows;
    EXPECT_EQ(line.find("nan"), std::string::npos) << line;
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) cells.push_back(cell);
    cells.resize(header.size());
    if (cells[status_col] == "ok") {
      ++ok;
      residuals.push_back(std::stod(cells[energy_col]));
      EXPECT_LT(residuals.back(), 1e-2) << line;
    } else {
      EXPECT_EQ(cells[status_col], "failed") << line;
      EXPECT_FALSE(cells[error_col].empty()) << line;
    }
  }
  EXPECT_GE(rows, 200);
  EXPECT_GT(ok, rows / 2);
  ASSERT_FALSE(residuals.empty());
  std::nth_element(residuals.begin(), residuals.begin() + residuals.size() / 2, residuals.end());
  EXPECT_LT(residuals[residuals.size() / 2], 1e4 * 1e-8);  // the sweep's rtol, the quickstart's
  fs::remove_all(out);
}

}  // namespace
