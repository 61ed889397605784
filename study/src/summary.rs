//! `summary.md`: the best method per (region, measure) and the paper's "keeping score"
//! count (Section 4.1), for our numbers and the paper's side by side.
use crate::paper::{untrustworthy, PaperTables, TableSpec};
use crate::record::{Failure, Kind, Row};
use crate::significance::{cell_samples, test_cell, CellTest, ALPHA};
use crate::stats::Aggregate;
use crate::tables::{describe_seeds, failed_runs};
use crate::{Measure, MethodId};
use std::collections::BTreeMap;
use std::fmt::Write;

/// The methods with the lowest value (all of them on an exact tie); empty if none has a
/// finite value.
pub fn winners(values: &[(MethodId, f64)]) -> Vec<MethodId> {
    let best = values
        .iter()
        .map(|v| v.1)
        .filter(|v| v.is_finite())
        .fold(f64::INFINITY, f64::min);
    if !best.is_finite() {
        return Vec::new();
    }
    values.iter().filter(|v| v.1 == best).map(|v| v.0).collect()
}

/// Which source a score counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Source {
    Exact,
    Sampled,
    Paper,
}

/// Win counts per method, over the (table, measure) pairs scored.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Score {
    /// Wins per method (ties count for every tied method).
    pub wins: BTreeMap<MethodId, usize>,
    /// Number of (table, measure) pairs scored.
    pub pairs: usize,
}

fn values_for(
    agg: &Aggregate,
    paper: &PaperTables,
    t: &TableSpec,
    m: Measure,
    methods: &[MethodId],
    src: Source,
) -> Vec<(MethodId, f64)> {
    methods
        .iter()
        .filter_map(|&method| {
            let v = match src {
                Source::Exact => agg
                    .get(t.region, t.k, method, Kind::Exact, m)
                    .map(|s| s.mean),
                Source::Sampled => agg
                    .get(t.region, t.k, method, Kind::Sampled, m)
                    .map(|s| s.mean),
                // The paper is compared at its printed precision: equal printed numbers tie.
                Source::Paper => paper.cell(t.number, m, method).map(|c| c.printed),
            };
            v.map(|v| (method, v))
        })
        .collect()
}

/// Count wins over every (table, quality measure) pair among `methods`, skipping Table 6's γ
/// and h (misprinted in the paper) so that all sources score the same pairs.
fn score(
    agg: &Aggregate,
    paper: &PaperTables,
    tables: &[&TableSpec],
    methods: &[MethodId],
    src: Source,
) -> Score {
    let mut s = Score::default();
    for m in methods {
        s.wins.insert(*m, 0);
    }
    for (t, m) in scored_cells(tables) {
        let w = winners(&values_for(agg, paper, t, m, methods, src));
        if w.is_empty() {
            continue;
        }
        s.pairs += 1;
        for method in w {
            *s.wins.entry(method).or_default() += 1;
        }
    }
    s
}

/// The (table, quality measure) cells that are scored: all but Table 6's γ and h.
fn scored_cells<'a>(
    tables: &'a [&'a TableSpec],
) -> impl Iterator<Item = (&'a TableSpec, Measure)> + 'a {
    tables.iter().flat_map(|t| {
        Measure::QUALITY
            .into_iter()
            .filter(move |&m| !untrustworthy(t.number, m))
            .map(move |m| (*t, m))
    })
}

/// Significant wins per method over the (table, quality measure) cells scored.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SignificantScore {
    /// Cells each method wins significantly (every method of the family listed, 0 if none).
    pub wins: BTreeMap<MethodId, usize>,
    /// Cells without a significant winner.
    pub ties: usize,
    /// Cells scored (two or more methods with values).
    pub cells: usize,
    /// Cells where the Friedman test rejects "all methods alike" at α.
    pub differ: usize,
    /// The test of every cell scored, by (table, measure).
    pub tests: BTreeMap<(u8, Measure), CellTest>,
}

