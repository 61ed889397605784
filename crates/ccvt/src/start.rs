//! Starts that already have the target spacing, along ∂Ω and inside, so that the constrained
//! iteration (Algorithm 1) only has to relax them: the vertices of a Delaunay refinement
//! driven by the density (a graded start), and a coarser CCVT prolongated by one level (every
//! edge of its mesh split at its midpoint, which turns a hexagonal lattice into the lattice of
//! half its spacing, and keeps any grading; ∂Ω laid out again).
use crate::scale::LocalScale;
use geometry::{DVec2, Region, Rng};
use mesh::{Mesh, MeshError, MeshRequest, VertexMarker};
use rayon::prelude::*;
use refine::Refine;
use std::collections::HashMap;

/// Points with a flag for those on ∂Ω (which count adjustments leave alone).
pub(crate) struct Seeds {
    pub points: Vec<DVec2>,
    pub on_boundary: Vec<bool>,
}

impl Seeds {
    fn from_mesh(mesh: &Mesh) -> Seeds {
        Seeds {
            points: mesh.points.clone(),
            on_boundary: mesh
                .markers
                .iter()
                .map(|m| !matches!(m, VertexMarker::Interior))
                .collect(),
        }
    }
}

/// From this many generators on, a start is listed along a Hilbert curve before the solve
/// ([`along_hilbert`]). Every per-generator pass of an evaluation (the cells, the Hessian's
/// rows, the active set) reads its Delaunay neighbours, which the triangulation numbers in
/// Hilbert order; the starts list their points otherwise (the row start by depth, the graded
/// start in the refinement's insertion order), so each neighbour read missed the cache once
/// the arrays outgrew it. Below, everything fits in the cache and the starts keep their own
/// order, and with it every path there (the study's sizes among them).
// Circle 10⁶, seed 1, the same path (163 evaluations, the same energy): 18.5 / 21.5 s → 17.5 /
// 18.0 s, the Hessian 4.3 / 5.0 s → 3.2 / 3.4 s; circle 10⁵, seeds 1–3, the same paths:
// 1.94 / 1.77 / 2.09 s → 1.64 / 1.62 / 1.73 s.
pub(crate) const HILBERT_FROM: usize = 10_000;

/// `z` listed along a Hilbert curve ([`tessellation::hilbert_order`]) if it has at least
/// [`HILBERT_FROM`] points; as it is otherwise. Which generator is which does not matter to
/// the method: only the order of the mesh's vertices, and the rounding of sums over them, see
/// it.
pub(crate) fn along_hilbert(z: Vec<DVec2>) -> Vec<DVec2> {
    if z.len() < HILBERT_FROM {
        return z;
    }
    tessellation::hilbert_order(&z)
        .into_iter()
        .map(|i| z[i as usize])
        .collect()
}

/// How many generators a coarse level needs so that its prolongation has about `k`, of which
/// about `fine_boundary` on ∂Ω ([`boundary_count`]): a triangulation of V vertices, B of them
/// on ∂Ω, has about 3V − B edges, so V + E ≈ 4V − B; B halves from the fine level to the
/// coarse one.
pub(crate) fn coarse_count(fine_boundary: f64, k: usize) -> usize {
    ((k as f64 + 0.5 * fine_boundary) / 4.0).round() as usize
}

/// The boundary spacing of a converged CCVT relative to the local hexagonal spacing h(x): the
/// uniform circle at 10⁵ settles with 990–1017 boundary generators where 2π/h is 1043.
const BOUNDARY_SPACING: f64 = 1.04;

/// Interior start points closer to ∂Ω than this many local spacings are dropped: in a converged
/// CCVT the first row of interior generators lies about 0.85 spacings from ∂Ω, and a point whose
/// cell reaches ∂Ω is labelled a boundary generator, which it then stays.
const CLEARANCE: f64 = 0.7;

