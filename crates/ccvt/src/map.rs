//! The fixed-point map of one phase and what the solvers share: the phase's inputs, the
//! triangulation and cells kept from one evaluation to the next, the labels of Section 2.2.3,
//! the progress trace and the time profile.
use crate::params::{Solver, Update};
use crate::scale::LocalScale;
use crate::sublevel::Sublevel;
use geometry::{DVec2, Density, PieceId, Polygon, Region};
use mesh::Progress;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use tessellation::{clipped_cells_on, Cells, CellsBuffer, Delaunay, DomainGrid};

/// Wall-clock seconds spent in each part of the iteration, summed over all iterations.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Profile {
    /// Delaunay triangulation of the generators.
    pub triangulation: f64,
    /// Clipped Voronoi cells with their moments and the energy.
    pub cells: f64,
    /// Labels, projections onto pieces and corners (Algorithm 1, steps 3–6).
    pub projection: f64,
    /// Largest move and the convergence test.
    pub convergence: f64,
    /// Anderson mixing and re-constraining (zero for Lloyd and Newton).
    pub acceleration: f64,
    /// Newton: the Hessian, its restriction to the allowed moves and the candidate.
    pub hessian: f64,
    /// Newton: the conjugate-gradient solves.
    pub linear_solve: f64,
    /// Evaluations of the map (iterations, including rejected accelerated steps).
    pub evaluations: usize,
    /// Accelerated steps rejected because they raised the energy.
    pub rejected: usize,
    /// Anderson histories dropped because a label (interior/piece/corner) changed.
    pub label_resets: usize,
    /// Conjugate-gradient iterations of Newton's linear solves (zero for Lloyd and Anderson).
    pub linear_iterations: usize,
    /// Evaluations whose triangulation was the previous one repaired by flips (the rest were
    /// built afresh).
    pub flipped: usize,
    /// Evaluations of active-set steps (included in `evaluations`): only a few generators
    /// moved, and only the cells around them were recomputed.
    pub local_evaluations: usize,
    /// Generators moved by active-set steps, summed over those steps.
    pub local_moved: usize,
}

impl Profile {
    /// Add another run's times and counts to these.
    pub fn add(&mut self, other: &Profile) {
        self.triangulation += other.triangulation;
        self.cells += other.cells;
        self.projection += other.projection;
        self.convergence += other.convergence;
        self.acceleration += other.acceleration;
        self.hessian += other.hessian;
        self.linear_solve += other.linear_solve;
        self.evaluations += other.evaluations;
        self.rejected += other.rejected;
        self.label_resets += other.label_resets;
        self.linear_iterations += other.linear_iterations;
        self.flipped += other.flipped;
        self.local_evaluations += other.local_evaluations;
        self.local_moved += other.local_moved;
    }

    /// Seconds of all timed parts.
    pub fn total(&self) -> f64 {
        self.triangulation
            + self.cells
            + self.projection
            + self.convergence
            + self.acceleration
            + self.hessian
            + self.linear_solve
    }
}

pub(crate) fn lap(t: &mut Instant) -> f64 {
    let now = Instant::now();
    let s = now.duration_since(*t).as_secs_f64();
    *t = now;
    s
}

/// What a generator is constrained to in the current iteration (Section 2.2.3 labels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Role {
    /// Interior region: moves to its centroid.
    Interior,
    /// Boundary region: moves to the projection of its centroid onto this piece.
    Boundary(PieceId),
    /// Corner region: sits on this corner.
    Corner(usize),
    /// Sits on this embedded point of the region ([`Region::embedded_points`]).
    Embedded(usize),
}

/// The triangulation and cells of the current iterate, in memory kept from one iteration to
/// the next (at 10⁶ generators, fresh ones would fault in hundreds of MB of new pages per
/// iteration).
pub struct Work {
    pub(crate) del: Delaunay,
    pub(crate) cells: Cells,
    buffer: CellsBuffer,
    /// The domain's boundary grid for partial updates, and the vertex count it was built for.
    grid: Option<(DomainGrid, usize)>,
}

