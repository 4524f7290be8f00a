#include "io/texture_map.h"

#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>

#include "core/error.h"
#include "core/limits.h"
#include "io/text_file.h"

namespace clothsim::io {
namespace {

// Rec. 709 luma weights, applied to the stored (gamma-encoded) values: a painter's grey 128 reads as 128.
double luminance(const double* c, int channels) {
  if (channels < 3) return c[0];  // grey, or grey + alpha
  return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

Real wrap(Real t) { return t >= 0 && t <= 1 ? t : t - std::floor(t); }

// Codes in the largest JPEG Huffman table (DHT segment) of the file, 0 for a file that is not a JPEG. Debian's
// stb_image trusts a table's 16 code counts, and more than 256 codes overrun its 257-entry arrays (found by
// fuzz_texture_reader: tests/fuzz/texture/crash-jpeg-huffman-*.jpg). Every FF C4 is read as stb would
// meet it, header or between scans: entropy-coded data stuffs FF with 00, so a valid file has no other.
int largest_jpeg_huffman_table(const std::string& b) {
  // stb reads a byte past the end of the file as 0; so does this.
  const auto at = [&](std::size_t i) { return i < b.size() ? static_cast<unsigned char>(b[i]) : 0; };
  // stb takes a JPEG from its start-of-image marker FF D8, after any number of FF fill bytes.
  std::size_t start = 0;
  while (start < b.size() && at(start) == 0xFF) ++start;
  if (start == 0 || at(start) != 0xD8) return 0;
  int largest = 0;
  for (std::size_t pos = start + 1; pos + 2 <= b.size(); ++pos) {
    if (at(pos) != 0xFF || at(pos + 1) != 0xC4) continue;
    long left = long(at(pos + 2)) * 256 + at(pos + 3) - 2;
    std::size_t p = pos + 4;
    while (left > 0 && p < b.size()) {
      int codes = 0;
      for (int i = 1; i <= 16; ++i) codes += at(p + i);
      largest = std::max(largest, codes);
      p += 17 + codes;
      left -= 17 + codes;
    }
  }
  return largest;
}

// The name of an image format that stb_image decodes but clothsim does not read (GIF, PSD, PIC, PNM, HDR), from
// the magic bytes stb's own tests look for; "" otherwise. Refusing them here keeps stb's less-used decoders
// away from hostile files: the documented formats are PNG, JPEG, TGA and BMP (docs/maps.md).
std::string unsupported_format(const std::string& b) {
  const auto starts = [&](const char* magic, std::size_t n) { return b.compare(0, n, magic, n) == 0; };
  if (starts("GIF8", 4)) return "GIF";
  if (starts("8BPS", 4)) return "Photoshop (PSD)";
  if (starts("\x53\x80\xF6\x34", 4)) return "Softimage PIC";
  if (starts("P5", 2) || starts("P6", 2)) return "PNM";
  if (starts("#?RADIANCE", 10) || starts("#?RGBE", 6)) return "Radiance HDR";
  return "";
}

// The first PNG chunk, in stb's reading order, whose declared length runs past the end of the file; "" when
// every chunk up to IEND (or the end) fits, or the file is not a PNG. Debian's stb_image grows its IDAT buffer
// to a chunk's declared length (doubling) before reading it, so a 100-byte file declaring a 1.7 GB IDAT
// allocated 2 GiB (found by fuzz_texture_reader: tests/fuzz/texture/crash-png-idat-length-past-end.png).
// A chunk is length (4, big-endian), type (4), data (length), CRC (4).
std::string png_chunk_past_end(const std::string& b) {
  static const std::string signature = "\x89PNG\r\n\x1a\n";
  if (b.compare(0, signature.size(), signature) != 0) return "";
  std::size_t pos = signature.size();
  while (pos + 8 <= b.size()) {
    std::uint64_t length = 0;
    for (int k = 0; k < 4; ++k) length = length * 256 + static_cast<unsigned char>(b[pos + k]);
    const std::string type = b.substr(pos + 4, 4);
    if (pos + 12 + length > b.size())
      return "chunk " + type + " at byte " + std::to_string(pos) + " declares " + std::to_string(length) +
             " bytes of data, past the end of the file (" + std::to_string(b.size()) + " bytes)";
    if (type == "IEND") return "";
    pos += 12 + length;
  }
  return "";
}

// stb_image's reason for a failed decode; some of its paths leave it empty (a PNG cut short inside its
// compressed data), and an empty pair of brackets tells the user nothing.
std::string decode_failure() {
  const char* why = stbi_failure_reason();
  return why && *why ? std::string(why) + ": the file is truncated or corrupt" : "the file is truncated or corrupt";
}

}  // namespace

GreyImage read_grey_image(const std::string& path) {
  const std::string what = "a PNG, JPEG, TGA or BMP image with 8 or 16 bits per channel", expected = "; expected " + what;
  // read_text_file checks the file size before reading (a hostile image need not be small); the header's
  // pixel count is checked below before stb allocates anything for the pixels: a 20000 x 20000 header would
  // otherwise cost 400 MB to decode and 3.2 GB of grey levels.
  const std::string bytes = read_text_file(path, what);
  if (bytes.size() > std::size_t(std::numeric_limits<int>::max()))
    throw Error(path, "file of " + std::to_string(bytes.size()) + " bytes is too large for the image reader" + expected);
  if (bytes.empty()) throw Error(path, "empty file" + expected);
  if (const int codes = largest_jpeg_huffman_table(bytes); codes > 256)
    throw Error(path, "JPEG Huffman table of " + std::to_string(codes) +
                          " codes, more than a table holds (256): the file is corrupt" + expected);
  if (const std::string format = unsupported_format(bytes); !format.empty())
    throw Error(path, format + " image, a format clothsim does not read" + expected);
  if (const std::string chunk = png_chunk_past_end(bytes); !chunk.empty())
    throw Error(path, "PNG " + chunk + ": the file is truncated or corrupt" + expected);
  const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
  const int size = static_cast<int>(bytes.size());

  GreyImage img;
  int channels = 0;
  if (!stbi_info_from_memory(data, size, &img.width, &img.height, &channels))
    throw Error(path, "cannot decode the image (" + decode_failure() + ")" + expected);
  if (std::int64_t(img.width) * img.height > limits::max_image_pixels)
    throw Error(path, "image of " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                          " pixels; expected at most " + std::to_string(limits::max_image_pixels) +
                          " pixels (docs/errors.md)");
  // No format we read packs more than 8 * 1032 pixels into a byte (1-bit PNG rows under deflate's largest
  // ratio; JPEG needs a bit per 8 x 8 block, RLE TGA a byte per 128 pixels). More pixels than that is a
  // truncated or forged file that stb would decode from zeros past its end, for as long as the header says
  // (fuzz_texture_reader: a 58-byte BMP claiming 3 x 16187137 pixels took over 10 s).
  constexpr std::int64_t max_pixels_per_byte = 8 * 1032;
  if (std::int64_t(img.width) * img.height > max_pixels_per_byte * std::int64_t(bytes.size()))
    throw Error(path, "image of " + std::to_string(img.width) + " x " + std::to_string(img.height) + " pixels in " +
                          std::to_string(bytes.size()) + " bytes, more than any image format packs (8256 pixels a " +
                          "byte): the file is truncated or corrupt" + expected);
  img.bits = stbi_is_16_bit_from_memory(data, size) ? 16 : 8;
  void* pixels = img.bits == 16 ? static_cast<void*>(stbi_load_16_from_memory(data, size, &img.width, &img.height, &channels, 0))
                                : static_cast<void*>(stbi_load_from_memory(data, size, &img.width, &img.height, &channels, 0));
  if (!pixels) throw Error(path, "cannot decode the image (" + decode_failure() + ")" + expected);
  std::unique_ptr<void, void (*)(void*)> owner(pixels, stbi_image_free);
  if (img.width <= 0 || img.height <= 0) throw Error(path, "image has no pixels" + expected);

  const std::size_t n = std::size_t(img.width) * img.height;
  const double scale = img.bits == 16 ? 1.0 / 65535 : 1.0 / 255;
  img.grey.resize(n);
  double c[4];
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < channels; ++k)
      c[k] = img.bits == 16 ? static_cast<const stbi_us*>(pixels)[i * channels + k]
                            : static_cast<const stbi_uc*>(pixels)[i * channels + k];
    img.grey[i] = std::clamp(luminance(c, channels) * scale, 0.0, 1.0);
  }
  return img;
}

Real sample_grey(const GreyImage& im, const Vec2& uv) {
  const Real x = std::clamp(wrap(uv[0]) * im.width - 0.5, 0.0, Real(im.width - 1));
  const Real y = std::clamp((1 - wrap(uv[1])) * im.height - 0.5, 0.0, Real(im.height - 1));
  const int x0 = int(x), y0 = int(y);
  const int x1 = std::min(x0 + 1, im.width - 1), y1 = std::min(y0 + 1, im.height - 1);
  const Real fx = x - x0, fy = y - y0;
  auto at = [&](int i, int j) { return im.grey[std::size_t(j) * im.width + i]; };
  // a + f (b - a) rather than (1 - f) a + f b: equal texels give their value exactly, so a constant map
  // reproduces a scalar parameter bit for bit.
  auto mix = [](Real a, Real b, Real f) { return a + f * (b - a); };
  return mix(mix(at(x0, y0), at(x1, y0), fx), mix(at(x0, y1), at(x1, y1), fx), fy);
}

}  // namespace clothsim::io
