// ego's dashboard: one WebSocket in (samples, camera JPEGs, state), commands out.
// Plain JS, no build step. The robot is drawn 1 unit = 1 mm, its front up.
"use strict";

const $ = (id) => document.getElementById(id);
const SVG = "http://www.w3.org/2000/svg";
const BODY_MM = 37;
// Bearings from the front, counter-clockwise positive (ps0 front-right .. ps7 front-left),
// then the Overo board's long-range IR8 and IR9.
const PS_BEARINGS = [-0.30, -0.80, -1.57, -2.64, 2.64, 1.57, 0.80, 0.30, 0.5, -0.5];
const DRIVE = { ArrowUp: [1, 1], ArrowDown: [-1, -1], ArrowLeft: [-0.6, 0.6], ArrowRight: [0.6, -0.6] };
const DRIVE_SPEED = 500;   // steps/s at full key
const HISTORY_S = 10;
const SERIES = {
  proximity: "proximity ps0-ps7", light: "light ls0-ls7", floor: "floor gs0-gs2",
  accelerometer: "accelerometer (m/s²)", speed: "wheel speeds (steps/s)",
  microphones: "microphones", step: "step time (ms)",
};
const COLOURS = ["#2f6fdf", "#e8871e", "#1f9d55", "#d62f2f", "#7b5cd6", "#12a4b4", "#b5651d", "#6b7385", "#c2185b", "#455a64"];

const view = { hello: null, sample: null, state: { role: "view", held: false, halted: false, keyboard: false },
  history: [], odometry: [], truth: [], floorImage: null, dirty: true, imageUrl: null };
const held = new Set();
let socket = null;
let drivingSent = false;

// -- connection -------------------------------------------------------------------------

function connect() {
  const token = new URLSearchParams(location.search).get("token");
  const scheme = location.protocol === "https:" ? "wss" : "ws";
  const url = `${scheme}://${location.host}/ws${token ? "?token=" + encodeURIComponent(token) : ""}`;
  socket = new WebSocket(url);
  socket.binaryType = "blob";
  socket.onopen = () => setStatus("live", "ok");
  socket.onclose = () => { setStatus("disconnected", "bad"); held.clear(); setTimeout(connect, 1000); };
  socket.onmessage = (event) => {
    if (typeof event.data !== "string") { showImage(event.data); return; }
    const message = JSON.parse(event.data);
    if (message.type === "sample") onSample(message);
    else if (message.type === "state") onState(message);
    else if (message.type === "hello") onHello(message);
    else if (message.type === "error") toast(message.error);
  };
}

function send(message) {
  if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
}

function setStatus(text, kind) {
  const el = $("link-status");
  el.textContent = text;
  el.className = "pill " + (kind || "");
}

function toast(text) {
  const el = $("toast");
  el.textContent = text;
  el.hidden = false;
  clearTimeout(toast.timer);
  toast.timer = setTimeout(() => { el.hidden = true; }, 3000);
}

// -- messages ---------------------------------------------------------------------------

function onHello(message) {
  view.hello = message;
  view.history = []; view.odometry = []; view.truth = [];
  const robot = message.robot || {};
  $("robot-id").textContent = message.robots
    ? `swarm of ${message.robots.length}: ${message.robots.join(", ")} · details of ${message.robots[0]}`
    : `${robot.port || ""} · ${robot.firmware || ""} firmware`;
  $("h-firmware").textContent = robot.profile || robot.firmware || "–";
  $("replay-bar").hidden = message.mode !== "replay";
  $("map-legend").textContent = message.world ? "odometry (blue) · true pose (orange)" : "odometry from the encoders";
  view.floorImage = null;
  if (message.world && message.world.floor_png) {
    const img = new Image();
    img.onload = () => { view.floorImage = img; view.dirty = true; };
    img.src = message.world.floor_png;
  }
  buildRobot(robot.proximity_count || 8, robot.led_count || 10);
  buildToggles(robot);
  view.dirty = true;
}

