// The SRICS dashboard: asks api/state every poll_ms (2 s) and redraws everything from it.
// Hand-written, no libraries: charts are inline SVG. Every text that came from the run
// (run ids, hosts, details) goes through textContent, never innerHTML.
'use strict';

const SVG = 'http://www.w3.org/2000/svg';
const COLORS = ['#2563eb', '#ea7a12', '#16a34a', '#9333ea', '#dc2626', '#0891b2', '#ca8a04', '#db2777'];
let selectedRun = null;
let lastOk = 0;
let pollMs = 2000;
let frameTimer = null;
let shownEpisode = '';

// ---- small DOM helpers ----
function $(id) { return document.getElementById(id); }
function el(tag, attrs, text) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}
function svg(tag, attrs, text) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}
function clear(node) { while (node.firstChild) node.removeChild(node.firstChild); return node; }
function thousands(n) { return n === null || n === undefined ? '–' : Math.round(n).toLocaleString('en-US'); }
function fixed(x, digits) { return x === null || x === undefined ? '–' : Number(x).toFixed(digits); }
function sig(x) {
  if (x === null || x === undefined) return '–';
  if (x === 0) return '0';
  const a = Math.abs(x);
  return a >= 1000 || a < 0.001 ? x.toExponential(2) : x.toPrecision(3);
}
function hms(s) {
  if (s === null || s === undefined) return '–';
  s = Math.max(0, Math.round(s));
  const h = Math.floor(s / 3600), m = Math.floor(s / 60) % 60, r = s % 60;
  return String(h).padStart(2, '0') + ':' + String(m).padStart(2, '0') + ':' + String(r).padStart(2, '0');
}
function facts(dl, items) {
  clear(dl);
  for (const [name, value] of items) {
    const d = el('div');
    d.appendChild(el('dt', {}, name));
    d.appendChild(el('dd', {title: value}, value));
    dl.appendChild(d);
  }
}

// ---- charts ----
// Round tick steps (1, 2, 5 x 10^k) covering [lo, hi] with about n ticks.
function ticks(lo, hi, n) {
  if (!(hi > lo)) { hi = lo + 1; }
  const raw = (hi - lo) / n, mag = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map(f => f * mag).find(s => s >= raw);
  const out = [];
  for (let t = Math.ceil(lo / step) * step; t <= hi + step * 1e-9; t += step) out.push(Number(t.toPrecision(12)));
  return out;
}
function tickText(t) {
  const a = Math.abs(t);
  if (a >= 1e6) return (t / 1e6) + 'M';
  if (a >= 1e3) return (t / 1e3) + 'k';
  return String(Number(t.toPrecision(4)));
}

