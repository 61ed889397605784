//! The CSV records: one row per (region, K, method, seed, kind), plus failed jobs.
use crate::paper::TABLES;
use crate::{Measure, MethodId, StudyError};
use cvtmesh::metrics::Measures;
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::collections::BTreeSet;
use std::path::Path;

/// Exact measures (Section 3 on clipped Voronoi cells) or the paper-style sampled estimate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// `cvtmesh::metrics::measures`.
    Exact,
    /// `cvtmesh::metrics::sampled_measures`.
    Sampled,
}

impl Kind {
    /// Both kinds, exact first.
    pub const ALL: [Kind; 2] = [Kind::Exact, Kind::Sampled];
}

/// One line of `csv/metrics.csv`. Floats are written with the shortest text that parses
/// back to the same `f64`, so the file round-trips exactly.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Row {
    /// Region name.
    pub region: String,
    /// The K asked for (the paper's K).
    pub K_requested: usize,
    /// Method name (`MethodId::name`).
    pub method: String,
    /// Seed of the method.
    pub seed: u64,
    /// Exact or sampled.
    pub kind: Kind,
    /// Vertices produced.
    pub K: usize,
    /// Triangles produced.
    pub Ktilde: usize,
    /// λ.
    pub lambda: f64,
    /// γ.
    pub gamma: f64,
    /// h.
    pub h: f64,
    /// μ.
    pub mu: f64,
    /// χ.
    pub chi: f64,
    /// ν.
    pub nu: f64,
    /// τ.
    pub tau: f64,
    /// d.
    pub d: f64,
    /// α.
    pub alpha: f64,
    /// β.
    pub beta: f64,
    /// q.
    pub q: f64,
    /// p.
    pub p: f64,
    /// Iterations the method ran.
    pub iterations: usize,
    /// Whether it met its convergence criterion.
    pub converged: bool,
    /// Wall time of the method (meshing only, not the measures), in seconds.
    pub seconds: f64,
}

impl Row {
    /// A row from the 14 values in table order.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        region: &str,
        k_requested: usize,
        method: MethodId,
        seed: u64,
        kind: Kind,
        values: [f64; 14],
        iterations: usize,
        converged: bool,
        seconds: f64,
    ) -> Row {
        let v = values;
        Row {
            region: region.to_string(),
            K_requested: k_requested,
            method: method.name().to_string(),
            seed,
            kind,
            K: v[0].max(0.0) as usize,
            Ktilde: v[1].max(0.0) as usize,
            lambda: v[2],
            gamma: v[3],
            h: v[4],
            mu: v[5],
            chi: v[6],
            nu: v[7],
            tau: v[8],
            d: v[9],
            alpha: v[10],
            beta: v[11],
            q: v[12],
            p: v[13],
            iterations,
            converged,
            seconds,
        }
    }

    /// The measures of this row.
    pub fn measures(&self) -> Measures {
        Measures {
            k: self.K,
            k_tilde: self.Ktilde,
            lambda: self.lambda,
            gamma: self.gamma,
            h: self.h,
            mu: self.mu,
            chi: self.chi,
            nu: self.nu,
            tau: self.tau,
            d: self.d,
            alpha: self.alpha,
            beta: self.beta,
            q: self.q,
            p: self.p,
        }
    }

    /// The value of one table row.
    pub fn value(&self, m: Measure) -> f64 {
        self.measures().values()[m.index()]
    }

    /// The method, if the name is known.
    pub fn method_id(&self) -> Option<MethodId> {
        MethodId::parse(&self.method)
    }

    /// "circle K=88 ccvt2 seed 1 exact": the identity of the row.
    pub fn key(&self) -> String {
        format!(
            "{} K={} {} seed {} {:?}",
            self.region, self.K_requested, self.method, self.seed, self.kind
        )
        .to_lowercase()
    }
}

/// A job that failed: it has no metrics rows.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Failure {
    /// Region name.
    pub region: String,
    /// The K asked for.
    pub K_requested: usize,
    /// Method name.
    pub method: String,
    /// Seed.
    pub seed: u64,
    /// The error message.
    pub error: String,
}

/// Canonical order of (region, K, method, seed): table order, column order, seed. Rows of
/// regions or K outside the paper's tables sort after, by name.
fn order(region: &str, k: usize, method: &str, seed: u64) -> (usize, String, usize, usize, u64) {
    let t = TABLES
        .iter()
        .position(|t| t.region == region && t.k == k)
        .unwrap_or(usize::MAX);
    let m = MethodId::parse(method).map_or(usize::MAX, |m| m as usize);
    (t, region.to_string(), k, m, seed)
}