function onSample(sample) {
  const previous = view.sample;
  if (previous && sample.t < previous.t) { view.history = []; view.odometry = []; view.truth = []; }
  view.sample = sample;
  view.history.push(sample);
  while (view.history.length && sample.t - view.history[0].t > HISTORY_S) view.history.shift();
  if (sample.odometry) view.odometry.push(sample.odometry);
  if (sample.truth) view.truth.push(sample.truth);
  for (const trace of [view.odometry, view.truth]) if (trace.length > 5000) trace.splice(0, trace.length - 5000);
  view.dirty = true;
}

function onState(state) {
  view.state = state;
  const control = state.role === "control";
  const role = $("role");
  role.textContent = control ? "in control" : (state.held ? "viewer (another page drives)" : "viewer");
  role.className = "pill " + (control ? "control" : "");
  $("take").hidden = control;
  $("take").disabled = state.held && !control;
  $("release").hidden = !control;
  $("stop").disabled = !control;
  $("stop").classList.toggle("latched", !!state.halted);
  $("resume").hidden = !(control && state.halted);
  $("keyboard-note").hidden = !state.keyboard;
  for (const el of document.querySelectorAll(".pad button, .toggles input")) el.disabled = !control;
  if (state.replay) onReplay(state.replay);
}

function showImage(blob) {
  const img = $("camera");
  if (view.imageUrl) URL.revokeObjectURL(view.imageUrl);
  view.imageUrl = URL.createObjectURL(blob);
  img.onload = () => {
    $("camera-size").textContent = `${img.naturalWidth}×${img.naturalHeight}`;
    img.dataset.frames = String(Number(img.dataset.frames || 0) + 1);  // frames shown
  };
  img.src = view.imageUrl;
  img.hidden = false;
  $("camera-off").hidden = true;
}

// -- the robot from above ---------------------------------------------------------------

function el(name, attrs, parent) {
  const node = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  if (parent) parent.appendChild(node);
  return node;
}

function direction(bearing) { return [-Math.sin(bearing), -Math.cos(bearing)]; }

function buildRobot(proximityCount, ledCount) {
  const svg = $("robot");
  svg.replaceChildren();
  el("rect", { x: -44, y: -18, width: 7, height: 36, rx: 2, fill: "#333" }, svg);
  el("rect", { x: 37, y: -18, width: 7, height: 36, rx: 2, fill: "#333" }, svg);
  el("circle", { id: "body", cx: 0, cy: 0, r: BODY_MM, fill: "#e9edf3", stroke: "#9aa3b3", "stroke-width": 1.5 }, svg);
  for (let i = 0; i < proximityCount; i++) {
    const [dx, dy] = direction(PS_BEARINGS[i]);
    el("line", { id: `ray-${i}`, class: "ray", x1: dx * BODY_MM, y1: dy * BODY_MM, x2: dx * BODY_MM, y2: dy * BODY_MM,
      stroke: i >= 8 ? "#7b5cd6" : "#2f6fdf", "stroke-width": 5, "stroke-linecap": "round", "data-value": 0 }, svg);
    const t = el("text", { id: `ray-label-${i}`, x: dx * 100, y: dy * 100 + 3, "text-anchor": "middle", "font-size": 8, fill: "#6b7385" }, svg);
    t.textContent = `ps${i}`;
  }
  for (let i = 0; i < 8; i++) {
    const [dx, dy] = direction(PS_BEARINGS[i]);
    el("circle", { id: `light-${i}`, cx: dx * 31, cy: dy * 31, r: 3.2, fill: "#ddd", stroke: "#bbb" }, svg);
  }
  for (let i = 0; i < 3; i++) {
    el("rect", { id: `floor-${i}`, x: -14 + i * 10, y: -28, width: 8, height: 6, fill: "#ccc", stroke: "#999" }, svg);
  }
  for (let i = 0; i < Math.min(8, ledCount); i++) {
    const [dx, dy] = direction(-i * Math.PI / 4);
    el("circle", { id: `led-${i}`, cx: dx * 22, cy: dy * 22, r: 4, fill: "#5a1b1b" }, svg);
  }
  if (ledCount > 8) el("circle", { id: "led-8", cx: 0, cy: 4, r: 9, fill: "none", stroke: "#1d5e2f", "stroke-width": 3 }, svg);
  if (ledCount > 9) el("circle", { id: "led-9", cx: 0, cy: -33, r: 3, fill: "#5a1b1b" }, svg);
  el("path", { d: "M -6 -8 L 0 -16 L 6 -8", fill: "none", stroke: "#6b7385", "stroke-width": 2 }, svg);
  el("line", { id: "accel-arrow", x1: 0, y1: 4, x2: 0, y2: 4, stroke: "#1f9d55", "stroke-width": 2.5 }, svg);
}

