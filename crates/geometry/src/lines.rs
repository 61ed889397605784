//! Lines embedded in a region: polylines inside it that every mesh must follow with its edges
//! (a material interface, a crack, an inclusion's outline, a line a solver reads values on),
//! as a Triangle `.poly`'s internal segments and Gmsh's embedded curves are.
use crate::predicates::{closest_on_segment, orient, segments_cross};
use crate::region::Region;
use crate::GeometryError;
use glam::DVec2;

/// A polyline embedded in a region ([`Region::embedded_lines`]): every vertex of it is a
/// vertex of each mesh, and between two of them the mesh's edges run along it. Closed when its
/// last point is its first (an inclusion's outline).
#[derive(Clone, Debug, PartialEq)]
pub struct EmbeddedLine {
    /// The vertices, in order; at least two.
    pub points: Vec<DVec2>,
    /// Its marker (0 for none): the number a solver knows the line by, as a `.poly`'s
    /// segment marker numbers a wall.
    pub marker: i64,
}

impl EmbeddedLine {
    /// Whether the line closes on itself (its last point is its first).
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, EmbeddedLine};
    /// let square = [(0.4, 0.4), (0.6, 0.4), (0.6, 0.6), (0.4, 0.6), (0.4, 0.4)];
    /// let line = EmbeddedLine { points: square.map(DVec2::from).to_vec(), marker: 3 };
    /// assert!(line.is_closed());
    /// ```
    pub fn is_closed(&self) -> bool {
        self.points.len() > 2 && self.points.first() == self.points.last()
    }

    /// Its segments, in order.
    pub fn segments(&self) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
        self.points.windows(2).map(|w| (w[0], w[1]))
    }

    /// Its length.
    pub fn length(&self) -> f64 {
        self.segments().map(|(a, b)| a.distance(b)).sum()
    }

    /// Segments (pairs of indices into `points`, each with its marker) joined into lines: a
    /// line ends where three or more segments meet, where one ends, at a vertex `ends` names
    /// (one on the region's boundary), and where the marker changes; a cycle with none of
    /// these is one closed line. Open lines first, each from an end, then the cycles.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, EmbeddedLine};
    /// let points = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (1.0, 1.0)].map(DVec2::from);
    /// // A T: three segments meeting at (1, 0), the stem marked 5.
    /// let lines = EmbeddedLine::join(&points, &[(0, 1, 2), (1, 2, 2), (1, 3, 5)], |_| false);
    /// assert_eq!(lines.len(), 3);
    /// assert_eq!(lines.iter().filter(|l| l.marker == 5).count(), 1);
    /// ```
    pub fn join(
        points: &[DVec2],
        segments: &[(usize, usize, i64)],
        ends: impl Fn(usize) -> bool,
    ) -> Vec<EmbeddedLine> {
        let mut at: std::collections::HashMap<usize, Vec<usize>> = Default::default();
        for (s, &(a, b, _)) in segments.iter().enumerate() {
            at.entry(a).or_default().push(s);
            at.entry(b).or_default().push(s);
        }
        let other = |s: usize, v: usize| {
            let (a, b, _) = segments[s];
            if a == v {
                b
            } else {
                a
            }
        };
        // A vertex a line passes through: two segments of one marker, not at an end.
        let through = |v: usize| {
            let ss = &at[&v];
            ss.len() == 2 && !ends(v) && segments[ss[0]].2 == segments[ss[1]].2
        };
        let mut used = vec![false; segments.len()];
        let walk = |s0: usize, v0: usize, used: &mut Vec<bool>| {
            let (mut s, mut v) = (s0, v0);
            let mut vs = vec![points[v0]];
            loop {
                used[s] = true;
                v = other(s, v);
                vs.push(points[v]);
                if v == v0 || !through(v) {
                    break;
                }
                match at[&v].iter().find(|&&t| !used[t]) {
                    Some(&t) => s = t,
                    None => break,
                }
            }
            EmbeddedLine {
                points: vs,
                marker: segments[s0].2,
            }
        };
        let mut out = Vec::new();
        for (s, &(a, b, _)) in segments.iter().enumerate() {
            for v in [a, b] {
                if !used[s] && !through(v) {
                    out.push(walk(s, v, &mut used));
                }
            }
        }
        for s in 0..segments.len() {
            if !used[s] {
                out.push(walk(s, segments[s].0, &mut used));
            }
        }
        out
    }

    /// The same line without the vertices where it runs straight on (turning by at most
    /// `radians`): a line read from a mesh's edges has a vertex at every old mesh vertex.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, EmbeddedLine};
    /// let line = EmbeddedLine { points: [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.0, 1.0)].map(DVec2::from).to_vec(), marker: 1 };
    /// assert_eq!(line.straightened(1e-9).points, [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)].map(DVec2::from));
    /// ```
    pub fn straightened(&self, radians: f64) -> EmbeddedLine {
        let p = &self.points;
        let turn = |a: DVec2, b: DVec2, c: DVec2| {
            let (u, v) = (b - a, c - b);
            u.perp_dot(v).atan2(u.dot(v)).abs()
        };
        let mut kept = vec![p[0]];
        for k in 1..p.len().saturating_sub(1) {
            if turn(*kept.last().expect("one kept"), p[k], p[k + 1]) > radians {
                kept.push(p[k]);
            }
        }
        if p.len() > 1 {
            kept.push(p[p.len() - 1]);
        }
        EmbeddedLine {
            points: kept,
            marker: self.marker,
        }
    }
}

