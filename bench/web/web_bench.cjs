// wheeltec-web's benchmark (issue #14, item 7), run by scripts/bench-web.sh inside one
// scripts/vcan-run session next to wheeltec-emu, wheeltecd and wheeltec-web:
//   1. latency from the 0x103 frame (the record's `time`: the kernel's receive time of its
//      last CAN frame) to the message at 8 Foxglove clients (npm's @foxglove/ws-protocol),
//      p50/p99, next to a direct subscriber of wheeltecd's socket in the same run;
//   2. wheeltec-web's CPU per record with those 8 viewers (utime+stime from /proc over the
//      run; User-Mode Linux counts them in 10 ms ticks) and its resident memory;
//   3. with --devtools PORT (headless Chromium started with --remote-debugging-port and a
//      blank page): the same latency at wheeltec-web's own page, measured in the page as
//      its WebSocket delivers each telemetry message, next to the daemon's subscriber again.
//   4. with --strace PATH: wheeltec-web's system calls per record with those 8 viewers,
//      counted exactly (strace -c -f -p, attached for half the run after the latency window,
//      so that strace's own cost is not in the latencies), by system call;
//   5. with --tls-url https://127.0.0.1:PORT2 --tls-web-pid PID2 (a second wheeltec-web with a
//      certificate that $NODE_EXTRA_CA_CERTS trusts): round 1 and 2 again over wss://;
//   6. with --relay-socket PATH (bench/web/relay.py): a third subscriber through one process
//      that only reads and writes, the floor of any bridge, and wheeltec-web over that floor.
//   node web_bench.cjs --socket PATH --url http://127.0.0.1:PORT --web-pid PID
//                      [--viewers 8] [--seconds 20] [--devtools PORT] [--relay-socket PATH]
//                      [--tls-url https://127.0.0.1:PORT2 --tls-web-pid PID2] [--strace PATH]
// Prints a table and, last, one JSON line with every figure.
'use strict';
const fs = require('fs');
const net = require('net');
const os = require('os');
const { spawn } = require('child_process');
const WebSocket = require('ws');
const { FoxgloveClient } = require('@foxglove/ws-protocol');
const { openPage } = require('../../tests/web/clients/devtools.cjs');

const options = { viewers: 8, seconds: 20 };
for (let i = 2; i < process.argv.length; i += 2) options[process.argv[i].replace(/^--/, '').replace(/-./g, (m) => m[1].toUpperCase())] = process.argv[i + 1];
const viewers = Number(options.viewers);
const seconds = Number(options.seconds);
const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
const nowS = () => (performance.timeOrigin + performance.now()) / 1000;
function fail(why) { console.error(`web_bench: ${why}`); process.exit(1); }

// Latencies in ms, collected while `recording` is true.
class Latencies {
  constructor() { this.values = []; this.recording = false; }
  add(recordTime) { if (this.recording) this.values.push((nowS() - recordTime) * 1000); }
  summary() {
    const sorted = [...this.values].sort((a, b) => a - b);
    const at = (q) => sorted.length ? sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))] : null;
    return { n: sorted.length, p50_ms: at(0.5), p99_ms: at(0.99), max_ms: sorted.at(-1) ?? null };
  }
}

// A JSON-RPC client of wheeltecd subscribed to telemetry.
function daemonSubscriber(path, latencies) {
  return new Promise((resolve, reject) => {
    const socket = net.createConnection(path, () => {
      socket.write('{"jsonrpc":"2.0","id":1,"method":"subscribe","params":{"topics":["telemetry"]}}\n');
      resolve(socket);
    });
    socket.on('error', reject);
    let buffered = '';
    socket.on('data', (chunk) => {
      buffered += chunk;
      let end;
      while ((end = buffered.indexOf('\n')) >= 0) {
        const line = buffered.slice(0, end);
        buffered = buffered.slice(end + 1);
        const message = JSON.parse(line);
        if (message.method === 'telemetry') latencies.add(message.params.time);
      }
    });
  });
}

// Telemetry messages that every Foxglove client of the bench has received.
let viewerMessages = 0;

// A Foxglove client subscribed to /wheeltec/telemetry.
function foxgloveViewer(url, latencies) {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
    const client = new FoxgloveClient({ ws });
    client.on('error', reject);
    client.on('advertise', (channels) => {
      const telemetry = channels.find((channel) => channel.topic === '/wheeltec/telemetry');
      if (!telemetry) return reject(new Error('no /wheeltec/telemetry channel'));
      client.subscribe(telemetry.id);
      resolve(client);
    });
    client.on('message', ({ data }) => {
      ++viewerMessages;
      latencies.add(JSON.parse(new TextDecoder().decode(data)).time);
    });
  });
}

