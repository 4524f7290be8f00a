// clothsim run --resume: a run killed with SIGKILL at random points and resumed writes the same bytes as an
// uninterrupted run; a corrupted checkpoint falls back to the previous one; a write that fails under a
// file-size limit stops the run with exit code 2 and leaves only whole frames.
#include <doctest/doctest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <random>
#include <thread>

#include "tests/support/cli_harness.h"
#include "tests/support/png_fixtures.h"
#include "tests/support/shell_command.h"

using namespace clothsim::test;
namespace fs = std::filesystem;

namespace {

// Random forces and wind, so the resumed run must restore the step counter (the random forces' state) and
// the velocities exactly to match.
std::string resume_scene(int end_frame, int checkpoint_every) {
  return "<scene>\n"
         "  <simulation timestep=\"0.0002\" fps=\"24\" startFrame=\"1\" endFrame=\"" + std::to_string(end_frame) +
         "\" checkpointEvery=\"" + std::to_string(checkpoint_every) + "\"/>\n"
         "  <forces><wind velocity=\"3 0 1\" strength=\"1\"/><random amplitude=\"2\" seed=\"11\"/></forces>\n"
         "  <cloth grid=\"16 16\" size=\"1 1\" rotate=\"90 0 0\" saveName=\"sheet\"><pins vertices=\"0 15\"/></cloth>\n"
         "</scene>\n";
}

std::vector<std::string> obj_files(const fs::path& dir) {
  std::vector<std::string> out;
  for (const std::string& f : files_in(dir))
    if (f.size() > 4 && f.compare(f.size() - 4, 4, ".obj") == 0) out.push_back(f);
  return out;
}

// Every frame of `a` exists in `b` with the same bytes, and no other frame.
void check_same_frames(const fs::path& a, const fs::path& b) {
  const auto fa = obj_files(a);
  REQUIRE(fa == obj_files(b));
  int same = 0;
  for (const std::string& f : fa) same += read_text(a / f) == read_text(b / f);
  CHECK(same == int(fa.size()));
}

pid_t spawn_run(const std::string& scene, const std::string& out, const char* threads) {
  const pid_t pid = fork();
  if (pid == 0) {
    freopen("/dev/null", "w", stderr);
    execl(CLOTHSIM_BIN, CLOTHSIM_BIN, "run", scene.c_str(), "--out", out.c_str(), "--threads", threads, "--quiet",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

}  // namespace

TEST_CASE("a run killed with SIGKILL at random points resumes to the bytes of an uninterrupted run") {
  const fs::path dir = scratch_dir("resume_kill");
  const int end_frame = 30;
  write_text(dir / "scene.xml", resume_scene(end_frame, 3));
  const CliResult ref = run_cli("run " + (dir / "scene.xml").string() + " --out " + (dir / "ref").string() +
                                " --checkpoint-every 0 --quiet");
  REQUIRE(ref.exit_code == 0);
  REQUIRE(obj_files(dir / "ref").size() == std::size_t(end_frame));
  CHECK(files_in(dir / "ref").size() == std::size_t(end_frame));  // no checkpoint with --checkpoint-every 0

  const unsigned seed = std::random_device{}();
  CAPTURE(seed);
  std::mt19937 rng(seed);
  for (int trial = 0; trial < 3; ++trial) {
    const fs::path out = dir / ("killed" + std::to_string(trial));
    // Kill once `k` frames are on disk, plus a random fraction of a frame, so the kill lands anywhere: mid-step,
    // mid-frame-write, mid-checkpoint.
    const int k = std::uniform_int_distribution<int>(2, end_frame - 4)(rng);
    const int extra_us = std::uniform_int_distribution<int>(0, 3000)(rng);
    CAPTURE(trial);
    CAPTURE(k);
    CAPTURE(extra_us);
    const pid_t pid = spawn_run((dir / "scene.xml").string(), out.string(), "1");
    REQUIRE(pid > 0);
    int status = 0;
    bool exited = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (obj_files(out).size() < std::size_t(k) && std::chrono::steady_clock::now() < deadline) {
      if (waitpid(pid, &status, WNOHANG) == pid) { exited = true; break; }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    std::this_thread::sleep_for(std::chrono::microseconds(extra_us));
    if (!exited) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
    }
    const bool killed = WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
    CHECK(killed);  // the run did not finish before the kill
    const std::size_t frames_before = obj_files(out).size();
    CHECK(frames_before < std::size_t(end_frame));

    // Resume at another thread count: output is identical for any number of threads.
    const CliResult resumed =
        run_cli("run " + (dir / "scene.xml").string() + " --out " + out.string() + " --threads 2 --resume");
    CAPTURE(resumed.output);
    REQUIRE(resumed.exit_code == 0);
    // Checkpoints are taken at frames 1, 4, 7, ...: the resume starts after the last one written before the kill.
    const bool from_checkpoint = resumed.output.find("resuming after frame") != std::string::npos;
    CHECK((from_checkpoint || frames_before < 2));
    check_same_frames(dir / "ref", out);
    // The last two checkpoints remain: frames 28 and 30 (the end).
    CHECK(fs::exists(out / "scene.0030.ckpt"));
    CHECK(fs::exists(out / "scene.0028.ckpt"));
    CHECK_FALSE(fs::exists(out / "scene.0025.ckpt"));
  }
}

TEST_CASE("a run with colliders and self-collision resumes to the bytes of an uninterrupted run") {
  // The collision stage keeps only scratch across steps (broad-phase arrays that grow, accumulators cleared each
  // step), except the collider contacts the implicit solve holds next (systems/contact_filter.h), which the
  // checkpoint carries with x, v, time and step: a resumed run must match byte for byte. The Cholesky
  // preconditioner's kept factor is not in the checkpoint; every frame starts with a fresh one
  // (Simulation::advance_frame), so a resumed run preconditions its first solve as the whole run did.
  for (const std::string integrator : {"symplectic", "implicit", "implicit cholesky"}) {
    CAPTURE(integrator);
    const bool implicit = integrator != "symplectic";
    const bool cholesky = integrator == "implicit cholesky";
    const fs::path dir = scratch_dir(std::string("resume_collide_") + (cholesky ? "cholesky" : integrator));
    write_text(dir / "scene.xml", R"(<scene>
  <simulation timestep=")" + std::string(implicit ? "0.005" : "0.0005") + R"(" fps="24" startFrame="1" endFrame="12"
              checkpointEvery="4" collisionIterations="2" integrator=")" + (implicit ? "implicit" : integrator.c_str()) +
                                      (cholesky ? R"(" preconditioner="cholesky)" : "") + R"("/>
  <sphere name="ball" center="0 0 0" radius="0.25" friction="0.4"/>
  <plane name="floor" point="0 -0.3 0" normal="0 1 0"/>
  <cloth grid="12 12" size="0.8 0.8" translate="0 0.32 0" saveName="sheet" selfCollision="true">
    <stiffness value="200" bend="0.1"/><damping value="0.05"/><thickness value="0.01"/>
  </cloth>
</scene>
)");
    const std::string scene = (dir / "scene.xml").string();
    REQUIRE(run_cli("run " + scene + " --out " + (dir / "ref").string() + " --quiet").exit_code == 0);
    // Checkpoints after frames 1, 5, 9 and 12 (the end); the newest two, 9 and 12, are kept. Take frames 10-12 and
    // the frame-12 checkpoint away, as if the run had been killed after frame 9's checkpoint.
    const fs::path out = dir / "cut";
    fs::copy(dir / "ref", out);
    for (const char* f : {"sheet.0010.obj", "sheet.0011.obj", "sheet.0012.obj", "scene.0012.ckpt"})
      REQUIRE(fs::remove(out / f));
    // The implicit run's checkpoint holds a collider contact per particle (72-byte header, x and v at 24 bytes
    // each, the contact at 56, 8-byte checksum); the symplectic run's holds none.
    CHECK(read_text(out / "scene.0009.ckpt").size() == 72 + 144 * (implicit ? 104 : 48) + 8);
    const CliResult resumed = run_cli("run " + scene + " --out " + out.string() + " --threads 2 --resume");
    CAPTURE(resumed.output);
    REQUIRE(resumed.exit_code == 0);
    CHECK(resumed.output.find("resuming after frame 9") != std::string::npos);
    check_same_frames(dir / "ref", out);
    // The cloth moved: the frames compared are not all the start frame.
    CHECK(read_text(out / "sheet.0012.obj") != read_text(out / "sheet.0001.obj"));
  }
}

TEST_CASE("a corrupted or truncated newest checkpoint is reported and the previous one is used") {
  const fs::path dir = scratch_dir("resume_corrupt");
  write_text(dir / "scene.xml", resume_scene(20, 5));
  const std::string scene = (dir / "scene.xml").string();
  REQUIRE(run_cli("run " + scene + " --out " + (dir / "ref").string() + " --quiet").exit_code == 0);
  // checkpoints at frames 1, 6, 11, 16 and 20 (the end); the newest two are kept
  CHECK(fs::exists(dir / "ref" / "scene.0016.ckpt"));
  CHECK(fs::exists(dir / "ref" / "scene.0020.ckpt"));
  CHECK(files_in(dir / "ref").size() == 22);  // 20 frames and 2 checkpoints

  for (const bool truncate : {false, true}) {
    CAPTURE(truncate);
    const fs::path out = dir / (truncate ? "truncated" : "flipped");
    fs::copy(dir / "ref", out);
    std::string bytes = read_text(out / "scene.0020.ckpt");
    if (truncate) bytes.resize(bytes.size() / 2);
    else bytes[bytes.size() / 3] = char(bytes[bytes.size() / 3] ^ 0x40);
    write_text(out / "scene.0020.ckpt", bytes);
    for (int f = 17; f <= 20; ++f) fs::remove(out / ("sheet.00" + std::to_string(f) + ".obj"));

    const CliResult r = run_cli("run " + scene + " --out " + out.string() + " --resume");
    CAPTURE(r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("warning: " + (out / "scene.0020.ckpt").string()) != std::string::npos);
    CHECK(r.output.find(truncate ? "truncated" : "checksum mismatch") != std::string::npos);
    CHECK(r.output.find("resuming after frame 16") != std::string::npos);
    check_same_frames(dir / "ref", out);
    // The rewritten end checkpoint is whole again.
    CHECK(read_text(out / "scene.0020.ckpt") == read_text(dir / "ref" / "scene.0020.ckpt"));
  }

  // Resuming a finished run computes nothing and changes nothing.
  const CliResult again = run_cli("run " + scene + " --out " + (dir / "ref").string() + " --resume");
  CHECK(again.exit_code == 0);
  CHECK(again.output.find("resuming after frame 20") != std::string::npos);
  CHECK(again.output.find("frame 0020") == std::string::npos);
}

TEST_CASE("a write refused by a file-size limit stops the run with exit code 2 and written frames stay whole") {
  const fs::path dir = scratch_dir("resume_ulimit");
  write_text(dir / "scene.xml", resume_scene(6, 0));
  const std::string scene = (dir / "scene.xml").string();
  REQUIRE(run_cli("run " + scene + " --out " + (dir / "ref").string() + " --quiet").exit_code == 0);
  // Frame 1 is the flat grid, with short coordinates; later frames have 9 significant digits and are larger.
  const auto first = fs::file_size(dir / "ref" / "sheet.0001.obj");
  const auto second = fs::file_size(dir / "ref" / "sheet.0002.obj");
  REQUIRE(first + 1024 < second);
  // popen's /bin/sh is dash, whose ulimit -f counts 512-byte blocks: frame 1 fits, frame 2 does not.
  const ShellResult r = run_shell("ulimit -f " + std::to_string((first + 1023) / 512) + " && exec " CLOTHSIM_BIN
                                  " run " + scene + " --out " + (dir / "out").string());
  CAPTURE(r.output);
  REQUIRE(WIFEXITED(r.status));
  CHECK(WEXITSTATUS(r.status) == 2);
  CHECK(r.output.find("File too large") != std::string::npos);
  CHECK(r.output.find("sheet.0002.obj") != std::string::npos);
  // Only whole frames are left, each identical to the reference; no temporary file remains.
  const auto written = files_in(dir / "out");
  CHECK(written == std::vector<std::string>{"sheet.0001.obj"});
  CHECK(read_text(dir / "out" / "sheet.0001.obj") == read_text(dir / "ref" / "sheet.0001.obj"));
}

TEST_CASE("--resume uses only a checkpoint whose run wrote every frame the resumed run needs") {
  const fs::path dir = scratch_dir("resume_coverage");
  write_text(dir / "scene.xml",
             "<scene><simulation timestep=\"0.001\" fps=\"25\" startFrame=\"1\" endFrame=\"20\"/>"
             "<cloth grid=\"3 3\" saveDir=\"out\" saveName=\"c\"><pins vertices=\"0\"/></cloth></scene>\n");
  const std::string run = "run " + (dir / "scene.xml").string() + " --checkpoint-every 4";
  REQUIRE(run_cli(run + " --frames 15:20").exit_code == 0);
  REQUIRE(obj_files(dir / "out").size() == 6);
  const CliResult resumed = run_cli(run + " --resume");
  CHECK(resumed.exit_code == 0);
  CHECK(resumed.output.find("wrote frames 15..20 only; this run needs frames from 1") != std::string::npos);
  CHECK(obj_files(dir / "out").size() == 20);  // frames 1..14 were computed, not skipped
  // A run resumed from a checkpoint of a whole run vouches for every frame since: a later resume uses it.
  const CliResult again = run_cli(run + " --resume");
  CHECK(again.output.find("resuming after frame 20") != std::string::npos);
}

TEST_CASE("--resume refuses a checkpoint once a parameter map or a collider mesh changed") {
  const fs::path dir = scratch_dir("resume_inputs");
  write_text(dir / "map.png", encode_png(2, 2, 1, 8, {0, 255, 255, 0}));
  write_text(dir / "body.obj", "v -1 -1 -1\nv 1 -1 -1\nv 0 -1 1\nf 1 2 3\n");
  write_text(dir / "scene.xml",
             "<scene><simulation timestep=\"0.001\" fps=\"25\" startFrame=\"1\" endFrame=\"2\"/>"
             "<static obj=\"body.obj\"/>"
             "<cloth grid=\"3 3\" saveDir=\"out\" saveName=\"c\"><pins vertices=\"0\"/>"
             "<stiffness min=\"10\" max=\"20\" map=\"map.png\"/></cloth></scene>\n");
  const std::string run = "run " + (dir / "scene.xml").string() + " --checkpoint-every 1";
  REQUIRE(run_cli(run).exit_code == 0);
  write_text(dir / "map.png", encode_png(2, 2, 1, 8, {255, 255, 255, 0}));
  const CliResult map = run_cli(run + " --resume");
  CHECK(map.exit_code == 0);
  CHECK(map.output.find("belongs to another scene") != std::string::npos);
  CHECK(map.output.find("resuming after") == std::string::npos);
  write_text(dir / "body.obj", "v -1 -2 -1\nv 1 -2 -1\nv 0 -2 1\nf 1 2 3\n");
  const CliResult body = run_cli(run + " --resume");
  CHECK(body.output.find("belongs to another scene") != std::string::npos);
  CHECK(body.output.find("resuming after") == std::string::npos);
  const CliResult same = run_cli(run + " --resume");  // nothing changed since: the checkpoint is used
  CHECK(same.output.find("resuming after frame 2") != std::string::npos);
}