impl Region {
    /// The lines embedded in the region ([`Region::with_embedded_lines`]); empty for most.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, EmbeddedLine, Region};
    /// let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from).to_vec();
    /// // A square whose outline has a vertex at the middle of the bottom and top edges...
    /// let outline = [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.0, 1.0), (0.5, 1.0), (0.0, 1.0)];
    /// let r = Region::from_loops("two materials", vec![(cvtmesh::geometry::LoopRole::Outer,
    ///     outline.map(DVec2::from).to_vec())])?;
    /// // ... and an interface between them, marked 7.
    /// let interface = EmbeddedLine { points: vec![DVec2::new(0.5, 0.0), DVec2::new(0.5, 1.0)], marker: 7 };
    /// let r = r.with_embedded_lines([interface])?;
    /// assert_eq!(r.embedded_lines()[0].marker, 7);
    /// // A line leaving the region is refused by name.
    /// let out = EmbeddedLine { points: vec![DVec2::new(0.5, 0.5), DVec2::new(1.5, 0.5)], marker: 0 };
    /// let e = Region::from_loops("sq", vec![(cvtmesh::geometry::LoopRole::Outer, square)])?
    ///     .with_embedded_lines([out]).unwrap_err();
    /// assert!(e.to_string().contains("(1.5, 0.5)"));
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn embedded_lines(&self) -> &[EmbeddedLine] {
        &self.lines
    }

    /// The same region with `lines` embedded as well ([`Region::embedded_lines`]). Every
    /// vertex of a line lies inside the region, off its boundary by more than 10⁻⁹ of its
    /// diameter, or on a polygonal wall, an arc or a circle (an interface from wall to wall, an
    /// inclusion touching a wall), where the piece is split if need be and the point becomes
    /// a corner whatever the corner angle; no segment leaves the region. Lines may share vertices (three materials meeting at
    /// a point); where two cross, or a vertex of one lies on a segment of another, both get a
    /// vertex there (as Triangle splits crossing segments), so each line lists it (a line that
    /// crosses itself, twice). Lines may not overlap along a segment. A marked line in
    /// a region that numbers no walls gives every piece Triangle's marker for a boundary, 1,
    /// as a marked embedded point does.
    pub fn with_embedded_lines(
        mut self,
        lines: impl IntoIterator<Item = EmbeddedLine>,
    ) -> Result<Region, GeometryError> {
        let off = 1e-9 * self.diameter();
        let bad = |message: String| GeometryError::Invalid {
            region: self.name.clone(),
            message,
        };
        let mut added: Vec<EmbeddedLine> = Vec::new();
        // Junctions where the boundary runs straight on, which a line's end makes corners.
        let mut new_corners: Vec<DVec2> = Vec::new();
        for (i, mut line) in lines.into_iter().enumerate() {
            let n = line.points.len();
            if n < 2 {
                return Err(bad(format!(
                    "embedded line {i} has {n} point(s); a line needs at least two"
                )));
            }
            if i32::try_from(line.marker).is_err() {
                return Err(bad(format!(
                    "marker {} of embedded line {i} is outside the 32-bit range of Triangle's \
                     markers and Gmsh's physical tags",
                    line.marker
                )));
            }
            for k in 0..n {
                let p = line.points[k];
                let sd = self.signed_distance(p);
                if !p.is_finite() || sd.is_nan() {
                    return Err(bad(format!(
                        "embedded line {i} has a point that is not finite: ({}, {})",
                        p.x, p.y
                    )));
                }
                if sd <= -off {
                    continue;
                }
                // Any vertex may touch the boundary (an end of an interface, an inclusion
                // touching a wall) at a junction of pieces, or at a point of a straight piece
                // or an arc, which is split there; there it becomes a corner.
                let junction = self
                    .pieces
                    .iter()
                    .map(|piece| piece.start())
                    .find(|q| q.distance(p) <= off)
                    .or_else(|| {
                        self.pieces
                            .iter()
                            .any(|piece| split_point(piece, p, off).is_some())
                            .then_some(p)
                    });
                match junction {
                    Some(q) => {
                        line.points[k] = q;
                        if self.corners.iter().all(|c| c.pos != q) && !new_corners.contains(&q) {
                            new_corners.push(q);
                        }
                    }
                    None => {
                        let place = if sd > off {
                            "outside the region"
                        } else {
                            "on a super-ellipse loop of the region's boundary (a line may \
                             meet a polygonal wall, an arc or a circle)"
                        };
                        return Err(bad(format!(
                            "embedded line {i} has the point ({}, {}) {place}",
                            p.x, p.y
                        )));
                    }
                }
            }
            if let Some(w) = line.points.windows(2).find(|w| w[0].distance(w[1]) <= off) {
                return Err(bad(format!(
                    "embedded line {i} repeats the point ({}, {})",
                    w[0].x, w[0].y
                )));
            }
            added.push(line);
        }
        // A segment whose ends are inside may still leave the region between them, or run
        // outside between two corners of a notch. The boundary's chords and the segments
        // are paired by a grid of their boxes, not each with each (a digitized interface of
        // 20 000 segments in a coastline of as many).
        let boundary = self.boundary_chords();
        let chord = 1e-6 * self.diameter();
        let segments: Vec<(usize, DVec2, DVec2)> = added
            .iter()
            .enumerate()
            .flat_map(|(i, l)| l.segments().map(move |(a, b)| (i, a, b)))
            .collect();
        let on_boundary = |p: DVec2| self.signed_distance(p).abs() <= off;
        let mut leaving: Option<usize> = segments
            .iter()
            .position(|&(_, a, b)| !self.contains(0.5 * (a + b)));
        let boxes: Vec<(DVec2, DVec2)> = boundary
            .iter()
            .copied()
            .chain(segments.iter().map(|&(_, a, b)| (a, b)))
            .collect();
        crate::crossings::candidate_pairs(&boxes, off, |e, k| {
            // Boundary chords first, then the segments: a pair of a chord and a segment.
            let Some(s) = k.checked_sub(boundary.len()).filter(|_| e < boundary.len()) else {
                return true;
            };
            let ((c, d), (_, a, b)) = (boundary[e], segments[s]);
            if leaving.is_some_and(|first| first <= s) || !segments_cross(a, b, c, d) {
                return true;
            }
            // A segment from a point of a curved piece crosses the piece's chords right
            // beside that point, within their sag: not a crossing of the boundary.
            let (o1, o2) = (orient(c, d, a), orient(c, d, b));
            let x = a + (b - a) * (o1 / (o1 - o2));
            let near_end = |p: DVec2| on_boundary(p) && x.distance(p) <= 1e3 * chord;
            if !near_end(a) && !near_end(b) {
                leaving = Some(s);
            }
            true
        });
        if let Some(s) = leaving {
            let (i, a, b) = segments[s];
            return Err(bad(format!(
                "embedded line {i}'s segment from ({}, {}) to ({}, {}) leaves the region",
                a.x, a.y, b.x, b.y
            )));
        }
        // Where two lines cross, or a vertex of one lies on a segment of another (a T whose
        // stem stops at the bar), both get a vertex there, as Triangle splits crossing
        // segments and Gmsh's fragments do; a line crossing itself visits its crossing twice,
        // and a line's end on its own segment splits it.
        let mut lines: Vec<EmbeddedLine> = std::mem::take(&mut self.lines);
        let existing = lines.len();
        lines.extend(added);
        split_where_lines_meet(&mut lines, off);
        added = lines.split_off(existing);
        self.lines = lines;
        // No two segments (of one line or of two) may cross, or touch except at a shared
        // vertex: the mesh could not have both as edges.
        let all: Vec<(usize, DVec2, DVec2)> = self
            .lines
            .iter()
            .chain(&added)
            .enumerate()
            .flat_map(|(i, l)| l.segments().map(move |(a, b)| (i, a, b)))
            .collect();
        // Pairs by a grid of their boxes padded by `off`; of the pairs that meet, the first in
        // the order of the lines' segments is named.
        let boxes: Vec<(DVec2, DVec2)> = all.iter().map(|&(_, a, b)| (a, b)).collect();
        let mut first: Option<(usize, usize, DVec2)> = None;
        crate::crossings::candidate_pairs(&boxes, off, |s, t| {
            let ((_, a, b), (_, c, d)) = (all[s], all[t]);
            if let Some(p) = meeting(a, b, c, d, off) {
                if first.is_none_or(|(fs, ft, _)| (s, t) < (fs, ft)) {
                    first = Some((s, t, p));
                }
            }
            true
        });
        if let Some((s, t, p)) = first {
            let (i, j) = (all[s].0, all[t].0);
            return Err(bad(if i == j {
                format!(
                    "embedded line {i} touches or runs along itself at ({}, {}) without a \
                     vertex there; give it as two lines that meet there",
                    p.x, p.y
                )
            } else {
                format!(
                    "embedded lines {i} and {j} overlap or touch at ({}, {}) without a shared \
                     vertex (closer than 10⁻⁹ of the region's diameter); lines may cross or \
                     meet at a vertex, not run along each other",
                    p.x, p.y
                )
            }));
        }
        if !new_corners.is_empty() {
            self = self.with_corners_at(&new_corners)?;
            // An arc split at a line's end ends at its own point of that angle, a rounding
            // away from the line's: the line ends where the pieces meet, so that the corner is
            // the line's vertex (kept whatever the corner angle) and the mesh's.
            let key = |p: DVec2| (p.x.to_bits(), p.y.to_bits());
            let exact: std::collections::HashMap<(u64, u64), DVec2> = new_corners
                .iter()
                .filter_map(|&q| {
                    let c = self.corners.iter().find(|c| c.pos.distance(q) <= off)?;
                    Some((key(q), c.pos))
                })
                .collect();
            for line in self.lines.iter_mut().chain(added.iter_mut()) {
                for p in &mut line.points {
                    if let Some(&c) = exact.get(&key(*p)) {
                        *p = c;
                    }
                }
            }
        }
        self.lines.extend(added);
        if self.markers.is_empty() && self.lines.iter().any(|l| l.marker != 0) {
            self.markers = vec![1; self.pieces.len()];
        }
        Ok(self)
    }

