//! TRIANGLE of the paper (Section 4): Delaunay refinement in the manner of Shewchuk's Triangle
//! (`triangle -q<angle> -a<area>`, Ruppert's algorithm with Triangle 1.6's off-centers and
//! concentric-shell segment splitting), reimplemented on spade's constrained Delaunay
//! triangulation.
//!
//! * Input: the region's boundary loops as a PSLG. Straight pieces enter as single segments,
//!   exactly as Triangle is given a polygon; the refinement splits them when encroached.
//!   Curved pieces are **pre-split** into chords of length ≈ the boundary spacing with every
//!   point on the exact curve (corners kept), and every later split of a curved subsegment puts
//!   its new vertex on the curve too (the chord point projected onto the piece). Pre-splitting
//!   is what a Triangle user does with a curved domain (the polygon is all Triangle sees), and it
//!   keeps each arc inside its chord's diametral circle, so a Steiner point in the sliver between
//!   chord and curve always encroaches that chord and is never inserted outside Ω.
//! * The region's embedded lines (an interface, a crack, a fracture network) are segments with
//!   the region on both sides, as a `.poly`'s segments inside the domain are to Triangle:
//!   pre-split at the boundary spacing, then split wherever encroached from either side, so
//!   that lines crossing at a small angle get small triangles there rather than slivers
//!   ([`Mesher::meshes_embedded_lines`]). An embedded point on a line splits it.
//!   A loop that is one closed curve (a circle, a super-ellipse) has no corner to start its
//!   chords from: by default they start at the curve's own start, and with
//!   [`CurveStart::Seeded`] at a seeded fraction of a chord past it, as a user's polygon of
//!   the curve may start anywhere.
//! * Refinement bounds: a minimum angle ([`Refine::min_angle_deg`], Triangle's default `-q` is
//!   20°) and a maximum triangle area A (`-a`; for a non-uniform density the local bound is
//!   A·ρ(centroid)^(-1/2), so the spacing goes like ρ^(-1/4) as for a CVT).
//! * Vertex count: Triangle gives no direct control of K (the paper's footnote 3), so, like the
//!   paper's authors, [`Refine`] searches A (secant steps on log A against log K, alternating
//!   with bisection once K is bracketed), with the curved-boundary spacing tied to A
//!   (h_b = [`BOUNDARY_FACTOR`]·√(4A/√3)). The result is the run whose K is nearest the request;
//!   `iterations` counts search steps and `converged` means K was hit exactly or the bracket on
//!   A shrank below a relative width of 1e-7 (K(A) jumps over the requested K there, so the
//!   reached K is as close as this method allows). On the paper's twelve cases the reached K
//!   is within 2 of the request, as was the paper's own TRIANGLE column (18 for 19, 86 for 88,
//!   242 for 240, …).
//! * Minimum angle: every triangle meets the bound except where a small input angle forces a
//!   smaller one (as in Triangle, a skinny triangle whose shortest edge joins two input segments
//!   meeting at a vertex, at equal distances from it, is not split), and except for triangles
//!   given up on (reported in the notes; none occur on the paper's regions at 20°).
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

mod boundary;
mod engine;
mod grid;
mod queue;

use boundary::VKind;
use geometry::{Density, Region, Rng};
use mesh::{Mesh, MeshError, MeshRequest, MeshResult, Mesher, Progress, VertexMarker};

/// Boundary chord length as a multiple of the edge of an equilateral triangle of area A,
/// chosen so that the pre-split curved boundaries have about the same edge length as the
/// refined interior at the default 20° bound.
// `cargo run --release -p cvtmesh-refine --example refine_probe -- circle 88` prints the mean
// boundary / interior edge ratio: 0.96 with this factor (square_hole 194: 0.92).
pub const BOUNDARY_FACTOR: f64 = 0.83;

