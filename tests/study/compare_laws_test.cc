// studies/compare_laws.json, the jump-speed map: for every law, the first
// grid speed with separation is the first grid speed above the law's
// rigid-model jump speed (docs/model.md §9: no damper, so the rigid model gives
// the exact onset; the grid keeps >= 2.5 % away from every jump speed).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"

namespace {

namespace fs = std::filesystem;

TEST(CompareLawsStudy, JumpOnsetPerLawIsTheFirstSpeedAboveItsJumpSpeed) {
  const fs::path dir = fs::temp_directory_path() / ("camdyn_compare_laws_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string study = std::string(CAMDYN_SOURCE_DIR) + "/studies/compare_laws.json";
  ASSERT_EQ(camdyn::test::run_camdyn({"run", study, "--out", (dir / "out").string()}, dir, "run").code, 0)
      << camdyn::test::read_text(dir / "run.err");

  std::istringstream csv(camdyn::test::read_text(dir / "out" / "comparison.csv"));
  std::string line;
  std::getline(csv, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  auto column = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  struct Law {
    double jump = 0.0;
    std::vector<std::pair<double, double>> speed_separation;
  };
  std::map<std::string, Law> laws;
  std::vector<std::string> order;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.at(column("status")), "ok") << line;
    const std::string name = cells.at(column("case"));
    if (!laws.count(name)) order.push_back(name);
    Law& law = laws[name];
    law.jump = std::stod(cells.at(column("jump_speed_rpm")));
    law.speed_separation.emplace_back(std::stod(cells.at(column("mechanism.cam.rpm"))),
                                      std::stod(cells.at(column("separation_fraction"))));
  }
  ASSERT_EQ(order.size(), 6u);
  for (const std::string& name : order) {
    const Law& law = laws[name];
    double first_separating = 0.0, first_above = 0.0;
    for (const auto& [rpm, separation] : law.speed_separation) {
      if (separation > 0.0 && first_separating == 0.0) first_separating = rpm;
      if (rpm > law.jump && first_above == 0.0) first_above = rpm;
      // The grid is chosen clear of every jump speed: the rule is tested, not grazed.
      EXPECT_GT(std::abs(rpm / law.jump - 1.0), 0.02) << name << " at " << rpm;
    }
    EXPECT_GT(first_above, 0.0) << name << ": no grid speed above " << law.jump;
    EXPECT_EQ(first_separating, first_above) << name << " (jump speed " << law.jump << " rpm)";
  }

  // The report ranks the laws by the highest grid speed each holds without
  // separation: the last grid speed below its jump speed, highest first.
  const std::string html = camdyn::test::read_text(dir / "out" / "report.html");
  const std::size_t standings = html.find("Cases at a glance (ranked: highest speed held without separation");
  ASSERT_NE(standings, std::string::npos);
  std::vector<std::pair<double, std::string>> expected;  // -(speed held), law
  for (const std::string& name : order) {
    double held = 0.0;
    for (const auto& [rpm, separation] : laws[name].speed_separation)
      if (rpm < laws[name].jump) held = std::max(held, rpm);
    expected.emplace_back(-held, name);
  }
  std::stable_sort(expected.begin(), expected.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::size_t at = standings;
  for (const auto& [minus_held, name] : expected) {
    std::ostringstream held;
    held << "up to " << -minus_held << " rpm";
    const std::size_t row = html.find(held.str(), at);
    ASSERT_NE(row, std::string::npos) << name << " should hold " << held.str() << " in rank order";
    at = row;
  }
  fs::remove_all(dir);
}

}  // namespace