    /// The same region with corners at the boundary points `extra` as well (a piece through
    /// one split there), everything else kept.
    fn with_corners_at(&self, extra: &[DVec2]) -> Result<Region, GeometryError> {
        let off = 1e-9 * self.diameter();
        let mut recipe = self.recipe();
        // The halves of a split piece keep its marker.
        for (_, pieces) in &mut recipe.loops {
            *pieces = std::mem::take(pieces)
                .into_iter()
                .flat_map(|(piece, m)| {
                    split_at_all(piece, extra, off)
                        .into_iter()
                        .map(move |half| (half, m))
                })
                .collect();
        }
        recipe.corners.extend_from_slice(extra);
        Region::assembled(recipe)
    }

    /// The parts of `lines` inside the region, as Triangle keeps the part of a `.poly` segment
    /// inside the domain and eats the rest with the triangles outside: each line cut where it
    /// crosses the boundary (the cut on the boundary, where [`Region::with_embedded_lines`]
    /// makes it a corner), each run inside a line of its own with the line's marker, the runs
    /// outside or in a hole dropped. For fractures generated in a box larger than the region.
    /// Pieces shorter than 10⁻⁹ of the diameter are dropped. O((S + B) log) for S segments
    /// and B boundary chords, as [`Region::with_embedded_lines`] pairs them.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, EmbeddedLine, Region};
    /// let square = Region::from_loops(
    ///     "square",
    ///     vec![(cvtmesh::geometry::LoopRole::Outer,
    ///           [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from).to_vec())],
    /// )?;
    /// // A fracture through the square and out, and one wholly outside.
    /// let through = EmbeddedLine { points: vec![DVec2::new(-0.5, 0.5), DVec2::new(1.5, 0.5)], marker: 3 };
    /// let away = EmbeddedLine { points: vec![DVec2::new(2.0, 0.0), DVec2::new(3.0, 1.0)], marker: 4 };
    /// let kept = square.lines_inside([through, away]);
    /// assert_eq!(kept.len(), 1);
    /// assert_eq!(kept[0].points, [DVec2::new(0.0, 0.5), DVec2::new(1.0, 0.5)]);
    /// let region = square.with_embedded_lines(kept)?;
    /// assert_eq!(region.embedded_lines()[0].marker, 3);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn lines_inside(&self, lines: impl IntoIterator<Item = EmbeddedLine>) -> Vec<EmbeddedLine> {
        self.cut_lines(lines.into_iter().collect()).0
    }

    /// [`Region::lines_inside`], and how many of the lines' segments lay in part or wholly
    /// outside (or in a hole).
    pub(crate) fn cut_lines(&self, lines: Vec<EmbeddedLine>) -> (Vec<EmbeddedLine>, usize) {
        let off = 1e-9 * self.diameter();
        let boundary = self.boundary_chords();
        let segments = numbered_segments(&lines);
        // Where along each segment the boundary crosses it.
        let mut cuts: Vec<Vec<f64>> = vec![Vec::new(); segments.len()];
        let boxes: Vec<(DVec2, DVec2)> = boundary
            .iter()
            .copied()
            .chain(segments.iter().map(|&(_, _, a, b)| (a, b)))
            .collect();
        crate::crossings::candidate_pairs(&boxes, off, |e, k| {
            let Some(s) = k.checked_sub(boundary.len()).filter(|_| e < boundary.len()) else {
                return true;
            };
            let ((c, d), (_, _, a, b)) = (boundary[e], segments[s]);
            let (o1, o2) = (orient(c, d, a), orient(c, d, b));
            let (o3, o4) = (orient(a, b, c), orient(a, b, d));
            if o1 * o2 < 0.0 && o3 * o4 <= 0.0 {
                cuts[s].push(o1 / (o1 - o2));
            }
            true
        });
        // The point where a cut lies, on the boundary itself (a chord of a curve is not it).
        let on_boundary = |p: DVec2| self.project(p).point;
        let mut out = Vec::new();
        let mut cut = 0;
        let mut s = 0;
        for (i, line) in lines.iter().enumerate() {
            let mut run: Vec<DVec2> = Vec::new();
            let flush = |run: &mut Vec<DVec2>, out: &mut Vec<EmbeddedLine>| {
                run.dedup_by(|a, b| a.distance(*b) <= off);
                if run.len() >= 2 {
                    out.push(EmbeddedLine {
                        points: std::mem::take(run),
                        marker: line.marker,
                    });
                }
                run.clear();
            };
            while s < segments.len() && segments[s].0 == i {
                let (_, _, a, b) = segments[s];
                let mut ts = std::mem::take(&mut cuts[s]);
                ts.sort_by(f64::total_cmp);
                // The segment's own ends exactly, a cut on the boundary itself.
                let at = |t: f64, cut: bool| match (t, cut) {
                    (_, true) => on_boundary(a + (b - a) * t),
                    (0.0, false) => a,
                    _ => b,
                };
                let bounds: Vec<(f64, bool)> = std::iter::once((0.0, false))
                    .chain(ts.iter().map(|&t| (t, true)))
                    .chain(std::iter::once((1.0, false)))
                    .collect();
                let mut whole = ts.is_empty();
                for w in bounds.windows(2) {
                    let ((t0, c0), (t1, c1)) = (w[0], w[1]);
                    if t1 <= t0 {
                        continue;
                    }
                    // A run along a wall is the wall's to judge (`with_embedded_lines`).
                    let inside = self.signed_distance(a + (b - a) * (0.5 * (t0 + t1))) <= off;
                    whole &= inside;
                    if inside {
                        if run.is_empty() || c0 {
                            flush(&mut run, &mut out);
                            run.push(at(t0, c0));
                        }
                        run.push(at(t1, c1));
                    } else {
                        flush(&mut run, &mut out);
                    }
                }
                cut += usize::from(!whole);
                s += 1;
            }
            flush(&mut run, &mut out);
        }
        (out, cut)
    }

    /// The boundary's polygon as segments, curves cut into chords within 10⁻⁶ of the diameter:
    /// what lines are paired with to find where they cross the boundary.
    fn boundary_chords(&self) -> Vec<(DVec2, DVec2)> {
        self.polygonize(1e-6 * self.diameter())
            .rings
            .iter()
            .flat_map(|r| {
                let m = r.points.len();
                (0..m).map(move |j| (r.points[j], r.points[(j + 1) % m]))
            })
            .collect()
    }

    /// Is `p` a vertex of an embedded line (on the boundary, a corner every corner angle
    /// keeps)?
    pub(crate) fn is_line_vertex(&self, p: DVec2) -> bool {
        self.lines.iter().any(|l| l.points.contains(&p))
    }
}

