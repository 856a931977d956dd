#!/usr/bin/env python3
"""Writes a synthetic OpenStreetMap XML extract of any size, for tests and measurements of
`lacet import` (issue 23: an extract made at test time, never stored).

The extract covers `--blocks` x `--blocks` blocks of about 400 m near (--lon, --lat):
  - a grid of roads along the block edges, each way three blocks long with a point every ~40 m,
    sharing its OSM nodes with the roads it crosses (junctions) and where it continues the next
    way; primary, tertiary and residential, each with a name;
  - a meandering river across every fifth row of blocks (sharing no node with the roads), and a
    riverbank polygon (natural=water, water=river) along its first two blocks;
  - in most other blocks a closed way: a lake, a field (landuse=farmland), a meadow or a forest.
Coordinates are jittered by a generator seeded with --seed: the same arguments give the same file.
The file is streamed, so any size can be written in constant memory.

  scripts/synthetic_osm.py --blocks 20 --seed 1 --out small.osm
"""
import argparse
import math
import random
import sys


class Writer:
    def __init__(self, out, seed):
        self.out = out
        self.next_node = 1
        self.next_way = 1
        # Ids with gaps, as a real extract's are: a way's references then do not differ by one, and
        # a PBF of the extract compresses as real data does (GDAL refuses a block compressed more
        # than 100 times). Their own generator, so the points are the same as without gaps.
        self.gaps = random.Random(seed * 7919 + 1)

    def node(self, lon, lat):
        i = self.next_node
        self.next_node += 1 + self.gaps.randrange(16)
        self.out.write(f'  <node id="{i}" lat="{lat:.7f}" lon="{lon:.7f}" version="1"/>\n')
        return i

    def way(self, refs, tags):
        i = self.next_way
        self.next_way += 1
        self.out.write(f'  <way id="{i}" version="1">\n')
        for r in refs:
            self.out.write(f'    <nd ref="{r}"/>\n')
        for k, v in tags.items():
            self.out.write(f'    <tag k="{k}" v="{v}"/>\n')
        self.out.write('  </way>\n')


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('--blocks', type=int, default=20, help='blocks a side (about 400 m each)')
    p.add_argument('--seed', type=int, default=1)
    p.add_argument('--lon', type=float, default=5.0)
    p.add_argument('--lat', type=float, default=45.0)
    p.add_argument('--out', required=True)
    a = p.parse_args()
    if a.blocks < 1:
        sys.exit('synthetic_osm.py: --blocks must be at least 1')
    rng = random.Random(a.seed)
    block = 400.0  # metres
    step = 40.0    # metres between the points of a way
    per = int(block / step)
    dlat = 1.0 / 111320.0
    dlon = 1.0 / (111320.0 * math.cos(math.radians(a.lat)))
    n = a.blocks

    def lonlat(x, y):
        return a.lon + x * dlon, a.lat + y * dlat

    def jitter():
        return rng.uniform(-4.0, 4.0)

    with open(a.out, 'w') as out:
        out.write('<?xml version="1.0" encoding="UTF-8"?>\n<osm version="0.6" generator="lacet scripts/synthetic_osm.py">\n')
        w = Writer(out, a.seed)
        # Nodes first (the OSM format's order): the grid's junctions and the points between them.
        junction = {}
        for j in range(n + 1):
            for i in range(n + 1):
                junction[i, j] = w.node(*lonlat(i * block + jitter(), j * block + jitter()))
        east = {}   # (i, j) -> the points between junction (i, j) and (i + 1, j)
        north = {}  # (i, j) -> between (i, j) and (i, j + 1)
        for j in range(n + 1):
            for i in range(n + 1):
                if i < n:
                    east[i, j] = [w.node(*lonlat(i * block + k * step + jitter(), j * block + jitter())) for k in range(1, per)]
                if j < n:
                    north[i, j] = [w.node(*lonlat(i * block + jitter(), j * block + k * step + jitter())) for k in range(1, per)]
        # Rivers: every fifth row, meandering between the roads (no node shared with them).
        rivers = []
        for j in range(2, n, 5):
            y0 = j * block + block / 2
            pts = []
            for k in range(n * per + 1):
                x = k * step
                pts.append(w.node(*lonlat(x, y0 + 60.0 * math.sin(x / 300.0) + jitter() * 0.5)))
            rivers.append((j, pts))
        # Areas inside blocks (a ring 60 m inside the block's edges, 12 points), most blocks.
        areas = []
        for j in range(n):
            for i in range(n):
                if any(j == rj for rj, _ in rivers):
                    continue
                kind = rng.randrange(5)
                if kind == 4:
                    continue
                cx, cy = i * block + block / 2, j * block + block / 2
                r = block / 2 - 60.0
                ring = [w.node(*lonlat(cx + r * math.cos(t * math.pi / 6) + jitter(), cy + r * math.sin(t * math.pi / 6) + jitter()))
                        for t in range(12)]
                areas.append((kind, ring))
        # Riverbanks: a polygon along the first blocks of each river.
        banks = []
        for rj, _ in rivers:
            y0 = rj * block + block / 2
            top = [w.node(*lonlat(k * step, y0 + 120.0)) for k in range(0, 2 * per + 1)]
            bottom = [w.node(*lonlat(k * step, y0 - 120.0)) for k in reversed(range(0, 2 * per + 1))]
            banks.append(top + bottom)
        # Ways: roads three blocks long along each grid line, east-west then north-south.
        names = 0
        for j in range(n + 1):
            for i0 in range(0, n, 3):
                refs = [junction[i0, j]]
                for i in range(i0, min(i0 + 3, n)):
                    refs += east[i, j] + [junction[i + 1, j]]
                names += 1
                w.way(refs, {'highway': 'primary' if j % 4 == 0 else 'residential', 'name': f'Rue {names}'})
        for i in range(n + 1):
            for j0 in range(0, n, 3):
                refs = [junction[i, j0]]
                for j in range(j0, min(j0 + 3, n)):
                    refs += north[i, j] + [junction[i, j + 1]]
                names += 1
                w.way(refs, {'highway': 'tertiary' if i % 3 == 0 else 'residential', 'name': f'Avenue {names}'})
        for rj, pts in rivers:
            w.way(pts, {'waterway': 'river', 'name': f'River {rj}'})
        tags = [{'natural': 'water'}, {'landuse': 'farmland'}, {'landuse': 'meadow'}, {'landuse': 'forest'}]
        for kind, ring in areas:
            w.way(ring + [ring[0]], tags[kind])
        for ring in banks:
            w.way(ring + [ring[0]], {'natural': 'water', 'water': 'river'})
        out.write('</osm>\n')


if __name__ == '__main__':
    main()
