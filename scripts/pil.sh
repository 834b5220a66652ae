#!/usr/bin/env bash
# Processor-in-the-loop: builds the firmware image with the sim-link board
# (the same executive, tasks and capacities as the real image, release
# profile; its own target directory so the real image is not replaced),
# builds host-sim, and runs a mission with the firmware in QEMU's
# netduinoplus2.
#
#   scripts/pil.sh --map maps/flat/studio.txt --people 1 [host-sim mission options]
set -euo pipefail
cd "$(dirname "$0")/.."
CARGO_TARGET_DIR=target/pil cargo build --release --target thumbv7em-none-eabihf \
  --bin robovac --features pil
cargo build --release -p host-sim
exec ./target/release/host-sim mission --pil \
  --pil-elf target/pil/thumbv7em-none-eabihf/release/robovac "$@"
