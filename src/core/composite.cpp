#include "core/composite.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/file_io.h"
#include "core/resample.h"

namespace multiray {

namespace {

constexpr int64_t kMaxPixels = int64_t(1) << 28;

bool is_exr(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".exr";
}

float decode_srgb(uint8_t v) {
  const double c = v / 255.0;
  return float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

// Width, height and channels from the file's header, without decoding its pixels (an
// EXR's channels are read straight into floats: reported as 0, no decoder copy).
struct ImageHeader {
  int64_t width = 0, height = 0;
  int channels = 0;
};
ImageHeader image_header(const std::string& path) {
  if (is_exr(path)) {
    try {
      Imf::InputFile file(path.c_str());
      const auto box = file.header().dataWindow();
      return {int64_t(box.max.x) - box.min.x + 1, int64_t(box.max.y) - box.min.y + 1, 0};
    } catch (const std::exception& e) {
      throw InputError("cannot read EXR '" + path + "': " + e.what());
    }
  }
  int w = 0, h = 0, n = 0;
  if (!stbi_info(path.c_str(), &w, &h, &n))
    throw InputError("'" + path + "' is not an image this build reads (PNG, JPEG, BMP, TGA, EXR)");
  return {w, h, n};
}
std::pair<int64_t, int64_t> image_size(const std::string& path) {
  const ImageHeader h = image_header(path);
  return {h.width, h.height};
}

std::string size_text(int64_t w, int64_t h) { return std::to_string(w) + "x" + std::to_string(h); }

}  // namespace

Framebuffer composite_over(const Framebuffer& layer, const Framebuffer& background) {
  if (layer.alpha.size() != layer.pixels.size() || background.width != layer.width ||
      background.height != layer.height)
    throw std::invalid_argument("composite_over: a layer with alpha over an image of its size");
  Framebuffer out(layer.width, layer.height);
  for (size_t i = 0; i < layer.pixels.size(); ++i)
    out.pixels[i] = layer.pixels[i] + background.pixels[i] * (1.0f - layer.alpha[i]);
  return out;
}

std::vector<uint8_t> to_srgba8(const Framebuffer& layer, const Display& d) {
  std::vector<uint8_t> out(layer.pixels.size() * 4, 0);
  Framebuffer straight(layer.width, layer.height);
  for (size_t i = 0; i < layer.pixels.size(); ++i) {
    const float a = layer.alpha.empty() ? 1.0f : layer.alpha[i];
    straight.pixels[i] = a > 0.0f ? layer.pixels[i] * (1.0f / a) : Vec3(0.0f);
  }
  const std::vector<uint8_t> rgb = to_srgb8(straight, d);
  for (size_t i = 0; i < layer.pixels.size(); ++i) {
    const float a = layer.alpha.empty() ? 1.0f : layer.alpha[i];
    std::copy_n(&rgb[3 * i], 3, &out[4 * i]);
    out[4 * i + 3] = uint8_t(std::lround(std::clamp(a, 0.0f, 1.0f) * 255.0f));
  }
  return out;
}

std::string encode_png_rgba(int width, int height, const std::vector<uint8_t>& rgba) {
  std::string png;
  auto append = [](void* out, void* data, int size) {
    static_cast<std::string*>(out)->append(static_cast<const char*>(data), size_t(size));
  };
  if (rgba.size() != size_t(width) * size_t(height) * 4 ||
      !stbi_write_png_to_func(append, &png, width, height, 4, rgba.data(), width * 4))
    throw InputError("cannot encode an RGBA PNG image");
  return png;
}

void write_png_rgba(const std::string& path, const Framebuffer& layer, const Display& d) {
  write_file_atomically(path, encode_png_rgba(layer.width, layer.height, to_srgba8(layer, d)));
}

Framebuffer read_image_linear(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError("'" + path + "' does not exist or is not a file");
  if (is_exr(path)) return read_exr(path);
  const auto [w0, h0] = image_size(path);
  if (w0 < 1 || h0 < 1 || w0 * h0 > kMaxPixels)
    throw InputError("'" + path + "': an image of " + size_text(w0, h0) +
                     " pixels (at most 2^28)");
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load(path.c_str(), &w, &h, &n, 3);
  if (px == nullptr)
    throw InputError("cannot decode '" + path +
                     "': " + (stbi_failure_reason() ? stbi_failure_reason() : "unknown reason"));
  Framebuffer fb(w, h);
  float table[256];
  for (int v = 0; v < 256; ++v) table[v] = decode_srgb(uint8_t(v));
  for (size_t i = 0; i < fb.pixels.size(); ++i)
    fb.pixels[i] = Vec3(table[px[3 * i]], table[px[3 * i + 1]], table[px[3 * i + 2]]);
  stbi_image_free(px);
  return fb;
}

BackgroundImages::BackgroundImages(std::string spec, int width, int height, int frames)
    : spec_(std::move(spec)), width_(width), height_(height) {
  const size_t slash = spec_.find_last_of('/');
  const size_t name_at = slash == std::string::npos ? 0 : slash + 1;
  hashes_at_ = spec_.find('#', name_at);
  if (hashes_at_ != std::string::npos) {
    hashes_ = spec_.find_first_not_of('#', hashes_at_) - hashes_at_;
    if (spec_.find('#', hashes_at_ + hashes_) != std::string::npos)
      throw InputError("--background '" + spec_ + "': one run of # (the frame number), not two");
  }
  const int count = hashes_at_ == std::string::npos ? 1 : frames;
  for (int f = 0; f < count; ++f) {
    const std::string p = path(f);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec))
      throw InputError("--background: '" + p + "' (frame " + std::to_string(f) +
                       ") does not exist or is not a file");
    const ImageHeader header = image_header(p);
    const int64_t w = header.width, h = header.height;
    const double a = double(w) / double(std::max<int64_t>(h, 1)), want = double(width) / height;
    if (w < 1 || h < 1 || w * h > kMaxPixels || !(std::abs(a / want - 1.0) <= 0.01))
      throw InputError("--background: '" + p + "' is " + size_text(w, h) +
                       ", whose aspect ratio is not the output's (" + size_text(width, height) +
                       "); crop it or change --res");
    const uint64_t bytes = background_decode_bytes(w, h, header.channels, width, height);
    if (bytes > largest_.bytes) largest_ = {p, w, h, bytes};
  }
}

