#include "render/denoise_rows.h"

#include "render/shared/denoise_atrous.h"
#include "render/shared/denoise_temporal.h"

// The block functions are compiled twice, for x86-64's baseline (SSE2) and for AVX2 (8
// lanes a vector), and the loader picks one for the machine. AVX2 brings no fma in GCC
// or clang (that is -mfma), so both compute the same bits: only the vector width differs.
#if defined(__x86_64__) && defined(__GNUC__)
#define MR_DENOISE_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MR_DENOISE_CLONES
#endif

namespace multiray {

// Named, not anonymous: this file shares a unity batch with others.
namespace denoise_blocks {

constexpr int L = kDenoiseLanes;
// Blocks take sigma_normal = 128 (2^7, the default and the only value any caller sets):
// the normals' weight is then the cosine squared 7 times, a loop the compiler unrolls.
// Other sigmas go pixel by pixel.
constexpr int kBlockSquarings = 7;

// denoise_normal_weight for weights with normal_squarings == kBlockSquarings: the same
// squarings, without the shared function's branches on the weights. Written out: a loop
// here would make the loop over a block's pixels an outer loop, which GCC does not
// vectorise.
inline float block_normal_weight(float v) {
  v *= v;
  v *= v;
  v *= v;
  v *= v;
  v *= v;
  v *= v;
  return v * v;
}

// Whether the taps `offset` columns away from the block at x0 lie inside the image for
// every pixel of the block or for none (else the block cannot be filtered as one).
bool column_uniform(int x0, int offset, int width) {
  const int first = x0 + offset, last = first + L - 1;
  return (first >= 0 && last < width) || last < 0 || first >= width;
}

// A block's DenoiseCentre, one array a field: loops over the block read and write them
// as vectors.
struct Centres {
  float nx[L], ny[L], nz[L], ax[L], ay[L], az[L];
  float inv_depth[L], slope_x[L], slope_y[L], turn_x[L], turn_y[L];
  float depth_scale[L], albedo_scale[L];
  int miss[L];

  void load(const DenoisePass& a, int p0) {
    const int pixels = a.width * a.height;
    for (int l = 0; l < L; ++l)
      set(l, denoise_centre(a.guides, a.slopes, pixels, p0 + l, &a.weights));
  }
  void set(int l, const DenoiseCentre& c) {
    nx[l] = c.normal.x, ny[l] = c.normal.y, nz[l] = c.normal.z;
    ax[l] = c.albedo.x, ay[l] = c.albedo.y, az[l] = c.albedo.z;
    inv_depth[l] = c.inv_depth, slope_x[l] = c.slope_x, slope_y[l] = c.slope_y;
    turn_x[l] = c.turn_x, turn_y[l] = c.turn_y;
    depth_scale[l] = c.depth_scale, albedo_scale[l] = c.albedo_scale, miss[l] = c.miss;
  }
  DenoiseCentre get(int l) const {
    DenoiseCentre c;
    c.normal = Vec3(nx[l], ny[l], nz[l]);
    c.albedo = Vec3(ax[l], ay[l], az[l]);
    c.inv_depth = inv_depth[l], c.slope_x = slope_x[l], c.slope_y = slope_y[l];
    c.turn_x = turn_x[l], c.turn_y = turn_y[l];
    c.depth_scale = depth_scale[l], c.albedo_scale = albedo_scale[l], c.miss = miss[l];
    return c;
  }
};

// A block's DenoiseSum, one array a field.
struct Sums {
  float weight[L] = {}, r[L] = {}, g[L] = {}, b[L] = {}, variance[L] = {};

  DenoiseSum get(int l) const {
    DenoiseSum s;
    s.weight = weight[l], s.r = r[l], s.g = g[l], s.b = b[l], s.variance = variance[l];
    return s;
  }
  void set(int l, const DenoiseSum& s) {
    weight[l] = s.weight, r[l] = s.r, g[l] = s.g, b[l] = s.b, variance[l] = s.variance;
  }
};

// A block's DenoiseMoments, one array a field.
struct Moments {
  float weight[L] = {}, m1[L] = {}, m2[L] = {};