/// Initial area bound as a multiple of the mean triangle area |Ω|/(2K): about the ratio of the
/// bound the search ends at to that mean area, so the search starts near the answer.
// The same refine_probe runs print the final area bound in their notes: 3.21e-2 for circle 88
// (1.80 · π/176) and 1.69e-2 for square_hole 194 (1.87 · |Ω|/388).
const AREA_FACTOR: f64 = 1.8;

/// Relative width of the area bracket at which the search stops: K(A) jumps over K there.
const BRACKET_TOL: f64 = 1e-7;

/// Delaunay refinement (TRIANGLE). `Refine::default()` is Triangle's `-q` (20°) with
/// off-centers and the area bound searched to reach the requested K.
///
/// Used through the [`Mesher`] trait like every method of the workspace:
///
/// ```
/// use cvtmesh::refine::Refine;
/// use cvtmesh::geometry::Region;
/// use cvtmesh::{check_conforming, MeshRequest, Mesher};
/// let region = Region::builtin("square_hole")?;
/// let result = Refine::default().mesh(&region, &MeshRequest::points(194), &mut |_| {})?;
/// let mesh = &result.mesh;
/// // Triangle gives no direct control of K: the area bound is searched to come close.
/// let k = mesh.num_vertices() as f64;
/// assert!((k - 194.0).abs() <= 0.05 * 194.0, "K = {k}");
/// // Every triangle meets the 20° bound (no small input angles here), and the mesh conforms
/// // to the region: boundary vertices on their pieces, corners kept, triangles tiling Ω.
/// assert!(mesh.min_angle_deg() >= 20.0 - 1e-9);
/// check_conforming(mesh, &region)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct Refine {
    /// Minimum angle bound in degrees (0 disables it; the algorithm may not terminate above
    /// about 34°, where the vertex budget stops it).
    pub min_angle_deg: f64,
    /// Insert Üngör's off-centers (Triangle 1.6's default) rather than plain circumcenters.
    pub off_centers: bool,
    /// A fixed area bound (Triangle's `-a`); `None` searches it so that K matches the request.
    pub max_area: Option<f64>,
    /// Cap on area-search steps (the request's `max_iter` caps it too).
    pub max_search_steps: usize,
    /// Cap on the steps (insertions, give-ups, re-checks) of one refinement run; `None`: 20
    /// per vertex of the run's vertex budget, plus 1000. A run that reaches it stops with the
    /// mesh it has, reported as not converged.
    pub max_steps: Option<usize>,
    /// Where the pre-split of a loop that is one closed curve starts
    /// ([`CurveStart::PieceStart`] by default).
    pub curve_start: CurveStart,
}

/// Where the chords of a loop that is one closed curve (a circle, a super-ellipse) start.
///
/// Such a loop has no corner to start from: the polygon a Triangle user writes for it starts
/// wherever they chose, and the refined mesh depends on that choice (on a circle only through
/// the ties of the Delaunay triangulation of its cocircular vertices; between two loops, as
/// in an annulus, through their relative phase).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CurveStart {
    /// At the curve's own start (angle 0): the same mesh for every seed.
    #[default]
    PieceStart,
    /// A seeded fraction of one chord past it, drawn per loop from the request's seed.
    Seeded,
}

