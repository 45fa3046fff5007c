#!/usr/bin/env python3
"""Writes spot_tets.node/.ele: Spot (spot.obj, Keenan Crane, CC0) simplified to 1,400
triangles and tetrahedralized by the external TetGen program with -p only (no quality bound),
as a user with Debian's `tetgen` package would: a real shape with real slivers (58 tets of
quality 6*sqrt(2)*V/Lmax^3 below 0.01). Run from this folder: python3 make_spot_tets.py
(needs `tetgen` on PATH; the shipped files do not). TetGen is only run, never linked."""
import heapq
import math
import os
import subprocess
import tempfile

TARGET_TRIANGLES = 1400


def read_obj(path):
    verts, faces = [], []
    for line in open(path):
        s = line.split()
        if s and s[0] == "v":
            verts.append([float(x) for x in s[1:4]])
        elif s and s[0] == "f":
            faces.append([int(x.split("/")[0]) - 1 for x in s[1:4]])
    return verts, faces


def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def simplify(verts, faces, target):
    """Collapses the shortest edge to its midpoint until `target` triangles are left. An edge
    collapses only when the surface stays a closed manifold (the two ends share exactly the two
    opposite vertices: the link condition) and no other triangle turns by more than 60 degrees."""
    alive = [True] * len(faces)
    around = [set() for _ in verts]
    for i, f in enumerate(faces):
        for v in f:
            around[v].add(i)

    def neighbours(v):
        return {u for fi in around[v] for u in faces[fi]} - {v}

    def length(a, b):
        d = sub(verts[a], verts[b])
        return math.sqrt(dot(d, d))

    heap = [(length(f[k], f[(k + 1) % 3]), f[k], f[(k + 1) % 3]) for f in faces for k in range(3) if f[k] < f[(k + 1) % 3]]
    heapq.heapify(heap)
    count = len(faces)
    while count > target and heap:
        edge, a, b = heapq.heappop(heap)
        if not around[a] or not around[b] or b not in neighbours(a) or abs(length(a, b) - edge) > 1e-12:
            continue  # a stale entry
        shared = around[a] & around[b]
        opposite = {u for fi in shared for u in faces[fi]} - {a, b}
        if len(shared) != 2 or neighbours(a) & neighbours(b) != opposite:
            continue
        mid = [(verts[a][i] + verts[b][i]) / 2 for i in range(3)]
        turned = False
        for fi in (around[a] | around[b]) - shared:
            f = faces[fi]
            p = [mid if v in (a, b) else verts[v] for v in f]
            n0 = cross(sub(verts[f[1]], verts[f[0]]), sub(verts[f[2]], verts[f[0]]))
            n1 = cross(sub(p[1], p[0]), sub(p[2], p[0]))
            l0, l1 = math.sqrt(dot(n0, n0)), math.sqrt(dot(n1, n1))
            if l1 < 1e-12 or dot(n0, n1) < 0.5 * l0 * l1:
                turned = True
                break
        if turned:
            continue
        verts[a] = mid
        for fi in shared:
            alive[fi] = False
            for v in faces[fi]:
                around[v].discard(fi)
        for fi in list(around[b]):
            faces[fi] = [a if v == b else v for v in faces[fi]]
            around[a].add(fi)
        around[b] = set()
        count -= 2
        for u in neighbours(a):
            heapq.heappush(heap, (length(a, u), min(a, u), max(a, u)))
    kept = [f for i, f in enumerate(faces) if alive[i]]
    used = sorted({v for f in kept for v in f})
    index = {v: i for i, v in enumerate(used)}
    return [verts[v] for v in used], [[index[v] for v in f] for f in kept]


def main():
    verts, faces = simplify(*read_obj("spot.obj"), TARGET_TRIANGLES)
    with tempfile.TemporaryDirectory() as tmp:
        smesh = os.path.join(tmp, "spot.smesh")
        with open(smesh, "w") as out:
            out.write(f"{len(verts)} 3 0 0\n")
            for i, v in enumerate(verts):
                out.write("%d %.6f %.6f %.6f\n" % (i, *v))
            out.write(f"{len(faces)} 0\n")
            for f in faces:
                out.write("3 %d %d %d\n" % tuple(f))
            out.write("0\n0\n")
        subprocess.run(["tetgen", "-pQ", smesh], check=True)
        for ext in ("node", "ele"):
            os.replace(os.path.join(tmp, "spot.1." + ext), "spot_tets." + ext)


if __name__ == "__main__":
    main()
