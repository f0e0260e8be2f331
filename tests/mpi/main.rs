//! The search on MPI ranks (issue 29), with `mpirun` (feature `mpi`; `cargo xtask ci` installs
//! Open MPI where it can). A test without the harness: run by `cargo test`, it starts itself
//! under `mpirun` on 1 to 4 ranks, each run checking every Kratos fixture whose setup a
//! distributed run takes against the one-process search of the same mesh and setup (the
//! whole result but the timings, in both compatibility modes, 2D and 3D, every kd-tree
//! search type); then it runs `mpirun -np N csm search` on the stability scenes against
//! `csm search`, and a bad input on one rank (`mpirun … : …`) against the clear error it must
//! give on every rank.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Output};
use std::sync::Arc;

use csm::distributed::{MpiTransport, distributed_plan, search_rank};
use csm::model::Transport;
use csm::search::{ContactSearch, SearchResult, parse_setup};

/// The environment variable that makes this binary the sweep of one `mpirun`.
const SWEEP: &str = "CSM_MPI_TEST_SWEEP";

fn main() -> ExitCode {
    if std::env::var_os(SWEEP).is_some() && MpiTransport::launched() {
        return sweep();
    }
    // `cargo test` passes harness flags (`--quiet`, filters): a listing asks for none.
    if std::env::args().any(|a| a == "--list") {
        return ExitCode::SUCCESS;
    }
    let mpirun = mpirun();
    let mut failed = Vec::new();
    for ranks in 1..=4 {
        let me = std::env::current_exe().expect("the test binary's path");
        let out = Command::new(&mpirun)
            .args(mpirun_args(ranks))
            .arg(&me)
            .env(SWEEP, "1")
            .output()
            .expect("mpirun runs");
        print!("{}", String::from_utf8_lossy(&out.stdout));
        if !out.status.success() {
            eprint!("{}", String::from_utf8_lossy(&out.stderr));
            failed.push(format!("the fixture sweep on {ranks} ranks"));
        }
    }
    failed.extend(cli_scenes(&mpirun));
    failed.extend(profile_on_ranks(&mpirun));
    failed.extend(bad_input_on_one_rank(&mpirun));
    if failed.is_empty() {
        println!("mpi: every check passed");
        ExitCode::SUCCESS
    } else {
        eprintln!("mpi: failed: {failed:#?}");
        ExitCode::FAILURE
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `mpirun` on the path, or a failure that says what to install.
fn mpirun() -> PathBuf {
    let found = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|p| p.join("mpirun"))
            .find(|p| p.is_file())
    });
    found.unwrap_or_else(|| {
        panic!(
            "mpirun is not on the PATH: install Open MPI (Debian: apt-get install openmpi-bin \
             libopenmpi-dev libclang-dev; `cargo xtask ci` does it as root)"
        )
    })
}

