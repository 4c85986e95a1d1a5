// Drives the page's gamepad support in Debian's headless Chromium for the web.Gamepad test
// (tests/web/gamepad_test.cpp). Headless Chromium has no virtual gamepad, so the page gets a
// mock behind navigator.getGamepads (installed before its scripts run) that this script moves:
// sticks, buttons, connecting and every way of going away.
//   node gamepad_browser.cjs DEVTOOLS_PORT SCREENSHOT_DIR BASE_URL TOKEN [short]
// (short: connect, the left stick with LB held, LB released: for a chassis without vy.)
// Prints one JSON line per phase: {"event":"phase","phase":NAME,"mono_ns":...,"dom":{...}}
// (mono_ns is CLOCK_MONOTONIC, the test's steady_clock, so frames can be judged per phase),
// then {"event":"done"}; exit 0 on success. Its progress goes to stderr.
'use strict';
const fs = require('fs');
const http = require('http');
const path = require('path');
const { openPage, sleep } = require('./devtools.cjs');

const [port, screenshots, base, token, variant] = process.argv.slice(2);
const say = (object) => console.log(JSON.stringify(object));
function fail(why) { say({ event: 'failed', why }); process.exit(1); }
setTimeout(() => fail('timed out'), 80000).unref();

const MOCK = `(() => {
  const pad = { id: 'Test Pad (STANDARD GAMEPAD Vendor: 045e Product: 028e)', index: 0, connected: true,
                mapping: 'standard', axes: [0, 0, 0, 0], timestamp: 0,
                buttons: Array.from({ length: 17 }, () => ({ pressed: false, touched: false, value: 0 })) };
  let pads = [];
  Object.defineProperty(navigator, 'getGamepads', { configurable: true, value: () => pads.slice() });
  const fire = (type) => { const e = new Event(type); Object.defineProperty(e, 'gamepad', { value: pad }); window.dispatchEvent(e); };
  window.__pad = {
    set(axes, held) {
      pad.axes = axes.slice();
      pad.buttons.forEach((b, i) => { b.pressed = held.includes(i); b.value = b.pressed ? 1 : 0; });
      pad.timestamp = performance.now();
    },
    connect() { pad.connected = true; pads = [pad]; fire('gamepadconnected'); },
    disconnectEvent() { pad.connected = false; pads = []; fire('gamepaddisconnected'); },
    nullEntry() { pads = [null]; },
    notConnected() { pad.connected = false; pads = [pad]; },
    hide(hidden) {
      Object.defineProperty(document, 'hidden', { configurable: true, get: () => hidden });
      Object.defineProperty(document, 'visibilityState', { configurable: true, get: () => (hidden ? 'hidden' : 'visible') });
      document.dispatchEvent(new Event('visibilitychange'));
    },
  };
})();`;

function post(target, headers) {
  const url = new URL(base);
  return new Promise((resolve) => {
    const request = http.request({ host: url.hostname, port: Number(url.port), path: target, method: 'POST', headers },
      (response) => { let body = ''; response.on('data', (c) => (body += c)); response.on('end', () => resolve({ status: response.statusCode, body })); });
    request.on('error', (error) => resolve({ status: 0, body: String(error) }));
    request.end();
  });
}

async function main() {
  const page = await openPage(port, 150);
  if (!page) fail('no page target in chromium');
  const { call, evaluate } = page;
  await call('Page.enable');
  await call('Page.addScriptToEvaluateOnNewDocument', { source: MOCK });
  await call('Page.navigate', { url: `${base}/?token=${encodeURIComponent(token)}` });
  const readDom = `(() => ({ gamepad: document.getElementById('gamepad').textContent,
    driving: document.getElementById('gamepad').dataset.driving, latched: document.body.dataset.latched,
    live: document.body.dataset.live, refusal: document.getElementById('refusal').textContent,
    safety: document.getElementById('safety').textContent, banner: document.getElementById('safety-text').textContent }))()`;
  for (let i = 0; i < 200; ++i) {
    const dom = await evaluate(readDom);
    if (dom && dom.live === 'true' && dom.latched === 'false' && dom.safety) break;
    await sleep(100);
  }
  const pad = (js) => evaluate(`window.__pad.${js}`);
  const phase = async (name, act, ms) => {
    say({ event: 'phase', phase: name, mono_ns: String(process.hrtime.bigint()) });
    await act();
    await sleep(ms);
    say({ event: 'seen', phase: name, dom: await evaluate(readDom) });
  };
  const forward = [0, -1, 0, 0];
  await phase('connected', () => pad('connect()'), 400);
  if (variant === 'short') {
    await phase('vy-left', () => pad('set([-1, -1, 0, 0], [4])'), 700);
    await phase('lb-released', () => pad('set([-1, -1, 0, 0], [])'), 500);
    say({ event: 'done' });
    process.exit(0);
  }
  await phase('stick-without-lb', () => pad(`set(${JSON.stringify(forward)}, [])`), 600);
  await phase('drive-forward', () => pad(`set(${JSON.stringify(forward)}, [4])`), 1000);
  await phase('dead-zone', () => pad('set([0.09, -1, -0.09, 0.05], [4])'), 500);
  await phase('vy-left', () => pad('set([-1, -1, 0, 0], [4])'), 500);
  await phase('wz-ccw', () => pad('set([0, 0, -1, 0], [4])'), 500);
  await phase('half', () => pad('set([0, -0.5, 0, 0], [4])'), 500);
  await phase('turbo', () => pad(`set(${JSON.stringify(forward)}, [4, 5])`), 700);
  await evaluate(`document.getElementById('joystick').scrollIntoView({ block: 'center' })`);
  await sleep(300);
  const shot = await call('Page.captureScreenshot', { format: 'png' });
  fs.writeFileSync(path.join(screenshots, 'gamepad.png'), Buffer.from(shot.result.data, 'base64'));
  await phase('lb-released', () => pad(`set(${JSON.stringify(forward)}, [])`), 700);
  await phase('drive-again', () => pad(`set(${JSON.stringify(forward)}, [4])`), 600);
  await phase('disconnect-event', () => pad('disconnectEvent()'), 700);
  await phase('drive-again', () => pad('connect()'), 600);
  await phase('null-entry', () => pad('nullEntry()'), 700);
  await phase('drive-again', () => pad('connect()'), 600);
  await phase('not-connected', () => pad('notConnected()'), 700);
  await phase('drive-again', () => pad('connect()'), 600);
  await phase('hidden', () => pad('hide(true)'), 700);
  await phase('released-while-hidden', async () => { await pad('set([0, 0, 0, 0], [])'); await pad('hide(false)'); }, 400);
  await phase('estop-button', () => pad('set([0, 0, 0, 0], [1])'), 800);
  await pad('set([0, 0, 0, 0], [])');
  const released = await post('/api/release', { Authorization: `Bearer ${token}` });
  say({ event: 'released', released });
  await sleep(300);
  await phase('drive-again', () => pad(`set(${JSON.stringify(forward)}, [4])`), 600);
  say({ event: 'phase', phase: 'closed', mono_ns: String(process.hrtime.bigint()) });
  await call('Page.close');
  await sleep(700);
  say({ event: 'done' });
  process.exit(0);
}
main().catch((error) => fail(String(error && error.stack || error)));
