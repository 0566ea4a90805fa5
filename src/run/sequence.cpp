#include "run/sequence.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "volume/transfer_function.h"

namespace multiray {

namespace {

constexpr int kMaxFrames = 1000000;
constexpr uintmax_t kMaxSequenceBytes = 1 << 20;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputError("sequence '" + path + "': " + what);
}

// [[frame, value], ...] with frames strictly increasing in [0, kMaxFrames].
template <class T, class Check>
std::vector<std::pair<int, T>> keyed(const nlohmann::json& list, const std::string& path,
                                     const char* key, Check check) {
  if (!list.is_array()) fail(path, std::string(key) + " must be a list of [frame, value]");
  std::vector<std::pair<int, T>> out;
  for (const auto& e : list) {
    if (!e.is_array() || e.size() != 2 || !e[0].is_number_integer())
      fail(path, std::string(key) + " entries must be [frame, value]");
    const auto frame = e[0].get<int64_t>();
    if (frame < 0 || frame > kMaxFrames || (!out.empty() && frame <= out.back().first))
      fail(path,
           std::string(key) + " frames must increase within 0.." + std::to_string(kMaxFrames));
    out.emplace_back(int(frame), check(e[1]));
  }
  return out;
}

}  // namespace

const std::string& InteractionSequence::tf_at(int frame) const {
  static const std::string none;
  const std::string* current = &none;
  for (const auto& [f, name] : transfer_functions)
    if (f <= frame) current = &name;
  return *current;
}

InteractionSequence load_sequence(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(path, "not a regular file");
  if (std::filesystem::file_size(path, ec) > kMaxSequenceBytes) fail(path, "larger than 1 MiB");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) fail(path, "not a JSON object");
  InteractionSequence seq;
  const std::string dir = std::filesystem::path(path).parent_path().string();
  for (const auto& [key, value] : j.items()) {
    if (key == "frames") {
      if (!value.is_number_integer() || value.get<int64_t>() < 1 ||
          value.get<int64_t>() > kMaxFrames)
        fail(path, "frames must be a whole number in 1..1000000");
      seq.frames = int(value.get<int64_t>());
    } else if (key == "orbit_degrees_per_frame") {
      if (!value.is_number() || !(std::abs(value.get<double>()) <= 360))
        fail(path, "orbit_degrees_per_frame must be a number in [-360, 360]");
      seq.degrees_per_frame = value.get<double>();
    } else if (key == "zoom") {
      seq.zoom = keyed<double>(value, path, "zoom", [&](const nlohmann::json& v) {
        if (!v.is_number() || !(v.get<double>() >= 0.01 && v.get<double>() <= 100))
          fail(path, "zoom factors must be numbers in [0.01, 100]");
        return v.get<double>();
      });
    } else if (key == "transfer_functions") {
      seq.transfer_functions =
          keyed<std::string>(value, path, "transfer_functions", [&](const nlohmann::json& v) {
            if (!v.is_string()) fail(path, "transfer functions are preset names or file names");
            const std::string name = v.get<std::string>();
            for (const std::string& p : transfer_preset_names())
              if (p == name) return name;
            return (std::filesystem::path(dir) / name).string();
          });
    } else {
      fail(path, "unknown key '" + key + "'");
    }
  }
  return seq;
}

CameraPath sequence_path(const InteractionSequence& seq, const Camera& base, int frames) {
  std::vector<Keyframe> keys;
  const Vec3 up = normalize(base.up), offset = base.eye - base.target;
  for (int f = 0; f < frames; ++f) {
    double zoom = 1;
    const auto& z = seq.zoom;
    if (!z.empty()) {
      zoom = f <= z.front().first ? z.front().second : z.back().second;
      for (size_t i = 1; i < z.size(); ++i)
        if (f >= z[i - 1].first && f <= z[i].first) {
          const double t = double(f - z[i - 1].first) / double(z[i].first - z[i - 1].first);
          zoom = z[i - 1].second + t * (z[i].second - z[i - 1].second);
        }
    }
    // Rodrigues' rotation of the eye offset about the up axis.
    const float a = float(seq.degrees_per_frame * f * kPi / 180.0);
    const Vec3 rotated = offset * std::cos(a) + cross(up, offset) * std::sin(a) +
                         up * (dot(up, offset) * (1 - std::cos(a)));
    Keyframe k;
    k.frame = float(f);
    k.camera = base;
    k.camera.eye = base.target + rotated * float(zoom);
    keys.push_back(k);
  }
  return CameraPath::keyframes(std::move(keys));
}

}  // namespace multiray
