"""Hand-written SVG log-log line plots (Python standard library only).

plot(path, series, ...) draws one polyline with markers per series on log10 axes with decade
grid lines, point labels and a legend. A series is
    {"name": str, "points": [(x, y, label or None[, hollow]), ...], "dash": bool (optional)}
(hollow: drawn as an open circle, e.g. a lower bound).
Points with x or y <= 0 cannot be drawn on log axes: they are clamped to the axis floor and
drawn hollow, and the caller says so in the caption.
"""

import math
from xml.sax.saxutils import escape

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2",
           "#17becf", "#7f7f7f", "#bcbd22"]


def _decades(lo, hi):
    a = math.floor(math.log10(lo) + 1e-9)
    b = math.ceil(math.log10(hi) - 1e-3)
    if a == b:
        b += 1
    return a, b


def _fmt(e):
    v = 10.0 ** e
    if e >= 0:
        return f"{v:.0f}"
    return f"{v:.{-e}f}"


def plot(path, series, title, xlabel, ylabel, caption=None, guides=None, width=900, height=600):
    """Write the plot to path. guides: extra dashed grey lines [(name, [(x, y), ...])]."""
    guides = guides or []
    xs = [p[0] for s in series for p in s["points"] if p[0] > 0]
    ys = [p[1] for s in series for p in s["points"] if p[1] > 0]
    for _, pts in guides:
        xs += [p[0] for p in pts if p[0] > 0]
        ys += [p[1] for p in pts if p[1] > 0]
    if not xs or not ys:
        xs, ys = [1.0, 10.0], [1.0, 10.0]
    x0, x1 = _decades(min(xs), max(xs))
    y0, y1 = _decades(min(ys), max(ys))
    caption = ([caption] if isinstance(caption, str) else caption) or []
    left, right, top, bottom = 80, 250, 50, 60 + 14 * len(caption)
    pw, ph = width - left - right, height - top - bottom

    def px(x):
        x = max(x, 10.0 ** x0)
        return left + (math.log10(x) - x0) / (x1 - x0) * pw

    def py(y):
        y = max(y, 10.0 ** y0)
        return top + ph - (math.log10(y) - y0) / (y1 - y0) * ph

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">',
           f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<text x="{left + pw / 2}" y="25" text-anchor="middle" font-size="15">'
           f'{escape(title)}</text>']
    # grid: decades solid, 2..9 faint
    for e in range(x0, x1 + 1):
        x = px(10.0 ** e)
        out.append(f'<line x1="{x:.1f}" y1="{top}" x2="{x:.1f}" y2="{top + ph}" stroke="#ccc"/>')
        out.append(f'<text x="{x:.1f}" y="{top + ph + 18}" text-anchor="middle">{_fmt(e)}</text>')
        if e < x1:
            for k in range(2, 10):
                xx = px(k * 10.0 ** e)
                out.append(f'<line x1="{xx:.1f}" y1="{top}" x2="{xx:.1f}" y2="{top + ph}" '
                           f'stroke="#eee"/>')
    for e in range(y0, y1 + 1):
        y = py(10.0 ** e)
        out.append(f'<line x1="{left}" y1="{y:.1f}" x2="{left + pw}" y2="{y:.1f}" stroke="#ccc"/>')
        out.append(f'<text x="{left - 6}" y="{y + 4:.1f}" text-anchor="end">{_fmt(e)}</text>')
        if e < y1:
            for k in range(2, 10):
                yy = py(k * 10.0 ** e)
                out.append(f'<line x1="{left}" y1="{yy:.1f}" x2="{left + pw}" y2="{yy:.1f}" '
                           f'stroke="#eee"/>')
    out.append(f'<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" '
               f'stroke="black"/>')
    out.append(f'<text x="{left + pw / 2}" y="{top + ph + 40}" text-anchor="middle">'
               f'{escape(xlabel)}</text>')
    out.append(f'<text x="20" y="{top + ph / 2}" text-anchor="middle" '
               f'transform="rotate(-90 20 {top + ph / 2})">{escape(ylabel)}</text>')
    for name, pts in guides:
        d = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in pts)
        out.append(f'<polyline points="{d}" fill="none" stroke="#888" stroke-dasharray="6 4"/>')
        lx, ly = pts[-1]
        out.append(f'<text x="{px(lx) - 4:.1f}" y="{py(ly) - 6:.1f}" text-anchor="end" '
                   f'fill="#666">{escape(name)}</text>')
    legend_y = top + 10
    for i, s in enumerate(series):
        colour = s.get("colour", COLOURS[i % len(COLOURS)])
        pts = [p for p in s["points"] if p[0] is not None and p[1] is not None]
        dash = ' stroke-dasharray="5 3"' if s.get("dash") else ""
        if len(pts) > 1:
            d = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y, *_ in pts)
            out.append(f'<polyline points="{d}" fill="none" stroke="{colour}" '
                       f'stroke-width="2"{dash}/>')
        for x, y, *rest in pts:
            hollow = x <= 0 or y <= 0 or x < 10.0 ** x0 or y < 10.0 ** y0 or \
                (len(rest) > 1 and rest[1])
            fill = "white" if hollow else colour
            out.append(f'<circle cx="{px(x):.1f}" cy="{py(y):.1f}" r="4" fill="{fill}" '
                       f'stroke="{colour}" stroke-width="1.5"/>')
            label = rest[0] if rest else None
            if label:
                out.append(f'<text x="{px(x) + 6:.1f}" y="{py(y) - 6:.1f}" font-size="10" '
                           f'fill="{colour}">{escape(label)}</text>')
        lx = left + pw + 15
        out.append(f'<line x1="{lx}" y1="{legend_y}" x2="{lx + 25}" y2="{legend_y}" '
                   f'stroke="{colour}" stroke-width="2"{dash}/>')
        out.append(f'<circle cx="{lx + 12.5}" cy="{legend_y}" r="4" fill="{colour}"/>')
        out.append(f'<text x="{lx + 32}" y="{legend_y + 4}">{escape(s["name"])}</text>')
        legend_y += 20
    for k, line in enumerate(caption):
        out.append(f'<text x="{left}" y="{top + ph + 62 + 14 * k}" font-size="10" '
                   f'fill="#444">{escape(line)}</text>')
    out.append("</svg>")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")
