"""Pictures for docs/benchmarks.md (matplotlib, Agg backend)."""
import json
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.patches import Circle, Polygon, Rectangle  # noqa: E402

from . import stats  # noqa: E402

METHOD_COLORS = {"kc_svsdf": "tab:blue", "svsdf_per_link": "tab:orange", "spheres": "tab:green"}


def success_vs_hb(records, path):
    runs = [r for r in records if r["table"] == "table1"]
    if not runs:
        return False
    fig, ax = plt.subplots(figsize=(5.5, 3.6))
    for method in sorted({r["method"] for r in runs}):
        pts = {}
        for r in runs:
            if r["method"] == method:
                pts.setdefault(float(r["sets"]["h_b"]), []).append(r["success"])
        xs = sorted(pts, reverse=True)
        ax.plot(xs, [100.0 * sum(pts[x]) / len(pts[x]) for x in xs], "o-", label=method,
                color=METHOD_COLORS.get(method))
    ax.plot([1.1, 1.0, 0.9, 0.8], [100, 100, 95, 80], "k--", lw=0.8, label="paper: KC-SVSDF")
    ax.plot([1.1, 1.0, 0.9, 0.8], [80, 35, 20, 0], "k:", lw=0.8, label="paper: per-link SVSDF")
    ax.set_xlabel("bridge clearance h_b (m)")
    ax.set_ylabel("validated success (%)")
    ax.set_ylim(-5, 105)
    ax.invert_xaxis()
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def stage_times(records, table, path):
    runs = [r for r in records if r["table"] == table]
    if not runs:
        return False
    groups = sorted({(r["group"], r["method"]) for r in runs})
    stages = [("front-end", "frontend_ms"), ("mid-end", "midend_ms"), ("back-end", "backend_ms"),
              ("total", "total_ms")]
    fig, axes = plt.subplots(1, len(stages), figsize=(3.2 * len(stages), 3.6), sharey=False)
    for ax, (title, key) in zip(axes, stages):
        data, labels = [], []
        for g, m in groups:
            v = stats.values([r for r in runs if r["group"] == g and r["method"] == m], lambda r: r["plan"][key])
            data.append(v if v else [float("nan")])
            labels.append("%s\n%s" % (g, m))
        ax.boxplot(data, labels=labels, showfliers=True, flierprops={"markersize": 2})
        ax.set_title(title, fontsize=9)
        ax.set_yscale("log")
        ax.tick_params(axis="x", labelsize=6, rotation=60)
        ax.grid(alpha=0.3, axis="y")
    axes[0].set_ylabel("wall time per run (ms, log)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def _draw_obstacles(ax, trace, view):
    for o in trace["obstacles"]:
        T = o["T_W_shape"]
        c = (T[0][3], T[1][3], T[2][3])
        if o["kind"] == "box":
            sx, sy, sz = o["size"]
            ext_z = 0.5 * (abs(T[2][0]) * sx + abs(T[2][1]) * sy + abs(T[2][2]) * sz)
            overhead = c[2] - ext_z > 0.05  # a deck or beam: drawn light from above
            if view == "top":
                corners = []
                for dx, dy in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                    px, py = 0.5 * sx * dx, 0.5 * sy * dy
                    corners.append((c[0] + T[0][0] * px + T[0][1] * py, c[1] + T[1][0] * px + T[1][1] * py))
                ax.add_patch(Polygon(corners, closed=True, facecolor="0.85" if overhead else "0.55",
                                     edgecolor="0.4", lw=0.5, ls="--" if overhead else "-"))
            else:
                ext_x = 0.5 * (abs(T[0][0]) * sx + abs(T[0][1]) * sy + abs(T[0][2]) * sz)
                if 2 * ext_x > 0.5 * (trace["bounds"]["max"][0] - trace["bounds"]["min"][0]):
                    continue  # a side wall along the whole scene would hide the rest
                ax.add_patch(Rectangle((c[0] - ext_x, c[2] - ext_z), 2 * ext_x, 2 * ext_z, color="0.55", alpha=0.35))
        elif o["kind"] in ("cylinder", "sphere"):
            r = o["radius"]
            if view == "top":
                ax.add_patch(Circle((c[0], c[1]), r, color="0.55"))
            else:
                h = 0.5 * o.get("length", 2 * r)
                ax.add_patch(Rectangle((c[0] - r, c[2] - h), 2 * r, 2 * h, color="0.55", alpha=0.35))
        else:
            lo, hi = o["bounds_min"], o["bounds_max"]
            i, j = (0, 1) if view == "top" else (0, 2)
            ax.add_patch(Rectangle((c[i] + lo[i], c[j] + lo[j]), hi[i] - lo[i], hi[j] - lo[j], color="0.55"))


def scene_picture(trace_path, title, path):
    with open(trace_path) as f:
        trace = json.load(f)
    b = trace["bounds"]
    fig, (top, side) = plt.subplots(2, 1, figsize=(10, 6.2),
                                    gridspec_kw={"height_ratios": [b["max"][1] - b["min"][1], 2.5]})
    for ax, view in ((top, "top"), (side, "side")):
        _draw_obstacles(ax, trace, view)
        j = 1 if view == "top" else 2
        polys = [[(p[0], p[j]) for p in tri] for pose in trace["payload"] for tri in pose["triangles"]]
        ax.add_collection(PolyCollection(polys, facecolors="tab:red", edgecolors="none", alpha=0.03))
        if view == "top":
            ax.plot([p[1] for p in trace["base"]], [p[2] for p in trace["base"]], "b-", lw=1, label="base path")
        ax.set_xlim(b["min"][0], b["max"][0])
        ax.set_ylim(b["min"][j], b["max"][j])
        ax.set_aspect("equal")
        ax.set_ylabel("y (m)" if view == "top" else "z (m)")
    top.set_title(title + "  (grey: obstacles, light: overhead decks; red: payload swept volume; top and side views)", fontsize=9)
    side.set_xlabel("x (m)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True