/// `mpirun`'s arguments for `ranks` ranks on any machine (more ranks than cores, as root in
/// a container), one thread per rank.
fn mpirun_args(ranks: usize) -> Vec<String> {
    let mut args = vec![
        "--oversubscribe".to_owned(),
        "-np".to_owned(),
        ranks.to_string(),
        "-x".to_owned(),
        "RAYON_NUM_THREADS=1".to_owned(),
    ];
    if is_root() {
        args.insert(0, "--allow-run-as-root".to_owned());
    }
    args
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// A fixture: its path, mesh (resolved) and setup text.
struct Fixture {
    name: String,
    mesh: PathBuf,
    setup: String,
}

/// Every search fixture whose mesh is here, by name; each octree fixture (Kratos' setups
/// are kratos mode, which a distributed run refuses for the octree) also in robust mode.
fn fixtures() -> Vec<Fixture> {
    let dir = root().join("tests/fixtures/search");
    let mut files = Vec::new();
    for scene in std::fs::read_dir(&dir).expect("the fixtures") {
        let scene = scene.expect("a fixture directory").path();
        if !scene.is_dir() {
            continue;
        }
        for f in std::fs::read_dir(&scene).expect("a fixture directory") {
            let f = f.expect("a fixture").path();
            if f.extension().is_some_and(|e| e == "json") {
                files.push(f);
            }
        }
    }
    // The multi-step and dynamic-search fixtures.
    let steps = root().join("tests/fixtures/steps");
    for f in std::fs::read_dir(&steps).expect("the steps fixtures") {
        let f = f.expect("a fixture").path();
        if f.extension().is_some_and(|e| e == "json") {
            files.push(f);
        }
    }
    files.sort();
    files
        .into_iter()
        .filter_map(|f| {
            let text = std::fs::read_to_string(&f).expect("a fixture reads");
            let json: serde_json::Value = serde_json::from_str(&text).expect("a fixture parses");
            let mesh = root().join(json.get("mesh")?.as_str()?);
            let setup = json.get("setup")?;
            let name = (f.strip_prefix(&dir).or_else(|_| f.strip_prefix(root())))
                .unwrap_or(&f)
                .display()
                .to_string();
            let mut robust = setup.clone();
            let octree = setup.pointer("/search_parameters/type_search")
                == Some(&serde_json::json!("octree_with_obb"));
            let robust =
                (octree && setup.get("compatibility").is_none_or(|c| c == "kratos")).then(|| {
                    robust["compatibility"] = serde_json::json!("robust");
                    Fixture {
                        name: format!("{name} (robust)"),
                        mesh: mesh.clone(),
                        setup: robust.to_string(),
                    }
                });
            let kratos = Fixture {
                name,
                mesh: mesh.clone(),
                setup: setup.to_string(),
            };
            mesh.is_file().then_some([Some(kratos), robust])
        })
        .flatten()
        .flatten()
        .collect()
}

/// One `mpirun`: every fixture a distributed run takes, on these ranks, against the one
/// process search on rank 0. Every rank runs every fixture in the same order.
fn sweep() -> ExitCode {
    let transport: Arc<dyn Transport> =
        Arc::new(MpiTransport::start().expect("MPI starts under mpirun"));
    let (rank, ranks) = (transport.rank(), transport.ranks());
    let (mut checked, mut mismatches) = (0, Vec::new());
    // Why setups were refused, with how many.
    let mut refused: std::collections::BTreeMap<String, usize> = Default::default();
    for fixture in fixtures() {
        let model = csm::io::read_mesh(&fixture.mesh).expect("a fixture mesh reads");
        let setup = parse_setup(&fixture.setup, &fixture.name).expect("a fixture setup parses");
        if let Err(why) = distributed_plan(&setup) {
            // Refused alike on every rank, with the reason.
            let err = search_rank(Arc::clone(&transport), &model.to_arrays(), &setup)
                .expect_err("refused");
            assert!(err.0.contains(&why), "{}: {err}", fixture.name);
            *refused.entry(why).or_default() += 1;
            continue;
        }
        let got = search_rank(Arc::clone(&transport), &model.to_arrays(), &setup).map(|r| {
            r.map(|mut r| {
                for step in &mut r.steps {
                    step.search_s = 0.0;
                }
                r
            })
        });
        if rank != 0 {
            continue;
        }
        let serial = one_process(model, &setup);
        if let Err(e) = &got
            && e.0.contains("a distributed run does not support")
        {
            // Refused once the mesh is seen (contact parts without conditions).
            let why = e.0.split(": ").skip(1).collect::<Vec<_>>().join(": ");
            *refused.entry(why).or_default() += 1;
            continue;
        }
        checked += 1;
        match (got, serial) {
            (Ok(Some(got)), Ok(serial)) if got == serial => {}
            (Err(got), Err(serial)) if got.0.ends_with(&serial) => {}
            (got, serial) => mismatches.push(format!(
                "{}: {ranks} ranks gave {}, one process {}",
                fixture.name,
                describe(&got.map(Option::unwrap_or_default).map_err(|e| e.0)),
                describe(&serial)
            )),
        }
    }
    drop(transport);
    if rank != 0 {
        return ExitCode::SUCCESS;
    }
    println!(
        "mpi sweep, {ranks} ranks: {checked} fixtures identical to one process: {}; {} refused:",
        checked - mismatches.len(),
        refused.values().sum::<usize>()
    );
    for (why, n) in &refused {
        println!("  {n:4}  {why}");
    }
    if mismatches.is_empty() {
        ExitCode::SUCCESS
    } else {
        eprintln!("{mismatches:#?}");
        ExitCode::FAILURE
    }
}

/// The search of the whole model in this process, as `csm search` runs it.
fn one_process(
    mut model: csm::model::ModelPart,
    setup: &csm::search::SearchSetup,
) -> Result<SearchResult, String> {
    let mut search = ContactSearch::initialize(&mut model, setup).map_err(|e| e.to_string())?;
    if setup.steps.is_empty() {
        return search.step(&mut model).map_err(|e| e.to_string());
    }
    let mut result =
        (search.run_steps(&mut model, &setup.steps, |_, _, _| {})).map_err(|e| e.to_string())?;
    // (Wall times are not compared.)
    for step in &mut result.steps {
        step.search_s = 0.0;
    }
    Ok(result)
}

fn describe(r: &Result<SearchResult, String>) -> String {
    match r {
        Ok(r) => format!(
            "{} pairs, {} active nodes, warnings {:?}",
            r.n_pairs(),
            r.nodes.values().filter(|n| n.active).count(),
            r.warnings
        ),
        Err(e) => format!("the error `{e}`"),
    }
}

/// RESULT.json without its timings.
fn result_of(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).expect("RESULT.json reads");
    let mut json: serde_json::Value = serde_json::from_str(&text).expect("RESULT.json parses");
    json.as_object_mut().expect("an object").remove("timings_s");
    json
}

