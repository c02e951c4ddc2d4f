// hullstress_driver.mjs: the JavaScript driver kit of hullstress (docs/executables.md).
//
//   import { runDriver, Reject } from './hullstress_driver.mjs';
//   runDriver({ dim: 3, output: 'i', driver: 'my driver 1.0', library: 'lib 2.3' }, (points) => {
//     // points: an array of [x, y(, z)] arrays of doubles, in input order
//     // return the answer's text in the announced format, or throw new Reject('why')
//   });
//
// With HULLSTRESS_EXEC_PROTOCOL set (persistent mode) it writes the handshake and answers
// case after case ("case N", the points; "hull N", the answer, "end N"; or "error N message")
// until end of file; without it (spawn mode) it reads one case, writes the answer and exits
// (status 1 with the message on stderr when the case is rejected).  "--version" prints the
// handshake line.  Node.js 18 or later; no dependencies.
import { writeSync } from 'node:fs';

export const PROTOCOL_VERSION = 1;

/** Thrown by a hull function to reject a case (an error row; the driver goes on). */
export class Reject extends Error {}

function handshake(info) {
  return `hullstress-exec/${PROTOCOL_VERSION}\tdim=${info.dim}\toutput=${info.output}` +
    `\tdriver=${info.driver ?? ''}\tlibrary=${info.library ?? ''}\n`;
}

function write(text) {
  // Synchronous, whole: the answer is on the pipe before the next case is read.
  const data = Buffer.from(text);
  for (let off = 0; off < data.length;) off += writeSync(1, data, off);
}

/** Parse Qhull's input format from `tokens` at `at`: [points, next index], or null when incomplete. */
function parsePoints(tokens, at, dim) {
  if (tokens.length < at + 2) return null;
  let d = Number(tokens[at]);
  let n = Number(tokens[at + 1]);
  if (d !== dim && n === dim) [d, n] = [n, d]; // Qhull reads either order
  if (!Number.isInteger(n) || n < 0 || d !== dim) throw new Reject(`cannot read ${dim}D points in Qhull's format`);
  if (tokens.length < at + 2 + n * d) return null;
  const points = new Array(n);
  let k = at + 2;
  for (let i = 0; i < n; i++) {
    const p = new Array(d);
    for (let j = 0; j < d; j++) p[j] = Number(tokens[k++]);
    points[i] = p;
  }
  return [points, k];
}

function solve(hull, points) {
  const text = String(hull(points));
  return text.endsWith('\n') || text === '' ? text : text + '\n';
}

/**
 * Run a driver.  `info`: {dim, output, driver, library}; `hull(points)` returns the answer's text.
 */
export function runDriver(info, hull) {
  if (process.argv[process.argv.length - 1] === '--version') {
    write(handshake(info));
    return;
  }
  const persistent = process.env.HULLSTRESS_EXEC_PROTOCOL !== undefined;
  let pending = '';
  const chunks = [];
  if (!persistent) {
    process.stdin.on('data', (chunk) => chunks.push(chunk));
    process.stdin.on('end', () => {
      try {
        const parsed = parsePoints(Buffer.concat(chunks).toString().split(/\s+/).filter(Boolean), 0, info.dim);
        if (parsed === null) throw new Reject(`cannot read ${info.dim}D points in Qhull's format`);
        write(solve(hull, parsed[0]));
      } catch (err) {
        process.stderr.write(`${err instanceof Reject ? '' : 'driver raised: '}${err.message}\n`);
        process.exitCode = err instanceof Reject ? 1 : 2;
      }
    });
    return;
  }
  write(handshake(info));
  process.stdin.setEncoding('utf8');
  let lines = 0; // newlines in `pending`
  let need = 3; // lines the case under way needs: "case N", the dimension, the count, then one per point
  process.stdin.on('data', (chunk) => {
    pending += chunk;
    for (let i = chunk.indexOf('\n'); i >= 0; i = chunk.indexOf('\n', i + 1)) lines++;
    while (lines >= need) {
      const head = pending.split('\n', 3);
      if (need === 3) {
        // Only the header is known complete: learn how many lines the points take.
        let [d, n] = [Number(head[1]), Number(head[2])];
        if (d !== info.dim && n === info.dim) [d, n] = [n, d]; // Qhull reads either order
        need = 3 + (d === info.dim && Number.isInteger(n) && n > 0 ? n : 0);
        if (need > 3) continue;
      }
      // The whole case is here: "case N", then Qhull's input format.
      let cut = -1;
      for (let k = 0; k < need; k++) cut = pending.indexOf('\n', cut + 1);
      const text = pending.slice(0, cut + 1);
      pending = pending.slice(cut + 1);
      lines -= need;
      need = 3;
      const tokens = text.split(/\s+/).filter(Boolean);
      const number = tokens[1];
      try {
        if (tokens[0] !== 'case') throw new Reject(`expected 'case N', got '${head[0].slice(0, 40)}'`);
        const parsed = parsePoints(tokens, 2, info.dim);
        if (parsed === null) throw new Reject(`cannot read ${info.dim}D points in Qhull's format`);
        write(`hull ${number}\n${solve(hull, parsed[0])}end ${number}\n`);
      } catch (err) {
        const why = String(err instanceof Reject ? err.message : `driver raised: ${err.message}`);
        write(`error ${number} ${why.replace(/[\r\n]+/g, ' ')}\n`);
      }
    }
  });
}
