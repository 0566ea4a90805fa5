#include "core/aov_exr.h"

#include "core/error.h"
#include "core/exr_planes.h"

namespace multiray {

namespace {

std::vector<ExrPlane> aov_planes(const std::string& name, const FeatureBuffers& f) {
  const std::vector<std::string> ch = aov_channels(name);
  if (name == "albedo")
    return {{ch[0], f.albedo.data(), 3},
            {ch[1], f.albedo.data() + 1, 3},
            {ch[2], f.albedo.data() + 2, 3}};
  if (name == "normal")
    return {{ch[0], f.normal.data(), 3},
            {ch[1], f.normal.data() + 1, 3},
            {ch[2], f.normal.data() + 2, 3}};
  if (name == "depth") return {{ch[0], f.depth.data(), 1}};
  if (name == "emission")
    return {{ch[0], f.emission.data(), 3},
            {ch[1], f.emission.data() + 1, 3},
            {ch[2], f.emission.data() + 2, 3}};
  return {{ch[0], f.variance.data(), 1}};
}

}  // namespace

std::vector<std::string> aov_channels(const std::string& name) {
  if (name == "albedo") return {"albedo.R", "albedo.G", "albedo.B"};
  if (name == "normal") return {"normal.X", "normal.Y", "normal.Z"};
  if (name == "depth") return {"depth.Z"};
  if (name == "variance") return {"variance.Y"};
  if (name == "emission") return {"emission.R", "emission.G", "emission.B"};
  throw InputError("no AOV called '" + name + "'");
}

void write_exr_with_aovs(const std::string& path, const Framebuffer& fb,
                         const std::vector<std::string>& aovs) {
  const FeatureBuffers& f = fb.features;
  if (!aovs.empty() && (f.empty() || f.width != fb.width || f.height != fb.height))
    throw InputError("cannot write EXR '" + path + "': the frame has no feature buffers");
  // A of 1 where the image has no coverage of its own: the beauty is opaque.
  const std::vector<float> opaque(fb.alpha.empty() ? fb.pixels.size() : 0, 1.0f);
  const std::vector<float>& alpha = fb.alpha.empty() ? opaque : fb.alpha;
  std::vector<ExrPlane> planes;
  const float* rgb = &fb.pixels.data()->x;
  planes.push_back({"R", rgb, 3}), planes.push_back({"G", rgb + 1, 3});
  planes.push_back({"B", rgb + 2, 3}), planes.push_back({"A", alpha.data(), 1});
  for (const std::string& name : aovs)
    for (const ExrPlane& p : aov_planes(name, f)) planes.push_back(p);
  write_exr_planes(path, fb.width, fb.height, planes);
}

}  // namespace multiray
