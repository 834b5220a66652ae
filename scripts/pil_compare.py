#!/usr/bin/env python3
"""Processor-in-the-loop against the host: runs one mission natively
(the firmware's capacity and call order) and with the firmware image in
QEMU (--pil), prints both side by side, and fails unless the firmware
covers the same floor within 1 point, collides no more than the host,
and, for a whole mission, docks as the host does.

Usage: pil_compare.py HOST_SIM ELF [host-sim mission options...]
(PIL_CAPACITY=fw16 for an image of the 16 x 16 m capacity: both runs then
 take that capacity's buffers; default fw)
(build the image first: scripts/pil.sh does, or
 CARGO_TARGET_DIR=target/pil cargo build --release \
   --target thumbv7em-none-eabihf --bin robovac --features pil)
"""
import json
import os
import subprocess
import sys
import tempfile
import time


def run(cmd):
    t0 = time.monotonic()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.monotonic() - t0


def main():
    if len(sys.argv) < 3:
        print(next(l for l in __doc__.splitlines() if l.startswith('Usage')), file=sys.stderr)
        return 2
    host_sim, elf, args = sys.argv[1], sys.argv[2], sys.argv[3:]
    # PIL_LOG=FILE keeps the firmware's raw defmt log (defmt-print -e ELF < FILE).
    log = ["--pil-log", os.environ["PIL_LOG"]] if os.environ.get("PIL_LOG") else []
    cap = ["--capacity", os.environ.get("PIL_CAPACITY", "fw")]
    out = {}
    with tempfile.TemporaryDirectory() as d:
        for name, extra in (("host", cap + ["--firmware-order"]),
                            ("firmware", cap + ["--pil", "--pil-elf", elf] + log)):
            path = f"{d}/{name}.json"
            wall = run([host_sim, "mission", *args, *extra, "--json", path])
            out[name] = json.load(open(path))
            out[name]["wall_s"] = wall
    h, f = out["host"], out["firmware"]
    rows = [("coverage %", lambda r: f"{100 * r['coverage']:.2f}"),
            ("collisions", lambda r: r["collisions"]),
            ("finished", lambda r: r["finished"]),
            ("docked", lambda r: r["docked"]),
            ("final state", lambda r: r["final_state"]),
            ("distance m", lambda r: f"{r['distance_m']:.2f}"),
            ("mission time s", lambda r: f"{r['sim_time_s']:.1f}"),
            ("wall time s", lambda r: f"{r['wall_s']:.1f}"),
            ("lidar frames", lambda r: r["lidar_parser"]["frames"]),
            ("lidar bad crc", lambda r: r["lidar_parser"]["crc_failures"]),
            ("bytes skipped", lambda r: r["lidar_parser"]["bytes_skipped"]),
            ("silence stop ms", lambda r: r.get("silence_stop_ms", "-")),
            ("map scrolls", lambda r: r.get("map_scrolls", "-"))]
    print(f"{'':16}{'host':>14}{'firmware':>14}")
    for label, get in rows:
        print(f"{label:16}{str(get(h)):>14}{str(get(f)):>14}")
    fw = f.get("firmware") or {}
    budget = 840_000
    for key in ("worst_control_insn", "worst_lidar_insn", "worst_plan_insn"):
        if key in fw:
            print(f"{key:22}{fw[key]:>12} instructions"
                  f" ({100 * fw[key] / budget:.1f} % of a 10 ms period at 84 MHz)")
    if "plan_steps_over_hold" in fw:
        print(f"held past the reflex's 60 ms while driving: {fw['plan_steps_over_hold']} plan steps,"
              f" {fw['lidar_events_over_hold']} lidar events; the robot would stand braked"
              f" {fw['reflex_braked_s']:.1f} s of {f['sim_time_s']:.0f} s")
    if fw.get("total_insn"):
        load = fw["total_insn"] / (84e6 * f["sim_time_s"])
        print(f"processor load         {fw['total_insn']:>12} instructions in {f['sim_time_s']:.0f} s:"
              f" {100 * load:.1f} % of 84 MHz (one instruction a cycle)")
    inj = f.get("injected", {})
    if any(inj.values()):
        print("injected: " + ", ".join(f"{k} {v}" for k, v in inj.items()))
        print(f"firmware link: {fw.get('link_frames')} frames, {fw.get('link_dropped')} dropped;"
              f" UART errors {fw.get('rx_errors')}, bytes lost to full queues {fw.get('rx_dropped')}")
    if "stack_used_bytes" in fw:
        print(f"stack high-water       {fw['stack_used_bytes']:>12} of {fw['stack_size_bytes']} bytes")
    bad = []
    if abs(h["coverage"] - f["coverage"]) > 0.01:
        bad.append("coverage differs by more than 1 point")
    if f["collisions"] > h["collisions"]:
        bad.append("the firmware collided more")
    if h["finished"] and not (f["finished"] and f["docked"] == h["docked"]):
        bad.append("the host's mission ended at the dock, the firmware's did not")
    if not fw:
        bad.append("no report from the firmware")
    if h.get("map_scrolls") != f.get("map_scrolls"):
        bad.append("the map scrolled a different number of times")
    if "--lidar-gap" in args and not (f.get("silence_stop_ms") is not None
                                      and f["silence_stop_ms"] <= 200):
        bad.append("the firmware's motors did not stop within 200 ms of the lidar's silence")
    if inj.get("link_garbage_bytes") and not fw.get("link_dropped"):
        bad.append("garbage on the link was not counted")
    for b in bad:
        print("FAIL:", b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
