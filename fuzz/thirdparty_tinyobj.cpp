// Instrumented third-party code, 3 of 3 (see fuzz/CMakeLists.txt): tinyobjloader from
// Debian's header (float build, like Debian's libtinyobjloader that multiray links).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
