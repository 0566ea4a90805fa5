// What the engine measured for one frame. Device times come from the devices' own
// reports (measured inside the device); frame, planning and gathering times are measured
// by the engine around them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "balance/plan.h"
#include "device/device.h"

namespace multiray {

struct FrameRecord {
  int frame = 0;
  double frame_ms = 0;  // engine wall time: devices started -> all finished
  // Two-pass targeting (FrameAdvisor::second_pass): the first pass's wall time, included in
  // frame_ms (as are its plan and gather times in theirs); 0 for one pass. The
  // device reports are the second pass's.
  double first_pass_ms = 0;
  double plan_ms = 0;       // balancer plan()
  double gather_ms = 0;     // recovery of failed work + composition after the devices
  double update_ms = 0;     // balancer update()
  double advise_ms = 0;     // the frame advisor's prediction, if any (pre-pass etc.)
  double predicted_ms = 0;  // the advisor's predicted frame time (0: none)
  double learn_ms = 0;      // the advisor learning from the frame (after it)
  // The denoiser on the master after the frame (Session::set_denoise; 0: none), outside
  // frame_ms: the frame's images were complete before it ran.
  double denoise_ms = 0;
  // Per device, the advisor's cost per unit of work predicted before the frame and measured
  // after it (volumes: ms per sample; 0 where unknown). Empty without an advisor.
  std::vector<double> predicted_cost, measured_cost;
  // Engine::render_frame from entry to return: what the parts above add up to, up to the
  // engine's own bookkeeping (how well they do is printed by the bench).
  double wall_ms = 0;
  int stolen = 0;                     // items taken by stealing
  std::vector<DeviceReport> devices;  // per device, with the engine's alive/share fields
  balance::Quality quality;           // the plan's quality, as rendered
  // balance::imbalance() and balance::deviation() of the live devices' times.
  double imbalance = 0;               // t_max / t_mean - 1
  double deviation = 0;               // max |t_i - t_mean| / t_mean (Harada)
  std::vector<std::string> messages;  // e.g. a device dropped
  std::vector<std::string> notes;     // news that is no fault: a device left out or back
  // The balancer's cost model of each device as it planned the frame (Plan::models; empty
  // for balancers without one).
  std::vector<balance::DeviceCostModel> models;
};

}  // namespace multiray
