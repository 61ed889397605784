//! The binary's argument handling: bad names are clear errors with a non-zero exit, before
//! any job runs or any file is written.
use std::process::Command;

fn study(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_study"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn unknown_names_and_bad_options_fail_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never");
    let out = out.to_str().unwrap();
    let (code, err) = study(&["--methods", "distmesh,lloyd", "--out", out]);
    assert_ne!(code, 0);
    assert!(
        err.contains("unknown method 'lloyd'") && err.contains("ccvt-fast"),
        "{err}"
    );
    let (code, err) = study(&["--regions", "moon", "--out", out]);
    assert_ne!(code, 0);
    assert!(
        err.contains("unknown region 'moon'") && err.contains("bike_seat"),
        "{err}"
    );
    let (code, err) = study(&["--shard", "9/8", "--out", out]);
    assert_ne!(code, 0);
    assert!(err.contains("bad shard '9/8'"), "{err}");
    let (code, _) = study(&["--seeds", "0", "--out", out]);
    assert_ne!(code, 0);
    let (code, err) = study(&[
        "merge",
        "--out",
        out,
        dir.path().join("no_such_shard").to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("metrics.csv"), "{err}");
    // Said once, not once as the message and again as its cause.
    assert_eq!(
        err.matches("is this a study output directory").count(),
        1,
        "{err}"
    );
    // A report of a directory no study wrote is refused, not an empty summary.
    let (code, err) = study(&["report", "--out", out]);
    assert_ne!(code, 0);
    assert!(err.contains("is this a study output directory"), "{err}");
    assert!(!dir.path().join("never").exists());
}

#[test]
fn a_merge_of_some_shards_of_a_run_fails_naming_the_missing_ones() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec!["merge".to_string()];
    for i in [1, 2] {
        let shard = dir.path().join(format!("shard_{i}"));
        let csv = shard.join("csv");
        std::fs::create_dir_all(&csv).unwrap();
        let metrics = format!("{}\n", study::record::METRICS_HEADER);
        std::fs::write(csv.join("metrics.csv"), metrics).unwrap();
        let record = format!(
            "index,count,seeds,first_seed,regions,methods,graded_methods\n\
             {i},4,1,1,circle,\"refine,vtm\",\n"
        );
        std::fs::write(csv.join("shard.csv"), record).unwrap();
        args.push(shard.to_str().unwrap().to_string());
    }
    let out = dir.path().join("merged");
    args.extend(["--out".to_string(), out.to_str().unwrap().to_string()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, err) = study(&args);
    assert_ne!(code, 0);
    assert!(
        err.contains("shards 3/4, 4/4 missing") && err.contains("tables of circle with refine,vtm"),
        "{err}"
    );
    assert!(!out.exists());
}
