//! DISTMESH of the paper (Section 4): Persson and Strang's `distmesh2d` (SIAM Review 2004), a
//! truss of Delaunay bars with repulsive forces in equilibrium, with the original constants.
//!
//! 1. Initial points on an equilateral grid of spacing h0 over the region's bounding box (rows
//!    h0·√3/2 apart, every other row offset by h0/2; from the box's lower-left corner, or from
//!    a seeded shift of it with [`GridOrigin::Seeded`]), kept where d < geps (d =
//!    `Region::signed_distance`, exact); for a non-uniform density each is kept with
//!    probability r0/max r0, r0 = 1/h², h = ρ^(-1/4) (the CVT spacing law in 2D). The region's
//!    corners and its embedded points are the fixed points pfix (listed first; they never
//!    move).
//! 2. Loop: retriangulate (Delaunay; keep triangles whose centroid has d < −geps) whenever a
//!    point moved more than ttol·h0 since the last triangulation; bar forces
//!    F = max(L0 − L, 0) with L0 = h·Fscale·√(ΣL²/Σh²); p += Δt·Ftot; points with d > 0 go back
//!    to the boundary by p −= d·∇d/|∇d|² (∇d by forward differences, deps = √ε·h0, or a
//!    thousand rounding steps of the largest coordinate if that is more); stop when
//!    every interior point (d < −geps) moved less than dptol·h0.
//!    Fscale = 1.2, Δt = 0.2, geps = 0.001·h0, ttol = 0.1, dptol = 0.001.
//! 3. K: the count is fixed by the initial grid, so h0 is bisected until #grid + #pfix = K; if
//!    the count jumps over K, the grid with the smallest count above K is used and the surplus
//!    (non-fixed) points are removed at random (seeded with `request.seed`); the notes say so.
//! 4. End (not in the original): points with d > −geps are snapped exactly onto ∂Ω with
//!    `Region::project` (so boundary markers are exact) and the final mesh is
//!    `tessellation::conforming_mesh` of the points, because the original's centroid filter can
//!    leave a mesh whose boundary does not follow ∂Ω (missing or overlapping boundary triangles).
//!
//! `request.max_iter` caps the loop (the run then reports `converged = false`); the original has
//! no cap. A capped run's mesh is built from the points as they are; if they do not resolve ∂Ω
//! yet (too few points on a hole), the result is an error
//! ([`MeshError::NotConforming`]) rather than a non-conforming
//! mesh, and if the conforming triangulation has to drop points the notes say how many.
//! `move_history` (and `Progress::max_move`) is the termination quantity: the largest interior
//! move divided by h0; `energy_history` is empty (DistMesh minimises no energy).
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links)]

use geometry::{DVec2, Density, Region, Rng};
use mesh::{MeshError, MeshRequest, MeshResult, Mesher, Progress, VertexMarker};
use spade::{DelaunayTriangulation, Point2, Triangulation};

/// DistMesh with its constants (defaults: the 2004 paper's).
///
/// ```
/// use cvtmesh::distmesh::DistMesh;
/// use cvtmesh::geometry::Region;
/// use cvtmesh::{check_conforming, MeshRequest, Mesher};
///
/// let region = Region::builtin("hex_hole")?; // a hexagon with a hexagonal hole
/// let result = DistMesh::default().mesh(&region, &MeshRequest::points(200), &mut |_| {})?;
/// assert!(result.converged);
/// check_conforming(&result.mesh, &region)?;
/// // K vertices (surplus grid points are removed); a truss equilibrium has no energy.
/// assert_eq!(result.mesh.num_vertices(), 200);
/// assert!(result.energy_history.is_empty());
/// assert!(*result.move_history.last().unwrap() < DistMesh::default().dptol);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct DistMesh {
    /// Internal pressure: desired bar length over actual mean (1.2).
    pub fscale: f64,
    /// Euler step Δt (0.2).
    pub deltat: f64,
    /// geps / h0: the boundary tolerance (0.001).
    pub geps: f64,
    /// Retriangulation tolerance ttol (0.1).
    pub ttol: f64,
    /// Termination tolerance dptol (0.001).
    pub dptol: f64,
    /// Where the initial grid starts ([`GridOrigin::BoxCorner`], the original's).
    pub grid_origin: GridOrigin,
}

