//! One smooth boundary piece Γ_j of Section 2.2.2.
use crate::predicates::closest_on_segment;
use crate::se::SuperEllipse;
use glam::DVec2;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};

/// A boundary piece: smooth between its end points (corners sit only at piece junctions).
/// Every piece is traversed in its loop's direction (outer CCW, holes CW).
#[derive(Clone, Debug, PartialEq)]
pub enum Piece {
    /// Straight segment from `a` to `b`.
    Line {
        /// Start.
        a: DVec2,
        /// End.
        b: DVec2,
    },
    /// Circular arc from angle `from` to angle `to` (radians); CCW when `to > from`.
    Arc {
        /// Centre.
        center: DVec2,
        /// Radius.
        radius: f64,
        /// Start angle (radians).
        from: f64,
        /// End angle (radians).
        to: f64,
    },
    /// A full circle, a whole loop on its own; `ccw` gives its direction.
    Circle {
        /// Centre.
        center: DVec2,
        /// Radius.
        radius: f64,
        /// Direction of traversal.
        ccw: bool,
    },
    /// A full super-ellipse |x/a|^n + |y/b|^n = 1 about `center`, a whole loop on its own.
    SuperEllipse {
        /// Centre.
        center: DVec2,
        /// Semi-axis along x.
        a: f64,
        /// Semi-axis along y.
        b: f64,
        /// Exponent n ≥ 2 (smooth).
        n: f64,
        /// Direction of traversal.
        ccw: bool,
    },
    /// A densely sampled curve (a parametric curve, or nearly straight polyline vertices merged
    /// by the corner-angle threshold), treated as one smooth piece.
    Chain(Vec<DVec2>),
}

