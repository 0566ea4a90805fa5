// The start render, bench and view share (and the Python module's bench through
// study/bench_run.h): the run built, a worker rank sent to serve its master, the session
// made and the run's notes printed.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "run/run.h"

namespace multiray {

// Applies --mapping to every balancer spec in `specs` (in place, before anything loads;
// bad specs reported as coming from `option`), builds the run of `o` into `s` (with
// `before_load`, and memory estimated for `specs.size()` lanes) and, on the master or a
// single process, prints its notes and returns a session with one lane per spec; `check`,
// if given, may refuse the built run before anything is printed; `quiet`: the notes are
// not printed (s.notes has them). On a worker rank of a distributed run it serves the
// master instead, sets `*worker_exit` to the exit code and returns null.
std::unique_ptr<Session> start_run(Run& s, const RunConfig& o, std::vector<std::string>& specs,
                                   const std::string& option, int* worker_exit,
                                   const std::function<void()>& before_load = {},
                                   const std::function<void(const Run&)>& check = {},
                                   bool quiet = false);

// `--balancer auto` (`spec` as given): what it picked for the built run `s`, printed once
// to stderr ("multiray: --balancer auto: hybrid (2 devices ...)") unless `quiet`; nullopt
// for any other spec.
std::optional<balance::AutoChoice> report_auto_choice(const Run& s, const std::string& spec,
                                                      const std::string& option, bool quiet);

}  // namespace multiray
