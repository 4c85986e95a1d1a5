// Clients of wheeltec-web for its integration tests (tests/web/live_test.cpp): a Foxglove
// client from npm (@foxglove/ws-protocol over the `ws` package), and hostile ones.
//   node foxglove_client.cjs MODE URL [TOKEN]      (watch: MODE URL SECONDS)
// Over wss:// it trusts the CA in $NODE_EXTRA_CA_CERTS.
// Prints one JSON line with what it saw; exit 0 when the expectation of MODE held, 1 if not.
'use strict';
const net = require('net');
const crypto = require('crypto');
const WebSocket = require('ws');
const { FoxgloveClient } = require('@foxglove/ws-protocol');

const [mode, url, token] = process.argv.slice(2);
const SUBPROTOCOL = FoxgloveClient.SUPPORTED_SUBPROTOCOL;
const result = { mode };
function done(ok, why) {
  if (why) result.why = why;
  result.ok = ok;
  console.log(JSON.stringify(result));
  process.exit(ok ? 0 : 1);
}
// never-reads watches for up to 30 s on its own (see there).
setTimeout(() => done(false, 'timed out'), mode === 'never-reads' ? 50000 : 30000).unref();
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
const withToken = (u) => (token ? `${u}${u.includes('?') ? '&' : '?'}token=${encodeURIComponent(token)}` : u);

// A FoxgloveClient on a `ws` WebSocket; resolves once the channels are advertised.
function foxglove(u, options = {}) {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(u, [SUBPROTOCOL], options);
    const client = new FoxgloveClient({ ws });
    const channels = new Map();
    const statuses = [];
    client.on('error', (error) => reject(error));
    client.on('status', (status) => statuses.push(status));
    client.on('advertise', (list) => {
      for (const channel of list) channels.set(channel.topic, channel);
      resolve({ client, channels, statuses, ws });
    });
  });
}

async function live() {
  const { client, channels, statuses } = await foxglove(withToken(url));
  result.topics = [...channels.keys()];
  const received = {};
  const bySubscription = new Map();
  for (const topic of ['/wheeltec/telemetry', '/wheeltec/status', '/wheeltec/odom', '/wheeltec/imu']) {
    if (!channels.has(topic)) return done(false, `no channel ${topic}`);
    JSON.parse(channels.get(topic).schema);  // a JSON schema
    bySubscription.set(client.subscribe(channels.get(topic).id), topic);
    received[topic] = [];
  }
  client.on('message', ({ subscriptionId, timestamp, data }) => {
    const topic = bySubscription.get(subscriptionId);
    received[topic].push({ timestamp: String(timestamp), payload: JSON.parse(new TextDecoder().decode(data)) });
  });
  for (let i = 0; i < 100 && !Object.values(received).every((list) => list.length > 0); ++i) await sleep(100);
  result.counts = Object.fromEntries(Object.entries(received).map(([topic, list]) => [topic, list.length]));
  if (!Object.values(received).every((list) => list.length > 0)) return done(false, 'not every channel delivered');
  const record = received['/wheeltec/telemetry'].at(-1).payload;
  const pose = received['/wheeltec/odom'].at(-1).payload;
  const imu = received['/wheeltec/imu'].at(-1).payload;
  result.seq = record.seq;
  if (typeof record.velocity.vx !== 'number' || typeof pose.pose.position.x !== 'number' ||
      typeof imu.angular_velocity.z !== 'number') {
    return done(false, 'payloads do not have their schema\'s shape');
  }
  if (mode === 'drive') {
    const channel = client.advertise({ topic: '/wheeltec/cmd_vel', encoding: 'json', schemaName: 'wheeltec.CmdVel' });
    const start = Date.now();
    while (Date.now() - start < 2000) {
      client.sendMessage(channel, new TextEncoder().encode(JSON.stringify({ vx: 0.3, vy: 0, wz: 0.5 })));
      await sleep(100);
    }
    result.measured_vx = received['/wheeltec/telemetry'].at(-1).payload.velocity.vx;
  }
  result.errors = statuses.filter((s) => s.level === 2).map((s) => s.message);
  client.close();
  done(result.errors.length === 0, result.errors.length ? 'status errors' : undefined);
}

