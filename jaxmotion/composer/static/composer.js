// The composer's page: draw paths on the ground, lay actions along them, generate, watch, download.
// Plain JavaScript, no library: the 3D view is a perspective projection drawn on a 2D canvas.
"use strict";

const COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                 "#bcbd22", "#17becf"];
const WALKING_SPEED = 1.3;  // m/s: a drawn path's first duration guess
const $ = (id) => document.getElementById(id);

const state = {
  model: null,
  actions: [],        // {kind: "path", points: [[x, z], ...]} or {kind: "point", at: [x, z]}; + tags, seconds
  selected: -1,
  mode: "idle",       // "draw" | "split" | "idle"
  drawing: null,      // the points of the curve being drawn
  dragging: false,
  body: null,         // the body model's mesh (rest vertices, faces, four weights and joints a vertex), if any
  motion: null,       // the server's motion: joints (flat), frames, fps, segments, controls, downloads
  frame: 0,
  playing: false,
  camera: {yaw: 0.7, pitch: 0.45, distance: 6, target: [0, 0.9, 0]},
};

// ---------------------------------------------------------------- geometry of drawn paths

function pathLength(points) {
  let total = 0;
  for (let i = 1; i < points.length; i++) total += Math.hypot(points[i][0] - points[i - 1][0], points[i][1] - points[i - 1][1]);
  return total;
}

function resample(points, count) {  // evenly along the arc length
  const lengths = [0];
  for (let i = 1; i < points.length; i++) lengths.push(lengths[i - 1] + Math.hypot(points[i][0] - points[i - 1][0], points[i][1] - points[i - 1][1]));
  const total = lengths[lengths.length - 1];
  const out = [];
  for (let k = 0; k < count; k++) {
    const s = total * k / (count - 1);
    let i = 1;
    while (i < points.length - 1 && lengths[i] < s) i++;
    const span = lengths[i] - lengths[i - 1] || 1;
    const u = Math.min(Math.max((s - lengths[i - 1]) / span, 0), 1);
    out.push([points[i - 1][0] + u * (points[i][0] - points[i - 1][0]), points[i - 1][1] + u * (points[i][1] - points[i - 1][1])]);
  }
  return out;
}

// The control points of the cubic Bézier closest (least squares, ends fixed) to a drawn curve: what the server
// samples per frame (the supplement's §5.2). Two points make a straight line.
function bezierControls(points) {
  if (points.length < 3) return points.map((p) => p.slice());
  const samples = resample(points, 16);
  const p0 = samples[0], p3 = samples[15];
  let a11 = 0, a12 = 0, a22 = 0;
  const r1 = [0, 0], r2 = [0, 0];
  samples.forEach((d, i) => {
    const t = i / 15, s = 1 - t;
    const b0 = s * s * s, b1 = 3 * s * s * t, b2 = 3 * s * t * t, b3 = t * t * t;
    a11 += b1 * b1; a12 += b1 * b2; a22 += b2 * b2;
    for (let c = 0; c < 2; c++) {
      const r = d[c] - b0 * p0[c] - b3 * p3[c];
      r1[c] += b1 * r; r2[c] += b2 * r;
    }
  });
  const det = a11 * a22 - a12 * a12;
  if (Math.abs(det) < 1e-12) return [p0, p3];
  const p1 = [0, 1].map((c) => (a22 * r1[c] - a12 * r2[c]) / det);
  const p2 = [0, 1].map((c) => (a11 * r2[c] - a12 * r1[c]) / det);
  return [p0, p1, p2, p3].map((p) => p.map((v) => Math.round(v * 1000) / 1000));
}

function bezier(controls, count) {  // de Casteljau at t = 0 .. 1
  const out = [];
  for (let k = 0; k <= count; k++) {
    const t = k / count;
    let curve = controls.map((p) => p.slice());
    while (curve.length > 1) curve = curve.slice(1).map((p, i) => [(1 - t) * curve[i][0] + t * p[0], (1 - t) * curve[i][1] + t * p[1]]);
    out.push(curve[0]);
  }
  return out;
}

function endOf(action) { return action.kind === "path" ? action.points[action.points.length - 1] : action.at; }

