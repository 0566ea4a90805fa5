#include "render/embree_device.h"

#include <cstdlib>

namespace multiray {

RTCDevice new_embree_device() {
  const char* config = std::getenv("MULTIRAY_EMBREE_CONFIG");
  return rtcNewDevice(config && *config ? config : nullptr);
}

}  // namespace multiray
