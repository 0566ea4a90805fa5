// Shared definitions of the OpenCL path tracer: buffer records (mirroring
// render/flat_bvh.h and device/opencl/scene_buffers.h byte for byte) and small vector helpers
// that evaluate in the same order as core/math.h (with dot3, cross3 and normalize3 of
// render/shared/language.h, which also turns fma contraction off for the whole program).

#define PI 3.14159265358979323846f
#define INV_PI (1.0f / PI)

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

// The scalars of the compact scene (scene_buffers.h ClCompactInfo): the position grid
// (PositionGrid; its cell-index table is SceneData::cells), the root node's box and the uv
// coding (UvCoding).
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

// Raw factors: the kernel multiplies them by their textures, then clamps them with
// bsdf_params (render/surface.cpp, render/shared/bsdf.h).
typedef struct {
  float color[3];
  int texture;  // base colour (sRGB, alpha = coverage) or -1
  float emission[3];
  int emission_texture;  // or -1
  float metallic;
  float roughness;  // perceptual; GGX alpha = roughness^2
  float ior;        // > 1
  uint dielectric;
  uint emissive;              // max component of emission > 0
  int metallic_roughness_texture;  // G: roughness, B: metallic; or -1
  int normal_texture;         // or -1
  float normal_scale;
  float opacity;
  uint alpha_mode;  // 0 opaque, 1 mask, 2 blend (AlphaMode)
  float alpha_cutoff;
  float pad;
} Material;

typedef struct {
  float a[3];
  float pdf_area;
  float b[3];
  uint prim;
  float c[3];
  float pad0;
  float radiance[3];  // the material's emission factor (times its texture per point)
  float pad1;
} Light;

typedef struct {
  uint offset;
  int width;
  int height;
  uint coding;  // TexelCoding: 0 srgb, 1 linear, 2 signed_unit (its 256-entry table)
} TexInfo;

// The environment light of render/environment.h: constant sky, equirectangular map (its
// tables in SceneData::sky_data at the offsets below) and sun.
typedef struct {
  float constant_sky[3];
  float choice;  // RenderScene::environment_choice() (the host passes it as p_env)
  float frame_x[3];
  float sun_cos;
  float frame_up[3];
  float sun_pdf;
  float frame_z[3];
  float p_sun;
  float sun_dir[3];
  uint sun_on;
  float sun_radiance[3];
  uint sky_on;  // constant or map
  int map_width, map_height;  // 0 x 0 without a map
  uint on;                    // EnvironmentLight::on()
  uint row_cdf;               // offsets into sky_data: height floats,
  uint row_pdf;               // height floats,
  uint col_cdf;               // width x height floats,
  uint pix_pdf;               // width x height floats,
  uint map;                   // width x height RGB radiance (scale applied)
} Sky;

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

float3 load3(const __global float* p) { return (float3)(p[0], p[1], p[2]); }

// Written out (not the built-ins) so the order of operations is core/math.h's.
float max3(float3 a) { return fmax(a.x, fmax(a.y, a.z)); }
float3 lerp3(float3 a, float3 b, float t) { return a * (1.0f - t) + b * t; }
bool finite3(float3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

// Orthonormal basis around unit `n` (Duff et al. 2017), as core/math.h's Frame.
typedef struct {
  float3 t, b, n;
} Frame;

Frame frame_from_normal(float3 n) {
  const float sign = copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float bb = n.x * n.y * a;
  Frame f;
  f.t = (float3)(1.0f + sign * n.x * n.x * a, sign * bb, -sign * n.x);
  f.b = (float3)(bb, sign + n.y * n.y * a, -n.y);
  f.n = n;
  return f;
}
float3 to_local(const Frame* f, float3 v) {
  return (float3)(dot3(v, f->t), dot3(v, f->b), dot3(v, f->n));
}
float3 to_world(const Frame* f, float3 v) { return f->t * v.x + f->b * v.y + f->n * v.z; }

// The render_rect kernel's scene buffers and scalars, passed down as one pointer.
typedef struct {
  const __global Node* nodes;
  const __global Tri* tris;
  const __global Shading* shading;
  const __global Material* materials;
  const __global Light* lights;
  const __global float* light_cdf;
  const __global float* light_pdf_by_prim;
  const __global uint* texels;
  const __global TexInfo* textures;
  const __global float* texel_luts;  // 3 x 256: a table per TexelCoding, in its order
  const __global float4* tangents;   // per triangle (TriangleTangent u, sign) if has_tangents
  const __global Sky* sky;
  const __global float* sky_data;
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
  float p_env;        // probability of sampling the environment (PathTracer::step's p_env)
  float eps;          // ray-origin offset
} SceneData;
