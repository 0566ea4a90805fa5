// The denoiser (render/denoise.h: atrous, and svgf's temporal step before it) on an
// OpenCL device: the same per-pixel steps (render/shared/denoise*.h) as the CPU's driver,
// two kernels (kernels/denoise.cl) launched once per pass over the full frame. The result
// equals the CPU's within float tolerance (the libraries' exp and pow may differ in the
// last ulp) and is the same on one device whatever the launch shape.
//
// Not done here: keeping svgf's history on the device between frames (it is uploaded and
// read back every frame, so a DenoiseState moves freely between the CPU and OpenCL), and
// filtering tiles with halos on the devices that rendered them (the filter runs on the
// full frame after the gather).
// No OpenCL types in this header, so the engine can include it.
#pragma once

#include <cstddef>
#include <memory>

#include "render/denoise.h"

namespace multiray {

class OpenClDenoiser {
 public:
  // Sets up opencl:`device_index` (the global index of `multiray devices`) and builds the
  // program (from the disk cache when it can, cl_program.h), with work groups of at most
  // `work_group`, fitted to what the compiled kernel allows, and launches of
  // tile x tile work-items (every launch the same size; the last covers the frame's end).
  // Neither changes a pixel. Throws InputError when there is no such device or a size is
  // out of range (1..4096) and DeviceError when it cannot be set up.
  explicit OpenClDenoiser(int device_index, int work_group = 64, int tile = 256);
  ~OpenClDenoiser();

  // As denoise(in, DenoiseMethod::atrous, nullptr, out_rgb, params) on the CPU. Throws
  // std::invalid_argument on bad input (as denoise) and DeviceError on an OpenCL error.
  void atrous(const DenoiseInput& in, float* out_rgb, const DenoiseParams& params = {});
  // As denoise(in, DenoiseMethod::svgf, &state, out_rgb, params) on the CPU; `state` has
  // the CPU's layout and meaning (either driver may continue the other's history).
  void svgf(const DenoiseInput& in, DenoiseState& state, float* out_rgb,
            const DenoiseParams& params = {});

  // The work-group size the launches use (fitted), and each launch's work-items.
  size_t work_group_size() const;
  size_t launch_items() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace multiray
