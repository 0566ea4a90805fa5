// Ray queries against the compact scene (compact_scene.h) on the CPU: the traversal the
// OpenCL kernel runs with compact=1 (device/opencl/kernels/traverse_compact.cl), in C++.
// Child boxes are decoded from their parent's box on the way down (so the stack holds
// boxes), triangles from the quantized positions at each leaf test. Hits carry the same
// fields as Embree's (accel.h), the geometric normal computed as Embree computes it.
#pragma once

#include "render/accel.h"
#include "render/compact_scene.h"

namespace multiray {

// `cutouts` is the scene whose materials and textures decide alpha cut-outs (as the
// Embree filter does), or null when no material has an alpha mode.
bool compact_intersect(const CompactScene& c, const Scene* cutouts, const Ray& ray, Hit& hit);
bool compact_occluded(const CompactScene& c, const Scene* cutouts, const Ray& ray);

}  // namespace multiray
