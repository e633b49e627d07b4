/* rove view: shows a scene written by rove (glTF 2.0 binary with extras.rove
 * metadata) with three.js: orbit/pan/zoom, layer toggles, point size, colour
 * modes, a time slider, picking, and a level of detail for large clouds.
 * Needs THREE, THREE.GLTFLoader and THREE.OrbitControls. */
(function () {
  'use strict';

  var RAMP = 'vec3 ramp(float t) {\n' +
    '  t = clamp(t, 0.0, 1.0) * 4.0;\n' +
    '  vec3 c0 = vec3(0.15, 0.25, 0.95), c1 = vec3(0.0, 0.85, 0.95), c2 = vec3(0.1, 0.85, 0.2),\n' +
    '       c3 = vec3(0.98, 0.9, 0.1), c4 = vec3(0.9, 0.15, 0.1);\n' +
    '  if (t < 1.0) return mix(c0, c1, t);\n' +
    '  if (t < 2.0) return mix(c1, c2, t - 1.0);\n' +
    '  if (t < 3.0) return mix(c2, c3, t - 2.0);\n' +
    '  return mix(c3, c4, t - 3.0);\n' +
    '}\n';

  // Only attributes the geometry has are declared: three.js leaves a missing
  // one's array state behind for the objects drawn next.
  var POINT_VERTEX = [
    '#ifdef HAS_COLOR',
    'attribute vec4 color;',
    '#endif',
    '#ifdef HAS_INTENSITY',
    'attribute float _intensity;',
    '#endif',
    'uniform float size;',
    'uniform int mode;',
    'uniform vec2 zrange;',
    'uniform vec3 up;',
    'uniform vec2 irange;',
    'uniform vec3 base;',
    'varying vec3 vColor;',
    RAMP,
    'void main() {',
    '  gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);',
    '  gl_PointSize = size;',
    '  vColor = base;',
    '#ifdef HAS_COLOR',
    '  if (mode == 0) vColor = color.rgb;',
    '#endif',
    '  if (mode == 1) vColor = ramp((dot(position, up) - zrange.x) / max(zrange.y - zrange.x, 1e-6));',
    '#ifdef HAS_INTENSITY',
    '  if (mode == 2) vColor = ramp((_intensity - irange.x) / max(irange.y - irange.x, 1e-12));',
    '#endif',
    '}'].join('\n');
  var POINT_FRAGMENT = 'varying vec3 vColor;\nvoid main() { gl_FragColor = vec4(vColor, 1.0); }';

  function el(tag, attrs, parent) {
    var e = document.createElement(tag);
    for (var k in attrs) { if (k === 'text') e.textContent = attrs[k]; else e.setAttribute(k, attrs[k]); }
    if (parent) parent.appendChild(e);
    return e;
  }

  // First index i with a[i] > t (a sorted ascending).
  function upperBound(a, t) {
    var lo = 0, hi = a.length;
    while (lo < hi) { var m = (lo + hi) >> 1; if (a[m] <= t) lo = m + 1; else hi = m; }
    return lo;
  }
  function lowerBound(a, t) {
    var lo = 0, hi = a.length;
    while (lo < hi) { var m = (lo + hi) >> 1; if (a[m] < t) lo = m + 1; else hi = m; }
    return lo;
  }
  function sorted(a) {
    for (var i = 1; i < a.length; ++i) if (a[i] < a[i - 1]) return false;
    return true;
  }
  function range(a) {
    var lo = Infinity, hi = -Infinity;
    for (var i = 0; i < a.length; ++i) { var v = a[i]; if (v < lo) lo = v; if (v > hi) hi = v; }
    return [lo, hi];
  }

  function View(opts) {
    this.opts = opts || {};
    this.stats = { status: 'loading', layers: 0, objects: 0, vertices: 0, kinds: {} };
    this.layers = [];
    this.colorMode = 'auto';
    this.pointScale = 1.0;
    this.lodBudget = this.opts.lodBudget || 1000000;
    // Points drawn per large cloud while moving: starts at lodBudget and
    // adapts to the frame time (software WebGL draws a few million points a
    // second, a GPU hundreds of millions).
    this.moveBudget = this.lodBudget;
    this.moving = false;
    this.t0 = performance.now();
  }

  View.prototype.start = function () {
    var self = this;
    var box = document.getElementById('rove-view');
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setSize(box.clientWidth, box.clientHeight);
    box.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x1b1e23);
    this.camera = new THREE.PerspectiveCamera(50, box.clientWidth / Math.max(1, box.clientHeight), 0.01, 1e7);
    this.controls = new THREE.OrbitControls(this.camera, this.renderer.domElement);
    this.controls.screenSpacePanning = true;
    this.controls.addEventListener('change', function () { self.requestRender(); });
    this.controls.addEventListener('start', function () { self.setMoving(true); });
    this.controls.addEventListener('end', function () { self.setMoving(false); });
    window.addEventListener('resize', function () { self.resize(); });
    this.installPicking();
    var onError = function (e) { self.fail(e && e.message ? e.message : String(e)); };
    var loader = new THREE.GLTFLoader();
    try {
      if (this.opts.base64 !== undefined) {
        var bin = atob(this.opts.base64.replace(/\s+/g, ''));
        var bytes = new Uint8Array(bin.length);
        for (var i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
        this.stats.glb_bytes = bytes.length;
        loader.parse(bytes.buffer, '', function (g) { self.setup(g); }, onError);
      } else {
        loader.load(this.opts.url, function (g) { self.setup(g); }, undefined, onError);
      }
    } catch (e) { onError(e); }
  };

  View.prototype.fail = function (message) {
    this.stats.status = 'error';
    this.stats.error = message;
    document.title = 'rove view: error';
    var p = document.getElementById('rove-pick');
    if (p) p.textContent = 'Could not load the scene: ' + message;
    this.publishStats();
  };

  View.prototype.publishStats = function () {
    var s = document.getElementById('rove-stats');
    if (s) s.textContent = JSON.stringify(this.stats);
    window.roveStats = this.stats;
  };

  View.prototype.setup = function (gltf) {
    var self = this;
    this.root = gltf.scene;
    this.meta = (gltf.scene.userData && gltf.scene.userData.rove) || {};
    if (gltf.scenes && gltf.scenes[0] && gltf.scenes[0].userData.rove) this.meta = gltf.scenes[0].userData.rove;
    this.scene.add(this.root);
    this.root.updateMatrixWorld(true);
    var found = [];
    this.root.traverse(function (o) { if (o.userData && o.userData.rove && o.geometry) found.push(o); });
    // In the file's order (the loader may attach nodes in another).
    found.sort(function (a, b) { return (a.userData.rove.index || 0) - (b.userData.rove.index || 0); });
    this.bounds = new THREE.Box3();
    // Height is along the scene's up axis, in the layers' own (rove's) frame.
    this.up = this.meta.up === '-y' ? new THREE.Vector3(0, -1, 0) : new THREE.Vector3(0, 0, 1);
    this.zrange = [Infinity, -Infinity];
    found.forEach(function (o) {
      var pos = o.geometry.attributes.position;
      o.geometry.computeBoundingBox();
      var bb = o.geometry.boundingBox, u = self.up, lo = 0, hi = 0;
      ['x', 'y', 'z'].forEach(function (a) {
        lo += u[a] * (u[a] > 0 ? bb.min[a] : bb.max[a]);
        hi += u[a] * (u[a] > 0 ? bb.max[a] : bb.min[a]);
      });
      self.zrange[0] = Math.min(self.zrange[0], lo);
      self.zrange[1] = Math.max(self.zrange[1], hi);
      self.bounds.union(bb.clone().applyMatrix4(o.matrixWorld));
      self.layers.push(self.makeLayer(o, pos.count));
    });
    this.timeRange = this.findTimeRange();
    this.buildPanel();
    this.frameCamera();
    this.applyTime(this.timeRange ? this.timeRange[1] : 0);
    this.render();
    setTimeout(function () {
      self.stats.drawn = self.drawnVertices();
      self.stats.status = 'ready';
      self.stats.load_ms = Math.round(performance.now() - self.t0);
      self.stats.title = self.meta.title || '';
      document.title = 'rove view: ' + (self.meta.title || 'scene');
      if (self.opts.pickAt) {
        var hit = self.pick(self.opts.pickAt[0], self.opts.pickAt[1]);
        self.stats.pick = hit ? { layer: hit.layer, kind: hit.kind, index: hit.index, x: hit.x, y: hit.y, z: hit.z }
          : null;
        if (hit && hit.cell) { self.stats.pick.cell = hit.cell; self.stats.pick.occupancy = hit.occupancy; }
      }
      self.publishStats();
      if (self.opts.bench) self.bench();
    }, 0);
  };

  View.prototype.makeLayer = function (o, count) {
    var info = o.userData.rove;
    var g = o.geometry;
    // Draw ranges count indices on indexed geometry (boxes, grids).
    var elements = g.index ? g.index.count : count;
    var L = { obj: o, info: info, kind: info.kind, count: count, visible: true, drawStart: 0, drawCount: elements };
    if (info.shown === false) o.visible = false;  // a layer that starts hidden (its box unticked)
    L.times = g.attributes._time ? g.attributes._time.array : null;
    L.timed = L.times && info.time_mode !== 'none' && sorted(L.times);
    L.hasColor = !!g.attributes.color;
    L.hasIntensity = !!g.attributes._intensity;
    if (L.hasIntensity) L.irange = range(g.attributes._intensity.array);
    if (info.kind === 'grid') {
      // The floor: drawn first and without depth, so that paths and graphs
      // at the same height stay on top of it.
      o.renderOrder = -1;
      o.material.depthWrite = false;
    }
    if (info.kind === 'label') {
      this.makeLabel(L);
    } else if (o.isPoints) {
      L.points = true;
      var defines = {};
      if (L.hasColor) defines.HAS_COLOR = 1;
      if (L.hasIntensity) defines.HAS_INTENSITY = 1;
      L.material = new THREE.ShaderMaterial({
        uniforms: {
          size: { value: info.point_size || 2 }, mode: { value: 3 },
          zrange: { value: new THREE.Vector2(0, 1) }, irange: { value: new THREE.Vector2(0, 1) },
          up: { value: this.up },
          base: { value: new THREE.Color(info.color[0] / 255, info.color[1] / 255, info.color[2] / 255) }
        },
        defines: defines, vertexShader: POINT_VERTEX, fragmentShader: POINT_FRAGMENT
      });
      o.material = L.material;
      L.lod = !L.timed && count > this.minBudget();
    }
    var k = this.stats.kinds[L.kind] || { layers: 0, vertices: 0 };
    k.layers += 1; k.vertices += count;
    this.stats.kinds[L.kind] = k;
    this.stats.layers += 1;
    this.stats.objects += 1;
    this.stats.vertices += count;
    return L;
  };

  View.prototype.makeLabel = function (L) {
    var text = L.info.text || L.info.name;
    var c = document.createElement('canvas');
    var ctx = c.getContext('2d');
    ctx.font = '28px sans-serif';
    c.width = Math.ceil(ctx.measureText(text).width) + 16; c.height = 40;
    ctx.font = '28px sans-serif';
    ctx.fillStyle = 'rgba(0,0,0,0.55)'; ctx.fillRect(0, 0, c.width, c.height);
    ctx.fillStyle = '#ffffff'; ctx.fillText(text, 8, 29);
    var sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(c), depthTest: false }));
    var p = L.obj.geometry.attributes.position;
    sprite.position.set(p.getX(0), p.getY(0), p.getZ(0));
    sprite.userData.aspect = c.width / c.height;
    L.obj.add(sprite);
    L.sprite = sprite;
  };

  View.prototype.frameCamera = function () {
    var c = new THREE.Vector3(), s = new THREE.Vector3();
    if (this.bounds.isEmpty()) { this.bounds.set(new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1)); }
    this.bounds.getCenter(c); this.bounds.getSize(s);
    var d = Math.max(s.length(), 1e-3);
    this.sceneSize = d;
    this.camera.near = d / 1e4; this.camera.far = d * 100;
    // Look down steeply on flat scenes (maps), at 45 degrees on others; y up
    // in three is the scene's up (z in rove's maps, -y in a camera's
    // optical frame); the camera stands on three's +z side (rove's -y side
    // of a map, behind an optical frame's forward z).
    var flat = s.y < 0.2 * Math.max(s.x, s.z);
    var elevation = flat ? 1.1 : 0.785;
    var dir = new THREE.Vector3(0, Math.sin(elevation), Math.cos(elevation));
    // Then move along that direction until the bounds' corners fill 90% of
    // the view's width or height (a few fixed-point steps: the projected
    // size goes nearly as 1 / distance).
    var b = this.bounds, corners = [], dist = 0.8 * d;
    for (var k = 0; k < 8; ++k) {
      corners.push(new THREE.Vector3(k & 1 ? b.max.x : b.min.x, k & 2 ? b.max.y : b.min.y, k & 4 ? b.max.z : b.min.z));
    }
    this.camera.updateProjectionMatrix();
    for (var it = 0; it < 6; ++it) {
      this.camera.position.copy(c).addScaledVector(dir, dist);
      this.camera.lookAt(c);
      this.camera.updateMatrixWorld();
      var m = 0;
      for (k = 0; k < 8; ++k) {
        var q = corners[k].clone().project(this.camera);
        m = Math.max(m, Math.abs(q.x), Math.abs(q.y));
      }
      if (!(m > 0) || !isFinite(m)) break;
      dist *= Math.max(0.5, Math.min(2, m / 0.9));
      dist = Math.max(dist, 0.55 * d);  // stay outside the bounds
    }
    this.camera.position.copy(c).addScaledVector(dir, dist);
    this.controls.target.copy(c);
    this.controls.update();
    this.layers.forEach(function (L) {
      if (L.sprite) L.sprite.scale.set(0.03 * d * L.sprite.userData.aspect, 0.03 * d, 1);
    });
    this.applyColors();
  };

  View.prototype.applyColors = function () {
    var self = this;
    this.layers.forEach(function (L) {
      if (!L.points) return;
      var u = L.material.uniforms, m = self.colorMode, mode;
      if (m === 'uniform') mode = 3;
      else if (m === 'intensity') mode = L.hasIntensity ? 2 : 1;
      else if (m === 'height') mode = 1;
      else if (L.kind === 'particles') mode = L.hasIntensity ? 2 : 3;
      else if (L.kind === 'point_cloud' || L.kind === 'scans' || L.kind === 'voxels') mode = L.hasColor ? 0 : 1;
      else mode = L.hasColor ? 0 : 3;
      u.mode.value = mode;
      u.zrange.value.set(self.zrange[0], self.zrange[1]);
      if (L.irange) u.irange.value.set(L.irange[0], L.irange[1]);
      u.size.value = (L.info.point_size || 2) * self.pointScale * (window.devicePixelRatio || 1);
    });
    this.requestRender();
  };

  // Shows the part of each layer the time slider and the level of detail allow.
  View.prototype.applyDrawRanges = function () {
    var self = this;
    this.layers.forEach(function (L) {
      var start = L.drawStart, count = L.drawCount;
      if (L.lod && self.moving) count = Math.min(count, Math.round(self.moveBudget));
      L.obj.geometry.setDrawRange(start, count);
    });
  };

  View.prototype.applyTime = function (t) {
    this.time = t;
    this.layers.forEach(function (L) {
      if (!L.timed) return;
      var end = upperBound(L.times, t);
      if (L.info.time_mode === 'snapshot' && end > 0) {
        var begin = lowerBound(L.times, L.times[end - 1]);
        L.drawStart = begin; L.drawCount = end - begin;
      } else {
        L.drawStart = 0; L.drawCount = end;
      }
    });
    var label = document.getElementById('rove-time-label');
    if (label) label.textContent = 't = ' + t.toFixed(2) + ' s';
    this.applyDrawRanges();
    this.requestRender();
  };

  // Vertices drawn per layer kind (the time slider and the level of detail
  // draw parts of layers).
  View.prototype.drawnVertices = function () {
    var out = {};
    this.layers.forEach(function (L) {
      var g = L.obj.geometry, r = g.drawRange;
      var total = g.index ? g.index.count : L.count;
      var n = Math.max(0, Math.min(total, r.start + r.count) - r.start);
      if (g.index && L.drawCount >= total) n = L.count;  // whole indexed layers: their vertices
      out[L.kind] = (out[L.kind] || 0) + (L.obj.visible ? n : 0);
    });
    return out;
  };

  View.prototype.setMoving = function (moving) {
    var self = this;
    clearTimeout(this.idleTimer);
    if (moving) { this.moving = true; this.applyDrawRanges(); return; }
    this.idleTimer = setTimeout(function () { self.moving = false; self.applyDrawRanges(); self.requestRender(); }, 200);
  };

  View.prototype.resize = function () {
    var box = document.getElementById('rove-view');
    this.camera.aspect = box.clientWidth / Math.max(1, box.clientHeight);
    this.camera.updateProjectionMatrix();
    this.renderer.setSize(box.clientWidth, box.clientHeight);
    this.requestRender();
  };

  View.prototype.minBudget = function () { return Math.min(this.lodBudget, 50000); };

  // Scales the moving budget towards 50 ms a frame (20 frames per second).
  View.prototype.adaptBudget = function (frameMs) {
    if (!(frameMs > 0)) return;
    var f = Math.max(0.5, Math.min(1.5, 50 / frameMs));
    this.moveBudget = Math.max(this.minBudget(), Math.min(this.lodBudget, this.moveBudget * f));
    this.applyDrawRanges();
  };

  View.prototype.requestRender = function () {
    var self = this;
    if (this.pending || !this.root) return;
    this.pending = true;
    requestAnimationFrame(function (now) {
      self.pending = false;
      if (self.moving && self.lastFrame !== undefined && now - self.lastFrame < 1000) self.adaptBudget(now - self.lastFrame);
      self.lastFrame = now;
      self.render();
    });
  };

  View.prototype.render = function () { this.renderer.render(this.scene, this.camera); };

  View.prototype.buildPanel = function () {
    var self = this;
    var panel = document.getElementById('rove-panel');
    el('h1', { text: this.meta.title || 'rove' }, panel);
    if (this.opts.panel === false) return;  // pictures: the title only
    var list = el('div', { id: 'rove-layers' }, panel);
    this.layers.forEach(function (L) {
      var row = el('label', { 'class': 'rove-layer' }, list);
      var box = el('input', { type: 'checkbox' }, row);
      box.checked = L.obj.visible;
      box.addEventListener('change', function () { L.obj.visible = box.checked; self.requestRender(); });
      var n = L.info.source_count > L.count ? L.count + ' of ' + L.info.source_count : String(L.count);
      el('span', { text: ' ' + L.info.name + ' (' + L.kind.replace(/_/g, ' ') + ', ' + n + ')' }, row);
    });
    var size = el('label', { text: 'point size ' }, panel);
    var slider = el('input', { type: 'range', id: 'rove-size', min: '0.25', max: '6', step: '0.25', value: '1' }, size);
    slider.addEventListener('input', function () { self.pointScale = parseFloat(slider.value); self.applyColors(); });
    var colors = el('label', { text: 'colour ' }, panel);
    var select = el('select', { id: 'rove-color' }, colors);
    [['auto', 'file colours, else height'], ['height', 'height'], ['intensity', 'intensity / weight'],
      ['uniform', 'one per layer']].forEach(function (o) { el('option', { value: o[0], text: o[1] }, select); });
    select.addEventListener('change', function () { self.colorMode = select.value; self.applyColors(); });
    this.buildTimeSlider(panel);
    el('div', { id: 'rove-pick', text: 'Click a point, a pose or a grid cell to see its coordinates.' }, panel);
    el('div', { 'class': 'rove-help',
      text: 'drag: orbit · right drag: pan · wheel: zoom · large clouds thin out while moving' }, panel);
  };

  // [first, last] time over the timed layers, or null.
  View.prototype.findTimeRange = function () {
    var lo = Infinity, hi = -Infinity;
    this.layers.forEach(function (L) {
      if (!L.timed || L.times.length === 0) return;
      lo = Math.min(lo, L.times[0]); hi = Math.max(hi, L.times[L.times.length - 1]);
    });
    return hi >= lo ? [lo, hi] : null;
  };

  View.prototype.buildTimeSlider = function (panel) {
    var self = this;
    if (!this.timeRange) return;
    var lo = this.timeRange[0], hi = this.timeRange[1];
    var box = el('div', { id: 'rove-time-box' }, panel);
    var slider = el('input', { type: 'range', id: 'rove-time', min: '0', max: '1000', step: '1', value: '1000' }, box);
    el('span', { id: 'rove-time-label' }, box);
    var play = el('button', { text: 'play' }, box);
    var toTime = function (v) { return lo + (hi - lo) * v / 1000; };
    slider.addEventListener('input', function () { self.applyTime(toTime(parseFloat(slider.value))); });
    play.addEventListener('click', function () {
      var v = 0;
      clearInterval(self.player);
      self.player = setInterval(function () {
        v += 5; slider.value = String(Math.min(v, 1000)); self.applyTime(toTime(Math.min(v, 1000)));
        if (v >= 1000) clearInterval(self.player);
      }, 40);
    });
  };

  View.prototype.installPicking = function () {
    var self = this, down = null;
    var canvas = this.renderer.domElement;
    canvas.addEventListener('pointerdown', function (e) { down = [e.clientX, e.clientY]; });
    canvas.addEventListener('pointerup', function (e) {
      if (!down || Math.abs(e.clientX - down[0]) + Math.abs(e.clientY - down[1]) > 4) return;
      var r = canvas.getBoundingClientRect();
      self.pick((e.clientX - r.left) / r.width * 2 - 1, -(e.clientY - r.top) / r.height * 2 + 1);
    });
  };

  // Picks the nearest point or vertex under normalized device coordinates (x, y).
  View.prototype.pick = function (x, y) {
    if (!this.root) return null;
    var ray = new THREE.Raycaster();
    ray.setFromCamera(new THREE.Vector2(x, y), this.camera);
    var dist = this.camera.position.distanceTo(this.controls.target);
    var h = this.renderer.domElement.clientHeight || 1;
    var perPixel = 2 * dist * Math.tan(this.camera.fov * Math.PI / 360) / h;
    ray.params.Points.threshold = 5 * perPixel;
    ray.params.Line.threshold = 4 * perPixel;
    // Points, poses and vertices first; a grid cell when none is under the cursor.
    var targets = [], grids = [];
    this.layers.forEach(function (L) {
      if (!L.obj.visible || L.kind === 'label') return;
      if (L.kind === 'grid') { if (L.info.grid) grids.push(L.obj); } else targets.push(L.obj);
    });
    var hits = ray.intersectObjects(targets, false);
    if (hits.length === 0) hits = ray.intersectObjects(grids, false);
    var box = document.getElementById('rove-pick');
    if (hits.length === 0) { if (box) box.textContent = 'Nothing under the cursor.'; return null; }
    var hit = hits[0], L = null;
    this.layers.forEach(function (l) { if (l.obj === hit.object) L = l; });
    var info = L.kind === 'grid' ? this.describeCell(L, hit.object.worldToLocal(hit.point.clone()))
      : this.describe(L, hit.index !== undefined ? hit.index : 0);
    if (box) box.textContent = info.text;
    return info;
  };

  // The gray levels of a grid's texture (255 p(free), row 0 at the top),
  // read once from the decoded image; null if the browser refuses.
  View.prototype.gridPixels = function (L) {
    if (L.pixels !== undefined) return L.pixels;
    L.pixels = null;
    var map = L.obj.material && L.obj.material.map, img = map && map.image;
    if (!img || !img.width) return null;
    try {
      var c = document.createElement('canvas');
      c.width = img.width; c.height = img.height;
      var ctx = c.getContext('2d');
      ctx.drawImage(img, 0, 0);
      L.pixels = { width: img.width, height: img.height, data: ctx.getImageData(0, 0, img.width, img.height).data };
    } catch (e) { L.pixels = null; }
    return L.pixels;
  };

  // The grid cell at a point in the layer's (rove's) frame: its indices,
  // its centre and p(occupied) from the texture.
  View.prototype.describeCell = function (L, p) {
    var g = L.info.grid;
    var clampIndex = function (v, n) { return Math.max(0, Math.min(n - 1, v)); };
    var cx = clampIndex(Math.floor((p.x - g.x_min) / g.resolution), g.size_x);
    var cy = clampIndex(Math.floor((p.y - g.y_min) / g.resolution), g.size_y);
    var out = { layer: L.info.name, kind: L.kind, index: cy * g.size_x + cx, cell: [cx, cy],
      x: g.x_min + (cx + 0.5) * g.resolution, y: g.y_min + (cy + 0.5) * g.resolution, z: p.z, occupancy: null };
    var text = L.info.name + ' (grid) cell (' + cx + ', ' + cy + ') of ' + g.size_x + ' x ' + g.size_y + '\n' +
      'centre x ' + out.x.toFixed(3) + '  y ' + out.y.toFixed(3) + ' m\n';
    var px = this.gridPixels(L), k = g.cells_per_texel || 1;
    if (px) {
      var tx = Math.floor(cx / k), ty = Math.floor((g.size_y - 1 - cy) / k);
      var gray = px.data[4 * (ty * px.width + tx)];
      out.occupancy = 1 - gray / 255;
      text += 'p(occupied) ' + out.occupancy.toFixed(3) + (gray === 127 || gray === 128 ? ' (unknown)' : '');
      if (k > 1) text += ', the most occupied of the ' + k + ' x ' + k + ' cells shown by this texel';
    } else {
      text += 'occupancy not readable from the texture';
    }
    out.text = text;
    return out;
  };

  View.prototype.describe = function (L, index) {
    var p = L.obj.geometry.attributes.position;
    var step = L.info.permutation_step || 0, n = L.info.source_count || L.count;
    var source = step ? Number((BigInt(index) * BigInt(step)) % BigInt(n)) : index;
    var out = { layer: L.info.name, kind: L.kind, index: source,
      x: p.getX(index), y: p.getY(index), z: p.getZ(index) };
    var text = L.info.name + ' (' + L.kind.replace(/_/g, ' ') + ') #' + source + '\n' +
      'x ' + out.x.toFixed(3) + '  y ' + out.y.toFixed(3) + '  z ' + out.z.toFixed(3) + ' m';
    if (L.times) {
      out.time = L.times[index] + (this.meta.time_origin || 0);
      text += '\nt ' + out.time.toFixed(3) + ' s';
    }
    if (L.hasIntensity) text += '\nvalue ' + L.obj.geometry.attributes._intensity.getX(index).toPrecision(4);
    out.text = text;
    return out;
  };

  // Renders frames while turning the camera (full detail, then the level of
  // detail used while moving) and records frames per second in the stats.
  View.prototype.bench = function () {
    var gl = this.renderer.getContext(), px = new Uint8Array(4), self = this;
    var frames = this.opts.benchFrames || 20;
    var frame = function () {
      var offset = self.camera.position.clone().sub(self.controls.target);
      offset.applyAxisAngle(new THREE.Vector3(0, 1, 0), 0.05);
      self.camera.position.copy(self.controls.target).add(offset);
      self.camera.lookAt(self.controls.target);
      self.render();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    };
    var run = function (moving) {
      self.moving = moving; self.applyDrawRanges();
      // While moving, let the budget settle as it does under the mouse.
      for (var w = 0; moving && w < 12; ++w) {
        var t0 = performance.now(); frame(); self.adaptBudget(performance.now() - t0);
      }
      var t = performance.now();
      for (var k = 0; k < frames; ++k) frame();
      return frames * 1000 / Math.max(1e-3, performance.now() - t);
    };
    this.stats.fps_full = Math.round(run(false) * 10) / 10;
    this.stats.fps_moving = Math.round(run(true) * 10) / 10;
    this.stats.points_moving = Math.round(this.moveBudget);
    this.moving = false; this.applyDrawRanges(); this.render();
    this.publishStats();
  };

  window.roveView = function (opts) {
    var v = new View(opts);
    window.roveViewer = v;
    v.start();
    return v;
  };
})();
