// SPDX-License-Identifier: Apache-2.0
// An independent DIS sender for Mirage's tests: Entity State PDUs encoded by open-dis (npm,
// BSD-2-Clause), not by Mirage, sent over UDP at the times the test wrote.
//   node dis_sender.js <node_modules> <version 6|7> <fields.csv> <port>
// Each CSV line: send_unix_ms, exercise, site, application, entity, timestamp, algorithm,
// vx, vy, vz, x, y, z, psi, theta, phi, ax, ay, az, wx, wy, wz.
'use strict';
const dgram = require('dgram');
const fs = require('fs');
const path = require('path');

const [modules, version, csv, port] = process.argv.slice(2);
const dis = require(path.join(modules, 'open-dis', 'dist', version === '6' ? 'dis6.min.js' : 'dis7.min.js'));

function pdu(f) {
    const p = new dis.EntityStatePdu();
    p.exerciseID = f[1];
    const id = p.entityID;  // field names differ between the two generated versions
    if (version === '6') { id.site = f[2]; id.application = f[3]; id.entity = f[4]; }
    else { id.siteID = f[2]; id.applicationID = f[3]; id.entityID = f[4]; }
    p.timestamp = f[5];
    if (version === '6') p.pduLength = 144; else p.length = 144;
    const dr = p.deadReckoningParameters;
    dr.deadReckoningAlgorithm = f[6];
    [p.entityLinearVelocity.x, p.entityLinearVelocity.y, p.entityLinearVelocity.z] = f.slice(7, 10);
    [p.entityLocation.x, p.entityLocation.y, p.entityLocation.z] = f.slice(10, 13);
    [p.entityOrientation.psi, p.entityOrientation.theta, p.entityOrientation.phi] = f.slice(13, 16);
    [dr.entityLinearAcceleration.x, dr.entityLinearAcceleration.y, dr.entityLinearAcceleration.z] = f.slice(16, 19);
    [dr.entityAngularVelocity.x, dr.entityAngularVelocity.y, dr.entityAngularVelocity.z] = f.slice(19, 22);
    const out = new dis.OutputStream(new ArrayBuffer(1500));
    p.encodeToBinary(out);
    return Buffer.from(out.toByteArray());
}

const rows = fs.readFileSync(csv, 'utf8').trim().split('\n').map((l) => l.split(',').map(Number));
const socket = dgram.createSocket('udp4');
let sent = 0;
function next() {
    if (sent === rows.length) {
        console.log(`dis_sender: sent ${sent} PDUs (DIS ${version}, open-dis)`);
        socket.close();
        return;
    }
    const row = rows[sent];
    const wait = row[0] - Date.now();
    if (wait > 0) { setTimeout(next, wait); return; }
    const b = pdu(row);
    if (b.length !== 144) throw new Error(`open-dis wrote ${b.length} bytes, expected 144`);
    socket.send(b, Number(port), '127.0.0.1', (err) => {
        if (err) throw err;
        ++sent;
        next();
    });
}
next();
