#include "distributed/scene_codec.h"

#include <cmath>

#include "core/error.h"
#include "distributed/wire.h"
#include "volume/volume.h"

namespace multiray::remote {

namespace {

constexpr uint32_t kSceneMagic = 0x4d52534eu;  // "MRSN"

void put_camera(ByteWriter& w, const Camera& c) {
  w.put(c.eye), w.put(c.target), w.put(c.up), w.put(c.fov_y_deg);
  w.put(int32_t(c.film_width)), w.put(int32_t(c.film_height));
}

Camera get_camera(ByteReader& r) {
  Camera c;
  c.eye = r.get<Vec3>(), c.target = r.get<Vec3>(), c.up = r.get<Vec3>();
  c.fov_y_deg = r.get<float>();
  c.film_width = r.get<int32_t>(), c.film_height = r.get<int32_t>();
  return c;
}

void put_material(ByteWriter& w, const Material& m) {
  w.put_string(m.name);
  w.put(m.base_color), w.put(int32_t(m.base_color_texture)), w.put(m.emission);
  w.put(int32_t(m.emission_texture)), w.put(m.metallic), w.put(m.roughness);
  w.put(int32_t(m.metallic_roughness_texture)), w.put(int32_t(m.normal_texture));
  w.put(m.normal_scale), w.put(m.opacity), w.put(uint8_t(m.alpha_mode)), w.put(m.alpha_cutoff);
  w.put(m.transmission), w.put(m.ior);
}

Material get_material(ByteReader& r, size_t textures) {
  Material m;
  m.name = r.get_string();
  m.base_color = r.get<Vec3>(), m.base_color_texture = r.get<int32_t>();
  m.emission = r.get<Vec3>(), m.emission_texture = r.get<int32_t>();
  m.metallic = r.get<float>(), m.roughness = r.get<float>();
  m.metallic_roughness_texture = r.get<int32_t>(), m.normal_texture = r.get<int32_t>();
  m.normal_scale = r.get<float>(), m.opacity = r.get<float>();
  const uint8_t mode = r.get<uint8_t>();
  if (mode > uint8_t(AlphaMode::blend)) throw WireError("unknown alpha mode");
  m.alpha_mode = AlphaMode(mode);
  m.alpha_cutoff = r.get<float>(), m.transmission = r.get<float>(), m.ior = r.get<float>();
  for (int t :
       {m.base_color_texture, m.emission_texture, m.metallic_roughness_texture, m.normal_texture})
    if (t < -1 || t >= int64_t(textures)) throw WireError("material names a missing texture");
  return m;
}

void put_texture(ByteWriter& w, const Texture& t) {
  w.put(int32_t(t.width)), w.put(int32_t(t.height)), w.put(uint8_t(t.coding));
  w.put_array(t.texels);
}

Texture get_texture(ByteReader& r) {
  Texture t;
  t.width = r.get<int32_t>(), t.height = r.get<int32_t>();
  const uint8_t coding = r.get<uint8_t>();
  if (coding > uint8_t(TexelCoding::signed_unit)) throw WireError("unknown texel coding");
  t.coding = TexelCoding(coding);
  t.texels = r.get_array<uint32_t>();
  if (t.width < 0 || t.height < 0 || int64_t(t.width) * t.height != int64_t(t.texels.size()))
    throw WireError("texture size does not match its texels");
  return t;
}

void put_volume(ByteWriter& w, const Volume& v) {
  w.put_string(v.name);
  w.put(int32_t(v.nx)), w.put(int32_t(v.ny)), w.put(int32_t(v.nz)), w.put(v.spacing);
  w.put(uint8_t(v.type)), w.put_array(v.values), w.put(v.min_value), w.put(v.max_value);
  w.put(v.orientation.anterior), w.put(v.orientation.superior);
  w.put(uint8_t(v.orientation.from_file));
}

std::shared_ptr<const Volume> get_volume(ByteReader& r) {
  auto v = std::make_shared<Volume>();
  v->name = r.get_string();
  v->nx = r.get<int32_t>(), v->ny = r.get<int32_t>(), v->nz = r.get<int32_t>();
  v->spacing = r.get<Vec3>();
  const uint8_t type = r.get<uint8_t>();
  if (type > uint8_t(VoxelType::i16)) throw WireError("unknown voxel type");
  v->type = VoxelType(type);
  v->values = r.get_array<float>();
  v->min_value = r.get<float>(), v->max_value = r.get<float>();
  v->orientation.anterior = r.get<Vec3>(), v->orientation.superior = r.get<Vec3>();
  v->orientation.from_file = r.get<uint8_t>() != 0;
  for (Vec3 axis : {v->orientation.anterior, v->orientation.superior}) {
    const Vec3 a{std::abs(axis.x), std::abs(axis.y), std::abs(axis.z)};
    if (a.x + a.y + a.z != 1.0f || max_component(a) != 1.0f)
      throw WireError("volume orientation is not a signed world axis");
  }
  for (int n : {v->nx, v->ny, v->nz})
    if (n < 1 || n > kMaxVolumeDimension) throw WireError("volume size out of range");
  if (v->values.size() != v->voxel_count()) throw WireError("volume size does not match");
  if (!(v->spacing.x > 0 && v->spacing.y > 0 && v->spacing.z > 0))
    throw WireError("volume spacing out of range");
  return v;
}

}  // namespace

std::vector<uint8_t> encode_scene(const Scene& s) {
  ByteWriter w;
  w.put(kSceneMagic);
  w.put_string(s.name);
  w.put_array(s.positions), w.put_array(s.normals), w.put_array(s.uvs);
  w.put_array(s.indices), w.put_array(s.material_ids);
  w.put(uint64_t(s.textures.size()));
  for (const Texture& t : s.textures) put_texture(w, t);
  w.put(uint64_t(s.materials.size()));
  for (const Material& m : s.materials) put_material(w, m);
  w.put(s.environment), w.put(s.environment_map_scale), w.put(s.up);
  w.put(uint8_t(s.environment_map != nullptr));
  if (s.environment_map) {
    w.put_string(s.environment_map->name);
    w.put(int32_t(s.environment_map->width)), w.put(int32_t(s.environment_map->height));
    w.put_array(s.environment_map->radiance);
  }
  w.put(s.sun.direction), w.put(s.sun.radiance), w.put(s.sun.half_angle_rad);
  w.put(uint64_t(s.cameras.size()));
  for (const Camera& c : s.cameras) put_camera(w, c);
  w.put(uint8_t(s.volume != nullptr));
  if (s.volume) put_volume(w, *s.volume);
  return w.take();
}

Scene decode_scene(const std::vector<uint8_t>& bytes) {
  ByteReader r(bytes);
  if (r.get<uint32_t>() != kSceneMagic) throw WireError("not a scene");
  Scene s;
  s.name = r.get_string();
  s.positions = r.get_array<Vec3>(), s.normals = r.get_array<Vec3>();
  s.uvs = r.get_array<Vec2>();
  s.indices = r.get_array<uint32_t>(), s.material_ids = r.get_array<uint32_t>();
  for (uint64_t n = r.count(9); n > 0; --n) s.textures.push_back(get_texture(r));
  for (uint64_t n = r.count(8); n > 0; --n)
    s.materials.push_back(get_material(r, s.textures.size()));
  s.environment = r.get<Vec3>(), s.environment_map_scale = r.get<float>(), s.up = r.get<Vec3>();
  if (r.get<uint8_t>()) {
    auto map = std::make_shared<EnvironmentMap>();
    map->name = r.get_string();
    map->width = r.get<int32_t>(), map->height = r.get<int32_t>();
    map->radiance = r.get_array<Vec3>();
    if (map->width < 1 || map->height < 1 ||
        int64_t(map->width) * map->height != int64_t(map->radiance.size()))
      throw WireError("environment map size does not match");
    s.environment_map = map;
  }
  s.sun.direction = r.get<Vec3>(), s.sun.radiance = r.get<Vec3>();
  s.sun.half_angle_rad = r.get<float>();
  for (uint64_t n = r.count(44); n > 0; --n) s.cameras.push_back(get_camera(r));
  if (r.get<uint8_t>()) s.volume = get_volume(r);
  if (!r.done()) throw WireError("bytes after the scene");
  validate(s);
  return s;
}

}  // namespace multiray::remote
