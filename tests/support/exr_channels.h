// Reading an EXR's channels with OpenEXR's own reader (not ours), for tests of what the
// writers put in a file: its channel names and any channel's floats.
#pragma once

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <string>
#include <vector>

namespace multiray::testing {

// The channel names of `path`, in the file's (alphabetical) order.
inline std::vector<std::string> exr_channels(const std::string& path) {
  Imf::InputFile file(path.c_str());
  std::vector<std::string> out;
  for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
    out.push_back(it.name());
  return out;
}

// Channel `name` of `path` as floats, row-major.
inline std::vector<float> exr_channel(const std::string& path, const std::string& name) {
  Imf::InputFile file(path.c_str());
  const Imath::Box2i box = file.header().dataWindow();
  const int w = box.max.x - box.min.x + 1, h = box.max.y - box.min.y + 1;
  std::vector<float> v(size_t(w) * size_t(h));
  Imf::FrameBuffer fb;
  fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(v.data()), sizeof(float),
                             sizeof(float) * size_t(w)));
  file.setFrameBuffer(fb);
  file.readPixels(box.min.y, box.max.y);
  return v;
}

}  // namespace multiray::testing
