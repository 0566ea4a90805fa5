// `--balancer auto` in the run layer: what the rules of balance/auto_choice.h see of a
// built run, and the spec a session then runs.
#include <stdexcept>

#include "balance/auto_choice.h"
#include "core/error.h"
#include "device/device_factory.h"
#include "run/run.h"
#include "util/link.h"
#include "util/spec.h"
#ifdef MULTIRAY_HAS_MPI
#include "distributed/remote_device.h"
#endif

namespace multiray {

balance::AutoInputs gather_auto_inputs(const Run& s, const RunConfig& o) {
  balance::AutoInputs in;
  for (const auto& d : s.devices) {
    const DeviceInfo& info = d->info();
    balance::AutoDevice a;
    a.type = info.type == "rank" ? "remote" : info.type;
    a.threads = info.threads;
    a.speed = info.emulated_speed;
    // The rules see backend features as data, from the registry, never a backend's name.
    a.item_cost = backend_features(info.type).item_cost;
#ifdef MULTIRAY_HAS_MPI
    if (const auto* r = dynamic_cast<const remote::RemoteDevice*>(d.get()))
      for (const DeviceInfo& local : r->local_devices())
        a.item_cost = a.item_cost || backend_features(local.type).item_cost;
#endif
    in.devices.push_back(a);
  }
  if (s.cluster) {
    in.distributed = true;
    in.ranks = s.cluster->size();
    in.latency_ms = s.cluster->link().latency_ms;
    in.mbit_per_s = s.cluster->link().mbit_per_s;
  }
  in.volume = s.volume != nullptr;
  in.views = s.views ? s.views->rig().view_count() : 1;
  in.sampling = o.sampling;
  in.frame_target = o.volume.target_ms > 0;
  in.catcher = !o.ground.empty();
  return in;
}

std::string Run::resolve_balancer(const std::string& spec, balance::AutoChoice* choice,
                                  const std::string& option) const {
  const bool is_auto = [&] {
    try {
      return Spec(spec).name() == "auto";
    } catch (const std::invalid_argument&) {
      return false;  // reported by make_balancer with the option's name
    }
  }();
  if (!is_auto) return spec;
  if (spec != "auto") make_balancer_or_throw(spec, 1, option);  // auto takes no options
  const balance::AutoChoice c = balance::choose_balancer(auto_inputs);
  if (choice) *choice = c;
  try {
    return apply_mapping(c.spec, mapping, option);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (the choice of " + option +
                     " auto; name a balancer)");
  }
}

}  // namespace multiray
