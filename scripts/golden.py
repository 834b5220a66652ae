#!/usr/bin/env python3
"""Behaviour check for restructurings: runs host-sim on fixed commands and
compares their JSON with the outputs kept in tests/golden/, field by field,
ignoring only wall-clock fields (times measured on the host, simulation
speed). Exit 1 on any difference.

    python3 scripts/golden.py target/release/host-sim            # check
    python3 scripts/golden.py target/release/host-sim --update   # re-record
    python3 scripts/golden.py --emu LOG   # an emulated run's log against tests/golden/emu.txt

The emulated run must give the same results line by line; instruction
counts (and the structures' bytes) may move by 2 % with code generation.

Re-record only for a change that is meant to alter behaviour, and say so in
the commit message.
"""
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GOLDEN = os.path.join(ROOT, "tests", "golden")
# Wall-clock fields: they measure the machine, not the algorithm.
CLOCK = re.compile(r"(^|_)time_us$|^wall_time_s$|^sim_speed$")

# name -> arguments; "{out}" is replaced by the JSON file to write, or the
# JSON goes to stdout when the command has no file argument.
COMMANDS = {
    "table2": ["bench", "table2", "--runs", "100", "--seed", "11", "--json", "{out}"],
    "table1": ["bench", "table1", "--runs", "100", "--seed", "7", "--json"],
    "mission_studio": ["mission", "--map", "maps/flat/studio.txt", "--mode", "known",
                       "--people", "1", "--noise", "none", "--seed", "1", "--json", "{out}"],
    # Realistic noise, three people, unknown map: drift, stalls, avoidance,
    # re-plans and the map growing all run.
    "mission_home_unknown": ["mission", "--map", "maps/flat/home.txt", "--mode", "unknown",
                             "--people", "3", "--noise", "realistic", "--seed", "2",
                             "--json", "{out}"],
    "plan_rooms64": ["plan", "--map", "maps/movingai/rooms64.map", "--planner", "b-oha",
                     "--json", "{out}"],
}


def strip(v):
    """The value without its wall-clock fields."""
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if not CLOCK.search(k)}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v


def run(binary, args):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.json")
        argv = [binary] + [out if a == "{out}" else a for a in args]
        res = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, check=True)
        text = open(out).read() if "{out}" in args else res.stdout
    return strip(json.loads(text))


def diff(a, b, path="$"):
    """The first few paths where a and b differ."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                out.append(f"{path}.{k}: only in {'new' if k in b else 'golden'}")
            else:
                out += diff(a[k], b[k], f"{path}.{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: length {len(a)} != {len(b)}"]
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in diff(x, y, f"{path}[{i}]")]
    return [] if a == b else [f"{path}: golden {a!r} != new {b!r}"]


NUM = re.compile(r"\d+")


def loose(line, m):
    """True for a number that counts instructions, bytes or SysTick ticks
    (2 % allowed: the calibration's tick count moves by one with the phase
    of SysTick when the boot code before it changes)."""
    after, before = line[m.end():m.end() + 40], line[max(0, m.start() - 5):m.start()]
    nxt = NUM.search(after)
    head = after[:nxt.start()] if nxt else after
    return (
        "instruction" in head
        or "bytes" in head
        or "SysTick ticks" in head
        or before.endswith("(max ")
    )


def check_emu(log_path):
    want = [l.rstrip() for l in open(os.path.join(GOLDEN, "emu.txt")) if l.strip()]
    cargo = re.compile(r"^\s+(Compiling|Finished|Running|Blocking)\b")
    got = [l.rstrip() for l in open(log_path) if l.strip() and not cargo.match(l)]
    bad, worst = [], 0.0
    if len(want) != len(got):
        bad.append(f"{len(got)} lines, golden has {len(want)}")
    for w, g in zip(want, got):
        if NUM.sub("#", w) != NUM.sub("#", g):
            bad.append(f"text differs: {g!r}")
            continue
        for mw, mg in zip(NUM.finditer(w), NUM.finditer(g)):
            a, b = int(mw.group()), int(mg.group())
            if a == b:
                continue
            r = abs(b - a) / max(a, 1)
            worst = max(worst, r if loose(w, mw) else 1.0)
            if not loose(w, mw) or r > 0.02:
                bad.append(f"{a} -> {b} in {g!r}")
    print(f"emulated run: {len(got)} lines, largest count change {100 * worst:.2f} %")
    for b in bad[:10]:
        print("   ", b)
    return 1 if bad else 0


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--emu":
        return check_emu(sys.argv[2])
    if len(sys.argv) < 2:
        print("usage: golden.py HOST_SIM_BINARY [--update]", file=sys.stderr)
        return 2
    binary, update = os.path.abspath(sys.argv[1]), "--update" in sys.argv[2:]
    failed = 0
    for name, args in COMMANDS.items():
        new = run(binary, args)
        path = os.path.join(GOLDEN, name + ".json")
        if update:
            with open(path, "w") as f:
                json.dump(new, f, indent=1, sort_keys=True)
                f.write("\n")
            print(f"recorded {name}")
            continue
        diffs = diff(json.load(open(path)), new)
        print(f"{name}: {'identical' if not diffs else f'{len(diffs)} differences'}")
        for d in diffs[:10]:
            print("   ", d)
        failed += bool(diffs)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
