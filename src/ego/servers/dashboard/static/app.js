// ego's dashboard: one WebSocket in (samples, camera JPEGs, state), commands out.
// Plain JS, no build step, no inline script or style (the page's CSP forbids them).
// The robot is drawn 1 unit = 1 mm, its front up; canvases are drawn in CSS pixels.
"use strict";

const $ = (id) => document.getElementById(id);
const SVG = "http://www.w3.org/2000/svg";
const BODY_MM = 37;
// Bearings from the front, counter-clockwise positive (ps0 front-right .. ps7 front-left),
// then the Overo board's long-range IR8 and IR9.
const PS_BEARINGS = [-0.30, -0.80, -1.57, -2.64, 2.64, 1.57, 0.80, 0.30, 0.5, -0.5];
const DRIVE = { ArrowUp: [1, 1], ArrowDown: [-1, -1], ArrowLeft: [-0.6, 0.6], ArrowRight: [0.6, -0.6] };
const DRIVE_SPEED = 500;   // steps/s at full key
const HISTORY_S = 60;      // what the page keeps (the server sends its last minute on connect)
const RAD_PER_STEP = 2 * Math.PI / 1000;  // 1000 steps a wheel turn: Webots' rad and rad/s
const SIDES = ["left", "right"];
// What the plot can show: its title, its unit, each line's name, and Webots' unit (if any).
// The sensor families' series are the device table's, as the server describes them in its
// hello (robot.series); only what every robot has besides is written here.
const OWN_SERIES = {
  speed: { title: "wheel speeds", unit: "steps/s", names: (i) => SIDES[i],
    webots: { unit: "rad/s", per: RAD_PER_STEP } },
  step: { title: "step time", unit: "ms", names: (i) => ["wall time", "asked"][i] },
};
let SERIES = { ...OWN_SERIES };
// The LEDs whose value is a colour 0xRRGGBB (the firmware's RGB LEDs: the hello's rgb_leds).
let RGB_LEDS = [];

function tableSeries(described) {
  const found = {};
  for (const s of described || []) {
    found[s.key] = { title: s.title, unit: s.unit, webots: s.webots,
      names: (i) => (i < s.lines.length ? s.lines[i] : `${i}`) };
  }
  return found;
}
const COLOURS = ["#2f6fdf", "#e8871e", "#1f9d55", "#d62f2f", "#7b5cd6", "#12a4b4", "#b5651d", "#6b7385", "#c2185b", "#455a64"];
const TRUTH = "#e8871e", ODOMETRY = "#2f6fdf", WALL = "#4a3c28", SWARM = "#7b5cd6";
const LABEL_PX = 12;       // the swarm's names on the map, in CSS pixels

