// Drives Debian's headless Chromium through its DevTools protocol (over the `ws` package)
// for tests/web/page_test.cpp: waits until wheeltec-web's page shows live telemetry, takes
// a screenshot, holds the Up arrow key (the joystick) for HOLD_MS, then closes the page.
//   node browser.cjs DEVTOOLS_PORT SCREENSHOT.png HOLD_MS
// Prints JSON lines: {"event":"live",...}, {"event":"driving"}, {"event":"closed"}; exit 0 on
// success. Its progress goes to stderr.
'use strict';
const fs = require('fs');
const { openPage, sleep } = require('./devtools.cjs');

const [port, screenshot, holdMs] = process.argv.slice(2);
const say = (object) => console.log(JSON.stringify(object));
function fail(why) { say({ event: 'failed', why }); process.exit(1); }
setTimeout(() => fail('timed out'), 50000).unref();

async function main() {
  const started = Date.now();
  const progress = (what) => console.error(`${((Date.now() - started) / 1000).toFixed(1)} s: ${what}`);
  const page = await openPage(port, 150);
  if (!page) fail('no page target in chromium');
  progress('page target open');
  const { call, evaluate } = page;

  const readDom = `(() => { const t = (id) => document.getElementById(id).textContent;
    return { live: document.body.dataset.live === 'true', records: Number(document.body.dataset.records || 0), seq: Number(t('seq')), bus: t('bus-state'),
             online: t('online'), velocity: t('velocity'), battery: t('battery'), connection: t('connection'),
             mode: t('mode'), plots: document.querySelectorAll('#plots canvas').length }; })()`;
  let dom = null;
  for (let i = 0; i < 150; ++i) {
    dom = await evaluate(readDom);
    if (dom && dom.live && dom.records > 100 && dom.bus.includes('up')) break;  // 2 s of plots at 50 Hz
    if (i % 25 === 0) progress(`waiting for live data: ${JSON.stringify(dom)} at ${await evaluate('location.href')}`);
    await sleep(200);
  }
  if (!dom || !dom.live) fail(`the page shows no live data: ${JSON.stringify(dom)}`);
  await sleep(500);  // the plots redraw at most every 200 ms
  const shot = await call('Page.captureScreenshot', { format: 'png' });
  fs.writeFileSync(screenshot, Buffer.from(shot.result.data, 'base64'));
  say({ event: 'live', dom: await evaluate(readDom) });

  await call('Page.bringToFront');
  await call('Input.dispatchKeyEvent', { type: 'rawKeyDown', key: 'ArrowUp', code: 'ArrowUp', windowsVirtualKeyCode: 38 });
  say({ event: 'driving' });
  await sleep(Number(holdMs));
  say({ event: 'drive-state', text: await evaluate(`document.getElementById('drive-state').textContent + ' | ' + document.getElementById('refusal').textContent`) });
  const driving = await call('Page.captureScreenshot', { format: 'png' });
  fs.writeFileSync(screenshot.replace(/\.png$/, '-driving.png'), Buffer.from(driving.result.data, 'base64'));
  // Closing the tab while the key is still held: the robot must stop within the deadman.
  await call('Page.close');
  say({ event: 'closed' });
  process.exit(0);
}
main().catch((error) => fail(String(error && error.stack || error)));
