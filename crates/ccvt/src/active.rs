//! Active-set steps. Late in a phase only a few hundred of 10⁵–10⁶ generators still move more
//! than the tolerance (rearrangements in the boundary layer), yet a full step re-triangulates and
//! re-clips every cell. An active-set step moves only the defects (generators whose move exceeds
//! `DEFECT_SHARE` of the largest), with `MARGIN_RINGS` rings of Delaunay neighbours, holds
//! every other one fixed, repairs the triangulation around the moved vertices (flips around
//! each, or its removal and reinsertion) and recomputes only the cells that changed:
//! O(active) per step instead of O(K).
//!
//! The stopping rule stays exact: a cell none of whose Voronoi neighbours (before or after)
//! moved is the same cell, so its generator's move is the one already known.
use crate::map::{assign_fixed, lap, map_cell, step, Phase, Profile, Step, Work};
use crate::moves::Moves;
use geometry::DVec2;
use rayon::prelude::*;
use std::time::Instant;
use tessellation::update_cells;

/// A generator is active when its move exceeds this fraction of the largest move (and half
/// the tolerance): the defects, not the smooth halo around them.
const DEFECT_SHARE: f64 = 0.1;
/// Below this many tolerances of largest move, what is left is mostly a smooth elastic residual
/// that only a global Newton step removes at once: active-set steps alone spread it like
/// Gauss–Seidel. There they are only a cleanup after a global step, taken while they lower the
/// count above the tolerance.
// Circle 10⁵: active-set steps alone took 200 steps at 1.5–3 tolerances.
const DEFECT_ABOVE: f64 = 4.0;
/// Rings of Delaunay neighbours around the active generators that move with them (room for the
/// Newton step to spread a rearrangement).
const MARGIN_RINGS: usize = 2;
/// Active-set steps only while the generators that move more than `DEFECT_GATE` tolerances
/// are at most this share of all: before that, a global relaxation is still under way and
/// active-set steps stall.
// At 1.6 % active, active-set steps stalled at circle 10⁵.
pub(crate) const ACTIVE_SHARE: f64 = 0.01;
/// The share in the ε-phase from the boundary row start. That start is the lattice's CVT
/// inside a row: what moves at first is the seam between the two, a few rows wide, which
/// active-set steps relax for a fraction of a global step's cost. The lattice path's
/// ε-phases dilate the whole lattice first, a global relaxation, and keep `ACTIVE_SHARE`.
// Circle 10⁵, seed 1: the ε-phase 0.62 → 0.27 s (62 → 27 evaluations); at 10⁶ 3.5 → 1.7 s.
pub(crate) const ACTIVE_SHARE_FROM_ROW: f64 = 0.05;
/// A move counts toward the active share only above this many tolerances. A relaxation ends
/// with dislocations that glide a few hundredths of a spacing per step, each with a halo of
/// generators just above the tolerance; counting the halos kept runs in global steps for
/// dozens of evaluations. Counted this way, the defects take active-set steps and the halos
/// are left to the cleanup and the global steps; the stopping rule is the same.
// Four graded cases at K = 10⁴, seeds 1–3 / 4–6: 18.9 → 15.8 s / 22.3 → 16.9 s with 30 (10:
// 15.9 / 19.9 s, 100: 16.2 / 18.4 s); at 10⁵, seeds 1 and 2, 41.0 → 34.2 s and 48.3 → 39.9 s
// (10: 51.3 s for seed 1; 100: 36.4 s for seed 2, with a lower efficiency on two cases).
// Uniform circle and lake 10⁵, 12 seeds each: 1.81 → 1.61 s and 2.37 → 2.13 s with λ, γ, β,
// q and p within 1.5 % of the means counted at the tolerance (10 tolerances: 8 % and 7 %).
const DEFECT_GATE: f64 = 30.0;

