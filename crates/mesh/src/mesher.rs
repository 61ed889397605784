use crate::{Mesh, MeshError};
use geometry::{DVec2, Density, Region, SizeField};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The most vertices a request may ask for. A CCVT mesh of 10⁶ vertices peaks below 1 GiB, so
/// this many would need about 45 GiB: a request above it is a mistake in the size (a unit, an
/// exponent), refused by [`MeshRequest::validate`] before any work.
pub const MAX_POINTS: usize = 50_000_000;

/// The boundary tolerance of an automatic simplification, in spacings
/// ([`MeshRequest::simplify_tolerance`]): a quarter of the local spacing. A rough coastline
/// simplified to a tenth kept nearly every vertex left as a corner (941 of 958 at K = 1000,
/// for 8000 given); at a quarter it keeps 399, about one per spacing along the shore, which is
/// what a mesh of this size can follow.
pub const SIMPLIFY_SPACINGS: f64 = 0.25;

/// How fine the mesh should be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Size {
    /// K, the number of vertices (generators).
    Points(usize),
    /// A target edge length h; K is derived as the hexagonal-lattice count for |Ω|.
    EdgeLength(f64),
}

impl Size {
    /// The vertex count requested for `region`: for an edge length h, K = 2|Ω| / (√3 h²).
    pub fn points(&self, region: &Region) -> usize {
        match *self {
            Size::Points(k) => k,
            Size::EdgeLength(h) => (2.0 * region.area() / (3f64.sqrt() * h * h)).round() as usize,
        }
    }
}

/// What every method is asked for. Defaults: seed 1, tolerance 1e-4, at most 10 000
/// iterations (Lloyd-type methods converge linearly; CCVT applies the cap per phase), ρ ≡ 1.
///
/// Build one with [`MeshRequest::points`] or [`MeshRequest::edge_length`] and the builder
/// methods; [`MeshRequest::validate`] refuses what no method can do, before any work is done:
///
/// ```
/// use cvtmesh::{MeshError, MeshRequest};
/// use cvtmesh::geometry::Region;
///
/// let circle = Region::builtin("circle")?; // radius 1
/// let request = MeshRequest::points(500).seed(7).tol(1e-5).max_iter(200);
/// assert_eq!((request.seed, request.tol, request.max_iter), (7, 1e-5, 200));
/// assert_eq!(request.validate(&circle)?, 500);
///
/// // An edge length gives K from the region's area; the mean spacing comes back close to it.
/// let by_size = MeshRequest::edge_length(0.1);
/// let k = by_size.validate(&circle)?;
/// assert!((350..380).contains(&k));
/// assert!((by_size.spacing(&circle) - 0.1).abs() < 1e-3);
///
/// // Refused: a tolerance of 0 (never met), and a size too coarse for the region.
/// let e = request.clone().tol(0.0).validate(&circle).unwrap_err();
/// assert!(matches!(e, MeshError::InvalidTolerance(_)));
/// let e = MeshRequest::edge_length(5.0).validate(&circle).unwrap_err();
/// assert!(matches!(e, MeshError::TooFewPoints { needed: 3, .. }));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct MeshRequest {
    /// Target size.
    pub size: Size,
    /// Seed of every random choice.
    pub seed: u64,
    /// Convergence tolerance, relative to the mean generator spacing (CCVT measures each
    /// generator's move against the local spacing its density asks for, which is the mean
    /// spacing for ρ ≡ 1).
    pub tol: f64,
    /// Iteration cap of each phase of a method that runs several (CCVT's Algorithm 2: its
    /// ε-phases, then the constrained one; [`MeshResult::iterations`] is their sum); hitting it
    /// is reported as not converged.
    pub max_iter: usize,
    /// Density ρ.
    pub density: Density,
    /// Set from another thread (a Ctrl-C handler, a progress callback, a user interface) to
    /// stop a run: every method checks it once per iteration and then returns
    /// [`MeshError::Cancelled`].
    pub cancel: Option<Arc<AtomicBool>>,
    /// When to stop iterating: every method checks it where it checks the iteration cap, and
    /// a run that reaches it hands back its mesh marked not converged (CCVT finishes each of
    /// its phases with one step more, so the mesh conforms).
    pub deadline: Option<Instant>,
    /// Polish after meshing ([`crate::polish`]): the vertices of triangles with an angle below
    /// this many degrees (corners excepted) move to raise the smallest angle around them.
    /// [`Mesher::mesh_parts`] applies it; 0 turns it off (the study's methods run without).
    /// Default [`POLISH_BELOW_DEG`](crate::POLISH_BELOW_DEG).
    pub polish_below_deg: f64,
}

/// [`MeshRequest::bounded_size_field`] notes a gradation limit that raised the field's vertex
/// count by more than this factor.
pub const GRADATION_NOTE: f64 = 1.1;

