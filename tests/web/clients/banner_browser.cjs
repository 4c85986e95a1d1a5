// Drives Debian's headless Chromium through its DevTools protocol for the web.Safety hazard
// test (tests/web/safety_test.cpp): the page, open before the robot tips over, shows the
// daemon's own latch on its banner.
//   node banner_browser.cjs DEVTOOLS_PORT SCREENSHOT_DIR
// Prints {"event":"live"} once the page shows live data unlatched, then {"event":"latched",
// "banner":..., "release_hidden":...} once the banner shows; exit 0. {"event":"failed"} and
// exit 1 when either does not come.
'use strict';
const fs = require('fs');
const path = require('path');
const { openPage, sleep } = require('./devtools.cjs');

const [port, screenshots] = process.argv.slice(2);
const say = (object) => console.log(JSON.stringify(object));
function fail(why) { say({ event: 'failed', why }); process.exit(1); }
setTimeout(() => fail('timed out'), 60000).unref();

async function main() {
  const page = await openPage(port, 150);
  if (!page) fail('no page target in chromium');
  const { call, evaluate } = page;
  const until = async (expression, seconds, what) => {
    for (let i = 0; i < seconds * 10; ++i) {
      if (await evaluate(expression)) return;
      await sleep(100);
    }
    fail(`${what}: latched=${await evaluate('document.body.dataset.latched')}`);
  };
  await until(`document.body.dataset.live === 'true' && document.body.dataset.latched === 'false'`, 30,
              'the page shows no live data unlatched');
  say({ event: 'live' });
  await until(`document.body.dataset.latched === 'true' && !document.getElementById('safety-banner').hidden`, 30,
              'the banner did not show the latch');
  await sleep(300);
  const shot = await call('Page.captureScreenshot', { format: 'png' });
  fs.writeFileSync(path.join(screenshots, 'hazard-banner.png'), Buffer.from(shot.result.data, 'base64'));
  say({ event: 'latched',
        banner: await evaluate(`document.getElementById('safety-banner').textContent.replace(/\\s+/g, ' ').trim()`),
        release_hidden: await evaluate(`document.getElementById('release').hidden`) });
  process.exit(0);
}
main().catch((error) => fail(String(error && error.stack || error)));
