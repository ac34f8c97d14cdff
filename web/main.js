// The cdt3d demo page: open a model (file picker, drag and drop or a bundled
// sample), mesh it in a Web Worker with a progress bar and Cancel, show the
// result with three.js, statistics and downloads.
import { createMeshWorker } from 'cdt3d/worker';

import { BACKGROUND, STEINER_COLORS, STEINER_MANY, Viewer, nextTask } from './viewer.js';

// `up`: the samples' own up axis (the Stanford scans are Y-up); files
// opened by the user get the remembered choice.
const SAMPLES = [
  { file: 'bunny.off', label: 'Stanford bunny (7k triangles)', up: 'y' },
  { file: 'cube_internal_facet.poly', label: 'Cube with an internal facet (2 regions)' },
  { file: 'nested_cubes_cavity.poly', label: 'Cube with a cavity' },
  { file: 'schonhardt.off', label: 'Schönhardt polyhedron' },
  { file: 'fandisk.off', label: 'Fandisk CAD part (14k triangles)' },
  { file: 'armadillo.obj', label: 'Armadillo (86k triangles, large)', up: 'y' },
];
const DEFAULT_SAMPLE = 'bunny.off';

const PHASES = [
  ['read', 'Reading'],
  ['delaunay', 'Delaunay'],
  ['segments', 'Segments'],
  ['degeneracy', 'Degeneracies'],
  ['facets', 'Facets'],
  ['carve', 'Carving'],
];
const REFINE_PHASE = ['refine', 'Refining'];
const PHASE_TIMES = [
  ['msRead', 'read'],
  ['msDelaunay', 'Delaunay'],
  ['msSegments', 'segments'],
  ['msDegeneracy', 'degeneracy'],
  ['msFacets', 'facets'],
  ['msCarve', 'carve'],
];
const REFINE_TIME = ['msRefine', 'refine'];
// Bins of the core's quality histograms (MeshStatistics in cdt3d.d.ts): a
// short label (lower bound) and the range for the tooltip.
const RATIO_BINS = ['<1', '1', '1.5', '2', '3', '5', '10', '20', '50', '100+'];
const RATIO_RANGES = ['< 1', '1-1.5', '1.5-2', '2-3', '3-5', '5-10', '10-20', '20-50', '50-100', '> 100'];
const ANGLE_BINS = ['<1°', '1°', '5°', '10°', '15°', '20°', '30°', '40°', '50°', '60°+'];
const ANGLE_RANGES = ['< 1°', '1-5°', '5-10°', '10-15°', '15-20°', '20-30°', '30-40°', '40-50°', '50-60°', '> 60°'];

// Min dihedral angle colour ramp (degrees -> rgb 0..1); 70.53 is a regular tet.
const QUALITY_RAMP = [
  [0, [0.78, 0.16, 0.16]],
  [12, [0.95, 0.42, 0.2]],
  [25, [0.98, 0.75, 0.3]],
  [40, [0.62, 0.83, 0.45]],
  [55, [0.3, 0.74, 0.68]],
  [70.5, [0.33, 0.55, 0.92]],
];
// No orange: that is the constrained-face colour.
const REGION_COLORS = [
  [0.36, 0.58, 0.93],
  [0.4, 0.74, 0.42],
  [0.87, 0.38, 0.42],
  [0.68, 0.5, 0.78],
  [0.45, 0.76, 0.78],
  [0.92, 0.8, 0.35],
  [0.95, 0.6, 0.7],
  [0.62, 0.5, 0.4],
  [0.7, 0.7, 0.72],
];
const PLAIN_COLOR = [0.62, 0.72, 0.86];

const $ = (id) => document.getElementById(id);
const fmt = new Intl.NumberFormat('en-US');

const viewer = new Viewer($('view'));
const mesher = createMeshWorker();
const geometry = new Worker(new URL('./geometry-worker.js', import.meta.url), { type: 'module' });

// Exposed for tests and the curious (read-only use).
const demo = {
  viewer,
  state: 'idle',
  stats: null,
  error: null,
  result: null,
  timings: [],
  highlighted: 0,
  snapshot: () => viewer.snapshot(),
  repair: null, // the repair report of the last "Repair and mesh"
  quality: null, // the quality option of the last job (null: no refinement)
  // The mesher: 'loading', 'warming' (meshing its built-in model), 'ready' or
  // 'failed'; threaded: the two-thread module; loadMs and runs (warm-up ms).
  engine: { state: 'loading', threaded: null, loadMs: NaN, runs: [] },
};
window.cdt3dDemo = demo;

let jobSeq = 0;
let job = null; // the model being meshed: {id, name, controller, t0}
let current = null; // the model shown: {id, name, source, result, built, origin}

function setState(state) {
  demo.state = state;
  document.body.dataset.state = state;
}

// ---------------------------------------------------------------- opening

function sourceName(source) {
  return source.file ? source.file.name : source.sample;
}