impl Work {
    /// For a phase on `domain`: the triangulation is framed around it, so that rebuilds after
    /// small moves repair it by flips.
    pub(crate) fn new(domain: &Polygon) -> Work {
        let (lo, hi) = domain.bbox();
        Work {
            del: Delaunay::framed(lo, hi),
            cells: Cells { cells: Vec::new() },
            buffer: CellsBuffer::default(),
            grid: None,
        }
    }

    /// Keep the triangulation (and the memory) for the next phase, on `domain`: its first
    /// evaluation then repairs the triangulation of the previous phase's last iterate instead of
    /// building one afresh.
    pub(crate) fn retarget(&mut self, domain: &Polygon) {
        let (lo, hi) = domain.bbox();
        self.del.set_frame_box(lo, hi);
        self.grid = None;
    }

    /// The triangulation, the cells and the domain's grid for partial cell and Hessian updates
    /// (built as a full cells pass builds it, so updated cells are bit-identical).
    pub(crate) fn parts(&mut self, domain: &Polygon) -> (&Delaunay, &mut Cells, &DomainGrid) {
        let grid = grid_for(&mut self.grid, domain, self.del.num_vertices());
        (&self.del, &mut self.cells, grid)
    }
}

/// The domain's grid for a triangulation of `nv` vertices, built when `kept` holds none for
/// that count (the domain is the `Work`'s: [`Work::retarget`] drops the grid).
fn grid_for<'a>(
    kept: &'a mut Option<(DomainGrid, usize)>,
    domain: &Polygon,
    nv: usize,
) -> &'a DomainGrid {
    if kept.as_ref().is_none_or(|g| g.1 != nv) {
        *kept = Some((DomainGrid::new(domain, nv), nv));
    }
    &kept.as_ref().expect("just built").0
}

/// The fixed-point map at one iterate (its cells are in the `Work`): energy, labels and the
/// next positions.
pub struct Step {
    pub energy: f64,
    pub roles: Vec<Role>,
    pub targets: Vec<DVec2>,
    /// The local spacing h(z_k) at each generator (empty for ρ ≡ 1, where it is the mean
    /// spacing): every per-generator yardstick of the iteration reads it here, so that an
    /// active-set step evaluates the density only where generators moved, not at all K.
    pub h: Vec<f64>,
    /// The generators whose role is `Corner` or `Embedded` ([`assign_fixed`] chose them), so
    /// that an active-set step finds them without reading all K roles.
    pub fixed: Vec<usize>,
    /// The generators whose position, target or local spacing changed since the moves were
    /// last brought up to date ([`crate::moves::Moves::sync`]); None for a whole evaluation.
    pub touched: Option<Vec<usize>>,
}

impl Step {
    /// h(z_k), the local spacing at generator `k` of the iterate this step was evaluated at.
    #[inline]
    pub(crate) fn h(&self, k: usize, scale: &LocalScale) -> f64 {
        if self.h.is_empty() {
            scale.mean()
        } else {
            self.h[k]
        }
    }
}

/// h(z_k) for every generator (empty for a uniform density): [`Step::h`].
pub(crate) fn yardsticks(scale: &LocalScale, z: &[DVec2]) -> Vec<f64> {
    if scale.is_uniform() {
        Vec::new()
    } else {
        z.par_iter().map(|&p| scale.at(p)).collect()
    }
}

/// Inputs shared by every iteration of a phase.
pub struct Phase<'a> {
    pub region: &'a Region,
    /// The tessellated domain: Ω (Algorithm 1) or Ω_ε (Algorithm 2), polygonized.
    pub domain: &'a Polygon,
    /// Where an interior generator may sit: Ω itself when constrained (signed distance < 0,
    /// exact), else a part of the domain polygon (signed distance < ε − 2·chord tolerance).
    pub inside: &'a Sublevel<'a>,
    pub density: &'a Density,
    /// Algorithm 1's labels and projections (false: ordinary CVT of the domain).
    pub constrained: bool,
    /// Where a generator moves before its label's projection (constrained phases only).
    pub update: Update,
    pub solver: Solver,
    pub tol: f64,
    pub max_iter: usize,
    pub spacing: f64,
    /// The local spacing, the yardstick of every per-generator move (`spacing` where ρ ≡ 1).
    pub scale: LocalScale<'a>,
    /// Newton's active-set steps from this many generators on (`Ccvt::active_from`).
    pub active_from: usize,
    /// Newton's active-set steps only while at most this share of the generators move more
    /// than the defect gate (`active::ACTIVE_SHARE`, or more where the start allows it).
    pub active_share: f64,
    /// The start lies off the constraints (boundary generators off ∂Ω, as Algorithm 2's CVT
    /// of Ω_ε leaves them): Newton takes the projection, a Lloyd step, before its first Newton
    /// step, which would otherwise be compared with an energy no feasible point can reach.
    pub project_first: bool,
    /// The request's cancel flag: a phase stops at its next evaluation once it is set.
    pub cancel: Option<&'a AtomicBool>,
    /// The request's deadline: a phase stops at its next evaluation once it has passed, as
    /// at the iteration cap.
    pub deadline: Option<Instant>,
}