/// Where the initial equilateral grid is anchored.
///
/// `distmesh2d` lays its grid from the lower-left corner of the bounding box its caller
/// passes, so the same region meshed with another (equally valid) box gets another grid, and
/// another mesh: the placement is a free choice of the user, not of the method.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GridOrigin {
    /// At the lower-left corner of the region's own bounding box: the same points for every
    /// seed.
    #[default]
    BoxCorner,
    /// Shifted from that corner by a random fraction of one period of the grid in x (h0) and
    /// in y (two rows), drawn from the request's seed: the grids of all bounding boxes, each
    /// seed one of them.
    Seeded,
}

impl GridOrigin {
    /// The shift as fractions of one grid period in x and y, in [0, 1)².
    ///
    /// ```
    /// use cvtmesh::distmesh::GridOrigin;
    /// use cvtmesh::geometry::DVec2;
    ///
    /// assert_eq!(GridOrigin::BoxCorner.shift(7), DVec2::ZERO);
    /// let s = GridOrigin::Seeded.shift(7);
    /// assert!((0.0..1.0).contains(&s.x) && (0.0..1.0).contains(&s.y));
    /// assert_eq!(GridOrigin::Seeded.shift(7), s); // a function of the seed
    /// ```
    pub fn shift(self, seed: u64) -> DVec2 {
        match self {
            GridOrigin::BoxCorner => DVec2::ZERO,
            GridOrigin::Seeded => {
                // A stream of its own, so the surplus removal (seeded too) stays independent.
                let mut rng = Rng::new(seed ^ 0x6772_6964_6f72_6967);
                DVec2::new(rng.uniform(), rng.uniform())
            }
        }
    }
}

impl DistMesh {
    /// Check the constants: every one positive and finite ([`MeshError::InvalidSetting`]
    /// otherwise). [`Mesher::mesh`] checks them first.
    pub fn validate(&self) -> Result<(), MeshError> {
        for (setting, value) in [
            ("fscale", self.fscale),
            ("deltat", self.deltat),
            ("geps", self.geps),
            ("ttol", self.ttol),
            ("dptol", self.dptol),
        ] {
            MeshError::check_positive("distmesh", setting, value)?;
        }
        Ok(())
    }
}

impl Default for DistMesh {
    fn default() -> Self {
        DistMesh {
            fscale: 1.2,
            deltat: 0.2,
            geps: 0.001,
            ttol: 0.1,
            dptol: 0.001,
            grid_origin: GridOrigin::BoxCorner,
        }
    }
}

/// The desired relative edge length h(x) = ρ(x)^(-1/4) (1 for ρ ≡ 1).
fn size_fn(density: &Density, p: DVec2) -> f64 {
    if density.is_uniform() {
        1.0
    } else {
        density.at(p).max(1e-300).powf(-0.25)
    }
}

/// The initial DistMesh point set for spacing `h0`: the fixed points (the corners, then the
/// region's embedded points), then the
/// equilateral-grid points with d < geps·h0 (rejection-sampled by the density, seeded). The
/// grid starts at the bounding box's lower-left corner moved back by `shift` (fractions of one
/// period: h0 in x, two rows in y; see [`GridOrigin::shift`]).
pub fn initial_points(
    region: &Region,
    h0: f64,
    geps: f64,
    density: &Density,
    seed: u64,
    shift: DVec2,
) -> Vec<DVec2> {
    let pfix: Vec<DVec2> = region
        .corners()
        .iter()
        .map(|c| c.pos)
        .chain(region.embedded_points().iter().map(|&(p, _)| p))
        .collect();
    let (lo, hi) = region.bbox();
    let dy = h0 * 3f64.sqrt() / 2.0;
    // A shifted grid starts up to one period before the box, so it needs that much more.
    let start = lo - DVec2::new(shift.x * h0, shift.y * 2.0 * dy);
    let ny = ((hi.y - start.y) / dy + 1e-9).floor() as usize + 1;
    let nx = ((hi.x - start.x) / h0 + 1e-9).floor() as usize + 1;
    let mut grid = Vec::new();
    for j in 0..ny {
        let y = start.y + j as f64 * dy;
        let offset = if j % 2 == 1 { h0 / 2.0 } else { 0.0 };
        for i in 0..nx {
            let p = DVec2::new(start.x + i as f64 * h0 + offset, y);
            // setdiff(p, pfix) of the original, with a tolerance: a grid point within geps of a
            // fixed point is the same point (corner coordinates carry rounding).
            if region.signed_distance(p) < geps * h0
                && pfix.iter().all(|f| (*f - p).length() >= geps * h0)
            {
                grid.push(p);
            }
        }
    }
    if !density.is_uniform() {
        let r0: Vec<f64> = grid.iter().map(|p| size_fn(density, *p).powi(-2)).collect();
        let max = r0.iter().cloned().fold(0.0, f64::max);
        let mut rng = Rng::new(seed);
        grid = grid
            .into_iter()
            .zip(r0)
            .filter(|(_, r)| rng.uniform() < r / max)
            .map(|(p, _)| p)
            .collect();
    }
    let mut p = pfix;
    p.extend(grid);
    p
}

