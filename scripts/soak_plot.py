#!/usr/bin/env python3
"""Plots scripts/soak.sh's CSV (panels: RSS, fds, threads, GL objects alive, fps, latency) as a
PNG with matplotlib (OUT.png) or as an SVG with the standard library only (OUT.svg), and prints
the growth after the warm-up (the first fifth of the run): RSS as the median of the last fifth
against the median of the second fifth, fds, threads and each kind of GL object as the count
at the end against the count at the end of the warm-up.
Exit status 1 when fds, threads or GL objects grew.   soak_plot.py SOAK.csv OUT.png|OUT.svg"""
import csv
import statistics
import sys


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))

    def column(name):
        out = []
        for r in rows:
            try:
                out.append(float(r[name]))
            except (KeyError, TypeError, ValueError):
                out.append(None)
        return out

    return {name: column(name) for name in rows[0].keys()} if rows else {}


def panel(x0, y0, w, h, title, t, series, unit):
    """One plot: series is [(name, values, colour)]."""
    points = [(ti, v) for _, vs, _ in series for ti, v in zip(t, vs) if v is not None]
    if not points:
        return f'<text x="{x0}" y="{y0 + 15}">{title}: no data</text>'
    lo = min(v for _, v in points)
    hi = max(v for _, v in points)
    if hi - lo < 1e-9:
        lo, hi = lo - 1, hi + 1
    pad = (hi - lo) * 0.1
    lo, hi = lo - pad, hi + pad
    tmax = max(t) or 1.0
    sx = lambda ti: x0 + 60 + (w - 80) * ti / tmax
    sy = lambda v: y0 + 25 + (h - 50) * (1 - (v - lo) / (hi - lo))
    svg = [f'<text x="{x0 + 60}" y="{y0 + 15}" font-size="13">{title}</text>',
           f'<rect x="{x0 + 60}" y="{y0 + 25}" width="{w - 80}" height="{h - 50}" fill="none" stroke="#999"/>']
    for frac in (0, 0.5, 1):
        v = lo + (hi - lo) * frac
        svg.append(f'<text x="{x0 + 55}" y="{sy(v) + 4:.1f}" font-size="10" text-anchor="end">{v:.4g}</text>')
    svg.append(f'<text x="{x0 + w - 20}" y="{y0 + h - 10}" font-size="10" text-anchor="end">{tmax:.0f} s</text>')
    svg.append(f'<text x="{x0 + 5}" y="{y0 + h / 2}" font-size="10">{unit}</text>')
    for i, (name, vs, colour) in enumerate(series):
        pts = " ".join(f"{sx(ti):.1f},{sy(v):.1f}" for ti, v in zip(t, vs) if v is not None)
        svg.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="1.5"/>')
        svg.append(f'<text x="{x0 + 70 + 90 * i}" y="{y0 + h - 10}" font-size="10" fill="{colour}">{name}</text>')
    return "\n".join(svg)


def growth(t, values):
    """(value at the end of the warm-up, value at the end) and the steady part's samples."""
    pairs = [(ti, v) for ti, v in zip(t, values) if v is not None]
    n = len(pairs)
    if n < 5:
        return None
    fifth = max(1, n // 5)
    second = [v for _, v in pairs[fifth:2 * fifth]]
    last = [v for _, v in pairs[-fifth:]]
    return statistics.median(second), statistics.median(last), max(v for _, v in pairs[fifth:]), pairs[fifth][1]


GL_COLOURS = ["#c33", "#36c", "#393", "#963", "#639", "#c6c", "#099", "#666"]


def gl_series(data):
    """[(kind, values, colour)] for the gl_* columns that have samples."""
    kinds = [name for name in data if name.startswith("gl_") and any(v is not None for v in data[name])]
    return [(k[3:], data[k], GL_COLOURS[i % len(GL_COLOURS)]) for i, k in enumerate(kinds)]


def write_png(path, t, panels):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 2.2 * len(panels)), sharex=True)
    for ax, (title, series, unit) in zip(axes, panels):
        for name, values, colour in series:
            pts = [(ti, v) for ti, v in zip(t, values) if v is not None]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], color=colour, label=name, linewidth=1.3)
        ax.set_title(title, fontsize=10, loc="left")
        ax.set_ylabel(unit, fontsize=9)
        ax.grid(alpha=0.3)
        if len(series) > 1:
            ax.legend(fontsize=7, ncol=4, loc="upper right")
    axes[-1].set_xlabel("seconds")
    fig.tight_layout()
    fig.savefig(path, dpi=80)


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    data = load(sys.argv[1])
    if not data:
        print("soak_plot.py: no samples", file=sys.stderr)
        return 1
    t = [v or 0.0 for v in data["t_s"]]
    rss_mb = [v / 1024 if v is not None else None for v in data["rss_kb"]]
    w, h = 900, 180
    panels = [
        ("resident memory", [("RSS", rss_mb, "#c33")], "MB"),
        ("open file descriptors", [("fds", data["fds"], "#36c")], "count"),
        ("threads", [("threads", data["threads"], "#393")], "count"),
        ("GL objects alive (status.json gl_objects)", gl_series(data), "count"),
        ("frame rate (status.json)", [("fps", data["fps"], "#963")], "fps"),
        ("capture-to-present latency", [("p50", data["latency_p50_ms"], "#639"),
                                        ("p99", data["latency_p99_ms"], "#c6c")], "ms"),
    ]
    if sys.argv[2].endswith(".png"):
        write_png(sys.argv[2], t, panels)
    else:
        body = [panel(0, i * h, w, h, title, t, series, unit) for i, (title, series, unit) in enumerate(panels)]
        with open(sys.argv[2], "w") as f:
            f.write(f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h * len(panels)}" '
                    f'font-family="sans-serif"><rect width="100%" height="100%" fill="white"/>\n')
            f.write("\n".join(body))
            f.write("\n</svg>\n")

    grew = False
    rss = growth(t, rss_mb)
    if rss:
        print(f"RSS after warm-up: median {rss[0]:.1f} MB (2nd fifth) -> {rss[1]:.1f} MB (last fifth), "
              f"{rss[1] - rss[0]:+.1f} MB")
    for name in ["fds", "threads"] + [k for k in data if k.startswith("gl_")]:
        g = growth(t, data[name])
        if g:
            print(f"{name}: {g[3]:.0f} at the end of the warm-up, at most {g[2]:.0f} after, {g[1]:.0f} at the end")
            grew |= g[1] > g[3]
    fps = [v for v in data["fps"] if v is not None]
    if fps:
        print(f"fps: median {statistics.median(fps):.2f}, min {min(fps):.2f}")
    return 1 if grew else 0


if __name__ == "__main__":
    sys.exit(main())
