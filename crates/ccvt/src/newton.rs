//! Newton's method for one phase: the CVT energy's Hessian (from `tessellation`) restricted to
//! the moves Algorithm 1 allows (interior generators anywhere, boundary ones along their piece,
//! corners fixed), shifted by σ·2m (Levenberg–Marquardt) plus a shift of each generator's own
//! where negative curvature was met, solved inexactly by block-Jacobi preconditioned conjugate
//! gradients. Lloyd's tail is a slow elastic mode, which the linear solve removes in one step;
//! Anderson's is a string of saddle escapes, where the Hessian is indefinite: the shifts, and a
//! floor on every diagonal block, keep the step a descent direction, and the direction of
//! negative curvature the solve met is added to the step so that the iterate leaves a saddle
//! instead of creeping away from it.
//!
//! A candidate is kept only if it lowers the energy; otherwise σ grows and the plain Lloyd step
//! (which always lowers it) is taken. Generators whose label changed this iteration (an interior
//! cell that reached the boundary, a corner) take their Lloyd target.
//!
//! From `Ccvt::active_from` generators on, once few still move more than the tolerance, the
//! same Newton step is taken on an active set only (module `active`), everyone else held fixed.
use crate::active;
use crate::map::{
    lap, record, record_move, step, Phase, PhaseResult, Profile, Role, Step, Trace, Work,
};
use crate::moves::Moves;
use geometry::{DVec2, PieceId, Region};
use glam::DMat2;
use rayon::prelude::*;
use std::time::Instant;
use tessellation::{dot, energy_hessian_on, energy_hessian_rows, BlockMatrix, DOT_CHUNK};

/// Evaluations without a new low of the largest move after which a phase stops, not
/// converged: the iterate is cycling. Over 17 converged runs (four graded cases at K = 10⁴,
/// seeds 1–3, and five uniform regions at 10⁴) the longest wait for a new low was 56
/// evaluations; a coastline of 5000 vertices meshed toward its shore at K = 3000 cycled with a
/// period of about 66 evaluations from evaluation 136 on, and would otherwise run to the cap
/// of 10 000 evaluations, over ten minutes. Counted in evaluations of the whole map: an
/// active-set step counts the share of the generators it moves, because a graded run converges
/// through hundreds of such steps of a few milliseconds each, which are progress, not a cycle.
/// Each evaluation of an active-set step counts at least `ACTIVE_WORK_FLOOR`, so that a cycle
/// of small active sets still ends: the same coastline takes active-set steps (K ≥
/// `Ccvt::active_from`), and cycled through them to the cap when each counted only the few
/// generators it moved.
// comb20 refined toward its outline at K = 20 000–25 000 converges in 547–980 evaluations;
// with every active-set step counted as one evaluation, three such runs stopped after 512–768.
pub(crate) const STALL_EVALUATIONS: usize = 300;
const ACTIVE_WORK_FLOOR: f64 = 0.1;

/// First shift σ (relative to 2m, Lloyd's own scale), its floor and its cap.
const SIGMA_START: f64 = 0.1;
const SIGMA_MIN: f64 = 1e-3;
const SIGMA_MAX: f64 = 1e6;
/// Least eigenvalue of a diagonal block on its allowed moves, relative to 2m.
const BLOCK_FLOOR: f64 = 0.1;
/// Relative residual at which the linear solve stops, and its iteration cap: an inexact Newton
/// step, since tighter solves buy nothing once boundary cells change their neighbours from one
/// step to the next.
// Six runs (circle and lake, 10⁴–10⁵ generators): 1643 evaluations in all with a cap of 20,
// 1808 with a cap of 400.
const CG_TOL: f64 = 1e-2;
const CG_MAX: usize = 20;
/// From this shift on, plain Lloyd steps (σ halves after each): where negative curvature
/// persists (a thin wedge), a strongly shifted Newton step is a poor Lloyd step.
// 12 runs (6 region/size pairs, seeds 1 and 2): 2747 evaluations in all with it, 7733 without;
// pie_hole at K = 287, seed 1: 565 against 4538.
const SIGMA_LLOYD: f64 = 1.0;
/// Largest Newton move of one generator, relative to the local spacing: the quadratic model holds
/// only while the Voronoi neighbours stay the same.
// 12 runs (6 regions, seeds 2 and 3): caps of ∞ / 0.15 / 0.1 / 0.05 took 5462 / 4982 / 3881 /
// 3951 evaluations in all.
const STEP_CAP: f64 = 0.1;
/// Linear solves per step: after negative curvature, raise the local shifts and solve again.
// Circle and lake at 10⁴ and 10⁵: 1 or 6 solves took 587 or 499 evaluations against 513 for 3
// (the path changes, with no trend).
const CURVATURE_RETRIES: usize = 3;
/// Negative curvature is met at a few defects of the boundary layer, and raising σ for every
/// generator there would throttle the whole elastic relaxation. Instead the generators whose
/// share of the offending CG direction is at least `LOCAL_SHARE` of its largest get a shift of
/// their own: `LOCAL_START`·2m, ×4 at each new encounter, halved (`LOCAL_DECAY`) after every
/// step.
// Against a global σ at 10⁵ generators: circle 107 evaluations against 138, lake 160 against
// 242, annulus 134 against 243, with 0.02–0.25 % lower energy over Ω and ~3 % fewer boundary
// generators in every run tried; a decay of 0.25, 0.8 or 0.95 was no better.
const LOCAL_SHARE: f64 = 0.1;
const LOCAL_START: f64 = 0.1;
const LOCAL_DECAY: f64 = 0.5;
/// Where the spacing varies, the largest entries of the offending direction are the coarse
/// region's (a move of a tenth of a coarse cell is many fine ones), so the share of the
/// direction picks generators that carry no negative curvature at all: a graded L-shape at
/// 10⁴ generators shifted 1000–4800 of them per step and crept. There the carriers are the
/// generators whose own term p_r·(Ap)_r of the curvature pᵀAp is at most
/// `CURVATURE_SHARE` of the most negative term.
// Four graded cases at 10⁴ (circle, L-shape, square_hole, lake), seeds 1–6: 4684 → 3000
// evaluations and 129 → 81 s with 0.01; 0.001, 0.03 and 0.1 took 1835, 1785 and 2704
// evaluations on seeds 1–3 against 1325 (2303 with the share of the direction); at 10⁵ the
// L-shape 567 → 249, the circle 404 → 320. At K = 1500 (seeds 1–6) the rules are even: 5405 /
// 5554 evaluations, mean smallest angle 34.6° / 34.5°. On uniform regions the two rules are
// within the seed-to-seed spread (ten regions at 3·10⁴, seeds 1–2: 1663 / 1435 evaluations;
// circle and lake 10⁵, seeds 1–3: 629 / 688; circle 10⁶, seeds 1–2: 325 / 355 and 63.7 /
// 69.5 s), so uniform runs keep the share of the direction.
const CURVATURE_SHARE: f64 = 0.01;
/// Where the linear solve met negative curvature, the direction it met (restricted to the
/// allowed moves, signed to descend) is added to the Newton move, scaled so that its largest
/// move is this share of the local spacing. The shifts alone turn that direction into a damped
/// one: a boundary generator with a first-row generator standing over it is a saddle of the
/// constrained energy (`docs/design-notes.md`, "Saddles of the constrained energy"), and with
/// a shift of its own ×4 at each encounter the iterate leaves it by a few per cent per step,
/// while the largest move stays above the tolerance and active-set steps chase it.
// Whole command at 10⁵, seeds 1–8, interleaved: lake 2.37 → 2.03 s (173 → 125 evaluations),
// circle 1.48 → 1.54 s (103 → 96; the same time in its parts), the five measures within 3 %.
// Graded, four cases at 10⁴ (seeds 1–3): 2648 → 1857 evaluations, 21.2 → 19.7 s; three at
// 10⁵ (seed 1) 26.1 → 24.4 s. 0.05: lake 10⁵ (seeds 1–4) 537 evaluations, 0.2: 613, against
// 541 with 0.1 and 688 without; in global steps only, 0.3: 568.
const CURVATURE_STEP: f64 = 0.1;
/// In the cleanup after a global step (module `active`), active-set steps continue while the
/// count above the tolerance falls, and for this many steps more without a new low before a
/// global step; more patience lets active-set steps alone spread a smooth residual that one
/// global step removes.
// Circle 10⁶, seeds 1–3: 31.4 / 36.7 / 31.0 s with 3, 37.6 / 42.0 / 38.2 s with 0; 10 took
// 43 s on seed 1 (before the row start). Six, after the row start's looser ε-phases: 0.95 of
// the time over seeds (circle and lake 10⁵) but seed 1's circle took 81 evaluations against 70
// at 10⁵ and 183 against 146 at 10⁶ (docs/performance.md, "Toward 10× Triangle").
const CLEANUP_PATIENCE: usize = 3;

