// Replays tests/fuzz/: the seed corpus of each fuzz target (valid inputs, all accepted) and every input a
// fuzzer ever crashed on (crash-*: refused with clothsim::Error, never a crash), so they run in every build,
// the AddressSanitizer one included.
#include <doctest/doctest.h>

#include <filesystem>

#include "tests/fuzz/fuzz_inputs.h"
#include "tests/support/cli_harness.h"

namespace fs = std::filesystem;

namespace {

// Runs every file of tests/fuzz/<target>/ through `fn`; counts the seeds accepted and the crash inputs refused.
template <class Fn>
void replay(const char* target, Fn fn, int expected_seeds) {
  int seeds = 0, seeds_accepted = 0, crashes = 0, crashes_refused = 0;
  for (const auto& e : fs::directory_iterator(fs::path(CLOTHSIM_SOURCE_DIR) / "tests" / "fuzz" / target)) {
    const std::string name = e.path().filename().string();
    CAPTURE(name);
    const bool accepted = fn(clothsim::test::read_text(e.path()));
    if (name.rfind("crash-", 0) == 0) {
      ++crashes;
      crashes_refused += !accepted;
    } else {
      ++seeds;
      seeds_accepted += accepted;
      CHECK(accepted);
    }
  }
  CHECK(seeds == expected_seeds);
  CHECK(seeds_accepted == seeds);
  CHECK(crashes_refused == crashes);
}

}  // namespace

TEST_CASE("the OBJ fuzz corpus: seeds are accepted and past crash inputs are refused cleanly") {
  replay("obj", clothsim::fuzz::fuzz_obj, 6);
}

TEST_CASE("the scene fuzz corpus: seeds are accepted and past crash inputs are refused cleanly") {
  replay("scene", clothsim::fuzz::fuzz_scene, 4);
}

TEST_CASE("the checkpoint fuzz corpus: seeds are accepted and past crash inputs are refused cleanly") {
  replay("checkpoint", clothsim::fuzz::fuzz_checkpoint, 1);
}

TEST_CASE("the image-map fuzz corpus: seeds are accepted and past crash inputs are refused cleanly") {
  // PNG 8/16-bit grey and RGB, TGA plain and RLE, BMP, JPEG grey and colour (tests/fuzz/texture_seeds)
  replay("texture", clothsim::fuzz::fuzz_texture, 9);
}