function rayLength(value) {
  const v = Math.max(0, Math.min(1, (value - 40) / 4000));
  return 4 + 60 * Math.sqrt(v);
}

function drawRobot(sample) {
  const prox = sample.proximity;
  for (let i = 0; i < PS_BEARINGS.length; i++) {
    const ray = $(`ray-${i}`);
    if (!ray) continue;
    const value = prox && i < prox.length ? prox[i] : null;
    const [dx, dy] = direction(PS_BEARINGS[i]);
    const length = value === null ? 0 : rayLength(value);
    ray.setAttribute("x2", dx * (BODY_MM + length));
    ray.setAttribute("y2", dy * (BODY_MM + length));
    ray.setAttribute("data-value", value === null ? "" : value);
    ray.setAttribute("data-length", length.toFixed(2));
    ray.setAttribute("opacity", value === null ? 0.15 : 1);
  }
  for (let i = 0; i < 8; i++) {
    const v = sample.light ? sample.light[i] : null;
    const shade = v === null ? 221 : Math.round(60 + 195 * (1 - v / 4095));
    $(`light-${i}`).setAttribute("fill", v === null ? "#ddd" : `rgb(${shade},${shade},${Math.round(shade * 0.6)})`);
  }
  for (let i = 0; i < 3; i++) {
    const v = sample.floor ? sample.floor[i] : null;
    const g = v === null ? 204 : Math.max(0, Math.min(255, Math.round(v / 1000 * 255)));
    $(`floor-${i}`).setAttribute("fill", `rgb(${g},${g},${g})`);
  }
  const leds = sample.leds || [];
  for (let i = 0; i < leds.length; i++) {
    const led = $(`led-${i}`);
    if (!led) continue;
    if (i === 8) led.setAttribute("stroke", leds[i] ? "#2ecc71" : "#1d5e2f");
    else led.setAttribute("fill", leds[i] ? "#ff3b30" : "#5a1b1b");
  }
  const acc = sample.accelerometer;
  const arrow = $("accel-arrow");
  if (acc && arrow) {  // the horizontal part of the vector: x forward, y left
    arrow.setAttribute("x2", -acc[1] * 4);
    arrow.setAttribute("y2", 4 - acc[0] * 4);
  }
  const [left, right] = sample.speed || [0, 0];
  $("speed-left").textContent = left;
  $("speed-right").textContent = right;
  for (const [id, v] of [["bar-left", left], ["bar-right", right]]) {
    const bar = $(id);
    const frac = Math.max(-1, Math.min(1, v / 1000)) / 2;
    bar.style.left = frac >= 0 ? "50%" : `${(0.5 + frac) * 100}%`;
    bar.style.width = `${Math.abs(frac) * 100}%`;
  }
}

// -- the map ----------------------------------------------------------------------------