function programEnd(before) {  // where the character is after the actions before index `before`
  for (let i = Math.min(before, state.actions.length) - 1; i >= 0; i--) {
    if (state.actions[i].kind === "path") return endOf(state.actions[i]).slice();
  }
  return [0, 0];
}

function clampSeconds(seconds) {
  const m = state.model;
  const frames = Math.min(Math.max(Math.round(seconds * m.fps), 1), m.max_frames);
  return Math.round(frames / m.fps * 10) / 10 || Math.round(frames / m.fps * 100) / 100;
}

function defaultTag(root) {
  const m = state.model;
  const index = m.root_tags.findIndex((r) => r === root);
  return m.tags[index < 0 ? 0 : index];
}

// ---------------------------------------------------------------- the program

function addPath(points) {
  state.actions.push({kind: "path", points, tags: [defaultTag(true)], seconds: clampSeconds(pathLength(points) / WALKING_SPEED)});
  state.selected = state.actions.length - 1;
}

function addInPlace() {
  const after = state.selected >= 0 ? state.selected + 1 : state.actions.length;
  const at = after > 0 ? endOf(state.actions[after - 1]).slice() : [0, 0];
  state.actions.splice(after, 0, {kind: "point", at, tags: [defaultTag(false)], seconds: clampSeconds(2)});
  state.selected = after;
  refresh();
}

function splitAt(index, point) {  // the path action `index` in two at the drawn point nearest `point`
  const action = state.actions[index];
  let best = {d: Infinity};
  for (let i = 1; i < action.points.length; i++) {
    const a = action.points[i - 1], b = action.points[i];
    const dx = b[0] - a[0], dz = b[1] - a[1];
    const u = Math.min(Math.max(((point[0] - a[0]) * dx + (point[1] - a[1]) * dz) / (dx * dx + dz * dz || 1), 0.05), 0.95);
    const q = [a[0] + u * dx, a[1] + u * dz];
    const d = Math.hypot(q[0] - point[0], q[1] - point[1]);
    if (d < best.d) best = {d, i, q};
  }
  const first = action.points.slice(0, best.i).concat([best.q]);
  const second = [best.q].concat(action.points.slice(best.i));
  const share = pathLength(first) / (pathLength(first) + pathLength(second));
  state.actions.splice(index, 1,
    {...action, points: first, seconds: clampSeconds(action.seconds * share)},
    {...action, points: second, tags: action.tags.slice(), seconds: clampSeconds(action.seconds * (1 - share))});
  state.selected = index + 1;
}

function requestBody() {
  return {
    actions: state.actions.map((a) => {
      const out = {tags: a.tags.filter((t) => t), seconds: a.seconds};
      if (a.kind === "path") out.path = bezierControls(a.points);
      return out;
    }),
    shadow: $("shadow").value,
    smoothing: Number($("smoothing").value),
    seed: Number($("seed").value),
    orientation: $("orientation").checked,
  };
}

// ---------------------------------------------------------------- the ground (top view: x right, z up the page)

const ground = {canvas: $("ground"), scale: 40};

function groundExtent() {
  let extent = 5;
  state.actions.forEach((a) => (a.kind === "path" ? a.points : [a.at]).forEach((p) => {
    extent = Math.max(extent, Math.abs(p[0]) + 1, Math.abs(p[1]) + 1);
  }));
  return extent;
}

function toScreen(p) { return [ground.canvas.width / 2 + p[0] * ground.scale, ground.canvas.height / 2 - p[1] * ground.scale]; }
function toGround(x, y) { return [(x - ground.canvas.width / 2) / ground.scale, (ground.canvas.height / 2 - y) / ground.scale]; }