/// `csm search MESH --setup SETUP -o OUTPUT --quiet`, alone or under `mpirun` (`runner`:
/// `mpirun` and the rank count).
fn csm_search(
    runner: Option<(&Path, usize)>,
    (mesh, setup, output): (&Path, &Path, &Path),
) -> Output {
    let mut cmd = match runner {
        Some((mpirun, ranks)) => {
            let mut cmd = Command::new(mpirun);
            cmd.args(mpirun_args(ranks)).arg(env!("CARGO_BIN_EXE_csm"));
            cmd
        }
        None => Command::new(env!("CARGO_BIN_EXE_csm")),
    };
    cmd.arg("search")
        .arg(mesh)
        .arg("--setup")
        .arg(setup)
        .arg("-o")
        .arg(output)
        .arg("--quiet")
        .output()
        .expect("csm runs")
}

/// A directory of its own for one check, with `robust.json`: the scenes' parts, robust mode,
/// the Advanced activation.
fn work_dir(check: &str) -> (PathBuf, PathBuf) {
    let dir = std::env::temp_dir().join(format!("csm-mpi-{check}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let robust = dir.join("robust.json");
    std::fs::write(
        &robust,
        r#"{"contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
            "assume_master_slave": {"0": ["Parts_Slave"]},
            "compatibility": "robust",
            "search_parameters": {"simple_search": false}}"#,
    )
    .expect("a setup writes");
    (dir, robust)
}

/// `mpirun -np N csm search` writes the RESULT.json of `csm search` (but the timings) on three
/// of the stability scenes, in robust mode with the Advanced activation (`work_dir`).
fn cli_scenes(mpirun: &Path) -> Vec<String> {
    let (dir, robust) = work_dir("scenes");
    let mut failed = Vec::new();
    for scene in [
        "stacked_blocks.mdpa",
        "sphere_on_plate_tri.mdpa",
        "cylinder_on_block_2d.mdpa",
    ] {
        let mesh = root().join("tests/data/scenes").join(scene);
        let serial = dir.join("serial.json");
        let out = csm_search(None, (&mesh, &robust, &serial));
        assert!(
            out.status.success(),
            "{scene}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        for ranks in [2, 3] {
            let got = dir.join(format!("ranks{ranks}.json"));
            let out = csm_search(Some((mpirun, ranks)), (&mesh, &robust, &got));
            if !out.status.success() {
                failed.push(format!(
                    "{scene}, {ranks} ranks: {}",
                    String::from_utf8_lossy(&out.stderr)
                ));
            } else if result_of(&got) != result_of(&serial) {
                failed.push(format!("{scene}, {ranks} ranks: RESULT.json differs"));
            } else {
                println!("mpirun -np {ranks} csm search {scene}: the RESULT.json of csm search");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    failed
}

/// `mpirun -np 2 csm search --profile`: rank 0 writes the stage profile of its part, its
/// stages in the phases they ran in, with every rank's phase times; `--vtk` is refused with
/// a message on every rank.
fn profile_on_ranks(mpirun: &Path) -> Vec<String> {
    let (dir, robust) = work_dir("profile");
    let mesh = root().join("tests/data/scenes/stacked_blocks.mdpa");
    let (result, profile) = (dir.join("result.json"), dir.join("profile.json"));
    let run = |more: &[&str]| {
        let mut cmd = Command::new(mpirun);
        cmd.args(mpirun_args(2)).arg(env!("CARGO_BIN_EXE_csm"));
        cmd.arg("search").arg(&mesh).arg("--setup").arg(&robust);
        cmd.arg("-o").arg(&result).arg("--quiet").args(more);
        cmd.output().expect("mpirun runs")
    };
    let mut failed = Vec::new();
    let out = run(&["--profile", &profile.to_string_lossy()]);
    let json: Option<serde_json::Value> = std::fs::read_to_string(&profile)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let stage_in = |p: &serde_json::Value, phase: &str, stage: &str| {
        (p["stages"].as_array().into_iter().flatten())
            .any(|s| s["phase"] == phase && s["stage"] == stage)
    };
    match json {
        _ if !out.status.success() => failed.push(format!(
            "--profile on 2 ranks: {}",
            String::from_utf8_lossy(&out.stderr)
        )),
        Some(p)
            if p["format"] == "csm-profile/1"
                && p["ranks"].as_array().is_some_and(|r| {
                    r.len() == 2 && r.iter().all(|t| t["search"].as_f64().is_some())
                })
                && ["read", "initialize", "search", "write", "total"]
                    .iter()
                    .all(|k| p["phases"][k].as_f64().is_some())
                && stage_in(&p, "initialize", "normal check")
                && stage_in(&p, "search", "mapping")
                && stage_in(&p, "write", "RESULT.json") =>
        {
            println!("mpirun -np 2 csm search --profile: rank 0's stages, every rank's phases");
        }
        p => failed.push(format!("--profile on 2 ranks wrote {p:?}")),
    }
    let out = run(&["--vtk", &dir.join("out.vtu").to_string_lossy()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let refused = stderr
        .lines()
        .filter(|l| l.contains("--vtk: a distributed run does not write it yet"))
        .count();
    if out.status.success() || refused != 2 {
        failed.push(format!("--vtk on 2 ranks: {stderr}"));
    } else {
        println!("mpirun -np 2 csm search --vtk: refused on every rank");
    }
    let _ = std::fs::remove_dir_all(&dir);
    failed
}

/// One rank of three given a mesh that is not there: every rank stops with its error, the
/// run exits non-zero, nothing hangs.
fn bad_input_on_one_rank(mpirun: &Path) -> Vec<String> {
    let good = root().join("tests/data/scenes/stacked_blocks.mdpa");
    let missing = root().join("tests/data/scenes/no_such_mesh.mdpa");
    let csm = env!("CARGO_BIN_EXE_csm");
    let (dir, robust) = work_dir("bad-input");
    let mut cmd = Command::new(mpirun);
    if is_root() {
        cmd.arg("--allow-run-as-root");
    }
    // mpirun stops the job at the first rank's non-zero exit (and so exits non-zero): every
    // rank has printed its error before any exits (they wait for each other after printing).
    // Three programs of one rank each, one world: `mpirun A : B : C`.
    for (k, mesh) in [&good, &missing, &good].into_iter().enumerate() {
        if k > 0 {
            cmd.arg(":");
        }
        cmd.args(["--oversubscribe", "-np", "1", csm, "search"])
            .arg(mesh)
            .arg("--setup")
            .arg(&robust)
            .args(["-o", "/dev/null", "--quiet"]);
    }
    let out = cmd.output().expect("mpirun runs");
    let _ = std::fs::remove_dir_all(&dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let errors: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("error: "))
        .collect();
    let mut failed = Vec::new();
    if out.status.success() {
        failed.push("a missing mesh on rank 1: the run succeeded".to_owned());
    }
    if errors.len() != 3 || errors.iter().any(|e| *e != errors[0]) {
        failed.push(format!(
            "a missing mesh on rank 1: not one error on every rank: {errors:?}"
        ));
    } else if !errors[0].starts_with("error: rank 1 of 3: ")
        || !errors[0].contains("no_such_mesh.mdpa")
    {
        failed.push(format!("a missing mesh on rank 1: {}", errors[0]));
    } else {
        println!(
            "a missing mesh on rank 1 of 3: `{}` on every rank",
            errors[0]
        );
    }
    failed
}
