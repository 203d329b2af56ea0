//! With the `coco` feature, compiles COCO's C core (vendor/coco at the
//! workspace root, BSD-3-Clause) with metabezier's own shim
//! (native/coco_shim.c) through the `cc` crate: the bbob suite needs only
//! the C compiler every machine has, no libclang and no bindgen. Without
//! the feature it compiles nothing.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_COCO").is_none() {
        return;
    }
    println!("cargo:rerun-if-changed=../../native/coco_shim.c");
    println!("cargo:rerun-if-changed=../../vendor/coco/coco.c");
    println!("cargo:rerun-if-changed=../../vendor/coco/coco.h");
    cc::Build::new()
        .file("../../native/coco_shim.c")
        .include("../../vendor/coco")
        .opt_level(2)
        .warnings(false)
        .flag_if_supported("-w")
        .compile("coco_shim");
}
