// The compare study through the command line: every case at every grid
// point, failures recorded without stopping the others, jump onset where the
// rigid model puts it.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace {

namespace fs = std::filesystem;

std::vector<std::map<std::string, std::string>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::stringstream ls(line);
    size_t i = 0;
    for (std::string cell; i < header.size(); ++i) {
      if (!std::getline(ls, cell, ',')) cell.clear();
      row[header[i]] = cell;
    }
    rows.push_back(row);
  }
  return rows;
}

TEST(CompareStudy, RunsEveryCaseAtEveryGridPointAndRecordsFailures) {
  const fs::path dir = fs::temp_directory_path() / ("camdyn_compare_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string quickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";
  std::ofstream(dir / "study.json") << R"({
    "extends": ")" << quickstart << R"(",
    "name": "laws", "study": "compare",
    "mechanism": { "follower": { "damping": 0.0 } },
    "simulation": { "cycles": 3, "discard_cycles": 1 },
    "cases": [ { "name": "cycloidal" },
               { "name": "soft", "set": ["mechanism.contact.stiffness=1e4"] } ],
    "grid": { "mechanism.cam.rpm": [900, 1100, 1250, 1400] }
  })";
  const std::string cmd = std::string(CAMDYN_BINARY) + " run " + (dir / "study.json").string() + " --quiet --out " +
                          (dir / "out").string() + " > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0);
  const auto rows = read_csv(dir / "out" / "comparison.csv");
  ASSERT_EQ(rows.size(), 8u);
  int failed = 0;
  for (const auto& row : rows) {
    if (row.at("case") == "soft") {
      EXPECT_EQ(row.at("status"), "failed");  // the contact cannot carry the preload
      EXPECT_FALSE(row.at("error").empty());
      ++failed;
      continue;
    }
    ASSERT_EQ(row.at("status"), "ok") << row.at("error");
    const double rpm = std::stod(row.at("mechanism.cam.rpm"));
    const double jump = std::stod(row.at("jump_speed_rpm"));
    const double separation = std::stod(row.at("separation_fraction"));
    // The rigid model (no damper) bounds the jump: none well below it, separation above it.
    if (rpm < 0.95 * jump) {
      EXPECT_EQ(separation, 0.0) << rpm;
    }
    if (rpm > 1.1 * jump) {
      EXPECT_GT(separation, 0.0) << rpm;
    }
  }
  EXPECT_EQ(failed, 4);
  EXPECT_TRUE(fs::exists(dir / "out" / "comparison.json"));
  EXPECT_TRUE(fs::exists(dir / "out" / "report.html"));
  fs::remove_all(dir);
}

}  // namespace