/// Sort rows canonically (so merged shards equal an unsharded run, row for row).
pub fn sort_rows(rows: &mut [Row]) {
    rows.sort_by(|a, b| {
        order(&a.region, a.K_requested, &a.method, a.seed)
            .cmp(&order(&b.region, b.K_requested, &b.method, b.seed))
            .then(a.kind.cmp(&b.kind))
            .then_with(|| a.method.cmp(&b.method))
    });
}

/// Sort failures canonically.
pub fn sort_failures(f: &mut [Failure]) {
    f.sort_by(|a, b| {
        order(&a.region, a.K_requested, &a.method, a.seed)
            .cmp(&order(&b.region, b.K_requested, &b.method, b.seed))
            .then(Ordering::Equal)
    });
}

/// Serialize records (with header) to CSV text.
pub fn to_csv<T: Serialize>(records: &[T]) -> Result<Vec<u8>, StudyError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in records {
        w.serialize(r).map_err(|e| StudyError::Csv {
            path: "(output)".into(),
            message: e.to_string(),
        })?;
    }
    w.into_inner().map_err(|e| StudyError::Csv {
        path: "(output)".into(),
        message: e.to_string(),
    })
}

/// The header line of `metrics.csv`, also written when there are no rows.
pub const METRICS_HEADER: &str = "region,K_requested,method,seed,kind,K,Ktilde,lambda,gamma,h,mu,chi,nu,tau,d,alpha,beta,q,p,iterations,converged,seconds";
/// The header line of `failures.csv`.
pub const FAILURES_HEADER: &str = "region,K_requested,method,seed,error";

/// CSV text of rows; just the header if there are none.
pub fn rows_csv(rows: &[Row]) -> Result<Vec<u8>, StudyError> {
    if rows.is_empty() {
        return Ok(format!("{METRICS_HEADER}\n").into_bytes());
    }
    to_csv(rows)
}

/// CSV text of failures; just the header if there are none.
pub fn failures_csv(f: &[Failure]) -> Result<Vec<u8>, StudyError> {
    if f.is_empty() {
        return Ok(format!("{FAILURES_HEADER}\n").into_bytes());
    }
    to_csv(f)
}

/// Parse CSV text of records; `label` names the source in errors.
pub fn from_csv<T: for<'de> Deserialize<'de>>(
    text: &[u8],
    label: &str,
) -> Result<Vec<T>, StudyError> {
    let mut rd = csv::Reader::from_reader(text);
    rd.deserialize()
        .enumerate()
        .map(|(i, r)| {
            r.map_err(|e| StudyError::Csv {
                path: label.to_string(),
                message: format!("record {}: {e}", i + 1),
            })
        })
        .collect()
}

/// Read a CSV file of records.
pub fn read_csv<T: for<'de> Deserialize<'de>>(path: &Path) -> Result<Vec<T>, StudyError> {
    let bytes = std::fs::read(path).map_err(|e| StudyError::io(path, e))?;
    from_csv(&bytes, &path.display().to_string())
}

/// Parse CSV text of records whose header line must be `header`. [`from_csv`] matches
/// fields by column name, so it reads a file without rows under any header (another CSV,
/// an empty file) as no rows: a run without results.
pub fn from_csv_with_header<T: for<'de> Deserialize<'de>>(
    text: &[u8],
    label: &str,
    header: &str,
) -> Result<Vec<T>, StudyError> {
    let mut rd = csv::Reader::from_reader(text);
    let found = rd.headers().map_err(|e| StudyError::Csv {
        path: label.to_string(),
        message: format!("header: {e}"),
    })?;
    if !found.iter().eq(header.split(',')) {
        let message = match found.is_empty() {
            true => format!("empty file; expected the header line {header}"),
            false => format!(
                "unexpected header '{}'; expected the columns {header}",
                found.iter().collect::<Vec<_>>().join(",")
            ),
        };
        return Err(StudyError::Csv {
            path: label.to_string(),
            message,
        });
    }
    from_csv(text, label)
}

/// Read a CSV file of records whose header line must be `header` ([`from_csv_with_header`]).
pub fn read_csv_with_header<T: for<'de> Deserialize<'de>>(
    path: &Path,
    header: &str,
) -> Result<Vec<T>, StudyError> {
    let bytes = std::fs::read(path).map_err(|e| StudyError::io(path, e))?;
    from_csv_with_header(&bytes, &path.display().to_string(), header)
}