/// h0 and its point set for K points: bisection on h0 for #points = K; if the count jumps
/// over K, the smallest count above K (the surplus is removed by the caller).
fn choose_h0(
    region: &Region,
    k: usize,
    geps: f64,
    density: &Density,
    seed: u64,
    shift: DVec2,
    h_start: f64,
) -> Result<(f64, Vec<DVec2>, usize), MeshError> {
    let count = |h: f64| initial_points(region, h, geps, density, seed, shift);
    let mut evals = 0;
    let mut h = h_start;
    // Bracket: h_lo with ≥ K points, h_hi with < K.
    let (mut lo, mut hi): (Option<(f64, Vec<DVec2>)>, Option<f64>) = (None, None);
    while lo.is_none() || hi.is_none() {
        evals += 1;
        if evals > 200 || !h.is_finite() || h <= 0.0 {
            return Err(MeshError::Failed {
                method: "distmesh".into(),
                message: format!("no grid spacing gives {k} points"),
            });
        }
        let p = count(h);
        let n = p.len();
        let ratio = (n.max(1) as f64 / k as f64).sqrt();
        if n >= k {
            if n == k {
                return Ok((h, p, evals));
            }
            lo = Some((h, p));
            h *= ratio.max(1.02);
        } else {
            hi = Some(h);
            h *= ratio.min(0.98);
        }
    }
    let (mut lo, mut hi) = (lo.unwrap(), hi.unwrap());
    for _ in 0..80 {
        if (hi - lo.0) <= 1e-14 * lo.0 {
            break;
        }
        let mid = 0.5 * (lo.0 + hi);
        evals += 1;
        let p = count(mid);
        if p.len() == k {
            return Ok((mid, p, evals));
        }
        if p.len() > k {
            lo = (mid, p);
        } else {
            hi = mid;
        }
    }
    Ok((lo.0, lo.1, evals))
}

/// Delaunay triangles of `p` (indices into `p`); duplicates fall back to slower insertion.
/// Boundary points closer than this share of h0 to their neighbour along the boundary are one
/// point: the projection step can push two onto the same spot of a spike's side, and the
/// triangle between them then has an angle of 1e-5°.
const MERGE_SHARE: f64 = 1e-2;

/// Drop every non-corner boundary point lying within `tol` of the last point kept before it
/// along its loop (in arc-length order, corners included); returns how many were dropped.
fn merge_coincident(p: &mut Vec<DVec2>, markers: &mut Vec<VertexMarker>, tol: f64) -> usize {
    let key = |i: usize| {
        (
            markers[i].loop_index(),
            markers[i].loop_param().unwrap_or(0.0),
        )
    };
    let is_corner = |i: usize| matches!(markers[i], VertexMarker::Corner { .. });
    let mut order: Vec<usize> = (0..p.len()).filter(|&i| markers[i].on_boundary()).collect();
    order.sort_by(|&a, &b| {
        let (ka, kb) = (key(a), key(b));
        ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
    });
    let mut drop = vec![false; p.len()];
    let mut last: Option<usize> = None;
    for &i in &order {
        if let Some(l) = last.filter(|&l| key(l).0 == key(i).0 && p[l].distance(p[i]) < tol) {
            // A corner stays: of a pair, the point that is not one goes.
            if !is_corner(i) {
                drop[i] = true;
                continue;
            }
            drop[l] = !is_corner(l);
        }
        last = Some(i);
    }
    let mut d = drop.iter();
    p.retain(|_| !d.next().expect("one flag per point"));
    let mut d = drop.iter();
    markers.retain(|_| !d.next().expect("one flag per marker"));
    drop.iter().filter(|&&d| d).count()
}

