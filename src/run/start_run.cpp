#include "run/start_run.h"

#include "core/console.h"
#include "run/parse_options.h"

namespace multiray {

std::optional<balance::AutoChoice> report_auto_choice(const Run& s, const std::string& spec,
                                                      const std::string& option, bool quiet) {
  balance::AutoChoice choice;
  if (s.resolve_balancer(spec, &choice, option) == spec) return std::nullopt;
  if (!quiet) print_err("multiray: {} auto: {} ({})\n", option, choice.spec, choice.reason);
  return choice;
}

std::unique_ptr<Session> start_run(Run& s, const RunConfig& o, std::vector<std::string>& specs,
                                   const std::string& option, int* worker_exit,
                                   const std::function<void()>& before_load,
                                   const std::function<void(const Run&)>& check, bool quiet) {
  for (std::string& spec : specs) spec = apply_mapping(spec, o.mapping, option);
  s = build_run(o, int(specs.size()), before_load);
  if (s.cluster && !s.cluster->master()) {
    *worker_exit = serve_as_worker(s);
    return nullptr;
  }
  if (check) check(s);
  std::unique_ptr<Session> session = s.make_session(specs, option);  // checks every spec
  for (const std::string& n : s.notes)
    if (!quiet) print_err("multiray: note: {}\n", n);
  return session;
}

}  // namespace multiray
