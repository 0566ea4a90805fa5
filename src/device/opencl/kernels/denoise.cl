// The denoiser's passes and SVGF's temporal step (render/shared/denoise*.h, written once
// for every backend) over full-frame buffers: one work-item per pixel, pixel offset +
// get_global_id(0), launches of MR_LAUNCH_ITEMS work-items until the image is covered
// (opencl_denoise.cpp). Every pass reads buffers it does not write, so pixels are
// independent of each other and of the launch shape.

// The passes, what each reads -> writes:
// beauty (+ variance) -> guides, slopes; the beauty demodulated: color, luminance, variance
#define MR_DENOISE_PREPARE 0
#define MR_DENOISE_VARIANCE 1    // variance_in, luminance_in -> variance_out: the start
                                 // (denoise_start_variance)
#define MR_DENOISE_ATROUS 2      // color, luminance, variance in -> the same out
#define MR_DENOISE_REMODULATE 3  // color_in -> color_out: the image

// `guides` and `slopes` are written by MR_DENOISE_PREPARE and read by the later passes.
__kernel __attribute__((reqd_work_group_size(MR_GROUP_ITEMS, 1, 1))) void denoise_pass(
    int pass, int offset, int width, int height, int step, int has_variance,
    float sigma_luminance, float sigma_normal, float sigma_depth, float sigma_albedo,
    __global const float* beauty, __global const float* albedo, __global const float* normal,
    __global const float* depth, __global const float* variance,
    __global const float* color_in, __global const float* variance_in,
    __global float* color_out, __global float* variance_out, __global float* guides,
    __global float* slopes, __global const float* luminance_in, __global float* luminance_out,
    int has_emission, __global const float* emission, int normal_turn) {
  // A division and no remainder: with both, clang pairs them through an LLVM `freeze`,
  // which Oclgrind's --uninitialized check cannot interpret.
  const int i = offset + (int)get_global_id(0);
  if (i >= width * height) return;
  const int y = i / width, x = i - y * width;
  const DenoiseWeights w = denoise_weights(sigma_luminance, sigma_normal, sigma_depth,
                                           sigma_albedo, normal_turn);
  if (pass == MR_DENOISE_PREPARE) {
    denoise_pack_guides(albedo, normal, depth, width, height, x, y, guides, slopes);
    denoise_demodulate(beauty, emission, has_emission, albedo, depth, variance, has_variance,
                       color_out, luminance_out, variance_out, i);
  } else if (pass == MR_DENOISE_VARIANCE) {
    variance_out[i] = denoise_start_variance(has_variance, variance_in, luminance_in, guides,
                                             slopes, width, height, x, y, &w);
  } else if (pass == MR_DENOISE_ATROUS) {
    denoise_atrous_pixel(color_in, luminance_in, variance_in, guides, slopes, color_out,
                         luminance_out, variance_out, width, height, x, y, step, &w);
  } else {
    denoise_remodulate(color_in, emission, has_emission, albedo, depth, color_out, i);
  }
}

// SVGF's temporal step (render/shared/denoise_temporal.h) for pixel offset +
// get_global_id(0): cameras[0] is the current frame's camera, cameras[1] the previous
// one's (read only when has_previous). Writes the accumulated colour, moments and
// (history length, variance), and for the filter the variance alone into variance_out and
// the colour's luminance into luminance_out.
__kernel __attribute__((reqd_work_group_size(MR_GROUP_ITEMS, 1, 1))) void denoise_temporal(
    int offset, int width, int height, int has_previous, int has_given_variance, float alpha,
    float moments_alpha, float depth_tolerance, float normal_tolerance,
    __global const CameraBlock* cameras, __global const float* color,
    __global const float* frame_variance, __global const float* depth,
    __global const float* normal, __global const float* prev_color,
    __global const float* prev_moments, __global const float* prev_history,
    __global const float* prev_depth, __global const float* prev_normal,
    __global float* out_color, __global float* out_moments, __global float* out_history,
    __global float* variance_out, __global float* luminance_out) {
  const int i = offset + (int)get_global_id(0);
  if (i >= width * height) return;
  const int y = i / width, x = i - y * width;  // no remainder: see denoise_pass
  TemporalParams t;
  t.alpha = alpha;
  t.moments_alpha = moments_alpha;
  t.depth_tolerance = depth_tolerance;
  t.normal_tolerance = normal_tolerance;
  t.has_given_variance = has_given_variance;
  const CameraBlock cur = cameras[0], prev = cameras[1];
  denoise_temporal_pixel(&cur, &prev, has_previous, color, frame_variance, depth, normal,
                         prev_color, prev_moments, prev_history, prev_depth, prev_normal,
                         out_color, out_moments, out_history, width, height, x, y, &t);
  variance_out[i] = out_history[2 * i + 1];
  denoise_store_luminance(out_color, luminance_out, i);
}