/// Test every (table, quality measure) cell among `methods` on our `kind` of measures, at
/// α = [`ALPHA`], skipping Table 6's γ and h as `score` does so that the counts compare.
pub fn significant_score(
    rows: &[Row],
    tables: &[&TableSpec],
    methods: &[MethodId],
    kind: Kind,
) -> SignificantScore {
    let mut s = SignificantScore::default();
    for m in methods {
        s.wins.insert(*m, 0);
    }
    for (t, m) in scored_cells(tables) {
        let test = test_cell(&cell_samples(rows, t.region, t.k, kind, m, methods), ALPHA);
        if !test.scored() {
            continue;
        }
        s.cells += 1;
        if test.friedman.is_some_and(|f| f.p_value < ALPHA) {
            s.differ += 1;
        }
        match test.winner {
            Some(w) => *s.wins.entry(w).or_default() += 1,
            None => s.ties += 1,
        }
        s.tests.insert((t.number, m), test);
    }
    s
}

/// A cell of the significance grid: "**C2**" for a significant win, "C2 ~ D,MG" for the best
/// by mean and the methods not significantly worse, "C2 ~ all" when none is.
fn significance_cell(t: &CellTest) -> String {
    match (t.winner, t.best) {
        (Some(w), _) => format!("**{}**", w.abbrev()),
        (None, Some(b)) => {
            let others: Vec<MethodId> = t
                .level_with_best
                .iter()
                .copied()
                .filter(|&m| m != b)
                .collect();
            if others.len() + 1 == t.methods.len() {
                format!("{} ~ all", b.abbrev())
            } else {
                format!("{} ~ {}", b.abbrev(), names(&others))
            }
        }
        _ => "—".into(),
    }
}

/// The smallest number of seeds with which a method can win a cell of `k` methods at all:
/// the exact two-sided Wilcoxon p-value is at least 2/2ⁿ and Holm's first step tests it
/// against α / (k(k−1)/2).
pub fn min_seeds_for_a_win(k: usize) -> u32 {
    let pairs = (k * (k.saturating_sub(1)) / 2).max(1) as f64;
    let mut n = 1;
    while 2.0 / 2f64.powi(n as i32) >= ALPHA / pairs {
        n += 1;
    }
    n
}

/// The `csv/significance.csv` of every cell tested: the Friedman test, the best method, the
/// winner (if any) and each other method's Holm-adjusted p-value against the best.
pub fn significance_csv(rows: &[Row], tables: &[&TableSpec], methods: &[MethodId]) -> Vec<u8> {
    let paper_methods: Vec<MethodId> = methods
        .iter()
        .copied()
        .filter(|m| m.paper_key().is_some())
        .collect();
    let mut out = String::from(
        "table,measure,kind,family,seeds,friedman_chi2,friedman_p,best,winner,holm_p_vs_best\n",
    );
    for (kind, kind_name) in [(Kind::Exact, "exact"), (Kind::Sampled, "sampled")] {
        for (family, ms) in [("paper", &paper_methods), ("all", &methods.to_vec())] {
            let s = significant_score(rows, tables, ms, kind);
            for ((table, m), t) in &s.tests {
                let vs: Vec<String> = t
                    .best
                    .map(|b| {
                        t.methods
                            .iter()
                            .filter(|&&o| o != b)
                            .filter_map(|&o| {
                                t.pair(b, o).map(|(_, p)| format!("{}:{p:.3e}", o.abbrev()))
                            })
                            .collect()
                    })
                    .unwrap_or_default();
                let _ = writeln!(
                    out,
                    "{table},{},{kind_name},{family},{},{},{},{},{},{}",
                    m.csv_name(),
                    t.seeds,
                    t.friedman
                        .map_or(String::new(), |f| format!("{}", f.statistic)),
                    t.friedman
                        .map_or(String::new(), |f| format!("{:e}", f.p_value)),
                    t.best.map_or("", |b| b.name()),
                    t.winner.map_or("", |b| b.name()),
                    vs.join(";")
                );
            }
        }
    }
    out.into_bytes()
}

