"""Vertex-group weights baked into the grey-scale maps clothsim reads (docs/maps.md). No bpy here.

clothsim samples a map at each vertex's UV, bilinearly between texel centres, and averages a vertex's distinct
UVs (docs/maps.md, "Seams"). So every distinct UV of a vertex gets the 2 x 2 texels around it set to the
vertex's weight: the bilinear sample there is the weight exactly (to the 16-bit grey step, 1.5e-5). The image
is square, from 64 up to 4096 texels: the smallest at which no texel is claimed by two vertices.
"""
import struct
import zlib

import numpy as np

MIN_SIDE, MAX_SIDE = 64, 4096


def write_png_grey16(path, grey):
    """grey: (h, w) array of 0..65535, written as a 16-bit grey-scale PNG (standard library zlib only)."""
    h, w = grey.shape
    rows = np.zeros((h, 1 + 2 * w), dtype=np.uint8)  # filter byte 0, then big-endian samples
    rows[:, 1:] = np.ascontiguousarray(grey.astype(">u2")).view(np.uint8).reshape(h, 2 * w)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(rows.tobytes(), 6)))
        f.write(chunk(b"IEND", b""))


def blocks(corner_uv, side):
    """Row and column of the 2 x 2 texels around each UV: (c, 4) each."""
    x = np.clip(corner_uv[:, 0], 0.0, 1.0) * side - 0.5
    y = (1.0 - np.clip(corner_uv[:, 1], 0.0, 1.0)) * side - 0.5
    i0, j0 = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    cols = np.clip(np.column_stack([i0, i0 + 1, i0, i0 + 1]), 0, side - 1)
    rows = np.clip(np.column_stack([j0, j0, j0 + 1, j0 + 1]), 0, side - 1)
    return rows, cols


def side_for(corner_vertex, corner_uv):
    """The smallest side (a power of two from MIN_SIDE) at which no texel is claimed by two vertices."""
    side = MIN_SIDE
    while side < MAX_SIDE:
        rows, cols = blocks(corner_uv, side)
        texel = (rows * side + cols).ravel()
        owner = np.repeat(corner_vertex, 4)
        pairs = np.unique(np.column_stack([texel, owner]), axis=0)
        if len(np.unique(pairs[:, 0])) == len(pairs):
            break
        side *= 2
    return side


def bake_weights(path, weights, corner_vertex, corner_uv):
    """Writes the map whose bilinear samples at each vertex's UVs are its weight (0..1).
    weights: (n,) per vertex; corner_vertex: (c,) vertex of each face corner; corner_uv: (c, 2)."""
    weights = np.clip(np.asarray(weights, dtype=np.float64), 0.0, 1.0)
    corner_vertex = np.asarray(corner_vertex, dtype=np.int64)
    corner_uv = np.asarray(corner_uv, dtype=np.float64)
    side = side_for(corner_vertex, corner_uv)
    grey = np.zeros((side, side), dtype=np.float64)
    rows, cols = blocks(corner_uv, side)
    grey[rows.ravel(), cols.ravel()] = np.repeat(weights[corner_vertex], 4)
    write_png_grey16(path, np.rint(grey * 65535))
    return side
