// studies/work_precision.json (label `slow`, about a minute on 2 cores): the
// CSV shows, for each adaptive method, errors spanning at least four decades.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"

namespace {

TEST(WorkPrecisionStudy, EveryAdaptiveMethodSpansFourDecadesOfError) {
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / ("camdyn_wp_" + std::to_string(::getpid()));
  fs::create_directories(out);
  const camdyn::test::Outcome run = camdyn::test::run_camdyn(
      {"run", std::string(CAMDYN_SOURCE_DIR) + "/studies/work_precision.json", "--quiet", "--out", out.string()}, out);
  ASSERT_EQ(run.code, 0) << run.err;
  std::ifstream in(out / "work_precision.csv");
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line.rfind("scene,method,tracking,rtol,step,error_position,error_peak_force,energy_residual,run_time_s,"
                       "steps,rhs_evaluations,status",
                       0),
            0u);
  std::map<std::string, std::pair<double, double>> range;  // method → (min, max) error
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) c.push_back(cell);
    c.resize(13);
    ASSERT_EQ(c[11], "ok") << line;
    const double e = std::stod(c[5]);
    auto& [lo, hi] = range.try_emplace(c[1], INFINITY, 0.0).first->second;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  for (const char* method : {"cvode_bdf", "cvode_adams", "arkode_erk", "arkode_dirk"}) {
    ASSERT_TRUE(range.count(method)) << method;
    EXPECT_GE(std::log10(range[method].second / range[method].first), 4.0) << method;
  }
  fs::remove_all(out);
}

}  // namespace
