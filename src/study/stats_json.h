// JSON forms of the engine's records, shared by `render` and `bench`.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "balance/balancer.h"
#include "device/device.h"
#include "engine/frame_record.h"

namespace multiray {
struct RunConfig;
struct Run;
struct FrameResult;
}  // namespace multiray

namespace multiray::study {

// The project version (CMake's PROJECT_VERSION), for --version and stats.json.
inline constexpr const char* kVersion = MULTIRAY_VERSION;

// `doc` as text, indented by `indent` (-1: one line). Strings that are not valid UTF-8
// (paths are bytes on Linux: a scene named "\xE9\xFF.obj") are recorded with their invalid
// bytes as "\xHH" (util/utf8.h), so the document is valid JSON whatever the names are.
std::string dump_json(const nlohmann::json& doc, int indent = 1);

nlohmann::json frame_to_json(const FrameRecord& rec);
// A rendered frame's record in stats.json's "frames" (and the Python module's per-frame
// stats): frame_to_json of its record, with sampling_ms, reprojection (reprojected
// sampling only) and image_hash (XXH3 over every view's float pixels, chained in view
// order, as 16 hex digits: core/image.h image_hash).
nlohmann::json frame_result_to_json(const FrameResult& r);
// A reprojected frame's summary: {"reference_views", "hole_fraction"}.
nlohmann::json reprojection_to_json(const std::vector<uint32_t>& reference_views,
                                    double hole_fraction);
// The settings a run was made with, so that stats.json alone says how to repeat it: the
// command line, version, scene, resolution, spp, bounces, frames, kernel, sampling, seed,
// camera (where it came from and the one used), up axis, camera path, environment, views
// and the devices asked for. Output options (balancer, exposure, tone) are the caller's.
nlohmann::json settings_to_json(const RunConfig& o, const Run& s,
                                const std::vector<std::string>& command_line);
nlohmann::json devices_to_json(const std::vector<std::unique_ptr<Device>>& devices);
}  // namespace multiray::study
