//! Build script: only with the `petsc` feature, finds the system PETSc with pkg-config
//! (`pkg-config --libs petsc`) and links it, with an rpath so the binary runs without
//! `LD_LIBRARY_PATH`. The default build does nothing here.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_PETSC").is_none() {
        return;
    }
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    let libs = std::process::Command::new("pkg-config").args(["--libs", "petsc"]).output();
    let out = match libs {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout).into_owned(),
        Ok(o) => panic!(
            "the `petsc` feature needs PETSc: `pkg-config --libs petsc` failed ({}); on Debian/Ubuntu install \
             libpetsc-real-dev (apt-get install libpetsc-real-dev libopenmpi-dev openmpi-bin libclang-dev \
             pkg-config), elsewhere set PKG_CONFIG_PATH to the directory holding petsc.pc",
            String::from_utf8_lossy(&o.stderr).trim()
        ),
        Err(e) => panic!("the `petsc` feature needs pkg-config to find PETSc: {e}"),
    };
    for flag in out.split_whitespace() {
        if let Some(dir) = flag.strip_prefix("-L") {
            println!("cargo:rustc-link-search=native={dir}");
            println!("cargo:rustc-link-arg=-Wl,-rpath,{dir}");
        } else if let Some(lib) = flag.strip_prefix("-l") {
            println!("cargo:rustc-link-lib={lib}");
        }
    }
}
