// wheeltec-web's page: a Foxglove WebSocket protocol client (the same protocol and server
// code path as Foxglove itself) for the plots, the status and the joystick; plain HTTP for
// STOP, E-STOP and Release, the daemon's counters and the recorder's files. docs/web.md
// describes it.
'use strict';

const WINDOW_S = 30;            // plotted history
const DRIVE_PERIOD_MS = 100;    // joystick repeat, well under wheeltecd's command_timeout_s (0.5 s)
const MAX_VX = 0.5, MAX_WZ = 1.5;
const token = new URLSearchParams(location.search).get('token');
const $ = (id) => document.getElementById(id);

// --- data kept for the plots ---
const series = { vx: [], vy: [], wz: [], gyro: [], accel: [], battery: [] };
const path = [];
let commanded = { vx: 0, vy: 0, wz: 0 };
let lowBatteryV = 10.8;
let records = 0, droppedHere = 0, lastSeq = null;

function trim(list, now) {
  while (list.length && list[0][0] < now - WINDOW_S * 1000) list.shift();
}

// --- plots (Debian's libjs-dygraphs) ---
const graphs = {};
function makeGraphs() {
  if (typeof Dygraph === 'undefined') { $('no-plots').hidden = false; return; }
  const make = (id, labels, title, extra) => {
    graphs[id] = new Dygraph($('plot-' + id), [[new Date(), ...labels.slice(1).map(() => null)]],
      Object.assign({ labels, title, legend: 'always', labelsSeparateLines: false, titleHeight: 18,
                      strokeWidth: 1.5, connectSeparatedPoints: true }, extra || {}));
  };
  make('vx', ['t', 'vx commanded', 'vx measured'], 'vx (m/s)');
  make('vy', ['t', 'vy commanded', 'vy measured'], 'vy (m/s)');
  make('wz', ['t', 'wz commanded', 'wz measured'], 'wz (rad/s)');
  make('gyro', ['t', 'gyro z'], 'gyro z (rad/s)');
  make('accel', ['t', 'accel x', 'accel y', 'accel z'], 'accel (m/s²)');
  make('battery', ['t', 'battery', 'low-battery line'], 'battery (V)');
}

let redrawPending = false;
function redraw() {
  if (redrawPending) return;
  redrawPending = true;
  setTimeout(() => {
    redrawPending = false;
    for (const [id, graph] of Object.entries(graphs)) {
      if (series[id].length) graph.updateOptions({ file: series[id] });
    }
    drawPath();
  }, 200);
}

function onTelemetry(r) {
  const t = new Date(r.time * 1000);
  if (lastSeq !== null && r.seq < lastSeq) path.length = 0;  // the daemon restarted
  lastSeq = r.seq;
  records++;
  series.vx.push([t, commanded.vx, r.velocity.vx]);
  series.vy.push([t, commanded.vy, r.velocity.vy]);
  series.wz.push([t, commanded.wz, r.velocity.wz]);
  series.gyro.push([t, r.gyro.z]);
  series.accel.push([t, r.accel.x, r.accel.y, r.accel.z]);
  series.battery.push([t, r.battery.voltage, lowBatteryV]);
  for (const list of Object.values(series)) trim(list, t.getTime());
  path.push([r.odom.x, r.odom.y, r.odom.yaw]);
  if (path.length > 20000) path.shift();
  $('seq').textContent = String(r.seq);
  $('velocity').textContent = `${r.velocity.vx.toFixed(3)} m/s, ${r.velocity.vy.toFixed(3)} m/s, ${r.velocity.wz.toFixed(3)} rad/s`;
  $('battery').textContent = `${r.battery.voltage.toFixed(2)} V${r.battery.low ? ' (LOW)' : ''}`;
  $('battery').className = r.battery.low ? 'bad' : '';
  $('pose').textContent = `x ${r.odom.x.toFixed(2)} m, y ${r.odom.y.toFixed(2)} m, yaw ${(r.odom.yaw * 180 / Math.PI).toFixed(0)}°`;
  document.body.dataset.live = 'true';
  document.body.dataset.records = String(records);  // received by this page
  redraw();
}

