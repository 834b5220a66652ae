#!/usr/bin/env python3
"""Link-time proof that the firmware cannot panic (issue 11 §6).

Disassembles the release ELF with llvm-objdump and lists every call or
branch into `core::panicking` (panic, panic_fmt, bounds checks, division
by zero, unwrap/expect failures all end there). Exits 1 and prints each
site, in the function that holds it, when there is any; 0 otherwise.

Usage: panic_check.py ELF
"""
import re
import shutil
import subprocess
import sys


def objdump():
    """llvm-objdump from PATH or from the Rust toolchain's llvm-tools."""
    for name in ("llvm-objdump", "rust-objdump"):
        if shutil.which(name):
            return name
    sysroot = subprocess.run(["rustc", "--print", "sysroot"], capture_output=True,
                             text=True, check=True).stdout.strip()
    found = subprocess.run(["find", sysroot, "-name", "llvm-objdump", "-type", "f"],
                           capture_output=True, text=True).stdout.split()
    if not found:
        sys.exit("panic_check: no llvm-objdump (rustup component add llvm-tools)")
    return found[0]


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    dis = subprocess.run([objdump(), "-d", "--no-show-raw-insn", "-C", sys.argv[1]],
                         capture_output=True, text=True, check=True).stdout
    func, sites = None, []
    head = re.compile(r"^[0-9a-f]+ <(.*)>:$")
    branch = re.compile(r"^\s*([0-9a-f]+):\s+(bl?|b\.w|bl\.w|b\.n)\s.*<(core::panicking[^>]*)>")
    for line in dis.splitlines():
        m = head.match(line)
        if m and not m.group(1).startswith("$"):
            func = m.group(1)
            continue
        m = branch.match(line)
        if m and not (func or "").startswith("core::panicking"):
            sites.append((m.group(1), func, m.group(3)))
    names = sorted({f for f in re.findall(r"<(core::panicking[^>+]*)>", dis)})
    print(f"panic check: {len(sites)} branch(es) into core::panicking from outside it; "
          f"core::panicking functions linked: {len(names)}")
    for addr, func, target in sites:
        print(f"    0x{addr} in {func} -> {target}")
    return 1 if sites or names else 0


if __name__ == "__main__":
    sys.exit(main())