  DenoiseMoments get(int l) const {
    DenoiseMoments m;
    m.weight = weight[l], m.m1 = m1[l], m.m2 = m2[l];
    return m;
  }
  void set(int l, const DenoiseMoments& m) { weight[l] = m.weight, m1[l] = m.m1, m2[l] = m.m2; }
};

// denoise_blurred_variance for the block at (x0, y), whose pixels all have both
// horizontal neighbours: the same sums in the same order, rows outside the image skipped.
[[gnu::always_inline]] inline void blurred_variances(const DenoisePass& a, int x0, int y,
                                                     float* out) {
  float sum[L] = {}, total = 0.0f;
  for (int dy = -1; dy <= 1; ++dy) {
    const int qy = y + dy;
    if (qy < 0 || qy >= a.height) continue;
    for (int dx = -1; dx <= 1; ++dx) {
      const float k = denoise_blur_weight(dx, dy);
      const float* v = a.variance + qy * a.width + x0 + dx;
      for (int l = 0; l < L; ++l) sum[l] += k * v[l];
      total += k;
    }
  }
  for (int l = 0; l < L; ++l) out[l] = sum[l] / total;
}

// denoise_atrous_pixel for the block of L pixels at (x0, y): every tap column uniform
// (column_uniform), both horizontal neighbours of every pixel inside the image.
[[gnu::always_inline]] inline void atrous_block(const DenoisePass& a, int x0, int y, int step) {
  const int pixels = a.width * a.height, p0 = y * a.width + x0;
  Centres c;
  c.load(a, p0);
  float lp[L], inv_scale[L];
  blurred_variances(a, x0, y, inv_scale);
  for (int l = 0; l < L; ++l) {
    lp[l] = a.luminance[p0 + l];
    inv_scale[l] = denoise_luminance_scale(inv_scale[l], &a.weights);
  }
  Sums s;
  for (int j = -2; j <= 2; ++j) {
    const int qy = y + j * step;
    if (qy < 0 || qy >= a.height) continue;
    for (int i = -2; i <= 2; ++i) {
      const int dx = i * step, dy = j * step;
      if (x0 + dx < 0 || x0 + dx >= a.width) continue;  // the whole block's column
      const float kernel = denoise_b3(i) * denoise_b3(j);
      const int q0 = qy * a.width + x0 + dx;
      for (int l = 0; l < L; ++l) {
        const DenoiseCentre centre = c.get(l);
        float exponent;
        const float cosine = denoise_atrous_terms(&centre, lp[l], inv_scale[l], a.guides,
                                                  a.luminance, pixels, q0 + l, dx, dy, &exponent);
        const float k = denoise_tap_weight(kernel, cosine, block_normal_weight(cosine), exponent);
        DenoiseSum sum = s.get(l);
        denoise_sum_add(&sum, k, a.color, a.variance, q0 + l);
        s.set(l, sum);
      }
    }
  }
  for (int l = 0; l < L; ++l) {
    const DenoiseSum sum = s.get(l);
    denoise_sum_store(&sum, a.color_out, a.luminance_out, a.variance_out, p0 + l);
  }
}

// denoise_spatial_variance for the block of L pixels at (x0, y), every window column
// uniform, into `out`.
[[gnu::always_inline]] inline void spatial_block(const DenoisePass& a, int x0, int y, float* out) {
  const int pixels = a.width * a.height, p0 = y * a.width + x0;
  Centres c;
  c.load(a, p0);
  Moments m;
  for (int dy = -MR_DENOISE_VARIANCE_RADIUS; dy <= MR_DENOISE_VARIANCE_RADIUS; ++dy) {
    const int qy = y + dy;
    if (qy < 0 || qy >= a.height) continue;
    for (int dx = -MR_DENOISE_VARIANCE_RADIUS; dx <= MR_DENOISE_VARIANCE_RADIUS; ++dx) {
      if (x0 + dx < 0 || x0 + dx >= a.width) continue;  // the whole block's column
      const int q0 = qy * a.width + x0 + dx;
      for (int l = 0; l < L; ++l) {
        const DenoiseCentre centre = c.get(l);
        float exponent;
        const float cosine =
            denoise_guide_terms(&centre, a.guides, pixels, q0 + l, dx, dy, &exponent);
        const float g = denoise_tap_weight(1.0f, cosine, block_normal_weight(cosine), exponent);
        DenoiseMoments sums = m.get(l);
        denoise_moments_add(&sums, g, a.luminance[q0 + l]);
        m.set(l, sums);
      }
    }
  }
  for (int l = 0; l < L; ++l) {
    const DenoiseMoments sums = m.get(l);
    out[l] = denoise_moments_variance(&sums);
  }
}

// Whether the block of L pixels at x0 can be filtered as one: the taps at every multiple
// of `step` in -reach..reach columns away uniform (column_uniform), and the pixels'
// horizontal neighbours (the variance's blur) inside the image.
bool block_fits(int x0, int reach, int step, int width) {
  if (x0 < 1 || x0 + L >= width) return false;
  for (int o = -reach; o <= reach; ++o)
    if (!column_uniform(x0, o * step, width)) return false;
  return true;
}

void atrous_pixels(const DenoisePass& a, int x_begin, int x_end, int y, int step) {
  for (int x = x_begin; x < x_end; ++x)
    denoise_atrous_pixel(a.color, a.luminance, a.variance, a.guides, a.slopes, a.color_out,
                         a.luminance_out, a.variance_out, a.width, a.height, x, y, step,
                         &a.weights);
}

void start_variance_pixels(const DenoisePass& a, int x_begin, int x_end, int y,
                           bool has_variance) {
  for (int x = x_begin; x < x_end; ++x)
    a.variance_out[y * a.width + x] =
        denoise_start_variance(has_variance, a.variance, a.luminance, a.guides, a.slopes, a.width,
                               a.height, x, y, &a.weights);
}

// Row y by blocks where they fit (block_fits), by pixels elsewhere; returns the pixels
// that went by blocks.
MR_DENOISE_CLONES int atrous_row_blocks(const DenoisePass& a, int y, int step) {
  int x0 = 0, by_blocks = 0;
  for (; x0 + L <= a.width; x0 += L)
    if (block_fits(x0, 2, step, a.width)) {
      atrous_block(a, x0, y, step);
      by_blocks += L;
    } else {
      atrous_pixels(a, x0, x0 + L, y, step);
    }
  atrous_pixels(a, x0, a.width, y, step);
  return by_blocks;
}

// The start variance of the block at (x0, y): the given where denoise_uses_given_variance,
// else the spatial estimate (computed for the block only if one of its pixels needs it).
[[gnu::always_inline]] inline void start_variance_block(const DenoisePass& a, int x0, int y,
                                                        bool has_variance) {
  const int p0 = y * a.width + x0;
  int given[L], all_given = 1;
  for (int l = 0; l < L; ++l) {
    given[l] = denoise_uses_given_variance(has_variance, a.variance, p0 + l);
    all_given = all_given && given[l];
  }
  float spatial[L] = {};
  if (!all_given) spatial_block(a, x0, y, spatial);
  for (int l = 0; l < L; ++l) a.variance_out[p0 + l] = given[l] ? a.variance[p0 + l] : spatial[l];
}

// As atrous_row_blocks.
MR_DENOISE_CLONES int start_variance_row_blocks(const DenoisePass& a, int y, bool has_variance) {
  int x0 = 0, by_blocks = 0;
  for (; x0 + L <= a.width; x0 += L)
    if (block_fits(x0, MR_DENOISE_VARIANCE_RADIUS, 1, a.width)) {
      start_variance_block(a, x0, y, has_variance);
      by_blocks += L;
    } else {
      start_variance_pixels(a, x0, x0 + L, y, has_variance);
    }
  start_variance_pixels(a, x0, a.width, y, has_variance);
  return by_blocks;
}

// Pixel i's young-history variance from `spatial` (denoise_young_history_row).
inline void young_history_pixel(const DenoisePass& a, float* history, float alpha, int i,
                                float spatial) {
  const float v =
      denoise_young_history_variance(history[2 * i + 1], history[2 * i], alpha, spatial);
  history[2 * i + 1] = v;
  a.variance_out[i] = v;
}

void young_history_pixels(const DenoisePass& a, int x_begin, int x_end, int y, float* history,
                          float alpha) {
  for (int x = x_begin; x < x_end; ++x) {
    const int i = y * a.width + x;
    if (!denoise_history_young(history[2 * i])) continue;
    young_history_pixel(a, history, alpha, i,
                        denoise_spatial_variance(a.luminance, a.guides, a.slopes, a.width,
                                                 a.height, x, y, &a.weights));
  }
}

// As atrous_row_blocks: a block's spatial estimate is made when one of its pixels is young.
MR_DENOISE_CLONES int young_history_row_blocks(const DenoisePass& a, int y, float* history,
                                               float alpha) {
  int x0 = 0, by_blocks = 0;
  for (; x0 + L <= a.width; x0 += L) {
    if (!block_fits(x0, MR_DENOISE_VARIANCE_RADIUS, 1, a.width)) {
      young_history_pixels(a, x0, x0 + L, y, history, alpha);
      continue;
    }
    const int p0 = y * a.width + x0;
    int young[L], any = 0;
    for (int l = 0; l < L; ++l) {
      young[l] = denoise_history_young(history[2 * (p0 + l)]);
      any = any || young[l];
    }
    by_blocks += L;
    if (!any) continue;
    float spatial[L];
    spatial_block(a, x0, y, spatial);
    for (int l = 0; l < L; ++l)
      if (young[l]) young_history_pixel(a, history, alpha, p0 + l, spatial[l]);
  }
  young_history_pixels(a, x0, a.width, y, history, alpha);
  return by_blocks;
}

}  // namespace denoise_blocks

int denoise_young_history_row(const DenoisePass& a, int y, float* history, float alpha,
                              bool blocks) {
  if (blocks && a.weights.normal_squarings == denoise_blocks::kBlockSquarings)
    return denoise_blocks::young_history_row_blocks(a, y, history, alpha);
  denoise_blocks::young_history_pixels(a, 0, a.width, y, history, alpha);
  return 0;
}

int denoise_atrous_row(const DenoisePass& a, int y, int step, bool blocks) {
  if (blocks && a.weights.normal_squarings == denoise_blocks::kBlockSquarings)
    return denoise_blocks::atrous_row_blocks(a, y, step);
  denoise_blocks::atrous_pixels(a, 0, a.width, y, step);
  return 0;
}

int denoise_start_variance_row(const DenoisePass& a, int y, bool has_variance, bool blocks) {
  if (blocks && a.weights.normal_squarings == denoise_blocks::kBlockSquarings)
    return denoise_blocks::start_variance_row_blocks(a, y, has_variance);
  denoise_blocks::start_variance_pixels(a, 0, a.width, y, has_variance);
  return 0;
}

}  // namespace multiray
