//! Simplifying a digitized boundary to a stated tolerance, so that a region drawn with more
//! vertices (and corners) than the mesh has can be meshed coarsely.
use crate::error::GeometryError;
use crate::piece::{douglas_peucker, Piece};
use crate::predicates::closest_on_segment;
use crate::region::Region;
use crate::EmbeddedLine;
use glam::DVec2;
use std::collections::{HashMap, HashSet};

impl std::fmt::Display for Simplified {
    /// One line for a user: what was simplified, at which tolerance, and how far the new
    /// boundary is from the given one.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (before, after) = self.vertices;
        let (lines_before, lines_after) = self.line_vertices;
        if before == after && lines_before == lines_after {
            return write!(
                f,
                "boundary: as given (no straight-edged loop has a vertex within {:.3e} of the rest)",
                self.asked
            );
        }
        write!(
            f,
            "boundary: simplified from {before} to {after} vertices at tolerance {:.3e}",
            self.tolerance
        )?;
        if lines_before != lines_after {
            write!(f, ", its lines inside from {lines_before} to {lines_after}")?;
        }
        if self.tolerance < self.asked {
            write!(
                f,
                " (lowered from {:.3e}, where loops would have crossed or a line passed a \
                 subdomain point)",
                self.asked
            )?;
        }
        write!(
            f,
            "; the mesh's boundary stays within {:.3e} of the given one",
            self.deviation
        )
    }
}

/// Halvings of the tolerance tried when a simplified boundary crosses itself or another loop.
const RETRIES: usize = 12;

/// A region whose straight-edged loops were simplified ([`Region::simplified`]).
#[derive(Clone, Debug)]
pub struct Simplified {
    /// The simplified region; its corners are computed afresh, so
    /// [`Region::with_default_corners`] and [`Region::with_corner_angle`] apply to it.
    pub region: Region,
    /// The tolerance asked for.
    pub asked: f64,
    /// The tolerance used: the one asked for, or a smaller one where that made loops cross.
    pub tolerance: f64,
    /// The largest distance from a dropped vertex to the simplified boundary; the simplified
    /// boundary lies within this distance of the original, and the original within it of the
    /// simplified one (Hausdorff distance).
    pub deviation: f64,
    /// Boundary vertices before and after, over the simplified loops.
    pub vertices: (usize, usize),
    /// The embedded lines' vertices before and after ([`Region::embedded_lines`]).
    pub line_vertices: (usize, usize),
}

