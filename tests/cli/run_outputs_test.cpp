// Output paths of `clothsim run` (tools/run_outputs.h, io/atomic_file.h): each is checked before the first
// step, a FIFO or device is written in place and never replaced, and temporaries of a killed write are removed.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "tests/support/cli_harness.h"

using namespace clothsim::test;
namespace fs = std::filesystem;

namespace {

const char* small_scene =
    "<scene><simulation timestep=\"0.005\" fps=\"25\" startFrame=\"1\" endFrame=\"2\"/>"
    "<cloth grid=\"3 3\" saveDir=\"out\" saveName=\"c\"/></scene>\n";

}  // namespace

TEST_CASE("a bad --stats or --out path stops the run before the first step and writes no frame") {
  const fs::path dir = scratch_dir("outputs_checked_first");
  write_text(dir / "scene.xml", small_scene);
  const std::string run = "run " + (dir / "scene.xml").string() + " --quiet ";
  const CliResult missing = run_cli(run + "--stats " + (dir / "no" / "such" / "s.json").string());
  CHECK(missing.exit_code == 2);
  CHECK(missing.output.find("s.json: cannot create file (No such file or directory)") != std::string::npos);
  const CliResult folder = run_cli(run + "--stats " + dir.string());
  CHECK(folder.exit_code == 2);
  CHECK(folder.output.find(dir.string() + ": is a folder; expected a file path") != std::string::npos);
  const CliResult too_long = run_cli(run + "--stats " + (dir / std::string(300, 's')).string());
  CHECK(too_long.exit_code == 2);
  CHECK(too_long.output.find("(File name too long)") != std::string::npos);
  CHECK(files_in(dir / "out").empty());  // no frame, no material: the failure came before the first step
  const CliResult empty_out = run_cli(run + "--out \"\"");
  CHECK(empty_out.exit_code == 2);
  CHECK(empty_out.output.find("--out expects a folder, got an empty name") != std::string::npos);
}

TEST_CASE("--stats to a FIFO writes through it and leaves the FIFO in place") {
  const fs::path dir = scratch_dir("outputs_fifo");
  write_text(dir / "scene.xml", small_scene);
  const fs::path fifo = dir / "stats.fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  // The reader end is opened first (non-blocking, so without a writer yet): the run finds a reader, and its few
  // kB of JSON fit the pipe's buffer until read below. A FIFO renamed over would never be written.
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  REQUIRE(reader >= 0);
  const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet --stats " + fifo.string());
  CHECK(r.exit_code == 0);
  CHECK(fs::is_fifo(fifo));
  std::string json(1 << 16, '\0');
  const ssize_t got = ::read(reader, json.data(), json.size());
  ::close(reader);
  json.resize(got > 0 ? std::size_t(got) : 0);
  CHECK(json.find("\"frames_written\":2") != std::string::npos);
}

TEST_CASE("temporaries of a killed write are removed by the next run and those of a live process kept") {
  const fs::path dir = scratch_dir("outputs_stale");
  write_text(dir / "scene.xml", small_scene);
  fs::create_directories(dir / "out");
  // 2147483646 is above any pid_max (at most 2^22 on Linux), so no process has that id.
  const std::string dead = ".tmp2147483646", live = ".tmp" + std::to_string(::getpid());
  for (const std::string& name : {"c.0001.obj" + dead, "c.0002.obj" + live, "scene.0004.ckpt" + dead,
                                  "other.0001.obj" + dead})
    write_text(dir / "out" / name, "partial");
  write_text(dir / ("s.json" + dead), "partial");
  REQUIRE(run_cli("run " + (dir / "scene.xml").string() + " --quiet --stats " + (dir / "s.json").string())
              .exit_code == 0);
  CHECK(files_in(dir / "out") ==
        std::vector<std::string>{"c.0001.obj", "c.0002.obj", "c.0002.obj" + live, "other.0001.obj" + dead});
  CHECK_FALSE(fs::exists(dir / ("s.json" + dead)));
  CHECK(fs::exists(dir / "s.json"));
}
