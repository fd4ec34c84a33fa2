#!/usr/bin/python3
"""The whole simulated stack under faults and world changes, on the empty scene (start (0, 0),
goal (8, 0), T bar), each case on its own private LCM URL and LiDAR ports, every process started
and stopped by PID (tests/integration/sim_stack.py):

  obstacle      a box appears on the path while the robot drives (SIM_COMMAND ADD_BOX, sent by
                porter-mission 1 s after the first trajectory starts): the simulated LiDAR sees
                it, it enters porter-mapper's map, porter-planner re-plans (or brakes, then plans
                from rest) and the robot arrives without touching it (exact geometry, every
                SIM_TRUTH configuration and every executed trajectory part). Prints the time from
                the map that showed the box to the new trajectory. The MID-360 is mounted 0.35 m
                higher than shipped here (the arm blocks the shipped sensor's forward view).
  kill_tracker  porter-tracker is killed (SIGKILL, not restarted) while the base drives:
                porter-base finds BASE_CMD stale and sends zero velocity (its log says so), the
                base comes to rest, and it does so before the firmware's own 500 ms command
                timeout would have acted.
  kill_planner  porter-planner is killed (SIGKILL, not restarted) while the base drives: the
                tracker carries on with the trajectory it has (it was checked when planned) and
                the robot either finishes it (FINISHED at its end) or stops on it (the tracker's
                own watchdogs: a fault on a tracking error, a stale state); it never leaves the
                trajectory's path, gets no new trajectory and rests after the trajectory's end.
  estop         ESTOP (active) while the base drives: the tracker commands disabled within one
                period (at most one enabled BASE_CMD after it arrives), the base comes to rest,
                the arm stays still, and the release alone does not restart motion.

Times of events the test causes (kill, e-stop) are compared with the receive time of SIM_TRUTH
("rx", wall clock): porter-sim's own stamps fall behind the wall clock when it runs slower than
real time on a loaded machine.

usage: stack_faults_test.py ROOT BUILD CASE [--keep DIR [--record]]
"""
import argparse
import json
import math
import os
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_stack import SimStack  # noqa: E402

TRACKER_ESTOP, TRACKER_FINISHED = 5, 2  # tracker_status_t.STATE_*
PLANNER_REPLANNING = 4                   # planner_status_t.STATE_REPLANNING


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def read_watch(path):
    out = {}
    with open(path) as f:
        for line in f:
            try:
                m = json.loads(line)
            except ValueError:
                continue  # the last line may be cut by the stop
            out.setdefault(m["ch"], []).append(m)
    return out


def wait_for(predicate, timeout_s, what):
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        r = predicate()
        if r:
            return r
        time.sleep(0.05)
    fail(f"{what} within {timeout_s} s")


def speed(s):
    return abs(s["v"])


class Case:
    def __init__(self, a, no_restart=(), sensor_raise_m=0.0):
        self.a = a
        self.tmp = tempfile.TemporaryDirectory()
        self.run_dir = a.keep or os.path.join(self.tmp.name, "run")
        self.stack = SimStack(a.root, a.build, "empty", "t_bar", self.run_dir, no_restart=no_restart,
                              sensor_raise_m=sensor_raise_m, record=a.record)
        self.watch_path = os.path.join(self.run_dir, "watch.jsonl")

    def __enter__(self):
        self.stack.__enter__()
        self.stack.start("porter-stack-probe", [self.stack.bin("tests", "integration", "porter-stack-probe"),
                                                "--lcm-url", self.stack.lcm_url, "watch", self.watch_path])
        return self

    def __exit__(self, *exc):
        self.stack.__exit__(*exc)
        self.tmp.cleanup()
        return False

    def watch(self):
        try:
            return read_watch(self.watch_path)
        except OSError:
            return {}

    def mission_in_background(self, timeout_s, extra=()):
        out = os.path.join(self.run_dir, "mission.json")
        return self.stack.start("porter-mission", [self.stack.bin("planner", "daemon", "app", "porter-mission"),
                                                   "--scene", self.stack.scene_file, "--lcm-url", self.stack.lcm_url,
                                                   "--timeout-s", str(timeout_s), "--out", out, *extra]), out

    def wait_driving(self, min_speed=0.3, timeout_s=120.0):
        """Waits until a trajectory is executing and the true base speed exceeds min_speed."""
        def driving():
            w = self.watch()
            if not w.get("TRAJECTORY"):
                return None
            truth = w.get("SIM_TRUTH", [])
            return truth[-1] if truth and speed(truth[-1]) > min_speed else None
        return wait_for(driving, timeout_s, f"no trajectory driving the base above {min_speed} m/s")


