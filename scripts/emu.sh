#!/usr/bin/env bash
# The emulated Cortex-M4 run: builds examples/emu.rs for thumbv7em, runs it
# on QEMU's netduinoplus2 (STM32F405) with deterministic instruction
# counting, and decodes its defmt log with defmt-print. Exits non-zero when
# any check on the target fails, or the run hangs past the time limit.
set -euo pipefail
cd "$(dirname "$0")/.."
# run_example NAME: build examples/NAME.rs for thumbv7em, run it on the
# emulated STM32F405, decode its defmt log.
run_example() {
  cargo build --release --target thumbv7em-none-eabihf --example "$1"
  local elf=target/thumbv7em-none-eabihf/release/examples/$1
  timeout "${EMU_TIMEOUT:-900}" qemu-system-arm \
    -machine netduinoplus2 -cpu cortex-m4 \
    -icount shift=0 \
    -nographic -monitor none -serial none \
    -semihosting-config enable=on,target=native \
    -kernel "$elf" \
    | defmt-print -e "$elf"
}
run_example emu
# The scan matcher's run: a recorded revolution matched on the target.
run_example emu_localize
