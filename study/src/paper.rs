//! The paper's Tables 1–12: which region and K each one is, and its printed numbers
//! (embedded from `data/paper_tables.csv`).
use crate::{Measure, MethodId, StudyError};
use std::collections::BTreeMap;

/// One of the paper's tables: a region at one K.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TableSpec {
    /// Table number, 1..=12.
    pub number: u8,
    /// Built-in region name (`cvtmesh::geometry::Region::builtin`).
    pub region: &'static str,
    /// The K the paper asked for.
    pub k: usize,
    /// The paper's caption after "Grid-quality measures for".
    pub caption: &'static str,
    /// The figure showing this region's meshes.
    pub figure: u8,
}

impl TableSpec {
    /// "Table 2. Grid-quality measures for circle (medium mesh)".
    pub fn title(&self) -> String {
        format!(
            "Table {}. Grid-quality measures for {}",
            self.number, self.caption
        )
    }
}

/// The twelve tables in order.
pub const TABLES: [TableSpec; 12] = [
    TableSpec {
        number: 1,
        region: "circle",
        k: 19,
        caption: "circle (coarsest mesh)",
        figure: 3,
    },
    TableSpec {
        number: 2,
        region: "circle",
        k: 88,
        caption: "circle (medium mesh)",
        figure: 3,
    },
    TableSpec {
        number: 3,
        region: "circle",
        k: 362,
        caption: "circle (finest mesh)",
        figure: 3,
    },
    TableSpec {
        number: 4,
        region: "annulus",
        k: 303,
        caption: "an annulus",
        figure: 4,
    },
    TableSpec {
        number: 5,
        region: "square_hole",
        k: 194,
        caption: "a square with a circular hole",
        figure: 4,
    },
    TableSpec {
        number: 6,
        region: "hex_hole",
        k: 240,
        caption: "a hexagon with a hexagonal hole",
        figure: 4,
    },
    TableSpec {
        number: 7,
        region: "horn",
        k: 138,
        caption: "a \"horn\"-shaped region",
        figure: 5,
    },
    TableSpec {
        number: 8,
        region: "superellipse",
        k: 505,
        caption: "a super-ellipse",
        figure: 5,
    },
    TableSpec {
        number: 9,
        region: "bike_seat",
        k: 136,
        caption: "a \"bike\" seat-shaped region",
        figure: 5,
    },
    TableSpec {
        number: 10,
        region: "pie_hole",
        k: 287,
        caption: "a \"pie slice\"-shaped region with a hole",
        figure: 6,
    },
    TableSpec {
        number: 11,
        region: "square_two_hex",
        k: 203,
        caption: "a square with 2 hexagonal holes",
        figure: 6,
    },
    TableSpec {
        number: 12,
        region: "lake",
        k: 1109,
        caption: "a \"lake\" with an island",
        figure: 7,
    },
];

/// The table for (region, K), if the paper has one.
pub fn table_for(region: &str, k: usize) -> Option<&'static TableSpec> {
    TABLES.iter().find(|t| t.region == region && t.k == k)
}

/// Distinct region names in table order.
pub fn region_names() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    for t in &TABLES {
        if !names.contains(&t.region) {
            names.push(t.region);
        }
    }
    names
}

/// Length scale of the paper-style sampled estimate: the circle and annulus tables match
/// coordinates halved (τ × ¼, d × 1/16), the others scale 1 (see the paper's README).
pub fn sample_scale(region: &str) -> f64 {
    if region == "circle" || region == "annulus" {
        0.5
    } else {
        1.0
    }
}

/// One printed number of the paper.
#[derive(Clone, Debug, PartialEq)]
pub struct PaperCell {
    /// The number as typeset.
    pub printed: f64,
    /// The row's printed ×10ⁿ exponent, as labelled in the paper.
    pub printed_exp: i32,
    /// The exponent the printed numbers really carry (differs from `printed_exp` where the
    /// label is wrong: Table 4 q and Table 9 h print ×10 but are labelled unscaled).
    pub true_exp: i32,
    /// The measure itself: `printed / 10^true_exp`.
    pub value: f64,
}