impl Phase<'_> {
    /// True once the request's cancel flag is set.
    pub fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }
    /// True once the request's deadline has passed.
    pub fn out_of_time(&self) -> bool {
        self.deadline.is_some_and(|d| Instant::now() >= d)
    }
}

/// Result of a phase.
pub struct PhaseResult {
    pub z: Vec<DVec2>,
    pub roles: Vec<Role>,
    pub iterations: usize,
    pub converged: bool,
    /// Stopped because the largest move had stopped falling (Newton's phases only).
    pub stalled: bool,
}

/// Evaluate the map at `z`: Voronoi cells clipped to the domain → centroids → labels →
/// projection of boundary centroids onto their own piece, corners to corners.
pub fn step(phase: &Phase, z: &[DVec2], work: &mut Work, prof: &mut Profile) -> Step {
    let mut t = Instant::now();
    prof.evaluations += 1;
    work.del.rebuild(z);
    let del = &work.del;
    prof.flipped += usize::from(del.flipped());
    prof.triangulation += lap(&mut t);
    let grid = grid_for(&mut work.grid, phase.domain, del.num_vertices());
    clipped_cells_on(
        z,
        del,
        grid,
        phase.density,
        &mut work.cells,
        &mut work.buffer,
    );
    let cells = &work.cells;
    let mut energy = cells.energy();
    prof.cells += lap(&mut t);
    let (mut roles, mut targets): (Vec<Role>, Vec<DVec2>) =
        if phase.constrained && phase.update == Update::Odt {
            // VTM's patch is the mesh: the Delaunay triangles of the generators inside Ω. Not
            // `conforming_mesh`, which refuses the transient labels of a run in progress; only
            // interior generators take these targets, and their patches are the same in both.
            let triangles: Vec<[u32; 3]> = del
                .triangles()
                .into_iter()
                .filter(|t| {
                    phase
                        .region
                        .contains(t.map(|v| z[v as usize]).iter().sum::<DVec2>() / 3.0)
                })
                .collect();
            let odt = tessellation::odt_targets(z, &triangles, phase.density);
            energy = tessellation::odt_energy(z, &triangles, phase.density);
            // A boundary generator's patch is cut by ∂Ω; it follows CCVT's rule instead.
            cells
                .cells
                .par_iter()
                .zip(&odt)
                .map(|(c, &x)| {
                    if c.on_boundary() {
                        map_cell(phase, c)
                    } else {
                        map_cell_at(phase, c, x)
                    }
                })
                .unzip()
        } else {
            cells.cells.par_iter().map(|c| map_cell(phase, c)).unzip()
        };
    let fixed = assign_fixed(phase, z, del, &mut roles, &mut targets);
    let h = yardsticks(&phase.scale, z);
    prof.projection += lap(&mut t);
    Step {
        energy,
        roles,
        targets,
        h,
        fixed,
        touched: None,
    }
}

/// The map at one cell: its label and where its generator goes (the centroid; for a boundary
/// cell of a constrained phase its projection onto the nearest piece the cell touches).
pub(crate) fn map_cell(phase: &Phase, cell: &tessellation::Cell) -> (Role, DVec2) {
    map_cell_at(phase, cell, cell.mass_centroid)
}