function drawGround() {
  const c = ground.canvas, g = c.getContext("2d");
  ground.scale = Math.min(c.width, c.height) / (2 * groundExtent());
  g.clearRect(0, 0, c.width, c.height);
  g.strokeStyle = "#e2e2dc"; g.lineWidth = 1;
  const extent = Math.ceil(groundExtent());
  for (let v = -extent; v <= extent; v++) {
    let [x0, y0] = toScreen([v, -extent]), [x1, y1] = toScreen([v, extent]);
    g.beginPath(); g.moveTo(x0, y0); g.lineTo(x1, y1); g.stroke();
    [x0, y0] = toScreen([-extent, v]); [x1, y1] = toScreen([extent, v]);
    g.beginPath(); g.moveTo(x0, y0); g.lineTo(x1, y1); g.stroke();
  }
  const [ox, oy] = toScreen([0, 0]);  // the start: over the origin, facing +z
  g.fillStyle = "#333"; g.beginPath(); g.moveTo(ox, oy - 12); g.lineTo(ox - 6, oy + 4); g.lineTo(ox + 6, oy + 4); g.fill();
  state.actions.forEach((a, i) => {
    const colour = COLOURS[i % COLOURS.length], selected = i === state.selected;
    g.strokeStyle = colour; g.fillStyle = colour; g.lineWidth = selected ? 4 : 2.5;
    let label;
    if (a.kind === "path") {
      const curve = bezier(bezierControls(a.points), 40).map(toScreen);
      g.beginPath(); curve.forEach(([x, y], k) => (k ? g.lineTo(x, y) : g.moveTo(x, y))); g.stroke();
      a.points.forEach((p) => { const [x, y] = toScreen(p); g.fillRect(x - 1.5, y - 1.5, 3, 3); });
      label = curve[Math.floor(curve.length / 2)];
    } else {
      const [x, y] = toScreen(a.at);
      const ring = 9 + 5 * state.actions.slice(0, i).filter((b) => b.kind === "point" && b.at[0] === a.at[0] && b.at[1] === a.at[1]).length;
      g.beginPath(); g.arc(x, y, ring, 0, 2 * Math.PI); g.stroke();
      label = [x + ring, y - ring];
    }
    g.font = "12px system-ui"; g.fillStyle = "#222";
    g.fillText(`${i + 1}. ${a.tags.filter((t) => t).join(" + ")}`, label[0] + 6, label[1] - 4);
  });
  if (state.drawing) {
    g.strokeStyle = "#444"; g.setLineDash([5, 4]); g.lineWidth = 2;
    g.beginPath(); state.drawing.map(toScreen).forEach(([x, y], k) => (k ? g.lineTo(x, y) : g.moveTo(x, y))); g.stroke();
    g.setLineDash([]);
  }
}

function nearestAction(point) {  // the action drawn nearest a ground point (within 12 px)
  let best = {d: 12 / ground.scale, index: -1};
  state.actions.forEach((a, i) => {
    const pts = a.kind === "path" ? bezier(bezierControls(a.points), 40) : [a.at];
    pts.forEach((p) => { const d = Math.hypot(p[0] - point[0], p[1] - point[1]); if (d < best.d) best = {d, index: i}; });
  });
  return best.index;
}

function groundPoint(event) {
  const rect = ground.canvas.getBoundingClientRect();
  const sx = ground.canvas.width / rect.width, sy = ground.canvas.height / rect.height;
  return toGround((event.clientX - rect.left) * sx, (event.clientY - rect.top) * sy).map((v) => Math.round(v * 100) / 100);
}

ground.canvas.addEventListener("mousedown", (event) => {
  const p = groundPoint(event);
  if (state.mode === "draw") {
    if (!state.drawing) state.drawing = [programEnd(state.actions.length)];
    state.drawing.push(p);
    state.dragging = true;
    $("finish").disabled = false;
  } else if (state.mode === "split") {
    const index = nearestAction(p);
    if (index >= 0 && state.actions[index].kind === "path") { splitAt(index, p); setMode("idle"); }
    else setHint("Click on a path to split it.");
  } else {
    state.selected = nearestAction(p);
  }
  refresh();
});
ground.canvas.addEventListener("mousemove", (event) => {
  if (!state.dragging || !state.drawing) return;
  const p = groundPoint(event), last = state.drawing[state.drawing.length - 1];
  if (Math.hypot(p[0] - last[0], p[1] - last[1]) > 0.15) { state.drawing.push(p); drawGround(); }
});
window.addEventListener("mouseup", () => { state.dragging = false; });
ground.canvas.addEventListener("dblclick", () => finishPath());

function finishPath() {
  if (state.drawing && state.drawing.length >= 2) addPath(state.drawing);
  state.drawing = null;
  setMode("idle");
  refresh();
}

