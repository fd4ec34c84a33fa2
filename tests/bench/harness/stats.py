"""Small statistics over run records."""
import statistics


def values(runs, get):
    out = []
    for r in runs:
        v = get(r)
        if v is not None:
            out.append(v)
    return out


def mean(v):
    return statistics.fmean(v) if v else None


def median(v):
    return statistics.median(v) if v else None


def pct(n, d):
    return 100.0 * n / d if d else None


def fmt(v, spec="%.1f", none="-"):
    return none if v is None else spec % v


def failure_cause(r):
    """One word for why a run did not succeed (None when it did)."""
    if r["success"]:
        return None
    p, v = r["plan"], r["validation"]
    if p["exit"] not in (0, 1):
        return "plan error %d" % p["exit"]
    if p["frontend_status"] != "success":
        return "front-end %s" % (p["frontend_status"] or "none")
    if not p["has_trajectory"]:
        return "no trajectory"
    if v is None or v["exit"] not in (0, 1):
        return "not validated"
    if v["collision"]:
        return "collision"
    if v["self_collision"]:
        return "self-collision"
    if any(f.startswith(("joint", "wheel")) for f in v["failures"]):
        return "limits"
    if v["goal_ok"] is False or v["start_ok"] is False:
        return "goal/start"
    if not r["within_budget"]:
        return "over budget"
    if p["exit"] != 0:
        return "planner rejected"
    return "other"
