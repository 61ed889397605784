//! One phase of Lloyd-type iteration on a fixed domain polygon: ordinary CVT (every generator
//! to its centroid) or the constrained rules of Algorithm 1, steps 1–7.
use crate::anderson::Anderson;
use crate::method::Solver;
use geometry::{DVec2, Density, PieceId, Polygon, Region};
use mesh::Progress;
use tessellation::{clipped_cells, Cells, Delaunay};

/// What a generator is constrained to in the current iteration (Section 2.2.3 labels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Role {
    /// Interior region: moves to its centroid.
    Interior,
    /// Boundary region: moves to the projection of its centroid onto this piece.
    Boundary(PieceId),
    /// Corner region: sits on this corner.
    Corner(usize),
}

/// The fixed-point map at one iterate: cells, energy, labels and the next positions.
pub struct Step {
    pub cells: Cells,
    pub energy: f64,
    pub roles: Vec<Role>,
    pub targets: Vec<DVec2>,
}

/// Inputs shared by every iteration of a phase.
pub struct Phase<'a> {
    pub region: &'a Region,
    /// The tessellated domain: Ω (Algorithm 1) or Ω_ε (Algorithm 2), polygonized.
    pub domain: &'a Polygon,
    pub density: &'a Density,
    /// Algorithm 1's labels and projections (false: ordinary CVT of the domain).
    pub constrained: bool,
    pub solver: Solver,
    pub tol: f64,
    pub max_iter: usize,
    pub spacing: f64,
}

/// Result of a phase.
pub struct PhaseResult {
    pub z: Vec<DVec2>,
    pub roles: Vec<Role>,
    /// Cells of the last iterate that was tessellated (for ε of Algorithm 2).
    pub cells: Cells,
    pub iterations: usize,
    pub converged: bool,
}

/// Evaluate the map at `z`: Voronoi cells clipped to the domain → centroids → labels →
/// projection of boundary centroids onto their own piece, corners to corners.
pub fn step(phase: &Phase, z: &[DVec2]) -> Step {
    let del = Delaunay::new(z);
    let cells = clipped_cells(z, &del, phase.domain, phase.density);
    let energy = cells.energy();
    let mut targets: Vec<DVec2> = cells.cells.iter().map(|c| c.mass_centroid).collect();
    let mut roles = vec![Role::Interior; z.len()];
    if phase.constrained {
        let region = phase.region;
        for (k, cell) in cells.cells.iter().enumerate() {
            if !cell.on_boundary() {
                continue;
            }
            // Section 2.3: of the projections onto the pieces the cell touches, the nearest.
            let best = cell
                .pieces
                .iter()
                .map(|&j| region.project_onto_piece(targets[k], j))
                .min_by(|a, b| a.distance.total_cmp(&b.distance))
                .expect("boundary cell has a piece");
            roles[k] = Role::Boundary(best.piece);
            targets[k] = best.point;
        }
        for k in 0..z.len() {
            // Interior centroids of Ω_ε may fall outside Ω; such a cell behaves as a boundary
            // cell (its generator must stay in Ω̄ for the mesh).
            if roles[k] == Role::Interior && region.signed_distance(targets[k]) > 0.0 {
                let bp = region.project(targets[k]);
                roles[k] = Role::Boundary(bp.piece);
                targets[k] = bp.point;
            }
        }
        assign_corners(region, z, &del, &mut roles, &mut targets);
    }
    Step {
        cells,
        energy,
        roles,
        targets,
    }
}

/// Corner regions: the cell whose closure holds the corner is its nearest generator's; if two
/// corners share a nearest generator (too coarse), the next-nearest free neighbour takes it.
fn assign_corners(
    region: &Region,
    z: &[DVec2],
    del: &Delaunay,
    roles: &mut [Role],
    targets: &mut [DVec2],
) {
    for (ci, c) in region.corners().iter().enumerate() {
        let mut k = del.nearest(c.pos);
        if matches!(roles[k], Role::Corner(_)) {
            let free = del
                .neighbors(k)
                .into_iter()
                .filter(|&j| !matches!(roles[j], Role::Corner(_)))
                .min_by(|&a, &b| (z[a] - c.pos).length().total_cmp(&(z[b] - c.pos).length()));
            match free {
                Some(j) => k = j,
                None => continue,
            }
        }
        roles[k] = Role::Corner(ci);
        targets[k] = c.pos;
    }
}

