//! Puts the memory layout on the linker search path for the firmware
//! target, as `layout.x` (which `memory.x` includes): the F411's
//! (`memory-f411.x`), the F405/F407's with its CCM (`memory-f407.x`,
//! feature `home16`), or the emulator's for that capacity
//! (`memory-qemu16.x`, features `home16` and `pil`). Host builds ignore
//! it.
use std::{env, fs, path::PathBuf};

fn main() {
    for f in [
        "memory.x",
        "memory-f411.x",
        "memory-f407.x",
        "memory-qemu16.x",
        "build.rs",
    ] {
        println!("cargo:rerun-if-changed={f}");
    }
    let target = env::var("TARGET").unwrap_or_default();
    if !target.starts_with("thumb") {
        return;
    }
    let feature = |f: &str| env::var_os(format!("CARGO_FEATURE_{f}")).is_some();
    let layout = match (feature("HOME16"), feature("PIL")) {
        (false, _) => "memory-f411.x",
        (true, false) => "memory-f407.x",
        (true, true) => "memory-qemu16.x",
    };
    let out = PathBuf::from(env::var_os("OUT_DIR").unwrap_or_default());
    match fs::read(layout) {
        Ok(bytes) => {
            if let Err(e) = fs::write(out.join("layout.x"), bytes) {
                println!("cargo:warning=cannot copy {layout}: {e}");
            }
        }
        Err(e) => println!("cargo:warning=cannot read {layout}: {e}"),
    }
    println!("cargo:rustc-link-search={}", out.display());
}