impl MeshRequest {
    /// A request for K points with the documented defaults.
    pub fn points(k: usize) -> Self {
        MeshRequest {
            size: Size::Points(k),
            seed: 1,
            tol: 1e-4,
            max_iter: 10_000,
            density: Density::Uniform,
            cancel: None,
            deadline: None,
            polish_below_deg: crate::POLISH_BELOW_DEG,
        }
    }
    /// A request for a target edge length `h` (K from the region's area, see
    /// [`Size::EdgeLength`]) with the documented defaults.
    pub fn edge_length(h: f64) -> Self {
        MeshRequest {
            size: Size::EdgeLength(h),
            ..MeshRequest::points(0)
        }
    }
    /// A request for a graded mesh whose edge lengths follow `field`: the CVT density
    /// ρ = (h_min / h)⁴ (uniform for a constant field), and `points` vertices, or when `None`
    /// the count the field asks for, (2/√3) ∫_Ω h⁻² dx. The field is checked first: positive
    /// and finite on the region ([`MeshError::SizeField`]), and asking for no more than
    /// [`MAX_POINTS`] vertices ([`MeshError::FieldTooFine`]). The field is used as given: the
    /// command line and Python limit its gradient to 0.3 first unless told otherwise, which
    /// here is [`SizeField::bounded`](geometry::SizeField::bounded)'s to do.
    ///
    /// ```
    /// use cvtmesh::geometry::{Region, SizeField};
    /// use cvtmesh::{MeshError, MeshRequest};
    ///
    /// let circle = Region::builtin("circle")?;
    /// let h = SizeField::from_expr("0.05 * (2 + x)")?;
    /// let request = MeshRequest::size_field(&h, &circle, None)?;
    /// let k = request.validate(&circle)?;
    /// assert!((k as f64 - h.predicted_points(&circle)).abs() <= 0.5);
    /// // Spacing ∝ ρ^(-1/4): where h is 5/3 as large, ρ is (5/3)⁴ as small (ρ is sampled on
    /// // the field's grid and interpolated, hence the tolerance).
    /// let rho = |x: f64| request.density.at(cvtmesh::geometry::DVec2::new(x, 0.0));
    /// assert!((rho(-0.5) / rho(0.5) / (5.0f64 / 3.0).powi(4) - 1.0).abs() < 1e-3);
    /// // A field that is not positive on the region is refused before any work.
    /// let bad = SizeField::from_expr("x")?;
    /// assert!(matches!(MeshRequest::size_field(&bad, &circle, None), Err(MeshError::SizeField(_))));
    /// // So is one asking for more vertices than fit in memory, with the count it asks for.
    /// let fine = SizeField::constant(1e-12);
    /// let e = MeshRequest::size_field(&fine, &circle, None).unwrap_err();
    /// assert!(matches!(e, MeshError::FieldTooFine { predicted, .. } if predicted > 3.6e24));
    /// assert!(e.to_string().contains("asks for about 3.628e24 vertices"), "{e}");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn size_field(
        field: &SizeField,
        region: &Region,
        points: Option<usize>,
    ) -> Result<Self, MeshError> {
        let range = field.check(region)?;
        let k = match points {
            Some(k) => {
                if !field.is_constant() {
                    refuse_unresolved_boundary(field, region, k, range)?;
                }
                k
            }
            None => {
                let predicted = field.predicted_points(region);
                if !(predicted.is_finite() && predicted <= MAX_POINTS as f64) {
                    return Err(MeshError::FieldTooFine {
                        predicted,
                        smallest: range.min,
                        max: MAX_POINTS,
                    });
                }
                // A field coarser than the region: say so in its terms, not as too few points.
                let needed = boundary_points_needed(region);
                if predicted.round() < needed as f64 {
                    return Err(MeshError::BadRequest(format!(
                        "the size field asks for {predicted:.2} vertices (its sizes from {:.3e} \
                         on a region {:.3e} across), fewer than the {needed} the region's boundary \
                         needs at the coarsest: smaller sizes, or a vertex count (n, --points), \
                         would mesh it",
                        range.min,
                        region.diameter()
                    )));
                }
                predicted.round() as usize
            }
        };
        // The density is evaluated dozens of times per cell and iteration: sample the field once.
        let field = field.on_grid(region, range.min);
        Ok(MeshRequest::points(k).density(field.density(range.min)))
    }
    /// [`MeshRequest::size_field`] of `field` bounded as the command line and Python bound it
    /// ([`SizeField::bounded`](geometry::SizeField::bounded): sizes clamped to `min` and
    /// `max`, their gradient limited to `gradation`), and the bounded field sampled on the grid
    /// the methods mesh from, and a note for the user where the gradation limit raised the
    /// field's vertex count by more than 10 %. `min` and `max` are edge lengths the mesh keeps,
    /// as Gmsh's `Mesh.MeshSizeMin` and `Mesh.MeshSizeMax` are: with `points` given, which
    /// scales the field to that many vertices and so would move them, they are refused.
    ///
    /// ```
    /// use cvtmesh::geometry::{Region, SizeField};
    /// use cvtmesh::MeshRequest;
    ///
    /// let circle = Region::builtin("circle")?;
    /// let h = SizeField::from_expr("0.01 + 0.2 * abs(x)")?;
    /// let (request, bounded, note) = MeshRequest::bounded_size_field(&h, &circle, Some(0.02), Some(0.1), Some(0.3), None)?;
    /// assert!((bounded.at(cvtmesh::geometry::DVec2::ZERO) - 0.02).abs() < 1e-9);
    /// assert_eq!(request.validate(&circle)?, bounded.predicted_points(&circle).round() as usize);
    /// assert!(note.is_none());
    /// // Sizes that grow by 0.5 per unit of distance, limited to 0.3: many more vertices.
    /// let steep = SizeField::from_expr("0.005 + 0.5*abs(x)")?;
    /// let (_, _, note) = MeshRequest::bounded_size_field(&steep, &circle, None, None, Some(0.3), None)?;
    /// assert!(note.unwrap().contains("the gradation limit 0.3"));
    /// let e = MeshRequest::bounded_size_field(&h, &circle, None, Some(0.1), None, Some(500)).unwrap_err();
    /// assert!(e.to_string().contains("--size-max"), "{e}");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn bounded_size_field(
        field: &SizeField,
        region: &Region,
        min: Option<f64>,
        max: Option<f64>,
        gradation: Option<f64>,
        points: Option<usize>,
    ) -> Result<(Self, SizeField, Option<String>), MeshError> {
        if let (Some(k), true) = (points, min.is_some() || max.is_some()) {
            let which = match (min, max) {
                (Some(_), Some(_)) => {
                    "size_min and size_max (--size-min, --size-max) are edge lengths"
                }
                (Some(_), None) => "size_min (--size-min) is an edge length",
                _ => "size_max (--size-max) is an edge length",
            };
            return Err(MeshError::BadRequest(format!(
                "{which} the mesh keeps, but with K = {k} vertices given the field is scaled to \
                 K and would not keep it: give the bounds or K, not both"
            )));
        }
        let (field, before) = field.bounded_counted(region, min, max, gradation)?;
        // The grid the methods mesh from, sampled once for the request and for the caller's
        // check of what it resolves.
        let field = field.on_grid(region, field.check(region)?.min);
        let after = field.predicted_points(region);
        // A Gmsh user's field is taken as given there: say when the limit made it much finer.
        let note = before.filter(|&b| after > GRADATION_NOTE * b).map(|b| {
            format!(
                "the gradation limit {} (sizes growing by at most that much per unit of \
                 distance) raised the field's vertex count from {b:.0} to {after:.0} (+{:.0} %); \
                 gradation inf (--gradation inf) takes the field as given",
                gradation.unwrap_or(f64::INFINITY),
                100.0 * (after / b - 1.0)
            )
        });
        Ok((Self::size_field(&field, region, points)?, field, note))
    }
    /// Builder: seed.
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }
    /// Builder: tolerance.
    pub fn tol(mut self, tol: f64) -> Self {
        self.tol = tol;
        self
    }
    /// Builder: iteration cap.
    pub fn max_iter(mut self, n: usize) -> Self {
        self.max_iter = n;
        self
    }
    /// Builder: the polish threshold in degrees ([`MeshRequest::polish_below_deg`]; 0 turns
    /// polishing off).
    ///
    /// ```
    /// use cvtmesh::{MeshError, MeshRequest};
    /// let circle = cvtmesh::geometry::Region::builtin("circle")?;
    /// assert!(MeshRequest::points(100).polish(0.0).validate(&circle).is_ok());
    /// let e = MeshRequest::points(100).polish(75.0).validate(&circle).unwrap_err();
    /// assert!(matches!(e, MeshError::InvalidPolish(_)));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn polish(mut self, below_deg: f64) -> Self {
        self.polish_below_deg = below_deg;
        self
    }
    /// Builder: density.
    pub fn density(mut self, d: Density) -> Self {
        self.density = d;
        self
    }
    /// Builder: a flag that stops the run when set (see [`MeshRequest::cancel`]).
    ///
    /// ```
    /// use cvtmesh::{MeshError, MeshRequest, Mesher};
    /// use std::sync::{atomic::{AtomicBool, Ordering}, Arc};
    /// # struct Count;
    /// # impl Mesher for Count {
    /// #     fn name(&self) -> &'static str { "count" }
    /// #     fn mesh(&self, _: &cvtmesh::geometry::Region, r: &MeshRequest, p: &mut dyn FnMut(cvtmesh::Progress))
    /// #         -> Result<cvtmesh::MeshResult, MeshError> {
    /// #         for iteration in 1.. {
    /// #             p(cvtmesh::Progress { iteration, max_iter: r.max_iter, energy: f64::NAN, max_move: 1.0 });
    /// #             r.check_cancel(self.name(), iteration)?;
    /// #         }
    /// #         unreachable!()
    /// #     }
    /// # }
    /// let stop = Arc::new(AtomicBool::new(false));
    /// let request = MeshRequest::points(100).cancel_flag(stop.clone());
    /// let region = cvtmesh::geometry::Region::builtin("circle")?;
    /// // Stop at the third progress report.
    /// let e = Count
    ///     .mesh(&region, &request, &mut |p| stop.store(p.iteration == 3, Ordering::Relaxed))
    ///     .unwrap_err();
    /// assert!(matches!(e, MeshError::Cancelled { iterations: 3, .. }));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn cancel_flag(mut self, flag: Arc<AtomicBool>) -> Self {
        self.cancel = Some(flag);
        self
    }
    /// Builder: stop iterating `limit` from now (see [`MeshRequest::deadline`]).
    ///
    /// ```
    /// use cvtmesh::MeshRequest;
    /// use std::time::Duration;
    /// let request = MeshRequest::points(100).time_limit(Duration::ZERO);
    /// assert!(request.out_of_time());
    /// assert!(!MeshRequest::points(100).out_of_time());
    /// ```
    pub fn time_limit(mut self, limit: Duration) -> Self {
        self.deadline = Instant::now().checked_add(limit);
        self
    }
    /// Builder: stop after `seconds` of wall time, as [`MeshRequest::time_limit`] does; a
    /// limit beyond any clock (1e308, infinity) is no limit. NaN or a negative number is
    /// [`MeshError::InvalidTimeLimit`].
    ///
    /// ```
    /// use cvtmesh::{MeshError, MeshRequest};
    /// assert!(MeshRequest::points(100).time_limit_secs(0.0)?.out_of_time());
    /// assert!(!MeshRequest::points(100).time_limit_secs(1e308)?.out_of_time());
    /// assert!(matches!(
    ///     MeshRequest::points(100).time_limit_secs(f64::NAN),
    ///     Err(MeshError::InvalidTimeLimit(_))
    /// ));
    /// # Ok::<(), MeshError>(())
    /// ```
    pub fn time_limit_secs(self, seconds: f64) -> Result<Self, MeshError> {
        if seconds.is_nan() || seconds < 0.0 {
            return Err(MeshError::InvalidTimeLimit(seconds));
        }
        Ok(match Duration::try_from_secs_f64(seconds) {
            Ok(limit) => self.time_limit(limit),
            Err(_) => self,
        })
    }
    /// True once the deadline has passed.
    pub fn out_of_time(&self) -> bool {
        self.deadline.is_some_and(|d| Instant::now() >= d)
    }
    /// True once the cancel flag is set.
    pub fn cancelled(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
    }
    /// `Err(MeshError::Cancelled)` once the cancel flag is set: what a method calls after
    /// each iteration.
    pub fn check_cancel(&self, method: &str, iterations: usize) -> Result<(), MeshError> {
        if self.cancelled() {
            return Err(MeshError::Cancelled {
                method: method.to_string(),
                iterations,
            });
        }
        Ok(())
    }
    /// Check the request against `region` before any work is done, and return K.
    ///
    /// Refused, in this order: an edge length that is not a positive finite number
    /// ([`MeshError::InvalidEdgeLength`]); K below [`boundary_points_needed`], a vertex on every
    /// corner and at least three on every boundary loop ([`MeshError::TooFewPoints`]); K above
    /// [`MAX_POINTS`] ([`MeshError::TooManyPoints`]); K whose memory estimate exceeds the
    /// machine's ([`MeshError::TooMuchMemory`], see [`memory_estimate`]); a tolerance that
    /// is not a positive finite number ([`MeshError::InvalidTolerance`]); an iteration cap of 0
    /// ([`MeshError::ZeroMaxIter`]); a polish threshold outside 0–60°
    /// ([`MeshError::InvalidPolish`]); a density that is negative or not finite
    /// ([`MeshError::InvalidDensity`], naming the first such point in the order of
    /// [`Region::inside_grid`]) or zero ([`MeshError::ZeroDensity`]) at every centre of the
    /// region's inside grid ([`geometry::INSIDE_GRID`]² cells over its bounding box); a region of
    /// several parts ([`MeshError::SeveralParts`]: [`Mesher::mesh_parts`] meshes those). Every
    /// method calls this first.
    pub fn validate(&self, region: &Region) -> Result<usize, MeshError> {
        let k = self.validate_whole(region)?;
        if region.num_parts() > 1 {
            return Err(MeshError::SeveralParts {
                region: region.name().to_string(),
                parts: region.num_parts(),
            });
        }
        Ok(k)
    }

    /// [`MeshRequest::validate`] without the refusal of several parts: the checks that hold
    /// for the whole region, as [`Mesher::mesh_parts`] makes them before splitting it. K is
    /// the total over the parts.
    pub fn validate_whole(&self, region: &Region) -> Result<usize, MeshError> {
        let edge_length = match self.size {
            Size::EdgeLength(h) if !(h.is_finite() && h > 0.0) => {
                return Err(MeshError::InvalidEdgeLength(h))
            }
            Size::EdgeLength(h) => Some(h),
            Size::Points(_) => None,
        };
        let k = self.size.points(region);
        let (corners, loops) = (region.corners().len(), region.loops().len());
        let embedded = region.embedded_points().len();
        let needed = boundary_points_needed(region) + embedded;
        if k < needed {
            return Err(MeshError::TooFewPoints {
                region: region.name().to_string(),
                requested: k,
                needed,
                corners,
                embedded,
                loops,
                edge_length,
            });
        }
        if k > MAX_POINTS {
            return Err(MeshError::TooManyPoints {
                requested: k,
                max: MAX_POINTS,
            });
        }
        check_memory(k, total_memory())?;
        if !(self.tol.is_finite() && self.tol > 0.0) {
            return Err(MeshError::InvalidTolerance(self.tol));
        }
        if self.max_iter == 0 {
            return Err(MeshError::ZeroMaxIter);
        }
        if !(0.0..=60.0).contains(&self.polish_below_deg) {
            return Err(MeshError::InvalidPolish(self.polish_below_deg));
        }
        check_density(&self.density, region)?;
        Ok(k)
    }

    /// Mean spacing of K generators on |Ω|: the hexagonal-lattice edge √(2|Ω| / (√3 K)).
    pub fn spacing(&self, region: &Region) -> f64 {
        let k = self.size.points(region).max(1) as f64;
        (2.0 * region.area() / (3f64.sqrt() * k)).sqrt()
    }

    /// Local spacing: [`MeshRequest::spacing`] where the density is uniform; for a graded
    /// request, the mean spacing × (ρ̄ / ρ(x))^(1/4), ρ̄^(1/2) the mean of ρ^(1/2) over the
    /// region (spacing ∝ ρ^(-1/4), and K ∝ ∫ ρ^(1/2)).
    ///
    /// ```
    /// use cvtmesh::MeshRequest;
    /// use cvtmesh::geometry::{DVec2, Density, Region};
    /// use std::sync::Arc;
    /// let region = Region::builtin("square_hole")?;
    /// let uniform = MeshRequest::points(1000);
    /// let h = uniform.spacing(&region);
    /// assert_eq!(uniform.spacing_at(&region)(DVec2::ZERO), h);
    /// // ρ 16 times larger on the right half: spacing half as large there as on the left.
    /// let graded = uniform.density(Density::Function(Arc::new(|p: DVec2| if p.x > 0.0 { 16.0 } else { 1.0 })));
    /// let at = graded.spacing_at(&region);
    /// let (left, right) = (at(DVec2::new(-0.5, 0.0)), at(DVec2::new(0.5, 0.0)));
    /// assert!((left / right - 2.0).abs() < 1e-9);
    /// assert!(right < h && h < left);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn spacing_at<'a>(&'a self, region: &Region) -> impl Fn(DVec2) -> f64 + 'a {
        let mean_spacing = self.spacing(region);
        let graded = !self.density.is_uniform();
        let mean_root = if graded {
            crate::parts::weight(region, &self.density) / region.area()
        } else {
            1.0
        };
        move |p: DVec2| {
            if graded {
                let root = self.density.at(p).max(1e-300).sqrt();
                mean_spacing * (mean_root / root).sqrt()
            } else {
                mean_spacing
            }
        }
    }

    /// The tolerance to simplify `region`'s boundary to for this request
    /// ([`Region::simplified`]): [`SIMPLIFY_SPACINGS`] of the smallest spacing the request
    /// asks for along the boundary (the spacing itself for a uniform mesh).
    ///
    /// ```
    /// use cvtmesh::{MeshRequest, SIMPLIFY_SPACINGS};
    /// use cvtmesh::geometry::Region;
    /// let region = Region::builtin("square_hole")?;
    /// let request = MeshRequest::points(1000);
    /// let tol = request.simplify_tolerance(&region);
    /// assert!((tol - SIMPLIFY_SPACINGS * request.spacing(&region)).abs() < 1e-15);
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn simplify_tolerance(&self, region: &Region) -> f64 {
        let spacing = self.spacing_at(region);
        let smallest = if self.density.is_uniform() {
            spacing(DVec2::ZERO)
        } else {
            region
                .polygonize(1e-4 * region.diameter())
                .rings
                .iter()
                .flat_map(|r| r.points.iter())
                .map(|&p| spacing(p))
                .fold(f64::INFINITY, f64::min)
        };
        SIMPLIFY_SPACINGS * smallest
    }
}

