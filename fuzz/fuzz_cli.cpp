// Fuzz target of the command line: the input is split into arguments at line breaks
// and NULs (at most 32 arguments of at most 200 bytes) and run as `multiray ARGS...`
// through the command line's one entry (app/cli.h: run_cli, which main() calls too; the
// only app/ header outside app/, since this target fuzzes the CLI itself), from a scratch
// folder holding a small scene in each format, a keyframe file and a trace.
//
// Bad input must give exit code 2 (README: "one line on stderr and exit code 2"); device
// faults 3. An exception other than InputError or DeviceError reaching the top (main's
// "internal error", exit code 4) is a finding, as is any crash or sanitizer report.
//
// Every run must stay small and stay in the scratch folder, so an input is skipped (not
// run, kept out of the corpus) when
//   - an argument holds '/' or "..", or names a cgroup quota (writes outside the folder),
//   - after parsing, the job would be big: more than 32x32 pixels, 4 samples per pixel,
//     4 views, 3 frames (bench: 6), 8 bounces, 3 devices of at most 2 threads, an
//     emulated speed below 0.25, a bench without --balancers (at most 2) and
//     --ideal-frames (at most 2), a simulation of more than 64 devices or 50 frames.
// Values the app would refuse anyway pass through, so its checks are fuzzed too.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/cli.h"
#include "core/error.h"
#include "device/device_factory.h"
#include "fuzz_support.h"
#include "run/parse_options.h"
#include "run/run.h"

namespace {

using namespace multiray;

// The files every run finds in its working folder (rewritten before each run, since a
// run may overwrite them).
const std::pair<const char*, const char*> kFiles[] = {
    {"box.obj",
     "mtllib box.mtl\nv -1 0 0\nv 1 0 0\nv 1 1 0\nv -1 1 0\nv 0 0 -1\nvt 0 0\nvt 1 0\nvt 1 1\n"
     "vn 0 0 1\nusemtl lamp\nf 1/1/1 2/2/1 3/3/1 4/1/1\nusemtl grey\nf 1 2 5\n"},
    {"box.mtl", "newmtl lamp\nKd 0.8 0.8 0.8\nKe 3 3 3\nnewmtl grey\nKd 0.5 0.5 0.5\n"},
    {"tri.ply",
     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
     "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
     "-1 0 0\n1 0 0\n0 1.5 0\n3 0 1 2\n"},
    {"tri.gltf",
     R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0},)"
     R"({"camera":0,"translation":[0,0.5,3]}],"cameras":[{"type":"perspective","perspective":)"
     R"({"yfov":0.8,"znear":0.1,"aspectRatio":1.0}}],"meshes":[{"primitives":[{"attributes":)"
     R"({"POSITION":0},"indices":1,"material":0}]}],"materials":[{"pbrMetallicRoughness":)"
     R"({"baseColorFactor":[0.8,0.6,0.4,1],"metallicFactor":0},"emissiveFactor":[1,1,1]}],)"
     R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":)"
     R"([-1,0,0],"max":[1,1.5,0]},{"bufferView":1,"componentType":5123,"count":3,"type":)"
     R"("SCALAR"}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,)"
     R"("byteOffset":36,"byteLength":6}],"buffers":[{"byteLength":44,"uri":"data:application/)"
     R"(octet-stream;base64,AACAvwAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAwD8AAAAAAAABAAIAAAA="}]})"},
    {"cam.json", R"({"keyframes":[{"frame":0,"eye":[0,0.5,3],"target":[0,0.5,0]},)"
                 R"({"frame":1,"eye":[1,0.8,2.5],"target":[0,0.4,0],"up":[0,1,0],"fov":50}]})"},
    {"run.trace",
     "multiray-trace 1\nbalancer static:ratios=2/1\ndevice 0 1 cpu:threads=1\n"
     "device 1 0.5 cpu:threads=1:speed=0.5\nframe 0 8 4 1\ntime 0 1 2.5 2.5\n"
     "item 0 0 0 0 0 8 3 24 2.5 2.5\ntime 1 1 2.75 1.25\nitem 1 1 0 0 3 8 4 8 2.75 1.25\n"
     "frame 1 8 4 1\ntime 0 1 2 2\nitem 0 0 0 0 0 8 2 16 2 2\ntime 1 0 0 0\n"},
};

// The value an option of `cmd` ends up with: the given one, else its default, else none.
std::optional<std::string> value(CLI::App* cmd, const std::string& name) {
  const CLI::Option* opt = cmd->get_option_no_throw(name);
  if (!opt) return std::nullopt;
  if (opt->count() > 0) return opt->as<std::string>();
  if (!opt->get_default_str().empty()) return opt->get_default_str();
  return std::nullopt;
}

// The option's value as a number; `missing` when it has none; NaN when it is not one
// (the app refuses those itself).
double number(CLI::App* cmd, const std::string& name, double missing) {
  const auto v = value(cmd, name);
  if (!v) return missing;
  char* end = nullptr;
  const double d = std::strtod(v->c_str(), &end);
  return !v->empty() && end == v->c_str() + v->size() ? d : std::nan("");
}

bool above(CLI::App* cmd, const std::string& name, double missing, double limit) {
  const double v = number(cmd, name, missing);
  return !std::isnan(v) && v > limit;  // NaN: not a number, refused by the app
}

