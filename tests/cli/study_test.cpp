// The studies through the real binary with --quick: measured convergence orders and stability limits against
// theory, every method and step in the CSV, and the charts written.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include "core/scene_desc.h"
#include "tests/support/cli_harness.h"

namespace fs = std::filesystem;
using namespace clothsim::test;

namespace {

using Row = std::map<std::string, std::string>;

// A CSV with a header line and no quoted fields, as the studies write it.
std::vector<Row> read_csv(const fs::path& path) {
  std::istringstream in(read_text(path));
  std::string line;
  std::vector<std::string> header;
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) fields.push_back(f);
    if (header.empty()) { header = fields; continue; }
    Row r;
    for (std::size_t i = 0; i < header.size() && i < fields.size(); ++i) r[header[i]] = fields[i];
    rows.push_back(r);
  }
  return rows;
}

// Least-squares slope of log(error) on log(step), written again here so the test does not trust the tool's.
double slope(const std::vector<double>& h, const std::vector<double>& e) {
  double n = double(h.size()), sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const double x = std::log(h[i]), y = std::log(e[i]);
    sx += x; sy += y; sxx += x * x; sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

bool gnuplot_present() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

void check_charts(const fs::path& dir, std::initializer_list<const char*> names) {
  if (!gnuplot_present()) {
    MESSAGE("gnuplot is not installed (tools/setup installs it): chart files not checked");
    return;
  }
  for (const char* name : names)
    for (const char* ext : {".png", ".svg"}) {
      const fs::path p = dir / (std::string(name) + ext);
      INFO(p.string());
      REQUIRE(fs::exists(p));
      CHECK(fs::file_size(p) > 1000);
    }
}

}  // namespace

TEST_CASE("study accuracy --quick: convergence orders of every method and step with converged references and charts" * doctest::test_suite("slow")) {
  const fs::path dir = scratch_dir("study_accuracy");
  const CliResult r = run_cli("study accuracy --quick --out " + dir.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::vector<Row> rows = read_csv(dir / "accuracy.csv");

  for (const char* problem : {"oscillator", "oscillator_damped", "sheet", "sheet_equilibrium"}) {
    for (const char* method : clothsim::integrator_names) {
      std::vector<double> h, e;
      for (const Row& row : rows)
        if (row.at("problem") == problem && row.at("method") == method) {
          h.push_back(std::stod(row.at("step_s")));
          if (row.at("status") == "ok") e.push_back(std::stod(row.at("error")));
          CHECK(std::stoll(row.at("steps")) > 0);
          CHECK(std::stoll(row.at("force_evaluations")) > 0);
        }
      INFO(problem << " " << method);
      // Every method has its 8 steps, each half the last.
      REQUIRE(h.size() == 8);
      for (std::size_t i = 1; i < h.size(); ++i) CHECK(h[i] == doctest::Approx(h[i - 1] / 2).epsilon(1e-9));
      // The oscillators converge at each method's formal order (their ladders stay in the asymptotic range).
      if (std::string(problem).rfind("oscillator", 0) == 0) {
        REQUIRE(e.size() == 8);
        const std::vector<double> hs(h.begin(), h.end());
        const int formal_order = std::string(method) == "rk4" ? 4 : 1;  // the textbook orders
        const double tolerance = formal_order == 1 ? 0.2 : 0.3;
        const double order = slope(hs, e);
        INFO("measured order " << order);
        CHECK(std::abs(order - formal_order) <= tolerance);
      }
    }
  }
  // The sheet's RK4 reference moves less, when its step is halved, than a tenth of any error measured against
  // it (in --quick the run is short and RK4's finest error is near round-off, hence a tenth, not a hundredth).
  double sheet_change = NAN;
  for (const Row& row : read_csv(dir / "accuracy_reference.csv"))
    if (row.at("problem") == "sheet") {
      sheet_change = std::stod(row.at("reference_change"));
      INFO(row.at("reference_change") << " vs " << row.at("smallest_error"));
      CHECK(sheet_change < 0.1 * std::stod(row.at("smallest_error")));
    }
  REQUIRE(std::isfinite(sheet_change));
  // A sheet error within 10x of the reference's own change cannot be told from it: the tool must say so
  // ("unresolved") rather than chart it, and must chart every error above that.
  for (const Row& row : rows)
    if (row.at("problem") == "sheet" && row.at("status") != "diverged") {
      const double e = std::stod(row.at("error"));
      INFO(row.at("method") << " h=" << row.at("step_s") << " error " << e);
      CHECK(row.at("status") == (e < 10 * sheet_change ? "unresolved" : "ok"));
    }
  check_charts(dir, {"work_precision", "error_vs_step"});
}

TEST_CASE("study stability --quick: measured limits within 10% of the linear theory" * doctest::test_suite("slow")) {
  const fs::path dir = scratch_dir("study_stability");
  const CliResult r = run_cli("study stability --quick --out " + dir.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::vector<Row> steps = read_csv(dir / "stability_step.csv");
  REQUIRE(steps.size() >= clothsim::integrator_names.size() * 2);
  for (const Row& row : steps) {
    INFO(row.at("method") << " at " << row.at("stiffness_n_per_m") << " N/m");
    const double w = std::stod(row.at("omega_max")), measured = std::stod(row.at("measured_step_s"));
    // w_max of the 8-mass chain, recomputed from its stiffness: 2 sqrt(k/m) sin(8 pi / 18), m = 0.01 kg.
    CHECK(w == doctest::Approx(2 * std::sqrt(std::stod(row.at("stiffness_n_per_m")) / 0.01) *
                               std::sin(8 * std::numbers::pi / 18)));
    if (row.at("method") == "symplectic") CHECK(measured * w == doctest::Approx(2).epsilon(0.1));
    if (row.at("method") == "rk4") CHECK(measured * w == doctest::Approx(2 * std::sqrt(2.0)).epsilon(0.1));
    // Explicit Euler has no stable step; its energy grows by 1 + (h w)^2 a step, so the 2x bound over 100
    // periods gives way at h w = ln 2 / (200 pi).
    if (row.at("method") == "euler") CHECK(measured * w == doctest::Approx(std::log(2.0) / (200 * std::numbers::pi)).epsilon(0.1));
    // Backward Euler has no limit: it stays bounded up to the search cap, at least 100x the RK4 limit.
    if (row.at("method") == "implicit") {
      CHECK(row.at("status") == "bounded_at_cap");
      CHECK(measured * w >= 100 * 2 * std::sqrt(2.0));
    }
  }
  for (const Row& row : read_csv(dir / "stability_stiffness.csv")) {
    INFO(row.at("method"));
    if (row.at("method") == "symplectic" || row.at("method") == "rk4")
      CHECK(std::stod(row.at("measured_stiffness_n_per_m")) ==
            doctest::Approx(std::stod(row.at("theory_stiffness_n_per_m"))).epsilon(0.1));
    // Backward Euler survives every stiffness up to the search cap (10^6 x the h w = 3 guess) at 1 ms. Before the
    // CG ignored subnormal dot products it "failed" at 4.97e6 N/m, when the decayed motion reached 1e-310 J.
    if (row.at("method") == "implicit") CHECK(row.at("status") == "bounded_at_cap");
  }
  check_charts(dir, {"stability"});
}

TEST_CASE("study: unknown study or option is a usage error, exit code 2") {
  CHECK(run_cli("study nosuch").exit_code == 2);
  CHECK(run_cli("study accuracy --bogus").exit_code == 2);
  CHECK(run_cli("study").exit_code == 2);
  CHECK(run_cli("study --help").exit_code == 0);
}