async function readOnly() {
  const { client, statuses } = await foxglove(url);
  const channel = client.advertise({ topic: '/wheeltec/cmd_vel', encoding: 'json', schemaName: 'wheeltec.CmdVel' });
  client.sendMessage(channel, new TextEncoder().encode('{"vx":0.3}'));
  for (let i = 0; i < 30 && !statuses.some((s) => s.level === 2); ++i) await sleep(100);
  result.statuses = statuses;
  done(statuses.some((s) => s.level === 2 && s.message.includes('-32005')), 'no -32005 status error');
}

// Resolves with how the upgrade went: 'open', or the HTTP status of the refusal.
function upgrade(u, options) {
  return new Promise((resolve) => {
    const ws = new WebSocket(u, [SUBPROTOCOL], options);
    ws.on('open', () => { ws.close(); resolve('open'); });
    ws.on('unexpected-response', (request, response) => resolve(response.statusCode));
    ws.on('error', (error) => resolve(`error ${error.message}`));
  });
}

async function origins() {
  const host = new URL(url).host;
  result.foreign = await upgrade(url, { origin: 'http://evil.example' });
  result.own = await upgrade(url, { origin: `${url.startsWith('wss:') ? 'https' : 'http'}://${host}` });
  result.allowed = await upgrade(url, { origin: 'https://app.foxglove.dev' });
  result.none = await upgrade(url, {});
  result.wrong_token = await upgrade(`${url}?token=wrong`, {});
  result.no_subprotocol = await new Promise((resolve) => {
    const ws = new WebSocket(url);
    ws.on('open', () => resolve('open'));
    ws.on('unexpected-response', (request, response) => resolve(response.statusCode));
    ws.on('error', () => resolve('error'));
  });
  done(result.foreign === 403 && result.own === 'open' && result.allowed === 'open' && result.none === 'open' &&
       result.wrong_token === 401 && result.no_subprotocol === 400);
}

async function malformed() {
  const { client, channels, statuses, ws } = await foxglove(url);
  ws.send('not json');
  ws.send(JSON.stringify({ op: 'subscribe', subscriptions: [{ id: 1, channelId: 999 }] }));
  ws.send(Buffer.from([0x07, 1, 2]));
  ws.send(Buffer.from([0x01, 0x02]));
  ws.send(Buffer.from([0x01, 9, 0, 0, 0, 0x7b, 0x7d]));  // a channel never advertised
  for (let i = 0; i < 30 && statuses.filter((s) => s.level === 2).length < 5; ++i) await sleep(100);
  result.errors = statuses.filter((s) => s.level === 2).map((s) => s.message);
  // Still served: telemetry keeps coming on the same connection.
  let count = 0;
  client.subscribe(channels.get('/wheeltec/telemetry').id);
  client.on('message', () => ++count);
  await sleep(1000);
  result.telemetry_after = count;
  client.close();
  done(result.errors.length === 5 && count > 0);
}

async function oversized() {
  const ws = new WebSocket(url, [SUBPROTOCOL]);
  await new Promise((resolve) => ws.on('open', resolve));
  ws.send('x'.repeat(70 * 1024));
  const code = await new Promise((resolve) => ws.on('close', (c) => resolve(c)));
  result.close_code = code;
  done(code === 1009);
}

