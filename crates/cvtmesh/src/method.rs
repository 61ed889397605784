//! The methods by name: one list that the command line, the study and the Python package share.
use crate::{MeshError, MeshRequest, MeshResult, Mesher, Region};
use std::fmt;
use std::str::FromStr;

/// A mesh generator, by the name it has on the command line and in the study's CSV.
///
/// ```
/// use cvtmesh::Method;
///
/// let m: Method = "ccvt2".parse()?;
/// assert_eq!(m, Method::Ccvt2);
/// assert_eq!(m.to_string(), "ccvt2");
/// assert_eq!("triangle".parse::<Method>()?, Method::Refine); // an alias
/// assert_eq!(Method::default(), Method::Ccvt);
/// assert!("lloyd".parse::<Method>().unwrap_err().to_string().contains("ccvt-anderson"));
/// # Ok::<(), cvtmesh::UnknownMethod>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Method {
    /// Algorithm 2 with Newton's method on the CVT energy ([`Ccvt::fast`](crate::Ccvt::fast)):
    /// the default.
    #[default]
    Ccvt,
    /// Algorithm 2 with Anderson acceleration ([`Ccvt::anderson`](crate::Ccvt::anderson)).
    CcvtAnderson,
    /// The paper's Algorithm 2 with Lloyd iteration ([`Ccvt::algorithm2`](crate::Ccvt::algorithm2)).
    Ccvt2,
    /// The paper's Algorithm 1 with Lloyd iteration ([`Ccvt::algorithm1`](crate::Ccvt::algorithm1)).
    Ccvt1,
    /// Persson and Strang's truss iteration ([`DistMesh`](crate::DistMesh)).
    Distmesh,
    /// Vertices to the centroids of their mixed Voronoi regions ([`Meshgen`](crate::Meshgen)).
    Meshgen,
    /// Optimal Delaunay triangulation fixed point ([`Vtm`](crate::Vtm)).
    Vtm,
    /// Constrained Delaunay refinement, as Triangle does it ([`Refine`](crate::Refine)).
    Refine,
}

impl Method {
    /// Every method, the default first.
    pub const ALL: [Method; 8] = [
        Method::Ccvt,
        Method::CcvtAnderson,
        Method::Ccvt2,
        Method::Ccvt1,
        Method::Distmesh,
        Method::Meshgen,
        Method::Vtm,
        Method::Refine,
    ];

    /// The name on the command line, in the study's CSV and in [`Mesher::name`].
    pub fn name(self) -> &'static str {
        match self {
            Method::Ccvt => "ccvt",
            Method::CcvtAnderson => "ccvt-anderson",
            Method::Ccvt2 => "ccvt2",
            Method::Ccvt1 => "ccvt1",
            Method::Distmesh => "distmesh",
            Method::Meshgen => "meshgen",
            Method::Vtm => "vtm",
            Method::Refine => "refine",
        }
    }

    /// Other names accepted by [`FromStr`]: `ccvt-fast` for `ccvt`, `triangle` for `refine`.
    pub fn aliases(self) -> &'static [&'static str] {
        match self {
            Method::Ccvt => &["ccvt-fast"],
            Method::Refine => &["triangle"],
            _ => &[],
        }
    }

    /// The mesher with its default settings.
    pub fn mesher(self) -> Box<dyn Mesher> {
        match self {
            Method::Ccvt => Box::new(crate::Ccvt::fast()),
            Method::CcvtAnderson => Box::new(crate::Ccvt::anderson()),
            Method::Ccvt2 => Box::new(crate::Ccvt::algorithm2()),
            Method::Ccvt1 => Box::new(crate::Ccvt::algorithm1()),
            Method::Distmesh => Box::new(crate::DistMesh::default()),
            Method::Meshgen => Box::new(crate::Meshgen),
            Method::Vtm => Box::new(crate::Vtm::default()),
            Method::Refine => Box::new(crate::Refine::default()),
        }
    }

    /// Mesh `region` as `request` asks, with this method's default settings and no progress
    /// reports; a region of several parts has each part meshed with its share of K and the
    /// meshes merged ([`Mesher::mesh_parts`]).
    pub fn run(self, region: &Region, request: &MeshRequest) -> Result<MeshResult, MeshError> {
        self.mesher().mesh_parts(region, request, &mut |_| {})
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A method name that is not one of [`Method::ALL`]'s names or aliases.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownMethod(pub String);

impl fmt::Display for UnknownMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        write!(
            f,
            "unknown method '{}'; choose one of: {}",
            self.0,
            names.join(", ")
        )
    }
}

impl std::error::Error for UnknownMethod {}

impl FromStr for Method {
    type Err = UnknownMethod;

    /// A name or alias, ignoring case and surrounding white space.
    fn from_str(s: &str) -> Result<Method, UnknownMethod> {
        let n = s.trim().to_ascii_lowercase();
        Method::ALL
            .into_iter()
            .find(|m| m.name() == n || m.aliases().contains(&n.as_str()))
            .ok_or_else(|| UnknownMethod(s.trim().to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_match_the_meshers() {
        for m in Method::ALL {
            assert_eq!(m.to_string().parse::<Method>(), Ok(m));
            assert_eq!(m.name().to_uppercase().parse::<Method>(), Ok(m));
            assert_eq!(m.mesher().name(), m.name());
            for a in m.aliases() {
                assert_eq!(a.parse::<Method>(), Ok(m));
            }
        }
    }

    #[test]
    fn unknown_names_are_refused_with_the_valid_ones() {
        let e = " lloyd ".parse::<Method>().unwrap_err();
        assert_eq!(e, UnknownMethod("lloyd".into()));
        let text = e.to_string();
        for m in Method::ALL {
            assert!(text.contains(m.name()), "{text}");
        }
        assert!("".parse::<Method>().is_err());
    }
}