const view = { hello: null, sample: null, swarm: null, pick: null, webots: false,
  state: { role: "view", held: false, halted: false, keyboard: false },
  history: [], odometry: [], truth: [], floorImage: null, dirty: true, mapDirty: true, imageUrl: null,
  legendKey: "", geometry: null };
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
  socket.onopen = () => setStatus("connected", "ok");
  socket.onclose = () => { setStatus("disconnected", "bad"); held.clear(); setTimeout(connect, 1000); };
  socket.onmessage = (event) => {
    if (typeof event.data !== "string") { showImage(event.data); return; }
    const message = JSON.parse(event.data);
    if (message.type === "sample") onSample(message);
    else if (message.type === "state") onState(message);
    else if (message.type === "history") onHistory(message);
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

function mode() { return view.hello ? view.hello.mode : "live"; }

// -- messages ---------------------------------------------------------------------------

function onHello(message) {
  view.hello = message;
  view.webots = !!message.webots;
  view.swarm = null;
  clearHistory();
  const robot = message.robot || {};
  const replay = message.mode === "replay";
  setStatus(replay ? "replay" : "live", replay ? "replay" : "ok");
  $("robot-id").textContent = message.robots
    ? `swarm of ${message.robots.length} robots`
    : `${robot.port || ""} · ${robot.firmware || ""} firmware${replay ? " · recorded" : ""}`;
  $("h-firmware").textContent = robot.profile || robot.firmware || "–";
  $("replay-bar").hidden = !replay;
  $("controls").hidden = message.mode !== "live";  // served, swarm: their controllers own the devices
  for (const el of document.querySelectorAll(".rad")) el.hidden = !view.webots;
  $("speed-unit").textContent = view.webots ? "steps/s (rad/s)" : "steps/s";
  $("encoder-unit").textContent = view.webots ? "left right, steps (rad)" : "left right, steps";
  buildPicker(message.robots);
  buildMapLegend(message);
  view.floorImage = null;
  if (message.world && message.world.floor_png) {
    const img = new Image();
    img.onload = () => { view.floorImage = img; view.mapDirty = true; };
    img.src = message.world.floor_png;
  }
  SERIES = { ...tableSeries(robot.series), ...OWN_SERIES };
  RGB_LEDS = robot.rgb_leds || [];
  buildRobot(robot.proximity_count || 8, robot.led_count || 10);
  buildToggles(robot);
  buildSeries();
  view.dirty = view.mapDirty = true;
}

function clearHistory() {
  view.history = []; view.odometry = []; view.truth = []; view.sample = null;
  view.dirty = view.mapDirty = true;
}

// The sample of the robot this page details: a swarm's other robots come under "details".
function detailOf(message) {
  const robots = view.hello && view.hello.robots;
  if (!robots || !view.pick || view.pick === robots[0]) return message;
  return (message.details && message.details[view.pick]) || null;
}

function onSample(message) {
  if (message.swarm) { view.swarm = message.swarm; view.mapDirty = true; }
  const sample = detailOf(message);
  if (sample) addSample(sample);
}

function addSample(sample) {
  const previous = view.sample;
  if (previous && sample.t < previous.t) clearHistory();
  view.sample = sample;
  view.history.push(sample);
  while (view.history.length && sample.t - view.history[0].t > HISTORY_S) view.history.shift();
  if (sample.odometry) view.odometry.push(sample.odometry);
  if (sample.truth) view.truth.push(sample.truth);
  for (const trace of [view.odometry, view.truth]) if (trace.length > 5000) trace.splice(0, trace.length - 5000);
  view.dirty = view.mapDirty = true;
}

// The server's last minute, sent as the page connects: what came before the live samples.
function onHistory(message) {
  const first = view.history.length ? view.history[0].t : Infinity;
  const older = [];
  for (const entry of message.samples) {
    const sample = detailOf(entry);
    if (sample && sample.t < first) older.push(sample);
  }
  const last = message.samples[message.samples.length - 1];
  if (last && last.swarm && !view.swarm) view.swarm = last.swarm;
  if (!older.length) return;
  view.history = older.concat(view.history);
  view.odometry = older.filter((s) => s.odometry).map((s) => s.odometry).concat(view.odometry);
  view.truth = older.filter((s) => s.truth).map((s) => s.truth).concat(view.truth);
  if (!view.sample) view.sample = older[older.length - 1];
  view.dirty = view.mapDirty = true;
}

function onState(state) {
  view.state = state;
  const replay = mode() === "replay";
  const control = state.role === "control";
  const role = $("role");
  role.textContent = control ? "in control" : (state.held ? "viewer (another page drives)" : "viewer");
  role.className = "pill " + (control ? "control" : "");
  role.hidden = replay;
  $("take").hidden = control || replay;
  $("take").disabled = state.held && !control;
  $("release").hidden = !control || replay;
  $("stop").hidden = replay;  // a recording has no robot to stop
  $("stop").disabled = !control;
  $("stop").classList.toggle("latched", !!state.halted);
  $("resume").hidden = !(control && state.halted) || replay;
  $("stopped-banner").hidden = !state.halted || replay;
  $("stopped-detail").textContent = control
    ? "the wheels are held at 0 whatever the controller asks: Resume lets it drive again"
    : "the wheels are held at 0 whatever the controller asks, until the page in control resumes";
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

// -- a swarm: which robot the page details ------------------------------------------------

function buildPicker(robots) {
  const select = $("robot-pick");
  $("pick-label").hidden = !robots;
  select.replaceChildren();
  if (!robots) { view.pick = null; $("robot-name").textContent = ""; return; }
  for (const name of robots) {
    const option = document.createElement("option");
    option.value = option.textContent = name;
    select.appendChild(option);
  }
  if (!robots.includes(view.pick)) view.pick = robots[0];
  pick(view.pick);
}

function pick(name) {
  const changed = view.pick !== name;
  view.pick = name;
  $("robot-pick").value = name;
  $("robot-name").textContent = name;
  send({ type: "pick", robot: name });
  if (changed) clearHistory();
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
    const t = el("text", { id: `ray-label-${i}`, x: dx * 100, y: dy * 100 + 3, "text-anchor": "middle", "font-size": 9, fill: "#6b7385" }, svg);
    t.textContent = SERIES.proximity ? SERIES.proximity.names(i) : `${i}`;
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

function ledColour(rgb) {
  return "#" + (rgb & 0xffffff).toString(16).padStart(6, "0");
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
    else if (RGB_LEDS.includes(i)) led.setAttribute("fill", leds[i] ? ledColour(leds[i]) : "#5a1b1b");
    else led.setAttribute("fill", leds[i] ? "#ff3b30" : "#5a1b1b");
  }
  const acc = sample.accelerometer;
  const arrow = $("accel-arrow");
  if (acc && arrow) {  // the horizontal part of the vector: x forward, y left
    arrow.setAttribute("x2", -acc[1] * 4);
    arrow.setAttribute("y2", 4 - acc[0] * 4);
  }
  drawWheels(sample.speed || [0, 0]);
}

function drawWheels([left, right]) {
  $("speed-left").textContent = left;
  $("speed-right").textContent = right;
  $("speed-left-rad").textContent = (left * RAD_PER_STEP).toFixed(2);
  $("speed-right-rad").textContent = (right * RAD_PER_STEP).toFixed(2);
  for (const [id, v] of [["bar-left", left], ["bar-right", right]]) {
    const bar = $(id);
    const frac = Math.max(-1, Math.min(1, v / 1000)) / 2;
    bar.style.left = frac >= 0 ? "50%" : `${(0.5 + frac) * 100}%`;
    bar.style.width = `${Math.abs(frac) * 100}%`;
  }
}

// -- canvases ---------------------------------------------------------------------------

// Size a canvas's pixels to its box on screen (sharp on any screen); its context, drawing
// in CSS pixels, and the box's width and height.
function fitCanvas(canvas) {
  const dpr = window.devicePixelRatio || 1;
  const w = Math.max(1, canvas.clientWidth), h = Math.max(1, canvas.clientHeight);
  const pw = Math.round(w * dpr), ph = Math.round(h * dpr);
  if (canvas.width !== pw || canvas.height !== ph) { canvas.width = pw; canvas.height = ph; }
  const ctx = canvas.getContext("2d");
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, w, h);
  return [ctx, w, h];
}

// -- the map ----------------------------------------------------------------------------

function buildMapLegend(hello) {
  const items = [["k-odometry", "odometry (from the encoders)"]];
  if (hello.world) {
    items.push(["k-truth", "true pose"], ["wall", "walls"], ["area k-box", "boxes"],
      ["area k-floor", "floor marks (on the floor)"], ["dot k-lamp", "lamp"]);
  }
  if (hello.robots) items.push(["dot k-robot", "robots (click one to detail it)"]);
  legend($("map-legend"), items);
}

function legend(list, items) {
  list.replaceChildren(...items.map(([kind, text]) => {
    const li = document.createElement("li");
    li.className = kind;
    const span = document.createElement("span");
    span.textContent = text;
    li.appendChild(span);
    return li;
  }));
}

// Where the map draws the world's point (x, y) m, in CSS pixels of its canvas.
function mapPoint(x, y) {
  const g = view.geometry;
  return g ? [g.cx + x * g.scale, g.cy - y * g.scale] : null;
}

function mapGeometry(w, h) {
  const world = view.hello && view.hello.world;
  let hx = 0.5, hy = 0.5;
  if (world) { hx = world.half_x; hy = world.half_y; }
  else for (const [x, y] of view.odometry) { hx = Math.max(hx, Math.abs(x) + 0.1); hy = Math.max(hy, Math.abs(y) + 0.1); }
  const scale = Math.min(w / (2 * hx), h / (2 * hy)) * 0.94;
  return { hx, hy, scale, cx: w / 2, cy: h / 2 };
}

function drawMap() {
  const canvas = $("map");
  const sized = canvas.width === Math.round(canvas.clientWidth * (window.devicePixelRatio || 1));
  if (!view.mapDirty && sized) return;
  view.mapDirty = false;
  const [ctx, w, h] = fitCanvas(canvas);
  view.geometry = mapGeometry(w, h);
  const world = view.hello && view.hello.world;
  if (world) drawWorld(ctx, world);
  else drawGrid(ctx, w, h);
  if (view.swarm) drawSwarm(ctx, canvas);
  drawTrace(ctx, view.truth, TRUTH, 5, 0.75);
  drawTrace(ctx, view.odometry, ODOMETRY, 2, 1);
  const pose = view.truth.length ? view.truth[view.truth.length - 1] : view.odometry[view.odometry.length - 1];
  if (pose && !view.swarm) drawBody(ctx, pose, "rgba(233,237,243,.9)", "#1d2330");  // a swarm's: drawn above
}

function drawWorld(ctx, world) {
  const { hx, hy, scale } = view.geometry;
  const [x0, y0] = mapPoint(-hx, hy);
  const w = 2 * hx * scale, h = 2 * hy * scale;
  ctx.fillStyle = "#fff";
  ctx.fillRect(x0, y0, w, h);
  if (view.floorImage) {  // faint: marks on the floor, not obstacles
    ctx.save();
    ctx.globalAlpha = 0.3;
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(view.floorImage, x0, y0, w, h);
    ctx.restore();
  }
  ctx.strokeStyle = WALL; ctx.lineWidth = 6;  // the walls, just outside the floor
  ctx.strokeRect(x0 - 3, y0 - 3, w + 6, h + 6);
  for (const box of world.boxes) {
    ctx.save();
    const [bx, by] = mapPoint(box.x, box.y);
    ctx.translate(bx, by); ctx.rotate(-box.yaw);
    ctx.fillStyle = `rgb(${box.rgb.join(",")})`; ctx.strokeStyle = "#1d2330"; ctx.lineWidth = 1.5;
    ctx.fillRect(-box.hx * scale, -box.hy * scale, 2 * box.hx * scale, 2 * box.hy * scale);
    ctx.strokeRect(-box.hx * scale, -box.hy * scale, 2 * box.hx * scale, 2 * box.hy * scale);
    ctx.restore();
  }
  const [lx, ly] = mapPoint(world.lamp[0], world.lamp[1]);
  ctx.fillStyle = "#ffd54a"; ctx.strokeStyle = "#b38f00"; ctx.lineWidth = 1.5;
  ctx.beginPath(); ctx.arc(lx, ly, 7, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
}

function drawGrid(ctx, w, h) {
  const { hx, hy } = view.geometry;
  ctx.strokeStyle = "#e3e6ec"; ctx.lineWidth = 1;
  for (let g = -Math.ceil(hx * 10); g <= Math.ceil(hx * 10); g++) {
    const [gx] = mapPoint(g / 10, 0); ctx.beginPath(); ctx.moveTo(gx, 0); ctx.lineTo(gx, h); ctx.stroke();
  }
  for (let g = -Math.ceil(hy * 10); g <= Math.ceil(hy * 10); g++) {
    const [, gy] = mapPoint(0, g / 10); ctx.beginPath(); ctx.moveTo(0, gy); ctx.lineTo(w, gy); ctx.stroke();
  }
  ctx.fillStyle = "#6b7385"; ctx.font = "11px system-ui";
  ctx.fillText("grid: 10 cm", 6, h - 6);
}

function drawBody(ctx, [x, y, theta], fill, stroke) {
  const [rx, ry] = mapPoint(x, y);
  const scale = view.geometry.scale;
  ctx.fillStyle = fill; ctx.strokeStyle = stroke; ctx.lineWidth = 1.5;
  ctx.beginPath(); ctx.arc(rx, ry, Math.max(4, 0.037 * scale), 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
  ctx.beginPath(); ctx.moveTo(rx, ry);
  ctx.lineTo(rx + Math.cos(theta) * 0.05 * scale, ry - Math.sin(theta) * 0.05 * scale); ctx.stroke();
}

// Every robot of a swarm where it truly is, each named, the names placed clear of the
// robots and of each other, with a leader line to a name that had to go further out.
function drawSwarm(ctx, canvas) {
  ctx.font = `${LABEL_PX}px system-ui`;
  const radius = Math.max(4, 0.037 * view.geometry.scale);
  const discs = view.swarm.map(([, x, y]) => { const [rx, ry] = mapPoint(x, y); return [rx - radius, ry - radius, 2 * radius, 2 * radius]; });
  for (const [name, x, y, theta] of view.swarm) {
    const picked = name === view.pick;
    drawBody(ctx, [x, y, theta], picked ? "rgba(47,111,223,.45)" : "rgba(123,92,214,.3)", picked ? ODOMETRY : SWARM);
  }
  const placed = [];
  for (const [name, x, y] of view.swarm) {
    const [rx, ry] = mapPoint(x, y);
    const box = placeLabel(ctx, name, rx, ry, radius, [...discs, ...placed], canvas.clientWidth, canvas.clientHeight);
    placed.push(box);
    const [nx, ny] = [Math.min(Math.max(rx, box[0]), box[0] + box[2]), Math.min(Math.max(ry, box[1]), box[1] + box[3])];
    if (Math.hypot(nx - rx, ny - ry) > radius + 6) {
      ctx.strokeStyle = "#6b7385"; ctx.lineWidth = 1;
      ctx.beginPath(); ctx.moveTo(rx, ry); ctx.lineTo(nx, ny); ctx.stroke();
    }
    ctx.fillStyle = "rgba(255,255,255,.9)"; ctx.fillRect(box[0], box[1], box[2], box[3]);
    ctx.fillStyle = name === view.pick ? ODOMETRY : "#1d2330";
    ctx.fillText(name, box[0] + 2, box[1] + box[3] - 4);
  }
  canvas.dataset.labels = JSON.stringify(placed.map((b) => b.map((v) => Math.round(v * 10) / 10)));
  canvas.dataset.labelPx = String(LABEL_PX);
  canvas.classList.add("pickable");
}

function placeLabel(ctx, name, rx, ry, radius, taken, w, h) {
  const bw = ctx.measureText(name).width + 4, bh = LABEL_PX + 5;
  const overlaps = (a) => taken.some((b) => a[0] < b[0] + b[2] && b[0] < a[0] + a[2] && a[1] < b[1] + b[3] && b[1] < a[1] + a[3]);
  const labels = taken.slice(view.swarm.length);  // the names placed so far
  const clearOfNames = (a) => !labels.some((b) => a[0] < b[0] + b[2] && b[0] < a[0] + a[2] && a[1] < b[1] + b[3] && b[1] < a[1] + a[3]);
  let fallback = null;
  for (const reach of [1, 1.6, 2.4, 3.4, 4.6, 6]) {
    const d = radius * reach + 2;
    for (const [ox, oy] of [[d, -bh / 2], [-d - bw, -bh / 2], [-bw / 2, -d - bh], [-bw / 2, d], [d, -d - bh], [d, d], [-d - bw, -d - bh], [-d - bw, d]]) {
      const box = [Math.min(Math.max(rx + ox, 0), w - bw), Math.min(Math.max(ry + oy, 0), h - bh), bw, bh];
      if (!overlaps(box)) return box;
      if (!fallback && clearOfNames(box)) fallback = box;  // over a robot, at worst
    }
  }
  return fallback || [Math.min(Math.max(rx + radius, 0), w - bw), Math.min(Math.max(ry, 0), h - bh), bw, bh];
}

function drawTrace(ctx, trace, colour, width, alpha) {
  if (trace.length < 2) return;
  ctx.save();
  ctx.globalAlpha = alpha; ctx.strokeStyle = colour; ctx.lineWidth = width; ctx.lineJoin = "round";
  ctx.beginPath();
  trace.forEach(([x, y], i) => { const [a, b] = mapPoint(x, y); if (i) ctx.lineTo(a, b); else ctx.moveTo(a, b); });
  ctx.stroke();
  ctx.restore();
}

$("map").addEventListener("click", (event) => {  // a swarm: the robot nearest the click
  if (!view.swarm || !view.geometry) return;
  const rect = $("map").getBoundingClientRect();
  const cx = event.clientX - rect.left, cy = event.clientY - rect.top;
  let best = null, bestD = 24;
  for (const [name, x, y] of view.swarm) {
    const [rx, ry] = mapPoint(x, y);
    const d = Math.hypot(rx - cx, ry - cy);
    if (d < bestD) { best = name; bestD = d; }
  }
  if (best) pick(best);
});

// -- panels -----------------------------------------------------------------------------

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
  $("encoders").textContent = encoderText(sample.encoders);
  drawMics(sample.microphones || []);
  for (const input of document.querySelectorAll("#sensor-toggles input")) {
    if (document.activeElement === input) continue;
    input.checked = sample[input.dataset.family] !== null && sample[input.dataset.family] !== undefined;
  }
  if (!sample.camera) { $("camera").hidden = true; $("camera-off").hidden = false; }
  for (const input of document.querySelectorAll("#led-toggles input")) {
    if (document.activeElement !== input) input.checked = !!(sample.leds || [])[Number(input.dataset.index)];
  }
}

function encoderText(encoders) {
  if (!encoders) return "off";
  const steps = encoders.map((v) => Math.round(v)).join("  ");
  return view.webots ? `${steps}  (${encoders.map((v) => (v * RAD_PER_STEP).toFixed(2)).join("  ")} rad)` : steps;
}

function drawMics(values) {
  const mics = $("mics");
  if (mics.querySelectorAll("div").length !== values.length || !mics.firstChild) {
    mics.replaceChildren(...values.map((_, i) => {
      const row = document.createElement("div");
      for (const [tag, cls, text] of [["span", "", `mic${i}`], ["span", "bar", ""], ["span", "mono", ""]]) {
        const part = document.createElement(tag);
        if (cls) part.className = cls;
        part.textContent = text;
        row.appendChild(part);
      }
      row.querySelector(".bar").appendChild(document.createElement("i"));
      return row;
    }));
    if (!values.length) mics.textContent = "off";
  }
  values.forEach((v, i) => {
    const row = mics.children[i];
    row.querySelector("i").style.width = `${Math.min(100, v / 40.95)}%`;
    row.querySelector(".mono").textContent = Math.round(v);
  });
}

// -- the plot ---------------------------------------------------------------------------

function buildSeries() {
  const select = $("plot-series");
  const chosen = select.value in SERIES ? select.value : Object.keys(SERIES)[0];
  select.replaceChildren();
  for (const [value, series] of Object.entries(SERIES)) {
    const option = document.createElement("option");
    option.value = value;
    const webots = series.webots && view.webots ? ` · ${series.webots.unit}` : "";
    option.textContent = `${series.title} (${series.unit}${webots})`;
    select.appendChild(option);
  }
  select.value = chosen;
  view.legendKey = "";
}

function seriesOf(sample, name) {
  if (name === "step") return [sample.wall_ms, sample.step_ms];
  return sample[name] || [];
}

// Round tick values spanning lo..hi, about `count` of them, and their step.
function ticks(lo, hi, count) {
  const raw = (hi - lo) / Math.max(1, count);
  const power = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 2.5, 5, 10].map((m) => m * power).find((s) => s >= raw) || 10 * power;
  const values = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) values.push(v);
  return { step, values };
}

