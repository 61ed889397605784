//! The region Ω: loops of pieces, corners, and the queries every method needs.
//!
//! Constructors live with their implementations: [`Region::new`] and
//! [`Region::with_corner_angle`] in `build.rs`, [`Region::expand`] in `expand.rs`, the file
//! readers in `file.rs` and `formats.rs`; this module depends on none of them.
use crate::index::{Hit, Index};
use crate::piece::Piece;
use crate::polygon::{Polygon, Ring};
use crate::types::{BoundaryPoint, Corner, Loop, LoopRole, PieceId};
use glam::DVec2;
use std::sync::Arc;

/// A planar region: one or more disjoint parts, each an outer loop and any number of holes,
/// validated and oriented (outer CCW, holes CW). Loops are numbered part by part: each outer
/// loop is followed by its holes, so a region of one part has its outer loop as loop 0.
/// [`Region::parts`] splits a region of several parts into regions of one, which is what the
/// methods mesh.
///
/// Make one with [`Region::builtin`] (the paper's ten regions), [`Region::from_file`] (every
/// supported file format) or [`Region::new`] (loops of [`Piece`]s). Regions are immutable and
/// cheap to clone (the search index is shared), and can be shared across threads.
///
/// ```
/// use cvtmesh::geometry::{DVec2, Region};
/// use std::f64::consts::PI;
/// // The square [-1, 1]² with a circular hole of radius 0.4 around the origin.
/// let r = Region::builtin("square_hole")?;
/// assert!((r.area() - (4.0 - PI * 0.16)).abs() < 1e-12);
/// assert_eq!(r.loops().len(), 2);
/// // The square's four vertices are the corners; the circle has none.
/// assert_eq!(r.corners().len(), 4);
/// assert!(r.corners().iter().all(|c| c.pos.abs() == DVec2::ONE));
///
/// // Inside, in the hole, outside.
/// assert!(r.contains(DVec2::new(0.7, 0.0)));
/// assert!(!r.contains(DVec2::ZERO));
/// assert!(!r.contains(DVec2::new(2.0, 0.0)));
/// // Signed distance: negative inside (here 0.3 from the hole and from the right side).
/// assert!((r.signed_distance(DVec2::new(0.7, 0.0)) + 0.3).abs() < 1e-12);
/// assert!((r.signed_distance(DVec2::ZERO) - 0.4).abs() < 1e-12);
///
/// // The nearest boundary point, on the hole's loop (loop 1).
/// let b = r.project(DVec2::new(0.0, 0.5));
/// assert!((b.point - DVec2::new(0.0, 0.4)).length() < 1e-12);
/// assert_eq!(b.loop_index, 1);
/// assert!((b.distance - 0.1).abs() < 1e-12);
///
/// // A straight-edged approximation: chord error ≤ 1e-3, corners kept as vertices. The
/// // hole's polygon is inscribed in the circle, so the polygon is a little larger.
/// let p = r.polygonize(1e-3);
/// assert_eq!(p.rings.len(), 2);
/// assert!(p.area() > r.area() && p.area() - r.area() < 1e-2);
/// for c in r.corners() {
///     assert!(p.rings[0].points.contains(&c.pos));
/// }
/// # Ok::<(), cvtmesh::geometry::GeometryError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Region {
    pub(crate) name: String,
    pub(crate) pieces: Vec<Piece>,
    pub(crate) piece_loop: Vec<usize>,
    pub(crate) loops: Vec<Loop>,
    pub(crate) corners: Vec<Corner>,
    pub(crate) area: f64,
    /// Corner-angle threshold applied (degrees), if any (`with_corner_angle`).
    pub(crate) corner_threshold: Option<f64>,
    /// True when the corners were computed from the turning of the boundary rather than
    /// listed by the caller or the file.
    pub(crate) corners_computed: bool,
    /// Exact bounding box (min, max).
    pub(crate) bbox: (DVec2, DVec2),
    /// Nearest-point index over the boundary (shared by clones).
    pub(crate) index: Arc<Index>,
    /// Corner at the start / end of each piece, if any.
    pub(crate) corner_at_start: Vec<Option<usize>>,
    pub(crate) corner_at_end: Vec<Option<usize>>,
    /// Arc length along its loop at the start of each piece.
    pub(crate) piece_offset: Vec<f64>,
    /// Each piece's marker as the region file named it (empty when it named none).
    pub(crate) markers: Vec<i64>,
    /// Names the region's file gave its markers (a Gmsh physical curve's name).
    pub(crate) marker_names: std::collections::BTreeMap<i64, String>,
    /// Boundary vertices with a marker of their own (a `.poly`'s vertex markers), each a
    /// corner: where a solver pins a value at a point. Sorted by the bits of their
    /// coordinates.
    pub(crate) vertex_markers: Vec<(DVec2, i64)>,
    /// Points inside Ω every mesh has as vertices, each with its marker (0 for none).
    pub(crate) embedded: Vec<(DVec2, i64)>,
    /// Polylines inside Ω every mesh follows with its edges ([`Region::embedded_lines`]).
    pub(crate) lines: Vec<crate::EmbeddedLine>,
    /// Points numbering the subdomains ([`Region::subdomain_points`]).
    pub(crate) subdomains: Vec<(DVec2, i64)>,
    /// Names of subdomain numbers ([`Region::subdomain_name`]).
    pub(crate) subdomain_names: std::collections::BTreeMap<i64, String>,
    /// [`Region::inside_grid`], made on first use (shared by clones, which have the same loops).
    pub(crate) inside_grid: Arc<InsideGrid>,
    /// What the region's file held that the region does not use ([`Region::notes`]).
    pub(crate) notes: Vec<String>,
    /// The physical surface its file put the whole region in ([`Region::surface_group`]).
    pub(crate) surface_group: Option<(i64, String)>,
}

