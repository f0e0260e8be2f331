//! Project automation for csm (`cargo xtask <command>`), in Rust rather than shell.
//!
//! - `cargo xtask ci`: exactly what CI runs: `cargo fmt --check`, `cargo clippy -D warnings`
//!   over every target, `cargo doc -D warnings` (every intra-doc link resolves), every test
//!   (insta snapshots fail when missing or changed), the Python package's tests, then the
//!   feature matrix.
//! - `cargo xtask python`: the Python package as a user gets it: `pip install .[test]` into
//!   the virtual environment `target/py-venv` (made on first use with `python3 -m venv`; pip
//!   fetches maturin, numpy, pytest and meshio), then the pytest suite `python/tests`, which
//!   compares with the `csm` binary of `target/debug` (built first) and the Kratos fixtures.
//!   `cargo xtask ci` runs it after the Rust tests.
//! - `cargo xtask mpi`: the search on MPI ranks (`tests/mpi`, feature `mpi`: `mpirun` on 1 to
//!   4 ranks against one process). Open MPI comes from the system: where `mpirun`, `mpicc` or
//!   libclang are missing, it installs Debian's `openmpi-bin`, `libopenmpi-dev` and
//!   `libclang-dev` with apt as root, or stops saying what to install. `cargo xtask ci` runs
//!   it (and lints and documents the `mpi` code) after the Python tests.
//! - `cargo xtask features`: the feature matrix alone: `cargo clippy -D warnings` of the
//!   facade with no feature and with each feature alone, of `csm-io` likewise, and `csm-io`'s
//!   unit tests without its default features (a user of one layer or one format compiles
//!   nothing else, and that must build cleanly).
//! - `cargo xtask fixtures`: regenerates the Kratos reference fixtures under `tests/fixtures/`
//!   by driving Kratos 10.4.4 (PyPI) with one thread through `tools/kratos_fixtures*.py`
//!   (`kratos_fixtures_steps.py`: multi-step runs and the dynamic-search test). The
//!   virtual environment is made in `target/kratos-venv` on first use (or set `KRATOS_PYTHON`
//!   to a Python that has Kratos). CI never runs this: the fixtures are committed data.
//! - `cargo xtask bench`: csm against Kratos 10.4.4 on generated scenes at sizes 1e3–2e5
//!   (search step, whole process, peak memory, identical pairs), written to
//!   `docs/performance.md` (see `bench.rs`).
//! - `cargo xtask scaling`: csm's stages with 1, 2, … threads (`--threads`), their speed-ups
//!   and serial fractions, written to the section "Parallel scaling" of
//!   `docs/performance.md` and `docs/scaling.svg` (see `scaling.rs`).
//! - `cargo xtask stability`: runs the full stability suite (`tests/it/stability/`, release
//!   build) and rewrites `docs/stability.md`; plain `cargo test` checks the CI-size cases
//!   against the committed file.
//! - `cargo xtask scene stacked_blocks N OUT.mdpa`: the benchmark's stacked blocks with about
//!   N slave faces, the file `tools/bench_scenes.py` writes, at sizes Python is too slow for
//!   (see `scene.rs`).
//! - `cargo xtask snapshots`: the snapshot tests alone, as CI runs them; review changes
//!   locally with `cargo insta review` (`cargo install cargo-insta` once).
//!
//! The tidy checks (dependency direction, file docs) are `#[test]`s in `tidy.rs`, so a plain
//! `cargo test` enforces them.

use std::process::Command;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};

mod bench;
mod scaling;
mod scene;
#[cfg(test)]
mod tidy;

/// Project automation for csm (`cargo xtask <command>`).
#[derive(Debug, Parser)]
#[command(name = "cargo xtask")]
struct Cli {
    #[command(subcommand)]
    command: Task,
}

#[derive(Debug, Subcommand)]
enum Task {
    /// Exactly what CI runs: fmt, clippy, doc, every test, the feature matrix.
    Ci,
    /// The snapshot tests alone, as CI runs them.
    Snapshots,
    /// The feature matrix alone.
    Features,
    /// The search on MPI ranks (installs Open MPI with apt where it can).
    Mpi,
    /// `pip install .[test]` into target/py-venv, then the pytest suite.
    Python,
    /// Regenerate the Kratos reference fixtures (needs Kratos 10.4.4 from PyPI).
    Fixtures,
    /// csm against Kratos on generated scenes; writes docs/performance.md.
    Bench(bench::Options),
    /// csm's stages with 1, 2, … threads; writes the scaling section of docs/performance.md.
    Scaling(scaling::Options),
    /// The full stability suite; rewrites docs/stability.md.
    Stability,
    /// Writes a benchmark scene (the stacked blocks) of any size, as tools/bench_scenes.py.
    Scene(scene::Options),
}

