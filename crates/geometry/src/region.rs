//! The region Ω: loops of pieces, corners, and the queries every method needs.
use crate::index::{Hit, Index};
use crate::polygon::Ring;
use crate::{piece::Piece, polygon::Polygon, GeometryError};
use glam::DVec2;
use std::sync::Arc;

/// Index of a boundary piece in `Region::pieces()` (global over all loops).
pub type PieceId = usize;

/// Outer boundary or hole.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoopRole {
    /// The outer boundary (CCW).
    Outer,
    /// A hole (CW).
    Hole,
}

/// One closed boundary loop: pieces in traversal order, each starting where the last ended.
#[derive(Clone, Debug)]
pub struct Loop {
    /// Outer or hole.
    pub role: LoopRole,
    /// Global ids of this loop's pieces in order.
    pub pieces: Vec<PieceId>,
    /// Arc length at the start of each piece, measured from the loop's start.
    pub offsets: Vec<f64>,
    /// Total length.
    pub length: f64,
}

/// A corner Γ_c of Section 2.2.3: a junction of two pieces where the tangent jumps.
#[derive(Clone, Debug, PartialEq)]
pub struct Corner {
    /// Position.
    pub pos: DVec2,
    /// Loop it lies on.
    pub loop_index: usize,
    /// Piece ending here.
    pub piece_in: PieceId,
    /// Piece starting here.
    pub piece_out: PieceId,
    /// Arc-length position along its loop.
    pub loop_param: f64,
}

/// Result of projecting a point onto the boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct BoundaryPoint {
    /// The nearest boundary point.
    pub point: DVec2,
    /// Its distance from the query point.
    pub distance: f64,
    /// Piece it lies on.
    pub piece: PieceId,
    /// Loop it lies on.
    pub loop_index: usize,
    /// Arc-length position along the loop (for ordering boundary vertices).
    pub loop_param: f64,
    /// The corner it coincides with (within 1e-12·diameter), if any.
    pub corner: Option<usize>,
}

/// A planar region: one outer loop and any number of holes, validated and oriented
/// (outer CCW, holes CW).
#[derive(Clone, Debug)]
pub struct Region {
    pub(crate) name: String,
    pub(crate) pieces: Vec<Piece>,
    pub(crate) piece_loop: Vec<usize>,
    pub(crate) loops: Vec<Loop>,
    pub(crate) corners: Vec<Corner>,
    pub(crate) area: f64,
    /// Corner-angle threshold applied (degrees), if any (`with_corner_angle`).
    pub(crate) corner_threshold: Option<f64>,
    /// Exact bounding box (min, max).
    pub(crate) bbox: (DVec2, DVec2),
    /// Nearest-point index over the boundary (shared by clones).
    pub(crate) index: Arc<Index>,
    /// Corner at the start / end of each piece, if any.
    pub(crate) corner_at_start: Vec<Option<usize>>,
    pub(crate) corner_at_end: Vec<Option<usize>>,
    /// Arc length along its loop at the start of each piece.
    pub(crate) piece_offset: Vec<f64>,
}

impl Region {
    /// Build from loops of pieces (outer first). Validates (closed, no self-intersection, no
    /// loops crossing, holes inside the outer loop, finite numbers), normalises orientation,
    /// and takes `corners` as given (`None`: every junction whose turning angle exceeds 1e-6 rad).
    ///
    /// Details:
    /// - exactly one loop must be `Outer`; it becomes loop 0 even if it is not listed first
    ///   (the holes keep their relative order). Messages number loops as given;
    /// - a gap of at most 1e-9·diameter between consecutive pieces is closed by moving the
    ///   end of the straight piece (line or chain) onto its neighbour; a larger gap is an error;
    /// - duplicate consecutive vertices (an edge of length ≤ 1e-9·diameter) are **rejected**,
    ///   not removed, with their position in the message;
    /// - crossings and touchings (closer than 1e-11·diameter) within a loop or between loops
    ///   are found on a polygonization with chord error 1e-6·diameter (chains exactly) and
    ///   reported with the crossing point; loops closer than that tolerance may go unnoticed;
    /// - a loop with the wrong orientation is reversed (pieces reversed and in reverse order,
    ///   so it keeps its start point);
    /// - each listed corner must lie within 1e-8·diameter of a junction of two pieces (or the
    ///   start of a single-piece loop); its position becomes that junction exactly.
    pub fn new(
        name: &str,
        loops: Vec<(LoopRole, Vec<Piece>)>,
        corners: Option<Vec<DVec2>>,
    ) -> Result<Region, GeometryError> {
        crate::build::new_region(name, loops, corners)
    }