// series: [{name, color, points: [[x, y], ...], dashed, markers}]; options: xLabel, yLabel,
// yMin, yMax (fixed range ends), height
function lineChart(container, series, options) {
  clear(container);
  const all = series.flatMap(s => s.points).filter(p => isFinite(p[0]) && isFinite(p[1]));
  if (all.length === 0) {
    container.appendChild(el('div', {class: 'empty'}, options.empty || 'no data yet'));
    return;
  }
  // the drawing is as wide as its box, so text keeps its size at any window width
  const W = Math.max(280, container.clientWidth || options.width || 760), H = options.height || 300;
  const m = {l: 56, r: 14, t: 10, b: 52};
  let x0 = Math.min(...all.map(p => p[0])), x1 = Math.max(...all.map(p => p[0]));
  let y0 = options.yMin !== undefined ? options.yMin : Math.min(...all.map(p => p[1]));
  let y1 = options.yMax !== undefined ? options.yMax : Math.max(...all.map(p => p[1]));
  if (options.xMin !== undefined) x0 = Math.min(x0, options.xMin);
  if (x1 === x0) x1 = x0 + 1;
  if (y1 === y0) { y1 += Math.abs(y1) * 0.1 || 1; y0 -= Math.abs(y0) * 0.1 || 0; }
  const pad = (y1 - y0) * 0.06;
  if (options.yMin === undefined) y0 -= pad;
  if (options.yMax === undefined) y1 += pad;
  const X = x => m.l + (x - x0) / (x1 - x0) * (W - m.l - m.r);
  const Y = y => H - m.b - (y - y0) / (y1 - y0) * (H - m.t - m.b);
  const root = svg('svg', {viewBox: `0 0 ${W} ${H}`, role: 'img'});
  for (const t of ticks(y0, y1, 5)) {
    if (t < y0 || t > y1) continue;
    root.appendChild(svg('line', {class: 'grid', x1: m.l, x2: W - m.r, y1: Y(t), y2: Y(t)}));
    root.appendChild(svg('text', {x: m.l - 6, y: Y(t) + 4, 'text-anchor': 'end'}, tickText(t)));
  }
  for (const t of ticks(x0, x1, 6)) {
    if (t < x0 || t > x1) continue;
    root.appendChild(svg('line', {class: 'axis', x1: X(t), x2: X(t), y1: H - m.b, y2: H - m.b + 4}));
    root.appendChild(svg('text', {x: X(t), y: H - m.b + 16, 'text-anchor': 'middle'}, tickText(t)));
  }
  root.appendChild(svg('line', {class: 'axis', x1: m.l, x2: W - m.r, y1: H - m.b, y2: H - m.b}));
  root.appendChild(svg('line', {class: 'axis', x1: m.l, x2: m.l, y1: m.t, y2: H - m.b}));
  if (options.xLabel) root.appendChild(svg('text', {x: (m.l + W - m.r) / 2, y: H - m.b + 31, 'text-anchor': 'middle'}, options.xLabel));
  if (options.yLabel) root.appendChild(svg('text', {x: 12, y: (m.t + H - m.b) / 2, 'text-anchor': 'middle', transform: `rotate(-90 12 ${(m.t + H - m.b) / 2})`}, options.yLabel));
  series.forEach((s, i) => {
    const pts = s.points.filter(p => isFinite(p[0]) && isFinite(p[1]));
    if (pts.length === 0) return;
    const d = pts.map((p, k) => (k ? 'L' : 'M') + X(p[0]).toFixed(1) + ' ' + Y(p[1]).toFixed(1)).join(' ');
    const path = svg('path', {class: 'series ' + (s.cls || ''), d: d, stroke: s.color, 'data-points': pts.length});
    if (s.dashed) path.setAttribute('stroke-dasharray', '6 4');
    root.appendChild(path);
    if (s.markers && pts.length <= 80)
      for (const p of pts) root.appendChild(svg('circle', {cx: X(p[0]), cy: Y(p[1]), r: 2.8, fill: s.color}));
  });
  // legend along the bottom
  let lx = m.l;
  const ly = H - 8;
  const legend = svg('g', {class: 'legend'});
  for (const s of series.filter(s => s.name)) {
    const line = svg('line', {x1: lx, x2: lx + 18, y1: ly - 4, y2: ly - 4, stroke: s.color, 'stroke-width': 2.5});
    if (s.dashed) line.setAttribute('stroke-dasharray', '5 3');
    legend.appendChild(line);
    const text = svg('text', {x: lx + 23, y: ly}, s.name);
    legend.appendChild(text);
    lx += 30 + s.name.length * 6.3;
  }
  root.appendChild(legend);
  container.appendChild(root);
}

// ---- sections ----
function drawProgress(doc, run) {
  $('env-steps').textContent = thousands(run.env_steps);
  const budget = run.budget_env_steps;
  $('budget').textContent = budget ? '/ ' + thousands(budget) + '  (' + fixed(100 * Math.min(1, run.env_steps / budget), 1) + '%)' : '';
  $('bar-fill').style.width = budget ? (100 * Math.min(1, run.env_steps / budget)) + '%' : '0';
  const e = run.latest_eval, p = run.passive;
  const rel = (a, b) => (a !== undefined && b) ? '  (' + (a <= b ? '' : '+') + fixed(100 * (a - b) / b, 0) + '%)' : '';
  facts($('progress-facts'), [
    ['run', run.run_id],
    ['env steps / s', run.env_steps_per_second === null ? '–' : fixed(run.env_steps_per_second, 0)],
    ['ETA', hms(run.eta_s)],
    ['elapsed', doc.elapsed_s === null ? '–' : hms(doc.elapsed_s)],
    ['object dist. (vs passive)', e ? fixed(e.avg_object_distance, 4) + rel(e.avg_object_distance, p && p.avg_object_distance) : '–'],
    ['distance (vs passive)', e ? fixed(e.avg_distance, 4) + rel(e.avg_distance, p && p.avg_distance) : '–'],
    ['success', e ? fixed(e.success_rate, 2) : '–'],
    ['policy', e ? 'v' + e.policy_version : (run.learner ? 'v' + run.learner.policy_version : '–')],
  ]);
}

