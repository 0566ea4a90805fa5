#include "render/accel.h"

#include <algorithm>
#include <cmath>

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <cstring>
#include <string>

#include "core/error.h"
#include "render/compact_accel.h"
#include "render/embree_device.h"
#include "render/shared/surface.h"
#include "render/surface.h"

namespace multiray {

void set_fast_float_mode() {
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

namespace {

// Embree filter for cut-out materials; geometryUserPtr is the Scene.
void alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto* scene = static_cast<const Scene*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    const Material& m = scene->materials[scene->material_ids[prim]];
    if (!m.may_be_transparent()) continue;
    const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    Vec2 uv{};
    if (!scene->uvs.empty()) {
      const uint32_t* idx = &scene->indices[3 * size_t(prim)];
      const Vec2 a = scene->uvs[idx[0]], b = scene->uvs[idx[1]], c = scene->uvs[idx[2]];
      const float w = 1.0f - u - v;
      uv = Vec2{a.x * w + b.x * u + c.x * v, a.y * w + b.y * u + c.y * v};
    }
    const float key[6] = {
        RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
        RTCRayN_org_z(args->ray, args->N, i), RTCRayN_dir_x(args->ray, args->N, i),
        RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i)};
    if (passes_through(*scene, m, uv, multiray::cutout_hash(key, prim))) args->valid[i] = 0;
  }
}

}  // namespace

float cutout_hash(const Ray& ray, uint32_t prim) {
  const float key[6] = {ray.org.x, ray.org.y, ray.org.z, ray.dir.x, ray.dir.y, ray.dir.z};
  return cutout_hash(key, prim);
}

Accel::Accel(const Scene& scene, const CompactScene* compact) : compact_(compact) {
  const bool any_cutout = std::any_of(scene.materials.begin(), scene.materials.end(),
                                      [](const Material& m) { return m.may_be_transparent(); });
  if (compact_) {
    if (any_cutout) cutouts_ = &scene;
    return;
  }
  device_ = new_embree_device();
  if (!device_) throw DeviceError("Embree: cannot create a device");
  // Embree reports every allocation of this device (the BVH and its vertex copies).
  rtcSetDeviceMemoryMonitorFunction(
      device_,
      [](void* user, ssize_t bytes, bool) {
        *static_cast<std::atomic<int64_t>*>(user) += int64_t(bytes);
        return true;
      },
      &embree_bytes_);
  scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree reads vertices with 16-byte loads, so its buffers (allocated here) are padded;
  // the Scene's own arrays are not, so they are copied.
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                              3 * sizeof(float), scene.positions.size()));
  auto* indices = static_cast<uint32_t*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(uint32_t), scene.triangle_count()));
  if (!vertices || !indices) throw DeviceError("Embree: out of memory for the scene buffers");
  std::memcpy(vertices, scene.positions.data(), scene.positions.size() * sizeof(Vec3));
  std::memcpy(indices, scene.indices.data(), scene.indices.size() * sizeof(uint32_t));
  if (any_cutout) {
    cutouts_ = &scene;
    rtcSetGeometryUserData(geom, const_cast<Scene*>(&scene));
    rtcSetGeometryIntersectFilterFunction(geom, alpha_filter);
    rtcSetGeometryOccludedFilterFunction(geom, alpha_filter);
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene_, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene_);
  if (rtcGetDeviceError(device_) != RTC_ERROR_NONE)
    throw DeviceError("Embree: building the BVH failed");
}

Accel::~Accel() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

bool Accel::intersect(const Ray& ray, Hit& hit) const {
  if (compact_) return compact_intersect(*compact_, cutouts_, ray, hit);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = ray.org.x, rh.ray.org_y = ray.org.y, rh.ray.org_z = ray.org.z;
  rh.ray.dir_x = ray.dir.x, rh.ray.dir_y = ray.dir.y, rh.ray.dir_z = ray.dir.z;
  rh.ray.tnear = ray.tmin;
  rh.ray.tfar = ray.tmax;
  rh.ray.time = 0;
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  // A ray grazing a plane can come back with a NaN distance (Embree divides by a
  // denormal); counted as a miss, so no later ray starts from a NaN point (fuzz finding F1).
  if (!std::isfinite(rh.ray.tfar)) return false;
  hit.t = rh.ray.tfar;
  hit.prim = rh.hit.primID;
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  hit.ng = Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  return true;
}

bool Accel::occluded(const Ray& ray) const {
  if (compact_) return compact_occluded(*compact_, cutouts_, ray);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  r.org_x = ray.org.x, r.org_y = ray.org.y, r.org_z = ray.org.z;
  r.dir_x = ray.dir.x, r.dir_y = ray.dir.y, r.dir_z = ray.dir.z;
  r.tnear = ray.tmin;
  r.tfar = ray.tmax;
  r.time = 0;
  r.mask = ~0u;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(scene_, &ctx, &r);
  return r.tfar < 0.0f;
}

void Accel::occluded_batch(const Ray* rays, size_t n, uint8_t* blocked) const {
  if (compact_) {
    for (size_t i = 0; i < n; ++i) blocked[i] = compact_occluded(*compact_, cutouts_, rays[i]);
    return;
  }
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  for (size_t first = 0; first < n; first += 8) {
    const size_t count = std::min<size_t>(8, n - first);
    alignas(32) int valid[8];
    alignas(32) RTCRay8 r;
    for (size_t k = 0; k < 8; ++k) {
      const Ray& ray = rays[first + (k < count ? k : 0)];  // idle lanes repeat a live ray
      valid[k] = k < count ? -1 : 0;
      r.org_x[k] = ray.org.x, r.org_y[k] = ray.org.y, r.org_z[k] = ray.org.z;
      r.dir_x[k] = ray.dir.x, r.dir_y[k] = ray.dir.y, r.dir_z[k] = ray.dir.z;
      r.tnear[k] = ray.tmin, r.tfar[k] = ray.tmax, r.time[k] = 0;
      r.mask[k] = ~0u, r.id[k] = 0, r.flags[k] = 0;
    }
    rtcOccluded8(valid, scene_, &ctx, &r);
    for (size_t k = 0; k < count; ++k) blocked[first + k] = r.tfar[k] < 0.0f;
  }
}

}  // namespace multiray
