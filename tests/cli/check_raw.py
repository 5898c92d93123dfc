#!/usr/bin/env python3
"""Checks raw rgbf32 frames: right size, every value finite and non-negative, not a flat image.
Usage: check_raw.py FILE WIDTH HEIGHT FRAMES"""
import array
import math
import sys

path, w, h, n = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
data = array.array("f")
with open(path, "rb") as f:
    data.frombytes(f.read())
if len(data) != w * h * 3 * n:
    sys.exit(f"{path}: {len(data)} floats, expected {w * h * 3 * n}")
bad = sum(1 for v in data if not math.isfinite(v) or v < 0.0)
if bad:
    sys.exit(f"{path}: {bad} non-finite or negative values")
frame = w * h * 3
for i in range(n):
    lum = data[i * frame:(i + 1) * frame]
    mean = sum(lum) / frame
    var = sum((v - mean) ** 2 for v in lum) / frame
    if var < 1e-6 * max(mean * mean, 1e-12):
        sys.exit(f"{path}: frame {i} is flat (mean {mean}, variance {var})")
print(f"{path}: ok")
