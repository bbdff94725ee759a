// gistream from Node.js with @grpc/grpc-js and @grpc/proto-loader: load the
// Cornell box, render one PNG, then stream a few frames of a session whose
// camera moves, printing the update each frame shows.
//
//   cd examples/node && npm install
//   node render.mjs [--server 127.0.0.1:50051] [--out box.png]
//                   [--ca ca.crt [--cert client.crt --key client.key]] [--token TOKEN]
// --ca connects with TLS; the token (default $GISTREAM_TOKEN) goes with
// every call as "authorization: Bearer TOKEN".
import { readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import path from 'node:path';
import grpc from '@grpc/grpc-js';
import protoLoader from '@grpc/proto-loader';

const arg = (name, fallback) => {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 ? process.argv[i + 1] : fallback;
};
const server = arg('server', process.env.GISTREAM_SERVER || '127.0.0.1:50051');
const out = arg('out', 'box.png');

const here = path.dirname(fileURLToPath(import.meta.url));
const definition = protoLoader.loadSync('gistream/v1/gistream.proto', {
  includeDirs: [path.join(here, '..', '..', 'proto')],
  keepCase: true, longs: Number, enums: String, defaults: true, oneofs: true,
});
const { Gistream } = grpc.loadPackageDefinition(definition).gistream.v1;
const ca = arg('ca'), cert = arg('cert'), key = arg('key');
const credentials = ca
  ? grpc.credentials.createSsl(readFileSync(ca), key && readFileSync(key), cert && readFileSync(cert))
  : grpc.credentials.createInsecure();
const metadata = new grpc.Metadata();
const token = arg('token', process.env.GISTREAM_TOKEN);
if (token) metadata.set('authorization', `Bearer ${token}`);
const client = new Gistream(server, credentials, {
  'grpc.max_receive_message_length': -1,
});
const call = (method, request) => new Promise((resolve, reject) =>
  client[method](request, metadata, (error, response) => (error ? reject(error) : resolve(response))));

const scene = await call('LoadScene', { name: 'cornell_box' });
console.log(`scene ${scene.scene_id}: ${scene.triangle_count} triangles`);
const frame = await call('Render', {
  scene_id: scene.scene_id, solver: 'direct', width: 256, height: 256,
  encoding: { format: 'IMAGE_FORMAT_PNG' },
});
writeFileSync(out, frame.image);
console.log(`wrote ${out} (${frame.width}x${frame.height}, ${frame.total_ms.toFixed(1)} ms)`);

// A session: config first, then updates; frames echo the last update.
const session = client.Session(metadata);
let seq = 0, frames = 0;
session.on('data', (event) => {
  if (event.opened) {
    console.log(`session ${event.opened.session_id} opened`);
  } else if (event.frame) {
    console.log(`frame ${event.frame.frame_number} shows update ${event.frame.last_update_seq}`);
    if (++frames === 5) session.end();
    else if (seq < 4) {
      seq += 1;
      const x = 0.28 + 0.05 * seq;
      session.write({ update: { seq, camera: { look_at: {
        eye: { x, y: 0.27, z: -0.8 }, target: { x: 0.28, y: 0.27, z: 0.28 }, up: { y: 1 } } } } });
    }
  } else if (event.rejected) {
    console.error(`update ${event.rejected.seq} rejected: ${event.rejected.message}`);
  }
});
session.on('error', (error) => { if (error.code !== grpc.status.CANCELLED) console.error(error.message); });
session.on('end', () => client.close());
session.write({ config: { scene_id: scene.scene_id, solver: 'direct', width: 160, height: 120,
                          continuous: { max_fps: 10 } } });