function setMode(mode) {
  if (state.mode === "draw" && mode !== "draw" && state.drawing) { const d = state.drawing; state.drawing = null; if (d.length >= 2) addPath(d); }
  state.mode = mode;
  $("draw").classList.toggle("active", mode === "draw");
  $("split").classList.toggle("active", mode === "split");
  $("finish").disabled = mode !== "draw";
  setHint({draw: "Click or drag on the ground to draw; double-click or \"Finish the path\" ends it.",
           split: "Click a path where it should split into two actions.",
           idle: "Click an action to select it; set its tags and duration in the list."}[mode]);
}

function setHint(text) { $("hint").textContent = text; }

// ---------------------------------------------------------------- the list of actions

function tagSelect(value, optional) {
  const select = document.createElement("select");
  if (optional) select.add(new Option("(no second tag)", ""));
  state.model.tags.forEach((t, i) => select.add(new Option(state.model.root_tags[i] ? `${t} (moves)` : t, t)));
  select.value = value || "";
  return select;
}

function renderActions() {
  const body = $("actions").querySelector("tbody");
  body.replaceChildren();
  state.actions.forEach((a, i) => {
    const row = body.insertRow();
    row.className = i === state.selected ? "selected" : "";
    row.dataset.index = i;
    row.addEventListener("click", () => { state.selected = i; drawGround(); markSelected(); });
    row.insertCell().innerHTML = `<span class="swatch" style="background:${COLOURS[i % COLOURS.length]}"></span> ${i + 1}`;
    row.insertCell().textContent = a.kind === "path" ? `path ${pathLength(a.points).toFixed(1)} m` : "in place";
    const tags = row.insertCell();
    [0, 1].forEach((k) => {
      const select = tagSelect(a.tags[k], k === 1);
      select.className = k ? "tag2" : "tag";
      select.addEventListener("change", () => { a.tags[k] = select.value; a.tags = a.tags.filter((t, j) => t || j === 0); drawGround(); });
      tags.appendChild(select);
    });
    const seconds = document.createElement("input");
    Object.assign(seconds, {type: "number", min: 0.1, step: 0.1, value: a.seconds, className: "seconds"});
    seconds.addEventListener("change", () => { a.seconds = Number(seconds.value); });
    row.insertCell().appendChild(seconds);
    const buttons = row.insertCell();
    [["↑", -1], ["↓", 1]].forEach(([text, step]) => {
      const b = document.createElement("button");
      b.textContent = text; b.title = step < 0 ? "earlier" : "later";
      b.disabled = i + step < 0 || i + step >= state.actions.length;
      b.addEventListener("click", (e) => { e.stopPropagation(); move(i, i + step); });
      buttons.appendChild(b);
    });
    const remove = document.createElement("button");
    remove.textContent = "✕"; remove.title = "delete"; remove.className = "delete";
    remove.addEventListener("click", (e) => { e.stopPropagation(); state.actions.splice(i, 1); state.selected = -1; refresh(); });
    buttons.appendChild(remove);
  });
}

function markSelected() {
  $("actions").querySelectorAll("tbody tr").forEach((row) => row.classList.toggle("selected", Number(row.dataset.index) === state.selected));
}

function move(from, to) {
  const [action] = state.actions.splice(from, 1);
  state.actions.splice(to, 0, action);
  state.selected = to;
  refresh();
}

function refresh() { renderActions(); drawGround(); }

// ---------------------------------------------------------------- generating

function setStatus(text, error) {
  $("status").textContent = text;
  $("status").classList.toggle("error", Boolean(error));
}