impl PaperCell {
    /// Half a unit in the last printed digit, at the measure's true scale: the number as
    /// typeset stands for every value that rounds to it, `value ± half_unit`. The paper prints
    /// K and K̃ as integers and every measure with two decimals after its row's ×10ⁿ.
    pub fn half_unit(&self, m: Measure) -> f64 {
        let decimals = match m {
            Measure::K | Measure::Ktilde => 0,
            _ => 2,
        };
        0.5 * 10f64.powi(-decimals - self.true_exp)
    }
}

/// Corrections of known defects in the source text's row labels: (table, measure, extra
/// exponent). Table 4's q and Table 9's h print ten times the measure under an unscaled label.
const LABEL_CORRECTIONS: [(u8, Measure, i32); 2] = [(4, Measure::Q, 1), (9, Measure::H, 1)];

/// Footnotes on the paper's defects, per table.
pub fn defect_notes(table: u8) -> Vec<&'static str> {
    match table {
        2 => vec!["The q row's label is lost in the source text; its values fit an unscaled q, which is assumed."],
        4 => vec!["The paper labels the q row \"q\" but prints q × 10 (its values are 10× those of the other tables); the scale is corrected here."],
        6 => vec!["The paper's γ and h rows print identical numbers, a typesetting error: neither row is a trustworthy reference, so their ratios are marked †."],
        9 => vec!["The paper labels the h row \"h\" but prints h × 10; the scale is corrected here."],
        _ => vec![],
    }
}

/// True where the paper's number is known to be wrong (Table 6, γ and h).
pub fn untrustworthy(table: u8, m: Measure) -> bool {
    table == 6 && matches!(m, Measure::Gamma | Measure::H)
}

/// All printed numbers of Tables 1–12.
#[derive(Clone, Debug, Default)]
pub struct PaperTables {
    cells: BTreeMap<(u8, Measure, MethodId), PaperCell>,
    exps: BTreeMap<(u8, Measure), (i32, i32)>,
}

const EMBEDDED: &str = include_str!("../data/paper_tables.csv");

impl PaperTables {
    /// The tables embedded in the binary.
    pub fn embedded() -> Result<PaperTables, StudyError> {
        Self::parse(EMBEDDED, "embedded paper_tables.csv")
    }

    /// Parse CSV with header `table,domain,paper_K,measure,printed_scale_exp,method,printed,value,note`.
    pub fn parse(text: &str, label: &str) -> Result<PaperTables, StudyError> {
        let err = |line: usize, message: String| StudyError::Csv {
            path: label.to_string(),
            message: format!("record {line}: {message}"),
        };
        let mut rd = csv::Reader::from_reader(text.as_bytes());
        let mut out = PaperTables::default();
        for (i, rec) in rd.records().enumerate() {
            let rec = rec.map_err(|e| err(i + 1, e.to_string()))?;
            let field = |j: usize| rec.get(j).unwrap_or("").trim();
            let table: u8 = field(0)
                .parse()
                .map_err(|_| err(i + 1, format!("bad table '{}'", field(0))))?;
            let spec = TABLES
                .iter()
                .find(|t| t.number == table)
                .ok_or_else(|| err(i + 1, format!("no table {table}")))?;
            if spec.region != field(1) || spec.k.to_string() != field(2) {
                return Err(err(
                    i + 1,
                    format!(
                        "table {table} is {} K={}, not {} K={}",
                        spec.region,
                        spec.k,
                        field(1),
                        field(2)
                    ),
                ));
            }
            let m = Measure::from_csv_name(field(3))
                .ok_or_else(|| err(i + 1, format!("unknown measure '{}'", field(3))))?;
            let printed_exp: i32 = field(4)
                .parse()
                .map_err(|_| err(i + 1, format!("bad exponent '{}'", field(4))))?;
            let method = MethodId::parse(field(5))
                .filter(|m| m.paper_key() == Some(field(5)))
                .ok_or_else(|| err(i + 1, format!("unknown method '{}'", field(5))))?;
            let printed: f64 = field(6)
                .parse()
                .map_err(|_| err(i + 1, format!("bad number '{}'", field(6))))?;
            let extra = LABEL_CORRECTIONS
                .iter()
                .find(|c| c.0 == table && c.1 == m)
                .map_or(0, |c| c.2);
            let true_exp = printed_exp + extra;
            let value = printed / 10f64.powi(true_exp);
            if out
                .cells
                .insert(
                    (table, m, method),
                    PaperCell {
                        printed,
                        printed_exp,
                        true_exp,
                        value,
                    },
                )
                .is_some()
            {
                return Err(err(
                    i + 1,
                    format!(
                        "duplicate entry table {table} {} {}",
                        m.csv_name(),
                        field(5)
                    ),
                ));
            }
            let e = out
                .exps
                .entry((table, m))
                .or_insert((printed_exp, true_exp));
            if *e != (printed_exp, true_exp) {
                return Err(err(
                    i + 1,
                    format!("table {table} row {} has mixed exponents", m.csv_name()),
                ));
            }
        }
        Ok(out)
    }