/// What a generator may do in the Newton step (8 bytes: at 10⁶ generators a copy of the
/// tangent data in every entry would be 40 MB more at the peak).
#[derive(Clone, Copy, PartialEq)]
enum Dof {
    /// Any move (interior generator).
    Free,
    /// Along the tangent of its piece: entry of `Buffers::tangents`.
    Tangent(u32),
    /// Goes to its Lloyd target (corner, or a label that changed).
    Fixed,
}

/// A boundary generator's unit tangent, piece and curvature vector d²γ/ds²: it moves along the
/// tangent, then back onto the piece.
#[derive(Clone, Copy)]
struct Tangent {
    t: DVec2,
    piece: PieceId,
    k: DVec2,
}

impl Dof {
    fn project(self, v: DVec2, tan: &[Tangent]) -> DVec2 {
        match self {
            Dof::Free => v,
            Dof::Tangent(i) => {
                let t = tan[i as usize].t;
                t * t.dot(v)
            }
            Dof::Fixed => DVec2::ZERO,
        }
    }
    fn matrix(self, tan: &[Tangent]) -> DMat2 {
        match self {
            Dof::Free => DMat2::IDENTITY,
            Dof::Tangent(i) => {
                let t = tan[i as usize].t;
                DMat2::from_cols(t * t.x, t * t.y)
            }
            Dof::Fixed => DMat2::ZERO,
        }
    }
}

/// Unit tangent and curvature vector d²γ/ds² of piece `j` at its point `z`, as Newton's method
/// takes them for a boundary generator (local spacing `spacing`): from projections onto the
/// piece of points 10⁻³ spacings either way, and of points a quarter spacing along the
/// tangent. The tangent's sign is arbitrary.
///
/// ```
/// use cvtmesh::ccvt::piece_tangent;
/// use cvtmesh::geometry::{DVec2, Region};
/// let circle = Region::builtin("circle")?; // the unit circle, one piece
/// let (t, k) = piece_tangent(&circle, DVec2::new(1.0, 0.0), 0, 0.01);
/// assert!((t.y.abs() - 1.0).abs() < 1e-9 && t.x.abs() < 1e-6);
/// // Curvature 1, toward the centre.
/// assert!((k - DVec2::new(-1.0, 0.0)).length() < 1e-4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn piece_tangent(region: &Region, z: DVec2, j: PieceId, spacing: f64) -> (DVec2, DVec2) {
    let along = |d: f64, e: DVec2| {
        (
            region.project_point_onto_piece(z + e * d, j),
            region.project_point_onto_piece(z - e * d, j),
        )
    };
    let d = 1e-3 * spacing;
    let ((a, b), (c, e)) = (along(d, DVec2::X), along(d, DVec2::Y));
    let t = if (a - b).length_squared() >= (c - e).length_squared() {
        a - b
    } else {
        c - e
    }
    .normalize_or_zero();
    // Over a quarter spacing (about a Newton step): the bend a polyline piece makes within a
    // step, not the spike at one of its vertices.
    let d = 0.25 * spacing;
    let (a, b) = along(d, t);
    (t, (a + b - 2.0 * z) / (d * d))
}

/// A row's generator, gathered once per step: rows are in vertex order and cells in input
/// order, so every pass that read the cells would miss the cache again.
#[derive(Clone, Copy)]
struct RowData {
    mass: f64,
    /// The energy's gradient 2m(z − c).
    grad: DVec2,
    /// σ plus the generator's own shift (relative to 2m).
    sigma: f64,
}

/// Memory reused from one Newton step to the next.
#[derive(Default)]
struct Buffers {
    hess: BlockMatrix,
    /// The other of the global Hessian and an active set's rows, swapped with `hess` around an
    /// active-set step: the global matrix keeps its arrays' length, and the next global step
    /// overwrites them instead of zeroing them again (120 MB at 10⁶ generators, on one thread).
    spare: BlockMatrix,
    /// Per Delaunay vertex.
    dofs: Vec<Dof>,
    tangents: Vec<Tangent>,
    /// Each generator's own shift (relative to 2m), by input index, as set after `local_at`
    /// steps; it has halved once per step since ([`shift_of`]), so that no step needs a pass
    /// over all K generators to halve them (an active-set step touches a few hundred).
    local: Vec<f64>,
    local_at: Vec<u32>,
    /// Newton steps (global and active-set) taken so far.
    steps: u32,
    rhs: Vec<DVec2>,
    x: Vec<DVec2>,
    cg: Vec<Vec<DVec2>>,
    rows: Vec<RowData>,
}