async function generate() {
  if (state.drawing) finishPath();
  $("warnings").replaceChildren();
  setStatus("Generating…");
  $("generate").disabled = true;
  $("player").dataset.state = "generating";
  try {
    const response = await fetch("/api/generate", {method: "POST", headers: {"Content-Type": "application/json"},
                                                    body: JSON.stringify(requestBody())});
    if (!response.ok) {
      const answer = await response.json().catch(() => ({error: response.statusText}));
      throw new Error(answer.error);
    }
    const reader = response.body.getReader(), decoder = new TextDecoder();
    let buffer = "", motion = null;
    for (;;) {
      const {value, done} = await reader.read();
      if (value) buffer += decoder.decode(value, {stream: true});
      let newline;
      while ((newline = buffer.indexOf("\n")) >= 0) {
        const event = JSON.parse(buffer.slice(0, newline));
        buffer = buffer.slice(newline + 1);
        if (event.event === "queued") setStatus("Waiting for another request to finish…");
        else if (event.event === "warning") { const li = document.createElement("li"); li.textContent = event.message; $("warnings").appendChild(li); }
        else if (event.event === "action") setStatus(`Generated action ${event.index + 1} of ${event.of}` + (event.revised ? " (revised)" : ""));
        else if (event.event === "error") throw new Error(event.message);
        else if (event.event === "done") motion = event.motion;
      }
      if (done) break;
    }
    if (!motion) throw new Error("the server closed the stream before the motion came");
    show(motion);
    const revised = motion.segments.map((s, i) => (s.revised ? i + 1 : 0)).filter((i) => i);
    const turned = motion.segments.map((s, i) => (s.turned ? `${i + 1} by ${s.turned}°` : "")).filter((t) => t);
    setStatus(`${motion.frames} frames, ${motion.segments.length} actions` +
              (revised.length ? `; Action Revision regenerated action ${revised.join(", ")}` : "; no action revised") +
              (turned.length ? `; the orientation check turned the start of action ${turned.join(", ")}` : ""));
  } catch (error) {
    setStatus(error.message, true);
    $("player").dataset.state = state.motion ? "paused" : "empty";
  } finally {
    $("generate").disabled = false;
  }
}

// ---------------------------------------------------------------- the 3D view

const view = {canvas: $("view"), drag: null};

function show(motion) {
  state.motion = motion;
  state.frame = 0;
  const J = motion.joint_count, xs = [], zs = [];
  for (let f = 0; f < motion.frames; f++) { xs.push(motion.joints[f * J * 3]); zs.push(motion.joints[f * J * 3 + 2]); }
  const [x0, x1, z0, z1] = [Math.min(...xs), Math.max(...xs), Math.min(...zs), Math.max(...zs)];
  state.camera.target = [(x0 + x1) / 2, 0.8, (z0 + z1) / 2];
  state.camera.distance = Math.max(4.5, 1.3 * Math.max(x1 - x0, z1 - z0) + 3);
  $("scrub").max = motion.frames - 1; $("scrub").disabled = false; $("play").disabled = false;
  $("downloads").replaceChildren(...Object.entries(motion.downloads).map(([name, href]) => {
    const a = document.createElement("a");
    Object.assign(a, {href, download: name, textContent: `Download ${name}`});
    return a;
  }));
  play(true);
}

function project(p) {
  const c = state.camera, w = view.canvas.width, h = view.canvas.height;
  const x = p[0] - c.target[0], y = p[1] - c.target[1], z = p[2] - c.target[2];
  const cy = Math.cos(c.yaw), sy = Math.sin(c.yaw), cp = Math.cos(c.pitch), sp = Math.sin(c.pitch);
  const x1 = cy * x - sy * z, z1 = sy * x + cy * z;
  const y2 = cp * y - sp * z1, z2 = sp * y + cp * z1;
  const depth = c.distance - z2;
  if (depth < 0.1) return null;
  const f = 1.2 * h;
  return [w / 2 + f * x1 / depth, h / 2 - f * y2 / depth, depth];
}

function line3d(g, a, b, pieces = 1) {  // a polyline of `pieces`, skipping what is behind the camera
  let previous = project(a);
  for (let k = 1; k <= pieces; k++) {
    const t = k / pieces, point = project([0, 1, 2].map((c) => a[c] + t * (b[c] - a[c])));
    if (previous && point) { g.beginPath(); g.moveTo(...previous); g.lineTo(...point); g.stroke(); }
    previous = point;
  }
}

function segmentOf(frame) {
  const segments = state.motion.segments;
  const index = segments.findIndex((s) => frame >= s.start && frame < s.end);
  return index < 0 ? segments.length - 1 : index;
}

