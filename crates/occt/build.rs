//! Compiles the C++ shim (src/shim.cpp) against the system OpenCASCADE 7.6
//! and links the toolkits it needs; links its IGES half (src/shim_iges.cpp)
//! into a shared object of its own, `$OUT_DIR/libquadrille_occt_iges.so`,
//! which `src/ffi.rs` embeds and the shim loads on the first IGES read or
//! write, so that a process reading STEP or BREP never loads (nor binds the
//! symbols of) OCCT's IGES toolkits.
//!
//! The include directory can be overridden with `OCCT_INCLUDE_DIR`, the
//! library directory with `OCCT_LIB_DIR`.

use std::env;
use std::path::{Path, PathBuf};

/// OCCT toolkits the shim uses, in link order (dependents before dependencies).
/// No IGES toolkit: those are the IGES half's ([`IGES_LIBS`]).
const LIBS: &[&str] = &[
    "TKSTEP",
    "TKSTEPAttr",
    "TKSTEP209",
    "TKSTEPBase",
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

/// OCCT toolkits the IGES half (src/shim_iges.cpp) links.
const IGES_LIBS: &[&str] = &["TKIGES", "TKXSBase", "TKBRep", "TKMath", "TKernel"];

fn main() {
    println!("cargo:rerun-if-changed=src/shim.cpp");
    println!("cargo:rerun-if-changed=src/shim_iges.cpp");
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
    build_iges_half(&include, &lib_dir);
}

/// Compiles and links src/shim_iges.cpp into
/// `$OUT_DIR/libquadrille_occt_iges.so` with the compiler `cc` picks for
/// the shim.
fn build_iges_half(include: &Path, lib_dir: &Path) {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"))
        .join("libquadrille_occt_iges.so");
    let compiler = cc::Build::new().cpp(true).opt_level(2).get_compiler();
    let mut cmd = compiler.to_command();
    cmd.args(["-shared", "-fPIC", "-std=c++17", "-DOCC_CONVERT_SIGNALS"])
        .args(["-Wno-deprecated-declarations", "-Wno-unused-parameter"])
        .arg("-I")
        .arg(include)
        .arg("src/shim_iges.cpp")
        .arg("-o")
        .arg(&out)
        .arg(format!("-L{}", lib_dir.display()))
        .arg("-Wl,--as-needed");
    for lib in IGES_LIBS {
        cmd.arg(format!("-l{lib}"));
    }
    let status = cmd
        .status()
        .unwrap_or_else(|e| panic!("could not run the C++ compiler for src/shim_iges.cpp: {e}"));
    if !status.success() {
        panic!("linking src/shim_iges.cpp into {} failed ({status})", out.display());
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