/// Cells of the [`Region::inside_grid`] a side.
pub const INSIDE_GRID: usize = 256;

/// The centres of [`Region::inside_grid`], once made.
#[derive(Default)]
pub(crate) struct InsideGrid(std::sync::OnceLock<Vec<DVec2>>);

impl std::fmt::Debug for InsideGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0.get() {
            Some(c) => write!(f, "InsideGrid({} centres)", c.len()),
            None => write!(f, "InsideGrid(not made)"),
        }
    }
}

impl Region {
    /// Name (file stem or built-in name).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// All pieces, indexed by `PieceId`.
    pub fn pieces(&self) -> &[Piece] {
        &self.pieces
    }
    /// Each piece's marker, indexed by `PieceId`, where the region file names walls by number
    /// (a Triangle `.poly`'s segment markers, how Triangle users set boundary conditions);
    /// `None` where it names none. Where the marker changes along a loop there is a corner, so
    /// a mesh has a vertex there and no boundary edge lies on two walls.
    ///
    /// ```
    /// use cvtmesh::geometry::formats::poly_from_str;
    /// // A 4 × 1 channel: bottom and top walls marked 1, the inlet 2 and the outlet 3; the
    /// // bottom wall is two collinear segments.
    /// let poly = "5 2 0 0\n1 0 0\n2 2 0\n3 4 0\n4 4 1\n5 0 1\n\
    ///             5 1\n1 1 2 1\n2 2 3 1\n3 3 4 3\n4 4 5 1\n5 5 1 2\n0\n";
    /// let r = poly_from_str(poly, "channel.poly", "channel")?;
    /// let markers = r.piece_markers().expect("the file marks its segments");
    /// let mut sorted = markers.to_vec();
    /// sorted.sort();
    /// // The bottom wall's two segments go straight on at (2, 0) with one marker: one piece.
    /// assert_eq!(sorted, [1, 1, 2, 3]);
    /// assert_eq!(r.with_default_corners().corners().len(), 4);
    /// assert!(cvtmesh::geometry::Region::builtin("circle")?.piece_markers().is_none());
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn piece_markers(&self) -> Option<&[i64]> {
        (!self.markers.is_empty()).then_some(&self.markers[..])
    }

