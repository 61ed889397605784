//! A region written down whole and read back: its loops of pieces, corners, markers, names,
//! embedded points and lines, subdomains and notes, every number by its bits. What Python's
//! `pickle` (and so `multiprocessing`) stores of a region; not a file format for people, who
//! write the JSON, `.poly` or Gmsh files `Region::from_file` reads.
use crate::{DVec2, EmbeddedLine, GeometryError, LoopRole, Piece, Region};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Bumped whenever the layout below changes: an old state is refused, not misread.
const VERSION: u32 = 1;

/// A point by the bits of its coordinates.
type Bits2 = [u64; 2];

fn bits(p: DVec2) -> Bits2 {
    [p.x.to_bits(), p.y.to_bits()]
}

fn point(b: Bits2) -> DVec2 {
    DVec2::new(f64::from_bits(b[0]), f64::from_bits(b[1]))
}

#[derive(Serialize, Deserialize)]
enum PieceState {
    Line(Bits2, Bits2),
    Arc(Bits2, u64, u64, u64),
    Circle(Bits2, u64, bool),
    SuperEllipse(Bits2, u64, u64, u64, bool),
    Chain(Vec<Bits2>),
}

#[derive(Serialize, Deserialize)]
struct State {
    version: u32,
    name: String,
    /// Per loop: whether it is a hole, and its pieces with their markers.
    loops: Vec<(bool, Vec<(PieceState, i64)>)>,
    has_markers: bool,
    corners: Vec<Bits2>,
    corner_threshold: Option<u64>,
    corners_computed: bool,
    marker_names: BTreeMap<i64, String>,
    vertex_markers: Vec<(Bits2, i64)>,
    embedded: Vec<(Bits2, i64)>,
    lines: Vec<(Vec<Bits2>, i64)>,
    subdomains: Vec<(Bits2, i64)>,
    subdomain_names: BTreeMap<i64, String>,
    notes: Vec<String>,
    surface_group: Option<(i64, String)>,
}

fn piece_state(p: &Piece) -> PieceState {
    match p {
        Piece::Line { a, b } => PieceState::Line(bits(*a), bits(*b)),
        Piece::Arc {
            center,
            radius,
            from,
            to,
        } => PieceState::Arc(
            bits(*center),
            radius.to_bits(),
            from.to_bits(),
            to.to_bits(),
        ),
        Piece::Circle {
            center,
            radius,
            ccw,
        } => PieceState::Circle(bits(*center), radius.to_bits(), *ccw),
        Piece::SuperEllipse {
            center,
            a,
            b,
            n,
            ccw,
        } => PieceState::SuperEllipse(bits(*center), a.to_bits(), b.to_bits(), n.to_bits(), *ccw),
        Piece::Chain(pts) => PieceState::Chain(pts.iter().map(|&p| bits(p)).collect()),
    }
}

fn piece(s: PieceState) -> Piece {
    let f = f64::from_bits;
    match s {
        PieceState::Line(a, b) => Piece::Line {
            a: point(a),
            b: point(b),
        },
        PieceState::Arc(center, radius, from, to) => Piece::Arc {
            center: point(center),
            radius: f(radius),
            from: f(from),
            to: f(to),
        },
        PieceState::Circle(center, radius, ccw) => Piece::Circle {
            center: point(center),
            radius: f(radius),
            ccw,
        },
        PieceState::SuperEllipse(center, a, b, n, ccw) => Piece::SuperEllipse {
            center: point(center),
            a: f(a),
            b: f(b),
            n: f(n),
            ccw,
        },
        PieceState::Chain(pts) => Piece::Chain(pts.into_iter().map(point).collect()),
    }
}

/// A region's pieces by loop with their markers, its corners and everything it carries
/// besides: what [`Region::assembled`] builds a region from.
pub(crate) struct Recipe {
    pub name: String,
    pub loops: Vec<(LoopRole, Vec<(Piece, i64)>)>,
    /// Whether the pieces' markers are the region's (else it numbers no walls).
    pub has_markers: bool,
    pub corners: Vec<DVec2>,
    pub corner_threshold: Option<f64>,
    pub corners_computed: bool,
    pub marker_names: BTreeMap<i64, String>,
    pub vertex_markers: Vec<(DVec2, i64)>,
    pub embedded: Vec<(DVec2, i64)>,
    pub lines: Vec<EmbeddedLine>,
    pub subdomains: Vec<(DVec2, i64)>,
    pub subdomain_names: BTreeMap<i64, String>,
    pub notes: Vec<String>,
    pub surface_group: Option<(i64, String)>,
}

impl Region {
    /// Its [`Recipe`], each piece with its marker (0 where the region numbers no walls).
    pub(crate) fn recipe(&self) -> Recipe {
        let loops = self
            .loops
            .iter()
            .map(|lp| {
                let pieces = lp
                    .pieces
                    .iter()
                    .map(|&j| {
                        let m = self.markers.get(j).copied().unwrap_or(0);
                        (self.pieces[j].clone(), m)
                    })
                    .collect();
                (lp.role, pieces)
            })
            .collect();
        Recipe {
            name: self.name.clone(),
            loops,
            has_markers: !self.markers.is_empty(),
            corners: self.corners.iter().map(|c| c.pos).collect(),
            corner_threshold: self.corner_threshold,
            corners_computed: self.corners_computed,
            marker_names: self.marker_names.clone(),
            vertex_markers: self.vertex_markers.clone(),
            embedded: self.embedded.clone(),
            lines: self.lines.clone(),
            subdomains: self.subdomains.clone(),
            subdomain_names: self.subdomain_names.clone(),
            notes: self.notes.clone(),
            surface_group: self.surface_group.clone(),
        }
    }

