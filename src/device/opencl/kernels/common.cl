// SceneData, the struct through which the integrator (render/shared/) reads the scene:
// the render_rect kernel's buffers and scalars, passed down as one pointer. Every record
// is shared (render/shared/bvh_records.h, scene_records.h, ray.h).
typedef struct {
  const __global FlatNode* nodes;
  const __global FlatTriangle* tris;
  const __global StoredShading* shading;
  const __global MaterialRecord* materials;
  const __global LightRecord* lights;
  const __global float* light_cdf;
  const __global float* light_pdf_by_prim;
  const __global uint* texels;
  const __global TextureRecord* textures;
  const __global float* texel_luts;  // 3 x 256: a table per TexelCoding, in its order
  const __global float4* tangents;   // per triangle (TriangleTangent u, sign) if has_tangents
  const __global SkyRecord* sky;
  const __global float* sky_tables;  // the map's sampling tables at sky's offsets
  const __global float* sky_map;     // the map's radiance, after the tables
  // The compact scene (placeholders without MR_COMPACT): the tree, triangle references in
  // leaf order (bit-packed; width in CompactInfo), the scalars, and the mesh's arrays.
  const __global CompactNode* cnodes;
  const __global uint* prims;
  const __global CompactInfo* compact;
  CompactMeshView cmesh;  // render/shared/compact_mesh.h
  uint light_count;
  bool has_tangents;  // some material has a normal map (and the scene has uvs)
  bool cutouts;       // some material has an alpha mode: traversal tests coverage
  float p_env;        // probability of sampling the environment (render/shared/path.h)
  float eps;          // ray-origin offset
} SceneData;