def case_obstacle(a):
    # The MID-360 0.35 m higher than shipped: at the shipped height the arm blocks its forward
    # view and a box straight ahead is never seen (docs/stack.md, "Unknown space").
    with Case(a, sensor_raise_m=0.35) as c:
        # 0.4 x 1.2 x 1.0 m box across the straight path, about 4 m ahead of the start.
        box = "box1,4.5,0.0,0.5,0.4,1.2,1.0,0.0"
        mission, out = c.mission_in_background(150, ["--add-box", box, "--add-after-s", "1.0"])
        wait_for(lambda: mission.poll() is not None, 300, "porter-mission did not end")
        w = c.watch()
        # Read before the case's temporary run folder goes (without --keep).
        if not os.path.exists(out):
            fail(f"porter-mission wrote no summary (exit {mission.returncode})")
        s = json.load(open(out))
    print(s["summary"])
    if not s["box_added"]:
        fail("the box was never added (no trajectory started?)")
    replanning = [m for m in w.get("PLANNER_STATUS", []) if m["state"] == PLANNER_REPLANNING]
    if not replanning:
        fail("porter-planner never re-planned or braked for the box: " + s["summary"])
    # Map-update-to-new-trajectory: the map after which the first re-plan was decided, to the
    # trajectory published next.
    first = replanning[0]
    maps = [m for m in w.get("MAP_OCTOMAP", []) if m["rx"] <= first["rx"]]
    after = [t for t in w.get("TRAJECTORY", []) if maps and t["rx"] >= maps[-1]["rx"]]
    if maps and after:
        print(f"re-plan: map {maps[-1]['map_id']} received -> REPLANNING {1e-3 * (first['rx'] - maps[-1]['rx']):.1f} ms"
              f" -> TRAJECTORY plan {after[0]['plan_id']} {1e-3 * (after[0]['rx'] - maps[-1]['rx']):.1f} ms "
              f"({first['reason']})")
    if s["executed_collision"]:
        fail("the executed path collides: " + s["summary"])
    if s["collided"]:
        fail("an executed trajectory part collides: " + s["summary"])
    if not s["arrived"]:
        fail("not arrived: " + s["summary"])


def case_kill_tracker(a):
    with Case(a, no_restart=("porter-tracker",)) as c:
        mission, _ = c.mission_in_background(150)
        moving = c.wait_driving()
        t_kill = int(time.time() * 1e6)
        c.stack.kill("porter-tracker")
        time.sleep(4.0)
        w = c.watch()
        base_log = open(os.path.join(c.run_dir, "porter-base.log")).read()
    truth = [m for m in w["SIM_TRUTH"] if m["rx"] >= t_kill]
    if len(truth) < 100:
        fail(f"only {len(truth)} SIM_TRUTH samples after the kill")
    v0 = speed(truth[0])
    slowing = next((m for m in truth if speed(m) < v0 - 0.05), None)
    rest = next((m for m in truth if speed(m) < 0.01), None)
    if slowing is None or rest is None:
        fail(f"the base did not stop after the tracker was killed (speed {v0:.2f} -> {speed(truth[-1]):.2f} m/s)")
    onset_s, rest_s = 1e-6 * (slowing["rx"] - t_kill), 1e-6 * (rest["rx"] - t_kill)
    print(f"tracker killed at {speed(moving):.2f} m/s: base decelerating {1e3 * onset_s:.0f} ms after the kill, "
          f"at rest after {1e3 * rest_s:.0f} ms (porter-base's BASE_CMD stale limit 200 ms, the firmware's 500 ms)")
    if "BASE_CMD stale" not in base_log:
        fail("porter-base did not log the stale BASE_CMD")
    if max(speed(m) for m in truth if m["rx"] >= rest["rx"]) > 0.02:
        fail("the base moved again after coming to rest")
    # Stopped by the driver's watchdog, not by the firmware's own command timeout (500 ms).
    if onset_s >= 0.5:
        fail(f"the base started slowing only {onset_s:.3f} s after the kill: the driver's stale limit did not act")


