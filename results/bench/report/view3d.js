// The 3D view: one panel per backend, one shared camera (so the views stay linked), one time
// slider and play button for all of them. Rings are one instanced torus per backend; each frame
// is a script of report/frames/ loaded the first time it is shown. A bench's page holds one view
// per scene that kept frames, each started when it first scrolls into sight.
'use strict';
window.chainmailView = (function () {
  const { el, colour, fmt } = window.cm;
  const SHOWN = ['max_stretch', 'mean_stretch', 'penetrating_linked', 'penetrating_other',
    'broken_links', 'false_links', 'drape_rms', 'kinetic_energy', 'max_speed'];
  const frames = {};    // key (backend, or scene/backend) -> k -> Float32Array (x y z qw qx qy qz per ring)
  const waiting = {};   // script path -> [callbacks]

  // the frame scripts call this, with integers: positions in micrometres, quaternions in 1e-4
  window.chainmailFrame = function (key, k, t, values) {
    const f = new Float32Array(values.length);
    for (let i = 0; i < values.length; ++i) f[i] = values[i] * (i % 7 < 3 ? 1e-6 : 1e-4);
    (frames[key] = frames[key] || {})[k] = f;
  };
  function loadScript(path, done) {
    if (waiting[path]) { waiting[path].push(done); return; }
    waiting[path] = [done];
    const s = document.createElement('script');
    const finish = (ok) => { const cbs = waiting[path]; delete waiting[path]; s.remove(); cbs.forEach((cb) => cb(ok)); };
    s.onload = () => finish(true);
    s.onerror = () => finish(false);
    s.src = path;
    document.head.append(s);
  }
  function framePath(key, k) {
    return `report/frames/${key}/${String(k).padStart(5, '0')}.js`;
  }
  function loadFrame(key, k, done) {
    if (frames[key] && frames[key][k]) { done(true); return; }
    loadScript(framePath(key, k), done);
  }

  function colliderMeshes(scene, size) {
    const mat = new THREE.MeshPhongMaterial({ color: 0x9aa3ad, side: THREE.DoubleSide,
      transparent: true, opacity: 0.55 });
    const out = [];
    for (const c of scene.colliders || []) {
      let m = null;
      if (c.type === 'sphere') m = new THREE.Mesh(new THREE.SphereBufferGeometry(c.radius, 40, 20), mat);
      if (c.type === 'box') m = new THREE.Mesh(new THREE.BoxBufferGeometry(...c.half_extents.map((h) => 2 * h)), mat);
      if (c.type === 'cylinder') m = new THREE.Mesh(new THREE.CylinderBufferGeometry(c.radius, c.radius, 2 * c.half_height, 48), mat);
      if (c.type === 'plane') {
        m = new THREE.Mesh(new THREE.CircleBufferGeometry(size, 48), mat);
        m.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), new THREE.Vector3(...c.normal).normalize());
        m.position.set(...c.point);
      } else if (m) {
        m.position.set(...c.center);
      }
      if (m) out.push(m);
    }
    return out;
  }

  // drag to turn about the target, wheel to come closer: the one camera every panel draws with
  function orbit(camera, target, up, onChange) {
    const toY = new THREE.Quaternion().setFromUnitVectors(up, new THREE.Vector3(0, 1, 0));
    const fromY = toY.clone().inverse();
    const move = (dTheta, dPhi, scale) => {
      const offset = camera.position.clone().sub(target).applyQuaternion(toY);
      const s = new THREE.Spherical().setFromVector3(offset);
      s.theta -= dTheta;
      s.phi = Math.min(Math.PI - 0.05, Math.max(0.05, s.phi - dPhi));
      s.radius *= scale;
      offset.setFromSpherical(s).applyQuaternion(fromY);
      camera.position.copy(target).add(offset);
      camera.lookAt(target);
      onChange();
    };
    let last = null;
    return function attach(node) {
      node.addEventListener('pointerdown', (e) => { last = [e.clientX, e.clientY]; node.setPointerCapture(e.pointerId); });
      node.addEventListener('pointerup', () => { last = null; });
      node.addEventListener('pointermove', (e) => {
        if (!last) return;
        move((e.clientX - last[0]) * 0.008, (e.clientY - last[1]) * 0.008, 1);
        last = [e.clientX, e.clientY];
      });
      node.addEventListener('wheel', (e) => { e.preventDefault(); move(0, 0, e.deltaY > 0 ? 1.1 : 1 / 1.1); },
        { passive: false });
    };
  }

  function metricsBy(csv) {
    const rows = {};
    for (const r of csv.rows) (rows[r[0]] = rows[r[0]] || []).push(r);
    return rows;
  }

  // F: the frames of one run (rings; per backend count, times and key); tag: the ids' suffix
  function build(section, summary, F, csv, tag) {
    const scene = summary.scene;
    const ring = summary.ring;
    const names = Object.keys(F.backends);
    const count = Math.max(...names.map((b) => F.backends[b].count));
    const times = F.backends[names.find((b) => F.backends[b].count === count)].times;
    const rows = metricsBy(csv);
    const keyOf = (b) => F.backends[b].key || b;

    const slider = el('input', { type: 'range', min: 0, max: count - 1, value: 0, step: 1, id: 'frame-slider' + tag });
    const play = el('button', { type: 'button', id: 'play' + tag, text: '▶ play' });
    const label = el('span', { id: 'frame-label' + tag, class: 'muted' });
    const panelsDiv = el('div', { class: 'panels' });
    const stage = el('div', { class: 'stage' }, panelsDiv);
    section.append(el('div', { class: 'controls' }, play, slider, label), stage,
      el('p', { class: 'muted', text: `Drag to turn, wheel to zoom: every panel shares one camera. ` +
        `${count} frames per backend, each loaded the first time it is shown.` }));

    const canvas = el('canvas');
    stage.append(canvas);
    const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, alpha: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setScissorTest(true);
    const g = new THREE.Vector3(...(scene.gravity || [0, -9.81, 0]));
    const up = g.lengthSq() > 0 ? g.clone().negate().normalize() : new THREE.Vector3(0, 1, 0);
    const cam = scene.camera || {};
    const target = new THREE.Vector3(...(cam.target || scene.weave.center || [0, 0, 0]));
    const eye = new THREE.Vector3(...(cam.position || [0, 0, 0.5]));
    const dist = Math.max(eye.distanceTo(target), 1e-3);
    const camera = new THREE.PerspectiveCamera(cam.fov_deg || 40, 4 / 3, dist / 200, dist * 200);
    camera.up.copy(up);
    camera.position.copy(eye);
    camera.lookAt(target);

    // fewer facets for large sheets: a ring is a few pixels there, and software WebGL stays usable
    const big = F.rings * names.length > 1500;
    const torus = new THREE.TorusBufferGeometry(ring.centre_radius, ring.wire_radius, big ? 6 : 8, big ? 12 : 20);
    torus.rotateX(Math.PI / 2);  // three.js's torus lies in x/y; a ring lies in its local x/z
    const panels = names.map((b, i) => {
      const view = el('div', { class: 'viewport' });
      const metrics = el('tbody');
      const node = el('div', { class: 'panel', 'data-backend': b }, view,
        el('div', { class: 'side' }, el('h3', { text: b, style: `color:${colour(b, i)}` }),
          el('table', {}, metrics)));
      panelsDiv.append(node);
      const s = new THREE.Scene();
      s.add(new THREE.HemisphereLight(0xffffff, 0x445566, 0.75));
      const sun = new THREE.DirectionalLight(0xffffff, 0.7);
      sun.position.copy(eye).sub(target).add(up.clone().multiplyScalar(dist)).normalize();
      s.add(sun);
      const mesh = new THREE.InstancedMesh(torus, new THREE.MeshPhongMaterial({ color: colour(b, i),
        specular: 0x666666, shininess: 60 }), F.rings);
      mesh.frustumCulled = false;  // the instances are far from the torus's own bounds
      s.add(mesh);
      for (const c of colliderMeshes(scene, dist * 3)) s.add(c);
      return { name: b, node, view, metrics, scene: s, mesh, shown: -1 };
    });
    orbit(camera, target, up, () => draw())(panelsDiv);

    function resize() {
      const w = stage.clientWidth, h = stage.clientHeight;
      renderer.setSize(w, h, false);
      canvas.style.width = w + 'px';
      canvas.style.height = h + 'px';
      draw();
    }
    let pending = false;
    let shownFrame = -1;
    function draw() {
      if (pending) return;
      pending = true;
      requestAnimationFrame(() => {
        pending = false;
        const box = stage.getBoundingClientRect();
        renderer.setClearColor(0xeef1f5, 1);
        for (const p of panels) {
          const r = p.view.getBoundingClientRect();
          const x = r.left - box.left, y = box.bottom - r.bottom;
          renderer.setViewport(x, y, r.width, r.height);
          renderer.setScissor(x, y, r.width, r.height);
          camera.aspect = r.width / r.height;
          camera.updateProjectionMatrix();
          renderer.render(p.scene, camera);
        }
        if (shownFrame >= 0) stage.dataset.frame = shownFrame;  // drawn, not only loaded
      });
    }
    const m4 = new THREE.Matrix4(), pos = new THREE.Vector3(), q = new THREE.Quaternion(), one = new THREE.Vector3(1, 1, 1);
    function show(p, k) {
      const f = frames[keyOf(p.name)][k];
      for (let i = 0; i < F.rings; ++i) {
        const o = 7 * i;
        pos.set(f[o], f[o + 1], f[o + 2]);
        q.set(f[o + 4], f[o + 5], f[o + 6], f[o + 3]);  // the files hold w first
        p.mesh.setMatrixAt(i, m4.compose(pos, q, one));
      }
      p.mesh.instanceMatrix.needsUpdate = true;
      p.shown = k;
      p.node.dataset.frame = k;
      const row = (rows[p.name] || [])[k] || [];
      p.metrics.replaceChildren(...SHOWN.filter((m) => csv.col(m) >= 0).map((m) => {
        const v = row[csv.col(m)];
        return el('tr', {}, el('td', { class: 'text', text: m }),
          el('td', { text: fmt(v === undefined || v === '' ? '' : Number(v)), 'data-metric': m, 'data-v': v || '' }));
      }));
    }
    // the first frame drawn fills the view, seen from the scene camera's side
    function fit(f) {
      const box = new THREE.Box3();
      for (let o = 0; o < f.length; o += 7) box.expandByPoint(pos.set(f[o], f[o + 1], f[o + 2]));
      const sphere = box.getBoundingSphere(new THREE.Sphere());
      const radius = sphere.radius + ring.centre_radius;
      const away = eye.clone().sub(target).normalize();
      const d = radius / Math.sin(camera.fov * Math.PI / 360) * 1.1;
      target.copy(sphere.center);
      camera.position.copy(target).addScaledVector(away, d);
      camera.near = d / 100;
      camera.far = d * 100;
      camera.lookAt(target);
    }
    let current = 0;
    // every panel to sample k (a backend with fewer frames keeps its last), once all are loaded
    function setFrame(k) {
      current = k;
      slider.value = k;
      label.textContent = `frame ${k + 1} / ${count}, t = ${fmt(times[k])} s (loading…)`;
      let left = panels.length;
      for (const p of panels) {
        const kb = Math.min(k, F.backends[p.name].count - 1);
        loadFrame(keyOf(p.name), kb, () => {
          if (--left > 0 || current !== k) return;
          for (const p2 of panels) {
            const k2 = Math.min(k, F.backends[p2.name].count - 1);
            const got = frames[keyOf(p2.name)];
            if (got && got[k2]) show(p2, k2);
          }
          label.textContent = `frame ${k + 1} / ${count}, t = ${fmt(times[k])} s`;
          const first = panels[0].name;
          if (shownFrame < 0) fit(frames[keyOf(first)][Math.min(k, F.backends[first].count - 1)]);
          shownFrame = k;
          draw();
        });
      }
    }
    slider.addEventListener('input', () => setFrame(Number(slider.value)));
    let timer = null;
    play.addEventListener('click', () => {
      if (timer) { clearInterval(timer); timer = null; play.textContent = '▶ play'; return; }
      play.textContent = '❚❚ pause';
      const step = Math.max(40, 1000 * (times.length > 1 ? times[1] - times[0] : 0.05));
      timer = setInterval(() => { if (stage.dataset.frame === String(current)) setFrame((current + 1) % count); }, step);
    });
    new ResizeObserver(resize).observe(stage);
    setFrame(0);
  }

  // lazy: started when `section` first scrolls into sight (a bench's page holds several views,
  // and three.js is loaded only then)
  function mount(section, summary, F, csv, tag, lazy) {
    if (lazy && window.IntersectionObserver) {
      const seen = new IntersectionObserver((entries) => {
        if (!entries.some((e) => e.isIntersecting)) return;
        seen.disconnect();
        mount(section, summary, F, csv, tag, false);
      }, { rootMargin: '200px' });
      seen.observe(section);
      return;
    }
    const note = (text) => section.append(el('p', { class: 'note', id: 'no-3d' + tag, text }));
    const start = () => {
      try {
        build(section, summary, F, csv, tag);
      } catch (e) {
        note('The 3D view could not start here (' + e.message + '); the tables above hold every number.');
      }
    };
    if (window.THREE) { start(); return; }
    loadScript('report/three.min.js', (ok) => (ok ? start() : note('three.js is not beside this page ' +
      '(report/three.min.js): this build of chainmail was made without it, so there is no 3D view.')));
  }
  return { mount };
})();
