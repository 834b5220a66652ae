//! Puts `memory.x` on the linker search path for the firmware target. Host
//! builds ignore it.
use std::{env, fs, path::PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    let target = env::var("TARGET").unwrap_or_default();
    if !target.starts_with("thumb") {
        return;
    }
    let out = PathBuf::from(env::var_os("OUT_DIR").unwrap_or_default());
    match fs::read("memory.x") {
        Ok(bytes) => {
            if let Err(e) = fs::write(out.join("memory.x"), bytes) {
                println!("cargo:warning=cannot copy memory.x: {e}");
            }
        }
        Err(e) => println!("cargo:warning=cannot read memory.x: {e}"),
    }
    println!("cargo:rustc-link-search={}", out.display());
}