/// The fewest vertices a mesh of `region` can have: one on every corner, and at least three on
/// every boundary loop (a loop with fewer corners needs boundary vertices besides them).
///
/// ```
/// use cvtmesh::boundary_points_needed;
/// use cvtmesh::geometry::Region;
/// // The disc: three on its circle; the square with a round hole: its 4 corners and three on
/// // the hole; the hexagon with a hexagonal hole: its 12 corners.
/// assert_eq!(boundary_points_needed(&Region::builtin("circle")?), 3);
/// assert_eq!(boundary_points_needed(&Region::builtin("square_hole")?), 7);
/// assert_eq!(boundary_points_needed(&Region::builtin("hex_hole")?), 12);
/// # Ok::<(), cvtmesh::geometry::GeometryError>(())
/// ```
pub fn boundary_points_needed(region: &Region) -> usize {
    let mut per_loop = vec![0usize; region.loops().len()];
    for c in region.corners() {
        per_loop[c.loop_index] += 1;
    }
    per_loop.into_iter().map(|c| c.max(3)).sum()
}

/// The share of the region that a field scaled to K may be predicted to leave out along its
/// curved boundary before [`MeshRequest::size_field`] refuses K. The prediction runs about 1.5×
/// the share a CCVT mesh leaves out (the disc at 20 vertices, sizes 1:10 from its centre: 11 %
/// predicted, 7.2 % left out), so this refuses what would be a mesh over less than about 80 %
/// of the region, which is no longer a coarse mesh but a distorted one, and lets coarse meshes
/// through to the warning every mesh under 90 % gets.
const UNRESOLVED_LOSS: f64 = 0.3;

