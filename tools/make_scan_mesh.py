#!/usr/bin/env python3
"""Writes scan-like stress meshes for the smoothest-field solver (issue 17).

    tools/make_scan_mesh.py IN.off OUT.off [--faces 100000] [--noise 0.3]
                            [--slivers 0.3] [--thin 0.15] [--seed 1]

From a clean mesh (e.g. data/meshes/bunny00.off) it makes what 3D scans look
like and CGAL's sample meshes do not:
  * large: midpoint subdivision (each triangle into four) until at least
    --faces triangles;
  * very uneven triangles: a fraction --slivers of the triangles is split 1-to-3
    at a point close to one of its edges, leaving needles next to normal ones;
  * noisy: every vertex moves along its normal by Gaussian noise of --noise
    times the mean edge length around it;
  * thin parts: the vertices in the top --thin fraction along the longest axis
    are pressed toward their mean in the shortest axis (to 5 %), a thin sheet
    like a scanned ear or fin.
Standard library only; deterministic for a given --seed. Writes ASCII OFF.
"""
import argparse
import math
import random
import sys


def read_off(path):
    with open(path) as f:
        tokens = [t for line in f for t in line.split('#', 1)[0].split()]
    if not tokens[0].endswith('OFF'):
        sys.exit(f'{path}: not an OFF file')
    nv, nf = int(tokens[1]), int(tokens[2])
    pos, i = [], 4
    for _ in range(nv):
        pos.append([float(tokens[i]), float(tokens[i + 1]), float(tokens[i + 2])])
        i += 3
    faces = []
    for _ in range(nf):
        n = int(tokens[i])
        poly = [int(t) for t in tokens[i + 1:i + 1 + n]]
        i += 1 + n
        for k in range(1, n - 1):
            faces.append((poly[0], poly[k], poly[k + 1]))
    return pos, faces


def subdivide(pos, faces):
    mid = {}

    def midpoint(a, b):
        key = (a, b) if a < b else (b, a)
        if key not in mid:
            pa, pb = pos[a], pos[b]
            pos.append([(pa[k] + pb[k]) / 2 for k in range(3)])
            mid[key] = len(pos) - 1
        return mid[key]

    out = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return out


def sliver_split(pos, faces, fraction, rng):
    out = []
    for a, b, c in faces:
        if rng.random() >= fraction:
            out.append((a, b, c))
            continue
        # A point 1-3 % away from edge (a, b): two needles and one ordinary triangle.
        t, s = rng.uniform(0.2, 0.8), rng.uniform(0.01, 0.03)
        p = [pos[a][k] * (1 - t) * (1 - s) + pos[b][k] * t * (1 - s) + pos[c][k] * s for k in range(3)]
        pos.append(p)
        m = len(pos) - 1
        out += [(a, b, m), (b, c, m), (c, a, m)]
    return out


def sub(p, q):
    return [p[0] - q[0], p[1] - q[1], p[2] - q[2]]


def cross(u, v):
    return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]


def add_noise(pos, faces, amount, rng):
    normal = [[0.0, 0.0, 0.0] for _ in pos]
    edge_sum = [0.0] * len(pos)
    edge_n = [0] * len(pos)
    for a, b, c in faces:
        n = cross(sub(pos[b], pos[a]), sub(pos[c], pos[a]))
        for v in (a, b, c):
            for k in range(3):
                normal[v][k] += n[k]
        for u, v in ((a, b), (b, c), (c, a)):
            length = math.dist(pos[u], pos[v])
            edge_sum[u] += length
            edge_sum[v] += length
            edge_n[u] += 1
            edge_n[v] += 1
    for v, p in enumerate(pos):
        if not edge_n[v]:
            continue
        norm = math.sqrt(sum(x * x for x in normal[v])) or 1.0
        d = rng.gauss(0.0, amount * edge_sum[v] / edge_n[v])
        for k in range(3):
            p[k] += d * normal[v][k] / norm


def thin_out(pos, fraction):
    lo = [min(p[k] for p in pos) for k in range(3)]
    hi = [max(p[k] for p in pos) for k in range(3)]
    ext = [hi[k] - lo[k] for k in range(3)]
    longest, shortest = ext.index(max(ext)), ext.index(min(ext))
    cut = hi[longest] - fraction * ext[longest]
    part = [p for p in pos if p[longest] > cut]
    if not part:
        return
    mean = sum(p[shortest] for p in part) / len(part)
    for p in part:
        p[shortest] = mean + 0.05 * (p[shortest] - mean)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('input')
    ap.add_argument('output')
    ap.add_argument('--faces', type=int, default=100000)
    ap.add_argument('--noise', type=float, default=0.3)
    ap.add_argument('--slivers', type=float, default=0.3)
    ap.add_argument('--thin', type=float, default=0.15)
    ap.add_argument('--seed', type=int, default=1)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    pos, faces = read_off(args.input)
    while len(faces) < args.faces:
        faces = subdivide(pos, faces)
    if args.thin > 0:
        thin_out(pos, args.thin)
    faces = sliver_split(pos, faces, args.slivers, rng)
    add_noise(pos, faces, args.noise, rng)
    with open(args.output, 'w') as f:
        f.write(f'OFF\n{len(pos)} {len(faces)} 0\n')
        f.writelines(f'{p[0]:.9g} {p[1]:.9g} {p[2]:.9g}\n' for p in pos)
        f.writelines(f'3 {a} {b} {c}\n' for a, b, c in faces)
    print(f'{args.output}: {len(pos)} vertices, {len(faces)} faces', file=sys.stderr)


if __name__ == '__main__':
    main()