fn names(ms: &[MethodId]) -> String {
    if ms.is_empty() {
        "—".into()
    } else {
        ms.iter().map(|m| m.abbrev()).collect::<Vec<_>>().join(",")
    }
}

fn significance_section(
    out: &mut String,
    rows: &[Row],
    tables: &[&TableSpec],
    methods: &[MethodId],
    paper_methods: &[MethodId],
) {
    let se = significant_score(rows, tables, paper_methods, Kind::Exact);
    let ss = significant_score(rows, tables, paper_methods, Kind::Sampled);
    let sf = significant_score(rows, tables, methods, Kind::Exact);
    let seeds = se.tests.values().map(|t| t.seeds).min().unwrap_or(0);
    out.push_str("## Keeping score with significance (α = 0.05)\n\n");
    let _ = writeln!(
        out,
        "A method wins a (table, measure) cell only if it has the lowest mean over the seeds, a \
         Friedman test across the methods (seeds as blocks) rejects \"all alike\" at α = 0.05, and \
         two-sided Wilcoxon signed-rank tests paired by seed, Holm-corrected over all the cell's \
         pairs, put it significantly below every other method; otherwise the cell is a tie. \
         Paired seeds per cell: at least {seeds}. With the paper's six methods a win needs at \
         least {} seeds, with seven {}. Per-cell tests: `csv/significance.csv`.\n",
        min_seeds_for_a_win(paper_methods.len()),
        min_seeds_for_a_win(methods.len())
    );
    out.push_str("| method | ours, exact | ours, sampled | ours, exact, with CCVT-fast |\n| :--- | ---: | ---: | ---: |\n");
    let wins = |s: &SignificantScore, m: MethodId| {
        s.wins.get(&m).map_or("—".to_string(), |w| w.to_string())
    };
    for &m in methods {
        let paper_col = |s: &SignificantScore| {
            if m.paper_key().is_some() {
                wins(s, m)
            } else {
                "—".to_string()
            }
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} |",
            m.column(),
            paper_col(&se),
            paper_col(&ss),
            wins(&sf, m)
        );
    }
    let _ = writeln!(
        out,
        "| ties (no significant winner) | {} | {} | {} |\n| (cells scored) | {} | {} | {} |\n",
        se.ties, ss.ties, sf.ties, se.cells, ss.cells, sf.cells
    );
    // The paper's claim excepts TRIANGLE: test the other five on their own too.
    let five: Vec<MethodId> = paper_methods
        .iter()
        .copied()
        .filter(|&m| m != MethodId::Triangle)
        .collect();
    let s5e = significant_score(rows, tables, &five, Kind::Exact);
    let s5s = significant_score(rows, tables, &five, Kind::Sampled);
    out.push_str(
        "\"The differences between the performance of the methods (with again the TRIANGLE \
         algorithm being a possible exception) are statistically insignificant\" (Section 4.1), \
         tested: cells where the Friedman test rejects \"all methods alike\" at α = 0.05, and \
         cells with a significant winner.\n\n\
         | methods | Friedman rejects, exact | significant winner, exact | Friedman rejects, sampled | significant winner, sampled |\n\
         | :--- | ---: | ---: | ---: | ---: |\n",
    );
    for (name, e, s) in [
        ("the paper's six", &se, &ss),
        ("the five without TRIANGLE", &s5e, &s5s),
    ] {
        let _ = writeln!(
            out,
            "| {name} | {}/{} | {}/{} | {}/{} | {}/{} |",
            e.differ,
            e.cells,
            e.cells - e.ties,
            e.cells,
            s.differ,
            s.cells,
            s.cells - s.ties,
            s.cells
        );
    }
    out.push('\n');
    out.push_str(
        "### Per table and measure\n\nEach cell: ours exact / ours sampled, the paper's six methods. \
         **X**: X wins significantly; X ~ Y,Z: X has the lowest mean but Y and Z are not \
         significantly worse (a tie); X ~ all: no method is significantly worse than X; ?: not \
         scored (the paper misprints Table 6's γ and h).\n\n",
    );
    out.push_str("| table |");
    for m in Measure::QUALITY {
        let _ = write!(out, " {} |", m.symbol());
    }
    out.push_str("\n| :--- |");
    for _ in Measure::QUALITY {
        out.push_str(" :---: |");
    }
    out.push('\n');
    for t in tables {
        let _ = write!(out, "| {} {} K={} |", t.number, t.region, t.k);
        for m in Measure::QUALITY {
            let cell = |s: &SignificantScore| {
                s.tests
                    .get(&(t.number, m))
                    .map_or("—".to_string(), significance_cell)
            };
            if untrustworthy(t.number, m) {
                out.push_str(" ? |");
            } else {
                let _ = write!(out, " {} / {} |", cell(&se), cell(&ss));
            }
        }
        out.push('\n');
    }
    out.push('\n');
}

