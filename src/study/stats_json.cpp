#include "study/stats_json.h"

#include <algorithm>

#include <fmt/core.h>

#include "core/error.h"
#include "engine/session.h"
#include "run/run.h"
#include "util/utf8.h"

namespace multiray::study {

namespace {
// A copy of `doc` whose every string (object keys too) is valid UTF-8.
nlohmann::json valid_utf8(const nlohmann::json& doc) {
  if (doc.is_string()) {
    const auto& s = doc.get_ref<const std::string&>();
    return is_valid_utf8(s) ? doc : nlohmann::json(escape_invalid_utf8(s));
  }
  if (doc.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& e : doc) out.push_back(valid_utf8(e));
    return out;
  }
  if (doc.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, value] : doc.items()) out[escape_invalid_utf8(key)] = valid_utf8(value);
    return out;
  }
  return doc;
}

nlohmann::json vec3_json(Vec3 v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json distributed_to_json(const Run& s) {
  if (!s.cluster) return nullptr;
  const DistributedOptions& o = s.cluster->options();
  return {{"ranks", s.cluster->size()},
          {"master_renders", o.master_renders},
          {"rank_devices", o.rank_devices},
          {"rank_balancer", o.rank_balancer},
          {"rank_split", o.same_direction ? "same direction" : "other direction"},
          {"link", s.cluster->link().describe()},
          {"link_emulated", s.cluster->link().active()},
          {"worker_timeout_s", o.worker_timeout_s},
          {"depth", o.depth},
          {"scene_from", o.scene_from},
          {"result_encoding", o.result_encoding}};
}

// True when every string in `doc` (keys too) is valid UTF-8: the common case, dumped
// without a copy.
bool all_valid_utf8(const nlohmann::json& doc) {
  if (doc.is_string()) return is_valid_utf8(doc.get_ref<const std::string&>());
  if (doc.is_array())
    return std::all_of(doc.begin(), doc.end(), [](const auto& e) { return all_valid_utf8(e); });
  if (doc.is_object())
    for (const auto& [key, value] : doc.items())
      if (!is_valid_utf8(key) || !all_valid_utf8(value)) return false;
  return true;
}
}  // namespace

std::string dump_json(const nlohmann::json& doc, int indent) {
  return all_valid_utf8(doc) ? doc.dump(indent) : valid_utf8(doc).dump(indent);
}

nlohmann::json settings_to_json(const RunConfig& o, const Run& s,
                                const std::vector<std::string>& command_line) {
  return {
      {"command_line", command_line},
      {"version", kVersion},
      {"scene", o.scene_path.empty() ? "(built-in Cornell box)" : o.scene_path},
      {"resolution", {s.res.width, s.res.height}},
      {"spp", s.settings.spp},
      {"bounces", s.settings.max_bounces},
      {"clamp", s.settings.sample_clamp},
      {"frames", o.frames},
      {"integrator", s.settings.kernel},
      {"sampling", o.sampling},
      {"seed", s.settings.seed},
      {"camera",
       {{"source", s.camera_source},
        {"eye", vec3_json(s.camera.eye)},
        {"target", vec3_json(s.camera.target)},
        {"up", vec3_json(s.camera.up)},
        {"fov_y_deg", s.camera.fov_y_deg}}},
      {"up", vec3_json(s.up)},
      {"camera_path", o.camera_path},
      {"poses", o.poses.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.poses)},
      {"ground",
       s.settings.catcher_axis < 0
           ? nlohmann::json(nullptr)
           : nlohmann::json{{"axis", std::string(1, char('x' + s.settings.catcher_axis))},
                            {"height", s.settings.catcher_height},
                            {"albedo", s.settings.catcher_albedo}}},
      {"environment", vec3_json(s.scene->environment)},
      {"environment_map",
       s.scene->environment_map ? nlohmann::json(s.scene->environment_map->name) : nullptr},
      {"environment_map_scale", s.scene->environment_map_scale},
      {"sun", s.scene->sun.on() ? nlohmann::json{{"direction", vec3_json(s.scene->sun.direction)},
                                                 {"radiance", vec3_json(s.scene->sun.radiance)},
                                                 {"half_angle_rad", s.scene->sun.half_angle_rad}}
                                : nlohmann::json(nullptr)},
      {"views", o.stereo > 0 ? "stereo" : o.views},
      {"view_spacing", s.view_spacing},
      {"devices", o.devices},
      {"distributed", distributed_to_json(s)}};
}

nlohmann::json reprojection_to_json(const std::vector<uint32_t>& reference_views,
                                    double hole_fraction) {
  return {{"reference_views", reference_views}, {"hole_fraction", hole_fraction}};
}

