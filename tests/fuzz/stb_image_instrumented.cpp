// stb_image compiled into the image-map fuzz target, so the decoder itself carries the fuzzer's coverage and
// the sanitizers: Debian's prebuilt libstb.so is not instrumented, and the executable's definitions of the
// stbi_* functions take precedence over the shared library's.
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
