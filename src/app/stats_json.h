// JSON forms of the engine's records, shared by `render` and `bench`.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "balance/balancer.h"
#include "device/device.h"
#include "engine/frame_record.h"

namespace multiray::app {

nlohmann::json frame_to_json(const FrameRecord& rec);
nlohmann::json devices_to_json(const std::vector<std::unique_ptr<Device>>& devices);
// make_balancer, with std::invalid_argument turned into InputError naming `option` (the
// command-line option the spec came from).
std::unique_ptr<balance::Balancer> make_balancer_or_throw(
    const std::string& spec, int devices, const std::string& option = "--balancer");

}  // namespace multiray::app
