// clothsim study scaling: CSV rows per thread count, byte-identical frames, weak scaling's grown sheet.
#include <doctest/doctest.h>

#include <sstream>

#include "tests/support/cli_harness.h"

using namespace clothsim::test;

namespace {

const char* small_sheet = R"(<?xml version="1.0"?>
<scene>
  <simulation timestep="0.001" fps="24" startFrame="1" endFrame="3" integrator="symplectic"/>
  <cloth name="s" grid="9 9" size="1 1" saveDir="out" saveName="s">
    <stiffness value="200"/>
    <pins vertices="0 8"/>
  </cloth>
</scene>
)";

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream l(line);
    std::string cell;
    while (std::getline(l, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

}  // namespace

TEST_CASE("study scaling: one row per thread count, identical frames, speed-up 1 at the first count") {
  const auto dir = scratch_dir("study_scaling");
  write_text(dir / "s.xml", small_sheet);
  const CliResult r = run_cli("study scaling " + (dir / "s.xml").string() + " --threads 1,2,3 --out " + dir.string());
  REQUIRE(r.exit_code == 0);
  const auto rows = csv_rows(read_text(dir / "scaling.csv"));
  REQUIRE(rows.size() == 4);
  CHECK(rows[0][0] == "threads");
  CHECK(rows[1][0] == "1");
  CHECK(rows[3][0] == "3");
  for (int k = 1; k <= 3; ++k) {
    CHECK(rows[k][1] == "81");        // 9 x 9 particles at every count
    CHECK(rows[k][6] == "yes");       // frames byte-identical to the first count's
  }
  CHECK(rows[1][4] == "1.0000");      // speed-up of the reference against itself
  CHECK(rows[1][5] == "1.0000");
  CHECK(read_text(dir / "scaling.gp").find("scaling.csv") != std::string::npos);
}

TEST_CASE("study scaling --weak grows the sheet with the thread count at the same spacing") {
  const auto dir = scratch_dir("study_scaling_weak");
  write_text(dir / "s.xml", small_sheet);
  const CliResult r =
      run_cli("study scaling " + (dir / "s.xml").string() + " --threads 1,4 --weak --out " + dir.string());
  REQUIRE(r.exit_code == 0);
  const auto rows = csv_rows(read_text(dir / "scaling.csv"));
  REQUIRE(rows.size() == 3);
  CHECK(rows[1][1] == "81");
  CHECK(rows[2][1] == "289");  // 2x the intervals per side: 17 x 17
}

TEST_CASE("study scaling: bad thread lists and unknown studies are usage errors (exit 2)") {
  const auto dir = scratch_dir("study_scaling_bad");
  write_text(dir / "s.xml", small_sheet);
  CHECK(run_cli("study scaling " + (dir / "s.xml").string() + " --threads 1,0").exit_code == 2);
  CHECK(run_cli("study scaling " + (dir / "s.xml").string()).exit_code == 2);
  CHECK(run_cli("study nope").exit_code == 2);
  CHECK(run_cli("study scaling " + (dir / "missing.xml").string() + " --threads 1").exit_code == 2);
}