// A raw client that subscribes to telemetry many times over, then never reads, next to a
// well-behaved Foxglove client that must keep receiving.
async function neverReads() {
  const target = new URL(url);
  const socket = net.connect(Number(target.port), target.hostname);
  await new Promise((resolve) => socket.on('connect', resolve));
  const key = crypto.randomBytes(16).toString('base64');
  socket.write(`GET / HTTP/1.1\r\nHost: ${target.host}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n` +
               `Sec-WebSocket-Key: ${key}\r\nSec-WebSocket-Version: 13\r\nSec-WebSocket-Protocol: ${SUBPROTOCOL}\r\n\r\n`);
  // Telemetry channels only (1 telemetry, 3 odom, 4 imu): the ones that may be dropped for it.
  const subscriptions = Array.from({ length: 240 }, (_, i) => ({ id: i, channelId: [1, 3, 4][i % 3] }));
  const text = Buffer.from(JSON.stringify({ op: 'subscribe', subscriptions }));
  const mask = crypto.randomBytes(4);
  const header = Buffer.from([0x81, 0x80 | 126, text.length >> 8, text.length & 0xff]);
  const masked = Buffer.from(text.map((byte, i) => byte ^ mask[i % 4]));
  let closed = false;
  socket.on('close', () => { closed = true; });
  socket.on('error', () => { closed = true; });
  await sleep(300);
  socket.pause();  // never reads again (until the end, to see whether the server closed it)
  socket.write(Buffer.concat([header, mask, masked]));

  const { client, channels } = await foxglove(url);
  let count = 0;
  client.subscribe(channels.get('/wheeltec/telemetry').id);
  client.on('message', () => ++count);
  // Until the server drops it: the socket buffers on both sides (several MB where the kernel
  // tunes them up) fill first, slowly on a loaded machine, then the 2 s stall timeout runs.
  // A ping written each second tells when: once the server has closed, the write fails.
  const counts = [];
  for (let i = 0; i < 30 && !closed; ++i) {
    await sleep(1000);
    counts.push(count);
    socket.write(Buffer.concat([Buffer.from([0x89, 0x80]), crypto.randomBytes(4)]));
  }
  result.good_client_counts = counts;
  socket.resume();
  for (let i = 0; i < 50 && !closed; ++i) await sleep(100);
  result.slow_client_closed = closed;
  // Kept receiving: something in every 2 s window (a loaded CI machine may pause it briefly).
  const steady = counts.every((c, i) => i < 2 || c > counts[i - 2]);
  client.close();
  done(closed && steady, !closed ? 'the reader-less client was not disconnected' : steady ? undefined : 'stalled');
}

// Stays subscribed to telemetry for SECONDS (the third argument) and counts what arrives each
// second: the connection must stay open and keep receiving (across a SIGHUP, say).
async function watch() {
  const seconds = Number(token || 5);
  const { client, channels, ws } = await foxglove(url);
  let count = 0, closed = false;
  ws.on('close', () => { closed = true; });
  client.subscribe(channels.get('/wheeltec/telemetry').id);
  client.on('message', () => ++count);
  const counts = [];
  for (let i = 0; i < seconds; ++i) { await sleep(1000); counts.push(count); }
  result.counts = counts;
  result.closed = closed;
  const steady = counts.every((c, i) => c > (i ? counts[i - 1] : 0));
  client.close();
  done(!closed && steady, closed ? 'the connection closed' : steady ? undefined : 'a second without telemetry');
}

// Two viewers with the token: the first drives, the second is refused by the daemon (-32001),
// because each viewer drives through a daemon connection of its own.
async function secondDriver() {
  const first = await foxglove(withToken(url));
  const second = await foxglove(withToken(url));
  const advertise = (c) => c.client.advertise({ topic: '/wheeltec/cmd_vel', encoding: 'json', schemaName: 'wheeltec.CmdVel' });
  const a = advertise(first), b = advertise(second);
  const drive = (c, channel) => c.client.sendMessage(channel, new TextEncoder().encode('{"vx":0.2}'));
  for (let i = 0; i < 5; ++i) { drive(first, a); await sleep(100); }
  for (let i = 0; i < 10 && !second.statuses.some((s) => s.level === 2); ++i) {
    drive(first, a); drive(second, b); await sleep(100);
  }
  result.first = first.statuses.filter((s) => s.level === 2).map((s) => s.message);
  result.second = second.statuses.filter((s) => s.level === 2).map((s) => s.message);
  first.client.close();
  second.client.close();
  done(result.first.length === 0 && result.second.some((m) => m.includes('-32001')));
}