function drawMap() {
  const canvas = $("map");
  const ctx = canvas.getContext("2d");
  const world = view.hello && view.hello.world;
  let hx = 0.5, hy = 0.5;
  if (world) { hx = world.half_x; hy = world.half_y; }
  else for (const [x, y] of view.odometry) { hx = Math.max(hx, Math.abs(x) + 0.1); hy = Math.max(hy, Math.abs(y) + 0.1); }
  const scale = Math.min(canvas.width / (2 * hx), canvas.height / (2 * hy)) * 0.96;
  const cx = canvas.width / 2, cy = canvas.height / 2;
  const px = (x, y) => [cx + x * scale, cy - y * scale];
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (world) {
    const [x0, y0] = px(-hx, hy);
    if (view.floorImage) {
      ctx.imageSmoothingEnabled = false;
      ctx.drawImage(view.floorImage, x0, y0, 2 * hx * scale, 2 * hy * scale);
    }
    ctx.strokeStyle = "#8a7f6a"; ctx.lineWidth = 4;
    ctx.strokeRect(x0, y0, 2 * hx * scale, 2 * hy * scale);
    for (const box of world.boxes) {
      ctx.save();
      const [bx, by] = px(box.x, box.y);
      ctx.translate(bx, by); ctx.rotate(-box.yaw);
      ctx.fillStyle = `rgb(${box.rgb.join(",")})`;
      ctx.fillRect(-box.hx * scale, -box.hy * scale, 2 * box.hx * scale, 2 * box.hy * scale);
      ctx.restore();
    }
    const [lx, ly] = px(world.lamp[0], world.lamp[1]);
    ctx.fillStyle = "#ffd54a"; ctx.strokeStyle = "#b38f00"; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.arc(lx, ly, 7, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
  } else {
    ctx.strokeStyle = "#e3e6ec"; ctx.lineWidth = 1;
    for (let g = -Math.ceil(hx * 10); g <= Math.ceil(hx * 10); g++) {
      const [gx] = px(g / 10, 0); ctx.beginPath(); ctx.moveTo(gx, 0); ctx.lineTo(gx, canvas.height); ctx.stroke();
    }
    for (let g = -Math.ceil(hy * 10); g <= Math.ceil(hy * 10); g++) {
      const [, gy] = px(0, g / 10); ctx.beginPath(); ctx.moveTo(0, gy); ctx.lineTo(canvas.width, gy); ctx.stroke();
    }
  }
  const swarm = view.sample && view.sample.swarm;
  if (swarm) {  // every robot of a swarm, where it truly is
    ctx.font = "11px system-ui";
    for (const [name, x, y, theta] of swarm) {
      const [rx, ry] = px(x, y);
      ctx.fillStyle = "rgba(123,92,214,.35)"; ctx.strokeStyle = "#7b5cd6"; ctx.lineWidth = 1.5;
      ctx.beginPath(); ctx.arc(rx, ry, Math.max(4, 0.037 * scale), 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      ctx.beginPath(); ctx.moveTo(rx, ry);
      ctx.lineTo(rx + Math.cos(theta) * 0.05 * scale, ry - Math.sin(theta) * 0.05 * scale); ctx.stroke();
      ctx.fillStyle = "#1d2330"; ctx.fillText(name, rx + 8, ry - 8);
    }
  }
  drawTrace(ctx, view.truth, px, "#e8871e");
  drawTrace(ctx, view.odometry, px, "#2f6fdf");
  const pose = view.truth.length ? view.truth[view.truth.length - 1] : view.odometry[view.odometry.length - 1];
  if (pose) {
    const [rx, ry] = px(pose[0], pose[1]);
    ctx.fillStyle = "rgba(233,237,243,.9)"; ctx.strokeStyle = "#1d2330"; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.arc(rx, ry, Math.max(4, 0.037 * scale), 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
    ctx.beginPath(); ctx.moveTo(rx, ry);
    ctx.lineTo(rx + Math.cos(pose[2]) * 0.05 * scale, ry - Math.sin(pose[2]) * 0.05 * scale); ctx.stroke();
  }
}

function drawTrace(ctx, trace, px, colour) {
  if (trace.length < 2) return;
  ctx.strokeStyle = colour; ctx.lineWidth = 2; ctx.beginPath();
  trace.forEach(([x, y], i) => { const [a, b] = px(x, y); if (i) ctx.lineTo(a, b); else ctx.moveTo(a, b); });
  ctx.stroke();
}

// -- panels and plots -------------------------------------------------------------------

function drawPanels(sample) {
  const hello = view.hello || { robot: {} };
  $("h-time").textContent = `${sample.t.toFixed(2)} s`;
  $("h-step").textContent = `${sample.wall_ms.toFixed(1)} ms (asked ${sample.step_ms.toFixed(0)})`;
  $("h-overruns").textContent = sample.overruns === null ? "–" : sample.overruns;
  $("h-faults").textContent = `${sample.link.retries} / ${sample.link.resyncs}`;
  $("h-restarts").textContent = sample.link.restarts;
  $("h-battery").textContent = sample.battery === null ? "not served" : sample.battery;
  $("h-firmware").textContent = hello.robot.profile || hello.robot.firmware || "–";
  $("accel").textContent = sample.accelerometer ? sample.accelerometer.map((v) => v.toFixed(2)).join("  ") : "off";
  $("encoders").textContent = sample.encoders ? sample.encoders.join("  ") : "off";
  const mics = $("mics");
  const values = sample.microphones || [];
  if (mics.querySelectorAll("div").length !== values.length || !mics.firstChild) {
    mics.replaceChildren(...values.map((_, i) => {
      const row = document.createElement("div");
      row.innerHTML = `<span>mic${i}</span><span class="bar"><i></i></span><span class="mono"></span>`;
      return row;
    }));
    if (!values.length) mics.textContent = "off";
  }
  values.forEach((v, i) => {
    const row = mics.children[i];
    row.querySelector("i").style.width = `${Math.min(100, v / 40.95)}%`;
    row.querySelector(".mono").textContent = v;
  });
  for (const input of document.querySelectorAll("#sensor-toggles input")) {
    if (document.activeElement === input) continue;
    input.checked = sample[input.dataset.family] !== null && sample[input.dataset.family] !== undefined;
  }
  if (!sample.camera) { $("camera").hidden = true; $("camera-off").hidden = false; }
  for (const input of document.querySelectorAll("#led-toggles input")) {
    if (document.activeElement !== input) input.checked = !!(sample.leds || [])[Number(input.dataset.index)];
  }
}

function seriesOf(sample, name) {
  if (name === "step") return [sample.wall_ms];
  return sample[name] || [];
}

function drawPlot() {
  const canvas = $("plot");
  const ctx = canvas.getContext("2d");
  const name = $("plot-series").value;
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const history = view.history;
  if (history.length < 2) return;
  const t1 = history[history.length - 1].t, t0 = t1 - HISTORY_S;
  let lo = Infinity, hi = -Infinity;
  for (const s of history) for (const v of seriesOf(s, name)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  if (!isFinite(lo)) { ctx.fillStyle = "#6b7385"; ctx.fillText(`${SERIES[name]}: off`, 10, 20); return; }
  if (hi - lo < 1e-6) { hi += 1; lo -= 1; }
  const pad = 24, w = canvas.width - pad - 8, h = canvas.height - 20;
  const x = (t) => pad + (t - t0) / HISTORY_S * w;
  const y = (v) => 8 + (1 - (v - lo) / (hi - lo)) * (h - 8);
  ctx.fillStyle = "#6b7385"; ctx.font = "11px system-ui";
  ctx.fillText(hi.toFixed(hi > 100 ? 0 : 2), 2, 12); ctx.fillText(lo.toFixed(lo > 100 ? 0 : 2), 2, h);
  const count = Math.max(...history.map((s) => seriesOf(s, name).length));
  for (let k = 0; k < count; k++) {
    ctx.strokeStyle = COLOURS[k % COLOURS.length]; ctx.lineWidth = 1.5; ctx.beginPath();
    let started = false;
    for (const s of history) {
      const values = seriesOf(s, name);
      if (k >= values.length) { started = false; continue; }
      if (started) ctx.lineTo(x(s.t), y(values[k])); else { ctx.moveTo(x(s.t), y(values[k])); started = true; }
    }
    ctx.stroke();
  }
}

function render() {
  if (view.dirty && view.sample) {
    drawRobot(view.sample);
    drawPanels(view.sample);
    drawPlot();
    view.dirty = false;
  }
  if (view.hello) drawMap();
  requestAnimationFrame(render);
}

// -- controls ---------------------------------------------------------------------------

function buildToggles(robot) {
  const leds = $("led-toggles");
  leds.replaceChildren();
  for (let i = 0; i < (robot.led_count || 10); i++) {
    const label = document.createElement("label");
    label.innerHTML = `<input type="checkbox" data-index="${i}"> led${i}`;
    label.querySelector("input").addEventListener("change", (e) => send({ type: "led", index: i, on: e.target.checked }));
    leds.appendChild(label);
  }
  const sensors = $("sensor-toggles");
  sensors.replaceChildren();
  for (const family of [...(robot.families || []), "camera"]) {
    const label = document.createElement("label");
    label.innerHTML = `<input type="checkbox" id="sensor-${family}" data-family="${family}"> ${family}`;
    label.querySelector("input").addEventListener("change", (e) => send({ type: "sensor", family, on: e.target.checked }));
    sensors.appendChild(label);
  }
  onState(view.state);
}

function driveFromHeld() {
  let left = 0, right = 0;
  for (const key of held) { left += DRIVE[key][0]; right += DRIVE[key][1]; }
  const clamp = (v) => Math.round(Math.max(-1, Math.min(1, v)) * DRIVE_SPEED);
  return [clamp(left), clamp(right)];
}

setInterval(() => {  // repeat the drive while keys are held: it lapses on its own otherwise
  if (view.state.role !== "control" || view.state.keyboard) return;
  if (held.size) { const [left, right] = driveFromHeld(); send({ type: "drive", left, right }); drivingSent = true; }
  else if (drivingSent) { send({ type: "drive", left: 0, right: 0 }); drivingSent = false; }
}, 100);

document.addEventListener("keydown", (event) => {
  if (view.state.role !== "control" || event.target.tagName === "INPUT" || event.target.tagName === "SELECT") return;
  send({ type: "key", key: event.key, shift: event.shiftKey, ctrl: event.ctrlKey, alt: event.altKey });
  if (event.key in DRIVE) { event.preventDefault(); held.add(event.key); }
});
document.addEventListener("keyup", (event) => held.delete(event.key));
window.addEventListener("blur", () => held.clear());

for (const button of document.querySelectorAll(".pad button")) {
  const key = button.dataset.drive;
  button.addEventListener("pointerdown", () => { held.add(key); send({ type: "key", key }); });
  for (const end of ["pointerup", "pointerleave", "pointercancel"]) button.addEventListener(end, () => held.delete(key));
}

$("take").addEventListener("click", () => send({ type: "take" }));
$("release").addEventListener("click", () => send({ type: "release" }));
$("stop").addEventListener("click", () => send({ type: "stop" }));
$("resume").addEventListener("click", () => send({ type: "resume" }));

// -- replay -----------------------------------------------------------------------------

function onReplay(replay) {
  $("play").textContent = replay.playing ? "Pause" : "Play";
  if (document.activeElement !== $("seek")) $("seek").value = Math.round(replay.position * 1000);
  $("replay-time").textContent = `${replay.t.toFixed(1)} / ${replay.duration.toFixed(1)} s`;
  $("replay-speed").value = String(replay.speed);
}
$("play").addEventListener("click", () => send({ type: "replay", action: $("play").textContent === "Pause" ? "pause" : "play" }));
$("seek").addEventListener("change", (e) => send({ type: "replay", action: "seek", position: Number(e.target.value) / 1000 }));
$("replay-speed").addEventListener("change", (e) => send({ type: "replay", action: "speed", speed: Number(e.target.value) }));

for (const [value, label] of Object.entries(SERIES)) {
  const option = document.createElement("option");
  option.value = value; option.textContent = label;
  $("plot-series").appendChild(option);
}
$("plot-series").addEventListener("change", () => { view.dirty = true; });

connect();
requestAnimationFrame(render);