function drawView() {
  const c = view.canvas, g = c.getContext("2d");
  g.clearRect(0, 0, c.width, c.height);
  const t = state.camera.target, reach = Math.ceil(state.camera.distance);
  g.strokeStyle = "#c9cfd6"; g.lineWidth = 1;
  for (let v = -reach; v <= reach; v++) {
    const x = Math.round(t[0]) + v, z = Math.round(t[2]) + v;
    line3d(g, [x, 0, t[2] - reach], [x, 0, t[2] + reach], 8);
    line3d(g, [t[0] - reach, 0, z], [t[0] + reach, 0, z], 8);
  }
  const m = state.motion;
  if (!m) return;
  const J = m.joint_count, joint = (f, j) => m.joints.slice((f * J + j) * 3, (f * J + j) * 3 + 3);
  (m.controls || []).forEach((controls, i) => {  // the drawn paths
    if (!controls) return;
    g.strokeStyle = COLOURS[i % COLOURS.length]; g.lineWidth = 2; g.setLineDash([6, 5]);
    const curve = bezier(controls, 30);
    for (let k = 1; k < curve.length; k++) line3d(g, [curve[k - 1][0], 0, curve[k - 1][1]], [curve[k][0], 0, curve[k][1]]);
    g.setLineDash([]);
  });
  g.lineWidth = 1.5;  // the root's path on the ground, coloured by action
  for (let f = 1; f < m.frames; f++) {
    g.strokeStyle = COLOURS[segmentOf(f) % COLOURS.length];
    const a = joint(f - 1, 0), b = joint(f, 0);
    line3d(g, [a[0], 0, a[2]], [b[0], 0, b[2]]);
  }
  const f = Math.min(Math.floor(state.frame), m.frames - 1), colour = COLOURS[segmentOf(f) % COLOURS.length];
  const parents = state.model.parents;
  g.strokeStyle = "rgba(0, 0, 0, 0.18)"; g.lineWidth = 4;  // its shadow
  for (let j = 1; j < J; j++) { const a = joint(f, j), b = joint(f, parents[j]); line3d(g, [a[0], 0, a[2]], [b[0], 0, b[2]]); }
  if (state.body && m.skin && $("mesh").checked) {
    drawMesh(g, f, colour);
  } else {
    g.strokeStyle = colour; g.lineWidth = 5; g.lineCap = "round";
    for (let j = 1; j < J; j++) line3d(g, joint(f, j), joint(f, parents[j]));
    g.fillStyle = "#222";
    for (let j = 0; j < J; j++) { const p = project(joint(f, j)); if (p) { g.beginPath(); g.arc(p[0], p[1], 2.5, 0, 2 * Math.PI); g.fill(); } }
  }
  const s = m.segments[segmentOf(f)];
  g.font = "14px system-ui"; g.fillStyle = "#222";
  g.fillText(`frame ${f + 1} / ${m.frames}   ${(f / m.fps).toFixed(2)} s   ${s.tags.join(" + ")}`, 10, 20);
}

// The body model's mesh at frame f: linear blend skinning of the rest vertices with the frame's per-joint transforms
// (the server's, 12 numbers a joint), then the triangles far to near, flat shaded.
function drawMesh(g, f, colour) {
  const b = state.body, skin = state.motion.skin, base = f * 24 * 12, count = b.rest.length / 3;
  const points = new Array(count), world = new Float32Array(count * 3);
  for (let v = 0; v < count; v++) {
    const x = b.rest[3 * v], y = b.rest[3 * v + 1], z = b.rest[3 * v + 2];
    let px = 0, py = 0, pz = 0;
    for (let k = 0; k < 4; k++) {
      const w = b.weights[4 * v + k];
      if (!w) continue;
      const o = base + 12 * b.joints[4 * v + k];
      px += w * (skin[o] * x + skin[o + 1] * y + skin[o + 2] * z + skin[o + 9]);
      py += w * (skin[o + 3] * x + skin[o + 4] * y + skin[o + 5] * z + skin[o + 10]);
      pz += w * (skin[o + 6] * x + skin[o + 7] * y + skin[o + 8] * z + skin[o + 11]);
    }
    world[3 * v] = px; world[3 * v + 1] = py; world[3 * v + 2] = pz;
    points[v] = project([px, py, pz]);
  }
  const faces = [];
  for (let i = 0; i < b.faces.length; i += 3) {
    const [p, q, r] = [points[b.faces[i]], points[b.faces[i + 1]], points[b.faces[i + 2]]];
    if (p && q && r) faces.push([i, p[2] + q[2] + r[2]]);
  }
  faces.sort((u, v) => v[1] - u[1]);
  const rgb = [1, 3, 5].map((k) => parseInt(colour.slice(k, k + 2), 16));
  const light = [0.32, 0.85, 0.42];
  for (const [i] of faces) {
    const [a, c, d] = [b.faces[i], b.faces[i + 1], b.faces[i + 2]].map((v) => [world[3 * v], world[3 * v + 1], world[3 * v + 2]]);
    const e1 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]], e2 = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
    const n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
    const shade = 0.45 + 0.55 * Math.abs(n[0] * light[0] + n[1] * light[1] + n[2] * light[2]) / (Math.hypot(...n) || 1);
    g.fillStyle = `rgb(${rgb.map((v) => Math.round(v * shade)).join(",")})`;
    const [p, q, r] = [points[b.faces[i]], points[b.faces[i + 1]], points[b.faces[i + 2]]];
    g.beginPath(); g.moveTo(p[0], p[1]); g.lineTo(q[0], q[1]); g.lineTo(r[0], r[1]); g.closePath(); g.fill();
  }
}

