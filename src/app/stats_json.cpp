#include "app/stats_json.h"

#include "core/error.h"

namespace multiray::app {

nlohmann::json frame_to_json(const FrameRecord& rec) {
  nlohmann::json device_ms = nlohmann::json::array(), busy_ms = nlohmann::json::array(),
                 share = nlohmann::json::array(), planned = nlohmann::json::array(),
                 samples = nlohmann::json::array(), pixels = nlohmann::json::array();
  for (const auto& d : rec.devices) {
    device_ms.push_back(d.time_ms);
    busy_ms.push_back(d.busy_ms);
    share.push_back(d.work_share);
    planned.push_back(d.planned_share);
    samples.push_back(d.samples);
    pixels.push_back(d.pixels);
  }
  return {{"frame", rec.frame},
          {"frame_ms", rec.frame_ms},
          {"first_pass_ms", rec.first_pass_ms},
          {"device_ms", device_ms},
          {"busy_ms", busy_ms},
          {"work_share", share},
          {"planned_share", planned},
          {"samples", samples},
          {"pixels", pixels},
          {"imbalance", rec.imbalance},
          {"deviation", rec.deviation},
          {"plan_ms", rec.plan_ms},
          {"gather_ms", rec.gather_ms},
          {"update_ms", rec.update_ms},
          {"stolen_items", rec.stolen},
          {"messages", rec.messages},
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
    out.push_back({{"type", i.type},
                   {"name", i.name},
                   {"spec", i.spec},
                   {"threads", i.threads},
                   {"emulated_speed", i.emulated_speed},
                   {"emulated", i.emulated_speed < 1.0},
                   {"cpu_quota", i.cpu_quota},
                   {"representation", i.caps.representation},
                   {"kernels", i.caps.kernels}});
  }
  return out;
}

std::unique_ptr<balance::Balancer> make_balancer_or_throw(const std::string& spec, int devices,
                                                          const std::string& option) {
  try {
    return balance::make_balancer(spec, devices);
  } catch (const std::invalid_argument& e) {
    throw InputError(option + ": " + e.what());
  }
}

}  // namespace multiray::app