fn max_move(a: &[DVec2], b: &[DVec2]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).length())
        .fold(0.0, f64::max)
}

/// Iterate the map of `step` from `z` until the largest move is below tol·spacing or the cap.
/// Energies and relative moves of every iteration are appended to the histories.
pub fn run(
    phase: &Phase,
    mut z: Vec<DVec2>,
    energies: &mut Vec<f64>,
    moves: &mut Vec<f64>,
    progress: &mut dyn FnMut(Progress),
) -> PhaseResult {
    let mut anderson = match phase.solver {
        Solver::Lloyd => None,
        Solver::Anderson { depth } => Some(Anderson::new(depth)),
    };
    // The last plain Lloyd step and its energy, to fall back on if acceleration overshoots.
    let mut fallback: Option<(Vec<DVec2>, f64)> = None;
    let mut prev_roles: Vec<Role> = Vec::new();
    let mut iterations = 0;
    loop {
        let s = step(phase, &z);
        iterations += 1;
        if let (Some(aa), Some((lloyd_z, e_prev))) = (anderson.as_mut(), fallback.as_ref()) {
            if s.energy > *e_prev * (1.0 + 1e-12) {
                // The accelerated iterate raised the energy: take the safe Lloyd step instead.
                aa.reset();
                z = lloyd_z.clone();
                fallback = None;
                if iterations >= phase.max_iter {
                    let s = step(phase, &z);
                    return finish(z, s, iterations, false);
                }
                continue;
            }
        }
        let mv = max_move(&s.targets, &z) / phase.spacing;
        energies.push(s.energy);
        moves.push(mv);
        progress(Progress {
            iteration: iterations,
            max_iter: phase.max_iter,
            energy: s.energy,
            max_move: mv,
        });
        if mv < phase.tol {
            return finish(s.targets.clone(), s, iterations, true);
        }
        if iterations >= phase.max_iter {
            return finish(s.targets.clone(), s, iterations, false);
        }
        let next = match anderson.as_mut() {
            None => s.targets.clone(),
            Some(aa) => {
                if s.roles != prev_roles {
                    aa.reset();
                }
                let flat = |v: &[DVec2]| v.iter().flat_map(|p| [p.x, p.y]).collect::<Vec<f64>>();
                let mixed = aa.step(&flat(&z), &flat(&s.targets));
                fallback = Some((s.targets.clone(), s.energy));
                constrain(phase, &s, &mixed)
            }
        };
        prev_roles = s.roles.clone();
        z = next;
    }
}

/// Put accelerated positions back on their constraint sets (pieces, corners, the domain).
fn constrain(phase: &Phase, s: &Step, mixed: &[f64]) -> Vec<DVec2> {
    (0..s.targets.len())
        .map(|k| {
            let p = DVec2::new(mixed[2 * k], mixed[2 * k + 1]);
            match s.roles[k] {
                Role::Corner(_) => s.targets[k],
                Role::Boundary(j) => phase.region.project_onto_piece(p, j).point,
                Role::Interior => {
                    let inside = if phase.constrained {
                        phase.region.signed_distance(p) < 0.0
                    } else {
                        phase.domain.contains(p)
                    };
                    if p.is_finite() && inside {
                        p
                    } else {
                        s.targets[k]
                    }
                }
            }
        })
        .collect()
}

fn finish(z: Vec<DVec2>, s: Step, iterations: usize, converged: bool) -> PhaseResult {
    PhaseResult {
        z,
        roles: s.roles,
        cells: s.cells,
        iterations,
        converged,
    }
}
