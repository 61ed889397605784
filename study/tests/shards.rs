//! End to end with real methods: a run split into two shards and merged gives the same CSV as
//! the unsharded run (all but the timing column), and the merge draws tables and figures from
//! the shards' stored meshes; a run extended to more seeds with `first_seed` equals one that
//! ran them all at once.
use std::path::Path;
use study::{output, record, MethodId, Row, Shard, StudyOptions};

fn rows(dir: &Path) -> Vec<Row> {
    let mut r: Vec<Row> = record::read_csv(&output::metrics_csv(dir)).unwrap();
    for row in &mut r {
        row.seconds = 0.0;
    }
    r
}

#[test]
fn sharded_then_merged_equals_unsharded() {
    let tmp = tempfile::tempdir().unwrap();
    let base = StudyOptions {
        regions: vec!["square_two_hex"],
        methods: vec![MethodId::Meshgen, MethodId::CcvtFast],
        seeds: 2,
        threads: Some(2),
        graded: false,
        ..StudyOptions::default()
    };
    let whole = tmp.path().join("whole");
    let o = study::run_study(
        &StudyOptions {
            out: whole.clone(),
            ..base.clone()
        },
        &|_| {},
    )
    .unwrap();
    assert_eq!(o.jobs, 4);
    assert!(o.failures.is_empty(), "{:?}", o.failures);

    let mut shard_dirs = Vec::new();
    for i in 1..=2 {
        let d = tmp.path().join(format!("shard_{i}"));
        let o = study::run_study(
            &StudyOptions {
                out: d.clone(),
                shard: Some(Shard { index: i, count: 2 }),
                ..base.clone()
            },
            &|_| {},
        )
        .unwrap();
        assert_eq!(o.jobs, 2);
        // A shard writes the CSV and meshes only, and which shard of which jobs it is.
        assert!(!d.join("tables").exists() && !d.join("figures").exists());
        let record = study::ShardRecord::read(&d).unwrap().unwrap();
        assert_eq!((record.index, record.count, record.seeds), (i, 2, 2));
        shard_dirs.push(d);
    }
    assert!(!output::shard_csv(&whole).exists());
    // One shard is not the run.
    let half = tmp.path().join("half");
    let e = study::merge(&shard_dirs[1..], &half)
        .unwrap_err()
        .to_string();
    assert!(e.contains("shard 1/2 missing"), "{e}");
    assert!(!half.exists());
    let merged = tmp.path().join("merged");
    study::merge(&shard_dirs, &merged).unwrap();

    let (a, b) = (rows(&whole), rows(&merged));
    assert_eq!(a.len(), 4 * 2);
    assert_eq!(a, b);
    for d in [&whole, &merged] {
        assert!(output::table_md(d, 11).exists());
        assert!(output::summary_md(d).exists());
        assert!(output::figure_png(d, 6).exists());
        assert!(output::mesh_png(d, "square_two_hex", 203, MethodId::CcvtFast).exists());
    }
    assert_eq!(
        std::fs::read_to_string(output::table_md(&whole, 11)).unwrap(),
        std::fs::read_to_string(output::table_md(&merged, 11)).unwrap()
    );
}

#[test]
fn extending_a_run_to_more_seeds_equals_running_them_at_once() {
    let tmp = tempfile::tempdir().unwrap();
    let base = StudyOptions {
        regions: vec!["square_two_hex"],
        methods: vec![MethodId::Meshgen],
        threads: Some(2),
        graded: false,
        ..StudyOptions::default()
    };
    let whole = tmp.path().join("whole");
    study::run_study(
        &StudyOptions {
            seeds: 3,
            out: whole.clone(),
            ..base.clone()
        },
        &|_| {},
    )
    .unwrap();
    let grown = tmp.path().join("grown");
    for (first_seed, seeds) in [(1, 1), (2, 3)] {
        let o = study::run_study(
            &StudyOptions {
                first_seed,
                seeds,
                out: grown.clone(),
                ..base.clone()
            },
            &|_| {},
        )
        .unwrap();
        assert_eq!(o.jobs as u64, seeds + 1 - first_seed);
    }
    assert_eq!(rows(&whole), rows(&grown));
    // Three seeds are enough for the significance section to be drawn, and for its CSV.
    assert!(output::significance_csv(&grown).exists());
    // Seed 1 run again keeps seeds 2 and 3 (else tables "over seeds 1–3" would hold one).
    study::run_study(
        &StudyOptions {
            out: grown.clone(),
            ..base.clone()
        },
        &|_| {},
    )
    .unwrap();
    assert_eq!(rows(&whole), rows(&grown));
    // A first seed beyond the last is refused.
    let bad = study::run_study(
        &StudyOptions {
            first_seed: 4,
            seeds: 3,
            out: grown,
            ..base
        },
        &|_| {},
    );
    assert!(bad.is_err());
}

