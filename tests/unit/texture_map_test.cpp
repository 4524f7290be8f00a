// Grey-scale maps: reading (8/16 bit, colour), the UV conventions, and sampling at vertices (seams included).
#include <doctest/doctest.h>

#include <cmath>

#include "core/build_model.h"
#include "core/error.h"
#include "io/cloth_maps.h"
#include "io/texture_map.h"
#include "tests/support/cli_harness.h"
#include "tests/support/png_fixtures.h"

#include <stb_image_write.h>

using namespace clothsim;
using namespace clothsim::test;

TEST_CASE("a horizontal gradient map gives each grid vertex min + (max - min) u within one grey level") {
  const auto dir = scratch_dir("map_gradient");
  // Texel i holds the u of its centre, (i + 0.5)/W, rounded to a grey level.
  const int w = 256, h = 4;
  std::vector<std::uint16_t> px;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) px.push_back(std::uint16_t(std::lround(255.0 * (i + 0.5) / w)));
  write_png(dir / "gradient.png", w, h, 1, 8, px);

  SceneDesc scene;
  scene.path = (dir / "scene.xml").string();
  ClothDesc cloth;
  cloth.name = "sheet";
  cloth.grid_nx = 21;
  cloth.grid_ny = 7;
  cloth.stiffness_map = {(dir / "gradient.png").string(), 100, 600, 3};
  MeshData mesh = make_cloth_grid(cloth);
  const VertexParams vp = io::sample_cloth_maps(scene, cloth, mesh);
  REQUIRE(vp.stiffness.size() == mesh.positions.size());
  CHECK(vp.density.empty());  // unmapped parameters stay scalars
  Real worst = 0;
  for (Index i = 0; i < mesh.vertex_count(); ++i)
    worst = std::max(worst, std::abs(vp.stiffness[i] - (100 + 500 * mesh.uvs[i][0])));
  CHECK(worst <= 500.0 / 255);
  CHECK(vp.stiffness[0] == 100);                               // u = 0: texel 0 is grey 0, min exactly
  CHECK(vp.stiffness[20] == 600);                               // u = 1: the last texel is white, max exactly

  // In the model a spring takes the mean of its two ends: the first structural spring joins u = 0 and 0.05.
  scene.cloths = {cloth};
  mesh.params = vp;
  const BuiltScene built = build_model(scene, {mesh});
  CHECK_FALSE(built.model.spring_ke.uniform());
  CHECK(built.model.spring_ke[0] == doctest::Approx(0.5 * (vp.stiffness[0] + vp.stiffness[1])));
  CHECK(built.model.spring_kd.uniform());  // damping was not mapped: one scalar
}

TEST_CASE("v runs bottom to top as in OBJ, UVs outside [0, 1] wrap, texel centres are exact") {
  const auto dir = scratch_dir("map_convention");
  // Row 0 (the top of the picture) white, row 1 black; columns: 0, 1/3, 2/3, 1 of white.
  write_png(dir / "rows.png", 4, 2, 1, 8, {255, 255, 255, 255, 0, 0, 0, 0});
  write_png(dir / "cols.png", 4, 1, 1, 8, {0, 85, 170, 255});
  const io::GreyImage rows = io::read_grey_image((dir / "rows.png").string());
  const io::GreyImage cols = io::read_grey_image((dir / "cols.png").string());
  CHECK(rows.bits == 8);
  CHECK(io::sample_grey(rows, Vec2(0.5, 0.0)) == 0);    // v = 0: bottom row, black
  CHECK(io::sample_grey(rows, Vec2(0.5, 1.0)) == 1);    // v = 1: top row, white
  CHECK(io::sample_grey(rows, Vec2(0.5, 0.5)) == doctest::Approx(0.5));  // between the rows' centres
  CHECK(io::sample_grey(cols, Vec2(0.375, 0.5)) == doctest::Approx(1.0 / 3));  // centre of texel 1
  CHECK(io::sample_grey(cols, Vec2(0.5, 0.5)) == doctest::Approx(0.5));        // halfway between texels 1 and 2
  CHECK(io::sample_grey(cols, Vec2(1.375, 0.5)) == doctest::Approx(1.0 / 3));  // wraps to 0.375
  CHECK(io::sample_grey(cols, Vec2(-0.625, 0.5)) == doctest::Approx(1.0 / 3)); // wraps to 0.375
  CHECK(io::sample_grey(cols, Vec2(1.0, 0.5)) == 1);    // 1 itself is the far edge, not 0
}

