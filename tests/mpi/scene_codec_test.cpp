// --scene-from master: a scene survives the trip to a worker intact (meshes, materials,
// textures, environment, sun, cameras, volumes), and damaged bytes are refused.
#include <gtest/gtest.h>

#include "core/error.h"
#include "distributed/scene_codec.h"
#include "distributed/wire.h"
#include "scene/builders.h"
#include "volume/volume.h"

namespace multiray::remote {
namespace scene_codec_test {

Scene rich_scene() {
  Scene s = make_cornell_box();
  s.uvs.assign(s.positions.size(), Vec2{0.25f, 0.75f});
  const unsigned char rgba[8] = {255, 0, 0, 255, 0, 255, 0, 128};
  s.textures.push_back(Texture::from_pixels(rgba, 2, 1, 4));
  s.materials[0].base_color_texture = 0;
  s.materials[0].alpha_mode = AlphaMode::mask;
  auto map = std::make_shared<EnvironmentMap>();
  map->name = "sky.hdr", map->width = 2, map->height = 1;
  map->radiance = {{1, 2, 3}, {4, 5, 6}};
  s.environment_map = map;
  s.sun.radiance = {3, 3, 3};
  Camera c;
  c.eye = {1, 2, 3}, c.film_width = 640;
  s.cameras.push_back(c);
  return s;
}

TEST(SceneCodec, AMeshSceneSurvivesTheTrip) {
  const Scene s = rich_scene();
  const Scene t = decode_scene(encode_scene(s));
  EXPECT_EQ(t.name, s.name);
  ASSERT_EQ(t.positions.size(), s.positions.size());
  EXPECT_EQ(t.positions.back().x, s.positions.back().x);
  EXPECT_EQ(t.indices, s.indices);
  EXPECT_EQ(t.material_ids, s.material_ids);
  ASSERT_EQ(t.materials.size(), s.materials.size());
  EXPECT_EQ(t.materials[0].base_color_texture, 0);
  EXPECT_EQ(t.materials[0].alpha_mode, AlphaMode::mask);
  EXPECT_EQ(t.materials[1].emission.x, s.materials[1].emission.x);
  ASSERT_EQ(t.textures.size(), 1u);
  EXPECT_EQ(t.textures[0].texels, s.textures[0].texels);
  ASSERT_TRUE(t.environment_map);
  EXPECT_EQ(t.environment_map->radiance[1].z, 6);
  EXPECT_EQ(t.sun.radiance.y, 3);
  ASSERT_EQ(t.cameras.size(), s.cameras.size());
  EXPECT_EQ(t.cameras.back().film_width, 640);
  // The same bytes again: nothing was lost or reordered.
  EXPECT_EQ(encode_scene(t), encode_scene(s));
}

TEST(SceneCodec, AVolumeSurvivesTheTrip) {
  Scene s;
  s.name = "cube.nhdr";
  auto v = std::make_shared<Volume>();
  v->nx = 2, v->ny = 3, v->nz = 4, v->spacing = {1, 1, 2};
  v->values.resize(24);
  for (size_t i = 0; i < 24; ++i) v->values[i] = float(i);
  v->max_value = 23;
  s.volume = v;
  const Scene t = decode_scene(encode_scene(s));
  ASSERT_TRUE(t.volume);
  EXPECT_EQ(t.volume->values, v->values);
  EXPECT_EQ(t.volume->spacing.z, 2);
}

TEST(SceneCodec, DamagedBytesAreRefused) {
  const std::vector<uint8_t> bytes = encode_scene(rich_scene());
  for (size_t n = 0; n < bytes.size(); n += 97)
    EXPECT_THROW(decode_scene(std::vector<uint8_t>(bytes.begin(), bytes.begin() + n)), WireError)
        << n;
  std::vector<uint8_t> longer = bytes;
  longer.push_back(0);
  EXPECT_THROW(decode_scene(longer), WireError);
  // A triangle naming a vertex that does not exist: refused as a loader would.
  Scene bad = rich_scene();
  bad.indices[0] = 1u << 30;
  EXPECT_THROW(decode_scene(encode_scene(bad)), InputError);
  Scene missing = rich_scene();
  missing.materials[0].base_color_texture = 5;
  EXPECT_THROW(decode_scene(encode_scene(missing)), WireError);
}

}  // namespace scene_codec_test
}  // namespace multiray::remote