/// Every segment of `lines` as (line, segment within it, from, to), line by line.
fn numbered_segments(lines: &[EmbeddedLine]) -> Vec<(usize, usize, DVec2, DVec2)> {
    lines
        .iter()
        .enumerate()
        .flat_map(|(i, l)| {
            l.segments()
                .enumerate()
                .map(move |(k, (a, b))| (i, k, a, b))
        })
        .collect()
}

/// Splits the lines where they meet other than at a shared vertex: where two segments cross
/// (of two lines, or of one), both get the crossing point (the same bits in each); a vertex
/// of one line within `off` of a segment of another, off its ends, is inserted into that
/// segment; a line's end on one of its own segments splits that segment. Segments are paired
/// by a grid of their boxes. What is left (segments overlapping along a line, points closer
/// than `off` but apart) the caller refuses.
fn split_where_lines_meet(lines: &mut [EmbeddedLine], off: f64) {
    let segments = numbered_segments(lines);
    let ends: Vec<[DVec2; 2]> = lines
        .iter()
        .map(|l| [l.points[0], l.points[l.points.len() - 1]])
        .collect();
    let boxes: Vec<(DVec2, DVec2)> = segments.iter().map(|&(_, _, a, b)| (a, b)).collect();
    // Points to insert, by segment: (where along it, the point).
    let mut inserted: Vec<Vec<(f64, DVec2)>> = vec![Vec::new(); segments.len()];
    let apart = |p: DVec2, a: DVec2, b: DVec2| p.distance(a) > off && p.distance(b) > off;
    let insert_on = |s: usize, p: DVec2, inserted: &mut Vec<Vec<(f64, DVec2)>>| {
        let (_, _, a, b) = segments[s];
        let (q, t, _) = closest_on_segment(a, b, p);
        if q.distance(p) <= off && apart(p, a, b) {
            inserted[s].push((t, p));
        }
    };
    crate::crossings::candidate_pairs(&boxes, off, |s, t| {
        let ((i, _, a, b), (j, _, c, d)) = (segments[s], segments[t]);
        // Two segments crossing, of two lines or of one (a line crossing itself visits the
        // crossing twice).
        if segments_cross(a, b, c, d) {
            let (o1, o2) = (orient(c, d, a), orient(c, d, b));
            let x = a + (b - a) * (o1 / (o1 - o2));
            if apart(x, a, b) && apart(x, c, d) {
                inserted[s].push((closest_on_segment(a, b, x).1, x));
                inserted[t].push((closest_on_segment(c, d, x).1, x));
                return true;
            }
        }
        if i == j {
            // A line's own end on its own segment (a loop closing on its side).
            for p in ends[i] {
                if p != c && p != d {
                    insert_on(t, p, &mut inserted);
                }
                if p != a && p != b {
                    insert_on(s, p, &mut inserted);
                }
            }
            return true;
        }
        for p in [a, b] {
            insert_on(t, p, &mut inserted);
        }
        for p in [c, d] {
            insert_on(s, p, &mut inserted);
        }
        true
    });
    // Several lines crossing at one point give crossings a rounding apart: each point to
    // insert becomes the first vertex or crossing within `off` of it, so that the lines share
    // one vertex there.
    let cell = |p: DVec2| ((p.x / off).floor() as i64, (p.y / off).floor() as i64);
    let mut near: std::collections::HashMap<(i64, i64), Vec<DVec2>> =
        std::collections::HashMap::new();
    for p in lines.iter().flat_map(|l| l.points.iter()) {
        near.entry(cell(*p)).or_default().push(*p);
    }
    let mut canonical = |p: DVec2| -> DVec2 {
        let (cx, cy) = cell(p);
        let found = (cx - 1..=cx + 1)
            .flat_map(|x| (cy - 1..=cy + 1).map(move |y| (x, y)))
            .filter_map(|c| near.get(&c))
            .flatten()
            .find(|q| q.distance(p) <= off)
            .copied();
        found.unwrap_or_else(|| {
            near.entry((cx, cy)).or_default().push(p);
            p
        })
    };
    let mut next = 0;
    for line in lines.iter_mut() {
        let n = line.points.len() - 1;
        let mut points = vec![line.points[0]];
        for (k, list) in inserted[next..next + n].iter_mut().enumerate() {
            list.sort_by(|x, y| x.0.total_cmp(&y.0));
            points.extend(list.iter().map(|&(_, p)| canonical(p)));
            points.push(line.points[k + 1]);
        }
        next += n;
        points.dedup();
        line.points = points;
    }
}