#[test]
fn graded_part_sharded_then_merged_equals_unsharded() {
    use study::graded;
    let tmp = tempfile::tempdir().unwrap();
    let base = StudyOptions {
        paper: false,
        graded_methods: vec![MethodId::Triangle],
        seeds: 2,
        threads: Some(2),
        ..StudyOptions::default()
    };
    let whole = tmp.path().join("whole");
    let o = study::run_study(
        &StudyOptions {
            out: whole.clone(),
            ..base.clone()
        },
        &|_| {},
    )
    .unwrap();
    assert_eq!(o.jobs, 3 * 2);
    assert!(o.failures.is_empty(), "{:?}", o.failures);
    assert!(
        o.notes.iter().any(|n| n.contains("no summary.md")),
        "{:?}",
        o.notes
    );
    let mut shard_dirs = Vec::new();
    for i in 1..=2 {
        let d = tmp.path().join(format!("shard_{i}"));
        study::run_study(
            &StudyOptions {
                out: d.clone(),
                shard: Some(Shard { index: i, count: 2 }),
                ..base.clone()
            },
            &|_| {},
        )
        .unwrap();
        shard_dirs.push(d);
    }
    let merged = tmp.path().join("merged");
    study::merge(&shard_dirs, &merged).unwrap();
    let read = |d: &Path| {
        let (mut rows, failures) = graded::read_graded(d).unwrap();
        assert!(failures.is_empty());
        for r in &mut rows {
            r.seconds = 0.0;
        }
        rows
    };
    let a = read(&whole);
    assert_eq!(a.len(), 6);
    assert_eq!(a, read(&merged));
    for d in [&whole, &merged] {
        let md = std::fs::read_to_string(graded::graded_md_path(d)).unwrap();
        assert!(md.contains("| TRIANGLE | "), "{md}");
        assert!(md.contains("means over 2 seeds"), "{md}");
        for case in &graded::CASES {
            assert!(graded::graded_png(d, case.name).exists(), "{}", case.name);
        }
        // Nothing of the paper's tables ran: a summary and fidelity report of them would be
        // empty tables.
        assert!(!output::summary_md(d).exists() && !output::fidelity_md(d).exists());
    }
    // A graded-only run, even with `fresh`, leaves the paper's CSV alone.
    let metrics = output::metrics_csv(&whole);
    let row = Row::new(
        "circle",
        19,
        MethodId::Triangle,
        1,
        study::Kind::Exact,
        [1.0; 14],
        1,
        true,
        0.1,
    );
    std::fs::write(&metrics, record::rows_csv(&[row]).unwrap()).unwrap();
    let before = std::fs::read(&metrics).unwrap();
    study::run_study(
        &StudyOptions {
            out: whole.clone(),
            fresh: true,
            seeds: 2,
            first_seed: 2,
            ..base
        },
        &|_| {},
    )
    .unwrap();
    assert_eq!(std::fs::read(&metrics).unwrap(), before);
    // With a row of the paper's tables in the directory they are drawn.
    assert!(output::summary_md(&whole).exists() && output::fidelity_md(&whole).exists());
}

#[test]
fn an_output_directory_that_cannot_be_made_fails_before_any_job() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("a_file");
    std::fs::write(&file, "").unwrap();
    let events = std::sync::atomic::AtomicUsize::new(0);
    let e = study::run_study(
        &StudyOptions {
            regions: vec!["circle"],
            methods: vec![MethodId::Meshgen],
            graded: false,
            out: file.join("out"),
            ..StudyOptions::default()
        },
        &|_| {
            events.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("a_file"), "{e}");
    assert_eq!(events.load(std::sync::atomic::Ordering::Relaxed), 0);
}

#[test]
fn a_refused_merge_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let run = tmp.path().join("run");
    study::run_study(
        &StudyOptions {
            regions: vec!["square_two_hex"],
            methods: vec![MethodId::Meshgen],
            threads: Some(2),
            graded: false,
            out: run.clone(),
            ..StudyOptions::default()
        },
        &|_| {},
    )
    .unwrap();
    // The same rows twice: refused before any mesh is copied.
    let out = tmp.path().join("merged");
    assert!(study::merge(&[run.clone(), run], &out).is_err());
    assert!(!out.exists() || std::fs::read_dir(&out).unwrap().next().is_none());
}
