//! `study --real-peers`: the driver's answer and mesh are read and scored (from a committed
//! fixture, without Python); without the interpreter the study runs as without the flag; with
//! a stand-in interpreter (`fixtures/real_peers/fake_python`) the whole part runs and leaves
//! the paper's tables alone. The end-to-end run with the real tools is ignored by default.
use std::path::{Path, PathBuf};
use std::process::Command;
use study::paper::TABLES;
use study::peers::{self, Peer};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/real_peers")
}

/// Run the study on circle with TRIANGLE only (three fast jobs) into `out`.
fn study(out: &Path, extra: &[&str], env: &[(&str, &str)]) -> (i32, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_study"));
    cmd.args(["--regions", "circle", "--methods", "refine", "--no-graded"])
        .arg("--out")
        .arg(out)
        .args(extra)
        .env_remove("CVTMESH_PYTHON");
    for (k, v) in env {
        cmd.env(k, v);
    }
    let o = cmd.output().unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The paper's tables and the fidelity report of two runs are byte for byte the same.
fn assert_same_tables(a: &Path, b: &Path) {
    for n in 1..=3 {
        let name = format!("tables/table_{n:02}.md");
        assert_eq!(read(&a.join(&name)), read(&b.join(&name)), "{name}");
    }
    assert_eq!(read(&a.join("fidelity.md")), read(&b.join("fidelity.md")));
    assert_eq!(
        read(&a.join("csv/fidelity.csv")),
        read(&b.join("csv/fidelity.csv"))
    );
}

#[test]
fn the_drivers_answer_and_mesh_are_read_and_scored() {
    let stdout = read(&fixtures().join("driver_stdout.txt"));
    let printed = peers::parse_driver_output(&stdout).unwrap();
    assert_eq!((printed.k, printed.triangles), (20, 24));
    assert_eq!(printed.params, "pq20a0.20542415878918535155");
    let node = fixtures().join("circle_K19_triangle-real.node");
    let region = cvtmesh::Region::builtin("circle").unwrap();
    let row = peers::score_mesh(&TABLES[0], Peer::Triangle, &printed, &node, &region).unwrap();
    assert_eq!(
        (row.table, row.K_requested, row.K, row.Ktilde),
        (1, 19, 20, 24)
    );
    assert_eq!(row.peer, "triangle-real");
    // The values the exact measures gave this mesh when the real Triangle wrote it.
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
    assert!(close(row.beta, 0.46518780460558595), "β = {}", row.beta);
    assert!(close(row.q, 0.21748508620987206), "q = {}", row.q);
    assert!(row.error.is_empty());

    // An answer that disagrees with the files, or names the other tool, is refused.
    let wrong = peers::parse_driver_output(&stdout.replace("K=20", "K=21")).unwrap();
    let e = peers::score_mesh(&TABLES[0], Peer::Triangle, &wrong, &node, &region).unwrap_err();
    assert!(e.contains("the driver said 21 and 24"), "{e}");
    let e = peers::score_mesh(&TABLES[0], Peer::GmshFrontal, &printed, &node, &region).unwrap_err();
    assert!(e.contains("not 'gmsh-frontal'"), "{e}");
    // A missing mesh is an error, not a panic.
    let gone = fixtures().join("no_such_mesh.node");
    assert!(peers::score_mesh(&TABLES[0], Peer::Triangle, &printed, &gone, &region).is_err());
}

#[test]
fn without_the_interpreter_the_study_runs_as_without_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let (plain, flagged) = (dir.path().join("plain"), dir.path().join("flagged"));
    let (code, _) = study(&plain, &[], &[]);
    assert_eq!(code, 0);
    let bogus = dir.path().join("no/python");
    let (code, err) = study(
        &flagged,
        &["--real-peers", "--python", bogus.to_str().unwrap()],
        &[],
    );
    assert_eq!(code, 0, "{err}");
    let note: Vec<&str> = err.lines().filter(|l| l.contains("real peers")).collect();
    assert_eq!(note.len(), 1, "{err}");
    assert!(
        note[0].starts_with("note: real peers skipped: no Python interpreter at")
            && note[0].contains("scripts/compare_tools.sh"),
        "{err}"
    );
    assert_same_tables(&plain, &flagged);
    assert!(!peers::peers_md(&flagged).exists());
    assert!(!peers::peers_csv(&flagged).exists());
}