fn main() -> Result<()> {
    match Cli::parse().command {
        Task::Ci => ci(),
        Task::Snapshots => snapshots(),
        Task::Features => features(),
        Task::Mpi => mpi(),
        Task::Python => python(),
        Task::Fixtures => fixtures(),
        Task::Bench(options) => bench::bench(&options),
        Task::Scaling(options) => scaling::scaling(&options),
        Task::Stability => stability(),
        Task::Scene(options) => scene::scene(&options),
    }
}

/// Runs `cargo` with `args` in the workspace root; fails if it fails.
fn cargo(args: &[&str], envs: &[(&str, &str)]) -> Result<()> {
    eprintln!("$ cargo {}", args.join(" "));
    let status = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned()))
        .args(args)
        .envs(envs.iter().copied())
        .current_dir(workspace_root())
        .status()
        .with_context(|| format!("cannot run cargo {}", args.join(" ")))?;
    if !status.success() {
        bail!("cargo {} failed ({status})", args.join(" "));
    }
    Ok(())
}

fn workspace_root() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(std::path::Path::to_path_buf)
        .unwrap_or_else(|| ".".into())
}

const TEST_ENV: [(&str, &str); 2] = [("CI", "true"), ("INSTA_UPDATE", "no")];

fn ci() -> Result<()> {
    cargo(&["fmt", "--all", "--", "--check"], &[])?;
    cargo(
        &[
            "clippy",
            "--workspace",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ],
        &[],
    )?;
    cargo(
        &["doc", "--workspace", "--no-deps"],
        &[("RUSTDOCFLAGS", "-D warnings")],
    )?;
    cargo(&["test", "--workspace", "--all-targets"], &TEST_ENV)?;
    python()?;
    features()?;
    mpi()?;
    eprintln!("xtask ci: all checks passed");
    Ok(())
}

/// The facade's features, each checked alone (`cli` is the default set, which the workspace
/// clippy run checks).
const FACADE_FEATURES: [&str; 12] = [
    "",
    "distributed",
    "geometry",
    "trees",
    "model",
    "activation",
    "search",
    "eval",
    "msh",
    "mdpa",
    "vtk",
    "io",
];

/// `csm-io`'s features, each checked alone.
const IO_FEATURES: [&str; 4] = ["", "msh", "mdpa", "vtu"];

/// The feature matrix (see the module docs). `clippy` rather than `check`, so that code a
/// feature leaves unused fails (`-D warnings`); dependencies are checked once per feature
/// set and reused.
fn features() -> Result<()> {
    for (package, features) in [("csm", &FACADE_FEATURES[..]), ("csm-io", &IO_FEATURES[..])] {
        for f in features {
            let mut args = vec!["clippy", "--quiet", "-p", package, "--no-default-features"];
            if !f.is_empty() {
                args.extend(["--features", f]);
            }
            args.extend(["--lib", "--", "-D", "warnings"]);
            cargo(&args, &[])?;
        }
    }
    cargo(
        &["test", "-p", "csm-io", "--no-default-features", "--lib"],
        &TEST_ENV,
    )
}

/// The full stability suite, writing `docs/stability.md`.
fn stability() -> Result<()> {
    cargo(
        &[
            "test",
            "--release",
            "--test",
            "integration",
            "--",
            "--exact",
            "stability::stability_report_is_current",
        ],
        &[("CSM_STABILITY_WRITE", "1")],
    )
}

fn snapshots() -> Result<()> {
    cargo(&["test", "--workspace", "--all-targets"], &TEST_ENV)
}

/// The Kratos wheels the fixtures are made with.
const KRATOS_WHEELS: [&str; 4] = [
    "KratosMultiphysics==10.4.4",
    "KratosStructuralMechanicsApplication==10.4.4",
    "KratosContactStructuralMechanicsApplication==10.4.4",
    "KratosLinearSolversApplication==10.4.4",
];

fn run(program: &str, args: &[&str], envs: &[(&str, &str)]) -> Result<()> {
    eprintln!("$ {program} {}", args.join(" "));
    let status = Command::new(program)
        .args(args)
        .envs(envs.iter().copied())
        .current_dir(workspace_root())
        .status()
        .with_context(|| format!("cannot run {program}"))?;
    if !status.success() {
        bail!("{program} {} failed ({status})", args.join(" "));
    }
    Ok(())
}

/// Debian's packages for the `mpi` feature: Open MPI, its headers, and libclang for rsmpi's
/// bindings.
const MPI_PACKAGES: [&str; 3] = ["openmpi-bin", "libopenmpi-dev", "libclang-dev"];

/// The search on MPI ranks (see the module docs): Open MPI made present, the `mpi` code
/// linted and documented, then `tests/mpi`.
fn mpi() -> Result<()> {
    ensure_open_mpi()?;
    let features = ["--features", "mpi"];
    let mut clippy = vec!["clippy", "--workspace", "--all-targets"];
    clippy.extend(features);
    clippy.extend(["--", "-D", "warnings"]);
    cargo(&clippy, &[])?;
    let mut doc = vec!["doc", "--workspace", "--no-deps"];
    doc.extend(features);
    cargo(&doc, &[("RUSTDOCFLAGS", "-D warnings")])?;
    let mut test = vec!["test", "--test", "mpi"];
    test.extend(features);
    cargo(&test, &TEST_ENV)
}

