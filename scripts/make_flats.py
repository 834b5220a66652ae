#!/usr/bin/env python3
"""Draws the built-in mission maps (ASCII, 0.1 m cells, '#' blocked):
maps/flat/home.txt (a multi-room flat with doorways) and
maps/flat/office.txt (a furnished office). Run from the repository root."""

def canvas(w, h):
    g = [['.'] * w for _ in range(h)]
    rect(g, 0, 0, w, 1); rect(g, 0, h - 1, w, 1); rect(g, 0, 0, 1, h); rect(g, w - 1, 0, 1, h)
    return g

def rect(g, x, y, w, h, c='#'):
    for yy in range(y, y + h):
        for xx in range(x, x + w):
            g[yy][xx] = c

def hwall(g, x0, x1, y, doors=()):
    rect(g, x0, y, x1 - x0, 1)
    for (dx, dw) in doors:
        rect(g, dx, y, dw, 1, '.')

def vwall(g, x, y0, y1, doors=()):
    rect(g, x, y0, 1, y1 - y0)
    for (dy, dh) in doors:
        rect(g, x, dy, 1, dh, '.')

def save(g, path):
    with open(path, 'w') as f:
        for row in g:
            f.write(''.join(row) + '\n')

# A multi-room flat, 9.6 m x 7.2 m: living room with sofa and table,
# kitchen counter, hallway, two bedrooms with beds and wardrobes, bathroom.
g = canvas(96, 72)
vwall(g, 52, 0, 72, doors=[(14, 8), (50, 8)])      # living | hallway, kitchen | hallway
hwall(g, 0, 52, 34, doors=[(20, 9)])               # living | kitchen (wide opening)
vwall(g, 64, 0, 72, doors=[(10, 8), (44, 8)])      # hallway | bedrooms
hwall(g, 64, 96, 30, doors=[])                     # bedroom 1 | bedroom 2
hwall(g, 52, 64, 58, doors=[(55, 7)])              # hallway | bathroom
rect(g, 53, 66, 4, 5)                              # bath tub
# living room
rect(g, 6, 4, 20, 8)                               # sofa
rect(g, 14, 18, 12, 7)                             # coffee table
rect(g, 40, 2, 11, 5)                              # tv cabinet
# kitchen
rect(g, 1, 62, 30, 9)                              # counter along the wall
rect(g, 20, 44, 14, 8)                             # dining table
# bedroom 1 (top right)
rect(g, 74, 1, 16, 20)                             # bed
rect(g, 92, 1, 3, 12)                              # wardrobe
# bedroom 2 (bottom right)
rect(g, 78, 52, 17, 19)                            # bed
rect(g, 65, 64, 10, 7)                             # desk
save(g, 'maps/flat/home.txt')

# A furnished office, 12 m x 8 m: three rows of desks in an open space, a
# meeting room with a table, a kitchenette, a printer island, a corridor.
g = canvas(120, 80)
vwall(g, 84, 0, 80, doors=[(10, 9), (52, 9)])      # open space | meeting / kitchen
hwall(g, 84, 120, 38, doors=[(100, 9)])            # meeting | kitchenette
rect(g, 94, 12, 18, 12)                            # meeting table
rect(g, 110, 60, 9, 19)                            # kitchen counter
rect(g, 90, 66, 8, 6)                              # kitchen table
for row in range(3):                               # desk rows (pairs of desks)
    y = 8 + row * 22
    for col in range(4):
        x = 6 + col * 19
        rect(g, x, y, 14, 7)
rect(g, 38, 72, 10, 4)                             # printer island
rect(g, 1, 1, 3, 20)                               # shelves along the wall
save(g, 'maps/flat/office.txt')
