//! The compared methods: the paper's six columns plus our accelerated CCVT.
use crate::StudyError;
use mesh::Mesher;

/// One column of the tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum MethodId {
    /// TRIANGLE in the paper; here our Delaunay refinement (crate `refine`).
    Triangle,
    /// DISTMESH (crate `distmesh`).
    Distmesh,
    /// MESHGEN (crate `meshgen`).
    Meshgen,
    /// VTM, variational tetrahedral meshing in 2-D (crate `vtm`).
    Vtm,
    /// CCVT Algorithm 1 (crate `ccvt`).
    Ccvt1,
    /// CCVT Algorithm 2 (crate `ccvt`).
    Ccvt2,
    /// Algorithm 2 with Newton's method and lattice start: not in the paper.
    CcvtFast,
}

impl MethodId {
    /// Every method in column order (the paper's order, then ours).
    pub const ALL: [MethodId; 7] = [
        MethodId::Triangle,
        MethodId::Distmesh,
        MethodId::Meshgen,
        MethodId::Vtm,
        MethodId::Ccvt1,
        MethodId::Ccvt2,
        MethodId::CcvtFast,
    ];

    /// The name on the command line and in the CSV (the mesher's own name).
    pub fn name(self) -> &'static str {
        match self {
            MethodId::Triangle => "refine",
            MethodId::Distmesh => "distmesh",
            MethodId::Meshgen => "meshgen",
            MethodId::Vtm => "vtm",
            MethodId::Ccvt1 => "ccvt1",
            MethodId::Ccvt2 => "ccvt2",
            MethodId::CcvtFast => "ccvt-fast",
        }
    }

    /// Column header in the tables and panel titles in the figures.
    pub fn column(self) -> &'static str {
        match self {
            MethodId::Triangle => "TRIANGLE",
            MethodId::Distmesh => "DISTMESH",
            MethodId::Meshgen => "MESHGEN",
            MethodId::Vtm => "VTM",
            MethodId::Ccvt1 => "CCVT(1)",
            MethodId::Ccvt2 => "CCVT(2)",
            MethodId::CcvtFast => "CCVT-fast",
        }
    }

    /// Short label for dense summary tables.
    pub fn abbrev(self) -> &'static str {
        match self {
            MethodId::Triangle => "T",
            MethodId::Distmesh => "D",
            MethodId::Meshgen => "MG",
            MethodId::Vtm => "V",
            MethodId::Ccvt1 => "C1",
            MethodId::Ccvt2 => "C2",
            MethodId::CcvtFast => "CF",
        }
    }

    /// The method's name in `paper_tables.csv`, or `None` if the paper did not run it.
    pub fn paper_key(self) -> Option<&'static str> {
        match self {
            MethodId::Triangle => Some("TRIANGLE"),
            MethodId::Distmesh => Some("DISTMESH"),
            MethodId::Meshgen => Some("MESHGEN"),
            MethodId::Vtm => Some("VTM"),
            MethodId::Ccvt1 => Some("CCVT1"),
            MethodId::Ccvt2 => Some("CCVT2"),
            MethodId::CcvtFast => None,
        }
    }

    /// Parse a command-line or CSV name, case-insensitively; `triangle` is accepted for
    /// `refine`, and the paper's column names (`CCVT1`, `CCVT(2)`, …) are accepted too.
    pub fn parse(name: &str) -> Option<MethodId> {
        let n = name.trim().to_ascii_lowercase();
        let n = n.replace(['(', ')'], "");
        let n = if n == "triangle" {
            "refine".to_string()
        } else {
            n
        };
        MethodId::ALL
            .into_iter()
            .find(|m| m.name() == n || m.column().to_ascii_lowercase().replace(['(', ')'], "") == n)
    }

    /// Parse a comma-separated list, keeping column order and dropping repeats.
    pub fn parse_list(list: &str) -> Result<Vec<MethodId>, StudyError> {
        let mut chosen = Vec::new();
        for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let m = MethodId::parse(name).ok_or_else(|| StudyError::UnknownMethod {
                name: name.to_string(),
                valid: Self::valid_names(),
            })?;
            chosen.push(m);
        }
        if chosen.is_empty() {
            return Err(StudyError::BadOption(format!(
                "--methods is empty; valid methods: {}",
                Self::valid_names()
            )));
        }
        chosen.sort();
        chosen.dedup();
        Ok(chosen)
    }

    /// The valid names, comma-separated, for error messages.
    pub fn valid_names() -> String {
        let mut names: Vec<&str> = MethodId::ALL.iter().map(|m| m.name()).collect();
        names.push("triangle (= refine)");
        names.join(", ")
    }

    /// The mesher with the settings used in the study (each crate's defaults).
    pub fn mesher(self) -> Box<dyn Mesher> {
        match self {
            MethodId::Triangle => Box::new(refine::Refine::default()),
            MethodId::Distmesh => Box::new(distmesh::DistMesh::default()),
            MethodId::Meshgen => Box::new(meshgen::Meshgen),
            MethodId::Vtm => Box::new(vtm::Vtm),
            MethodId::Ccvt1 => Box::new(ccvt::Ccvt::algorithm1()),
            MethodId::Ccvt2 => Box::new(ccvt::Ccvt::algorithm2()),
            MethodId::CcvtFast => Box::new(ccvt::Ccvt::fast()),
        }
    }

    /// A rough relative cost, used only to start expensive jobs first.
    pub fn cost_weight(self) -> f64 {
        match self {
            MethodId::Triangle => 0.1,
            MethodId::Distmesh | MethodId::Vtm | MethodId::Meshgen => 1.0,
            MethodId::Ccvt1 | MethodId::CcvtFast => 2.0,
            MethodId::Ccvt2 => 4.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_names_and_aliases() {
        for m in MethodId::ALL {
            assert_eq!(MethodId::parse(m.name()), Some(m));
            assert_eq!(MethodId::parse(m.column()), Some(m));
        }
        assert_eq!(MethodId::parse("TRIANGLE"), Some(MethodId::Triangle));
        assert_eq!(MethodId::parse("CCVT1"), Some(MethodId::Ccvt1));
        assert_eq!(MethodId::parse("ccvt(2)"), Some(MethodId::Ccvt2));
        assert_eq!(MethodId::parse("lloyd"), None);
    }

    #[test]
    fn parse_list_orders_and_reports_unknown_names() {
        let l = MethodId::parse_list("ccvt2, distmesh,ccvt2").unwrap();
        assert_eq!(l, vec![MethodId::Distmesh, MethodId::Ccvt2]);
        let e = MethodId::parse_list("distmesh,nope")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("'nope'") && e.contains("ccvt-fast") && e.contains("refine"),
            "{e}"
        );
        assert!(MethodId::parse_list(" , ").is_err());
    }

    #[test]
    fn names_match_the_meshers() {
        for m in MethodId::ALL {
            assert_eq!(m.mesher().name(), m.name());
        }
    }
}