function cpuSeconds(pid) {
  const fields = fs.readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
  return (Number(fields[11]) + Number(fields[12])) / 100;  // utime, stime in USER_HZ (100)
}
function memoryKiB(pid) {
  const status = fs.readFileSync(`/proc/${pid}/status`, 'utf8');
  const read = (name) => Number((status.match(new RegExp(`^${name}:\\s+(\\d+) kB`, 'm')) || [])[1]);
  return { rss_kib: read('VmRSS'), peak_rss_kib: read('VmHWM') };
}

// The page's own latency: a script that Chromium runs before the page's own wraps WebSocket
// and times each telemetry message as the page receives it.
const pageProbe = `(() => {
  window.__benchLatencies = [];
  const Native = window.WebSocket;
  window.WebSocket = function (url, protocols) {
    const ws = new Native(url, protocols);
    ws.addEventListener('message', (event) => {
      if (typeof event.data === 'string') return;
      const arrived = (performance.timeOrigin + performance.now()) / 1000;
      const parse = (buffer) => {
        const bytes = new Uint8Array(buffer);
        if (bytes[0] !== 1) return;
        try {
          const record = JSON.parse(new TextDecoder().decode(bytes.subarray(13)));
          if (record.seq !== undefined && record.velocity && window.__benchRecording) {
            window.__benchLatencies.push((arrived - record.time) * 1000);
          }
        } catch (error) { /* not JSON */ }
      };
      if (event.data instanceof ArrayBuffer) parse(event.data); else event.data.arrayBuffer().then(parse);
    });
    return ws;
  };
  window.WebSocket.prototype = Native.prototype;
  Object.assign(window.WebSocket, { CONNECTING: 0, OPEN: 1, CLOSING: 2, CLOSED: 3 });
})();`;

async function browserLatencies(port, pageUrl, daemonLatencies) {
  const devtools = await openPage(port, 300);
  if (!devtools) fail('no page target in Chromium');
  const { call, evaluate } = devtools;
  await call('Page.enable');
  await call('Page.addScriptToEvaluateOnNewDocument', { source: pageProbe });
  await call('Page.navigate', { url: pageUrl });
  for (let i = 0; i < 300; ++i) {
    if (await evaluate('document.body && document.body.dataset.live === "true"')) break;
    await sleep(200);
  }
  await sleep(2000);  // past the page's start-up
  await evaluate('window.__benchRecording = true');
  daemonLatencies.recording = true;
  await sleep(seconds * 1000);
  daemonLatencies.recording = false;
  const values = await evaluate('window.__benchRecording = false, window.__benchLatencies');
  devtools.close();
  const page = new Latencies();
  page.values = values || [];
  return page;
}

// strace -c's table: calls per system call name, and "total".
function straceCalls(text) {
  const calls = {};
  for (const line of text.split('\n')) {
    const fields = line.trim().split(/\s+/);
    const name = fields.at(-1);
    if (fields.length < 5 || !/^[a-z_0-9]+$/.test(name) || !/^[0-9.]+$/.test(fields[0])) continue;
    // % time, seconds, usecs/call, calls, [errors,] syscall
    calls[name] = Number(fields[3]);
  }
  return calls;
}

// wheeltec-web's system calls per record over `windowS`: strace attached to `pid`, the
// records the daemon published counted from strace's "attached" to its detach, and the
// records wheeltec-web forwarded (messages at the viewers / viewers): slowed by ptrace, it
// reads the daemon late and the daemon coalesces telemetry for it, so these are fewer.
async function syscallsPerRecord(pid, windowS) {
  const out = `${os.tmpdir()}/web-bench-strace-${pid}.txt`;
  let records = 0;
  const counter = new Latencies();
  counter.add = () => { if (counter.recording) ++records; };
  const socket = await daemonSubscriber(options.socket, counter);
  await sleep(300);
  const strace = spawn(options.strace, ['-c', '-f', '-p', String(pid), '-o', out], { stdio: ['ignore', 'ignore', 'pipe'] });
  const exited = new Promise((resolve) => strace.on('exit', resolve));
  const attached = new Promise((resolve) => strace.stderr.on('data', (chunk) => { if (/attached/.test(chunk)) resolve(true); }));
  if (!await Promise.race([attached, sleep(10000).then(() => false)])) {
    strace.kill('SIGKILL');
    socket.destroy();
    return { error: 'strace did not attach' };
  }
  counter.recording = true;
  const messagesBefore = viewerMessages;
  await sleep(windowS * 1000);
  counter.recording = false;
  const forwarded = (viewerMessages - messagesBefore) / viewers;
  strace.kill('SIGINT');
  await exited;
  socket.destroy();
  const calls = straceCalls(fs.readFileSync(out, 'utf8'));
  fs.rmSync(out, { force: true });
  const perRecord = {};
  for (const [name, count] of Object.entries(calls)) perRecord[name] = records ? count / records : null;
  const perForwarded = {};
  for (const [name, count] of Object.entries(calls)) perForwarded[name] = forwarded ? count / forwarded : null;
  return { seconds: windowS, records, forwarded, calls, per_record: perRecord, per_forwarded_record: perForwarded };
}