impl Region {
    /// The region with every loop made only of straight pieces (lines and chains: what
    /// polygon files give) simplified by Douglas–Peucker: each loop keeps the fewest of its
    /// own vertices such that every dropped vertex lies within `tolerance` of the result, and
    /// at least three. Loops with curved pieces are kept as they are. The embedded lines are
    /// simplified alike, each keeping its ends, the vertices it shares with another line and
    /// those on the boundary: a digitized interface of thousands of segments no longer forces a
    /// vertex, and tiny angles, at each.
    ///
    /// The result is validated like any region: where the simplification made a loop cross
    /// itself or another loop, the tolerance is halved (up to 12 times) and
    /// [`Simplified::tolerance`] says which one was used. A region with nothing to simplify
    /// comes back unchanged. The simplified region's corners are computed afresh: with this
    /// region's corner angle if one was applied, otherwise at every vertex where it turns, so
    /// that [`Region::with_default_corners`] applies to it.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, LoopRole, Region};
    /// use std::f64::consts::TAU;
    /// // A unit square whose bottom side wiggles by ±0.002 over 400 points.
    /// let mut pts: Vec<DVec2> = (0..400)
    ///     .map(|i| DVec2::new(i as f64 / 400.0, 0.002 * (TAU * i as f64 / 7.0).sin()))
    ///     .collect();
    /// pts.extend([DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)]);
    /// let raw = Region::from_loops("wiggly", vec![(LoopRole::Outer, pts)])?;
    /// let s = raw.simplified(0.01)?;
    /// assert!(s.vertices.0 > 300 && s.vertices.1 == 4, "{s}");
    /// assert!(s.deviation <= 0.002 + 1e-12);
    /// assert_eq!(s.region.with_default_corners().corners().len(), 4);
    /// assert!((s.region.area() - raw.area()).abs() < 0.002);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn simplified(&self, tolerance: f64) -> Result<Simplified, GeometryError> {
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(GeometryError::Invalid {
                region: self.name.clone(),
                message: format!(
                    "the simplification tolerance must be finite and not negative, got {tolerance}"
                ),
            });
        }
        let rings: Vec<Option<Vec<DVec2>>> = (0..self.loops.len())
            .map(|l| self.straight_ring(l))
            .collect();
        let before: usize = rings.iter().flatten().map(Vec::len).sum();
        let lines_before: usize = self.lines.iter().map(|l| l.points.len()).sum();
        let unchanged = Simplified {
            region: self.clone(),
            asked: tolerance,
            tolerance: 0.0,
            deviation: 0.0,
            vertices: (before, before),
            line_vertices: (lines_before, lines_before),
        };
        if tolerance == 0.0 || before + lines_before == 0 {
            return Ok(unchanged);
        }
        let line_fixed = self.line_vertices_to_keep();
        // Where the pieces carry markers, the vertices where the marker changes stay, and stay
        // corners, and each simplified edge keeps the marker of the edges it replaces.
        let ring_markers: Vec<Option<Vec<i64>>> = (0..self.loops.len())
            .map(|l| rings[l].as_ref().and(self.ring_markers(l)))
            .collect();
        // So do the vertices with markers of their own.
        let changes: Vec<Vec<usize>> = ring_markers
            .iter()
            .zip(&rings)
            .map(|(m, ring)| match (m, ring) {
                (Some(m), Some(ring)) => (0..m.len())
                    .filter(|&i| {
                        m[(i + m.len() - 1) % m.len()] != m[i]
                            || self.is_marked_vertex(ring[i])
                            || self.is_line_vertex(ring[i])
                    })
                    .collect(),
                // An embedded line's end on the boundary stays a vertex and a corner.
                (None, Some(ring)) => (0..ring.len())
                    .filter(|&i| self.is_line_vertex(ring[i]))
                    .collect(),
                _ => Vec::new(),
            })
            .collect();
        let marked = self.piece_markers().is_some() || !self.lines.is_empty();
        // A simplified line stays within the tolerance of the given one, so it can pass a
        // subdomain point, and number the part beyond it, only where the point is nearer than
        // that: the tolerance stays below half the nearest such distance.
        let nearest_point = self
            .subdomains
            .iter()
            .flat_map(|&(p, _)| {
                self.lines.iter().flat_map(move |l| {
                    l.segments()
                        .map(move |(a, b)| closest_on_segment(a, b, p).2)
                })
            })
            .fold(f64::INFINITY, f64::min)
            .sqrt();
        let mut tol = tolerance.min(0.5 * nearest_point);
        for _ in 0..=RETRIES {
            let mut loops = Vec::with_capacity(self.loops.len());
            let mut markers = Vec::new();
            let mut corners = Vec::new();
            let (mut after, mut deviation) = (0, 0.0f64);
            let lines: Vec<EmbeddedLine> = self
                .lines
                .iter()
                .map(|line| {
                    let (kept, d) = simplify_line(line, tol, &line_fixed);
                    deviation = deviation.max(d);
                    kept
                })
                .collect();
            let lines_after: usize = lines.iter().map(|l| l.points.len()).sum();
            for (l, ring) in rings.iter().enumerate() {
                let lp = &self.loops[l];
                let pieces: Vec<Piece> = match ring {
                    Some(ring) => {
                        let kept = simplify_ring(ring, tol, &changes[l]);
                        after += kept.len();
                        deviation = deviation.max(ring_deviation(ring, &kept));
                        let index: HashMap<(u64, u64), usize> = ring
                            .iter()
                            .enumerate()
                            .map(|(i, p)| ((p.x.to_bits(), p.y.to_bits()), i))
                            .collect();
                        let at = |p: DVec2| index[&(p.x.to_bits(), p.y.to_bits())];
                        if let Some(m) = &ring_markers[l] {
                            markers.extend(kept.iter().map(|&p| m[at(p)]));
                        }
                        corners.extend(
                            kept.iter()
                                .copied()
                                .filter(|&p| changes[l].binary_search(&at(p)).is_ok()),
                        );
                        (0..kept.len())
                            .map(|i| Piece::Line {
                                a: kept[i],
                                b: kept[(i + 1) % kept.len()],
                            })
                            .collect()
                    }
                    None => {
                        let pieces = lp.pieces.iter().map(|&p| self.pieces[p].clone());
                        if let Some(m) = self.piece_markers() {
                            markers.extend(lp.pieces.iter().map(|&p| m[p]));
                        }
                        pieces.collect()
                    }
                };
                if marked {
                    corners.extend(turning_vertices(&pieces));
                }
                loops.push((lp.role, pieces));
            }
            if after == before && lines_after == lines_before {
                return Ok(unchanged);
            }
            corners.sort_by_key(|p| (p.x.to_bits(), p.y.to_bits()));
            corners.dedup();
            let listed = marked.then_some(corners);
            if let Ok(mut region) = Region::new(&self.name, loops, listed) {
                if marked {
                    if self.piece_markers().is_some() {
                        region.markers = markers;
                    }
                    region.marker_names = self.marker_names.clone();
                    region.vertex_markers = self.vertex_markers.clone();
                }
                region.corners_computed = true;
                region.notes = self.notes.clone();
                region.surface_group = self.surface_group.clone();
                // Embedded points stay where they are; one the simplified boundary no longer
                // holds well inside is a reason to simplify less.
                let embedded = region
                    .clone()
                    .with_embedded_points(self.embedded.iter().copied())
                    .and_then(|r| r.with_embedded_lines(lines))
                    .and_then(|r| r.with_subdomain_points(self.subdomains.iter().copied()))
                    .map(|r| r.with_subdomain_names(self.subdomain_names.clone()));
                let Ok(mut region) = embedded else {
                    tol *= 0.5;
                    continue;
                };
                if let Some(degrees) = self.corner_threshold {
                    region = region.with_corner_angle(degrees);
                }
                return Ok(Simplified {
                    region,
                    asked: tolerance,
                    tolerance: tol,
                    deviation,
                    vertices: (before, after),
                    line_vertices: (lines_before, lines_after),
                });
            }
            tol *= 0.5;
        }
        Ok(unchanged)
    }

    /// The vertices of the embedded lines that simplifying them keeps besides their ends: those
    /// on the boundary (a wall is split there) and those two lines share (a junction) or one
    /// line visits twice (where it crosses itself).
    fn line_vertices_to_keep(&self) -> HashSet<(u64, u64)> {
        let key = |p: DVec2| (p.x.to_bits(), p.y.to_bits());
        let off = 1e-9 * self.diameter();
        // Visits of each point: a junction of two lines, or a crossing one line makes with
        // itself, is visited twice or more (a closed line's ends, kept anyway, twice).
        let mut lines_at: HashMap<(u64, u64), usize> = HashMap::new();
        for line in &self.lines {
            for p in &line.points {
                *lines_at.entry(key(*p)).or_insert(0) += 1;
            }
        }
        self.lines
            .iter()
            .flat_map(|l| l.points.iter().copied())
            .filter(|&p| lines_at[&key(p)] > 1 || self.signed_distance(p) > -off)
            .map(key)
            .collect()
    }

    /// Loop `l`'s vertices in order, if it is made of lines and chains only.
    fn straight_ring(&self, l: usize) -> Option<Vec<DVec2>> {
        // Each piece gives every point but its end, which starts the next piece (a single
        // closed chain ends where it starts).
        let mut ring = Vec::new();
        for &p in &self.loops[l].pieces {
            match &self.pieces[p] {
                Piece::Line { a, .. } => ring.push(*a),
                Piece::Chain(c) => ring.extend_from_slice(&c[..c.len() - 1]),
                _ => return None,
            }
        }
        Some(ring)
    }

    /// The marker of the edge leaving each vertex of [`Region::straight_ring`]`(l)`, where
    /// the region's pieces have markers.
    fn ring_markers(&self, l: usize) -> Option<Vec<i64>> {
        let markers = self.piece_markers()?;
        let mut out = Vec::new();
        for &p in &self.loops[l].pieces {
            let edges = match &self.pieces[p] {
                Piece::Chain(c) => c.len() - 1,
                _ => 1,
            };
            out.extend(std::iter::repeat_n(markers[p], edges));
        }
        Some(out)
    }
}

