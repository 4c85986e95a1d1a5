// A bare TLS client for tests/web/tls_test.cpp: what certificate wheeltec-web presents, and
// whether it refuses a client that offers only TLS 1.0 and 1.1.
//   node tls_probe.cjs peer PORT CA.pem   -> {"ok":true,"subject":CN,"protocol":"TLSv1.3"}
//   node tls_probe.cjs old PORT           -> {"ok":true,"refused":MESSAGE} when refused
'use strict';
const fs = require('fs');
const tls = require('tls');

const [mode, port, ca] = process.argv.slice(2);
const say = (object) => { console.log(JSON.stringify(object)); process.exit(object.ok ? 0 : 1); };
setTimeout(() => say({ ok: false, why: 'timed out' }), 15000).unref();

if (mode === 'peer') {
  const socket = tls.connect({ host: '127.0.0.1', port: Number(port), ca: fs.readFileSync(ca) }, () => {
    const certificate = socket.getPeerCertificate();
    say({ ok: socket.authorized, subject: certificate.subject.CN, protocol: socket.getProtocol() });
  });
  socket.on('error', (error) => say({ ok: false, why: error.message }));
} else if (mode === 'old') {
  const socket = tls.connect({ host: '127.0.0.1', port: Number(port), rejectUnauthorized: false,
                               minVersion: 'TLSv1', maxVersion: 'TLSv1.1', ciphers: 'DEFAULT@SECLEVEL=0' }, () => {
    say({ ok: false, why: `accepted ${socket.getProtocol()}` });
  });
  socket.on('error', (error) => say({ ok: true, refused: error.message }));
} else {
  say({ ok: false, why: `unknown mode ${mode}` });
}