const row = (name, s) => `| ${name} | ${s.n} | ${s.p50_ms?.toFixed(2)} | ${s.p99_ms?.toFixed(2)} | ${s.max_ms?.toFixed(2)} |`;

// One round: `viewers` Foxglove clients at wsUrl next to a direct subscriber of the daemon,
// and the CPU the wheeltec-web process `pid` used meanwhile.
async function foxgloveRound(wsUrl, pid) {
  const daemon = new Latencies();
  const foxglove = new Latencies();
  const daemonSocket = await daemonSubscriber(options.socket, daemon);
  // The same subscription through bench/web/relay.py: the floor of one process in between.
  const relayed = new Latencies();
  const relaySocket = options.relaySocket ? await daemonSubscriber(options.relaySocket, relayed) : null;
  const clients = [];
  for (let i = 0; i < viewers; ++i) clients.push(await foxgloveViewer(wsUrl, foxglove));
  await sleep(2000);
  let records = 0;
  const counter = new Latencies();
  counter.add = () => { if (counter.recording) ++records; };
  const counting = await daemonSubscriber(options.socket, counter);
  await sleep(500);
  const cpuBefore = cpuSeconds(pid);
  daemon.recording = foxglove.recording = counter.recording = relayed.recording = true;
  await sleep(seconds * 1000);
  daemon.recording = foxglove.recording = counter.recording = relayed.recording = false;
  const cpu = cpuSeconds(pid) - cpuBefore;
  counting.destroy();
  console.error(`web_bench: latency window done (${wsUrl})`);
  const syscalls = options.strace ? await syscallsPerRecord(pid, Math.max(2, seconds / 2)) : null;
  if (options.strace) console.error('web_bench: system calls counted');
  daemonSocket.destroy();
  relaySocket?.destroy();
  for (const client of clients) client.close();
  return {
    daemon: daemon.summary(), viewers: foxglove.summary(), relayed: relaySocket ? relayed.summary() : null,
    cpu: { records, cpu_s: cpu, us_per_record: records ? (cpu / records) * 1e6 : null,
           us_per_message: records ? (cpu / (records * viewers)) * 1e6 : null, tick_s: 0.01 },
    memory: memoryKiB(pid),
    syscalls,
  };
}

// What wheeltec-web adds to the daemon's own subscriber in the same run, against issue
// #23's target of at most 0.3 ms at p50 and at p99.
function added(round) {
  const p50 = round.viewers.p50_ms - round.daemon.p50_ms;
  const p99 = round.viewers.p99_ms - round.daemon.p99_ms;
  return { p50_ms: p50, p99_ms: p99, target_ms: 0.3, met: p50 <= 0.3 && p99 <= 0.3 };
}
// What one relay process adds (the floor of any bridge on this machine), and wheeltec-web over that floor.
function relayFloor(round) {
  if (!round.relayed?.n) return null;
  return { relay_p50_ms: round.relayed.p50_ms - round.daemon.p50_ms, relay_p99_ms: round.relayed.p99_ms - round.daemon.p99_ms,
           web_over_relay_p50_ms: round.viewers.p50_ms - round.relayed.p50_ms,
           web_over_relay_p99_ms: round.viewers.p99_ms - round.relayed.p99_ms };
}
const floorLine = (what, f) => f ? `one relay process (bench/web/relay.py)${what} adds over the daemon's subscriber: p50 ` +
  `${f.relay_p50_ms.toFixed(2)} ms, p99 ${f.relay_p99_ms.toFixed(2)} ms; wheeltec-web adds over that relay: p50 ` +
  `${f.web_over_relay_p50_ms.toFixed(2)} ms, p99 ${f.web_over_relay_p99_ms.toFixed(2)} ms` : null;
const addedLine = (what, a) => `added by wheeltec-web${what} over the daemon's subscriber: p50 ${a.p50_ms.toFixed(2)} ms, ` +
  `p99 ${a.p99_ms.toFixed(2)} ms (target: at most ${a.target_ms} ms each; ${a.met ? 'met' : 'not met'})`;