fn delaunay(p: &[DVec2]) -> Result<Vec<[usize; 3]>, MeshError> {
    let pts: Vec<Point2<f64>> = p.iter().map(|q| Point2::new(q.x, q.y)).collect();
    let err = |e| MeshError::Failed {
        method: "distmesh".into(),
        message: format!("Delaunay: {e:?}"),
    };
    let dt: DelaunayTriangulation<Point2<f64>> =
        DelaunayTriangulation::bulk_load_stable(pts.clone()).map_err(err)?;
    let map: Vec<usize> = if dt.num_vertices() == p.len() {
        (0..p.len()).collect()
    } else {
        // Coincident points: index each spade vertex by the first input point at it.
        let mut dt2: DelaunayTriangulation<Point2<f64>> = DelaunayTriangulation::new();
        let mut first = Vec::new();
        for (i, q) in pts.iter().enumerate() {
            let n = dt2.num_vertices();
            let v = dt2.insert(*q).map_err(err)?;
            if v.index() == n {
                first.push(i);
            }
        }
        return Ok(dt2
            .inner_faces()
            .map(|f| f.vertices().map(|v| first[v.fix().index()]))
            .collect());
    };
    Ok(dt
        .inner_faces()
        .map(|f| f.vertices().map(|v| map[v.fix().index()]))
        .collect())
}

