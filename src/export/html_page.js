// The comparison page's player (src/export/html.rs embeds it). F holds one sprite per frame:
// the panes side by side, unzoomed; META their labels, size, rate and zoom; RECORD the clip's
// record (the recipe and the figures).
"use strict";
const N = META.labels.length, W = META.width, H = META.height;
const CW = Math.max(1, Math.min(W * META.zoom, META.max_view));
const CH = Math.max(1, Math.round(CW * H / W));
const byId = (id) => document.getElementById(id);
const state = { frame: 0, playing: false, zoom: Math.max(1, Math.round(CW / W)), cx: W / 2, cy: H / 2, wipe: 0.5, left: 0, right: N - 1 };
const sprites = F.map((src) => { const image = new Image(); image.src = src; return image; });
let canvases = [];

// The source window every view shows: integer zoom, whole pixels, the same for every pane.
function view() {
  const z = state.zoom;
  const sw = Math.min(W, Math.ceil(CW / z)), sh = Math.min(H, Math.ceil(CH / z));
  const sx = Math.max(0, Math.min(W - sw, Math.floor(state.cx - sw / 2)));
  const sy = Math.max(0, Math.min(H - sh, Math.floor(state.cy - sh / 2)));
  return { z, sx, sy, sw, sh };
}

function drawPane(ctx, pane, v, clipX) {
  ctx.save();
  if (clipX !== undefined) { ctx.beginPath(); ctx.rect(clipX, 0, CW - clipX, CH); ctx.clip(); }
  ctx.imageSmoothingEnabled = false;
  ctx.drawImage(sprites[state.frame], pane * W + v.sx, v.sy, v.sw, v.sh, 0, 0, v.sw * v.z, v.sh * v.z);
  ctx.restore();
}

function wipeX() { return Math.round(state.wipe * CW); }

function draw() {
  const v = view();
  const wipe = byId("wipe").getContext("2d");
  wipe.fillStyle = "#18191e"; wipe.fillRect(0, 0, CW, CH);
  drawPane(wipe, state.left, v);
  drawPane(wipe, state.right, v, wipeX());
  canvases.forEach((canvas, pane) => {
    const ctx = canvas.getContext("2d");
    ctx.fillStyle = "#18191e"; ctx.fillRect(0, 0, CW, CH);
    drawPane(ctx, pane, v);
  });
  byId("wipeline").style.left = wipeX() + "px";
  byId("frame").textContent = (state.frame + 1) + "/" + F.length;
  byId("zoomvalue").textContent = state.zoom + "x";
  byId("play").textContent = state.playing ? "Pause" : "Play";
}

function step(delta) { state.frame = (state.frame + delta + F.length) % F.length; draw(); }
function setPlaying(playing) { state.playing = playing; draw(); }
// Playback: one frame per 1/fps s on a timer (frames are never skipped).
let played = 0;
function tick() { if (state.playing) { played += 1; step(1); } }

function dragOn(element, move) {
  element.addEventListener("pointerdown", (e) => {
    element.setPointerCapture(e.pointerId); move(e);
    const onMove = (m) => move(m);
    element.addEventListener("pointermove", onMove);
    element.addEventListener("pointerup", () => element.removeEventListener("pointermove", onMove), { once: true });
  });
}

function setup() {
  const wipe = byId("wipe");
  wipe.width = CW; wipe.height = CH;
  byId("wipebox").style.width = CW + "px";
  for (const [id, pane] of [["left", state.left], ["right", state.right]]) {
    const select = byId(id);
    META.labels.forEach((label, i) => select.add(new Option(label, i, i === pane, i === pane)));
    select.addEventListener("change", () => { state[id] = Number(select.value); draw(); });
  }
  const grid = byId("grid");
  canvases = META.labels.map((label) => {
    const figure = document.createElement("figure");
    const canvas = document.createElement("canvas");
    canvas.width = CW; canvas.height = CH;
    const caption = document.createElement("figcaption");
    caption.textContent = label;
    figure.append(canvas, caption); grid.append(figure);
    // Dragging a pane moves every view (the zoom is synchronised).
    dragOn(canvas, (e) => {
      const v = view(), r = canvas.getBoundingClientRect();
      state.cx = v.sx + (e.clientX - r.left) / v.z; state.cy = v.sy + (e.clientY - r.top) / v.z; draw();
    });
    return canvas;
  });
  dragOn(wipe, (e) => {
    const r = wipe.getBoundingClientRect();
    state.wipe = Math.max(0, Math.min(1, (e.clientX - r.left) / CW)); draw();
  });
  const zoom = byId("zoom");
  zoom.value = state.zoom;
  zoom.addEventListener("input", () => { state.zoom = Number(zoom.value); draw(); });
  byId("play").addEventListener("click", () => setPlaying(!state.playing));
  byId("prev").addEventListener("click", () => { setPlaying(false); step(-1); });
  byId("next").addEventListener("click", () => { setPlaying(false); step(1); });
  metricsTable();
  byId("recipe").textContent = JSON.stringify(RECORD, null, 2);
}