    /// The region of `recipe`: its loops built and checked as any region's, its corners where
    /// `recipe` lists them, each piece keeping its marker (found by its ends: the build may
    /// start a loop at another piece).
    pub(crate) fn assembled(recipe: Recipe) -> Result<Region, GeometryError> {
        let ends = |p: &Piece| {
            let b = |q: DVec2| (q.x.to_bits(), q.y.to_bits());
            (b(p.start()), b(p.end()))
        };
        let mut marker_by_ends = std::collections::HashMap::new();
        let loops: Vec<(Option<LoopRole>, Vec<Piece>)> = recipe
            .loops
            .into_iter()
            .map(|(role, pieces)| {
                let pieces = pieces
                    .into_iter()
                    .map(|(p, m)| {
                        marker_by_ends.insert(ends(&p), m);
                        p
                    })
                    .collect();
                (Some(role), pieces)
            })
            .collect();
        let mut r = crate::build::new_region(&recipe.name, loops, Some(recipe.corners))?;
        if recipe.has_markers {
            r.markers = r
                .pieces
                .iter()
                .map(|p| marker_by_ends.get(&ends(p)).copied().unwrap_or(0))
                .collect();
        }
        r.corner_threshold = recipe.corner_threshold;
        r.corners_computed = recipe.corners_computed;
        r.marker_names = recipe.marker_names;
        r.vertex_markers = recipe.vertex_markers;
        r.embedded = recipe.embedded;
        r.lines = recipe.lines;
        r.subdomains = recipe.subdomains;
        r.subdomain_names = recipe.subdomain_names;
        r.notes = recipe.notes;
        r.surface_group = recipe.surface_group;
        Ok(r)
    }

    /// The region written down whole, every number by its bits, for [`Region::from_state`]
    /// to read back (Python's `pickle` stores a region so). Not meant to be edited.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, EmbeddedLine, Region};
    /// let crack = EmbeddedLine { points: vec![DVec2::new(0.0, 1.0), DVec2::new(0.0, 0.2)], marker: 4 };
    /// let region = Region::builtin("circle")?.with_embedded_lines([crack])?;
    /// let back = Region::from_state(&region.to_state())?;
    /// assert_eq!(back.to_state(), region.to_state());
    /// assert_eq!(back.embedded_lines(), region.embedded_lines());
    /// assert_eq!(back.area(), region.area());
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn to_state(&self) -> String {
        let p = self.recipe();
        let pts = |v: &[(DVec2, i64)]| v.iter().map(|&(p, m)| (bits(p), m)).collect();
        let state = State {
            version: VERSION,
            name: p.name,
            loops: p
                .loops
                .iter()
                .map(|(role, pieces)| {
                    (
                        *role == LoopRole::Hole,
                        pieces.iter().map(|(q, m)| (piece_state(q), *m)).collect(),
                    )
                })
                .collect(),
            has_markers: p.has_markers,
            corners: p.corners.iter().map(|&c| bits(c)).collect(),
            corner_threshold: p.corner_threshold.map(f64::to_bits),
            corners_computed: p.corners_computed,
            marker_names: p.marker_names,
            vertex_markers: pts(&p.vertex_markers),
            embedded: pts(&p.embedded),
            lines: p
                .lines
                .iter()
                .map(|l| (l.points.iter().map(|&q| bits(q)).collect(), l.marker))
                .collect(),
            subdomains: pts(&p.subdomains),
            subdomain_names: p.subdomain_names,
            notes: p.notes,
            surface_group: p.surface_group,
        };
        serde_json::to_string(&state).expect("a state of numbers and strings serialises")
    }

    /// The region [`Region::to_state`] wrote down, built again: the same loops, corners,
    /// markers and everything it carries, to the bit. A text that is not such a state (or
    /// one of another layout) is refused, naming the problem.
    pub fn from_state(text: &str) -> Result<Region, GeometryError> {
        let bad = |message: String| GeometryError::Invalid {
            region: "(a saved region)".into(),
            message,
        };
        let s: State = serde_json::from_str(text)
            .map_err(|e| bad(format!("not a region's saved state: {e}")))?;
        if s.version != VERSION {
            return Err(bad(format!(
                "a region's state of layout {} (this build reads layout {VERSION})",
                s.version
            )));
        }
        let pts = |v: Vec<(Bits2, i64)>| v.into_iter().map(|(p, m)| (point(p), m)).collect();
        Region::assembled(Recipe {
            name: s.name,
            loops: s
                .loops
                .into_iter()
                .map(|(hole, pieces)| {
                    let role = if hole {
                        LoopRole::Hole
                    } else {
                        LoopRole::Outer
                    };
                    (
                        role,
                        pieces.into_iter().map(|(q, m)| (piece(q), m)).collect(),
                    )
                })
                .collect(),
            has_markers: s.has_markers,
            corners: s.corners.into_iter().map(point).collect(),
            corner_threshold: s.corner_threshold.map(f64::from_bits),
            corners_computed: s.corners_computed,
            marker_names: s.marker_names,
            vertex_markers: pts(s.vertex_markers),
            embedded: pts(s.embedded),
            lines: s
                .lines
                .into_iter()
                .map(|(points, marker)| EmbeddedLine {
                    points: points.into_iter().map(point).collect(),
                    marker,
                })
                .collect(),
            subdomains: pts(s.subdomains),
            subdomain_names: s.subdomain_names,
            notes: s.notes,
            surface_group: s.surface_group,
        })
    }
}