/// An active-set step on offer.
pub(crate) struct Active {
    /// The Delaunay vertices it moves (sorted).
    pub set: Vec<u32>,
    /// Generators moving more than `DEFECT_GATE` tolerances.
    pub above: usize,
    /// The largest move is below `DEFECT_ABOVE` tolerances (a cleanup after a global step).
    pub cleanup: bool,
}

/// The active-set step at this iterate, or None when the phase is too small for active-set
/// steps or too many generators are active.
pub(crate) fn active_set(
    phase: &Phase,
    z: &[DVec2],
    s: &Step,
    work: &Work,
    moves: &Moves,
    max_move: f64,
) -> Option<Active> {
    let k = z.len();
    if k < phase.active_from {
        return None;
    }
    let del = &work.del;
    let cap = (phase.active_share * k as f64) as usize;
    // Relative to the local spacing, as the convergence test measures moves.
    let tol2 = phase.tol.powi(2);
    let gate2 = DEFECT_GATE.powi(2) * tol2;
    let thr2 = (DEFECT_SHARE * max_move).max(0.5 * phase.tol).powi(2);
    let scale = &phase.scale;
    // How many move more than the tolerance, and the defects: only the generators of the
    // blocks that can hold either.
    let (mut above, mut seeds) = (0usize, Vec::new());
    for k in moves.candidates(scale, gate2.min(thr2)) {
        let d2 = (s.targets[k] - z[k]).length_squared() / s.h(k, scale).powi(2);
        above += usize::from(d2 > gate2);
        if d2 > thr2 {
            if let Some(v) = del.vertex_index(k) {
                seeds.push(v as u32);
            }
        }
        if above > cap || seeds.len() > cap {
            return None;
        }
    }
    if seeds.is_empty() {
        return None;
    }
    // Breadth-first over the rings, with marks (a zeroed allocation costs only the pages
    // touched).
    let nv = del.num_vertices();
    let mut marked = vec![false; nv];
    for &v in &seeds {
        marked[v as usize] = true;
    }
    let mut set = seeds.clone();
    let mut front = seeds;
    for _ in 0..MARGIN_RINGS {
        let mut next = Vec::new();
        for &v in &front {
            for &u in del.ring(v as usize) {
                if (u as usize) < nv && !marked[u as usize] {
                    marked[u as usize] = true;
                    next.push(u);
                }
            }
        }
        set.extend_from_slice(&next);
        front = next;
    }
    set.sort_unstable();
    Some(Active {
        set,
        above,
        cleanup: max_move < DEFECT_ABOVE * phase.tol,
    })
}

