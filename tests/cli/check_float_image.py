#!/usr/bin/env python3
"""Checks that an image holds the linear frame of a raw rgbf32 file, within the precision of its
format: half (EXR), RGBE (HDR: 8 bits of mantissa shared by a pixel's channels) or float (TIFF).
The image's pixels come as `oiiotool --dumpdata IMAGE` prints them (9 significant digits).
Usage: check_float_image.py RAW.f32 DUMP.txt half|rgbe|float"""
import array
import re
import sys

raw_path, dump_path, precision = sys.argv[1], sys.argv[2], sys.argv[3]
ref = array.array("f")
with open(raw_path, "rb") as f:
    ref.frombytes(f.read())
with open(dump_path) as f:
    header = f.readline()
    pixels = [line.split(":")[1].split() for line in f if line.strip().startswith("Pixel")]
size = re.search(r"\d+ x +\d+, 3 channel", header)
if not size or len(pixels) * 3 != len(ref):
    sys.exit(f"{dump_path}: {header.strip()}, {len(pixels)} pixels; the raw frame has {len(ref) // 3}")
worst = 0.0
for p, values in enumerate(pixels):  # row by row from the top, as raw frames are
    a, b = ref[3 * p:3 * p + 3], [float(v) for v in values]
    for i in range(3):
        # The error the format may make: half's 11-bit mantissa per value (and half its smallest
        # subnormal, 2^-25, below which a value becomes 0), RGBE's 8 truncated bits of the pixel's
        # largest channel; none for float, whose bits the dump prints to about 8 significant digits
        # (so one float epsilon, 2^-23, relative).
        allowed = {"half": abs(a[i]) * 2.0**-11 + 2.0**-25, "rgbe": max(a) * 2.0**-7, "float": abs(a[i]) * 2.0**-23}[precision] + 1e-30
        worst = max(worst, abs(a[i] - b[i]) / allowed)
if worst > 1.0:
    sys.exit(f"{dump_path}: off the raw linear frame by {worst:.3g} times the {precision} format's precision")
