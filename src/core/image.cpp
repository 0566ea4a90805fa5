#include "core/image.h"

#include "core/exr_planes.h"

#include <stb_image_write.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <xxhash.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/file_io.h"

namespace multiray {

namespace {
uint8_t encode_srgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return uint8_t(std::lround(s * 255.0f));
}
}  // namespace

uint64_t image_hash(const Framebuffer& fb, uint64_t seed) {
  uint64_t h = XXH3_64bits_withSeed(fb.pixels.data(), fb.pixels.size() * sizeof(Vec3), seed);
  if (!fb.alpha.empty())
    h = XXH3_64bits_withSeed(fb.alpha.data(), fb.alpha.size() * sizeof(float), h);
  return h;
}

float exposure_scale(float ev) { return std::exp2(ev); }

float tone_filmic(float x) {
  if (!(x > 0.0f)) return 0.0f;  // negative or NaN
  // Narkowicz's fit of the ACES reference rendering transform (2015), per channel.
  constexpr float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;
  if (x > 1e6f) return 1.0f;  // x * x would overflow long before this matters
  return std::min((x * (a * x + b)) / (x * (c * x + d) + e), 1.0f);
}

float display_value(float radiance, const Display& d) {
  const float v = radiance * exposure_scale(d.exposure_ev);
  return d.tone == ToneCurve::Filmic ? tone_filmic(v) : std::clamp(v, 0.0f, 1.0f);
}

std::vector<uint8_t> to_srgb8(const Framebuffer& fb, const Display& d) {
  std::vector<uint8_t> out(fb.pixels.size() * 3);
  const float scale = exposure_scale(d.exposure_ev);
  const bool filmic = d.tone == ToneCurve::Filmic;
  for (size_t i = 0; i < fb.pixels.size(); ++i) {
    const Vec3 c = fb.pixels[i] * scale;
    for (int k = 0; k < 3; ++k)
      out[3 * i + size_t(k)] = encode_srgb(filmic ? tone_filmic(c[k]) : c[k]);
  }
  return out;
}

Framebuffer make_quilt(const std::vector<Framebuffer>& views, int columns) {
  if (views.empty() || columns < 1) return {};
  const int w = views[0].width, h = views[0].height;
  const int rows = int((views.size() + size_t(columns) - 1) / size_t(columns));
  Framebuffer q(w * columns, h * rows);
  for (size_t v = 0; v < views.size(); ++v) {
    const int ox = int(v % size_t(columns)) * w, oy = int(v / size_t(columns)) * h;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) q.at(ox + x, oy + y) = views[v].at(x, y);
  }
  return q;
}

void write_png_rgb8(const std::string& path, int width, int height,
                    const std::vector<uint8_t>& rgb) {
  // Encoded in memory (stb's own file writer does not check its writes), then written
  // atomically.
  std::string png;
  auto append = [](void* out, void* data, int size) {
    static_cast<std::string*>(out)->append(static_cast<const char*>(data), size_t(size));
  };
  if (!stbi_write_png_to_func(append, &png, width, height, 3, rgb.data(), width * 3))
    throw InputError("cannot encode PNG '" + path + "'");
  write_file_atomically(path, png);
}

std::string encode_jpeg(int width, int height, const std::vector<uint8_t>& rgb, int quality) {
  std::string jpeg;
  auto append = [](void* out, void* data, int size) {
    static_cast<std::string*>(out)->append(static_cast<const char*>(data), size_t(size));
  };
  if (rgb.size() != size_t(width) * size_t(height) * 3 ||
      !stbi_write_jpg_to_func(append, &jpeg, width, height, 3, rgb.data(), quality))
    throw InputError("cannot encode a JPEG image");
  return jpeg;
}

void write_png(const std::string& path, const Framebuffer& fb, const Display& d) {
  write_png_rgb8(path, fb.width, fb.height, to_srgb8(fb, d));
}

void write_exr_planes(const std::string& path, int width, int height,
                      const std::vector<ExrPlane>& planes) {
  try {
    replace_file_atomically(path, [&](const std::string& temp) {
      Imf::Header header(width, height);
      header.compression() = Imf::ZIP_COMPRESSION;
      Imf::FrameBuffer slices;
      for (const ExrPlane& p : planes) {
        header.channels().insert(p.channel, Imf::Channel(Imf::FLOAT));
        char* base = const_cast<char*>(reinterpret_cast<const char*>(p.base));
        const size_t xs = p.stride * sizeof(float);
        slices.insert(p.channel, Imf::Slice(Imf::FLOAT, base, xs, xs * size_t(width)));
      }
      Imf::OutputFile file(temp.c_str(), header);
      file.setFrameBuffer(slices);
      file.writePixels(height);
    });
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot write EXR '" + path + "': " + e.what());
  }
}

static_assert(sizeof(Vec3) == 3 * sizeof(float), "write_exr reads pixels as float triples");

void write_exr(const std::string& path, const Framebuffer& fb) {
  // Pixels are Vec3 of floats, row-major: one plane per channel over the same array.
  const float* rgb = &fb.pixels.data()->x;
  std::vector<ExrPlane> planes{{"R", rgb, 3}, {"G", rgb + 1, 3}, {"B", rgb + 2, 3}};
  if (fb.alpha.size() == fb.pixels.size() && !fb.alpha.empty())
    planes.push_back({"A", fb.alpha.data(), 1});
  write_exr_planes(path, fb.width, fb.height, planes);
}

Framebuffer read_exr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i box = file.header().dataWindow();
    const int64_t w = int64_t(box.max.x) - box.min.x + 1, h = int64_t(box.max.y) - box.min.y + 1;
    if (w < 1 || h < 1 || w * h > (int64_t(1) << 28))
      throw InputError("EXR '" + path + "': an image of " + std::to_string(w) + "x" +
                       std::to_string(h) + " pixels is out of range");
    const char* names[3] = {"R", "G", "B"};
    for (const char* n : names)
      if (!file.header().channels().findChannel(n))
        throw InputError("EXR '" + path + "' has no channel " + n);
    Framebuffer fb{int(w), int(h)};
    Imf::FrameBuffer slices;
    const size_t xs = sizeof(Vec3), ys = sizeof(Vec3) * size_t(w);
    // OpenEXR addresses slices by absolute pixel coordinates: shift the base by the
    // data window's origin.
    char* base = reinterpret_cast<char*>(fb.pixels.data()) - int64_t(box.min.x) * int64_t(xs) -
                 int64_t(box.min.y) * int64_t(ys);
    for (int c = 0; c < 3; ++c)
      slices.insert(names[c], Imf::Slice(Imf::FLOAT, base + size_t(c) * sizeof(float), xs, ys));
    file.setFrameBuffer(slices);
    file.readPixels(box.min.y, box.max.y);
    return fb;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError("cannot read EXR '" + path + "': " + e.what());
  }
}

}  // namespace multiray