/// [`map_cell`] with the generator moving to `c` instead of the cell's centroid; the label
/// still comes from the cell.
fn map_cell_at(phase: &Phase, cell: &tessellation::Cell, c: DVec2) -> (Role, DVec2) {
    if !phase.constrained {
        return (Role::Interior, c);
    }
    let region = phase.region;
    if cell.on_boundary() {
        // Section 2.3: of the projections onto the pieces the cell touches, the nearest.
        let (j, best) = cell
            .pieces
            .iter()
            .map(|&j| (j, region.project_onto_piece(c, j)))
            .min_by(|a, b| a.1.distance.total_cmp(&b.1.distance))
            .expect("boundary cell has a piece");
        match best.corner {
            Some(corner) => (
                Role::Boundary(j),
                off_corner(region, corner, j, c, &phase.scale),
            ),
            None => (Role::Boundary(j), best.point),
        }
    } else if phase.inside.contains(c) || !c.is_finite() {
        (Role::Interior, c)
    } else {
        // Interior centroids of Ω_ε may fall outside Ω (or on ∂Ω); such a cell behaves as a
        // boundary cell (its generator must stay in Ω̄ for the mesh).
        let sd = region.signed_distance(c);
        if sd > 0.0 {
            let bp = region.project(c);
            (Role::Boundary(bp.piece), bp.point)
        } else {
            (Role::Interior, c)
        }
    }
}

/// A centroid beyond the end of its piece (in the normal cone of a reflex corner) projects onto
/// the corner itself, where the corner's own generator sits: the two would coincide and one cell
/// would vanish. Section 2.3 allows any constrained centroid in that case; keep the generator on
/// its piece at the centroid's distance from the corner, clamped to [0.1, 0.5] of the local
/// spacing at the corner (and to half the piece).
fn off_corner(
    region: &Region,
    corner: usize,
    piece: PieceId,
    centroid: DVec2,
    scale: &LocalScale,
) -> DVec2 {
    let c = &region.corners()[corner];
    let spacing = scale.at(c.pos);
    let p = &region.pieces()[piece];
    let (t_start, t_end) = p.end_tangents();
    let into_piece = if c.piece_out == piece {
        t_start
    } else {
        -t_end
    };
    let d = (centroid - c.pos)
        .length()
        .clamp(0.1 * spacing, 0.5 * spacing)
        .min(0.5 * p.length());
    region.project_point_onto_piece(c.pos + into_piece * d, piece)
}

/// Rings of Delaunay neighbours searched for a free generator when a corner's nearest one is
/// taken.
const CORNER_RINGS: usize = 8;

/// The generators held at fixed points: in a constrained phase the corners' ([`assign_corners`]),
/// in every phase the embedded points' (each the generator nearest it, as for a corner).
/// `roles` must hold no `Corner` or `Embedded` role but those of its returned holders' (a
/// fresh map, or one whose previous holders were mapped again). Returns the holders.
pub(crate) fn assign_fixed(
    phase: &Phase,
    z: &[DVec2],
    del: &Delaunay,
    roles: &mut [Role],
    targets: &mut [DVec2],
) -> Vec<usize> {
    let region = phase.region;
    let corners = region.corners().iter().enumerate();
    let corners = corners.map(|(c, k)| (k.pos, Role::Corner(c)));
    let embedded = region.embedded_points().iter().enumerate();
    let embedded = embedded.map(|(e, &(p, _))| (p, Role::Embedded(e)));
    if phase.constrained {
        assign_corners(corners.chain(embedded), z, del, roles, targets)
    } else if !region.embedded_points().is_empty() {
        assign_corners(embedded, z, del, roles, targets)
    } else {
        Vec::new()
    }
}