/// Generator i's own shift after `steps` Newton steps, set to `local[i]` after `local_at[i]`
/// of them and halved once per step since. Halving is exact until a value falls below the
/// smallest normal number, so this is the value repeated halving gives; beyond that (a shift
/// below 10⁻³⁰⁷, which neither σ nor the next raise can tell from 0) it may differ in its last
/// bits.
fn shift_of(local: &[f64], local_at: &[u32], steps: u32, i: usize) -> f64 {
    // Most generators never had a shift of their own: no power to take.
    if local[i] == 0.0 {
        return 0.0;
    }
    let k = steps - local_at[i];
    local[i] * LOCAL_DECAY.powi(k.min(2000) as i32)
}

/// Newton iteration of one phase; the same stopping rule and result as `iterate::run`.
pub fn run(phase: &Phase, mut z: Vec<DVec2>, work: &mut Work, trace: &mut Trace) -> PhaseResult {
    let mut buf = Buffers::default();
    let mut sigma = SIGMA_START;
    let mut s = step(phase, &z, work, &mut trace.prof);
    let mut iterations = 1;
    // In a cleanup by active-set steps: the fewest generators above the tolerance seen, and the
    // steps since that count last fell (None after any other step).
    let mut cleanup: Option<(usize, usize)> = None;
    // Work done, in evaluations of the whole map (an active-set step counts the share of the
    // generators it moves, at least `ACTIVE_WORK_FLOOR`); the smallest largest move so far and
    // the work done when it came.
    let mut spent = 1.0;
    let (mut best_move, mut best_spent) = (f64::INFINITY, 0.0);
    // Past the deadline (or cancelled) the first evaluation's targets, projected already, end
    // the phase.
    if phase.project_first && phase.max_iter > 1 && !phase.out_of_time() && !phase.cancelled() {
        // σ stays where it starts: after a rejected first candidate it would have quadrupled,
        // and a large σ confines the next steps to the boundary layer.
        record(phase, &s, &z, iterations, trace);
        (z, s) = lloyd(phase, s, work, &mut trace.prof);
        iterations += 1;
        spent += 1.0;
    }
    // The moves, kept up to date by blocks for the convergence test and the active sets (the
    // same largest move as `map::record`'s; Newton never runs VTM's update, whose measure of a
    // disc's moves differs).
    let mut moves = Moves::empty();
    loop {
        let t = Instant::now();
        moves.sync(&z, &mut s, &phase.scale);
        let mv = record_move(phase, &s, moves.largest(&phase.scale), iterations, trace, t);
        if mv < best_move {
            (best_move, best_spent) = (mv, spent);
        }
        let stalled = spent - best_spent >= STALL_EVALUATIONS as f64;
        if mv < phase.tol
            || iterations >= phase.max_iter
            || phase.cancelled()
            || phase.out_of_time()
            || stalled
        {
            return PhaseResult {
                z: s.targets,
                roles: s.roles,
                iterations,
                converged: mv < phase.tol,
                stalled: stalled && mv >= phase.tol,
            };
        }
        // An active-set step takes up to 3 evaluations. In the cleanup after a global step,
        // active-set steps continue while the count above the tolerance falls (with patience).
        let room = iterations + 3 <= phase.max_iter;
        if let Some(a) = room
            .then(|| active::active_set(phase, &z, &s, work, &moves, mv))
            .flatten()
            .filter(|a| {
                !a.cleanup
                    || cleanup
                        .is_none_or(|(best, stale)| a.above < best || stale < CLEANUP_PATIENCE)
            })
        {
            cleanup = a.cleanup.then(|| match cleanup {
                Some((best, stale)) if a.above >= best => (best, stale + 1),
                _ => (a.above, 0),
            });
            let taken = active_step(
                phase,
                &mut z,
                &mut s,
                work,
                &mut buf,
                &mut sigma,
                &a.set,
                &mut trace.prof,
            );
            iterations += taken;
            spent += taken as f64 * (a.set.len() as f64 / z.len() as f64).max(ACTIVE_WORK_FLOOR);
            continue;
        }
        cleanup = None;
        // σ ≥ 1: the shift dominates the Hessian, and a Newton step would be a damped Lloyd step
        // at the cost of two evaluations; take Lloyd's and let σ decay until Newton pays again.
        // With room for one evaluation only, the Lloyd step needs no fallback.
        if sigma >= SIGMA_LLOYD || iterations + 1 >= phase.max_iter {
            if sigma >= SIGMA_LLOYD {
                sigma *= 0.5;
            }
            (z, s) = lloyd(phase, s, work, &mut trace.prof);
            iterations += 1;
            spent += 1.0;
            continue;
        }
        let candidate = newton_point(phase, &z, &s, work, &mut buf, &mut sigma, &mut trace.prof);
        let next = step(phase, &candidate, work, &mut trace.prof);
        iterations += 1;
        spent += 1.0;
        if next.energy < s.energy {
            z = candidate;
            s = next;
            sigma = (sigma * 0.5).max(SIGMA_MIN);
        } else {
            trace.prof.rejected += 1;
            sigma = (sigma * 4.0).min(SIGMA_MAX);
            (z, s) = lloyd(phase, s, work, &mut trace.prof);
            iterations += 1;
            spent += 1.0;
        }
    }
}

/// The plain Lloyd step from the iterate whose map value is `s`: the new iterate and its map.
fn lloyd(phase: &Phase, s: Step, work: &mut Work, prof: &mut Profile) -> (Vec<DVec2>, Step) {
    let z = s.targets;
    let s = step(phase, &z, work, prof);
    (z, s)
}

/// The rows of a Newton step: every Delaunay vertex, or an active set (sorted vertices) with
/// every other generator held where it is.
#[derive(Clone, Copy)]
enum Rows<'a> {
    All(usize),
    Active(&'a [u32]),
}

impl Rows<'_> {
    fn len(self) -> usize {
        match self {
            Rows::All(n) => n,
            Rows::Active(a) => a.len(),
        }
    }
    fn vertex(self, r: usize) -> usize {
        match self {
            Rows::All(_) => r,
            Rows::Active(a) => a[r] as usize,
        }
    }
}

/// The Newton candidate from `z`, whose map value is `s` and whose triangulation and cells are
/// in `work`. Raises `sigma` when the shifted Hessian is not positive definite.
fn newton_point(
    phase: &Phase,
    z: &[DVec2],
    s: &Step,
    work: &mut Work,
    buf: &mut Buffers,
    sigma: &mut f64,
    prof: &mut Profile,
) -> Vec<DVec2> {
    let mut t = Instant::now();
    let (del, cells, grid) = work.parts(phase.domain);
    energy_hessian_on(del, grid, phase.density, cells, &mut buf.hess);
    prof.hessian += lap(&mut t);
    let work = &*work;
    let del = &work.del;
    newton_move(
        phase,
        z,
        s,
        work,
        Rows::All(del.num_vertices()),
        buf,
        sigma,
        prof,
    );
    let mut t = Instant::now();
    // A point without a Newton move (a duplicate) goes to its Lloyd target.
    let candidate = (0..z.len())
        .into_par_iter()
        .map(|i| match del.vertex_index(i) {
            Some(v) => moved_to(
                phase,
                (z[i], s.h(i, &phase.scale)),
                buf.x[v],
                buf.dofs[v],
                &buf.tangents,
                s.targets[i],
            ),
            None => s.targets[i],
        })
        .collect();
    prof.hessian += lap(&mut t);
    candidate
}