async function openModel(source) {
  if (job) job.controller.abort();
  const id = ++jobSeq;
  const name = sourceName(source);
  const controller = new AbortController();
  job = { id, name, controller, t0: performance.now(), source };
  const timing = { name, start: job.t0, meshStart: NaN, meshEnd: NaN, shown: NaN };
  demo.timings.push(timing);

  setState('loading');
  demo.error = null;
  demo.stats = null;
  demo.result = null;
  demo.highlighted = 0;
  $('error').hidden = true;
  $('repair').hidden = true;
  $('repair-parts').hidden = true;
  $('no-validate').hidden = true;
  $('fill-holes').hidden = true;
  $('repair-report').hidden = true;
  demo.repair = null;
  $('notice').hidden = true;
  $('stats').hidden = true;
  $('downloads').hidden = true;
  $('legend').hidden = true;
  $('remesh').disabled = true;
  $('model-name').textContent = name;
  $('model-status').textContent = 'Meshing…';
  document.title = `${name} — cdt3d`;
  viewer.clear();
  updateSteinerNote();
  showUp(SAMPLES.find((s) => s.file === source.sample)?.up ?? storedUp());
  if (source.partsAsRegions) $('color-mode').value = 'region'; // what the user asked to see
  current = { id, name, source, result: null, built: null, origin: null, surface: null };
  updateVisibleCount();
  showProgress(name, qualityOption() ? [...PHASES, REFINE_PHASE] : PHASES);

  try {
    let input = source.file;
    if (source.sample) {
      setPhase('downloading sample…');
      const response = await fetch(`samples/${source.sample}`, { signal: controller.signal });
      if (!response.ok) throw new Error(`Could not load the sample ${source.sample} (HTTP ${response.status}).`);
      input = await response.arrayBuffer();
    }
    if (id !== jobSeq) return;
    // The renderer's start-up (its shader programs link on the main thread,
    // hundreds of ms each with a software GPU) ends before a job starts, so
    // that progress and Cancel never wait behind it while a model is meshed.
    if (!viewer.warm) {
      setPhase('starting the renderer…');
      await viewer.ready;
      if (id !== jobSeq) return;
    }
    setState('meshing');
    timing.meshStart = performance.now();
    const options = meshOptions();
    if (source.repair) {
      options.repair = source.fillHoles ? { fillHoles: true } : source.partsAsRegions ? { partsAsRegions: true } : true;
    }
    const quality = qualityOption();
    if (quality) options.quality = quality;
    demo.quality = quality;
    let result;
    try {
      result = await mesher.mesh(input, options, {
        fileName: name,
        signal: controller.signal,
        onProgress: (p) => id === jobSeq && onProgress(p),
        onSurface: (surface) => id === jobSeq && showSurface(surface),
      });
    } finally {
      timing.meshEnd = performance.now();
    }
    if (id !== jobSeq) return;
    job = null;
    hideProgress();
    current.result = result;
    demo.result = result;
    demo.stats = result.stats;
    if (!current.surface && result.inputTriangles) {
      showSurface({
        points: result.points,
        triangles: result.inputTriangles,
        triangleFacets: result.inputTriangleFacets,
      });
    }
    showStats(result, !!options.quality);
    setState('building');
    $('model-status').textContent = 'Preparing the view…';
    // What follows is split into tasks, so that none of them blocks the main
    // thread for long on a loaded machine: copying the arrays to the geometry
    // worker, the panels (their layout in a frame of its own), the colours,
    // then the tets (their upload in the next frame).
    await nextTask();
    if (id !== jobSeq) return;
    const built = await buildGeometry(id, result);
    if (id !== jobSeq) return;
    current.built = built;
    showHistogram(built.histogram);
    showLegend();
    await nextFrames(1);
    await nextTask();
    if (id !== jobSeq) return;
    const mode = $('color-mode').value;
    let colors = await tetColors(built, mode);
    if (id !== jobSeq) return;
    if ($('color-mode').value !== mode) colors = await tetColors(built); // changed meanwhile
    if (id !== jobSeq) return;
    viewer.setExtent(...relativeBounds(result.points, current.origin));
    // Uploaded to the GPU a slice per task; false when cleared by a newer model.
    if (!(await viewer.setTets({ position: built.position, center: built.center, colors, order: built.order }))) return;
    if (id !== jobSeq) return;
    viewer.setSteiner(built.steinerPosition, built.steinerKinds);
    updateSteinerNote();
    applyViewControls();
    $('downloads').hidden = false;
    $('remesh').disabled = false;
    if (result.repair) showRepair(result.repair);
    await nextFrames(2);
    if (id !== jobSeq) return;
    timing.shown = performance.now();
    const s = result.stats;
    $('model-status').textContent =
      `${fmt.format(s.tets)} tetrahedra in ${seconds(timing.meshEnd - timing.meshStart)} ` +
      `(shown after ${seconds(timing.shown - timing.start)})`;
    setState('done');
  } catch (e) {
    if (id !== jobSeq) return; // superseded by a newer model
    job = null;
    hideProgress();
    $('remesh').disabled = false;
    if (e?.code === 'cancelled' || e?.name === 'AbortError') {
      $('model-status').textContent = 'Cancelled.';
      showNotice(`Meshing ${name} was cancelled.`);
      setState('cancelled');
      return;
    }
    showError(e, name);
    setState('error');
  }
}

function nextFrames(n) {
  return new Promise((resolve) => {
    const step = () => (n-- <= 0 ? resolve() : requestAnimationFrame(step));
    requestAnimationFrame(step);
  });
}

function seconds(ms) {
  return ms < 1000 ? `${Math.round(ms)} ms` : `${(ms / 1000).toFixed(2)} s`;
}