TEST_CASE("a 16-bit map resolves steps of 1/65535") {
  const auto dir = scratch_dir("map_16bit");
  write_png(dir / "deep.png", 4, 1, 1, 16, {30000, 30001, 30002, 65535});
  const io::GreyImage img = io::read_grey_image((dir / "deep.png").string());
  CHECK(img.bits == 16);
  const Real g0 = io::sample_grey(img, Vec2(0.125, 0.5)), g1 = io::sample_grey(img, Vec2(0.375, 0.5)),
             g2 = io::sample_grey(img, Vec2(0.625, 0.5));
  CHECK(g0 == doctest::Approx(30000.0 / 65535).epsilon(1e-12));
  CHECK((g1 - g0) * 65535 == doctest::Approx(1).epsilon(1e-9));
  CHECK((g2 - g1) * 65535 == doctest::Approx(1).epsilon(1e-9));
  // An 8-bit file cannot tell these apart: its steps are 257 times coarser.
  CHECK(65535.0 / 255 == 257);
}

TEST_CASE("colour maps are reduced to Rec. 709 luminance") {
  const auto dir = scratch_dir("map_colour");
  write_png(dir / "rgb.png", 3, 1, 3, 8, {255, 0, 0, 0, 255, 0, 0, 0, 255});
  const io::GreyImage img = io::read_grey_image((dir / "rgb.png").string());
  REQUIRE(img.grey.size() == 3);
  CHECK(img.grey[0] == doctest::Approx(0.2126));
  CHECK(img.grey[1] == doctest::Approx(0.7152));
  CHECK(img.grey[2] == doctest::Approx(0.0722));
}

TEST_CASE("a seam vertex takes the mean of the samples at its UVs") {
  const auto dir = scratch_dir("map_seam");
  write_png(dir / "halves.png", 2, 1, 1, 8, {0, 255});  // left half black, right half white
  // Two triangles share vertices 0 and 1; the first uses UVs on the black side, the second on the white side,
  // so vertices 0 and 1 sit on a seam. A third triangle uses vertex 0's black UV again: the mean is over its
  // distinct UVs (1/2), not over its corners (1/3). Vertices 2 and 4 are black only, vertex 3 white only.
  MeshData mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, -1, 0), Vec3(-1, 0, 0)};
  mesh.uvs = {Vec2(0.25, 0.2), Vec2(0.25, 0.4), Vec2(0.25, 0.8), Vec2(0.75, 0.2), Vec2(0.75, 0.4), Vec2(0.75, 0.8),
              Vec2(0.1, 0.2)};
  mesh.tri_index = {0, 1, 2, 0, 3, 1, 0, 2, 4};
  mesh.tri_uv = {0, 1, 2, 3, 5, 4, 0, 2, 6};
  const io::GreyImage img = io::read_grey_image((dir / "halves.png").string());
  const std::vector<Real> g = io::vertex_grey(img, mesh);
  CHECK(g[0] == 0.5);
  CHECK(g[1] == 0.5);
  CHECK(g[2] == 0);
  CHECK(g[3] == 1);
  CHECK(g[4] == 0);

  SceneDesc scene;
  ClothDesc cloth;
  cloth.damping_map = {(dir / "halves.png").string(), 0.25, 1.25, 1};
  const VertexParams vp = io::sample_cloth_maps(scene, cloth, mesh);
  CHECK(vp.damping == std::vector<Real>{0.75, 0.75, 0.25, 1.25, 0.25});
}

TEST_CASE("TGA, BMP and JPEG maps read like PNG") {
  const auto dir = scratch_dir("map_formats");
  // 4 x 2 RGB: a grey ramp 0, 85, 170, 255 on both rows, stored as colour.
  std::vector<unsigned char> rgb;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) rgb.push_back(static_cast<unsigned char>(85 * i));
  REQUIRE(stbi_write_tga((dir / "m.tga").c_str(), 4, 2, 3, rgb.data()));
  REQUIRE(stbi_write_bmp((dir / "m.bmp").c_str(), 4, 2, 3, rgb.data()));
  for (const char* name : {"m.tga", "m.bmp"}) {
    INFO(name);
    const io::GreyImage img = io::read_grey_image((dir / name).string());
    REQUIRE(img.grey.size() == 8);
    for (int i = 0; i < 4; ++i) CHECK(img.grey[i] == doctest::Approx(i / 3.0));  // lossless: exact levels
  }
  // JPEG is lossy: a flat mid-grey survives within two levels.
  std::vector<unsigned char> flat(16 * 16 * 3, 128);
  REQUIRE(stbi_write_jpg((dir / "m.jpg").c_str(), 16, 16, 3, flat.data(), 95));
  const io::GreyImage jpg = io::read_grey_image((dir / "m.jpg").string());
  CHECK(io::sample_grey(jpg, Vec2(0.5, 0.5)) == doctest::Approx(128.0 / 255).epsilon(2.0 / 128));
}