/// Combine row sets: reject duplicates and unknown methods, sort canonically.
pub fn merge_rows(parts: Vec<Vec<Row>>) -> Result<Vec<Row>, StudyError> {
    let mut seen = BTreeSet::new();
    let mut all = Vec::new();
    for row in parts.into_iter().flatten() {
        if row.method_id().is_none() {
            return Err(StudyError::Csv {
                path: "merge input".into(),
                message: format!(
                    "unknown method '{}'; valid methods: {}",
                    row.method,
                    MethodId::valid_names()
                ),
            });
        }
        if !seen.insert(row.key()) {
            return Err(StudyError::Duplicate(row.key()));
        }
        all.push(row);
    }
    sort_rows(&mut all);
    Ok(all)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::fake_row;

    #[test]
    fn csv_round_trip_is_exact_and_has_the_documented_header() {
        let rows = vec![
            fake_row("circle", 88, MethodId::Ccvt2, 1, Kind::Exact, 0.1 + 0.2),
            fake_row(
                "lake",
                1109,
                MethodId::CcvtFast,
                2,
                Kind::Sampled,
                f64::INFINITY,
            ),
        ];
        let bytes = rows_csv(&rows).unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        assert_eq!(text.lines().next().unwrap(), METRICS_HEADER);
        assert!(text.contains("ccvt,2,sampled,"));
        // The measure columns are the metrics crate's, in its order.
        let columns: Vec<&str> = METRICS_HEADER.split(',').skip(5).take(14).collect();
        assert_eq!(columns, Measures::NAMES);
        for m in Measure::ALL {
            let want = rows[0].measures().get(m.csv_name());
            assert_eq!(Some(rows[0].value(m)), want, "{m:?}");
        }
        let back: Vec<Row> = from_csv(&bytes, "t").unwrap();
        assert_eq!(back, rows);
        assert_eq!(back[0].lambda.to_bits(), rows[0].lambda.to_bits());
        assert_eq!(
            String::from_utf8(rows_csv(&[]).unwrap()).unwrap().trim(),
            METRICS_HEADER
        );
        let f = vec![Failure {
            region: "horn".into(),
            K_requested: 138,
            method: "vtm".into(),
            seed: 1,
            error: "it broke, badly".into(),
        }];
        let fb = failures_csv(&f).unwrap();
        assert_eq!(
            String::from_utf8(fb.clone())
                .unwrap()
                .lines()
                .next()
                .unwrap(),
            FAILURES_HEADER
        );
        assert_eq!(from_csv::<Failure>(&fb, "t").unwrap(), f);
    }

    #[test]
    fn a_wrong_or_missing_header_is_an_error_not_an_empty_run() {
        let read =
            |text: &str| from_csv_with_header::<Row>(text.as_bytes(), "m.csv", METRICS_HEADER);
        // The header a run writes when every job failed: no rows, no error.
        assert_eq!(read(&format!("{METRICS_HEADER}\n")).unwrap(), vec![]);
        let row = fake_row("circle", 19, MethodId::Vtm, 1, Kind::Exact, 1.0);
        let text = String::from_utf8(rows_csv(std::slice::from_ref(&row)).unwrap()).unwrap();
        assert_eq!(read(&text).unwrap(), vec![row]);
        for bad in [
            format!("{FAILURES_HEADER}\n"),
            "case,K_requested,method\n".to_string(),
            text.replacen("lambda", "lambda2", 1),
            text.replacen(",seconds", "", 1),
            String::new(),
        ] {
            let e = read(&bad).unwrap_err().to_string();
            assert!(
                e.starts_with("m.csv: ") && e.contains(METRICS_HEADER),
                "{bad:?}: {e}"
            );
        }
        assert!(read("").unwrap_err().to_string().contains("empty file"));
    }

    #[test]
    fn merge_sorts_canonically_and_rejects_duplicates() {
        let a = fake_row("lake", 1109, MethodId::Triangle, 1, Kind::Exact, 1.0);
        let b = fake_row("circle", 362, MethodId::Vtm, 1, Kind::Sampled, 1.0);
        let c = fake_row("circle", 362, MethodId::Vtm, 1, Kind::Exact, 1.0);
        let d = fake_row("circle", 19, MethodId::CcvtFast, 1, Kind::Exact, 1.0);
        let merged =
            merge_rows(vec![vec![a.clone(), b.clone()], vec![c.clone(), d.clone()]]).unwrap();
        assert_eq!(merged, vec![d, c.clone(), b, a]);
        assert!(matches!(
            merge_rows(vec![vec![c.clone()], vec![c.clone()]]),
            Err(StudyError::Duplicate(_))
        ));
        let mut bad = c;
        bad.method = "lloyd".into();
        assert!(merge_rows(vec![vec![bad]]).is_err());
    }
}