function drawCurve(run) {
  const evals = run.evals.slice().sort((a, b) => a.env_steps - b.env_steps);
  const series = [
    {name: 'object distance', cls: 'curve-object', color: COLORS[0], markers: true,
     points: evals.map(e => [e.env_steps, e.avg_object_distance])},
    {name: 'distance (arm + objects)', cls: 'curve-distance', color: COLORS[1], markers: true,
     points: evals.map(e => [e.env_steps, e.avg_distance])},
  ];
  if (run.passive && evals.length) {
    const xs = [0, Math.max(run.env_steps, evals[evals.length - 1].env_steps)];
    series.push({name: 'passive: object distance', cls: 'passive-object', color: COLORS[0], dashed: true,
                 points: xs.map(x => [x, run.passive.avg_object_distance])});
    series.push({name: 'passive: distance', cls: 'passive-distance', color: COLORS[1], dashed: true,
                 points: xs.map(x => [x, run.passive.avg_distance])});
  }
  lineChart($('curve'), series, {xLabel: 'env steps', yLabel: 'distance to goal (m)', yMin: 0, xMin: 0, height: 300,
                                 empty: run.passive ? 'passive policy evaluated; waiting for the first trained policy\'s evaluation'
                                                    : 'no evaluation yet'});
}

function drawSubgoals(run) {
  const evals = run.evals.slice().sort((a, b) => a.env_steps - b.env_steps);
  const n = evals.reduce((m, e) => Math.max(m, e.subgoal_success.length), 0);
  const series = [];
  for (let i = 0; i < n; ++i) {
    const last = evals.length ? evals[evals.length - 1].subgoal_success[i] : undefined;
    series.push({name: (i === 0 ? 'e0 (arm)' : 'e' + i) + (last !== undefined ? ' ' + fixed(last, 2) : ''),
                 color: COLORS[i % COLORS.length], markers: true,
                 points: evals.filter(e => i < e.subgoal_success.length).map(e => [e.env_steps, e.subgoal_success[i]])});
  }
  lineChart($('subgoals'), series, {xLabel: 'env steps', yLabel: 'success rate', yMin: 0, yMax: 1, xMin: 0, height: 260});
}

function drawLearner(run) {
  const s = run.learner;
  $('learner-meta').textContent = s ? 'stats ' + (s.age_s < 60 ? fixed(s.age_s, 1) + ' s' : hms(s.age_s)) + ' ago' + (run.weights ? ', weights v' + run.weights.version : '') : 'no stats yet';
  facts($('learner-facts'), s ? [
    ['updates', thousands(s.updates)], ['updates / s', fixed(s.updates_per_second, 1)],
    ['inserts / s', fixed(s.inserts_per_second, 0)], ['replay', thousands(s.replay_size)],
    ['q loss', sig(s.q_loss)], ['policy loss', sig(s.policy_loss)],
    ['alpha', sig(s.alpha)], ['entropy', sig(s.entropy)], ['mean reward', sig(s.mean_reward)],
    ['episodes', thousands(s.episodes_accepted) + (s.episodes_rejected ? ' (' + thousands(s.episodes_rejected) + ' bad)' : '')],
  ] : []);
  const h = run.learner_history;
  const col = name => h.updates.map((u, i) => [u, h[name][i]]);
  const trained = pts => pts.filter(p => p[0] > 0);
  const small = {xLabel: 'updates', height: 170, empty: 'no updates yet'};
  lineChart($('q-loss'), [{name: 'q loss', color: COLORS[3], points: trained(col('q_loss'))}], small);
  lineChart($('policy-loss'), [{name: 'policy loss', color: COLORS[5], points: trained(col('policy_loss'))}], small);
  lineChart($('alpha'), [{name: 'alpha (temperature)', color: COLORS[7], points: trained(col('alpha'))}], small);
  lineChart($('rates'), [
    {name: 'updates / s', color: COLORS[2], points: col('updates_per_second')},
    {name: 'inserts / s', color: COLORS[6], points: col('inserts_per_second')},
  ], Object.assign({}, small, {yMin: 0, empty: 'no stats yet'}));
}

