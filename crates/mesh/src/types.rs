use geometry::{DVec2, PieceId};

/// What a vertex is with respect to the region's boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VertexMarker {
    /// Strictly inside.
    Interior,
    /// On a boundary piece (not at a corner).
    Boundary {
        /// Loop index (0 = outer).
        loop_index: usize,
        /// Piece id.
        piece: PieceId,
        /// Arc-length position along the loop.
        loop_param: f64,
    },
    /// At a corner of the region.
    Corner {
        /// Loop index.
        loop_index: usize,
        /// Corner index in `Region::corners()`.
        corner: usize,
        /// Arc-length position along the loop.
        loop_param: f64,
    },
}

impl VertexMarker {
    /// The marker of a vertex sitting on corner `corner` of `region`.
    pub fn at_corner(region: &geometry::Region, corner: usize) -> VertexMarker {
        let c = &region.corners()[corner];
        VertexMarker::Corner {
            loop_index: c.loop_index,
            corner,
            loop_param: c.loop_param,
        }
    }

    /// The marker of a vertex at `p` on boundary piece `piece` (its loop and arc-length position
    /// come from the projection onto that piece).
    pub fn on_piece(region: &geometry::Region, p: DVec2, piece: PieceId) -> VertexMarker {
        let bp = region.project_onto_piece(p, piece);
        VertexMarker::Boundary {
            loop_index: bp.loop_index,
            piece,
            loop_param: bp.loop_param,
        }
    }

    /// True for boundary and corner vertices.
    pub fn on_boundary(&self) -> bool {
        !matches!(self, VertexMarker::Interior)
    }
    /// Loop index of a boundary or corner vertex.
    pub fn loop_index(&self) -> Option<usize> {
        match *self {
            VertexMarker::Interior => None,
            VertexMarker::Boundary { loop_index, .. } | VertexMarker::Corner { loop_index, .. } => {
                Some(loop_index)
            }
        }
    }
    /// Arc-length position of a boundary or corner vertex.
    pub fn loop_param(&self) -> Option<f64> {
        match *self {
            VertexMarker::Interior => None,
            VertexMarker::Boundary { loop_param, .. } | VertexMarker::Corner { loop_param, .. } => {
                Some(loop_param)
            }
        }
    }
}

/// A triangle mesh: vertices, CCW triangles, and a boundary marker per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex coordinates (the generators, for CVT methods).
    pub points: Vec<DVec2>,
    /// Triangles as CCW vertex index triples.
    pub triangles: Vec<[u32; 3]>,
    /// One marker per vertex.
    pub markers: Vec<VertexMarker>,
}

impl Mesh {
    /// K, the number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.points.len()
    }
    /// K̃, the number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.triangles.len()
    }
    /// The three corner points of triangle `t`.
    pub fn triangle(&self, t: usize) -> [DVec2; 3] {
        let [a, b, c] = self.triangles[t];
        [
            self.points[a as usize],
            self.points[b as usize],
            self.points[c as usize],
        ]
    }
    /// Sum of triangle areas.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.triangle(t);
                0.5 * (b - a).perp_dot(c - a)
            })
            .sum()
    }
    /// Smallest interior angle over all triangles, in degrees.
    pub fn min_angle_deg(&self) -> f64 {
        let mut m = f64::INFINITY;
        for t in 0..self.triangles.len() {
            let p = self.triangle(t);
            for i in 0..3 {
                let (u, v) = (p[(i + 1) % 3] - p[i], p[(i + 2) % 3] - p[i]);
                m = m.min(u.angle_to(v).abs().to_degrees());
            }
        }
        m
    }
}
