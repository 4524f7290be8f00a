// clothsim batch: scenes run in child processes; a bad or diverging scene is reported and skipped; the summary
// (table and JSON) says what happened; a re-run skips completed scenes and resumes interrupted ones.
#include <doctest/doctest.h>

#include "tests/support/cli_harness.h"

using namespace clothsim::test;
namespace fs = std::filesystem;

namespace {

std::string grid_scene(const std::string& simulation_extra, const std::string& cloth_extra) {
  return "<scene>\n  <simulation timestep=\"0.0002\" fps=\"24\" startFrame=\"1\" endFrame=\"6\"" + simulation_extra +
         "/>\n  <forces><random amplitude=\"1\" seed=\"3\"/></forces>\n"
         "  <cloth grid=\"8 8\" size=\"1 1\" saveName=\"c\"" + cloth_extra + "><pins vertices=\"0 7\"/></cloth>\n"
         "</scene>\n";
}

}  // namespace

TEST_CASE("a batch runs every scene and reports the failing ones and a re-run skips or resumes") {
  const fs::path dir = scratch_dir("batch");
  fs::create_directories(dir / "sub");
  write_text(dir / "good.xml", grid_scene("", ""));
  write_text(dir / "sub" / "good.xml", grid_scene(" gravity=\"0 -1 0\"", ""));  // same stem: gets good-2
  write_text(dir / "typo.xml", grid_scene(" fsp=\"24\"", ""));
  // Explicit Euler at 4x the stable step: the energy guard (docs/stability.md) stops it at frame 2 (exit code 3)
  write_text(dir / "unstable.xml",
             "<scene><simulation timestep=\"0.002\" fps=\"24\" endFrame=\"24\" integrator=\"euler\"/>"
             "<cloth grid=\"8 8\" saveName=\"u\"><pins vertices=\"0\"/></cloth></scene>");
  write_text(dir / "list.txt",
             "# nightly batch\n\ngood.xml\n  sub/good.xml  # same name, other folder\ntypo.xml\nunstable.xml\n"
             "missing.xml\n");

  // Reference frames of the good scene, run alone.
  REQUIRE(run_cli("run " + (dir / "good.xml").string() + " --out " + (dir / "ref").string() + " --quiet")
              .exit_code == 0);
  // An interrupted scene: its first 3 frames and a checkpoint are already in its batch folder.
  REQUIRE(run_cli("run " + (dir / "sub" / "good.xml").string() + " --out " + (dir / "out" / "good-2").string() +
                  " --frames 1:3 --checkpoint-every 5 --quiet")
              .exit_code == 0);
  REQUIRE(fs::exists(dir / "out" / "good-2" / "good.0003.ckpt"));

  const std::string batch = "batch " + (dir / "list.txt").string() + " --jobs 2 --threads-per-job 1 --out " +
                            (dir / "out").string();
  const CliResult r = run_cli(batch);
  CAPTURE(r.output);
  CHECK(r.exit_code == 1);
  const std::string summary = read_text(dir / "out" / "summary.json");
  CAPTURE(summary);
  // One row per scene, in list order, with its status.
  for (const char* row : {"\"status\":\"ok\"", "\"status\":\"bad input\"", "\"status\":\"diverged\""})
    CHECK(summary.find(row) != std::string::npos);
  CHECK(summary.find("\"failed\":3") != std::string::npos);
  CHECK(summary.find("unknown attribute 'fsp'") != std::string::npos);
  CHECK(summary.find("missing.xml: cannot read file") != std::string::npos);
  CHECK(summary.find("frame 2, step 21: the simulation diverged") != std::string::npos);
  CHECK(summary.find("\"frames\":1,") != std::string::npos);  // only frame 1 was written before it diverged
  CHECK(summary.find("\"frames\":6,") != std::string::npos);
  CHECK(r.output.find("scene") != std::string::npos);  // the table header

  // The good scene's frames equal a lone run's; the interrupted one resumed after frame 3.
  for (int f = 1; f <= 6; ++f) {
    const std::string name = "c.000" + std::to_string(f) + ".obj";
    CHECK(read_text(dir / "out" / "good" / name) == read_text(dir / "ref" / name));
  }
  CHECK(read_text(dir / "out" / "good-2" / "run.log").find("resuming after frame 3") != std::string::npos);
  CHECK(fs::exists(dir / "out" / "good-2" / "c.0006.obj"));
  CHECK(fs::exists(dir / "out" / "good" / "batch.done"));
  CHECK_FALSE(fs::exists(dir / "out" / "typo" / "batch.done"));

  // Re-run: the two good scenes are complete and not run again; the failing ones are tried and fail again.
  const auto stamp = fs::last_write_time(dir / "out" / "good" / "c.0006.obj");
  const CliResult again = run_cli(batch);
  CHECK(again.exit_code == 1);
  const std::string summary2 = read_text(dir / "out" / "summary.json");
  CAPTURE(summary2);
  int complete = 0;
  for (std::size_t at = 0; (at = summary2.find("\"status\":\"complete\"", at)) != std::string::npos; ++at) ++complete;
  CHECK(complete == 2);
  CHECK(fs::last_write_time(dir / "out" / "good" / "c.0006.obj") == stamp);
}