function entityName(i) { return i === 0 ? 'arm' : 'e' + i; }

function drawGraph(run) {
  const box = clear($('graph')), heat = clear($('heatmap'));
  const g = run.graph;
  if (!g) {
    $('graph-meta').textContent = '';
    box.appendChild(el('div', {class: 'empty'}, 'no graph yet (the graph service is learning it)'));
    return;
  }
  $('graph-meta').textContent = 'v' + g.version + ', ' + g.edge_count + ' edges, threshold ' + fixed(g.threshold, 2) +
      ', held-out loss ' + sig(g.held_out_loss) + ', ' + thousands(g.episodes_used) + ' episodes';
  const n = g.num_entities, W = 400, H = 340, cx = W / 2, cy = H / 2 + 4, R = Math.min(W, H) / 2 - 42;
  const root = svg('svg', {viewBox: `0 0 ${W} ${H}`, id: 'graph-svg'});
  const defs = svg('defs');
  const marker = svg('marker', {id: 'arrow', viewBox: '0 0 10 10', refX: 9, refY: 5, markerWidth: 9, markerHeight: 9,
                                markerUnits: 'userSpaceOnUse', orient: 'auto-start-reverse'});
  marker.appendChild(svg('path', {d: 'M0 0 L10 5 L0 10 z', fill: '#4b5563'}));
  defs.appendChild(marker);
  root.appendChild(defs);
  // the action node at the top of a regular (n + 1)-gon, the entities on its other corners
  const corner = k => {
    const a = -Math.PI / 2 + k * 2 * Math.PI / (n + 1);
    return [cx + R * Math.cos(a), cy + R * Math.sin(a), a];
  };
  const action = corner(0);
  const pos = [];
  for (let i = 0; i < n; ++i) pos.push(corner(i + 1));
  const nodeR = 18;
  const arrow = (from, to, weight, bend, cls) => {
    const dx = to[0] - from[0], dy = to[1] - from[1], len = Math.hypot(dx, dy) || 1;
    const ux = dx / len, uy = dy / len;
    const a = [from[0] + ux * nodeR, from[1] + uy * nodeR], b = [to[0] - ux * (nodeR + 2), to[1] - uy * (nodeR + 2)];
    const mx = (a[0] + b[0]) / 2 - uy * bend, my = (a[1] + b[1]) / 2 + ux * bend;
    const width = weight === null ? 1.6 : 1 + 3 * Math.max(0, Math.min(1, weight));
    root.appendChild(svg('path', {class: cls, d: `M${a[0]} ${a[1]} Q${mx} ${my} ${b[0]} ${b[1]}`, fill: 'none',
                                  stroke: '#4b5563', 'stroke-width': width, 'marker-end': 'url(#arrow)'}));
    if (weight !== null)
      root.appendChild(svg('text', {class: 'edge-label', x: (a[0] + 2 * mx + b[0]) / 4, y: (a[1] + 2 * my + b[1]) / 4 + 4,
                                    'text-anchor': 'middle'}, fixed(weight, 2)));
  };
  if (g.action_entity >= 0 && g.action_entity < n) arrow(action, pos[g.action_entity], null, 0, 'edge action-edge');
  for (const e of g.edges) {
    const reciprocal = g.edges.some(o => o.from === e.to && o.to === e.from);
    arrow(pos[e.from], pos[e.to], e.weight, reciprocal ? 30 : 0, 'edge');
  }
  const node = (p, label, color, title) => {
    const gEl = svg('g', {class: 'node'});
    gEl.appendChild(svg('circle', {cx: p[0], cy: p[1], r: nodeR, fill: color}));
    gEl.appendChild(svg('text', {x: p[0], y: p[1] + 4, 'text-anchor': 'middle'}, label));
    gEl.appendChild(svg('title', {}, title));
    root.appendChild(gEl);
  };
  node(action, 'act', '#1f2430', 'the action');
  for (let i = 0; i < n; ++i) {
    const depth = g.depths[i];
    node(pos[i], i === 0 ? 'arm' : 'e' + i, depth < 0 ? COLORS[4] : COLORS[i % COLORS.length],
         entityName(i) + ': depth ' + (depth < 0 ? '– (not controllable)' : depth));
    // the depth outside the polygon, beyond the node
    const a = pos[i][2], c = Math.cos(a), side = Math.abs(c) > 0.35;
    const out = R + nodeR + (side ? 5 : 13);
    root.appendChild(svg('text', {x: cx + out * c, y: cy + out * Math.sin(a) + 4,
                                  'text-anchor': side ? (c > 0 ? 'start' : 'end') : 'middle'},
                         'depth ' + (depth < 0 ? '–' : depth)));
  }
  box.appendChild(root);
  // the mean weight matrix as a heat map (rows: from, columns: to)
  const table = el('table');
  table.appendChild(el('caption', {}, 'mean edge weights, row → column'));
  const head = el('tr');
  head.appendChild(el('th'));
  for (let j = 0; j < n; ++j) head.appendChild(el('th', {}, entityName(j)));
  table.appendChild(head);
  for (let i = 0; i < n; ++i) {
    const tr = el('tr');
    tr.appendChild(el('th', {}, entityName(i)));
    for (let j = 0; j < n; ++j) {
      const w = g.mean_weights[i][j];
      const td = el('td', {}, i === j ? '' : fixed(w, 2));
      const kept = g.edges.some(e => e.from === i && e.to === j);
      td.style.background = i === j ? '#f3f4f6' : `rgba(37, 99, 235, ${0.08 + 0.8 * Math.max(0, Math.min(1, w))})`;
      td.style.color = w > 0.5 && i !== j ? '#fff' : '#1f2430';
      if (kept) td.style.fontWeight = '700';
      tr.appendChild(td);
    }
    table.appendChild(tr);
  }
  heat.appendChild(table);
}