/// Refuse `k` vertices for `field` where the field scaled to `k` would give the boundary
/// edges far too long for its curvature (a field whose sizes span 10⁵, scaled to 1000
/// vertices on the disc, leaves DistMesh a mesh over two thirds of it, nearly every triangle
/// a sliver), naming the K that keeps the boundary to the
/// [`MIN_COVERAGE`](crate::check::MIN_COVERAGE) of a coarse mesh.
///
/// A chord of length h across a boundary arc of radius R leaves out h³ / (12 R), so an arc
/// whose tangent turns by θ loses about θ h² / 12 where its vertices lie h apart: summed over
/// the convex turns of the boundary polygon away from corners (which are vertices), with h the
/// field scaled by √(N / k), N the field's own count.
fn refuse_unresolved_boundary(
    field: &SizeField,
    region: &Region,
    k: usize,
    range: geometry::SizeRange,
) -> Result<(), MeshError> {
    let predicted = field.predicted_points(region);
    if !(predicted.is_finite() && predicted > 0.0 && k > 0) {
        return Ok(());
    }
    let scale = (predicted / k as f64).sqrt();
    let corners: std::collections::HashSet<(u64, u64)> = region
        .corners()
        .iter()
        .map(|c| (c.pos.x.to_bits(), c.pos.y.to_bits()))
        .collect();
    let mut lost = 0.0;
    for ring in region.polygonize(1e-3 * region.diameter()).rings {
        let n = ring.points.len();
        for i in 0..n {
            let (a, p, b) = (
                ring.points[(i + n - 1) % n],
                ring.points[i],
                ring.points[(i + 1) % n],
            );
            if corners.contains(&(p.x.to_bits(), p.y.to_bits())) {
                continue;
            }
            let turn = (p - a).perp_dot(b - p).atan2((p - a).dot(b - p));
            if turn > 0.0 {
                lost += turn * (scale * field.at(p)).powi(2) / 12.0;
            }
        }
    }
    if lost.is_nan() || lost <= UNRESOLVED_LOSS * region.area() {
        return Ok(());
    }
    let allowed = (1.0 - crate::check::MIN_COVERAGE) * region.area();
    let needed = (k as f64 * lost / allowed).ceil();
    let instead = if needed <= predicted {
        format!(
            "; or leave the count out (the field asks for {predicted:.0}) and bound the field \
             (size_max, --size-max)"
        )
    } else {
        String::new()
    };
    Err(MeshError::BadRequest(format!(
        "K = {k} vertices are too few for this size field: scaled to K, its sizes run from \
         {:.3e} to {:.3e} (a ratio of {:.3e}), and the boundary edges they give are too long for \
         the boundary's curvature, leaving out about {} of the region; K >= {needed:.0} keeps \
         the boundary{instead}",
        scale * range.min,
        scale * range.max,
        range.max / range.min,
        if lost >= region.area() {
            "all".to_string()
        } else {
            format!("{:.0} %", 100.0 * lost / region.area())
        },
    )))
}

