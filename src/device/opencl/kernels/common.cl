// The OpenCL kernels' own records: the BVHs' nodes and triangles (render/flat_bvh.h,
// render/compact_scene.h byte for byte), a triangle's shading record, rays and hits, and
// SceneData, the struct through which the integrator (render/shared/) reads the scene.
// The integrator's records (materials, lights, textures, sky) are
// render/shared/scene_records.h's.

typedef struct {
  float lo[2][3];  // boxes of the two children
  float hi[2][3];
  uint child[2];  // node index, or LEAF_BIT | first triangle << LEAF_COUNT_BITS | (count - 1)
  uint pad[2];
} Node;

typedef struct {
  float v0[3];
  uint prim;  // index of the triangle in the scene
  float e1n[3];  // v0 - v1 (Embree's e1)
  float pad0;
  float e2[3];
  float pad1;
} Tri;

// The compact scene (render/compact_scene.h, built with -DMR_COMPACT=1): a node of the
// quantized BVH, 20 bytes, its children's boxes in 8 bits per plane of its own box,
// axis by axis: q[axis] = child 0's lower plane, child 1's lower, child 0's upper, child 1's
// upper.
typedef struct {
  uchar q[3][4];
  uint child[2];  // as Node::child, `first` indexing SceneData::prims
} CompactNode;

// The scalars of the compact scene (device/gpu_scene/scene_buffers.h GpuCompactInfo): the
// position grid (PositionGrid; its cell-index table is SceneData::cells), the root node's
// box and the uv coding (UvCoding).
typedef struct {
  float origin[3];
  float cell;
  float root_lo[3];
  uint has_nodes;  // 0: the tree is empty, nothing can be hit
  float root_hi[3];
  uint has_normals;  // 0: the mesh has no normals, shading uses the face normal
  float uv_step[2];
  uint uv_period_log2[2];
  float step;  // PositionGrid::step: cell / 1023
  // Bit widths of the packed arrays (compact_read_bits): vertex index in bits 0-7,
  // material id 8-15, uv shift offsets u 16-23 and v 24-31.
  uint widths;
  int uv_shift_base[2];
  uint prim_bits;  // width of the tree's packed triangle references (SceneData::prims)
  uint has_uvs;    // 0: the mesh has no uvs (SceneData::quvs is a placeholder byte)
  uint pad[2];
} CompactInfo;

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
  const __global Node* nodes;
  const __global Tri* tris;
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
  // leaf order, 3 ushorts per vertex (QuantizedPosition), the cell-index table (3 ushorts
  // per geometry cell), faces (bit-packed vertex indices), normal codes and uv codes per
  // vertex, uv shifts and material ids per triangle (bit-packed; widths in CompactInfo).
  const __global CompactNode* cnodes;
  const __global uint* prims;
  const __global ushort* qpos;
  const __global ushort* cells;
  const __global uint* indices;
  const __global ushort* qnormals;
  const __global ushort* quvs;
  const __global uint* uv_shifts;     // bit-packed, one entry per triangle
  const __global uint* material_ids;  // bit-packed
  const __global CompactInfo* compact;
  uint light_count;
  bool has_tangents;  // some material has a normal map (and the scene has uvs)
  bool cutouts;       // some material has an alpha mode: traversal tests coverage
  float p_env;        // probability of sampling the environment (render/shared/path.h)
  float eps;          // ray-origin offset
} SceneData;