function drawNodes(doc, runId) {
  const table = clear($('nodes'));
  const counts = doc.node_counts;
  $('node-counts').textContent = counts.alive + ' alive, ' + counts.quiet + ' quiet, ' + counts.exited + ' exited, ' +
      counts.lost + ' lost';
  const head = el('tr');
  for (const h of ['role', 'id', 'host', 'pid', 'state', 'health', 'policy', 'graph', 'env steps', 'dropped', 'uptime', 'last seen', 'detail'])
    head.appendChild(el('th', {}, h));
  table.appendChild(head);
  const nodes = doc.nodes.filter(n => !runId || n.run_id === runId);
  if (nodes.length === 0) {
    const tr = el('tr');
    tr.appendChild(el('td', {colspan: 13, class: 'muted'}, 'none seen yet'));
    table.appendChild(tr);
  }
  for (const n of nodes) {
    const tr = el('tr');
    const cells = [n.role, n.id, n.host, n.pid, n.state, null, 'v' + n.policy_version, 'v' + n.graph_version,
                   thousands(n.env_steps), n.dropped_samples, hms(n.uptime_s),
                   n.last_seen_s < 60 ? fixed(n.last_seen_s, 1) + ' s ago' : hms(n.last_seen_s) + ' ago', n.detail];
    cells.forEach((c, i) => {
      const td = el('td', {class: i === 12 ? 'detail' : ([1, 3, 8, 9].includes(i) ? 'num' : '')});
      if (i === 5) td.appendChild(el('span', {class: 'health ' + n.health}, n.health));
      else td.textContent = String(c);
      tr.appendChild(td);
    });
    table.appendChild(tr);
  }
}

function drawProcesses(doc) {
  const card = $('processes-card');
  card.hidden = doc.processes.length === 0 && doc.events.length === 0;
  const table = clear($('processes'));
  if (doc.processes.length) {
    const head = el('tr');
    for (const h of ['name', 'pid', 'state', 'restarts', 'last exit']) head.appendChild(el('th', {}, h));
    table.appendChild(head);
    for (const p of doc.processes) {
      const tr = el('tr');
      for (const c of [p.name, p.pid || '–', p.state, p.restarts, p.last_exit || '–']) tr.appendChild(el('td', {}, String(c)));
      table.appendChild(tr);
    }
  }
  const events = clear($('events'));
  for (const e of doc.events) events.appendChild(el('li', {}, e));
}

