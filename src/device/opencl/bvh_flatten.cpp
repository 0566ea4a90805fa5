#include "device/opencl/bvh_flatten.h"

#include <embree3/rtcore.h>

#include <memory>
#include <string>

#include "core/error.h"

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

  // Appends `node` (whose box is `b`) and its subtree in depth-first order.
  void emit(const BuildNode* node, const RTCBounds& b, int depth) {
    if (depth + 1 > kMaxBvhDepth)
      throw DeviceError("OpenCL BVH: tree deeper than the kernel's stack (" +
                        std::to_string(kMaxBvhDepth) + ")");
    out.depth = std::max(out.depth, depth + 1);
    const size_t index = out.nodes.size();
    out.nodes.push_back(
        FlatNode{{b.lower_x, b.lower_y, b.lower_z}, 0, {b.upper_x, b.upper_y, b.upper_z}, 0});
    if (node->count > 0) {
      out.nodes[index].offset = uint32_t(out.triangles.size());
      out.nodes[index].count = node->count;
      for (uint32_t i = 0; i < node->count; ++i) {
        const uint32_t prim = node->prims[i];
        const Vec3 v0 = vertex(prim, 0), e1 = vertex(prim, 1) - v0, e2 = vertex(prim, 2) - v0;
        out.triangles.push_back(
            FlatTriangle{{v0.x, v0.y, v0.z}, prim, {e1.x, e1.y, e1.z}, 0, {e2.x, e2.y, e2.z}, 0});
      }
      return;
    }
    emit(node->child[0], node->bounds[0], depth + 1);
    out.nodes[index].offset = uint32_t(out.nodes.size());
    emit(node->child[1], node->bounds[1], depth + 1);
  }
};

}  // namespace

FlatBvh build_flat_bvh(const Scene& scene) {
  // Build primitives: the box of every triangle that can be hit.
  std::vector<RTCBuildPrimitive> prims;
  prims.reserve(scene.triangle_count());
  RTCBounds root{INFINITY, INFINITY, INFINITY, 0, -INFINITY, -INFINITY, -INFINITY, 0};
  for (uint32_t t = 0; t < scene.triangle_count(); ++t) {
    const Vec3 a = scene.positions[scene.indices[3 * t]],
               b = scene.positions[scene.indices[3 * t + 1]],
               c = scene.positions[scene.indices[3 * t + 2]];
    const Vec3 n = cross(b - a, c - a);
    if (n.x == 0 && n.y == 0 && n.z == 0) continue;  // zero area: never hit
    const Vec3 lo = min(a, min(b, c)), hi = max(a, max(b, c));
    prims.push_back(RTCBuildPrimitive{lo.x, lo.y, lo.z, 0, hi.x, hi.y, hi.z, t});
    root.lower_x = std::min(root.lower_x, lo.x), root.upper_x = std::max(root.upper_x, hi.x);
    root.lower_y = std::min(root.lower_y, lo.y), root.upper_y = std::max(root.upper_y, hi.y);
    root.lower_z = std::min(root.lower_z, lo.z), root.upper_z = std::max(root.upper_z, hi.z);
  }
  if (prims.empty()) throw DeviceError("OpenCL BVH: the scene has no triangle of non-zero area");

  std::unique_ptr<RTCDeviceTy, void (*)(RTCDevice)> device(rtcNewDevice(nullptr),
                                                           rtcReleaseDevice);
  if (!device) throw DeviceError("OpenCL BVH: cannot create an Embree device");
  std::unique_ptr<RTCBVHTy, void (*)(RTCBVH)> bvh(rtcNewBVH(device.get()), rtcReleaseBVH);

  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;  // binned SAH, no spatial splits
  args.maxBranchingFactor = 2;
  args.maxDepth = kMaxBvhDepth - 2;
  args.minLeafSize = 1;
  // Small leaves: in the kernel a triangle test costs about two box tests, and the SAH
  // weights below make the builder stop splitting where that pays off.
  args.maxLeafSize = 8;
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
  out.nodes.reserve(2 * prims.size());
  out.triangles.reserve(prims.size());
  Flattener{scene, out}.emit(top, root, 0);
  return out;
}

}  // namespace multiray
