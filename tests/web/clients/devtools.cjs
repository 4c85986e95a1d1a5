// Headless Chromium's DevTools protocol over the `ws` package, for browser.cjs (the web.Page
// test) and bench/web/web_bench.cjs: the first page target of a Chromium started with
// --remote-debugging-port, and calls on it.
'use strict';
const http = require('http');
const WebSocket = require('ws');

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

function getJson(port, path) {
  return new Promise((resolve, reject) => {
    http.get({ host: '127.0.0.1', port: Number(port), path }, (response) => {
      let body = '';
      response.on('data', (chunk) => (body += chunk));
      response.on('end', () => { try { resolve(JSON.parse(body)); } catch (error) { reject(error); } });
    }).on('error', reject);
  });
}

// Resolves to { call(method, params), evaluate(expression), close() } once Chromium lists a
// page, or to null when it lists none within `tries` looks 200 ms apart.
async function openPage(port, tries) {
  let target = null;
  for (let i = 0; i < tries && !target; ++i) {
    try { target = (await getJson(port, '/json/list')).find((t) => t.type === 'page'); } catch (error) { /* starting */ }
    if (!target) await sleep(200);
  }
  if (!target) return null;
  const ws = new WebSocket(target.webSocketDebuggerUrl, { perMessageDeflate: false });
  await new Promise((resolve, reject) => { ws.on('open', resolve); ws.on('error', reject); });
  let nextId = 1;
  const pending = new Map();
  ws.on('message', (data) => {
    const message = JSON.parse(data);
    if (message.id && pending.has(message.id)) { pending.get(message.id)(message); pending.delete(message.id); }
  });
  const call = (method, params = {}) => new Promise((resolve) => {
    const id = nextId++;
    pending.set(id, resolve);
    ws.send(JSON.stringify({ id, method, params }));
  });
  const evaluate = async (expression) => (await call('Runtime.evaluate', { expression, returnByValue: true })).result.result.value;
  return { call, evaluate, close: () => ws.close() };
}

module.exports = { openPage, sleep };
