"""The real-time benchmark (scripts/bench --realtime): tunnel and forest at porter-plan's default
budgets, the bridge at the paper's budgets, every run validated at mesh level with the goal
tolerances and the clearance margin a user would ask for, and a plain-text summary per scene.

Success here is stricter than the paper tables': porter-plan exit 0, porter-validate valid with
the start and goal poses within POSE_TOLERANCE_M / POSE_TOLERANCE_RAD, and the least exact
clearance to every obstacle (the ground included) at least the margin.
"""
from . import stats

# The goal a robot that sets its payload down must reach, and the start it must leave from.
POSE_TOLERANCE_M = 0.01
POSE_TOLERANCE_RAD = 0.02
DEFAULT_MARGIN_M = 0.02
# The targets, printed beside the figures (success %, median ms).
TARGETS = {"tunnel": (97.0, 300.0), "forest": (95.0, 800.0)}


def definitions(seeds, bridge_seeds):
    """The runs: 'realtime' (tunnel, forest at porter-plan's defaults) and 'realtime_bridge'
    (Table I's groups and budgets, ours only)."""
    return {
        "realtime": {
            "title": "Real time: tunnel (T payload) and forest (long bar) at porter-plan's default budgets",
            "stages": "full", "budgets": {"frontend": None, "midend": None, "backend": None},
            "seeds": seeds,
            "groups": [{"scene": "tunnel", "sets": {}, "label": "tunnel"},
                       {"scene": "forest", "sets": {}, "label": "forest"}],
            "methods": ["kc_svsdf"],
        },
        "realtime_bridge": {
            "title": "Bridge at the paper's budgets (Table I, ours)",
            "stages": "full", "budgets": {"frontend": 80, "midend": 100, "backend": 300},
            "seeds": bridge_seeds,
            "groups": [{"scene": "bridge", "sets": {"h_b": v}, "label": "bridge h_b=%s" % v}
                       for v in ["1.1", "1.0", "0.9", "0.8"]],
            "methods": ["kc_svsdf"],
        },
    }


def validate_flags():
    return ["--pose-tolerance-m", str(POSE_TOLERANCE_M), "--pose-tolerance-rad", str(POSE_TOLERANCE_RAD)]


def apply_margin(rec, margin_m):
    """Adds the clearance verdict to a finished record (success requires clearance >= margin)."""
    v = rec["validation"]
    c = v["min_clearance_m"] if v else None
    rec["margin_m"] = margin_m
    rec["clearance_ok"] = c is not None and c >= margin_m
    if rec["success"] and not rec["clearance_ok"]:
        rec["success"] = False
    return rec


def cause(r):
    """Why a run failed, with the detail a reader needs (None on success)."""
    if r["success"]:
        return None
    base = stats.failure_cause(r)
    v = r["validation"]
    if base in ("collision", "self-collision") and v:
        what = v["collision"] or v["self_collision"]
        body = what.get("body") or what.get("body_a") or "?"
        other = what.get("obstacle") or what.get("body_b") or "?"
        return "%s (%s / %s)" % (base, body, other)
    if base == "goal/start" and v:
        return "goal/start (%s)" % "; ".join(f for f in v["failures"] if f.startswith(("goal", "start")))
    if base == "other" and not r.get("clearance_ok", True):
        return "clearance %.1f mm < margin" % (1000.0 * v["min_clearance_m"])
    if base == "planner rejected":
        return "planner rejected (%s)" % (r["plan"]["status"] or "?")
    return base


def _q(v, p):
    if not v:
        return None
    v = sorted(v)
    return v[min(len(v) - 1, int(round(p * (len(v) - 1))))]


def summary(records):
    """The per-scene text the issue asks for."""
    out = []
    groups = []
    for r in records:
        if r["group"] not in groups:
            groups.append(r["group"])
    for g in groups:
        rs = [r for r in records if r["group"] == g]
        ok = sum(r["success"] for r in rs)
        direct = sum(r["plan"]["direct"] for r in rs)
        be = sum(r["plan"]["backend_ran"] for r in rs)
        line = "%s: success %d/%d (%.0f %%), direct execution %d/%d, back-end ran %d" % (
            g, ok, len(rs), stats.pct(ok, len(rs)), direct, len(rs), be)
        if g in TARGETS:
            line += "   [target >= %.0f %%, median total <= %.0f ms]" % TARGETS[g]
        out.append(line)
        out.append("  %-10s %8s %8s %8s %8s %8s" % ("stage ms", "median", "p90", "p95", "max", "runs"))
        for key, label in (("frontend_ms", "front"), ("midend_ms", "mid"), ("backend_ms", "back"),
                           ("total_ms", "total")):
            v = stats.values(rs, lambda r: r["plan"][key])
            out.append("  %-10s %8s %8s %8s %8s %8d" % (label, stats.fmt(_q(v, 0.5), "%.0f"), stats.fmt(_q(v, 0.9), "%.0f"),
                                                      stats.fmt(_q(v, 0.95), "%.0f"), stats.fmt(max(v) if v else None, "%.0f"),
                                                      len(v)))
        cl = stats.values(rs, lambda r: r["validation"]["min_clearance_m"] if r["validation"] else None)
        cl_ok = stats.values(rs, lambda r: r["validation"]["min_clearance_m"] if r["success"] else None)
        out.append("  min exact clearance: %s mm over every trajectory, %s mm over the successes (margin %.0f mm)" % (
            stats.fmt(min(cl) * 1000.0 if cl else None), stats.fmt(min(cl_ok) * 1000.0 if cl_ok else None),
            1000.0 * rs[0].get("margin_m", DEFAULT_MARGIN_M)))
        fails = [(r["seed"], cause(r)) for r in rs if not r["success"]]
        if fails:
            out.append("  failures: " + "; ".join("s%d %s" % f for f in fails))
    return out
