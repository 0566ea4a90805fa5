// Fuzz target of the volume loader and the raycaster behind it: the input is a NRRD
// header, attached data included, or a detached header with its data file as an
// "@@file NAME" section (fuzz_support.h), written to volume.nhdr and loaded with
// load_volume() as `multiray render VOLUME.nhdr` does (loads of more than 64 MiB are
// refused by the limit, as --max-memory would). The contract (load_volume.h): a Volume
// whose values match its grid, or an InputError. A loaded volume is then rendered: its
// blocks and a `grey` style built, and a few rays cast, which must give finite pixels.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "fuzz_support.h"
#include "render/path_tracer.h"
#include "render/volume_raycaster.h"
#include "volume/load_volume.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace multiray;
  const auto path = fuzz::write_files(fuzz::split_files(data, size), "volume.nhdr");
  VolumeLoadOptions options;
  options.max_bytes = uint64_t(64) << 20;
  Volume volume;
  try {
    volume = load_volume(path.string(), options);
  } catch (const InputError&) {
    return 0;  // refused with a message: the contract
  }
  if (volume.values.size() != volume.voxel_count() || volume.values.empty())
    fuzz::fail("a loaded volume's values do not match its grid");
  if (!(volume.min_value <= volume.max_value) || !std::isfinite(volume.min_value) ||
      !std::isfinite(volume.max_value))
    fuzz::fail("a loaded volume has a bad value range");
  const VolumeScene vs(volume);
  const auto style = make_volume_style(vs, transfer_preset("grey", volume), 1.0f);
  Camera cam;
  cam.eye = volume.extent() * 1.5f + Vec3(0.1f, 0.2f, 0.3f);
  cam.target = Vec3(0.0f);
  const PinholeCamera camera(cam, fuzz::kRenderWidth, fuzz::kRenderHeight);
  const VolumeRaycaster kernel(vs);
  for (int y = 0; y < fuzz::kRenderHeight; ++y)
    for (int x = 0; x < fuzz::kRenderWidth; ++x) {
      Ray ray = camera.ray(float(x) + 0.5f, float(y) + 0.5f);
      ray.dir = normalize(ray.dir);
      uint64_t steps = 0;
      if (!is_finite(kernel.cast(ray, *style, 1.0f, steps)))
        fuzz::fail("a loaded volume renders a non-finite pixel");
    }
  return 0;
}