// The options of the check boxes (quality is added by the caller).
function meshOptions() {
  return {
    validate: $('opt-validate').checked,
    keepConvexHull: $('opt-hull').checked,
    keepTriangles: $('opt-keep-triangles').checked,
  };
}

// ---------------------------------------------------------------- the mesher

// The worker starts now: the WebAssembly module is compiled while it
// downloads, then the package's built-in models are meshed with the page's
// options, so that the engine has optimised the hot code before the
// user's first model (a cold module meshed it several times slower). All of
// it runs in the worker; a model opened meanwhile goes first.
function setEngine(state, text) {
  demo.engine.state = state;
  document.body.dataset.engine = state;
  $('engine').textContent = text;
}

function threadsText(threaded) {
  if (threaded) return 'two threads';
  return self.crossOriginIsolated ? 'one thread (the two-thread module did not start)' : 'one thread (the page is not cross-origin isolated)';
}

setEngine('loading', 'Loading the mesher…');
mesher
  .prepare({ rounds: 0 })
  .then((loaded) => {
    demo.engine.threaded = loaded.threaded;
    demo.engine.loadMs = loaded.loadMs;
    setEngine('warming', `Mesher: ${threadsText(loaded.threaded)}; warming up…`);
    // After the renderer's start-up: its shader links need a free core.
    return viewer.ready.then(() => mesher.prepare({ options: meshOptions() }));
  })
  .then((warmed) => {
    demo.engine.runs = warmed.runs;
    setEngine('ready', `Mesher: ${threadsText(warmed.threaded)}; ready.`);
  })
  .catch((e) => {
    // Jobs still start the worker on their own; their errors say what failed.
    setEngine('failed', `The mesher could not be prepared: ${e?.message ?? e}`);
  });

// ---------------------------------------------------------------- surface & geometry

function boundsOf(points) {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < points.length; i += 3) {
    for (let a = 0; a < 3; a++) {
      const v = points[i + a];
      if (v < lo[a]) lo[a] = v;
      if (v > hi[a]) hi[a] = v;
    }
  }
  if (!(lo[0] <= hi[0])) return [[-1, -1, -1], [1, 1, 1]];
  return [lo, hi];
}

function relativeBounds(points, origin) {
  const [lo, hi] = boundsOf(points);
  return [lo.map((v, a) => v - origin[a]), hi.map((v, a) => v - origin[a])];
}

// The input surface, solid until tets arrive (then a faint ghost).
function showSurface(surface, highlight = null) {
  if (!current) return 0;
  current.surface = surface;
  if (!current.origin) {
    const [lo, hi] = boundsOf(surface.points);
    current.origin = lo.map((v, a) => (v + hi[a]) / 2);
    viewer.setExtent(...relativeBounds(surface.points, current.origin));
    viewer.fitView();
  }
  return viewer.setSurface(surface, current.origin, highlight);
}

let geometryWaiters = new Map();
geometry.onmessage = (e) => {
  const msg = e.data;
  if (msg.type === 'order') {
    if (current?.built && msg.id === current.id) {
      current.built.order = msg;
      viewer.setOrder(msg).then(updateVisibleCount);
    }
    return;
  }
  const waiter = geometryWaiters.get(msg.id);
  if (!waiter) return;
  geometryWaiters.delete(msg.id);
  if (msg.type === 'failed') waiter.reject(new Error(`Preparing the view failed: ${msg.message}`));
  else waiter.resolve(msg);
};
geometry.onerror = (e) => {
  for (const w of geometryWaiters.values()) w.reject(new Error(`The geometry worker failed: ${e.message ?? ''}`));
  geometryWaiters = new Map();
};

function buildGeometry(id, result) {
  if (!current.origin) {
    const [lo, hi] = boundsOf(result.points);
    current.origin = lo.map((v, a) => (v + hi[a]) / 2);
  }
  return new Promise((resolve, reject) => {
    geometryWaiters.set(id, { resolve, reject });
    // Copies (the page keeps the result for downloads), transferred: a
    // plain slice is a memory copy, while cloning the arrays inside
    // postMessage took over 100 ms of the main thread for a 150k-tet mesh.
    const arrays = {};
    for (const key of ['points', 'tets', 'faces', 'tetAttributes', 'steinerKinds']) {
      if (ArrayBuffer.isView(result[key])) arrays[key] = result[key].slice();
    }
    geometry.postMessage(
      {
        type: 'build',
        id,
        ...arrays,
        inputPoints: result.inputPoints ?? result.stats?.inputPoints ?? 0,
        origin: current.origin,
        axis: viewer.axis,
        flip: viewer.flip,
      },
      Object.values(arrays).map((a) => a.buffer),
    );
  });
}

let pendingOrder = false;
let orderInFlight = false;
function requestOrder() {
  if (!current?.built) return;
  const b = current.built;
  if (b.order.axis === viewer.axis && b.order.flip === viewer.flip) {
    pendingOrder = false;
    return;
  }
  if (orderInFlight) {
    pendingOrder = true;
    return;
  }
  orderInFlight = true;
  pendingOrder = false;
  const want = { axis: viewer.axis, flip: viewer.flip };
  const done = (e) => {
    if (e.data.type === 'order') {
      geometry.removeEventListener('message', done);
      orderInFlight = false;
      if (pendingOrder || want.axis !== viewer.axis || want.flip !== viewer.flip) requestOrder();
    }
  };
  geometry.addEventListener('message', done);
  geometry.postMessage({ type: 'order', id: current.id, ...want });
}

