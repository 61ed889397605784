//! Subdomains: the parts of a region its embedded lines cut it into (the materials of a
//! laminate, an inclusion), each numbered by a point inside it, as Triangle's regional
//! attributes number them and Gmsh's physical surfaces name them.
use crate::predicates::closest_on_segment;
use crate::region::Region;
use glam::DVec2;

impl Region {
    /// The points that number the region's subdomains, each with its number: every triangle
    /// of a mesh that the region's embedded lines, walls and holes do not separate from the
    /// point gets that number (`cvtmesh::subdomains`), as Triangle's `-A` spreads a regional
    /// attribute. Where two points lie in one subdomain the later one's number is kept, as in
    /// Triangle. Empty for most regions.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    /// let square = Region::builtin("square_hole")?;
    /// let r = square.with_subdomain_points([(DVec2::new(0.8, 0.8), 3)])?;
    /// assert_eq!(r.subdomain_points(), &[(DVec2::new(0.8, 0.8), 3)]);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn subdomain_points(&self) -> &[(DVec2, i64)] {
        &self.subdomains
    }

    /// The name of a subdomain number, where the region's file gives one (a Gmsh physical
    /// surface's name, a JSON subdomain's `"name"`): the `.msh` files written for its meshes
    /// name the physical surface so (else `subdomain<N>`).
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, Region};
    /// let r = Region::builtin("circle")?
    ///     .with_subdomain_points([(DVec2::ZERO, 10)])?
    ///     .with_subdomain_names([(10, "steel".to_string())]);
    /// assert_eq!((r.subdomain_name(10), r.subdomain_name(11)), (Some("steel"), None));
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn subdomain_name(&self, id: i64) -> Option<&str> {
        self.subdomain_names.get(&id).map(String::as_str)
    }

    /// Every subdomain number's name ([`Region::subdomain_name`]), by number.
    pub fn subdomain_names(&self) -> &std::collections::BTreeMap<i64, String> {
        &self.subdomain_names
    }

    /// The same region with names for subdomain numbers ([`Region::subdomain_name`]).
    pub fn with_subdomain_names(
        mut self,
        names: impl IntoIterator<Item = (i64, String)>,
    ) -> Region {
        self.subdomain_names.extend(names);
        self
    }

    /// The same region with `points` numbering its subdomains as well
    /// ([`Region::subdomain_points`]). Each must be finite and inside the region, off its
    /// boundary and its embedded lines by more than 10⁻⁹ of its diameter (on a line, it would
    /// number both sides), and its number within the 32-bit range of Triangle's attributes and
    /// Gmsh's physical tags.
    ///
    /// ```
    /// use cvtmesh::geometry::{DVec2, EmbeddedLine, Region};
    /// let line = EmbeddedLine { points: vec![DVec2::new(0.0, -0.5), DVec2::new(0.0, 0.5)], marker: 0 };
    /// let disc = Region::builtin("circle")?.with_embedded_lines([line])?;
    /// // A point on the line, or outside, is refused by name.
    /// let e = disc.clone().with_subdomain_points([(DVec2::new(0.0, 0.5), 1)]);
    /// assert!(e.unwrap_err().to_string().contains("on an embedded line"));
    /// let e = disc.with_subdomain_points([(DVec2::new(2.0, 0.0), 1)]);
    /// assert!(e.unwrap_err().to_string().contains("outside the region"));
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn with_subdomain_points(
        mut self,
        points: impl IntoIterator<Item = (DVec2, i64)>,
    ) -> Result<Region, crate::GeometryError> {
        let off = 1e-9 * self.diameter();
        for (p, id) in points {
            let refuse = |what: String| crate::GeometryError::Invalid {
                region: self.name.clone(),
                message: format!("the subdomain point ({}, {}) {what}", p.x, p.y),
            };
            let sd = self.signed_distance(p);
            if !p.is_finite() || sd.is_nan() || sd > off {
                return Err(refuse("lies outside the region".into()));
            }
            if sd > -off {
                return Err(refuse("lies on the region's boundary".into()));
            }
            let on_line = self.lines.iter().any(|l| {
                l.segments()
                    .any(|(a, b)| closest_on_segment(a, b, p).2 <= off * off)
            });
            if on_line {
                return Err(refuse(
                    "lies on an embedded line, which parts two subdomains".into(),
                ));
            }
            if i32::try_from(id).is_err() {
                return Err(refuse(format!(
                    "has the number {id}, outside the 32-bit range of Triangle's attributes \
                     and Gmsh's physical tags"
                )));
            }
            self.subdomains.push((p, id));
        }
        Ok(self)
    }
}