let transport = null;  // bus.transport: 'can' or 'serial' (protocol 3; absent from older daemons)
function onStatus(s) {
  const yes = (v) => (v ? 'yes' : 'no');
  transport = s.bus.transport || null;
  // "serial /dev/wheeltec_controller: up", "can can0: up"; an older daemon: "can0: up".
  $('bus-state').textContent = `${transport ? transport + ' ' : ''}${s.bus.interface}: ${s.bus.state}`;
  $('bus-state').className = s.bus.state === 'up' ? 'good' : 'bad';
  $('online').textContent = yes(s.chassis.online);
  $('online').className = s.chassis.online ? 'good' : 'bad';
  const ignored = transport === 'serial' ? ' (commands ignored)' : ' (commands ignored: check can.dialect)';
  $('phase').textContent = s.chassis.phase === null || s.chassis.phase === undefined ? '-' : s.chassis.phase +
    (s.chassis.commands_ignored ? ignored : '');
  $('enabled').textContent = yes(s.control.enabled);
  $('owner').textContent = s.control.owner === null ? 'nobody' : `client ${s.control.owner}`;
  commanded = s.control.target || { vx: 0, vy: 0, wz: 0 };
  chassisType = s.chassis.type || null;
  limits = s.control.limits || null;
  safety = s.safety || null;
  showSafety();
}

// --- the latched emergency stop (protocol 5): status `safety`, E-STOP and Release ---
let safety = null;     // status `safety`; null from a daemon before protocol 5
let readOnly = false;  // the server said this page may not drive
function showSafety() {
  const latched = Boolean(safety && safety.latched);
  document.body.dataset.latched = String(latched);
  $('safety').textContent = !safety ? '-' : latched ? `latched (${safety.source})` : 'not latched';
  $('safety').className = latched ? 'bad' : '';
  $('safety-banner').hidden = !latched;
  $('release').hidden = !latched || readOnly;
  if (!latched) return;
  const by = safety.source === 'client' && safety.by !== null ? ` (client ${safety.by})` : '';
  const since = safety.since ? new Date(safety.since * 1000) : null;
  $('safety-text').textContent = `source: ${safety.source}${by}; reason: ${safety.reason ? safety.reason : '(none given)'}` +
    (since ? `; since ${since.toLocaleString()}` : '');
}
// The answer of /api/estop or /api/release: {} or the daemon's error object with its code.
async function safetyRequest(what, init) {
  try {
    const response = await fetch(`/api/${what}`, Object.assign({ method: 'POST' }, init));
    const text = await response.text();
    let answer = null;
    try { answer = JSON.parse(text); } catch (error) { /* a plain-text refusal */ }
    if (response.ok) { showMessage(0, `${what === 'estop' ? 'E-STOP' : 'Release'} sent`); return; }
    const why = answer && answer.message ? `${answer.message} (${answer.code})` : text;
    showMessage(2, `${what === 'estop' ? 'E-STOP' : 'Release'} refused: ${why}`);
  } catch (error) {
    showMessage(2, `${what === 'estop' ? 'E-STOP' : 'Release'} failed: ${error}`);
  }
}
function estop(reason = 'operator pressed E-STOP') {
  joystickRelease(false);
  return safetyRequest('estop', { headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ reason }) });
}
function release() {
  return safetyRequest('release', { headers: token ? { Authorization: `Bearer ${token}` } : {} });
}