// ---------------------------------------------------------------- colours

function rampColor(deg) {
  if (!(deg > 0)) return QUALITY_RAMP[0][1];
  for (let i = 1; i < QUALITY_RAMP.length; i++) {
    const [d1, c1] = QUALITY_RAMP[i];
    if (deg <= d1) {
      const [d0, c0] = QUALITY_RAMP[i - 1];
      const f = (deg - d0) / (d1 - d0);
      return [c0[0] + f * (c1[0] - c0[0]), c0[1] + f * (c1[1] - c0[1]), c0[2] + f * (c1[2] - c0[2])];
    }
  }
  return QUALITY_RAMP[QUALITY_RAMP.length - 1][1];
}

const css = (c) => `rgb(${c.map((v) => Math.round(v * 255)).join(',')})`;

// Per vertex rgba8: the tet colour (shader works in linear space, so colours
// are squared roughly) and, in alpha, the constrained flag. Computed in
// slices of at most COLOR_SLICE_MS, so that a large mesh does not block the
// page (the first slices run as cold, interpreted code: 32k tets took up to
// about 100 ms on a loaded machine).
const COLOR_SLICE_MS = 15;
async function tetColors(built, mode = $('color-mode').value) {
  const nt = built.quality.length;
  const out = new Uint8Array(nt * 16);
  const lut = new Uint8Array(256 * 3); // quality in 0.5 degree steps
  for (let i = 0; i < 256; i++) {
    const c = rampColor(i * 0.5);
    for (let k = 0; k < 3; k++) lut[3 * i + k] = Math.round(255 * c[k] ** 2.2);
  }
  const lin = (c) => c.map((v) => Math.round(255 * v ** 2.2));
  const regionLut = REGION_COLORS.map(lin);
  const plain = lin(PLAIN_COLOR);
  const { quality, region, flags } = built;
  let sliceStart = performance.now();
  for (let t = 0; t < nt; t++) {
    if ((t & 1023) === 1023 && performance.now() - sliceStart > COLOR_SLICE_MS) {
      await nextTask();
      sliceStart = performance.now();
    }
    let r;
    let g;
    let b;
    if (mode === 'quality') {
      const i = Math.min(255, Math.max(0, Math.round(quality[t] * 2))) * 3;
      r = lut[i];
      g = lut[i + 1];
      b = lut[i + 2];
    } else if (mode === 'region') {
      [r, g, b] = regionLut[region[t] % regionLut.length];
    } else {
      [r, g, b] = plain;
    }
    for (let j = 0; j < 4; j++) {
      const o = 16 * t + 4 * j;
      out[o] = r;
      out[o + 1] = g;
      out[o + 2] = b;
      out[o + 3] = flags[4 * t + j] ? 255 : 0;
    }
  }
  return out;
}

function showLegend() {
  const legend = $('legend');
  const mode = $('color-mode').value;
  const parts = [];
  if (mode === 'quality') {
    const stops = QUALITY_RAMP.map(([d, c]) => `${css(c)} ${((d / 70.5) * 100).toFixed(1)}%`).join(',');
    parts.push('<div>min dihedral angle</div>');
    parts.push(`<div class="ramp" style="background:linear-gradient(90deg,${stops})"></div>`);
    parts.push('<div class="ends"><span>0°</span><span>35°</span><span>70.5°</span></div>');
  } else if (mode === 'region' && current?.built) {
    const values = current.built.regionValues;
    parts.push(`<div>${values.length} region${values.length === 1 ? '' : 's'}</div>`);
    values.slice(0, 8).forEach((v, i) => {
      const c = css(REGION_COLORS[i % REGION_COLORS.length]);
      parts.push(`<div class="item"><span class="swatch" style="background:${c}"></span>attribute ${v}</div>`);
    });
  }
  parts.push('<div class="item"><span class="swatch constrained"></span>constrained face</div>');
  legend.innerHTML = parts.join('');
  legend.hidden = false;
}

// ---------------------------------------------------------------- progress

let progressTimer = null;
let progressPhases = PHASES; // the phases of the running job
function showProgress(name, phases) {
  progressPhases = phases;
  $('progress').hidden = false;
  $('progress-file').textContent = name;
  $('progress-bar').style.width = '0%';
  delete $('progress').dataset.phase;
  delete $('progress').dataset.fraction;
  $('progress-steps').innerHTML = phases.map(([p, label]) => `<li data-phase="${p}">${label}</li>`).join('');
  const t0 = performance.now();
  clearInterval(progressTimer);
  pendingProgress = null;
  drawnPhase = null;
  progressTimer = setInterval(() => {
    $('progress-time').textContent = seconds(performance.now() - t0);
    if (pendingProgress) drawProgress(pendingProgress);
  }, PROGRESS_PAINT_MS);
  setPhase('starting…');
}

function hideProgress() {
  $('progress').hidden = true;
  clearInterval(progressTimer);
}

function setPhase(text) {
  $('progress-phase').textContent = text;
}

