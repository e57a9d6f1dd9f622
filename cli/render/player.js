// rustycs player: draws an embedded trajectory on a canvas. No network, no libraries.
// window.player exposes the state (frame, playing, speed, overlay toggles, camera) for scripts and tests.
// Sensors light up while something is inside (sensorLit, from the run's sensor events); the scrub bar
// carries a mark per frame where events happened, coloured by kind (eventMarks, with a legend). Bodies
// asleep in a frame (world.sleep) are filled paler (asleepColors: their colour halfway to the background).
"use strict";
(() => {
  const header = JSON.parse(document.getElementById("rustycs-header").textContent);

  function decode(name, Type) {
    const element = document.getElementById("rustycs-" + name);
    if (!element) return null;
    const text = atob(element.textContent.trim());
    const bytes = new Uint8Array(text.length);
    for (let i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
    return new Type(bytes.buffer);
  }

  const position = decode("position", Float32Array);
  const angle = decode("angle", Float32Array);
  const velocity = decode("velocity", Float32Array);
  const angularVelocity = decode("angularVelocity", Float32Array);
  const active = decode("active", Uint8Array);
  const asleep = decode("asleep", Uint8Array); // [F, N]: 1 while the body sleeps
  const contactOffset = decode("contactOffset", Int32Array);
  const contactPoint = decode("contactPoint", Float32Array);
  const contactNormal = decode("contactNormal", Float32Array);
  const jointActive = decode("jointActive", Uint8Array);
  const sensorLit = decode("sensorLit", Uint8Array); // [F, K]: 1 while something is inside sensor body k

  const bodies = header.bodies;
  const N = bodies.names.length;
  const joints = header.joints;
  const J = joints.types.length;
  const F = header.steps.length;
  const times = header.times;
  const K = header.sensorBodies.length;
  const sensorColumn = new Int32Array(N).fill(-1); // a body's column in sensorLit, -1: no sensor shape
  header.sensorBodies.forEach((body, k) => { sensorColumn[body] = k; });
  const lit = (f, i) => sensorColumn[i] >= 0 && sensorLit[f * K + sensorColumn[i]] === 1;
  const COLORS = { grid: "#e4e4e4", axes: "#b4b4b4", text: "#1e1e1e", hitbox: "#0079f1", contact: "#0079f1",
    velocity: "#c800c8", attractor: "#e6a000", bounds: "#e67878", spoke: "#ffffff", hover: "#ff8c00" };

  // Per-shape constants (body frame, about the body origin): "area" outlines in counter-clockwise
  // order, so that overlapping fills of one colour never cancel out; each body's shape rows
  // (consecutive), how far it reaches from its origin (for culling and hit tests), the draw order
  // (statics first).
  const shapes = header.shapes;
  const S = shapes.body.length;
  const local = shapes.points.map((flat, s) => {
    if (shapes.style[s] !== "area") return flat;
    let area = 0;
    const count = flat.length / 2;
    for (let k = 0; k < count; k++) {
      const j = (k + 1) % count;
      area += flat[2 * k] * flat[2 * j + 1] - flat[2 * j] * flat[2 * k + 1];
    }
    if (area >= 0) return flat;
    const reversed = [];
    for (let k = count - 1; k >= 0; k--) reversed.push(flat[2 * k], flat[2 * k + 1]);
    return reversed;
  });
  const firstShape = new Int32Array(N + 1);
  for (let s = 0; s < S; s++) firstShape[shapes.body[s] + 1] = s + 1;
  for (let i = 1; i <= N; i++) firstShape[i] = Math.max(firstShape[i], firstShape[i - 1]);
  const reach = new Float64Array(N);
  for (let s = 0; s < S; s++) {
    const flat = local[s], i = shapes.body[s];
    for (let k = 0; k < flat.length; k += 2) {
      reach[i] = Math.max(reach[i], Math.hypot(flat[k], flat[k + 1]) + shapes.radius[s]);
    }
  }
  const isStatic = bodies.types.map((type) => type === "static");
  const order = [...Array(N).keys()].sort((a, b) => (isStatic[b] - isStatic[a]) || (a - b));
  const LINE_PICK = 4; // pixels: how close to a segment or chain the mouse picks it

  const canvas = document.getElementById("view");
  const ctx = canvas.getContext("2d");
  const stage = document.getElementById("stage");
  const label = document.getElementById("label");
  const tooltip = document.getElementById("tooltip");
  const scrub = document.getElementById("scrub");
  const playButton = document.getElementById("play");
  const speedSelect = document.getElementById("speed");
  document.getElementById("note").textContent = header.note || "";
  scrub.max = String(Math.max(F - 1, 0));

  const state = {
    frame: Math.min(Math.max(header.startFrame || 0, 0), F - 1),
    playing: false,
    speed: 1,
    hitboxes: !!header.overlays.hitboxes,
    contacts: !!header.overlays.contacts,
    velocities: !!header.overlays.velocities,
    names: !!header.overlays.names,
    joints: !!header.overlays.joints,
    scale: 1, // pixels per metre
    cx: 0, // world point at the centre of the canvas
    cy: 0,
    hover: -1, // body under the mouse
  };
  const OVERLAYS = ["hitboxes", "contacts", "velocities", "names", "joints"];
  for (const name of OVERLAYS) document.getElementById(name).checked = state[name];
  const stats = { draws: 0, lastDrawMs: 0, maxDrawMs: 0 };
  let width = 1, height = 1, dpr = 1, dirty = true, clock = 0, lastNow = null;
  let mouse = null, drag = null;

  // ---- camera ----
  const sx = (x) => (x - state.cx) * state.scale + width / 2;
  const sy = (y) => height / 2 - (y - state.cy) * state.scale;
  const wx = (px) => (px - width / 2) / state.scale + state.cx;
  const wy = (py) => state.cy - (py - height / 2) / state.scale;

  function resize() {
    const rect = canvas.getBoundingClientRect();
    dpr = window.devicePixelRatio || 1;
    width = Math.max(rect.width, 1);
    height = Math.max(rect.height, 1);
    canvas.width = Math.round(width * dpr);
    canvas.height = Math.round(height * dpr);
    dirty = true;
  }

  function fit() {
    const [x0, y0, x1, y1] = header.view;
    state.scale = Math.min(width / (x1 - x0), height / (y1 - y0));
    state.cx = (x0 + x1) / 2;
    state.cy = (y0 + y1) / 2;
    dirty = true;
  }

  function zoomAt(px, py, factor) {
    const x = wx(px), y = wy(py);
    state.scale = Math.min(Math.max(state.scale * factor, 1e-4), 1e7);
    state.cx = x - (px - width / 2) / state.scale;
    state.cy = y + (py - height / 2) / state.scale;
    dirty = true;
  }

  // ---- geometry of shape s at frame f ----
  const world = new Float64Array(local.reduce((most, flat) => Math.max(most, flat.length), 2));
  const points = new Float64Array(world.length);

  function shapeWorld(f, s) { // fills `world` with the shape's points in metres, returns their count
    const base = f * N + shapes.body[s];
    const x = position[2 * base], y = position[2 * base + 1], a = angle[base];
    const c = Math.cos(a), sn = Math.sin(a), flat = local[s];
    for (let k = 0; k < flat.length; k += 2) {
      world[k] = x + c * flat[k] - sn * flat[k + 1];
      world[k + 1] = y + sn * flat[k] + c * flat[k + 1];
    }
    return flat.length / 2;
  }

  function shapePoints(f, s) { // fills `points` with the shape's points in screen pixels
    const count = shapeWorld(f, s);
    for (let k = 0; k < 2 * count; k += 2) {
      points[k] = sx(world[k]);
      points[k + 1] = sy(world[k + 1]);
    }
    return count;
  }

  function visible(f, i) {
    const base = f * N + i;
    if (!active[base]) return false;
    const x = position[2 * base], y = position[2 * base + 1];
    if (!Number.isFinite(x) || !Number.isFinite(y)) return false;
    const px = sx(x), py = sy(y), r = reach[i] * state.scale + 2;
    return px + r >= 0 && px - r <= width && py + r >= 0 && py - r <= height;
  }

  function centerOfMass(f, i) {
    const base = f * N + i, a = angle[base], [lx, ly] = bodies.centroid[i];
    return [position[2 * base] + Math.cos(a) * lx - Math.sin(a) * ly,
      position[2 * base + 1] + Math.sin(a) * lx + Math.cos(a) * ly];
  }

  function shapeBox(f, s) { // [xmin, ymin, xmax, ymax] in pixels: the points grown by the radius
    const count = shapePoints(f, s), r = shapes.radius[s] * state.scale;
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (let k = 0; k < 2 * count; k += 2) {
      x0 = Math.min(x0, points[k]); x1 = Math.max(x1, points[k]);
      y0 = Math.min(y0, points[k + 1]); y1 = Math.max(y1, points[k + 1]);
    }
    return [x0 - r, y0 - r, x1 + r, y1 + r];
  }

  function screenBox(f, i) { // the box around all of body i's shapes, in pixels
    let box = [Infinity, Infinity, -Infinity, -Infinity];
    for (let s = firstShape[i]; s < firstShape[i + 1]; s++) {
      const [x0, y0, x1, y1] = shapeBox(f, s);
      box = [Math.min(box[0], x0), Math.min(box[1], y0), Math.max(box[2], x1), Math.max(box[3], y1)];
    }
    return box;
  }

  function addShape(path, f, s) { // a closed sub-path: disc, polygon or stadium (not lines)
    const count = shapePoints(f, s), style = shapes.style[s];
    const r = Math.max(shapes.radius[s] * state.scale, 0.5);
    if (style === "disc") {
      path.moveTo(points[0] + r, points[1]);
      path.arc(points[0], points[1], r, 0, 2 * Math.PI, true); // anticlockwise on screen = counter-clockwise in the world
    } else if (style === "stadium") { // both half circles anticlockwise on screen, joined by the sides
      const heading = Math.atan2(points[3] - points[1], points[2] - points[0]);
      path.moveTo(points[2] + r * Math.cos(heading + Math.PI / 2), points[3] + r * Math.sin(heading + Math.PI / 2));
      path.arc(points[2], points[3], r, heading + Math.PI / 2, heading - Math.PI / 2, true);
      path.arc(points[0], points[1], r, heading - Math.PI / 2, heading - 1.5 * Math.PI, true);
      path.closePath();
    } else {
      path.moveTo(points[0], points[1]);
      for (let k = 2; k < 2 * count; k += 2) path.lineTo(points[k], points[k + 1]);
      path.closePath();
    }
  }

  function addLine(path, f, s) { // a segment or chain, back to its first point when it loops
    const count = shapePoints(f, s);
    path.moveTo(points[0], points[1]);
    for (let k = 2; k < 2 * count; k += 2) path.lineTo(points[k], points[k + 1]);
    if (shapes.closed[s]) path.closePath();
  }

  function addSpoke(path, f, s) { // discs: centre to the rotated shape-local point (0, r)
    const r = shapes.radius[s] * state.scale;
    if (shapes.style[s] !== "disc" || r < 3) return;
    const base = f * N + shapes.body[s], a = angle[base], [lx, ly] = shapes.spoke[s];
    const x = position[2 * base] + Math.cos(a) * lx - Math.sin(a) * ly;
    const y = position[2 * base + 1] + Math.sin(a) * lx + Math.cos(a) * ly;
    shapePoints(f, s);
    path.moveTo(points[0], points[1]);
    path.lineTo(sx(x), sy(y));
  }

  function addBody(path, f, i) { // every shape of body i, lines included (for the hover outline)
    for (let s = firstShape[i]; s < firstShape[i + 1]; s++) {
      if (shapes.style[s] === "line") addLine(path, f, s); else addShape(path, f, s);
    }
  }

  // ---- drawing ----
  function gridSpacing(scale) { // as rustycs_cli.render.view.grid_spacing
    const minPixels = 24, maxPixels = 240;
    if (scale >= minPixels && scale <= maxPixels) return 1;
    const target = scale < minPixels ? minPixels / scale : (2 * minPixels) / scale;
    const power = 10 ** Math.floor(Math.log10(target));
    for (const m of [1, 2, 5, 10]) if (m * power >= target * (1 - 1e-9)) return m * power;
    return 10 * power;
  }

  function drawGrid() {
    const spacing = gridSpacing(state.scale);
    const x0 = wx(0), x1 = wx(width), y0 = wy(height), y1 = wy(0);
    const lines = new Path2D(), axes = new Path2D();
    for (let k = Math.ceil(x0 / spacing); k <= Math.floor(x1 / spacing); k++) {
      const px = Math.round(sx(k * spacing)) + 0.5;
      (k === 0 ? axes : lines).moveTo(px, 0);
      (k === 0 ? axes : lines).lineTo(px, height);
    }
    for (let k = Math.ceil(y0 / spacing); k <= Math.floor(y1 / spacing); k++) {
      const py = Math.round(sy(k * spacing)) + 0.5;
      (k === 0 ? axes : lines).moveTo(0, py);
      (k === 0 ? axes : lines).lineTo(width, py);
    }
    ctx.lineWidth = 1;
    ctx.strokeStyle = COLORS.grid;
    ctx.stroke(lines);
    ctx.strokeStyle = COLORS.axes;
    ctx.stroke(axes);
    const every = Math.max(1, Math.ceil(64 / (spacing * state.scale))), step = spacing * every;
    const decimals = Math.max(0, -Math.floor(Math.log10(step)));
    const text = (v) => (Math.abs(v) < step / 2 ? "0" : v.toFixed(decimals));
    ctx.fillStyle = COLORS.axes;
    ctx.font = "10px sans-serif";
    ctx.textAlign = "left";
    ctx.textBaseline = "bottom";
    for (let k = Math.ceil(x0 / step); k <= Math.floor(x1 / step); k++) {
      ctx.fillText(text(k * step), sx(k * step) + 2, height - 3);
    }
    for (let k = Math.ceil(y0 / step); k <= Math.floor(y1 / step); k++) {
      if (sy(k * step) > 34) ctx.fillText(text(k * step), 3, sy(k * step) - 2);
    }
  }

  function drawWorld() {
    if (header.bounds) {
      const [x0, y0, x1, y1] = header.bounds;
      ctx.strokeStyle = COLORS.bounds;
      ctx.lineWidth = 1;
      ctx.strokeRect(sx(x0), sy(y1), (x1 - x0) * state.scale, (y1 - y0) * state.scale);
    }
    for (const attractor of header.attractors) {
      const px = sx(attractor.x), py = sy(attractor.y);
      ctx.lineWidth = 1;
      if (attractor.range !== null) {
        ctx.strokeStyle = COLORS.attractor;
        ctx.beginPath();
        ctx.arc(px, py, attractor.range * state.scale, 0, 2 * Math.PI);
        ctx.stroke();
      }
      ctx.fillStyle = COLORS.attractor;
      ctx.strokeStyle = COLORS.text;
      ctx.beginPath();
      ctx.arc(px, py, 5, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
    }
  }

  function drawBodies(f, shown) {
    const fills = new Map(), outlines = new Map(), lines = new Map(), sensorFills = new Map();
    const litFills = new Map(), sensorLines = new Map(), spokes = new Path2D(), kinematic = new Path2D();
    const pathFor = (map, color) => map.get(color) || map.set(color, new Path2D()).get(color);
    for (const i of shown) {
      for (let s = firstShape[i]; s < firstShape[i + 1]; s++) {
        const color = shapes.colors[s], style = shapes.style[s];
        if (shapes.sensor[s]) {
          if (style === "line") addLine(pathFor(sensorLines, color), f, s);
          else {
            addShape(pathFor(lit(f, i) ? litFills : sensorFills, color), f, s);
            addShape(pathFor(sensorLines, color), f, s);
          }
        } else if (style === "line") {
          addLine(pathFor(lines, color), f, s);
        } else if (isStatic[i]) {
          const path = pathFor(outlines, color);
          addShape(path, f, s);
          addSpoke(path, f, s);
        } else {
          addShape(pathFor(fills, asleep[f * N + i] ? shapes.asleepColors[s] : color), f, s);
          addSpoke(spokes, f, s);
          if (bodies.types[i] === "kinematic") addShape(kinematic, f, s);
        }
      }
    }
    ctx.lineWidth = 2;
    for (const [color, path] of outlines) { ctx.strokeStyle = color; ctx.stroke(path); }
    for (const [color, path] of lines) { ctx.strokeStyle = color; ctx.stroke(path); }
    for (const [color, path] of fills) { ctx.fillStyle = color; ctx.fill(path); }
    ctx.lineWidth = 1;
    ctx.strokeStyle = COLORS.text;
    ctx.stroke(kinematic);
    ctx.strokeStyle = COLORS.spoke;
    ctx.stroke(spokes);
    // sensors: a faint fill and a dashed outline over everything, the fill bright while something is inside
    ctx.globalAlpha = 0.25;
    for (const [color, path] of sensorFills) { ctx.fillStyle = color; ctx.fill(path); }
    ctx.globalAlpha = 0.6;
    for (const [color, path] of litFills) { ctx.fillStyle = color; ctx.fill(path); }
    ctx.globalAlpha = 0.7;
    ctx.setLineDash([5, 4]);
    ctx.lineWidth = 1.5;
    for (const [color, path] of sensorLines) { ctx.strokeStyle = color; ctx.stroke(path); }
    ctx.setLineDash([]);
    ctx.globalAlpha = 1;
  }

  function anchorWorld(f, body, local) { // an anchor in its body's frame, in metres (-1: a world point)
    if (body < 0) return local;
    const base = f * N + body, c = Math.cos(angle[base]), s = Math.sin(angle[base]);
    return [position[2 * base] + c * local[0] - s * local[1], position[2 * base + 1] + s * local[0] + c * local[1]];
  }

  function drawJoints(f) { // as rustycs_cli.render.joints.joint_lines: gears and broken joints are not drawn
    if (!state.joints || J === 0) return;
    const lines = new Path2D(), rings = new Path2D(), teeth = 2 * joints.zigzag.teeth;
    for (let j = 0; j < J; j++) {
      if (joints.types[j] === "gear" || !jointActive[f * J + j]) continue;
      const a = anchorWorld(f, joints.bodyA[j], joints.anchorA[j]);
      const b = anchorWorld(f, joints.bodyB[j], joints.anchorB[j]);
      lines.moveTo(sx(a[0]), sy(a[1]));
      if (joints.types[j] === "pulley") {
        for (const [x, y] of joints.ground[j]) lines.lineTo(sx(x), sy(y));
      } else if (joints.spring[j]) { // teeth across the line between the anchors
        const dx = b[0] - a[0], dy = b[1] - a[1], w = joints.zigzag.width;
        for (let k = 0; k < teeth; k++) {
          const t = (k + 0.5) / teeth, side = k % 2 === 0 ? w : -w;
          lines.lineTo(sx(a[0] + t * dx - side * dy), sy(a[1] + t * dy + side * dx));
        }
      }
      lines.lineTo(sx(b[0]), sy(b[1]));
      for (const [x, y] of [a, b]) {
        rings.moveTo(sx(x) + 3, sy(y));
        rings.arc(sx(x), sy(y), 3, 0, 2 * Math.PI);
      }
    }
    ctx.strokeStyle = joints.color;
    ctx.lineWidth = 1.5;
    ctx.stroke(lines);
    ctx.lineWidth = 1;
    ctx.stroke(rings);
  }

  function drawOverlays(f, shown) {
    if (state.hitboxes) {
      const path = new Path2D();
      for (const i of shown) {
        for (let s = firstShape[i]; s < firstShape[i + 1]; s++) {
          const [x0, y0, x1, y1] = shapeBox(f, s);
          path.rect(x0, y0, x1 - x0, y1 - y0);
        }
      }
      ctx.lineWidth = 1;
      ctx.strokeStyle = COLORS.hitbox;
      ctx.stroke(path);
    }
    if (state.contacts && contactOffset) {
      const dots = new Path2D(), normals = new Path2D();
      for (let row = contactOffset[f]; row < contactOffset[f + 1]; row++) {
        const px = sx(contactPoint[2 * row]), py = sy(contactPoint[2 * row + 1]);
        normals.moveTo(px, py);
        normals.lineTo(px + 14 * contactNormal[2 * row], py - 14 * contactNormal[2 * row + 1]);
        dots.moveTo(px + 3, py);
        dots.arc(px, py, 3, 0, 2 * Math.PI);
      }
      ctx.lineWidth = 1;
      ctx.strokeStyle = COLORS.contact;
      ctx.stroke(normals);
      ctx.fillStyle = COLORS.contact;
      ctx.fill(dots);
    }
    if (state.velocities) {
      const arrows = new Path2D(), seconds = header.velocitySeconds;
      for (const i of shown) {
        if (isStatic[i]) continue;
        const base = f * N + i, [x, y] = centerOfMass(f, i);
        const x0 = sx(x), y0 = sy(y);
        const x1 = sx(x + velocity[2 * base] * seconds), y1 = sy(y + velocity[2 * base + 1] * seconds);
        const length = Math.hypot(x1 - x0, y1 - y0);
        if (!(length >= 2)) continue;
        const ux = (x1 - x0) / length, uy = (y1 - y0) / length;
        arrows.moveTo(x0, y0);
        arrows.lineTo(x1, y1);
        arrows.moveTo(x1 - 6 * (ux + 0.5 * uy), y1 - 6 * (uy - 0.5 * ux));
        arrows.lineTo(x1, y1);
        arrows.lineTo(x1 - 6 * (ux - 0.5 * uy), y1 - 6 * (uy + 0.5 * ux));
      }
      ctx.lineWidth = 1.5;
      ctx.strokeStyle = COLORS.velocity;
      ctx.stroke(arrows);
    }
    if (state.names) {
      ctx.fillStyle = COLORS.text;
      ctx.font = "11px sans-serif";
      ctx.textAlign = "center";
      ctx.textBaseline = "bottom";
      for (const i of shown) { // above the body; inside it for static (outlined) bodies
        const [x0, y0, x1, y1] = screenBox(f, i);
        ctx.textBaseline = isStatic[i] ? "middle" : "bottom";
        ctx.fillText(bodies.names[i], (x0 + x1) / 2, isStatic[i] ? (y0 + y1) / 2 : y0 - 2);
      }
      ctx.textBaseline = "bottom";
      for (const attractor of header.attractors) ctx.fillText(attractor.name, sx(attractor.x), sy(attractor.y) - 7);
    }
  }

  function drawHover(f) {
    const i = state.hover;
    if (i < 0 || !active[f * N + i]) { tooltip.style.display = "none"; return; }
    const path = new Path2D();
    addBody(path, f, i);
    ctx.lineWidth = 2;
    ctx.strokeStyle = COLORS.hover;
    ctx.stroke(path);
    const base = f * N + i, num = (v) => v.toFixed(4);
    const vx = velocity[2 * base], vy = velocity[2 * base + 1];
    tooltip.textContent = `${bodies.names[i]}  (${bodies.types[i]} ${bodies.shapes[i]}, ${bodies.materials[i]})\n`
      + `position          ${num(position[2 * base])}, ${num(position[2 * base + 1])} m\n`
      + `velocity          ${num(vx)}, ${num(vy)} m/s  (|v| ${num(Math.hypot(vx, vy))})\n`
      + `angular velocity  ${num(angularVelocity[base])} rad/s${asleep[base] ? "\nasleep" : ""}`;
    tooltip.style.display = "block";
    if (mouse) {
      const left = Math.min(mouse.x + 14, width - tooltip.offsetWidth - 4);
      const top = mouse.y + 14 + tooltip.offsetHeight > height ? mouse.y - tooltip.offsetHeight - 8 : mouse.y + 14;
      tooltip.style.left = `${Math.max(left, 4)}px`;
      tooltip.style.top = `${Math.max(top, 4)}px`;
    }
  }

  function draw() {
    const started = performance.now();
    const f = state.frame;
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = "#ffffff";
    ctx.fillRect(0, 0, width, height);
    drawGrid();
    drawWorld();
    const shown = order.filter((i) => visible(f, i));
    drawBodies(f, shown);
    drawJoints(f);
    drawOverlays(f, shown);
    drawHover(f);
    const missing = state.contacts && !header.hasContacts ? "   (no contacts recorded)" : "";
    label.textContent = `tick ${header.steps[f]}   t = ${times[f].toFixed(3)} s   frame ${f + 1}/${F}${missing}`;
    scrub.value = String(f);
    playButton.innerHTML = state.playing ? "&#10074;&#10074;" : "&#9654;";
    dirty = false;
    stats.draws += 1;
    stats.lastDrawMs = performance.now() - started;
    stats.maxDrawMs = Math.max(stats.maxDrawMs, stats.lastDrawMs);
  }

  // ---- the scrub bar's event marks: a short coloured tick above the track per frame with events ----
  const marksCanvas = document.getElementById("marks");
  const THUMB = 12; // pixels: the range's thumb (player.html), whose centre spans the bar less its width
  const markNotes = new Map(); // frame -> "2 spawn, 1 sensor_enter"
  for (const mark of header.eventMarks) {
    mark.frames.forEach((frame, k) => {
      const note = `${mark.counts[k]} ${mark.kind}`;
      markNotes.set(frame, markNotes.has(frame) ? `${markNotes.get(frame)}, ${note}` : note);
    });
  }

  function markX(f) { // where frame f sits on the bar, CSS pixels from its left edge
    const barWidth = scrub.getBoundingClientRect().width;
    return THUMB / 2 + (F > 1 ? f / (F - 1) : 0) * (barWidth - THUMB);
  }

  function drawMarks() {
    const rect = marksCanvas.getBoundingClientRect();
    marksCanvas.width = Math.round(Math.max(rect.width, 1) * dpr);
    marksCanvas.height = Math.round(Math.max(rect.height, 1) * dpr);
    const marks = marksCanvas.getContext("2d");
    marks.setTransform(dpr, 0, 0, dpr, 0, 0);
    marks.clearRect(0, 0, rect.width, rect.height);
    for (const mark of header.eventMarks) {
      marks.fillStyle = mark.color;
      for (const frame of mark.frames) marks.fillRect(Math.round(markX(frame)) - 1, 0, 2, rect.height / 2 - 3);
    }
  }

  function markNear(offsetX) { // the text of the marks within 4 pixels of a point on the bar, or ""
    let best = "", distance = 4.5;
    for (const [frame, note] of markNotes) {
      const d = Math.abs(markX(frame) - offsetX);
      if (d < distance) { distance = d; best = `tick ${header.steps[frame]}: ${note}`; }
    }
    return best;
  }

  const legend = document.getElementById("legend");
  for (const mark of header.eventMarks) {
    const swatch = document.createElement("i");
    swatch.style.background = mark.color;
    legend.append(swatch, mark.kind);
  }

  // ---- hit test: the topmost active body under a screen point ----
  function segmentDistance(x, y, ax, ay, bx, by) {
    const dx = bx - ax, dy = by - ay, length2 = dx * dx + dy * dy;
    const t = length2 > 0 ? Math.min(Math.max(((x - ax) * dx + (y - ay) * dy) / length2, 0), 1) : 0;
    return Math.hypot(x - ax - t * dx, y - ay - t * dy);
  }

  function shapeHolds(f, s, x, y) { // is world point (x, y) on shape s?
    const count = shapeWorld(f, s), style = shapes.style[s], r = shapes.radius[s];
    if (style === "disc") return Math.hypot(x - world[0], y - world[1]) <= r;
    if (style === "stadium") return segmentDistance(x, y, world[0], world[1], world[2], world[3]) <= r;
    if (style === "line") {
      const pick = LINE_PICK / state.scale, last = shapes.closed[s] ? count : count - 1;
      for (let k = 0; k < last; k++) {
        const j = (k + 1) % count;
        if (segmentDistance(x, y, world[2 * k], world[2 * k + 1], world[2 * j], world[2 * j + 1]) <= pick) return true;
      }
      return false;
    }
    let inside = false; // crossings of a ray to the right: concave polygons too
    for (let k = 0, j = count - 1; k < count; j = k++) {
      const yk = world[2 * k + 1], yj = world[2 * j + 1];
      if ((yk > y) !== (yj > y)
          && x < world[2 * j] + ((y - yj) * (world[2 * k] - world[2 * j])) / (yk - yj)) inside = !inside;
    }
    return inside;
  }

  function bodyAt(px, py) {
    const f = state.frame, x = wx(px), y = wy(py), pick = LINE_PICK / state.scale;
    for (let n = order.length - 1; n >= 0; n--) {
      const i = order[n], base = f * N + i;
      if (!active[base]) continue;
      const dx = x - position[2 * base], dy = y - position[2 * base + 1];
      if (!(Math.hypot(dx, dy) <= reach[i] + pick)) continue;
      for (let s = firstShape[i]; s < firstShape[i + 1]; s++) if (shapeHolds(f, s, x, y)) return i;
    }
    return -1;
  }

  // ---- playback ----
  function setFrame(f) {
    state.frame = Math.min(Math.max(Math.round(f), 0), F - 1);
    clock = times[state.frame];
    dirty = true;
  }

  function togglePlay() {
    state.playing = !state.playing;
    if (state.playing && state.frame >= F - 1) setFrame(0);
    clock = times[state.frame];
    lastNow = null;
    dirty = true;
  }

  function step(delta) {
    state.playing = false;
    setFrame(state.frame + delta);
  }

  function toggle(name) {
    state[name] = !state[name];
    document.getElementById(name).checked = state[name];
    dirty = true;
  }

  function setSpeed(index) {
    const options = speedSelect.options;
    speedSelect.selectedIndex = Math.min(Math.max(index, 0), options.length - 1);
    state.speed = Number(speedSelect.value);
  }

  const interval = F > 1 ? (times[F - 1] - times[0]) / (F - 1) : 0;

  function animate(now) {
    if (state.playing && F > 1) {
      if (lastNow !== null) {
        clock += ((now - lastNow) / 1000) * state.speed;
        let f = state.frame;
        while (f + 1 < F && times[f + 1] <= clock) f += 1;
        if (f === F - 1 && clock >= times[F - 1] + interval) { f = 0; clock = times[0]; } // loop
        if (f !== state.frame) { state.frame = f; dirty = true; }
      }
      lastNow = now;
    }
    if (dirty) draw();
    requestAnimationFrame(animate);
  }

  // ---- input ----
  const keys = { h: "hitboxes", c: "contacts", v: "velocities", n: "names", j: "joints" };
  window.addEventListener("keydown", (event) => {
    if (event.ctrlKey || event.metaKey || event.altKey) return;
    const key = event.key.length === 1 ? event.key.toLowerCase() : event.key;
    if (key === " " || key === "Spacebar") togglePlay();
    else if (key === "ArrowRight") step(event.shiftKey ? 10 : 1);
    else if (key === "ArrowLeft") step(event.shiftKey ? -10 : -1);
    else if (key === "Home") step(-F);
    else if (key === "End") step(F);
    else if (keys[key]) toggle(keys[key]);
    else if (key === "f" || key === "r") fit();
    else if (key === "+" || key === "=") setSpeed(speedSelect.selectedIndex + 1);
    else if (key === "-") setSpeed(speedSelect.selectedIndex - 1);
    else return;
    event.preventDefault(); // also keeps a focused button or slider from acting on the key
  }, true);

  playButton.addEventListener("click", togglePlay);
  document.getElementById("back").addEventListener("click", () => step(-1));
  document.getElementById("forward").addEventListener("click", () => step(1));
  document.getElementById("fit").addEventListener("click", fit);
  scrub.addEventListener("input", () => setFrame(Number(scrub.value)));
  scrub.addEventListener("mousemove", (event) => { scrub.title = markNear(event.offsetX) || "scrub"; });
  speedSelect.addEventListener("change", () => setSpeed(speedSelect.selectedIndex));
  for (const name of OVERLAYS) {
    document.getElementById(name).addEventListener("change", (event) => {
      state[name] = event.target.checked;
      dirty = true;
    });
  }

  canvas.addEventListener("wheel", (event) => {
    event.preventDefault();
    const lines = event.deltaMode === 1 ? 33 : event.deltaMode === 2 ? height : 1;
    zoomAt(event.offsetX, event.offsetY, Math.exp(-event.deltaY * lines * 0.0015));
  }, { passive: false });
  canvas.addEventListener("pointerdown", (event) => {
    drag = { x: event.offsetX, y: event.offsetY };
    canvas.setPointerCapture(event.pointerId);
    canvas.classList.add("dragging");
  });
  canvas.addEventListener("pointermove", (event) => {
    mouse = { x: event.offsetX, y: event.offsetY };
    if (drag) {
      state.cx -= (event.offsetX - drag.x) / state.scale;
      state.cy += (event.offsetY - drag.y) / state.scale;
      drag = { x: event.offsetX, y: event.offsetY };
    }
    state.hover = bodyAt(mouse.x, mouse.y);
    dirty = true;
  });
  const release = () => { drag = null; canvas.classList.remove("dragging"); };
  canvas.addEventListener("pointerup", release);
  canvas.addEventListener("pointercancel", release);
  canvas.addEventListener("pointerleave", () => { mouse = null; state.hover = -1; dirty = true; });
  window.addEventListener("resize", () => {
    const x = state.cx, y = state.cy, scale = state.scale;
    resize();
    Object.assign(state, { cx: x, cy: y, scale });
    drawMarks();
  });

  window.player = {
    state,
    stats,
    header,
    frameCount: F,
    bodyCount: N,
    jointCount: J,
    setFrame,
    togglePlay,
    step,
    fit,
    draw,
    bodyAt,
    sensorLit: (i, f = state.frame) => lit(f, i), // whether sensor body i holds something at frame f
    asleep: (i, f = state.frame) => asleep[f * N + i] === 1, // whether body i sleeps at frame f
    scrubPoint: (f) => { // page pixels of frame f's place on the scrub bar (its mark), mid-height
      const rect = scrub.getBoundingClientRect();
      return [rect.left + markX(f), rect.top + rect.height / 2];
    },
    worldToScreen: (x, y) => [sx(x), sy(y)], // CSS pixels within the canvas
    ready: false,
  };
  resize();
  fit();
  draw();
  drawMarks();
  window.player.ready = true;
  requestAnimationFrame(animate);
})();
