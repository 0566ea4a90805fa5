// The emulated memory limit of a device (`mem=` in its --devices spec): a device whose
// scene representation would not fit is refused before anything is built, with one line
// that says what it needs and whether compact=1 would fit (Seo, Park & Ihm, Sensors 2022,
// §3: the compact scene exists so that a weak device can hold the whole scene). The limit
// is an emulation: nothing stops the process from taking more, and every message and
// report says "emulated".
#pragma once

#include <cstdint>
#include <string>

#include "scene/scene.h"
#include "util/parse.h"

namespace multiray {

// Bytes a device needs for `scene` before building it: an upper bound for either backend
// (full precision: float mesh, one tree node and a 48-byte triangle copy per triangle and a
// 64-byte shading record per triangle; compact: compact_scene.h's estimate). Volumes are
// not counted (their backends check their own memory).
uint64_t estimate_scene_bytes(const Scene& scene, bool compact);

// mem=: a size as util/parse.h reads one ("512M", "2g", "65536": binary K/M/G/T, either
// case). Throws std::invalid_argument (one line) unless it lies in [1 MiB, 1 PiB].
// (format_bytes, for the other direction, is util/parse.h's.)
uint64_t parse_memory_size(const std::string& text);

// Throws InputError when `limit` > 0 and the scene does not fit the chosen representation;
// the message names both representations' needs. `what` prefixes it ("--devices 'cpu:mem=1G'").
void check_scene_fits(const Scene& scene, bool compact, uint64_t limit, const std::string& what);

}  // namespace multiray
