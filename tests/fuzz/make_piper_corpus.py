#!/usr/bin/env python3
"""Writes the seed corpora of the Piper fuzz targets (tests/fuzz/corpus/piper_*/): 12-byte
records (milliseconds to advance, ID big-endian, flags = dlc | 0x10 extended | 0x20 RTR, 8 data
bytes; see piper_fuzz_input.hpp) built from the protocol's real layouts. Re-run after a layout
change: python3 tests/fuzz/make_piper_corpus.py"""
import os
import struct

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def rec(frame_id, data, ms=0, dlc=None, ext=False, rtr=False):
    data = bytes(data)
    n = len(data) if dlc is None else dlc
    flags = (n & 0x0F) | (0x10 if ext else 0) | (0x20 if rtr else 0)
    return struct.pack(">BHB", ms, frame_id, flags) + data.ljust(8, b"\0")[:8]


def i32(v):
    return struct.pack(">i", v)


def feedback(ms=5, ctrl=0x01, enabled=True, q_mdeg=(0, 0, 0, 0, 0, 0), err=0, arm_status=0):
    out = rec(0x2A1, [ctrl, arm_status, 0x01, 0, 0, 0, err >> 8, err & 0xFF], ms)
    for i in range(3):
        out += rec(0x2A5 + i, i32(q_mdeg[2 * i]) + i32(q_mdeg[2 * i + 1]))
    out += rec(0x2A8, i32(35000) + struct.pack(">h", -200) + bytes([0xC0, 0]))
    for j in range(6):
        out += rec(0x251 + j, struct.pack(">hhi", -1000 * j, 500, 1000 * j))
        out += rec(0x261 + j, struct.pack(">HhbBH", 240, 35, 30, 0x40 if enabled else 0x00, 100))
    return out


def commands():
    out = rec(0x471, [0x07, 0x02, 0, 0, 0, 0, 0, 0])
    out += rec(0x151, [0x01, 0x01, 50, 0, 0, 0, 0, 0], 30)
    out += rec(0x155, i32(90000) + i32(-90000), 5)
    out += rec(0x156, i32(5730) + i32(-28648))
    out += rec(0x157, i32(180000) + i32(57296))
    out += rec(0x159, i32(35000) + struct.pack(">H", 1500) + bytes([0x01, 0x00]))
    out += rec(0x150, [0x01, 0, 0, 0, 0, 0, 0, 0], 100)
    out += rec(0x150, [0x02, 0, 0, 0, 0, 0, 0, 0], 100)
    out += rec(0x471, [0xFF, 0x01, 0, 0, 0, 0, 0, 0], 50)
    return out


def odd_frames():
    out = rec(0x2A5, [1, 2, 3], dlc=3)            # short
    out += rec(0x2A1, [0] * 8, dlc=15)            # dlc > 8
    out += rec(0x155, [0] * 8, ext=True)          # extended ID
    out += rec(0x2A1, [], rtr=True)               # remote frame
    out += rec(0x471, [0x09, 0x05], dlc=2)        # undefined values
    return out


def write(name, files):
    d = os.path.join(ROOT, name)
    os.makedirs(d, exist_ok=True)
    for fname, blob in files.items():
        with open(os.path.join(d, fname), "wb") as f:
            f.write(blob)


fb_standby = feedback(ctrl=0x00, enabled=False)
fb_active = feedback(q_mdeg=(90000, -90000, 5730, -28648, 180000, 57296))
fb_fault = feedback(err=0x0402, arm_status=0x07)
write("piper_feedback", {"standby": fb_standby, "active": fb_active, "fault": fb_fault, "odd": odd_frames()})
write("piper_command", {"sequence": commands(), "odd": odd_frames()})
write("piper_firmware", {"sequence": commands() + rec(0, [0] * 8, 200), "odd": odd_frames() + commands()})
# The driver: standby, then enabled, then CAN mode, commands (0xC3 in B0 of an ignored frame),
# an e-stop and its release (0xE5), then faults.
drive = fb_standby + feedback(ms=20, ctrl=0x00) + feedback(ms=20) + rec(0x7FF, [0xC3, 0, 0, 0, 0, 0, 0, 0])
drive += feedback(ms=20) * 4 + rec(0x7FF, [0xE5, 1, 0, 0, 0, 0, 0, 0]) + feedback(ms=20, arm_status=0x01) * 3
drive += rec(0x7FF, [0xE5, 0, 0, 0, 0, 0, 0, 0]) + feedback(ms=20) * 3 + fb_fault
write("piper_driver", {"session": drive, "odd": odd_frames() + fb_active})
