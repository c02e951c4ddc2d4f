#!/usr/bin/env node
// The JavaScript driver kit's example: Andrew's monotone chain in 2D, writing Qhull's Fx
// (the extreme points, counter-clockwise).  No install needed.
// Run: python -m hullstress run --exec 'mcjs[dim=2,output=Fx,mode=persistent]=node drivers/examples/monotone_chain.mjs'
import { runDriver } from '../kit/hullstress_driver.mjs';

const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);

runDriver({ dim: 2, output: 'Fx', driver: 'monotone_chain.mjs example 1.0', library: 'none' }, (points) => {
  const order = points.map((_, i) => i).sort((i, j) => points[i][0] - points[j][0] || points[i][1] - points[j][1]);
  const chain = (indices) => {
    const h = [];
    for (const i of indices) {
      while (h.length >= 2 && cross(points[h[h.length - 2]], points[h[h.length - 1]], points[i]) <= 0) h.pop();
      h.push(i);
    }
    return h.slice(0, -1);
  };
  const hull = order.length < 2 ? order : chain(order).concat(chain([...order].reverse()));
  return `${hull.length}\n${hull.join('\n')}\n`;
});