function rangeOf(lo, hi, step) {
  const values = [];
  for (let k = Math.round(lo / step); k <= Math.round(hi / step); k++) values.push(k * step);
  return values;
}

// A tick's label: whole numbers as whole numbers, decimals only as many as the step needs.
function tickText(value, step) {
  const decimals = step >= 1 ? 0 : Math.min(6, Math.ceil(-Math.log10(step) - 1e-9));
  const text = (Math.abs(value) < step * 1e-6 ? 0 : value).toFixed(decimals);
  return text === "-0" ? "0" : text;
}

function plotLegend(name, count) {
  const key = `${name}:${count}`;
  if (view.legendKey === key) return;
  view.legendKey = key;
  const items = [];
  for (let k = 0; k < count; k++) items.push([`c${k % COLOURS.length}`, SERIES[name].names(k)]);
  legend($("plot-legend"), items);
}

function drawPlot() {
  const canvas = $("plot");
  const [ctx, w, h] = fitCanvas(canvas);
  const name = $("plot-series").value;
  const series = SERIES[name];
  const window_s = Number($("plot-window").value);
  const history = view.history;
  ctx.font = "11px system-ui"; ctx.fillStyle = "#6b7385";
  if (history.length < 2) { plotLegend(name, 0); ctx.fillText("waiting for samples…", 10, 20); return; }
  const t1 = history[history.length - 1].t, t0 = t1 - window_s;
  const shown = history.filter((s) => s.t >= t0);
  let lo = Infinity, hi = -Infinity, count = 0;
  for (const s of shown) {
    const values = seriesOf(s, name);
    count = Math.max(count, values.length);
    for (const v of values) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  }
  plotLegend(name, count);
  if (!isFinite(lo)) { ctx.fillText(`${series.title}: off (not sampled)`, 10, 20); return; }
  if (hi - lo < 1e-6) { hi += 1; lo -= 1; }
  const webots = series.webots && view.webots ? series.webots : null;
  const box = { left: 56, right: webots ? 56 : 14, top: 28, bottom: 34 };
  const pw = w - box.left - box.right, ph = h - box.top - box.bottom;
  const yt = ticks(lo, hi, Math.max(2, Math.floor(ph / 40)));  // the axis spans whole ticks
  lo = Math.floor(lo / yt.step + 1e-9) * yt.step; hi = Math.ceil(hi / yt.step - 1e-9) * yt.step;
  yt.values = rangeOf(lo, hi, yt.step);
  const x = (t) => box.left + (t - t0) / window_s * pw;
  const y = (v) => box.top + (1 - (v - lo) / (hi - lo)) * ph;
  drawAxes(ctx, { box, w, h, pw, ph, x, y, yt, t0, t1, series, webots, first: shown[0].t });
  for (let k = 0; k < count; k++) {
    ctx.strokeStyle = COLOURS[k % COLOURS.length]; ctx.lineWidth = 1.5; ctx.beginPath();
    let started = false;
    for (const s of shown) {
      const values = seriesOf(s, name);
      if (k >= values.length) { started = false; continue; }
      if (started) ctx.lineTo(x(s.t), y(values[k])); else { ctx.moveTo(x(s.t), y(values[k])); started = true; }
    }
    ctx.stroke();
  }
  canvas.dataset.yTicks = JSON.stringify(yt.values.map((v) => tickText(v, yt.step)));
  canvas.dataset.units = webots ? `${series.unit} | ${webots.unit}` : series.unit;
}

