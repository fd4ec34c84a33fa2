#!/usr/bin/python3
"""scripts/replay on a run recorded here: the sim stack drives the empty scene's mission with
lcm-logger recording (tests/integration/sim_stack.py), then scripts/replay --twice --scene plays
the log's inputs through a fresh porter-mapper and porter-planner, twice, and must report: maps
made, the recorded goal reaching the recorded final state, the two replays' maps of the same
newest scan byte-identical, and no replayed trajectory colliding with the scene (exact geometry).

usage: replay_test.py ROOT BUILD [--keep DIR]
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_stack import SimStack  # noqa: E402


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


parser = argparse.ArgumentParser()
parser.add_argument("root")
parser.add_argument("build")
parser.add_argument("--keep")
a = parser.parse_args()

with tempfile.TemporaryDirectory() as tmp:
    run_dir = a.keep or os.path.join(tmp, "run")
    stack = SimStack(a.root, a.build, "empty", "t_bar", run_dir, record=True)
    with stack:
        rc, summary, line = stack.mission(timeout_s=120)
    print(line)
    # The recording needs maps and a goal the planner took up; arrival is the mission's business.
    if summary is None or not summary["plans"]:
        fail(f"the recorded run has no plan (porter-mission exit {rc})")
    log = os.path.join(run_dir, "run.lcmlog")
    if not os.path.exists(log):
        fail("no run.lcmlog recorded")
    out = os.path.join(run_dir, "replay")
    r = subprocess.run([os.path.join(a.root, "scripts", "replay"), log, "--build", a.build, "--out", out, "--twice",
                        "--scene", stack.scene_file], capture_output=True, text=True, timeout=600)
    print(r.stdout.strip())
    if r.returncode != 0:
        fail(f"scripts/replay exit {r.returncode}: {r.stderr.strip()[-2000:]}")
    if "byte-identical" not in r.stdout or "NOT identical" in r.stdout:
        fail("the two replays' maps are not byte-identical")
print("OK")