/// Douglas–Peucker on a closed ring, anchored at three of its vertices that are always kept:
/// the vertex farthest from the first one's farthest vertex, that vertex, and the vertex
/// farthest from the chord between them (so at least three are kept, and every dropped vertex
/// lies within `tol` of the arc of kept vertices that spans it). The vertices at the indices
/// `fixed` are kept too.
fn simplify_ring(ring: &[DVec2], tol: f64, fixed: &[usize]) -> Vec<DVec2> {
    let n = ring.len();
    if n <= 3 {
        return ring.to_vec();
    }
    let farthest_by = |key: &dyn Fn(DVec2) -> f64| {
        (0..n)
            .max_by(|&i, &j| key(ring[i]).total_cmp(&key(ring[j])))
            .expect("not empty")
    };
    let a = farthest_by(&|p| (p - ring[0]).length_squared());
    let b = farthest_by(&|p| (p - ring[a]).length_squared());
    let mut c = farthest_by(&|p| closest_on_segment(ring[a], ring[b], p).2);
    if c == a || c == b {
        // Only a degenerate ring has nothing off the chord; any third vertex will do.
        c = (0..n).find(|&i| i != a && i != b).expect("n > 3");
    }
    let mut anchors: Vec<usize> = [a, b, c].into_iter().chain(fixed.iter().copied()).collect();
    anchors.sort_unstable();
    anchors.dedup();
    let m = anchors.len();
    let mut kept = Vec::with_capacity(n);
    for k in 0..m {
        let (from, to) = (anchors[k], anchors[(k + 1) % m]);
        let arc: Vec<DVec2> = if from < to {
            ring[from..=to].to_vec()
        } else {
            ring[from..].iter().chain(&ring[..=to]).copied().collect()
        };
        let part = douglas_peucker(&arc, tol);
        kept.extend_from_slice(&part[..part.len() - 1]);
    }
    kept
}

