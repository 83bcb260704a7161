// A short-axis-only test input (session 14's apex floor acts only where no long-axis curve reaches
// the apex): the left half of an ellipsoidal cavity, semi-axes 26 x 22 mm across and 60 mm along
// its axis, cut by short-axis planes every 8 mm from 2 mm below its equator (z = -2) down to
// z = -50, 10 mm above the apex at z = -60, 48 points a ring. No long-axis curve, so the app's
// default (the apex floor on) puts one lid point near z = -60 and the mesh reaches further down
// than without it. Built in the test, so no fixture is committed. Used by
// tests/e2e/apexfloor.test.mjs and tests/node/apexFloor.test.ts.

export const SAX_ONLY_NAME = 'ellipsoid-sax-only.csv';
/** The cavity's apex, z in mm (its axis is z). */
export const APEX_Z = -60;

/** The CSV text (`contour,x,y,z,surface`, surface LV_ENDO) and its ring heights. */
export function saxOnlyEllipsoid({ a = 26, b = 22, c = 60, points = 48 } = {}) {
  const heights = [];
  for (let z = -2; z >= -50; z -= 8) heights.push(z);
  const rows = ['contour,x,y,z,surface'];
  heights.forEach((z, k) => {
    const s = Math.sqrt(1 - (z / c) ** 2);
    for (let i = 0; i < points; i++) {
      const t = (2 * Math.PI * i) / points;
      rows.push(`sax${String(k + 1).padStart(2, '0')},${(a * s * Math.cos(t)).toFixed(4)},${(b * s * Math.sin(t)).toFixed(4)},${z},LV_ENDO`);
    }
  });
  return { csv: `${rows.join('\n')}\n`, heights };
}