    /// Name (file stem or built-in name).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// All pieces, indexed by `PieceId`.
    pub fn pieces(&self) -> &[Piece] {
        &self.pieces
    }
    /// Loop of each piece.
    pub fn piece_loop(&self, piece: PieceId) -> usize {
        self.piece_loop[piece]
    }
    /// The loops, outer first.
    pub fn loops(&self) -> &[Loop] {
        &self.loops
    }
    /// The corners.
    pub fn corners(&self) -> &[Corner] {
        &self.corners
    }
    /// The corner-angle threshold (degrees) applied when the region was loaded, if any.
    pub fn corner_threshold(&self) -> Option<f64> {
        self.corner_threshold
    }
    /// Exact area |Ω| (analytic for circles, arcs, super-ellipses).
    pub fn area(&self) -> f64 {
        self.area
    }
    /// Bounding box (min, max).
    pub fn bbox(&self) -> (DVec2, DVec2) {
        self.bbox
    }
    /// Length of the bounding box diagonal.
    pub fn diameter(&self) -> f64 {
        let (lo, hi) = self.bbox();
        (hi - lo).length()
    }
    /// Total boundary length.
    pub fn perimeter(&self) -> f64 {
        self.loops.iter().map(|l| l.length).sum()
    }
    /// True if `p` is in the closed region.
    pub fn contains(&self, p: DVec2) -> bool {
        self.signed_distance(p) <= 0.0
    }
    /// Signed distance to the boundary: negative inside, positive outside.
    ///
    /// The magnitude is the exact distance to the pieces (a bounding-volume hierarchy over
    /// segments and curves finds the nearest one); the sign comes from the side of the
    /// nearest piece, or at a vertex from the wedge of the two tangents, which is exact for
    /// every point off the boundary. NaN for a non-finite point.
    pub fn signed_distance(&self, p: DVec2) -> f64 {
        if !p.is_finite() {
            return f64::NAN;
        }
        let hit = self.index.nearest(&self.pieces, p);
        let d = hit.d2.sqrt();
        if d == 0.0 {
            0.0
        } else if self.index.inside(&self.pieces, p, &hit) {
            -d
        } else {
            d
        }
    }
    /// Nearest boundary point over all pieces.
    ///
    /// When the nearest point is within 1e-12·diameter of a corner, the corner is reported
    /// exactly: `point` is the corner, `piece` its `piece_out`, `loop_param` its `loop_param`.
    /// `loop_param` is always in [0, loop length).
    pub fn project(&self, p: DVec2) -> BoundaryPoint {
        let hit = self.index.nearest(&self.pieces, p);
        self.boundary_point(p, &hit, None)
    }
    /// Nearest point on one given piece (the "own piece" projection of CCVT step 5).
    /// A corner at either end of the piece is reported as in `project`, but `piece` stays
    /// the given one.
    ///
    /// # Panics
    /// If `piece` is not a valid piece id.
    pub fn project_onto_piece(&self, p: DVec2, piece: PieceId) -> BoundaryPoint {
        let hit = self.index.nearest_on_piece(&self.pieces, p, piece);
        self.boundary_point(p, &hit, Some(piece))
    }
    /// The first interior vertex of a sampled piece (`Piece::Chain`) met going along piece
    /// `piece` from the nearest point of `a` to that of `b`, a vertex at `a`'s own nearest point
    /// included. The piece bends there, so the energy along it has a kink: a generator moved
    /// along its tangent must stop at the vertex. None for the other (smooth) pieces.
    ///
    /// # Panics
    /// If `piece` is not a valid piece id.
    pub fn chain_vertex_between(&self, a: DVec2, b: DVec2, piece: PieceId) -> Option<DVec2> {
        let Piece::Chain(pts) = &self.pieces[piece] else {
            return None;
        };
        // Chain parameters: segment index + t; vertex i is at parameter i.
        let param = |p| self.index.nearest_on_piece(&self.pieces, p, piece).aux;
        let (sa, sb) = (param(a), param(b));
        let interior = |i: f64| (i >= 1.0 && (i as usize) + 1 < pts.len()).then(|| pts[i as usize]);
        if (sa - sa.round()).abs() <= 1e-9 {
            return interior(sa.round());
        }
        if sb > sa && sa.ceil() < sb {
            interior(sa.ceil())
        } else if sb < sa && sa.floor() > sb {
            interior(sa.floor())
        } else {
            None
        }
    }
    /// Straight-edged approximation with chord error ≤ `tol`; corners are kept as vertices.
    ///
    /// Every piece junction is a vertex (so corners are exact vertices); `tol` is clamped
    /// below at 1e-12·diameter (a NaN or non-positive `tol` means that).
    pub fn polygonize(&self, tol: f64) -> Polygon {
        let tol = tol.max(1e-12 * self.diameter());
        let rings = self
            .loops
            .iter()
            .enumerate()
            .map(|(l, lp)| {
                let (mut points, mut pieces) = (Vec::new(), Vec::new());
                for &pid in &lp.pieces {
                    let pts = self.pieces[pid].polygonize(tol);
                    let k = pts.len().saturating_sub(1);
                    points.extend_from_slice(&pts[..k]);
                    pieces.extend(std::iter::repeat_n(pid, k));
                }
                Ring {
                    points,
                    pieces,
                    loop_index: l,
                    hole: lp.role == LoopRole::Hole,
                }
            })
            .collect();
        Polygon { rings }
    }

