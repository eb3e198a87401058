// What the replay page and the explorer's page draw alike: the colours of robots and of
// Look rays, the hull, the arrow of a move, the log-scale chart, the panel's swatches.
// Both pages include it before their own script (monoculus_plot::VIEW_JS).
"use strict";
window.MonoculusView = (function () {
  // A robot's colour by what it does: not activated, looked and stays, computing
  // (ASYNC), moving.
  const STATE = [
    { name: "idle", color: "#6b7280" },
    { name: "looked, stays", color: "#2563eb" },
    { name: "computing", color: "#d97706" },
    { name: "moving", color: "#dc2626" },
  ];
  // The terminating algorithm: by the memory bits set, green once all are.
  const BITS = ["#9ca3af", "#a78bfa", "#7c3aed", "#5b21b6", "#3b0764", "#1e1b4b", "#0f172a"];
  const TERMINATED = "#16a34a";
  function bitsColor(b, nbits) {
    let c = 0; for (let i = 0; i < nbits; i++) if (b & (1 << i)) c++;
    return c === nbits ? TERMINATED : BITS[c];
  }
  // LD rays: far (beyond c) or near.
  const FAR = "#ea580c", NEAR = "#0284c7";
  // OLA: a colour per quadrant (octant in space) of the observer's agreed axes; points on
  // an axis (within the tolerance) grey. Keys: the sides, "+" or "-", x first.
  const AXIS = "#6b7280";
  function sides(dim) {
    return dim === 2
      ? { "++": "#dc2626", "-+": "#2563eb", "--": "#16a34a", "+-": "#9333ea" }
      : { "+++": "#dc2626", "-++": "#2563eb", "--+": "#16a34a", "+-+": "#9333ea",
          "++-": "#f97316", "-+-": "#0891b2", "---": "#65a30d", "+--": "#db2777" };
  }
  // The key of sides given as -1, 0, 1 per axis (null: on an axis).
  function sideKey(signs) {
    let key = "";
    for (const s of signs) { if (s === 0) return null; key += s > 0 ? "+" : "-"; }
    return key;
  }
  const MOVE = "#059669";
  function esc(t) { return String(t).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;"); }
  function sw(color, label) { return '<span class="sw" style="background:' + color + '"></span>' + label + " "; }
  function fmt(x) { return Math.abs(x) >= 1e4 || (Math.abs(x) < 1e-3 && x !== 0) ? x.toExponential(4) : x.toFixed(4); }
  // A closed polygon of canvas points, the hull's fill and outline.
  function polygon(ctx, pts) {
    if (!pts.length) return;
    ctx.beginPath();
    ctx.moveTo(pts[0][0], pts[0][1]);
    for (let i = 1; i < pts.length; i++) ctx.lineTo(pts[i][0], pts[i][1]);
    ctx.closePath();
    ctx.fillStyle = "rgba(148,163,184,0.10)"; ctx.fill();
    ctx.strokeStyle = "#94a3b8"; ctx.lineWidth = 1; ctx.stroke();
  }
  // An arrow from a to b (canvas points), dashed or not.
  function arrow(ctx, a, b, color, dashed) {
    ctx.setLineDash(dashed ? [5, 4] : []);
    ctx.strokeStyle = color; ctx.fillStyle = color; ctx.lineWidth = 2.5;
    ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke();
    ctx.setLineDash([]);
    const ang = Math.atan2(b[1] - a[1], b[0] - a[0]);
    ctx.beginPath(); ctx.moveTo(b[0], b[1]);
    ctx.lineTo(b[0] - 9 * Math.cos(ang - 0.4), b[1] - 9 * Math.sin(ang - 0.4));
    ctx.lineTo(b[0] - 9 * Math.cos(ang + 0.4), b[1] - 9 * Math.sin(ang + 0.4));
    ctx.closePath(); ctx.fill();
  }
  // Series against time on a log scale, each scaled to its own range ([values, colour]
  // pairs), and a red line at time `mark` (null: none).
  function logChart(canvas, time, series, mark) {
    const g = canvas.getContext("2d"), w = canvas.width, h = canvas.height, n = time.length;
    g.fillStyle = "#fff"; g.fillRect(0, 0, w, h);
    if (n < 2) return;
    const t0 = time[0], t1 = time[n - 1], span = t1 > t0 ? t1 - t0 : 1;
    for (const [values, color] of series) {
      let a = Infinity, b = -Infinity;
      for (const v of values) if (v > 0) { a = Math.min(a, Math.log(v)); b = Math.max(b, Math.log(v)); }
      if (!isFinite(a)) continue;
      if (b - a < 1e-9) { a -= 1; b += 1; }
      g.strokeStyle = color; g.lineWidth = 1; g.beginPath();
      for (let i = 0; i < n; i++) {
        const v = values[i] > 0 ? Math.log(values[i]) : a;
        const x = 4 + (w - 8) * (time[i] - t0) / span, y = h - 4 - (h - 8) * (v - a) / (b - a);
        if (i) g.lineTo(x, y); else g.moveTo(x, y);
      }
      g.stroke();
    }
    if (mark !== null) {
      const x = 4 + (w - 8) * (mark - t0) / span;
      g.strokeStyle = "#dc2626"; g.beginPath(); g.moveTo(x, 0); g.lineTo(x, h); g.stroke();
    }
  }
  return { STATE, BITS, TERMINATED, bitsColor, FAR, NEAR, AXIS, sides, sideKey, MOVE, esc, sw, fmt, polygon, arrow, logChart };
})();