/// Where a generator at `z` (local spacing `h`) goes with the Newton move `x`: a long move is
/// shortened to the cap, and one that is not allowed (a fixed generator, a move out of the
/// domain) goes to its Lloyd target.
fn moved_to(
    phase: &Phase,
    (z, h): (DVec2, f64),
    x: DVec2,
    dof: Dof,
    tan: &[Tangent],
    target: DVec2,
) -> DVec2 {
    let p = z + x.clamp_length_max(STEP_CAP * h);
    match dof {
        Dof::Fixed => target,
        Dof::Free if phase.inside.contains(p) => p,
        Dof::Free => target,
        // Along the piece, but not past a bend of a sampled piece (see `newton_move`).
        Dof::Tangent(n) if p.is_finite() => {
            let piece = tan[n as usize].piece;
            let q = phase.region.project_point_onto_piece(p, piece);
            phase.region.chain_vertex_between(z, q, piece).unwrap_or(q)
        }
        Dof::Tangent(..) => target,
    }
}

/// An active-set step (module `active`): Newton on the active generators with every other one
/// held fixed, or the Lloyd step on them when σ ≥ 1 or the Newton step does not lower the
/// energy. Returns the evaluations it took.
#[allow(clippy::too_many_arguments)]
fn active_step(
    phase: &Phase,
    z: &mut [DVec2],
    s: &mut Step,
    work: &mut Work,
    buf: &mut Buffers,
    sigma: &mut f64,
    set: &[u32],
    prof: &mut Profile,
) -> usize {
    if *sigma >= SIGMA_LLOYD {
        *sigma *= 0.5;
        let m = active::lloyd_moves(z, s, work, set);
        active::apply(phase, z, s, work, &m, prof);
        return 1;
    }
    let mut t = Instant::now();
    let (del, cells, grid) = work.parts(phase.domain);
    std::mem::swap(&mut buf.hess, &mut buf.spare);
    energy_hessian_rows(del, grid, phase.density, cells, set, &mut buf.hess);
    prof.hessian += lap(&mut t);
    newton_move(phase, z, s, work, Rows::Active(set), buf, sigma, prof);
    std::mem::swap(&mut buf.hess, &mut buf.spare);
    let moves: Vec<(u32, DVec2)> = set
        .iter()
        .enumerate()
        .filter_map(|(r, &v)| {
            let i = work.del.point_of_vertex(v as usize);
            let p = moved_to(
                phase,
                (z[i], s.h(i, &phase.scale)),
                buf.x[r],
                buf.dofs[r],
                &buf.tangents,
                s.targets[i],
            );
            (p != z[i]).then_some((i as u32, p))
        })
        .collect();
    let e0 = s.energy;
    let undo = active::apply(phase, z, s, work, &moves, prof);
    if s.energy < e0 {
        *sigma = (*sigma * 0.5).max(SIGMA_MIN);
        return 1;
    }
    prof.rejected += 1;
    *sigma = (*sigma * 4.0).min(SIGMA_MAX);
    active::apply(phase, z, s, work, &undo, prof);
    let m = active::lloyd_moves(z, s, work, set);
    active::apply(phase, z, s, work, &m, prof);
    3
}

/// Newton's move for the rows `rows` (whose Hessian block is in `buf.hess`), left in `buf.x`
/// with the rows' degrees of freedom in `buf.dofs` and `buf.tangents`. Raises `sigma` when the
/// shifted Hessian is not positive definite.
#[allow(clippy::too_many_arguments)]
fn newton_move(
    phase: &Phase,
    z: &[DVec2],
    s: &Step,
    work: &Work,
    rows: Rows,
    buf: &mut Buffers,
    sigma: &mut f64,
    prof: &mut Profile,
) {
    let mut t = Instant::now();
    let (del, cells) = (&work.del, &work.cells.cells);
    let n = rows.len();
    let pt = |r: usize| del.point_of_vertex(rows.vertex(r));
    let region = phase.region;
    buf.local.resize(z.len(), 0.0);
    buf.local_at.resize(z.len(), 0);
    let (local, local_at, steps, sig) = (&buf.local, &buf.local_at, buf.steps, *sigma);
    // Boundary generators on their piece (and not at a corner) move along it; `Tangent(0)`
    // marks them until their tangents are numbered.
    (0..n)
        .into_par_iter()
        .map(|r| {
            let i = pt(r);
            let (p, c) = (z[i], &cells[i]);
            let data = RowData {
                mass: c.mass,
                grad: 2.0 * c.mass * (p - c.mass_centroid),
                sigma: sig + shift_of(local, local_at, steps, i),
            };
            if c.mass <= 0.0 {
                return (Dof::Fixed, data);
            }
            let dof = match s.roles[i] {
                Role::Corner(_) | Role::Embedded(_) => Dof::Fixed,
                // At a bend of a sampled piece, or with one between it and its Lloyd target,
                // the energy along the piece has a kink that a Newton step oversteps (the
                // generator swings across the chain vertex and back): Lloyd's projection
                // instead.
                Role::Boundary(j) => {
                    let bp = region.project_onto_piece(p, j);
                    if bp.distance <= 1e-9 * phase.spacing
                        && bp.corner.is_none()
                        && region.chain_vertex_between(p, s.targets[i], j).is_none()
                    {
                        Dof::Tangent(0)
                    } else {
                        Dof::Fixed
                    }
                }
                Role::Interior if phase.inside.contains(p) => Dof::Free,
                Role::Interior => Dof::Fixed,
            };
            (dof, data)
        })
        .unzip_into_vecs(&mut buf.dofs, &mut buf.rows);
    let on_piece: Vec<u32> = (0..n as u32)
        .filter(|&r| buf.dofs[r as usize] == Dof::Tangent(0))
        .collect();
    on_piece
        .par_iter()
        .map(|&r| {
            let (i, Role::Boundary(piece)) = (pt(r as usize), s.roles[pt(r as usize)]) else {
                unreachable!("tangent dofs are boundary generators")
            };
            let (t, k) = piece_tangent(region, z[i], piece, s.h(i, &phase.scale));
            Tangent { t, piece, k }
        })
        .collect_into_vec(&mut buf.tangents);
    for (k, &r) in on_piece.iter().enumerate() {
        buf.dofs[r as usize] = Dof::Tangent(k as u32);
    }
    let (dofs, tan) = (&buf.dofs, &buf.tangents);
    // rhs = −P (g + H d_fixed), with the fixed generators' prescribed moves d_fixed (in x,
    // which the linear solve overwrites).
    (0..n)
        .into_par_iter()
        .map(|r| match dofs[r] {
            Dof::Fixed => s.targets[pt(r)] - z[pt(r)],
            _ => DVec2::ZERO,
        })
        .collect_into_vec(&mut buf.x);
    newton_rhs(&buf.hess, dofs, tan, &buf.rows, &buf.x, &mut buf.rhs);
    shift(&mut buf.hess, dofs, tan, &buf.rows);
    // Not kept through the solve: 32 MB at 10⁶ generators, where the solve is near the peak.
    buf.rows = Vec::new();
    prof.hessian += lap(&mut t);
    // The direction of negative curvature the first solve met, if any.
    let mut descent: Option<Vec<DVec2>> = None;
    for attempt in 0..=CURVATURE_RETRIES {
        let h = &buf.hess;
        // Block Jacobi (the 2×2 inverses recomputed on the fly from the diagonal, read in order).
        let (negative, its) = pcg(h, &buf.rhs, &mut buf.x, &mut buf.cg, |r, v| {
            h.diagonal(r).inverse() * v
        });
        prof.linear_iterations += its;
        if negative && descent.is_none() {
            descent = Some(buf.cg[2].par_iter().copied().collect());
        }
        if !negative || attempt == CURVATURE_RETRIES {
            break;
        }
        // Negative curvature along the CG direction p (`cg[2]`): raise the shift of the
        // generators that carry it, and solve again.
        let carriers = curvature_carriers(&buf.cg[2], &buf.cg[3], phase.density.is_uniform());
        for r in carriers {
            let i = pt(r);
            let old = shift_of(&buf.local, &buf.local_at, buf.steps, i);
            buf.local[i] = (old * 4.0).max(LOCAL_START);
            buf.local_at[i] = buf.steps;
            let add = (buf.local[i] - old) * 2.0 * cells[i].mass;
            buf.hess.diag[r] += buf.dofs[r].matrix(&buf.tangents) * add;
        }
    }
    if let Some(p) = descent {
        let h: Vec<f64> = (0..n)
            .into_par_iter()
            .map(|r| s.h(pt(r), &phase.scale))
            .collect();
        add_curvature_step(&mut buf.x, p, &buf.rhs, &buf.dofs, &buf.tangents, &h);
    }
    // The solver's work vectors are not kept for the next step: at 10⁶ generators they are
    // 64 MB more at the memory peak (a fresh triangulation of the candidate), and allocating
    // them again costs ~1 % of a step.
    buf.cg = Vec::new();
    buf.steps += 1;
    prof.linear_solve += lap(&mut t);
}

