#!/usr/bin/python3
"""Checks a scripts/bench output folder: every run planned, every trajectory validated by
porter-validate, the tables and pictures written. Used by the bench_harness CTest smoke test.

  check_bench_results.py OUT_DIR
"""
import json
import os
import sys


def main():
    out = sys.argv[1]
    with open(os.path.join(out, "results.json")) as f:
        doc = json.load(f)
    runs, problems = doc["runs"], []
    if doc["meta"].get("partial"):
        problems.append("results.json is partial")
    if doc["meta"]["runs"] != len(runs) or not runs:
        problems.append("%d of %d runs recorded" % (len(runs), doc["meta"]["runs"]))
    tables = {r["table"] for r in runs}
    for t in ("table1", "table3"):
        if t not in tables:
            problems.append("no run of %s" % t)
    validated = 0
    for r in runs:
        p, v = r["plan"], r["validation"]
        if p["exit"] not in (0, 1):
            problems.append("%s: porter-plan exit %d: %s" % (r["id"], p["exit"], p["stderr"]))
        if p["has_trajectory"]:
            if v is None or v["exit"] not in (0, 1) or v["samples"] is None:
                problems.append("%s: trajectory not validated" % r["id"])
                continue
            validated += 1
            if v["valid"] != (v["exit"] == 0) or (not v["valid"] and not v["failures"]):
                problems.append("%s: validation verdict inconsistent" % r["id"])
        elif v is not None:
            problems.append("%s: validated without a trajectory" % r["id"])
        if r["success"] and not (v and v["valid"] and p["exit"] == 0):
            problems.append("%s: success without a valid trajectory" % r["id"])
    if validated == 0:
        problems.append("no trajectory was validated")
    md = os.path.join(out, "docs", "benchmarks.md")
    text = open(md).read() if os.path.exists(md) else ""
    for heading in ("## Table I", "## Table II", "## Table III", "## Where the planner's own check"):
        if heading not in text:
            problems.append("benchmarks.md lacks '%s'" % heading)
    for png in ("table1_success.png", "table3_stage_times.png"):
        path = os.path.join(out, "docs", "img", png)
        if not os.path.exists(path) or os.path.getsize(path) < 1000:
            problems.append("missing picture %s" % png)
    for p in problems:
        print("check: " + p)
    print("check: %d runs, %d trajectories validated, %d problems" % (len(runs), validated, len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
