// `multiray view`: render continuously and watch (and steer) it in a browser
// (app/viewer/live_view.h). Without civetweb the command says so in one line.
#include <algorithm>

#include <fmt/core.h>

#include "app/commands.h"
#include "core/console.h"
#include "core/error.h"
#include "render/denoise.h"
#include "run/interrupt.h"

#ifdef MULTIRAY_HAS_VIEWER
#include "app/viewer/live_view.h"
#endif

namespace multiray::app {

Runner add_view_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "view",
      "Render continuously and watch it in a web browser: orbit, pan and zoom with the "
      "mouse, switch the balancer, see which device drew what and how long each took");
  auto o = std::make_shared<RunConfig>();
  add_common_options(*cmd, *o);
  auto balancer = std::make_shared<std::string>("auto");
  auto bind = std::make_shared<std::string>("127.0.0.1");
  auto port = std::make_shared<int>(8080);
  auto max_clients = std::make_shared<int>(16);
  auto max_frames = std::make_shared<int>(0);
  auto exposure = std::make_shared<std::string>("auto");
  auto frame_spp = std::make_shared<int>(1);
  auto move_scale = std::make_shared<double>(0.5);
  auto tone = std::make_shared<std::string>("auto");
  auto ar = std::make_shared<bool>(false);
  cmd->add_option("--balancer", *balancer, "The balancer to start with (switchable in the page)")
      ->capture_default_str();
  cmd->add_option("--port", *port, "TCP port of the page (0: any free port, printed)")
      ->capture_default_str();
  cmd->add_option("--bind", *bind,
                  "IP address to listen on (IPv4, IPv6 when civetweb has it, or localhost); "
                  "the default serves this machine only. Anything else lets every machine "
                  "that reaches it watch and steer the render")
      ->capture_default_str();
  cmd->add_option("--max-clients", *max_clients,
                  "Pages that may watch at once, 1..256; one more is refused (HTTP 503)")
      ->capture_default_str();
  cmd->add_option("--max-frames", *max_frames, "Stop after this many frames (0: at Ctrl-C)")
      ->capture_default_str();
  cmd->add_option("--exposure", *exposure,
                  "Exposure of the streamed frames: auto (metered on the first frame, then held; "
                  "volumes: 0) or stops in [-20, 20]")
      ->capture_default_str();
  cmd->add_option("--tone", *tone, "Tone curve of the streamed frames: filmic, clamp or auto")
      ->capture_default_str();
  cmd->add_option("--frame-spp", *frame_spp,
                  "Meshes: samples per pixel of each frame, 1..1024. While the camera stands "
                  "still the page shows the mean of the frames since it stopped, refining to "
                  "--spp: each frame continues the samples of those before it, so the mean is "
                  "one render of all their samples (powers of two spread them best); a move "
                  "starts again from one frame (volumes: every frame as rendered)")
      ->capture_default_str();
  cmd->add_option("--move-scale", *move_scale,
                  "Meshes with uniform sampling: while the camera moves, frames are rendered at "
                  "this scale of the image's width and height, in [0.1, 1], and upsampled "
                  "(1: full size always)")
      ->capture_default_str();
  auto denoise = std::make_shared<std::string>("auto");
  {
    std::string help =
        "The denoiser of the streamed frames, switchable in the page (docs/noise.md, \"The "
        "denoiser\"):";
    for (const DenoiseMethodInfo& m : denoise_methods())
      help += std::string(" ") + m.name + ": " + m.help + ";";
    help.back() = '.';
    help +=
        " While the camera moves each frame is filtered (svgf with its history over the "
        "moves); while it stands the refined image is filtered by the à-trous filter alone "
        "(the refinement is the history). Meshes with the path integrator, uniform or "
        "adaptive sampling and no --ground (auto: none elsewhere)";
    cmd->add_option("--denoise", *denoise, help)->capture_default_str();
  }
  auto no_overlap = std::make_shared<bool>(false);
  cmd->add_flag("--no-denoise-overlap", *no_overlap,
                "Filter each moving frame before the next one renders. By default it is "
                "filtered while the next renders: the same images, shown one frame later, the "
                "filter's time hidden where the devices are not the host's cores (docs/noise.md, "
                "\"Beside the rendering\")");
  cmd->add_flag("--ar", *ar,
                "Augmented reality (docs/ar.md): the page films with the device's camera and "
                "shows the --ground layer over it, turned with the device's orientation. A "
                "phone on the network is the master of the cluster (--bind; its browser allows "
                "the camera only over https or on localhost)");
  return [=]() -> int {
#ifndef MULTIRAY_HAS_VIEWER
    throw InputError(
        "view: this multiray was built without the viewer (install "
        "libcivetweb-dev and build with MULTIRAY_WITH_VIEWER=AUTO or ON)");
#else
    if (*max_frames < 0 || *max_frames > 100000000)
      throw InputError("--max-frames must be in 0..100000000 (0: until Ctrl-C)");
    if (*port < 0 || *port > 65535) throw InputError("--port must be in 0..65535");
    if (*max_clients < 1 || *max_clients > viewer::WebServer::kMaxClientsLimit)
      throw InputError("--max-clients must be in 1.." +
                       std::to_string(viewer::WebServer::kMaxClientsLimit));
    viewer::LiveViewOptions vo;  // checked before the scene loads
    vo.bind = viewer::parse_listen_address(*bind, viewer::WebServer::has_ipv6());
    vo.port = *port;
    vo.max_clients = *max_clients;
    const bool volume_input = is_volume_input(o->scene_path, o->volume);
    vo.meter_exposure = *exposure == "auto" && !volume_input;
    if (*exposure != "auto") {
      const std::optional<double> ev = parse_number(*exposure);
      if (!ev)
        throw InputError("--exposure '" + *exposure + "' must be auto or stops in [-20, 20]");
      vo.display.exposure_ev = parse_exposure(*ev);
    }
    vo.display.tone = parse_tone(*tone, volume_input);
    if (*frame_spp < 1 || *frame_spp > 1024) throw InputError("--frame-spp must be in 1..1024");
    if (*ar && o->ground.empty())
      throw InputError("--ar needs --ground (the plane standing for the real ground)");
    vo.ar = *ar;
    // The camera's picture is shown as it is: the layer over it neither metered nor toned.
    if (*ar && *exposure == "auto") vo.meter_exposure = false;
    if (*ar && *tone == "auto") vo.display.tone = ToneCurve::Clamp;
    if (!volume_input) {  // progressive refinement (engine/refinement.h)
      vo.refine_spp = o->spp > 0 ? o->spp : o->mesh_spp;
      vo.frame_spp = std::min(*frame_spp, vo.refine_spp);
      o->spp = vo.frame_spp;
    }
    if (!(*move_scale >= 0.1 && *move_scale <= 1.0))
      throw InputError("--move-scale must be in [0.1, 1] (1: full size while moving)");
    // A reduced scale needs the uniform sampling of meshes (the engine's image scale does
    // not apply to sample maps); volumes have frame-time targeting instead.
    if (!volume_input && o->sampling == "uniform") vo.move_scale = *move_scale;
    vo.distributed = o->distributed.enabled;
    o->viewer = true;  // --denoise auto: svgf where the run can record feature buffers
    o->denoise = *denoise;
    Run s;
    int worker_exit = 0;
    std::vector<std::string> specs{*balancer};
    std::unique_ptr<Session> session = start_run(s, *o, specs, "--balancer", &worker_exit);
    if (!session) return worker_exit;  // a worker rank: it served the master until the end
    session->set_denoise_overlap(!*no_overlap);  // a moving frame filtered while the next renders
    report_auto_choice(s, specs[0], "--balancer", false);
    vo.volume = s.volume;
    vo.can_denoise = s.can_record_features;
    parse_denoise(*denoise, vo.denoise);                    // checked by start_run
    if (!vo.can_denoise) vo.denoise = DenoiseChoice::none;  // auto (others were refused)
    std::vector<std::string> names;
    for (const auto& d : s.devices) names.push_back(d->info().name);
    viewer::LiveView view(*session, OrbitCamera(s.camera, s.up), names, vo);
    if (!vo.bind.loopback)
      print_err("multiray: warning: --bind {}: anyone who reaches it can steer this run\n",
                vo.bind.host);
    int interrupted = 0;
    {
      // Ctrl-C is watched before the address is printed: whoever reads the address may
      // stop the viewer at once, and a SIGINT ignored or defaulted before the watch (a
      // shell's background job inherits it ignored) would leave it running or kill it.
      InterruptWatch watch(*session);
      print_out("multiray: viewer at {}  (Ctrl-C to stop)\n", vo.bind.url(view.port()));
      std::fflush(stdout);
      const int count = *max_frames > 0 ? *max_frames : 1000000000;
      session->run(0, count, view);
      interrupted = watch.signal();
    }
    print_out("multiray: {} frames dropped while encoding, {} skipped for slow clients\n",
              view.frames_dropped(), view.server().frames_skipped());
    return interrupted ? 128 + interrupted : 0;
#endif
  };
}

}  // namespace multiray::app
