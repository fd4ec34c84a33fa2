#!/usr/bin/python3
"""A picture of a run: the scene's obstacles (footprints), the planned trajectories, the executed
path (SIM_TRUTH) with robot heading snapshots, start and goal.

usage: scripts/plot_run.py MISSION_JSON SCENE_YAML OUT_PNG   (MISSION_JSON from porter-mission)
"""
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import yaml  # noqa: E402


def main():
    if len(sys.argv) != 4:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    mission = json.load(open(sys.argv[1]))
    scene = yaml.safe_load(open(sys.argv[2]))
    fig, ax = plt.subplots(figsize=(12, 5))
    lo, hi = scene["bounds"]["min"], scene["bounds"]["max"]
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    for o in scene.get("obstacles") or []:
        if o.get("type") == "box" and "center" in o and "size" in o:
            c, s = o["center"], o["size"]
            ax.add_patch(plt.Rectangle((c[0] - s[0] / 2, c[1] - s[1] / 2), s[0], s[1], color="0.6"))
    for i, p in enumerate(mission["plans"]):
        xy = p["xy"]
        ax.plot([q[0] for q in xy], [q[1] for q in xy], "--", lw=1,
                label=f"plan {p['plan_id']} (clearance {p['min_clearance_m']:.2f} m)")
    path = mission["truth_xy_yaw"]
    ax.plot([q[0] for q in path], [q[1] for q in path], "k-", lw=2, label="executed (SIM_TRUTH)")
    for q in path[:: max(1, len(path) // 15)]:
        ax.arrow(q[0], q[1], 0.3 * math.cos(q[2]), 0.3 * math.sin(q[2]), head_width=0.08, color="tab:red")
    ax.plot(*mission["start"], "go", label="start")
    ax.plot(*mission["goal"], "r*", ms=12, label="goal")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(mission["summary"][:120], fontsize=8)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(sys.argv[3], dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
