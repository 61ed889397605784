//! `fidelity.md` and `csv/fidelity.csv`: where each of the paper's printed numbers falls in
//! our distribution over seeds, and how often it is inside our range or near our median.
use crate::paper::{sample_scale, untrustworthy, PaperTables, TableSpec};
use crate::record::{Kind, Row};
use crate::{scaled_label, Measure, MethodId};
use std::collections::BTreeMap;
use std::fmt::Write;

/// "Near" our median: the paper's number within this relative distance of it.
pub const NEAR: f64 = 0.30;

/// Which of our numbers a printed number is held against.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Basis {
    /// The exact measures with τ and d taken at the paper's length scale (× s², × s⁴ with
    /// s = [`sample_scale`]; the other measures are scale-free). The closest model of the
    /// paper's numbers found.
    ExactPaperScale,
    /// The paper-style sampled estimate (10⁴ samples, the same length scale).
    Sampled,
    /// The exact measures as the study reports them.
    Exact,
}

impl Basis {
    /// Name in `csv/fidelity.csv`.
    pub fn name(self) -> &'static str {
        match self {
            Basis::ExactPaperScale => "exact_paper_scale",
            Basis::Sampled => "sampled",
            Basis::Exact => "exact",
        }
    }
}

/// Where a paper number falls among our values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Position {
    /// Below our smallest value.
    Below,
    /// Within [min, max]: the mid-rank percentile, 100 · (#below + ½ #equal) / n.
    Within(f64),
    /// Above our largest value.
    Above,
}

/// One printed number against our values of the same cell.
#[derive(Clone, Debug, PartialEq)]
pub struct Fidelity {
    /// The paper's table.
    pub table: u8,
    /// The row.
    pub measure: Measure,
    /// The column.
    pub method: MethodId,
    /// Which of our numbers it is compared with.
    pub basis: Basis,
    /// The paper's value (true scale).
    pub paper: f64,
    /// Half a unit in the paper's last printed digit ([`PaperCell::half_unit`]): the printed
    /// number stands for `paper ± half_unit`.
    ///
    /// [`PaperCell::half_unit`]: crate::paper::PaperCell::half_unit
    pub half_unit: f64,
    /// Our values over seeds, sorted.
    pub ours: Vec<f64>,
}

impl Fidelity {
    /// Our median (NaN without values).
    pub fn median(&self) -> f64 {
        median(&self.ours)
    }

    /// The paper's number relative to our median.
    pub fn ratio(&self) -> f64 {
        self.paper / self.median()
    }

    /// Where the paper's number falls; `None` without values. It is inside our range when any
    /// value it rounds to is (a deterministic method equals the paper's number when its value
    /// prints the same).
    pub fn position(&self) -> Option<Position> {
        let (first, last) = (self.ours.first()?, self.ours.last()?);
        Some(if self.paper + self.half_unit < *first {
            Position::Below
        } else if self.paper - self.half_unit > *last {
            Position::Above
        } else {
            let below = self.ours.iter().filter(|&&v| v < self.paper).count() as f64;
            let equal = self.ours.iter().filter(|&&v| v == self.paper).count() as f64;
            Position::Within(100.0 * (below + 0.5 * equal) / self.ours.len() as f64)
        })
    }

    /// True if the paper's number lies within our range over seeds.
    pub fn in_range(&self) -> bool {
        matches!(self.position(), Some(Position::Within(_)))
    }

    /// True if the paper's number is within ±[`NEAR`] of our median.
    pub fn near_median(&self) -> bool {
        let m = self.median();
        m.is_finite() && (self.paper - m).abs() <= NEAR * m.abs()
    }

    /// "p37", "below ×0.52" or "above ×1.80" (paper / our median), "—" without values.
    pub fn label(&self) -> String {
        match self.position() {
            None => "—".into(),
            Some(Position::Within(p)) => format!("p{p:.0}"),
            Some(Position::Below) => format!("below ×{}", ratio_text(self.ratio())),
            Some(Position::Above) => format!("above ×{}", ratio_text(self.ratio())),
        }
    }
}

fn ratio_text(r: f64) -> String {
    if r.is_finite() {
        format!("{r:.2}")
    } else {
        "∞".into()
    }
}

/// The median of sorted values (NaN if empty).
pub fn median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => sorted[n / 2],
        _ => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
    }
}

