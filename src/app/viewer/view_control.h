// What the live viewer's page may ask for, parsed and checked (a hostile or broken page
// gets an error reply, never a crash), and the mouse-driven camera it moves. Pure: no
// server, no session.
#pragma once

#include <string>

#include "scene/scene.h"

namespace multiray::app::viewer {

// A camera orbiting its target about the scene's up axis, panned and zoomed by the mouse;
// starts from `base` (its eye, target and fov).
class OrbitCamera {
 public:
  OrbitCamera(const Camera& base, Vec3 up);
  // Degrees: yaw about the up axis, pitch towards it (kept within 89 degrees of level).
  void orbit(float yaw_deg, float pitch_deg);
  // Moves eye and target across the view by fractions of the view's height at the target.
  void pan(float right, float up);
  // Multiplies the distance to the target by `factor` (kept within 1e-4 .. 1e4 of the
  // starting distance).
  void zoom(float factor);
  void reset();
  Camera camera() const;

 private:
  Camera base_;
  Vec3 up_, target_;
  float distance_ = 1, start_distance_ = 1, yaw_ = 0, pitch_ = 0;  // yaw, pitch in radians
  Vec3 start_target_;
  float start_yaw_ = 0, start_pitch_ = 0;
};

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
struct Command {
  enum class Kind { Orbit, Pan, Zoom, Reset, Balancer, View, Tf, Target } kind = Kind::Reset;
  float x = 0, y = 0;  // orbit / pan amounts, zoom factor or target ms in x
  std::string spec;    // balancer, or transfer-function preset
  std::string json;    // transfer function as JSON text
  int view = 0;
};

// Throws InputError (one line) for a message that is not such an object: bad JSON, an
// unknown type, a missing, non-numeric, non-finite or out-of-range field, or more than
// 4096 bytes.
Command parse_command(const std::string& text, int views);

}  // namespace multiray::app::viewer
