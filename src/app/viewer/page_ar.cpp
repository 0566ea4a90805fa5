// The viewer page's augmented-reality script (view --ar, docs/ar.md), appended to the
// page's own (page.cpp: $, image, send, nextFrame, selftestDone). The device's camera is
// drawn behind every RGBA frame, cropped to the frame's aspect ratio; the device's
// orientation, relative to its first reading, turns the view ({"type":"look"}, at most once
// per animation frame). Phones grant the camera only to secure pages (https, or localhost),
// and iOS asks for the orientation on a tap: hence the "start AR camera" button.
// ?selftest=ar checks, with Chromium's fake camera: a frame arrives, the camera plays, the
// composite is the camera where the frame is transparent and the frame where it is opaque,
// and an orientation event moves the view; the outcome goes into document.title.
#include "app/viewer/live_view.h"

namespace multiray::app::viewer {

const std::string& ar_page_script() {
  static const std::string script = R"JS(
const camera = $("camera"), backdrop = document.createElement("canvas");
let arOn = false, lastBitmap = null, orientation0 = null, look = null, lookQueued = false;
function showFrame(bitmap) {
  lastBitmap = bitmap;
  if (arOn) return composite();
  const g = image.getContext("2d");
  g.clearRect(0, 0, image.width, image.height);
  g.drawImage(bitmap, 0, 0);
}
function drawBackdrop() {
  backdrop.width = image.width; backdrop.height = image.height;
  const g = backdrop.getContext("2d"), vw = camera.videoWidth, vh = camera.videoHeight;
  if (!vw || !vh) { g.fillStyle = "#444"; g.fillRect(0, 0, backdrop.width, backdrop.height); return; }
  const s = Math.max(backdrop.width / vw, backdrop.height / vh), w = backdrop.width / s, h = backdrop.height / s;
  g.drawImage(camera, (vw - w) / 2, (vh - h) / 2, w, h, 0, 0, backdrop.width, backdrop.height);
}
function composite() {
  drawBackdrop();
  const g = image.getContext("2d");
  g.clearRect(0, 0, image.width, image.height);
  g.drawImage(backdrop, 0, 0);
  if (lastBitmap) g.drawImage(lastBitmap, 0, 0);
}
function arLoop() { if (arOn) { composite(); requestAnimationFrame(arLoop); } }
async function startAr() {
  $("err").textContent = "";
  if (!navigator.mediaDevices || !navigator.mediaDevices.getUserMedia) {
    $("err").textContent = "no camera: browsers allow it only over https or on localhost (docs/ar.md)";
    return false;
  }
  try {  // iOS asks the user for the orientation, on a tap
    if (typeof DeviceOrientationEvent !== "undefined" && DeviceOrientationEvent.requestPermission)
      await DeviceOrientationEvent.requestPermission();
  } catch (e) { /* no orientation: the mouse still orbits */ }
  try {
    camera.srcObject = await navigator.mediaDevices.getUserMedia({ video: { facingMode: "environment" }, audio: false });
    await camera.play();
  } catch (e) { $("err").textContent = "camera refused: " + e.message; return false; }
  arOn = true; orientation0 = null;
  requestAnimationFrame(arLoop);
  return true;
}
$("arStart").addEventListener("click", startAr);
function sendLook() { lookQueued = false; if (look) send({ type: "look", yaw: look.yaw, pitch: look.pitch }); }
window.addEventListener("deviceorientation", (e) => {
  if (!arOn || e.alpha === null || e.beta === null) return;
  if (!orientation0) orientation0 = { alpha: e.alpha, beta: e.beta };
  const yaw = ((e.alpha - orientation0.alpha + 540) % 360) - 180;  // turning left: positive
  const pitch = Math.max(-180, Math.min(180, e.beta - orientation0.beta));  // tilting up: positive
  look = { yaw, pitch };
  if (!lookQueued) { lookQueued = true; requestAnimationFrame(sendLook); }
});
if (new URLSearchParams(location.search).get("selftest") === "ar") {
  const result = { frame: 0, camera: 0, over: 0, moved: 0 };
  const report = () => { document.title = "selftest " + Object.entries(result).map(([k, v]) => k + "=" + v).join(" "); };
  const pixels = (source) => {
    const c = document.createElement("canvas"); c.width = image.width; c.height = image.height;
    const g = c.getContext("2d"); g.drawImage(source, 0, 0);
    return g.getImageData(0, 0, c.width, c.height).data;
  };
  (async () => {
    const first = await nextFrame(); result.frame = 1; report();
    const started = await startAr();
    for (let i = 0; i < 100 && !camera.videoWidth; i++) await new Promise((ok) => setTimeout(ok, 50));
    result.camera = started && camera.videoWidth > 0 ? 1 : 0; report();
    composite();
    const shown = pixels(image), back = pixels(backdrop), frame = pixels(lastBitmap);
    let clear = 0, solid = 0, wrong = 0;
    for (let i = 0; i < shown.length; i += 4) {
      const want = frame[i + 3] === 0 ? back : frame[i + 3] === 255 ? frame : null;
      if (!want) continue;
      want === back ? clear++ : solid++;
      if (shown[i] !== want[i] || shown[i + 1] !== want[i + 1] || shown[i + 2] !== want[i + 2]) wrong++;
    }
    result.over = clear > 0 && solid > 0 && wrong === 0 ? 1 : 0; report();
    window.dispatchEvent(new DeviceOrientationEvent("deviceorientation", { alpha: 10, beta: 60, gamma: 0 }));
    await new Promise((ok) => setTimeout(ok, 100));
    window.dispatchEvent(new DeviceOrientationEvent("deviceorientation", { alpha: 40, beta: 70, gamma: 0 }));
    const seen = JSON.stringify(last.camera);
    await nextFrame((m) => JSON.stringify(m.camera) !== seen);
    result.moved = 1; report();
    selftestDone = true;
  })();
}
)JS";
  return script;
}

}  // namespace multiray::app::viewer