    /// The boundary vertices that carry a marker of their own, as (position, marker): a
    /// Triangle `.poly` vertex whose nonzero marker differs from the markers of both segments
    /// at it (a point where a solver pins a value). Each is a corner, kept whatever the corner
    /// angle or simplification, so every mesh has a vertex there, and the mesh files give
    /// that vertex this marker. Empty for regions whose files give no such vertex.
    ///
    /// ```
    /// use cvtmesh::geometry::formats::poly_from_str;
    /// use cvtmesh::geometry::DVec2;
    /// // A 4 × 1 channel, its walls marked 1; vertex 2 in the middle of the bottom wall marks
    /// // itself 7. Vertices marked as their walls are (Triangle writes such files) pin nothing.
    /// let poly = "5 2 0 1\n1 0 0 1\n2 2 0 7\n3 4 0 1\n4 4 1 1\n5 0 1 1\n\
    ///             5 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 5 1\n5 5 1 1\n0\n";
    /// let r = poly_from_str(poly, "channel.poly", "channel")?.with_default_corners();
    /// assert_eq!(r.vertex_markers(), &[(DVec2::new(2.0, 0.0), 7)]);
    /// let c = r.corners().iter().position(|c| c.pos == DVec2::new(2.0, 0.0)).unwrap();
    /// assert_eq!(r.corner_marker(c), Some(7));
    /// assert_eq!(r.corners().len(), 5);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn vertex_markers(&self) -> &[(DVec2, i64)] {
        &self.vertex_markers
    }

    /// The marker of corner `c` ([`Region::corners`]) where it is one of the
    /// [`Region::vertex_markers`].
    pub fn corner_marker(&self, c: usize) -> Option<i64> {
        let pos = self.corners.get(c)?.pos;
        self.marked_vertex(pos).map(|k| self.vertex_markers[k].1)
    }

    /// Points inside the region that every mesh of it has as vertices, each with its marker
    /// (0 where it has none): a Triangle `.poly`'s vertices that lie on no segment (Triangle
    /// keeps every input vertex), Gmsh's `Point{..} In Surface{..}`, DistMesh's fixed points
    /// inside, where a source sits or a solver reads a value. Empty for most regions.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    /// let r = Region::builtin("circle")?.with_embedded_points([(DVec2::new(0.3, 0.1), 5)])?;
    /// assert_eq!(r.embedded_points(), &[(DVec2::new(0.3, 0.1), 5)]);
    /// // A point outside the region, or on its boundary, is refused by name.
    /// let e = Region::builtin("circle")?.with_embedded_points([(DVec2::new(2.0, 0.0), 0)]);
    /// assert!(e.unwrap_err().to_string().contains("(2, 0)"));
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn embedded_points(&self) -> &[(DVec2, i64)] {
        &self.embedded
    }

    /// What the region's file held that the region does not use, for the user to hear (a
    /// Triangle `.poly`'s area constraints); empty for most regions.
    ///
    /// ```
    /// use cvtmesh::geometry::formats::poly_from_str;
    /// let square = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n";
    /// assert!(poly_from_str(square, "sq.poly", "sq")?.notes().is_empty());
    /// let with_area = format!("{square}1\n1 0.5 0.5 7 0.001\n");
    /// let r = poly_from_str(&with_area, "sq.poly", "sq")?;
    /// assert!(r.notes()[0].contains("1 area constraint is not used"));
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// The same region with `points` embedded as well ([`Region::embedded_points`]), each
    /// with its marker (0 for none). Each must be finite and inside the region, off its
    /// boundary by more than 10⁻⁹ of its diameter; a point given twice counts once. A marked
    /// point in a region that numbers no walls gives every piece Triangle's marker for a
    /// boundary, 1, so that the mesh files carry markers at all.
    pub fn with_embedded_points(
        mut self,
        points: impl IntoIterator<Item = (DVec2, i64)>,
    ) -> Result<Region, crate::GeometryError> {
        let off = 1e-9 * self.diameter();
        // The points already embedded, by their bits: a line's thousands are added at once.
        let mut seen: std::collections::HashSet<(u64, u64)> = self
            .embedded
            .iter()
            .map(|(q, _)| (q.x.to_bits(), q.y.to_bits()))
            .collect();
        for (p, m) in points {
            let sd = self.signed_distance(p);
            if !p.is_finite() || sd.is_nan() || sd > -off {
                let place = if sd.is_nan() || sd > off {
                    "outside the region"
                } else {
                    "on the region's boundary (a boundary vertex is one of its loops' vertices)"
                };
                return Err(crate::GeometryError::Invalid {
                    region: self.name.clone(),
                    message: format!("the point ({}, {}) to embed lies {place}", p.x, p.y),
                });
            }
            if i32::try_from(m).is_err() {
                return Err(crate::GeometryError::Invalid {
                    region: self.name.clone(),
                    message: format!(
                        "marker {m} of the point ({}, {}) is outside the 32-bit range of \
                         Triangle's markers and Gmsh's physical tags",
                        p.x, p.y
                    ),
                });
            }
            if seen.insert((p.x.to_bits(), p.y.to_bits())) {
                self.embedded.push((p, m));
            }
        }
        if self.markers.is_empty() && self.embedded.iter().any(|&(_, m)| m != 0) {
            self.markers = vec![1; self.pieces.len()];
        }
        Ok(self)
    }

    /// Is `p` one of the [`Region::vertex_markers`]?
    pub(crate) fn is_marked_vertex(&self, p: DVec2) -> bool {
        self.marked_vertex(p).is_some()
    }

    /// Where `p` is in [`Region::vertex_markers`], which are sorted by their coordinates' bits
    /// (a digitized outline may mark thousands, and corners and simplification ask at every
    /// vertex).
    fn marked_vertex(&self, p: DVec2) -> Option<usize> {
        let bits = |q: DVec2| (q.x.to_bits(), q.y.to_bits());
        self.vertex_markers
            .binary_search_by_key(&bits(p), |&(q, _)| bits(q))
            .ok()
    }

    /// The name the region's file gave `marker` (a Gmsh physical curve's name, such as
    /// `"inlet"`), if it gave one ([`Region::with_marker_names`]).
    pub fn marker_name(&self, marker: i64) -> Option<&str> {
        self.marker_names.get(&marker).map(String::as_str)
    }

    /// Every marker's name ([`Region::marker_name`]), by marker.
    ///
    /// ```
    /// use cvtmesh::geometry::Region;
    /// let r = Region::builtin("circle")?.with_marker_names([(2, "inlet".to_string())]);
    /// assert_eq!(r.marker_names().get(&2).map(String::as_str), Some("inlet"));
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn marker_names(&self) -> &std::collections::BTreeMap<i64, String> {
        &self.marker_names
    }

    /// The same region with names for its markers, as a mesh file gives them (Gmsh's physical
    /// curves have a tag and a name): the files written for its meshes name the walls so.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    /// let points = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(DVec2::from).to_vec();
    /// let walls = [([0, 1], 7), ([1, 2], 9), ([2, 3], 9), ([3, 0], 9)];
    /// let r = Region::from_triangles_marked("sq", &points, &[[0, 1, 2], [0, 2, 3]], &walls)?
    ///     .with_marker_names([(7, "heated".to_string())]);
    /// assert_eq!((r.marker_name(7), r.marker_name(9)), (Some("heated"), None));
    /// assert_eq!(r.with_default_corners().marker_name(7), Some("heated"));
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn with_marker_names(mut self, names: impl IntoIterator<Item = (i64, String)>) -> Region {
        self.marker_names.extend(names);
        self
    }

    /// The tag and name of the physical surface the region's file put all of it in (a Gmsh
    /// mesh's single physical surface, such as 1 `"fluid"`), which the `.msh` files written
    /// for its meshes give their triangles again; `None` where the file named none (they are
    /// then in the surface `"domain"`).
    ///
    /// ```
    /// use cvtmesh::geometry::Region;
    /// let r = Region::builtin("circle")?;
    /// assert_eq!(r.surface_group(), None);
    /// let r = r.with_surface_group(1, "fluid");
    /// assert_eq!(r.with_default_corners().surface_group(), Some((1, "fluid")));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn surface_group(&self) -> Option<(i64, &str)> {
        self.surface_group.as_ref().map(|(t, n)| (*t, n.as_str()))
    }

    /// The same region with the physical surface ([`Region::surface_group`]) `tag` `name`.
    pub fn with_surface_group(mut self, tag: i64, name: &str) -> Region {
        self.surface_group = Some((tag, name.to_string()));
        self
    }

    /// The same region with `notes` added to [`Region::notes`] (what its file held that the
    /// region does not keep).
    pub fn with_notes(mut self, notes: impl IntoIterator<Item = String>) -> Region {
        self.notes.extend(notes);
        self
    }
    /// The centre about which the region is rotationally symmetric: every piece a full circle
    /// about one centre (a disc, an annulus). `None` otherwise.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    ///
    /// assert_eq!(Region::builtin("annulus")?.rotation_centre(), Some(DVec2::ZERO));
    /// assert_eq!(Region::builtin("pie_hole")?.rotation_centre(), None);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn rotation_centre(&self) -> Option<DVec2> {
        let mut centre = None;
        for piece in &self.pieces {
            let Piece::Circle { center, .. } = piece else {
                return None;
            };
            match centre {
                None => centre = Some(*center),
                Some(c) if c == *center => {}
                Some(_) => return None,
            }
        }
        centre
    }

    /// The moves from `old` to `new`, with the best-fitting rotation of the whole set about
    /// [`Region::rotation_centre`], ω = Σ rᵢ × dᵢ / Σ |rᵢ|², taken out (the plain moves on a
    /// region without one). On a disc or an annulus such a rotation changes no mesh measure,
    /// and a boundary rule that is not an energy gradient can drive one that never dies out;
    /// stopping rules that measure the mesh's change of shape use these moves.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    ///
    /// let old: Vec<DVec2> = (0..12).map(|i| DVec2::from_angle(i as f64 * 0.5) * 0.5).collect();
    /// let turned: Vec<DVec2> = old.iter().map(|p| DVec2::from_angle(1e-3).rotate(*p)).collect();
    /// let disc = Region::builtin("circle")?;
    /// // What is left is second order: the chord against the tangent, r θ² / 2.
    /// assert!(disc.moves_without_rotation(&old, &turned).iter().all(|d| d.length() < 1e-6));
    /// let square = Region::builtin("square_hole")?;
    /// assert!(square.moves_without_rotation(&old, &turned)[0].length() > 4e-4);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn moves_without_rotation(&self, old: &[DVec2], new: &[DVec2]) -> Vec<DVec2> {
        let moves = old.iter().zip(new).map(|(a, b)| *b - *a);
        let Some(c) = self.rotation_centre() else {
            return moves.collect();
        };
        let (mut torque, mut inertia) = (0.0, 0.0);
        for (a, d) in old.iter().zip(moves.clone()) {
            let r = *a - c;
            torque += r.perp_dot(d);
            inertia += r.length_squared();
        }
        let omega = if inertia > 0.0 { torque / inertia } else { 0.0 };
        old.iter()
            .zip(moves)
            .map(|(a, d)| d - omega * (*a - c).perp())
            .collect()
    }

    /// Loop of each piece.
    pub fn piece_loop(&self, piece: PieceId) -> usize {
        self.piece_loop[piece]
    }
    /// The loops, outer first.
    pub fn loops(&self) -> &[Loop] {
        &self.loops
    }
    /// The corners.
    pub fn corners(&self) -> &[Corner] {
        &self.corners
    }
    /// The corner-angle threshold (degrees) applied when the region was loaded, if any.
    pub fn corner_threshold(&self) -> Option<f64> {
        self.corner_threshold
    }
    /// True when the corners were computed from how the boundary turns (polygon file formats,
    /// [`Region::from_loops`], [`Region::new`] without a corner list), false when they were
    /// listed (every built-in region). [`Region::with_default_corners`] thins only the former.
    pub fn corners_computed(&self) -> bool {
        self.corners_computed
    }
    /// Number of disjoint parts: one per outer loop.
    pub fn num_parts(&self) -> usize {
        self.loops
            .iter()
            .filter(|l| l.role == LoopRole::Outer)
            .count()
    }
    /// The region's parts as regions of one part each, in loop order, with the maps from
    /// each part's loop, piece and corner numbers to this region's. A region of one part
    /// gives itself.
    ///
    /// ```
    /// // Two unit squares side by side, the second with a hole; in a loop list, nesting
    /// // decides which loop is a hole.
    /// let text = "0 0\n1 0\n1 1\n0 1\n\n2 0\n3 0\n3 1\n2 1\n\n2.4 0.4\n2.6 0.4\n2.6 0.6\n2.4 0.6\n";
    /// let r = cvtmesh::geometry::formats::loops_from_str(text, "two", "two")?;
    /// assert_eq!(r.num_parts(), 2);
    /// let parts = r.parts();
    /// assert_eq!(parts[1].loops, vec![1, 2]);
    /// assert_eq!(parts[1].region.loops().len(), 2);
    /// assert!((parts[0].region.area() + parts[1].region.area() - r.area()).abs() < 1e-12);
    /// // Piece and corner numbers map back to the whole region's.
    /// let c = &parts[1].region.corners()[0];
    /// assert_eq!(r.corners()[parts[1].corners[0]].pos, c.pos);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn parts(&self) -> Vec<Part> {
        let outers: Vec<usize> = (0..self.loops.len())
            .filter(|&l| self.loops[l].role == LoopRole::Outer)
            .collect();
        if outers.len() <= 1 {
            return vec![Part {
                region: self.clone(),
                loops: (0..self.loops.len()).collect(),
                pieces: (0..self.pieces.len()).collect(),
                corners: (0..self.corners.len()).collect(),
            }];
        }
        outers
            .iter()
            .enumerate()
            .map(|(i, &o)| {
                let end = outers.get(i + 1).copied().unwrap_or(self.loops.len());
                let loops: Vec<usize> = (o..end).collect();
                let lps = loops
                    .iter()
                    .map(|&l| {
                        let lp = &self.loops[l];
                        (
                            lp.role,
                            lp.pieces.iter().map(|&p| self.pieces[p].clone()).collect(),
                        )
                    })
                    .collect();
                let flags: Vec<Vec<bool>> = loops
                    .iter()
                    .map(|&l| {
                        self.loops[l]
                            .pieces
                            .iter()
                            .map(|&p| self.corner_at_start[p].is_some())
                            .collect()
                    })
                    .collect();
                let mut region = crate::build::assemble(
                    format!("{} part {i}", self.name),
                    lps,
                    &flags,
                    self.corner_threshold,
                );
                region.corners_computed = self.corners_computed;
                region.embedded = self
                    .embedded
                    .iter()
                    .copied()
                    .filter(|&(p, _)| region.contains(p))
                    .collect();
                // A line lies in one part: the one holding its first segment's midpoint.
                region.lines = self
                    .lines
                    .iter()
                    .filter(|l| region.contains(0.5 * (l.points[0] + l.points[1])))
                    .cloned()
                    .collect();
                region.subdomains = self
                    .subdomains
                    .iter()
                    .copied()
                    .filter(|&(p, _)| region.contains(p))
                    .collect();
                region.subdomain_names = self.subdomain_names.clone();
                // Pieces and corners are numbered loop by loop, so a part's are a run of ours.
                let pieces = loops
                    .iter()
                    .flat_map(|&l| self.loops[l].pieces.iter().copied())
                    .collect();
                let corners = (0..self.corners.len())
                    .filter(|&c| loops.contains(&self.corners[c].loop_index))
                    .collect();
                Part {
                    region,
                    loops,
                    pieces,
                    corners,
                }
            })
            .collect()
    }
    /// Exact area |Ω| (analytic for circles, arcs, super-ellipses).
    pub fn area(&self) -> f64 {
        self.area
    }
    /// Bounding box (min, max).
    pub fn bbox(&self) -> (DVec2, DVec2) {
        self.bbox
    }
    /// The centres of the cells of an [`INSIDE_GRID`] × [`INSIDE_GRID`] grid over the bounding
    /// box that lie in Ω, row by row from the bottom (x fastest), and the area of one cell:
    /// where a size field is checked and integrated and a density averaged. One inside test per
    /// cell, made on first use and shared by the region's clones, since a graded mesh asks for
    /// it three or four times.
    ///
    /// ```
    /// use cvtmesh::geometry::Region;
    /// let disc = Region::builtin("circle")?;
    /// let (centres, cell) = disc.inside_grid();
    /// // The unit disc covers π/4 of its bounding box.
    /// let covered = centres.len() as f64 * cell;
    /// assert!((covered - std::f64::consts::PI).abs() < 0.01 * std::f64::consts::PI);
    /// assert!(centres.iter().all(|&p| disc.contains(p)));
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn inside_grid(&self) -> (&[DVec2], f64) {
        use rayon::prelude::*;
        let n = INSIDE_GRID;
        let (lo, hi) = self.bbox;
        let step = (hi - lo) / n as f64;
        let centres = self.inside_grid.0.get_or_init(|| {
            // Each a signed-distance query: in parallel, the order kept.
            (0..n * n)
                .into_par_iter()
                .map(|k| lo + step * DVec2::new((k % n) as f64 + 0.5, (k / n) as f64 + 0.5))
                .filter(|&p| self.contains(p))
                .collect()
        });
        (centres, step.x * step.y)
    }
    /// Length of the bounding box diagonal.
    pub fn diameter(&self) -> f64 {
        let (lo, hi) = self.bbox();
        (hi - lo).length()
    }
    /// Total boundary length.
    pub fn perimeter(&self) -> f64 {
        self.loops.iter().map(|l| l.length).sum()
    }
    /// True if `p` is in the closed region.
    pub fn contains(&self, p: DVec2) -> bool {
        self.signed_distance(p) <= 0.0
    }
    /// Signed distance to the boundary: negative inside, positive outside.
    ///
    /// The magnitude is the exact distance to the pieces (a bounding-volume hierarchy over
    /// segments and curves finds the nearest one); the sign comes from the side of the
    /// nearest piece, or at a vertex from the wedge of the two tangents, which is exact for
    /// every point off the boundary. NaN for a non-finite point.
    pub fn signed_distance(&self, p: DVec2) -> f64 {
        if !p.is_finite() {
            return f64::NAN;
        }
        let hit = self.index.nearest(&self.pieces, p);
        let d = hit.d2.sqrt();
        // Outside the bounding box the point is outside, however the nearest piece came out:
        // far away (10¹⁰⁰ spacings) every piece is as near as rounding can tell, and the side
        // of whichever won is no answer.
        let (lo, hi) = self.bbox;
        let boxed = p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
        if d == 0.0 {
            0.0
        } else if boxed && self.index.inside(&self.pieces, p, &hit) {
            -d
        } else {
            d
        }
    }
    /// Distance from `p` to the nearest of the pieces `keep` accepts (∞ if it accepts none),
    /// by the same hierarchy as [`Region::signed_distance`].
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    /// let r = Region::builtin("square_hole")?; // the square [-1, 1]², a hole of radius 0.4
    /// let hole: Vec<usize> = r.loops()[1].pieces.clone();
    /// let d = r.distance_where(DVec2::new(0.9, 0.0), |piece| hole.contains(&piece));
    /// assert!((d - 0.5).abs() < 1e-12);
    /// assert!((r.signed_distance(DVec2::new(0.9, 0.0)) + 0.1).abs() < 1e-12);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn distance_where(&self, p: DVec2, keep: impl Fn(PieceId) -> bool) -> f64 {
        self.index.nearest_where(&self.pieces, p, keep).d2.sqrt()
    }
    /// Nearest boundary point over all pieces.
    ///
    /// When the nearest point is within 1e-12·diameter of a corner, the corner is reported
    /// exactly: `point` is the corner, `piece` its `piece_out`, `loop_param` its `loop_param`.
    /// `loop_param` is always in [0, loop length).
    pub fn project(&self, p: DVec2) -> BoundaryPoint {
        let hit = self.index.nearest(&self.pieces, p);
        self.boundary_point(p, &hit, None)
    }
    /// Nearest point on one given piece (the "own piece" projection of CCVT step 5).
    /// A corner at either end of the piece is reported as in `project`, but `piece` stays
    /// the given one.
    ///
    /// # Panics
    /// If `piece` is not a valid piece id.
    pub fn project_onto_piece(&self, p: DVec2, piece: PieceId) -> BoundaryPoint {
        let hit = self.index.nearest_on_piece(&self.pieces, p, piece);
        self.boundary_point(p, &hit, Some(piece))
    }
    /// `project_onto_piece(p, piece).point` alone: the point without its loop parameter, which
    /// on a super-ellipse is an arc length by quadrature, several times the projection's own
    /// cost. The same point, a corner within 1e-12·diameter reported exactly.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    /// let r = Region::builtin("superellipse")?;
    /// let p = DVec2::new(0.9, 0.8);
    /// assert_eq!(r.project_point_onto_piece(p, 0), r.project_onto_piece(p, 0).point);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    ///
    /// # Panics
    /// If `piece` is not a valid piece id.
    pub fn project_point_onto_piece(&self, p: DVec2, piece: PieceId) -> DVec2 {
        let hit = self.index.nearest_on_piece(&self.pieces, p, piece);
        self.corner_at(piece, hit.point)
            .map_or(hit.point, |c| self.corners[c].pos)
    }
    /// The first interior vertex of a sampled piece (`Piece::Chain`) met going along piece
    /// `piece` from the nearest point of `a` to that of `b`, a vertex at `a`'s own nearest point
    /// included. The piece bends there, so the energy along it has a kink: a generator moved
    /// along its tangent must stop at the vertex. None for the other (smooth) pieces.
    ///
    /// # Panics
    /// If `piece` is not a valid piece id.
    pub fn chain_vertex_between(&self, a: DVec2, b: DVec2, piece: PieceId) -> Option<DVec2> {
        let Piece::Chain(pts) = &self.pieces[piece] else {
            return None;
        };
        // Chain parameters: segment index + t; vertex i is at parameter i.
        let param = |p| self.index.nearest_on_piece(&self.pieces, p, piece).aux;
        let (sa, sb) = (param(a), param(b));
        let interior = |i: f64| (i >= 1.0 && (i as usize) + 1 < pts.len()).then(|| pts[i as usize]);
        if (sa - sa.round()).abs() <= 1e-9 {
            return interior(sa.round());
        }
        if sb > sa && sa.ceil() < sb {
            interior(sa.ceil())
        } else if sb < sa && sa.floor() > sb {
            interior(sa.floor())
        } else {
            None
        }
    }
    /// Straight-edged approximation with chord error ≤ `tol`; corners are kept as vertices.
    ///
    /// Every piece junction is a vertex (so corners are exact vertices); `tol` is clamped
    /// below at 1e-12·diameter (a NaN or non-positive `tol` means that).
    pub fn polygonize(&self, tol: f64) -> Polygon {
        let tol = tol.max(1e-12 * self.diameter());
        let rings = self
            .loops
            .iter()
            .enumerate()
            .map(|(l, lp)| {
                let (mut points, mut pieces) = (Vec::new(), Vec::new());
                for &pid in &lp.pieces {
                    let pts = self.pieces[pid].polygonize(tol);
                    let k = pts.len().saturating_sub(1);
                    points.extend_from_slice(&pts[..k]);
                    pieces.extend(std::iter::repeat_n(pid, k));
                }
                Ring {
                    points,
                    pieces,
                    loop_index: l,
                    hole: lp.role == LoopRole::Hole,
                }
            })
            .collect();
        Polygon { rings }
    }

    /// The corner at an end of `piece` within 1e-12·diameter of its point `q`, if any.
    fn corner_at(&self, piece: PieceId, q: DVec2) -> Option<usize> {
        let tol = 1e-12 * self.diameter();
        [self.corner_at_start[piece], self.corner_at_end[piece]]
            .into_iter()
            .flatten()
            .find(|&c| self.corners[c].pos.distance(q) <= tol)
    }

    fn boundary_point(&self, p: DVec2, hit: &Hit, keep_piece: Option<PieceId>) -> BoundaryPoint {
        let el = &self.index.elems[hit.elem as usize];
        let mut piece = el.piece as usize;
        let loop_index = self.piece_loop[piece];
        let length = self.loops[loop_index].length;
        let mut point = hit.point;
        let mut loop_param = self.piece_offset[piece] + self.index.piece_param(&self.pieces, hit);
        let corner = self.corner_at(piece, hit.point);
        if let Some(c) = corner {
            let c = &self.corners[c];
            point = c.pos;
            loop_param = c.loop_param;
            piece = c.piece_out;
        }
        if let Some(k) = keep_piece {
            piece = k;
        }
        if loop_param >= length {
            loop_param -= length;
        }
        BoundaryPoint {
            point,
            distance: p.distance(point),
            piece,
            loop_index,
            loop_param: loop_param.clamp(0.0, length),
            corner,
        }
    }
}

/// One part of a region ([`Region::parts`]): a region of one outer loop and its holes, and
/// where its loops, pieces and corners are in the whole region.
#[derive(Clone, Debug)]
pub struct Part {
    /// The part as a region of its own (loop 0 its outer loop).
    pub region: Region,
    /// The whole region's number of each of the part's loops.
    pub loops: Vec<usize>,
    /// The whole region's id of each of the part's pieces.
    pub pieces: Vec<PieceId>,
    /// The whole region's number of each of the part's corners.
    pub corners: Vec<usize>,
}
