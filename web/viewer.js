// three.js view of a cdt3d result: the input surface, the tetrahedra as one
// merged indexed BufferGeometry (4 vertices per tet, shrink and flat shading
// in the shaders), Steiner points, and a cut along one axis that keeps the
// tetrahedra crossing it whole (the tets are pre-sorted along the axis, so a
// cut is just a draw range: nothing is rebuilt while the slider moves).
// Model coordinates stay as they are; the model group is turned so that the
// chosen up axis (Z or Y) points up on screen, and the clipping planes,
// which three.js takes in world coordinates, are turned with it.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

export const BACKGROUND = 0x1b1f27;

const TET_VERTEX = /* glsl */ `
uniform float shrink;
in vec3 center;
in vec4 color;
out vec3 vViewPos;
flat out vec4 vColor;
flat out int vFace;
out vec4 vBary;
void main() {
  vec3 p = center + shrink * (position - center);
  vec4 mv = modelViewMatrix * vec4(p, 1.0);
  vViewPos = mv.xyz;
  vColor = color;
  int j = gl_VertexID % 4;
  vFace = (j + 3) % 4;
  vBary = vec4(j == 0, j == 1, j == 2, j == 3);
  gl_Position = projectionMatrix * mv;
}`;

const TET_FRAGMENT = /* glsl */ `
precision highp float;
uniform vec3 constrainedColor;
uniform float showConstrained;
uniform float edges;
in vec3 vViewPos;
flat in vec4 vColor;
flat in int vFace;
in vec4 vBary;
out vec4 outColor;
void main() {
  vec3 n = normalize(cross(dFdx(vViewPos), dFdy(vViewPos)));
  vec3 base = (vColor.a > 0.5 && showConstrained > 0.5) ? constrainedColor : vColor.rgb;
  // Headlight plus a little light from above.
  vec3 l1 = normalize(-vViewPos);
  float diffuse = 0.62 * abs(dot(n, l1)) + 0.22 * max(dot(n, normalize(vec3(0.3, 1.0, 0.4))), 0.0);
  vec3 c = base * (0.28 + diffuse);
  // Edges: the distance to the nearest edge of this face is the smallest
  // barycentric coordinate other than the one of the opposite vertex.
  if (edges > 0.5) {
    float d = 1e9;
    float w = 0.0;
    for (int k = 0; k < 4; k++) {
      if (k == vFace) continue;
      float fw = fwidth(vBary[k]);
      d = min(d, vBary[k] / max(fw, 1e-6));
      w = max(w, fw);
    }
    // Fade the lines out where faces are only a few pixels wide.
    float strength = 0.55 * (1.0 - smoothstep(0.12, 0.35, w));
    c = mix(c, c * 0.35, strength * (1.0 - smoothstep(0.4, 1.3, d)));
  }
  outColor = vec4(pow(c, vec3(1.0 / 2.2)), 1.0);
}`;

const SURFACE_VERTEX = /* glsl */ `
out vec3 vViewPos;
#include <clipping_planes_pars_vertex>
void main() {
  vec4 mvPosition = modelViewMatrix * vec4(position, 1.0);
  vViewPos = mvPosition.xyz;
  gl_Position = projectionMatrix * mvPosition;
  #include <clipping_planes_vertex>
}`;

const SURFACE_FRAGMENT = /* glsl */ `
precision highp float;
uniform float opacity;
uniform vec3 baseColor;
in vec3 vViewPos;
out vec4 outColor;
#include <clipping_planes_pars_fragment>
void main() {
  #include <clipping_planes_fragment>
  vec3 n = normalize(cross(dFdx(vViewPos), dFdy(vViewPos)));
  vec3 l1 = normalize(-vViewPos);
  float diffuse = 0.65 * abs(dot(n, l1)) + 0.2 * max(dot(n, normalize(vec3(0.3, 1.0, 0.4))), 0.0);
  vec3 c = baseColor * (0.3 + diffuse);
  outColor = vec4(pow(c, vec3(1.0 / 2.2)), opacity);
}`;

// Bytes uploaded to the GPU per task (see upload()).
const UPLOAD_BYTES = 1 << 20;

