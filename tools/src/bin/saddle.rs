//! Is a converged CCVT a minimum of the constrained energy, or a saddle? The Hessian Newton
//! uses (interior generators free, boundary ones along their piece with the curvature term
//! g · γ'' from `ccvt::piece_tangent`, corners fixed), its least eigenvalue by power iteration,
//! and finite differences of the energy along the same constrained path (boundary generators
//! projected back onto their piece) to check it.
//! `cargo run --release -p cvtmesh-tools --bin saddle -- REGION [K] [SEED] [ITERATIONS]`
//!
//! Prints the least eigenvalue relative to the mean 2m (Lloyd's scale), the generators that
//! carry its eigenvector (marker, depth in spacings), the energy change along it at 0.05–0.8
//! spacings either way and its curvature by finite differences at three steps; then the
//! boundary patches (a boundary generator and two rings of its Delaunay neighbours) whose own
//! least eigenvalue is negative, each with the best energy change a step of 0.1–0.5 spacings
//! along its eigenvector gives; and the Hessian against differences along random directions.
use cvtmesh::ccvt::{piece_tangent, Ccvt};
use cvtmesh::geometry::{DVec2, Density, PieceId, Rng};
use cvtmesh::tessellation::{clipped_cells, dot, energy_hessian, BlockMatrix, Delaunay};
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
        clipped_cells(p, &d, &omega, &density).energy()
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
                let (t, curve) = piece_tangent(&region, z[i], piece, spacing);
                Dof::Along(t, curve, piece)
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
    // Local patches: each boundary generator with its Delaunay neighbours, the same matrix
    // restricted to their moves. A negative eigenvalue there is one of the whole matrix too
    // (interlacing), with its eigenvector padded by zeros.
    let mut saddles: Vec<(f64, Vec<(usize, DVec2)>)> = Vec::new();
    for b in 0..n {
        if !matches!(dofs[b], Dof::Along(..)) {
            continue;
        }
        if del.vertex_index(b).is_none() {
            continue;
        }
        // The generator, its Delaunay neighbours and theirs.
        let mut patch = vec![b];
        for u in del.neighbors(b) {
            patch.push(u);
            patch.extend(del.neighbors(u));
        }
        patch.sort_unstable();
        patch.dedup();
        if let Some(at) = patch.iter().position(|&i| i == b) {
            patch.swap(0, at);
        }
        // Columns: (generator, unit direction).
        let mut cols: Vec<(usize, DVec2)> = Vec::new();
        for &i in &patch {
            match dofs[i] {
                Dof::Free => cols.extend([(i, DVec2::X), (i, DVec2::Y)]),
                Dof::Along(t, ..) => cols.push((i, t)),
                Dof::Fixed => {}
            }
        }
        let m = cols.len();
        let mut a = vec![0.0; m * m];
        for (p, &(i, u)) in cols.iter().enumerate() {
            for (q, &(j, w)) in cols.iter().enumerate() {
                let (vi, vj) = (del.vertex_index(i).unwrap(), del.vertex_index(j).unwrap());
                let mut x = u.dot(hessian.get(vi, vj) * w);
                if i == j {
                    if let Dof::Along(t, curve, _) = dofs[i] {
                        x += grad[i].dot(curve) * u.dot(t) * w.dot(t);
                    }
                }
                a[p * m + q] = x;
            }
        }
        let (lam, vec) = least_eigen(&a, m);
        if lam < -1e-3 * m2 {
            saddles.push((
                lam,
                cols.iter()
                    .zip(&vec)
                    .map(|(&(i, u), &c)| (i, u * c))
                    .collect(),
            ));
        }
    }
    saddles.sort_by(|x, y| x.0.total_cmp(&y.0));
    println!(
        "{} boundary patches with negative curvature below -1e-3 of 2m",
        saddles.len()
    );
    let mut gain = 0.0;
    let mut escaped = z.clone();
    for (lam, v) in &saddles {
        let mut dir = vec![DVec2::ZERO; n];
        for &(i, d) in v {
            dir[i] += d;
        }
        let big = dir.iter().fold(0.0f64, |m, d| m.max(d.length()));
        let mut best = (0.0, 0.0);
        for f in [0.1, 0.2, 0.3, 0.4, 0.5] {
            for sg in [1.0, -1.0] {
                let e = energy(&path(&dir, sg * f * spacing / big));
                if e - e0 < best.0 {
                    best = (e - e0, sg * f);
                }
            }
        }
        gain += best.0;
        let moved = path(&dir, best.1 * spacing / big);
        for &(i, _) in v {
            escaped[i] = moved[i];
        }
        if saddles.len() <= 12 || *lam == saddles[0].0 {
            println!(
                "  {:.4} of 2m at generator {} ({:?}): best {:+.3e} of E at {:+.1} spacings",
                lam / m2,
                v[0].0,
                g.markers[v[0].0],
                best.0 / e0,
                best.1
            );
        }
    }
    println!(
        "sum of the best single escapes {:+.3e} of E; all at once {:+.3e}",
        gain / e0,
        (energy(&escaped) - e0) / e0
    );
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

/// Least eigenvalue and its unit eigenvector of the symmetric `m`×`m` matrix `a` (row-major),
/// by cyclic Jacobi rotations.
fn least_eigen(a: &[f64], m: usize) -> (f64, Vec<f64>) {
    let mut a = a.to_vec();
    let mut v = vec![0.0; m * m];
    for i in 0..m {
        v[i * m + i] = 1.0;
    }
    for _ in 0..50 {
        let off: f64 = (0..m)
            .flat_map(|p| (0..m).filter(move |&q| q != p).map(move |q| (p, q)))
            .map(|(p, q)| a[p * m + q] * a[p * m + q])
            .sum();
        if off < 1e-30 {
            break;
        }
        for p in 0..m {
            for q in p + 1..m {
                let apq = a[p * m + q];
                if apq.abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q * m + q] - a[p * m + p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..m {
                    let (akp, akq) = (a[k * m + p], a[k * m + q]);
                    a[k * m + p] = c * akp - s * akq;
                    a[k * m + q] = s * akp + c * akq;
                }
                for k in 0..m {
                    let (apk, aqk) = (a[p * m + k], a[q * m + k]);
                    a[p * m + k] = c * apk - s * aqk;
                    a[q * m + k] = s * apk + c * aqk;
                }
                for k in 0..m {
                    let (vkp, vkq) = (v[k * m + p], v[k * m + q]);
                    v[k * m + p] = c * vkp - s * vkq;
                    v[k * m + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    let j = (0..m)
        .min_by(|&x, &y| a[x * m + x].total_cmp(&a[y * m + y]))
        .unwrap_or(0);
    (a[j * m + j], (0..m).map(|k| v[k * m + j]).collect())
}