function drawAxes(ctx, a) {
  const { box, pw, ph, x, y, yt, t0, t1, series, webots } = a;
  ctx.strokeStyle = "#e3e6ec"; ctx.lineWidth = 1; ctx.fillStyle = "#6b7385"; ctx.font = "11px system-ui";
  ctx.textAlign = "right"; ctx.textBaseline = "middle";
  for (const v of yt.values) {
    const yy = Math.round(y(v)) + 0.5;
    ctx.beginPath(); ctx.moveTo(box.left, yy); ctx.lineTo(box.left + pw, yy); ctx.stroke();
    ctx.fillText(tickText(v, yt.step), box.left - 6, yy);
  }
  if (webots) {
    ctx.textAlign = "left";
    for (const v of yt.values) ctx.fillText(tickText(v * webots.per, yt.step * webots.per), box.left + pw + 6, y(v));
  }
  const xt = ticks(Math.max(t0, a.first), t1, Math.max(2, Math.floor(pw / 80)));
  ctx.textAlign = "center"; ctx.textBaseline = "top";
  for (const t of xt.values) {
    const xx = Math.round(x(t)) + 0.5;
    ctx.beginPath(); ctx.moveTo(xx, box.top); ctx.lineTo(xx, box.top + ph); ctx.stroke();
    ctx.fillText(tickText(t, xt.step), xx, box.top + ph + 5);
  }
  ctx.strokeStyle = "#9aa3b3";
  ctx.beginPath(); ctx.moveTo(box.left, box.top); ctx.lineTo(box.left, box.top + ph); ctx.lineTo(box.left + pw, box.top + ph); ctx.stroke();
  ctx.fillStyle = "#1d2330"; ctx.textBaseline = "alphabetic";
  ctx.textAlign = "left"; ctx.fillText(series.unit, 4, 12);
  if (webots) { ctx.textAlign = "right"; ctx.fillText(webots.unit, box.left + pw + box.right - 4, 12); }
  ctx.textAlign = "right"; ctx.fillText("controller time (s)", box.left + pw, box.top + ph + 30);
  ctx.textAlign = "left";
}