function metricsTable() {
  const table = byId("metrics");
  const figure = (v, d) => (typeof v === "number" ? v.toFixed(d) : "n/a");
  const head = ["technique", "temporal instability", "mean change", "ghosting"];
  const regional = RECORD.techniques.some((t) => t.region);
  if (regional) head.push("region: instability", "region: ghosting");
  const judged = RECORD.techniques.some((t) => typeof t.jod === "number");
  if (judged) head.push(`JOD (${RECORD.jod ? RECORD.jod.display : "ColorVideoVDP"})`);
  table.insertRow().append(...head.map((h) => Object.assign(document.createElement("th"), { textContent: h })));
  for (const t of RECORD.techniques) {
    const cells = [t.label, figure(t.temporal_instability, 3), figure(t.mean_change, 3), figure(t.ghosting, 2)];
    if (regional) cells.push(figure(t.region && t.region.temporal_instability, 3), figure(t.region && t.region.ghosting, 2));
    if (judged) cells.push(figure(t.jod, 2));
    const row = table.insertRow();
    cells.forEach((c) => (row.insertCell().textContent = c));
  }
}

// Under #selftest: steps, zooms, moves the wipe and plays, reading back what the wipe view
// shows. The results go into #selftest and, between markers, to the console (headless
// Chromium logs it to stderr, where tests/html.rs reads them in real time); then the page
// closes itself, which ends a headless browser.
function reportSelftest(text) {
  byId("selftest").textContent = text;
  console.log("aa-lab-selftest<<<" + text + ">>>");
  window.close();
}

function selftest() {
  const out = { frames: F.length, width: CW, height: CH, samples: [] };
  setPlaying(false);
  state.frame = 0; step(1); step(1);
  // Twice the zoom that fits the pane: the views show a window around the centre.
  state.zoom = 2 * Math.ceil(CW / W); state.cx = W / 2; state.cy = H / 2;
  state.left = 0; state.right = N - 1;
  state.wipe = 0.5;
  draw();
  const v = view(), ctx = byId("wipe").getContext("2d");
  const shown = Math.min(CW, v.sw * v.z), rows = Math.min(CH, v.sh * v.z);
  for (const py of [Math.floor(rows / 4), Math.floor(rows / 2), Math.floor(rows * 3 / 4)]) {
    const line = ctx.getImageData(0, py, shown, 1).data;
    for (let px = 0; px < shown; px += 1) {
      const pane = px < wipeX() ? state.left : state.right;
      const rgba = Array.from(line.slice(px * 4, px * 4 + 4));
      out.samples.push({ frame: state.frame, pane, x: v.sx + Math.floor(px / v.z), y: v.sy + Math.floor(py / v.z), rgba });
    }
  }
  out.stepped_to = state.frame;
  // Plays until three frames have gone by, or for at most five seconds on a loaded machine.
  played = 0;
  setPlaying(true);
  const started = performance.now();
  const watch = setInterval(() => {
    if (played < 3 && performance.now() - started < 5000) return;
    clearInterval(watch);
    out.played_frames = played;
    setPlaying(false);
    reportSelftest(JSON.stringify(out));
  }, 1000 / META.fps);
}

Promise.all(sprites.map((s) => s.decode())).then(() => {
  setup(); draw();
  if (location.hash === "#selftest") selftest(); else setPlaying(true);
  setInterval(tick, 1000 / META.fps);
}, (e) => {
  if (location.hash === "#selftest") reportSelftest(JSON.stringify({ error: String(e) }));
  else byId("frame").textContent = "the frames cannot be decoded: " + e;
});
