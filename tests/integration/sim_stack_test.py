#!/usr/bin/python3
"""The simulated stack drives start to goal on the bridge scene with no collision.

Launches the sim profile (porter-sim with the Scout Mini and Piper firmware and the simulated
MID-360, porter-base, porter-arm, porter-lidar, porter-state, porter-mapper, porter-tracker,
porter-planner) through scripts/launch on a private udpm URL, with the LiDAR's UDP on free
loopback ports, sends the bridge goal with porter-mission and requires: arrival within the
mission's distance, no collision of the executed path (every SIM_TRUTH configuration, exact
geometry) nor of any executed trajectory, at least one plan, and a clean stop by PID that leaves
none of the launched processes running.

usage: sim_stack_test.py ROOT BUILD
"""
import json
import os
import re
import signal
import socket
import subprocess
import sys
import tempfile
import time

ROOT, BUILD = sys.argv[1], sys.argv[2]
CONFIG = os.path.join(ROOT, "config")


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def free_udp_port():
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def alive(pid):
    try:
        os.kill(pid, 0)
        return True
    except ProcessLookupError:
        return False


def absolute_paths(text, folder):
    """Relative '../x' paths of a shipped config, made absolute (the copy lives elsewhere)."""
    return re.sub(r"(:\s*)\.\./", lambda m: m.group(1) + os.path.dirname(folder) + "/", text)


def edited(name, folder, replacements, tmp):
    with open(os.path.join(folder, name)) as f:
        text = absolute_paths(f.read(), folder)
    for old, new in replacements:
        if old not in text:
            fail(f"{name}: '{old}' not found")
        text = text.replace(old, new)
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write(text)
    return path


with tempfile.TemporaryDirectory() as tmp:
    lcm_url = f"udpm://239.255.76.67:{free_udp_port()}?ttl=0"
    point_port, imu_port = free_udp_port(), free_udp_port()
    drivers = os.path.join(CONFIG, "drivers")
    edited("porter_sim.yaml", drivers, [
        ("point_port: 56301", f"point_port: {point_port}"), ("imu_port: 56401", f"imu_port: {imu_port}"),
        ("point_source_port: 56300", "point_source_port: 0"), ("imu_source_port: 56400", "imu_source_port: 0")], tmp)
    edited("porter_lidar.yaml", drivers, [
        ("address: 0.0.0.0", "address: 127.0.0.1"),
        ("point_port: 56301", f"point_port: {point_port}"), ("imu_port: 56401", f"imu_port: {imu_port}")], tmp)
    with open(os.path.join(CONFIG, "launch", "sim.yaml")) as f:
        profile = f.read()
    for name in ("porter_sim.yaml", "porter_lidar.yaml"):
        profile = profile.replace('"{config}/drivers/' + name + '"', '"' + os.path.join(tmp, name) + '"')
    profile_path = os.path.join(tmp, "sim_test.yaml")
    with open(profile_path, "w") as f:
        f.write(profile)

    run_dir = os.path.join(tmp, "run")
    scene = os.path.join(CONFIG, "scenes", "bridge.yaml")
    launch = subprocess.Popen([os.path.join(ROOT, "scripts", "launch"), profile_path, "--set", "scene=bridge",
                               "--set", "payload=t_bar", "--lcm-url", lcm_url, "--run-dir", run_dir,
                               "--build", BUILD, "--no-record"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    pids = []
    try:
        out = os.path.join(tmp, "mission.json")
        mission = subprocess.run([os.path.join(BUILD, "planner", "daemon", "app", "porter-mission"), "--scene", scene,
                                  "--lcm-url", lcm_url, "--timeout-s", "150", "--out", out],
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=300)
        with open(os.path.join(run_dir, "launch.json")) as f:
            pids = [p["pid"] for p in json.load(f)["processes"] if p.get("pid")]
        print(mission.stdout.strip())
        if not os.path.exists(out):
            sys.stdout.write(mission.stderr[-3000:])
            fail(f"porter-mission wrote no summary (exit {mission.returncode})")
        with open(out) as f:
            summary = json.load(f)
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
        if mission.returncode != 0:
            fail(f"porter-mission exit {mission.returncode}")
    finally:
        launch.send_signal(signal.SIGINT)
        try:
            launch.wait(timeout=30)
        except subprocess.TimeoutExpired:
            launch.kill()
            launch.wait()
    left = [p for p in pids if alive(p)]
    for p in left:
        os.kill(p, signal.SIGKILL)
    if left:
        fail(f"processes left running after the stop: {left}")
    if launch.returncode != 0:
        fail(f"scripts/launch exit {launch.returncode}")
print("OK")
