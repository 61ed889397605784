//! Curved loops from fuzzed bytes: arcs (up to nearly a full turn) and lines between points
//! of a 16 × 16 grid, whole circles and super-ellipses.

use geometry::{DVec2, LoopRole, Piece};
use std::f64::consts::PI;

/// A signed turn below this many bend units is a straight piece; beyond it an arc turning
/// from 0.05 rad to just under a full turn.
const STRAIGHT: i32 = 48;

/// The piece from `p` to `q`: a line, or the arc that turns by an angle set by `bend` (CCW
/// for a positive byte read as `i8`, CW for a negative one).
pub fn piece(p: DVec2, q: DVec2, bend: u8) -> Piece {
    let b = bend as i8 as i32;
    if b.abs() < STRAIGHT {
        return Piece::Line { a: p, b: q };
    }
    let turn = (0.05 + (b.abs() - STRAIGHT) as f64 / (128 - STRAIGHT) as f64 * (1.9 * PI - 0.05))
        * b.signum() as f64;
    let chord = q - p;
    let left = DVec2::new(-chord.y, chord.x) / chord.length();
    // The centre is on the chord's bisector, to the left for a CCW turn below half a turn.
    let center = 0.5 * (p + q) + left * (0.5 * chord.length() / (0.5 * turn).tan());
    let radius = 0.5 * chord.length() / (0.5 * turn.abs()).sin();
    let from = (p - center).y.atan2((p - center).x);
    Piece::Arc {
        center,
        radius,
        from,
        to: from + turn,
    }
}

/// Up to three loops. Pieces between grid points: 2 to 9 points of the 16 × 16 grid, three
/// bytes each (x, y and the bend of the piece to the next point; a point equal to the one
/// before is skipped). A circle: its centre (two bytes) and radius (half a grid step to 8).
/// A super-ellipse: its centre, semi-axes and exponent (2 to 9.75), a byte each.
pub fn loops_from(mut bytes: &[u8]) -> Vec<(LoopRole, Vec<Piece>)> {
    let mut loops = Vec::new();
    let grid = |b: u8| (b % 16) as f64;
    let half_steps = |b: u8| 0.5 * (1 + b % 16) as f64;
    while let [head, rest @ ..] = bytes {
        if loops.len() == 3 {
            break;
        }
        let role = if loops.is_empty() || head & 0x80 == 0 {
            LoopRole::Outer
        } else {
            LoopRole::Hole
        };
        let ccw = head & 0x40 != 0;
        let (pieces, used) = match head & 3 {
            2 => {
                let [x, y, r, ..] = rest else { break };
                let circle = Piece::Circle {
                    center: DVec2::new(grid(*x), grid(*y)),
                    radius: half_steps(*r),
                    ccw,
                };
                (vec![circle], 3)
            }
            3 => {
                let [x, y, a, b, n, ..] = rest else { break };
                let curve = Piece::SuperEllipse {
                    center: DVec2::new(grid(*x), grid(*y)),
                    a: half_steps(*a),
                    b: half_steps(*b),
                    n: 2.0 + (n % 32) as f64 * 0.25,
                    ccw,
                };
                (vec![curve], 5)
            }
            _ => {
                let n = (2 + (head >> 2) as usize % 8).min(rest.len() / 3);
                let mut points: Vec<(DVec2, u8)> = Vec::new();
                for c in rest[..3 * n].chunks(3) {
                    let p = DVec2::new(grid(c[0]), grid(c[1]));
                    if points.last().is_none_or(|(q, _)| *q != p) {
                        points.push((p, c[2]));
                    }
                }
                if points.len() > 1 && points[0].0 == points[points.len() - 1].0 {
                    points.pop();
                }
                let pieces = (0..points.len())
                    .map(|i| {
                        let (p, bend) = points[i];
                        piece(p, points[(i + 1) % points.len()].0, bend)
                    })
                    .collect();
                (pieces, 3 * n)
            }
        };
        loops.push((role, pieces));
        bytes = &rest[used..];
    }
    loops
}