    /// The paper's number for (table, measure, method), if it ran that method.
    pub fn cell(&self, table: u8, m: Measure, method: MethodId) -> Option<&PaperCell> {
        self.cells.get(&(table, m, method))
    }

    /// (printed, true) exponent of a row; (0, 0) if the row is missing.
    pub fn row_exps(&self, table: u8, m: Measure) -> (i32, i32) {
        self.exps.get(&(table, m)).copied().unwrap_or((0, 0))
    }

    /// Number of printed numbers.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// True if nothing was parsed.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cvtmesh::geometry::Region;

    #[test]
    fn embedded_tables_are_complete() {
        let p = PaperTables::embedded().unwrap();
        assert_eq!(p.len(), 12 * 14 * 6);
        for t in &TABLES {
            for m in Measure::ALL {
                for method in MethodId::ALL {
                    assert_eq!(
                        p.cell(t.number, m, method).is_some(),
                        method.paper_key().is_some()
                    );
                }
            }
        }
        // Spot checks against the typeset Table 2 and the defect corrections.
        let c = p.cell(2, Measure::Lambda, MethodId::Distmesh).unwrap();
        assert_eq!((c.printed, c.printed_exp, c.true_exp), (0.61, 1, 1));
        assert!((c.value - 0.061).abs() < 1e-15);
        assert_eq!(
            p.cell(2, Measure::K, MethodId::Triangle).unwrap().value,
            86.0
        );
        let q4 = p.cell(4, Measure::Q, MethodId::Ccvt2).unwrap();
        assert_eq!((q4.printed_exp, q4.true_exp), (0, 1));
        assert!((q4.value - 0.22).abs() < 1e-15);
        let h9 = p.cell(9, Measure::H, MethodId::Triangle).unwrap();
        assert!((h9.value - 0.64).abs() < 1e-15);
        assert_eq!(p.row_exps(1, Measure::D), (6, 6));
    }

    #[test]
    fn parse_rejects_inconsistent_rows() {
        let head = "table,domain,paper_K,measure,printed_scale_exp,method,printed,value,note\n";
        assert!(
            PaperTables::parse(&format!("{head}2,circle,19,K,0,DISTMESH,1,1,\n"), "t").is_err()
        );
        assert!(
            PaperTables::parse(&format!("{head}2,circle,88,zeta,0,DISTMESH,1,1,\n"), "t").is_err()
        );
        assert!(
            PaperTables::parse(&format!("{head}2,circle,88,K,0,ccvt-fast,1,1,\n"), "t").is_err()
        );
        let dup = format!("{head}2,circle,88,K,0,VTM,1,1,\n2,circle,88,K,0,VTM,1,1,\n");
        assert!(PaperTables::parse(&dup, "t").is_err());
        assert_eq!(
            PaperTables::parse(&format!("{head}2,circle,88,K,0,VTM,88,88,\n"), "t")
                .unwrap()
                .len(),
            1
        );
    }

    #[test]
    fn tables_cover_every_region_once_in_order() {
        assert_eq!(region_names(), Region::builtin_names());
        // Each table is a (region, K) of the regions' files, in the same order.
        let specs: Vec<(&str, usize)> = TABLES.iter().map(|t| (t.region, t.k)).collect();
        assert_eq!(specs, Region::paper_cases().collect::<Vec<_>>());
        assert_eq!(table_for("circle", 88).unwrap().number, 2);
        assert!(table_for("circle", 90).is_none());
        assert_eq!(
            TABLES[1].title(),
            "Table 2. Grid-quality measures for circle (medium mesh)"
        );
    }
}