function syscallLine(what, s) {
  if (!s) return `wheeltec-web system calls${what}: not counted (no strace)`;
  if (s.error) return `wheeltec-web system calls${what}: not counted (${s.error})`;
  const top = Object.entries(s.per_record).filter(([name]) => name !== 'total').sort((a, b) => b[1] - a[1]).slice(0, 5)
    .map(([name, n]) => `${name} ${n.toFixed(2)}`).join(', ');
  const topForwarded = Object.entries(s.per_forwarded_record).filter(([name]) => name !== 'total')
    .sort((a, b) => b[1] - a[1]).slice(0, 5).map(([name, n]) => `${name} ${n.toFixed(2)}`).join(', ');
  return `wheeltec-web system calls with ${viewers} viewers${what} (strace -c -f, ${s.seconds} s): ` +
    `${s.per_record.total?.toFixed(2)} per record the daemon published (${s.records}; ${top}); ` +
    `${s.per_forwarded_record.total?.toFixed(2)} per record wheeltec-web forwarded (${s.forwarded.toFixed(0)}; ${topForwarded})`;
}

const cpuLine = (what, cpu) => `wheeltec-web CPU with ${viewers} viewers${what}: ${cpu.cpu_s.toFixed(2)} s for ${cpu.records} ` +
  `records = ${cpu.us_per_record?.toFixed(0)} us/record (${cpu.us_per_message?.toFixed(1)} us per message sent; 10 ms ticks)`;

async function main() {
  setTimeout(() => fail('timed out'), (4 * seconds + 240) * 1000).unref();  // Chromium in User-Mode Linux loads slowly
  const result = { viewers, seconds };
  const plain = await foxgloveRound(options.url.replace(/^http/, 'ws'), options.webPid);
  result.foxglove = { daemon: plain.daemon, viewers: plain.viewers, relayed: plain.relayed };
  result.relay_floor = relayFloor(plain);
  result.cpu = plain.cpu;
  result.syscalls = plain.syscalls;
  result.added = added(plain);
  result.memory = plain.memory;
  if (options.tlsUrl) {
    // wss:// to a second wheeltec-web with a certificate ($NODE_EXTRA_CA_CERTS trusts it).
    const tls = await foxgloveRound(options.tlsUrl.replace(/^https/, 'wss'), options.tlsWebPid);
    result.tls = { daemon: tls.daemon, viewers: tls.viewers, relayed: tls.relayed, relay_floor: relayFloor(tls),
                   cpu: tls.cpu, memory: tls.memory, added: added(tls),
                   syscalls: tls.syscalls };
  }

  if (options.devtools) {
    const daemonAgain = new Latencies();
    const again = await daemonSubscriber(options.socket, daemonAgain);
    const page = await browserLatencies(options.devtools, options.url + '/', daemonAgain);
    again.destroy();
    result.browser = { daemon: daemonAgain.summary(), page: page.summary() };
  }

  console.log('| 0x103 frame -> message | n | p50 ms | p99 ms | max ms |');
  console.log('|---|---|---|---|---|');
  console.log(row('wheeltecd subscriber (same run)', result.foxglove.daemon));
  console.log(row(`${viewers} Foxglove clients via wheeltec-web`, result.foxglove.viewers));
  if (result.foxglove.relayed) console.log(row('wheeltecd subscriber through one relay process', result.foxglove.relayed));
  if (result.tls) {
    console.log(row('wheeltecd subscriber (wss:// run)', result.tls.daemon));
    console.log(row(`${viewers} Foxglove clients over wss://`, result.tls.viewers));
  }
  if (result.browser) {
    console.log(row('wheeltecd subscriber (browser run)', result.browser.daemon));
    console.log(row('the page in headless Chromium', result.browser.page));
  }
  console.log(addedLine('', result.added));
  if (result.tls) console.log(addedLine(' over wss://', result.tls.added));
  if (result.relay_floor) console.log(floorLine('', result.relay_floor));
  if (result.tls?.relay_floor) console.log(floorLine(' (wss:// run)', result.tls.relay_floor));
  console.log(cpuLine('', result.cpu));
  if (result.tls) console.log(cpuLine(' over wss://', result.tls.cpu));
  console.log(syscallLine('', result.syscalls));
  if (result.tls) console.log(syscallLine(' over wss://', result.tls.syscalls));
  console.log(`wheeltec-web memory: RSS ${result.memory.rss_kib} KiB, peak ${result.memory.peak_rss_kib} KiB` +
              (result.tls ? `; with TLS: RSS ${result.tls.memory.rss_kib} KiB, peak ${result.tls.memory.peak_rss_kib} KiB` : ''));
  console.log(JSON.stringify(result));
  if (!result.foxglove.viewers.n || !result.foxglove.daemon.n || (result.browser && !result.browser.page.n) ||
      (result.tls && !result.tls.viewers.n)) {
    fail('some client received nothing');
  }
  process.exit(0);
}

main().catch((error) => fail(error.stack || String(error)));
