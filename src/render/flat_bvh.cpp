#include "render/flat_bvh.h"

#include <embree3/rtcore.h>

#include <memory>
#include <string>

#include "core/error.h"
#include "render/embree_device.h"

namespace multiray {

namespace {

// Embree's builder calls back to make nodes of our own choosing, allocated from its
// per-thread allocator and freed with the RTCBVH. One type serves both kinds of node.
struct BuildNode {
  BuildNode* child[2] = {nullptr, nullptr};  // interior only
  RTCBounds bounds[2];                       // interior only: the children's boxes
  uint32_t* prims = nullptr;                 // leaf only: scene triangle indices
  uint32_t count = 0;                        // leaf: > 0; interior: 0
};

void* create_node(RTCThreadLocalAllocator alloc, unsigned child_count, void*) {
  if (child_count != 2) return nullptr;  // maxBranchingFactor is 2
  return new (rtcThreadLocalAlloc(alloc, sizeof(BuildNode), 16)) BuildNode();
}

void set_children(void* node, void** children, unsigned count, void*) {
  for (unsigned i = 0; i < count && i < 2; ++i)
    static_cast<BuildNode*>(node)->child[i] = static_cast<BuildNode*>(children[i]);
}

void set_bounds(void* node, const RTCBounds** bounds, unsigned count, void*) {
  for (unsigned i = 0; i < count && i < 2; ++i)
    static_cast<BuildNode*>(node)->bounds[i] = *bounds[i];
}

void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count,
                  void*) {
  auto* leaf = new (rtcThreadLocalAlloc(alloc, sizeof(BuildNode), 16)) BuildNode();
  leaf->prims = static_cast<uint32_t*>(rtcThreadLocalAlloc(alloc, count * sizeof(uint32_t), 4));
  for (size_t i = 0; i < count; ++i) leaf->prims[i] = prims[i].primID;
  leaf->count = uint32_t(count);
  return leaf;
}

struct Flattener {
  const Scene& scene;
  FlatBvh& out;

  Vec3 vertex(uint32_t prim, int k) const { return scene.positions[scene.indices[3 * prim + k]]; }

  // Appends the leaf's triangles and returns its reference.
  uint32_t leaf(const BuildNode* node) {
    if (node->count > kMaxLeafTriangles)
      throw DeviceError("OpenCL BVH: a leaf holds more triangles than the kernel allows");
    const uint32_t first = uint32_t(out.triangles.size());
    for (uint32_t i = 0; i < node->count; ++i) {
      const uint32_t prim = node->prims[i];
      const Vec3 v0 = vertex(prim, 0), e1n = v0 - vertex(prim, 1), e2 = vertex(prim, 2) - v0;
      out.triangles.push_back(
          FlatTriangle{{v0.x, v0.y, v0.z}, prim, {e1n.x, e1n.y, e1n.z}, 0, {e2.x, e2.y, e2.z}, 0});
    }
    return kLeafBit | first << kLeafCountBits | (node->count - 1);
  }

  // Appends interior `node` and its subtree in depth-first order; returns its index.
  uint32_t interior(const BuildNode* node, int depth) {
    if (depth + 1 > kMaxBvhDepth)
      throw DeviceError("OpenCL BVH: tree deeper than the kernel's stack (" +
                        std::to_string(kMaxBvhDepth) + ")");
    out.depth = std::max(out.depth, depth + 1);
    const uint32_t index = uint32_t(out.nodes.size());
    out.nodes.emplace_back();
    for (int c = 0; c < 2; ++c) {
      const BuildNode* child = node->child[c];
      const uint32_t ref = child->count > 0 ? leaf(child) : interior(child, depth + 1);
      FlatNode& n = out.nodes[index];  // emplace_back above may have moved the array
      const RTCBounds& b = node->bounds[c];
      n.lo[c][0] = b.lower_x, n.lo[c][1] = b.lower_y, n.lo[c][2] = b.lower_z;
      n.hi[c][0] = b.upper_x, n.hi[c][1] = b.upper_y, n.hi[c][2] = b.upper_z;
      n.child[c] = ref;
    }
    return index;
  }
};

}  // namespace