/// Refuse a region with embedded points ([`Region::embedded_points`]) or lines
/// ([`Region::embedded_lines`]) for a method that cannot keep them as vertices and edges
/// (`method` names it in the error).
///
/// ```
/// use cvtmesh::geometry::{DVec2, Region};
/// let r = Region::builtin("circle")?.with_embedded_points([(DVec2::new(0.2, 0.0), 0)])?;
/// let e = cvtmesh::refuse_embedded(&r, "meshgen").unwrap_err().to_string();
/// assert!(e.contains("meshgen") && e.contains("embeds 1 point"), "{e}");
/// assert!(cvtmesh::refuse_embedded(&Region::builtin("circle")?, "meshgen").is_ok());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn refuse_embedded(region: &Region, method: &str) -> Result<(), MeshError> {
    let lines = region.embedded_lines().len();
    if lines > 0 {
        return Err(MeshError::BadRequest(format!(
            "{method} cannot keep lines inside a region as edges, and region '{}' embeds {lines} \
             line{}; use ccvt (the default), refine or distmesh",
            region.name(),
            if lines == 1 { "" } else { "s" }
        )));
    }
    match region.embedded_points().len() {
        0 => Ok(()),
        n => Err(MeshError::BadRequest(format!(
            "{method} cannot keep points inside a region as vertices, and region '{}' embeds \
             {n} point{}; use ccvt (the default), refine or distmesh",
            region.name(),
            if n == 1 { "" } else { "s" }
        ))),
    }
}

/// Peak bytes per vertex assumed by [`memory_estimate`]: a CCVT run at 10⁶ vertices peaks at
/// 834–922 MiB, and the other methods at less.
pub const BYTES_PER_VERTEX: u64 = 1024;

/// The peak memory, in bytes, that a mesh of `k` vertices is assumed to need: K ×
/// [`BYTES_PER_VERTEX`] plus 64 MiB for the program itself.
///
/// ```
/// assert_eq!(cvtmesh::memory_estimate(1_000_000), 1_000_000 * 1024 + (64 << 20));
/// ```
pub fn memory_estimate(k: usize) -> u64 {
    (k as u64)
        .saturating_mul(BYTES_PER_VERTEX)
        .saturating_add(64 << 20)
}

/// K vertices against a machine of `available` bytes (unknown: no bound).
fn check_memory(k: usize, available: Option<u64>) -> Result<(), MeshError> {
    let bytes = memory_estimate(k);
    match available {
        Some(available) if bytes > available => Err(MeshError::TooMuchMemory {
            requested: k,
            bytes,
            bytes_per_vertex: BYTES_PER_VERTEX,
            available,
        }),
        _ => Ok(()),
    }
}

/// The machine's total memory in bytes (`MemTotal` of `/proc/meminfo`), or `None` where it
/// cannot be read; then only [`MAX_POINTS`] bounds a request.
pub fn total_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// A density must be finite and non-negative on the region and positive somewhere. It is only
/// sampled (a function can hide a negative value between grid points); the grid is fine enough
/// to catch a sign error or a pole of a user formula.
fn check_density(density: &Density, region: &Region) -> Result<(), MeshError> {
    if density.is_uniform() {
        return Ok(());
    }
    // The region's own inside grid: its inside tests are made once per region and shared by
    // every validation (the command's, a method's, each part's and level's).
    let (centres, _) = region.inside_grid();
    let values: Vec<f64> = centres.par_iter().map(|&p| density.at(p)).collect();
    let mut positive = false;
    for (&p, &value) in centres.iter().zip(&values) {
        if !value.is_finite() || value < 0.0 {
            return Err(MeshError::InvalidDensity {
                x: p.x,
                y: p.y,
                value,
            });
        }
        positive |= value > 0.0;
    }
    if positive {
        Ok(())
    } else {
        Err(MeshError::ZeroDensity)
    }
}