/// The vertices of `mesh` with its boundary vertices replaced by points at CCVT's own boundary
/// spacing (`BOUNDARY_SPACING`·h, h the local spacing; corners kept) and its interior vertices
/// within `CLEARANCE`·h of ∂Ω dropped. Under the paper's labels a generator on ∂Ω never leaves
/// it, and interior generators of a refinement's near-boundary layer joined ∂Ω during the
/// relaxation: the boundary came out 20–35 % denser than the interior, with flat triangles
/// along it.
fn resample_boundary(region: &Region, scale: &LocalScale, mesh: &Mesh) -> Seeds {
    let interior = mesh
        .points
        .iter()
        .zip(&mesh.markers)
        .filter(|(_, m)| matches!(m, VertexMarker::Interior))
        .map(|(p, _)| *p);
    with_boundary_laid_out(region, scale, mesh, interior)
}

/// Is the interior point `p` at least `CLEARANCE`·h inside Ω?
fn clear_of_boundary(region: &Region, scale: &LocalScale, p: DVec2) -> bool {
    -region.signed_distance(p) >= CLEARANCE * scale.at(p)
}

/// The points of `interior` clear of ∂Ω, and ∂Ω laid out at `BOUNDARY_SPACING`·h along the
/// boundary vertices of `mesh` (corners kept, each run between corners split evenly by its
/// length in boundary spacings, the points projected onto their piece).
fn with_boundary_laid_out(
    region: &Region,
    scale: &LocalScale,
    mesh: &Mesh,
    interior: impl Iterator<Item = DVec2>,
) -> Seeds {
    let mut seeds = Seeds {
        points: Vec::with_capacity(mesh.points.len()),
        on_boundary: Vec::with_capacity(mesh.points.len()),
    };
    for p in interior.filter(|p| clear_of_boundary(region, scale, *p)) {
        seeds.points.push(p);
        seeds.on_boundary.push(false);
    }
    // Per loop: (loop parameter, point, piece if not a corner).
    let mut loops: Vec<Vec<(f64, DVec2, Option<geometry::PieceId>)>> =
        vec![Vec::new(); region.loops().len()];
    let at = |vs: &[(f64, DVec2, Option<geometry::PieceId>)], i: usize| vs[i % vs.len()];
    for (p, m) in mesh.points.iter().zip(&mesh.markers) {
        match *m {
            VertexMarker::Interior => {}
            VertexMarker::Boundary {
                loop_index,
                piece,
                loop_param,
            } => loops[loop_index].push((loop_param, *p, Some(piece))),
            VertexMarker::Corner {
                loop_index,
                loop_param,
                ..
            } => loops[loop_index].push((loop_param, *p, None)),
        }
    }
    for mut vs in loops.into_iter().filter(|v| !v.is_empty()) {
        vs.sort_by(|a, b| a.0.total_cmp(&b.0));
        // Start at a corner if there is one: runs go from anchor to anchor.
        let first = vs.iter().position(|v| v.2.is_none()).unwrap_or(0);
        vs.rotate_left(first);
        let n = vs.len();
        let anchors: Vec<usize> = (0..n).filter(|&i| i == 0 || vs[i].2.is_none()).collect();
        for (a, &start) in anchors.iter().enumerate() {
            let end = anchors.get(a + 1).copied().unwrap_or(n);
            seeds.points.push(vs[start].1);
            seeds.on_boundary.push(true);
            // The run's polyline, anchor to next anchor (the first one again at the end):
            // the weight of each step is its length in boundary spacings.
            let weights: Vec<f64> = (start..end)
                .map(|i| {
                    let (p, q) = (at(&vs, i).1, at(&vs, i + 1).1);
                    (q - p).length() / (BOUNDARY_SPACING * scale.at(0.5 * (p + q)))
                })
                .collect();
            for (k, f) in even_split(&weights) {
                let (p, q) = (at(&vs, start + k), at(&vs, start + k + 1));
                let x = p.1 + (q.1 - p.1) * f;
                let point = match p.2.or(q.2) {
                    Some(piece) => region.project_point_onto_piece(x, piece),
                    None => region.project(x).point,
                };
                seeds.points.push(point);
                seeds.on_boundary.push(true);
            }
        }
    }
    seeds
}

