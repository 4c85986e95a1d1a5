// Drives Debian's headless Chromium through its DevTools protocol for the web.Safety suite
// (tests/web/safety_test.cpp): the page's E-STOP, its banner, a joystick drive refused while
// latched, Release refused without the token, and Release with it.
//   node estop_browser.cjs DEVTOOLS_PORT SCREENSHOT_DIR WEB_PORT CONTINUE_FILE
// Prints JSON lines: {"event":"driving"}, {"event":"latched",...}, {"event":"refused",...},
// {"event":"release-without-token",...}, then waits for CONTINUE_FILE (the test has judged
// the latch at the controller), {"event":"released",...}, {"event":"driving-again"},
// {"event":"closed"}; exit 0 on success. Its progress goes to stderr.
'use strict';
const fs = require('fs');
const http = require('http');
const path = require('path');
const { openPage, sleep } = require('./devtools.cjs');

const [port, screenshots, webPort, continueFile] = process.argv.slice(2);
const say = (object) => console.log(JSON.stringify(object));
function fail(why) { say({ event: 'failed', why }); process.exit(1); }
setTimeout(() => fail('timed out'), 80000).unref();

function post(target, headers) {
  return new Promise((resolve) => {
    const request = http.request({ host: '127.0.0.1', port: Number(webPort), path: target, method: 'POST', headers },
      (response) => {
        let body = '';
        response.on('data', (chunk) => (body += chunk));
        response.on('end', () => resolve({ status: response.statusCode, body }));
      });
    request.on('error', (error) => resolve({ status: 0, body: String(error) }));
    request.end();
  });
}

async function main() {
  const started = Date.now();
  const progress = (what) => console.error(`${((Date.now() - started) / 1000).toFixed(1)} s: ${what}`);
  const page = await openPage(port, 150);
  if (!page) fail('no page target in chromium');
  const { call, evaluate } = page;
  const until = async (expression, tries, what) => {
    for (let i = 0; i < tries; ++i) {
      const value = await evaluate(expression);
      if (value) return value;
      await sleep(100);
    }
    fail(`${what}: ${JSON.stringify(await evaluate(readDom))}`);
  };
  const readDom = `(() => { const t = (id) => document.getElementById(id);
    return { live: document.body.dataset.live === 'true', records: Number(document.body.dataset.records || 0),
             latched: document.body.dataset.latched, banner_hidden: t('safety-banner').hidden,
             banner: t('safety-banner').textContent.replace(/\\s+/g, ' ').trim(), release_hidden: t('release').hidden,
             safety: t('safety').textContent, refusal: t('refusal').textContent, drive: t('drive-state').textContent,
             messages: t('messages').textContent }; })()`;
  const shoot = async (name) => {
    const shot = await call('Page.captureScreenshot', { format: 'png' });
    fs.writeFileSync(path.join(screenshots, name), Buffer.from(shot.result.data, 'base64'));
  };
  const key = (type) => call('Input.dispatchKeyEvent', { type, key: 'ArrowUp', code: 'ArrowUp', windowsVirtualKeyCode: 38 });
  // A real click at the element's centre, as a user's.
  const click = async (id) => {
    const box = await evaluate(`(() => { const r = document.getElementById('${id}').getBoundingClientRect();
      return { x: r.left + r.width / 2, y: r.top + r.height / 2 }; })()`);
    for (const type of ['mousePressed', 'mouseReleased']) {
      await call('Input.dispatchMouseEvent', { type, x: box.x, y: box.y, button: 'left', clickCount: 1 });
    }
  };

  await until(`document.body.dataset.live === 'true' && Number(document.body.dataset.records) > 50 &&
               document.body.dataset.latched === 'false'`, 300, 'the page shows no live data or no safety');
  progress('live');
  await call('Page.bringToFront');
  await key('rawKeyDown');
  say({ event: 'driving' });
  await sleep(800);

  await click('estop');  // the arrow key still held
  await until(`document.body.dataset.latched === 'true' && !document.getElementById('safety-banner').hidden`, 50,
              'E-STOP did not latch');
  await sleep(300);
  await shoot('estop.png');
  say({ event: 'latched', dom: await evaluate(readDom) });

  await key('keyUp');
  await key('rawKeyDown');  // the joystick again, while latched
  await until(`document.getElementById('refusal').textContent`, 50, 'a drive while latched was not refused');
  say({ event: 'refused', dom: await evaluate(readDom) });
  await key('keyUp');

  const none = await post('/api/release', {});
  const wrong = await post('/api/release', { Authorization: 'Bearer wrong' });
  say({ event: 'release-without-token', none, wrong });

  for (let i = 0; i < 300 && !fs.existsSync(continueFile); ++i) await sleep(100);
  if (!fs.existsSync(continueFile)) fail('the test did not let the page release');
  await click('release');
  await until(`document.body.dataset.latched === 'false' && document.getElementById('safety-banner').hidden`, 50,
              'Release did not clear the latch');
  say({ event: 'released', dom: await evaluate(readDom) });

  await key('rawKeyDown');
  say({ event: 'driving-again' });
  await sleep(800);
  await call('Page.close');
  say({ event: 'closed' });
  process.exit(0);
}
main().catch((error) => fail(String(error && error.stack || error)));
