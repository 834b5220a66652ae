#!/usr/bin/env python3
"""Flash and static-RAM report for a firmware ELF (no binutils needed).

Flash = the allocated sections stored in flash (vector table, text, rodata,
and the initial values of .data and .ccmram); static RAM = .data + .bss +
.uninit in SRAM, and .ccmram in the core-coupled RAM (the F405/F407's
16 x 16 m layout, memory-f407.x). The stack is what the linker script
leaves it, from `_stack_end` up to `_stack_start` (read from the symbol
table): the top of SRAM on the F411, the top of the CCM at 16 x 16 m.

With --stack-need N (the high-water mark a processor-in-the-loop run of
the same executive measured, painted at boot), exit 1 when the image
leaves the stack fewer than N bytes: static RAM grown into the stack's
room fails CI instead of corrupting .bss on a flashed robot.
It also lists static RAM per structure: every symbol of 256 bytes or more
in SRAM or the CCM, from the ELF's own symbol table (the mission's
buffers, the DMA ring, the log's ring), and the rest in one line.
Usage: size_report.py ELF [RAM_BYTES] [--stack-need N]"""
import argparse, struct, sys

ap = argparse.ArgumentParser(description="flash, static RAM and stack of a firmware ELF")
ap.add_argument("elf")
ap.add_argument("ram_bytes", nargs="?", type=int, default=128 * 1024)
ap.add_argument("--stack-need", type=int, help="fail when the stack has fewer bytes")
args = ap.parse_args()
path = args.elf
ram_total = args.ram_bytes
CCM_BYTES = 64 * 1024
f = open(path, 'rb').read()
if f[:4] != b'\x7fELF' or f[4] != 1:
    sys.exit(f"{path}: not a 32-bit ELF")
shoff = struct.unpack_from('<I', f, 0x20)[0]
shentsize, shnum, shstrndx = struct.unpack_from('<HHH', f, 0x2E)
secs = [struct.unpack_from('<IIIIIIIIII', f, shoff + i * shentsize) for i in range(shnum)]
def cstr(off):
    return f[off:f.index(b'\0', off)].decode()
stroff = secs[shstrndx][4]
def symbols():
    """Name -> (value, size) of the ELF's symbols."""
    out = {}
    for s in secs:
        if s[1] != 2:                  # SHT_SYMTAB
            continue
        strtab = secs[s[6]][4]
        for i in range(s[5] // 16):
            st_name, st_value, st_size = struct.unpack_from('<III', f, s[4] + i * 16)
            out[cstr(strtab + st_name)] = (st_value, st_size)
    return out


def plain(name):
    """A Rust symbol's path without its hash (legacy mangling `_ZN...E`),
    RTIC's prefix for an init-local resource shortened (`app::init::map`)
    and cortex-m-rt's for an entry point's static dropped."""
    if not name.startswith('_ZN'):
        return name
    parts, i = [], 3
    while i < len(name) and name[i].isdigit():
        j = i
        while j < len(name) and name[j].isdigit():
            j += 1
        n = int(name[i:j])
        parts.append(name[j:j + n])
        i = j + n
    if parts and parts[-1].startswith('h') and len(parts[-1]) == 17:
        parts.pop()
    path = '::'.join(parts).replace('$LT$', '<').replace('$GT$', '>').replace('..', '::')
    path = path.replace('__rtic_internal_local_init_', 'init::')
    return path.replace('__cortex_m_rt_main_trampoline::', '')


def structures(sym, lo, hi, least=256):
    """(bytes, name) of the symbols of `least` bytes or more in [lo, hi),
    largest first."""
    big = [(size, plain(name)) for name, (value, size) in sym.items()
           if lo <= value < hi and size >= least]
    return sorted(big, reverse=True)
flash = ram = ccm = 0
rows = []
for s in secs:
    n, typ, flags, addr, size = cstr(stroff + s[0]), s[1], s[2], s[3], s[5]
    if not flags & 2 or size == 0:   # SHF_ALLOC
        continue
    nobits = typ == 8                  # SHT_NOBITS (.bss, .uninit)
    if n == '.ccmram':
        ccm += size
        flash += size                  # initial values copied at reset
    elif addr >= 0x20000000:
        ram += size
        if not nobits:
            flash += size              # .data initial values live in flash
    else:
        flash += size
    rows.append((n, addr, size))
for n, addr, size in rows:
    print(f"  {n:<16} 0x{addr:08x} {size:>8} bytes")
print(f"flash: {flash} bytes ({flash / 1024:.1f} KiB)")
print(f"static RAM: {ram} bytes ({ram / 1024:.1f} KiB of {ram_total // 1024} KiB SRAM; {ram_total - ram} bytes left)")
if ccm:
    print(f"CCM: {ccm} bytes ({ccm / 1024:.1f} KiB of {CCM_BYTES // 1024} KiB; {CCM_BYTES - ccm} bytes left)")
sym = symbols()
# Static RAM per structure: every symbol in SRAM or the CCM of 256 bytes
# or more (the mission's buffers are RTIC init-local resources).
for where, lo, hi, total in (("SRAM", 0x20000000, 0x20000000 + ram_total, ram),
                             ("CCM", 0x10000000, 0x10000000 + CCM_BYTES, ccm)):
    big = structures(sym, lo, hi)
    if big:
        print(f"static {where} per structure (256 bytes or more):")
        for size, name in big:
            print(f"  {size:>8}  {name}")
        print(f"  {total - sum(b for b, _ in big):>8}  the rest (smaller statics, alignment)")
if '_stack_start' in sym and '_stack_end' in sym:
    where = 'CCM' if ccm else 'SRAM'
    stack = sym['_stack_start'][0] - sym['_stack_end'][0]
    print(f"stack: {stack} bytes (top of {where})")
    if args.stack_need is not None:
        spare = stack - args.stack_need
        print(f"stack need (measured in the loop): {args.stack_need} bytes; {spare} spare")
        if spare < 0:
            sys.exit(f"{path}: the stack ({stack} bytes) is smaller than the {args.stack_need} bytes measured")
elif args.stack_need is not None:
    sys.exit(f"{path}: no _stack_start/_stack_end symbols to check the stack against")
