//! Compiles the C++ shim (src/shim.cpp) against the system OpenCASCADE 7.6
//! and links the toolkits it needs.
//!
//! The include directory can be overridden with `OCCT_INCLUDE_DIR`, the
//! library directory with `OCCT_LIB_DIR`.

use std::env;
use std::path::{Path, PathBuf};

/// OCCT toolkits the shim uses, in link order (dependents before dependencies).
const LIBS: &[&str] = &[
    "TKXDESTEP",
    "TKSTEP",
    "TKSTEPAttr",
    "TKSTEP209",
    "TKSTEPBase",
    "TKXDEIGES",
    "TKIGES",
    "TKXSBase",
    "TKShHealing",
    "TKTopAlgo",
    "TKGeomAlgo",
    "TKBRep",
    "TKGeomBase",
    "TKG3d",
    "TKG2d",
    "TKMath",
    "TKernel",
];

fn main() {
    println!("cargo:rerun-if-changed=src/shim.cpp");
    println!("cargo:rerun-if-env-changed=OCCT_INCLUDE_DIR");
    println!("cargo:rerun-if-env-changed=OCCT_LIB_DIR");

    let include = env::var_os("OCCT_INCLUDE_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/usr/include/opencascade"));
    if !include.join("STEPControl_Reader.hxx").exists() || !include.join("BRep_Tool.hxx").exists() {
        panic!(
            "\n\nOpenCASCADE headers not found in {}.\n\
             The `occt` crate needs the system OpenCASCADE 7.6 development packages. On Debian/Ubuntu:\n\
             \n    sudo apt-get install libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-foundation-dev\n\
             \n(or set OCCT_INCLUDE_DIR / OCCT_LIB_DIR to another OpenCASCADE installation).\n\n",
            include.display()
        );
    }
    let lib_dir = env::var_os("OCCT_LIB_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(default_lib_dir);
    if !lib_dir.join("libTKernel.so").exists() {
        panic!(
            "\n\nOpenCASCADE libraries (libTKernel.so …) not found in {}.\n\
             Install them with:\n\
             \n    sudo apt-get install libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-foundation-dev\n\
             \n(or set OCCT_LIB_DIR).\n\n",
            lib_dir.display()
        );
    }

    cc::Build::new()
        .cpp(true)
        .file("src/shim.cpp")
        .include(&include)
        .flag_if_supported("-std=c++17")
        // OCC_CATCH_SIGNALS jumps to the shim's handlers (see shim.cpp)
        .define("OCC_CONVERT_SIGNALS", None)
        .flag_if_supported("-Wno-deprecated-declarations")
        .flag_if_supported("-Wno-unused-parameter")
        .opt_level(2)
        .compile("occt_shim");

    println!("cargo:rustc-link-search=native={}", lib_dir.display());
    for lib in LIBS {
        println!("cargo:rustc-link-lib=dylib={lib}");
    }
}

/// The multiarch library directory of the Debian packages, else /usr/lib.
fn default_lib_dir() -> PathBuf {
    for d in [
        "/usr/lib/x86_64-linux-gnu",
        "/usr/lib/aarch64-linux-gnu",
        "/usr/lib64",
        "/usr/lib",
    ] {
        if Path::new(d).join("libTKernel.so").exists() {
            return PathBuf::from(d);
        }
    }
    PathBuf::from("/usr/lib/x86_64-linux-gnu")
}
