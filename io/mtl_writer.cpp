#include "io/mtl_writer.h"

#include <filesystem>

#include "io/atomic_file.h"

namespace clothsim::io {

std::string material_path(const std::string& dir, const std::string& save_name) {
  return (dir.empty() ? std::string(".") : dir) + "/" + save_name + ".mtl";
}

std::string format_material(const std::string& dir, const ClothInfo& cloth, const std::string& save_name) {
  namespace fs = std::filesystem;
  const fs::path texture = fs::absolute(cloth.texture).lexically_normal();
  const fs::path folder = fs::absolute(dir.empty() ? "." : dir).lexically_normal();
  fs::path rel = texture.lexically_relative(folder);
  if (rel.empty()) rel = texture;
  return "# clothsim material for cloth " + cloth.name + "\nnewmtl " + save_name +
         "\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nillum 1\nmap_Kd " + rel.generic_string() + "\n";
}

void write_material(const std::string& dir, const ClothInfo& cloth, const std::string& save_name) {
  if (cloth.texture.empty()) return;
  write_file_atomic(material_path(dir, save_name), format_material(dir, cloth, save_name));
}

}  // namespace clothsim::io
