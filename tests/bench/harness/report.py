"""docs/benchmarks.md from results.json."""
from collections import Counter

from . import stats, tables
from .stats import fmt

PAPER_TABLE1 = {"kc_svsdf": {"1.1": 100, "1.0": 100, "0.9": 95, "0.8": 80},
                "svsdf_per_link": {"1.1": 80, "1.0": 35, "0.9": 20, "0.8": 0}}
PAPER_TABLE3 = {"tunnel": "2305 / 604 / 1253 ms, total 4162 ms, 91 %",
                "forest": "9024 / 1022 / 3567 ms, total 13613 ms, 83 %"}


def _runs(records, table):
    return [r for r in records if r["table"] == table]


def _groups(runs):
    seen = []
    for r in runs:
        if r["group"] not in seen:
            seen.append(r["group"])
    return seen


def _methods(runs):
    present = {r["method"] for r in runs}
    return [m for m in tables.METHOD_FLAGS if m in present]


def _causes(runs):
    c = Counter(stats.failure_cause(r) for r in runs if not r["success"])
    return ", ".join("%s %d" % (k, n) for k, n in c.most_common()) or "-"


def table1(records):
    runs = _runs(records, "table1")
    if not runs:
        return []
    b = runs[0]["budgets"]
    out = ["## Table I: ablation (bridge, T payload)", "",
           "`porter-plan --stages full` on `bridge` with `--set h_b=...`, seeds 1..%d, budgets front-end %s ms, "
           "mid-end %s ms, back-end %s ms. Success = porter-plan returned its answer (exit 0), porter-validate "
           "found it collision-free with limits kept and goal reached, and every stage kept its budget "
           "(+%d %%)." % (max(r["seed"] for r in runs), b["frontend"], b["midend"], b["backend"],
                          int(100 * 0.10)), "",
           "| h_b (m) | method | success | paper | front-end ok | direct | back-end ran | median fe / mid / be ms | failures |",
           "|---|---|---|---|---|---|---|---|---|"]
    for g in _groups(runs):
        for m in _methods(runs):
            rs = [r for r in runs if r["group"] == g and r["method"] == m]
            if not rs:
                continue
            hb = rs[0]["sets"]["h_b"]
            ok = sum(r["success"] for r in rs)
            paper = PAPER_TABLE1.get(m, {}).get(hb)
            med = lambda k: stats.median(stats.values(rs, lambda r: r["plan"][k]))
            out.append("| %s | %s | %.0f %% (%d/%d) | %s | %d | %d | %d | %s / %s / %s | %s |" % (
                hb, m, stats.pct(ok, len(rs)), ok, len(rs), "-" if paper is None else "%d %%" % paper,
                sum(r["plan"]["frontend_status"] == "success" for r in rs), sum(r["plan"]["direct"] for r in rs),
                sum(r["plan"]["backend_ran"] for r in rs), fmt(med("frontend_ms")), fmt(med("midend_ms")),
                fmt(med("backend_ms")), _causes(rs)))
    out += ["", "![success vs h_b](img/table1_success.png)", ""]
    return out


def table3(records):
    runs = _runs(records, "table3")
    if not runs:
        return []
    b = runs[0]["budgets"]
    out = ["## Table III: comparison (tunnel with the T payload, forest with the long bar)", "",
           "`porter-plan --stages full`, seeds 1..%d, budgets front-end %s ms, mid-end %s ms, back-end %s ms; "
           "per-stage wall times from the result files (mean / median over the runs where the stage ran; the "
           "back-end runs only when the mid-end trajectory is not collision-free), total = their sum per run. "
           "Success as in Table I." % (max(r["seed"] for r in runs), b["frontend"], b["midend"], b["backend"]), "",
           "| scene | method | front-end ms | mid-end ms | back-end ms (runs) | total ms | success | paper (ours) | failures |",
           "|---|---|---|---|---|---|---|---|---|"]
    for g in _groups(runs):
        for m in _methods(runs):
            rs = [r for r in runs if r["group"] == g and r["method"] == m]
            if not rs:
                continue
            mm = lambda k: "%s / %s" % (fmt(stats.mean(stats.values(rs, lambda r: r["plan"][k])), "%.0f"),
                                        fmt(stats.median(stats.values(rs, lambda r: r["plan"][k])), "%.0f"))
            ok = sum(r["success"] for r in rs)
            out.append("| %s | %s | %s | %s | %s (%d) | %s | %.0f %% (%d/%d) | %s | %s |" % (
                g, m, mm("frontend_ms"), mm("midend_ms"), mm("backend_ms"), sum(r["plan"]["backend_ran"] for r in rs),
                mm("total_ms"), stats.pct(ok, len(rs)), ok, len(rs),
                PAPER_TABLE3.get(g, "-") if m == "kc_svsdf" else "17-29 % (sphere planners)", _causes(rs)))
    out += ["", "![stage times](img/table3_stage_times.png)", ""]
    return out


