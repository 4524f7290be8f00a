// io/checkpoint: the bytes round-trip exactly, and every truncation or flipped byte is refused.
#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "io/checkpoint.h"
#include "tests/support/cli_harness.h"

using namespace clothsim;

namespace {

io::Checkpoint sample_checkpoint(int n, int frame, bool contacts = false) {
  io::Checkpoint c;
  c.fingerprint = 0x1234abcd5678ef90ULL;
  c.frame = frame;
  c.state.step = 1000 + frame;
  c.state.time = 0.1 * frame + 1e-17;
  c.cholesky_renewal = {32, 7};
  for (int i = 0; i < n; ++i) {
    c.state.x.emplace_back(0.1 * i, -1.0 / (i + 3), 1e-300 * i);
    c.state.v.emplace_back(-0.0, 3.0 * i + 1.0 / 7, std::nextafter(1.0, 2.0));
    if (contacts) c.state.contact.push_back(i % 2 ? ContactHold{Vec3(0, 1, 0), Vec3(0.5, -0.0, 1e-300), 0.3} : ContactHold{});
  }
  return c;
}

bool same_bits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

}  // namespace

TEST_CASE("a checkpoint decodes to the bit-identical state it encoded") {
  const io::Checkpoint c = sample_checkpoint(7, 12);
  const std::string bytes = io::encode_checkpoint(c);
  // header 72 bytes + 7 particles * 2 vectors * 24 bytes + 8-byte checksum
  CHECK(bytes.size() == 72 + 7 * 48 + 8);
  const io::Checkpoint d = io::decode_checkpoint("c.ckpt", bytes);
  CHECK(d.state.contact.empty());
  CHECK(d.fingerprint == c.fingerprint);
  CHECK(d.frame == 12);
  CHECK(d.state.step == 1012);
  CHECK(d.cholesky_renewal.run == 32);
  CHECK(d.cholesky_renewal.left == 7);
  CHECK(std::memcmp(&d.state.time, &c.state.time, sizeof(double)) == 0);
  CHECK(same_bits(d.state.x, c.state.x));
  CHECK(same_bits(d.state.v, c.state.v));  // including the sign of -0.0
  // With the implicit solve's collider contacts: 7 more numbers per particle.
  const io::Checkpoint held = sample_checkpoint(7, 12, true);
  const std::string held_bytes = io::encode_checkpoint(held);
  CHECK(held_bytes.size() == 72 + 7 * (48 + 56) + 8);
  const std::vector<ContactHold> back = io::decode_checkpoint("c.ckpt", held_bytes).state.contact;
  REQUIRE(back.size() == held.state.contact.size());
  CHECK(std::memcmp(static_cast<const void*>(back.data()), static_cast<const void*>(held.state.contact.data()),
                    back.size() * sizeof(ContactHold)) == 0);
}

TEST_CASE("every truncation and every flipped byte of a checkpoint is detected") {
  const std::string bytes = io::encode_checkpoint(sample_checkpoint(3, 4, true));
  int refused = 0;
  for (std::size_t len = 0; len < bytes.size(); ++len) {
    try {
      io::decode_checkpoint("c.ckpt", std::string_view(bytes).substr(0, len));
    } catch (const Error&) {
      ++refused;
    }
  }
  CHECK(refused == int(bytes.size()));
  refused = 0;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    std::string bad = bytes;
    bad[i] = char(bad[i] ^ 0x10);
    try {
      io::decode_checkpoint("c.ckpt", bad);
    } catch (const Error&) {
      ++refused;
    }
  }
  CHECK(refused == int(bytes.size()));
  std::string longer = bytes + "x";
  CHECK_THROWS_WITH_AS(io::decode_checkpoint("c.ckpt", longer), doctest::Contains("trailing bytes"), Error);
}

TEST_CASE("a checkpoint whose Cholesky renewal counts are impossible is refused, though its checksum holds") {
  io::Checkpoint c = sample_checkpoint(3, 4);
  c.cholesky_renewal = {16, 17};  // more refactorisations left than the run has
  CHECK_THROWS_WITH_AS(io::decode_checkpoint("c.ckpt", io::encode_checkpoint(c)),
                       doctest::Contains("renewal counts out of range"), Error);
  c.cholesky_renewal = {0, -1};
  CHECK_THROWS_WITH_AS(io::decode_checkpoint("c.ckpt", io::encode_checkpoint(c)),
                       doctest::Contains("renewal counts out of range"), Error);
  c.cholesky_renewal = {16, 16};
  CHECK(io::decode_checkpoint("c.ckpt", io::encode_checkpoint(c)).cholesky_renewal.left == 16);
}

TEST_CASE("the newest valid checkpoint is found and a corrupted newer one is skipped with a warning") {
  const auto dir = test::scratch_dir("checkpoint_find").string();
  for (int frame : {3, 6, 9}) io::write_checkpoint(dir, "scene", sample_checkpoint(4, frame));
  // keep = 2: the checkpoint of frame 3 was deleted when 9 was written
  CHECK(test::files_in(dir) == std::vector<std::string>{"scene.0006.ckpt", "scene.0009.ckpt"});

  std::vector<std::string> warnings;
  auto c = io::find_latest_checkpoint(dir, "scene", 0x1234abcd5678ef90ULL, 4, 0, warnings);
  REQUIRE(c);
  CHECK(c->frame == 9);
  CHECK(warnings.empty());

  // Flip one byte in the middle of the newest: the previous one is used.
  const std::string newest = io::checkpoint_path(dir, "scene", 9);
  std::string bytes = test::read_text(newest);
  bytes[bytes.size() / 2] = char(bytes[bytes.size() / 2] ^ 1);
  test::write_text(newest, bytes);
  c = io::find_latest_checkpoint(dir, "scene", 0x1234abcd5678ef90ULL, 4, 0, warnings);
  REQUIRE(c);
  CHECK(c->frame == 6);
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0].find("scene.0009.ckpt") != std::string::npos);
  CHECK(warnings[0].find("checksum") != std::string::npos);

  // Another scene's fingerprint or particle count: nothing valid.
  warnings.clear();
  CHECK_FALSE(io::find_latest_checkpoint(dir, "scene", 42, 4, 0, warnings));
  CHECK(warnings.size() == 2);
  warnings.clear();
  CHECK_FALSE(io::find_latest_checkpoint(dir, "scene", 0x1234abcd5678ef90ULL, 5, 0, warnings));

  io::remove_checkpoints_after(dir, "scene", 6);
  CHECK(test::files_in(dir) == std::vector<std::string>{"scene.0006.ckpt"});
}
