#pragma once
// What the fuzz targets do with one input, shared with tests/unit/fuzz_corpus_test.cpp, which replays the seed
// corpus and every input a fuzzer ever crashed on in the ordinary (and the sanitizer) test build. A reader
// may refuse an input only with clothsim::Error (the functions return false); any other exception, crash or sanitizer report is a bug.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/build_model.h"
#include "core/error.h"
#include "io/checkpoint.h"
#include "io/obj_reader.h"
#include "io/scene_xml.h"
#include "io/texture_map.h"

namespace clothsim::fuzz {

// The readers take paths: the input goes to a scratch file named once per process.
inline std::string input_file(std::string_view bytes, const char* extension) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("clothsim_fuzz_" + std::to_string(::getpid()) + extension)).string();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  std::fwrite(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
  return path;
}

// An OBJ file, then a model built from it as one cloth with default settings (topology on hostile meshes).
inline bool fuzz_obj(std::string_view bytes) {
  const std::string path = input_file(bytes, ".obj");
  try {
    MeshData mesh = io::read_obj(path);
    SceneDesc scene;
    scene.path = "fuzz.xml";
    scene.cloths.emplace_back();
    scene.cloths.back().obj = path;
    scene.cloths.back().save_name = "fuzz";
    build_model(scene, {mesh});
  } catch (const Error&) {
    return false;
  }
  return true;
}

// A scene file: the reader alone (the meshes it names are not read).
inline bool fuzz_scene(std::string_view bytes) {
  const std::string path = input_file(bytes, ".xml");
  try {
    io::read_scene(path);
  } catch (const Error&) {
    return false;
  }
  return true;
}

// A checkpoint file's bytes: decoded in memory, as --resume does after reading it.
inline bool fuzz_checkpoint(std::string_view bytes) {
  try {
    io::decode_checkpoint("fuzz.ckpt", bytes);
  } catch (const Error&) {
    return false;
  }
  return true;
}

// An image map (stb_image: PNG, JPEG, TGA, BMP, 8 or 16 bits), then sampled inside, on and beyond [0, 1]^2
// (bilinear filtering at the borders, wrapping).
inline bool fuzz_texture(std::string_view bytes) {
  const std::string path = input_file(bytes, ".img");
  try {
    const io::GreyImage image = io::read_grey_image(path);
    for (const Vec2& uv : {Vec2(0, 0), Vec2(1, 1), Vec2(0.37, 0.61), Vec2(-2.25, 3.5)}) {
      const Real g = io::sample_grey(image, uv);
      if (!(g >= 0 && g <= 1)) std::abort();  // a grey level outside [0, 1] is a bug, like a crash
    }
  } catch (const Error&) {
    return false;
  }
  return true;
}

}  // namespace clothsim::fuzz