/// The Markdown of `summary.md`. `tables` are the tables that have rows; `methods` the
/// columns run.
pub fn render_summary(
    rows: &[Row],
    paper: &PaperTables,
    tables: &[&TableSpec],
    methods: &[MethodId],
    failures: &[Failure],
) -> String {
    let agg = Aggregate::from_rows(rows);
    let paper_methods: Vec<MethodId> = methods
        .iter()
        .copied()
        .filter(|m| m.paper_key().is_some())
        .collect();
    let mut out = String::new();
    out.push_str("# Summary: which method is best\n\n");
    let _ = writeln!(
        out,
        "Tables: {}. Methods: {}. Ours: {}. Lower is better for all twelve measures.\n",
        tables
            .iter()
            .map(|t| t.number.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        methods
            .iter()
            .map(|m| m.column())
            .collect::<Vec<_>>()
            .join(", "),
        describe_seeds(&agg.all_seeds())
    );
    out.push_str("Legend: ");
    out.push_str(
        &MethodId::ALL
            .iter()
            .map(|m| format!("{} = {}", m.abbrev(), m.column()))
            .collect::<Vec<_>>()
            .join(", "),
    );
    out.push_str(".\n\n");

    let n_seeds = agg.all_seeds().len();
    if n_seeds >= 2 {
        significance_section(&mut out, rows, tables, methods, &paper_methods);
    } else {
        let _ = writeln!(
            out,
            "## Keeping score with significance\n\nOne seed: nothing here can be tested. Run \
             `study --seeds 10` or more (with the paper's six methods a significant win needs at \
             least {} seeds) for Friedman and Holm-corrected Wilcoxon tests over seeds.\n",
            min_seeds_for_a_win(paper_methods.len().max(2))
        );
    }

    out.push_str("## Keeping score by mean (Section 4.1)\n\n");
    out.push_str(
        "\"If one were to keep score of which method is best for each domain and for each quality \
         measure, one finds that DISTMESH and the second CCVT algorithm do 'best', with the latter \
         being slightly 'better'.\" A win is the lowest value of one measure in one table (ties \
         count for every tied method; the paper is compared at its printed precision, ours at \
         full precision). The paper's six methods only; Table 6's γ and h are left out because \
         the paper misprints them.\n\n",
    );
    let se = score(&agg, paper, tables, &paper_methods, Source::Exact);
    let ss = score(&agg, paper, tables, &paper_methods, Source::Sampled);
    let sp = score(&agg, paper, tables, &paper_methods, Source::Paper);
    let sf = score(&agg, paper, tables, methods, Source::Exact);
    out.push_str("| method | ours, exact | ours, sampled | paper | ours, exact, with CCVT-fast |\n| :--- | ---: | ---: | ---: | ---: |\n");
    let wins = |s: &Score, m: MethodId| s.wins.get(&m).map_or("—".to_string(), |w| w.to_string());
    for &m in methods {
        let paper_col = |s: &Score| {
            if m.paper_key().is_some() {
                wins(s, m)
            } else {
                "—".to_string()
            }
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} |",
            m.column(),
            paper_col(&se),
            paper_col(&ss),
            paper_col(&sp),
            wins(&sf, m)
        );
    }
    let _ = writeln!(
        out,
        "| (pairs scored) | {} | {} | {} | {} |\n",
        se.pairs, ss.pairs, sp.pairs, sf.pairs
    );

    out.push_str("## Best method per table and measure\n\n");
    out.push_str(
        "Each cell: ours (exact) / ours (sampled) / paper, among the paper's six methods.\n\n",
    );
    out.push_str("| table |");
    for m in Measure::QUALITY {
        let _ = write!(out, " {} |", m.symbol());
    }
    out.push_str("\n| :--- |");
    for _ in Measure::QUALITY {
        out.push_str(" :---: |");
    }
    out.push('\n');
    for t in tables {
        let _ = write!(out, "| {} {} K={} |", t.number, t.region, t.k);
        for m in Measure::QUALITY {
            let e = winners(&values_for(
                &agg,
                paper,
                t,
                m,
                &paper_methods,
                Source::Exact,
            ));
            let s = winners(&values_for(
                &agg,
                paper,
                t,
                m,
                &paper_methods,
                Source::Sampled,
            ));
            let p = if untrustworthy(t.number, m) {
                "?".to_string()
            } else {
                names(&winners(&values_for(
                    &agg,
                    paper,
                    t,
                    m,
                    &paper_methods,
                    Source::Paper,
                )))
            };
            let _ = write!(out, " {} / {} / {} |", names(&e), names(&s), p);
        }
        out.push('\n');
    }
    out.push('\n');

    let unconverged: Vec<&Row> = rows
        .iter()
        .filter(|r| r.kind == Kind::Exact && !r.converged)
        .collect();
    out.push_str("## Convergence\n\n");
    if unconverged.is_empty() {
        out.push_str("Every run met its method's convergence criterion.\n");
    } else {
        out.push_str(
            "Runs that stopped at the iteration cap (their meshes are still measured):\n\n",
        );
        for r in unconverged {
            let _ = writeln!(
                out,
                "- {} K={} {} seed {} ({} iterations)",
                r.region, r.K_requested, r.method, r.seed, r.iterations
            );
        }
    }
    failed_runs(&mut out, failures, |f| {
        format!(
            "{} K={} {} seed {}",
            f.region, f.K_requested, f.method, f.seed
        )
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::paper::TABLES;
    use crate::testutil::fake_row;

    #[test]
    fn winners_handle_ties_and_non_finite_values() {
        use MethodId::*;
        assert_eq!(
            winners(&[(Distmesh, 0.3), (Ccvt2, 0.2), (Vtm, 0.2)]),
            vec![Ccvt2, Vtm]
        );
        assert_eq!(winners(&[(Distmesh, f64::NAN), (Ccvt2, 0.5)]), vec![Ccvt2]);
        assert!(winners(&[(Distmesh, f64::INFINITY)]).is_empty());
        assert!(winners(&[]).is_empty());
    }

    #[test]
    fn paper_score_matches_the_printed_tables() {
        // With all twelve tables the paper's own numbers must make CCVT(2) the winner,
        // DISTMESH second, as Section 4.1 says.
        let paper = PaperTables::embedded().unwrap();
        let tables: Vec<&TableSpec> = TABLES.iter().collect();
        let methods: Vec<MethodId> = MethodId::ALL[..6].to_vec();
        let s = score(
            &Aggregate::default(),
            &paper,
            &tables,
            &methods,
            Source::Paper,
        );
        assert_eq!(s.pairs, 12 * 12 - 2);
        let mut ranked: Vec<(usize, MethodId)> = s.wins.iter().map(|(m, w)| (*w, *m)).collect();
        ranked.sort_by(|a, b| b.cmp(a));
        assert_eq!(ranked[0].1, MethodId::Ccvt2, "{ranked:?}");
        assert_eq!(ranked[1].1, MethodId::Distmesh, "{ranked:?}");
    }

    #[test]
    fn our_score_counts_lowest_means() {
        let paper = PaperTables::embedded().unwrap();
        // fake_row values grow with x: DISTMESH (x = 0) wins every measure.
        let rows = vec![
            fake_row("circle", 19, MethodId::Distmesh, 1, Kind::Exact, 0.0),
            fake_row("circle", 19, MethodId::Ccvt2, 1, Kind::Exact, 1.0),
            fake_row("circle", 19, MethodId::CcvtFast, 1, Kind::Exact, -1.0),
        ];
        let agg = Aggregate::from_rows(&rows);
        let t = [&TABLES[0]];
        let s = score(
            &agg,
            &paper,
            &t,
            &[MethodId::Distmesh, MethodId::Ccvt2],
            Source::Exact,
        );
        assert_eq!(s.pairs, 12);
        assert_eq!(s.wins[&MethodId::Distmesh], 12);
        assert_eq!(s.wins[&MethodId::Ccvt2], 0);
        let md = render_summary(
            &rows,
            &paper,
            &t,
            &[MethodId::Distmesh, MethodId::Ccvt2, MethodId::CcvtFast],
            &[],
        );
        assert!(md.contains("| DISTMESH | 12 | 0 |"), "{md}");
        assert!(md.contains("| CCVT-fast | — | — | — | 12 |"), "{md}");
        assert!(md.contains("| 1 circle K=19 | D / — /"), "{md}");
    }

    #[test]
    fn report_declares_a_significant_win_and_ties() {
        use MethodId::*;
        let paper = PaperTables::embedded().unwrap();
        let t = [&TABLES[0]];
        let methods = [Distmesh, Vtm, Ccvt2];
        let rows_with = |x: fn(MethodId) -> f64| -> Vec<Row> {
            (1..=8u64)
                .flat_map(|s| {
                    methods.map(|m| {
                        let noise = ((s * 37) % 11) as f64 * 0.01;
                        fake_row("circle", 19, m, s, Kind::Exact, x(m) + noise)
                    })
                })
                .collect()
        };
        // CCVT(2) below the other two in every measure and all 8 seeds: raw p = 2/2⁸ for each
        // pair, under Holm's 0.05/3 for three pairs: a significant win in each of 12 cells.
        let better = rows_with(|m| if m == Ccvt2 { 0.0 } else { 1.0 });
        let md = render_summary(&better, &paper, &t, &methods, &[]);
        assert!(md.contains("| CCVT(2) | 12 | 0 | 12 |"), "{md}");
        assert!(md.contains("| DISTMESH | 0 | 0 | 0 |"), "{md}");
        assert!(
            md.contains("| ties (no significant winner) | 0 | 0 | 0 |"),
            "{md}"
        );
        assert!(md.contains("| 1 circle K=19 | **C2** / — |"), "{md}");
        // Three identical methods: every cell is a tie.
        let same = rows_with(|_| 1.0);
        let md = render_summary(&same, &paper, &t, &methods, &[]);
        assert!(md.contains("| CCVT(2) | 0 | 0 | 0 |"), "{md}");
        assert!(
            md.contains("| ties (no significant winner) | 12 | 0 | 12 |"),
            "{md}"
        );
        assert!(md.contains("| 1 circle K=19 | D ~ all / — |"), "{md}");
        // One seed: no test, and the summary says how many seeds a win needs.
        let one: Vec<Row> = better.into_iter().filter(|r| r.seed == 1).collect();
        let md = render_summary(&one, &paper, &t, &methods, &[]);
        assert!(md.contains("One seed: nothing here can be tested"), "{md}");
        assert_eq!(min_seeds_for_a_win(6), 10);
        assert_eq!(min_seeds_for_a_win(3), 7);
        assert_eq!(min_seeds_for_a_win(2), 6);
    }
}