impl Piece {
    /// First point.
    pub fn start(&self) -> DVec2 {
        match self {
            Piece::Line { a, .. } => *a,
            Piece::Arc {
                center,
                radius,
                from,
                ..
            } => *center + *radius * unit(*from),
            Piece::Circle { center, radius, .. } => *center + DVec2::new(*radius, 0.0),
            Piece::SuperEllipse { center, a, .. } => *center + DVec2::new(*a, 0.0),
            Piece::Chain(p) => p.first().copied().unwrap_or(DVec2::NAN),
        }
    }
    /// Last point (equals `start()` for closed pieces).
    pub fn end(&self) -> DVec2 {
        match self {
            Piece::Line { b, .. } => *b,
            Piece::Arc {
                center, radius, to, ..
            } => *center + *radius * unit(*to),
            Piece::Circle { .. } | Piece::SuperEllipse { .. } => self.start(),
            Piece::Chain(p) => p.last().copied().unwrap_or(DVec2::NAN),
        }
    }
    /// What the piece is, in a word: `line`, `arc`, `circle`, `super-ellipse` or `chain`.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Piece};
    /// assert_eq!(Piece::Line { a: DVec2::ZERO, b: DVec2::X }.kind(), "line");
    /// ```
    pub fn kind(&self) -> &'static str {
        match self {
            Piece::Line { .. } => "line",
            Piece::Arc { .. } => "arc",
            Piece::Circle { .. } => "circle",
            Piece::SuperEllipse { .. } => "super-ellipse",
            Piece::Chain(_) => "chain",
        }
    }
    /// True for pieces that form a whole loop (circle, super-ellipse).
    pub fn is_closed(&self) -> bool {
        matches!(self, Piece::Circle { .. } | Piece::SuperEllipse { .. })
    }
    /// Arc length.
    pub fn length(&self) -> f64 {
        match self {
            Piece::Line { a, b } => a.distance(*b),
            Piece::Arc {
                radius, from, to, ..
            } => radius * (to - from).abs(),
            Piece::Circle { radius, .. } => TAU * radius,
            Piece::SuperEllipse { .. } => self.superellipse().map_or(f64::NAN, |s| s.length()),
            Piece::Chain(p) => p.windows(2).map(|w| w[0].distance(w[1])).sum(),
        }
    }
    /// Nearest point of the piece to `p` and its arc-length parameter from `start()`.
    pub fn closest_point(&self, p: DVec2) -> (DVec2, f64) {
        let f = self.foot(p);
        (f.point, self.arc_length_at(f.aux))
    }
    /// Points along the piece from `start()` to `end()` inclusive, such that the chord error
    /// (largest distance from the curve to the polyline) is at most `tol`.
    ///
    /// Arcs and circles are split uniformly (at least one segment per 45°), super-ellipses
    /// adaptively (at least two segments per octant). A chain is simplified by
    /// Douglas–Peucker (every dropped point stays within `tol` of the result, with `tol`
    /// capped at a tenth of the chain's extent), so a chain keeps all its points when `tol`
    /// is below its smallest feature.
    pub fn polygonize(&self, tol: f64) -> Vec<DVec2> {
        let tol = if tol > 0.0 { tol } else { f64::MIN_POSITIVE };
        match self {
            Piece::Line { a, b } => vec![*a, *b],
            Piece::Arc {
                center,
                radius,
                from,
                to,
            } => {
                let n = arc_segments((to - from).abs(), *radius, tol);
                let mut pts = Vec::with_capacity(n + 1);
                pts.push(self.start());
                for i in 1..n {
                    let th = from + (to - from) * (i as f64 / n as f64);
                    pts.push(*center + *radius * unit(th));
                }
                pts.push(self.end());
                pts
            }
            Piece::Circle {
                center,
                radius,
                ccw,
            } => {
                let n = arc_segments(TAU, *radius, tol);
                let sign = if *ccw { 1.0 } else { -1.0 };
                let mut pts: Vec<DVec2> = (0..n)
                    .map(|i| *center + *radius * unit(sign * TAU * (i as f64 / n as f64)))
                    .collect();
                pts[0] = self.start();
                pts.push(pts[0]);
                pts
            }
            Piece::SuperEllipse { .. } => self
                .superellipse()
                .map_or_else(Vec::new, |s| s.polygonize(tol)),
            Piece::Chain(p) => {
                // Keep some shape even for a huge tolerance (a closed chain must not collapse).
                let (lo, hi) = self.bbox();
                douglas_peucker(p, tol.min(0.1 * (hi - lo).length()))
            }
        }
    }
    /// Exact ∮ x dy over the piece (Green's theorem); summed over a loop it is the signed area.
    pub fn area_integral(&self) -> f64 {
        match self {
            Piece::Line { a, b } => 0.5 * (a.x + b.x) * (b.y - a.y),
            Piece::Arc {
                center,
                radius,
                from,
                to,
            } => {
                let r = *radius;
                center.x * r * (to.sin() - from.sin())
                    + r * r * (0.5 * (to - from) + 0.25 * ((2.0 * to).sin() - (2.0 * from).sin()))
            }
            Piece::Circle { radius, ccw, .. } => sign(*ccw) * PI * radius * radius,
            Piece::SuperEllipse { ccw, .. } => {
                sign(*ccw) * self.superellipse().map_or(f64::NAN, |s| s.area())
            }
            Piece::Chain(p) => p
                .windows(2)
                .map(|w| 0.5 * (w[0].x + w[1].x) * (w[1].y - w[0].y))
                .sum(),
        }
    }
    /// Unit tangent at the start and at the end, in traversal direction (for corner angles).
    pub fn end_tangents(&self) -> (DVec2, DVec2) {
        match self {
            Piece::Line { a, b } => {
                let d = (*b - *a).normalize_or_zero();
                (d, d)
            }
            Piece::Arc { from, to, .. } => {
                let s = if to > from { 1.0 } else { -1.0 };
                (s * unit(*from).perp(), s * unit(*to).perp())
            }
            Piece::Circle { ccw, .. } | Piece::SuperEllipse { ccw, .. } => {
                let t = DVec2::new(0.0, sign(*ccw));
                (t, t)
            }
            Piece::Chain(p) => {
                let first = p
                    .windows(2)
                    .map(|w| w[1] - w[0])
                    .find(|d| *d != DVec2::ZERO);
                let last = p
                    .windows(2)
                    .rev()
                    .map(|w| w[1] - w[0])
                    .find(|d| *d != DVec2::ZERO);
                (
                    first.unwrap_or(DVec2::ZERO).normalize_or_zero(),
                    last.unwrap_or(DVec2::ZERO).normalize_or_zero(),
                )
            }
        }
    }

    // ----- crate-internal helpers -----

    /// The super-ellipse helper for a `SuperEllipse` piece.
    pub(crate) fn superellipse(&self) -> Option<SuperEllipse> {
        match self {
            Piece::SuperEllipse {
                center,
                a,
                b,
                n,
                ccw,
            } => Some(SuperEllipse::new(*center, *a, *b, *n, *ccw)),
            _ => None,
        }
    }

    /// Nearest point with a piece-specific parameter (`aux`) and whether it is an end point.
    pub(crate) fn foot(&self, p: DVec2) -> Foot {
        match self {
            Piece::Line { a, b } => {
                let (q, t, d2) = closest_on_segment(*a, *b, p);
                Foot {
                    point: q,
                    d2,
                    aux: t,
                    end: FootAt::of_t(t),
                }
            }
            Piece::Arc {
                center,
                radius,
                from,
                to,
            } => {
                let rel = p - *center;
                let (s, sweep) = (if to > from { 1.0 } else { -1.0 }, (to - from).abs());
                let delta = (s * (rel.y.atan2(rel.x) - from)).rem_euclid(TAU);
                let len = rel.length();
                if delta <= sweep && len > 0.0 {
                    let q = *center + rel * (*radius / len);
                    Foot {
                        point: q,
                        d2: (p - q).length_squared(),
                        aux: delta,
                        end: FootAt::Interior,
                    }
                } else {
                    let (qs, qe) = (self.start(), self.end());
                    let (ds, de) = ((p - qs).length_squared(), (p - qe).length_squared());
                    if ds <= de {
                        Foot {
                            point: qs,
                            d2: ds,
                            aux: 0.0,
                            end: FootAt::Start,
                        }
                    } else {
                        Foot {
                            point: qe,
                            d2: de,
                            aux: sweep,
                            end: FootAt::End,
                        }
                    }
                }
            }
            Piece::Circle {
                center,
                radius,
                ccw,
            } => {
                let rel = p - *center;
                let len = rel.length();
                if len == 0.0 {
                    return Foot {
                        point: self.start(),
                        d2: radius * radius,
                        aux: 0.0,
                        end: FootAt::Interior,
                    };
                }
                let q = *center + rel * (*radius / len);
                let aux = (sign(*ccw) * rel.y.atan2(rel.x)).rem_euclid(TAU);
                Foot {
                    point: q,
                    d2: (p - q).length_squared(),
                    aux,
                    end: FootAt::Interior,
                }
            }
            Piece::SuperEllipse {
                center,
                a,
                b,
                n,
                ccw,
            } => {
                let (q, d2, t) = SuperEllipse::new(*center, *a, *b, *n, *ccw).closest(p);
                Foot {
                    point: q,
                    d2,
                    aux: t,
                    end: FootAt::Interior,
                }
            }
            Piece::Chain(pts) => {
                let mut best = Foot {
                    point: self.start(),
                    d2: f64::INFINITY,
                    aux: 0.0,
                    end: FootAt::Start,
                };
                for (i, w) in pts.windows(2).enumerate() {
                    let (q, t, d2) = closest_on_segment(w[0], w[1], p);
                    if d2 < best.d2 {
                        best = Foot {
                            point: q,
                            d2,
                            aux: i as f64 + t,
                            end: FootAt::Interior,
                        };
                    }
                }
                if pts.len() < 2 {
                    best.d2 = (p - best.point).length_squared();
                }
                let last = pts.len().saturating_sub(1) as f64;
                best.end = if best.aux <= 0.0 {
                    FootAt::Start
                } else if best.aux >= last {
                    FootAt::End
                } else {
                    FootAt::Interior
                };
                best
            }
        }
    }

    /// Arc length from `start()` to the point with parameter `aux` (as returned by `foot`).
    pub(crate) fn arc_length_at(&self, aux: f64) -> f64 {
        match self {
            Piece::Line { a, b } => aux * a.distance(*b),
            Piece::Arc { radius, .. } | Piece::Circle { radius, .. } => radius * aux,
            Piece::SuperEllipse { .. } => {
                self.superellipse().map_or(f64::NAN, |s| s.arc_length(aux))
            }
            Piece::Chain(p) => {
                let i = (aux.floor().max(0.0) as usize).min(p.len().saturating_sub(2));
                let before: f64 = p[..=i].windows(2).map(|w| w[0].distance(w[1])).sum();
                before + (aux - i as f64) * p.get(i + 1).map_or(0.0, |q| q.distance(p[i]))
            }
        }
    }

    /// Signed side of p for a curved piece: positive when p is left of the traversal
    /// (inside the region near this piece), judged on the whole underlying curve.
    pub(crate) fn side(&self, p: DVec2) -> f64 {
        match self {
            Piece::Line { a, b } => crate::predicates::orient(*a, *b, p),
            Piece::Arc {
                center,
                radius,
                from,
                to,
            } => {
                let s = if to > from { 1.0 } else { -1.0 };
                s * (radius - p.distance(*center))
            }
            Piece::Circle {
                center,
                radius,
                ccw,
            } => sign(*ccw) * (radius - p.distance(*center)),
            Piece::SuperEllipse { ccw, .. } => {
                -sign(*ccw) * self.superellipse().map_or(f64::NAN, |s| s.implicit(p))
            }
            Piece::Chain(_) => f64::NAN,
        }
    }

    /// The same curve traversed the other way.
    pub(crate) fn reversed(&self) -> Piece {
        match self {
            Piece::Line { a, b } => Piece::Line { a: *b, b: *a },
            Piece::Arc {
                center,
                radius,
                from,
                to,
            } => Piece::Arc {
                center: *center,
                radius: *radius,
                from: *to,
                to: *from,
            },
            Piece::Circle {
                center,
                radius,
                ccw,
            } => Piece::Circle {
                center: *center,
                radius: *radius,
                ccw: !ccw,
            },
            Piece::SuperEllipse {
                center,
                a,
                b,
                n,
                ccw,
            } => Piece::SuperEllipse {
                center: *center,
                a: *a,
                b: *b,
                n: *n,
                ccw: !ccw,
            },
            Piece::Chain(p) => Piece::Chain(p.iter().rev().copied().collect()),
        }
    }

    /// Exact axis-aligned bounding box.
    pub(crate) fn bbox(&self) -> (DVec2, DVec2) {
        match self {
            Piece::Line { a, b } => (a.min(*b), a.max(*b)),
            Piece::Arc {
                center,
                radius,
                from,
                to,
            } => {
                let (s, e) = (self.start(), self.end());
                let (mut lo, mut hi) = (s.min(e), s.max(e));
                let (amin, amax) = (from.min(*to), from.max(*to));
                let mut k = (amin / FRAC_PI_2).ceil();
                while k * FRAC_PI_2 <= amax {
                    let q = *center + *radius * unit(k * FRAC_PI_2);
                    lo = lo.min(q);
                    hi = hi.max(q);
                    k += 1.0;
                }
                (lo, hi)
            }
            Piece::Circle { center, radius, .. } => (*center - *radius, *center + *radius),
            Piece::SuperEllipse { center, a, b, .. } => {
                let r = DVec2::new(*a, *b);
                (*center - r, *center + r)
            }
            Piece::Chain(p) => p.iter().fold(
                (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
                |(lo, hi), q| (lo.min(*q), hi.max(*q)),
            ),
        }
    }

    /// Checks the numbers of one piece; returns what is wrong.
    pub(crate) fn check(&self) -> Result<(), String> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        match self {
            Piece::Line { a, b } => {
                if !finite(&[a.x, a.y, b.x, b.y]) {
                    return Err(format!(
                        "line ({}, {}) → ({}, {}) has a non-finite coordinate",
                        a.x, a.y, b.x, b.y
                    ));
                }
            }
            Piece::Arc {
                center,
                radius,
                from,
                to,
            } => {
                if !finite(&[center.x, center.y, *radius, *from, *to]) {
                    return Err("arc has a non-finite centre, radius or angle".into());
                }
                if *radius <= 0.0 {
                    return Err(format!("arc radius {radius} is not positive"));
                }
                let sweep = (to - from).abs();
                if sweep == 0.0 || sweep > TAU * (1.0 + 1e-12) {
                    return Err(format!(
                        "arc sweep {} degrees is not in (0, 360]",
                        sweep.to_degrees()
                    ));
                }
            }
            Piece::Circle { center, radius, .. } => {
                if !finite(&[center.x, center.y, *radius]) || *radius <= 0.0 {
                    return Err(format!(
                        "circle radius {radius} must be positive and finite"
                    ));
                }
            }
            Piece::SuperEllipse {
                center, a, b, n, ..
            } => {
                if !finite(&[center.x, center.y, *a, *b, *n]) || *a <= 0.0 || *b <= 0.0 {
                    return Err(format!(
                        "super-ellipse semi-axes {a}, {b} must be positive and finite"
                    ));
                }
                if n.is_nan() || *n < 2.0 || *n > 1e3 {
                    return Err(format!(
                        "super-ellipse exponent {n} must be in [2, 1000] (smooth)"
                    ));
                }
            }
            Piece::Chain(p) => {
                if p.len() < 2 {
                    return Err(format!(
                        "curve has {} point(s); at least 2 are needed",
                        p.len()
                    ));
                }
                if let Some(q) = p.iter().find(|q| !q.is_finite()) {
                    return Err(format!("curve point ({}, {}) is not finite", q.x, q.y));
                }
            }
        }
        Ok(())
    }
}

