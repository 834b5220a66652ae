//! The core-coupled RAM's statics (feature `home16`: the F405/F407's 64
//! KiB CCM, `memory-f407.x`; the emulator's stand-in, `memory-qemu16.x`).
//!
//! cortex-m-rt copies `.data` and zeroes `.bss` at reset, but knows nothing
//! of `.ccmram`. Its statics (the evidence map, `link_section =
//! ".ccmram"`) are given their initial values here, from the copy the
//! linker stores in flash (`ccm.x`), in `__pre_init`: before any Rust code
//! runs, so no reference to them exists yet. It is written in assembly, as
//! cortex-m-rt asks of `__pre_init` (Rust code there is undefined
//! behaviour). It uses no stack (the stack is in the CCM too, above them),
//! and the CCM's clock is on at reset (RCC_AHB1ENR.CCMDATARAMEN resets to
//! 1).

core::arch::global_asm!(
    ".section .text.__pre_init,\"ax\",%progbits",
    ".global __pre_init",
    ".type __pre_init,%function",
    ".thumb_func",
    "__pre_init:",
    "    ldr r0, =__sccm",
    "    ldr r1, =__eccm",
    "    ldr r2, =__siccm",
    "0:  cmp r0, r1",
    "    bhs 1f",
    "    ldr r3, [r2], #4",
    "    str r3, [r0], #4",
    "    b 0b",
    "1:  bx lr",
    ".ltorg",
);