/// `line` simplified by Douglas–Peucker at `tol`, keeping its ends and the vertices in `fixed`
/// (a closed line as a ring, at least three vertices), and the largest distance from a dropped
/// vertex to the result.
fn simplify_line(
    line: &EmbeddedLine,
    tol: f64,
    fixed: &HashSet<(u64, u64)>,
) -> (EmbeddedLine, f64) {
    let pts = &line.points;
    let is_fixed = |p: DVec2| fixed.contains(&(p.x.to_bits(), p.y.to_bits()));
    if line.is_closed() {
        let ring = &pts[..pts.len() - 1];
        let anchors: Vec<usize> = (0..ring.len()).filter(|&i| is_fixed(ring[i])).collect();
        let mut kept = simplify_ring(ring, tol, &anchors);
        let deviation = ring_deviation(ring, &kept);
        // The ring starts where the line did, so that its first point is its last.
        let start = kept.iter().position(|&p| p == pts[0]).unwrap_or(0);
        kept.rotate_left(start);
        kept.push(kept[0]);
        return (
            EmbeddedLine {
                points: kept,
                marker: line.marker,
            },
            deviation,
        );
    }
    let mut points = vec![pts[0]];
    let mut from = 0;
    for i in 1..pts.len() {
        if i == pts.len() - 1 || is_fixed(pts[i]) {
            points.extend_from_slice(&douglas_peucker(&pts[from..=i], tol)[1..]);
            from = i;
        }
    }
    let deviation = polyline_deviation(pts, &points);
    (
        EmbeddedLine {
            points,
            marker: line.marker,
        },
        deviation,
    )
}

/// The largest distance from a vertex of the open polyline `given` to `kept`, a subsequence of
/// it with the same ends.
fn polyline_deviation(given: &[DVec2], kept: &[DVec2]) -> f64 {
    let mut worst = 0.0f64;
    let mut j = 0;
    for w in kept.windows(2) {
        while j < given.len() && given[j] != w[1] {
            worst = worst.max(closest_on_segment(w[0], w[1], given[j]).2.sqrt());
            j += 1;
        }
    }
    worst
}

