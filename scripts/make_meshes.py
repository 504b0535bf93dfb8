#!/usr/bin/python3
"""Writes the shipped meshes (binary STL, metres, counter-clockwise seen from outside):

  meshes/seabed.stl  a gently rolling seabed heightfield around z = -20 m, 40 m x 40 m, 1 m cells
                     (3,200 triangles), front side up;
  meshes/wreck.stl   a closed hull-like shape 6 m long (x), 2 m wide, 1.5 m deep, keel down, deck up,
                     centred on its own origin, outward normals.

Plain python (no numpy). Run from anywhere: scripts/make_meshes.py [output folder]
"""
import math
import pathlib
import struct
import sys


def write_stl(path, triangles, header):
    """Binary STL: an 80-byte header, the count, then per triangle its unit normal (from the winding),
    its three corners (float32) and a zero attribute."""
    with open(path, "wb") as out:
        out.write(header.encode()[:80].ljust(80, b" "))
        out.write(struct.pack("<I", len(triangles)))
        for a, b, c in triangles:
            u = [b[i] - a[i] for i in range(3)]
            v = [c[i] - a[i] for i in range(3)]
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            length = math.sqrt(sum(x * x for x in n))
            n = [x / length for x in n]
            out.write(struct.pack("<12fH", *n, *a, *b, *c, 0))


def seabed_height(x, y):
    """Depth of the seabed [m]: -20 m with swells of at most 0.8 m, slopes below 0.3."""
    return -20.0 + 0.5 * math.sin(2 * math.pi * x / 17.0) * math.cos(2 * math.pi * y / 13.0) + 0.3 * math.sin(
        2 * math.pi * (x + 0.5 * y) / 9.0)


def seabed(half_width=20.0, cell=1.0):
    n = int(round(2 * half_width / cell))
    point = [[(-half_width + i * cell, -half_width + j * cell,
               seabed_height(-half_width + i * cell, -half_width + j * cell)) for j in range(n + 1)]
             for i in range(n + 1)]
    triangles = []
    for i in range(n):
        for j in range(n):
            p00, p10, p01, p11 = point[i][j], point[i + 1][j], point[i][j + 1], point[i + 1][j + 1]
            # Counter-clockwise seen from above: the front side is up.
            triangles.append((p00, p10, p11))
            triangles.append((p00, p11, p01))
    return triangles


def wreck(length=6.0, beam=2.0, depth=1.5, deck=0.4, stations=24, ring=24):
    """A lofted hull: stations along x, each an oval ring (half-ellipse keel of `depth` below, a low
    half-ellipse deck of `deck` above), narrowing toward bow and stern; the two end rings are closed by fans
    to their centres."""
    rings = []
    for s in range(stations + 1):
        x = -0.5 * length + length * s / stations
        taper = 0.25 + 0.75 * math.sqrt(max(0.0, 1.0 - (2.0 * x / (1.02 * length)) ** 2))
        section = []
        for k in range(ring):
            theta = 2 * math.pi * k / ring  # from +y, through +z (deck), -y, -z (keel)
            y = 0.5 * beam * taper * math.cos(theta)
            z = (deck if math.sin(theta) > 0 else depth) * taper * math.sin(theta)
            section.append((x, y, z))
        rings.append(section)
    triangles = []
    for s in range(stations):
        for k in range(ring):
            a, b = rings[s][k], rings[s][(k + 1) % ring]
            c, d = rings[s + 1][k], rings[s + 1][(k + 1) % ring]
            # theta grows counter-clockwise seen from +x, stations along +x: (c - a) x (d - a) points in,
            # so outward is (a, d, c).
            triangles.append((a, d, c))
            triangles.append((a, b, d))
    for s, facing in ((0, -1), (stations, 1)):
        centre = (rings[s][0][0], 0.0, sum(p[2] for p in rings[s]) / ring)
        for k in range(ring):
            a, b = rings[s][k], rings[s][(k + 1) % ring]
            # Seen from +x the ring runs counter-clockwise: the bow cap (+x) is (centre, a, b).
            triangles.append((centre, a, b) if facing > 0 else (centre, b, a))
    return triangles


def signed_volume(triangles):
    """Divergence theorem: positive for a closed surface with outward normals."""
    return sum((a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] *
                (b[0] * c[1] - b[1] * c[0])) / 6.0 for a, b, c in triangles)


def main():
    folder = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent / "meshes"
    folder.mkdir(parents=True, exist_ok=True)
    bed = seabed()
    write_stl(folder / "seabed.stl", bed, "rov_tether seabed: 40 m x 40 m around z = -20 m, up is front")
    hull = wreck()
    volume = signed_volume(hull)
    assert volume > 0.0, "wreck normals point inward"
    write_stl(folder / "wreck.stl", hull, "rov_tether wreck: 6 m hull, outward normals")
    print(f"{folder / 'seabed.stl'}: {len(bed)} triangles")
    print(f"{folder / 'wreck.stl'}: {len(hull)} triangles, enclosed volume {volume:.2f} m^3")


if __name__ == "__main__":
    main()
