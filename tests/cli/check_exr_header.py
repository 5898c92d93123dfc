#!/usr/bin/env python3
"""Reads an OpenEXR file's header attributes from its bytes (name, type, value: the format's own
layout, without OpenImageIO's renaming) and checks what houle render writes: no date, the frame number
and scene time, framesPerSecond, Software, and worldToCamera / worldToNDC as 4x4 float matrices that
put the camera at the origin and the point it looks at straight ahead, in the middle of the image.
Usage: check_exr_header.py FILE.exr FRAME FPS_NUM/FPS_DEN CAM_X,CAM_Y,CAM_Z LOOK_X,LOOK_Y,LOOK_Z"""
import math
import struct
import sys

path, frame, fps, cam, look = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5]
data = open(path, "rb").read()
assert data[:4] == b"\x76\x2f\x31\x01", "not an OpenEXR file"
attrs, pos = {}, 8
while data[pos] != 0:
    name_end = data.index(b"\0", pos)
    type_end = data.index(b"\0", name_end + 1)
    size = struct.unpack_from("<i", data, type_end + 1)[0]
    value = data[type_end + 5:type_end + 5 + size]
    attrs[data[pos:name_end].decode()] = (data[name_end + 1:type_end].decode(), value)
    pos = type_end + 5 + size


def need(name, kind):
    if name not in attrs or attrs[name][0] != kind:
        sys.exit(f"{path}: no {kind} attribute {name} (has {sorted(attrs)})")
    return attrs[name][1]


errors = []
if attrs.get("capDate", ("string", b""))[1] != b"":
    errors.append(f"a date: {attrs['capDate']}")
if struct.unpack("<i", need("houle:frame", "int"))[0] != frame:
    errors.append("houle:frame")
num, den = (int(v) for v in fps.split("/"))
if struct.unpack("<iI", need("framesPerSecond", "rational")) != (num, den):
    errors.append("framesPerSecond")
if abs(struct.unpack("<d", need("houle:time", "double"))[0] - frame * den / num) > 1e-9:
    errors.append("houle:time")
if not need("Software", "string").startswith(b"houle "):
    errors.append("Software")
w2c = struct.unpack("<16f", need("worldToCamera", "m44f"))
w2n = struct.unpack("<16f", need("worldToNDC", "m44f"))


def apply(m, p):  # row vector times matrix, OpenEXR's convention
    v = [sum(([*p, 1.0][i] * m[4 * i + j] for i in range(4))) for j in range(4)]
    return v


c = [float(v) for v in cam.split(",")]
a = [float(v) for v in look.split(",")]
dist = math.dist(c, a)
pc, pa = apply(w2c, c), apply(w2c, a)
if max(abs(v) for v in pc[:3]) > 1e-3 * dist:
    errors.append(f"worldToCamera takes the camera to {pc[:3]}, not the origin")
if abs(pa[0]) > 1e-4 * dist or abs(pa[1]) > 1e-4 * dist or abs(pa[2] - dist) > 1e-4 * dist:
    errors.append(f"worldToCamera takes the look-at point to {pa[:3]}, not (0, 0, {dist})")
na = apply(w2n, a)
if abs(na[0] / na[3] - 0.5) > 1e-5 or abs(na[1] / na[3] - 0.5) > 1e-5:
    errors.append(f"worldToNDC takes the look-at point to {na[0] / na[3]}, {na[1] / na[3]}, not the centre")
# A point above the look-at point is higher in the image (NDC y grows downwards), one to the camera's
# right further right.
up = apply(w2n, [a[0], a[1], a[2] + 1.0])
if not up[1] / up[3] < 0.5:
    errors.append("worldToNDC: y does not grow downwards")
if errors:
    sys.exit(f"{path}: " + "; ".join(errors))