/// Newton's right-hand side −P (g + H d) for the rows' gradients g and the moves `d` of the
/// fixed rows (zero in every other row), into `rhs`. H d is zero but in the rows of the fixed rows'
/// neighbours (a fixed row's own entry is projected away), so the product is taken there only,
/// not over the whole matrix; elsewhere the entry is −P g, as the full product gives it.
fn newton_rhs(
    hess: &BlockMatrix,
    dofs: &[Dof],
    tan: &[Tangent],
    rows: &[RowData],
    d: &[DVec2],
    rhs: &mut Vec<DVec2>,
) {
    let n = dofs.len();
    let fixed: Vec<usize> = (0..n)
        .into_par_iter()
        .filter(|&r| dofs[r] == Dof::Fixed)
        .collect();
    let mut near_fixed = vec![false; n];
    for r in fixed {
        for &c in &hess.col[hess.row_start[r]..hess.row_start[r + 1]] {
            near_fixed[c as usize] = true;
        }
    }
    (0..n)
        .into_par_iter()
        .map(|r| {
            let g = if near_fixed[r] {
                rows[r].grad + hess.row_times(r, d)
            } else {
                rows[r].grad
            };
            -dofs[r].project(g, tan)
        })
        .collect_into_vec(rhs);
}

/// Adds to the move `x` the direction of negative curvature `p` (one entry per row),
/// restricted to each row's allowed moves, turned to point down the energy (along `rhs`, the
/// negative projected gradient) and scaled so that its largest move is `CURVATURE_STEP` of
/// the row's local spacing `h`. A direction with no allowed move, or with an entry that is not
/// finite, adds nothing.
fn add_curvature_step(
    x: &mut [DVec2],
    mut p: Vec<DVec2>,
    rhs: &[DVec2],
    dofs: &[Dof],
    tan: &[Tangent],
    h: &[f64],
) {
    // CG reports a direction it could not measure (pᵀAp not finite) as negative curvature too.
    if p.iter().any(|q| !q.is_finite()) {
        return;
    }
    for (q, d) in p.iter_mut().zip(dofs) {
        *q = d.project(*q, tan);
    }
    let largest = p
        .iter()
        .zip(h)
        .map(|(q, h)| q.length() / h)
        .fold(0.0, f64::max);
    if !(largest > 0.0 && largest.is_finite()) {
        return;
    }
    let down = if dot(&p, rhs) < 0.0 { -1.0 } else { 1.0 };
    let alpha = down * CURVATURE_STEP / largest;
    for (x, q) in x.iter_mut().zip(&p) {
        *x += *q * alpha;
    }
}

/// The rows that carry the negative curvature pᵀAp ≤ 0 met along the CG direction `p` (with
/// `ap` = A p): those whose share of `p` is at least `LOCAL_SHARE` of the largest (`uniform`),
/// else those whose term p_r·(Ap)_r is at most `CURVATURE_SHARE` of the most negative term
/// (the share of `p` when no term is negative, as where pᵀAp was not finite).
fn curvature_carriers(p: &[DVec2], ap: &[DVec2], uniform: bool) -> Vec<usize> {
    if !uniform {
        let least = p
            .iter()
            .zip(ap)
            .map(|(p, ap)| p.dot(*ap))
            .fold(0.0f64, f64::min);
        if least < 0.0 {
            return (0..p.len())
                .filter(|&r| p[r].dot(ap[r]) <= CURVATURE_SHARE * least)
                .collect();
        }
    }
    let pmax = p.iter().fold(0.0f64, |m, q| m.max(q.length()));
    (0..p.len())
        .filter(|&r| p[r].length() >= LOCAL_SHARE * pmax)
        .collect()
}