/// Which part of a piece a nearest point is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FootAt {
    /// Strictly between the ends (or on a closed piece).
    Interior,
    /// The start point.
    Start,
    /// The end point.
    End,
}

impl FootAt {
    fn of_t(t: f64) -> FootAt {
        if t <= 0.0 {
            FootAt::Start
        } else if t >= 1.0 {
            FootAt::End
        } else {
            FootAt::Interior
        }
    }
}

/// Nearest point of a piece to a query point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Foot {
    pub point: DVec2,
    pub d2: f64,
    /// Piece-specific parameter (segment t, angle from `from`, super-ellipse octant t,
    /// chain segment index + t).
    pub aux: f64,
    pub end: FootAt,
}

#[inline]
fn unit(theta: f64) -> DVec2 {
    let (s, c) = theta.sin_cos();
    DVec2::new(c, s)
}

#[inline]
fn sign(ccw: bool) -> f64 {
    if ccw {
        1.0
    } else {
        -1.0
    }
}

/// Number of equal segments of an arc of `sweep` radians and radius r with sagitta ≤ tol.
fn arc_segments(sweep: f64, r: f64, tol: f64) -> usize {
    let step = 2.0 * (1.0 - tol / r).max(-1.0).acos();
    let by_tol = if step > 0.0 {
        (sweep / step).ceil()
    } else {
        f64::INFINITY
    };
    let by_shape = (sweep / FRAC_PI_4).ceil();
    by_tol.max(by_shape).clamp(1.0, 1e7) as usize
}