/// Move the generators `moves` (input index, new position) of the iterate `z`, whose map is `s`
/// and whose triangulation and cells are in `work`: the triangulation is repaired around them,
/// the cells that changed are recomputed with their labels and targets, and `s.energy` is the
/// new energy. Returns the positions the moved generators had (to undo the move). If the
/// triangulation cannot be repaired locally it is rebuilt and the whole map recomputed.
pub(crate) fn apply(
    phase: &Phase,
    z: &mut [DVec2],
    s: &mut Step,
    work: &mut Work,
    moves: &[(u32, DVec2)],
    prof: &mut Profile,
) -> Vec<(u32, DVec2)> {
    let mut t = Instant::now();
    let undo: Vec<(u32, DVec2)> = moves.iter().map(|&(i, _)| (i, z[i as usize])).collect();
    // The local spacing at the new positions (where ρ varies, a B-spline and a power each).
    let h: Vec<f64> = if s.h.is_empty() {
        Vec::new()
    } else {
        moves
            .par_iter()
            .with_min_len(256)
            .map(|&(_, p)| phase.scale.at(p))
            .collect()
    };
    for (k, &(i, p)) in moves.iter().enumerate() {
        z[i as usize] = p;
        if let Some(&h) = h.get(k) {
            s.h[i as usize] = h;
        }
    }
    let moved: Vec<u32> = moves.iter().map(|m| m.0).collect();
    let Some(changed) = work.del.move_points(z, &moved) else {
        prof.triangulation += lap(&mut t);
        // Rebuilt from scratch: the whole map (its rebuild finds the triangulation current).
        *s = step(phase, z, work, prof);
        return undo;
    };
    prof.evaluations += 1;
    prof.local_evaluations += 1;
    prof.local_moved += moves.len();
    prof.triangulation += lap(&mut t);
    let (del, cells, grid) = work.parts(phase.domain);
    // The energy changes by the changed cells' terms (summing all K terms again would read
    // every cell).
    let energy_of = |cells: &tessellation::Cells| -> f64 {
        changed
            .iter()
            .map(|&v| cells.cells[del.point_of_vertex(v as usize)].energy)
            .sum()
    };
    let before = energy_of(cells);
    update_cells(del, grid, phase.density, &changed, cells);
    s.energy += energy_of(cells) - before;
    prof.cells += lap(&mut t);
    // Labels and targets of the changed cells; corners are re-assigned from scratch (their
    // previous holders first get their own cell's label back).
    let redo: Vec<usize> = changed
        .iter()
        .map(|&v| del.point_of_vertex(v as usize))
        .chain(s.fixed.iter().copied())
        .collect();
    for &i in &redo {
        (s.roles[i], s.targets[i]) = map_cell(phase, &cells.cells[i]);
    }
    s.fixed = assign_fixed(phase, z, del, &mut s.roles, &mut s.targets);
    if let Some(touched) = s.touched.as_mut() {
        touched.extend(moves.iter().map(|m| m.0 as usize));
        touched.extend(redo.iter().chain(&s.fixed));
    }
    prof.projection += lap(&mut t);
    undo
}