impl Mesher for DistMesh {
    fn name(&self) -> &'static str {
        "distmesh"
    }

    fn mesh(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<MeshResult, MeshError> {
        self.validate()?;
        let k = request.validate(region)?;
        let ncorners = region.corners().len();
        let nfix = ncorners + region.embedded_points().len();
        let density = &request.density;
        let fd = |q: DVec2| region.signed_distance(q);
        let shift = self.grid_origin.shift(request.seed);
        let (h0, mut p, evals) = choose_h0(
            region,
            k,
            self.geps,
            density,
            request.seed,
            shift,
            request.spacing(region),
        )?;
        let mut notes = vec![format!("h0 = {h0:.6e} ({evals} grid counts)")];
        if self.grid_origin == GridOrigin::Seeded {
            notes.push(format!(
                "grid shifted by ({:.4}, {:.4}) of a period (seed {})",
                shift.x, shift.y, request.seed
            ));
        }
        if p.len() > k {
            let surplus = p.len() - k;
            notes.push(format!(
                "grid count jumps over K: {} points at h0, {surplus} removed at random (seed {})",
                p.len(),
                request.seed
            ));
            let mut rng = Rng::new(request.seed);
            for _ in 0..surplus {
                let i = nfix + rng.below(p.len() - nfix);
                p.remove(i);
            }
        }
        let n = p.len();
        let geps = self.geps * h0;
        // √ε·h0 is below the coordinates' rounding for a small region far from the origin (a
        // diameter of 0.03 at 10⁶), where every difference quotient would be noise: the step
        // stays a thousand rounding steps of the largest coordinate at least.
        let (lo, hi) = region.bbox();
        let reach = lo.abs().max(hi.abs()).max_element();
        let deps = (f64::EPSILON.sqrt() * h0).max(1e3 * f64::EPSILON * reach);
        let mut pold = vec![DVec2::splat(f64::INFINITY); n];
        let mut bars: Vec<(usize, usize)> = Vec::new();
        let mut move_history = Vec::new();
        let mut converged = false;
        let mut retri = 0;
        let mut iterations = 0;
        let mut ftot = vec![DVec2::ZERO; n];
        while iterations < request.max_iter && !(iterations > 0 && request.out_of_time()) {
            iterations += 1;
            // 3. Retriangulate when anything moved more than ttol·h0.
            let moved = p
                .iter()
                .zip(&pold)
                .map(|(a, b)| (*a - *b).length())
                .fold(0.0, f64::max);
            if moved.is_nan() || moved / h0 > self.ttol {
                pold.clone_from(&p);
                retri += 1;
                let t = delaunay(&p)?;
                let mut b: Vec<(usize, usize)> = Vec::with_capacity(3 * t.len());
                for tri in t {
                    let c = (p[tri[0]] + p[tri[1]] + p[tri[2]]) / 3.0;
                    if fd(c) < -geps {
                        for (x, y) in [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])] {
                            b.push((x.min(y), x.max(y)));
                        }
                    }
                }
                b.sort_unstable();
                b.dedup();
                if b.is_empty() {
                    return Err(MeshError::Failed {
                        method: "distmesh".into(),
                        message: format!(
                            "no triangle has its centroid inside the region: the spacing \
                             {h0:.3e} of K = {k} is too coarse for it; a larger K would mesh it"
                        ),
                    });
                }
                bars = b;
            }
            // 6. Bar forces.
            let (mut sl2, mut sh2) = (0.0, 0.0);
            let mut lens = Vec::with_capacity(bars.len());
            for &(a, b) in &bars {
                let l = (p[a] - p[b]).length();
                let h = size_fn(density, 0.5 * (p[a] + p[b]));
                sl2 += l * l;
                sh2 += h * h;
                lens.push((l, h));
            }
            let scale = self.fscale * (sl2 / sh2).sqrt();
            ftot.iter_mut().for_each(|f| *f = DVec2::ZERO);
            for (&(a, b), &(l, h)) in bars.iter().zip(&lens) {
                let f = (h * scale - l).max(0.0);
                if l > 0.0 && f > 0.0 {
                    let fv = (f / l) * (p[a] - p[b]);
                    ftot[a] += fv;
                    ftot[b] -= fv;
                }
            }
            ftot[..nfix].iter_mut().for_each(|f| *f = DVec2::ZERO);
            let mut max_move = 0.0f64;
            for i in 0..n {
                p[i] += self.deltat * ftot[i];
                // 7. Back to the boundary.
                let d = fd(p[i]);
                if d > 0.0 {
                    let gx = (fd(p[i] + DVec2::new(deps, 0.0)) - d) / deps;
                    let gy = (fd(p[i] + DVec2::new(0.0, deps)) - d) / deps;
                    let g2 = gx * gx + gy * gy;
                    if g2 > 0.0 {
                        p[i] -= d * DVec2::new(gx, gy) / g2;
                    }
                }
                // 8. Termination measure over interior points (d before projection).
                if d < -geps {
                    max_move = max_move.max(self.deltat * ftot[i].length() / h0);
                }
            }
            move_history.push(max_move);
            progress(Progress {
                iteration: iterations,
                max_iter: request.max_iter,
                energy: f64::NAN,
                max_move,
            });
            request.check_cancel(self.name(), iterations)?;
            if max_move < self.dptol {
                converged = true;
                break;
            }
        }
        // Snap boundary points exactly onto ∂Ω and mark every point.
        let corners = region.corners();
        let mut markers = Vec::with_capacity(n);
        let mut relocated = 0;
        let others = p.clone();
        for (i, q) in p.iter_mut().enumerate() {
            if (ncorners..nfix).contains(&i) {
                *q = region.embedded_points()[i - ncorners].0;
                markers.push(VertexMarker::Interior);
            } else if i < nfix {
                let c = &corners[i];
                *q = c.pos;
                markers.push(VertexMarker::Corner {
                    loop_index: c.loop_index,
                    corner: i,
                    loop_param: c.loop_param,
                });
            } else if fd(*q) > -geps {
                let mut bp = region.project(*q);
                if let Some(c) = corners.iter().find(|c| (c.pos - bp.point).length() < geps) {
                    // A point pushed out near a convex corner projects onto the corner itself
                    // (a duplicate of the fixed point): move it h0/2 along the adjacent piece
                    // whose side has more room.
                    let (t_out, _) = region.pieces()[c.piece_out].end_tangents();
                    let (_, t_in) = region.pieces()[c.piece_in].end_tangents();
                    let room = |x: DVec2| {
                        others
                            .iter()
                            .map(|o| (*o - x).length())
                            .fold(f64::INFINITY, f64::min)
                    };
                    bp = [
                        (c.piece_out, c.pos + 0.5 * h0 * t_out),
                        (c.piece_in, c.pos - 0.5 * h0 * t_in),
                    ]
                    .into_iter()
                    .map(|(piece, x)| region.project_onto_piece(x, piece))
                    .max_by(|a, b| room(a.point).total_cmp(&room(b.point)))
                    .unwrap();
                    relocated += 1;
                }
                *q = bp.point;
                markers.push(VertexMarker::Boundary {
                    loop_index: bp.loop_index,
                    piece: bp.piece,
                    loop_param: bp.loop_param,
                });
            } else {
                markers.push(VertexMarker::Interior);
            }
        }
        if relocated > 0 {
            notes.push(format!("{relocated} boundary points had converged onto a corner and were moved h0/2 along the boundary"));
        }
        let merged = merge_coincident(&mut p, &mut markers, MERGE_SHARE * h0);
        if merged > 0 {
            notes.push(format!(
                "{merged} boundary points had converged within {MERGE_SHARE}·h0 of a neighbour \
                 on the boundary and were dropped"
            ));
        }
        let stopped_at = if iterations < request.max_iter {
            "the time limit".to_string()
        } else {
            format!("max_iter = {}", request.max_iter)
        };
        let capped = |e: String| MeshError::Failed {
            method: "distmesh".into(),
            message: format!("stopped at {stopped_at} before the boundary was resolved: {e}"),
        };
        let mesh = match tessellation::conforming_mesh(&p, &markers, region) {
            Ok(m) => m,
            Err(e) if !converged => return Err(capped(e.to_string())),
            Err(e) => return Err(e),
        };
        if !converged {
            // Mid-run point sets may not resolve ∂Ω yet (a hole with too few points on it).
            mesh::check_conforming(&mesh, region).map_err(|cause| MeshError::NotConforming {
                method: "distmesh".into(),
                cause,
                hint: format!(
                    "the run stopped at {stopped_at} before the boundary was resolved; allow \
                     more iterations or time"
                ),
            })?;
        }
        if mesh.num_vertices() < n {
            notes.push(format!(
                "{} points dropped by the conforming triangulation (outside the boundary chords or on them)",
                n - mesh.num_vertices()
            ));
        }
        notes.push(format!(
            "{iterations} iterations, {retri} retriangulations, {}",
            if converged {
                "converged (max interior move < dptol·h0)".to_string()
            } else {
                format!("stopped at {stopped_at}")
            }
        ));
        Ok(MeshResult {
            mesh,
            iterations,
            converged,
            energy_history: Vec::new(),
            move_history,
            notes,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two points pushed onto the same spot of a side 2e-6 apart (the 50-spike star at K = 300
    /// gave a triangle of 5e-5° between such a pair): the later one goes, a corner never does,
    /// and points on different loops or farther apart stay.
    #[test]
    fn boundary_points_on_one_spot_are_merged_corners_kept() {
        let on = |loop_index: usize, t: f64| VertexMarker::Boundary {
            loop_index,
            piece: 0,
            loop_param: t,
        };
        let corner = VertexMarker::Corner {
            loop_index: 0,
            corner: 0,
            loop_param: 0.0,
        };
        let mut p = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(0.5, 0.0),
            DVec2::new(0.5 + 2e-6, 0.0),
            DVec2::new(1e-6, 0.0),
            DVec2::new(0.5, 0.0),
            DVec2::new(0.3, 0.3),
            DVec2::new(0.7, 0.0),
        ];
        let mut markers = vec![
            corner,
            on(0, 0.5),
            on(0, 0.5 + 2e-6),
            on(0, 1e-6),
            on(1, 0.5),
            VertexMarker::Interior,
            on(0, 0.7),
        ];
        assert_eq!(merge_coincident(&mut p, &mut markers, 1e-3), 2);
        assert_eq!(
            p,
            [(0.0, 0.0), (0.5, 0.0), (0.5, 0.0), (0.3, 0.3), (0.7, 0.0)]
                .map(|(x, y)| DVec2::new(x, y))
        );
        assert_eq!(markers[0], corner);
        assert_eq!(markers[2], on(1, 0.5));
    }
}