def case_kill_planner(a):
    with Case(a, no_restart=("porter-planner",)) as c:
        mission, _ = c.mission_in_background(150)
        c.wait_driving()
        t_kill = int(time.time() * 1e6)
        c.stack.kill("porter-planner")
        trajectories = c.watch().get("TRAJECTORY", [])
        last = trajectories[-1]
        end_utime = last["start_utime"] + int(last["duration_s"] * 1e6)
        wait_for(lambda: time.time() * 1e6 > end_utime + 3e6, last["duration_s"] + 10, "trajectory end not reached")
        w = c.watch()
    statuses = [m for m in w.get("TRACKER_STATUS", []) if m["rx"] >= t_kill]
    finished = any(m["state"] == TRACKER_FINISHED for m in statuses)
    if [t for t in w.get("TRAJECTORY", []) if t["rx"] > t_kill + 100000]:
        fail("a TRAJECTORY arrived after the planner was killed")
    truth = [m for m in w["SIM_TRUTH"] if m["rx"] >= t_kill]
    final = truth[-1]
    # The empty scene's trajectory is the straight segment (0, 0) -> (8, 0).
    off_path = max(abs(m["y"]) for m in truth)
    err = math.hypot(final["x"] - 8.0, final["y"] - 0.0)
    print(f"planner killed; the tracker {'finished' if finished else 'stopped (states ' + str(sorted({m['state'] for m in statuses})) + ')'} "
          f"trajectory plan {last['plan_id']}: final distance to its end {err:.3f} m, largest distance from its path "
          f"{off_path:.3f} m, final speed {speed(final):.3f} m/s")
    if off_path > 0.3:
        fail(f"the robot left the path of the trajectory it was executing by {off_path:.2f} m")
    if finished and err > 0.3:
        fail(f"FINISHED {err:.2f} m from the end of the trajectory it was executing")
    after_end = [m for m in truth if m["rx"] > end_utime + 1.5e6]
    if not after_end or max(speed(m) for m in after_end) > 0.02:
        fail("the robot moves after the end of its trajectory")


def case_estop(a):
    with Case(a) as c:
        mission, _ = c.mission_in_background(150)
        c.wait_driving()
        subprocess.run([c.stack.bin("tests", "integration", "porter-stack-probe"), "--lcm-url", c.stack.lcm_url,
                        "estop", "on"], check=True)
        t_estop = int(time.time() * 1e6)
        time.sleep(3.0)
        subprocess.run([c.stack.bin("tests", "integration", "porter-stack-probe"), "--lcm-url", c.stack.lcm_url,
                        "estop", "off"], check=True)
        t_release = int(time.time() * 1e6)
        time.sleep(2.0)
        w = c.watch()
    estops = [m for m in w.get("ESTOP", []) if m["active"]]
    if not estops:
        fail("the ESTOP was not seen on the bus")
    t_rx = estops[0]["rx"]
    cmds = [m for m in w["BASE_CMD"] if m["rx"] > t_rx]
    first_disabled = next((i for i, m in enumerate(cmds) if not m["enabled"]), None)
    if first_disabled is None or first_disabled > 1:
        fail(f"{first_disabled} enabled BASE_CMDs after the ESTOP before a disabled one (at most the one in flight)")
    if any(m["enabled"] for m in cmds[first_disabled:]):
        fail("an enabled BASE_CMD after the e-stop took effect (held, then released without a new trajectory)")
    if not any(m["state"] == TRACKER_ESTOP for m in w.get("TRACKER_STATUS", []) if m["rx"] > t_rx):
        fail("porter-tracker never reported ESTOP")
    truth = [m for m in w["SIM_TRUTH"] if m["rx"] >= t_estop]
    rest = next((m for m in truth if speed(m) < 0.01), None)
    if rest is None:
        fail("the base did not come to rest after the e-stop")
    print(f"e-stop: {first_disabled} enabled BASE_CMD after it, base at rest "
          f"{1e-3 * (rest['rx'] - t_estop):.0f} ms after it was sent")
    still = [m for m in truth if m["rx"] >= rest["rx"]]
    if max(speed(m) for m in still) > 0.02:
        fail("the base moved after coming to rest (e-stop held, then released without a new trajectory)")
    settled = [m for m in truth if m["rx"] >= t_estop + 1000000]
    q0 = settled[0]["q"]
    dq = max(abs(m["q"][j] - q0[j]) for m in settled for j in range(len(q0)))
    if dq > 0.01:
        fail(f"the arm moved {dq:.3f} rad while the e-stop was held or after its release")
    moved = math.hypot(truth[-1]["x"] - rest["x"], truth[-1]["y"] - rest["y"])
    if moved > 0.01 or [m for m in truth if m["rx"] > t_release and speed(m) > 0.02]:
        fail(f"the robot moved {moved:.3f} m after the release")


parser = argparse.ArgumentParser()
parser.add_argument("root")
parser.add_argument("build")
parser.add_argument("case", choices=["obstacle", "kill_tracker", "kill_planner", "estop"])
parser.add_argument("--keep")
parser.add_argument("--record", action="store_true", help="record the run (run.lcmlog in the run folder; with --keep)")
args = parser.parse_args()
{"obstacle": case_obstacle, "kill_tracker": case_kill_tracker, "kill_planner": case_kill_planner,
 "estop": case_estop}[args.case](args)
print("OK")