/// The inner points that split a polyline run into round(Σ weights) pieces of equal weight
/// (at least one piece), each as (step, fraction along that step); `weights[i]` is step i's
/// length in target spacings.
fn even_split(weights: &[f64]) -> Vec<(usize, f64)> {
    let total: f64 = weights.iter().sum();
    let pieces = (total.round() as usize).max(1);
    let (mut k, mut below) = (0, 0.0);
    (1..pieces)
        .map(|j| {
            let target = total * j as f64 / pieces as f64;
            while k + 1 < weights.len() && below + weights[k] < target {
                below += weights[k];
                k += 1;
            }
            let f = if weights[k] > 0.0 {
                ((target - below) / weights[k]).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (k, f)
        })
        .collect()
}

/// About how many generators lie on ∂Ω at the local spacing: ∫_∂Ω ds / h.
pub(crate) fn boundary_count(region: &Region, scale: &LocalScale) -> f64 {
    let poly = region.polygonize(1e-3 * scale.mean());
    poly.rings
        .iter()
        .flat_map(|ring| {
            let n = ring.points.len();
            (0..n).map(move |i| (ring.points[i], ring.points[(i + 1) % n]))
        })
        .map(|(a, b)| (b - a).length() / scale.at(0.5 * (a + b)))
        .sum()
}

/// The start from a coarser level's `mesh`: the interior points of [`prolongate`] at least
/// `CLEARANCE`·h inside Ω, and ∂Ω laid out again at CCVT's own boundary spacing as the graded
/// start lays it out. Splitting the boundary edges instead doubles every boundary generator the
/// coarse relaxation gained: graded meshes at 10⁵ came out with boundary edges 0.92–0.99 of the
/// interior's (relative to h), against 0.98–1.02 with the boundary laid out again.
pub(crate) fn prolongate_resampled(region: &Region, scale: &LocalScale, mesh: &Mesh) -> Seeds {
    let split = prolongate(region, mesh);
    let interior = split
        .points
        .iter()
        .zip(&split.on_boundary)
        .filter(|(_, &b)| !b)
        .map(|(p, _)| *p);
    let mut seeds = with_boundary_laid_out(region, scale, mesh, interior);
    // ∂Ω's points first, then the interior's: `fit_count`'s seeded choices follow this order.
    let inside = seeds.on_boundary.iter().filter(|&&b| !b).count();
    seeds.points.rotate_left(inside);
    seeds.on_boundary.rotate_left(inside);
    seeds
}

/// The vertices of `mesh` and the midpoint of each of its edges; midpoints of boundary edges
/// go onto ∂Ω (the nearest point of the piece the edge follows).
pub(crate) fn prolongate(region: &Region, mesh: &Mesh) -> Seeds {
    let mut seeds = Seeds::from_mesh(mesh);
    let boundary: HashMap<(u32, u32), ()> = mesh
        .boundary_edges()
        .iter()
        .map(|e| ((e.a.min(e.b), e.a.max(e.b)), ()))
        .collect();
    let mut seen: HashMap<(u32, u32), ()> = HashMap::with_capacity(3 * mesh.points.len());
    for t in &mesh.triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let key = (a.min(b), a.max(b));
            if seen.insert(key, ()).is_some() {
                continue;
            }
            let mid = 0.5 * (mesh.points[a as usize] + mesh.points[b as usize]);
            let on_boundary = boundary.contains_key(&key);
            let p = if on_boundary {
                let piece = [a, b].iter().find_map(|&v| match mesh.markers[v as usize] {
                    VertexMarker::Boundary { piece, .. } => Some(piece),
                    _ => None,
                });
                match piece {
                    Some(j) => region.project_point_onto_piece(mid, j),
                    None => region.project(mid).point,
                }
            } else {
                mid
            };
            seeds.points.push(p);
            seeds.on_boundary.push(on_boundary);
        }
    }
    seeds
}

