"""The simulated stack on a private LCM URL, for the integration tests and for measurements.

SimStack copies the sim profile and the two configs that name UDP ports (porter-sim's and
porter-lidar's) into a folder of its own with a free udpm port and free loopback LiDAR ports, so
several stacks can run on one machine; starts scripts/launch on it; knows every launched
process's PID (launch.json); and stops the stack by PID. Processes it did not start are never
touched.

    with SimStack(root, build, "bridge", "t_bar", run_dir) as stack:
        stack.wait_ready()
        rc, summary = stack.mission(timeout_s=150)
"""
import json
import os
import re
import signal
import socket
import subprocess
import tempfile
import time

import yaml


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


def _absolute_paths(text, folder):
    """Relative '../x' paths of a shipped config, made absolute (the copy lives elsewhere)."""
    return re.sub(r"(:\s*)\.\./", lambda m: m.group(1) + os.path.dirname(folder) + "/", text)


def _edited(name, folder, replacements, out_dir):
    with open(os.path.join(folder, name)) as f:
        text = _absolute_paths(f.read(), folder)
    for old, new in replacements:
        if old not in text:
            raise RuntimeError(f"{name}: '{old}' not found")
        text = text.replace(old, new)
    path = os.path.join(out_dir, name)
    with open(path, "w") as f:
        f.write(text)
    return path


