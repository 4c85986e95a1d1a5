// Drives Debian's headless Chromium through its DevTools protocol for the web.Viewer test
// (tests/web/viewer_test.cpp): the incident viewer opened by /#record=NAME at a phone's width,
// then from the Recordings table's "view" link at a desktop's.
//   node viewer_browser.cjs DEVTOOLS_PORT SCREENSHOT_DIR BASE_URL NAME
// Prints JSON lines {"event":"phone",...} and {"event":"table",...} with what the viewer
// shows; exit 0 on success. Its progress goes to stderr.
'use strict';
const fs = require('fs');
const path = require('path');
const { openPage, sleep } = require('./devtools.cjs');

const [port, screenshots, base, name] = process.argv.slice(2);
const say = (object) => console.log(JSON.stringify(object));
function fail(why) { say({ event: 'failed', why }); process.exit(1); }
setTimeout(() => fail('timed out'), 60000).unref();

const readViewer = `(() => { const box = document.getElementById('incident');
  const rows = [...document.querySelectorAll('#incident-events tr')].slice(1).map((r) => [...r.cells].map((c) => c.textContent));
  return { hidden: box.hidden, state: box.dataset.state, name: box.dataset.name,
           telemetry: Number(box.dataset.telemetry || 0), events: Number(box.dataset.events || 0),
           triggers: Number(box.dataset.triggers || 0), rows, summary: document.getElementById('incident-state').textContent,
           trigger_text: document.getElementById('incident-triggers').textContent,
           download: document.getElementById('incident-download').getAttribute('href'),
           plots: box.querySelectorAll('.incident-plots canvas').length,
           path_drawn: (() => { const c = document.getElementById('incident-path');
             const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
             for (let i = 3; i < d.length; i += 4) if (d[i]) return true; return false; })(),
           page_width: document.documentElement.scrollWidth, viewport: window.innerWidth }; })()`;

async function main() {
  const page = await openPage(port, 150);
  if (!page) fail('no page target in chromium');
  const { call, evaluate } = page;
  const shown = async (what) => {
    for (let i = 0; i < 150; ++i) {
      const state = await evaluate(`document.getElementById('incident') && document.getElementById('incident').dataset.state`);
      if (state === 'shown' || state === 'error') return;
      await sleep(100);
    }
    fail(`${what}: the viewer did not open: ${JSON.stringify(await evaluate(readViewer))}`);
  };
  const shoot = async (file) => {
    await sleep(600);  // dygraphs draws after layout
    const shot = await call('Page.captureScreenshot', { format: 'png', captureBeyondViewport: false });
    fs.writeFileSync(path.join(screenshots, file), Buffer.from(shot.result.data, 'base64'));
  };

  await call('Emulation.setDeviceMetricsOverride', { width: 390, height: 844, deviceScaleFactor: 2, mobile: true });
  await call('Page.navigate', { url: `${base}/#record=${encodeURIComponent(name)}` });
  await sleep(300);
  await shown('phone');
  await shoot('viewer-phone.png');
  say({ event: 'phone', viewer: await evaluate(readViewer) });

  await call('Emulation.clearDeviceMetricsOverride');
  await call('Page.navigate', { url: `${base}/` });
  for (let i = 0; i < 100 && !(await evaluate(`Boolean(document.querySelector('#records a.view'))`)); ++i) await sleep(100);
  // The table is re-rendered by its poll and the page's layout moves while the graphs draw, so a
  // click aims at the link only once elementFromPoint finds it there, and is tried again if the
  // hash did not change.
  const hash = `#record=${encodeURIComponent(name)}`;
  let clicked = false;
  for (let attempt = 0; attempt < 10 && !clicked; ++attempt) {
    const box = await evaluate(`(() => { const a = [...document.querySelectorAll('#records a.view')]
        .find((l) => l.getAttribute('href') === '${hash}');
      if (!a) return null; a.scrollIntoView({ block: 'center' }); const r = a.getBoundingClientRect();
      const x = r.left + r.width / 2, y = r.top + r.height / 2;
      return { x, y, hit: a.contains(document.elementFromPoint(x, y)) }; })()`);
    if (!box) fail('no view link for the file in the Recordings table');
    if (!box.hit) { await sleep(200); continue; }
    for (const type of ['mousePressed', 'mouseReleased']) {
      await call('Input.dispatchMouseEvent', { type, x: box.x, y: box.y, button: 'left', clickCount: 1 });
    }
    for (let i = 0; i < 20 && !clicked; ++i) {
      clicked = (await evaluate('location.hash')) === hash;
      if (!clicked) await sleep(100);
    }
  }
  if (!clicked) fail(`clicking the view link did not open ${hash}: ${JSON.stringify(await evaluate(readViewer))}`);
  await shown('table');
  await evaluate(`window.scrollTo(0, 0)`);
  await shoot('viewer.png');
  say({ event: 'table', viewer: await evaluate(readViewer), hash: await evaluate('location.hash') });
  process.exit(0);
}
main().catch((error) => fail(String(error && error.stack || error)));
