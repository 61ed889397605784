//! `measures_from_parts` on hand-built cells and triangles with hand-worked answers.
use cvtmesh_metrics::{measures_from_parts, Measures, MetricsError};
use geometry::DVec2;
use std::f64::consts::{FRAC_1_SQRT_2, PI, SQRT_2};
use tessellation::{Cell, Cells};

/// The cell of generator `z` whose region is the convex CCW polygon `verts`: exact area,
/// centroid and second moment (shoelace-type formulas about `z`), h = farthest vertex.
fn cell(z: DVec2, verts: &[DVec2]) -> Cell {
    let n = verts.len();
    let (mut a, mut cx, mut cy, mut ixx, mut ixy, mut iyy) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..n {
        let (p, q) = (verts[i] - z, verts[(i + 1) % n] - z);
        let w = p.perp_dot(q);
        a += w / 2.0;
        cx += (p.x + q.x) * w / 6.0;
        cy += (p.y + q.y) * w / 6.0;
        ixx += (p.x * p.x + p.x * q.x + q.x * q.x) * w / 12.0;
        iyy += (p.y * p.y + p.y * q.y + q.y * q.y) * w / 12.0;
        ixy += (p.x * q.y + 2.0 * p.x * p.y + 2.0 * q.x * q.y + q.x * p.y) * w / 24.0;
    }
    let c = DVec2::new(cx / a, cy / a);
    let m = [
        ixx / a - c.x * c.x,
        ixy / a - c.x * c.y,
        iyy / a - c.y * c.y,
    ];
    let h = verts.iter().map(|v| (*v - z).length()).fold(0.0, f64::max);
    Cell {
        area: a,
        centroid: z + c,
        second_moment: m,
        mass: a,
        mass_centroid: z + c,
        energy: ixx + iyy,
        h,
        pieces: Vec::new(),
    }
}

fn rect(lo: DVec2, hi: DVec2) -> Vec<DVec2> {
    vec![lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)]
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

#[track_caller]
fn assert_close(name: &str, got: f64, want: f64, tol: f64) {
    assert!(close(got, want, tol), "{name}: got {got}, want {want}");
}

/// A patch of the triangular lattice with spacing `s`, rotated by `theta` and shifted by
/// `shift`; every point gets its full regular hexagonal Voronoi cell, every rhombus two
/// equilateral triangles.
fn hex_patch(n: usize, s: f64, theta: f64, shift: DVec2) -> (Vec<DVec2>, Vec<[u32; 3]>, Cells) {
    let rot = DVec2::from_angle(theta);
    let mut points = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let p = DVec2::new(i as f64 + 0.5 * j as f64, j as f64 * 3f64.sqrt() / 2.0) * s;
            points.push(rot.rotate(p) + shift);
        }
    }
    let mut tris = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let v = |i: usize, j: usize| (j * n + i) as u32;
            tris.push([v(i, j), v(i + 1, j), v(i, j + 1)]);
            tris.push([v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    let r = s / 3f64.sqrt();
    let cells = points
        .iter()
        .map(|z| {
            let verts: Vec<DVec2> = (0..6)
                .map(|m| *z + rot.rotate(DVec2::from_angle(PI / 6.0 + m as f64 * PI / 3.0) * r))
                .collect();
            cell(*z, &verts)
        })
        .collect();
    (points, tris, Cells { cells })
}

#[test]
fn regular_hexagonal_lattice_is_ideal() {
    for &(s, theta, shift) in &[
        (1.0, 0.0, DVec2::ZERO),
        (0.037, 0.61, DVec2::new(12.5, -3.25)),
    ] {
        let (points, tris, cells) = hex_patch(7, s, theta, shift);
        let k = points.len() as f64;
        let hex_area = 3f64.sqrt() / 2.0 * s * s;
        assert_close("cell area", cells.cells[3].area, hex_area, 1e-12);
        // |Ω| = K·|hexagon| makes h* the actual h_k, so h = 0 too.
        let m = measures_from_parts(&points, &tris, &cells, k * hex_area).unwrap();
        assert_eq!((m.k, m.k_tilde), (49, 72));
        let tau_scale = s * s;
        for (name, v) in [
            ("lambda", m.lambda),
            ("gamma", m.gamma),
            ("h", m.h),
            ("mu", m.mu),
            ("chi", m.chi),
            ("nu", m.nu),
            ("tau", m.tau / tau_scale),
            ("d", m.d / (tau_scale * tau_scale)),
            ("beta", m.beta),
            ("q", m.q),
            ("p", m.p),
        ] {
            assert!(v.abs() < 1e-12, "{name} = {v}");
        }
        // α = 0 when |Ω| is exactly the triangles' total area.
        let tri_area = 3f64.sqrt() / 4.0 * s * s;
        let m = measures_from_parts(&points, &tris, &cells, tris.len() as f64 * tri_area).unwrap();
        assert!(m.alpha.abs() < 1e-12, "alpha = {}", m.alpha);
    }
}

#[test]
fn unit_square_by_hand() {
    let points = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(0.0, 1.0),
    ];
    let tris = vec![[0, 1, 2], [0, 2, 3]];
    // Each corner's Voronoi cell in the unit square is the quarter square at that corner.
    let cells = Cells {
        cells: points
            .iter()
            .map(|z| {
                let lo = DVec2::new(
                    if z.x < 0.5 { 0.0 } else { 0.5 },
                    if z.y < 0.5 { 0.0 } else { 0.5 },
                );
                cell(*z, &rect(lo, lo + 0.5))
            })
            .collect(),
    };
    let m = measures_from_parts(&points, &tris, &cells, 1.0).unwrap();
    let h_star = (12f64.sqrt() / 36.0).sqrt();
    let want = Measures {
        k: 4,
        k_tilde: 2,
        lambda: 0.0,
        gamma: 0.0,
        h: FRAC_1_SQRT_2 / h_star - 1.0,
        mu: 0.0,
        chi: 6f64.sqrt() / 2.0 - 1.0,
        nu: 0.0,
        tau: 0.0,
        d: 0.0,
        alpha: 0.0,
        beta: 1.0 / 3.0,
        q: (SQRT_2 - 1.0) / 2.0, // R/(2r) of the right isosceles triangle is (√2 + 1)/2
        p: 0.0,
    };
    for (i, name) in Measures::NAMES.iter().enumerate() {
        assert_close(name, m.values()[i], want.values()[i], 1e-13);
    }
}