// The bar is repainted at most every PROGRESS_PAINT_MS, and at once when
// the phase changes: each repaint of the overlay composites the page again,
// which with a software GPU took CPU time from the meshing threads (the
// worker reports up to 25 times a second).
const PROGRESS_PAINT_MS = 250;
let pendingProgress = null;
let drawnPhase = null;
function onProgress(progress) {
  pendingProgress = progress;
  if (progress.phase !== drawnPhase) drawProgress(progress);
}

function drawProgress({ phase, fraction }) {
  pendingProgress = null;
  drawnPhase = phase;
  const i = progressPhases.findIndex(([p]) => p === phase);
  const f = Math.max(0, Math.min(1, Number(fraction) || 0));
  if (phase === 'done') {
    $('progress-bar').style.width = '100%';
    setPhase('finishing…');
  } else if (i >= 0) {
    $('progress-bar').style.width = `${(((i + f) / progressPhases.length) * 100).toFixed(1)}%`;
    setPhase(`${progressPhases[i][1]} ${Math.floor(f * 100)}%`);
  } else {
    setPhase(`${phase} ${Math.floor(f * 100)}%`);
  }
  const bar = $('progress');
  bar.dataset.phase = phase;
  bar.dataset.fraction = String(f);
  for (const li of $('progress-steps').children) {
    const k = progressPhases.findIndex(([p]) => p === li.dataset.phase);
    li.className = phase === 'done' || k < i ? 'done' : k === i ? 'active' : '';
  }
}

// ---------------------------------------------------------------- panels

function setStat(key, value, text = null) {
  const el = $(`stat-${key}`);
  if (!el) return;
  el.dataset.value = String(value);
  el.textContent = text ?? (typeof value === 'number' ? fmt.format(value) : String(value ?? '—'));
}

function showStats(result, refined) {
  const s = result.stats;
  for (const key of [
    'inputPoints', 'inputFacets', 'inputSegments', 'flatEdges', 'mergedFacets', 'points', 'tets', 'faces',
    'steinerSegment', 'steinerFacet', 'facetSplits', 'steinerVolume', 'flatTets',
    'splitProjection', 'splitShell', 'splitRemoved',
  ]) {
    setStat(key, s[key]);
  }
  setStat('splitRules', s.rule1 + s.rule2 + s.rule3 + s.acuteBoth);
  $('stat-flatTets').className = s.flatTets > 0 ? 'bad' : '';
  setStat('minDihedral', s.minDihedral, Number.isFinite(s.minDihedral) ? `${s.minDihedral.toFixed(2)}°` : '—');
  setStat('maxDihedral', s.maxDihedral, Number.isFinite(s.maxDihedral) ? `${s.maxDihedral.toFixed(2)}°` : '—');
  const v = result.validation;
  const vEl = $('stat-validation');
  if (!v) {
    setStat('validation', 'not run', 'not run');
    vEl.className = '';
  } else {
    setStat('validation', v.ok ? 'ok' : 'failed', v.ok ? 'passed' : 'FAILED');
    vEl.className = v.ok ? 'ok' : 'bad';
    vEl.title = v.message ?? '';
  }
  // Time per phase.
  const times = (refined ? [...PHASE_TIMES, REFINE_TIME] : PHASE_TIMES).map(([k, label]) => [label, Number(s[k]) || 0]);
  const max = Math.max(1e-9, ...times.map(([, ms]) => ms));
  const rows = times.map(
    ([label, ms]) =>
      `<span>${label}</span><div class="bar" style="width:${((ms / max) * 100).toFixed(1)}%"></div><span class="ms">${ms.toFixed(ms < 10 ? 1 : 0)} ms</span>`,
  );
  const total = Number(s.msTotal) || times.reduce((a, [, ms]) => a + ms, 0);
  rows.push(`<span class="total">total</span><span></span><span class="ms total" id="stat-msTotal">${total.toFixed(0)} ms</span>`);
  $('timing').innerHTML = rows.join('');
  // Radius-edge histogram from the core; with refinement, before and after.
  const re = s.radiusEdgeHistogram;
  $('re-block').hidden = refined || !Array.isArray(re);
  if (!$('re-block').hidden) drawHistogram($('re-histogram'), re, () => [0.36, 0.58, 0.93], (i) => RATIO_BINS[i]);
  $('refine-block').hidden = !refined;
  if (refined) showRefinement(s);
  $('stats').hidden = false;
  $('stats').dataset.json = JSON.stringify(s);
}

// What quality refinement did: points added, what it left, and the quality
// histograms of the core before and after it.
function showRefinement(s) {
  for (const key of ['refineSegment', 'refineFacet', 'refineVolume', 'refineSkipped', 'refineSmallAngle']) setStat(key, s[key]);
  setStat(
    'improve',
    `${s.improveFlips}/${s.improveSmooths}/${s.improvePoints}`,
    `${fmt.format(s.improveFlips)} / ${fmt.format(s.improveSmooths)} / ${fmt.format(s.improvePoints)}`,
  );
  setStat('minDihedralBefore', s.minDihedralBefore, `${s.minDihedralBefore.toFixed(2)}°`);
  $('refine-capped').hidden = !s.refineCapped;
  drawCompare($('re-compare'), s.radiusEdgeHistogramBefore, s.radiusEdgeHistogram, RATIO_BINS, RATIO_RANGES);
  drawCompare($('dihedral-compare'), s.dihedralHistogramBefore, s.dihedralHistogram, ANGLE_BINS, ANGLE_RANGES);
}

