// The live viewer's page: plain HTML, CSS and script, no framework, served from memory.
// Protocol (app/viewer/live_view.h): the server sends {"type":"hello"} once, then per
// frame a {"type":"frame",...} text message followed by the frame as a JPEG binary
// message; the page sends the commands of app/viewer/view_control.h.
// ?overlay=1 starts with the partition overlay on; ?ar=1 starts the AR camera at once
// (where the browser allows it without a tap); ?hold=N is for screenshots (below). With
// ?selftest=1 the page exercises itself (drag, balancer switch, overlay) and writes the outcome
// into document.title, for the headless-browser test (tests/viewer); ?selftest=ar does the
// same for augmented reality (page_ar.cpp).
#include "app/viewer/live_view.h"

namespace multiray::app::viewer {

const std::string& viewer_page() {
  static const std::string page = std::string(R"PAGE(<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>multiray view</title>
<style>
body { font: 13px system-ui, sans-serif; margin: 0; background: #1e1f22; color: #ddd;
       height: 100vh; display: flex; flex-direction: column; overflow: hidden; }
header { padding: 6px 10px; background: #2b2d31; display: flex; gap: 14px; align-items: center; flex-wrap: wrap; }
main { flex: 1; display: flex; min-height: 0; }
/* The frame fills the space the window leaves, scaled to fit with its aspect kept. */
#stage { position: relative; flex: 1; min-width: 0; margin: 10px; cursor: grab; }
#stage canvas { position: absolute; left: 0; top: 0; width: 100%; height: 100%; object-fit: contain; }
#overlay { pointer-events: none; }
#side { flex: 0 0 370px; margin: 10px; overflow: auto; }
.dev { display: flex; gap: 6px; align-items: center; }
.sw { width: 12px; height: 12px; display: inline-block; }
#err { color: #f88; }
</style></head><body>
<header>
 <b>multiray view</b>
 <label>balancer <select id="balancer"></select></label>
 <label><input type="checkbox" id="overlayOn"> partition overlay</label>
 <label id="viewBox" hidden>view <select id="view"></select></label>
 <label id="denoiseBox" hidden title="none: as rendered; atrous: each frame alone; svgf: with the frames before; auto: svgf while the camera moves and until the still image has 256 samples per pixel">denoise <select id="denoise"><option>none</option><option>atrous</option><option>svgf</option><option>auto</option></select></label>
 <button id="reset">reset camera</button>
 <button id="arStart" hidden>start AR camera</button>
 <span id="volBox" hidden><label>transfer function <select id="tf"></select></label>
  <button id="tfEdit">edit</button>
  <label>target ms <input id="target" type="number" min="1" max="100000" step="1" style="width:5em"></label></span>
 <span id="stats">waiting for the first frame ...</span>
 <span id="err"></span>
</header>
<main><div id="stage"><video id="camera" playsinline muted hidden></video><canvas id="image" width="640" height="360"></canvas><canvas id="overlay" width="640" height="360"></canvas></div>
<div id="side"><div id="devices"></div><canvas id="plot" width="360" height="200"></canvas>
<div>drag: orbit &middot; shift+drag or right drag: pan &middot; wheel: zoom</div>
<div id="tfPanel" hidden style="margin-top:10px">transfer function (JSON, docs/volumes.md):<br>
<textarea id="tfJson" rows="9" style="width:100%;box-sizing:border-box">{"units": "fraction", "points": [
 {"value": 0.0, "color": [0, 0, 0], "opacity": 0},
 {"value": 0.3, "color": [0.9, 0.5, 0.3], "opacity": 0.02},
 {"value": 1.0, "color": [1, 1, 1], "opacity": 0.6}]}</textarea>
<button id="tfApply">apply</button></div>
</div></main>
<script>
"use strict";
const colors = ["#e6194b","#3cb44b","#4363d8","#f58231","#911eb4","#42d4f4","#f032e6","#bfef45","#fabed4","#469990","#dcbeff","#9a6324"];
const $ = (id) => document.getElementById(id);
const image = $("image"), overlay = $("overlay"), plot = $("plot");
const history = [];  // per frame: device times
let ws, meta = null, last = null, devices = [], frames = 0, t0 = performance.now();
function send(obj) { if (ws && ws.readyState === 1) ws.send(JSON.stringify(obj)); }
function connect() {
  ws = new WebSocket((location.protocol === "https:" ? "wss://" : "ws://") + location.host + "/ws");
  ws.binaryType = "blob";
  ws.onmessage = async (ev) => {
    if (typeof ev.data === "string") {
      const m = JSON.parse(ev.data);
      if (m.type === "hello") hello(m);
      else if (m.type === "frame") meta = m;
      else if (m.type === "error") { $("err").textContent = "server: " + m.message; }
      return;
    }
    if (!meta) return;
    const m = meta; meta = null;
    const bitmap = await createImageBitmap(ev.data);
    for (const c of [image, overlay]) if (c.width !== m.width || c.height !== m.height) { c.width = m.width; c.height = m.height; }
    showFrame(bitmap);
    last = m; frames++;
    drawOverlay(); drawStats(m);
    if (window.onFrameForTest) window.onFrameForTest(m);
  };
  // A refused connection (the viewer already has --max-clients pages) closes too.
  ws.onclose = () => { $("stats").textContent = "disconnected (or the viewer is full); retrying ..."; setTimeout(connect, 1000); };
}
function hello(m) {
  devices = m.devices;
  const sel = $("balancer"); sel.innerHTML = "";
  for (const b of m.balancers) { const o = document.createElement("option"); o.value = o.textContent = b; sel.appendChild(o); }
  sel.value = m.balancer;
  const vs = $("view"); vs.innerHTML = "";
  for (let i = 0; i < m.views; i++) { const o = document.createElement("option"); o.value = i; o.textContent = i; vs.appendChild(o); }
  $("viewBox").hidden = m.views < 2;
  $("denoiseBox").hidden = !m.can_denoise;
  $("denoise").value = m.denoise;
  $("volBox").hidden = !m.volume;
  $("arStart").hidden = !m.ar;
  if (m.ar && new URLSearchParams(location.search).get("ar")) startAr();  // ?ar=1: at once
  if (m.volume) {
    const tf = $("tf"); tf.innerHTML = "<option value=''>(as started)</option>";
    for (const p of m.presets) { const o = document.createElement("option"); o.value = o.textContent = p; tf.appendChild(o); }
    if (m.target_ms > 0) $("target").value = m.target_ms;
  }
  $("devices").innerHTML = devices.map((d, i) => `<div class="dev"><span class="sw" style="background:${colors[i % colors.length]}"></span>${d}</div>`).join("");
}
function drawOverlay() {
  const g = overlay.getContext("2d");
  g.clearRect(0, 0, overlay.width, overlay.height);
  if (!$("overlayOn").checked || !last) return;
  g.globalAlpha = 0.35;
  for (const [d, x0, y0, x1, y1] of last.items) { g.fillStyle = colors[d % colors.length]; g.fillRect(x0, y0, x1 - x0, y1 - y0); }
  g.globalAlpha = 1;
}
function drawStats(m) {
  const fps = frames / ((performance.now() - t0) / 1000);
  const refine = m.refine_spp > 0 ? `  ${m.spp < m.refine_spp ? "refining" : "done refining"} ${m.spp}/${m.refine_spp} spp` : "";
  const denoised = m.denoise !== "none" ? `  denoised (${m.denoise})` : "";
  $("stats").textContent = `frame ${m.frame}  ${m.frame_ms.toFixed(1)} ms  ${fps.toFixed(1)} fps shown${refine}${denoised}  imbalance ${(100 * m.imbalance).toFixed(1)}%  ${m.balancer}  dropped ${m.dropped}`;
  if ($("balancer").value !== m.balancer.split(":")[0] && document.activeElement !== $("balancer")) $("balancer").value = m.balancer.split(":")[0];
  history.push(m.devices.map((d) => d.time_ms)); if (history.length > 100) history.shift();
  const g = plot.getContext("2d"), W = plot.width, H = plot.height - 40;
  g.fillStyle = "#26282c"; g.fillRect(0, 0, W, plot.height);
  const max = Math.max(1, ...history.flat());
  g.fillStyle = "#aaa"; g.fillText(`device ms (max ${max.toFixed(0)})`, 4, 12);
  for (let d = 0; d < m.devices.length; d++) {
    g.strokeStyle = colors[d % colors.length]; g.beginPath();
    history.forEach((t, i) => { const x = i * W / 100, y = H - (t[d] || 0) / max * (H - 16); i ? g.lineTo(x, y) : g.moveTo(x, y); });
    g.stroke();
  }
  let x = 0;  // this frame's shares, stacked
  m.devices.forEach((d, i) => { g.fillStyle = colors[i % colors.length]; g.fillRect(x, H + 14, d.share * W, 20); x += d.share * W; });
  g.fillStyle = "#aaa"; g.fillText("work share", 4, H + 10);
}
// Mouse: orbit, pan, zoom; moves are summed and sent at most once per animation frame.
let drag = null, acc = { orbit: [0, 0], pan: [0, 0], zoom: 1 }, queued = false;
function flush() {
  queued = false;
  if (acc.orbit[0] || acc.orbit[1]) send({ type: "orbit", dx: acc.orbit[0], dy: acc.orbit[1] });
  if (acc.pan[0] || acc.pan[1]) send({ type: "pan", dx: acc.pan[0], dy: acc.pan[1] });
  if (acc.zoom !== 1) send({ type: "zoom", factor: Math.min(10, Math.max(0.1, acc.zoom)) });
  acc = { orbit: [0, 0], pan: [0, 0], zoom: 1 };
}
function queue() { if (!queued) { queued = true; requestAnimationFrame(flush); } }
const stage = $("stage");
// The size the frame is shown at on the page (object-fit: contain inside the stage).
function shownSize() {
  const r = stage.getBoundingClientRect(), s = Math.min(r.width / image.width, r.height / image.height);
  return { w: image.width * s, h: image.height * s, r };
}
// Before the first frame: say so where the plot will be.
(() => { const g = plot.getContext("2d"); g.fillStyle = "#26282c"; g.fillRect(0, 0, plot.width, plot.height);
  g.fillStyle = "#aaa"; g.fillText("device times appear with the first frame", 10, 20); })();
stage.addEventListener("contextmenu", (e) => e.preventDefault());
stage.addEventListener("mousedown", (e) => { drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 }; });
window.addEventListener("mouseup", () => { drag = null; });
window.addEventListener("mousemove", (e) => {
  if (!drag) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y; drag.x = e.clientX; drag.y = e.clientY;
  if (drag.pan) { const h = shownSize().h; acc.pan[0] -= dx / h; acc.pan[1] += dy / h; }
  else { acc.orbit[0] -= dx * 0.3; acc.orbit[1] += dy * 0.3; }
  acc.orbit = acc.orbit.map((v) => Math.max(-360, Math.min(360, v)));
  acc.pan = acc.pan.map((v) => Math.max(-10, Math.min(10, v)));
  queue();
});
stage.addEventListener("wheel", (e) => { e.preventDefault(); acc.zoom *= Math.exp(e.deltaY * 0.001); queue(); }, { passive: false });
$("balancer").addEventListener("change", () => send({ type: "balancer", spec: $("balancer").value }));
$("view").addEventListener("change", () => send({ type: "view", index: Number($("view").value) }));
$("denoise").addEventListener("change", () => send({ type: "denoise", method: $("denoise").value }));
$("overlayOn").addEventListener("change", drawOverlay);
$("reset").addEventListener("click", () => send({ type: "reset" }));
$("tf").addEventListener("change", () => { if ($("tf").value) send({ type: "tf", preset: $("tf").value }); });
$("tfEdit").addEventListener("click", () => { $("tfPanel").hidden = !$("tfPanel").hidden; });
$("tfApply").addEventListener("click", () => { $("err").textContent = ""; send({ type: "tf", json: $("tfJson").value }); });
$("target").addEventListener("change", () => { const v = Number($("target").value); if (v >= 1) send({ type: "target", ms: v }); });
if (new URLSearchParams(location.search).get("overlay")) $("overlayOn").checked = true;
// ?hold=N: keep a request open until N frames were shown (headless screenshots: a pending
// request holds the browser's virtual clock while frames arrive).
let selftestDone = !new URLSearchParams(location.search).get("selftest");
const nextFrame = (pred) => new Promise((ok) => { window.onFrameForTest = (m) => { if (!pred || pred(m)) { window.onFrameForTest = null; ok(m); } }; });
(async () => {
  const n = Number(new URLSearchParams(location.search).get("hold") || 0);
  while (frames < n || !selftestDone) await fetch("/?hold", { cache: "no-store" }).catch(() => {});
})();
connect();

// ?selftest=1: what a user would do, checked; the result goes into the title.
if (new URLSearchParams(location.search).get("selftest") === "1") {
  const result = { frame: 0, drag: 0, balancer: 0, colors: 0, fits: 0 };
  const report = () => { document.title = "selftest " + Object.entries(result).map(([k, v]) => k + "=" + v).join(" "); };
  (async () => {
    const first = await nextFrame(); result.frame = 1; report();
    // The frame is scaled to the space the window leaves: inside the window, and filling
    // the stage across or down (a 96x54 frame is shown larger than its pixels).
    const shown = shownSize();
    result.fits = shown.r.right <= innerWidth + 1 && shown.r.bottom <= innerHeight + 1 &&
      (Math.abs(shown.w - shown.r.width) < 2 || Math.abs(shown.h - shown.r.height) < 2) && shown.w > image.width ? 1 : 0;
    const r = stage.getBoundingClientRect(), cx = r.left + 50, cy = r.top + 50;
    stage.dispatchEvent(new MouseEvent("mousedown", { clientX: cx, clientY: cy, bubbles: true }));
    window.dispatchEvent(new MouseEvent("mousemove", { clientX: cx + 80, clientY: cy + 10, bubbles: true }));
    window.dispatchEvent(new MouseEvent("mouseup", { clientX: cx + 80, clientY: cy + 10, bubbles: true }));
    const moved = await nextFrame((m) => m.frame > first.frame + 1);
    result.drag = moved.image_hash !== first.image_hash ? 1 : 0; report();
    // uniform: every device gets a part of every frame, so the overlay must show them all
    // (a queue may leave a device without a tile in a small frame).
    const sel = $("balancer"); sel.value = "uniform"; sel.dispatchEvent(new Event("change"));
    await nextFrame((m) => m.balancer.startsWith("uniform")); result.balancer = 1; report();
    $("overlayOn").checked = true; $("overlayOn").dispatchEvent(new Event("change"));
    const px = overlay.getContext("2d").getImageData(0, 0, overlay.width, overlay.height).data, seen = new Set();
    for (let i = 0; i < px.length; i += 4) if (px[i + 3] > 0) seen.add(px[i] + "," + px[i + 1] + "," + px[i + 2]);
    result.colors = seen.size; report();
    selftestDone = true;
  })();
}
)PAGE") + ar_page_script() + R"PAGE(</script></body></html>
)PAGE";
  return page;
}

}  // namespace multiray::app::viewer