function drawTimeline() {
  const c = $("timeline"), g = c.getContext("2d"), m = state.motion;
  g.clearRect(0, 0, c.width, c.height);
  if (!m) return;
  const scale = c.width / m.frames;
  m.segments.forEach((s, i) => {
    g.fillStyle = COLOURS[i % COLOURS.length];
    g.fillRect(s.start * scale, 4, (s.end - s.start) * scale - 1, 28);
    if (s.revised) { g.strokeStyle = "#b00020"; g.lineWidth = 3; g.strokeRect(s.start * scale + 1.5, 5.5, (s.end - s.start) * scale - 4, 25); }
    g.save(); g.beginPath(); g.rect(s.start * scale, 4, (s.end - s.start) * scale - 1, 28); g.clip();
    g.fillStyle = "#fff"; g.font = "12px system-ui";
    g.fillText(s.tags.join(" + ") + (s.revised ? " (AR)" : s.shadowed ? " (SS)" : ""), s.start * scale + 4, 22);
    g.restore();
  });
  g.fillStyle = "#000";
  g.fillRect(Math.floor(state.frame) * scale, 0, 2, 36);
  g.font = "11px system-ui";
  g.fillText("AR: regenerated by Action Revision; SS: started from its shadow", 4, 45);
}

function setFrame(frame) {
  const m = state.motion;
  state.frame = Math.min(Math.max(frame, 0), m.frames - 1);
  $("scrub").value = Math.floor(state.frame);
  $("frame").textContent = `frame ${Math.floor(state.frame) + 1} / ${m.frames}`;
  drawView(); drawTimeline();
}

function play(on) {
  state.playing = on;
  $("play").textContent = on ? "Pause" : "Play";
  $("player").dataset.state = on ? "playing" : "paused";
}

let last = null;
function tick(time) {
  if (state.motion && state.playing && last !== null) {
    const next = state.frame + (time - last) / 1000 * state.motion.fps * Number($("speed").value);
    setFrame(next >= state.motion.frames ? 0 : next);
  }
  last = time;
  requestAnimationFrame(tick);
}

view.canvas.addEventListener("mousedown", (e) => { view.drag = [e.clientX, e.clientY]; });
window.addEventListener("mousemove", (e) => {
  if (!view.drag) return;
  state.camera.yaw += (e.clientX - view.drag[0]) * 0.01;
  state.camera.pitch = Math.min(Math.max(state.camera.pitch + (e.clientY - view.drag[1]) * 0.01, 0.05), 1.5);
  view.drag = [e.clientX, e.clientY];
  drawView();
});
window.addEventListener("mouseup", () => { view.drag = null; });
view.canvas.addEventListener("wheel", (e) => {
  e.preventDefault();
  state.camera.distance = Math.min(Math.max(state.camera.distance * Math.exp(e.deltaY * 0.001), 1.5), 60);
  drawView();
}, {passive: false});
$("timeline").addEventListener("mousedown", (e) => {
  if (!state.motion) return;
  const rect = e.target.getBoundingClientRect();
  play(false);
  setFrame((e.clientX - rect.left) / rect.width * state.motion.frames);
});

// ---------------------------------------------------------------- saving and loading a program