/// Douglas–Peucker: keeps the first and last point and every point needed so that each
/// dropped point lies within `tol` of the kept polyline.
pub(crate) fn douglas_peucker(p: &[DVec2], tol: f64) -> Vec<DVec2> {
    if p.len() <= 2 {
        return p.to_vec();
    }
    let mut keep = vec![false; p.len()];
    keep[0] = true;
    keep[p.len() - 1] = true;
    let mut stack = vec![(0usize, p.len() - 1)];
    let tol2 = tol * tol;
    while let Some((i, j)) = stack.pop() {
        if j <= i + 1 {
            continue;
        }
        let (mut far, mut worst) = (i, -1.0);
        for (k, q) in p.iter().enumerate().take(j).skip(i + 1) {
            let d2 = closest_on_segment(p[i], p[j], *q).2;
            if d2 > worst {
                worst = d2;
                far = k;
            }
        }
        if worst > tol2 {
            keep[far] = true;
            stack.push((i, far));
            stack.push((far, j));
        }
    }
    p.iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(q, _)| *q)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples() -> Vec<Piece> {
        let v = DVec2::new;
        vec![
            Piece::Line {
                a: v(0.1, 0.2),
                b: v(1.5, -0.7),
            },
            Piece::Arc {
                center: v(0.3, -0.2),
                radius: 0.8,
                from: -0.4,
                to: 2.9,
            },
            Piece::Arc {
                center: v(-1.0, 0.5),
                radius: 2.0,
                from: 1.0,
                to: -3.5,
            },
            Piece::Circle {
                center: v(0.5, 0.5),
                radius: 0.7,
                ccw: true,
            },
            Piece::Circle {
                center: v(0.5, 0.5),
                radius: 0.7,
                ccw: false,
            },
            Piece::SuperEllipse {
                center: v(0.2, 0.1),
                a: 1.2,
                b: 0.6,
                n: 4.0,
                ccw: true,
            },
            Piece::SuperEllipse {
                center: v(0.0, 0.0),
                a: 0.5,
                b: 0.5,
                n: 3.0,
                ccw: false,
            },
            Piece::Chain(
                (0..40)
                    .map(|i| v(i as f64 * 0.1, (i as f64 * 0.3).sin()))
                    .collect(),
            ),
        ]
    }

    /// A dense sampling of the exact curve (chains: their own points and midpoints).
    fn dense(p: &Piece) -> Vec<DVec2> {
        match p {
            Piece::Line { a, b } => (0..=2000).map(|k| a.lerp(*b, k as f64 / 2000.0)).collect(),
            Piece::Chain(c) => c
                .windows(2)
                .flat_map(|w| (0..20).map(move |k| w[0].lerp(w[1], k as f64 / 20.0)))
                .chain(c.last().copied())
                .collect(),
            _ => p.polygonize(1e-8),
        }
    }

    #[test]
    fn ends_lengths_and_tangents_are_consistent() {
        for p in samples() {
            let pts = dense(&p);
            let poly_len: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
            assert!(
                (p.length() - poly_len).abs() < 1e-6 * p.length(),
                "{p:?}: {} vs {poly_len}",
                p.length()
            );
            assert!((pts[0] - p.start()).length() < 1e-12);
            if !matches!(p, Piece::Chain(_)) {
                assert!((pts[pts.len() - 1] - p.end()).length() < 1e-12);
            }
            let (t0, t1) = p.end_tangents();
            let d0 = (pts[1] - pts[0]).normalize();
            assert!(t0.dot(d0) > 1.0 - 1e-6, "{p:?}: start tangent {t0} vs {d0}");
            let d1 = (pts[pts.len() - 1] - pts[pts.len() - 2]).normalize();
            assert!(t1.dot(d1) > 1.0 - 1e-6, "{p:?}: end tangent");
            // Reversal swaps the ends and negates the area integral.
            let r = p.reversed();
            assert!(
                (r.start() - p.end()).length() < 1e-15 && (r.end() - p.start()).length() < 1e-15
            );
            assert!((r.area_integral() + p.area_integral()).abs() < 1e-12);
            assert!((r.length() - p.length()).abs() < 1e-12);
        }
    }

    #[test]
    fn area_integral_matches_the_fine_polygon() {
        for p in samples() {
            let pts = dense(&p);
            let poly: f64 = pts
                .windows(2)
                .map(|w| 0.5 * (w[0].x + w[1].x) * (w[1].y - w[0].y))
                .sum();
            assert!(
                (p.area_integral() - poly).abs() < 1e-6,
                "{p:?}: {} vs {poly}",
                p.area_integral()
            );
        }
    }

    #[test]
    fn closest_point_is_the_nearest_dense_sample_and_has_the_right_arc_length() {
        let mut rng = crate::rng::Rng::new(9);
        for p in samples() {
            let pts = dense(&p);
            let cum: Vec<f64> = std::iter::once(0.0)
                .chain(pts.windows(2).scan(0.0, |s, w| {
                    *s += w[0].distance(w[1]);
                    Some(*s)
                }))
                .collect();
            for _ in 0..100 {
                let x = DVec2::new(rng.range(-2.5, 2.5), rng.range(-2.5, 2.5));
                let (q, s) = p.closest_point(x);
                let (k, best) = pts
                    .iter()
                    .enumerate()
                    .map(|(k, y)| (k, y.distance(x)))
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .unwrap();
                assert!(
                    q.distance(x) <= best + 1e-12,
                    "{p:?} at {x}: {} > {best}",
                    q.distance(x)
                );
                assert!(
                    (q.distance(x) - best).abs() < 1e-2,
                    "{p:?} at {x}: {} vs {best}",
                    q.distance(x)
                );
                // The arc length of the dense sample nearest to q (away from ties).
                let kq = pts
                    .iter()
                    .enumerate()
                    .min_by(|a, b| a.1.distance(q).total_cmp(&b.1.distance(q)))
                    .unwrap()
                    .0;
                if (k as i64 - kq as i64).abs() < 3 && !p.is_closed() {
                    let spacing =
                        pts[kq.saturating_sub(1)].distance(pts[(kq + 1).min(pts.len() - 1)]);
                    assert!(
                        (s - cum[kq]).abs() <= spacing,
                        "{p:?}: s {s} vs {}",
                        cum[kq]
                    );
                }
                assert!((0.0..=p.length() + 1e-12).contains(&s));
            }
        }
    }

    #[test]
    fn polygonize_keeps_the_chord_error_below_tol() {
        for p in samples() {
            for tol in [0.1, 1e-3, 1e-5] {
                let poly = p.polygonize(tol);
                assert!((poly[0] - p.start()).length() < 1e-15);
                assert!((poly[poly.len() - 1] - p.end()).length() < 1e-15);
                for x in dense(&p).iter().step_by(7) {
                    let d = poly
                        .windows(2)
                        .map(|w| crate::predicates::closest_on_segment(w[0], w[1], *x).2)
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        d.sqrt() <= tol * (1.0 + 1e-9) + 1e-14,
                        "{p:?} tol {tol}: {}",
                        d.sqrt()
                    );
                }
            }
        }
    }

    #[test]
    fn douglas_peucker_keeps_ends_and_drops_collinear_points() {
        let pts: Vec<DVec2> = (0..10).map(|i| DVec2::new(i as f64, 0.0)).collect();
        assert_eq!(douglas_peucker(&pts, 1e-9), vec![pts[0], pts[9]]);
        let mut bent = pts.clone();
        bent[5].y = 1.0;
        assert_eq!(douglas_peucker(&bent, 0.9), vec![bent[0], bent[5], bent[9]]);
        // Every dropped point stays within tol of the kept polyline.
        let wave: Vec<DVec2> = (0..200)
            .map(|i| DVec2::new(i as f64 * 0.05, (i as f64 * 0.05).sin()))
            .collect();
        let kept = douglas_peucker(&wave, 0.01);
        assert!(kept.len() < wave.len() / 3);
        for p in &wave {
            let d = kept
                .windows(2)
                .map(|w| closest_on_segment(w[0], w[1], *p).2)
                .fold(f64::INFINITY, f64::min);
            assert!(d.sqrt() <= 0.01 + 1e-15);
        }
    }

    #[test]
    fn check_rejects_bad_numbers() {
        let v = DVec2::new;
        assert!(Piece::Line {
            a: v(f64::NAN, 0.0),
            b: v(1.0, 0.0)
        }
        .check()
        .is_err());
        assert!(Piece::Arc {
            center: v(0.0, 0.0),
            radius: -1.0,
            from: 0.0,
            to: 1.0
        }
        .check()
        .is_err());
        assert!(Piece::Arc {
            center: v(0.0, 0.0),
            radius: 1.0,
            from: 0.0,
            to: 7.0
        }
        .check()
        .is_err());
        assert!(Piece::SuperEllipse {
            center: v(0.0, 0.0),
            a: 1.0,
            b: 1.0,
            n: 1.5,
            ccw: true
        }
        .check()
        .is_err());
        assert!(Piece::Chain(vec![v(0.0, 0.0)]).check().is_err());
        assert!(Piece::Circle {
            center: v(0.0, 0.0),
            radius: 1.0,
            ccw: true
        }
        .check()
        .is_ok());
    }
}