// Two counts per bin side by side (before grey, after blue), on one square-root scale.
function drawCompare(el, before, after, labels, ranges) {
  const max = Math.max(1, ...before, ...after);
  const height = (c) => (c > 0 ? Math.max(2, (Math.sqrt(c) / Math.sqrt(max)) * 100) : 0).toFixed(1);
  el.innerHTML = before
    .map(
      (b, i) =>
        `<div class="pair" title="${ranges[i]}: ${fmt.format(b)} before, ${fmt.format(after[i])} after">` +
        `<div class="col before" style="height:${height(b)}%"></div>` +
        `<div class="col after" style="height:${height(after[i])}%"></div>` +
        `<span class="tick">${labels[i]}</span></div>`,
    )
    .join('');
  el.dataset.before = JSON.stringify(before);
  el.dataset.after = JSON.stringify(after);
}

function showHistogram(histogram) {
  drawHistogram(
    $('histogram'),
    histogram,
    (i) => rampColor(i * 5 + 2.5),
    (i) => `${i * 5}°`,
    3,
  );
}

function drawHistogram(el, counts, colorOf, tickOf, tickEvery = 1) {
  const max = Math.max(1, ...counts);
  const n = counts.length;
  el.innerHTML = counts
    .map((c, i) => {
      const h = c > 0 ? Math.max(2, (Math.sqrt(c) / Math.sqrt(max)) * 100) : 0;
      const tick = i % tickEvery === 0 ? `<span class="tick" style="left:0">${tickOf(i)}</span>` : '';
      return `<div class="col" title="${tickOf(i)}: ${fmt.format(c)}" style="height:${h.toFixed(1)}%;background:${css(colorOf(i))}">${tick}</div>`;
    })
    .join('');
  el.dataset.counts = JSON.stringify(counts);
  void n;
}

const WHERE = [
  ['file', 'file'],
  ['line', 'line'],
  ['record', 'record'],
  ['facet', 'facet'],
  ['otherFacet', 'other facet'],
  ['vertex', 'vertex'],
];

function showError(e, name) {
  const isCdt = e && typeof e.code === 'string';
  const error = isCdt
    ? { code: e.code, message: e.message, file: e.file, line: e.line, record: e.record, facet: e.facet, otherFacet: e.otherFacet, vertex: e.vertex, facets: e.facets }
    : { code: 'page', message: String(e?.message ?? e) };
  demo.error = error;
  $('error-title').textContent = `Cannot mesh ${name}${isCdt ? ` (${e.code})` : ''}`;
  $('error-message').textContent = error.message;
  const where = WHERE.filter(([k]) => (k === 'file' ? !!error[k] : Number.isInteger(error[k]) && error[k] >= 0));
  $('error-where').innerHTML = '';
  for (const [k, label] of where) {
    const dt = document.createElement('dt');
    dt.textContent = label;
    const dd = document.createElement('dd');
    dd.textContent = String(error[k]);
    $('error-where').append(dt, dd);
  }
  // Facets named by the error, in red on the input surface.
  const named = new Set();
  if (Array.isArray(error.facets)) for (const f of error.facets) if (f >= 0) named.add(f);
  if (error.facet >= 0) named.add(error.facet);
  if (error.otherFacet >= 0) named.add(error.otherFacet);
  const surface = e?.surface ?? current?.surface ?? null;
  let hint = '';
  if (named.size > 0 && surface) {
    demo.highlighted = showSurface(surface, named);
    const list = [...named].sort((a, b) => a - b);
    hint = `Facet${list.length === 1 ? '' : 's'} ${list.slice(0, 12).join(', ')}${list.length > 12 ? '…' : ''} highlighted in red.`;
  } else if (named.size > 0) {
    hint = 'The input surface could not be read, so the facets cannot be shown.';
  }
  $('error-hint').textContent = hint;
  $('error-hint').hidden = !hint;
  $('repair').hidden = !(REPAIRABLE.has(error.code) && current?.source && !current.source.repair);
  $('fill-holes').hidden = !(error.code === 'open-boundary' && current?.source && !current.source.fillHoles);
  // Parts passing through one another: their union by default, or each
  // part and each overlap a region of its own.
  $('repair-parts').hidden = !(error.code === 'self-intersection' && current?.source && !current.source.repair);
  // Validation needs about half as much heap again as meshing: a model over
  // the limit with it may fit without.
  $('no-validate').hidden = !(error.code === 'too-large' && current?.source && $('opt-validate').checked);
  $('error').hidden = false;
  $('model-status').textContent = `Error: ${error.code}`;
}

// Errors that repair can fix: the error panel offers "Repair and mesh".
const REPAIRABLE = new Set(['self-intersection', 'duplicate', 'degenerate', 'nonplanar']);

$('repair').addEventListener('click', () => {
  if (current?.source) openModel({ ...current.source, repair: true });
});
$('repair-parts').addEventListener('click', () => {
  if (current?.source) openModel({ ...current.source, repair: true, partsAsRegions: true });
});
$('no-validate').addEventListener('click', () => {
  $('opt-validate').checked = false;
  if (current?.source) openModel(current.source);
});
// An open surface: "Fill holes and mesh" closes its holes, then repairs.
$('fill-holes').addEventListener('click', () => {
  if (current?.source) openModel({ ...current.source, repair: true, fillHoles: true });
});

