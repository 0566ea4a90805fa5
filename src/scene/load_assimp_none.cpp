// load_assimp() of a build without assimp (MULTIRAY_WITH_ASSIMP=OFF, or AUTO without
// libassimp-dev): the formats only assimp reads are refused with one line.
#include "scene/loaders.h"

namespace multiray {

Scene load_assimp(const std::string& path, const LoadOptions&) {
  detail::fail(path,
               "this multiray was built without assimp, which reads this format "
               "(install libassimp-dev and rebuild)");
}

}  // namespace multiray