/// Turn the Hessian into A = P H P + σ·2m·P + 2m·(I − P) (+ the curvature term of boundary
/// generators, + a floor on each diagonal block): symmetric, the identity's multiple on moves a
/// generator may not make, and positive definite wherever the shift suffices.
fn shift(h: &mut BlockMatrix, dofs: &[Dof], tan: &[Tangent], rows: &[RowData]) {
    h.par_rows_mut(
        || (),
        |_, v, diagonal, col, block| {
            let pv = dofs[v].matrix(tan);
            for (j, b) in col.iter().zip(block.iter_mut()) {
                // P = I for the (many) free generators.
                if !matches!((dofs[v], dofs[*j as usize]), (Dof::Free, Dof::Free)) {
                    *b = (pv * b.as_dmat2() * dofs[*j as usize].matrix(tan)).as_mat2();
                }
            }
            let mut d = pv * *diagonal * pv;
            let row = &rows[v];
            let m2 = (2.0 * row.mass).max(f64::MIN_POSITIVE);
            d += pv * (row.sigma * m2) + (DMat2::IDENTITY - pv) * m2;
            // Along a curved piece the second derivative of the energy also has g · γ''.
            if let Dof::Tangent(n) = dofs[v] {
                d += pv * row.grad.dot(tan[n as usize].k);
            }
            // Two close generators with a long common edge make their diagonal blocks
            // indefinite (a saddle): lift each to a least eigenvalue of BLOCK_FLOOR·2m.
            let lowest = match dofs[v] {
                Dof::Free => {
                    let (a, c, e) = (d.x_axis.x, 0.5 * (d.x_axis.y + d.y_axis.x), d.y_axis.y);
                    0.5 * (a + e) - (0.25 * (a - e) * (a - e) + c * c).sqrt()
                }
                Dof::Tangent(n) => {
                    let t = tan[n as usize].t;
                    t.dot(d * t)
                }
                Dof::Fixed => f64::INFINITY,
            };
            let floor = BLOCK_FLOOR * m2;
            if lowest < floor {
                d += pv * (floor - lowest);
            }
            *diagonal = d;
        },
    );
}

