#!/usr/bin/env python3
"""Writes the seed corpora of the LCM guard fuzz targets (tests/fuzz/corpus/lcm_<type>/): for
each lcmtypes/*.lcm, a mode byte 0 (the target prepends the type's fingerprint) and the members
encoded big-endian, with array counts 0, 1 and 3. Re-run after a type changes:
python3 tests/fuzz/make_lcm_corpus.py"""
import os
import re
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
LCM_DIR = os.path.join(HERE, "..", "..", "lcmtypes")
FMT = {"int8_t": ">b", "int16_t": ">h", "int32_t": ">i", "int64_t": ">q", "float": ">f",
       "double": ">d", "boolean": ">b", "byte": ">B"}


def members(path):
    text = open(path).read()
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    body = re.search(r"struct\s+(\w+)\s*\{(.*)\}", text, re.S)
    out = []
    for m in body.group(2).split(";"):
        m = " ".join(m.split())
        if not m or m.startswith("const "):
            continue
        mm = re.match(r"^(\S+) (\w+)(?: ?\[ ?(\w+) ?\])?$", m)
        out.append((mm.group(1), mm.group(2), mm.group(3)))
    return body.group(1), out


def encode(fields, count, text):
    out = b"\0"
    values = {}
    for typ, name, dim in fields:
        n = values[dim] if dim else 1
        for i in range(n):
            if typ == "string":
                s = text.encode() + b"\0"
                out += struct.pack(">i", len(s)) + s
            else:
                is_count = any(d == name for _, _, d in fields)
                v = count if is_count else (1.5 if typ in ("float", "double") else 1)
                values[name] = v
                out += struct.pack(FMT[typ], v)
    return out


for f in sorted(os.listdir(LCM_DIR)):
    if not f.endswith(".lcm"):
        continue
    name, fields = members(os.path.join(LCM_DIR, f))
    corpus = os.path.join(HERE, "corpus", "lcm_" + name)
    os.makedirs(corpus, exist_ok=True)
    for i, (count, text) in enumerate([(0, ""), (1, "world"), (3, "porter-tracker")]):
        with open(os.path.join(corpus, "seed_%d" % i), "wb") as out:
            out.write(encode(fields, count, text))