TEST_CASE("the pixel limit (core/limits.h) and the pixels a file can hold are checked from the header, before decoding") {
  const auto dir = scratch_dir("map_limit");
  // Headers alone, no pixel data: 16384 x 16384 = 2^28 passes the limit and is refused by the next check (far
  // more pixels than 45 bytes can hold); one row more is refused by the limit, with the size it read.
  write_text(dir / "at_limit.png", encode_png_header_only(16384, 16384));
  write_text(dir / "over.png", encode_png_header_only(16384, 16385));
  auto message = [&](const char* name) {
    try {
      io::read_grey_image((dir / name).string());
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CHECK(message("at_limit.png").find("at_limit.png: image of 16384 x 16384 pixels in 45 bytes, more than any image "
                                     "format packs (8256 pixels a byte)") != std::string::npos);
  CHECK(message("over.png").find("over.png: image of 16384 x 16385 pixels; expected at most 268435456 pixels") !=
        std::string::npos);
}

TEST_CASE("an image may pack at most 8256 pixels a byte: a real PNG is read, a forged header is not") {
  const auto dir = scratch_dir("map_density");
  write_constant_png(dir / "flat.png", 512, 512, 200);
  CHECK(io::read_grey_image((dir / "flat.png").string()).grey.size() == 512u * 512u);
  // A header alone (45 bytes) claiming 1024 x 1024 = 1,048,576 pixels, above 8256 x 45 = 371,520.
  write_text(dir / "forged.png", encode_png_header_only(1024, 1024));
  std::string what = "accepted";
  try {
    io::read_grey_image((dir / "forged.png").string());
  } catch (const Error& e) {
    what = e.what();
  }
  CHECK(what.find("forged.png: image of 1024 x 1024 pixels in 45 bytes") != std::string::npos);
}

TEST_CASE("a PNG chunk longer than the rest of the file is refused before stb allocates for it") {
  const auto dir = scratch_dir("map_chunk");
  // A valid 4 x 4 PNG whose IDAT (at byte 33, after the signature and the 25-byte IHDR chunk) declares
  // 0x6500001F = 1,694,498,847 bytes: stb would grow its buffer to 2 GiB before finding the data missing.
  std::string png = encode_png(4, 4, 1, 8, std::vector<std::uint16_t>(16, 100));
  REQUIRE(png.substr(37, 4) == "IDAT");
  const std::size_t size = png.size();
  png[33] = char(0x65), png[34] = 0, png[35] = 0, png[36] = char(0x1f);
  write_text(dir / "long.png", png);
  std::string what = "accepted";
  try {
    io::read_grey_image((dir / "long.png").string());
  } catch (const Error& e) {
    what = e.what();
  }
  CHECK(what.find("long.png: PNG chunk IDAT at byte 33 declares 1694498847 bytes of data, past the end of the file (" +
                  std::to_string(size) + " bytes)") != std::string::npos);
}

TEST_CASE("stb_image's other formats (GIF, PSD, PIC, PNM, HDR) are refused by their magic bytes") {
  const auto dir = scratch_dir("map_formats");
  const std::pair<const char*, std::string> files[] = {
      {"GIF", std::string("GIF89a\x01\x00\x01\x00\x00\x00\x00", 13)},
      {"Photoshop (PSD)", std::string("8BPS\x00\x01", 6)},
      {"Softimage PIC", std::string("\x53\x80\xF6\x34", 4) + std::string(84, '\0') + "PICT"},
      {"PNM", "P5\n1 1\n255\n\x80"},
      {"Radiance HDR", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 1\n\x80\x80\x80\x80"},
  };
  for (const auto& [format, bytes] : files) {
    CAPTURE(format);
    write_text(dir / "map.img", bytes);
    std::string what = "accepted";
    try {
      io::read_grey_image((dir / "map.img").string());
    } catch (const Error& e) {
      what = e.what();
    }
    CHECK(what.find(std::string("map.img: ") + format + " image, a format clothsim does not read") != std::string::npos);
  }
}

TEST_CASE("a PNG cut short after its header says it is truncated instead of an empty reason") {
  const auto dir = scratch_dir("map_truncated");
  // A valid 8 x 8 PNG's header, then its IDAT cut to half its data (CRC made anew), and no IEND: stb_image
  // fails on it without a reason.
  const std::string whole = encode_png(8, 8, 1, 8, std::vector<std::uint16_t>(64, 100));
  REQUIRE(whole.substr(37, 4) == "IDAT");
  const std::size_t length = std::uint32_t(std::uint8_t(whole[35])) * 256 + std::uint8_t(whole[36]);
  std::string cut = png_signature_and_header(8, 8, 1, 8);
  png_chunk(cut, "IDAT", whole.substr(41, length / 2));
  write_text(dir / "cut.png", cut);
  std::string what = "accepted";
  try {
    io::read_grey_image((dir / "cut.png").string());
  } catch (const Error& e) {
    what = e.what();
  }
  CHECK(what.find("cut.png: cannot decode the image (the file is truncated or corrupt); expected a PNG") !=
        std::string::npos);
}