def table2(records):
    out = ["## Table II: validated clearance at the hardest obstacles", "",
           "Least signed distance (mm; negative = penetration) from any robot or payload shape to the named "
           "obstacles over the whole trajectory, measured by porter-validate (FCL, meshes and primitives). "
           "Median [minimum] over the successful runs of each method; bridge from Table I at h_b = 1.0 m, "
           "tunnel and forest from Table III. A value marked > is a lower bound (never within the "
           "validator's 0.5 m distance horizon).", "",
           "| scene | method | runs | %s |" % " | ".join("obstacle %d" % (i + 1) for i in range(3)),
           "|---|---|---|---|---|---|"]
    sources = [("bridge", "table1", "h_b=1.0"), ("tunnel", "table3", "tunnel"), ("forest", "table3", "forest")]
    any_row = False
    for scene, table, group in sources:
        rs_all = [r for r in records if r["table"] == table and r["group"] == group]
        for m in _methods(rs_all):
            rs = [r for r in rs_all if r["method"] == m and r["success"]]
            cells = []
            for i, (label, _) in enumerate(tables.HARDEST[scene]):
                vals = []
                exact = True
                for r in rs:
                    label_, v, ex = tables.hardest_clearance(scene, r["validation"]["clearance"])[i]
                    if v is not None:
                        vals.append(v * 1000.0)
                        exact = exact and ex
                mark = "" if exact else ">"
                cells.append("%s: %s%s [%s]" % (label, mark, fmt(stats.median(vals)), fmt(min(vals) if vals else None)))
            out.append("| %s | %s | %d | %s |" % (scene, m, len(rs), " | ".join(cells)))
            any_row = True
    return out + [""] if any_row else []


def disagreements(records):
    rows = [r for r in records if r["disagreement"]]
    out = ["## Where the planner's own check and the validator disagree", ""]
    if not rows:
        return out + ["None: on every run with a trajectory, porter-plan's kernel trajectory check and "
                      "porter-validate agreed on whether it is collision-free (self-collision included).", ""]
    judged = sum(1 for r in records if r["validation"] is not None and r["plan"]["collision_free"] is not None)
    counts = Counter(r["disagreement"] for r in rows)
    out += ["porter-plan's final kernel trajectory check (`final_check.collision_free`, on its voxel map) "
            "against porter-validate's environment and self-collision checks (exact geometry), on the %d runs "
            "that both judged: %s." % (judged, "; ".join("%s: %d" % kv for kv in counts.most_common())), "",
            "| run | planner exit | disagreement | validator: closest obstacle (mm) or collision |",
            "|---|---|---|---|"]
    for r in rows:
        v = r["validation"]
        what = "; ".join(f for f in v["failures"] if "collision" in f)
        if not what:
            closest = min((c for c in v["clearance"] if c["obstacle"] != "ground" and c["min_m"] is not None),
                          key=lambda c: c["min_m"], default=None)
            what = "%.1f (%s, %s)" % (closest["min_m"] * 1000.0, closest["obstacle"], closest["body"]) if closest else "-"
        out.append("| %s | %d | %s | %s |" % (r["id"], r["plan"]["exit"], r["disagreement"], what))
    return out + [""]


def stage_tables(records):
    out = []
    for table, title in (("frontend", "Front-end alone"), ("midend", "Front-end and mid-end, validated")):
        runs = _runs(records, table)
        if not runs:
            continue
        out += ["## %s (`porter-plan --stages %s`)" % (title, runs[0]["stages"]), "",
                "| case | front-end budget ms | runs | success | fe median / p90 / max ms | mid-end median ms | failures |",
                "|---|---|---|---|---|---|---|"]
        for g in _groups(runs):
            rs = [r for r in runs if r["group"] == g]
            fe = sorted(stats.values(rs, lambda r: r["plan"]["frontend_ms"]))
            p90 = fe[min(len(fe) - 1, int(0.9 * len(fe)))] if fe else None
            ok = sum(r["success"] for r in rs)
            out.append("| %s | %s | %d | %.0f %% | %s / %s / %s | %s | %s |" % (
                g, rs[0]["budgets"]["frontend"], len(rs), stats.pct(ok, len(rs)), fmt(stats.median(fe)), fmt(p90),
                fmt(fe[-1] if fe else None), fmt(stats.median(stats.values(rs, lambda r: r["plan"]["midend_ms"]))),
                _causes(rs)))
        out.append("")
    return out
