// The page's building blocks: elements, number formatting, CSV parsing, sortable tables and SVG
// plots drawn from the folder's own numbers (no library).
'use strict';
window.cm = (function () {
  const SVG = 'http://www.w3.org/2000/svg';
  const COLOURS = { plausible: '#2f6fb5', massspring: '#e07b1a', bullet: '#2e9a4a',
    ode: '#c83a3a', torus_xpbd: '#7c4bb8' };
  const SPARE = ['#1a9aa0', '#a0761a', '#d0509a', '#5a6a7a'];

  function el(tag, attrs, ...children) {
    const node = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (k === 'text') node.textContent = v; else node.setAttribute(k, v);
    }
    for (const c of children) node.append(c);
    return node;
  }
  function svg(tag, attrs) {
    const node = document.createElementNS(SVG, tag);
    for (const [k, v] of Object.entries(attrs || {})) node.setAttribute(k, v);
    return node;
  }
  function colour(name, index) {
    return COLOURS[name] || SPARE[(index || 0) % SPARE.length];
  }
  // 4 significant digits; exponents for very large or small values; text as it is
  function fmt(v) {
    if (v === null || v === undefined || v === '') return '–';
    if (typeof v === 'boolean') return v ? 'yes' : 'no';
    const x = typeof v === 'number' ? v : Number(v);
    if (typeof v !== 'number' && (v.trim() === '' || !isFinite(x))) return String(v);
    if (x === 0 || Number.isInteger(x) && Math.abs(x) < 1e7) return String(x);
    const a = Math.abs(x);
    return a >= 1e5 || a < 1e-3 ? Number(x.toPrecision(4)).toExponential() : String(Number(x.toPrecision(4)));
  }
  // chainmail's CSV: a header line, comma-separated cells, no quoting
  function parseCSV(text) {
    const lines = text.split('\n').filter((l) => l.length > 0);
    const header = lines.length ? lines[0].split(',') : [];
    const rows = lines.slice(1).map((l) => l.split(','));
    return { header, rows, col: (name) => header.indexOf(name) };
  }
  function isNumber(s) {
    return typeof s === 'number' || (typeof s === 'string' && s.trim() !== '' && isFinite(Number(s)));
  }
  function sortBy(table, column, th) {
    const body = table.tBodies[0];
    const asc = !th.classList.contains('sorted-asc');
    for (const h of table.tHead.rows[0].cells) h.classList.remove('sorted-asc', 'sorted-desc');
    th.classList.add(asc ? 'sorted-asc' : 'sorted-desc');
    const rows = Array.from(body.rows);
    const key = (r) => r.cells[column].dataset.v;
    rows.sort((a, b) => {
      const x = key(a), y = key(b);
      const c = isNumber(x) && isNumber(y) ? Number(x) - Number(y) : String(x).localeCompare(y);
      return asc ? c : -c;
    });
    for (const r of rows) body.append(r);
  }
  // columns: [{name, title?, cls?(value,row)}]; rows: arrays of raw values (numbers or text)
  function table(columns, rows, id) {
    const head = el('tr');
    columns.forEach((c, i) => {
      const th = el('th', { text: c.title || c.name, 'data-col': c.name });
      th.addEventListener('click', () => sortBy(t, i, th));
      head.append(th);
    });
    const body = el('tbody');
    for (const row of rows) {
      const tr = el('tr');
      columns.forEach((c, i) => {
        const v = row[i];
        const td = el('td', { text: fmt(v), 'data-col': c.name });
        td.dataset.v = v === null || v === undefined ? '' : String(v);
        if (!isNumber(v)) td.classList.add('text');
        const extra = c.cls && c.cls(v, row);
        if (extra) td.classList.add(extra);
        tr.append(td);
      });
      body.append(tr);
    }
    const t = el('table', { class: 'sortable' }, el('thead', {}, head), body);
    if (id) t.id = id;
    return el('div', { class: 'scroll' }, t);
  }
  function csvTable(text, id, cls) {
    const csv = parseCSV(text);
    const rows = csv.rows.map((r) => r.map((v) => (isNumber(v) ? Number(v) : v)));
    return table(csv.header.map((h) => ({ name: h, cls: cls && cls(h) })), rows, id);
  }
  function verdictClass(v) {
    return v === 'stable' || v === 'yes' || v === 'true' || v === true ? 'good' : 'bad';
  }

  // an axis: linear or log10, ticks at round values
  function axis(values, log, lo, hi) {
    let a = Math.min(...values), b = Math.max(...values);
    if (log) { a = Math.log10(a); b = Math.log10(b); }
    if (a === b) { a -= 0.5; b += 0.5; }
    const pad = (b - a) * 0.06;
    a -= pad; b += pad;
    const map = (v) => lo + ((log ? Math.log10(v) : v) - a) / (b - a) * (hi - lo);
    const ticks = [];
    if (log) {
      const every = Math.max(1, Math.ceil((Math.floor(b) - Math.ceil(a)) / 7));
      for (let e = Math.ceil(a); e <= Math.floor(b); e += every) ticks.push(Math.pow(10, e));
      if (ticks.length < 2) ticks.push(Math.pow(10, a + (b - a) / 2));
    } else {
      const step = Math.pow(10, Math.floor(Math.log10((b - a) / 4)));
      const nice = [1, 2, 5, 10].map((m) => m * step).find((s) => (b - a) / s <= 6) || step * 10;
      for (let v = Math.ceil(a / nice) * nice; v <= b; v += nice) ticks.push(Number(v.toPrecision(12)));
    }
    return { map, ticks };
  }
  // series: [{name, colour, points: [[x, y, filled?]], line?}]; extra(svg, X, Y) draws on top
  function plot(series, opts) {
    const W = opts.width || 620, H = opts.height || 360, L = 70, R = 16, T = 14, B = 44;
    const all = series.flatMap((s) => s.points).filter((p) => isFinite(p[0]) && isFinite(p[1]) &&
      (!opts.logx || p[0] > 0) && (!opts.logy || p[1] > 0));
    const root = svg('svg', { class: 'plot', width: W, height: H, viewBox: `0 0 ${W} ${H}` });
    if (opts.id) root.id = opts.id;
    if (!all.length) {
      const t = svg('text', { x: W / 2, y: H / 2, 'text-anchor': 'middle' });
      t.textContent = 'no finite values to plot';
      root.append(t);
      return root;
    }
    const X = axis(all.map((p) => p[0]), opts.logx, L, W - R);
    const Y = axis(all.map((p) => p[1]), opts.logy, H - B, T);
    for (const v of X.ticks) {
      root.append(svg('line', { class: 'grid', x1: X.map(v), x2: X.map(v), y1: T, y2: H - B }));
      const t = svg('text', { x: X.map(v), y: H - B + 14, 'text-anchor': 'middle' });
      t.textContent = fmt(v);
      root.append(t);
    }
    for (const v of Y.ticks) {
      root.append(svg('line', { class: 'grid', x1: L, x2: W - R, y1: Y.map(v), y2: Y.map(v) }));
      const t = svg('text', { x: L - 4, y: Y.map(v) + 4, 'text-anchor': 'end' });
      t.textContent = fmt(v);
      root.append(t);
    }
    root.append(svg('rect', { class: 'axis', x: L, y: T, width: W - R - L, height: H - B - T, fill: 'none' }));
    const xl = svg('text', { x: (L + W - R) / 2, y: H - 8, 'text-anchor': 'middle' });
    xl.textContent = opts.xlabel;
    const yl = svg('text', { x: 14, y: (T + H - B) / 2, 'text-anchor': 'middle',
      transform: `rotate(-90 14 ${(T + H - B) / 2})` });
    yl.textContent = opts.ylabel;
    root.append(xl, yl);
    const ok = (p) => all.includes(p);
    for (const s of series) {
      const pts = s.points.filter(ok);
      if (s.line !== false && pts.length > 1) {
        root.append(svg('polyline', { fill: 'none', stroke: s.colour, 'stroke-width': 1.5,
          points: pts.map((p) => `${X.map(p[0])},${Y.map(p[1])}`).join(' ') }));
      }
      for (const p of pts) {
        root.append(svg('circle', { cx: X.map(p[0]), cy: Y.map(p[1]), r: 3.5, stroke: s.colour,
          fill: p[2] === false ? '#fff' : s.colour, 'data-series': s.name }));
      }
    }
    if (opts.extra) opts.extra(root, X, Y);
    return root;
  }
  function legend(names) {
    return el('div', { class: 'legend' },
      ...names.map((n, i) => el('span', {}, el('i', { style: `background:${colour(n, i)}` }), n)));
  }
  // the points no other point beats on both run time and error (smaller is better on both)
  function pareto(points) {
    const sorted = points.slice().sort((a, b) => a[0] - b[0] || a[1] - b[1]);
    const front = [];
    for (const p of sorted) if (!front.length || p[1] < front[front.length - 1][1]) front.push(p);
    return front;
  }
  return { el, svg, colour, fmt, parseCSV, isNumber, table, csvTable, verdictClass, plot, legend,
    pareto };
})();
