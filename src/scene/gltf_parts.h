// Stateless pieces of the glTF loader (load_gltf.cpp): bounds-checked accessor reading,
// node transforms and the image callback. Private to src/scene.
#pragma once

#include <tiny_gltf.h>

#include <cstring>
#include <initializer_list>
#include <string>

#include "core/math.h"

namespace multiray::detail {

// Checked view of an accessor's elements (see checked_accessor).
struct AccessorView {
  const unsigned char* base = nullptr;
  size_t stride = 0, count = 0;
  int type = 0, ncomp = 0;
  bool normalized = false;

  float get(size_t i, int c) const {
    const unsigned char* p = base + i * stride;
    auto as = [p, c](auto v) { return std::memcpy(&v, p + c * sizeof v, sizeof v), v; };
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return as(float());
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? as(uint8_t()) / 255.0f : float(as(uint8_t()));
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return normalized ? as(uint16_t()) / 65535.0f : float(as(uint16_t()));
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        return float(as(uint32_t()));
    }
    return 0.0f;
  }
  uint32_t index(size_t i) const {
    const unsigned char* p = base + i * stride;
    uint32_t v = 0;
    if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) v = *p;
    if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
      uint16_t s;
      std::memcpy(&s, p, 2);
      v = s;
    }
    if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) std::memcpy(&v, p, 4);
    return v;
  }
};

// The elements of accessor `index` of `model`, after checking that it exists, has type
// `want_type` with one of `component_types`, is not sparse, and that every element lies
// inside its bufferView and buffer. Throws InputError "<path>: <what> ...: problem".
AccessorView checked_accessor(const tinygltf::Model& model, int index, const std::string& what,
                              int want_type, std::initializer_list<int> component_types,
                              const std::string& path);

// A node's matrix, or its translation x rotation x scale.
Mat4 local_transform(const tinygltf::Node& n);
// Determinant of the upper 3x3 (negative: the transform mirrors).
float det3(const Mat4& a);

// tinygltf image callback: keeps the encoded bytes (as_is) for later decoding. Images
// in a bufferView whose range lies outside its buffer are dropped, because tinygltf
// hands us a pointer into the buffer without checking the range. Always succeeds.
bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void* user);

}  // namespace multiray::detail