// True when running the parsed command line would take long (see the top of the file).
bool too_big(CLI::App& app) {
  for (const char* name : {"render", "bench"}) {
    if (!app.got_subcommand(name)) continue;
    CLI::App* cmd = app.get_subcommand(name);
    const bool bench = std::string(name) == "bench";
    if (const auto res = value(cmd, "--res")) {
      try {
        const Resolution r = parse_resolution(*res);
        if (int64_t(r.width) * r.height > 32 * 32) return true;
      } catch (const InputError&) {
      }
    } else {
      return true;
    }
    if (above(cmd, "--spp", 1e9, 4) || above(cmd, "--bounces", 1e9, 8) ||
        above(cmd, "--frames", 1e9, bench ? 6 : 3) || above(cmd, "--ao-rays", 1e9, 4) ||
        above(cmd, "--edge-spp", 1e9, 8) || above(cmd, "--fovea-spp", 1e9, 8))
      return true;
    if (const auto views = value(cmd, "--views")) {
      const size_t x = views->find('x');
      if (x != std::string::npos) {
        const double k = std::strtod(views->substr(0, x).c_str(), nullptr),
                     l = std::strtod(views->substr(x + 1).c_str(), nullptr);
        if (std::isfinite(k) && std::isfinite(l) && k * l > 4) return true;
      }
    }
    std::string devices = value(cmd, "--devices").value_or("cpu:threads=0");
    for (size_t p; (p = devices.find("threads=0")) != std::string::npos;)
      devices.replace(p, 9, "threads=2");
    size_t device_count = 0;
    try {
      const auto specs = parse_device_specs(devices);
      device_count = specs.size();
      if (specs.size() > 3) return true;
      for (const DeviceSpec& d : specs) {
        if (d.type != "cpu" || d.options.count("quota")) return true;
        if (auto t = d.options.find("threads");
            t != d.options.end() && std::atof(t->second.c_str()) > 2)
          return true;
        if (auto s = d.options.find("speed");
            s != d.options.end() && std::atof(s->second.c_str()) < 0.25)
          return true;
      }
    } catch (const InputError&) {
    }
    if (const CLI::Option* p = cmd->get_option_no_throw("--perturb"); p && p->count() > 0) {
      try {
        for (const Perturbation& q : parse_perturbations(p->as<std::vector<std::string>>(),
                                                         int(std::max<size_t>(device_count, 1))))
          if (q.speed < 0.25) return true;
      } catch (const InputError&) {
      }
    }
    if (bench) {
      const CLI::Option* b = cmd->get_option_no_throw("--balancers");
      if (!b || b->count() == 0) return true;
      const std::string list = b->as<std::string>();
      if (std::count(list.begin(), list.end(), ',') > 1) return true;
      const CLI::Option* ideal = cmd->get_option_no_throw("--ideal-frames");
      if (!ideal || ideal->count() == 0 || above(cmd, "--ideal-frames", 1e9, 2)) return true;
    }
  }
  if (app.got_subcommand("simulate")) {
    CLI::App* cmd = app.get_subcommand("simulate");
    const std::string devices = value(cmd, "--devices").value_or("2,4,8,16");
    int counts = 0;
    for (size_t begin = 0; begin <= devices.size(); ++counts) {
      size_t end = devices.find(',', begin);
      if (end == std::string::npos) end = devices.size();
      if (std::atof(devices.substr(begin, end - begin).c_str()) > 64) return true;
      begin = end + 1;
    }
    if (counts > 4 || above(cmd, "--frames", 0, 50)) return true;
  }
  return false;
}

// The real command line (app/cli.h), silent, skipping inputs too big to run quickly; an
// internal error (exit code 4) is a finding.
int run(int argc, char** argv, const std::vector<std::string>& args) {
  app::CliHooks hooks;
  hooks.quiet = true;
  hooks.skip = [](CLI::App& app) { return too_big(app); };
  hooks.internal_error = [&](const char* what) {
    std::string line = "internal error (exit code 4) from `multiray";
    for (const std::string& a : args) line += " '" + a + "'";
    fuzz::fail(line + "`: " + what);
  };
  return app::run_cli(argc, argv, hooks);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (chdir(fuzz::scratch_dir().c_str()) != 0) fuzz::fail("cannot enter the scratch folder");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> args;
  std::string arg;
  for (size_t i = 0; i < size; ++i) {
    const char c = char(data[i]);
    if (c == '\n' || c == '\0') {
      args.push_back(arg), arg.clear();
    } else {
      arg += c;
    }
  }
  if (!arg.empty()) args.push_back(arg);  // a last argument without a line break
  if (args.size() > 32) return -1;
  for (const std::string& a : args)
    if (a.size() > 200 || a.find('/') != std::string::npos || a.find("..") != std::string::npos ||
        a.find("quota") != std::string::npos)
      return -1;
  fuzz::clear_scratch();
  for (const auto& [name, text] : kFiles) fuzz::write_file(name, text);
  std::vector<std::string> storage = args;
  storage.insert(storage.begin(), "multiray");
  std::vector<char*> argv;
  for (std::string& s : storage) argv.push_back(s.data());
  argv.push_back(nullptr);
  const int code = run(int(storage.size()), argv.data(), args);
  return code < 0 ? -1 : 0;
}
