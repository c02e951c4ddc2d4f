#!/usr/bin/env node
// hullstress driver for the quickhull3d npm package (3D).  Writes Qhull's i layout: one
// triangle per line, input point indices, counter-clockwise seen from outside (quickhull3d's
// orientation).  Install: npm install --prefix drivers/js
// Run: python -m hullstress run --exec 'qh3d[mode=persistent]=node drivers/js/quickhull3d_driver.mjs'
import { register } from 'node:module';
import { readFileSync } from 'node:fs';
import { runDriver } from '../kit/hullstress_driver.mjs';

register('./resolve_js_extension.mjs', import.meta.url);
const { default: quickhull } = await import('quickhull3d');
const { version } = JSON.parse(readFileSync(new URL('./node_modules/quickhull3d/package.json', import.meta.url)));

runDriver({ dim: 3, output: 'i', driver: 'hullstress quickhull3d driver 1.0', library: `quickhull3d ${version}` },
  (points) => {
    const faces = quickhull(points);
    return `${faces.length}\n${faces.map((f) => f.join(' ')).join('\n')}\n`;
  });
