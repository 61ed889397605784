//! Straight loops from fuzzed bytes: small integer coordinates make collinear, touching and
//! crossing loops common.

use geometry::{DVec2, LoopRole};

/// Up to four loops of 3 to 10 points on a 16 × 16 grid: per loop a byte for the point count
/// (3 + value mod 8; its high bit makes any loop but the first a hole), then a byte pair per
/// point. Bytes left over that cannot make a loop are ignored.
pub fn loops_from(mut bytes: &[u8]) -> Vec<(LoopRole, Vec<DVec2>)> {
    let mut loops = Vec::new();
    while bytes.len() >= 6 && loops.len() < 4 {
        let n = (3 + bytes[0] as usize % 8).min((bytes.len() - 1) / 2);
        let pts: Vec<DVec2> = bytes[1..1 + 2 * n]
            .chunks(2)
            .map(|c| DVec2::new((c[0] % 16) as f64, (c[1] % 16) as f64))
            .collect();
        let role = if loops.is_empty() || bytes[0] & 0x80 == 0 {
            LoopRole::Outer
        } else {
            LoopRole::Hole
        };
        loops.push((role, pts));
        bytes = &bytes[1 + 2 * n..];
    }
    loops
}