/// Every printed number of `tables` against our values on `basis` (NaN values dropped).
pub fn compare(
    rows: &[Row],
    paper: &PaperTables,
    tables: &[&TableSpec],
    basis: Basis,
) -> Vec<Fidelity> {
    let kind = match basis {
        Basis::Sampled => Kind::Sampled,
        Basis::Exact | Basis::ExactPaperScale => Kind::Exact,
    };
    let mut ours: BTreeMap<(u8, MethodId), Vec<&Row>> = BTreeMap::new();
    for t in tables {
        for r in rows
            .iter()
            .filter(|r| r.region == t.region && r.K_requested == t.k && r.kind == kind)
        {
            if let Some(m) = r.method_id() {
                ours.entry((t.number, m)).or_default().push(r);
            }
        }
    }
    let mut out = Vec::new();
    for t in tables {
        for method in MethodId::ALL {
            let Some(rs) = ours.get(&(t.number, method)) else {
                continue;
            };
            let s = sample_scale(t.region);
            for m in Measure::ALL {
                let Some(c) = paper.cell(t.number, m, method) else {
                    continue;
                };
                let factor = match (basis, m) {
                    (Basis::ExactPaperScale, Measure::Tau) => s * s,
                    (Basis::ExactPaperScale, Measure::D) => s.powi(4),
                    _ => 1.0,
                };
                let mut v: Vec<f64> = rs
                    .iter()
                    .map(|r| r.value(m) * factor)
                    .filter(|v| !v.is_nan())
                    .collect();
                v.sort_by(f64::total_cmp);
                out.push(Fidelity {
                    table: t.number,
                    measure: m,
                    method,
                    basis,
                    paper: c.value,
                    half_unit: c.half_unit(m),
                    ours: v,
                });
            }
        }
    }
    out
}

/// True for the cells that enter the shares: quality measures the paper printed correctly.
fn scored(f: &Fidelity) -> bool {
    !f.measure.is_count() && !untrustworthy(f.table, f.measure) && !f.ours.is_empty()
}

fn share(cells: &[&Fidelity], pred: impl Fn(&Fidelity) -> bool) -> String {
    if cells.is_empty() {
        return "—".into();
    }
    let k = cells.iter().filter(|f| pred(f)).count();
    format!(
        "{k}/{} ({:.0} %)",
        cells.len(),
        100.0 * k as f64 / cells.len() as f64
    )
}

fn percent(cells: &[&Fidelity], pred: impl Fn(&Fidelity) -> bool) -> String {
    if cells.is_empty() {
        return "—".into();
    }
    let k = cells.iter().filter(|f| pred(f)).count();
    format!("{:.0}", 100.0 * k as f64 / cells.len() as f64)
}

/// The scored cells of one method and one measure (`None`: all of them).
fn pick(cells: &[Fidelity], method: Option<MethodId>, measure: Option<Measure>) -> Vec<&Fidelity> {
    cells
        .iter()
        .filter(|f| {
            scored(f)
                && method.is_none_or(|m| f.method == m)
                && measure.is_none_or(|m| f.measure == m)
        })
        .collect()
}

/// The methods present in `cells`, in column order.
fn methods_of(cells: &[Fidelity]) -> Vec<MethodId> {
    let mut m: Vec<MethodId> = cells.iter().map(|f| f.method).collect();
    m.sort();
    m.dedup();
    m
}

fn shares_by_measure(out: &mut String, cells: &[Fidelity], methods: &[MethodId]) {
    out.push_str("| measure |");
    for m in methods {
        let _ = write!(out, " {} |", m.column());
    }
    out.push_str(" all |\n| :--- |");
    for _ in methods {
        out.push_str(" ---: |");
    }
    out.push_str(" ---: |\n");
    for measure in Measure::QUALITY {
        let _ = write!(out, "| {} |", measure.symbol());
        for m in methods.iter().map(|&m| Some(m)).chain([None]) {
            let c = pick(cells, m, Some(measure));
            let mut r: Vec<f64> = c
                .iter()
                .map(|f| f.ratio())
                .filter(|r| r.is_finite())
                .collect();
            r.sort_by(f64::total_cmp);
            let med = median(&r);
            let _ = write!(
                out,
                " {} / {} / {} |",
                percent(&c, Fidelity::in_range),
                percent(&c, Fidelity::near_median),
                if med.is_finite() {
                    format!("{med:.2}")
                } else {
                    "—".into()
                }
            );
        }
        out.push('\n');
    }
    out.push('\n');
}

