#include <doctest/doctest.h>

#include <cmath>
#include <sstream>

#include "tests/support/cli_harness.h"

using namespace clothsim::test;

namespace {

std::string sheet_scene(const std::string& simulation, const std::string& cloth_extra = "",
                        const std::string& stiffness = "2000") {
  return "<scene>\n  <simulation " + simulation + "/>\n"
         "  <cloth name=\"sheet\" grid=\"12 12\" size=\"1 1\" rotate=\"90 0 0\" saveDir=\"out\" saveName=\"sheet\"" +
         cloth_extra + ">\n    <stiffness value=\"" + stiffness + "\" bend=\"0.2\"/>\n    <damping value=\"0.02\"/>\n"
         "    <pins vertices=\"0 11\"/>\n  </cloth>\n</scene>\n";
}

// Largest |coordinate| over the vertex lines of an OBJ; NaN when any coordinate is not a finite number.
double largest_coordinate(const std::string& obj) {
  std::istringstream in(obj);
  std::string line;
  double worst = 0;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream fields(line.substr(2));
    std::string tok;
    while (fields >> tok) {
      const double v = std::strtod(tok.c_str(), nullptr);
      if (!std::isfinite(v) || tok.find("nan") != std::string::npos) return NAN;
      worst = std::max(worst, std::abs(v));
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("an exploding scene stops with exit code 3, names frame, step and a time step, and writes no bad frame") {
  const auto dir = scratch_dir("explode");
  // Symplectic Euler at 3.8 ms (11 steps a frame) on springs whose limit is 0.46 ms: the energy grows by orders per step.
  write_text(dir / "scene.xml", sheet_scene("timestep=\"0.004\" fps=\"24\" endFrame=\"10\" integrator=\"symplectic\""));
  const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet");
  CHECK(r.exit_code == 3);
  CHECK(r.output.find("frame 2, step ") != std::string::npos);
  CHECK(r.output.find("use a time step below") != std::string::npos);
  CHECK(r.output.find("integrator=\"implicit\"") != std::string::npos);
  // The advice is never the step that diverged: below it.
  const auto was = r.output.find("The step was ");
  REQUIRE(was != std::string::npos);
  const double failed = std::strtod(r.output.c_str() + was + 13, nullptr);
  const auto below = r.output.find("use a time step below ", was);
  REQUIRE(below != std::string::npos);
  const double advised = std::strtod(r.output.c_str() + below + 22, nullptr);
  CHECK(failed == doctest::Approx(1.0 / 264).epsilon(1e-3));
  CHECK(advised < failed);
  const auto files = files_in(dir / "out");
  CHECK(files == std::vector<std::string>{"sheet.0001.obj"});  // only the start frame, from the initial state
  for (const auto& f : files) CHECK(largest_coordinate(read_text(dir / "out" / f)) <= 1.0);
}

TEST_CASE("explicit Euler diverging slowly is stopped by the energy bound before any NaN, frames written stay sane") {
  const auto dir = scratch_dir("explode_euler");
  write_text(dir / "scene.xml",
             sheet_scene("timestep=\"0.00002\" fps=\"240\" endFrame=\"400\" integrator=\"euler\""));
  const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet --stats " +
                              (dir / "stats.json").string());
  CHECK(r.exit_code == 3);
  CHECK(r.output.find("the mechanical energy rose by") != std::string::npos);
  // Its springs are damped (0.02 N s/m on 2000 N/m), so explicit Euler has a limit, near kd/ke = 1e-5 s.
  const auto below = r.output.find("use a time step below ");
  REQUIRE(below != std::string::npos);
  const double advised = std::strtod(r.output.c_str() + below + 22, nullptr);
  CHECK(advised < 2e-5);
  CHECK(advised > 2e-6);
  const auto files = files_in(dir / "out");
  CHECK(files.size() >= 2);  // it ran for a while before the bound caught it
  CHECK(files.size() < 400);
  MESSAGE(files.size() << " frames written before the energy bound stopped explicit Euler");
  for (const auto& f : files) CHECK(largest_coordinate(read_text(dir / "out" / f)) < 2.0);
  CHECK(read_text(dir / "stats.json").find("\"status\":\"diverged\"") != std::string::npos);
}

TEST_CASE("validate prints the stable steps and warns when the scene's step is past its integrator's limit") {
  const auto dir = scratch_dir("validate_limits");
  write_text(dir / "fast.xml", sheet_scene("timestep=\"0.004\" integrator=\"rk4\""));
  const CliResult fast = run_cli("validate " + (dir / "fast.xml").string());
  CHECK(fast.exit_code == 0);
  CHECK(fast.output.find("largest stable step: symplectic ") != std::string::npos);
  CHECK(fast.output.find(", euler ") != std::string::npos);  // damped springs: explicit Euler has a limit
  CHECK(fast.output.find("euler none") == std::string::npos);
  CHECK(fast.output.find("warning: the step 0.00379 s exceeds the RK4 limit") != std::string::npos);
  write_text(dir / "implicit.xml", sheet_scene("timestep=\"0.004\" integrator=\"implicit\""));
  const CliResult imp = run_cli("validate " + (dir / "implicit.xml").string());
  CHECK(imp.exit_code == 0);
  CHECK(imp.output.find("warning") == std::string::npos);
  // The printed limit is the one the run obeys: omega_max of 12 x 12 at 2000 N/m, 0.2 kg/m^2 puts it near 1e-4 s.
  const auto at = fast.output.find("symplectic ") + 11;
  const double limit = std::strtod(fast.output.c_str() + at, nullptr);
  CHECK(limit > 5e-5);
  CHECK(limit < 5e-4);
}

TEST_CASE("timestep=auto: validate names the step, run reports steps per frame and a solve failing below minTimestep exits 3") {
  const auto dir = scratch_dir("auto_step_cli");
  write_text(dir / "auto.xml", sheet_scene("timestep=\"auto\" fps=\"24\" endFrame=\"3\" integrator=\"symplectic\""));
  const CliResult v = run_cli("validate " + (dir / "auto.xml").string());
  CHECK(v.exit_code == 0);
  CHECK(v.output.find("timestep auto: ") != std::string::npos);
  CHECK(v.output.find("warning") == std::string::npos);
  const CliResult r = run_cli("run " + (dir / "auto.xml").string() + " --quiet --stats " + (dir / "auto.json").string());
  CHECK(r.exit_code == 0);
  const std::string stats = read_text(dir / "auto.json");
  CHECK(stats.find("\"timestep\":\"auto\"") != std::string::npos);
  CHECK(stats.find("\"steps_rejected\":0") != std::string::npos);
  CHECK(stats.find("\"step_min\":") != std::string::npos);
  // One CG iteration against a 1e-12 tolerance fails every implicit solve: halved down to minTimestep, then exit 3.
  write_text(dir / "fail.xml", sheet_scene("timestep=\"auto\" fps=\"24\" endFrame=\"3\" integrator=\"implicit\" "
                                          "preconditioner=\"jacobi\" cgMaxIterations=\"1\" cgTolerance=\"1e-12\""));
  const CliResult f = run_cli("run " + (dir / "fail.xml").string() + " --quiet");
  CHECK(f.exit_code == 3);
  CHECK(f.output.find("below minTimestep") != std::string::npos);
  CHECK(f.output.find("cgMaxIterations") != std::string::npos);
}

TEST_CASE("an implicit run that tears a spring is told why, not that its converged solve failed") {
  // 0.002 N/m springs under gravity at 1/24 s: every solve converges, yet the largest strain climbs from 5.56 to
  // 6.65 within frame 12 (past the guard's 1), so the run stops with exit 3.
  const auto dir = scratch_dir("implicit_torn");
  write_text(dir / "soft.xml",
             sheet_scene("timestep=\"0.0416666667\" fps=\"24\" endFrame=\"12\" integrator=\"implicit\"", "", "0.002"));
  const CliResult r = run_cli("run " + (dir / "soft.xml").string() + " --quiet --out " + (dir / "out").string());
  CHECK(r.exit_code == 3);
  CHECK(r.output.find("within one frame") != std::string::npos);
  CHECK(r.output.find("linearises the forces about its start") != std::string::npos);
  CHECK(r.output.find("use a time step below 0.0104 s") != std::string::npos);  // a quarter of the step taken
  CHECK(r.output.find("linear solve failed") == std::string::npos);
}

TEST_CASE("a strain limit the cloth cannot meet is warned about, not written as if it held") {
  // A 3 x 3 vertex sheet of 1 m whose rest mesh is the same sheet at 0.85 of its size, pinned at two opposite
  // corners: every path of springs between the pins is 1/0.85 = 1.176 times its rest length, past maxStrain 0.1,
  // so no placement of the free vertices meets the limit and every step's sweeps stop at the cap.
  const auto dir = scratch_dir("strain_limit_unmet");
  auto sheet = [](double size) {
    std::string obj;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) obj += "v " + std::to_string(0.5 * size * i) + " 0 " + std::to_string(0.5 * size * j) + "\n";
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const int a = 1 + j * 3 + i;
        obj += "f " + std::to_string(a) + " " + std::to_string(a + 1) + " " + std::to_string(a + 4) + "\n";
        obj += "f " + std::to_string(a) + " " + std::to_string(a + 4) + " " + std::to_string(a + 3) + "\n";
      }
    return obj;
  };
  write_text(dir / "sheet.obj", sheet(1.0));
  write_text(dir / "rest.obj", sheet(0.85));
  write_text(dir / "scene.xml",
             "<scene>\n  <simulation timestep=\"0.001\" fps=\"100\" endFrame=\"2\" integrator=\"symplectic\"/>\n"
             "  <cloth name=\"sheet\" obj=\"sheet.obj\" rest=\"rest.obj\" maxStrain=\"0.1\" saveDir=\"out\">\n"
             "    <stiffness value=\"10\"/>\n    <pins vertices=\"0 8\"/>\n  </cloth>\n</scene>\n");
  const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet --stats " + (dir / "s.json").string());
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("10 of 10 steps failed their check") != std::string::npos);
  CHECK(r.output.find("the strain limit stopped after 500 sweeps with springs still past maxStrain") !=
        std::string::npos);
  CHECK(read_text(dir / "s.json").find("\"failed_steps\":10") != std::string::npos);
}