function drawEpisode(doc) {
  const ep = doc.episode;
  const key = ep ? ep.url + '@' + ep.modified + '#' + ep.frames : '';
  if (key === shownEpisode) return;
  shownEpisode = key;
  const box = $('episode');
  if (frameTimer) { clearInterval(frameTimer); frameTimer = null; }
  if (!ep) return;
  clear(box);
  const m = ep.metrics || {};
  $('episode-meta').textContent = ep.name + ', written ' + new Date(ep.modified * 1000).toISOString().slice(0, 16).replace('T', ' ') + ' UTC';
  const num = (k, d) => m[k] === undefined || m[k] === '' ? '–' : Number(m[k]).toFixed(d);
  facts($('episode-facts'), m.episode === undefined ? [] : [
    ['distance', num('avg_distance', 4)], ['object distance', num('avg_object_distance', 4)],
    ['success', m.success === '1' ? 'yes' : m.success === '0' ? 'no' : '–'], ['steps', m.steps || '–'],
    ['selectivity', num('selectivity', 3)]]);
  if (ep.kind === 'mp4') {
    box.appendChild(el('video', {src: ep.url + '?t=' + ep.modified, autoplay: '', loop: '', muted: '', controls: '',
                                 playsinline: ''}));
  } else if (ep.kind === 'gif') {
    box.appendChild(el('img', {src: ep.url + '?t=' + ep.modified, alt: ep.name}));
  } else {
    // a folder of PNG frames: played at 10 frames per second
    const frame = k => ep.url + '/frame-' + String(k).padStart(5, '0') + '.png?t=' + ep.modified;
    const img = el('img', {alt: ep.name, src: frame(0)});
    box.appendChild(img);
    let k = 0;
    frameTimer = setInterval(() => {
      k = (k + 1) % ep.frames;
      img.src = frame(k);
    }, 100);
  }
}

let lastDoc = null;
function draw(doc) {
  lastDoc = doc;
  pollMs = doc.poll_ms || 2000;
  $('title').textContent = doc.title;
  $('source').textContent = doc.source + (doc.run_dir ? ' · ' + doc.run_dir : '');
  const select = $('run-select');
  const ids = doc.runs.map(r => r.run_id);
  $('runs-bar').hidden = ids.length <= 1;
  if (select.options.length !== ids.length || ids.some((id, i) => select.options[i].value !== id)) {
    clear(select);
    for (const id of ids) select.appendChild(el('option', {value: id}, id));
  }
  if (!ids.includes(selectedRun)) selectedRun = ids.length ? ids[ids.length - 1] : null;
  select.value = selectedRun || '';
  const run = doc.runs.find(r => r.run_id === selectedRun);
  if (run) {
    drawProgress(doc, run);
    drawCurve(run);
    drawSubgoals(run);
    drawLearner(run);
    drawGraph(run);
  }
  drawNodes(doc, ids.length > 1 ? selectedRun : null);
  drawProcesses(doc);
  drawEpisode(doc);
}

async function poll() {
  try {
    const response = await fetch('api/state', {cache: 'no-store'});
    if (response.ok) {
      const doc = await response.json();
      draw(doc);
      lastOk = Date.now();
      $('source').classList.remove('stale');
    }
  } catch (e) {
    // the program went away (the run ended) or the link broke: keep the last picture
  }
  const age = lastOk ? (Date.now() - lastOk) / 1000 : null;
  $('updated').textContent = age === null ? 'no answer yet' : age < pollMs / 1000 + 1 ? 'live, every ' + pollMs / 1000 + ' s'
                                                             : 'no answer for ' + age.toFixed(0) + ' s';
  if (age !== null && age > 3 * pollMs / 1000) $('source').classList.add('stale');
  setTimeout(poll, pollMs);
}

$('run-select').addEventListener('change', e => { selectedRun = e.target.value; if (lastDoc) draw(lastDoc); });
window.addEventListener('resize', () => { if (lastDoc) draw(lastDoc); });
poll();