function drawPath() {
  const canvas = $('odom'), g = canvas.getContext('2d');
  g.clearRect(0, 0, canvas.width, canvas.height);
  if (!path.length) return;
  let minX = 0, maxX = 0, minY = 0, maxY = 0;
  for (const [x, y] of path) { minX = Math.min(minX, x); maxX = Math.max(maxX, x); minY = Math.min(minY, y); maxY = Math.max(maxY, y); }
  const span = Math.max(maxX - minX, maxY - minY, 1) * 1.2;
  const cx = (minX + maxX) / 2, cy = (minY + maxY) / 2, scale = canvas.width / span;
  const px = (x) => canvas.width / 2 + (x - cx) * scale, py = (y) => canvas.height / 2 - (y - cy) * scale;
  g.strokeStyle = '#ccc'; g.beginPath(); g.moveTo(px(0), 0); g.lineTo(px(0), canvas.height);
  g.moveTo(0, py(0)); g.lineTo(canvas.width, py(0)); g.stroke();
  g.strokeStyle = '#36c'; g.lineWidth = 2; g.beginPath();
  path.forEach(([x, y], i) => (i ? g.lineTo(px(x), py(y)) : g.moveTo(px(x), py(y))));
  g.stroke();
  const [x, y, yaw] = path[path.length - 1];
  g.fillStyle = '#d22'; g.beginPath();
  g.moveTo(px(x) + 10 * Math.cos(yaw), py(y) - 10 * Math.sin(yaw));
  g.lineTo(px(x) + 6 * Math.cos(yaw + 2.5), py(y) - 6 * Math.sin(yaw + 2.5));
  g.lineTo(px(x) + 6 * Math.cos(yaw - 2.5), py(y) - 6 * Math.sin(yaw - 2.5));
  g.fill();
}

// --- messages shown to the user ---
function showMessage(level, text) {
  const box = $('messages'), line = document.createElement('div');
  line.className = ['info', 'warning', 'error'][level] || 'error';
  line.textContent = `${new Date().toLocaleTimeString()} ${text}`;
  box.prepend(line);
  while (box.children.length > 5) box.lastChild.remove();
}