#[test]
fn anisotropic_cells_tau_d_nu_by_hand() {
    // Pure function: the cells need not be these points' Voronoi cells.
    let points = vec![
        DVec2::new(0.5, 0.5),
        DVec2::new(1.75, 0.5),
        DVec2::new(3.75, 0.75),
    ];
    let tris = vec![[0, 1, 2]];
    let widths = [(0.0, 1.0), (1.0, 2.5), (2.5, 5.0)];
    let cells = Cells {
        cells: widths
            .iter()
            .zip(&points)
            .map(|(&(a, b), z)| cell(*z, &rect(DVec2::new(a, 0.0), DVec2::new(b, 1.0))))
            .collect(),
    };
    let m = measures_from_parts(&points, &tris, &cells, 5.0).unwrap();
    // A w×1 rectangle: τ = (w² + 1)/12, |D| = ((w² − 1)/24)². Widths 1, 1.5, 2.5.
    assert_close("tau", m.tau, 37.0 / 144.0, 1e-13);
    assert_close("d", m.d, 49.0 / 1024.0, 1e-13);
    assert_close("nu", m.nu, 1.5, 1e-13);
    // h_k: generator to farthest rectangle corner.
    let hk = [0.5f64.hypot(0.5), 0.75f64.hypot(0.5), 1.25f64.hypot(0.75)];
    assert_close("mu", m.mu, hk[2] / hk[0] - 1.0, 1e-13);
    // γ_k: z0–z1 = 1.25 is nearest for both, z2's nearest is z1 at (2, 0.25).
    let gk = [1.25, 1.25, 2f64.hypot(0.25)];
    let chi = (0..3)
        .map(|i| 3f64.sqrt() * hk[i] / gk[i])
        .fold(0.0, f64::max)
        - 1.0;
    assert_close("chi", m.chi, chi, 1e-13);
    let mean = (gk[0] + gk[1] + gk[2]) / 3.0;
    let sd = (gk.iter().map(|g| (g - mean).powi(2)).sum::<f64>() / 3.0).sqrt();
    assert_close("lambda", m.lambda, sd / mean, 1e-13);
    assert_close("gamma", m.gamma, gk[2] / 1.25 - 1.0, 1e-13);
}

