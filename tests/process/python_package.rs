//! The Python package's pytest suite (python/tests), run by `cargo test`
//! when `TMC_PYTHON` names a Python that has the package installed (`.ci/run`
//! makes one: a virtual environment with `pip install ./python`). Without
//! it the test says how to get one and passes without running anything.

use std::path::Path;

#[test]
fn pytest_suite_of_the_python_package() {
    let Some(python) = std::env::var_os("TMC_PYTHON") else {
        eprintln!(
            "skipped: set TMC_PYTHON to a Python with the package and its test \
             dependencies installed (python3 -m venv v && v/bin/pip install ./python \
             pytest scikit-image scipy pynrrd; TMC_PYTHON=v/bin/python)"
        );
        return;
    };
    let _cores = crate::CORES.write().unwrap_or_else(|e| e.into_inner());
    let tests = Path::new(env!("CARGO_MANIFEST_DIR")).join("python/tests");
    // Signals at their defaults: the interrupt tests send SIGINT, which a
    // Python started with it ignored keeps ignored.
    let status = crate::common::signals::default_signals(&python)
        .args(["-m", "pytest", "-q", "-rs"])
        .arg(&tests)
        .env("TMC_BIN", env!("CARGO_BIN_EXE_tmc"))
        .status()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", Path::new(&python).display()));
    assert!(status.success(), "the Python package's tests failed");
}