/// Corner regions: the cell whose closure holds the corner is its nearest generator's; if two
/// corners share a nearest generator (corners closer together than the spacing, as on a
/// digitized coastline), the nearest free generator of the first ring of Delaunay neighbours
/// that has one takes it (up to `CORNER_RINGS` rings), and sits on the corner from then on.
/// `fixed` lists each fixed point with the role of the generator that takes it.
fn assign_corners(
    fixed: impl Iterator<Item = (DVec2, Role)>,
    z: &[DVec2],
    del: &Delaunay,
    roles: &mut [Role],
    targets: &mut [DVec2],
) -> Vec<usize> {
    let mut holders = Vec::new();
    let is_fixed = |r: &Role| matches!(r, Role::Corner(_) | Role::Embedded(_));
    for (pos, role) in fixed {
        let mut k = del.nearest(pos);
        if is_fixed(&roles[k]) {
            let mut seen = vec![k];
            let mut ring = vec![k];
            let mut free = None;
            for _ in 0..CORNER_RINGS {
                let mut next = Vec::new();
                for &i in &ring {
                    for j in del.neighbors(i) {
                        if !seen.contains(&j) {
                            seen.push(j);
                            next.push(j);
                        }
                    }
                }
                free = next
                    .iter()
                    .copied()
                    .filter(|&j| !is_fixed(&roles[j]))
                    .min_by(|&a, &b| {
                        (z[a] - pos)
                            .length()
                            .total_cmp(&(z[b] - pos).length())
                            .then(a.cmp(&b))
                    });
                if free.is_some() || next.is_empty() {
                    break;
                }
                ring = next;
            }
            match free {
                Some(j) => k = j,
                None => continue,
            }
        }
        roles[k] = role;
        targets[k] = pos;
        holders.push(k);
    }
    holders
}

/// Largest |a_k − b_k| / h_k, h_k the local spacing at b_k (`h`, empty for a uniform density;
/// a parallel max: exact and independent of the thread count); infinite if any move is NaN,
/// so that a non-finite centroid never passes the convergence test.
pub(crate) fn max_move(a: &[DVec2], b: &[DVec2], h: &[f64], scale: &LocalScale) -> f64 {
    let relative = |(k, (p, q)): (usize, (&DVec2, &DVec2))| {
        let d = (*p - *q).length_squared();
        if d.is_nan() {
            f64::INFINITY
        } else if scale.is_uniform() {
            d
        } else {
            d / h[k].powi(2)
        }
    };
    let m = a
        .par_iter()
        .zip(b)
        .enumerate()
        .map(relative)
        .reduce(|| 0.0, f64::max);
    if scale.is_uniform() {
        m.sqrt() / scale.mean()
    } else {
        m.sqrt()
    }
}

/// What every phase reports: energy and relative largest move per iteration, progress, and
/// where the time went.
pub struct Trace<'a> {
    /// CVT energy per iteration (the ODT energy of the mesh under [`Update::Odt`]).
    pub energies: Vec<f64>,
    /// Largest move / local spacing per iteration.
    pub moves: Vec<f64>,
    /// Called after every iteration.
    pub progress: &'a mut dyn FnMut(Progress),
    /// Where the time went.
    pub prof: Profile,
}

/// The largest move of the map at `z` (relative to the local spacing), appended with the energy to
/// the histories and reported as progress.
pub(crate) fn record(
    phase: &Phase,
    s: &Step,
    z: &[DVec2],
    iterations: usize,
    trace: &mut Trace,
) -> f64 {
    let t = Instant::now();
    let mv = largest_move(phase, s, z);
    record_move(phase, s, mv, iterations, trace, t)
}

/// The largest move of the map at `z`, relative to the local spacing.
fn largest_move(phase: &Phase, s: &Step, z: &[DVec2]) -> f64 {
    match phase.update {
        // VTM's update with projected boundary vertices can turn the whole set on a disc, as
        // the sliding VTM does: only the change of shape counts.
        Update::Odt if phase.region.rotation_centre().is_some() => {
            let shape: Vec<DVec2> = z
                .iter()
                .zip(phase.region.moves_without_rotation(z, &s.targets))
                .map(|(p, d)| *p + d)
                .collect();
            max_move(&shape, z, &s.h, &phase.scale)
        }
        _ => max_move(&s.targets, z, &s.h, &phase.scale),
    }
}

/// [`record`] of the largest move `mv`, found since `t`.
pub(crate) fn record_move(
    phase: &Phase,
    s: &Step,
    mv: f64,
    iterations: usize,
    trace: &mut Trace,
    mut t: Instant,
) -> f64 {
    trace.energies.push(s.energy);
    trace.moves.push(mv);
    trace.prof.convergence += lap(&mut t);
    (trace.progress)(Progress {
        iteration: iterations,
        max_iter: phase.max_iter,
        energy: s.energy,
        max_move: mv,
    });
    mv
}
