// Instrumented third-party code, 2 of 3 (see fuzz/CMakeLists.txt): tinygltf from Debian's
// header, which Debian otherwise ships compiled (libtinygltf). stb comes from
// thirdparty_stb.cpp.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#include <stb_image.h>
#include <stb_image_write.h>
#include <tiny_gltf.h>