impl CurveStart {
    /// The start of each loop's chords as a fraction of one chord, in [0, 1).
    ///
    /// ```
    /// use cvtmesh::refine::{CurveStart, Refine};
    /// use cvtmesh::geometry::Region;
    /// use cvtmesh::{check_conforming, MeshRequest, Mesher};
    ///
    /// let annulus = Region::builtin("annulus")?;
    /// assert_eq!(CurveStart::PieceStart.phases(&annulus, 3), vec![0.0, 0.0]);
    /// let phases = CurveStart::Seeded.phases(&annulus, 3);
    /// assert!(phases.iter().all(|p| (0.0..1.0).contains(p)));
    /// // Each seed meshes another (equally valid) polygon of the two circles.
    /// let seeded = Refine { curve_start: CurveStart::Seeded, ..Refine::default() };
    /// let mesh = |seed| seeded.mesh(&annulus, &MeshRequest::points(300).seed(seed), &mut |_| {});
    /// let (a, b) = (mesh(1)?.mesh, mesh(2)?.mesh);
    /// assert_ne!(a.points, b.points);
    /// check_conforming(&a, &annulus)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn phases(self, region: &Region, seed: u64) -> Vec<f64> {
        match self {
            CurveStart::PieceStart => vec![0.0; region.loops().len()],
            CurveStart::Seeded => {
                let mut rng = Rng::new(seed ^ 0x6375_7276_6573_7461);
                region.loops().iter().map(|_| rng.uniform()).collect()
            }
        }
    }
}

impl Default for Refine {
    fn default() -> Self {
        Refine {
            min_angle_deg: 20.0,
            off_centers: true,
            max_area: None,
            max_search_steps: 60,
            max_steps: None,
            curve_start: CurveStart::PieceStart,
        }
    }
}

/// One refinement run with a given area bound.
#[derive(Clone, Debug)]
pub struct Refinement {
    /// The refined mesh (CCW triangles, markers from the refinement's own bookkeeping).
    pub mesh: Mesh,
    /// The area bound used.
    pub max_area: f64,
    /// The chord length curved pieces were pre-split to.
    pub boundary_spacing: f64,
    /// False if the vertex budget stopped the refinement early.
    pub complete: bool,
    /// Triangles or subsegments the refinement had to leave as they were.
    pub given_up: usize,
}

impl Refine {
    /// Refine `region` once with area bound `max_area` and vertex budget `max_vertices`, closed
    /// curves split from their own start ([`CurveStart::PieceStart`]).
    ///
    /// Refused with [`MeshError::Failed`] when the bound is so coarse that a chord of a curved
    /// piece, pre-split at the spacing it implies, crosses another piece of the boundary or
    /// runs through one of its vertices, or leaves a boundary loop no area.
    pub fn refine_with_area(
        &self,
        region: &Region,
        max_area: f64,
        density: &Density,
        max_vertices: usize,
    ) -> Result<Refinement, MeshError> {
        self.refine_once(region, max_area, density, max_vertices, &[])?
            .ok_or_else(|| too_coarse(max_area))
    }

    /// [`Refine::refine_with_area`] with the closed curves' splits started at `phases` (see
    /// [`CurveStart::phases`]), and `None` for a bound too coarse for the curved pieces.
    fn refine_once(
        &self,
        region: &Region,
        max_area: f64,
        density: &Density,
        max_vertices: usize,
        phases: &[f64],
    ) -> Result<Option<Refinement>, MeshError> {
        if !(max_area.is_finite() && max_area > 0.0) {
            return Err(MeshError::BadRequest(format!(
                "area bound must be positive, got {max_area}"
            )));
        }
        let spacing = BOUNDARY_FACTOR * (4.0 * max_area / 3f64.sqrt()).sqrt();
        let Some(pslg) = boundary::build(region, spacing, density, phases)? else {
            return Ok(None);
        };
        let bounds = engine::Bounds {
            min_angle_deg: self.min_angle_deg,
            max_area,
            off_centers: self.off_centers,
            max_vertices: max_vertices.max(pslg.points.len() + 1),
            max_steps: self.max_steps.unwrap_or_else(|| {
                max_vertices
                    .max(pslg.points.len() + 1)
                    .saturating_mul(20)
                    .saturating_add(1000)
            }),
        };
        let Some(r) = engine::refine(region, pslg, density, bounds)? else {
            return Ok(None);
        };
        let markers = r
            .points
            .iter()
            .zip(&r.kinds)
            .map(|(p, k)| match *k {
                VKind::Interior | VKind::Line => VertexMarker::Interior,
                VKind::Corner(c) => VertexMarker::at_corner(region, c),
                VKind::Boundary(piece) => VertexMarker::on_piece(region, *p, piece),
            })
            .collect();
        Ok(Some(Refinement {
            mesh: Mesh {
                points: r.points,
                triangles: r.triangles,
                markers,
            },
            max_area,
            boundary_spacing: spacing,
            complete: r.complete,
            given_up: r.given_up,
        }))
    }