/// The active generators whose target differs from their position, sent to their targets (a
/// Lloyd step on the active set; it never raises the energy).
pub(crate) fn lloyd_moves(z: &[DVec2], s: &Step, work: &Work, active: &[u32]) -> Vec<(u32, DVec2)> {
    active
        .iter()
        .map(|&v| work.del.point_of_vertex(v as usize) as u32)
        .filter(|&i| s.targets[i as usize] != z[i as usize])
        .map(|i| (i, s.targets[i as usize]))
        .collect()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::init::{initial_points, Init};
    use crate::params::Solver;
    use crate::sublevel::Sublevel;
    use geometry::{Density, Polygon, Region, Rng};
    use mesh::MeshRequest;

    /// A Newton phase over `domain` with active-set steps from any size, tolerance 1e-4.
    pub(crate) fn test_phase<'a>(
        region: &'a Region,
        domain: &'a Polygon,
        inside: &'a Sublevel<'a>,
        density: &'a Density,
        constrained: bool,
        spacing: f64,
    ) -> Phase<'a> {
        Phase {
            region,
            domain,
            inside,
            density,
            constrained,
            update: crate::params::Update::Centroid,
            solver: Solver::Newton,
            tol: 1e-4,
            max_iter: 100,
            spacing,
            scale: crate::scale::LocalScale::new(region, density, spacing),
            active_from: 0,
            active_share: ACTIVE_SHARE,
            project_first: false,
            cancel: None,
            deadline: None,
        }
    }

    /// Moves applied by `apply` (the triangulation repaired around them, only the changed
    /// cells recomputed) leave exactly the map a fresh evaluation computes: cells, labels,
    /// targets, energy and the local spacing at every generator, bit for bit; and undoing them
    /// restores the first map.
    fn assert_local_map_is_the_fresh_map(name: &str, k: usize, constrained: bool, graded: bool) {
        let density = if graded {
            Density::Function(std::sync::Arc::new(|p: DVec2| 1.0 + 4.0 * p.x * p.x))
        } else {
            Density::Uniform
        };
        let region = Region::builtin(name).unwrap();
        let spacing = MeshRequest::points(k).spacing(&region);
        let domain = region.polygonize(1e-4 * spacing);
        let inside = Sublevel::new(&region, 0.0, 3.0 * spacing);
        let phase = test_phase(&region, &domain, &inside, &density, constrained, spacing);
        let mut z = initial_points(&region, k, Init::Lattice, 1);
        let mut prof = Profile::default();
        let mut work = Work::new(&domain);
        // A constrained start: every generator at its target.
        let s0 = step(&phase, &z, &mut work, &mut prof);
        z = s0.targets.clone();
        let mut s = step(&phase, &z, &mut work, &mut prof);
        let first = (s.energy, s.roles.clone(), s.targets.clone(), s.h.clone());
        // Every 13th generator: its Lloyd target, or a random move inside Ω.
        let mut rng = Rng::new(7);
        let moves: Vec<(u32, DVec2)> = (0..k as u32)
            .step_by(13)
            .map(|i| {
                let p = z[i as usize];
                let q = p + DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * 0.3 * spacing;
                let q = if i % 2 == 0 || region.signed_distance(q) >= 0.0 {
                    s.targets[i as usize]
                } else {
                    q
                };
                (i, q)
            })
            .collect();
        let undo = apply(&phase, &mut z, &mut s, &mut work, &moves, &mut prof);
        assert!(prof.local_evaluations == 1, "{name}: applied locally");
        // Bit for bit a full pass over the same triangulation.
        let full = tessellation::clipped_cells(&z, &work.del, &domain, &density);
        assert!(
            work.cells.cells == full.cells,
            "{name}: cells differ from a full pass"
        );
        // And, to rounding (vertices are numbered differently), a fresh evaluation.
        let mut fresh_work = Work::new(&domain);
        let fresh = step(&phase, &z, &mut fresh_work, &mut Profile::default());
        assert!(s.roles == fresh.roles, "{name}: labels");
        for (i, (a, b)) in s.targets.iter().zip(&fresh.targets).enumerate() {
            assert!(
                a.distance(*b) <= 1e-9 * spacing,
                "{name}: target {i}: {a} vs {b}"
            );
        }
        assert!(
            (s.energy - fresh.energy).abs() <= 1e-12 * fresh.energy,
            "{name}: energy"
        );
        // The local spacing at every generator, bit for bit: at the moved ones recomputed,
        // at the others kept.
        assert!(s.h == fresh.h, "{name}: yardsticks");
        assert_eq!(
            s.h.is_empty(),
            !graded,
            "{name}: yardsticks only where ρ varies"
        );
        apply(&phase, &mut z, &mut s, &mut work, &undo, &mut prof);
        assert!(s.h == first.3, "{name}: yardsticks not undone");
        // Labels and targets bit for bit; the energy, updated by differences, to rounding.
        assert!(
            (s.roles, s.targets) == (first.1, first.2),
            "{name}: not undone"
        );
        assert!(
            (s.energy - first.0).abs() <= 1e-12 * first.0,
            "{name}: energy not undone"
        );
    }

    /// `active_set` on the circle's lattice of `k` generators whose targets lie `residual(i)`
    /// tolerances (of the local spacing) from them, the largest move `largest` tolerances, in a
    /// phase with this density and active share: the set on offer as input indices, and the
    /// count above the gate.
    fn offered(
        density: &Density,
        share: f64,
        k: usize,
        residual: impl Fn(usize) -> f64,
        largest: f64,
    ) -> Option<(Vec<usize>, usize)> {
        let region = Region::builtin("circle").unwrap();
        let spacing = MeshRequest::points(k).spacing(&region);
        let domain = region.polygonize(1e-4 * spacing);
        let inside = Sublevel::new(&region, 0.0, 3.0 * spacing);
        let phase = Phase {
            active_share: share,
            ..test_phase(&region, &domain, &inside, density, true, spacing)
        };
        let z = initial_points(&region, k, Init::Lattice, 1);
        let mut work = Work::new(&domain);
        let mut s = step(&phase, &z, &mut work, &mut Profile::default());
        for (i, p) in z.iter().enumerate() {
            s.targets[i] = *p + DVec2::X * (residual(i) * phase.tol * s.h(i, &phase.scale));
        }
        let mut moves = Moves::empty();
        moves.sync(&z, &mut s, &phase.scale);
        active_set(&phase, &z, &s, &work, &moves, largest * phase.tol).map(|a| {
            let set = a.set.iter();
            let set = set.map(|&v| work.del.point_of_vertex(v as usize));
            (set.collect(), a.above)
        })
    }

    /// The share that gates active-set steps counts only the generators that move more than
    /// `DEFECT_GATE` tolerances: a few defects among many generators just above the tolerance
    /// get an active-set step (the defects and their rings, not the halo), with ρ uniform or
    /// not; the same halo moving above the gate asks for a global step.
    #[test]
    fn active_set_steps_are_gated_on_the_defects() {
        let k = 4000;
        let graded = Density::Function(std::sync::Arc::new(|p: DVec2| 1.0 + 4.0 * p.x * p.x));
        let cases = [
            (Density::Uniform, 2.0, true),
            (graded.clone(), 2.0, true),
            (Density::Uniform, 2.0 * DEFECT_GATE, false),
            (graded, 2.0 * DEFECT_GATE, false),
        ];
        // 10 defects far above the gate, 5 % of the generators at `halo` tolerances.
        let defects: Vec<usize> = (0..10).map(|j| 7 + 397 * j).collect();
        let far = 100.0 * DEFECT_GATE;
        for (density, halo, expect_step) in cases {
            let residual = |i: usize| match i {
                _ if defects.contains(&i) => far,
                _ if i % 20 == 3 => halo,
                _ => 0.0,
            };
            let a = offered(&density, ACTIVE_SHARE, k, residual, far);
            let case = format!("uniform: {}, halo {halo}", density.is_uniform());
            assert_eq!(a.is_some(), expect_step, "{case}");
            if let Some((set, above)) = a {
                assert_eq!(above, defects.len(), "{case}: only the defects are counted");
                assert!(
                    defects.iter().all(|d| set.contains(d)),
                    "{case}: every defect moves"
                );
                // The defects and two rings of neighbours: far fewer than the halo.
                assert!(set.len() < k / 20, "{} generators in the set", set.len());
            }
        }
    }

    /// The share is the phase's: 3 % of the generators moving far asks for a global step at
    /// `ACTIVE_SHARE` and gets an active-set step at the row start's `ACTIVE_SHARE_FROM_ROW`.
    #[test]
    fn the_row_starts_share_takes_active_set_steps_where_the_default_does_not() {
        let moving = 0.03;
        assert!(ACTIVE_SHARE < moving && moving < ACTIVE_SHARE_FROM_ROW);
        let every = (1.0 / moving) as usize;
        let far = 100.0 * DEFECT_GATE;
        for (share, expect_step) in [(ACTIVE_SHARE, false), (ACTIVE_SHARE_FROM_ROW, true)] {
            let residual = |i: usize| if i % every == 0 { far } else { 0.0 };
            let a = offered(&Density::Uniform, share, 4000, residual, far);
            assert_eq!(a.is_some(), expect_step, "share {share}");
        }
    }

    #[test]
    fn local_updates_equal_fresh_evaluations() {
        assert_local_map_is_the_fresh_map("circle", 3000, true, false);
        assert_local_map_is_the_fresh_map("circle", 3000, false, false);
        // Corners, holes, and pieces meeting at reflex corners.
        assert_local_map_is_the_fresh_map("square_hole", 2000, true, false);
        assert_local_map_is_the_fresh_map("pie_hole", 2000, true, false);
        assert_local_map_is_the_fresh_map("lake", 3000, true, false);
        // A graded mesh: ρ-weighted moments.
        assert_local_map_is_the_fresh_map("square_hole", 2000, true, true);
    }
}
