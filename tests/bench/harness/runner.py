"""Runs porter-plan and porter-validate for one benchmark run and condenses both JSON files
into one record (the rows of results.json)."""
import json
import os
import subprocess

from . import tables

# Stage times over their budget by more than this fraction count as over budget (a budget stop
# takes effect after the evaluation that crosses it).
BUDGET_SLACK = 0.10


def run_id(run):
    sets = "_".join("%s%s" % (k, v) for k, v in sorted(run["sets"].items()))
    return "%s_%s%s_%s_s%d" % (run["table"], run["scene"], ("_" + sets) if sets else "", run["method"], run["seed"])


def plan_command(exe, root, run, out_path):
    cmd = [exe, "--scene", os.path.join(root, "config", "scenes", run["scene"] + ".yaml"),
           "--seed", str(run["seed"]), "--stages", run["stages"], "--out", out_path, "--quiet",
           "--robot", os.path.join(root, "config", "robots", "scout_mini_piper", "robot.yaml")]
    for k, v in sorted(run["sets"].items()):
        cmd += ["--set", "%s=%s" % (k, v)]
    # A budget of None leaves porter-plan's default (config/planner/pipeline.yaml).
    for stage, value in sorted(run["budgets"].items()):
        if value is not None:
            cmd += ["--%s-budget-ms" % stage, str(value)]
    return cmd + tables.METHOD_FLAGS[run["method"]] + list(run.get("plan_args", []))


def validate_command(exe, root, run, plan_path, report_path, trace_path=None):
    cmd = [exe, "--scene", os.path.join(root, "config", "scenes", run["scene"] + ".yaml"),
           "--seed", str(run["seed"]), "--quiet", "--json", report_path, plan_path]
    for k, v in sorted(run["sets"].items()):
        cmd += ["--set", "%s=%s" % (k, v)]
    if trace_path:
        cmd += ["--trace", trace_path]
    return cmd + list(run.get("validate_flags", []))


def _load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def plan(exes, root, run, run_dir):
    """Runs porter-plan; returns the plan part of the record."""
    path = os.path.join(run_dir, run_id(run) + ".plan.json")
    proc = subprocess.run(plan_command(exes["plan"], root, run, path), capture_output=True, text=True)
    doc = _load(path)
    rec = {"exit": proc.returncode, "file": os.path.basename(path), "stderr": proc.stderr.strip()[-400:],
           "has_trajectory": bool(doc and doc.get("trajectory")), "status": None,
           "frontend_status": None, "frontend_ms": None, "midend_ms": None, "midend_optimize_ms": None,
           "backend_ran": False, "backend_ms": None, "backend_optimize_ms": None, "direct": False,
           "collision_free": None, "total_ms": None}
    if not doc:
        return rec
    rec["status"] = doc.get("status")
    fe, mid, be = doc.get("frontend"), doc.get("midend"), doc.get("backend")
    total = 0.0
    if fe:
        rec["frontend_status"], rec["frontend_ms"] = fe["status"], fe["time_ms"]
        total += fe["time_ms"]
    if mid:
        rec["midend_ms"], rec["midend_optimize_ms"] = mid["time_ms"], mid["optimize_ms"]
        rec["direct"] = bool(mid.get("direct_execution"))
        total += mid["time_ms"]
    if be:
        rec["backend_ran"] = True
        rec["backend_ms"], rec["backend_optimize_ms"] = be["time_ms"], be["optimize_ms"]
        total += be["time_ms"]
    rec["total_ms"] = total if fe else None
    fc = doc.get("final_check")
    if fc is not None:
        rec["collision_free"] = bool(fc.get("collision_free"))
    return rec


def within_budget(run, p):
    b = run["budgets"]
    limit = lambda ms: ms * (1.0 + BUDGET_SLACK)
    if p["frontend_status"] != "success" or p["frontend_ms"] is None:
        return False
    if b["frontend"] is not None and p["frontend_ms"] > limit(b["frontend"]):
        return False
    if b["midend"] is not None and p["midend_optimize_ms"] is not None and p["midend_optimize_ms"] > limit(b["midend"]):
        return False
    if b["backend"] is not None and p["backend_optimize_ms"] is not None and \
            p["backend_optimize_ms"] > limit(b["backend"]):
        return False
    return True


def validate(exes, root, run, p, run_dir):
    """Runs porter-validate on a plan with a trajectory; returns the validation part."""
    path = os.path.join(run_dir, run_id(run) + ".validate.json")
    proc = subprocess.run(validate_command(exes["validate"], root, run, os.path.join(run_dir, p["file"]), path),
                          capture_output=True, text=True)
    doc = _load(path)
    rec = {"exit": proc.returncode, "file": os.path.basename(path), "stderr": proc.stderr.strip()[-400:],
           "valid": False,
           "failures": [], "collision": None, "self_collision": None, "min_clearance_m": None,
           "clearance": [], "limits": {}, "goal_ok": None, "start_ok": None, "samples": None,
           "time_ms": None}
    if not doc:
        return rec
    rec["valid"] = bool(doc.get("valid"))
    rec["failures"] = doc.get("failures", [])
    if "collision" in doc:
        c, s = doc["collision"], doc["self_collision"]
        rec["collision"] = c if c["found"] else None
        rec["self_collision"] = s if s["found"] else None
        rec["min_clearance_m"] = doc["min_clearance_m"]
        rec["clearance"] = doc["clearance"]
        rec["limits"] = {l["quantity"]: l["worst_ratio"] for l in doc["limits"]}
        rec["goal_ok"], rec["start_ok"] = doc["goal"]["ok"], doc["start"]["ok"]
        rec["samples"], rec["time_ms"] = doc["samples"], doc["time_ms"]
    return rec


def finish(run, p, v):
    """The record of a run: plan, validation and the verdicts derived from them."""
    validated = v is not None and v["valid"]
    budget = within_budget(run, p)
    rec = dict(run)
    rec["id"] = run_id(run)
    rec["plan"], rec["validation"] = p, v
    rec["within_budget"] = budget
    if run["stages"] == "front":
        rec["success"] = p["frontend_status"] == "success" and budget
    else:
        rec["success"] = p["exit"] == 0 and validated and budget
    # The planner's kernel check against the validator, where both judged a trajectory.
    planner_ok = p["collision_free"]
    rec["disagreement"] = None
    if v is not None and v["exit"] in (0, 1) and planner_ok is not None:
        geometric_ok = v["collision"] is None and v["self_collision"] is None
        if planner_ok != geometric_ok:
            rec["disagreement"] = ("planner: collision-free, validator: in collision"
                                   if planner_ok else "planner: in collision, validator: collision-free")
    return rec
