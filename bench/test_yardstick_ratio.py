#!/usr/bin/env python3
"""Runs bench/yardstick_ratio.py for one round at a tiny size against the built houle and a stand-in
for the bare marcher that prints its table with fixed times (10 ms median, 12 ms p99), and checks
what it reports: the ratio is houle's median over 10 ms, the fly-along's ratio its median over the
fixed shot's, and a missing bare marcher is a clear error. No timing is judged.
Usage: test_yardstick_ratio.py <houle binary> <source dir>"""
import os
import re
import subprocess
import sys
import tempfile

houle, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
script = os.path.join(src, "bench", "yardstick_ratio.py")
# The bare marcher's output as its README shows it (the last column, diff, empty).
table = """# W=64 H=36 threads=2 G=1 frames=40
mode           W     H   med_ms   p99_ms  mean_ms   Mpix/s      fps steps/sp   ev/sp     Mev/s   Mslot/s   util rebld_ms    diff
tile16b_opt_hw    64    36    10.00    12.00    10.10     0.23    100.0     17.7    23.7     410.1     482.2   0.81    0.831
"""


def fail(message):
    sys.exit(f"test_yardstick_ratio: {message}")


with tempfile.TemporaryDirectory() as yard:
    for name in ("ocean_v3", "ocean_v4"):
        path = os.path.join(yard, name)
        with open(path, "w") as f:
            f.write(f"#!/bin/sh\ncat <<'EOF'\n{table}EOF\n")
        os.chmod(path, 0o755)
    run = subprocess.run([sys.executable, script, "--yardstick", yard, "--houle", houle, "--rounds", "1",
                          "--sizes", "64x36", "--fly", os.path.join(src, "scenes", "coast_flyby.toml")],
                         capture_output=True, text=True, cwd=src)
    if run.returncode != 0:
        fail(f"exit {run.returncode}:\n{run.stdout}{run.stderr}")
    m = re.search(r"round 1 64x36: bare marcher 10\.00/10\.00 ms, houle ([\d.]+) ms .*fly-along ([\d.]+) ms "
                  r"\| ratio ([\d.]+), fly-along/fixed ([\d.]+)", run.stdout)
    if not m:
        fail(f"no round line as expected in:\n{run.stdout}")
    fixed, fly, ratio, fly_fixed = (float(x) for x in m.groups())
    # Each printed figure is rounded to 0.005: the ratios' bounds carry their inputs' rounding too.
    off = lambda q, a, b: 0.005 + q * (0.005 / a + 0.005 / b)
    if abs(ratio - fixed / 10.0) > off(ratio, fixed, 10.0) or abs(fly_fixed - fly / fixed) > off(fly_fixed, fly, fixed):
        fail(f"ratio {ratio} or fly-along/fixed {fly_fixed} is not from houle {fixed} ms and fly-along {fly} ms")
    for line in ("1 rounds; ranges over the rounds", "ratio to the bare marcher", "<= 1.2 in", "p99 / median",
                 "the least of each"):
        if line not in run.stdout:
            fail(f"summary without '{line}':\n{run.stdout}")

missing = subprocess.run([sys.executable, script, "--yardstick", os.path.join(src, "no-such-dir"), "--houle", houle,
                          "--rounds", "1"],
                         capture_output=True, text=True, cwd=src)
if missing.returncode == 0 or "no such program; build it with `make -C" not in missing.stderr:
    fail(f"a missing bare marcher: exit {missing.returncode}, {missing.stderr.strip()!r}")
print(f"yardstick_ratio: ratio {ratio} for houle {fixed} ms, fly-along/fixed {fly_fixed}")
