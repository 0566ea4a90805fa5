// Shared definitions of the OpenCL path tracer: buffer records (mirroring
// device/opencl/bvh_flatten.h and scene_buffers.h byte for byte) and small vector helpers
// that evaluate in the same order as core/math.h.
//
// Contraction of a*b+c into fma is off: a fused and an unfused evaluation of the same
// pixel must never coexist (e.g. vectorised and scalar work-item loops), or images would
// depend on how the frame was split.
#pragma OPENCL FP_CONTRACT OFF

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
  float e1[3];
  float pad0;
  float e2[3];
  float pad1;
} Tri;

typedef struct {
  float normal[9];  // three corner normals
  float uv[6];      // three corner uvs
  uint material;
} Shading;

typedef struct {
  float color[3];
  int texture;
  float emission[3];
  float metallic;
  float alpha;
  float ior;
  uint dielectric;
  uint emissive;
} Material;

typedef struct {
  float a[3];
  float pdf_area;
  float b[3];
  uint prim;
  float c[3];
  float pad0;
  float radiance[3];
  float pad1;
} Light;

typedef struct {
  uint offset;
  int width;
  int height;
  int pad;
} TexInfo;

typedef struct {
  float3 org, dir;
  float tmin, tmax;
} Ray;

typedef struct {
  float t;
  uint prim;
  float u, v;  // barycentrics of vertices 1 and 2
  float3 ng;   // unnormalised, cross(e1, e2)
} Hit;

float3 load3(const __global float* p) { return (float3)(p[0], p[1], p[2]); }

// Written out (not the built-ins) so the order of operations is core/math.h's.
float dot3(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
float3 cross3(float3 a, float3 b) {
  return (float3)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
float3 normalize3(float3 a) {
  const float l = sqrt(dot3(a, a));
  return l > 0.0f ? a * (1.0f / l) : (float3)(0.0f, 0.0f, 1.0f);
}
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