class SimStack:
    def __init__(self, root, build, scene, payload, run_dir, record=False, lcm_url=None, known_map=False,
                 no_restart=(), sensor_raise_m=0.0):
        self.root, self.build = os.path.abspath(root), os.path.abspath(build)
        self.scene, self.payload = scene, payload
        self.run_dir = run_dir
        self.record = record
        self.known_map = known_map
        self.no_restart = set(no_restart)  # processes whose restart policy becomes `never`
        # > 0: the simulated MID-360 (porter-sim's mount) and porter-mapper's sensor extrinsic
        # are raised by this much on the mast (a sensor placement other than the shipped one).
        self.sensor_raise_m = sensor_raise_m
        # recv_buf_size: a LiDAR cloud is ~0.4 MB (config/mapping/porter_mapper.yaml).
        self.lcm_url = lcm_url or f"udpm://239.255.76.67:{free_udp_port()}?ttl=0&recv_buf_size=4194304"
        self.scene_file = os.path.join(self.root, "config", "scenes", scene + ".yaml")
        self.launch = None
        self.extra = []  # (name, Popen) started by this object besides scripts/launch
        self._tmp = tempfile.TemporaryDirectory()

    def bin(self, *parts):
        return os.path.join(self.build, *parts)

    def __enter__(self):
        tmp = self._tmp.name
        config = os.path.join(self.root, "config")
        point_port, imu_port = free_udp_port(), free_udp_port()
        drivers = os.path.join(config, "drivers")
        sim_edits = [
            ("point_port: 56301", f"point_port: {point_port}"), ("imu_port: 56401", f"imu_port: {imu_port}"),
            ("point_source_port: 56300", "point_source_port: 0"), ("imu_source_port: 56400", "imu_source_port: 0")]
        if self.sensor_raise_m > 0.0:
            sim_edits.append(("xyz: [0.0, 0.0, 0.2875]", f"xyz: [0.0, 0.0, {0.2875 + self.sensor_raise_m:.4f}]"))
            _edited("porter_mapper.yaml", os.path.join(config, "mapping"), [
                ("T_B_S: {xyz: [-0.22, 0.0, 0.5325]", f"T_B_S: {{xyz: [-0.22, 0.0, {0.5325 + self.sensor_raise_m:.4f}]")],
                tmp)
        _edited("porter_sim.yaml", drivers, sim_edits, tmp)
        _edited("porter_lidar.yaml", drivers, [
            ("address: 0.0.0.0", "address: 127.0.0.1"),
            ("point_port: 56301", f"point_port: {point_port}"), ("imu_port: 56401", f"imu_port: {imu_port}")], tmp)
        with open(os.path.join(config, "launch", "sim.yaml")) as f:
            profile = f.read()
        for name in ("porter_sim.yaml", "porter_lidar.yaml"):
            profile = profile.replace('"{config}/drivers/' + name + '"', '"' + os.path.join(tmp, name) + '"')
        if self.sensor_raise_m > 0.0:
            profile = profile.replace('"{config}/mapping/porter_mapper.yaml"', '"' + os.path.join(tmp, "porter_mapper.yaml") + '"')
        if self.no_restart:
            doc = yaml.safe_load(profile)
            for p in doc["processes"]:
                if p["name"] in self.no_restart:
                    p["restart"], p["max_restarts"] = "never", 0
            profile = yaml.safe_dump(doc, sort_keys=False)
        profile_path = os.path.join(tmp, "sim_test.yaml")
        with open(profile_path, "w") as f:
            f.write(profile)
        os.makedirs(self.run_dir, exist_ok=True)
        args = [os.path.join(self.root, "scripts", "launch"), profile_path, "--set", f"scene={self.scene}",
                "--set", f"payload={self.payload}", "--lcm-url", self.lcm_url, "--run-dir", self.run_dir,
                "--build", self.build]
        if not self.record:
            args.append("--no-record")
        self.launch = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if self.known_map:
            self.start("porter-scene-map", [self.bin("planner", "daemon", "app", "porter-scene-map"),
                                            "--scene", self.scene_file, "--rate-hz", "2", "--lcm-url", self.lcm_url])
        return self

    def start(self, name, args):
        """Starts a process of the test's own (logged to RUN_DIR/<name>.log) and returns it."""
        log = open(os.path.join(self.run_dir, name + ".log"), "w")
        p = subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT)
        self.extra.append((name, p))
        return p

    def processes(self):
        """{name: pid} of the processes scripts/launch runs now."""
        try:
            with open(os.path.join(self.run_dir, "launch.json")) as f:
                return {p["name"]: p["pid"] for p in json.load(f)["processes"] if p.get("pid")}
        except (OSError, ValueError, KeyError):
            return {}

    def wait_processes(self, names, timeout_s=60.0):
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            procs = self.processes()
            if all(n in procs for n in names):
                return procs
            time.sleep(0.2)
        raise RuntimeError(f"processes {names} not all started within {timeout_s} s: {self.processes()}")

    def kill(self, name, sig=signal.SIGKILL):
        """Sends `sig` to the launched process `name` (by its PID); returns the PID."""
        pid = self.processes()[name]
        os.kill(pid, sig)
        return pid

    def mission(self, timeout_s=150.0, out_name="mission.json", extra_args=()):
        """Runs porter-mission to the scene's goal; returns (exit code, summary dict or None, stdout)."""
        out = os.path.join(self.run_dir, out_name)
        with open(os.path.join(self.run_dir, "porter-mission.log"), "w") as err:
            r = subprocess.run([self.bin("planner", "daemon", "app", "porter-mission"), "--scene", self.scene_file,
                                "--lcm-url", self.lcm_url, "--timeout-s", str(timeout_s), "--out", out,
                                *extra_args], stdout=subprocess.PIPE, stderr=err, text=True, timeout=timeout_s + 120)
        summary = None
        if os.path.exists(out):
            with open(out) as f:
                summary = json.load(f)
        return r.returncode, summary, r.stdout.strip()

    def stop(self):
        """Stops the stack (SIGINT to scripts/launch, which stops its processes in reverse order)
        and this object's own processes; returns the PIDs still alive afterwards (killed)."""
        pids = list(self.processes().values())
        for _, p in self.extra:
            if p.poll() is None:
                p.send_signal(signal.SIGINT)
        if self.launch and self.launch.poll() is None:
            self.launch.send_signal(signal.SIGINT)
            try:
                self.launch.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self.launch.kill()
                self.launch.wait()
        for _, p in self.extra:
            try:
                p.wait(timeout=5)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        left = [p for p in pids if alive(p)]
        for p in left:
            os.kill(p, signal.SIGKILL)
        return left

    def __exit__(self, *exc):
        self.left_running = self.stop()
        self._tmp.cleanup()
        return False