    fn boundary_point(&self, p: DVec2, hit: &Hit, keep_piece: Option<PieceId>) -> BoundaryPoint {
        let el = &self.index.elems[hit.elem as usize];
        let mut piece = el.piece as usize;
        let loop_index = self.piece_loop[piece];
        let length = self.loops[loop_index].length;
        let mut point = hit.point;
        let mut loop_param = self.piece_offset[piece] + self.index.piece_param(&self.pieces, hit);
        let tol = 1e-12 * self.diameter();
        let corner = [self.corner_at_start[piece], self.corner_at_end[piece]]
            .into_iter()
            .flatten()
            .find(|&c| self.corners[c].pos.distance(hit.point) <= tol);
        if let Some(c) = corner {
            let c = &self.corners[c];
            point = c.pos;
            loop_param = c.loop_param;
            piece = c.piece_out;
        }
        if let Some(k) = keep_piece {
            piece = k;
        }
        if loop_param >= length {
            loop_param -= length;
        }
        BoundaryPoint {
            point,
            distance: p.distance(point),
            piece,
            loop_index,
            loop_param: loop_param.clamp(0.0, length),
            corner,
        }
    }
    /// Ω_ε = {x : dist(x, Ω) ≤ ε} of Section 2.4, polygonized to `tol`; each edge's piece is
    /// the piece of Ω it is nearest to. Holes shrink and vanish when ε exceeds their inradius.
    ///
    /// The result is a simple polygon (outer ring CCW first, holes CW) whose vertices lie
    /// within `tol` of distance ε from Ω. A bay of the outer boundary whose mouth is narrower
    /// than 2ε but which is wider inside becomes a new hole (its `loop_index` is the loop of
    /// its first edge's piece). ε ≤ 0 or NaN gives `polygonize(tol)`; see `expand.rs` for
    /// the method.
    pub fn expand(&self, eps: f64, tol: f64) -> Polygon {
        crate::expand::expand(self, eps, tol)
    }
    /// The same region with only the corners whose turning angle exceeds `degrees`; pieces
    /// joined at the dropped corners merge into `Piece::Chain`s.
    ///
    /// The turning angle of a corner is the angle between the incoming and outgoing
    /// tangents (0° = straight on, 180° = turning back). Runs of pieces between kept corners
    /// (and junctions that never were corners, such as tangent line–arc joins) become one
    /// `Chain`: lines and chains contribute their points exactly; an arc in such a run is
    /// sampled with chord error 1e-7·diameter. A loop left with no corner at all becomes a
    /// single closed chain. The geometry is otherwise unchanged (no re-validation), `degrees`
    /// is recorded in `corner_threshold`, and a NaN threshold counts as 0.
    pub fn with_corner_angle(&self, degrees: f64) -> Region {
        let degrees = if degrees.is_nan() { 0.0 } else { degrees };
        let threshold = degrees.to_radians();
        let arc_tol = 1e-7 * self.diameter();
        let mut lps = Vec::with_capacity(self.loops.len());
        let mut flags = Vec::with_capacity(self.loops.len());
        for lp in &self.loops {
            let n = lp.pieces.len();
            // keep[k]: the junction at the start of piece k stays a corner; cut[k]: pieces
            // are not merged across it.
            let keep: Vec<bool> = lp
                .pieces
                .iter()
                .map(|&p| {
                    self.corner_at_start[p].is_some_and(|c| {
                        let c = &self.corners[c];
                        crate::build::turning_angle(
                            &self.pieces[c.piece_in],
                            &self.pieces[c.piece_out],
                        ) > threshold
                    })
                })
                .collect();
            let cut: Vec<bool> = (0..n)
                .map(|k| keep[k] || self.corner_at_start[lp.pieces[k]].is_none())
                .collect();
            let first = (0..n).find(|&k| cut[k]).unwrap_or(0);
            let (mut pieces, mut f) = (Vec::new(), Vec::new());
            let mut k = 0;
            while k < n {
                // One run: from a cut up to (not including) the next cut.
                let start = (first + k) % n;
                let mut run = vec![start];
                k += 1;
                while k < n && !cut[(first + k) % n] {
                    run.push((first + k) % n);
                    k += 1;
                }
                f.push(keep[start]);
                if run.len() == 1 {
                    pieces.push(self.pieces[lp.pieces[start]].clone());
                } else {
                    let mut pts: Vec<DVec2> = Vec::new();
                    for &r in &run {
                        let piece = &self.pieces[lp.pieces[r]];
                        let sample = match piece {
                            Piece::Line { a, b } => vec![*a, *b],
                            Piece::Chain(c) => c.clone(),
                            other => other.polygonize(arc_tol),
                        };
                        let skip = usize::from(!pts.is_empty());
                        pts.extend_from_slice(&sample[skip..]);
                    }
                    pieces.push(Piece::Chain(pts));
                }
            }
            lps.push((lp.role, pieces));
            flags.push(f);
        }
        crate::build::assemble(self.name.clone(), lps, &flags, Some(degrees))
    }
    /// Read a region file (the project's JSON schema, see `regions/` in this crate).
    pub fn from_file(path: &std::path::Path) -> Result<Region, GeometryError> {
        crate::file::from_file(path)
    }
    /// Parse region JSON; `label` names the source in errors.
    pub fn from_json_str(text: &str, label: &str) -> Result<Region, GeometryError> {
        crate::file::from_json_str(text, label)
    }
    /// One of the paper's ten regions by name (`circle`, `lake`, ...).
    pub fn builtin(name: &str) -> Result<Region, GeometryError> {
        crate::file::builtin(name)
    }
    /// Names of the built-in regions, in the paper's table order.
    pub fn builtin_names() -> &'static [&'static str] {
        crate::file::BUILTIN_NAMES
    }
}