/// The junctions of a loop's pieces where it turns (the corners a polygon file gets).
fn turning_vertices(pieces: &[Piece]) -> Vec<DVec2> {
    let n = pieces.len();
    (0..n)
        .filter(|&k| {
            let (a, b) = (&pieces[(k + n - 1) % n], &pieces[k]);
            a.end_tangents().1.angle_to(b.end_tangents().0).abs() > 1e-9
        })
        .map(|k| pieces[k].start())
        .collect()
}

/// The largest distance from a vertex of `ring` to the closed polyline `kept`.
fn ring_deviation(ring: &[DVec2], kept: &[DVec2]) -> f64 {
    // Both are in the same order and `kept` is a subsequence of `ring`, so each vertex is
    // measured against the kept edge that spans it.
    let (n, m) = (ring.len(), kept.len());
    let mut worst = 0.0f64;
    let mut j = ring
        .iter()
        .position(|p| *p == kept[0])
        .expect("kept vertices come from the ring");
    for k in 0..m {
        let (p, q) = (kept[k], kept[(k + 1) % m]);
        j = (j + 1) % n;
        for _ in 0..n {
            if ring[j] == q {
                break;
            }
            worst = worst.max(closest_on_segment(p, q, ring[j]).2.sqrt());
            j = (j + 1) % n;
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::LoopRole;
    use std::f64::consts::TAU;

    fn roles(r: &Region) -> Vec<LoopRole> {
        r.loops().iter().map(|l| l.role).collect()
    }

    fn wiggly_circle(n: usize, amp: f64) -> Vec<DVec2> {
        (0..n)
            .map(|i| {
                let t = TAU * i as f64 / n as f64;
                (1.0 + amp * (37.0 * t).sin()) * DVec2::new(t.cos(), t.sin())
            })
            .collect()
    }

    #[test]
    fn simplifying_keeps_where_the_marker_changes_and_each_edge_its_marker() {
        // A 4 × 1 rectangle whose bottom wiggles by ±0.001 over 41 vertices, marked 1 left of
        // x = 2 and 4 from there on; the other sides 2 (x = 4), 3 (top), 5 (x = 0).
        let mut pts: Vec<DVec2> = (0..=40)
            .map(|i| DVec2::new(0.1 * i as f64, 0.001 * (i as f64 * 1.7).sin()))
            .collect();
        pts.extend([DVec2::new(4.0, 1.0), DVec2::new(0.0, 1.0)]);
        let n = pts.len();
        let mut poly = format!("{n} 2 0 0\n");
        for (i, p) in pts.iter().enumerate() {
            poly += &format!("{} {} {}\n", i + 1, p.x, p.y);
        }
        poly += &format!("{n} 1\n");
        for i in 0..n {
            let m = match i {
                0..=19 => 1,
                20..=39 => 4,
                40 => 2,
                41 => 3,
                _ => 5,
            };
            poly += &format!("{} {} {} {m}\n", i + 1, i + 1, (i + 1) % n + 1);
        }
        poly += "0\n";
        let raw = crate::formats::poly_from_str(&poly, "wiggly.poly", "wiggly").unwrap();
        let s = raw.simplified(0.01).unwrap();
        assert_eq!(s.vertices, (43, 5), "{s}");
        let r = s.region.with_default_corners();
        let m = r.piece_markers().expect("the markers survive");
        let mut by_start: Vec<(f64, f64, i64)> = r
            .pieces()
            .iter()
            .zip(m)
            .map(|(p, &m)| (p.start().x, p.start().y, m))
            .collect();
        by_start.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let change = pts[20];
        assert_eq!(
            by_start,
            [
                (0.0, 0.0, 1),
                (0.0, 1.0, 5),
                (change.x, change.y, 4),
                (4.0, pts[40].y, 2),
                (4.0, 1.0, 3)
            ]
        );
        // The change of marker is a corner though the boundary hardly turns there.
        assert!(r.corners().iter().any(|c| c.pos == change));
        // Unmarked, the same boundary keeps its four corners only.
        let plain = poly.replace(&format!("{n} 1\n"), &format!("{n} 0\n"));
        let raw = crate::formats::poly_from_str(&plain, "wiggly.poly", "wiggly").unwrap();
        assert_eq!(raw.simplified(0.01).unwrap().vertices, (43, 4));
    }

    #[test]
    fn digitized_lines_are_simplified_keeping_their_ends_junctions_and_closure() {
        let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from);
        let r = Region::from_loops("square", vec![(LoopRole::Outer, square.to_vec())]).unwrap();
        // A wall-to-wall interface x = 0.5 wiggling by ±0.001 over 2001 points, a branch from
        // its point (0.5, 0.5) to the right wall, and a wiggly closed inclusion.
        let wiggle = |i: usize| 0.001 * (TAU * i as f64 / 9.0).sin();
        let interface: Vec<DVec2> = (0..=2000)
            .map(|i| {
                let y = i as f64 / 2000.0;
                DVec2::new(if i % 1000 == 0 { 0.5 } else { 0.5 + wiggle(i) }, y)
            })
            .collect();
        let branch = vec![
            DVec2::new(0.5, 0.5),
            DVec2::new(0.75, 0.5),
            DVec2::new(1.0, 0.5),
        ];
        let mut ring: Vec<DVec2> = wiggly_circle(600, 0.0005)
            .iter()
            .map(|p| DVec2::new(0.25, 0.5) + 0.1 * *p)
            .collect();
        ring.push(ring[0]);
        let lines = [interface.clone(), branch, ring.clone()]
            .map(|points| EmbeddedLine { points, marker: 3 });
        let r = r.with_embedded_lines(lines).unwrap();
        let s = r.simplified(0.01).unwrap();
        let (before, after) = s.line_vertices;
        assert_eq!(before, 2001 + 3 + 601);
        assert!(after < 40, "{s}");
        assert!(s
            .to_string()
            .contains(&format!("its lines inside from {before} to {after}")));
        assert!(s.deviation <= 0.01, "{}", s.deviation);
        let kept = s.region.embedded_lines();
        // The straight interface's wiggles are all that was dropped from it.
        let off = polyline_deviation(&interface, &kept[0].points);
        assert!(off <= 0.001 + 1e-12 && off <= s.deviation, "{off}");
        // The interface keeps its ends and the junction, the branch loses its middle vertex, the
        // inclusion stays closed with at least three vertices, every line its marker.
        let first = &kept[0].points;
        assert_eq!(
            (first[0], first[first.len() - 1]),
            (interface[0], interface[2000])
        );
        assert!(first.contains(&DVec2::new(0.5, 0.5)));
        assert_eq!(kept[1].points, [DVec2::new(0.5, 0.5), DVec2::new(1.0, 0.5)]);
        assert!(kept[2].is_closed() && kept[2].points.len() >= 4);
        assert!(kept.iter().all(|l| l.marker == 3));
        // A tolerance below the wiggles keeps the interface's wiggles (only the vertices on
        // the chord between their neighbours go).
        let fine = r.simplified(1e-6).unwrap();
        assert!(fine.region.embedded_lines()[0].points.len() > 1700);
        assert!(fine.deviation <= 1e-6, "{}", fine.deviation);
    }

    #[test]
    fn a_simplified_line_does_not_pass_a_subdomain_point() {
        let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from);
        let wave = |x: f64| 0.5 + 0.1 * (TAU * x).sin();
        let line = EmbeddedLine {
            points: (0..=2000)
                .map(|i| i as f64 / 2000.0)
                .map(|x| DVec2::new(x, wave(x)))
                .collect(),
            marker: 0,
        };
        // A point 0.0024 below the wave, where a chord at tolerance 0.01 passes above it.
        let below = DVec2::new(0.2134, 0.595);
        assert!(wave(below.x) - below.y > 0.002);
        let r = Region::from_loops("square", vec![(LoopRole::Outer, square.to_vec())])
            .unwrap()
            .with_embedded_lines([line])
            .unwrap()
            .with_subdomain_points([(below, 1), (DVec2::new(0.5, 0.95), 2)])
            .unwrap();
        let s = r.simplified(0.01).unwrap();
        assert!(s.tolerance < 0.5 * 0.0025, "{s}");
        assert!(
            s.to_string().contains("a line passed a subdomain point"),
            "{s}"
        );
        let kept = &s.region.embedded_lines()[0].points;
        assert!(kept.len() < 200, "{}", kept.len());
        // The simplified wave still passes above the point.
        let k = kept.iter().position(|p| p.x > below.x).unwrap();
        let (a, b) = (kept[k - 1], kept[k]);
        let at = a.y + (b.y - a.y) * (below.x - a.x) / (b.x - a.x);
        assert!(at > below.y, "the line passes {at} at the point {below}");
    }

    #[test]
    fn deviation_bounds_every_dropped_vertex() {
        let ring = wiggly_circle(2000, 0.01);
        let kept = simplify_ring(&ring, 0.03, &[]);
        assert!(kept.len() < 200, "{}", kept.len());
        let dev = ring_deviation(&ring, &kept);
        assert!(dev <= 0.03, "{dev}");
        // Brute force: every original vertex against every kept edge.
        for p in &ring {
            let d = (0..kept.len())
                .map(|k| closest_on_segment(kept[k], kept[(k + 1) % kept.len()], *p).2)
                .fold(f64::INFINITY, f64::min)
                .sqrt();
            assert!(d <= dev + 1e-12, "{d} > {dev}");
        }
    }

    #[test]
    fn every_vertex_stays_within_the_tolerance_when_only_three_are_kept() {
        // Found by the `mesh_loops` fuzz target: a hexagon whose two halves both collapse to
        // their chord at 7.5. A third vertex used to be added afterwards, and the vertices on
        // its side were measured against the two new edges only: 7.62 from the result.
        let ring: Vec<DVec2> = [(15, 15), (3, 0), (0, 0), (9, 11), (0, 5), (2, 8)]
            .map(|(x, y)| DVec2::new(x as f64, y as f64))
            .to_vec();
        let region = Region::from_loops("hexagon", vec![(LoopRole::Outer, ring)]).unwrap();
        let s = region.simplified(7.5).unwrap();
        assert!(s.deviation <= s.tolerance, "{s:?}");
    }

    #[test]
    fn a_tiny_hole_keeps_three_vertices_and_its_role() {
        let outer = wiggly_circle(500, 0.02);
        let hole: Vec<DVec2> = (0..40)
            .map(|i| {
                let t = TAU * i as f64 / 40.0;
                DVec2::new(0.3, 0.2) + 0.001 * DVec2::new(t.cos(), t.sin())
            })
            .collect();
        let raw = Region::from_loops("r", vec![(LoopRole::Outer, outer), (LoopRole::Hole, hole)])
            .unwrap();
        let s = raw.simplified(0.05).unwrap();
        assert_eq!(roles(&s.region), vec![LoopRole::Outer, LoopRole::Hole]);
        let hole_pieces = s.region.loops()[1].pieces.len();
        assert_eq!(hole_pieces, 3);
        assert!(s.deviation <= 0.05);
    }

    #[test]
    fn crossings_halve_the_tolerance() {
        // A peninsula 0.3 long holds a hole: simplifying at 0.5 would cut the peninsula off
        // and leave the hole outside; at 0.25 the peninsula stays.
        let v = DVec2::new;
        let outer = vec![
            v(0.0, 0.0),
            v(1.0, 0.0),
            v(1.0, 1.0),
            v(0.6, 1.0),
            v(0.6, 1.3),
            v(0.5, 1.3),
            v(0.5, 1.0),
            v(0.0, 1.0),
        ];
        let hole = vec![v(0.53, 1.1), v(0.57, 1.1), v(0.57, 1.2), v(0.53, 1.2)];
        let raw = Region::from_loops(
            "peninsula",
            vec![(LoopRole::Outer, outer), (LoopRole::Hole, hole)],
        )
        .unwrap();
        let s = raw.simplified(0.5).unwrap();
        assert_eq!(s.tolerance, 0.25);
        assert!(s.deviation <= s.tolerance && s.vertices.1 < 12, "{s:?}");
        assert_eq!(s.region.loops().len(), 2);
    }

    #[test]
    fn curved_regions_are_unchanged() {
        let circle = Region::builtin("circle").unwrap();
        let s = circle.simplified(0.1).unwrap();
        assert_eq!(s.vertices, (0, 0));
        assert_eq!(s.region.pieces().len(), circle.pieces().len());
    }

    #[test]
    fn bad_tolerances_are_errors() {
        let circle = Region::builtin("circle").unwrap();
        for t in [f64::NAN, -1.0, f64::INFINITY] {
            let e = circle.simplified(t).unwrap_err().to_string();
            assert!(e.contains("simplification tolerance"), "{e}");
        }
    }
}
