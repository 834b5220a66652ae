#!/usr/bin/env python3
"""Flash and static-RAM report for a firmware ELF (no binutils needed).

Flash = the allocated sections stored in flash (vector table, text, rodata,
and the initial values of .data); static RAM = .data + .bss + .uninit. The
stack grows down from the top of RAM into what is left.
Usage: size_report.py ELF [RAM_BYTES]"""
import struct, sys

path = sys.argv[1]
ram_total = int(sys.argv[2]) if len(sys.argv) > 2 else 128 * 1024
f = open(path, 'rb').read()
if f[:4] != b'\x7fELF' or f[4] != 1:
    sys.exit(f"{path}: not a 32-bit ELF")
shoff = struct.unpack_from('<I', f, 0x20)[0]
shentsize, shnum, shstrndx = struct.unpack_from('<HHH', f, 0x2E)
secs = [struct.unpack_from('<IIIIIIIIII', f, shoff + i * shentsize) for i in range(shnum)]
stroff = secs[shstrndx][4]
def name(o):
    return f[stroff + o:f.index(b'\0', stroff + o)].decode()
flash = ram = 0
rows = []
for s in secs:
    n, typ, flags, addr, size = name(s[0]), s[1], s[2], s[3], s[5]
    if not flags & 2 or size == 0:   # SHF_ALLOC
        continue
    in_ram = addr >= 0x20000000
    nobits = typ == 8                  # SHT_NOBITS (.bss, .uninit)
    if in_ram:
        ram += size
        if not nobits:
            flash += size              # .data initial values live in flash
    else:
        flash += size
    rows.append((n, addr, size))
for n, addr, size in rows:
    print(f"  {n:<16} 0x{addr:08x} {size:>8} bytes")
print(f"flash: {flash} bytes ({flash / 1024:.1f} KiB)")
print(f"static RAM: {ram} bytes ({ram / 1024:.1f} KiB of {ram_total // 1024} KiB; {ram_total - ram} bytes left for the stack)")
