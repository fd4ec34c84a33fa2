#!/usr/bin/python3
"""scripts/launch on a profile of small stand-in processes: start order and the run folder (a log
per process, launch.json with PIDs), the restart policy (a process that fails is restarted
max_restarts times, then given up; a required one makes the exit code 1), variables, and a clean
stop on SIGINT that leaves no process behind. A strict profile: an unknown key is refused (exit 2).

usage: launch_test.py ROOT
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

ROOT = sys.argv[1]
LAUNCH = os.path.join(ROOT, "scripts", "launch")


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def alive(pid):
    try:
        os.kill(pid, 0)
        return True
    except ProcessLookupError:
        return False


with tempfile.TemporaryDirectory() as tmp:
    profile = os.path.join(tmp, "test.yaml")
    with open(profile, "w") as f:
        f.write("""description: launch test
lcm_url: memq://
record: false
vars: {word: hello}
processes:
  - name: sleeper
    command: [/bin/sh, -c, "echo {word}; exec sleep 60"]
    restart: never
    max_restarts: 0
    restart_delay_s: 0.1
    start_delay_s: 0.1
    optional: false
  - name: crasher
    command: [/bin/sh, -c, "echo crash; exit 3"]
    restart: on-failure
    max_restarts: 2
    restart_delay_s: 0.1
    start_delay_s: 0.1
    optional: false
  - name: missing
    command: [/nonexistent/porter-nothing]
    restart: never
    max_restarts: 0
    restart_delay_s: 0.1
    start_delay_s: 0.0
    optional: true
""")
    run = os.path.join(tmp, "run")
    p = subprocess.Popen([sys.executable, LAUNCH, profile, "--run-dir", run, "--set", "word=porter"],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    deadline = time.monotonic() + 20
    state = None
    while time.monotonic() < deadline:
        time.sleep(0.2)
        try:
            state = json.load(open(os.path.join(run, "launch.json")))
        except (OSError, ValueError):
            continue
        procs = {q["name"]: q for q in state["processes"]}
        if "crasher" in procs and procs["crasher"]["restarts"] == 2:
            break
    time.sleep(0.5)
    procs = {q["name"]: q for q in state["processes"]}
    if list(procs) != ["sleeper", "crasher"]:
        fail(f"processes {list(procs)} (the optional missing one must be skipped)")
    if procs["crasher"]["restarts"] != 2:
        fail(f"crasher restarted {procs['crasher']['restarts']} times, expected 2")
    sleeper_pid = procs["sleeper"]["pid"]
    if not alive(sleeper_pid):
        fail("sleeper is not running")
    if open(os.path.join(run, "sleeper.log")).read().strip() != "porter":
        fail("variable not substituted or log missing")
    if open(os.path.join(run, "crasher.log")).read().count("crash") != 3:
        fail("crasher's log must hold its three runs")
    log = open(os.path.join(run, "launch.log")).read()
    if "not restarted (2 restarts used)" not in log:
        fail("the give-up is not logged:\n" + log)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=15)
    if p.returncode != 1:
        fail(f"exit code {p.returncode}, expected 1 (a required process failed)\n{out}")
    if alive(sleeper_pid):
        os.kill(sleeper_pid, signal.SIGKILL)
        fail("sleeper left running after the stop")
    if "sleeper stopped" not in open(os.path.join(run, "launch.log")).read():
        fail("the stop is not logged")

    bad = os.path.join(tmp, "bad.yaml")
    with open(bad, "w") as f:
        f.write(open(profile).read().replace("record: false", "record: false\nrecrod: true"))
    r = subprocess.run([sys.executable, LAUNCH, bad, "--run-dir", os.path.join(tmp, "r2")], capture_output=True, text=True)
    if r.returncode != 2 or "unknown key 'recrod'" not in r.stderr:
        fail(f"a bad profile: exit {r.returncode}, {r.stderr}")
    for name in ("sim", "robot"):  # the shipped profiles parse (the unknown variable is caught after)
        r = subprocess.run([sys.executable, LAUNCH, name, "--set", "zz=1", "--run-dir", os.path.join(tmp, name)],
                           capture_output=True, text=True)
        if r.returncode != 2 or "not a variable of the profile" not in r.stderr:
            fail(f"shipped profile {name}: exit {r.returncode}, {r.stderr}")
# The receive-buffer check: a URL asking for more than net.core.rmem_max allows is warned about
# (subscribers of LIDAR_POINTS would lose clouds); one within it, or asking for nothing, is not.
import importlib.machinery  # noqa: E402
import importlib.util  # noqa: E402
loader = importlib.machinery.SourceFileLoader("porter_launch", LAUNCH)
launch = importlib.util.module_from_spec(importlib.util.spec_from_loader("porter_launch", loader))
loader.exec_module(launch)
with tempfile.TemporaryDirectory() as tmp:
    rmem = os.path.join(tmp, "rmem_max")
    with open(rmem, "w") as f:
        f.write("212992\n")
    url = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304"
    w = launch.receive_buffer_warning(url, rmem)
    if "212992" not in w or "sysctl -w net.core.rmem_max=4194304" not in w:
        fail("no warning for a receive buffer the kernel caps: " + repr(w))
    with open(rmem, "w") as f:
        f.write("4194304\n")
    if launch.receive_buffer_warning(url, rmem):
        fail("warned although the kernel grants the buffer")
    if launch.receive_buffer_warning("udpm://239.255.76.67:7667?ttl=0", os.path.join(tmp, "none")):
        fail("warned for a URL that asks for no buffer")
print("OK")
