// mpirun -np 3 clothsim batch: rank 0 hands out the scenes, ranks 1 and 2 run them; a failing scene among
// them is reported and the others are done, as in a local batch. Runs only when clothsim was built with MPI.
#include <doctest/doctest.h>

#include "tests/support/cli_harness.h"
#include "tests/support/shell_command.h"

using namespace clothsim::test;
namespace fs = std::filesystem;

TEST_CASE("an MPI batch over 3 ranks on loopback runs every scene and reports the failing one") {
#ifndef CLOTHSIM_MPIEXEC
  MESSAGE("clothsim was built without MPI: skipped");
#else
  const fs::path dir = scratch_dir("batch_mpi");
  // Four good scenes (s1..s4, random forces seeded 1..4) and a broken one, second in the list.
  for (const char* i : {"1", "2", "3", "4"}) {
    std::string scene = "<scene><simulation timestep=\"0.0002\" fps=\"24\" endFrame=\"5\"/><forces>";
    scene.append("<random amplitude=\"1\" seed=\"").append(i).append("\"/></forces>");
    scene.append("<cloth grid=\"8 8\" saveName=\"c\"><pins vertices=\"0 7\"/></cloth></scene>");
    write_text(dir / std::string("s").append(i).append(".xml"), scene);
  }
  write_text(dir / "broken.xml", "<scene><cloth grid=\"8\"/></scene>");
  write_text(dir / "list.txt", "s1.xml\nbroken.xml\ns2.xml\ns3.xml\ns4.xml\n");
  // Reference frames of one scene run alone.
  REQUIRE(run_cli("run " + (dir / "s3.xml").string() + " --out " + (dir / "ref").string() + " --quiet").exit_code == 0);

  // LeakSanitizer (the sanitizer build) reports Open MPI's own allocations at exit; leaks are checked elsewhere.
  const ShellResult r = run_shell("env ASAN_OPTIONS=detect_leaks=0 " CLOTHSIM_MPIEXEC
                                  " --oversubscribe --allow-run-as-root -np 3 " CLOTHSIM_BIN " batch " +
                                  (dir / "list.txt").string() + " --threads-per-job 1 --out " +
                                  (dir / "out").string());
  CAPTURE(r.output);
  CHECK(WIFEXITED(r.status));
  CHECK(WEXITSTATUS(r.status) != 0);  // a scene failed
  const std::string summary = read_text(dir / "out" / "summary.json");
  CAPTURE(summary);
  int ok = 0;
  for (std::size_t at = 0; (at = summary.find("\"status\":\"ok\"", at)) != std::string::npos; ++at) ++ok;
  CHECK(ok == 4);
  CHECK(summary.find("\"failed\":1") != std::string::npos);
  CHECK(summary.find("broken.xml:1: <cloth>: attribute grid=") != std::string::npos);
  CHECK(summary.find("\"exit_code\":2") != std::string::npos);
  // Results were gathered on rank 0 into list order, whatever order the workers finished in.
  CHECK(summary.find("s1.xml") < summary.find("broken.xml"));
  CHECK(summary.find("broken.xml") < summary.find("s2.xml"));
  for (int f = 1; f <= 5; ++f) {
    const std::string name = "c.000" + std::to_string(f) + ".obj";
    CHECK(read_text(dir / "out" / "s3" / name) == read_text(dir / "ref" / name));
  }
#endif
}