/// `piece` split at every one of `points` on it, in order along it.
fn split_at_all(piece: crate::Piece, points: &[DVec2], off: f64) -> Vec<crate::Piece> {
    match points.iter().find_map(|&p| split_point(&piece, p, off)) {
        Some((a, b)) => {
            let mut out = split_at_all(a, points, off);
            out.extend(split_at_all(b, points, off));
            out
        }
        None => vec![piece],
    }
}

/// The angle of `p` about `center` where `p` lies within `off` of the circle of `radius`.
fn angle_on_circle(center: DVec2, radius: f64, p: DVec2, off: f64) -> Option<f64> {
    let d = p - center;
    ((d.length() - radius).abs() <= off).then(|| d.y.atan2(d.x))
}

/// `piece` split in two at `p`, where `p` lies on it within `off` and not at its ends: a line
/// or a chain at the point, an arc at the angle of `p`, a circle into two half-circle arcs
/// from `p` (so that `p` is where pieces meet). `None` otherwise (and for a super-ellipse,
/// which has no arcs to be cut into).
fn split_point(piece: &crate::Piece, p: DVec2, off: f64) -> Option<(crate::Piece, crate::Piece)> {
    use crate::Piece;
    if piece.start().distance(p) <= off || piece.end().distance(p) <= off {
        return None;
    }
    match piece {
        Piece::Circle {
            center,
            radius,
            ccw,
        } => {
            let t = angle_on_circle(*center, *radius, p, off)?;
            let half = if *ccw {
                std::f64::consts::PI
            } else {
                -std::f64::consts::PI
            };
            let arc = |from: f64, to: f64| Piece::Arc {
                center: *center,
                radius: *radius,
                from,
                to,
            };
            Some((arc(t, t + half), arc(t + half, t + 2.0 * half)))
        }
        Piece::Line { a, b } => (closest_on_segment(*a, *b, p).0.distance(p) <= off)
            .then_some((Piece::Line { a: *a, b: p }, Piece::Line { a: p, b: *b })),
        Piece::Chain(pts) => {
            let k = pts
                .windows(2)
                .position(|w| closest_on_segment(w[0], w[1], p).0.distance(p) <= off)?;
            let mut first = pts[..=k].to_vec();
            first.push(p);
            let mut second = vec![p];
            second.extend_from_slice(&pts[k + 1..]);
            // A split at a chain's vertex leaves that vertex once.
            first.dedup();
            second.dedup();
            Some((Piece::Chain(first), Piece::Chain(second)))
        }
        Piece::Arc {
            center,
            radius,
            from,
            to,
        } => {
            let mut t = angle_on_circle(*center, *radius, p, off)?;
            // The angle within the arc's sweep, either way round.
            let (lo, hi) = (from.min(*to), from.max(*to));
            while t < lo {
                t += std::f64::consts::TAU;
            }
            while t > hi {
                t -= std::f64::consts::TAU;
            }
            (t > lo && t < hi).then_some((
                Piece::Arc {
                    center: *center,
                    radius: *radius,
                    from: *from,
                    to: t,
                },
                Piece::Arc {
                    center: *center,
                    radius: *radius,
                    from: t,
                    to: *to,
                },
            ))
        }
        _ => None,
    }
}

