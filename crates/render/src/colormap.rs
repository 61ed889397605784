//! The viridis colormap (perceptually uniform, readable in grey and by colour-blind readers),
//! as nine control points of the published table, linearly interpolated.

/// viridis at t = 0, 1/8, ..., 1 (sRGB).
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 45, 123],
    [59, 82, 139],
    [44, 114, 142],
    [33, 145, 140],
    [40, 174, 128],
    [94, 201, 98],
    [173, 220, 48],
    [253, 231, 37],
];

/// Viridis colour at `t` in [0, 1] (clamped; NaN maps to 0), as sRGB.
pub fn viridis(t: f64) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mut out = [0u8; 3];
    for k in 0..3 {
        out[k] = (a[k] as f64 + f * (b[k] as f64 - a[k] as f64)).round() as u8;
    }
    out
}

/// Number of distinct fill colours used for triangles: one path per colour keeps drawing fast
/// (a few dozen fills instead of one per triangle) and is finer than the eye can tell apart.
pub(crate) const BINS: usize = 64;

/// Bin of a value in [lo, hi] (NaN and infinities: `None`).
pub(crate) fn bin(v: f64, lo: f64, hi: f64) -> Option<usize> {
    if !v.is_finite() {
        return None;
    }
    let t = if hi > lo { (v - lo) / (hi - lo) } else { 0.5 };
    Some(((t.clamp(0.0, 1.0) * (BINS - 1) as f64).round()) as usize)
}

/// Colour of a bin.
pub(crate) fn bin_colour(b: usize) -> [u8; 3] {
    viridis(b as f64 / (BINS - 1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_and_control_points() {
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(1.0), [253, 231, 37]);
        assert_eq!(viridis(0.5), [33, 145, 140]);
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(7.0), viridis(1.0));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
    }

    #[test]
    fn luminance_increases() {
        // Perceptual order: viridis gets brighter monotonically.
        let lum = |c: [u8; 3]| 0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64;
        let mut prev = -1.0;
        for i in 0..=100 {
            let l = lum(viridis(i as f64 / 100.0));
            assert!(l > prev, "luminance not increasing at {i}");
            prev = l;
        }
    }

    #[test]
    fn bins_cover_range() {
        assert_eq!(bin(2.0, 2.0, 5.0), Some(0));
        assert_eq!(bin(5.0, 2.0, 5.0), Some(BINS - 1));
        assert_eq!(bin(f64::NAN, 2.0, 5.0), None);
        assert_eq!(bin(3.0, 3.0, 3.0), Some(32));
        assert_eq!(bin_colour(0), viridis(0.0));
        assert_eq!(bin_colour(BINS - 1), viridis(1.0));
    }
}