// What repair changed, counts per kind, and the changed input facets in red
// on the (ghosted) input surface.
const REPAIR_ROWS = [
  ['weldedPoints', 'welded points'],
  ['duplicateFacets', 'duplicate facets dropped'],
  ['degenerateFacets', 'zero-area facets dropped'],
  ['zeroAreaPolygons', 'zero-area polygons dropped'],
  ['repeatedVertices', 'repeated vertices dropped'],
  ['filledHoles', 'holes filled'],
  ['fillTriangles', 'triangles filling them'],
  ['fillPoints', 'points added filling them'],
  ['nonplanarFacets', 'non-planar facets split'],
  ['tjunctionVertices', 'T-junction vertices'],
  ['crossingPairs', 'crossing facet pairs'],
  ['intersectionPoints', 'new intersection points'],
  ['crossingSegments', 'segments crossing or touching'],
  ['innerFacets', 'facets inside the union dropped'],
  ['outsideFacets', 'fins outside the model dropped'],
  ['parts', 'parts kept as regions'],
];

function showRepair(report) {
  demo.repair = report;
  const rows = $('repair-rows');
  rows.innerHTML = '';
  for (const [key, label] of REPAIR_ROWS) {
    if (key === 'parts' && !report.parts) continue;
    const tr = document.createElement('tr');
    tr.dataset.kind = key;
    const a = document.createElement('td');
    a.textContent = label;
    const b = document.createElement('td');
    b.textContent = fmt.format(report[key]);
    tr.append(a, b);
    rows.append(tr);
  }
  const changed = new Set(report.changedFacets);
  let shown = 0;
  if (changed.size > 0 && current?.surface) shown = showSurface(current.surface, changed);
  demo.highlighted = shown;
  $('repair-changed').textContent = report.changed
    ? `${fmt.format(changed.size)} input facets changed${shown > 0 ? ' (in red)' : ''}.`
    : 'Nothing to change: the model was valid.';
  $('repair-report').hidden = false;
}

function showNotice(text) {
  const n = $('notice');
  n.textContent = text;
  n.hidden = false;
}

function updateVisibleCount() {
  if (!current?.built) {
    $('visible-count').textContent = '';
    return;
  }
  const total = current.built.quality.length;
  const shown = viewer.visibleTets();
  $('visible-count').textContent = `${fmt.format(shown)} of ${fmt.format(total)} tets shown`;
  $('visible-count').dataset.visible = String(shown);
}

// ---------------------------------------------------------------- controls

function applyViewControls() {
  viewer.setShrink(Number($('shrink').value) / 100);
  viewer.setShowSurface($('show-surface').checked);
  viewer.setShowSteiner($('show-steiner').checked);
  viewer.setShowConstrained($('show-constrained').checked);
  viewer.setShowEdges($('show-edges').checked);
  viewer.setCut({ cut: Number($('cut').value) / 1000 });
  updateVisibleCount();
}

$('cut').addEventListener('input', () => {
  viewer.setCut({ cut: Number($('cut').value) / 1000 });
  updateVisibleCount();
});
$('shrink').addEventListener('input', () => viewer.setShrink(Number($('shrink').value) / 100));
$('show-surface').addEventListener('change', (e) => viewer.setShowSurface(e.target.checked));
$('show-steiner').addEventListener('change', (e) => viewer.setShowSteiner(e.target.checked));
$('show-constrained').addEventListener('change', (e) => viewer.setShowConstrained(e.target.checked));
$('show-edges').addEventListener('change', (e) => viewer.setShowEdges(e.target.checked));
$('fit').addEventListener('click', () => viewer.fitView());

// Up axis, remembered between visits (storage may be unavailable).
const UP_KEY = 'cdt3d.up';
function storedUp() {
  try {
    return localStorage.getItem(UP_KEY) === 'y' ? 'y' : 'z';
  } catch {
    return 'z';
  }
}
function showUp(up) {
  $('up-axis').value = up;
  if (viewer.up !== up) viewer.setUp(up);
}
showUp(storedUp());
// A choice made by hand is remembered (a sample's own axis is not).
$('up-axis').addEventListener('change', () => {
  const up = $('up-axis').value;
  try {
    localStorage.setItem(UP_KEY, up);
  } catch {}
  viewer.setUp(up);
});

// Steiner points: thousands of markers hide the mesh, so beyond
// STEINER_MANY 'auto' shows those near the cut plane only, and says so.
function updateSteinerNote() {
  const n = viewer.steinerCount();
  const note = $('steiner-note');
  note.hidden = n === 0;
  if (n === 0) return;
  note.textContent =
    viewer.steinerShown() === 'cut'
      ? `${fmt.format(n)} Steiner points: only those within 2% of the cut plane are drawn; move the cut to sweep through them.`
      : `${fmt.format(n)} Steiner points drawn${n > STEINER_MANY ? ' (they hide the mesh: try "near the cut plane")' : ''}.`;
  note.dataset.shown = viewer.steinerShown();
}
$('steiner-mode').addEventListener('change', () => {
  viewer.setSteinerMode($('steiner-mode').value);
  updateSteinerNote();
});
$('color-mode').addEventListener('change', async () => {
  const built = current?.built;
  if (!built) return;
  const mode = $('color-mode').value;
  const colors = await tetColors(built, mode);
  // Only the latest choice for the model still shown.
  if (current?.built === built && $('color-mode').value === mode) {
    viewer.setTetColors(colors);
    showLegend();
  }
});
for (const b of $('cut-axis').querySelectorAll('button[data-axis]')) {
  b.addEventListener('click', () => {
    for (const o of $('cut-axis').querySelectorAll('button[data-axis]')) o.classList.toggle('on', o === b);
    viewer.setCut({ axis: Number(b.dataset.axis) });
    requestOrder();
    updateVisibleCount();
  });
}
$('cut-flip').addEventListener('click', () => {
  viewer.setCut({ flip: !viewer.flip });
  $('cut-flip').classList.toggle('on', viewer.flip);
  requestOrder();
  updateVisibleCount();
});

