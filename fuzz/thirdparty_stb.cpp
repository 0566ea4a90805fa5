// Instrumented third-party code, 1 of 3 (see fuzz/CMakeLists.txt): stb_image and
// stb_image_write from Debian's headers. Debian ships them compiled (libstb); these
// definitions, linked into each fuzz target, are the ones every call resolves to, so the
// image decoding behind glTF and MTL textures carries the fuzz build's coverage and
// sanitizer instrumentation.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image.h>
#include <stb_image_write.h>
