// The page: what the folder holds (report/data.js, written by `chainmail report`), as sections.
'use strict';
(function () {
  const { el, fmt, table, csvTable, verdictClass, plot, legend, colour, parseCSV, pareto } = window.cm;
  const R = window.CHAINMAIL_REPORT;
  const main = document.getElementById('main');
  const toc = document.getElementById('toc');
  const files = (R && R.files) || {};

  function section(id, title, ...children) {
    const s = el('section', { id }, el('h2', { text: title }), ...children);
    main.append(s);
    toc.append(el('a', { href: '#' + id, text: title }));
    return s;
  }
  function prefixOf(path) {
    const i = path.lastIndexOf('/');
    return i < 0 ? '' : path.slice(0, i + 1);
  }
  function summaries() {
    return Object.keys(files).filter((p) => p.endsWith('summary.json')).map((p) => [p, files[p]]);
  }
  function provenance() {
    const s = summaries()[0];
    const b = s && s[1].build;
    const what = `${R.kind} folder ${R.folder}`;
    document.getElementById('provenance').textContent = !b ? what :
      `${what} · chainmail ${b.version} (${b.commit}), ${b.compiler}, ${b.build_type}, ` +
      `${b.threads} threads on ${b.host_cores} cores`;
    document.title = `chainmail ${R.kind}: ${R.folder}`;
  }

  function sceneFacts(scene, ring) {
    const w = scene.weave || {};
    const facts = [['scene', scene.name], ['description', scene.description || ''],
      ['weave', `${w.type} ${w.rows} × ${w.cols} (${ring && ring.count || '?'} rings)`],
      ['ring', `wire ⌀ ${scene.ring.wire_diameter * 1000} mm, inner ⌀ ${scene.ring.inner_diameter * 1000} mm`],
      ['duration', `${scene.duration} s, sampled every ${scene.sample_interval} s`],
      ['colliders', (scene.colliders || []).map((c) => c.type).join(', ') || 'none'],
      ['pins', (scene.pins || []).map((p) => p.edge || p.corner || JSON.stringify(p)).join(', ') || 'none']];
    return el('table', { class: 'facts' }, el('tbody', {}, ...facts.map(([k, v]) =>
      el('tr', {}, el('th', { class: 'text', text: k }), el('td', { class: 'text', text: v })))));
  }
  const TIMING = ['dt', 'steps', 'wall_s', 'ms_per_step', 'realtime_factor', 'verdict', 'settled',
    'overstretched', 'hash'];
  function timingTable(summary, id) {
    const names = Object.keys(summary.backends);
    const cols = [{ name: 'backend' }].concat(TIMING.map((n) => ({ name: n,
      cls: n === 'verdict' ? verdictClass : null })));
    return table(cols, names.map((b) => [b].concat(TIMING.map((n) => summary.backends[b][n]))), id);
  }
  function metricsTable(summary, id) {
    const names = Object.keys(summary.backends);
    const keys = [];
    for (const b of names) for (const k of Object.keys(summary.backends[b].final || {}))
      if (!keys.includes(k)) keys.push(k);
    return table([{ name: 'backend' }].concat(keys.map((k) => ({ name: k }))),
      names.map((b) => [b].concat(keys.map((k) => (summary.backends[b].final || {})[k]))), id);
  }
  // one metric over time from metrics.csv, a line per backend, the metric chosen from a list
  function timePlot(text, id) {
    const csv = parseCSV(text);
    const metrics = csv.header.slice(2);
    const holder = el('div');
    const select = el('select', {}, ...metrics.map((m) => el('option', { value: m, text: m })));
    const draw = () => {
      const m = csv.col(select.value);
      const byBackend = {};
      for (const r of csv.rows) (byBackend[r[0]] = byBackend[r[0]] || []).push([Number(r[1]), r[m] === '' ? NaN : Number(r[m])]);
      const series = Object.keys(byBackend).map((b, i) => ({ name: b, colour: colour(b, i), points: byBackend[b] }));
      holder.replaceChildren(plot(series, { xlabel: 't (s)', ylabel: select.value, id }),
        legend(Object.keys(byBackend)));
    };
    select.addEventListener('change', draw);
    draw();
    return el('div', {}, el('label', { text: 'metric over time: ' }, select), holder);
  }
  function images(prefix) {
    return (R.images || []).filter((p) => prefixOf(p).startsWith(prefix) && !p.includes('sweep/') &&
      !p.startsWith('scaling')).map((p) => el('figure', {}, el('img', { src: p, loading: 'lazy', alt: p }),
      el('figcaption', { text: p })));
  }

  function runSections(path, summary, anchor) {
    const prefix = prefixOf(path);
    const scene = summary.scene;
    const children = [sceneFacts(scene, summary.ring),
      el('details', {}, el('summary', { text: 'resolved scene (JSON)' }),
        el('pre', { text: JSON.stringify(scene, null, 2) })),
      el('h3', { text: 'timing and verdicts' }), timingTable(summary, `timing-${anchor}`),
      el('h3', { text: 'final metrics' }), metricsTable(summary, `metrics-${anchor}`)];
    if (files[prefix + 'metrics.csv']) children.push(timePlot(files[prefix + 'metrics.csv'], `time-${anchor}`));
    children.push(...images(prefix));
    const folder = prefix.slice(0, -1);
    // a bench scene that kept frames: its 3D view, started when scrolled to
    const F = R.kind === 'bench' && R.scene_frames && R.scene_frames[folder];
    const view = F ? el('div', { class: 'view3d', id: `view3d-${anchor}` }) : null;
    if (view) children.push(el('h3', { text: '3D view of every backend' }), view);
    section(anchor, `scene ${scene.name}` + (folder && folder !== scene.name ? ` (${folder})` : ''), ...children);
    if (view) window.chainmailView.mount(view, summary, F, parseCSV(files[prefix + 'metrics.csv'] || ''), `-${anchor}`, true);
  }

  function sweepSection(path, anchor) {
    const csv = parseCSV(files[path]);
    const [b, t, e, st] = ['backend', 'wall_per_sim_s', 'error_m', 'stable'].map(csv.col);
    const byBackend = {};
    const finite = [];
    for (const r of csv.rows) {
      const p = [Number(r[t]), r[e] === '' ? NaN : Number(r[e]), r[st] === 'true'];
      (byBackend[r[b]] = byBackend[r[b]] || []).push(p);
      if (p[2] && isFinite(p[1]) && p[1] > 0 && p[0] > 0) finite.push(p.concat([r[b]]));
    }
    const front = pareto(finite);
    // an unstable point's error can be astronomic: drawn at 10x the largest stable error at most
    const cap = 10 * Math.max(...finite.map((p) => p[1]));
    if (isFinite(cap)) for (const pts of Object.values(byBackend)) for (const p of pts) if (!p[2] && p[1] > cap) p[1] = cap;
    const series = Object.keys(byBackend).map((n, i) => ({ name: n, colour: colour(n, i),
      points: byBackend[n].slice().sort((p, q) => p[0] - q[0]) }));
    const extra = (root, X, Y) => {
      if (front.length > 1) root.append(window.cm.svg('polyline', { fill: 'none', stroke: '#1d2430',
        'stroke-dasharray': '5 4', 'stroke-width': 1.2, class: 'pareto',
        points: front.map((p) => `${X.map(p[0])},${Y.map(p[1])}`).join(' ') }));
    };
    const name = path.split('/').slice(-2, -1)[0] || R.folder;
    section(anchor, `sweep ${name}: error against run time`,
      plot(series, { logx: true, logy: true, xlabel: 'wall time per simulated second (s)',
        ylabel: 'error against the reference (m)', extra, id: `sweep-plot-${anchor}` }),
      legend(Object.keys(byBackend)),
      el('p', { class: 'muted', text: 'Hollow points: unstable (errors beyond the plot drawn at its top). Dashed: the Pareto front (no other ' +
        'stable point is both faster and closer to the reference).' }),
      el('h3', { text: 'Pareto front' }),
      table([{ name: 'backend' }, { name: 'wall_per_sim_s' }, { name: 'error_m' }],
        front.map((p) => [p[3], p[0], p[1]]), `pareto-${anchor}`),
      el('details', {}, el('summary', { text: 'every point' }), csvTable(files[path], `sweep-${anchor}`,
        (h) => (h === 'verdict' || h === 'stable' ? verdictClass : null))));
  }

  function stabilitySection(path, anchor) {
    const csv = parseCSV(files[path]);
    const v = csv.col('verdict');
    const stable = csv.rows.filter((r) => r[v] === 'stable').length;
    section(anchor, 'stability verdicts',
      el('p', { text: `${stable} of ${csv.rows.length} runs stable.` }),
      csvTable(files[path], `stability-${anchor}`,
        (h) => (h === 'verdict' ? verdictClass : h === 'overstretched' ? (x) => (x === 'yes' ? 'bad' : null) : null)));
  }

  function benchSections() {
    if (files['timing.csv']) section('timing', 'timing of every scene and backend', csvTable(files['timing.csv'], 'timing-table',
      (h) => (h === 'verdict' ? verdictClass : null)));
    if (files['scaling.csv']) section('scaling', 'scaling with the sheet size and threads',
      csvTable(files['scaling.csv'], 'scaling-table'),
      ...(R.images || []).filter((p) => p.startsWith('scaling')).map((p) => el('figure', {}, el('img', { src: p, alt: p }))));
    summaries().forEach(([p, s], i) => runSections(p, s, `scene-${i}`));
    Object.keys(files).filter((p) => p.endsWith('sweep.csv')).forEach((p, i) => sweepSection(p, `sweep-${i}`));
    Object.keys(files).filter((p) => p.endsWith('stability.csv')).forEach((p, i) => stabilitySection(p, `stability-${i}`));
  }

  function view3dSection() {
    const s = section('view3d', '3D view of every backend');
    s.classList.add('view3d');
    if (!R.frames) {
      s.append(el('p', { class: 'note', id: 'no-frames', text: 'This run kept no frames, so there is ' +
        'no 3D view: run it again with --frames --report to see the backends side by side in 3D.' }));
      return;
    }
    window.chainmailView.mount(s, files['summary.json'], R.frames, parseCSV(files['metrics.csv'] || ''), '', false);
  }

  if (!R) {
    main.append(el('p', { class: 'note', text: 'report/data.js is missing: write the page with chainmail report.' }));
    return;
  }
  provenance();
  if (R.kind === 'run') {
    const summary = files['summary.json'];
    runSections('summary.json', summary, 'scene');
    view3dSection();
  } else if (R.kind === 'bench') {
    benchSections();
  } else if (R.kind === 'sweep') {
    sweepSection('sweep.csv', 'sweep');
  } else if (R.kind === 'stability') {
    stabilitySection('stability.csv', 'stability');
  }
  document.body.dataset.ready = 'true';
})();