/// Where segments [a, b] and [c, d] cross or touch, other than at an end point they share
/// exactly: `None` when they are apart (or meet only so).
fn meeting(a: DVec2, b: DVec2, c: DVec2, d: DVec2, off: f64) -> Option<DVec2> {
    if (a == c && b == d) || (a == d && b == c) {
        return Some(a);
    }
    if segments_cross(a, b, c, d) {
        let (o1, o2) = (orient(c, d, a), orient(c, d, b));
        return Some(a + (b - a) * (o1 / (o1 - o2)));
    }
    let shared = |p: DVec2| p == c || p == d;
    // An end of one within `off` of the other segment touches it (collinear overlaps too).
    let near = |p: DVec2, s: DVec2, t: DVec2| closest_on_segment(s, t, p).0.distance(p) <= off;
    [(a, c, d), (b, c, d)]
        .into_iter()
        .filter(|&(p, _, _)| !shared(p))
        .chain(
            [(c, a, b), (d, a, b)]
                .into_iter()
                .filter(|&(p, _, _)| p != a && p != b),
        )
        .find(|&(p, s, t)| near(p, s, t))
        .map(|(p, _, _)| p)
        .or_else(|| {
            // Two segments sharing one end, overlapping along a line.
            let one_shared = [a, b].iter().filter(|p| shared(**p)).count() == 1;
            let collinear = orient(a, b, c).abs() <= off * a.distance(b)
                && orient(a, b, d).abs() <= off * a.distance(b);
            let (p, q) = if shared(a) { (a, b) } else { (b, a) };
            let other = if p == c { d } else { c };
            (one_shared && collinear && (q - p).dot(other - p) > 0.0).then_some(p)
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::LoopRole;

    fn outline() -> Region {
        let pts = [
            (0.0, 0.0),
            (0.5, 0.0),
            (1.0, 0.0),
            (1.0, 1.0),
            (0.5, 1.0),
            (0.0, 1.0),
        ];
        Region::from_loops("sq", vec![(LoopRole::Outer, pts.map(DVec2::from).to_vec())]).unwrap()
    }

    fn unit_square() -> Vec<DVec2> {
        [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .map(DVec2::from)
            .to_vec()
    }

    fn line(pts: &[(f64, f64)], marker: i64) -> EmbeddedLine {
        EmbeddedLine {
            points: pts.iter().map(|&p| DVec2::from(p)).collect(),
            marker,
        }
    }

    #[test]
    fn an_interface_from_wall_to_wall_keeps_its_ends_as_corners() {
        let r = outline()
            .with_embedded_lines([line(&[(0.5, 0.0), (0.5, 1.0)], 7)])
            .unwrap();
        // The straight junctions at the interface's ends survive any corner angle.
        let bent = r.with_corner_angle(30.0);
        let corners: Vec<DVec2> = bent.corners().iter().map(|c| c.pos).collect();
        assert!(corners.contains(&DVec2::new(0.5, 0.0)) && corners.contains(&DVec2::new(0.5, 1.0)));
        assert_eq!(corners.len(), 6);
        assert_eq!(bent.embedded_lines(), r.embedded_lines());
        // Without the line, they are dropped.
        assert_eq!(outline().with_corner_angle(30.0).corners().len(), 4);
    }

    #[test]
    fn bad_lines_are_refused_naming_the_place() {
        let cases: [(&[(f64, f64)], &str); 4] = [
            (&[(0.5, 0.5)], "at least two"),
            (
                &[(0.2, 0.5), (0.8, 0.5), (0.8, 0.5)],
                "repeats the point (0.8, 0.5)",
            ),
            (&[(0.2, 0.5), (1.2, 0.5)], "(1.2, 0.5) outside"),
            (&[(0.2, 0.5), (f64::NAN, 0.5)], "not finite"),
        ];
        for (pts, says) in cases {
            let e = outline()
                .with_embedded_lines([line(pts, 0)])
                .unwrap_err()
                .to_string();
            assert!(e.contains(says), "{pts:?}: {e}");
        }
    }

    /// A line wholly inside is kept to the bit: its ends are where other lines cross or meet
    /// it (a + (b − a)·1 is not b for these two points).
    #[test]
    fn a_line_inside_is_kept_to_the_bit() {
        let (a, b) = (
            DVec2::new(0.02693213872252037, 0.48320643259543933),
            DVec2::new(0.011058913144804573, 0.4886578946384607),
        );
        assert_ne!(a + (b - a) * 1.0, b);
        let kept = outline().lines_inside([line(&[(a.x, a.y), (b.x, b.y)], 3)]);
        assert_eq!(kept.len(), 1);
        assert_eq!(kept[0].points, [a, b]);
    }

    #[test]
    fn a_line_may_end_inside_a_wall_an_arc_or_a_circle_but_not_a_super_ellipse() {
        // Inside the bottom wall: the wall is split there, the halves keep its marker.
        let marked = Region::from_loops_marked(
            "sq",
            vec![(LoopRole::Outer, unit_square(), vec![4, 5, 5, 5])],
        )
        .unwrap();
        let r = marked
            .with_embedded_lines([line(&[(0.2, 0.0), (0.2, 0.5)], 9)])
            .unwrap();
        assert!(r.corners().iter().any(|c| c.pos == DVec2::new(0.2, 0.0)));
        assert_eq!(r.pieces().len(), 5);
        assert_eq!(r.piece_markers(), Some(&[4, 4, 5, 5, 5][..]));
        assert_eq!(r.area(), 1.0);
        // On the pie's arc (a half disc's upper boundary): split at the point's angle.
        let half = Region::builtin("pie_hole").unwrap();
        let arc_point = half
            .pieces()
            .iter()
            .find_map(|p| match p {
                crate::Piece::Arc {
                    center,
                    radius,
                    from,
                    to,
                } => Some(*center + *radius * DVec2::from_angle(0.5 * (from + to))),
                _ => None,
            })
            .unwrap();
        let inside = half.polygonize(1e-3).rings[0].points.iter().sum::<DVec2>()
            / half.polygonize(1e-3).rings[0].points.len() as f64;
        let split = half.clone().with_embedded_lines([EmbeddedLine {
            points: vec![arc_point, 0.5 * (arc_point + inside)],
            marker: 0,
        }]);
        let split = split.unwrap();
        assert!((split.area() - half.area()).abs() < 1e-12 * half.area());
        assert_eq!(split.pieces().len(), half.pieces().len() + 1);
        // On a circle loop, anywhere round it: the circle becomes two half-circle arcs from
        // the point, which is a corner; a second line ending opposite adds nothing more.
        let disc = Region::builtin("circle").unwrap();
        for (x, y) in [(0.0, 1.0), (-0.6, -0.8), (1.0, 0.0)] {
            let r = disc
                .clone()
                .with_embedded_lines([line(&[(x, y), (0.0, 0.0)], 0)])
                .unwrap();
            assert!(
                (r.area() - disc.area()).abs() < 1e-12 * disc.area(),
                "{x} {y}"
            );
            let end = r.embedded_lines()[0].points[0];
            assert!(end.distance(DVec2::new(x, y)) < 1e-15, "{end}");
            assert!(r.corners().iter().any(|c| c.pos == end), "{x} {y}");
        }
        let both = disc
            .clone()
            .with_embedded_lines([
                line(&[(0.0, 1.0), (0.0, 0.5)], 0),
                line(&[(0.0, -1.0), (0.0, -0.5)], 0),
            ])
            .unwrap();
        assert_eq!(both.pieces().len(), 2);
        assert_eq!(both.corners().len(), 2);
        // A hole's circle runs clockwise: its halves too.
        let annulus = Region::builtin("annulus").unwrap();
        let r = annulus
            .clone()
            .with_embedded_lines([line(&[(0.0, 0.4), (0.0, 1.0)], 0)])
            .unwrap();
        assert!((r.area() - annulus.area()).abs() < 1e-12 * annulus.area());
        assert_eq!(r.corners().len(), 2);
        // A super-ellipse is not cut into arcs.
        let e = Region::builtin("superellipse")
            .unwrap()
            .with_embedded_lines([line(&[(0.0, 1.0), (0.0, 0.0)], 0)])
            .unwrap_err()
            .to_string();
        assert!(e.contains("super-ellipse"), "{e}");
    }

    #[test]
    fn a_laminate_splits_each_wall_at_every_interface_and_an_inclusion_may_touch_one() {
        let square = Region::from_loops("sq", vec![(LoopRole::Outer, unit_square())]).unwrap();
        // Two interfaces, listed either way: both walls are split twice.
        let layers = [
            line(&[(0.3, 0.0), (0.3, 1.0)], 1),
            line(&[(0.7, 0.0), (0.7, 1.0)], 2),
        ];
        for order in [[0, 1], [1, 0]] {
            let r = square
                .clone()
                .with_embedded_lines(order.map(|i| layers[i].clone()))
                .unwrap();
            assert_eq!(r.pieces().len(), 8);
            assert_eq!(r.with_corner_angle(30.0).corners().len(), 8);
        }
        // A triangle standing on the bottom wall, touching it at one vertex.
        let r = square
            .with_embedded_lines([line(&[(0.5, 0.0), (0.7, 0.3), (0.3, 0.3), (0.5, 0.0)], 3)])
            .unwrap();
        assert!(r.corners().iter().any(|c| c.pos == DVec2::new(0.5, 0.0)));
    }

    #[test]
    fn a_line_from_a_point_of_an_arc_is_inside_beside_the_arc_s_chords() {
        for deg in [10.0f64, 60.0, 100.0, 150.0] {
            let (y, x) = deg.to_radians().sin_cos();
            let text = format!(
                r#"{{"loops": [{{"segments": [{{"kind": "arc", "center": [0, 0], "radius": 1,
                "from_deg": 0, "to_deg": 180}}, {{"kind": "polyline", "points": [[-1, 0], [1, 0]]}}]}}],
                "lines": [{{"points": [[{x}, {y}], [0.2, 0.0]], "marker": 7}}]}}"#
            );
            let r =
                Region::from_json_str(&text, "half.json").unwrap_or_else(|e| panic!("{deg}: {e}"));
            assert_eq!(r.pieces().len(), 4, "{deg}");
        }
        // A line that does leave the disc through its arc is still refused.
        let text = r#"{"loops": [{"segments": [{"kind": "arc", "center": [0, 0], "radius": 1,
            "from_deg": 0, "to_deg": 180}, {"kind": "polyline", "points": [[-1, 0], [1, 0]]}]}],
            "lines": [{"points": [[0.0, 0.5], [0.9, 0.9]]}]}"#;
        assert!(Region::from_json_str(text, "half.json").is_err());
    }

    #[test]
    fn a_stem_ending_on_a_bar_splits_the_bar_there() {
        let bar = line(&[(0.2, 0.5), (0.8, 0.5)], 1);
        let stem = line(&[(0.5, 0.5), (0.5, 0.9)], 2);
        let r = outline().with_embedded_lines([bar, stem]).unwrap();
        assert_eq!(
            r.embedded_lines()[0].points,
            [(0.2, 0.5), (0.5, 0.5), (0.8, 0.5)].map(DVec2::from)
        );
        // A stem through the bar: both get the crossing.
        let through = line(&[(0.5, 0.2), (0.5, 0.9)], 2);
        let bar = line(&[(0.2, 0.5), (0.8, 0.5)], 1);
        let r = outline().with_embedded_lines([bar, through]).unwrap();
        let [bar, stem] = r.embedded_lines() else {
            panic!("two lines")
        };
        assert_eq!(bar.points[1], DVec2::new(0.5, 0.5));
        assert_eq!(stem.points[1], DVec2::new(0.5, 0.5));
    }

    #[test]
    fn crossing_lines_are_split_and_overlapping_ones_refused() {
        let a = line(&[(0.2, 0.2), (0.8, 0.8)], 1);
        let crossing = line(&[(0.2, 0.8), (0.8, 0.2)], 2);
        let r = outline()
            .with_embedded_lines([a.clone(), crossing])
            .unwrap();
        let x = r.embedded_lines()[0].points[1];
        assert!(x.distance(DVec2::splat(0.5)) < 1e-15, "{x}");
        // The same bits in both, so the mesh has one vertex there.
        assert_eq!(r.embedded_lines()[1].points[1], x);
        assert!(r.embedded_lines().iter().all(|l| l.points.len() == 3));
        // Ending on it splits it there (a T), and so does a middle vertex on it.
        let touching = line(&[(0.5, 0.5), (0.8, 0.2)], 2);
        assert!(outline().with_embedded_lines([a.clone(), touching]).is_ok());
        let bent = line(&[(0.2, 0.6), (0.5, 0.5), (0.8, 0.6)], 2);
        let r = outline().with_embedded_lines([a.clone(), bent]).unwrap();
        assert_eq!(r.embedded_lines()[0].points[1], DVec2::splat(0.5));
        // Running along it is refused, naming the place.
        let overlapping = line(&[(0.8, 0.8), (0.5, 0.5)], 2);
        let e = outline()
            .with_embedded_lines([a.clone(), overlapping])
            .unwrap_err()
            .to_string();
        assert!(e.contains("overlap or touch at (0.5, 0.5)"), "{e}");
        // Three lines meeting at a vertex of each: a triple junction.
        let star = [
            line(&[(0.5, 0.5), (0.5, 0.0)], 1),
            line(&[(0.5, 0.5), (0.2, 0.8)], 2),
            line(&[(0.5, 0.5), (0.8, 0.8)], 3),
        ];
        assert_eq!(
            outline()
                .with_embedded_lines(star)
                .unwrap()
                .embedded_lines()
                .len(),
            3
        );
        // A line crossing itself visits the crossing twice; one whose middle vertex touches
        // its own segment is refused.
        let bow = line(&[(0.2, 0.2), (0.8, 0.8), (0.8, 0.2), (0.2, 0.8)], 0);
        let r = outline().with_embedded_lines([bow]).unwrap();
        let points = &r.embedded_lines()[0].points;
        assert_eq!(points.len(), 6);
        assert!(points[1] == points[4] && points[1].distance(DVec2::splat(0.5)) < 1e-15);
        let kink = line(
            &[(0.2, 0.5), (0.8, 0.5), (0.8, 0.8), (0.5, 0.5), (0.5, 0.9)],
            0,
        );
        let e = outline()
            .with_embedded_lines([kink])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("touches or runs along itself at (0.5, 0.5)"),
            "{e}"
        );
    }

    #[test]
    fn lines_crossing_at_one_point_share_one_vertex_there() {
        // Three lines through one point, at angles whose crossings round apart.
        let through = |angle: f64, m: i64| {
            let c = DVec2::new(0.5, 0.5);
            let d = 0.37 * DVec2::from_angle(angle);
            line(&[((c - d).x, (c - d).y), ((c + d).x, (c + d).y)], m)
        };
        let lines = [through(0.1, 1), through(1.2, 2), through(2.3, 3)];
        let r = outline().with_embedded_lines(lines).unwrap();
        let centres: Vec<DVec2> = r.embedded_lines().iter().map(|l| l.points[1]).collect();
        assert!(r.embedded_lines().iter().all(|l| l.points.len() == 3));
        assert!(centres.iter().all(|&c| c == centres[0]), "{centres:?}");
        assert!(centres[0].distance(DVec2::splat(0.5)) < 1e-12);
    }

    #[test]
    fn a_segment_crossed_several_times_takes_the_crossings_in_order() {
        // A comb: a spine crossed by three teeth, given in no particular order, and a tooth
        // added to a region that has the spine already.
        let spine = line(&[(0.1, 0.5), (0.9, 0.5)], 1);
        let teeth = [0.7, 0.3, 0.5].map(|x| line(&[(x, 0.2), (x, 0.8)], 2));
        let r = outline().with_embedded_lines([spine]).unwrap();
        let r = r.with_embedded_lines(teeth).unwrap();
        let xs: Vec<f64> = r.embedded_lines()[0].points.iter().map(|p| p.x).collect();
        assert_eq!(xs, [0.1, 0.3, 0.5, 0.7, 0.9]);
        assert!(r.embedded_lines()[0].points.iter().all(|p| p.y == 0.5));
        for tooth in &r.embedded_lines()[1..] {
            assert_eq!(tooth.points.len(), 3);
            assert_eq!(tooth.points[1].y, 0.5);
        }
    }

    #[test]
    fn a_segment_leaving_a_notch_is_refused() {
        // An L: a chord between the two inner corners of the notch lies outside.
        let l = [
            (0.0, 0.0),
            (1.0, 0.0),
            (1.0, 0.5),
            (0.5, 0.5),
            (0.5, 1.0),
            (0.0, 1.0),
        ];
        let r =
            Region::from_loops("L", vec![(LoopRole::Outer, l.map(DVec2::from).to_vec())]).unwrap();
        let e = r
            .clone()
            .with_embedded_lines([line(&[(1.0, 0.5), (0.5, 1.0)], 0)])
            .unwrap_err()
            .to_string();
        assert!(e.contains("leaves the region"), "{e}");
        assert!(r
            .with_embedded_lines([line(&[(1.0, 0.5), (0.0, 0.0)], 0)])
            .is_ok());
    }
}
