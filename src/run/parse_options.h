// Strict parsing of a RunConfig's values that are richer than a number. Each throws
// InputError with a one-line message naming the option ("--res '64' must look like
// 640x360").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "balance/balancer.h"
#include "core/image.h"
#include "engine/frame_views.h"
#include "engine/session.h"
#include "scene/scene.h"
#include "util/parse.h"

namespace multiray {

// Parses --gaze "X,Y" (each in [0, 1]) and --gaze-path (fixed | orbit | orbit:PERIOD).
GazePath parse_gaze(const std::string& gaze, const std::string& path);

struct Resolution {
  int width = 0, height = 0;
};

Resolution parse_resolution(const std::string& text);
uint64_t parse_seed(const std::string& text);
Camera parse_camera(const std::string& text);
// --up: "auto" (+y for meshes, +z for volumes, whose slices stack along z) or an axis
// x, y, z with an optional sign.
Vec3 parse_up(const std::string& text, bool volume);
// --exposure in stops, [-20, 20].
float parse_exposure(double ev);
// --tone: filmic, clamp, or auto (filmic for meshes; clamp for volumes, whose raycaster
// already writes display colours in [0, 1]).
ToneCurve parse_tone(const std::string& text, bool volume);
// Adds the layout `mapping` asks for to a balancer spec: strips (every device renders its
// share of every view's shuffled strips) or views (whole views per device). Empty: spec
// unchanged, and `auto` too (Run::resolve_balancer applies it to what auto picks).
// Throws InputError when the balancer has no such layout, or a malformed spec as a bad
// value of `option` (the command-line option that gave the spec).
std::string apply_mapping(const std::string& balancer_spec, const std::string& mapping,
                          const std::string& option = "--balancer");

std::vector<Perturbation> parse_perturbations(const std::vector<std::string>& items,
                                              int device_count);

// A number filling the whole token (util/parse.h's parse_number), else InputError
// "<what>: '<tok>' is not a number".
double to_number(const std::string& tok, const std::string& what);

// make_balancer, with std::invalid_argument turned into InputError naming `option` (the
// command-line option the spec came from).
std::unique_ptr<balance::Balancer> make_balancer_or_throw(
    const std::string& spec, int devices, const std::string& option = "--balancer");

}  // namespace multiray