FlatBvh build_flat_bvh(const Scene& scene) {
  // Build primitives: the box of every triangle that can be hit.
  std::vector<RTCBuildPrimitive> prims;
  prims.reserve(scene.triangle_count());
  RTCBounds bounds{INFINITY, INFINITY, INFINITY, 0, -INFINITY, -INFINITY, -INFINITY, 0};
  for (uint32_t t = 0; t < scene.triangle_count(); ++t) {
    const Vec3 a = scene.positions[scene.indices[3 * t]],
               b = scene.positions[scene.indices[3 * t + 1]],
               c = scene.positions[scene.indices[3 * t + 2]];
    const Vec3 n = cross(b - a, c - a);
    if (n.x == 0 && n.y == 0 && n.z == 0) continue;  // zero area: never hit
    const Vec3 lo = min(a, min(b, c)), hi = max(a, max(b, c));
    prims.push_back(RTCBuildPrimitive{lo.x, lo.y, lo.z, 0, hi.x, hi.y, hi.z, t});
    bounds.lower_x = std::min(bounds.lower_x, lo.x),
    bounds.upper_x = std::max(bounds.upper_x, hi.x);
    bounds.lower_y = std::min(bounds.lower_y, lo.y),
    bounds.upper_y = std::max(bounds.upper_y, hi.y);
    bounds.lower_z = std::min(bounds.lower_z, lo.z),
    bounds.upper_z = std::max(bounds.upper_z, hi.z);
  }
  if (prims.empty()) throw DeviceError("OpenCL BVH: the scene has no triangle of non-zero area");
  if (prims.size() >= kMaxFlatTriangles)
    throw DeviceError("OpenCL BVH: more than " + std::to_string(kMaxFlatTriangles) +
                      " triangles, the kernel's limit");

  std::unique_ptr<RTCDeviceTy, void (*)(RTCDevice)> device(new_embree_device(), rtcReleaseDevice);
  if (!device) throw DeviceError("OpenCL BVH: cannot create an Embree device");
  std::unique_ptr<RTCBVHTy, void (*)(RTCBVH)> bvh(rtcNewBVH(device.get()), rtcReleaseBVH);

  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;  // binned SAH, no spatial splits
  args.maxBranchingFactor = 2;
  args.maxDepth = kMaxBvhDepth - 2;
  args.minLeafSize = 1;
  // Small leaves: in the kernel a triangle test costs about two box tests, and the SAH
  // weights below make the builder stop splitting where that pays off.
  args.maxLeafSize = 8;  // <= kMaxLeafTriangles
  args.traversalCost = 1.0f;
  args.intersectionCost = 2.0f;
  args.bvh = bvh.get();
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  args.primitiveArrayCapacity = prims.size();
  args.createNode = create_node;
  args.setNodeChildren = set_children;
  args.setNodeBounds = set_bounds;
  args.createLeaf = create_leaf;
  const auto* top = static_cast<const BuildNode*>(rtcBuildBVH(&args));
  if (!top || rtcGetDeviceError(device.get()) != RTC_ERROR_NONE)
    throw DeviceError("OpenCL BVH: Embree's rtcBuildBVH failed");

  FlatBvh out;
  out.nodes.reserve(prims.size());
  out.triangles.reserve(prims.size());
  Flattener flat{scene, out};
  if (top->count > 0) {
    // A single leaf: a root whose two children are that leaf (tested twice, harmless),
    // since nodes only hold children.
    const uint32_t ref = flat.leaf(top);
    FlatNode root{};
    for (int c = 0; c < 2; ++c) {
      root.lo[c][0] = bounds.lower_x, root.lo[c][1] = bounds.lower_y,
      root.lo[c][2] = bounds.lower_z;
      root.hi[c][0] = bounds.upper_x, root.hi[c][1] = bounds.upper_y,
      root.hi[c][2] = bounds.upper_z;
      root.child[c] = ref;
    }
    out.nodes.push_back(root);
    out.depth = 1;
  } else {
    flat.interior(top, 0);
  }
  return out;
}

}  // namespace multiray