    fn check(&self) -> Result<(), MeshError> {
        if !(self.min_angle_deg.is_finite() && (0.0..60.0).contains(&self.min_angle_deg)) {
            return Err(MeshError::invalid_setting(
                "refine",
                "min_angle_deg",
                self.min_angle_deg,
                "in [0, 60) degrees",
            ));
        }
        Ok(())
    }
}

/// The refusal of an area bound whose pre-split chords would cross the boundary.
fn too_coarse(max_area: f64) -> MeshError {
    MeshError::Failed {
        method: "refine".into(),
        message: format!(
            "area bound {max_area:.6e} too coarse: a boundary chord pre-split at its spacing \
             crosses another piece of the boundary or runs through its vertex, or leaves a \
             boundary loop no area"
        ),
    }
}

impl Mesher for Refine {
    fn name(&self) -> &'static str {
        "refine"
    }

    /// The region's embedded lines are segments of the refinement's input, split where
    /// encroached, as Triangle refines a `.poly`'s segments inside the domain.
    fn meshes_embedded_lines(&self) -> bool {
        true
    }

    /// Search the area bound until the refined mesh has the requested K (see the crate
    /// docs). Progress reports NaN energy and |K(A) − K|/K as `max_move`.
    fn mesh(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<MeshResult, MeshError> {
        let k = request.validate(region)?;
        self.check()?;
        let budget = 10 * k + 1000;
        let phases = self.curve_start.phases(region, request.seed);
        let mut angle_note = format!(
            "minimum angle bound {}°, off-centers {}",
            self.min_angle_deg, self.off_centers
        );
        if self.curve_start == CurveStart::Seeded {
            angle_note += &format!(
                "; closed curves split from a seeded start (seed {})",
                request.seed
            );
        }
        if let Some(a) = self.max_area {
            // A fixed bound sets its own K: the vertex budget is what fits in memory.
            let budget = mesh::total_memory()
                .map_or(mesh::MAX_POINTS, |m| (m / mesh::BYTES_PER_VERTEX) as usize)
                .min(mesh::MAX_POINTS);
            let r = self
                .refine_once(region, a, &request.density, budget, &phases)?
                .ok_or_else(|| too_coarse(a))?;
            progress(Progress {
                iteration: 1,
                max_iter: 1,
                energy: f64::NAN,
                max_move: f64::NAN,
            });
            return Ok(MeshResult {
                notes: vec![
                    format!(
                        "fixed area bound {a:.6e}, boundary spacing {:.6e}",
                        r.boundary_spacing
                    ),
                    format!(
                        "K reached {} (no search: fixed area bound)",
                        r.mesh.num_vertices()
                    ),
                    angle_note,
                    format!("{} triangles or segments given up", r.given_up),
                ],
                mesh: r.mesh,
                iterations: 1,
                converged: r.complete,
                energy_history: Vec::new(),
                move_history: Vec::new(),
            });
        }
        let cap = self.max_search_steps.min(request.max_iter).max(1);
        let mut a = AREA_FACTOR * region.area() / (2.0 * k as f64);
        // (A, K(A)) with K(A) > K (A too small) and with K(A) < K (A too large).
        let mut small: Option<(f64, usize)> = None;
        let mut large: Option<(f64, usize)> = None;
        let mut best: Option<Refinement> = None;
        let mut converged = false;
        let mut steps = 0;
        let dist = |r: &Refinement| r.mesh.num_vertices().abs_diff(k);
        // The points of the last run that ran out of budget.
        let mut stuck: Option<Vec<geometry::DVec2>> = None;
        let mut over_budget = false;
        while steps < cap {
            steps += 1;
            // A bound whose chords cross the boundary or run through its vertices is too
            // coarse: count it as too few vertices, so the search shrinks it.
            let run = self.refine_once(region, a, &request.density, budget, &phases)?;
            let got = match &run {
                Some(r) if r.complete => r.mesh.num_vertices(),
                Some(_) => usize::MAX,
                None => 0,
            };
            progress(Progress {
                iteration: steps,
                max_iter: cap,
                energy: f64::NAN,
                max_move: got.abs_diff(k) as f64 / k as f64,
            });
            request.check_cancel(self.name(), steps)?;
            // A coarser bound that ran out of budget exactly as the last one did will keep
            // doing so: the boundary's small angles, not the area, set the count there.
            if let Some(r) = run.as_ref().filter(|r| !r.complete) {
                over_budget |= r.mesh.num_vertices() >= budget;
                if stuck.as_ref() == Some(&r.mesh.points) {
                    break;
                }
                stuck = Some(r.mesh.points.clone());
            }
            if let Some(r) = run.filter(|r| r.complete) {
                if best.as_ref().is_none_or(|b| dist(&r) < dist(b)) {
                    best = Some(r);
                }
            }
            if got == k {
                converged = true;
                break;
            }
            if request.out_of_time() && best.is_some() {
                break;
            }
            if got > k {
                small = Some((a, got));
            } else {
                large = Some((a, got));
            }
            a = match (small, large) {
                (Some((a1, k1)), Some((a2, k2))) => {
                    if (a2.ln() - a1.ln()).abs() < BRACKET_TOL {
                        // K(A) jumps over K here; an incomplete run on the small side means
                        // the refinement cannot get there at all.
                        converged = k1 != usize::MAX;
                        break;
                    }
                    // Secant on log K against log A, alternating with bisection so the bracket
                    // always shrinks.
                    let t = if steps % 2 == 0 || k1 == usize::MAX {
                        0.5
                    } else {
                        ((k1 as f64).ln() - (k as f64).ln()) / ((k1 as f64).ln() - (k2 as f64).ln())
                    };
                    let t = t.clamp(0.05, 0.95);
                    (a1.ln() + t * (a2.ln() - a1.ln())).exp()
                }
                (Some((a1, k1)), None) => {
                    a1 * if k1 == usize::MAX {
                        4.0
                    } else {
                        (k1 as f64 / k as f64).max(1.02)
                    }
                }
                (None, Some((a2, k2))) => a2 * (k2.max(1) as f64 / k as f64).min(0.98),
                (None, None) => unreachable!(),
            };
        }
        let best = best.ok_or_else(|| MeshError::Failed {
            method: "refine".into(),
            message: if over_budget {
                format!(
                    "no area bound gave a refinement within the budget of {budget} vertices \
                     ({steps} search steps): the {}° angle bound grades the mesh down to the \
                     region's narrowest gaps and sharpest corners, which at K = {k} need more \
                     vertices than that; a larger K would mesh it",
                    self.min_angle_deg
                )
            } else {
                format!("no complete refinement within {steps} search steps")
            },
        })?;
        let reached = best.mesh.num_vertices();
        Ok(MeshResult {
            notes: vec![
                format!(
                    "area bound {:.6e}, boundary spacing {:.6e} after {steps} search steps",
                    best.max_area, best.boundary_spacing
                ),
                format!(
                    "K reached {reached} (requested {k}, {}{})",
                    if reached == k {
                        "exact"
                    } else {
                        "nearest reachable"
                    },
                    if converged { "" } else { "; search capped" }
                ),
                angle_note,
                format!("{} triangles or segments given up", best.given_up),
            ],
            mesh: best.mesh,
            iterations: steps,
            converged,
            energy_history: Vec::new(),
            move_history: Vec::new(),
        })
    }
}
