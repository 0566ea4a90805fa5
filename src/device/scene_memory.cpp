#include "device/scene_memory.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "core/error.h"
#include "render/compact_scene.h"

namespace multiray {

uint64_t estimate_scene_bytes(const Scene& s, bool compact) {
  if (compact) return estimate_compact_bytes(s).total();
  const SceneBytes mesh_and_tree = full_precision_bytes(s, s.triangle_count());
  return mesh_and_tree.total() + s.triangle_count() * (48 + 64);
}

uint64_t parse_memory_size(const std::string& text) {
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw std::invalid_argument("mem=" + text + " is not a size like 512M or 2G");
  }
  const std::string unit = text.substr(used);
  double scale = 1;
  if (unit == "K" || unit == "k")
    scale = 1024.0;
  else if (unit == "M" || unit == "m")
    scale = 1024.0 * 1024;
  else if (unit == "G" || unit == "g")
    scale = 1024.0 * 1024 * 1024;
  else if (unit == "T" || unit == "t")
    scale = 1024.0 * 1024 * 1024 * 1024;
  else if (!unit.empty())
    throw std::invalid_argument("mem=" + text + ": unknown unit '" + unit + "' (K, M, G or T)");
  const double bytes = value * scale;
  if (!std::isfinite(bytes) || bytes < 1024.0 * 1024 || bytes > 1024.0 * 1024 * 1024 * 1024 * 1024)
    throw std::invalid_argument("mem=" + text + " must lie between 1M and 1024T");
  return uint64_t(bytes);
}

std::string format_bytes(uint64_t b) {
  if (b >= (1ull << 30)) return fmt::format("{:.1f} GiB", double(b) / double(1ull << 30));
  if (b >= (1ull << 20)) return fmt::format("{:.1f} MiB", double(b) / double(1ull << 20));
  return fmt::format("{:.1f} KiB", double(b) / 1024.0);
}

void check_scene_fits(const Scene& scene, bool compact, uint64_t limit, const std::string& what) {
  if (limit == 0 || !scene.has_triangles()) return;
  const uint64_t need = estimate_scene_bytes(scene, compact);
  if (need <= limit) return;
  const uint64_t compact_need = estimate_scene_bytes(scene, true);
  std::string hint;
  if (!compact)
    hint = compact_need <= limit
               ? fmt::format("; compact=1 would need about {} and fit", format_bytes(compact_need))
               : fmt::format("; even compact=1 needs about {}", format_bytes(compact_need));
  throw InputError(
      fmt::format("{}: the scene needs about {} as {} and the device has {} (emulated "
                  "limit){}",
                  what, format_bytes(need), compact ? "compact" : "full precision",
                  format_bytes(limit), hint));
}

}  // namespace multiray
