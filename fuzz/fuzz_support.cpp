#include "fuzz_support.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <system_error>

#include "balance/balancer.h"
#include "device/cpu/cpu_device.h"
#include "engine/frame_views.h"
#include "engine/session.h"
#include "render/scene_cache.h"
#include "scene/builders.h"
#include "scene/camera_path.h"
#include "scene/camera_rig.h"

namespace multiray::fuzz {

namespace fs = std::filesystem;

namespace {

// stderr as it was when the process started: libFuzzer's -close_fd_mask=2 later points fd 2
// at /dev/null (the CLI target's runs print a lot), but fail() must still be heard.
const int kReportFd = dup(2);

fs::path make_scratch_dir() {
  std::error_code ec;
  fs::path base;
  if (const char* given = std::getenv("MULTIRAY_FUZZ_SCRATCH");
      given && fs::is_directory(given, ec))
    base = given;
  else if (fs::is_directory("/dev/shm", ec) && access("/dev/shm", W_OK) == 0)
    base = "/dev/shm";
  else
    base = fs::temp_directory_path(ec);
  if (ec || base.empty()) base = "/tmp";
  std::string pattern = (base / "multiray-fuzz-XXXXXX").string();
  if (!mkdtemp(pattern.data())) fail("cannot create a scratch folder under " + base.string());
  return pattern;
}

void remove_scratch() {
  std::error_code ec;
  fs::remove_all(scratch_dir(), ec);
}

}  // namespace

const fs::path& scratch_dir() {
  // Never destroyed: remove_scratch() reads it at exit. A static path, complete only after
  // that registration, was destroyed before it ran, and the folder stayed (unseen under
  // libFuzzer, whose runs end with _Exit(); replay_main.cpp's return from main()).
  static const fs::path* dir = [] {
    auto* d = new fs::path(make_scratch_dir());
    std::atexit(remove_scratch);
    return d;
  }();
  return *dir;
}

void clear_scratch() {
  std::error_code ec;
  for (fs::directory_iterator it(scratch_dir(), ec), end; !ec && it != end; it.increment(ec))
    fs::remove_all(it->path(), ec);
}

void write_file(const fs::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) fail("cannot write " + path.string());
}

FileSet split_files(const uint8_t* data, size_t size) {
  static constexpr std::string_view kMarker = "\n@@file ";
  const std::string_view in(reinterpret_cast<const char*>(data), size);
  FileSet out;
  size_t at = in.find(kMarker);
  out.main = in.substr(0, at);
  while (at != std::string_view::npos) {
    const size_t name_begin = at + kMarker.size();
    const size_t name_end = in.find('\n', name_begin);
    if (name_end == std::string_view::npos) break;
    const size_t next = in.find(kMarker, name_end);
    const std::string_view name = in.substr(name_begin, name_end - name_begin);
    const std::string_view body =
        in.substr(name_end + 1, next == std::string_view::npos ? next : next - name_end - 1);
    const bool plain = !name.empty() && name.size() <= 64 && name != "." && name != ".." &&
                       name.find('/') == std::string_view::npos &&
                       name.find('\0') == std::string_view::npos;
    if (plain) out.others.emplace_back(std::string(name), body);
    at = next;
  }
  return out;
}

fs::path write_files(const FileSet& files, const std::string& main_name) {
  clear_scratch();
  for (const auto& [name, bytes] : files.others) write_file(scratch_dir() / name, bytes);
  const fs::path main = scratch_dir() / main_name;
  write_file(main, files.main);
  return main;
}

void fail(const std::string& what) {
  const std::string line = "multiray fuzz: " + what + "\n";
  const int fd = kReportFd >= 0 ? kReportFd : 2;
  if (write(fd, line.data(), line.size()) < 0) std::fputs(line.c_str(), stderr);
  std::abort();
}

namespace {

struct PixelCheck : FrameObserver {
  const Camera* camera = nullptr;
  int frames = 0;
  void on_frame(const std::shared_ptr<const FrameResult>& r) override {
    ++frames;
    for (const Framebuffer& img : r->images)
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
          const Vec3& p = img.at(x, y);
          if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) continue;
          const Camera& c = *camera;
          char text[512];
          std::snprintf(text, sizeof text,
                        "pixel (%d, %d) = (%g, %g, %g) is not finite; camera eye (%g, %g, %g) "
                        "target (%g, %g, %g) up (%g, %g, %g) fov %g",
                        x, y, double(p.x), double(p.y), double(p.z), double(c.eye.x),
                        double(c.eye.y), double(c.eye.z), double(c.target.x), double(c.target.y),
                        double(c.target.z), double(c.up.x), double(c.up.y), double(c.up.z),
                        double(c.fov_y_deg));
          fail(text);
        }
  }
};

}  // namespace

void render_and_check(const Camera& camera, const std::string& kernel) {
  // Made once and kept to the end of the process (a device owns threads; tearing it down
  // in static destructors would race with TBB's own shutdown).
  static const Scene* scene = new Scene(make_cornell_box());
  static SceneCache* cache = new SceneCache(*scene);
  static CpuDevice* device = new CpuDevice(*cache, CpuDeviceOptions{}, "cpu");
  std::vector<std::unique_ptr<balance::Balancer>> lanes;
  lanes.push_back(balance::make_balancer("uniform", 1));
  RenderSettings settings;
  settings.spp = 1;
  settings.max_bounces = 3;
  settings.kernel = kernel;
  Session session({device}, std::move(lanes),
                  FrameViews(CameraRig::single(), kRenderWidth, kRenderHeight, {}),
                  CameraPath::fixed(camera), settings);
  PixelCheck check;
  check.camera = &camera;
  if (session.run(0, 1, check) != 1 || check.frames != 1)
    fail("the session did not complete the frame");
}

}  // namespace multiray::fuzz
