// The browser HMI (hmi-bridge/README.md "Web HMI"): plain JavaScript, no
// build step. One WebSocket (/api/ws) brings everything the bridge
// publishes; commands go as POST /api/command with the session's CSRF token.
'use strict';

const $ = (s) => document.querySelector(s);
const el = (tag, attrs = {}, ...kids) => {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') e.className = v; else if (k.startsWith('data-')) e.setAttribute(k, v);
    else e[k] = v;
  }
  for (const c of kids) e.append(c);
  return e;
};

const S = {
  csrf: '', desc: null, vars: [], index: new Map(), text: [], num: [], forced: new Set(),
  rows: new Map(), trend: new Map(), trendWindow: 60, zoom: null, lastStats: 0, lastScans: null,
  stalled: false, ws: null, alarms: new Map(), diag: null, history: [],
};
window.plcHmi = S;  // for the browser tests: what the page holds

// ------------------------------------------------------------ session

async function api(path, body) {
  const opt = body === undefined ? {} : {
    method: 'POST', body, headers: {'X-CSRF-Token': S.csrf, 'Content-Type': 'text/plain'}};
  const r = await fetch(path, opt);
  let j = {};
  try { j = await r.json(); } catch (e) { j = {ok: false, refusal: 'HTTP ' + r.status}; }
  j.status = r.status;
  return j;
}

async function start() {
  const s = await api('/api/session');
  if (!s.session) return showLogin(s.login);
  S.csrf = s.csrf;
  $('#login').hidden = true;
  $('#views').hidden = false;
  $('#logout').hidden = s.login === 'none';
  connect();
}

function showLogin(kind) {
  $('#login').hidden = false;
  $('#views').hidden = true;
  $('#login-hint').textContent = kind === 'key'
    ? 'The password is the cell\'s HMI key (the 64 hex digits of hmi: key_file).'
    : 'The password of hmi: web: login.';
  $('#password').focus();
}

$('#login-form').addEventListener('submit', async (ev) => {
  ev.preventDefault();
  const r = await fetch('/api/login', {method: 'POST', body: $('#password').value,
    headers: {'Content-Type': 'text/plain'}});
  if (r.status === 429) {
    $('#login-error').textContent = 'too many failed logins: try again in ' +
      (r.headers.get('Retry-After') || '60') + ' s';
    return;
  }
  if (r.status !== 200) { $('#login-error').textContent = 'wrong password'; return; }
  $('#password').value = '';
  $('#login-error').textContent = '';
  start();
});
$('#logout').addEventListener('click', async () => {
  await api('/api/logout', '');
  location.reload();
});