/// One progress report: iteration number, a method-specific objective (CVT energy for CVT
/// methods) and the largest vertex move relative to the mean spacing.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Iteration (1-based).
    pub iteration: usize,
    /// The iteration cap.
    pub max_iter: usize,
    /// Objective value (NaN if the method has none).
    pub energy: f64,
    /// Largest move divided by the mean spacing.
    pub max_move: f64,
}

/// What a method produced and how it got there.
#[derive(Clone, Debug)]
pub struct MeshResult {
    /// The conforming mesh.
    pub mesh: Mesh,
    /// Iterations run (outer iterations for nested schemes).
    pub iterations: usize,
    /// True only if the convergence criterion was met before the cap.
    pub converged: bool,
    /// Objective per iteration (CVT energy of eq. (4) for CVT methods; empty if none). For a
    /// region of several parts, meshed one after another, the parts' histories follow each
    /// other, each entry the energy of the parts already meshed plus the current part's: the
    /// last is the whole region's. A run of Algorithm 2 (whose notes give an ε) ends on Ω_ε,
    /// so its energy is of the cells clipped to Ω_ε, larger than over Ω by the band's share:
    /// methods compare through the measures, not through it.
    pub energy_history: Vec<f64>,
    /// Largest relative move per iteration.
    pub move_history: Vec<f64>,
    /// Free-form notes for the user (e.g. "area bound 1.2e-3 after 14 bisection steps").
    pub notes: Vec<String>,
}

