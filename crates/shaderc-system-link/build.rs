//! Debian's `libshaderc.so.1` leaves glslang's symbols undefined and names no glslang
//! library (glslang-dev ships only static archives), so the link of anything using the
//! system shaderc fails. This adds those archives to the link, when they are present.
use std::path::Path;

const LIBS: &[&str] = &[
    "glslang",
    "MachineIndependent",
    "GenericCodeGen",
    "OSDependent",
    "OGLCompiler",
    "HLSL",
    "SPIRV",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
    "glslang-default-resource-limits",
];

const SEARCH_DIRS: &[&str] = &[
    "/usr/lib/x86_64-linux-gnu",
    "/usr/lib/aarch64-linux-gnu",
    "/usr/lib64",
    "/usr/lib",
];

fn main() {
    println!("cargo:rerun-if-env-changed=SHADERC_LIB_DIR");
    let dir = std::env::var("SHADERC_LIB_DIR").ok().or_else(|| {
        SEARCH_DIRS
            .iter()
            .find(|d| Path::new(d).join("libglslang.a").exists())
            .map(|d| d.to_string())
    });
    let Some(dir) = dir else {
        println!("cargo:warning=static glslang libraries not found; linking shaderc as it is");
        return;
    };
    if !LIBS.iter().all(|l| Path::new(&dir).join(format!("lib{l}.a")).exists()) {
        println!("cargo:warning=some glslang/SPIRV-Tools archives missing in {dir}; linking shaderc as it is");
        return;
    }
    println!("cargo:rustc-link-search=native={dir}");
    for lib in LIBS {
        println!("cargo:rustc-link-lib=static={lib}");
    }
}