function render() {
  if (view.dirty && view.sample) {
    drawRobot(view.sample);
    drawPanels(view.sample);
  }
  if (view.dirty || $("plot").width !== Math.round($("plot").clientWidth * (window.devicePixelRatio || 1))) {
    drawPlot();
  }
  view.dirty = false;
  if (view.hello) drawMap();
  requestAnimationFrame(render);
}

// -- controls ---------------------------------------------------------------------------

function buildToggles(robot) {
  const leds = $("led-toggles");
  leds.replaceChildren();
  for (let i = 0; i < (robot.led_count || 10); i++) {
    leds.appendChild(toggle({ "data-index": i }, `led${i}`, (on) => send({ type: "led", index: i, on })));
  }
  const sensors = $("sensor-toggles");
  sensors.replaceChildren();
  for (const family of [...(robot.families || []), "camera"]) {
    sensors.appendChild(toggle({ id: `sensor-${family}`, "data-family": family }, family,
      (on) => send({ type: "sensor", family, on })));
  }
  onState(view.state);
}

function toggle(attrs, text, changed) {
  const label = document.createElement("label");
  const input = document.createElement("input");
  input.type = "checkbox";
  for (const [k, v] of Object.entries(attrs)) input.setAttribute(k, v);
  input.addEventListener("change", (e) => changed(e.target.checked));
  label.append(input, ` ${text}`);
  return label;
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
$("robot-pick").addEventListener("change", (e) => pick(e.target.value));
$("plot-series").addEventListener("change", () => { view.dirty = true; });
$("plot-window").addEventListener("change", () => { view.dirty = true; });

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

buildSeries();
connect();
requestAnimationFrame(render);
