#!/usr/bin/env python3
"""Checks an EXR's AOV channels against its own camera matrices: every pixel whose `sea` is 1 puts,
through its Z (depth along the view axis) and the worldToCamera matrix, a point on the sea surface
(|z| below the scene's wave height bound); pixels with alpha 0 have Z = inf and a zero normal; normals
of covered pixels are unit and face the camera.
The pixels come as `oiiotool --info -v` then `oiiotool --dumpdata` print them, the matrices from check_exr_header.py's reader.
Usage: check_aovs.py FILE.exr DUMP.txt MAX_WAVE_HEIGHT_M"""
import math
import re
import struct
import sys

path, dump_path, bound = sys.argv[1], sys.argv[2], float(sys.argv[3])
data = open(path, "rb").read()
pos, attrs = 8, {}
while data[pos] != 0:
    n = data.index(b"\0", pos)
    t = data.index(b"\0", n + 1)
    size = struct.unpack_from("<i", data, t + 1)[0]
    attrs[data[pos:n].decode()] = data[t + 5:t + 5 + size]
    pos = t + 5 + size
w2c = struct.unpack("<16f", attrs["worldToCamera"])
w2n = struct.unpack("<16f", attrs["worldToNDC"])
lines = open(dump_path).read().splitlines()
size = re.search(r"(\d+) x +(\d+), (\d+) channel", "\n".join(lines))
width, height = int(size.group(1)), int(size.group(2))
channels = [c.split(" (")[0].strip() for c in re.search(r"channel list: (.*)", open(dump_path).read()).group(1).split(",")]
pixels = {}
for line in lines:
    m = re.match(r"\s*Pixel \((\d+), (\d+)\): (.*)", line)
    if m:
        pixels[(int(m.group(1)), int(m.group(2)))] = dict(zip(channels, (float(v) for v in m.group(3).split())))
assert len(pixels) == width * height, (len(pixels), width, height)
# Camera position and axes from worldToCamera (its 3x3 part is a rotation, rows of the world axes).
R = [[w2c[4 * i + j] for j in range(3)] for i in range(3)]  # R[i][j]: world axis i's camera component j
pos_world = [-sum(R[i][j] * w2c[12 + j] for j in range(3)) for i in range(3)]
errors, sea = [], 0
for (x, y), p in pixels.items():
    if p["sea"] == 1.0:
        sea += 1
        # The pixel centre's NDC is (x_c sx / z + 0.5, y_c sy / z + 0.5) for the camera-space point
        # (x_c, y_c, z), with sx, sy the diagonal of the camera-to-NDC part of worldToNDC:
        # C[k][j] = sum_i R[i][k] w2n[i][j] (worldToNDC = worldToCamera C, R a rotation).
        ndc = ((x + 0.5) / width, (y + 0.5) / height)
        sx = sum(R[i][0] * w2n[4 * i] for i in range(3))
        sy = sum(R[i][1] * w2n[4 * i + 1] for i in range(3))
        z = p["Z"]
        cam = [(ndc[0] - 0.5) * z / sx, (ndc[1] - 0.5) * z / sy, z]
        world = [pos_world[i] + sum(R[i][j] * cam[j] for j in range(3)) for i in range(3)]
        if abs(world[2]) > bound:
            errors.append(f"pixel {x},{y}: Z {z} puts the sea at z = {world[2]:.3f} m")
    if p["A"] == 0.0 and (p["Z"] != math.inf or (p["N.X"], p["N.Y"], p["N.Z"]) != (0.0, 0.0, 0.0)):
        errors.append(f"pixel {x},{y}: uncovered but Z {p['Z']} normal {p['N.X'], p['N.Y'], p['N.Z']}")
if sea == 0:
    errors.append("no sea pixel")
if errors:
    sys.exit(f"{path}: {len(errors)} bad pixels, e.g. " + "; ".join(errors[:5]))
