//! Is a converged CCVT a minimum of the constrained energy, or a saddle? The Hessian Newton
//! uses (interior generators free, boundary ones along their piece with the curvature term
//! g · γ'', corners fixed), its least eigenvalue by power iteration, and finite differences of
//! the energy along the same constrained path (boundary generators projected back onto their
//! piece) to check it.
//! `cargo run --release -p cvtmesh-tools --bin saddle -- REGION [K] [SEED] [ITERATIONS]`
//!
//! Prints the least eigenvalue relative to the mean 2m (Lloyd's scale), the generators that
//! carry its eigenvector (kind 0 interior, 1 boundary; depth in spacings), the energy change
//! along it at 0.05–0.8 spacings either way, its curvature by finite differences at three
//! steps, and the same comparison along random directions.
use cvtmesh::ccvt::Ccvt;
use cvtmesh::geometry::{DVec2, Density, PieceId, Rng};
use cvtmesh::tessellation::{clipped_cells, energy_hessian, BlockMatrix, Delaunay};
use cvtmesh::{MeshRequest, VertexMarker};

/// A generator's moves: free, along a piece (unit tangent, curvature vector, piece), fixed.
#[derive(Clone, Copy)]
enum Dof {
    Free,
    Along(DVec2, DVec2, PieceId),
    Fixed,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let region = cvtmesh::load_region(args.get(1).map_or("lake", String::as_str))?;
    let arg = |i: usize, default: u64| -> Result<u64, Box<dyn std::error::Error>> {
        Ok(args
            .get(i)
            .map(|s| s.parse())
            .transpose()?
            .unwrap_or(default))
    };
    let (k, seed, iterations) = (arg(2, 2000)? as usize, arg(3, 1)?, arg(4, 3000)?);
    let request = MeshRequest::points(k).seed(seed);
    let g = Ccvt::fast().generators(&region, &request, &mut |_| {})?;
    let z = &g.points;
    let n = z.len();
    let spacing = request.spacing(&region);
    // The solver's own domain polygon.
    let omega = region.polygonize(Ccvt::fast().polygon_tol * spacing);
    let density = Density::Uniform;
    let energy = |p: &[DVec2]| -> f64 {
        let d = Delaunay::new(p);
        let cells = clipped_cells(p, &d, &omega, &density);
        cells.cells.iter().map(|c| c.energy).sum()
    };
    let del = Delaunay::new(z);
    let cells = clipped_cells(z, &del, &omega, &density);
    let mut hessian = BlockMatrix::default();
    energy_hessian(&del, &omega, &density, &cells, &mut hessian);
    // Tangent and curvature vector from projections, as Newton takes them.
    let dofs: Vec<Dof> = (0..n)
        .map(|i| match g.markers[i] {
            VertexMarker::Interior => Dof::Free,
            VertexMarker::Boundary { piece, .. } => {
                let along = |d: f64, e: DVec2| {
                    (
                        region.project_onto_piece(z[i] + e * d, piece).point,
                        region.project_onto_piece(z[i] - e * d, piece).point,
                    )
                };
                let d = 1e-3 * spacing;
                let ((a, b), (c, e)) = (along(d, DVec2::X), along(d, DVec2::Y));
                let t = if (a - b).length_squared() >= (c - e).length_squared() {
                    a - b
                } else {
                    c - e
                }
                .normalize();
                let d = 0.25 * spacing;
                let (a, b) = along(d, t);
                Dof::Along(t, (a + b - 2.0 * z[i]) / (d * d), piece)
            }
            _ => Dof::Fixed,
        })
        .collect();
    let grad: Vec<DVec2> = (0..n)
        .map(|i| 2.0 * cells.cells[i].mass * (z[i] - cells.cells[i].mass_centroid))
        .collect();
    let project = |v: &mut [DVec2]| {
        for (x, d) in v.iter_mut().zip(&dofs) {
            *x = match *d {
                Dof::Free => *x,
                Dof::Along(t, ..) => t * t.dot(*x),
                Dof::Fixed => DVec2::ZERO,
            };
        }
    };
    // P H P v + the curvature term, v and the result in input order.
    let apply = |v: &[DVec2]| -> Vec<DVec2> {
        let nv = del.num_vertices();
        let by_vertex: Vec<DVec2> = (0..nv).map(|r| v[del.point_of_vertex(r)]).collect();
        let mut out = vec![DVec2::ZERO; nv];
        hessian.mul_vec(&by_vertex, &mut out);
        let mut res = vec![DVec2::ZERO; n];
        for (r, o) in out.iter().enumerate() {
            res[del.point_of_vertex(r)] = *o;
        }
        for i in 0..n {
            if let Dof::Along(t, curve, _) = dofs[i] {
                res[i] += t * (grad[i].dot(curve) * t.dot(v[i]));
            }
        }
        project(&mut res);
        res
    };
    let dot = |a: &[DVec2], b: &[DVec2]| a.iter().zip(b).map(|(x, y)| x.dot(*y)).sum::<f64>();
    let path = |v: &[DVec2], s: f64| -> Vec<DVec2> {
        (0..n)
            .map(|i| match dofs[i] {
                Dof::Free => z[i] + v[i] * s,
                Dof::Along(_, _, piece) => region.project_onto_piece(z[i] + v[i] * s, piece).point,
                Dof::Fixed => z[i],
            })
            .collect()
    };
    let e0 = energy(z);
    let second =
        |v: &[DVec2], d: f64| (energy(&path(v, d)) - 2.0 * e0 + energy(&path(v, -d))) / (d * d);
    let m2 = 2.0 * cells.cells.iter().map(|c| c.mass).sum::<f64>() / n as f64;
    println!(
        "{k} generators, seed {seed}, converged {}, {} on pieces, mean 2m {m2:.4e}",
        g.converged,
        dofs.iter().filter(|d| matches!(d, Dof::Along(..))).count()
    );
    // Power iteration on c I − A: a Voronoi cell's block is at most a few 2m.
    let c = 16.0 * m2;
    let mut rng = Rng::new(seed);
    let random = |rng: &mut Rng| {
        let mut v: Vec<DVec2> = (0..n)
            .map(|_| DVec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)))
            .collect();
        project(&mut v);
        let norm = dot(&v, &v).sqrt();
        v.iter_mut().for_each(|x| *x /= norm);
        v
    };
    let mut v = random(&mut rng);
    for _ in 0..iterations {
        let av = apply(&v);
        let w: Vec<DVec2> = v.iter().zip(&av).map(|(x, y)| *x * c - *y).collect();
        let norm = dot(&w, &w).sqrt();
        v = w.into_iter().map(|x| x / norm).collect();
    }
    let least = dot(&v, &apply(&v));
    println!(
        "least eigenvalue {least:.4e} ({:.4} of 2m) after {iterations} iterations",
        least / m2
    );
    let mut carriers: Vec<(f64, usize)> = (0..n).map(|i| (v[i].length(), i)).collect();
    carriers.sort_by(|a, b| b.0.total_cmp(&a.0));
    for &(a, i) in carriers.iter().take(6) {
        println!(
            "  generator {i} at ({:.4}, {:.4}) {:?}: share {a:.3}, depth {:.2} spacings",
            z[i].x,
            z[i].y,
            g.markers[i],
            -region.signed_distance(z[i]) / spacing
        );
    }
    for f in [0.05, 0.1, 0.2, 0.4, 0.8] {
        let (up, down) = (
            energy(&path(&v, f * spacing)),
            energy(&path(&v, -f * spacing)),
        );
        println!(
            "  moved {f} spacings along it: energy {:+.3e} / {:+.3e} of itself",
            (up - e0) / e0,
            (down - e0) / e0
        );
    }
    for d in [1e-2, 3e-3, 1e-3] {
        println!(
            "  curvature along it by differences at {d:e} spacings: {:.4e}",
            second(&v, d * spacing)
        );
    }
    for _ in 0..3 {
        let r = random(&mut rng);
        println!(
            "random direction: Hessian {:.6e}, differences {:.6e}",
            dot(&r, &apply(&r)),
            second(&r, 1e-3 * spacing)
        );
    }
    Ok(())
}