/// Exactly `k` points: surplus interior points removed at random, missing ones added beside
/// random interior points (a third of the local spacing away, inside Ω), all from `seed`.
/// Either leaves a few scattered local defects for the relaxation.
pub(crate) fn fit_count(
    region: &Region,
    scale: &LocalScale,
    mut seeds: Seeds,
    k: usize,
    seed: u64,
) -> Vec<DVec2> {
    let mut rng = Rng::new(seed ^ 0x5eed_5eed);
    let interior: Vec<usize> = (0..seeds.points.len())
        .filter(|&i| !seeds.on_boundary[i])
        .collect();
    let n = seeds.points.len();
    if n > k && !interior.is_empty() {
        let mut drop = vec![false; n];
        let mut pool = interior.clone();
        let mut excess = n - k;
        while excess > 0 && !pool.is_empty() {
            let i = pool.swap_remove(rng.below(pool.len()));
            drop[i] = true;
            excess -= 1;
        }
        let mut kept = Vec::with_capacity(k);
        for (i, p) in seeds.points.iter().enumerate() {
            if !drop[i] {
                kept.push(*p);
            }
        }
        seeds.points = kept;
    }
    seeds.points.truncate(k);
    let mut tries = 0;
    while seeds.points.len() < k {
        tries += 1;
        let base = if interior.is_empty() || tries > 100 * k {
            // Nothing to stand beside: anywhere in Ω.
            let (lo, hi) = region.bbox();
            DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y))
        } else {
            seeds.points[interior[rng.below(interior.len())].min(seeds.points.len() - 1)]
        };
        let h = scale.at(base);
        let angle = rng.range(0.0, std::f64::consts::TAU);
        let p = base + DVec2::from_angle(angle) * (h / 3.0);
        if region.signed_distance(p) < -0.1 * h {
            seeds.points.push(p);
        }
    }
    seeds.points
}

/// A graded start of exactly `k` points: the vertices of a Delaunay refinement whose area
/// bound follows the density (20° minimum angle), its boundary resampled
/// ([`resample_boundary`]), sized by one trial refinement and one corrected by the count it
/// gave, then fitted to `k`.
pub(crate) fn graded(
    region: &Region,
    request: &MeshRequest,
    scale: &LocalScale,
    k: usize,
) -> Result<Vec<DVec2>, MeshError> {
    let refine = Refine::default();
    // Triangles average about 0.6 of the area bound and number about 2K; the bound is scaled
    // by ρ^(−½), so the ρ^(½)-weighted area decides the count.
    let weighted = region.area() * scale.mean_sqrt_density();
    let mut area = weighted / (1.2 * k as f64);
    let budget = 4 * k + 1000;
    let seeds = |area: f64| -> Result<Seeds, MeshError> {
        let r = refine.refine_with_area(region, area, &request.density, budget)?;
        Ok(resample_boundary(region, scale, &r.mesh))
    };
    let mut s = seeds(area)?;
    let got = s.points.len();
    if got != k && got > 0 {
        area *= got as f64 / k as f64;
        s = seeds(area)?;
    }
    // Sizes along ∂Ω far finer than the field's background grid follows: the grid's count of
    // the whole region falls short of what ∂Ω alone takes at its own sizes, and a start of
    // boundary points only would be a triangulation of long collinear runs, minutes per
    // evaluation (a wall layer of 10⁻⁵ on the unit square: 274 292 boundary points for K =
    // 138 141).
    let boundary = s.on_boundary.iter().filter(|&&b| b).count();
    if boundary >= k {
        return Err(MeshError::BadRequest(format!(
            "the size field asks for about {boundary} vertices along the boundary alone, more \
             than the {k} it asks for in all: its sizes along the boundary are finer than its \
             background grid follows (the warning says where), so its count of the region is \
             far too low; a smallest size nearer the grid's step meshes"
        )));
    }
    Ok(fit_count(region, scale, s, k, request.seed))
}

/// The boundary spacing of the row start relative to the hexagonal spacing h of K points in Ω:
/// the outer row of the default path's last CVT of Ω_ε at circle 10⁵ (1017 generators on a
/// perimeter of 1043 h).
pub(crate) const ROW_SPACING: f64 = 1.026;

/// Depth of that row below ∂Ω_ε, in spacings: where the outer row of a CVT of Ω_ε sits.
const ROW_DEPTH: f64 = 0.35;

/// The ε, in spacings, that a row start begins Algorithm 2 with: where the lattice path's ε
/// settles at circle 10⁵ (0.6856; 0.68–0.75 in all ten regions).
pub(crate) const ROW_EPS: f64 = 0.686;

