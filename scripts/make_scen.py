#!/usr/bin/env python3
"""Make MovingAI-format test maps and .scen files with independently computed optima.

This is deliberately a separate implementation from the Rust core: a float
Dijkstra (heapq) on the 8-connected grid with costs 1 and sqrt(2) and no
corner cutting (a diagonal step needs both orthogonal neighbours passable),
which is the MovingAI convention. Outputs go to maps/movingai/.

Usage: python3 scripts/make_scen.py [--eightroom PATH_TO_8room_001.map]
       python3 scripts/make_scen.py --maze512   (only maze512.map, its own seed)
"""
import heapq, math, random, sys, os

OUT = os.path.join(os.path.dirname(__file__), '..', 'maps', 'movingai')
SQ2 = math.sqrt(2.0)


def write_map(name, rows):
    h, w = len(rows), len(rows[0])
    with open(os.path.join(OUT, name), 'w') as f:
        f.write(f"type octile\nheight {h}\nwidth {w}\nmap\n")
        for r in rows:
            f.write(''.join(r) + "\n")


def read_map(path):
    with open(path) as f:
        lines = f.read().splitlines()
    h = int(lines[1].split()[1]); w = int(lines[2].split()[1])
    return [list(l[:w]) for l in lines[4:4 + h]]


def passable(rows, x, y):
    return 0 <= y < len(rows) and 0 <= x < len(rows[0]) and rows[y][x] in '.G'


def dijkstra(rows, sx, sy):
    h, w = len(rows), len(rows[0])
    dist = {(sx, sy): 0.0}
    pq = [(0.0, sx, sy)]
    done = set()
    while pq:
        d, x, y = heapq.heappop(pq)
        if (x, y) in done:
            continue
        done.add((x, y))
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                if dx == 0 and dy == 0:
                    continue
                nx, ny = x + dx, y + dy
                if not passable(rows, nx, ny):
                    continue
                if dx and dy and not (passable(rows, x + dx, y) and passable(rows, x, y + dy)):
                    continue
                nd = d + (SQ2 if dx and dy else 1.0)
                if nd < dist.get((nx, ny), math.inf) - 1e-12:
                    dist[(nx, ny)] = nd
                    heapq.heappush(pq, (nd, nx, ny))
    return dist


def make_scen(name, rows, rng, starts, goals_per_start):
    h, w = len(rows), len(rows[0])
    free = [(x, y) for y in range(h) for x in range(w) if passable(rows, x, y)]
    probs = []
    for _ in range(starts):
        sx, sy = rng.choice(free)
        dist = dijkstra(rows, sx, sy)
        reach = [p for p in dist if p != (sx, sy)]
        for (gx, gy) in rng.sample(reach, min(goals_per_start, len(reach))):
            d = dist[(gx, gy)]
            probs.append((int(d // 4), sx, sy, gx, gy, d))
    probs.sort()
    with open(os.path.join(OUT, name + '.scen'), 'w') as f:
        f.write("version 1\n")
        for b, sx, sy, gx, gy, d in probs:
            f.write(f"{b}\t{name}\t{w}\t{h}\t{sx}\t{sy}\t{gx}\t{gy}\t{d:.8f}\n")
    print(f"{name}: {w}x{h}, {len(probs)} problems")


def rooms(rng, w=64, h=64, room=12):
    rows = [['.'] * w for _ in range(h)]
    for y in range(h):
        for x in range(w):
            if x % room == 0 or y % room == 0 or x == w - 1 or y == h - 1:
                rows[y][x] = '@'
    # doors in every wall segment, 1-3 cells wide
    for y in range(0, h, room):
        for x0 in range(0, w - 1, room):
            if 0 < y < h - 1:
                dw = rng.randint(1, 3); dx = rng.randint(x0 + 1, max(x0 + 1, x0 + room - dw - 1))
                for x in range(dx, min(dx + dw, w - 1)):
                    rows[y][x] = '.'
    for x in range(0, w, room):
        for y0 in range(0, h - 1, room):
            if 0 < x < w - 1:
                dh = rng.randint(1, 3); dy = rng.randint(y0 + 1, max(y0 + 1, y0 + room - dh - 1))
                for y in range(dy, min(dy + dh, h - 1)):
                    rows[y][x] = '.'
    # furniture
    for _ in range(40):
        x, y = rng.randrange(1, w - 3), rng.randrange(1, h - 3)
        for yy in range(y, y + rng.randint(1, 2)):
            for xx in range(x, x + rng.randint(1, 3)):
                rows[yy][xx] = 'T'
    return rows


def corridors(rng, w=49, h=49):
    # a maze of one-cell corridors (recursive backtracker), plus some loops
    rows = [['@'] * w for _ in range(h)]
    stack = [(1, 1)]; rows[1][1] = '.'
    while stack:
        x, y = stack[-1]
        nbrs = [(x + dx, y + dy, dx, dy) for dx, dy in ((2, 0), (-2, 0), (0, 2), (0, -2))
                if 0 < x + dx < w - 1 and 0 < y + dy < h - 1 and rows[y + dy][x + dx] == '@']
        if not nbrs:
            stack.pop(); continue
        nx, ny, dx, dy = rng.choice(nbrs)
        rows[y + dy // 2][x + dx // 2] = '.'; rows[ny][nx] = '.'
        stack.append((nx, ny))
    for _ in range(60):
        x, y = rng.randrange(1, w - 1), rng.randrange(1, h - 1)
        rows[y][x] = '.'
    return rows


def open_area(rng, w=96, h=72):
    rows = [['.'] * w for _ in range(h)]
    for _ in range(180):
        x, y = rng.randrange(0, w), rng.randrange(0, h)
        for yy in range(y, min(h, y + rng.randint(1, 4))):
            for xx in range(x, min(w, x + rng.randint(1, 4))):
                rows[yy][xx] = '@'
    # swamp/water/tree characters are blocked in our loader too
    for _ in range(30):
        rows[rng.randrange(h)][rng.randrange(w)] = rng.choice('TWS')
    return rows


def maze512():
    """A 512 x 512 maze of one-cell corridors, the size and corridor width
    of the Moving AI Lab's maze512-1-* maps, with its own seed so that the
    other maps stay as they are."""
    rng = random.Random(512)
    rows = corridors(rng, w=511, h=511)
    for r in rows:
        r.append('@')
    rows.append(['@'] * 512)
    write_map('maze512.map', rows)
    make_scen('maze512.map', rows, rng, 30, 10)


def main():
    os.makedirs(OUT, exist_ok=True)
    if sys.argv[1:] == ['--maze512']:
        maze512()
        return
    rng = random.Random(2026)
    for name, gen, starts, per in (('rooms64.map', rooms, 20, 10),
                                   ('maze49.map', corridors, 20, 10),
                                   ('open96x72.map', open_area, 20, 10)):
        rows = gen(rng)
        write_map(name, rows)
        make_scen(name, rows, rng, starts, per)
    if len(sys.argv) > 2 and sys.argv[1] == '--eightroom':
        rows = read_map(sys.argv[2])
        make_scen('8room_001.map', rows, rng, 30, 10)


if __name__ == '__main__':
    main()