// The emergency stop's topics (spec section 12): a viewer without the token latches it on
// /wheeltec/estop and may not release it; a driver with the token (TOKEN) is refused while
// latched (-32007), releases it on /wheeltec/release and drives again. Each status message's
// `safety` is kept, so the test sees the latch as the channel showed it.
async function estopRelease() {
  const driver = await foxglove(withToken(url));
  const viewer = await foxglove(url);
  const safeties = [];
  viewer.client.on('message', ({ data }) => {
    const status = JSON.parse(new TextDecoder().decode(data));
    if (status.safety) safeties.push(status.safety);
  });
  viewer.client.subscribe(viewer.channels.get('/wheeltec/status').id);
  const advertise = (c, topic) => c.client.advertise({ topic, encoding: 'json', schemaName: 'wheeltec.Any' });
  const send = (c, channel, object) => c.client.sendMessage(channel, new TextEncoder().encode(JSON.stringify(object)));
  const waitStatus = async (c, predicate) => {
    for (let i = 0; i < 50; ++i) {
      const found = c.statuses.find(predicate);
      if (found) return found;
      await sleep(100);
    }
    return null;
  };
  const errors = (c) => c.statuses.filter((s) => s.level === 2).map((s) => s.message);
  const cmdVel = advertise(driver, '/wheeltec/cmd_vel');
  const driverRelease = advertise(driver, '/wheeltec/release');
  const viewerEstop = advertise(viewer, '/wheeltec/estop');
  const viewerRelease = advertise(viewer, '/wheeltec/release');
  const drive = async (ms) => {
    for (const start = Date.now(); Date.now() - start < ms;) { send(driver, cmdVel, { vx: 0.3 }); await sleep(100); }
  };
  await drive(800);
  result.errors_before = errors(driver);

  send(viewer, viewerEstop, { reason: 'foxglove viewer' });
  const latched = await waitStatus(viewer, (s) => s.id === 'estop' || s.id === 'estop-refused');
  result.estop_status = latched;
  for (let i = 0; i < 30 && !safeties.some((s) => s.latched); ++i) await sleep(100);
  result.safety_latched = safeties.find((s) => s.latched) || null;

  await drive(500);
  result.drive_refused = errors(driver).find((m) => m.includes('-32007')) || null;

  send(viewer, viewerRelease, {});
  result.viewer_release = await waitStatus(viewer, (s) => s.id === 'release' || s.id === 'release-refused');
  await sleep(300);
  result.latched_after_viewer_release = safeties.at(-1) ? safeties.at(-1).latched : null;

  send(driver, driverRelease, {});
  result.driver_release = await waitStatus(driver, (s) => s.id === 'release' || s.id === 'release-refused');
  for (let i = 0; i < 30 && safeties.at(-1).latched; ++i) await sleep(100);
  result.latched_after_release = safeties.at(-1).latched;

  const before = errors(driver).length;
  await drive(800);
  result.errors_after_release = errors(driver).slice(before);
  driver.client.close();
  viewer.client.close();
  done(Boolean(latched && latched.id === 'estop' && result.safety_latched && result.drive_refused &&
               result.viewer_release && result.viewer_release.id === 'release-refused' &&
               result.viewer_release.message.includes('-32005') && result.latched_after_viewer_release === true &&
               result.driver_release && result.driver_release.id === 'release' &&
               result.latched_after_release === false && result.errors_after_release.length === 0 &&
               result.errors_before.length === 0));
}

const modes = { 'estop-release': estopRelease, watch, 'second-driver': secondDriver, live, drive: live, 'read-only': readOnly, origins, malformed, oversized, 'never-reads': neverReads };
if (!modes[mode]) done(false, `unknown mode ${mode}`);
modes[mode]().catch((error) => done(false, String(error && error.stack || error)));