/// A start for Algorithm 2 from ε = `eps`·h (h the hexagonal spacing of K points in Ω,
/// [`MeshRequest::spacing`]): an outer row at `ROW_SPACING`·h along every loop
/// of ∂Ω (corner to corner, corners included), pushed outward to `ROW_DEPTH`·h below ∂Ω_ε, and
/// inside it the `Init::Lattice` lattice dilated to the area of Ω_ε, of which the K − (row)
/// points deepest in Ω are kept. The CVTs of Ω_ε keep the outer row's count, and the
/// constrained phase takes exactly that row as its boundary generators: a CVT of Ω (the
/// lattice relaxed) has about 6 % more there, which the default path sheds only in the slow,
/// capped dilation into Ω_ε.
/// `None` if Ω_ε would close a hole at this ε, or if the row would hold more than a quarter of
/// the K points.
pub(crate) fn boundary_row(
    region: &Region,
    k: usize,
    h: f64,
    eps: f64,
    seed: u64,
) -> Option<Vec<DVec2>> {
    let mut rng = Rng::new(seed);
    let tol = 1e-3 * h;
    if region.expand(eps * h, tol).rings.len() != region.loops().len() {
        return None;
    }
    let push = (eps - ROW_DEPTH).max(0.0) * h;
    let mut row: Vec<DVec2> = Vec::new();
    // Each loop's spacing scaled by its length over the length of its offset by `push`: the
    // outer row of a CVT of Ω_ε lies on the offset, longer than a convex outer loop and
    // shorter than a convex hole.
    let offset = region.expand(push, tol);
    let ring_len = |pts: &[DVec2]| -> f64 {
        let n = pts.len();
        (0..n).map(|i| (pts[(i + 1) % n] - pts[i]).length()).sum()
    };
    let stretch: Vec<f64> = (0..region.loops().len())
        .map(|li| {
            if offset.rings.len() != region.loops().len() {
                return 1.0;
            }
            let own: f64 = region.loops()[li].length;
            let off: f64 = offset
                .rings
                .iter()
                .filter(|r| r.loop_index == li)
                .map(|r| ring_len(&r.points))
                .sum();
            if off > 0.0 {
                own / off
            } else {
                1.0
            }
        })
        .collect();
    for (li, lp) in region.loops().iter().enumerate() {
        // The loop as a polyline, each vertex flagged if it is a corner (an anchor).
        let mut poly: Vec<(DVec2, bool)> = Vec::new();
        for &id in &lp.pieces {
            let corner = region
                .corners()
                .iter()
                .any(|c| c.loop_index == li && c.piece_out == id);
            let pts = region.pieces()[id].polygonize(tol);
            let n = pts.len().saturating_sub(1).max(1);
            for (j, &p) in pts.iter().take(n).enumerate() {
                poly.push((p, j == 0 && corner));
            }
        }
        let n = poly.len();
        if n < 2 {
            continue;
        }
        let first = poly.iter().position(|v| v.1).unwrap_or(0);
        poly.rotate_left(first);
        let anchors: Vec<usize> = (0..n).filter(|&i| i == 0 || poly[i].1).collect();
        let at = |i: usize| poly[i % n].0;
        for (a, &start) in anchors.iter().enumerate() {
            let end = anchors.get(a + 1).copied().unwrap_or(n);
            row.push(at(start));
            let weights: Vec<f64> = (start..end)
                .map(|i| (at(i + 1) - at(i)).length() / (ROW_SPACING * h * stretch[li]))
                .collect();
            for (i, f) in even_split(&weights) {
                row.push(at(start + i).lerp(at(start + i + 1), f));
            }
        }
    }
    // Outward along the gradient of the signed distance (the bisector at a corner).
    let step = 1e-3 * h;
    let row: Vec<DVec2> = row
        .into_par_iter()
        .map(|p| {
            let d = |q: DVec2| region.signed_distance(q);
            let (ex, ey) = (DVec2::new(step, 0.0), DVec2::new(0.0, step));
            let g = DVec2::new(d(p + ex) - d(p - ex), d(p + ey) - d(p - ey));
            p + g.normalize_or_zero() * push
        })
        .collect();
    // A region about as narrow as the spacing is mostly boundary layer: no lattice to keep
    // clear of the row, and the lattice path's own handling of thin places applies.
    if row.len() * 4 > k {
        return None;
    }
    let want = k - row.len();
    // The lattice of Init::Lattice, dilated from Ω's area to Ω_ε's.
    let hl = h * (1.0 + eps * h * region.perimeter() / region.area()).sqrt();
    let (lo, hi) = region.bbox();
    let centre = region.polygonize(tol).centroid();
    let angle = rng.range(0.0, std::f64::consts::FRAC_PI_3);
    let (u, v) = (
        DVec2::from_angle(angle) * hl,
        DVec2::from_angle(angle + std::f64::consts::FRAC_PI_3) * hl,
    );
    let reach = ((hi - lo).length() / hl).ceil() as i64 + 1;
    let (blo, bhi) = (lo - DVec2::splat(hl), hi + DVec2::splat(hl));
    let mut lattice: Vec<(f64, DVec2)> = (-reach..=reach)
        .into_par_iter()
        .map(|i| {
            (-reach..=reach)
                .map(|j| centre + u * i as f64 + v * j as f64)
                .filter(|p| p.cmpge(blo).all() && p.cmple(bhi).all())
                .filter_map(|p| {
                    let d = region.signed_distance(p);
                    (d < -1e-3 * hl).then_some((d, p))
                })
                .collect::<Vec<_>>()
        })
        .collect::<Vec<_>>()
        .concat();
    for (_, p) in lattice.iter_mut() {
        *p += DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)) * (1e-9 * h);
    }
    // The deepest first: the shallowest surplus makes the gap between the row and the lattice.
    // A stable sort, so the same order on any number of threads (ties keep the lattice's).
    lattice.par_sort_by(|a, b| a.0.total_cmp(&b.0));
    lattice.truncate(want);
    let mut z = row;
    z.extend(lattice.into_iter().map(|(_, p)| p));
    while z.len() < k {
        let p = DVec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
        if region.signed_distance(p) < 0.0 {
            z.push(p);
        }
    }
    z.truncate(k);
    Some(z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::Density;

    #[test]
    fn the_row_start_lies_just_inside_the_expanded_boundary_with_the_lattice_in_the_region() {
        for name in ["circle", "square_two_hex", "lake"] {
            let region = Region::builtin(name).unwrap();
            let k = 5000;
            let h = MeshRequest::points(k).spacing(&region);
            let z = boundary_row(&region, k, h, ROW_EPS, 7).unwrap();
            assert_eq!(z.len(), k, "{name}");
            let push = (ROW_EPS - ROW_DEPTH) * h;
            let (row, lattice): (Vec<DVec2>, Vec<DVec2>) =
                z.iter().partition(|p| region.signed_distance(**p) > 0.0);
            // Every row point is `push` out along a normal (closer at a hole's corner, where
            // the offset is not a normal one), so inside Ω_ε; the lattice is inside Ω.
            for p in &row {
                let d = region.signed_distance(*p);
                assert!(
                    d <= push * (1.0 + 1e-6) && d < ROW_EPS * h,
                    "{name}: {p} at {d:e}"
                );
            }
            assert!(lattice.iter().all(|p| region.signed_distance(*p) < 0.0));
            // One row point per ROW_SPACING·h of each loop's offset: about the perimeter's count.
            let expected = region.perimeter() / (ROW_SPACING * h);
            let got = row.len() as f64;
            assert!(
                (got / expected - 1.0).abs() < 0.05,
                "{name}: {got} row points, about {expected:.0} expected"
            );
            // Each corner has its row point, pushed out from it.
            for c in region.corners() {
                let near = row
                    .iter()
                    .map(|p| (*p - c.pos).length())
                    .fold(f64::MAX, f64::min);
                assert!(
                    near <= push * (1.0 + 1e-3),
                    "{name}: corner {} {near:e}",
                    c.pos
                );
            }
            assert_eq!(
                boundary_row(&region, k, h, ROW_EPS, 7).unwrap(),
                z,
                "{name}: same seed"
            );
            assert_ne!(
                boundary_row(&region, k, h, ROW_EPS, 8).unwrap(),
                z,
                "{name}: other seed"
            );
        }
        // The circle's row is one ring at radius 1 + push (within the polygon's chord error),
        // with a point per ROW_SPACING·h of that ring.
        let circle = Region::builtin("circle").unwrap();
        let h = MeshRequest::points(5000).spacing(&circle);
        let z = boundary_row(&circle, 5000, h, ROW_EPS, 1).unwrap();
        let radius = 1.0 + (ROW_EPS - ROW_DEPTH) * h;
        let ring: Vec<&DVec2> = z.iter().filter(|p| p.length() > 1.0).collect();
        assert!(ring.iter().all(|p| (p.length() - radius).abs() < 2e-3 * h));
        let expected = std::f64::consts::TAU * radius / (ROW_SPACING * h);
        assert!(
            (ring.len() as f64 - expected).abs() <= 1.0,
            "{} {expected}",
            ring.len()
        );
    }

    #[test]
    fn no_row_start_where_the_expanded_region_closes_a_hole_or_the_region_is_all_boundary() {
        let row = |region: &Region, k: usize| {
            boundary_row(
                region,
                k,
                MeshRequest::points(k).spacing(region),
                ROW_EPS,
                1,
            )
        };
        // A hole 0.1 wide in a unit square: at K = 100 the spacing is about 0.09, and Ω_ε at
        // 0.686 of it fills the hole.
        let region = geometry::formats::loops_from_str(
            "0 0\n1 0\n1 1\n0 1\n\n0.2 0.2\n0.3 0.2\n0.3 0.8\n0.2 0.8\n",
            "thin hole",
            "thin hole",
        )
        .unwrap();
        assert!(row(&region, 100).is_none());
        assert!(row(&region, 2000).is_some());
        // A ring 0.02 wide: at K = 2000 the spacing is about 0.009 and the row alone would
        // take 1400 points.
        let ring = |r: f64| -> Vec<DVec2> {
            (0..256)
                .map(|i| DVec2::from_angle(std::f64::consts::TAU * i as f64 / 256.0) * r)
                .collect()
        };
        let thin = Region::from_loops(
            "thin ring",
            vec![
                (geometry::LoopRole::Outer, ring(1.0)),
                (geometry::LoopRole::Hole, ring(0.98)),
            ],
        )
        .unwrap();
        assert!(row(&thin, 2000).is_none());
        assert!(row(&thin, 200_000).is_some());
    }

    #[test]
    fn prolongation_of_a_mesh_splits_every_edge_once() {
        let region = Region::builtin("square_hole").unwrap();
        let r = Refine::default()
            .refine_with_area(&region, 0.05, &Density::Uniform, usize::MAX)
            .unwrap();
        let mesh = &r.mesh;
        let seeds = prolongate(&region, mesh);
        let (v, t) = (mesh.num_vertices(), mesh.triangles.len());
        let b = mesh.boundary_edges().len();
        // Euler: every triangle has 3 edges, interior ones shared by two.
        let edges = (3 * t + b) / 2;
        assert_eq!(seeds.points.len(), v + edges);
        // Boundary midpoints lie on ∂Ω; the others inside.
        for (p, on) in seeds.points.iter().zip(&seeds.on_boundary) {
            let d = region.signed_distance(*p);
            if *on {
                assert!(d.abs() < 1e-9, "{p}: {d}");
            } else {
                assert!(d < 0.0, "{p}: {d}");
            }
        }
        assert_eq!(seeds.on_boundary.iter().filter(|&&b| b).count(), 2 * b);
    }

    #[test]
    fn resampled_boundary_has_the_ccvt_spacing_and_keeps_the_corners() {
        // Graded toward the hole: the spacing along ∂Ω varies tenfold.
        let region = Region::builtin("square_hole").unwrap();
        let t = geometry::Threshold {
            size_min: 0.02,
            size_max: 0.2,
            dist_min: 0.0,
            dist_max: 1.0,
        };
        let field =
            geometry::SizeField::threshold(&region, &[geometry::Toward::Loop(1)], t).unwrap();
        let density = field.density(0.02);
        let scale = LocalScale::new(&region, &density, 0.05);
        let r = Refine::default()
            .refine_with_area(&region, 1e-3, &density, usize::MAX)
            .unwrap();
        let seeds = resample_boundary(&region, &scale, &r.mesh);
        let boundary: Vec<DVec2> = (0..seeds.points.len())
            .filter(|&i| seeds.on_boundary[i])
            .map(|i| seeds.points[i])
            .collect();
        for c in region.corners() {
            assert_eq!(boundary.iter().filter(|p| **p == c.pos).count(), 1, "{c:?}");
        }
        for p in &boundary {
            assert!(region.project(*p).distance < 1e-9, "{p}");
        }
        // Neighbours along each loop are BOUNDARY_SPACING·h apart, give or take the rounding
        // of each side's count and h's change along a step.
        for l in 0..region.loops().len() {
            let mut on: Vec<(f64, DVec2)> = boundary
                .iter()
                .map(|p| (region.project(*p), *p))
                .filter(|(b, _)| b.loop_index == l)
                .map(|(b, p)| (b.loop_param, p))
                .collect();
            on.sort_by(|a, b| a.0.total_cmp(&b.0));
            for i in 0..on.len() {
                let (p, q) = (on[i].1, on[(i + 1) % on.len()].1);
                let r = (q - p).length() / (BOUNDARY_SPACING * scale.at(0.5 * (p + q)));
                assert!((0.8..1.25).contains(&r), "loop {l} at {p}: {r}");
            }
        }
        for (p, on) in seeds.points.iter().zip(&seeds.on_boundary) {
            if !on {
                assert!(
                    -region.signed_distance(*p) >= CLEARANCE * scale.at(*p),
                    "{p}"
                );
            }
        }
    }

    /// Splitting a coarse mesh's edges doubles its boundary count, whatever it was (here 140
    /// points where CCVT's spacing asks for 121); laying ∂Ω out again gives the fine level
    /// CCVT's own boundary spacing, and the interior points are the split mesh's, clear of ∂Ω.
    #[test]
    fn a_prolongated_boundary_is_laid_out_at_the_fine_spacing() {
        let region = Region::builtin("circle").unwrap();
        let coarse_h = 0.1;
        let r = Refine::default()
            .refine_with_area(
                &region,
                0.5 * coarse_h * coarse_h,
                &Density::Uniform,
                usize::MAX,
            )
            .unwrap();
        let mesh = &r.mesh;
        let fine_h = 0.5 * coarse_h;
        let scale = LocalScale::new(&region, &Density::Uniform, fine_h);
        let on = |s: &Seeds| s.on_boundary.iter().filter(|&&b| b).count();
        let split = prolongate(&region, mesh);
        let seeds = prolongate_resampled(&region, &scale, mesh);
        let want = (std::f64::consts::TAU / (BOUNDARY_SPACING * fine_h)).round() as usize;
        assert!(
            on(&seeds).abs_diff(want) <= 1,
            "{} against {want}",
            on(&seeds)
        );
        assert_eq!(on(&split), 2 * mesh.boundary_edges().len());
        for (p, b) in seeds.points.iter().zip(&seeds.on_boundary) {
            let d = region.signed_distance(*p);
            if *b {
                assert!(d.abs() < 1e-9, "{p}: {d}");
            } else {
                assert!(-d >= CLEARANCE * fine_h, "{p}: {d}");
                assert!(split.points.contains(p), "{p}");
            }
        }
    }

    #[test]
    fn fitted_counts_are_exact_inside_and_reproducible() {
        let region = Region::builtin("lake").unwrap();
        // About a thousand vertices (the lake is 125 000 units of area).
        let spacing = (region.area() / 1000.0).sqrt();
        let scale = LocalScale::new(&region, &Density::Uniform, spacing);
        let r = Refine::default()
            .refine_with_area(
                &region,
                region.area() / 2000.0,
                &Density::Uniform,
                usize::MAX,
            )
            .unwrap();
        let n = r.mesh.num_vertices();
        for k in [n - 37, n, n + 41] {
            let a = fit_count(&region, &scale, Seeds::from_mesh(&r.mesh), k, 3);
            assert_eq!(a.len(), k);
            assert!(a.iter().all(|p| region.signed_distance(*p) <= 1e-12));
            let b = fit_count(&region, &scale, Seeds::from_mesh(&r.mesh), k, 3);
            assert_eq!(a, b);
        }
    }
}
