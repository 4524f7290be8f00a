#pragma once
// Grey-scale maps for per-vertex parameters: images read through stb_image (PNG, JPEG, TGA, BMP; 8 or 16 bits
// per channel), colour reduced to Rec. 709 luminance, sampled bilinearly by UV. Conventions (docs/maps.md):
// v runs bottom to top as in OBJ, so v = 0 is the image's last row; texel centres sit at ((i + 0.5)/W,
// (j + 0.5)/H); filtering clamps at the image border; coordinates outside [0, 1] wrap (t - floor t).
#include <string>
#include <vector>

#include "core/math.h"

namespace clothsim::io {

struct GreyImage {
  int width = 0, height = 0;
  int bits = 8;                // bits per channel in the file (8 or 16)
  std::vector<double> grey;    // luminance in [0, 1], row 0 at the top (width * height)
};

// Throws Error(path, ...) for a missing, unreadable, empty, truncated or unsupported image.
GreyImage read_grey_image(const std::string& path);

// Bilinear grey level in [0, 1] at texture coordinate uv.
Real sample_grey(const GreyImage& image, const Vec2& uv);

}  // namespace clothsim::io
