#pragma once
// Writes small PNG files at test time (8 or 16 bits, grey or RGB), so the map tests need no image on disk.
// Deflate "stored" blocks keep the encoder a few lines long; stb_image reads them like any other PNG.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace clothsim::test {

inline std::uint32_t png_crc(const std::string& bytes) {
  std::uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

inline void put_be32(std::string& s, std::uint32_t v) {
  for (int k = 3; k >= 0; --k) s += char((v >> (8 * k)) & 0xff);
}

inline void png_chunk(std::string& png, const char* type, const std::string& data) {
  put_be32(png, std::uint32_t(data.size()));
  const std::string body = type + data;
  png += body;
  put_be32(png, png_crc(body));
}

inline std::string png_signature_and_header(int width, int height, int channels, int bits) {
  std::string png = "\x89PNG\r\n\x1a\n", ihdr;
  put_be32(ihdr, width);
  put_be32(ihdr, height);
  ihdr += char(bits); ihdr += char(channels == 3 ? 2 : 0);
  ihdr += std::string(3, '\0');
  png_chunk(png, "IHDR", ihdr);
  return png;
}

// samples: row-major from the top row, `channels` (1 grey, 3 RGB) per pixel, each < 2^bits.
inline std::string encode_png(int width, int height, int channels, int bits, const std::vector<std::uint16_t>& samples) {
  std::string raw;
  for (int j = 0; j < height; ++j) {
    raw += char(0);  // filter: none
    for (int i = 0; i < width * channels; ++i) {
      const std::uint16_t s = samples[std::size_t(j) * width * channels + i];
      if (bits == 16) raw += char(s >> 8);
      raw += char(s & 0xff);
    }
  }
  std::string z = "\x78\x01";
  for (std::size_t off = 0; off < raw.size() || off == 0; off += 65535) {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - off);
    z += char(off + n >= raw.size() ? 1 : 0);
    z += char(n & 0xff); z += char(n >> 8);
    z += char(~n & 0xff); z += char((~n >> 8) & 0xff);
    z += raw.substr(off, n);
    if (n == 0) break;
  }
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : raw) { a = (a + c) % 65521; b = (b + a) % 65521; }
  put_be32(z, (b << 16) | a);

  std::string png = png_signature_and_header(width, height, channels, bits);
  png_chunk(png, "IDAT", z);
  png_chunk(png, "IEND", "");
  return png;
}

// A PNG with a header and no pixel data: what a hostile file claiming a huge image looks like (45 bytes).
inline std::string encode_png_header_only(int width, int height) {
  std::string png = png_signature_and_header(width, height, 1, 8);
  png_chunk(png, "IEND", "");
  return png;
}

inline void write_png(const std::filesystem::path& path, int width, int height, int channels, int bits,
                      const std::vector<std::uint16_t>& samples) {
  std::ofstream(path, std::ios::binary) << encode_png(width, height, channels, bits, samples);
}

// An 8-bit grey image of one value.
inline void write_constant_png(const std::filesystem::path& path, int width, int height, std::uint16_t grey) {
  write_png(path, width, height, 1, 8, std::vector<std::uint16_t>(std::size_t(width) * height, grey));
}

}  // namespace clothsim::test
