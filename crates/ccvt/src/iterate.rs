//! One phase of Lloyd-type iteration on a fixed domain polygon: ordinary CVT (every generator
//! to its centroid) or the constrained rules of Algorithm 1, steps 1–7, by plain Lloyd steps or
//! Anderson mixing (Newton's method is in `newton`).
use crate::anderson::Anderson;
use crate::map::{lap, record, step, Phase, PhaseResult, Role, Step, Trace, Work};
use crate::params::Solver;
use geometry::DVec2;
use rayon::prelude::*;
use std::time::Instant;

/// Iterate the map of `step` from `z` until the largest move is below tol·spacing or the cap.
/// Energies and relative moves of every iteration are appended to the trace's histories.
/// `work` holds the triangulation and cells of the last iterate tessellated (kept for the next
/// phase, and for ε of Algorithm 2).
pub fn run(phase: &Phase, mut z: Vec<DVec2>, work: &mut Work, trace: &mut Trace) -> PhaseResult {
    let mut anderson = match phase.solver {
        Solver::Lloyd => None,
        Solver::Anderson { depth } => Some(Anderson::new(depth)),
        Solver::Newton => return crate::newton::run(phase, z, work, trace),
    };
    // The last plain Lloyd step and the energy at the iterate it came from, to fall back on if
    // acceleration overshoots.
    let mut fallback: Option<(Vec<DVec2>, f64)> = None;
    let mut prev_roles: Vec<Role> = Vec::new();
    let mut mixed: Vec<DVec2> = Vec::new();
    let mut iterations = 0;
    loop {
        let s = step(phase, &z, work, &mut trace.prof);
        iterations += 1;
        if let (Some(aa), Some(&(_, e_prev))) = (anderson.as_mut(), fallback.as_ref()) {
            if s.energy > e_prev * (1.0 + 1e-12) {
                // The accelerated iterate raised the energy: take the safe Lloyd step instead.
                aa.reset();
                trace.prof.rejected += 1;
                z = fallback.take().expect("checked above").0;
                if iterations >= phase.max_iter {
                    let s = step(phase, &z, work, &mut trace.prof);
                    return PhaseResult {
                        z,
                        roles: s.roles,
                        iterations,
                        converged: false,
                        stalled: false,
                    };
                }
                continue;
            }
        }
        let mv = record(phase, &s, &z, iterations, trace);
        let mut t = Instant::now();
        if mv < phase.tol
            || iterations >= phase.max_iter
            || phase.cancelled()
            || phase.out_of_time()
        {
            let converged = mv < phase.tol;
            let Step { roles, targets, .. } = s;
            return PhaseResult {
                z: targets,
                roles,
                iterations,
                converged,
                stalled: false,
            };
        }
        let Step {
            energy,
            roles,
            targets,
            ..
        } = s;
        match anderson.as_mut() {
            None => z = targets,
            Some(aa) => {
                if roles != prev_roles {
                    aa.reset();
                    trace.prof.label_resets += 1;
                }
                aa.step(&z, &targets, &mut mixed);
                constrain(phase, &roles, &targets, &mut mixed);
                std::mem::swap(&mut z, &mut mixed);
                fallback = Some((targets, energy));
                trace.prof.acceleration += lap(&mut t);
            }
        }
        prev_roles = roles;
    }
}

/// Put accelerated positions back on their constraint sets (pieces, corners, the domain);
/// a position that cannot be kept falls back to the plain Lloyd target.
fn constrain(phase: &Phase, roles: &[Role], targets: &[DVec2], mixed: &mut [DVec2]) {
    mixed
        .par_iter_mut()
        .zip(roles.par_iter().zip(targets))
        .for_each(|(p, (role, target))| {
            *p = match *role {
                Role::Corner(_) | Role::Embedded(_) => *target,
                Role::Boundary(j) if p.is_finite() => phase.region.project_point_onto_piece(*p, j),
                Role::Boundary(_) => *target,
                Role::Interior => {
                    if phase.inside.contains(*p) {
                        *p
                    } else {
                        *target
                    }
                }
            }
        });
}
