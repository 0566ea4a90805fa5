// The OpenCL kernels' own records: the compact tree's node (render/compact_scene.h byte
// for byte), a triangle's shading record, rays and hits, and SceneData, the struct through
// which the integrator (render/shared/) reads the scene. The other records are shared:
// render/shared/bvh_records.h (flat BVH, compact scalars) and scene_records.h.

// The compact scene (render/compact_scene.h, built with -DMR_COMPACT=1): a node of the
// quantized BVH, 20 bytes, its children's boxes in 8 bits per plane of its own box,
// axis by axis: q[axis] = child 0's lower plane, child 1's lower, child 0's upper, child 1's
// upper.
typedef struct {
  uchar q[3][4];
  uint child[2];  // as Node::child, `first` indexing SceneData::prims
} CompactNode;

typedef struct {
  float normal[9];  // three corner normals
  float uv[6];      // three corner uvs
  uint material;
} Shading;

// A triangle's shading record as the integrator reads it (render/scene_data.h's).
typedef struct {
  float3 normal[3];
  float2 uv[3];
  uint material;
} ShadingRecord;

typedef struct {
  float3 org, dir;
  float tmin, tmax;
} Ray;

typedef struct {
  float t;
  uint prim;
  float u, v;  // barycentrics of vertices 1 and 2
  float3 ng;   // unnormalised, Embree's Ng = cross(v2 - v0, v0 - v1)
} Hit;

// The render_rect kernel's scene buffers and scalars, passed down as one pointer.
typedef struct {
  const __global FlatNode* nodes;
  const __global FlatTriangle* tris;
  const __global Shading* shading;
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
