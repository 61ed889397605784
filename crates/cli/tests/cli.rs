//! End-to-end tests of the `cvtmesh` binary: every command, formats, and the errors users hit.
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn cvtmesh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cvtmesh"))
        .args(args)
        .output()
        .expect("run cvtmesh")
}

/// `cvtmesh mesh REGION -n K EXTRA... -q -o OUT`.
fn quiet_mesh(region: &str, k: &str, extra: &[&str], out: &std::path::Path) -> Output {
    let mut args = vec!["mesh", region, "-n", k];
    args.extend_from_slice(extra);
    args.extend(["-q", "-o", s(out)]);
    cvtmesh(&args)
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// A fresh scratch directory per test, removed when the test ends (even when it fails).
struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = std::path::Path;
    fn deref(&self) -> &std::path::Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn scratch(name: &str) -> Scratch {
    let d = std::env::temp_dir().join(format!("cvtmesh-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    Scratch(d)
}

fn s(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn regions_lists_the_ten_builtins() {
    let o = cvtmesh(&["regions"]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    let names = cvtmesh::geometry::Region::builtin_names();
    assert_eq!(names.len(), 10);
    for name in names {
        let title = cvtmesh::geometry::Region::builtin_title(name).unwrap();
        assert!(!title.is_empty(), "{name} has no title");
        let row = t
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name));
        assert!(
            row.is_some_and(|l| l.ends_with(title)),
            "no row for {name} ending with its title in\n{t}"
        );
    }
}

#[test]
fn version_is_printed_by_both_flags() {
    for flag in ["--version", "-V"] {
        let o = cvtmesh(&[flag]);
        assert!(o.status.success(), "{flag}: {}", text(&o));
        assert_eq!(
            String::from_utf8_lossy(&o.stdout).trim(),
            format!("cvtmesh {}", env!("CARGO_PKG_VERSION")),
            "{flag}"
        );
    }
    assert_eq!(env!("CARGO_PKG_VERSION"), "0.1.0");
}

/// Help text of `cvtmesh ARGS --help`.
fn help(args: &[&str]) -> String {
    let mut all = args.to_vec();
    all.push("--help");
    let o = cvtmesh(&all);
    assert!(o.status.success(), "{args:?}: {}", text(&o));
    // One line per option: clap puts descriptions beside the flags or, when they are long,
    // on the lines below (indented further); either way they are joined to their flag.
    let mut joined = String::new();
    for line in String::from_utf8_lossy(&o.stdout).lines() {
        if line.starts_with("          ") && !joined.is_empty() {
            joined.pop();
            joined.push(' ');
            joined.push_str(line.trim_start());
        } else {
            joined.push_str(line);
        }
        joined.push('\n');
    }
    joined
}

/// The help line of option `--name`.
fn option_line<'h>(help: &'h str, name: &str) -> &'h str {
    let flag = format!("--{name} ");
    help.lines()
        .find(|l| l.trim_start().starts_with(&flag) || l.contains(&format!(", {flag}")))
        .unwrap_or_else(|| panic!("no --{name} in\n{help}"))
}

#[test]
fn help_names_every_default() {
    let mesh = help(&["mesh"]);
    for (option, default) in [
        ("method", "ccvt"),
        ("seed", "1"),
        ("tol", "1e-4"),
        ("max-iter", "10000"),
        ("density", "1, a uniform mesh"),
        ("corner-angle", "30, or the corners the region lists"),
        ("simplify", "none, the boundary as given"),
    ] {
        let line = option_line(&mesh, option);
        assert!(
            line.contains(&format!("[default: {default}]")),
            "--{option}: {line}"
        );
    }
    let method = option_line(&mesh, "method");
    for m in cvtmesh::Method::ALL {
        assert!(method.contains(m.name()), "{m} missing: {method}");
    }
    let measure = help(&["measure"]);
    assert!(option_line(&measure, "scale").contains("[default: 1]"));
    assert!(option_line(&measure, "sampled").contains("[default: none"));
    let show = help(&["show"]);
    assert!(option_line(&show, "px").contains("[default: 1200]"));
    assert!(option_line(&show, "colour").contains("[default: none"));
    assert!(option_line(&show, "region").contains("[default: none: the mesh's own boundary"));

    // Every option that takes a value names its default, unless it is required.
    let required = ["points", "size", "output", "region"];
    for (command, text) in [("mesh", &mesh), ("measure", &measure), ("show", &show)] {
        for line in text.lines().map(str::trim_start) {
            let Some(start) = line.find("--") else {
                continue;
            };
            if !(line.starts_with("--") || line.starts_with('-')) {
                continue;
            }
            let name: String = line[start + 2..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                .collect();
            let takes_value = line[start..]
                .split_whitespace()
                .nth(1)
                .is_some_and(|w| w.starts_with('<'));
            let required_here =
                required.contains(&name.as_str()) && !(command == "show" && name == "region");
            if takes_value && !required_here {
                assert!(line.contains("[default: "), "{command} --{name}: {line}");
            }
        }
    }
}

#[test]
fn mesh_then_measure_csv_round_trip() {
    let d = scratch("roundtrip");
    let out = d.join("c.node");
    let o = cvtmesh(&["mesh", "circle", "--points", "88", "--quiet", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("K=88") && t.contains("converged"), "{t}");
    assert!(out.exists() && d.join("c.ele").exists());
    let o = cvtmesh(&["measure", s(&out), "--region", "circle", "--csv"]);
    assert!(o.status.success(), "{}", text(&o));
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    assert_eq!(
        lines[0],
        "K,Ktilde,lambda,gamma,h,mu,chi,nu,tau,d,alpha,beta,q,p"
    );
    let v: Vec<f64> = lines[1].split(',').map(|x| x.parse().unwrap()).collect();
    assert_eq!(v.len(), 14);
    assert_eq!(v[0], 88.0);
    assert!(v[2..].iter().all(|x| x.is_finite() && *x >= 0.0), "{v:?}");
    // Readable table without --csv, with the smallest angle that `mesh` printed.
    let o = cvtmesh(&["measure", s(&out), "--region", "circle"]);
    assert!(o.status.success() && text(&o).contains("lambda"));
    let angle = |t: &str, key: &str, end: &str| {
        let at = t.find(key).unwrap() + key.len();
        t[at..].split(end).next().unwrap().to_string()
    };
    let made = cvtmesh(&["mesh", "circle", "--points", "88", "--quiet", "-o", s(&out)]);
    let printed: f64 = angle(&text(&made), "min-angle=", "deg").parse().unwrap();
    let measured: f64 = angle(&text(&o), "smallest angle ", "°").parse().unwrap();
    assert!((printed - measured).abs() < 0.01, "{printed} {measured}");
    // Too few samples for the cells: the inf that follows is explained; enough: no note.
    for (n, note) in [("50", true), ("20000", false)] {
        let o = cvtmesh(&["measure", s(&out), "--region", "circle", "--sampled", n]);
        assert!(o.status.success(), "{}", text(&o));
        assert_eq!(
            text(&o).contains("got none of the"),
            note,
            "{n}: {}",
            text(&o)
        );
    }
    // A mesh of another region is refused by name, not measured into nonsense.
    let o = cvtmesh(&["measure", s(&out), "--region", "lake"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("not a mesh of that region"),
        "{}",
        text(&o)
    );
    // A scale without the sampled estimate it scales is refused, not ignored.
    let o = cvtmesh(&["measure", s(&out), "--region", "circle", "--scale", "0.5"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--sampled"), "{}", text(&o));
}

/// `cvtmesh measure … | head -1`: the reader goes away before the table is printed. The
/// command ends quietly with success, as Unix tools do, instead of a panic.
#[test]
fn a_closed_pipe_on_standard_output_is_not_a_panic() {
    use std::process::Stdio;
    let d = scratch("pipe");
    let out = d.join("c.node");
    let o = quiet_mesh("circle", "3000", &[], &out);
    assert!(o.status.success(), "{}", text(&o));
    for extra in [&["--csv"][..], &[][..]] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_cvtmesh"))
            .args(["measure", s(&out), "--region", "circle"])
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("run cvtmesh");
        // Close the read end before the measures of 3000 vertices are ready to print.
        drop(child.stdout.take());
        let o = child.wait_with_output().expect("wait for cvtmesh");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("panicked"), "{err}");
        assert!(o.status.success(), "{:?}: {err}", o.status);
    }
}

#[test]
fn every_output_format_is_written_and_meshes_read_back() {
    let d = scratch("formats");
    for ext in ["msh", "vtu", "obj", "svg", "png", "node"] {
        let out = d.join(format!("m.{ext}"));
        let o = cvtmesh(&[
            "mesh",
            "square_two_hex",
            "--points",
            "203",
            "--method",
            "ccvt",
            "--quiet",
            "-o",
            s(&out),
        ]);
        assert!(o.status.success(), "{ext}: {}", text(&o));
        let len = std::fs::metadata(&out).unwrap().len();
        assert!(len > 100, "{ext}: {len} bytes");
    }
    // The formats that read back give the same mesh: the same seed, vertices and triangles
    // (`.msh` and `.obj` print coordinates to the last bit, as `.node` does).
    let node = cvtmesh::io::read_mesh(&d.join("m.node")).unwrap();
    assert_eq!(node.num_vertices(), 203);
    for ext in ["msh", "obj"] {
        let m = cvtmesh::io::read_mesh(&d.join(format!("m.{ext}"))).unwrap();
        assert_eq!(m.points, node.points, "{ext}");
        assert_eq!(m.triangles, node.triangles, "{ext}");
    }
    let vtu = std::fs::read_to_string(d.join("m.vtu")).unwrap();
    assert!(
        vtu.contains("NumberOfPoints=\"203\"")
            && vtu.contains(&format!("NumberOfCells=\"{}\"", node.triangles.len())),
        "{}",
        &vtu[..vtu.len().min(400)]
    );
    let o = cvtmesh(&[
        "measure",
        s(&d.join("m.msh")),
        "--region",
        "square_two_hex",
        "--csv",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = cvtmesh(&[
        "show",
        s(&d.join("m.node")),
        "--region",
        "square_two_hex",
        "--colour",
        "min-angle",
        "-o",
        s(&d.join("q.png")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = cvtmesh(&["show", "lake", "-o", s(&d.join("lake.svg"))]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(std::fs::read_to_string(d.join("lake.svg"))
        .unwrap()
        .contains("<svg"));
}

/// Mean length of the mesh's edges (counted once per triangle side) whose midpoint `near`
/// accepts.
fn mean_edge_where(m: &cvtmesh::Mesh, near: impl Fn(cvtmesh::DVec2) -> bool) -> f64 {
    let (mut sum, mut n) = (0.0, 0);
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b) = (m.points[t[k] as usize], m.points[t[(k + 1) % 3] as usize]);
            if near(0.5 * (a + b)) {
                sum += (b - a).length();
                n += 1;
            }
        }
    }
    sum / n as f64
}

/// Number of edges used by exactly one triangle of the mesh in `path`.
fn boundary_edge_count(path: &std::path::Path) -> usize {
    let mesh = cvtmesh::io::read_mesh(path).unwrap();
    let mut uses = std::collections::HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses.values().filter(|&&n| n == 1).count()
}

#[test]
fn show_draws_a_mesh_without_its_region() {
    let d = scratch("showme");
    let mesh = d.join("sq.msh");
    let o = cvtmesh(&[
        "mesh",
        "square_hole",
        "--points",
        "300",
        "--quiet",
        "-o",
        s(&mesh),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let expected = boundary_edge_count(&mesh);
    // The square and its square hole: at least the 8 corners' edges.
    assert!(expected >= 8, "{expected}");

    let png = d.join("sq.png");
    let o = cvtmesh(&["show", s(&mesh), "-o", s(&png)]);
    assert!(o.status.success(), "{}", text(&o));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR");
    let dim = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    // The square region at 1200 px plus margins and the title.
    let (w, h) = (dim(16), dim(20));
    assert!(
        (1200..1400).contains(&w) && (1200..1500).contains(&h),
        "{w}x{h}"
    );

    let svg = d.join("sq.svg");
    let o = cvtmesh(&["show", s(&mesh), "-o", s(&svg)]);
    assert!(o.status.success(), "{}", text(&o));
    let doc = std::fs::read_to_string(&svg).unwrap();
    assert!(doc.starts_with("<?xml") && doc.trim_end().ends_with("</svg>"));
    assert!(doc.contains(">sq.msh K=300 K~="), "title names the file");
    let boundary: Vec<&str> = doc
        .lines()
        .filter(|l| l.contains(r#"class="boundary""#))
        .collect();
    assert_eq!(boundary.len(), 1, "one boundary path");
    assert!(boundary[0].contains(r##"stroke="#000000""##));
    assert_eq!(
        boundary[0].matches('M').count(),
        expected,
        "one boundary stroke per edge of exactly one triangle"
    );

    let coloured = d.join("angles.svg");
    let o = cvtmesh(&[
        "show",
        s(&mesh),
        "--colour",
        "min-angle",
        "-o",
        s(&coloured),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let doc = std::fs::read_to_string(&coloured).unwrap();
    let filled: usize = doc
        .lines()
        .filter(|l| l.contains(r#"class="fill""#))
        .map(|l| l.matches('Z').count())
        .sum();
    let triangles = cvtmesh::io::read_mesh(&mesh).unwrap().num_triangles();
    assert_eq!(filled, triangles, "every triangle coloured once");
    assert!(doc.contains(">min-angle</text>"), "colour bar label");
    assert_eq!(doc.matches(r#"class="boundary""#).count(), 1);

    // --px sets the drawing's size.
    let small = d.join("small.png");
    let o = cvtmesh(&["show", s(&mesh), "--px", "300", "-o", s(&small)]);
    assert!(o.status.success(), "{}", text(&o));
    let bytes = std::fs::read(&small).unwrap();
    let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    assert!((300..400).contains(&w), "{w}");

    // Unreadable meshes, unknown picture types and absurd sizes are refused and write nothing.
    let out = d.join("never.svg");
    assert_refused(
        &["show", s(&mesh), "--px", "5", "-o", s(&out)],
        &out,
        "--px",
    );
    let out = d.join("never.png");
    assert_refused(
        &["show", s(&d.join("missing.msh")), "-o", s(&out)],
        &out,
        "missing.msh",
    );
    let o = cvtmesh(&["show", s(&d.join("missing.msh")), "-o", s(&out)]);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    // The system's message (ending "(os error N)") once, not again as the error's cause.
    assert_eq!(err.matches("(os error").count(), 1, "{err}");
    for picture in ["never.gif", "never.msh"] {
        let out = d.join(picture);
        assert_refused(
            &["show", s(&mesh), "-o", s(&out)],
            &out,
            "show writes .png or .svg",
        );
    }
}

#[test]
fn each_method_is_reachable() {
    let d = scratch("methods");
    for m in ["ccvt1", "ccvt2", "distmesh", "meshgen", "vtm", "refine"] {
        let out = d.join(format!("{m}.node"));
        let o = cvtmesh(&[
            "mesh",
            "circle",
            "--points",
            "88",
            "--method",
            m,
            "--quiet",
            "-o",
            s(&out),
        ]);
        assert!(o.status.success(), "{m}: {}", text(&o));
        assert!(out.exists());
    }
}

#[test]
fn strict_turns_a_capped_run_into_an_error_but_keeps_the_mesh() {
    let d = scratch("strict");
    let out = d.join("m.node");
    let o = cvtmesh(&[
        "mesh",
        "circle",
        "--points",
        "88",
        "--method",
        "ccvt1",
        "--max-iter",
        "2",
        "--quiet",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success());
    assert!(text(&o).contains("NOT CONVERGED"), "{}", text(&o));
    let o = cvtmesh(&[
        "mesh",
        "circle",
        "--points",
        "88",
        "--method",
        "ccvt1",
        "--max-iter",
        "2",
        "--strict",
        "--quiet",
        "-o",
        s(&out),
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("did not converge (2 iterations, a phase reached the iteration cap 2"),
        "{}",
        text(&o)
    );
    assert!(out.exists());
}

#[test]
fn a_time_limit_writes_the_mesh_reached_marked_not_converged() {
    let d = scratch("time_limit");
    let out = d.join("m.msh");
    let run = |limit: &str| quiet_mesh("lake", "3000", &["--time-limit", limit], &out);
    let o = run("0");
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("NOT CONVERGED (time limit reached)")
            && text(&o).contains("note: stopped at the time limit before converging"),
        "{}",
        text(&o)
    );
    let mesh = cvtmesh::io::read_mesh(&out).unwrap();
    cvtmesh::check_conforming(&mesh, &cvtmesh::Region::builtin("lake").unwrap()).unwrap();
    std::fs::remove_file(&out).unwrap();
    // Under --strict the refusal names the time limit, not the iteration cap.
    let o = quiet_mesh("lake", "3000", &["--time-limit", "0", "--strict"], &out);
    assert!(!o.status.success());
    assert!(text(&o).contains("the time limit reached"), "{}", text(&o));
    std::fs::remove_file(&out).unwrap();
    for bad in ["-1", "NaN"] {
        let o = run(bad);
        assert!(!o.status.success() && !out.exists());
        assert!(
            text(&o).contains("must be a number of seconds, 0 or more"),
            "{}",
            text(&o)
        );
    }
    // A limit beyond any clock is none (it panicked converting to a Duration).
    let o = run("1e308");
    assert!(o.status.success(), "{}", text(&o));
    assert!(out.exists());
}

/// Bad input: clear message naming the problem, non-zero exit, no output file.
fn assert_refused(args: &[&str], out: &std::path::Path, needle: &str) {
    let o = cvtmesh(args);
    let t = text(&o);
    assert!(!o.status.success(), "accepted {args:?}:\n{t}");
    assert!(!t.contains("panicked"), "panic for {args:?}:\n{t}");
    assert!(
        t.to_lowercase().contains(&needle.to_lowercase()),
        "{args:?}: expected '{needle}' in:\n{t}"
    );
    assert!(!out.exists(), "{args:?} left a file behind");
}

#[test]
fn bad_input_is_refused_with_a_clear_message() {
    let d = scratch("errors");
    let out = d.join("out.node");
    let o = s(&out);
    assert_refused(
        &[
            "mesh",
            s(&d.join("missing.json")),
            "--points",
            "50",
            "-o",
            o,
        ],
        &out,
        "missing.json",
    );
    assert_refused(
        &[
            "mesh",
            "circle",
            "--points",
            "50",
            "-o",
            s(&d.join("out.xyz")),
        ],
        &d.join("out.xyz"),
        "unknown extension",
    );
    assert_refused(
        &[
            "mesh", "circle", "--points", "50", "--method", "magic", "-o", o,
        ],
        &out,
        "unknown method",
    );
    assert_refused(
        &["mesh", "hex_hole", "--points", "8", "-o", o],
        &out,
        "too small",
    );
    assert_refused(
        &["mesh", "circle", "--size", "5", "-o", o],
        &out,
        "too small",
    );
    assert_refused(
        &[
            "mesh",
            "circle",
            "--points",
            "50",
            "--density",
            "x - 2",
            "-o",
            o,
        ],
        &out,
        "non-negative",
    );
    assert_refused(
        &[
            "mesh",
            "circle",
            "--points",
            "50",
            "--density",
            "1 + (x",
            "-o",
            o,
        ],
        &out,
        "column",
    );
    assert_refused(
        &["mesh", "nonesuch", "--points", "50", "-o", o],
        &out,
        "unknown region",
    );
    // Bounds on a size field without one: refused, not ignored.
    assert_refused(
        &["mesh", "circle", "-n", "200", "--size-min", "0.01", "-o", o],
        &out,
        "<--size-field <EXPR|MESH>|--size-toward",
    );
    // A field coarser than the region: named as such, not as too few points asked for.
    assert_refused(
        &["mesh", "circle", "--size-field", "10", "-o", o],
        &out,
        "the size field asks for 0.04 vertices (its sizes from 1.000e1 on a region 2.828e0 across)",
    );
    // K too few for the field's range: the scaled field would leave most of the disc out.
    assert_refused(
        &[
            "mesh",
            "circle",
            "--size-field",
            "1e-5+x^2",
            "-n",
            "1000",
            "-m",
            "distmesh",
            "-o",
            o,
        ],
        &out,
        "K = 1000 vertices are too few for this size field",
    );
    // A threshold with a uniform size: refused, not ignored (it was, without a word).
    assert_refused(
        &[
            "mesh",
            "square_hole",
            "--size",
            "0.05",
            "--size-threshold",
            "0.001,0.01,0,0.5",
            "-o",
            o,
        ],
        &out,
        "cannot be used with '--size-threshold",
    );
    // Bounds the mesh keeps, with K that scales the field: refused, naming the bound.
    assert_refused(
        &[
            "mesh",
            "square_hole",
            "--size-field",
            "0.01+0.1*abs(x)",
            "--size-max",
            "0.05",
            "-n",
            "300",
            "-o",
            o,
        ],
        &out,
        "size_max (--size-max) is an edge length the mesh keeps",
    );
    // A bound at fault is the one named, not the other's default.
    assert_refused(
        &[
            "mesh",
            "square_hole",
            "--size-field",
            "0.02+0.1*abs(x)",
            "--size-max",
            "-1",
            "-o",
            o,
        ],
        &out,
        "(size_max, --size-max) must be positive (inf bounds nothing), got -1",
    );
    // An output directory that does not exist, named before any work.
    let (mesh_to, picture_to) = (
        d.join("no_such_dir").join("out.msh"),
        d.join("no_such_dir").join("out.png"),
    );
    assert_refused(
        &["mesh", "circle", "--points", "50", "-o", s(&mesh_to)],
        &mesh_to,
        "no directory",
    );
    assert_refused(
        &["show", "circle", "-o", s(&picture_to)],
        &picture_to,
        "no directory",
    );
    // A directory that takes no file (even for root), also named before any work (after
    // it, the writer's error would name the temporary file instead).
    #[cfg(target_os = "linux")]
    {
        let proc_out = std::path::Path::new("/proc/cvtmesh_out.msh");
        assert_refused(
            &["mesh", "lake", "--points", "100000", "-o", s(proc_out)],
            proc_out,
            "takes no new file",
        );
    }
    // An unknown region format names the mesh formats too, which also give regions.
    assert_refused(
        &["mesh", s(&d.join("r.xyz")), "--points", "50", "-o", o],
        &out,
        ".msh",
    );
    // How many vertices: any of the four ways is named when none is given.
    for way in ["--points", "--size", "--size-field", "--size-toward"] {
        assert_refused(&["mesh", "circle", "-o", o], &out, way);
    }
    // A negative size is a size, refused as one (not an unknown option "-0").
    let negative = cvtmesh(&["mesh", "circle", "--size", "-0.1", "-o", o]);
    assert_eq!(negative.status.code(), Some(1), "{}", text(&negative));
    assert!(text(&negative).contains("size"), "{}", text(&negative));
    assert!(!out.exists());
    // So is a negative size field or threshold, whose value starts with a minus.
    for args in [
        &["--size-field", "-0.1"][..],
        &["--size-field", "-0.1 + x"],
        &[
            "--size-toward",
            "loop:0",
            "--size-threshold",
            "-0.01,0.1,0,0.5",
        ],
    ] {
        let mut all = vec!["mesh", "circle"];
        all.extend_from_slice(args);
        all.extend(["-o", o]);
        let t = text(&cvtmesh(&all));
        assert!(!t.contains("unexpected argument"), "{args:?}: {t}");
        assert!(
            t.contains("positive") || t.contains("0 < h_min"),
            "{args:?}: {t}"
        );
        assert!(!out.exists());
    }
    // A uniform size and a density contradict each other, as in Python.
    assert_refused(
        &[
            "mesh",
            "circle",
            "--size",
            "0.1",
            "--density",
            "x + 2",
            "-o",
            o,
        ],
        &out,
        "--density",
    );

    // Region files that cannot be meshed, and what the refusal must say.
    for (name, body, want) in [
        ("bowtie.txt", "0 0\n1 1\n1 0\n0 1\n", "crosses itself at"),
        (
            "overlap.txt",
            "0 0\n1 0\n1 1\n0 1\n\n0.5 0.5\n6 5\n6 6\n",
            "cross",
        ),
        (
            "nan.txt",
            "0 0\n1 0\nnan 1\n0 1\n",
            "nan.txt: line 3: x is not finite",
        ),
        ("dup.txt", "0 0\n1 0\n1 0\n1 1\n0 1\n", "duplicate"),
        (
            "open.json",
            r#"{"loops":[{"role":"outer","segments":[{"kind":"polyline","points":[[0,0],[1,0],[1,1],[0,1]]}]}]}"#,
            "open.json): loop 0 (outer) is not closed",
        ),
        (
            "garbage.json",
            "{ this is not json",
            "garbage.json: invalid JSON",
        ),
        // Coordinates whose squares and fourth powers overflow or underflow, or a region so
        // far from the origin that its coordinates keep few digits of it.
        (
            "huge.txt",
            "0 0\n1e150 0\n1e150 1e150\n0 1e150\n",
            "scale its coordinates",
        ),
        (
            "tiny.txt",
            "0 0\n1e-160 0\n1e-160 1e-160\n0 1e-160\n",
            "scale its coordinates",
        ),
        (
            "far.txt",
            "1e11 1e11\n100000000001 1e11\n100000000001 100000000001\n1e11 100000000001\n",
            "translate its coordinates",
        ),
    ] {
        let p = d.join(name);
        std::fs::write(&p, body).unwrap();
        assert_refused(&["mesh", s(&p), "--points", "50", "-o", o], &out, want);
    }
    assert_refused(
        &["measure", s(&d.join("none.node")), "--region", "circle"],
        &d.join("none.node"),
        "none.node: cannot read",
    );
}

#[test]
fn user_region_files_in_every_input_format_mesh() {
    let d = scratch("inputs");
    let write = |name: &str, body: &str| {
        let p = d.join(name);
        std::fs::write(&p, body).unwrap();
        p
    };
    let poly = write(
        "sq.poly",
        "8 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 0.4 0.4\n6 0.6 0.4\n7 0.6 0.6\n8 0.4 0.6\n8 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 6 7\n7 7 8\n8 8 5\n1\n1 0.5 0.5\n",
    );
    let geojson = write(
        "sq.geojson",
        r#"{"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,1],[0,0]],[[0.4,0.4],[0.4,0.6],[0.6,0.6],[0.6,0.4],[0.4,0.4]]]}"#,
    );
    let loops = write(
        "sq.txt",
        "# square with a hole\n0 0\n1 0\n1 1\n0 1\n\n0.4 0.4\n0.6 0.4\n0.6 0.6\n0.4 0.6\n",
    );
    for input in [poly, geojson, loops] {
        let out = d.join("m.node");
        let o = cvtmesh(&[
            "mesh",
            s(&input),
            "--points",
            "150",
            "--quiet",
            "-o",
            s(&out),
        ]);
        assert!(o.status.success(), "{}: {}", input.display(), text(&o));
        let o = cvtmesh(&["measure", s(&out), "--region", s(&input), "--csv"]);
        assert!(o.status.success(), "{}", text(&o));
        assert!(!text(&o).contains("does not conform"), "{}", text(&o));
    }
}

#[test]
fn absurd_sizes_are_refused_up_front() {
    let d = scratch("limits");
    let out = d.join("m.node");
    assert_refused(
        &[
            "mesh",
            "circle",
            "--size",
            "1e-12",
            "--method",
            "refine",
            "-o",
            s(&out),
        ],
        &out,
        "more than cvtmesh meshes",
    );
    let o = cvtmesh(&["mesh", "circle", "--points", "50", "--quiet", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    let o = cvtmesh(&[
        "measure",
        s(&out),
        "--region",
        "circle",
        "--sampled",
        "1000000000000",
    ]);
    assert!(
        !o.status.success() && text(&o).contains("--sampled"),
        "{}",
        text(&o)
    );
}

/// `measure --size-field FIELD --csv`'s size conformity row: edges, unit share, efficiency,
/// mean length, min angle, its 1st percentile, vertices, predicted vertices.
fn size_conformity(mesh: &std::path::Path, region: &str, field: &str) -> Vec<f64> {
    size_conformity_by(mesh, region, &["--size-field", field])
}

/// `measure --csv`'s size conformity row against the field of `field_args`.
fn size_conformity_by(mesh: &std::path::Path, region: &str, field_args: &[&str]) -> Vec<f64> {
    let o = cvtmesh(
        &[
            &["measure", s(mesh), "--region", region, "--csv"][..],
            field_args,
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    stdout
        .lines()
        .skip_while(|l| !l.starts_with("edges,unit_share"))
        .nth(1)
        .expect("a size conformity row")
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect()
}

/// `cvtmesh mesh circle --size-field FIELD -o OUT`, which must succeed.
fn mesh_circle_by(field: &str, out: &std::path::Path) -> Output {
    let o = cvtmesh(&[
        "mesh",
        "circle",
        "--size-field",
        field,
        "--quiet",
        "-o",
        s(out),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    o
}

/// A point source asking for sizes far below its background grid's step is followed only as
/// finely as the grid: the command says where; a field the grid follows says nothing.
#[test]
fn a_size_field_finer_than_its_background_grid_is_named_in_a_warning() {
    let dir = scratch("unresolved_field");
    let out = dir.join("graded.node");
    let run = |size_min: &str| {
        let threshold = format!("{size_min},0.1,0,1");
        let o = cvtmesh(&[
            "mesh",
            "circle",
            "--size-toward",
            "point:0.3,0.2",
            "--size-threshold",
            &threshold,
            "--points",
            "500",
            "--max-iter",
            "1",
            "--quiet",
            "-o",
            s(&out),
        ]);
        assert!(o.status.success(), "{}", text(&o));
        text(&o)
    };
    let said = run("1e-5");
    assert!(
        said.contains("warning: size field: near (0.30")
            && said.contains("over one step")
            && said.contains("come out longer than the field asks"),
        "{said}"
    );
    // Measured against the same field, the sizes there are the grid's.
    let measured = |size_min: &str| {
        let threshold = format!("{size_min},0.1,0,1");
        let o = cvtmesh(&[
            "measure",
            s(&out),
            "--region",
            "circle",
            "--size-toward",
            "point:0.3,0.2",
            "--size-threshold",
            &threshold,
        ]);
        assert!(o.status.success(), "{}", text(&o));
        text(&o)
    };
    assert!(measured("1e-5").contains("measured against the smoothed sizes"));
    assert!(!run("1e-2").contains("warning"));
    assert!(!measured("1e-2").contains("warning"));
}

#[test]
fn a_size_field_grades_the_mesh_and_measure_reports_how_well() {
    let dir = scratch("size_field");
    let out = dir.join("graded.msh");
    let field = "0.03 + 0.12*sqrt(x^2+y^2)";
    let o = mesh_circle_by(field, &out);
    assert!(text(&o).contains("asked for by the field"), "{}", text(&o));
    let row = size_conformity(&out, "circle", field);
    let (unit_share, efficiency, min_angle) = (row[1], row[2], row[4]);
    assert!(
        unit_share >= 0.95 && efficiency >= 0.9 && min_angle >= 30.0,
        "{row:?}"
    );
    // With --points, the field's shape is kept and K is as asked.
    let o = cvtmesh(&[
        "mesh",
        "circle",
        "--size-field",
        field,
        "--points",
        "300",
        "--quiet",
        "-o",
        s(&out),
    ]);
    assert!(
        o.status.success() && text(&o).contains("K=300"),
        "{}",
        text(&o)
    );
}

/// A size at each vertex of a mesh, as an adaptive solver leaves them: h = 0.02 + 0.08 |x − c|
/// on a mesh of the circle, written as Triangle files (first attribute) and as Gmsh 2.2 with a
/// `$NodeData` view. Returns the two paths and the same field as an expression.
fn sizes_on_a_mesh(
    dir: &std::path::Path,
) -> (std::path::PathBuf, std::path::PathBuf, &'static str) {
    let expr = "0.02 + 0.08*sqrt((x-0.3)^2 + y^2)";
    let h = |x: f64, y: f64| 0.02 + 0.08 * ((x - 0.3).powi(2) + y * y).sqrt();
    let src = dir.join("src.node");
    let o = cvtmesh(&[
        "mesh",
        "circle",
        "--points",
        "1500",
        "--quiet",
        "-o",
        s(&src),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let mesh = cvtmesh::io::read_mesh(&src).unwrap();
    let (mut node, mut nodes) = (format!("{} 2 1 0\n", mesh.points.len()), String::new());
    for (i, p) in mesh.points.iter().enumerate() {
        node += &format!("{} {} {} {}\n", i + 1, p.x, p.y, h(p.x, p.y));
        nodes += &format!("{} {} {} 0\n", i + 1, p.x, p.y);
    }
    let (mut ele, mut elements) = (format!("{} 3 0\n", mesh.triangles.len()), String::new());
    for (i, t) in mesh.triangles.iter().enumerate() {
        ele += &format!("{} {} {} {}\n", i + 1, t[0] + 1, t[1] + 1, t[2] + 1);
        elements += &format!("{} 2 0 {} {} {}\n", i + 1, t[0] + 1, t[1] + 1, t[2] + 1);
    }
    let data: String = mesh
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| format!("{} {}\n", i + 1, h(p.x, p.y)))
        .collect();
    let (tri, msh) = (dir.join("sizes.node"), dir.join("sizes.msh"));
    std::fs::write(&tri, node).unwrap();
    std::fs::write(tri.with_extension("ele"), ele).unwrap();
    let n = mesh.points.len();
    std::fs::write(
        &msh,
        format!(
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{n}\n{nodes}$EndNodes\n$Elements\n{}\n\
             {elements}$EndElements\n$NodeData\n1\n\"h\"\n1\n0\n3\n0\n1\n{n}\n{data}$EndNodeData\n",
            mesh.triangles.len()
        ),
    )
    .unwrap();
    (tri, msh, expr)
}

#[test]
fn a_size_field_on_a_mesh_grades_the_mesh_as_its_expression_does() {
    let dir = scratch("size_mesh");
    let (tri, msh, expr) = sizes_on_a_mesh(&dir);
    let mut rows = Vec::new();
    for field in [s(&tri), s(&msh)] {
        let out = dir.join("graded.msh");
        mesh_circle_by(field, &out);
        // Judged against the field as given and against the expression it samples.
        for judge in [field, expr] {
            let row = size_conformity(&out, "circle", judge);
            assert!(
                row[1] >= 0.95 && row[2] >= 0.9 && row[4] >= 30.0,
                "{field} by {judge}: {row:?}"
            );
        }
        rows.push(size_conformity(&out, "circle", expr));
    }
    // The two files hold the same sizes: the same mesh.
    assert_eq!(rows[0], rows[1]);
    // K follows the field: within 2 % of what the expression asks for.
    let predicted = rows[0][7];
    assert!(
        (rows[0][6] - predicted).abs() <= 0.02 * predicted,
        "{:?}",
        rows[0]
    );
    // A mesh file is an input: never overwritten.
    let before = std::fs::read(&msh).unwrap();
    let o = cvtmesh(&["mesh", "circle", "--size-field", s(&msh), "-o", s(&msh)]);
    let t = text(&o);
    assert!(!o.status.success(), "accepted:\n{t}");
    assert!(t.contains("would replace the input file"), "{t}");
    assert_eq!(
        std::fs::read(&msh).unwrap(),
        before,
        "the sizes file was changed"
    );
}

/// What `cvtmesh regions REGION` prints.
/// A 4 × 1 channel as a loop list in `dir`: pieces 0 (bottom wall), 1 (outlet), 2 (top wall)
/// and 3 (inlet).
fn channel_file(dir: &Path) -> PathBuf {
    let channel = dir.join("channel.txt");
    std::fs::write(&channel, "0 0\n4 0\n4 1\n0 1\n").unwrap();
    channel
}

fn pieces_of(region: &std::path::Path) -> String {
    let o = cvtmesh(&["regions", s(region)]);
    assert!(o.status.success(), "{}", text(&o));
    String::from_utf8_lossy(&o.stdout).to_string()
}

#[test]
fn a_distance_field_toward_one_piece_refines_that_wall_and_regions_names_it() {
    let dir = scratch("size_piece");
    let channel = channel_file(&dir);
    // `regions REGION` lists the pieces: the bottom wall is piece 0.
    let listing = pieces_of(&channel);
    assert!(
        listing.contains("piece 0    line          from (0, 0) to (4, 0)"),
        "{listing}"
    );
    let out = dir.join("wall.node");
    let field = [
        "--size-toward",
        "piece:0",
        "--size-threshold",
        "0.01,0.08,0,0.4",
    ];
    let o = cvtmesh(
        &[
            &["mesh", s(&channel), "--quiet", "-o", s(&out)][..],
            &field[..],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let m = cvtmesh::io::read_mesh(&out).unwrap();
    // Edges near the bottom wall are several times shorter than near the top one.
    let (bottom, top) = (
        mean_edge_where(&m, |p| p.y < 0.05),
        mean_edge_where(&m, |p| p.y > 0.9),
    );
    assert!(top > 4.0 * bottom, "bottom {bottom}, top {top}");
    let o = cvtmesh(
        &[
            &["measure", s(&out), "--region", s(&channel), "--csv"][..],
            &field[..],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", text(&o));
    assert_refused(
        &[
            &["mesh", s(&channel), "-o", s(&dir.join("never.node"))][..],
            &[
                "--size-toward",
                "piece:4",
                "--size-threshold",
                "0.01,0.08,0,0.4",
            ][..],
        ]
        .concat(),
        &dir.join("never.node"),
        "no piece 4",
    );
}

#[test]
fn pieces_are_numbered_alike_by_regions_mesh_measure_and_simplify() {
    let dir = scratch("piece_numbers");
    // The vertex at (0, -1.02) turns by less than the default corner angle: with the default
    // corners the bottom is one piece and the region has four.
    let sq = dir.join("sq.txt");
    std::fs::write(&sq, "-1 -1\n0 -1.02\n1 -1\n1 1\n-1 1\n").unwrap();
    let listing = pieces_of(&sq);
    assert!(
        listing.contains("4 pieces") && !listing.contains("piece 4"),
        "{listing}"
    );
    let out = dir.join("sq.node");
    let wall = [
        "--size-toward",
        "piece:3",
        "--size-threshold",
        "0.02,0.2,0,1",
    ];
    let o = cvtmesh(&[&["mesh", s(&sq), "--quiet", "-o", s(&out)][..], &wall[..]].concat());
    assert!(o.status.success(), "{}", text(&o));
    // measure numbers the pieces as mesh does: the field it judges by is the one meshed.
    let row = size_conformity_by(&out, s(&sq), &wall);
    assert!(row[1] >= 0.95, "{row:?}");
    let beyond = [
        "--size-toward",
        "piece:4",
        "--size-threshold",
        "0.02,0.2,0,1",
    ];
    let o = cvtmesh(&[&["measure", s(&out), "--region", s(&sq)][..], &beyond[..]].concat());
    assert!(
        !o.status.success() && text(&o).contains("no piece 4"),
        "{}",
        text(&o)
    );
    // With --simplify the pieces are still those `regions` lists (of the region as given).
    let notch = dir.join("notch.txt");
    std::fs::write(
        &notch,
        "-1 -1\n-0.01 -1\n0 -1.005\n0.01 -1\n1 -1\n1 1\n-1 1\n",
    )
    .unwrap();
    let listing = pieces_of(&notch);
    let last = listing
        .lines()
        .filter(|l| l.trim_start().starts_with("piece"))
        .count()
        - 1;
    let field = format!("piece:{last}");
    let o = cvtmesh(&[
        "mesh",
        s(&notch),
        "--points",
        "300",
        "--simplify",
        "0.01",
        "--size-toward",
        &field,
        "--size-threshold",
        "0.02,0.2,0,1",
        "--quiet",
        "-o",
        s(&dir.join("notch.node")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    // The mesh is refined toward that piece of the region as given: its left side.
    assert!(listing.contains(&format!(
        "piece {last}    line          from (-1, 1) to (-1, -1)"
    )));
    let m = cvtmesh::io::read_mesh(&dir.join("notch.node")).unwrap();
    let (near, far) = (
        mean_edge_where(&m, |p| p.x < -0.9),
        mean_edge_where(&m, |p| p.x > 0.8),
    );
    assert!(far > 3.0 * near, "near the piece {near}, far from it {far}");
    // An expression or a .msh field is not a Triangle pair: meshing twice to the same name
    // is no overwrite of an input.
    for _ in 0..2 {
        let o = cvtmesh(&[
            "mesh",
            "circle",
            "--size-field",
            "0.08",
            "--quiet",
            "-o",
            s(&dir.join("0.node")),
        ]);
        assert!(o.status.success(), "{}", text(&o));
    }
}

/// A wall layer of 10⁻⁵ on the unit square is a hundred times finer than the size field's
/// background grid: the grid counts 138 141 vertices where the walls alone take about 274 000.
/// Refused, naming both counts, instead of a start of boundary points whose first
/// triangulation took minutes.
#[test]
fn a_wall_layer_finer_than_the_field_s_grid_is_refused_naming_the_counts() {
    let d = scratch("wall_layer");
    let square = d.join("square.txt");
    std::fs::write(&square, "0 0\n1 0\n1 1\n0 1\n").unwrap();
    let out = d.join("m.msh");
    let o = cvtmesh(&[
        "mesh",
        s(&square),
        "--size-toward",
        "loop:0",
        "--size-threshold",
        "1e-5,0.1,0,0.5",
        "-q",
        "-o",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("vertices along the boundary alone"), "{t}");
    assert!(t.contains("more than the 138141 it asks for in all"), "{t}");
    assert!(!out.exists());
}

#[test]
fn bad_size_fields_are_refused_before_any_work() {
    let dir = scratch("bad_size_field");
    let out = dir.join("never.msh");
    let missing = dir.join("missing.msh");
    let region_as_sizes = dir.join("ours.node");
    let o = cvtmesh(&[
        "mesh",
        "circle",
        "--points",
        "50",
        "--quiet",
        "-o",
        s(&region_as_sizes),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    for (field, needle) in [
        ("x", "positive and finite"),
        ("1/0", "positive and finite"),
        ("0.1 +", "--size-field"),
        ("1e-9", "more than cvtmesh meshes"),
        (s(&missing), "cannot read"),
        (s(&region_as_sizes), "vertex markers, not sizes"),
        // A file name in a format that holds no sizes is not taken for an expression.
        ("sizes.txt", "no such file"),
        ("run3/h.h5", "no such file"),
        ("x.y", "no such file"),
    ] {
        assert_refused(
            &["mesh", "circle", "--size-field", field, "-o", s(&out)],
            &out,
            needle,
        );
    }
    assert_refused(
        &[
            "mesh",
            "circle",
            "--size-field",
            "0.1",
            "--density",
            "1",
            "-o",
            s(&out),
        ],
        &out,
        "cannot be used with",
    );
    assert_refused(
        &[
            "mesh",
            "circle",
            "--size-field",
            "0.1",
            "--size-min",
            "0.2",
            "--size-max",
            "0.1",
            "-o",
            s(&out),
        ],
        &out,
        "0.2 is larger than the largest (size_max, --size-max) 0.1",
    );
    assert_refused(
        &[
            "mesh",
            "circle",
            "--size-field",
            "0.1",
            "--gradation",
            "0",
            "-o",
            s(&out),
        ],
        &out,
        "gradation",
    );
}

#[test]
fn gradation_limiting_adds_vertices_where_a_field_grows_too_fast() {
    let dir = scratch("gradation");
    let out = dir.join("m.node");
    // The size grows with slope 0.5 away from a disc of radius 0.3: above the default limit.
    let field = "0.01 + 0.5*max(0, sqrt(x^2+y^2)-0.3)";
    let count = |extra: &[&str]| -> usize {
        let mut args = vec!["mesh", "circle", "--size-field", field, "--tol", "1e-2"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--quiet", "-o", s(&out)]);
        let o = cvtmesh(&args);
        assert!(o.status.success(), "{}", text(&o));
        let t = text(&o);
        let k = t
            .split("K=")
            .nth(1)
            .expect("K=")
            .split_whitespace()
            .next()
            .unwrap();
        k.parse().unwrap()
    };
    let limited = count(&[]);
    let free = count(&["--gradation", "inf"]);
    assert!(limited > free + free / 20, "{limited} vs {free}");
    assert!(count(&["--size-max", "0.05"]) > limited);
}

#[test]
fn distance_fields_refine_toward_loops_and_points() {
    let dir = scratch("size_toward");
    let out = dir.join("m.msh");
    // A point source: h = 0.02 at the centre growing to 0.1 at distance 0.5, the same as the
    // expression below, against which the mesh is then measured.
    let o = cvtmesh(&[
        "mesh",
        "circle",
        "--size-toward",
        "point:0,0",
        "--size-threshold",
        "0.02,0.1,0,0.5",
        "--quiet",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let row = size_conformity(&out, "circle", "min(0.1, 0.02 + 0.16*sqrt(x^2+y^2))");
    assert!(row[1] >= 0.95 && row[2] >= 0.9, "{row:?}");
    for (args, needle) in [
        (
            vec![
                "--size-toward",
                "loop:2",
                "--size-threshold",
                "0.01,0.1,0,1",
            ],
            "no loop 2",
        ),
        (
            vec![
                "--size-toward",
                "edge:1",
                "--size-threshold",
                "0.01,0.1,0,1",
            ],
            "expected loop:I",
        ),
        (
            vec!["--size-toward", "loop:0", "--size-threshold", "0.01,0.1,1"],
            "four numbers",
        ),
        (
            vec!["--size-toward", "loop:0", "--size-threshold", "0.2,0.1,0,1"],
            "size threshold",
        ),
        (vec!["--size-toward", "loop:0"], "--size-threshold"),
    ] {
        let mut all = vec!["mesh", "annulus"];
        all.extend(args);
        all.extend(["-o", s(&out)]);
        let _ = std::fs::remove_file(&out);
        assert_refused(&all, &out, needle);
    }
}

#[test]
fn every_part_of_a_multipolygon_is_meshed() {
    let d = scratch("multipart");
    let input = d.join("two.geojson");
    std::fs::write(
        &input,
        r#"{"type":"MultiPolygon","coordinates":[[[[0,0],[1,0],[1,1],[0,1],[0,0]]],
           [[[2,0],[4,0],[4,1],[2,1],[2,0]],[[2.5,0.25],[2.5,0.75],[3,0.75],[3,0.25],[2.5,0.25]]]]}"#,
    )
    .unwrap();
    let out = d.join("two.msh");
    let o = cvtmesh(&["mesh", s(&input), "-n", "1000", "-q", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("region: 2 disjoint parts"), "{t}");
    assert!(
        t.contains("part 0: K = 364") && t.contains("part 1: K = 636"),
        "{t}"
    );
    let mesh = cvtmesh::io::read_mesh(&out).unwrap();
    assert_eq!(mesh.num_vertices(), 1000);
    assert!((mesh.area() - 2.75).abs() < 1e-9, "{}", mesh.area());
    // The measures accept the mesh of the whole region.
    let o = cvtmesh(&["measure", s(&out), "--region", s(&input), "--csv"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!text(&o).contains("does not conform"), "{}", text(&o));
}

/// A digitized coastline: 3000 points around a wavy disc, with digitizer noise; no vertex
/// turns by more than a few degrees.
fn coastline(n: usize) -> String {
    let mut state = 7u64;
    let mut noise = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    (0..n)
        .map(|i| {
            let t = std::f64::consts::TAU * i as f64 / n as f64;
            let r = 1.0 + 0.05 * (7.0 * t).sin() + 0.003 * (53.0 * t).sin() + 2e-4 * noise();
            format!("{} {}\n", r * t.cos(), r * t.sin())
        })
        .collect()
}

#[test]
fn a_coastline_meshes_far_below_its_vertex_count() {
    let d = scratch("coast");
    let input = d.join("coast.txt");
    std::fs::write(&input, coastline(3000)).unwrap();
    let out = d.join("coast.vtu");
    let o = cvtmesh(&["mesh", s(&input), "-n", "300", "-q", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("corners: 0 of 3000 kept"), "{}", text(&o));
    // --corner-angle 0 keeps every vertex a corner, as before: far too many for K = 300.
    let o = cvtmesh(&[
        "mesh",
        s(&input),
        "-n",
        "300",
        "--corner-angle",
        "0",
        "-q",
        "-o",
        s(&out),
    ]);
    assert!(!o.status.success());
    assert!(text(&o).contains("at least 3000 vertices"), "{}", text(&o));
    assert!(text(&o).contains("--simplify auto"), "{}", text(&o));
    // Simplified to a quarter of the spacing, every vertex left may stay a corner.
    let simplified = |tol: &str| {
        quiet_mesh(
            s(&input),
            "300",
            &["--corner-angle", "0", "--simplify", tol],
            &out,
        )
    };
    let o = simplified("auto");
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("boundary: simplified from 3000 to ")
            && text(&o).contains("the mesh's boundary stays within"),
        "{}",
        text(&o)
    );
    for bad in ["0", "-1", "nan", "coarse"] {
        std::fs::remove_file(&out).unwrap_or(());
        let o = simplified(bad);
        assert!(!o.status.success() && !out.exists(), "{bad}");
        assert!(
            text(&o).contains("--simplify needs a positive number or `auto`"),
            "{}",
            text(&o)
        );
    }
    // Listed corners are kept: the square's four.
    let o = cvtmesh(&["mesh", "square_hole", "-n", "200", "-q", "-o", s(&out)]);
    assert!(
        text(&o).contains("corners: 4 (as the region lists them)"),
        "{}",
        text(&o)
    );
}

#[test]
fn a_channel_thinner_than_the_spacing_is_named_and_refused_under_strict() {
    let d = scratch("channel");
    let input = d.join("channel.txt");
    std::fs::write(&input, "0 0\n10 0\n10 0.001\n0 0.001\n").unwrap();
    let out = d.join("channel.vtu");
    let o = cvtmesh(&["mesh", s(&input), "-n", "300", "-q", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("warning: the region is 1.000e-3 wide near ("),
        "{t}"
    );
    assert!(
        t.contains("thinner than the spacing") && t.contains("K ≥ 11548"),
        "{t}"
    );
    std::fs::remove_file(&out).unwrap();
    let o = cvtmesh(&[
        "mesh",
        s(&input),
        "-n",
        "300",
        "--strict",
        "-q",
        "-o",
        s(&out),
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("--strict: the region is 1.000e-3 wide"),
        "{}",
        text(&o)
    );
    assert!(!out.exists());
}

/// Meshes `input` with `method` at K = 300, unpolished (the method's own mesh): the command
/// succeeds with `warning` on stderr; with --strict it fails saying `--strict: ` and `refusal`,
/// and leaves no file.
fn warns_then_refuses_under_strict(input: &Path, method: &str, warning: &str, refusal: &str) {
    let out = input.with_extension("node");
    let args = |strict: bool| {
        let mut v = vec![
            "mesh",
            s(input),
            "-n",
            "300",
            "-m",
            method,
            "--polish",
            "0",
            "-q",
        ];
        if strict {
            v.push("--strict");
        }
        v.extend(["-o", s(&out)]);
        v
    };
    let o = cvtmesh(&args(false));
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains(warning), "{}", text(&o));
    std::fs::remove_file(&out).unwrap();
    let o = cvtmesh(&args(true));
    assert!(!o.status.success());
    assert!(text(&o).contains("--strict: "), "{}", text(&o));
    assert!(text(&o).contains(refusal), "{}", text(&o));
    assert!(!out.exists());
}

#[test]
fn a_mesh_that_leaves_out_part_of_the_region_is_named_and_refused_under_strict() {
    // A ring 0.01 wide: Algorithm 1 at K = 300 keeps too few vertices on the outer circle,
    // and the chords between them cut off 17 % of the ring.
    let d = scratch("ring");
    let input = d.join("ring.json");
    std::fs::write(
        &input,
        r#"{"loops": [{"role": "outer", "segments": [{"kind": "circle", "center": [0, 0], "radius": 1.0}]},
            {"role": "hole", "segments": [{"kind": "circle", "center": [0, 0], "radius": 0.99}]}]}"#,
    )
    .unwrap();
    warns_then_refuses_under_strict(
        &input,
        "ccvt1",
        "warning: the mesh covers 82.6 % of the region's area",
        "the mesh covers 82.6 %",
    );
}

/// A strip 1000 × 1 at K = 300 is 0.51 spacings wide, just wide enough to pass the check
/// for thin places: DistMesh's grid there is one row, whose points all go to one side, and it
/// fans across the strip. The slivers are named, and refused under --strict.
#[test]
fn slivers_are_named_and_refused_under_strict() {
    let d = scratch("strip");
    let input = d.join("strip.txt");
    std::fs::write(&input, "0 0\n1000 0\n1000 1\n0 1\n").unwrap();
    warns_then_refuses_under_strict(
        &input,
        "distmesh",
        "triangles have an angle under 1° (the smallest",
        "nothing written",
    );
    // The default method fits triangles of 8° there: no warning.
    let out = d.join("strip.node");
    let o = cvtmesh(&["mesh", s(&input), "-n", "300", "-q", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!text(&o).contains("under 1°"), "{}", text(&o));
    // `measure` names them in a mesh made elsewhere too (here, DistMesh's).
    let fan = d.join("fan.node");
    let o = cvtmesh(&[
        "mesh",
        s(&input),
        "-n",
        "300",
        "-m",
        "distmesh",
        "--polish",
        "0",
        "-q",
        "-o",
        s(&fan),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = cvtmesh(&["measure", s(&fan), "--region", s(&input)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("warning: 296 of 298 triangles have an angle under 1°"),
        "{}",
        text(&o)
    );
}

/// A fracture whose end stops a ten-thousandth short of another: the CVT places both lines'
/// points at the spacing, and the triangles between the end and the other line are slivers,
/// which the warning names with the method that leaves none; Delaunay refinement splits the
/// lines there, as Triangle does, and keeps its 20° bound.
#[test]
fn a_near_miss_of_two_fractures_is_refined_by_refine_and_named_for_ccvt() {
    let dir = scratch("near_miss");
    let poly = dir.join("near.poly");
    std::fs::write(
        &poly,
        "8 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 0.1 0.5\n6 0.9 0.5\n7 0.5 0.5001\n\
         8 0.55 0.9\n6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 7 8\n0\n",
    )
    .unwrap();
    let out = dir.join("m.node");
    let o = quiet_mesh(s(&poly), "1000", &[], &out);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("triangles have an angle under 1°")
            && text(&o).contains("the refine method (--method refine"),
        "{}",
        text(&o)
    );
    let o = quiet_mesh(s(&poly), "1000", &["--method", "refine"], &out);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!text(&o).contains("warning"), "{}", text(&o));
    assert!(printed_min_angle(&o) >= 20.0, "{}", text(&o));
}

/// Two fractures crossing at half a degree: every mesh that keeps both has that angle, so
/// Delaunay refinement's mesh, which has no smaller one, is neither warned about nor refused
/// under --strict, nor is it when measured (the CVT's slivers beside a line, which no input
/// forces, are still named: the near miss above).
#[test]
fn an_angle_the_input_lines_force_is_no_sliver_even_under_strict() {
    let dir = scratch("forced");
    let (c, s5) = (0.5f64.to_radians().cos(), 0.5f64.to_radians().sin());
    let poly = dir.join("cross.poly");
    std::fs::write(
        &poly,
        format!(
            "8 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 0.1 0.5\n6 0.9 0.5\n7 {} {}\n8 {} {}\n\
             6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n6 7 8\n0\n",
            0.5 - 0.4 * c,
            0.5 - 0.4 * s5,
            0.5 + 0.4 * c,
            0.5 + 0.4 * s5
        ),
    )
    .unwrap();
    let out = dir.join("m.node");
    let o = quiet_mesh(s(&poly), "2000", &["--method", "refine", "--strict"], &out);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!text(&o).contains("warning"), "{}", text(&o));
    let angle = printed_min_angle(&o);
    assert!((angle - 0.5).abs() < 0.01, "{}", text(&o));
    let o = cvtmesh(&["measure", s(&out), "--region", s(&poly)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!text(&o).contains("under 1°"), "{}", text(&o));
}

/// `-o coast.node` writes `coast.poly` beside it: meshing `coast.poly` that way would replace
/// the region with the mesh's boundary. It is refused before any work, the region untouched.
#[test]
fn an_output_that_would_replace_the_input_region_is_refused() {
    let d = scratch("overwrite");
    let poly = d.join("coast.poly");
    let region = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n";
    std::fs::write(&poly, region).unwrap();
    let node = d.join("coast.node");
    let o = cvtmesh(&["mesh", s(&poly), "--points", "50", "-o", s(&node)]);
    let t = text(&o);
    assert!(!o.status.success(), "accepted:\n{t}");
    assert!(t.contains("would replace the input file"), "{t}");
    assert_eq!(std::fs::read_to_string(&poly).unwrap(), region);
    assert!(!node.exists(), "a .node was written");
    // Another name beside it is fine.
    let o = cvtmesh(&[
        "mesh",
        s(&poly),
        "--points",
        "50",
        "-o",
        s(&d.join("m.node")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    // No extension at all is named as such.
    let bare = d.join("mesh");
    assert_refused(
        &["mesh", "circle", "--points", "50", "-o", s(&bare)],
        &bare,
        "no extension",
    );
}

/// `mesh` of square_hole refined toward its hole, quietly, to `out`.
fn graded_square_hole(out: &Path) -> Vec<&str> {
    vec![
        "mesh",
        "square_hole",
        "--size-toward",
        "loop:1",
        "--size-threshold",
        "0.02,0.1,0.02,0.6",
        "--quiet",
        "-o",
        s(out),
    ]
}

/// The `min-angle=…deg` a `mesh` run prints.
fn printed_min_angle(o: &Output) -> f64 {
    let t = text(o);
    let at = t.find("min-angle=").expect("a min-angle") + "min-angle=".len();
    t[at..].split("deg").next().unwrap().parse().unwrap()
}

#[test]
fn polish_raises_the_smallest_angle_and_zero_turns_it_off() {
    let dir = scratch("polish");
    let out = dir.join("m.node");
    let graded = graded_square_hole(&out);
    let off = cvtmesh(&[&graded[..], &["--polish", "0"]].concat());
    assert!(off.status.success(), "{}", text(&off));
    assert!(!text(&off).contains("polish:"), "{}", text(&off));
    let on = cvtmesh(&graded);
    assert!(on.status.success(), "{}", text(&on));
    let (before, after) = (printed_min_angle(&off), printed_min_angle(&on));
    assert!(before < 40.0, "nothing to polish: {before}");
    assert!(text(&on).contains("polish:"), "{}", text(&on));
    assert!(after > before + 0.5, "{before} -> {after}");
    for bad in ["75", "-1", "nan"] {
        let _ = std::fs::remove_file(&out);
        assert_refused(
            &[&graded[..], &["--polish", bad]].concat(),
            &out,
            "--polish",
        );
    }
}

#[test]
fn polish_raises_the_smallest_angle_of_a_mesh_from_a_file() {
    let dir = scratch("polish_file");
    let raw = dir.join("raw.msh");
    let o = cvtmesh(&[&graded_square_hole(&raw)[..], &["--polish", "0"]].concat());
    assert!(o.status.success(), "{}", text(&o));
    let before = printed_min_angle(&o);
    let out = dir.join("polished.node");
    let o = cvtmesh(&["polish", s(&raw), "--region", "square_hole", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    let t = text(&o);
    let after: f64 = t
        .split("-> ")
        .nth(1)
        .unwrap()
        .split("deg")
        .next()
        .unwrap()
        .parse()
        .unwrap();
    // Up to the threshold where the mesh's extreme triangles and cells allow (35.0° → 38.4°).
    assert!(after > before + 2.0, "{before} -> {after}: {t}");
    // The polished mesh conforms (measure would warn otherwise) and keeps its triangles.
    let m = cvtmesh(&["measure", s(&out), "--region", "square_hole", "--csv"]);
    assert!(
        m.status.success() && !text(&m).contains("warning"),
        "{}",
        text(&m)
    );
    let triangles =
        |t: &str| -> String { t.lines().last().unwrap().split(',').nth(1).unwrap().into() };
    let r = cvtmesh(&["measure", s(&raw), "--region", "square_hole", "--csv"]);
    assert_eq!(triangles(&text(&m)), triangles(&text(&r)));
    // A threshold out of range, and a mesh of another region, are refused with nothing written.
    let bad = dir.join("bad.node");
    assert_refused(
        &[
            "polish",
            s(&raw),
            "--region",
            "square_hole",
            "--below",
            "90",
            "-o",
            s(&bad),
        ],
        &bad,
        "--below",
    );
    assert_refused(
        &["polish", s(&raw), "--region", "circle", "-o", s(&bad)],
        &bad,
        "does not conform",
    );
}

#[test]
fn a_mesh_names_its_own_region_to_mesh_again_measure_and_polish() {
    let dir = scratch("own_region");
    let old = dir.join("old.node");
    let o = quiet_mesh("square_hole", "800", &["--method", "triangle"], &old);
    assert!(o.status.success(), "{}", text(&o));
    // Meshed again from the old mesh alone: the new mesh conforms to the region the old one
    // covers (its boundary vertices on the old boundary, nothing outside, nothing missing).
    let again = dir.join("again.msh");
    let o = quiet_mesh(s(&old), "800", &[], &again);
    assert!(o.status.success(), "{}", text(&o));
    let m = cvtmesh(&["measure", s(&again), "--region", s(&old), "--csv"]);
    assert!(
        m.status.success() && !text(&m).contains("warning"),
        "{}",
        text(&m)
    );
    assert!(text(&m).lines().nth(1).unwrap().starts_with("800,"));
    // Measured and polished with no region: the mesh's own.
    let own = cvtmesh(&["measure", s(&again), "--csv"]);
    assert!(own.status.success() && !text(&own).contains("warning"));
    let polished = dir.join("polished.vtu");
    let p = cvtmesh(&["polish", s(&old), "-o", s(&polished)]);
    assert!(p.status.success(), "{}", text(&p));
    let listed = cvtmesh(&["regions", s(&old)]);
    assert!(text(&listed).contains("region old: "), "{}", text(&listed));
    assert!(text(&listed).contains("2 loops"), "{}", text(&listed));
    // Writing over the mesh's own files is refused, as for any input, and leaves them.
    let ele = std::fs::read(old.with_extension("ele")).unwrap();
    let o = cvtmesh(&[
        "mesh",
        s(&old),
        "-n",
        "800",
        "-o",
        s(&old.with_extension("ele")),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("would replace the input file"),
        "{}",
        text(&o)
    );
    assert_eq!(std::fs::read(old.with_extension("ele")).unwrap(), ele);
}

#[test]
fn a_mesh_whose_triangles_make_no_region_is_refused_by_name() {
    let dir = scratch("bad_own_region");
    let node = "5 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n5 2 2\n";
    // Two triangles on the same side of edge 1–3: they overlap.
    let overlap = dir.join("overlap.node");
    std::fs::write(&overlap, node).unwrap();
    std::fs::write(overlap.with_extension("ele"), "2 3 0\n1 1 2 3\n2 1 3 2\n").unwrap();
    let out = dir.join("x.msh");
    assert_refused(
        &["mesh", s(&overlap), "-n", "50", "-o", s(&out)],
        &out,
        "overlap",
    );
    // Two triangles that meet at one vertex only: loops that touch.
    let pinch = dir.join("pinch.node");
    std::fs::write(&pinch, node).unwrap();
    std::fs::write(pinch.with_extension("ele"), "2 3 0\n1 1 2 3\n2 3 5 4\n").unwrap();
    let m = cvtmesh(&["measure", s(&pinch)]);
    assert_eq!(m.status.code(), Some(1), "{}", text(&m));
    assert!(text(&m).contains("no --region given"), "{}", text(&m));
}

/// The element blocks of a Gmsh 4.1 file: each block's header (entity dimension, entity tag,
/// element type, count) and its elements' lines.
fn element_blocks(msh: &str) -> Vec<([usize; 4], Vec<&str>)> {
    let mut lines = msh.split("$Elements\n").nth(1).unwrap().lines();
    let nblocks: usize = lines
        .next()
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    (0..nblocks)
        .map(|_| {
            let h: Vec<usize> = lines
                .next()
                .unwrap()
                .split(' ')
                .map(|x| x.parse().unwrap())
                .collect();
            let header = [h[0], h[1], h[2], h[3]];
            (header, (0..h[3]).map(|_| lines.next().unwrap()).collect())
        })
        .collect()
}

#[test]
fn order_two_writes_six_node_triangles_on_the_exact_boundary() {
    let dir = scratch("order2");
    let msh = dir.join("c.msh");
    let o = quiet_mesh("annulus", "300", &["--order", "2"], &msh);
    assert!(o.status.success(), "{}", text(&o));
    let t = std::fs::read_to_string(&msh).unwrap();
    // Six-node triangles (type 9) and three-node boundary lines (type 8), nothing linear.
    let mut types = Vec::new();
    for (header, elements) in element_blocks(&t) {
        let nodes = if header[2] == 9 { 6 } else { 3 };
        for e in elements {
            assert_eq!(e.split(' ').count(), 1 + nodes);
        }
        types.push(header[2].to_string());
    }
    let types: Vec<&str> = types.iter().map(String::as_str).collect();
    assert!(types.contains(&"9") && types.contains(&"8"), "{types:?}");
    assert!(!types.contains(&"2") && !types.contains(&"1"), "{types:?}");
    // Read back by its corners: the same mesh as the linear run.
    let linear = dir.join("c1.msh");
    assert!(quiet_mesh("annulus", "300", &[], &linear).status.success());
    let measured = |p: &Path| {
        let o = cvtmesh(&["measure", s(p), "--region", "annulus", "--csv"]);
        assert!(o.status.success(), "measure {}: {}", p.display(), text(&o));
        o
    };
    let csv = |p: &Path| String::from_utf8_lossy(&measured(p).stdout).to_string();
    assert_eq!(csv(&msh), csv(&linear));
    // Measured by its corners, and said so.
    let said = String::from_utf8_lossy(&measured(&msh).stderr).to_string();
    assert!(
        said.contains("note: 6-node triangles measured as the three-node mesh of their corners"),
        "{said}"
    );
    // Polished, six-node triangles stay six-node triangles, on the same corners as the
    // polished linear mesh.
    let unpolished = dir.join("raw2.msh");
    let o = quiet_mesh(
        "annulus",
        "300",
        &["--order", "2", "--polish", "0"],
        &unpolished,
    );
    assert!(o.status.success(), "{}", text(&o));
    let polished = dir.join("polished2.msh");
    let o = cvtmesh(&[
        "polish",
        s(&unpolished),
        "--region",
        "annulus",
        "-o",
        s(&polished),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let t = std::fs::read_to_string(&polished).unwrap();
    let types: Vec<usize> = element_blocks(&t).iter().map(|(h, _)| h[2]).collect();
    assert!(types.contains(&9) && !types.contains(&2), "{types:?}");
    let linear_raw = dir.join("raw1.msh");
    let o = quiet_mesh("annulus", "300", &["--polish", "0"], &linear_raw);
    assert!(o.status.success(), "{}", text(&o));
    let linear_polished = dir.join("polished1.msh");
    let o = cvtmesh(&[
        "polish",
        s(&linear_raw),
        "--region",
        "annulus",
        "-o",
        s(&linear_polished),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(csv(&polished), csv(&linear_polished));
    // Triangle's format and VTK take it too; .obj and orders other than 1 and 2 are refused.
    for ok in ["c.node", "c.vtu"] {
        let o = quiet_mesh("annulus", "300", &["--order", "2"], &dir.join(ok));
        assert!(o.status.success(), "{ok}: {}", text(&o));
    }
    assert!(quiet_mesh("annulus", "300", &[], &dir.join("c1.node"))
        .status
        .success());
    // Every boundary node (marker > 0 in the .node file) lies on its circle (radii 1 and 0.4),
    // the nodes the second order adds as well as the corners: twice the boundary vertices.
    let boundary_radii = |p: &Path| -> Vec<f64> {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .skip(1)
            .filter_map(|l| {
                let v: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
                (v[6] > 0.0).then(|| v[1].hypot(v[2]))
            })
            .collect()
    };
    let (quadratic, linear) = (
        boundary_radii(&dir.join("c.node")),
        boundary_radii(&dir.join("c1.node")),
    );
    assert_eq!(quadratic.len(), 2 * linear.len());
    for r in quadratic {
        assert!(
            (r - 1.0).abs() < 1e-12 || (r - 0.4).abs() < 1e-12,
            "radius {r}"
        );
    }
    // Polished without the region (the file's own, whose boundary is the corners' polygon),
    // the file's edge nodes stay on the circles where their edges did not move: here none.
    let same = dir.join("same.node");
    let o = cvtmesh(&[
        "polish",
        s(&dir.join("c.node")),
        "--below",
        "1",
        "-o",
        s(&same),
    ]);
    assert!(
        o.status.success() && text(&o).contains("kept"),
        "{}",
        text(&o)
    );
    let kept = boundary_radii(&same);
    assert_eq!(kept.len(), 2 * linear.len());
    for r in kept {
        assert!(
            (r - 1.0).abs() < 1e-12 || (r - 0.4).abs() < 1e-12,
            "radius {r}"
        );
    }
    let ele = std::fs::read_to_string(dir.join("c.ele")).unwrap();
    assert!(ele.lines().nth(1).unwrap().ends_with(" 6 0"), "{ele}");
    let bad = dir.join("c.obj");
    assert_refused(
        &[
            "mesh",
            "annulus",
            "-n",
            "300",
            "--order",
            "2",
            "-o",
            s(&bad),
        ],
        &bad,
        "six-node",
    );
    assert_refused(
        &[
            "mesh",
            "annulus",
            "-n",
            "300",
            "--order",
            "3",
            "-o",
            s(&msh.with_extension("x.msh")),
        ],
        &msh.with_extension("x.msh"),
        "--order",
    );
}

#[test]
fn gmsh_files_name_each_wall_as_a_physical_curve() {
    let dir = scratch("pieces_msh");
    let channel = channel_file(&dir);
    for order in ["1", "2"] {
        let out = dir.join(format!("c{order}.msh"));
        let o = quiet_mesh(s(&channel), "800", &["--order", order], &out);
        assert!(o.status.success(), "{}", text(&o));
        let t = std::fs::read_to_string(&out).unwrap();
        // The loop as before, and each of the four sides: "piece<j>" with tag 101 + j.
        for (tag, name) in [
            (1, "loop0"),
            (101, "piece0"),
            (102, "piece1"),
            (103, "piece2"),
            (104, "piece3"),
        ] {
            assert!(
                t.contains(&format!("1 {tag} \"{name}\"")),
                "{name} in order {order}"
            );
        }
        // Each curve entity is in its loop's and its piece's physical curves.
        let entities: Vec<&str> = t
            .split("$Entities\n")
            .nth(1)
            .unwrap()
            .lines()
            .skip(1)
            .take(4)
            .collect();
        for (j, e) in entities.iter().enumerate() {
            let f: Vec<&str> = e.split(' ').collect();
            assert_eq!(&f[7..10], ["2", "1", &(101 + j).to_string()], "{e}");
        }
        // The line elements of each piece's entity: the walls (length 4) hold about four
        // times the edges of the ends (length 1).
        let per_entity: Vec<usize> = element_blocks(&t)
            .iter()
            .filter(|(h, _)| h[0] == 1)
            .map(|(h, _)| h[3])
            .collect();
        assert_eq!(per_entity.len(), 4, "{per_entity:?}");
        let (ends, walls) = (per_entity[1] + per_entity[3], per_entity[0] + per_entity[2]);
        assert!(
            (3.0..5.0).contains(&(walls as f64 / ends as f64)),
            "{per_entity:?}"
        );
        // And it reads back as any .msh: the loop's markers, the same mesh measured.
        let m = cvtmesh(&["measure", s(&out), "--region", s(&channel), "--csv"]);
        assert!(
            m.status.success() && !text(&m).contains("warning"),
            "{}",
            text(&m)
        );
    }
}

#[test]
fn a_solvers_mesh_with_sizes_alone_gives_the_next_mesh() {
    // The adaptive loop with nothing but the solver's files: its mesh is the region and its
    // sizes at the vertices are the field (Triangle's .node/.ele and Gmsh's .msh alike).
    let dir = scratch("solver_files");
    let (tri, msh, _) = sizes_on_a_mesh(&dir);
    for input in [&tri, &msh] {
        let next = dir.join("next.msh");
        let _ = std::fs::remove_file(&next);
        let o = cvtmesh(&[
            "mesh",
            s(input),
            "--size-field",
            s(input),
            "-q",
            "-o",
            s(&next),
        ]);
        assert!(o.status.success(), "{}", text(&o));
        // It covers the region the old mesh covers, and its edges follow the old sizes.
        let m = cvtmesh(&["measure", s(&next), "--region", s(input)]);
        assert!(
            m.status.success() && !text(&m).contains("warning"),
            "{}",
            text(&m)
        );
        let row = size_conformity_by(&next, s(input), &["--size-field", s(input)]);
        assert!(row[1] > 0.95, "unit share {}", row[1]);
    }
}

/// A 4 × 1 channel as Triangle users write it: walls marked 1, the inlet 2, the outlet 3, and
/// a heated strip 4 on the bottom wall from x = 1.5 to 2.5 (three collinear segments).
fn marked_channel(dir: &Path) -> PathBuf {
    let poly = dir.join("marked.poly");
    std::fs::write(
        &poly,
        "6 2 0 0\n1 0 0\n2 1.5 0\n3 2.5 0\n4 4 0\n5 4 1\n6 0 1\n\
         6 1\n1 1 2 1\n2 2 3 4\n3 3 4 1\n4 4 5 3\n5 5 6 1\n6 6 1 2\n0\n",
    )
    .unwrap();
    poly
}

#[test]
fn poly_segment_markers_reach_the_mesh_files() {
    let dir = scratch("markers");
    let poly = marked_channel(&dir);
    let listed = pieces_of(&poly);
    assert!(
        listed.contains("from (1.5, 0) to (2.5, 0), length 1.000000, marker 4"),
        "{listed}"
    );
    // Triangle's files: each segment and boundary vertex carries its wall's number.
    let base = dir.join("c.node");
    let o = quiet_mesh(s(&poly), "800", &[], &base);
    assert!(o.status.success(), "{}", text(&o));
    let node = std::fs::read_to_string(&base).unwrap();
    let points: Vec<(f64, f64, i64)> = node
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(f.len(), 8, "{l}");
            (
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
                f[7].parse().unwrap(),
            )
        })
        .collect();
    assert_eq!(points.len(), 800);
    let on = |m: i64| points.iter().filter(move |p| p.2 == m);
    assert!(on(2).all(|p| p.0 == 0.0) && on(2).count() > 5);
    assert!(on(3).all(|p| p.0 == 4.0) && on(3).count() > 5);
    assert!(on(4).all(|p| p.1 == 0.0 && (1.5..2.5).contains(&p.0)));
    assert!(on(4).any(|p| p.0 == 1.5), "the strip's start is a vertex");
    let poly_out = std::fs::read_to_string(dir.join("c.poly")).unwrap();
    let strip: f64 = poly_out
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(2)
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() == 4 && f[3] == "4").then(|| {
                let p = |k: &str| points[k.parse::<usize>().unwrap() - 1];
                let (a, b) = (p(f[1]), p(f[2]));
                assert!(a.1 == 0.0 && b.1 == 0.0, "{l}");
                (a.0 - b.0).abs()
            })
        })
        .sum();
    assert!((strip - 1.0).abs() < 1e-12, "strip edges span {strip}");
    // Read back: the same mesh, its vertices on their loop.
    let m = cvtmesh(&["measure", s(&base), "--region", s(&poly), "--csv"]);
    assert!(
        m.status.success() && !text(&m).contains("warning"),
        "{}",
        text(&m)
    );
    // Gmsh's file: a physical curve per marker beside the loop's and the pieces'.
    let msh = dir.join("c.msh");
    let o = quiet_mesh(s(&poly), "800", &[], &msh);
    assert!(o.status.success(), "{}", text(&o));
    let t = std::fs::read_to_string(&msh).unwrap();
    for name in [
        "loop0", "piece0", "marker1", "marker2", "marker3", "marker4",
    ] {
        assert!(t.contains(&format!("\"{name}\"")), "{name}");
    }
}

#[test]
fn a_mesh_meshed_again_keeps_its_walls() {
    let dir = scratch("walls_again");
    let poly = marked_channel(&dir);
    for ext in ["msh", "node"] {
        let old = dir.join(format!("old.{ext}"));
        let o = quiet_mesh(s(&poly), "800", &[], &old);
        assert!(o.status.success(), "{}", text(&o));
        // The old mesh's region is the channel again: its straight walls one piece each
        // (a piece per old boundary edge used to leave Algorithm 2 cycling), with the markers.
        let listed = pieces_of(&old);
        assert!(listed.contains("6 pieces, 6 corners"), "{listed}");
        assert!(
            listed.contains("from (1.5, 0) to (2.5, 0), length 1.000000, marker 4"),
            "{listed}"
        );
        let new = dir.join(format!("new.{ext}"));
        let o = quiet_mesh(s(&old), "2000", &[], &new);
        assert!(
            o.status.success() && !text(&o).contains("NOT CONVERGED"),
            "{}",
            text(&o)
        );
        if ext == "msh" {
            let t = std::fs::read_to_string(&new).unwrap();
            for m in 1..=4 {
                assert!(t.contains(&format!("\"marker{m}\"")), "marker{m}");
            }
        } else {
            let segments = std::fs::read_to_string(dir.join("new.poly")).unwrap();
            let mut markers: Vec<&str> = segments
                .lines()
                .filter(|l| !l.starts_with('#'))
                .skip(2)
                .filter_map(|l| l.split_whitespace().nth(3))
                .collect();
            markers.sort_unstable();
            markers.dedup();
            assert_eq!(markers, ["1", "2", "3", "4"]);
        }
    }
}

/// The rows of a Triangle `.node` written by `cvtmesh mesh` for a marked region: (x, y,
/// boundary marker).
fn node_rows(node: &Path) -> Vec<(f64, f64, i64)> {
    std::fs::read_to_string(node)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            let num = |k: usize| f[k].parse::<f64>().unwrap();
            (num(1), num(2), f[f.len() - 1].parse().unwrap())
        })
        .collect()
}

#[test]
fn a_vertex_marked_on_its_own_is_a_mesh_vertex_in_every_file_and_mesh_again() {
    // The channel's walls all marked 1 but the outlet (3) and inlet (2); vertex 2 at (1.5, 0)
    // marks itself 7, a point where a solver pins a value; vertex 3 is marked as its wall.
    let dir = scratch("pinned");
    let poly = dir.join("pinned.poly");
    std::fs::write(
        &poly,
        "6 2 0 1\n1 0 0 1\n2 1.5 0 7\n3 2.5 0 1\n4 4 0 1\n5 4 1 1\n6 0 1 1\n\
         6 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 5 3\n5 5 6 1\n6 6 1 2\n0\n",
    )
    .unwrap();
    let listed = pieces_of(&poly);
    assert!(listed.contains("vertex (1.5, 0): marker 7"), "{listed}");
    let pinned = |rows: &[(f64, f64, i64)]| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r.2 == 7)
            .map(|r| (r.0, r.1))
            .collect()
    };
    // Triangle's files: that vertex, and only it, carries 7.
    let node = dir.join("a.node");
    let o = quiet_mesh(s(&poly), "500", &[], &node);
    assert!(o.status.success(), "{}", text(&o));
    let rows = node_rows(&node);
    assert_eq!(pinned(&rows), [(1.5, 0.0)]);
    assert!(rows.iter().any(|r| r.1 == 0.0 && r.2 == 1));
    // Gmsh's file: a physical point tagged 7 holding the node at (1.5, 0).
    let msh = dir.join("a.msh");
    let o = quiet_mesh(s(&poly), "500", &[], &msh);
    assert!(o.status.success(), "{}", text(&o));
    let t = std::fs::read_to_string(&msh).unwrap();
    assert!(
        t.contains("0 7 \"marker7\"") && t.contains("$Entities\n1 "),
        "{t:.400}"
    );
    let point_block = t.split("$Nodes\n").nth(1).unwrap();
    assert!(point_block.lines().nth(1).unwrap().starts_with("0 1 0 1"));
    assert!(
        point_block.lines().nth(3) == Some("1.5 0 0"),
        "{point_block:.200}"
    );
    // VTK's: point data `wall_marker` 7 once.
    let vtu = dir.join("a.vtu");
    let o = quiet_mesh(s(&poly), "500", &[], &vtu);
    assert!(o.status.success(), "{}", text(&o));
    let v = std::fs::read_to_string(&vtu).unwrap();
    let walls = v.split("Name=\"wall_marker\"").nth(1).unwrap();
    let values = walls.split('>').nth(1).unwrap().split('<').next().unwrap();
    assert_eq!(values.split_whitespace().filter(|&m| m == "7").count(), 1);
    // Meshed again from either file, at another size: the point is still a vertex marked 7.
    for old in [&msh, &node] {
        let again = dir.join(format!(
            "again_{}.node",
            old.extension().unwrap().to_string_lossy()
        ));
        let o = quiet_mesh(s(old), "300", &[], &again);
        assert!(o.status.success(), "{}", text(&o));
        let rows = node_rows(&again);
        assert_eq!(rows.len(), 300);
        assert_eq!(pinned(&rows), [(1.5, 0.0)], "{}", old.display());
    }
}

#[test]
fn a_poly_vertex_on_no_segment_is_a_vertex_of_every_mesh() {
    // The channel with vertex 7 at (1, 0.5) marked 9 (a probe) and vertex 8 at (3, 0.25)
    // unmarked, on no segment: Triangle keeps such vertices, and so does every mesh here.
    let dir = scratch("embedded");
    let poly = dir.join("probe.poly");
    std::fs::write(
        &poly,
        "8 2 0 1\n1 0 0 1\n2 1.5 0 1\n3 2.5 0 1\n4 4 0 1\n5 4 1 1\n6 0 1 1\n\
         7 1 0.5 9\n8 3 0.25 0\n6 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 5 3\n5 5 6 1\n\
         6 6 1 2\n0\n",
    )
    .unwrap();
    let listed = pieces_of(&poly);
    assert!(
        listed.contains("point (1, 0.5) inside, marker 9"),
        "{listed}"
    );
    assert!(
        listed.contains("point (3, 0.25) inside, a vertex"),
        "{listed}"
    );
    for method in ["ccvt", "refine", "distmesh"] {
        let node = dir.join(format!("{method}.node"));
        let o = quiet_mesh(s(&poly), "400", &["-m", method], &node);
        assert!(o.status.success(), "{method}: {}", text(&o));
        let rows = node_rows(&node);
        assert!(rows.contains(&(1.0, 0.5, 9)), "{method}");
        assert!(rows.contains(&(3.0, 0.25, 0)), "{method}");
    }
    // A method that cannot keep them says so, and writes nothing.
    let out = dir.join("meshgen.node");
    let o = quiet_mesh(s(&poly), "400", &["-m", "meshgen"], &out);
    assert!(
        !o.status.success() && text(&o).contains("embeds 2 points"),
        "{}",
        text(&o)
    );
    assert!(!out.exists());
    // Gmsh's file: the marked point a physical point 9; meshed again from it, still a vertex.
    let msh = dir.join("probe.msh");
    let o = quiet_mesh(s(&poly), "400", &[], &msh);
    assert!(o.status.success(), "{}", text(&o));
    assert!(std::fs::read_to_string(&msh)
        .unwrap()
        .contains("0 9 \"marker9\""));
    let again = dir.join("again.node");
    let o = quiet_mesh(s(&msh), "250", &[], &again);
    assert!(o.status.success(), "{}", text(&o));
    let rows = node_rows(&again);
    assert_eq!(rows.len(), 250);
    assert!(rows.contains(&(1.0, 0.5, 9)));
}

#[test]
fn embed_puts_a_vertex_on_each_point_and_refuses_bad_ones_by_name() {
    let dir = scratch("embed");
    let node = dir.join("c.node");
    let o = quiet_mesh(
        "circle",
        "500",
        &["--embed", "0.3,0.1:5", "--embed=-0.2,0.4"],
        &node,
    );
    assert!(o.status.success(), "{}", text(&o));
    let rows = node_rows(&node);
    // The circle numbers no walls: the marked point gives them Triangle's 1.
    assert!(rows.contains(&(0.3, 0.1, 5)) && rows.contains(&(-0.2, 0.4, 0)));
    for (bad, says) in [
        ("3,0", "lies outside the region"),
        ("1,0", "on the region's boundary"),
        ("0.3", "expected X,Y"),
        ("0.3,nan", "not a finite number"),
        ("0.3,0.1:x", "must be an integer"),
    ] {
        let out = dir.join("bad.node");
        let o = quiet_mesh("circle", "500", &["--embed", bad], &out);
        assert!(
            !o.status.success() && text(&o).contains(says),
            "{bad}: {}",
            text(&o)
        );
        assert!(!out.exists(), "{bad}");
    }
}

#[test]
fn a_gmsh_users_physical_curves_survive_meshing_again() {
    // A 4 × 1 rectangle of two triangles in Gmsh 2.2's format, its bottom and top in physical
    // curve 12, the outlet 13, the inlet 11: a solver's boundary-condition numbers.
    let dir = scratch("gmsh_walls");
    let old = dir.join("g.msh");
    std::fs::write(
        &old,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 11 \"inlet\"\n\
         1 13 \"outlet\"\n$EndPhysicalNames\n$Nodes\n4\n1 0 0 0\n2 4 0 0\n3 4 1 0\n4 0 1 0\n\
         $EndNodes\n$Elements\n6\n1 1 2 12 1 1 2\n2 1 2 13 2 2 3\n3 1 2 12 3 3 4\n\
         4 1 2 11 4 4 1\n5 2 2 1 1 1 2 3\n6 2 2 1 1 1 3 4\n$EndElements\n",
    )
    .unwrap();
    let listed = pieces_of(&old);
    assert!(
        listed.contains("from (0, 1) to (0, 0), length 1.000000, marker 11 (inlet)"),
        "{listed}"
    );
    let new = dir.join("h.msh");
    let o = quiet_mesh(s(&old), "600", &[], &new);
    assert!(o.status.success(), "{}", text(&o));
    // The same tags and names, each wall's group first in its curve's list (what readers that
    // take one tag per curve report), the loop and pieces numbered past them.
    let t = std::fs::read_to_string(&new).unwrap();
    for group in [
        "1 11 \"inlet\"",
        "1 12 \"marker12\"",
        "1 13 \"outlet\"",
        "1 14 \"loop0\"",
    ] {
        assert!(t.contains(group), "{group}");
    }
    let first_tags: Vec<&str> = t
        .split("$Entities\n")
        .nth(1)
        .unwrap()
        .lines()
        .skip(1)
        .take(4)
        .map(|l| l.split(' ').nth(8).unwrap())
        .collect();
    assert_eq!(first_tags, ["12", "13", "12", "11"]);
    // And as a size field's target: refine toward the inlet by its number.
    let graded = dir.join("i.msh");
    let o = quiet_mesh(
        s(&old),
        "1500",
        &[
            "--size-toward",
            "marker:11",
            "--size-threshold",
            "0.01,0.1,0,2",
        ],
        &graded,
    );
    assert!(o.status.success(), "{}", text(&o));
    let m = cvtmesh::io::read_mesh(&graded).unwrap();
    let (inlet, outlet) = (
        mean_edge_where(&m, |p| p.x < 0.05),
        mean_edge_where(&m, |p| p.x > 3.5),
    );
    assert!(outlet > 4.0 * inlet, "inlet {inlet}, outlet {outlet}");
}

#[test]
fn a_tolerance_a_method_does_not_use_is_named_for_that_method() {
    let d = scratch("tol_note");
    for (method, why, not) in [
        ("refine", "refinement is not iterative", "DistMesh"),
        (
            "distmesh",
            "DistMesh stops at its original dptol",
            "refinement",
        ),
    ] {
        let out = d.join(format!("{method}.node"));
        let o = cvtmesh(&[
            "mesh",
            "circle",
            "-n",
            "100",
            "-m",
            method,
            "--tol",
            "0.5",
            "-o",
            s(&out),
        ]);
        let t = text(&o);
        assert!(o.status.success(), "{t}");
        let note = t.lines().find(|l| l.contains("--tol")).unwrap_or_default();
        assert!(
            note.contains(why) && !note.contains(not),
            "{method}: {note}"
        );
    }
}

#[test]
fn a_file_named_like_a_built_in_region_does_not_hide_it() {
    let d = scratch("shadow");
    std::fs::write(d.join("lake"), "not a region").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_cvtmesh"))
        .args(["mesh", "lake", "-n", "300", "-q", "-o", "m.node"])
        .current_dir(&*d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert!(d.join("m.node").exists());
    // `./lake` names the file, which is in no format.
    let o = Command::new(env!("CARGO_BIN_EXE_cvtmesh"))
        .args(["regions", "./lake"])
        .current_dir(&*d)
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        text(&o).contains("unknown region file extension"),
        "{}",
        text(&o)
    );
}

/// A field steeper than the gradation limit: `mesh` says how many vertices the limit added,
/// and `measure` with the same options measures against the limited field the mesh was made
/// for (it had measured against the field as given, and called a good mesh poor).
#[test]
fn measure_limits_the_gradation_as_mesh_does() {
    let dir = scratch("gradation_measure");
    let out = dir.join("steep.node");
    let field = "0.01+0.5*abs(x)";
    let o = cvtmesh(&[
        "mesh",
        "square_hole",
        "--size-field",
        field,
        "--tol",
        "1e-3",
        "--quiet",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("note: the gradation limit 0.3") && text(&o).contains("--gradation inf"),
        "{}",
        text(&o)
    );
    let same = size_conformity(&out, "square_hole", field);
    let given = size_conformity_by(
        &out,
        "square_hole",
        &["--size-field", field, "--gradation", "inf"],
    );
    assert!(same[1] > 0.99, "unit share {}", same[1]);
    assert!(
        given[1] < 0.9,
        "unit share against the field as given {}",
        given[1]
    );
    // The count the measured field asks for is the mesh's.
    assert!((same[7] / same[6] - 1.0).abs() < 0.01, "{same:?}");
}

/// A `.poly`'s area constraints are not used (cvtmesh takes sizes from a size field): the
/// user hears so, where they had been dropped without a word.
#[test]
fn a_poly_s_regional_area_constraints_are_named_as_not_used() {
    let dir = scratch("regional");
    let poly = dir.join("sq.poly");
    std::fs::write(
        &poly,
        "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n\
         2\n1 0.5 0.5 10 0.001\n2 0.2 0.2 20 0.1\n",
    )
    .unwrap();
    let out = dir.join("sq.msh");
    let o = cvtmesh(&["mesh", s(&poly), "-n", "100", "--quiet", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("warning:") && text(&o).contains("its 2 area constraints are not used"),
        "{}",
        text(&o)
    );
}

/// A Triangle mesh of two materials (the `.ele`'s attribute 10 left of x = 1, 20 right of it):
/// `polish` holds the vertices of the interface where they are (it had moved 14 of 17 off
/// it), and meshing the region its triangles cover again, which would lose the interface, is
/// refused by name.
#[test]
fn an_interface_between_materials_is_held_by_polish_and_kept_by_a_new_mesh() {
    let dir = scratch("interface");
    // A 9 × 5 grid over [0, 2] × [0, 1], each square cut into two triangles, its interior
    // vertices jittered (seeded) so that the polish has work everywhere, the interface too.
    let (nx, ny) = (9usize, 5usize);
    let mut rng = cvtmesh::geometry::Rng::new(1);
    let mut node = format!("{} 2 0 0\n", nx * ny);
    let mut xs = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let (mut x, mut y) = (2.0 * i as f64 / (nx - 1) as f64, j as f64 / (ny - 1) as f64);
            if i > 0 && i < nx - 1 && j > 0 && j < ny - 1 {
                // The interface's own vertices stay on it.
                if i != nx / 2 {
                    x += 0.1 * (rng.uniform() - 0.5);
                }
                y += 0.1 * (rng.uniform() - 0.5);
            }
            xs.push(x);
            node.push_str(&format!("{} {x} {y}\n", j * nx + i + 1));
        }
    }
    let mut tris = Vec::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let v = |a: usize, b: usize| (j + b) * nx + i + a + 1;
            let material = if i < nx / 2 { 10 } else { 20 };
            tris.push((v(0, 0), v(1, 0), v(1, 1), material));
            tris.push((v(0, 0), v(1, 1), v(0, 1), material));
        }
    }
    let mut ele = format!("{} 3 1\n", tris.len());
    for (k, (a, b, c, m)) in tris.iter().enumerate() {
        ele.push_str(&format!("{} {a} {b} {c} {m}\n", k + 1));
    }
    std::fs::write(dir.join("two.node"), node).unwrap();
    std::fs::write(dir.join("two.ele"), ele).unwrap();
    let out = dir.join("polished.node");
    let o = cvtmesh(&[
        "polish",
        s(&dir.join("two.node")),
        "--below",
        "60",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("note: 5 vertices on the 4 edges"),
        "{}",
        text(&o)
    );
    let (polished, kept) = cvtmesh::io::read_mesh_with_walls(&out).unwrap();
    // The polished mesh's files keep the interface as segments inside it.
    assert_eq!(kept.inner.len(), ny - 1, "{:?}", kept.inner);
    let on_interface = polished.points.iter().filter(|p| p.x == 1.0).count();
    assert_eq!(on_interface, ny);
    let moved = polished
        .points
        .iter()
        .zip(&xs)
        .filter(|(p, &x)| p.x != x)
        .count();
    assert!(moved > 0, "no vertex moved");
    // Not held, the polish takes interface vertices off x = 1.
    let file = cvtmesh::io::read_mesh_file(&dir.join("two.node")).unwrap();
    let mut free = file.mesh.clone();
    let unheld = cvtmesh::io::Walls {
        inner: Vec::new(),
        ..file.walls.clone()
    };
    let region = cvtmesh::region_of_mesh(&free, &unheld, &dir.join("two.node")).unwrap();
    cvtmesh::polish_restored(&mut free, &region, 60.0).unwrap();
    assert!(free.points.iter().filter(|p| p.x == 1.0).count() < ny);
    // Meshed again, the interface stays: a line of the region its triangles cover, which the
    // new mesh's edges follow and its file keeps.
    let again = dir.join("again.msh");
    let o = cvtmesh(&[
        "mesh",
        s(&dir.join("two.node")),
        "-n",
        "300",
        "-o",
        s(&again),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let (mesh, walls) = cvtmesh::io::read_mesh_with_walls(&again).unwrap();
    assert!(walls.inner.len() >= 4, "{:?}", walls.inner);
    let length: f64 = walls
        .inner
        .iter()
        .map(|&[a, b]| {
            let (p, q) = (mesh.points[a as usize], mesh.points[b as usize]);
            assert!(p.x == 1.0 && q.x == 1.0, "{p} {q}");
            p.distance(q)
        })
        .sum();
    assert!((length - 1.0).abs() < 1e-12, "{length}");
}

/// `-o mesh.poly` writes Triangle's three files, as `-o mesh.node` and `-o mesh.ele` do (the
/// README lists `.poly` among the outputs; it had been an unknown extension).
#[test]
fn a_poly_output_writes_triangle_s_three_files() {
    let dir = scratch("poly_out");
    let o = cvtmesh(&[
        "mesh",
        "circle",
        "-n",
        "100",
        "--quiet",
        "-o",
        s(&dir.join("c.poly")),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    for ext in ["node", "ele", "poly"] {
        assert!(dir.join(format!("c.{ext}")).is_file(), "no c.{ext}");
    }
    assert_eq!(
        cvtmesh::io::read_mesh(&dir.join("c.node"))
            .unwrap()
            .num_vertices(),
        100
    );
}

/// A method that starts from a uniform lattice says that it follows a size field loosely; the
/// default method, which starts from graded points, says nothing of the kind.
#[test]
fn methods_from_a_uniform_lattice_note_that_they_follow_a_size_field_loosely() {
    let dir = scratch("loose_field");
    let run = |method: &str| {
        let out = dir.join(format!("{method}.msh"));
        let o = cvtmesh(&[
            "mesh",
            "square_hole",
            "--size-field",
            "0.02+0.1*abs(x)",
            "-n",
            "300",
            "--max-iter",
            "40",
            "--method",
            method,
            "--quiet",
            "-o",
            s(&out),
        ]);
        assert!(o.status.success(), "{method}: {}", text(&o));
        text(&o).contains("follows a size field loosely")
    };
    assert!(run("vtm") && run("meshgen") && run("ccvt1"));
    assert!(!run("ccvt") && !run("distmesh"));
}

/// A wall a `.poly` leaves unmarked (segment marker 0) is written with marker 1, as Triangle
/// writes it, so that a nonzero marker tells a boundary vertex from an interior one (0 had been
/// written on the boundary too).
#[test]
fn an_unmarked_wall_is_written_with_marker_one_as_triangle_does() {
    let dir = scratch("marker_zero");
    let poly = dir.join("walls.poly");
    std::fs::write(
        &poly,
        "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 1\n1 1 2 0\n2 2 3 2\n3 3 4 0\n4 4 1 2\n0\n",
    )
    .unwrap();
    let out = dir.join("sq.node");
    let o = cvtmesh(&["mesh", s(&poly), "-n", "200", "--quiet", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    let node = std::fs::read_to_string(&out).unwrap();
    let rows: Vec<Vec<&str>> = node
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split_whitespace().collect())
        .collect();
    // index x y kind id param loop wall: kind 0 inside, 1 and 2 on the boundary.
    for r in &rows {
        let (kind, wall) = (r[3], r[7]);
        assert_eq!(kind == "0", wall == "0", "{r:?}");
    }
    let segments = std::fs::read_to_string(out.with_extension("poly")).unwrap();
    let markers: std::collections::BTreeSet<&str> = segments
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(2)
        .take_while(|l| l.split_whitespace().count() == 4)
        .map(|l| l.split_whitespace().nth(3).unwrap())
        .collect();
    assert_eq!(markers, ["1", "2"].into_iter().collect());
}

/// A Gmsh user's rectangle: its curves in `inlet` 11 or `walls` 12 and all of them in
/// `all_boundary` 99 too, the surface in `fluid` 1. Meshed again and polished, the new files
/// keep the walls and the surface group with their tags and names, and say that 99 is not
/// kept (a boundary edge keeps one wall).
#[test]
fn gmsh_groups_come_through_a_new_mesh_and_a_polish() {
    let d = scratch("groups");
    let old = d.join("rect.msh");
    std::fs::copy(
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../mesh/tests/data/msh/overlapping_groups.msh"
        ),
        &old,
    )
    .unwrap();
    let new = d.join("new.msh");
    let o = cvtmesh(&[
        "mesh",
        old.to_str().unwrap(),
        "-n",
        "300",
        "-o",
        new.to_str().unwrap(),
    ]);
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(
        t.contains("warning: physical curve 99 \"all_boundary\" is not kept"),
        "{t}"
    );
    let written = std::fs::read_to_string(&new).unwrap();
    for group in ["1 11 \"inlet\"", "1 12 \"walls\"", "2 1 \"fluid\""] {
        assert!(written.contains(group), "{group} missing:\n{written}");
    }
    assert!(!written.contains("\"domain\""));
    let polished = d.join("polished.msh");
    let o = cvtmesh(&[
        "polish",
        new.to_str().unwrap(),
        "-o",
        polished.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let written = std::fs::read_to_string(&polished).unwrap();
    assert!(written.contains("2 1 \"fluid\"") && written.contains("1 11 \"inlet\""));
}

/// `dual` prints each edge's length and face and each vertex's volume: the volumes sum to the
/// mesh's area, every interior face of a CCVT mesh (a Delaunay triangulation) is non-negative,
/// and the faces of the edges around an inner vertex close its cell (Σ face × unit normal = 0).
/// The one boundary edge of this mesh opposite an obtuse angle is named in a note.
#[test]
fn dual_prints_the_finite_volume_cells() {
    let d = scratch("dual");
    let mesh = d.join("sq.node");
    let o = cvtmesh(&[
        "mesh",
        "square_hole",
        "-n",
        "800",
        "-o",
        mesh.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let rows = |args: &[&str]| -> Vec<Vec<f64>> {
        let o = cvtmesh(args);
        assert!(o.status.success(), "{}", text(&o));
        let out = String::from_utf8(o.stdout).unwrap();
        out.lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let volumes = rows(&["dual", mesh.to_str().unwrap(), "--volumes"]);
    let faces = rows(&["dual", mesh.to_str().unwrap()]);
    let o = cvtmesh(&["dual", mesh.to_str().unwrap()]);
    let negative = faces.iter().filter(|r| r[3] < -1e-12 * r[2]).count();
    assert_eq!(negative, 1);
    assert!(text(&o).contains("note: negative faces, where a two-point flux is not monotone: 1 boundary edge opposite an obtuse angle"), "{}", text(&o));
    assert_eq!(volumes.len(), 800);
    let total: f64 = volumes.iter().map(|r| r[3]).sum();
    let square_hole = 4.0 - std::f64::consts::PI * 0.16;
    assert!((total / square_hole - 1.0).abs() < 0.01, "{total}");
    assert!(faces.iter().all(|r| r[4] == 1.0 || r[3] >= -1e-12 * r[2]));
    // Around an inner vertex: Σ face · (x_w − x_v)/|x_w − x_v| = 0.
    let xy = |v: usize| (volumes[v][1], volumes[v][2]);
    let inner = (0..800)
        .find(|&v| {
            faces
                .iter()
                .filter(|r| r[0] as usize == v || r[1] as usize == v)
                .all(|r| r[4] == 0.0)
        })
        .unwrap();
    let (mut sx, mut sy) = (0.0, 0.0);
    for r in faces
        .iter()
        .filter(|r| r[0] as usize == inner || r[1] as usize == inner)
    {
        let other = if r[0] as usize == inner { r[1] } else { r[0] } as usize;
        let ((x0, y0), (x1, y1)) = (xy(inner), xy(other));
        sx += r[3] * (x1 - x0) / r[2];
        sy += r[3] * (y1 - y0) / r[2];
    }
    assert!(sx.hypot(sy) < 1e-9, "{sx} {sy}");
    let o = cvtmesh(&["dual", d.join("none.msh").to_str().unwrap()]);
    assert!(!o.status.success() && text(&o).contains("none.msh"));
    // A triangle of three points on a line has no circumcentre: refused, not printed as inf.
    std::fs::write(d.join("flat.node"), "4 2 0 0\n1 0 0\n2 1 0\n3 2 0\n4 0 1\n").unwrap();
    std::fs::write(d.join("flat.ele"), "2 3 0\n1 1 2 4\n2 1 2 3\n").unwrap();
    let o = cvtmesh(&["dual", d.join("flat.node").to_str().unwrap()]);
    assert!(!o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("has no positive area") && o.stdout.is_empty(),
        "{}",
        text(&o)
    );
}

/// A Triangle `.poly` with an interface from wall to wall (its segment with the region on both
/// sides, marked 7): `regions` lists it, `mesh` follows it with edges that its `.msh` keeps in
/// physical curve 7, and an interface that leaves the region is refused with no file written.
#[test]
fn a_poly_interface_is_listed_meshed_along_and_kept_in_the_file() {
    let dir = scratch("poly_interface");
    let poly = dir.join("two.poly");
    std::fs::write(
        &poly,
        "6 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n5 0.5 0 0\n6 0.5 1 0\n\
         7 1\n1 1 5 1\n2 5 2 1\n3 2 3 1\n4 3 6 1\n5 6 4 1\n6 4 1 1\n7 5 6 7\n0\n",
    )
    .unwrap();
    let o = cvtmesh(&["regions", s(&poly)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o)
            .contains("line 0 from (0.5, 0) to (0.5, 1), 2 vertices, length 1.000000, marker 7"),
        "{}",
        text(&o)
    );
    let out = dir.join("two.msh");
    let o = cvtmesh(&["mesh", s(&poly), "-n", "400", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    let (mesh, walls) = cvtmesh::io::read_mesh_with_walls(&out).unwrap();
    assert_eq!(walls.inner_markers.len(), walls.inner.len());
    assert!(walls.inner_markers.iter().all(|&m| m == 7));
    let length: f64 = walls
        .inner
        .iter()
        .map(|&[a, b]| mesh.points[a as usize].distance(mesh.points[b as usize]))
        .sum();
    assert!((length - 1.0).abs() < 1e-12, "{length}");
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .contains("1 7 \"marker7\""));
    // A crack run past the right wall keeps its part inside, cut at the wall, as Triangle
    // keeps it; the note gives the length cut off.
    let past = dir.join("past.poly");
    std::fs::write(
        &past,
        "7 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n5 0.5 0.5 0\n6 1.5 0.5 0\n7 0.5 0.2 0\n\
         5 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n5 5 6 7\n0\n",
    )
    .unwrap();
    let cut = dir.join("cut.msh");
    let o = cvtmesh(&["mesh", s(&past), "-n", "400", "-q", "-o", s(&cut)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("1 segment in a hole or outside the region, wholly or in part (0.500000"),
        "{}",
        text(&o)
    );
    let (mesh, walls) = cvtmesh::io::read_mesh_with_walls(&cut).unwrap();
    let length: f64 = walls
        .inner
        .iter()
        .map(|&[a, b]| mesh.points[a as usize].distance(mesh.points[b as usize]))
        .sum();
    assert!((length - 0.5).abs() < 1e-12, "{length}");
    assert!(mesh.points.contains(&cvtmesh::DVec2::new(1.0, 0.5)));
}

/// A digitized interface of more vertices than the mesh has: refused as it is (every vertex of
/// a line is a mesh vertex), meshed under `--simplify auto` with the line simplified too, and
/// the mesh's interface within the printed distance of the given one.
#[test]
fn simplify_auto_simplifies_a_digitized_interface() {
    let dir = scratch("digitized_interface");
    let poly = dir.join("wave.poly");
    let n = 3000;
    let wave = |i: usize| {
        let x = i as f64 / n as f64;
        (x, 0.5 + 0.05 * (std::f64::consts::TAU * x).sin())
    };
    let mut file = format!("{} 2 0 1\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n", n + 5);
    for i in 0..=n {
        let (x, y) = wave(i);
        file += &format!("{} {x} {y} 0\n", i + 5);
    }
    // The walls, the right and left ones split where the wave meets them, then the wave.
    let last = n + 5;
    file += &format!(
        "{} 1\n1 1 2 1\n2 2 {last} 1\n3 {last} 3 1\n4 3 4 1\n",
        n + 6
    );
    file += "5 4 5 1\n6 5 1 1\n";
    for i in 0..n {
        file += &format!("{} {} {} 7\n", i + 7, i + 5, i + 6);
    }
    file += "0\n";
    std::fs::write(&poly, file).unwrap();
    let out = dir.join("wave.msh");
    let o = cvtmesh(&["mesh", s(&poly), "-n", "1500", "-o", s(&out)]);
    assert!(!o.status.success() && !out.exists(), "{}", text(&o));
    assert!(text(&o).contains("too small"), "{}", text(&o));
    let o = cvtmesh(&[
        "mesh",
        s(&poly),
        "-n",
        "1500",
        "--simplify",
        "auto",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let said = text(&o);
    let lines = said
        .split("its lines inside from 3001 to ")
        .nth(1)
        .unwrap_or_else(|| panic!("{said}"));
    let kept: usize = lines.split(';').next().unwrap().parse().unwrap();
    assert!(kept < 100, "{said}");
    let (mesh, walls) = cvtmesh::io::read_mesh_with_walls(&out).unwrap();
    // Every vertex of the mesh's interface lies on the given wave, within the deviation.
    let deviation: f64 = said
        .split("stays within ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .unwrap()
        .parse()
        .unwrap();
    assert!(!walls.inner.is_empty());
    for v in walls.inner.iter().flatten() {
        let p = mesh.points[*v as usize];
        let on = 0.5 + 0.05 * (std::f64::consts::TAU * p.x).sin();
        assert!(
            (p.y - on).abs() <= deviation + 1e-3,
            "{p} off the wave by {}",
            p.y - on
        );
    }
}

/// A `.poly`'s regional attributes number the parts its interface cuts the region into: listed
/// by `regions`, each triangle's `.ele` attribute (Triangle's `-A`), and kept by a polish.
/// The area of the triangles of each attribute of a Triangle `.node`/`.ele` pair, from the
/// files as Triangle's readers see them.
fn areas_by_attribute(node: &std::path::Path) -> std::collections::BTreeMap<i64, f64> {
    let nodes: Vec<Vec<f64>> = std::fs::read_to_string(node)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
        .collect();
    let ele = std::fs::read_to_string(node.with_extension("ele")).unwrap();
    let mut rows = ele.lines().filter(|l| !l.starts_with('#'));
    assert!(rows.next().unwrap().ends_with(" 3 1"));
    let mut by = std::collections::BTreeMap::new();
    for row in rows {
        let v: Vec<f64> = row.split_whitespace().map(|w| w.parse().unwrap()).collect();
        let p = |k: usize| &nodes[v[k] as usize - 1][1..3];
        let (a, b, c) = (p(1), p(2), p(3));
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
        *by.entry(v[4] as i64).or_insert(0.0) += area;
    }
    by
}

#[test]
fn a_poly_s_crossing_segments_are_split_as_triangle_splits_them() {
    // Two interfaces crossing at the centre of the square, a regional attribute per quarter.
    let dir = scratch("poly_crossing");
    let poly = dir.join("cross.poly");
    std::fs::write(
        &poly,
        "8 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n5 0.5 0 1\n6 0.5 1 1\n7 0 0.5 1\n\
         8 1 0.5 1\n10 1\n1 1 5 1\n2 5 2 1\n3 2 8 1\n4 8 3 1\n5 3 6 1\n6 6 4 1\n7 4 7 1\n\
         8 7 1 1\n9 5 6 2\n10 7 8 3\n0\n4\n1 0.25 0.25 1 -1\n2 0.75 0.25 2 -1\n\
         3 0.75 0.75 3 -1\n4 0.25 0.75 4 -1\n",
    )
    .unwrap();
    let o = cvtmesh(&["regions", s(&poly)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("line 0 from (0.5, 0) to (0.5, 1), 3 vertices")
            && text(&o).contains("line 1 from (0, 0.5) to (1, 0.5), 3 vertices"),
        "{}",
        text(&o)
    );
    for method in ["ccvt", "refine"] {
        let out = dir.join(format!("{method}.node"));
        let o = cvtmesh(&["mesh", s(&poly), "-n", "600", "-m", method, "-o", s(&out)]);
        assert!(o.status.success(), "{method}: {}", text(&o));
        let by = areas_by_attribute(&out);
        assert_eq!(by.len(), 4, "{method}: {by:?}");
        assert!(
            by.values().all(|a| (a - 0.25).abs() < 1e-12),
            "{method}: {by:?}"
        );
    }
}

#[test]
fn a_poly_s_regional_attributes_are_the_triangles_attributes() {
    let dir = scratch("poly_subdomains");
    let poly = dir.join("two.poly");
    std::fs::write(
        &poly,
        "6 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n5 0.5 0 0\n6 0.5 1 0\n\
         7 1\n1 1 5 1\n2 5 2 1\n3 2 3 1\n4 3 6 1\n5 6 4 1\n6 4 1 1\n7 5 6 7\n0\n\
         2\n1 0.25 0.5 3 -1\n2 0.75 0.5 4 -1\n",
    )
    .unwrap();
    let o = cvtmesh(&["regions", s(&poly)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("subdomain 3 holds (0.25, 0.5)")
            && text(&o).contains("subdomain 4 holds (0.75, 0.5)"),
        "{}",
        text(&o)
    );
    let out = dir.join("out.node");
    let o = cvtmesh(&["mesh", s(&poly), "-n", "400", "-o", s(&out)]);
    assert!(o.status.success(), "{}", text(&o));
    let by = areas_by_attribute(&out);
    assert_eq!(by.len(), 2, "{by:?}");
    assert!(
        (by[&3] - 0.5).abs() < 1e-12 && (by[&4] - 0.5).abs() < 1e-12,
        "{by:?}"
    );
    let polished = dir.join("polished.node");
    let o = cvtmesh(&["polish", s(&out), "--below", "45", "-o", s(&polished)]);
    assert!(o.status.success(), "{}", text(&o));
    let by = areas_by_attribute(&polished);
    assert!(
        (by[&3] - 0.5).abs() < 1e-12 && (by[&4] - 0.5).abs() < 1e-12,
        "{by:?}"
    );
}
