#!/usr/bin/python3
"""The simulated stack drives start to goal on a scene with no collision.

Launches the sim profile (porter-sim with the Scout Mini and Piper firmware and the simulated
MID-360, porter-base, porter-arm, porter-lidar, porter-state, porter-mapper, porter-tracker,
porter-planner) through scripts/launch on a private udpm URL, with the LiDAR's UDP on free
loopback ports, sends the scene's goal with porter-mission and requires: arrival within the
mission's distance, no collision of the executed path (every SIM_TRUTH configuration, exact
geometry) nor of any executed trajectory, at least one plan, and a clean stop by PID that leaves
none of the launched processes running.

usage: sim_stack_test.py ROOT BUILD [SCENE] [--keep DIR] [--record] [--timeout-s T]
                         [--sensor-raise-m H] [--safety-only]
  SCENE       a scene of config/scenes (default bridge; its payload)
  --keep DIR  run folder kept there (process logs, mission.json; run.lcmlog with --record)
  --sensor-raise-m H  the simulated MID-360 and porter-mapper's extrinsic H m higher on the mast
  --safety-only       require no collision and a clean stop only (arrival not required)
"""
import argparse
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_stack import SimStack  # noqa: E402


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def scene_payload(root, scene):
    with open(os.path.join(root, "config", "scenes", scene + ".yaml")) as f:
        for line in f:
            if line.startswith("payload:"):
                return os.path.basename(line.split(":", 1)[1].strip()).replace(".yaml", "")
    fail(f"scene {scene} names no payload")


parser = argparse.ArgumentParser()
parser.add_argument("root")
parser.add_argument("build")
parser.add_argument("scene", nargs="?", default="bridge")
parser.add_argument("--keep")
parser.add_argument("--record", action="store_true")
parser.add_argument("--timeout-s", type=float, default=150.0)
parser.add_argument("--sensor-raise-m", type=float, default=0.0)
parser.add_argument("--safety-only", action="store_true")
a = parser.parse_args()

with tempfile.TemporaryDirectory() as tmp:
    run_dir = a.keep or os.path.join(tmp, "run")
    stack = SimStack(a.root, a.build, a.scene, scene_payload(a.root, a.scene), run_dir, record=a.record,
                     sensor_raise_m=a.sensor_raise_m)
    with stack:
        rc, summary, line = stack.mission(timeout_s=a.timeout_s)
    print(line)
    if summary is None:
        fail(f"porter-mission wrote no summary (exit {rc}); see {run_dir}/porter-mission.log")
    if stack.left_running:
        fail(f"processes left running after the stop: {stack.left_running}")
    if stack.launch.returncode != 0:
        fail(f"scripts/launch exit {stack.launch.returncode}")
    if summary["executed_collision"]:
        fail("the executed path collides: " + summary["summary"])
    if summary["collided"]:
        fail("an executed trajectory collides: " + summary["summary"])
    if a.safety_only:
        print("OK")
        sys.exit(0)
    if not summary["plans"]:
        fail("no trajectory was executed")
    if summary["executed_samples"] < 100:
        fail(f"only {summary['executed_samples']} SIM_TRUTH samples of the executed path")
    if summary["executed_collision"]:
        fail("the executed path collides: " + summary["summary"])
    if summary["collided"]:
        fail("an executed trajectory collides: " + summary["summary"])
    if not summary["arrived"]:
        fail("not arrived: " + summary["summary"])
    if rc != 0:
        fail(f"porter-mission exit {rc}")
print("OK")
