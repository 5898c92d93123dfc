#!/usr/bin/env python3
"""Checks that PNG files are complete: signature, WIDTHxHEIGHT 8-bit RGB, image data that inflates
to the full size, and the closing IEND chunk. Usage: check_png.py WIDTH HEIGHT FILE..."""
import struct
import sys
import zlib

w, h = int(sys.argv[1]), int(sys.argv[2])
bad = []
for path in sys.argv[3:]:
    with open(path, "rb") as f:
        data = f.read()
    try:
        assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
        pos, idat, chunks = 8, b"", []
        while pos < len(data):
            length, kind = struct.unpack(">I4s", data[pos:pos + 8])
            body = data[pos + 8:pos + 8 + length]
            assert len(body) == length, "truncated chunk"
            chunks.append(kind)
            if kind == b"IHDR":
                assert struct.unpack(">IIBB", body[:10]) == (w, h, 8, 2), f"not {w}x{h} 8-bit RGB"
            elif kind == b"IDAT":
                idat += body
            pos += 12 + length
        assert chunks[0] == b"IHDR" and chunks[-1] == b"IEND", "no IHDR or IEND"
        assert len(zlib.decompress(idat)) == h * (1 + 3 * w), "short image data"
    except (AssertionError, struct.error, zlib.error, IndexError) as e:
        bad.append(f"{path}: {e}")
if bad:
    sys.exit("\n".join(bad))
print(f"{len(sys.argv) - 3} complete PNG files")
