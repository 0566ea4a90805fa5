#include "device/scene_memory.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "core/error.h"
#include "render/compact_scene.h"
#include "util/parse.h"

namespace multiray {

uint64_t estimate_scene_bytes(const Scene& s, bool compact) {
  if (compact) return estimate_compact_bytes(s).total();
  const SceneBytes mesh_and_tree = full_precision_bytes(s, s.triangle_count());
  return mesh_and_tree.total() + s.triangle_count() * (48 + 64);
}

uint64_t parse_memory_size(const std::string& text) {
  const double bytes = parse_size(text).value_or(-1);
  if (bytes < 0)
    throw std::invalid_argument("mem=" + text + " is not a size like 512M or 2G (K, M, G or T)");
  if (bytes < 1024.0 * 1024 || bytes > 1024.0 * 1024 * 1024 * 1024 * 1024)
    throw std::invalid_argument("mem=" + text + " must lie between 1M and 1024T");
  return uint64_t(bytes);
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