nlohmann::json frame_result_to_json(const FrameResult& r) {
  nlohmann::json record = frame_to_json(r.record);
  record["sampling_ms"] = r.sampling_ms;
  if (r.reprojection)
    record["reprojection"] =
        reprojection_to_json(r.reprojection->references, r.reprojection->hole_fraction());
  uint64_t hash = 0xcbf29ce484222325ull;
  for (const Framebuffer& img : r.images) hash = image_hash(img, hash);
  record["image_hash"] = fmt::format("{:016x}", hash);
  // --aov: the feature buffers' fingerprint too (as split-independent as the image's).
  if (!r.images.empty() && !r.images[0].features.empty()) {
    uint64_t features = 0xcbf29ce484222325ull;
    for (const Framebuffer& img : r.images) features = feature_hash(img.features, features);
    record["feature_hash"] = fmt::format("{:016x}", features);
  }
  return record;
}

nlohmann::json frame_to_json(const FrameRecord& rec) {
  nlohmann::json device_ms = nlohmann::json::array(), busy_ms = nlohmann::json::array(),
                 share = nlohmann::json::array(), planned = nlohmann::json::array(),
                 samples = nlohmann::json::array(), pixels = nlohmann::json::array(),
                 result_bytes = nlohmann::json::array(), left_out = nlohmann::json::array();
  // Every device at the bottom of the hierarchy: a rank's own devices, or the device.
  nlohmann::json leaf_ms = nlohmann::json::array();
  std::vector<double> leaves;
  for (const auto& d : rec.devices) {
    if (!d.alive) continue;
    const std::vector<double> mine =
        d.local_ms.empty() ? std::vector<double>{d.time_ms} : d.local_ms;
    leaf_ms.push_back(mine);
    leaves.insert(leaves.end(), mine.begin(), mine.end());
  }
  const double leaf_deviation = balance::deviation(leaves);
  for (const auto& d : rec.devices) {
    device_ms.push_back(d.time_ms);
    busy_ms.push_back(d.busy_ms);
    share.push_back(d.work_share);
    planned.push_back(d.planned_share);
    samples.push_back(d.samples);
    pixels.push_back(d.pixels);
    result_bytes.push_back(d.result_bytes);
    left_out.push_back(d.rested);
  }
  // The balancer's model of each device (hybrid's: fixed cost per frame and speed, fitted
  // over frames; participation.h), or null.
  nlohmann::json models = nlohmann::json::array();
  for (const balance::DeviceCostModel& m : rec.models)
    models.push_back({{"fixed_ms", m.fixed_ms},
                      {"fixed_sigma_ms", m.fixed_sigma},
                      {"speed", m.speed},
                      {"determined", m.determined},
                      {"contention", m.contention}});
  return {{"frame", rec.frame},
          {"frame_ms", rec.frame_ms},
          {"first_pass_ms", rec.first_pass_ms},
          {"device_ms", device_ms},
          {"busy_ms", busy_ms},
          {"work_share", share},
          {"planned_share", planned},
          {"samples", samples},
          {"pixels", pixels},
          {"result_bytes", result_bytes},
          {"left_out", left_out},
          {"device_model", rec.models.empty() ? nlohmann::json() : models},
          {"imbalance", rec.imbalance},
          {"deviation", rec.deviation},
          {"leaf_device_ms", leaf_ms},
          {"leaf_deviation", leaf_deviation},
          {"plan_ms", rec.plan_ms},
          {"gather_ms", rec.gather_ms},
          {"denoise_ms", rec.denoise_ms},
          {"update_ms", rec.update_ms},
          {"stolen_items", rec.stolen},
          {"messages", rec.messages},
          {"notes", rec.notes},
          {"quality",
           {{"image_scale", rec.quality.image_scale}, {"step_scale", rec.quality.step_scale}}},
          {"advise_ms", rec.advise_ms},
          {"learn_ms", rec.learn_ms},
          {"predicted_ms", rec.predicted_ms},
          {"predicted_cost", rec.predicted_cost},
          {"measured_cost", rec.measured_cost}};
}

nlohmann::json devices_to_json(const std::vector<std::unique_ptr<Device>>& devices) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& d : devices) {
    const DeviceInfo& i = d->info();
    out.push_back(
        {{"type", i.type},
         {"name", i.name},
         {"spec", i.spec},
         {"threads", i.threads},
         {"emulated_speed", i.emulated_speed},
         {"emulated", i.emulated_speed < 1.0},
         {"cpu_quota", i.cpu_quota},
         {"representation", i.representation.empty() ? i.caps.representation : i.representation},
         {"scene_bytes", i.scene_bytes},
         {"memory_limit_bytes", i.memory_limit},
         {"memory_limit_emulated", i.memory_limit > 0},
         {"kernels", i.caps.kernels}});
  }
  return out;
}

}  // namespace multiray::study