/// The Markdown of `fidelity.md`. `main` is the comparison with the exact measures at the
/// paper's length scale, `sampled` with the paper-style estimate, `exact` with the exact
/// measures as reported; `seeds` names the seeds ("seeds 1–10").
pub fn render_fidelity(
    main: &[Fidelity],
    sampled: &[Fidelity],
    exact: &[Fidelity],
    tables: &[&TableSpec],
    paper: &PaperTables,
    seeds: &str,
) -> String {
    let mut out = String::new();
    out.push_str("# Fidelity: the paper's numbers against our distribution over seeds\n\n");
    let _ = writeln!(
        out,
        "Ours: {seeds}. For every number the paper prints, where it falls among our values of \
         the same (table, method, measure): inside our range (the mid-rank percentile pNN), or \
         below/above it (with the paper's number over our median). A printed number stands for \
         every value that rounds to it (± half a unit in its last digit): it is in our range if \
         any of them is. \"Near\" means within \
         ±{:.0} % of our median. Shares count the twelve quality measures (Table 6's misprinted \
         γ and h left out): 142 cells per method.\n\n\
         Three bases: **exact, paper's scale** is our exact measures with τ and d taken at the \
         length scale the paper's circle and annulus tables use (coordinates halved: τ × ¼, \
         d × 1/16; every other measure is scale-free), the closest model of the paper's numbers \
         found; **paper-style** is our 10⁴-sample estimate at that scale; **exact** is the exact \
         measures as the tables print them. Each seed draws every method's free choices: the \
         random-start methods' initial points, where DISTMESH's grid starts, and where \
         TRIANGLE's polygon of a closed curve starts; TRIANGLE has no such choice on a region \
         without a closed curve (hex_hole, horn, bike_seat, square_two_hex, lake), where its \
         range is a single value (last column; with one seed every range is) and \"in range\" \
         would mean equal: judge those by \"near\". See docs/study-statistics.md for what \
         explains the gaps.\n",
        NEAR * 100.0
    );
    let methods = methods_of(main);
    out.push_str("## By method\n\n");
    out.push_str(
        "| method | in range, exact at paper's scale | near median, exact at paper's scale | \
         in range, paper-style | near median, paper-style | in range, exact | near median, exact \
         | our range a single value |\n\
         | :--- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
    );
    for m in methods.iter().map(|&m| Some(m)).chain([None]) {
        let _ = write!(out, "| {} |", m.map_or("all", |m| m.column()));
        // One seed's range is one value, as the text above says.
        let point = share(&pick(main, m, None), |f| {
            !f.ours.is_empty() && f.ours.first() == f.ours.last()
        });
        for cells in [main, sampled, exact] {
            let c = pick(cells, m, None);
            let _ = write!(
                out,
                " {} | {} |",
                share(&c, Fidelity::in_range),
                share(&c, Fidelity::near_median)
            );
        }
        let _ = writeln!(out, " {point} |");
    }
    out.push('\n');

    out.push_str("## By measure and method\n\n");
    out.push_str("Each cell: % of tables with the paper's number in our range / % near our median / median over tables of paper ÷ our median.\n\n");
    out.push_str("### Exact measures at the paper's length scale\n\n");
    shares_by_measure(&mut out, main, &methods);
    out.push_str("### Paper-style sampled estimate\n\n");
    shares_by_measure(&mut out, sampled, &methods);

    out.push_str("## Cell by cell (exact measures at the paper's length scale)\n\n");
    let by_cell: BTreeMap<(u8, Measure, MethodId), &Fidelity> = main
        .iter()
        .map(|f| ((f.table, f.measure, f.method), f))
        .collect();
    for t in tables {
        let _ = writeln!(out, "### {}\n", t.title());
        out.push('|');
        for m in &methods {
            let _ = write!(out, " | {}", m.column());
        }
        out.push_str(" |\n| :--- |");
        for _ in &methods {
            out.push_str(" ---: |");
        }
        out.push('\n');
        for measure in Measure::ALL {
            let (_, exp) = paper.row_exps(t.number, measure);
            let _ = write!(out, "| {} |", scaled_label(measure, exp));
            for &m in &methods {
                let cell = by_cell
                    .get(&(t.number, measure, m))
                    .map_or("—".to_string(), |f| {
                        let l = f.label();
                        if untrustworthy(t.number, measure) {
                            format!("{l} †")
                        } else {
                            l
                        }
                    });
                let _ = write!(out, " {cell} |");
            }
            out.push('\n');
        }
        out.push('\n');
    }
    if tables.iter().any(|t| t.number == 6) {
        out.push_str("† The paper's γ and h rows of Table 6 are a typesetting error.\n");
    }
    out
}