/// Preconditioned conjugate gradients for A x = b from x = 0, to a relative residual of
/// `CG_TOL`; stops early at a direction of non-positive curvature, left in `work[2]` with A
/// times it in `work[3]`. Returns whether it met one, and the number of iterations.
fn pcg(
    a: &BlockMatrix,
    b: &[DVec2],
    x: &mut Vec<DVec2>,
    work: &mut Vec<Vec<DVec2>>,
    precond: impl Fn(usize, DVec2) -> DVec2 + Sync,
) -> (bool, usize) {
    let n = b.len();
    // Each vector is written in parallel with its first values: at 10⁶ generators they are
    // fresh memory (dropped after every solve), whose pages one thread alone would fault in.
    let zeros = |v: &mut Vec<DVec2>| {
        (0..n)
            .into_par_iter()
            .map(|_| DVec2::ZERO)
            .collect_into_vec(v)
    };
    zeros(x);
    work.resize_with(4, Vec::new);
    let [r, zv, p, ap] = &mut work[..] else {
        unreachable!("four vectors")
    };
    b.par_iter().copied().collect_into_vec(r);
    zeros(ap);
    (0..n)
        .into_par_iter()
        .map(|i| precond(i, b[i]))
        .collect_into_vec(zv);
    zv.par_iter().copied().collect_into_vec(p);
    let b_norm = dot(b, b).sqrt();
    if b_norm == 0.0 || !b_norm.is_finite() {
        return (false, 0);
    }
    let mut rz = dot(r, zv);
    // Each iteration is three passes over the vectors (memory bandwidth is the cost): A p with
    // p·Ap; the x and r updates with r·r, z = M⁻¹ r and r·z; the new direction. Dot products
    // are summed per fixed chunk, then in chunk order, as `dot` does.
    let ordered = |partial: Vec<f64>| partial.iter().sum::<f64>();
    for it in 1..=CG_MAX {
        let p_ = &*p;
        let pap = ordered(
            ap.par_chunks_mut(DOT_CHUNK)
                .enumerate()
                .map(|(c, ap)| {
                    let base = c * DOT_CHUNK;
                    for (k, o) in ap.iter_mut().enumerate() {
                        *o = a.row_times(base + k, p_);
                    }
                    p_[base..base + ap.len()]
                        .iter()
                        .zip(ap.iter())
                        .map(|(p, q)| p.dot(*q))
                        .sum()
                })
                .collect(),
        );
        if pap <= 0.0 || !pap.is_finite() {
            return (true, it);
        }
        let alpha = rz / pap;
        let (rr, rz_new): (Vec<f64>, Vec<f64>) = r
            .par_chunks_mut(DOT_CHUNK)
            .zip(zv.par_chunks_mut(DOT_CHUNK))
            .zip(ap.par_chunks(DOT_CHUNK))
            .enumerate()
            .map(|(c, ((r, z), ap))| {
                for k in 0..r.len() {
                    r[k] -= ap[k] * alpha;
                    z[k] = precond(c * DOT_CHUNK + k, r[k]);
                }
                (
                    r.iter().zip(r.iter()).map(|(p, q)| p.dot(*q)).sum::<f64>(),
                    r.iter().zip(z.iter()).map(|(p, q)| p.dot(*q)).sum::<f64>(),
                )
            })
            .unzip();
        // x += α p waits for the pass that reads p anyway (the new direction's), where it
        // costs no read of its own; or, at the end, a pass of its own.
        if ordered(rr).sqrt() <= CG_TOL * b_norm || it == CG_MAX {
            x.par_iter_mut()
                .zip(p.par_iter())
                .for_each(|(x, p)| *x += *p * alpha);
            return (false, it);
        }
        let rz_new = ordered(rz_new);
        let beta = rz_new / rz;
        rz = rz_new;
        x.par_iter_mut()
            .zip(p.par_iter_mut())
            .zip(zv.par_iter())
            .for_each(|((x, p), z)| {
                *x += *p * alpha;
                *p = *z + *p * beta;
            });
    }
    (false, CG_MAX)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::active::tests::test_phase;
    use crate::sublevel::Sublevel;
    use geometry::{Density, Region};
    use mesh::MeshRequest;

    /// Algorithm 2's constrained phase starts from the CVT of Ω_ε, whose boundary generators lie
    /// outside Ω. Without `project_first` its second evaluation is a Newton candidate (a linear
    /// solve first); with it, the projection: no linear solve before the phase's last
    /// evaluation (a Lloyd step, for want of room), and every boundary generator on ∂Ω.
    #[test]
    fn a_start_off_the_boundary_is_projected_before_any_newton_step() {
        let region = Region::builtin("circle").unwrap();
        let k = 4000;
        let h = MeshRequest::points(k).spacing(&region);
        let (eps, tol_poly) = (crate::start::ROW_EPS * h, 1e-4 * h);
        let density = Density::Uniform;
        let trace_of = |phase: &Phase, z: Vec<DVec2>| {
            let mut progress = |_| {};
            let mut trace = Trace {
                energies: Vec::new(),
                moves: Vec::new(),
                progress: &mut progress,
                prof: Profile::default(),
            };
            let mut work = Work::new(phase.domain);
            let r = run(phase, z, &mut work, &mut trace);
            (r, trace.prof)
        };
        // The row start's CVT of Ω_ε.
        let start = crate::start::boundary_row(&region, k, h, crate::start::ROW_EPS, 1).unwrap();
        let omega_eps = region.expand(eps, tol_poly);
        let inside_eps = Sublevel::new(&region, eps - 2.0 * tol_poly, 3.0 * h);
        let eps_phase = Phase {
            tol: 1e-3,
            max_iter: 500,
            ..test_phase(&region, &omega_eps, &inside_eps, &density, false, h)
        };
        let (cvt, _) = trace_of(&eps_phase, start);
        let omega = region.polygonize(tol_poly);
        let inside = Sublevel::new(&region, 0.0, 3.0 * h);
        for project_first in [false, true] {
            let phase = Phase {
                project_first,
                max_iter: 3,
                ..test_phase(&region, &omega, &inside, &density, true, h)
            };
            let (r, prof) = trace_of(&phase, cvt.z.clone());
            assert_eq!(prof.evaluations, 3, "project first: {project_first}");
            assert_eq!(
                prof.linear_iterations == 0,
                project_first,
                "project first: {project_first}, {} CG iterations",
                prof.linear_iterations
            );
            let off = r
                .roles
                .iter()
                .zip(&r.z)
                .filter(|(role, _)| matches!(role, Role::Boundary(_)))
                .map(|(_, p)| region.signed_distance(*p).abs())
                .fold(0.0, f64::max);
            assert!(off < 1e-9 * h, "a boundary generator {off:e} off ∂Ω");
        }
    }

    /// A chain of n points with springs of stiffness `k` between neighbours and `mass` added to
    /// the diagonal, as a block matrix: positive definite for mass > 0, indefinite for mass < 0.
    fn chain(n: usize, k: f64, mass: f64) -> BlockMatrix {
        let mut a = BlockMatrix::default();
        a.row_start.push(0);
        for i in 0..n {
            let mut diag = mass;
            let mut row = Vec::new();
            for j in [i.wrapping_sub(1), i + 1] {
                if j < n {
                    diag += k;
                    row.push((j as u32, DMat2::from_diagonal(DVec2::new(-k, -0.5 * k))));
                }
            }
            a.diag.push(DMat2::from_diagonal(DVec2::new(
                diag,
                diag - 0.5 * (diag - mass),
            )));
            for (j, b) in row {
                a.col.push(j);
                a.block.push(b.as_mat2());
            }
            a.row_start.push(a.col.len());
        }
        a
    }

    fn jacobi(a: &BlockMatrix) -> impl Fn(usize, DVec2) -> DVec2 + Sync + '_ {
        move |i, r| a.diagonal(i).inverse() * r
    }

    #[test]
    fn pcg_reaches_its_tolerance_on_a_positive_definite_system() {
        let a = chain(500, 1.0, 0.5);
        let b: Vec<DVec2> = (0..500)
            .map(|i| DVec2::new((i as f64 * 0.1).sin(), (i % 7) as f64 - 3.0))
            .collect();
        let (mut x, mut work) = (Vec::new(), Vec::new());
        let (negative, its) = pcg(&a, &b, &mut x, &mut work, jacobi(&a));
        assert!(!negative);
        assert!(its > 1 && its <= CG_MAX, "{its} iterations");
        let mut ax = vec![DVec2::ZERO; 500];
        a.mul_vec(&x, &mut ax);
        let r: Vec<DVec2> = ax.iter().zip(&b).map(|(p, q)| *p - *q).collect();
        assert!(dot(&r, &r).sqrt() <= CG_TOL * dot(&b, &b).sqrt() * (1.0 + 1e-9));
    }

    /// The solve is textbook preconditioned CG operation for operation (its passes only fuse
    /// them, and x's update waits for the pass that reads p): the same iterate bit for bit,
    /// whether it stops at its tolerance or at the iteration cap.
    #[test]
    fn pcg_is_the_textbook_iteration_bit_for_bit() {
        for (n, mass, capped) in [(300, 0.5, false), (9000, 1e-4, true)] {
            let a = chain(n, 1.0, mass);
            let b: Vec<DVec2> = (0..n)
                .map(|i| DVec2::new((i as f64 * 0.37).sin(), (i % 11) as f64 - 5.0))
                .collect();
            let (mut x, mut work) = (Vec::new(), Vec::new());
            let (negative, its) = pcg(&a, &b, &mut x, &mut work, jacobi(&a));
            assert!(!negative);
            let pre = jacobi(&a);
            let mut xr = vec![DVec2::ZERO; n];
            let mut r = b.clone();
            let mut z: Vec<DVec2> = (0..n).map(|i| pre(i, r[i])).collect();
            let mut p = z.clone();
            let mut ap = vec![DVec2::ZERO; n];
            let mut rz = dot(&r, &z);
            let mut taken = CG_MAX;
            for it in 1..=CG_MAX {
                a.mul_vec(&p, &mut ap);
                let alpha = rz / dot(&p, &ap);
                for i in 0..n {
                    xr[i] += p[i] * alpha;
                    r[i] -= ap[i] * alpha;
                    z[i] = pre(i, r[i]);
                }
                if dot(&r, &r).sqrt() <= CG_TOL * dot(&b, &b).sqrt() {
                    taken = it;
                    break;
                }
                let rz_new = dot(&r, &z);
                let beta = rz_new / rz;
                rz = rz_new;
                for i in 0..n {
                    p[i] = z[i] + p[i] * beta;
                }
            }
            assert_eq!(its, taken);
            assert_eq!(its == CG_MAX, capped, "{its} iterations");
            let bits = |v: &[DVec2]| -> Vec<[u64; 2]> {
                v.iter().map(|v| [v.x.to_bits(), v.y.to_bits()]).collect()
            };
            assert_eq!(bits(&x), bits(&xr));
        }
    }

    /// The right-hand side takes H d only in the rows next to a fixed row, and is what the full
    /// product gives in every row.
    #[test]
    fn the_right_hand_side_is_the_full_product_where_it_matters() {
        let n = 400;
        let a = chain(n, 1.0, 0.5);
        let tan = [Tangent {
            t: DVec2::new(0.6, 0.8),
            piece: 0,
            k: DVec2::ZERO,
        }];
        let dofs: Vec<Dof> = (0..n)
            .map(|i| match i % 37 {
                0 | 5 => Dof::Fixed,
                3 | 9 => Dof::Tangent(0),
                _ => Dof::Free,
            })
            .collect();
        let rows: Vec<RowData> = (0..n)
            .map(|i| RowData {
                mass: 1.0,
                grad: DVec2::new((i as f64).cos(), 0.25 * (i % 5) as f64 - 0.5),
                sigma: 0.0,
            })
            .collect();
        let d: Vec<DVec2> = (0..n)
            .map(|i| match dofs[i] {
                Dof::Fixed => DVec2::new(0.1 * i as f64, -0.3),
                _ => DVec2::ZERO,
            })
            .collect();
        let mut rhs = Vec::new();
        newton_rhs(&a, &dofs, &tan, &rows, &d, &mut rhs);
        let mut hd = vec![DVec2::ZERO; n];
        a.mul_vec(&d, &mut hd);
        for r in 0..n {
            let full = -dofs[r].project(rows[r].grad + hd[r], &tan);
            assert_eq!(rhs[r], full, "row {r}");
        }
        // The rows next to a fixed row do take H d.
        assert_ne!(rhs[1], -rows[1].grad);
        assert_eq!(rhs[2], -rows[2].grad);
    }

    /// The step along negative curvature: nothing for a fixed generator, only the tangent for
    /// one on a piece, downhill, and its largest move `CURVATURE_STEP` of that row's spacing.
    #[test]
    fn the_curvature_step_goes_downhill_within_the_allowed_moves() {
        let tan = [Tangent {
            t: DVec2::X,
            piece: 0,
            k: DVec2::ZERO,
        }];
        let dofs = [Dof::Free, Dof::Tangent(0), Dof::Fixed];
        let h = [1.0, 2.0, 1.0];
        let p = vec![
            DVec2::new(0.3, 0.4),
            DVec2::new(2.0, 5.0),
            DVec2::new(9.0, 9.0),
        ];
        // The direction as given climbs: the step must turn it round.
        let rhs = [DVec2::new(-1.0, 0.0), DVec2::new(-1.0, 0.0), DVec2::ZERO];
        assert!(dot(&p, &rhs) < 0.0);
        let mut x = vec![DVec2::new(1.0, 1.0); 3];
        add_curvature_step(&mut x, p, &rhs, &dofs, &tan, &h);
        let step: Vec<DVec2> = x.iter().map(|x| *x - DVec2::new(1.0, 1.0)).collect();
        assert_eq!(step[2], DVec2::ZERO, "a fixed generator does not move");
        assert_eq!(
            step[1].y, 0.0,
            "a generator on a piece moves along its tangent"
        );
        assert!(dot(&step, &rhs) > 0.0, "downhill");
        // Row 1's allowed move (2, 0) over h = 2 is the largest: 0.1 of its spacing.
        assert!((step[1].length() / h[1] - CURVATURE_STEP).abs() < 1e-15);
        assert!((step[0].length() / h[0]) < CURVATURE_STEP);
        assert!((step[0] / step[0].length() - DVec2::new(-0.6, -0.8)).length() < 1e-15);

        // No allowed move, or no finite one: nothing added.
        for p in [
            vec![DVec2::ZERO, DVec2::new(0.0, 3.0), DVec2::ONE],
            vec![DVec2::new(f64::NAN, 0.0), DVec2::ZERO, DVec2::ZERO],
            vec![
                DVec2::new(0.3, 0.4),
                DVec2::new(f64::INFINITY, 1.0),
                DVec2::ZERO,
            ],
        ] {
            let mut x = vec![DVec2::ONE; 3];
            add_curvature_step(&mut x, p, &rhs, &dofs, &tan, &h);
            assert_eq!(x, vec![DVec2::ONE; 3]);
        }
    }

    #[test]
    fn shifts_halved_when_read_are_the_shifts_halved_every_step() {
        for x in [0.1, 0.4, 1638.4, 3.7e5, 1e-300] {
            let mut eager = x;
            for k in 0..2100u32 {
                let lazy = shift_of(&[x], &[7], 7 + k, 0);
                if eager >= f64::MIN_POSITIVE {
                    assert_eq!(lazy.to_bits(), eager.to_bits(), "{x} after {k} steps");
                } else {
                    assert!(lazy < 1e-300 && eager < 1e-300, "{x} after {k} steps");
                }
                eager *= LOCAL_DECAY;
            }
            assert_eq!(eager, 0.0);
            assert_eq!(shift_of(&[x], &[0], 3000, 0), 0.0);
        }
    }

    #[test]
    fn pcg_reports_negative_curvature() {
        // A negative mass makes the smooth modes of the chain directions of negative curvature.
        let a = chain(200, 1.0, -0.05);
        let b = vec![DVec2::new(1.0, 1.0); 200];
        let (mut x, mut work) = (Vec::new(), Vec::new());
        let (negative, _) = pcg(&a, &b, &mut x, &mut work, |_, r| r);
        assert!(negative);
        assert!(x.iter().all(|p| p.is_finite()));
    }

    #[test]
    fn the_carriers_of_negative_curvature_are_where_it_is_not_where_the_moves_are_longest() {
        // Five coarse rows with long moves and positive curvature, three fine ones with short
        // moves and negative curvature.
        let mut p = vec![DVec2::new(10.0, 0.0); 5];
        let mut ap = vec![DVec2::new(1.0, 0.0); 5];
        p.extend([DVec2::new(0.0, 0.1); 3]);
        ap.extend([DVec2::new(0.0, -2.0); 3]);
        assert_eq!(curvature_carriers(&p, &ap, false), vec![5, 6, 7]);
        // On a uniform region the share of the direction decides.
        assert_eq!(curvature_carriers(&p, &ap, true), vec![0, 1, 2, 3, 4]);
        // With no negative term, the share of the direction.
        let positive = vec![DVec2::new(1.0, 0.0); 8];
        assert_eq!(
            curvature_carriers(&p, &positive, false),
            vec![0, 1, 2, 3, 4]
        );
    }

    #[test]
    fn negative_curvature_met_by_pcg_is_carried_by_the_indefinite_rows() {
        // A positive definite chain with one indefinite block at row 100.
        let mut a = chain(200, 1.0, 0.5);
        a.diag[100] = DMat2::from_diagonal(DVec2::new(-3.0, -3.0));
        let b = vec![DVec2::new(1.0, 0.5); 200];
        let (mut x, mut work) = (Vec::new(), Vec::new());
        let (negative, _) = pcg(&a, &b, &mut x, &mut work, |_, r| r);
        assert!(negative);
        let carriers = curvature_carriers(&work[2], &work[3], false);
        assert!(carriers.contains(&100), "{carriers:?}");
        assert!(
            carriers.iter().all(|r| r.abs_diff(100) <= 3),
            "{carriers:?}"
        );
    }

    #[test]
    fn tangent_and_curvature_of_the_unit_circle() {
        let region = Region::builtin("circle").unwrap();
        let z = DVec2::from_angle(0.7);
        let j = region.project(z).piece;
        let (t, k) = piece_tangent(&region, z, j, 0.01);
        assert!(
            t.dot(z).abs() < 1e-6,
            "tangent {t} not perpendicular to {z}"
        );
        assert!((t.length() - 1.0).abs() < 1e-12);
        // d²γ/ds² = −z / R² on a circle of radius 1.
        assert!((k + z).length() < 1e-3, "curvature vector {k}");
    }
}