// The `quality` option from the controls: null when the box is unchecked;
// empty fields are left to the defaults. Values are checked by the core: a
// bad one comes back as an "invalid-argument" error naming it.
function qualityOption() {
  if (!$('opt-quality').checked) return null;
  const quality = {};
  for (const [id, key] of [['opt-radius-edge', 'radiusEdge'], ['opt-max-volume', 'maxVolume'], ['opt-min-dihedral', 'minDihedral']]) {
    const text = $(id).value.trim();
    if (text !== '') quality[key] = Number(text);
  }
  return quality;
}

function syncQualityControls() {
  const on = $('opt-quality').checked;
  $('quality-controls').classList.toggle('off', !on);
  for (const id of ['opt-radius-edge', 'opt-max-volume', 'opt-min-dihedral']) $(id).disabled = !on;
}
$('opt-quality').addEventListener('change', syncQualityControls);
syncQualityControls();

$('cancel').addEventListener('click', () => job?.controller.abort());
$('remesh').addEventListener('click', () => current?.source && openModel(current.source));

// Samples.
const sampleSelect = $('sample');
sampleSelect.innerHTML =
  '<option value="" disabled>choose…</option>' +
  SAMPLES.map((s) => `<option value="${s.file}">${s.label}</option>`).join('');
sampleSelect.value = DEFAULT_SAMPLE;
sampleSelect.addEventListener('change', () => {
  if (sampleSelect.value) openModel({ sample: sampleSelect.value });
});

// File picker.
$('file').addEventListener('change', (e) => {
  const file = e.target.files?.[0];
  if (file) {
    sampleSelect.value = '';
    openModel({ file });
  }
  e.target.value = '';
});

// Drag and drop anywhere on the page.
let dragDepth = 0;
window.addEventListener('dragenter', (e) => {
  if (!e.dataTransfer?.types?.includes('Files')) return;
  e.preventDefault();
  dragDepth++;
  $('drop').hidden = false;
});
window.addEventListener('dragover', (e) => {
  if (e.dataTransfer?.types?.includes('Files')) e.preventDefault();
});
window.addEventListener('dragleave', () => {
  dragDepth = Math.max(0, dragDepth - 1);
  if (dragDepth === 0) $('drop').hidden = true;
});
window.addEventListener('drop', (e) => {
  e.preventDefault();
  dragDepth = 0;
  $('drop').hidden = true;
  const file = e.dataTransfer?.files?.[0];
  if (file) {
    sampleSelect.value = '';
    openModel({ file });
  }
});

// Downloads (written by the worker: the main thread stays free).
for (const b of $('downloads').querySelectorAll('button[data-format]')) {
  b.addEventListener('click', async () => {
    if (!current?.result) return;
    const format = b.dataset.format;
    b.disabled = true;
    try {
      // A string for the text formats, bytes for msh, msh-binary and vtu.
      const data = await mesher.write(current.result, format);
      const base = current.name.replace(/\.[^.]*$/, '') || 'mesh';
      const type = typeof data === 'string' ? 'text/plain' : 'application/octet-stream';
      const url = URL.createObjectURL(new Blob([data], { type }));
      const a = document.createElement('a');
      a.href = url;
      a.download = `${base}.${format === 'msh-binary' ? 'msh' : format}`;
      document.body.append(a);
      a.click();
      a.remove();
      setTimeout(() => URL.revokeObjectURL(url), 10_000);
    } catch (e) {
      showNotice(`Could not write .${format}: ${e.message}`);
    } finally {
      b.disabled = false;
    }
  });
}

document.documentElement.style.setProperty('--s1', css(STEINER_COLORS[1]));
document.documentElement.style.setProperty('--s2', css(STEINER_COLORS[2]));
document.documentElement.style.setProperty('--s3', css(STEINER_COLORS[3]));
document.documentElement.style.setProperty('--bg', `#${BACKGROUND.toString(16).padStart(6, '0')}`);

// The default sample, meshed on arrival (?model=<sample> picks another, ?model= none).
const wanted = new URLSearchParams(location.search).get('model');
const first = wanted === null ? DEFAULT_SAMPLE : wanted;
if (first && SAMPLES.some((s) => s.file === first)) {
  sampleSelect.value = first;
  // After the renderer's start-up work (context, shader programs), so that
  // none of it competes with the first job.
  viewer.ready.then(() => {
    if (jobSeq === 0) openModel({ sample: first });
  });
} else {
  sampleSelect.value = '';
}