/// CSV of every comparison (any bases).
pub fn fidelity_csv(cells: &[Fidelity]) -> Vec<u8> {
    let mut s = String::from(
        "table,measure,method,basis,paper,seeds,min,median,max,position,percentile,paper_over_median,near_median\n",
    );
    for f in cells {
        let (pos, pct) = match f.position() {
            None => ("none", String::new()),
            Some(Position::Below) => ("below", String::new()),
            Some(Position::Above) => ("above", String::new()),
            Some(Position::Within(p)) => ("within", format!("{p}")),
        };
        let num = |x: Option<&f64>| x.map_or(String::new(), |v| format!("{v}"));
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{}",
            f.table,
            f.measure.csv_name(),
            f.method.name(),
            f.basis.name(),
            f.paper,
            f.ours.len(),
            num(f.ours.first()),
            f.median(),
            num(f.ours.last()),
            pos,
            pct,
            f.ratio(),
            f.near_median()
        );
    }
    s.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::paper::TABLES;
    use crate::testutil::fake_row;

    fn cell(paper: f64, ours: &[f64]) -> Fidelity {
        let mut v = ours.to_vec();
        v.sort_by(f64::total_cmp);
        Fidelity {
            table: 2,
            measure: Measure::Lambda,
            method: MethodId::Ccvt2,
            basis: Basis::Sampled,
            paper,
            half_unit: 0.0,
            ours: v,
        }
    }

    #[test]
    fn a_printed_number_is_in_range_where_any_value_it_rounds_to_is() {
        // Printed "1.00" at ×10: 0.100 ± 0.0005.
        let c = |ours: &[f64]| Fidelity {
            half_unit: 0.0005,
            ..cell(0.1, ours)
        };
        assert!(c(&[0.1004]).in_range());
        assert!(c(&[0.0996, 0.0997]).in_range());
        assert_eq!(c(&[0.1006]).position(), Some(Position::Below));
        assert_eq!(c(&[0.0994]).position(), Some(Position::Above));
        let tables = PaperTables::embedded().unwrap();
        let lambda = tables.cell(1, Measure::Lambda, MethodId::Triangle).unwrap();
        // Table 1 prints λ × 10² = 0.38.
        assert!((lambda.half_unit(Measure::Lambda) - 0.5e-4).abs() < 1e-18);
        let k = tables.cell(1, Measure::K, MethodId::Triangle).unwrap();
        assert_eq!(k.half_unit(Measure::K), 0.5);
    }

    #[test]
    fn positions_percentiles_and_nearness() {
        let c = cell(2.0, &[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(c.position(), Some(Position::Within(37.5)));
        assert_eq!(c.median(), 2.5);
        assert!(c.in_range() && c.near_median());
        assert_eq!(c.label(), "p38");
        let c = cell(0.5, &[1.0, 2.0, 3.0]);
        assert_eq!(c.position(), Some(Position::Below));
        assert_eq!(c.label(), "below ×0.25");
        assert!(!c.near_median());
        let c = cell(3.9, &[3.0]);
        assert_eq!(c.position(), Some(Position::Above));
        assert!(c.near_median());
        // One value: only an equal number is in range, at the 50th percentile.
        assert_eq!(cell(3.0, &[3.0]).position(), Some(Position::Within(50.0)));
        assert_eq!(cell(3.0, &[]).position(), None);
        assert_eq!(cell(3.0, &[]).label(), "—");
    }

    #[test]
    fn compare_covers_every_printed_number_of_the_methods_run() {
        let paper = PaperTables::embedded().unwrap();
        let rows: Vec<Row> = (1..=3)
            .map(|s| fake_row("circle", 88, MethodId::Ccvt2, s, Kind::Sampled, s as f64))
            .collect();
        let t = [&TABLES[1]];
        let f = compare(&rows, &paper, &t, Basis::Sampled);
        assert_eq!(f.len(), 14);
        assert!(f
            .iter()
            .all(|c| c.ours.len() == 3 && c.method == MethodId::Ccvt2));
        assert!(compare(&rows, &paper, &t, Basis::Exact).is_empty());
        let md = render_fidelity(&f, &f, &[], &t, &paper, "seeds 1–3");
        // Only β (paper 0.48 against 0.42, 0.52, 0.61) falls in the fake range.
        assert!(md.contains("| CCVT(2) | 1/12 (8 %) |"), "{md}");
        assert!(md.contains("### Table 2."));
        let csv = String::from_utf8(fidelity_csv(&f)).unwrap();
        assert_eq!(csv.lines().count(), 15);
        // At the paper's scale the circle's τ is a quarter and d a sixteenth of the exact value.
        let exact: Vec<Row> = (1..=3)
            .map(|s| fake_row("circle", 88, MethodId::Ccvt2, s, Kind::Exact, s as f64))
            .collect();
        let e = compare(&exact, &paper, &t, Basis::Exact);
        let p = compare(&exact, &paper, &t, Basis::ExactPaperScale);
        assert_eq!((e.len(), p.len()), (14, 14));
        for (a, b) in e.iter().zip(&p) {
            let want = match a.measure {
                Measure::Tau => 0.25,
                Measure::D => 1.0 / 16.0,
                _ => 1.0,
            };
            assert_eq!(b.median(), a.median() * want, "{:?}", a.measure);
        }
    }
}
