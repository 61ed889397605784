//! The fourteen table rows: K, K̃ and the twelve quality measures of Section 3.
use cvtmesh::metrics::Measures;

/// One row of the paper's tables, in table order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Measure {
    /// K, the number of vertices.
    K,
    /// K̃, the number of triangles.
    Ktilde,
    /// λ, the covariance (COV) measure (Section 3.1).
    Lambda,
    /// γ, the mesh ratio (Section 3.1).
    Gamma,
    /// h, the point distribution measure (Section 3.2).
    H,
    /// μ, the point distribution ratio (Section 3.2).
    Mu,
    /// χ, the regularity measure (Section 3.2).
    Chi,
    /// ν, the cell volume deviation (Section 3.2).
    Nu,
    /// τ, the second moment trace measure (Section 3.2).
    Tau,
    /// d, the second moment determinant measure (Section 3.2).
    D,
    /// α, the maximum area measure (Section 3.3).
    Alpha,
    /// β, the minimum angle measure (Section 3.3).
    Beta,
    /// q, the circle ratio measure (Section 3.3).
    Q,
    /// p, the normalized standard deviation measure (Section 3.3).
    P,
}

impl Measure {
    /// All fourteen rows in table order.
    pub const ALL: [Measure; 14] = [
        Measure::K,
        Measure::Ktilde,
        Measure::Lambda,
        Measure::Gamma,
        Measure::H,
        Measure::Mu,
        Measure::Chi,
        Measure::Nu,
        Measure::Tau,
        Measure::D,
        Measure::Alpha,
        Measure::Beta,
        Measure::Q,
        Measure::P,
    ];

    /// The twelve quality measures (every row but K and K̃); for all of them lower is better.
    pub const QUALITY: [Measure; 12] = {
        let mut q = [Measure::Lambda; 12];
        let mut i = 0;
        while i < q.len() {
            q[i] = Measure::ALL[i + 2];
            i += 1;
        }
        q
    };

    /// Position in [`Measure::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// Column name in the CSV files (and in the paper-table data): the metrics crate's name.
    pub fn csv_name(self) -> &'static str {
        Measures::NAMES[self.index()]
    }

    /// The measure with this CSV name.
    pub fn from_csv_name(name: &str) -> Option<Measure> {
        Measure::ALL.into_iter().find(|m| m.csv_name() == name)
    }

    /// The symbol used in the paper's tables.
    pub fn symbol(self) -> &'static str {
        match self {
            Measure::K => "K",
            Measure::Ktilde => "K̃",
            Measure::Lambda => "λ",
            Measure::Gamma => "γ",
            Measure::H => "h",
            Measure::Mu => "μ",
            Measure::Chi => "χ",
            Measure::Nu => "ν",
            Measure::Tau => "τ",
            Measure::D => "d",
            Measure::Alpha => "α",
            Measure::Beta => "β",
            Measure::Q => "q",
            Measure::P => "p",
        }
    }

    /// True for the two counts (K, K̃), printed as integers.
    pub fn is_count(self) -> bool {
        matches!(self, Measure::K | Measure::Ktilde)
    }
}

/// `n` written with Unicode superscript digits (and a superscript minus).
pub fn superscript(n: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::new();
    if n < 0 {
        s.push('⁻');
    }
    for c in n.unsigned_abs().to_string().chars() {
        s.push(DIGITS[c.to_digit(10).unwrap_or(0) as usize]);
    }
    s
}

/// A row label with the paper's scaling: `λ`, `λ × 10`, `d × 10⁷`.
pub fn scaled_label(m: Measure, exp: i32) -> String {
    match exp {
        0 => m.symbol().to_string(),
        1 => format!("{} × 10", m.symbol()),
        e => format!("{} × 10{}", m.symbol(), superscript(e)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_order() {
        for (i, m) in Measure::ALL.into_iter().enumerate() {
            assert_eq!(m.index(), i);
            assert_eq!(Measure::from_csv_name(m.csv_name()), Some(m));
        }
        assert_eq!(Measure::from_csv_name("bogus"), None);
        assert_eq!(Measure::QUALITY.len(), 12);
        assert!(Measure::QUALITY.iter().all(|m| !m.is_count()));
        assert_eq!(
            Measure::QUALITY.to_vec(),
            Measure::ALL
                .into_iter()
                .filter(|m| !m.is_count())
                .collect::<Vec<_>>()
        );
    }

    #[test]
    fn scaled_labels() {
        assert_eq!(scaled_label(Measure::Nu, 0), "ν");
        assert_eq!(scaled_label(Measure::Lambda, 1), "λ × 10");
        assert_eq!(scaled_label(Measure::Lambda, 2), "λ × 10²");
        assert_eq!(scaled_label(Measure::D, 7), "d × 10⁷");
        assert_eq!(scaled_label(Measure::D, 12), "d × 10¹²");
        assert_eq!(scaled_label(Measure::Tau, -3), "τ × 10⁻³");
    }
}