// --- the Foxglove WebSocket protocol ---
let ws = null, channels = {}, subscriptions = {}, cmdVelChannel = 1;
function connect() {
  const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/foxglove` +
    (token ? `?token=${encodeURIComponent(token)}` : '');
  ws = new WebSocket(url, 'foxglove.websocket.v1');
  ws.binaryType = 'arraybuffer';
  ws.onopen = () => { $('connection').textContent = 'connected'; $('connection').className = 'good'; };
  ws.onclose = () => {
    $('connection').textContent = 'disconnected: reconnecting'; $('connection').className = 'bad';
    joystickRelease();
    setTimeout(connect, 1000);
  };
  ws.onmessage = (event) => (typeof event.data === 'string' ? onText(JSON.parse(event.data)) : onBinary(event.data));
}

function onText(msg) {
  if (msg.op === 'serverInfo') {
    if (msg.metadata && msg.metadata.low_battery_v) lowBatteryV = Number(msg.metadata.low_battery_v);
  } else if (msg.op === 'advertise') {
    const wanted = [];
    for (const ch of msg.channels) {
      channels[ch.id] = ch.topic;
      if (ch.topic === '/wheeltec/telemetry' || ch.topic === '/wheeltec/status') {
        const id = Object.keys(subscriptions).length + 1;
        subscriptions[id] = ch.topic;
        wanted.push({ id, channelId: ch.id });
      }
    }
    ws.send(JSON.stringify({ op: 'subscribe', subscriptions: wanted }));
    ws.send(JSON.stringify({ op: 'advertise', channels: [{ id: cmdVelChannel, topic: '/wheeltec/cmd_vel',
      encoding: 'json', schemaName: 'wheeltec.CmdVel' }] }));
  } else if (msg.op === 'status') {
    if (msg.id === 'read-only') {
      readOnly = true;
      $('mode').textContent = 'read-only (no token): STOP and E-STOP only';
      showSafety();
      return;
    }
    if (msg.id === 'slow-viewer') droppedHere++;
    if (msg.id === 'drive-refused') { $('refusal').textContent = msg.message; joystickRelease(false); }
    showMessage(msg.level, msg.message);
  }
}

function onBinary(buffer) {
  const view = new DataView(buffer);
  if (view.getUint8(0) !== 1) return;
  const topic = subscriptions[view.getUint32(1, true)];
  const payload = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 13)));
  if (topic === '/wheeltec/telemetry') onTelemetry(payload);
  else if (topic === '/wheeltec/status') onStatus(payload);
}

function publishDrive(v) {
  if (!ws || ws.readyState !== WebSocket.OPEN) return;
  const body = new TextEncoder().encode(JSON.stringify(v));
  const frame = new Uint8Array(5 + body.length);
  frame[0] = 1;
  new DataView(frame.buffer).setUint32(1, cmdVelChannel, true);
  frame.set(body, 5);
  ws.send(frame);
}

// --- the joystick: repeats drive while held; release, blur and closing stop ---
let held = null, repeat = null, keys = new Set();
function joystickSet(x, y) {  // x, y in [-1, 1]; up = forward, left = turn left
  held = { vx: Number((MAX_VX * y).toFixed(3)), vy: 0, wz: Number((-MAX_WZ * x).toFixed(3)) };
  $('refusal').textContent = '';
  $('drive-state').textContent = `driving vx ${held.vx} m/s, wz ${held.wz} rad/s`;
  if (!repeat) { publishDrive(held); repeat = setInterval(() => publishDrive(held), DRIVE_PERIOD_MS); }
  drawJoystick(x, y);
}
function joystickRelease(sendZero = true) {
  if (repeat) { clearInterval(repeat); repeat = null; }
  if (held && sendZero) publishDrive({ vx: 0, vy: 0, wz: 0 });  // then silence: the deadman releases control
  held = null;
  $('drive-state').textContent = 'idle';
  drawJoystick(0, 0);
}
function drawJoystick(x, y) {
  const c = $('joystick'), g = c.getContext('2d'), r = c.width / 2;
  g.clearRect(0, 0, c.width, c.height);
  g.strokeStyle = '#aaa'; g.beginPath(); g.arc(r, r, r - 2, 0, 2 * Math.PI); g.stroke();
  g.fillStyle = held ? '#36c' : '#889'; g.beginPath(); g.arc(r + x * (r - 25), r - y * (r - 25), 22, 0, 2 * Math.PI); g.fill();
}
function setupJoystick() {
  const c = $('joystick');
  const fromEvent = (e) => {
    const box = c.getBoundingClientRect(), r = box.width / 2;
    let x = (e.clientX - box.left - r) / (r - 25), y = -(e.clientY - box.top - r) / (r - 25);
    const n = Math.hypot(x, y);
    if (n > 1) { x /= n; y /= n; }
    joystickSet(x, y);
  };
  c.addEventListener('pointerdown', (e) => { c.setPointerCapture(e.pointerId); fromEvent(e); });
  c.addEventListener('pointermove', (e) => { if (held && !keys.size) fromEvent(e); });
  for (const type of ['pointerup', 'pointercancel', 'lostpointercapture']) c.addEventListener(type, () => joystickRelease());
  const arrows = { ArrowUp: [0, 1], ArrowDown: [0, -1], ArrowLeft: [-1, 0], ArrowRight: [1, 0] };
  const fromKeys = () => {
    let x = 0, y = 0;
    for (const k of keys) { x += arrows[k][0]; y += arrows[k][1]; }
    if (keys.size) joystickSet(Math.max(-1, Math.min(1, x)), Math.max(-1, Math.min(1, y))); else joystickRelease();
  };
  window.addEventListener('keydown', (e) => { if (arrows[e.key] && !keys.has(e.key)) { keys.add(e.key); fromKeys(); e.preventDefault(); } });
  window.addEventListener('keyup', (e) => { if (keys.delete(e.key)) fromKeys(); });
  window.addEventListener('blur', () => { keys.clear(); joystickRelease(); });
  document.addEventListener('visibilitychange', () => { if (document.hidden) { keys.clear(); joystickRelease(); } });
  window.addEventListener('pagehide', () => { joystickRelease(); if (ws) ws.close(); });
  drawJoystick(0, 0);
}

// --- the gamepad (the Gamepad API, standard mapping; spec section 14) ---
// Drives only while LB (button 4) is held, like teleop_twist_joy's deadman button; RB (5)
// scales to the daemon's limits; B (1) is E-STOP. Any way the pad can go away, and the page
// being hidden or closed, sends a `stop` at once instead of waiting for the deadman.
const PAD_POLL_MS = 50;  // 20 polls a second; a held pad publishes on each
const DEAD_ZONE = 0.1;
const HOLONOMIC = new Set(['mecanum', 'omni']);
let chassisType = null, limits = null;  // status chassis.type, control.limits (protocol 5)
const pad = { index: null, id: null, driving: false, estopHeld: false };
function connectedPad() {
  const pads = navigator.getGamepads ? Array.from(navigator.getGamepads() || []) : [];
  const usable = (p) => p && p.connected && p.mapping === 'standard';
  if (pad.index !== null) return usable(pads[pad.index]) ? pads[pad.index] : null;
  return pads.find(usable) || null;
}
function showPad(text) {
  const line = $('gamepad');
  line.textContent = text;
  line.dataset.driving = String(pad.driving);
  line.dataset.connected = String(pad.index !== null);
}
function padStop(why) {
  if (!pad.driving) return;
  pad.driving = false;
  fetch('/api/stop', { method: 'POST', keepalive: true }).catch(() => {});
  if (why) showMessage(0, `gamepad: stopped (${why})`);
}
function padLost(why) {
  padStop(why);
  if (pad.index !== null) showPad(`gamepad ${pad.id} gone (${why})`);
  pad.index = null;
  pad.id = null;
  pad.estopHeld = false;
}
function padSpeeds(turbo) {
  const limit = (axis, normal) => (limits && typeof limits[axis] === 'number'
    ? (turbo ? limits[axis] : Math.min(normal, limits[axis])) : normal);
  return { vx: limit('vx', MAX_VX), vy: limit('vy', MAX_VX), wz: limit('wz', MAX_WZ) };
}
function padAxis(p, i) {
  const value = Number(p.axes[i] || 0);
  return Math.abs(value) < DEAD_ZONE ? 0 : value;
}
function padPoll() {
  const p = connectedPad();
  if (!p) {
    if (pad.index !== null) padLost('disconnected');
    return;
  }
  if (pad.index === null) { pad.index = p.index; pad.id = p.id; }
  const button = (i) => Boolean(p.buttons[i] && (p.buttons[i].pressed || p.buttons[i].value > 0.5));
  if (button(1) && !pad.estopHeld) estop('gamepad');
  pad.estopHeld = button(1);
  if (!button(4) || document.hidden) {
    padStop(document.hidden ? 'page hidden' : 'LB released');
    showPad(`gamepad ${p.id}: idle${readOnly ? ' (read-only: driving needs the token)' : ' (hold LB to drive)'}`);
    return;
  }
  if (readOnly) { showPad(`gamepad ${p.id}: read-only, driving needs the token`); return; }
  const max = padSpeeds(button(5));
  const round = (v) => Number(v.toFixed(3)) + 0;  // + 0: no -0
  const v = { vx: round(-padAxis(p, 1) * max.vx), vy: HOLONOMIC.has(chassisType) ? round(-padAxis(p, 0) * max.vy) : 0,
              wz: round(-padAxis(p, 2) * max.wz) };
  pad.driving = true;
  publishDrive(v);
  showPad(`gamepad ${p.id}: driving vx ${v.vx} m/s, vy ${v.vy} m/s, wz ${v.wz} rad/s${button(5) ? ' (turbo)' : ''}`);
}
function setupGamepad() {
  if (!navigator.getGamepads) { showPad('no Gamepad API in this browser'); return; }
  window.addEventListener('gamepadconnected', () => padPoll());
  window.addEventListener('gamepaddisconnected', (e) => {
    if (e.gamepad && e.gamepad.index === pad.index) padLost('disconnected');
  });
  document.addEventListener('visibilitychange', () => { if (document.hidden) padStop('page hidden'); });
  window.addEventListener('pagehide', () => padStop());
  setInterval(padPoll, PAD_POLL_MS);
}

// --- STOP and the daemon's counters over HTTP ---
async function stop() {
  joystickRelease(false);
  try {
    const response = await fetch('/api/stop', { method: 'POST' });
    showMessage(response.ok ? 0 : 2, response.ok ? 'STOP sent' : `STOP failed: ${await response.text()}`);
  } catch (error) {
    showMessage(2, `STOP failed: ${error}`);
  }
}
const sum = (object) => Object.values(object || {}).reduce((a, b) => a + (typeof b === 'number' ? b : 0), 0);
async function pollStats() {
  try {
    const response = await fetch('/api/stats');
    if (response.ok) {
      const stats = await response.json();
      $('discards').textContent = String(sum(stats.groups_discarded));
      $('rejects').textContent = String(sum(stats.records_rejected));
      // The serial link's counters (protocol 3, serial only) in place of the CAN frame groups'.
      const serial = stats.serial;
      $('discards-row').hidden = Boolean(serial);
      $('serial-row').hidden = !serial;
      if (serial) {
        // Rejected frames are in "rejected records" already; reopens counts the first open.
        $('serial-line').textContent = `${serial.bytes_received} bytes received, ${serial.bytes_skipped} skipped, ` +
          `port opened ${serial.reopens} time${serial.reopens === 1 ? '' : 's'}`;
      }
    }
  } catch (error) { /* shown by the connection state */ }
  $('dropped').textContent = droppedHere ? 'yes (this page is too slow)' : '0';
}

// --- the black box's files (wheeltec-record), newest first, each a download ---
const RECORDS_PERIOD_MS = 10000;
function sizeText(bytes) {
  if (bytes < 1024) return `${bytes} B`;
  return bytes < 1048576 ? `${Math.round(bytes / 1024)} kB` : `${(bytes / 1048576).toFixed(1)} MB`;
}
function tableRow(...cells) {  // each cell a text or an element
  const row = document.createElement('tr');
  for (const content of cells) { const cell = row.insertCell(); cell.append(content); }
  return row;
}
async function pollRecords() {
  const table = $('records');
  try {
    const response = await fetch('/api/records');
    if (!response.ok) { table.replaceChildren(tableRow(await response.text())); return; }
    const list = (await response.json()).records;
    if (!list.length) { table.replaceChildren(tableRow('none')); return; }
    table.replaceChildren(...list.map((r) => {
      const link = document.createElement('a');
      link.href = `/api/records/${encodeURIComponent(r.name)}`;
      link.download = r.name;
      link.title = r.name;
      link.textContent = new Date(r.time * 1000).toLocaleString();
      const view = document.createElement('a');
      view.href = `#record=${encodeURIComponent(r.name)}`;
      view.className = 'view';
      view.textContent = 'view';
      return tableRow(link, r.trigger, sizeText(r.bytes), view);
    }));
  } catch (error) { /* shown by the connection state */ }
}

