// The denoiser's passes (render/shared/denoise*.h, written once for every backend) over
// full-frame buffers: one work-item per pixel, pixel offset + get_global_id(0), launches of
// MR_LAUNCH_ITEMS work-items until the image is covered (opencl_denoise.cpp). Every pass
// reads buffers it does not write, so pixels are independent of each other and of the
// launch shape.

#define MR_DENOISE_DEMODULATE 0  // beauty (+ variance) -> color_out, variance_out
#define MR_DENOISE_VARIANCE 1    // color_in -> variance_out: the spatial estimate
#define MR_DENOISE_ATROUS 2      // color_in, variance_in -> color_out, variance_out
#define MR_DENOISE_REMODULATE 3  // color_in -> color_out: the image

__kernel __attribute__((reqd_work_group_size(MR_GROUP_ITEMS, 1, 1))) void denoise_pass(
    int pass, int offset, int width, int height, int step, int has_variance,
    float sigma_luminance, float sigma_normal, float sigma_depth, float sigma_albedo,
    __global const float* beauty, __global const float* albedo, __global const float* normal,
    __global const float* depth, __global const float* variance,
    __global const float* color_in, __global const float* variance_in,
    __global float* color_out, __global float* variance_out) {
  const int i = offset + (int)get_global_id(0);
  if (i >= width * height) return;
  const int x = i % width, y = i / width;
  DenoiseWeights w;
  w.sigma_luminance = sigma_luminance;
  w.sigma_normal = sigma_normal;
  w.sigma_depth = sigma_depth;
  w.sigma_albedo = sigma_albedo;
  if (pass == MR_DENOISE_DEMODULATE) {
    denoise_demodulate(beauty, albedo, depth, variance, has_variance, color_out, variance_out, i);
  } else if (pass == MR_DENOISE_VARIANCE) {
    variance_out[i] =
        denoise_spatial_variance(color_in, albedo, normal, depth, width, height, x, y, &w);
  } else if (pass == MR_DENOISE_ATROUS) {
    denoise_atrous_pixel(color_in, variance_in, albedo, normal, depth, color_out, variance_out,
                         width, height, x, y, step, &w);
  } else {
    denoise_remodulate(color_in, albedo, depth, color_out, i);
  }
}