TEST_CASE("a batch of good scenes from a folder exits 0 and a bad list exits 2") {
  const fs::path dir = scratch_dir("batch_folder");
  fs::create_directories(dir / "scenes");
  write_text(dir / "scenes" / "a.xml", grid_scene("", ""));
  write_text(dir / "scenes" / "b.xml", grid_scene(" gravity=\"0 0 -9.81\"", ""));
  const CliResult r = run_cli("batch " + (dir / "scenes").string() + " --out " + (dir / "out").string() + " --quiet");
  CAPTURE(r.output);
  CHECK(r.exit_code == 0);
  CHECK(fs::exists(dir / "out" / "a" / "c.0006.obj"));
  CHECK(read_text(dir / "out" / "summary.json").find("\"failed\":0") != std::string::npos);

  write_text(dir / "empty.txt", "# nothing here\n\n");
  const CliResult empty = run_cli("batch " + (dir / "empty.txt").string() + " --out " + (dir / "out2").string());
  CHECK(empty.exit_code == 2);
  CHECK(empty.output.find("no scene listed") != std::string::npos);
}

TEST_CASE("a batch list entry whose name is too long fails alone and the scenes after it run") {
  const fs::path dir = scratch_dir("batch_long_name");
  write_text(dir / "good.xml", grid_scene("", ""));
  write_text(dir / "list.txt", std::string(300, 'n') + ".xml\n" + std::string(1 << 20, 'm') + "\ngood.xml\n");
  const CliResult r = run_cli("batch " + (dir / "list.txt").string() + " --quiet --out " + (dir / "out").string());
  CAPTURE(r.output.substr(0, 2000));
  CHECK(r.exit_code == 1);  // some scene failed; not 134 (an uncaught exception)
  const std::string summary = read_text(dir / "out" / "summary.json");
  CHECK(summary.find("\"failed\":2") != std::string::npos);
  CHECK(summary.find("File name too long") != std::string::npos);
  CHECK(fs::exists(dir / "out" / "good" / "c.0006.obj"));
}

TEST_CASE("a re-run batch does not take one scene's output for another's after the list is reordered") {
  const fs::path dir = scratch_dir("batch_reorder");
  fs::create_directories(dir / "sub");
  write_text(dir / "a.xml", grid_scene("", ""));
  write_text(dir / "sub" / "a.xml", grid_scene(" gravity=\"0 -1 0\"", ""));
  const std::string batch = "batch " + (dir / "list.txt").string() + " --quiet --out " + (dir / "out").string();
  write_text(dir / "list.txt", "a.xml\nsub/a.xml\n");
  REQUIRE(run_cli(batch).exit_code == 0);
  const std::string top = read_text(dir / "out" / "a" / "c.0006.obj"), sub = read_text(dir / "out" / "a-2" / "c.0006.obj");
  REQUIRE(top != sub);
  write_text(dir / "list.txt", "sub/a.xml\na.xml\n");  // now sub/a.xml is named a, and a.xml a-2
  const CliResult again = run_cli(batch);
  CHECK(again.exit_code == 0);
  CHECK(read_text(dir / "out" / "summary.json").find("\"status\":\"complete\"") == std::string::npos);
  CHECK(read_text(dir / "out" / "a" / "c.0006.obj") == sub);
  CHECK(read_text(dir / "out" / "a-2" / "c.0006.obj") == top);
}
