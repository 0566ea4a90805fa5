#include "app/output_target.h"

#include <cctype>
#include <filesystem>

#include <fmt/core.h>

#include "core/error.h"

namespace multiray::app {

namespace {

namespace fs = std::filesystem;

bool ends_with_ci(const std::string& s, const std::string& end) {
  if (s.size() < end.size()) return false;
  for (size_t i = 0; i < end.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - end.size() + i])) != end[i])
      return false;
  return true;
}

// The stats file's stem: the pattern without its frame number and the separator that led to
// it ("shot_" + "" -> "shot", "shot_" + "_beauty" -> "shot_beauty").
std::string stats_stem(std::string prefix, const std::string& suffix) {
  while (!prefix.empty() && (prefix.back() == '_' || prefix.back() == '-' || prefix.back() == '.'))
    prefix.pop_back();
  const std::string stem = prefix + suffix;
  return stem.empty() ? "render" : stem;
}

bool all_digits(const std::string& s, size_t from, size_t to) {
  if (from >= to) return false;
  for (size_t i = from; i < to; ++i)
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
  return true;
}

}  // namespace

std::string OutputTarget::image_base(int frame, const std::string& tag) const {
  const std::string number = digits > 0 ? fmt::format("{:0{}d}", frame, digits) : "";
  return dir + "/" + prefix + number + suffix + tag;
}

bool OutputTarget::owns(const std::string& name) const {
  if (name == stats) return true;
  if (!pattern) return name.rfind(prefix, 0) == 0;  // frame_*, as every earlier version wrote
  if (name.rfind(prefix, 0) != 0) return false;
  // prefix, the frame number, suffix, an optional view or quilt tag, the extension.
  size_t end = name.size();
  if (ends_with_ci(name, ".png") || ends_with_ci(name, ".exr"))
    end -= 4;
  else
    return false;
  std::string rest = name.substr(0, end);
  if (rest.size() >= 6 && rest.compare(rest.size() - 6, 6, "_split") == 0)
    rest.resize(rest.size() - 6);  // --overlay's picture of the split
  if (rest.size() >= 4 && rest.compare(rest.size() - 4, 4, "_aov") == 0)
    rest.resize(rest.size() - 4);  // --aov's layers beside a PNG (docs/usage.md)
  if (rest.size() >= 5 && rest.compare(rest.size() - 5, 5, "_rgba") == 0)
    rest.resize(rest.size() - 5);  // an augmented-reality layer (docs/ar.md)
  if (rest.size() >= 6 && rest.compare(rest.size() - 6, 6, "_quilt") == 0)
    rest.resize(rest.size() - 6);
  else if (rest.size() >= 7 && rest.compare(rest.size() - 7, 5, "_view") == 0 &&
           all_digits(rest, rest.size() - 2, rest.size()))
    rest.resize(rest.size() - 7);
  if (rest.size() < prefix.size() + suffix.size()) return false;
  if (rest.compare(rest.size() - suffix.size(), suffix.size(), suffix) != 0) return false;
  const size_t from = prefix.size(), to = rest.size() - suffix.size();
  return digits == 0 ? from == to : all_digits(rest, from, to);
}

OutputTarget parse_output_target(const std::string& out, int frames, bool exr_flag) {
  OutputTarget t;
  const bool png = ends_with_ci(out, ".png"), exr = ends_with_ci(out, ".exr");
  if (!png && !exr) {  // a folder
    t.dir = out;
    t.prefix = "frame_";
    t.stats = "stats.json";
    t.exr = exr_flag;
    return t;
  }
  t.pattern = true;
  const fs::path path(out);
  t.dir = path.has_parent_path() ? path.parent_path().string() : ".";
  const std::string name = path.filename().string();
  const std::string stem = name.substr(0, name.size() - 4);
  const size_t first = stem.find('#');
  if (first == std::string::npos) {
    if (frames > 1)
      throw InputError(fmt::format(
          "-o '{}' names one file but {} frames are rendered; put #### where the frame "
          "number goes (e.g. {}_####{}) or give a folder",
          out, frames, stem, name.substr(name.size() - 4)));
    t.prefix = stem;
    t.digits = 0;
  } else {
    const size_t last = stem.find_first_not_of('#', first);
    const size_t run_end = last == std::string::npos ? stem.size() : last;
    if (stem.find('#', run_end) != std::string::npos)
      throw InputError("-o '" + out +
                       "' has two runs of '#'; one run stands for the frame number");
    t.prefix = stem.substr(0, first);
    t.digits = int(run_end - first);
    t.suffix = stem.substr(run_end);
  }
  if (exr && exr_flag)
    throw InputError("--exr adds EXR files beside PNG ones; -o '" + out +
                     "' already asks for EXR files only");
  t.png = png;
  t.exr = exr || exr_flag;
  t.stats = stats_stem(t.prefix, t.suffix) + ".stats.json";
  return t;
}

std::string first_free_folder(const std::string& base) {
  const OutputTarget folder = parse_output_target(base, 1, false);
  auto holds_outputs = [&](const std::string& dir) {
    std::error_code ec;
    if (!fs::exists(dir, ec)) return false;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (folder.owns(e.path().filename().string())) return true;
    return bool(ec) || !fs::is_directory(dir, ec);
  };
  if (!holds_outputs(base)) return base;
  for (int i = 2; i < 10000; ++i) {
    const std::string dir = fmt::format("{}-{}", base, i);
    if (!holds_outputs(dir)) return dir;
  }
  throw InputError("no free output folder '" + base + "-N' (N up to 9999); pass -o");
}

}  // namespace multiray::app
