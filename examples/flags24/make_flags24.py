#!/usr/bin/env python3
"""Writes flags24.obj (24 flags in one OBJ), stiffness.png (flag k's block of grey rising with k) and the pins
list of flags24.xml. Run from this folder: python3 make_flags24.py. Standard library only."""
import struct
import zlib

FLAGS, COLS = 24, 6            # flags, laid out 6 across and 4 down
NX, NY = 7, 5                  # vertices along a flag's width and height
W, H = 0.6, 0.4                # flag size, m
BLOCK = 16                     # texels per flag in the stiffness map
INSET = 0.05                   # flag k's u spans [(k + INSET)/24, (k + 1 - INSET)/24]: inside its own block


def grey(k):
    return round(255 * k / (FLAGS - 1))


def write_obj(path):
    lines = ["# 24 flags, one connected piece each; flag k uses vertices k*35 .. k*35+34 (0-based)"]
    uvs, faces = [], []
    for k in range(FLAGS):
        x0, y0 = (k % COLS) * 1.0, -(k // COLS) * 0.8
        u0, u1 = (k + INSET) / FLAGS, (k + 1 - INSET) / FLAGS
        for j in range(NY):
            for i in range(NX):
                lines.append("v %.6g %.6g 0" % (x0 + W * i / (NX - 1), y0 + H * j / (NY - 1)))
                uvs.append("vt %.6g %.6g" % (u0 + (u1 - u0) * i / (NX - 1), 0.25 + 0.5 * j / (NY - 1)))
        base = k * NX * NY + 1
        for j in range(NY - 1):
            for i in range(NX - 1):
                a = base + j * NX + i
                b, c, d = a + 1, a + NX, a + NX + 1
                faces.append("f %d/%d %d/%d %d/%d" % (a, a, b, b, d, d))
                faces.append("f %d/%d %d/%d %d/%d" % (a, a, d, d, c, c))
    with open(path, "w") as f:
        f.write("\n".join(lines + uvs + faces) + "\n")


def write_png(path, width, height, rows):
    raw = b"".join(b"\0" + bytes(r) for r in rows)
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def pins():
    # The pole side: the i = 0 column of every flag.
    return " ".join(str(k * NX * NY + j * NX) for k in range(FLAGS) for j in range(NY))


if __name__ == "__main__":
    write_obj("flags24.obj")
    row = [grey(t // BLOCK) for t in range(FLAGS * BLOCK)]
    write_png("stiffness.png", FLAGS * BLOCK, 2, [row, row])
    print(pins())