#[test]
fn a_stand_in_interpreter_runs_the_whole_part_and_leaves_the_tables_alone() {
    let dir = tempfile::tempdir().unwrap();
    let (plain, flagged) = (dir.path().join("plain"), dir.path().join("flagged"));
    let fake = fixtures().join("fake_python");
    let (code, _) = study(&plain, &[], &[]);
    assert_eq!(code, 0);
    let (code, err) = study(
        &flagged,
        &["--real-peers", "--python", fake.to_str().unwrap()],
        &[],
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("with gmsh=fake numpy=fake triangle=fake"),
        "{err}"
    );
    assert_same_tables(&plain, &flagged);

    let rows = peers::read_peers(&flagged).unwrap();
    assert_eq!(rows.len(), 6, "three circle tables × two tools");
    assert!(rows.iter().all(|r| r.error.is_empty() && r.K == 20));
    let md = read(&peers::peers_md(&flagged));
    assert!(
        md.contains("| 1 | circle | Gmsh-FD (real) | 19 | 20 | 24 |"),
        "{md}"
    );
    assert!(
        md.contains("| | TRIANGLE (ours) | Triangle (real) | Gmsh-FD (real) | paper's TRIANGLE |")
    );
    let fid = read(&peers::peers_fidelity_csv(&flagged));
    // Per table: TRIANGLE against the real Triangle and against Gmsh, 14 rows each.
    assert_eq!(fid.lines().count(), 1 + 3 * 2 * 14);

    // The report redraws the part from the CSV, identically.
    std::fs::remove_file(peers::peers_md(&flagged)).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_study"))
        .args(["report", "--out"])
        .arg(&flagged)
        .output()
        .unwrap();
    assert!(out.status.success());
    assert_eq!(read(&peers::peers_md(&flagged)), md);

    // Tools that fail leave rows with their errors, and a note; the study still succeeds.
    let (code, err) = study(
        &flagged,
        &["--real-peers-only", "--python", fake.to_str().unwrap()],
        &[("FAKE_PEERS_FAIL", "1")],
    );
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("real peers: 6 of 6 runs failed"), "{err}");
    let rows = peers::read_peers(&flagged).unwrap();
    assert!(rows
        .iter()
        .all(|r| r.error.contains("the fake tool failed") && r.beta.is_nan()));
    assert!(read(&peers::peers_md(&flagged)).contains("## Failed runs"));
    // --real-peers-only ran no method: the tables are still the first run's.
    assert_same_tables(&plain, &flagged);
}

/// With the real tools (scripts/.venv, made by scripts/compare_tools.sh, or $CVTMESH_PYTHON):
/// every run succeeds near the paper's K. `cargo test --release -p study -- --ignored`.
#[test]
#[ignore = "needs scripts/.venv with triangle and gmsh"]
fn the_real_tools_mesh_every_table_near_the_papers_k() {
    let python = peers::default_python();
    assert!(
        python.exists(),
        "{} is missing: run scripts/compare_tools.sh or set CVTMESH_PYTHON",
        python.display()
    );
    let dir = tempfile::tempdir().unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_study"));
    cmd.args([
        "--real-peers-only",
        "--regions",
        "circle,pie_hole,square_two_hex,bike_seat,superellipse",
        "--python",
    ])
    .arg(&python)
    .arg("--out")
    .arg(dir.path());
    let out = cmd.output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let rows = peers::read_peers(dir.path()).unwrap();
    assert_eq!(rows.len(), 2 * 7);
    for r in &rows {
        assert!(r.error.is_empty(), "{} {}: {}", r.region, r.peer, r.error);
        let off = (r.K as f64 - r.K_requested as f64).abs() / r.K_requested as f64;
        assert!(off <= 0.06, "{} {}: K = {}", r.region, r.peer, r.K);
        assert!(r.beta.is_finite() && r.q.is_finite());
        if r.peer == "triangle-real" {
            let q = format!("pq{}a", study::methods::TRIANGLE_MIN_ANGLE_DEG);
            assert!(r.params.starts_with(&q), "{}", r.params);
        }
    }
}