function connect() {
  const ws = new WebSocket((location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/api/ws');
  S.ws = ws;
  ws.onmessage = (ev) => on(JSON.parse(ev.data));
  ws.onclose = () => {
    S.ws = null;
    setStale('No connection to the HMI bridge (plchmi): reconnecting ...');
    setTimeout(() => api('/api/session').then((s) => s.session ? connect() : showLogin(s.login))
      .catch(() => setTimeout(connect, 2000)), 1000);
  };
}

// ------------------------------------------------------------ messages

function on(m) {
  switch (m.t) {
    case 'desc': return onDesc(m);
    case 'values': return onValues(m);
    case 'stats': return onStats(m);
    case 'diag': return onDiag(m);
    case 'alarm': return onAlarm(m);
    case 'ack': return onAck(m.id);
  }
}

function onDesc(m) {
  S.desc = m;
  S.vars = m.vars;
  S.index = new Map(m.vars.map((v, i) => [v.p, i]));
  S.text = new Array(m.vars.length).fill('');
  S.num = new Array(m.vars.length).fill(null);
  $('#cell-name').textContent = 'softplc · ' + m.cell;
  $('#mode').textContent = (m.read_only ? 'read-only' : 'operate') +
    (m.stop_commands ? ' · pause/step allowed' : '');
  for (const b of ['#btn-pause', '#btn-step', '#btn-continue']) {
    $(b).disabled = !m.stop_commands || m.read_only;
    $(b).title = m.read_only ? 'the web HMI is read-only (hmi: web: read_only)'
      : m.stop_commands ? '' : 'not allowed: the cell\'s hmi: stop_commands is false';
  }
  buildTree();
}

function onValues(m) {
  const t = m.scan_utime ? m.scan_utime / 1e6 : Date.now() / 1000;
  for (const [i, text, num] of m.v) {
    if (i >= S.text.length) continue;
    S.text[i] = text;
    S.num[i] = num;
    const row = S.rows.get(i);
    if (row) row.textContent = text;
  }
  if (m.task) for (const [i, series] of S.trend) {
    if (S.vars[i] && S.vars[i].k === m.task && S.num[i] !== null) {
      series.push([t, S.num[i]]);
      if (series.length > 20000) series.splice(0, series.length - 20000);
    }
  }
  if (m.task && !$('#view-trends').hidden) drawTrend();
}

function onStats(m) {
  S.lastStats = Date.now();
  const tb = $('#tasks tbody');
  tb.replaceChildren(...m.tasks.map((k) => el('tr', {'data-task': k.name},
    el('td', {}, k.name), el('td', {class: 'num'}, ms(k.period_ns)),
    el('td', {class: 'num scans'}, String(k.scans)), el('td', {class: 'num'}, String(k.overruns)),
    el('td', {class: 'num'}, us(k.min_ns)), el('td', {class: 'num'}, us(k.avg_ns)),
    el('td', {class: 'num'}, us(k.max_ns)), el('td', {}, k.stop || 'running'))));
  const scans = m.tasks.map((k) => k.scans).join(',');
  S.stalled = S.lastScans !== null && scans === S.lastScans;
  S.lastScans = scans;
  const b = Object.assign({}, m.bridge, m.web);
  $('#bridge tbody').replaceChildren(...Object.entries(b).map(([k, v]) =>
    el('tr', {}, el('td', {}, k), el('td', {class: 'num'}, String(v)))));
  checkStale();
}

function onDiag(m) {
  S.diag = m;
  $('#devices tbody').replaceChildren(...m.devices.map((d) => el('tr', {'data-device': d.name},
    el('td', {}, d.name), el('td', {}, d.plugin), el('td', {}, d.task), el('td', {}, d.input),
    el('td', {}, d.output), el('td', {class: 'state state-' + d.state}, d.state),
    el('td', {class: 'num'}, String(d.changes)), el('td', {}, el('code', {}, d.diag)))));
  $('#alarms-active tbody').replaceChildren(...m.alarms.map((a) => el('tr', {},
    el('td', {}, a.source), el('td', {}, a.text || a.kind), el('td', {class: 'num'}, String(a.scan)))));
  $('#alarm-count').textContent = m.alarms.length ? '(' + m.alarms.length + ')' : '';
}

function onAlarm(a) {
  S.alarms.set(a.id, a);
  const when = new Date(a.utime / 1000).toLocaleTimeString();
  const ev = a.kind === 'device_lost' ? 'lost' : a.kind === 'device_back' ? 'back'
    : a.kind === 'device_online' ? 'online' : a.kind;
  const row = el('tr', {'data-alarm': String(a.id), class: a.acked ? 'acked' : ''},
    el('td', {}, when), el('td', {}, a.source), el('td', {}, a.text || (a.from + ' -> ' + a.to)),
    el('td', {}, a.acked ? 'acknowledged' : el('button', {onclick: () => ack(a.id)}, 'Acknowledge')));
  $('#alarm-events tbody').prepend(row);
  if (a.kind.startsWith('device_')) {
    $('#device-history tbody').prepend(el('tr', {class: 'hist-' + ev, 'data-device': a.source},
      el('td', {}, when), el('td', {}, a.source.replace(/^device /, '')),
      el('td', {}, ev + ' (' + a.from + ' -> ' + a.to + ')'), el('td', {class: 'num'}, String(a.scan))));
  }
}

function onAck(id) {
  const row = document.querySelector('tr[data-alarm="' + id + '"]');
  if (!row) return;
  row.className = 'acked';
  row.lastChild.textContent = 'acknowledged';
}

async function ack(id) {
  const r = await api('/api/command', 'ack\n' + (id === 'all' ? 'all' : String(id)));
  if (!r.ok) alert(r.refusal);
}
$('#ack-all').addEventListener('click', () => ack('all'));

const ms = (ns) => (ns / 1e6).toFixed(ns % 1e6 ? 3 : 0) + ' ms';
const us = (ns) => (ns / 1e3).toFixed(1) + ' µs';

function setStale(text) {
  $('#stale').hidden = !text;
  $('#stale').textContent = text || '';
}

function checkStale() {
  if (!S.ws) return;
  if (Date.now() - S.lastStats > 3500) setStale('Stale data: the bridge has sent nothing for ' +
    Math.round((Date.now() - S.lastStats) / 1000) + ' s (plcrun or plchmi stopped?)');
  else if (S.stalled) setStale('Stale data: the cell is not scanning (stopped, paused or at a breakpoint)');
  else setStale('');
}
setInterval(checkStale, 1000);

// ------------------------------------------------------------ variables

function buildTree() {
  S.rows.clear();
  const q = $('#search').value.trim().toLowerCase();
  const root = {kids: new Map(), vars: []};
  let shown = 0;
  S.vars.forEach((v, i) => {
    if (q && !(v.p.toLowerCase().includes(q) || v.ty.toLowerCase().includes(q) ||
               v.a.toLowerCase().includes(q))) return;
    shown++;
    const parts = v.p.split('.');
    let node = root;
    for (const p of parts.slice(0, -1)) {
      if (!node.kids.has(p)) node.kids.set(p, {kids: new Map(), vars: []});
      node = node.kids.get(p);
    }
    node.vars.push(i);
  });
  $('#var-count').textContent = shown + ' of ' + S.vars.length;
  const render = (node, name, depth) => {
    const kids = [];
    if (node.vars.length) {
      kids.push(el('table', {}, el('tbody', {}, ...node.vars.map((i) => varRow(i)))));
    }
    for (const [k, sub] of node.kids) kids.push(render(sub, k, depth + 1));
    if (name === null) return el('div', {}, ...kids);
    const d = el('details', {open: depth < 2 || q !== ''}, el('summary', {}, name), ...kids);
    return d;
  };
  $('#tree').replaceChildren(render(root, null, 0));
}

function varRow(i) {
  const v = S.vars[i];
  const val = el('td', {class: 'val'}, S.text[i]);
  S.rows.set(i, val);
  const flags = [v.w ? 'writable' : '', v.f ? 'forceable' : '', v.pub ? '' : 'not published']
    .filter(Boolean).join(' · ');
  const trend = el('input', {type: 'checkbox', checked: S.trend.has(i), title: 'trend'});
  trend.addEventListener('change', () => setTrend(i, trend.checked));
  return el('tr', {'data-path': v.p},
    el('td', {}, el('a', {href: '#', onclick: (e) => { e.preventDefault(); openDialog(i); }},
      v.p.split('.').pop())),
    el('td', {}, v.ty), el('td', {}, v.a), val,
    el('td', {}, S.forced.has(i) ? el('span', {class: 'forced'}, 'F') : ''),
    el('td', {class: 'flag'}, flags), el('td', {}, el('label', {}, trend, ' trend')));
}
$('#search').addEventListener('input', () => buildTree());

// ------------------------------------------------------------ write / force

let dlgIndex = -1;

async function openDialog(i) {
  dlgIndex = i;
  const v = S.vars[i];
  $('#dlg-path').textContent = v.p;
  $('#dlg-info').textContent = v.ty + (v.a ? ' at ' + v.a : '') + (v.k ? ', task ' + v.k : '');
  $('#dlg-now').textContent = S.text[i];
  $('#dlg-value').value = S.text[i];
  $('#dlg-result').textContent = '';
  $('#dlg-result').className = '';
  const rules = [];
  if (S.desc.read_only) rules.push('The web HMI is read-only (hmi: web: read_only): nothing can be written or forced.');
  else {
    if (!v.w) rules.push('Not writable: the cell\'s hmi: writable patterns do not match it.');
    if (!v.f) rules.push('Not forceable: the cell\'s hmi: forceable patterns do not match it.');
  }
  $('#dlg-rules').textContent = rules.join(' ');
  $('#dlg-rules').className = rules.length ? 'refusal' : '';
  $('#dialog').showModal();
  await refreshForced(i);
}

async function refreshForced(i) {
  const r = await api('/api/command', 'read\n' + S.vars[i].p);
  if (!r.ok || !r.values || !r.values[0]) return;
  const forced = r.values[0].forced;
  if (forced) S.forced.add(i); else S.forced.delete(i);
  if (dlgIndex === i) {
    $('#dlg-now').textContent = r.values[0].text;
    $('#dlg-forced').replaceChildren(forced ? el('span', {class: 'forced'}, 'FORCED') : '');
  }
  const row = S.rows.get(i);
  if (row) row.nextSibling.replaceChildren(forced ? el('span', {class: 'forced'}, 'F') : '');
}

$('#dlg-form').addEventListener('submit', async (ev) => {
  const verb = ev.submitter ? ev.submitter.value : 'close';
  if (verb === 'close') return;
  ev.preventDefault();
  const p = S.vars[dlgIndex].p;
  const body = verb === 'unforce' ? 'unforce\n' + p : verb + '\n' + p + '\n' + $('#dlg-value').value;
  const r = await api('/api/command', body);
  $('#dlg-result').className = r.ok ? 'ok' : 'refusal';
  $('#dlg-result').textContent = r.ok ? (verb + ' done' + (r.text ? ': ' + r.text : ''))
    : 'Refused: ' + r.refusal;
  await refreshForced(dlgIndex);
});

async function runCommand(verb) {
  const r = await api('/api/command', verb);
  $('#run-result').className = r.ok ? 'ok' : 'refusal';
  $('#run-result').textContent = r.ok ? verb + ': ' + (r.text || 'done') : 'Refused: ' + r.refusal;
}
$('#btn-pause').addEventListener('click', () => runCommand('pause'));
$('#btn-step').addEventListener('click', () => runCommand('step'));
$('#btn-continue').addEventListener('click', () => runCommand('continue'));

// ------------------------------------------------------------ trends

function setTrend(i, on) {
  if (on) S.trend.set(i, S.num[i] !== null ? [[Date.now() / 1000, S.num[i]]] : []);
  else S.trend.delete(i);
  $('#trend-list').textContent = S.trend.size
    ? [...S.trend.keys()].map((k) => S.vars[k].p).join(', ') : 'Tick "trend" next to a variable to plot it.';
}

// BOOL and integers step, REAL and TIME are lines; an axis per class.
const classOf = (ty) => ty === 'BOOL' ? 'BOOL' : /REAL/.test(ty) ? 'REAL'
  : /TIME/.test(ty) ? 'TIME' : 'INT';
const colors = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf', '#8c564b'];

function trendRange() {
  if (S.zoom) return S.zoom;
  let tmax = 0;
  for (const s of S.trend.values()) if (s.length) tmax = Math.max(tmax, s[s.length - 1][0]);
  if (!tmax) tmax = Date.now() / 1000;
  return [tmax - S.trendWindow, tmax];
}

function drawTrend() {
  const c = $('#trend-canvas');
  const g = c.getContext('2d');
  g.fillStyle = '#fff';
  g.fillRect(0, 0, c.width, c.height);
  const groups = new Map();
  for (const i of S.trend.keys()) {
    const k = classOf(S.vars[i].ty);
    if (!groups.has(k)) groups.set(k, []);
    groups.get(k).push(i);
  }
  S.drawn = 0;
  if (!groups.size) return;
  const [t0, t1] = trendRange();
  const L = 70, R = 10, H = (c.height - 30) / groups.size;
  let gi = 0, ci = 0;
  for (const [cls, idx] of groups) {
    const top = 5 + gi * H, h = H - 15;
    let lo = Infinity, hi = -Infinity;
    for (const i of idx) for (const [t, v] of S.trend.get(i)) {
      if (t >= t0 && t <= t1 && v !== null) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    }
    if (cls === 'BOOL') { lo = -0.1; hi = 1.1; }
    if (!isFinite(lo)) { lo = 0; hi = 1; }
    if (hi === lo) { hi += 1; lo -= 1; }
    const y = (v) => top + h - (v - lo) / (hi - lo) * h;
    const x = (t) => L + (t - t0) / (t1 - t0) * (c.width - L - R);
    g.strokeStyle = '#ccd'; g.strokeRect(L, top, c.width - L - R, h);
    g.fillStyle = '#333'; g.font = '11px sans-serif';
    g.fillText(cls, 4, top + 12);
    g.fillText(fmt(hi), 4, top + 26); g.fillText(fmt(lo), 4, top + h);
    for (const i of idx) {
      const color = colors[ci++ % colors.length];
      g.strokeStyle = color; g.lineWidth = 1.5; g.beginPath();
      const step = cls === 'BOOL' || cls === 'INT';
      let prev = null;
      for (const [t, v] of S.trend.get(i)) {
        if (t < t0 || t > t1 || v === null) continue;
        if (prev === null) g.moveTo(x(t), y(v));
        else if (step) { g.lineTo(x(t), y(prev)); g.lineTo(x(t), y(v)); } else g.lineTo(x(t), y(v));
        prev = v;
        S.drawn++;
      }
      g.stroke();
      g.fillStyle = color;
      g.fillText(S.vars[i].p, L + 8 + 160 * (idx.indexOf(i)), top + 12);
    }
    gi++;
  }
  g.fillStyle = '#333';
  g.fillText(new Date(t0 * 1000).toLocaleTimeString(), L, c.height - 8);
  g.fillText(new Date(t1 * 1000).toLocaleTimeString(), c.width - R - 60, c.height - 8);
}
const fmt = (v) => Math.abs(v) >= 1e5 || (v !== 0 && Math.abs(v) < 1e-3) ? v.toExponential(2)
  : String(+v.toFixed(3));

document.querySelectorAll('[data-window]').forEach((b) => b.addEventListener('click', () => {
  S.trendWindow = +b.dataset.window; S.zoom = null; drawTrend();
}));
$('#trend-live').addEventListener('click', () => { S.zoom = null; drawTrend(); });
{
  const c = $('#trend-canvas');
  let from = null;
  const tAt = (ev) => {
    const r = c.getBoundingClientRect();
    const px = (ev.clientX - r.left) * c.width / r.width;
    const [t0, t1] = trendRange();
    return t0 + (px - 70) / (c.width - 80) * (t1 - t0);
  };
  c.addEventListener('mousedown', (ev) => { from = tAt(ev); });
  c.addEventListener('mouseup', (ev) => {
    if (from === null) return;
    const to = tAt(ev);
    if (Math.abs(to - from) > 0.01) S.zoom = [Math.min(from, to), Math.max(from, to)];
    from = null;
    drawTrend();
  });
}

$('#trend-csv').addEventListener('click', () => {
  const idx = [...S.trend.keys()];
  const times = [...new Set(idx.flatMap((i) => S.trend.get(i).map((p) => p[0])))].sort((a, b) => a - b);
  const last = new Map();
  const rows = ['time_s,' + idx.map((i) => S.vars[i].p).join(',')];
  const pos = new Map(idx.map((i) => [i, 0]));
  for (const t of times) {
    for (const i of idx) {
      const s = S.trend.get(i);
      let p = pos.get(i);
      while (p < s.length && s[p][0] <= t) { last.set(i, s[p][1]); p++; }
      pos.set(i, p);
    }
    rows.push(t.toFixed(6) + ',' + idx.map((i) => last.has(i) ? last.get(i) : '').join(','));
  }
  const a = el('a', {href: URL.createObjectURL(new Blob([rows.join('\n') + '\n'], {type: 'text/csv'})),
    download: 'trend.csv'});
  document.body.append(a); a.click(); a.remove();
});

// ------------------------------------------------------------ views

document.querySelectorAll('header nav button').forEach((b) => b.addEventListener('click', () => {
  document.querySelectorAll('header nav button').forEach((x) => x.classList.toggle('active', x === b));
  document.querySelectorAll('.view').forEach((v) => { v.hidden = v.id !== 'view-' + b.dataset.view; });
  if (b.dataset.view === 'trends') drawTrend();
}));

start();