/// Whether `program` runs (`--version`).
fn runs(program: &str) -> bool {
    Command::new(program)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Whether a libclang shared library is where rsmpi's bindings generator looks.
fn has_libclang() -> bool {
    let dirs = [
        "/usr/lib",
        "/usr/lib/x86_64-linux-gnu",
        "/usr/lib/aarch64-linux-gnu",
        "/usr/local/lib",
    ];
    let llvm: Vec<std::path::PathBuf> = std::fs::read_dir("/usr/lib")
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("llvm"))
        })
        .map(|p| p.join("lib"))
        .collect();
    let libclang = |dir: &std::path::Path| {
        std::fs::read_dir(dir)
            .into_iter()
            .flatten()
            .flatten()
            .any(|e| {
                e.file_name().to_string_lossy().starts_with("libclang")
                    && e.file_name().to_string_lossy().contains(".so")
            })
    };
    std::env::var_os("LIBCLANG_PATH").is_some()
        || dirs.iter().map(std::path::Path::new).any(libclang)
        || llvm.iter().any(|d| libclang(d))
}

/// `mpirun`, `mpicc` and libclang present, installed with apt as root where they are not, or
/// an error that says what to install.
fn ensure_open_mpi() -> Result<()> {
    if runs("mpirun") && runs("mpicc") && has_libclang() {
        return Ok(());
    }
    let root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
    if !(root && runs("apt-get")) {
        bail!(
            "the MPI tests need Open MPI and libclang: install them (Debian: `sudo apt-get \
             install {}`; elsewhere your Open MPI and libclang packages) and run again",
            MPI_PACKAGES.join(" ")
        );
    }
    let apt = [("DEBIAN_FRONTEND", "noninteractive")];
    run("apt-get", &["update", "-qq"], &apt)?;
    let mut install = vec!["install", "-y", "-qq", "--no-install-recommends"];
    install.extend(MPI_PACKAGES);
    run("apt-get", &install, &apt)?;
    if !(runs("mpirun") && runs("mpicc") && has_libclang()) {
        bail!(
            "apt-get installed {} but mpirun, mpicc or libclang is still missing",
            MPI_PACKAGES.join(" ")
        );
    }
    Ok(())
}

/// The Python package's tests (see the module docs): the package is built and installed
/// exactly as `pip install .` does for a user, in release mode.
fn python() -> Result<()> {
    cargo(&["build", "--bin", "csm"], &[])?;
    let venv = workspace_root().join("target/py-venv");
    let python = venv.join("bin/python");
    if !python.exists() {
        let system = std::env::var("CSM_PYTHON").unwrap_or_else(|_| "python3".to_owned());
        run(&system, &["-m", "venv", &venv.to_string_lossy()], &[]).with_context(|| {
            format!(
                "cannot make the virtual environment {} with {system}: install Python 3.9 or                  later with its venv module (Debian: `apt install python3-venv`), or set                  CSM_PYTHON to such a Python",
                venv.display()
            )
        })?;
    }
    let python = python.to_string_lossy().into_owned();
    let pip_env = [("PIP_DISABLE_PIP_VERSION_CHECK", "1")];
    run(
        &python,
        &["-m", "pip", "install", "--quiet", ".[test]"],
        &pip_env,
    )?;
    let csm_bin = workspace_root().join("target/debug/csm");
    run(
        &python,
        &["-m", "pytest", "-q", "python/tests"],
        &[("CSM_BIN", &csm_bin.to_string_lossy())],
    )
}

fn kratos_python() -> Result<String> {
    if let Ok(python) = std::env::var("KRATOS_PYTHON") {
        return Ok(python);
    }
    let venv = workspace_root().join("target/kratos-venv");
    let python = venv.join("bin/python");
    if !python.exists() {
        let venv = venv.to_string_lossy().into_owned();
        run("python3", &["-m", "venv", &venv], &[])?;
        let python = python.to_string_lossy().into_owned();
        let mut args = vec!["-m", "pip", "install", "--quiet"];
        args.extend(KRATOS_WHEELS);
        run(&python, &args, &[])?;
    }
    Ok(python.to_string_lossy().into_owned())
}

/// Runs every `tools/kratos_fixtures*.py`, in name order.
fn fixtures() -> Result<()> {
    let python = kratos_python()?;
    let env = [("OMP_NUM_THREADS", "1"), ("OMP_WAIT_POLICY", "passive")];
    let mut scripts: Vec<String> = std::fs::read_dir(workspace_root().join("tools"))?
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("kratos_fixtures") && n.ends_with(".py"))
        .collect();
    scripts.sort();
    for script in scripts {
        run(&python, &[&format!("tools/{script}")], &env)?;
    }
    Ok(())
}