/// A mesh generator: a region and a request in, a conforming mesh out.
///
/// Every method of the workspace implements it (`Ccvt`, `DistMesh`, `Refine`, `Meshgen`,
/// `Vtm`), so a caller can hold any of them as a `Box<dyn Mesher>`. An implementation
/// validates the request first and reports progress as it goes; this one splits a triangular
/// region into four by its edge midpoints:
///
/// ```
/// use cvtmesh::{
///     check_conforming, Mesh, MeshError, MeshRequest, MeshResult, Mesher, Progress, VertexMarker,
/// };
/// use cvtmesh::geometry::{DVec2, LoopRole, Piece, Region};
///
/// struct Midpoints;
///
/// impl Mesher for Midpoints {
///     fn name(&self) -> &'static str {
///         "midpoints"
///     }
///     fn mesh(
///         &self,
///         region: &Region,
///         request: &MeshRequest,
///         progress: &mut dyn FnMut(Progress),
///     ) -> Result<MeshResult, MeshError> {
///         let k = request.validate(region)?;
///         let c: Vec<DVec2> = region.corners().iter().map(|c| c.pos).collect();
///         if k != 6 || c.len() != 3 {
///             let why = "midpoints meshes a triangle with K = 6";
///             return Err(MeshError::BadRequest(why.into()));
///         }
///         let points = vec![
///             c[0], c[1], c[2],
///             (c[0] + c[1]) / 2.0, (c[1] + c[2]) / 2.0, (c[2] + c[0]) / 2.0,
///         ];
///         let markers = points
///             .iter()
///             .map(|&p| {
///                 let b = region.project(p);
///                 match b.corner {
///                     Some(i) => VertexMarker::at_corner(region, i),
///                     None => VertexMarker::on_piece(region, p, b.piece),
///                 }
///             })
///             .collect();
///         let triangles = vec![[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]];
///         progress(Progress {
///             iteration: 1,
///             max_iter: request.max_iter,
///             energy: f64::NAN,
///             max_move: 0.0,
///         });
///         Ok(MeshResult {
///             mesh: Mesh { points, triangles, markers },
///             iterations: 1,
///             converged: true,
///             energy_history: Vec::new(),
///             move_history: vec![0.0],
///             notes: Vec::new(),
///         })
///     }
/// }
///
/// let [a, b, c] = [(0.0, 0.0), (1.0, 0.0), (0.5, 0.75f64.sqrt())].map(|(x, y)| DVec2::new(x, y));
/// let line = |a, b| Piece::Line { a, b };
/// let sides = vec![line(a, b), line(b, c), line(c, a)];
/// let triangle = Region::new("triangle", vec![(LoopRole::Outer, sides)], None)?;
///
/// let mesher: Box<dyn Mesher> = Box::new(Midpoints);
/// let result = mesher.mesh(&triangle, &MeshRequest::points(6), &mut |_| {})?;
/// // The corners and the three midpoints: four equilateral triangles that tile the region.
/// assert_eq!((result.mesh.num_vertices(), result.mesh.num_triangles()), (6, 4));
/// check_conforming(&result.mesh, &triangle)?;
/// assert!((result.mesh.min_angle_deg() - 60.0).abs() < 1e-9);
/// // K below the 3 corners: refused by `validate` before any work.
/// let e = mesher.mesh(&triangle, &MeshRequest::points(2), &mut |_| {}).unwrap_err();
/// assert!(matches!(e, MeshError::TooFewPoints { needed: 3, .. }));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub trait Mesher: Sync {
    /// Short name used on the command line and in tables (`ccvt2`, `distmesh`, ...).
    fn name(&self) -> &'static str;
    /// Mesh `region`, after [`MeshRequest::validate`] accepted `request`: the method's own
    /// mesh, of a region of one part, neither polished nor checked for conformity (what the
    /// study compares). [`Mesher::mesh_parts`] is what the front ends run: it also meshes
    /// regions of several parts, polishes ([`MeshRequest::polish`]) and checks the result.
    /// `progress` is called as iterations complete; for CCVT the iteration number restarts
    /// with each phase, and evaluations a safeguard rejects count in [`MeshResult::iterations`]
    /// without a report.
    fn mesh(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<MeshResult, MeshError>;

    /// Mesh a region of any number of parts: a region of one part as [`Mesher::mesh`] does;
    /// otherwise each part ([`Region::parts`]) with its share of K, then the meshes merged.
    /// The mesh returned conforms to the region ([`check_conforming`](crate::check_conforming),
    /// up to [`CONFORMITY_CHECK_LIMIT`](crate::CONFORMITY_CHECK_LIMIT) vertices): where a
    /// method's does not, the error ([`MeshError::NotConforming`]) names the first problem and,
    /// where the region is thinner than the spacing, the place and the K that would resolve it.
    ///
    /// Shares follow the count the density asks for in each part, ∫ ρ^(1/2) (its area for a
    /// uniform density), by largest remainders, so they add up to K and each is within one
    /// of K times the part's fraction; a part whose fraction is below what its boundary needs
    /// ([`Mesher::min_boundary_points`]) gets that, and the others share the rest; a K below
    /// the parts' needs together is refused. The merged mesh
    /// numbers the parts' vertices one part after another, its markers name the whole
    /// region's loops, pieces and corners, and it is converged only if every part is; the
    /// iterations add up, the histories follow one another and each part's notes are
    /// prefixed with its number.
    ///
    /// ```
    /// use cvtmesh::{check_conforming, MeshRequest, Mesher};
    /// # use cvtmesh::{Mesh, MeshError, MeshResult, Progress, VertexMarker};
    /// # use cvtmesh::geometry::{DVec2, Region};
    /// # /// Fans a convex polygon's corners from its first corner (K = corners).
    /// # struct Fan;
    /// # impl Mesher for Fan {
    /// #     fn name(&self) -> &'static str { "fan" }
    /// #     fn mesh(&self, region: &Region, request: &MeshRequest, _: &mut dyn FnMut(Progress))
    /// #         -> Result<MeshResult, MeshError> {
    /// #         request.validate(region)?;
    /// #         let points: Vec<DVec2> = region.corners().iter().map(|c| c.pos).collect();
    /// #         let markers = (0..points.len()).map(|i| VertexMarker::at_corner(region, i)).collect();
    /// #         let triangles = (1..points.len() as u32 - 1).map(|i| [0, i, i + 1]).collect();
    /// #         let mesh = Mesh { points, triangles, markers };
    /// #         Ok(MeshResult { mesh, iterations: 1, converged: true, energy_history: vec![],
    /// #             move_history: vec![], notes: vec![] })
    /// #     }
    /// # }
    /// // Two squares, the second twice as wide: two parts.
    /// let text = "0 0\n1 0\n1 1\n0 1\n\n2 0\n4 0\n4 1\n2 1\n";
    /// let region = cvtmesh::geometry::formats::loops_from_str(text, "two", "two")?;
    /// assert_eq!(region.num_parts(), 2);
    /// // A method alone refuses it; mesh_parts meshes both parts and merges them.
    /// assert!(Fan.mesh(&region, &MeshRequest::points(21), &mut |_| {}).is_err());
    /// let result = Fan.mesh_parts(&region, &MeshRequest::points(21), &mut |_| {})?;
    /// check_conforming(&result.mesh, &region)?;
    /// assert_eq!(result.mesh.num_vertices(), 8);
    /// assert!((result.mesh.area() - region.area()).abs() < 1e-12);
    /// assert!(result.notes[0].starts_with("part 0: K = 4"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    fn mesh_parts(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<MeshResult, MeshError> {
        crate::parts::mesh_parts(self, region, request, progress)
    }

    /// The fewest boundary vertices this method puts on `region` at any K: the least share
    /// of K [`Mesher::mesh_parts`] gives a part. By default [`boundary_points_needed`] (every
    /// corner, at least three per loop); a method whose boundary needs more (MESHGEN and VTM
    /// keep chords from cutting into concave curves) says so here.
    ///
    /// ```
    /// use cvtmesh::{boundary_points_needed, Mesher};
    /// # use cvtmesh::{MeshError, MeshRequest, MeshResult, Progress};
    /// # use cvtmesh::geometry::Region;
    /// # struct Any;
    /// # impl Mesher for Any {
    /// #     fn name(&self) -> &'static str { "any" }
    /// #     fn mesh(&self, _: &Region, _: &MeshRequest, _: &mut dyn FnMut(Progress))
    /// #         -> Result<MeshResult, MeshError> { unimplemented!() }
    /// # }
    /// let hex_hole = Region::builtin("hex_hole")?;
    /// assert_eq!(Any.min_boundary_points(&hex_hole), boundary_points_needed(&hex_hole));
    /// assert_eq!(Any.min_boundary_points(&hex_hole), 12); // two hexagons' corners
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    fn min_boundary_points(&self, region: &Region) -> usize {
        boundary_points_needed(region)
    }

    /// Whether the method starts from points already spaced as a non-uniform density asks
    /// (a graded start), rather than from a uniform lattice the density only reshapes. Those
    /// that do not follow a size field loosely, and [`Mesher::mesh_parts`] says so in a note.
    /// True by default.
    ///
    /// ```
    /// use cvtmesh::{Mesher, Method};
    /// assert!("ccvt".parse::<Method>()?.mesher().follows_size_fields());
    /// assert!(!"vtm".parse::<Method>()?.mesher().follows_size_fields());
    /// assert!(!"ccvt1".parse::<Method>()?.mesher().follows_size_fields());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    fn follows_size_fields(&self) -> bool {
        true
    }

    /// Whether the method keeps the region's embedded lines ([`Region::embedded_lines`]) as
    /// edges itself. For those that do not (the default), [`Mesher::mesh_parts`] places each
    /// line's vertices at the local spacing as embedded points first and restores the edges
    /// between them by flips after; one that does is handed the lines as they are.
    ///
    /// ```
    /// use cvtmesh::{Mesher, Method};
    /// assert!("refine".parse::<Method>()?.mesher().meshes_embedded_lines());
    /// assert!(!"ccvt".parse::<Method>()?.mesher().meshes_embedded_lines());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    fn meshes_embedded_lines(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn region(name: &str) -> Region {
        Region::builtin(name).unwrap()
    }

    /// A K too small for a field's range is refused with the K that keeps the boundary; a
    /// coarse but sound mesh of the same field is not.
    #[test]
    fn k_too_few_for_the_fields_boundary_is_refused_with_the_k_needed() {
        let circle = region("circle");
        let steep = SizeField::from_expr("1e-5 + x^2")
            .unwrap()
            .bounded(&circle, None, None, Some(0.3))
            .unwrap();
        let e = MeshRequest::size_field(&steep, &circle, Some(1000))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("K = 1000 vertices are too few") && e.contains("K >= "),
            "{e}"
        );
        let needed: f64 = e
            .split("K >= ")
            .nth(1)
            .unwrap()
            .split(|c: char| !c.is_ascii_digit())
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert!(MeshRequest::size_field(&steep, &circle, Some(needed as usize)).is_ok());
        let source = SizeField::from_expr("0.01 + 0.1 * sqrt(x^2 + y^2)").unwrap();
        let e = MeshRequest::size_field(&source, &circle, Some(5))
            .unwrap_err()
            .to_string();
        assert!(e.contains("K >= 22"), "{e}");
        // A coarse mesh of 10 vertices covers 92 % of the disc: let through.
        assert!(MeshRequest::size_field(&source, &circle, Some(10)).is_ok());
        // A polygon loses nothing along its straight sides, whatever K.
        let hexagons = region("hex_hole");
        assert!(MeshRequest::size_field(&source, &hexagons, Some(4)).is_ok());
    }

    #[test]
    fn a_valid_request_gives_its_k() {
        let circle = region("circle");
        assert_eq!(MeshRequest::points(88).validate(&circle).unwrap(), 88);
        let by_size = MeshRequest {
            size: Size::EdgeLength(0.1),
            ..MeshRequest::points(0)
        };
        let k = by_size.validate(&circle).unwrap();
        assert_eq!(k, by_size.size.points(&circle));
        assert!(k > 300, "{k}");
    }

    #[test]
    fn too_few_points_names_the_corners_and_the_flag() {
        let r = region("hex_hole");
        let (corners, loops) = (r.corners().len(), r.loops().len());
        let needed = boundary_points_needed(&r);
        assert_eq!(needed, corners);
        let e = MeshRequest::points(needed - 1).validate(&r).unwrap_err();
        match &e {
            MeshError::TooFewPoints {
                requested,
                needed: n,
                corners: c,
                loops: l,
                edge_length: None,
                ..
            } => assert_eq!(
                (*requested, *n, *c, *l),
                (needed - 1, needed, corners, loops)
            ),
            other => panic!("{other:?}"),
        }
        let text = e.to_string();
        assert!(text.contains("too small") && text.contains(&format!("{corners} corners")));
        // Named as the library and Python call the setting, and as the command line does.
        assert!(text.contains("(corner_angle, --corner-angle)"), "{text}");
        assert!(
            text.contains("(simplify \"auto\", --simplify auto)"),
            "{text}"
        );
        assert!(e.is_invalid_request());
        assert_eq!(MeshRequest::points(needed).validate(&r).unwrap(), needed);
    }

    #[test]
    fn an_edge_length_too_large_for_the_region_is_too_few_points() {
        let e = MeshRequest::edge_length(5.0)
            .validate(&region("circle"))
            .unwrap_err();
        match &e {
            MeshError::TooFewPoints {
                requested,
                needed,
                edge_length,
                ..
            } => assert_eq!((*requested, *needed, *edge_length), (0, 3, Some(5.0))),
            other => panic!("{other:?}"),
        }
        assert!(e.to_string().contains("(size, --size)"), "{e}");
    }

    #[test]
    fn an_edge_length_must_be_positive_and_finite() {
        let circle = region("circle");
        for h in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            let e = MeshRequest {
                size: Size::EdgeLength(h),
                ..MeshRequest::points(0)
            }
            .validate(&circle)
            .unwrap_err();
            assert!(
                matches!(e, MeshError::InvalidEdgeLength(x) if x.to_bits() == h.to_bits()),
                "{h}: {e:?}"
            );
        }
    }

    #[test]
    fn the_tolerance_must_be_positive_and_finite() {
        let circle = region("circle");
        for tol in [0.0, -1e-4, f64::NAN, f64::INFINITY] {
            let e = MeshRequest::points(50)
                .tol(tol)
                .validate(&circle)
                .unwrap_err();
            assert!(matches!(e, MeshError::InvalidTolerance(_)), "{tol}: {e:?}");
            assert!(e.to_string().contains("(tol, --tol)"), "{e}");
        }
    }

    #[test]
    fn a_request_beyond_a_given_memory_is_refused_with_the_figures() {
        let gib = 1u64 << 30;
        let k = 2_000_000;
        let e = check_memory(k, Some(gib)).unwrap_err();
        match &e {
            MeshError::TooMuchMemory {
                requested,
                bytes,
                available,
                ..
            } => assert_eq!(
                (*requested, *bytes, *available),
                (k, memory_estimate(k), gib)
            ),
            other => panic!("{other:?}"),
        }
        assert!(e.to_string().contains("1.0 GiB"), "{e}");
        // What fits is accepted, and without a figure for the machine nothing is refused.
        assert!(check_memory(100_000, Some(gib)).is_ok());
        assert!(check_memory(k, None).is_ok());
    }

    #[test]
    fn a_request_beyond_the_machines_memory_is_refused_with_the_figure() {
        // On this machine, where its memory can be read and lies below MAX_POINTS vertices'.
        let Some(total) = total_memory() else { return };
        let k = (total / BYTES_PER_VERTEX) as usize + 1;
        if k > MAX_POINTS {
            return;
        }
        let e = MeshRequest::points(k)
            .validate(&region("circle"))
            .unwrap_err();
        match &e {
            MeshError::TooMuchMemory {
                requested, bytes, ..
            } => assert_eq!((*requested, *bytes), (k, memory_estimate(k))),
            other => panic!("{other:?}"),
        }
        assert!(
            e.to_string().contains("GiB") && e.is_invalid_request(),
            "{e}"
        );
    }

    #[test]
    fn the_iteration_cap_must_be_at_least_one() {
        let e = MeshRequest::points(50)
            .max_iter(0)
            .validate(&region("circle"))
            .unwrap_err();
        assert!(matches!(e, MeshError::ZeroMaxIter), "{e:?}");
        assert!(MeshRequest::points(50)
            .max_iter(1)
            .validate(&region("circle"))
            .is_ok());
    }

    #[test]
    fn the_density_must_be_non_negative_finite_and_not_zero() {
        let square = region("square_hole");
        let density =
            |f: fn(DVec2) -> f64| MeshRequest::points(100).density(Density::Function(Arc::new(f)));
        let e = density(|p| p.x - 0.5).validate(&square).unwrap_err();
        match e {
            MeshError::InvalidDensity { x, value, .. } => assert!(value < 0.0 && x < 0.5),
            other => panic!("{other:?}"),
        }
        let e = density(|_| f64::NAN).validate(&square).unwrap_err();
        assert!(matches!(e, MeshError::InvalidDensity { value, .. } if value.is_nan()));
        let e = density(|_| 0.0).validate(&square).unwrap_err();
        assert!(matches!(e, MeshError::ZeroDensity), "{e:?}");
        assert_eq!(density(|p| 1.0 + p.x * p.x).validate(&square).unwrap(), 100);
    }
}
