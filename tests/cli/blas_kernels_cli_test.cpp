// `clothsim run` sets OpenBLAS's kernels itself where OpenBLAS chose ones older than the CPU (tools/main.cpp), and a
// user's OPENBLAS_CORETYPE wins. The expectation comes from this test process, which loads the same OpenBLAS with
// no OPENBLAS_CORETYPE of clothsim's making: what it picked, and the advice core/blas_kernel.h gives for it.
#include <doctest/doctest.h>

#include <cstdlib>
#include <string>

#include "core/blas_kernel.h"
#include "tests/support/cli_harness.h"

using namespace clothsim;
using namespace clothsim::test;
namespace fs = std::filesystem;

namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("run sets better OpenBLAS kernels than OpenBLAS picked by itself and keeps a user's OPENBLAS_CORETYPE") {
  const std::string picked = blas_kernel_name();  // OpenBLAS's own choice in this process
  if (picked.empty()) {
    MESSAGE("the BLAS is not OpenBLAS: nothing to choose");
    return;
  }
  if (std::getenv("OPENBLAS_CORETYPE")) {
    MESSAGE("OPENBLAS_CORETYPE is set for the tests: OpenBLAS's own choice is unknown here");
    return;
  }
  const std::string advice = better_openblas_coretype(picked, cpu_vector_units());
  MESSAGE("OpenBLAS picked '" << picked << "', advice '" << advice << "'");

  const fs::path dir = scratch_dir("blas_kernels");
  write_text(dir / "scene.xml", R"(<scene>
  <simulation timestep="0.01" fps="25" startFrame="1" endFrame="3" integrator="implicit" preconditioner="cholesky"/>
  <cloth name="s" grid="24 24" size="1 1" translate="0 1 0" saveName="s">
    <density value="0.2"/><stiffness value="1000" bend="0.1"/><damping value="0.1"/><pins vertices="0 23"/>
  </cloth>
</scene>
)");
  const auto run = [&](const std::string& name, const std::string& env) {
    const CliResult r = run_cli("run " + (dir / "scene.xml").string() + " --quiet --threads 2 --out " +
                                    (dir / name).string() + " --stats " + (dir / name).string() + ".json",
                                "env -u OPENBLAS_CORETYPE -u CLOTHSIM_CHOSE_OPENBLAS_CORETYPE " + env);
    REQUIRE(r.exit_code == 0);
    CHECK(!has(r.output, "OPENBLAS_CORETYPE="));  // no advice: clothsim took it, or the user chose
    return read_text(dir / (name + ".json"));
  };

  const std::string chosen = advice.empty() ? picked : advice;
  const std::string by_itself = run("auto", "");
  CHECK(has(by_itself, "\"blas_kernel\":\"" + chosen + "\""));
  CHECK(has(by_itself, std::string("\"blas_kernel_chosen_by\":\"") + (advice.empty() ? "OpenBLAS" : "clothsim") + "\""));

  // The user asking for the same kernels gets the same bytes: the restart changes nothing else.
  const std::string asked = run("asked", "OPENBLAS_CORETYPE=" + chosen + " ");
  CHECK(has(asked, "\"blas_kernel\":\"" + chosen + "\""));
  CHECK(has(asked, "\"blas_kernel_chosen_by\":\"OPENBLAS_CORETYPE\""));
  const auto files = files_in(dir / "auto");
  REQUIRE(files.size() == 3);  // three frames
  CHECK(files == files_in(dir / "asked"));
  for (const std::string& f : files) CHECK(read_text(dir / "auto" / f) == read_text(dir / "asked" / f));

  // The user's older kernels are kept, without a warning: theirs is a choice.
  if (!advice.empty()) {
    const std::string older = run("older", "OPENBLAS_CORETYPE=Prescott ");
    CHECK(has(older, "\"blas_kernel\":\"Prescott\""));
    CHECK(has(older, "\"blas_kernel_chosen_by\":\"OPENBLAS_CORETYPE\""));
  }
}