// --- the incident viewer: one black-box file on the page (#record=NAME) ---
// Commanded velocity comes from the file's events (a `drive` sets it; stops zero it), measured
// velocity, battery and odometry from its telemetry; triggers (the metadata's) are marked.
const ZEROING_EVENTS = new Set(['stop', 'deadman', 'estop', 'disable']);
const incidentGraphs = {};
let incidentMarkers = [];  // [{time (s), trigger}] for the plots' underlay
function clockText(seconds) {
  const d = new Date(seconds * 1000);
  return `${d.toLocaleTimeString([], { hour12: false })}.${String(d.getMilliseconds()).padStart(3, '0')}`;
}
function eventDetails(e) {
  return Object.entries(e).filter(([k]) => !['time', 'event', 'client'].includes(k))
    .map(([k, v]) => `${k} ${typeof v === 'object' && v !== null ? JSON.stringify(v) : v}`).join(', ');
}
function parseTriggers(metadata) {
  try {
    const list = JSON.parse(metadata.triggers || '[]');
    return Array.isArray(list) ? list.filter((t) => t && typeof t.time === 'number') : [];
  } catch (error) { return []; }
}
function drawIncidentPath(telemetry) {
  const canvas = $('incident-path'), g = canvas.getContext('2d');
  g.clearRect(0, 0, canvas.width, canvas.height);
  const points = telemetry.filter((r) => r.odom).map((r) => [r.odom.x, r.odom.y]);
  if (!points.length) return;
  let minX = Infinity, maxX = -Infinity, minY = Infinity, maxY = -Infinity;
  for (const [x, y] of points) { minX = Math.min(minX, x); maxX = Math.max(maxX, x); minY = Math.min(minY, y); maxY = Math.max(maxY, y); }
  const span = Math.max(maxX - minX, maxY - minY, 0.5) * 1.2, scale = canvas.width / span;
  const cx = (minX + maxX) / 2, cy = (minY + maxY) / 2;
  const px = (x) => canvas.width / 2 + (x - cx) * scale, py = (y) => canvas.height / 2 - (y - cy) * scale;
  g.strokeStyle = '#36c'; g.lineWidth = 2; g.beginPath();
  points.forEach(([x, y], i) => (i ? g.lineTo(px(x), py(y)) : g.moveTo(px(x), py(y))));
  g.stroke();
  g.fillStyle = '#2a2'; g.beginPath(); g.arc(px(points[0][0]), py(points[0][1]), 5, 0, 2 * Math.PI); g.fill();
  g.fillStyle = '#d22'; g.beginPath(); g.arc(px(points.at(-1)[0]), py(points.at(-1)[1]), 5, 0, 2 * Math.PI); g.fill();
}
function markTriggers(canvas, area, graph) {
  canvas.fillStyle = 'rgba(220, 0, 0, 0.7)';
  for (const marker of incidentMarkers) {
    const x = graph.toDomXCoord(new Date(marker.time * 1000));
    if (x >= area.x && x <= area.x + area.w) canvas.fillRect(x - 1, area.y, 2, area.h);
  }
}
function showIncident(file) {
  const box = $('incident');
  const telemetry = file.telemetry || [], events = (file.events || []).slice().sort((a, b) => a.time - b.time);
  const triggers = parseTriggers(file.metadata || {});
  incidentMarkers = triggers;
  const m = file.metadata || {};
  $('incident-state').textContent = `${telemetry.length} records, ${events.length} events, ${(file.status || []).length} status` +
    (m.chassis ? `; chassis ${m.chassis}` : '') + (m.transport ? `, ${m.transport} ${m.device || ''}` : '') +
    (m.version ? `, wheeltecd ${m.version}` : '');
  $('incident-triggers').textContent = triggers.length
    ? 'triggers: ' + triggers.map((t) => `${t.trigger} at ${clockText(t.time)}`).join(', ') : 'no triggers';
  // Commanded velocity at each record's time: the last drive before it, zero after a stop.
  let next = 0, commandedNow = { vx: 0, vy: 0, wz: 0 };
  const rows = { vx: [], vy: [], wz: [], battery: [] };
  for (const r of telemetry) {
    while (next < events.length && events[next].time <= r.time) {
      const e = events[next++];
      if (e.event === 'drive') commandedNow = { vx: e.vx || 0, vy: e.vy || 0, wz: e.wz || 0 };
      else if (ZEROING_EVENTS.has(e.event)) commandedNow = { vx: 0, vy: 0, wz: 0 };
    }
    const t = new Date(r.time * 1000), v = r.velocity || {};
    rows.vx.push([t, commandedNow.vx, v.vx]);
    rows.vy.push([t, commandedNow.vy, v.vy]);
    rows.wz.push([t, commandedNow.wz, v.wz]);
    rows.battery.push([t, r.battery ? r.battery.voltage : null]);
  }
  if (typeof Dygraph !== 'undefined' && telemetry.length) {
    const labels = { vx: ['t', 'vx commanded', 'vx measured'], vy: ['t', 'vy commanded', 'vy measured'],
                     wz: ['t', 'wz commanded', 'wz measured'], battery: ['t', 'battery'] };
    const titles = { vx: 'vx (m/s)', vy: 'vy (m/s)', wz: 'wz (rad/s)', battery: 'battery (V)' };
    for (const id of Object.keys(rows)) {
      if (incidentGraphs[id]) incidentGraphs[id].destroy();
      incidentGraphs[id] = new Dygraph($(`incident-${id}`), rows[id], { labels: labels[id], title: titles[id],
        legend: 'always', titleHeight: 18, strokeWidth: 1.5, underlayCallback: markTriggers });
    }
  }
  drawIncidentPath(telemetry);
  // The events and triggers as one list, on the plots' time axis.
  const start = telemetry.length ? telemetry[0].time : (events.length ? events[0].time : 0);
  const items = events.map((e) => ({ time: e.time, kind: e.event, client: e.client, details: eventDetails(e) }))
    .concat(triggers.map((t) => ({ time: t.time, kind: `trigger: ${t.trigger}`, client: null, details: '', trigger: true })))
    .sort((a, b) => a.time - b.time);
  const table = $('incident-events');
  table.replaceChildren(tableRow('time', 'event', 'client', 'keys'), ...items.map((item) => {
    const row = tableRow(`${clockText(item.time)} (${(item.time - start >= 0 ? '+' : '')}${(item.time - start).toFixed(2)} s)`,
      item.kind, item.client === null || item.client === undefined ? '-' : String(item.client), item.details);
    if (item.trigger) row.className = 'trigger';
    return row;
  }));
  box.dataset.state = 'shown';
  box.dataset.telemetry = String(telemetry.length);
  box.dataset.events = String(events.length);
  box.dataset.triggers = String(triggers.length);
}
async function openIncident(name) {
  const box = $('incident');
  box.hidden = false;
  box.dataset.state = 'loading';
  box.dataset.name = name;
  $('incident-title').textContent = name;
  $('incident-download').href = `/api/records/${encodeURIComponent(name)}`;
  $('incident-download').download = name;
  $('incident-state').textContent = 'loading…';
  $('incident-triggers').textContent = '';
  $('incident-events').replaceChildren();
  try {
    const response = await fetch(`/api/records/${encodeURIComponent(name)}/messages`);
    const text = await response.text();
    let answer = null;
    try { answer = JSON.parse(text); } catch (error) { /* a plain-text 404 */ }
    if (box.dataset.name !== name) return;  // another one was opened meanwhile
    if (!response.ok) {
      $('incident-state').textContent = `cannot show ${name}: ${answer && answer.error ? answer.error : text.trim()}`;
      box.dataset.state = 'error';
      return;
    }
    showIncident(answer);
    box.scrollIntoView();
  } catch (error) {
    $('incident-state').textContent = `cannot show ${name}: ${error}`;
    box.dataset.state = 'error';
  }
}
function incidentFromHash() {
  const match = location.hash.match(/^#record=(.+)$/);
  if (match) { openIncident(decodeURIComponent(match[1])); return; }
  $('incident').hidden = true;
  delete $('incident').dataset.name;
}
$('incident-close').addEventListener('click', () => { history.replaceState(null, '', location.pathname + location.search); incidentFromHash(); });
window.addEventListener('hashchange', incidentFromHash);
incidentFromHash();

makeGraphs();
setupJoystick();
setupGamepad();
$('stop').addEventListener('click', stop);
$('estop').addEventListener('click', () => estop());
$('release').addEventListener('click', release);
connect();
pollStats();
setInterval(pollStats, 2000);
pollRecords();
setInterval(pollRecords, RECORDS_PERIOD_MS);
