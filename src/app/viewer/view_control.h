// What the live viewer's page may ask for, parsed and checked (a hostile or broken page
// gets an error reply, never a crash). Pure: no server, no session. The camera the mouse
// moves is scene/orbit_camera.h.
#pragma once

#include <string>

#include "render/denoise.h"

namespace multiray::app::viewer {

// One message from the page, a JSON object with "type":
//   {"type":"orbit","dx":DEG,"dy":DEG}      |dx|, |dy| <= 360
//   {"type":"pan","dx":F,"dy":F}            |dx|, |dy| <= 10 (view heights)
//   {"type":"zoom","factor":F}              F in [0.1, 10]
//   {"type":"reset"}                        the starting camera
//   {"type":"balancer","spec":"hybrid"}     a balancer spec (checked by make_balancer)
//   {"type":"view","index":K}               K in [0, views): the view to stream
//   {"type":"tf","preset":NAME}             volumes: a transfer-function preset
//   {"type":"tf","json":TEXT}               volumes: a transfer function in the JSON file
//                                           format (docs/volumes.md), as text
//   {"type":"target","ms":F}                volumes: frame-time target, F in [1, 100000]
//   {"type":"look","yaw":DEG,"pitch":DEG}   AR: the device's turn since it started,
//                                           |yaw| <= 360, |pitch| <= 180 (OrbitCamera::look)
//   {"type":"denoise","method":NAME}        the denoiser: none, atrous, svgf or auto
//                                           (render/denoise.h denoise_methods())
struct Command {
  enum class Kind { Orbit, Pan, Zoom, Reset, Balancer, View, Tf, Target, Look, Denoise };
  Kind kind = Kind::Reset;
  float x = 0, y = 0;  // orbit / pan / look amounts, zoom factor or target ms in x
  std::string spec;    // balancer, or transfer-function preset
  std::string json;    // transfer function as JSON text
  int view = 0;
  DenoiseChoice denoise = DenoiseChoice::none;
};

// Throws InputError (one line) for a message that is not such an object: bad JSON, an
// unknown type, a missing, non-numeric, non-finite or out-of-range field, or more than
// 4096 bytes.
Command parse_command(const std::string& text, int views);

}  // namespace multiray::app::viewer
