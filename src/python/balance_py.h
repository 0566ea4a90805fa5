// Balancers in Python (balancer.cpp) and traces (trace_py.cpp): the pieces the two share.
// Python sees multiray.WorkItem, FrameShape, Plan, FrameStats (with DeviceStats and
// ItemReport) and the base class multiray.Balancer; src/python/README.md describes them.
#pragma once

#include <memory>
#include <string>

#include "balance/balancer.h"
#include "python/bindings.h"

namespace multiray::python {

// A plan as multiray.Plan (fresh lists of WorkItem: the caller may change them).
py::object plan_to_python(const balance::Plan& plan);
// A multiray.Plan as a balance::Plan. TypeError naming `who` and the offending field for
// anything of the wrong type (not a Plan, a list that is not one, an item that is not a
// WorkItem, a ratio that is not a number). Does not check coverage (check_plan does).
balance::Plan plan_from_python(const py::handle& value, const std::string& who);

// `instance` (a multiray.Balancer) as a balance::Balancer: plan() and update() call its
// methods holding the GIL, from whatever thread the engine or the simulator runs in; every
// plan is checked with check_plan (ValueError naming the balancer and the frame). `name`
// and `spec` are what name() and spec() return ("" : instance.name()). TypeError when
// `instance` is not a multiray.Balancer.
std::unique_ptr<balance::Balancer> wrap_python_balancer(const py::object& instance,
                                                        const std::string& name = "",
                                                        const std::string& spec = "");

}  // namespace multiray::python