function saveProgram() {
  const program = {composer: 1, actions: state.actions,
                   settings: {shadow: $("shadow").value, smoothing: Number($("smoothing").value), seed: Number($("seed").value),
                              orientation: $("orientation").checked}};
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([JSON.stringify(program, null, 1)], {type: "application/json"}));
  a.download = "program.json";
  a.click();
  URL.revokeObjectURL(a.href);
}

function checkProgram(program) {  // a loaded file: the first thing wrong, named
  const isPoint = (p) => Array.isArray(p) && p.length === 2 && p.every(Number.isFinite);
  if (!program || !Array.isArray(program.actions)) throw new Error("expected an object with 'actions' (a file saved by this page)");
  program.actions.forEach((a, i) => {
    const where = `actions[${i}]`;
    if (!a || (a.kind !== "path" && a.kind !== "point")) throw new Error(`${where}.kind: expected "path" or "point"`);
    if (a.kind === "path" && (!Array.isArray(a.points) || a.points.length < 2 || !a.points.every(isPoint))) throw new Error(`${where}.points: expected two or more [x, z]`);
    if (a.kind === "point" && !isPoint(a.at)) throw new Error(`${where}.at: expected [x, z]`);
    if (!Array.isArray(a.tags) || !a.tags.length || !a.tags.every((t) => state.model.tags.includes(t) || (t === "")))
      throw new Error(`${where}.tags: expected tags of this model (${JSON.stringify(a.tags)})`);
    if (!Number.isFinite(a.seconds) || a.seconds <= 0) throw new Error(`${where}.seconds: expected a positive number`);
  });
}

$("load").addEventListener("change", async (e) => {
  const file = e.target.files[0];
  if (!file) return;
  try {
    const program = JSON.parse(await file.text());
    checkProgram(program);
    state.actions = program.actions;
    const s = program.settings || {};
    if (state.model.shadow_modes.includes(s.shadow)) $("shadow").value = s.shadow;
    if (Number.isInteger(s.smoothing)) $("smoothing").value = s.smoothing;
    if (Number.isInteger(s.seed)) $("seed").value = s.seed;
    if (typeof s.orientation === "boolean") $("orientation").checked = s.orientation;
    state.selected = -1;
    refresh();
    setStatus(`Loaded ${file.name}: ${state.actions.length} actions`);
  } catch (error) {
    setStatus(`${file.name}: ${error.message}`, true);
  }
  e.target.value = "";
});

// ---------------------------------------------------------------- start

$("draw").addEventListener("click", () => setMode(state.mode === "draw" ? "idle" : "draw"));
$("finish").addEventListener("click", finishPath);
$("split").addEventListener("click", () => setMode(state.mode === "split" ? "idle" : "split"));
$("in-place").addEventListener("click", addInPlace);
$("clear").addEventListener("click", () => { state.actions = []; state.drawing = null; state.selected = -1; setMode("idle"); refresh(); });
$("generate").addEventListener("click", generate);
$("save").addEventListener("click", saveProgram);
$("play").addEventListener("click", () => play(!state.playing));
$("scrub").addEventListener("input", () => { play(false); setFrame(Number($("scrub").value)); });
$("mesh").addEventListener("change", () => drawView());

fetch("/api/model").then((r) => r.json()).then((model) => {
  state.model = model;
  $("model-info").textContent = `${model.method}: ${model.tags.length} tags, ${model.fps} fps, actions up to ${(model.max_frames / model.fps).toFixed(1)} s`;
  const names = {revision: "Neural Marionette (Shadow Start on Action Revision)", always: "Shadow Start always", never: "pure pipeline"};
  model.shadow_modes.forEach((m) => $("shadow").add(new Option(names[m], m)));
  if (model.body) {
    $("mesh-choice").hidden = false;
    fetch("/api/body").then((r) => r.json()).then((body) => {
      state.body = {rest: body.vertices, faces: body.faces, joints: body.joints, weights: body.weights};
      drawView();
    });
  }
  $("smoothing").value = model.defaults.smoothing;
  refresh();
  drawView();
  document.body.dataset.ready = "true";
  requestAnimationFrame(tick);
}).catch((error) => setStatus(`Could not load the model: ${error.message}`, true));
