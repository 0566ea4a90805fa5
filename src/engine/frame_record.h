// What the engine measured for one frame. Device times come from the devices' own
// reports (measured inside the device); frame, planning and gathering times are measured
// by the engine around them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace multiray {

struct DeviceFrameRecord {
  double time_ms = 0;  // device's own wall time for the frame (busy + emulated idle)
  double busy_ms = 0;  // rendering only
  uint64_t samples = 0, pixels = 0, rays = 0;
  int units = 0;
  double work_share = 0;     // fraction of the frame's samples this device rendered
  double planned_share = 0;  // ratio the balancer intended
  bool alive = true;
};

struct FrameRecord {
  int frame = 0;
  double frame_ms = 0;   // engine wall time: devices started -> all finished
  double plan_ms = 0;    // balancer plan()
  double gather_ms = 0;  // recovery of failed work + composition after the devices
  double update_ms = 0;  // balancer update()
  int stolen = 0;        // items taken by stealing
  std::vector<DeviceFrameRecord> devices;
  double imbalance = 0;               // t_max / t_mean - 1 over live devices
  double deviation = 0;               // max |t_i - t_mean| / t_mean (Harada)
  std::vector<std::string> messages;  // e.g. a device dropped
};

// Imbalance and deviation of the given device times; 0 for fewer than two devices or a
// zero mean.
void imbalance_of(const std::vector<double>& times, double& imbalance, double& deviation);

}  // namespace multiray