#[test]
fn p_uses_population_standard_deviation() {
    // Two right isosceles triangles, legs 1 and 2: R = √2/2 and √2, mean 3√2/4, population
    // std √2/4, so p = 1/3 (the sample std would give √2/3).
    let points = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(0.0, 1.0),
        DVec2::new(3.0, 0.0),
        DVec2::new(5.0, 0.0),
        DVec2::new(3.0, 2.0),
    ];
    let tris = vec![[0, 1, 2], [3, 4, 5]];
    let cells = Cells {
        cells: points
            .iter()
            .map(|z| cell(*z, &rect(*z - 0.1, *z + 0.1)))
            .collect(),
    };
    let m = measures_from_parts(&points, &tris, &cells, 2.5).unwrap();
    assert_close("p", m.p, 1.0 / 3.0, 1e-14);
    // α: K̃/|Ω|·max area − 1 = 2/2.5·2 − 1.
    assert_close("alpha", m.alpha, 0.6, 1e-14);
    assert_close("beta", m.beta, 1.0 / 3.0, 1e-14);
    assert_close("q", m.q, (SQRT_2 - 1.0) / 2.0, 1e-14);
    // Orientation of the triangles does not matter.
    let cw = vec![[0, 2, 1], [3, 5, 4]];
    assert_eq!(measures_from_parts(&points, &cw, &cells, 2.5).unwrap(), m);
}

#[test]
fn degenerate_input_gives_infinite_measures() {
    let mut points = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(0.0, 1.0),
    ];
    points.push(points[1]); // duplicate point: γ_k = 0
    let c = |z: DVec2| cell(z, &rect(z - 0.1, z + 0.1));
    let cells = Cells {
        cells: points.iter().map(|z| c(*z)).collect(),
    };
    let m = measures_from_parts(&points, &[[0, 1, 2]], &cells, 1.0).unwrap();
    assert_eq!(m.gamma, f64::INFINITY);
    assert_eq!(m.chi, f64::INFINITY);
    assert!(m.lambda.is_finite() && m.lambda > 0.0);
    // A flat triangle.
    let flat = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(2.0, 0.0),
    ];
    let cells = Cells {
        cells: flat.iter().map(|z| c(*z)).collect(),
    };
    let m = measures_from_parts(&flat, &[[0, 1, 2]], &cells, 1.0).unwrap();
    assert_eq!(
        (m.beta, m.q, m.p),
        (f64::INFINITY, f64::INFINITY, f64::INFINITY)
    );
    assert_eq!(m.alpha, -1.0);
}

#[test]
fn bad_input_is_an_error_value() {
    let pts = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(0.0, 1.0),
    ];
    let cells = Cells {
        cells: pts
            .iter()
            .map(|z| cell(*z, &rect(*z - 0.1, *z + 0.1)))
            .collect(),
    };
    let t = [[0u32, 1, 2]];
    let e = |r: Result<Measures, MetricsError>| r.unwrap_err();
    assert_eq!(
        e(measures_from_parts(
            &pts[..1],
            &t,
            &Cells {
                cells: cells.cells[..1].to_vec()
            },
            1.0
        )),
        MetricsError::TooFewPoints(1)
    );
    assert_eq!(
        e(measures_from_parts(&pts, &[], &cells, 1.0)),
        MetricsError::NoTriangles
    );
    assert!(matches!(
        e(measures_from_parts(&pts, &[[0, 1, 3]], &cells, 1.0)),
        MetricsError::BadTriangle { vertex: 3, .. }
    ));
    assert!(matches!(
        e(measures_from_parts(
            &pts,
            &t,
            &Cells {
                cells: cells.cells[..2].to_vec()
            },
            1.0
        )),
        MetricsError::CellCount {
            cells: 2,
            points: 3
        }
    ));
    assert!(matches!(
        e(measures_from_parts(&pts, &t, &cells, 0.0)),
        MetricsError::BadArea(_)
    ));
    assert!(matches!(
        e(measures_from_parts(&pts, &t, &cells, f64::NAN)),
        MetricsError::BadArea(_)
    ));
    let mut nan = pts.clone();
    nan[2].y = f64::NAN;
    assert!(matches!(
        e(measures_from_parts(&nan, &t, &cells, 1.0)),
        MetricsError::NonFinitePoint { index: 2, .. }
    ));
}
