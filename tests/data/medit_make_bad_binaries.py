#!/usr/bin/env python3
"""Writes the broken Medit binary files of tests/data/bad (run from tests/data).

Layout of a .meshb / .solb version 2 file (little endian): int32 code 1,
int32 version, then keywords: int32 code, int32 position of the next keyword,
int32 count (most keywords), data (int32 ids, float64 reals)."""
import struct


def i32(*v):
    return struct.pack("<%di" % len(v), *v)


def f64(*v):
    return struct.pack("<%dd" % len(v), *v)


def header(version=2, dim=3):
    return i32(1, version, 3, 20, dim)


def keyword(code, count, data, start, nxt=None):
    body = i32(count) + data
    if nxt is None:
        nxt = start + 8 + len(body)
    return i32(code, nxt) + body


def vertices(pts):
    return b"".join(f64(*p) + i32(0) for p in pts)


def triangles(tris):
    return b"".join(i32(a, b, c, 0) for a, b, c in tris)


PTS = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]


def mesh(pts=PTS, tris=((1, 2, 3),), vnext=None):
    out = header()
    out += keyword(4, len(pts), vertices(pts), len(out), vnext)
    out += keyword(6, len(tris), triangles(tris), len(out))
    return out + i32(54, 0)


def write(name, data):
    with open("bad/" + name, "wb") as f:
        f.write(data)


# Vertices announces 4 vertices (28 bytes each, from byte 32): cut after 2.
write("bad_meshb_truncated.meshb", mesh()[: 32 + 2 * 28])
# Wrong endianness code (2 instead of 1).
write("bad_meshb_magic.meshb", i32(2) + mesh()[4:])
# Unsupported version 9.
write("bad_meshb_version.meshb", i32(1, 9) + mesh()[8:])
# The Vertices keyword's next position points past the end of the file.
write("bad_meshb_next_past_end.meshb", mesh(vnext=100000))
# Two unknown keywords (code 200) whose next positions form a loop 20 -> 36 -> 20.
write("bad_meshb_next_loop.meshb", header() + i32(200, 36, 7, 0) + i32(200, 20, 7, 0) + i32(54, 0))
# A triangle refers to vertex 9 of 4.
write("bad_meshb_index_range.meshb", mesh(tris=((1, 2, 3), (2, 9, 4))))
# A NaN coordinate.
write("bad_meshb_nan.meshb", mesh(pts=[(0, 0, 0), (1, float("nan"), 0), (0, 1, 0), (0, 0, 1)]))
# A .solb whose SolAtVertices announces 10 scalars but holds 3.
sol = header() + i32(62, 0, 10, 1, 1) + f64(1, 2, 3)
write("bad_sol_truncated.solb", sol)