TEST_CASE("implicit run: byte-identical frames at 1 and 2 threads, CG figures per step in --stats") {
  const auto dir = scratch_dir("implicit_threads");
  write_text(dir / "scene.xml", sheet_scene("timestep=\"0.01\" fps=\"24\" endFrame=\"6\" integrator=\"implicit\" "
                                            "cgTolerance=\"1e-5\" cgMaxIterations=\"300\"", " maxStrain=\"0.1\""));
  for (const char* t : {"1", "2"}) {
    const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet --threads " + t + " --out " +
                                (dir / (std::string("t") + t)).string() + " --stats " +
                                (dir / (std::string("s") + t + ".json")).string());
    REQUIRE(r.exit_code == 0);
  }
  const auto files = files_in(dir / "t1");
  CHECK(files.size() == 6);
  for (const auto& f : files) CHECK(read_text(dir / "t1" / f) == read_text(dir / "t2" / f));
  const std::string stats = read_text(dir / "s1.json");
  CHECK(stats.find("\"integrator\":\"implicit\"") != std::string::npos);
  CHECK(stats.find("\"preconditioner\":\"multigrid\"") != std::string::npos);  // the default
  // 5 steps per frame: each frame after the first lists 5 iteration counts and 5 residuals.
  const auto at = stats.find("\"frame\":3");
  REQUIRE(at != std::string::npos);
  const auto list = stats.find("\"cg_iterations\":[", at);
  const auto end = stats.find(']', list);
  CHECK(std::count(stats.begin() + list, stats.begin() + end, ',') == 4);
  CHECK(stats.find("\"cg_residual\":[", at) != std::string::npos);
  CHECK(stats.find("\"strain_limit_iterations\":") != std::string::npos);
}

TEST_CASE("bad implicit and strain-limit settings are input errors with the line") {
  const auto dir = scratch_dir("implicit_bad");
  const std::pair<std::string, std::string> cases[] = {
      {sheet_scene("integrator=\"backward\""), "one of euler, symplectic, rk4, implicit"},
      {sheet_scene("integrator=\"implicit\" cgTolerance=\"2\""), "cgTolerance"},
      {sheet_scene("integrator=\"implicit\" cgMaxIterations=\"0\""), "cgMaxIterations"},
      {sheet_scene("integrator=\"implicit\" newtonIterations=\"-1\""), "newtonIterations"},
      {sheet_scene("integrator=\"implicit\" preconditioner=\"ilu\""), "jacobi, multigrid or cholesky"},
      {sheet_scene("integrator=\"implicit\"", " maxStrain=\"-0.1\""), "maxStrain"},
  };
  for (const auto& [scene, expected] : cases) {
    write_text(dir / "scene.xml", scene);
    const CliResult r = run_cli("validate " + (dir / "scene.xml").string());
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("scene.xml:") != std::string::npos);
    CHECK(r.output.find(expected) != std::string::npos);
  }
}