uint64_t background_decode_bytes(int64_t w, int64_t h, int channels, int width, int height) {
  const uint64_t pixels = uint64_t(std::max<int64_t>(w, 0)) * uint64_t(std::max<int64_t>(h, 0));
  // stb's 8-bit RGB copy (3) and its decoder's own pixels in the file's channels of up to
  // 16 bits (2 each), as texture_load.cpp charges them; then the linear Framebuffer.
  const uint64_t decoder = channels > 0 ? 3 + 2 * uint64_t(std::clamp(channels, 1, 4)) : 0;
  const bool resized = w != width || h != height;
  return pixels * (sizeof(Vec3) + decoder) +
         (resized ? uint64_t(width) * uint64_t(height) * sizeof(Vec3) : 0);
}

std::string BackgroundImages::path(int frame) const {
  if (hashes_at_ == std::string::npos) return spec_;
  std::string number = std::to_string(frame);
  if (number.size() < hashes_) number.insert(0, hashes_ - number.size(), '0');
  return spec_.substr(0, hashes_at_) + number + spec_.substr(hashes_at_ + hashes_);
}

Framebuffer BackgroundImages::frame(int frame) const {
  const Framebuffer image = read_image_linear(path(frame));
  if (image.width == width_ && image.height == height_) return image;
  Framebuffer sized(width_, height_);
  upscale_bilinear(image, sized);
  return sized;
}

}  // namespace multiray