// Marker size in pixels, and the count beyond which 'auto' shows only the
// points near the cut plane.
const STEINER_SIZE_MAX = 5;
export const STEINER_MANY = 1000;

export const STEINER_COLORS = {
  1: [1.0, 0.84, 0.1], // on a segment
  2: [0.15, 0.85, 1.0], // on a facet
  3: [1.0, 0.25, 0.85], // in the volume
};

export class Viewer {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: false, powerPreference: 'high-performance' });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.setClearColor(BACKGROUND, 1);
    this.renderer.localClippingEnabled = true;
    container.appendChild(this.renderer.domElement);
    this.canvas = this.renderer.domElement;

    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.enableDamping = true;
    this.controls.dampingFactor = 0.15;
    this.controls.addEventListener('change', () => this.requestRender());

    this.model = new THREE.Group(); // everything of the current model, relative to its origin
    this.scene.add(this.model);

    // Cut: keep the side below `cutValue` on `axis` (or above when flipped).
    this.axis = 0;
    this.flip = false;
    this.cut = 1; // fraction of the extent along the axis
    this.extent = [new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1)];
    this.keepPlane = new THREE.Plane(new THREE.Vector3(-1, 0, 0), 0);
    this.ghostPlane = new THREE.Plane(new THREE.Vector3(1, 0, 0), 0);
    // Steiner points near the cut only: the far side of a slab on the kept side.
    this.slabPlane = new THREE.Plane(new THREE.Vector3(1, 0, 0), 0);
    this.up = 'y';

    this.surface = null;
    this.surfaceHighlighted = 0;
    this.tets = null; // {mesh, buffers, keys, axis, flip, count, visible}
    this.generation = 0; // bumped by clear() and setTets(): older uploads stop
    this.steiner = null;
    this.showSurface = true;
    this.surfaceMode = 'ghost'; // 'solid' before/without a mesh, 'ghost' with one
    this.showSteiner = true;
    this.steinerMode = 'auto'; // 'all', 'cut' (near the cut plane), 'auto' (cut when many)
    this.frames = 0;
    this.needsRender = true;

    this.tetMaterial = new THREE.ShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader: TET_VERTEX,
      fragmentShader: TET_FRAGMENT,
      uniforms: {
        shrink: { value: 1 },
        constrainedColor: { value: new THREE.Color(0xff9a3c) },
        showConstrained: { value: 1 },
        edges: { value: 1 },
      },
      side: THREE.FrontSide,
    });

    const surfaceMaterial = (color, opacity, transparent, clip) =>
      new THREE.ShaderMaterial({
        glslVersion: THREE.GLSL3,
        vertexShader: SURFACE_VERTEX,
        fragmentShader: SURFACE_FRAGMENT,
        uniforms: { opacity: { value: opacity }, baseColor: { value: new THREE.Color(...color) } },
        clipping: true,
        clippingPlanes: clip ? [this.ghostPlane] : [],
        transparent,
        depthWrite: !transparent,
        side: THREE.DoubleSide,
      });
    const grey = [0.6, 0.63, 0.68];
    this.surfaceMaterials = {
      solid: surfaceMaterial(grey, 1, false, false), // the input surface alone
      highlight: surfaceMaterial(grey, 0.3, true, false), // translucent, over the red facets
      red: surfaceMaterial([1.0, 0.06, 0.04], 1, false, false), // facets named by an error
      ghost: surfaceMaterial([0.62, 0.72, 0.88], 0.1, true, true), // faint, on the side removed by the cut
    };
    this.surfaceMaterials.ghost.side = THREE.FrontSide;
    this.pointsMaterial = new THREE.PointsMaterial({
      size: STEINER_SIZE_MAX,
      sizeAttenuation: false,
      vertexColors: true,
      map: dotTexture(),
      alphaTest: 0.5,
      depthTest: false,
      clippingPlanes: [this.keepPlane],
    });
    this.ready = this.warmUp();

    const resize = () => {
      const w = Math.max(1, container.clientWidth);
      const h = Math.max(1, container.clientHeight);
      this.renderer.setSize(w, h, false);
      this.canvas.style.width = '100%';
      this.canvas.style.height = '100%';
      this.camera.aspect = w / h;
      this.camera.updateProjectionMatrix();
      this.requestRender();
    };
    new ResizeObserver(resize).observe(container);
    resize();

    const loop = () => {
      requestAnimationFrame(loop);
      this.controls.update(); // damping; dispatches 'change' when the view moves
      if (this.needsRender && this.warm) {
        this.needsRender = false;
        this.renderer.render(this.scene, this.camera);
        this.frames++;
      }
    };
    requestAnimationFrame(loop);
  }

  /**
   * Compiles every shader program up front, so that no compile lands in a
   * frame later: a first compile can take hundreds of ms with a software
   * renderer. Rendering starts once they are ready.
   */
  async warmUp() {
    this.warm = false;
    const scene = new THREE.Scene();
    const tri = new THREE.BufferGeometry();
    tri.setAttribute('position', new THREE.BufferAttribute(new Float32Array(9), 3));
    tri.setAttribute('color', new THREE.BufferAttribute(new Float32Array(12), 4));
    tri.setAttribute('center', new THREE.BufferAttribute(new Float32Array(9), 3));
    for (const m of [this.tetMaterial, ...Object.values(this.surfaceMaterials)]) scene.add(new THREE.Mesh(tri, m));
    const pts = new THREE.BufferGeometry();
    pts.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3), 3));
    pts.setAttribute('color', new THREE.BufferAttribute(new Float32Array(3), 3));
    scene.add(new THREE.Points(pts, this.pointsMaterial));
    // The points' program with the slab's second clipping plane (Steiner
    // points near the cut) is another program: compiled now too.
    const slabbed = this.pointsMaterial.clone();
    slabbed.clippingPlanes = [this.keepPlane, this.slabPlane];
    scene.add(new THREE.Points(pts, slabbed));
    try {
      await this.renderer.compileAsync(scene, this.camera);
      // compileAsync waits for the programs only with KHR_parallel_shader_compile
      // (Chromium on SwiftShader has none): otherwise the first frame that uses
      // a program blocks the main thread on its link (a long stall in headless
      // Chromium while the model is meshing). So: a fence polled between tasks tells when the GPU process
      // has got through the compiles, and only then does each program's first
      // use (a synchronous query) run, one per task, before the first job.
      if (!this.renderer.extensions.has('KHR_parallel_shader_compile')) {
        await gpuDone(this.renderer.getContext());
        for (const program of [...this.renderer.info.programs]) {
          await nextTask();
          program.getUniforms(); // the first use: three.js reads the link status and uniforms
          program.getAttributes();
        }
      }
      // The Steiner points' sprite: uploaded now, not in the first frame of a mesh.
      await nextTask();
      this.renderer.initTexture(this.pointsMaterial.map);
    } catch {
      // Programs then compile on first use.
    }
    this.warm = true;
    this.requestRender();
  }

  requestRender() {
    this.needsRender = true;
  }

  /** Removes the current model. */
  clear() {
    // Geometries only: the materials (and their compiled programs) are kept.
    for (const part of ['surface', 'steiner']) {
      if (this[part]) {
        this.model.remove(this[part]);
        this[part].geometry.dispose();
        for (const child of this[part].children) child.geometry.dispose();
        this[part] = null;
      }
    }
    this.generation++; // uploads under way are dropped
    this.removeTets();
    this.requestRender();
  }

  /**
   * The input surface: `points` (xyz, relative to `origin` applied here),
   * `triangles`, `triangleFacets`. Triangles of facets in `highlight` are red.
   */
  setSurface({ points, triangles, triangleFacets }, origin, highlight = null) {
    if (this.surface) {
      this.model.remove(this.surface);
      this.surface.geometry.dispose();
      for (const child of this.surface.children) child.geometry.dispose();
      this.surface = null;
    }
    // Indexed, straight from the arrays (flat normals come from the shader).
    const np = points.length / 3;
    const pos = new Float32Array(np * 3);
    for (let i = 0; i < np; i++) {
      pos[3 * i] = points[3 * i] - origin[0];
      pos[3 * i + 1] = points[3 * i + 1] - origin[1];
      pos[3 * i + 2] = points[3 * i + 2] - origin[2];
    }
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    g.setIndex(new THREE.BufferAttribute(triangles instanceof Uint32Array ? triangles : Uint32Array.from(triangles), 1));
    g.boundingSphere = new THREE.Sphere(new THREE.Vector3(), Infinity);
    this.surface = new THREE.Mesh(g, this.surfaceMaterials.solid);
    this.surface.frustumCulled = false;
    this.surface.renderOrder = 2;
    // Triangles of the facets named by an error: an opaque red overlay.
    let highlighted = 0;
    if (highlight && highlight.size > 0 && triangleFacets) {
      const red = [];
      for (let t = 0; t < triangles.length / 3; t++) {
        if (highlight.has(triangleFacets[t])) red.push(triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]);
      }
      highlighted = red.length / 3;
      if (highlighted > 0) {
        const rg = new THREE.BufferGeometry();
        rg.setAttribute('position', g.getAttribute('position'));
        rg.setIndex(red);
        const overlay = new THREE.Mesh(rg, this.surfaceMaterials.red);
        overlay.frustumCulled = false;
        overlay.renderOrder = 1;
        this.surface.add(overlay);
      }
    }
    this.surfaceHighlighted = highlighted;
    this.model.add(this.surface);
    this.setSurfaceMode(this.tets ? 'ghost' : 'solid');
    this.requestRender();
    return highlighted;
  }

  setSurfaceMode(mode) {
    this.surfaceMode = mode;
    if (!this.surface) return;
    const ghost = mode === 'ghost';
    const m = this.surfaceMaterials;
    this.surface.material = ghost ? m.ghost : this.surfaceHighlighted > 0 ? m.highlight : m.solid;
    this.surface.visible = ghost ? this.showSurface : true;
    this.requestRender();
  }

  /**
   * The tetrahedra from the geometry worker's arrays; `colors` is a
   * Uint8Array (4 per vertex: rgb and the constrained flag). Resolves once
   * they are on the GPU and shown; false if the view was cleared meanwhile.
   */
  async setTets({ position, center, colors, order }) {
    const generation = ++this.generation;
    const buffers = [];
    const stale = () => generation !== this.generation;
    const attributes = [];
    for (const [array, size, target] of [
      [position, 3, 'ARRAY_BUFFER'],
      [center, 3, 'ARRAY_BUFFER'],
      [order.index, 1, 'ELEMENT_ARRAY_BUFFER'],
    ]) {
      const attribute = await this.upload(array, size, target, stale);
      if (attribute === null) break;
      buffers.push(attribute.buffer);
      attributes.push(attribute);
    }
    // The first draw would otherwise wait for the GPU process to take in
    // the uploads (hundreds of ms with a software GPU): wait between tasks.
    if (!stale()) await gpuDone(this.renderer.getContext());
    if (stale()) {
      this.deleteBuffers(buffers);
      return false;
    }
    this.removeTets();
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', attributes[0]);
    g.setAttribute('center', attributes[1]);
    g.setAttribute('color', new THREE.BufferAttribute(colors, 4, true));
    g.setIndex(attributes[2]);
    g.boundingSphere = new THREE.Sphere(new THREE.Vector3(), Infinity);
    const mesh = new THREE.Mesh(g, this.tetMaterial);
    mesh.frustumCulled = false;
    mesh.renderOrder = 1;
    this.tets = { mesh, buffers, keys: order.keys, axis: order.axis, flip: order.flip, count: position.length / 12 };
    this.model.add(mesh);
    this.setSurfaceMode('ghost');
    this.applyCut();
    return true;
  }

  /**
   * A GL buffer holding `array`, filled a slice per task (UPLOAD_BYTES each),
   * as a three.js GLBufferAttribute: one upload of the tens of megabytes a
   * large mesh has blocks the main thread for hundreds of milliseconds with
   * a software GPU. null (and no buffer) once `stale()` says the view moved on.
   */
  async upload(array, itemSize, target, stale) {
    const gl = this.renderer.getContext();
    const buffer = gl.createBuffer();
    const step = Math.max(itemSize, Math.floor(UPLOAD_BYTES / array.BYTES_PER_ELEMENT / itemSize) * itemSize);
    for (let offset = 0; offset < array.length || offset === 0; offset += step) {
      // No vertex array object of three.js bound while an element buffer is
      // bound (it would take the binding); resetState() tells three.js that
      // its cached GL state is gone.
      this.renderer.resetState();
      gl.bindBuffer(gl[target], buffer);
      if (offset === 0) gl.bufferData(gl[target], array.byteLength, gl.STATIC_DRAW);
      if (array.length > 0) gl.bufferSubData(gl[target], offset * array.BYTES_PER_ELEMENT, array, offset, Math.min(step, array.length - offset));
      gl.bindBuffer(gl[target], null);
      this.renderer.resetState();
      // The next slice only once the GPU process has taken this one: with
      // its transfer buffer full, a bufferSubData call blocks the main
      // thread until there is room.
      await gpuDone(gl);
      if (stale()) {
        gl.deleteBuffer(buffer);
        return null;
      }
    }
    const type = array instanceof Float32Array ? gl.FLOAT : gl.UNSIGNED_INT;
    return new THREE.GLBufferAttribute(buffer, type, itemSize, array.BYTES_PER_ELEMENT, array.length / itemSize);
  }

  deleteBuffers(buffers) {
    const gl = this.renderer.getContext();
    for (const b of buffers) gl.deleteBuffer(b);
  }

  removeTets() {
    if (!this.tets) return;
    this.model.remove(this.tets.mesh);
    this.tets.mesh.geometry.dispose();
    this.deleteBuffers(this.tets.buffers);
    this.tets = null;
  }

  /** New colours for the tets (same layout as in setTets). */
  setTetColors(colors) {
    if (!this.tets) return;
    const attr = this.tets.mesh.geometry.getAttribute('color');
    attr.array.set(colors);
    attr.needsUpdate = true;
    this.requestRender();
  }

  /** A new order of the tets for another axis or side (from the geometry worker). */
  async setOrder(order) {
    const tets = this.tets;
    if (!tets) return;
    // Uploads of two orders can overlap (the user turned the cut twice); the
    // older one must not land last, or the tets keep the older order.
    const seq = (this.orderSeq = (this.orderSeq ?? 0) + 1);
    const index = await this.upload(order.index, 1, 'ELEMENT_ARRAY_BUFFER', () => this.tets !== tets || this.orderSeq !== seq);
    if (index === null) return;
    const g = tets.mesh.geometry;
    const old = g.index;
    g.setIndex(index);
    this.deleteBuffers([old.buffer]);
    tets.buffers = tets.buffers.map((b) => (b === old.buffer ? index.buffer : b));
    tets.keys = order.keys;
    tets.axis = order.axis;
    tets.flip = order.flip;
    this.applyCut();
  }

  setSteiner(positions, kinds) {
    if (this.steiner) {
      this.model.remove(this.steiner);
      this.steiner.geometry.dispose();
      this.steiner = null;
    }
    const n = kinds.length;
    if (n === 0) return;
    const col = new Float32Array(n * 3);
    for (let i = 0; i < n; i++) col.set(STEINER_COLORS[kinds[i]] ?? [1, 1, 1], 3 * i);
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    g.setAttribute('color', new THREE.BufferAttribute(col, 3));
    g.computeBoundingSphere();
    this.steiner = new THREE.Points(g, this.pointsMaterial);
    this.steiner.renderOrder = 3;
    this.steiner.visible = this.showSteiner;
    this.model.add(this.steiner);
    this.applySteinerMode();
  }

  /** Count of the Steiner points of the model shown (0 without one). */
  steinerCount() {
    return this.steiner ? this.steiner.geometry.getAttribute('position').count : 0;
  }

  /**
   * 'all', 'cut' (only the points within a thin slab at the cut plane) or
   * 'auto' ('cut' beyond STEINER_MANY points, whose markers would otherwise
   * hide the mesh). Markers shrink as their number grows.
   */
  setSteinerMode(mode) {
    this.steinerMode = mode;
    this.applySteinerMode();
  }

  /** The mode in effect for the current points: 'all' or 'cut'. */
  steinerShown() {
    if (this.steinerMode !== 'auto') return this.steinerMode;
    return this.steinerCount() > STEINER_MANY ? 'cut' : 'all';
  }

  applySteinerMode() {
    const n = this.steinerCount();
    // 5 px up to a few hundred points, down to 2 px for tens of thousands.
    const size = n <= 300 ? STEINER_SIZE_MAX : Math.max(2, STEINER_SIZE_MAX * Math.sqrt(300 / n) * 1.6);
    this.pointsMaterial.size = Math.min(STEINER_SIZE_MAX, Math.round(size * 2) / 2);
    const planes = this.steinerShown() === 'cut' ? [this.keepPlane, this.slabPlane] : [this.keepPlane];
    if (this.pointsMaterial.clippingPlanes.length !== planes.length) {
      this.pointsMaterial.clippingPlanes = planes;
      this.pointsMaterial.needsUpdate = true; // another number of planes: another program
    }
    this.requestRender();
  }

  /**
   * Which model axis points up on screen: 'z' (CAD parts and most scans) or
   * 'y'. The camera is framed again.
   */
  setUp(up) {
    this.up = up === 'z' ? 'z' : 'y';
    // -90 degrees about X takes the model's Z to the world's Y (up).
    this.model.rotation.set(this.up === 'z' ? -Math.PI / 2 : 0, 0, 0);
    this.model.updateMatrixWorld(true);
    this.applyCut();
    this.fitView();
  }

  /** Bounds of the model relative to its origin (for the cut and the camera). */
  setExtent(min, max) {
    this.extent = [new THREE.Vector3(...min), new THREE.Vector3(...max)];
    this.applyCut();
  }

  setCut({ axis = this.axis, flip = this.flip, cut = this.cut }) {
    this.axis = axis;
    this.flip = flip;
    this.cut = cut;
    this.applyCut();
  }

  /** Coordinate of the cut along the axis. */
  cutValue() {
    const lo = this.extent[0].getComponent(this.axis);
    const hi = this.extent[1].getComponent(this.axis);
    const pad = (hi - lo) * 1e-4 + 1e-12;
    const f = this.flip ? 1 - this.cut : this.cut;
    return lo - pad + f * (hi - lo + 2 * pad);
  }

  applyCut() {
    const c = this.cutValue();
    const n = new THREE.Vector3();
    n.setComponent(this.axis, this.flip ? 1 : -1);
    // Keep: signed distance >= 0 (three.js clips the negative side).
    this.keepPlane.set(n, this.flip ? -c : c);
    this.ghostPlane.set(n.clone().negate(), this.flip ? c : -c);
    // The slab: within 2% of the extent of the cut, on the kept side.
    const lo = this.extent[0].getComponent(this.axis);
    const hi = this.extent[1].getComponent(this.axis);
    const depth = 0.02 * Math.max(1e-12, hi - lo);
    this.slabPlane.set(n.clone().negate(), (this.flip ? c : -c) + depth);
    for (const plane of [this.keepPlane, this.ghostPlane, this.slabPlane]) plane.applyMatrix4(this.model.matrixWorld);
    if (this.tets) {
      const t = this.tets;
      let visible = 0;
      if (t.axis === this.axis && t.flip === this.flip) {
        // Tets whose key (min coordinate, or minus the max when flipped) passes the cut.
        const limit = this.flip ? -c : c;
        let lo = 0;
        let hi = t.keys.length;
        while (lo < hi) {
          const mid = (lo + hi) >>> 1;
          if (t.keys[mid] <= limit) lo = mid + 1;
          else hi = mid;
        }
        visible = lo;
      } else {
        visible = t.visible ?? t.count; // the order for this axis is on its way
      }
      t.visible = visible;
      t.mesh.geometry.setDrawRange(0, visible * 12);
    }
    this.requestRender();
  }

  visibleTets() {
    return this.tets ? this.tets.visible : 0;
  }

  setShrink(s) {
    this.tetMaterial.uniforms.shrink.value = s;
    this.requestRender();
  }

  setShowConstrained(on) {
    this.tetMaterial.uniforms.showConstrained.value = on ? 1 : 0;
    this.requestRender();
  }

  setShowEdges(on) {
    this.tetMaterial.uniforms.edges.value = on ? 1 : 0;
    this.requestRender();
  }

  setShowSurface(on) {
    this.showSurface = on;
    if (this.surface && this.surfaceMode === 'ghost') this.surface.visible = on;
    this.requestRender();
  }

  setShowSteiner(on) {
    this.showSteiner = on;
    if (this.steiner) this.steiner.visible = on;
    this.requestRender();
  }

  /** Frames the model: looks at its bounds from a pleasant oblique direction. */
  fitView() {
    const [lo, hi] = this.extent;
    const centre = lo.clone().add(hi).multiplyScalar(0.5).applyMatrix4(this.model.matrixWorld);
    const radius = Math.max(1e-9, lo.distanceTo(hi) / 2);
    const fov = (this.camera.fov * Math.PI) / 180;
    const fit = Math.min(fov, 2 * Math.atan(Math.tan(fov / 2) * this.camera.aspect));
    const dist = (radius / Math.sin(fit / 2)) * 0.88;
    const dir = new THREE.Vector3(0.9, 0.55, 1.25).normalize();
    this.camera.position.copy(centre).addScaledVector(dir, dist);
    this.camera.near = dist / 100;
    this.camera.far = dist * 10;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
    this.requestRender();
  }

  /** Rotates the view around the target by `radians` (for tests and demos). */
  orbit(radians) {
    const offset = this.camera.position.clone().sub(this.controls.target);
    offset.applyAxisAngle(new THREE.Vector3(0, 1, 0), radians);
    this.camera.position.copy(this.controls.target).add(offset);
    this.camera.lookAt(this.controls.target);
    this.requestRender();
  }

  /**
   * Renders now and reads the pixels back: the fraction of pixels in the
   * central region that differ from the background, and a checksum.
   */
  snapshot() {
    this.renderer.render(this.scene, this.camera);
    const gl = this.renderer.getContext();
    const w = gl.drawingBufferWidth;
    const h = gl.drawingBufferHeight;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    const bg = new THREE.Color(BACKGROUND);
    const br = Math.round(bg.r * 255);
    const bgG = Math.round(bg.g * 255);
    const bb = Math.round(bg.b * 255);
    let differ = 0;
    let total = 0;
    let sum = 0;
    for (let y = Math.floor(h * 0.3); y < Math.floor(h * 0.7); y++) {
      for (let x = Math.floor(w * 0.3); x < Math.floor(w * 0.7); x++) {
        const o = 4 * (y * w + x);
        total++;
        if (Math.abs(px[o] - br) + Math.abs(px[o + 1] - bgG) + Math.abs(px[o + 2] - bb) > 24) differ++;
      }
    }
    for (let i = 0; i < px.length; i += 4) sum = (sum * 31 + px[i] + 3 * px[i + 1] + 7 * px[i + 2]) >>> 0;
    return { width: w, height: h, centreCoverage: differ / Math.max(1, total), checksum: sum };
  }
}

/** Resolves in a later task (the main thread can paint and take input in between). */
export function nextTask() {
  return new Promise((resolve) => setTimeout(resolve, 0));
}

// Resolves once the GPU has run every command issued so far, polling a fence
// between tasks (a blocking query would stall the main thread instead).
async function gpuDone(gl, timeoutMs = 10_000) {
  const sync = gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0);
  if (!sync) return;
  gl.flush();
  const t0 = performance.now();
  try {
    while (gl.getSyncParameter(sync, gl.SYNC_STATUS) !== gl.SIGNALED && performance.now() - t0 < timeoutMs) {
      await new Promise((resolve) => setTimeout(resolve, 10));
    }
  } finally {
    gl.deleteSync(sync);
  }
}

let dot = null;
function dotTexture() {
  if (dot) return dot;
  const c = document.createElement('canvas');
  c.width = c.height = 32;
  const ctx = c.getContext('2d');
  ctx.fillStyle = '#fff';
  ctx.beginPath();
  ctx.arc(16, 16, 14, 0, Math.PI * 2);
  ctx.fill();
  ctx.lineWidth = 3;
  ctx.strokeStyle = '#222';
  ctx.stroke();
  dot = new THREE.CanvasTexture(c);
  return dot;
}
