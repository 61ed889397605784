//! The `Mesher` for CCVT: Algorithm 1 or 2, with Lloyd, Anderson-accelerated or Newton
//! iteration.
use crate::active;
use crate::init::{initial_points, Init};
use crate::iterate::run;
use crate::map::{Phase, PhaseResult, Profile, Role, Trace, Work};
use crate::params::{Algorithm, Solver, Update};
use crate::scale::LocalScale;
use crate::start;
use crate::sublevel::Sublevel;
use geometry::Region;
use mesh::{MeshError, MeshRequest, MeshResult, Mesher, Progress, VertexMarker};
use tessellation::Delaunay;

/// CCVT mesher.
///
/// [`Ccvt::default`] (the same as [`Ccvt::fast`]) is what `cvtmesh mesh` and
/// `cvtmesh::Method::Ccvt` run: Algorithm 2 with Newton's method, from the centred equilateral
/// lattice ([`Init::Lattice`], one of step 0's options), polygonization tolerance 1e-4 of the
/// mean spacing, ε tolerance 1e-2 of the spacing with at most 30 ε-updates, intermediate CVTs of
/// Ω_ε stopped at moves below 1e-3 of the spacing, active-set Newton steps from 3000
/// generators on and ε starting at 0. [`Ccvt::algorithm1`] and [`Ccvt::algorithm2`] are the
/// paper's algorithms with Lloyd iteration, [`Ccvt::anderson`] Algorithm 2 with Anderson
/// acceleration; they differ from the default only in `algorithm` and `solver`.
///
/// ```
/// use cvtmesh::ccvt::Ccvt;
/// use cvtmesh::geometry::Region;
/// use cvtmesh::{check_conforming, MeshRequest, Mesher, VertexMarker};
///
/// let region = Region::builtin("square_hole")?; // a square with a square hole: 8 corners
/// let result = Ccvt::default().mesh(&region, &MeshRequest::points(200), &mut |_| {})?;
/// assert!(result.converged);
/// assert_eq!(result.mesh.num_vertices(), 200);
/// check_conforming(&result.mesh, &region)?;
/// // Every corner carries a vertex, exactly.
/// for (i, corner) in region.corners().iter().enumerate() {
///     let on_it = |(p, m): (&cvtmesh::geometry::DVec2, &VertexMarker)| {
///         *p == corner.pos && matches!(m, VertexMarker::Corner { corner, .. } if *corner == i)
///     };
///     assert!(result.mesh.points.iter().zip(&result.mesh.markers).any(on_it));
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Ccvt {
    /// Algorithm 1 or 2.
    pub algorithm: Algorithm,
    /// Lloyd, Anderson or Newton.
    pub solver: Solver,
    /// Initial generators.
    pub init: Init,
    /// Chord tolerance of the domain polygon, relative to the mean spacing.
    pub polygon_tol: f64,
    /// Algorithm 2 stops updating ε when |ε_new − ε| < eps_tol·spacing.
    pub eps_tol: f64,
    /// Cap on ε-updates of Algorithm 2.
    pub max_eps_updates: usize,
    /// Algorithm 2's intermediate CVTs of Ω_ε (steps 1–3, "some convergence criteria" in the
    /// paper) stop when the largest move is below this fraction of the spacing (three times it
    /// from the boundary row start of large runs, whose Ω_ε is a lattice's CVT but for the
    /// seam along the row), or below the request's tolerance if that is looser: they only
    /// serve to estimate ε to `eps_tol`. The final constrained phase always uses the request's
    /// tolerance.
    pub eps_phase_tol: f64,
    /// Newton only: from this many generators on, once at most 1 % of them move more than the
    /// tolerance, steps move only the defects (the largest moves) and two rings of their
    /// neighbours, updating the triangulation and cells around them (active-set steps, module
    /// `active`: O(active) instead of O(K) per step; the stopping rule is the same). 3000 by
    /// default: from there on the steps save time with the same measures and size conformity,
    /// below it they did not, and the study's K stay below it (measured in
    /// `docs/design-notes.md`, "Active-set steps below 10⁴ generators").
    pub active_from: usize,
    /// Algorithm 2's first ε, relative to the spacing (0, as in the paper, by default). A start
    /// near the settled ε (about 0.7 of the spacing) skips the CVT of Ω itself, which saves
    /// time at large K, but the meshes' worst cells come out worse, so it is not the default.
    pub eps_start: f64,
    /// From this many generators on, step 0 is a coarser CCVT (about a quarter of K, itself
    /// solved the same way) prolongated by splitting every edge of its mesh at its midpoint
    /// (∂Ω laid out again at CCVT's boundary spacing), and the run is Algorithm 1 from it: the
    /// start already has the target spacing along ∂Ω and inside, so the fine level only
    /// relaxes it. `usize::MAX` (the default) turns the
    /// levels off: on the uniform circle at 10⁵ the relaxation of the prolongated lattice's
    /// boundary layer took more evaluations than the lattice start with Algorithm 2 and gave
    /// a smallest angle of 34.5° instead of 41.6°. Graded runs take
    /// [`Ccvt::graded_multilevel_from`] instead.
    pub multilevel_from: usize,
    /// [`Ccvt::multilevel_from`] for a non-uniform density (a size field): from this many
    /// generators on (20 000 by default), the graded start is a coarser graded CCVT of about a
    /// quarter of K, every edge of its mesh split, its boundary laid out again at CCVT's
    /// boundary spacing; the coarser level takes levels of its own by the same rule (10⁵ →
    /// 25 000 → 6 250). The circle's point source and the L-shape's corner of the graded
    /// comparison took 0.56–0.92 and 0.71–0.89 of the time with one level less at 2.5·10⁴–10⁵
    /// (seeds 1–3 or 1–5), with the edges following the field more closely in every run; at
    /// 10⁴ the L-shape was slower (`docs/design-notes.md`, "Multilevel start"). Neither kind of
    /// run takes levels where more than [`Ccvt::levels_max_boundary_share`] of its generators
    /// would lie on ∂Ω.
    pub graded_multilevel_from: usize,
    /// No levels ([`Ccvt::multilevel_from`], [`Ccvt::graded_multilevel_from`]) where more than
    /// this share of the generators would lie on ∂Ω (∫_∂Ω ds/h over K; 0.03 by default, a
    /// large value such as `f64::MAX` turns the rule off). A coarser level relaxes the interior
    /// cheaply, but the fine level lays ∂Ω out again and relaxes its boundary layer from
    /// scratch: where that layer is much of the mesh the coarse level is spent for nothing.
    /// Graded runs, levels against a single level (`graded` probe): below 3 % the circle's point
    /// source (0.55 % of 10⁵ generators on ∂Ω), the L-shape's corner (0.83 %) and
    /// square_hole's hole (1.95 %) took 0.50–0.89 of the time; above it the lake's shores
    /// (5.5 %) 1.07–1.22 at 10⁵ and 1.28–1.60 at 5·10⁴, and eight regions of the robustness
    /// sweep refined toward their outer loop at 8·10⁴ (3.7–21 %) 0.86–2.9, 329 s against 213 s
    /// in all (two of them, `holes40` and `comb20`, cycled from the coarser level and were
    /// solved again without it).
    pub levels_max_boundary_share: f64,
    /// For a non-uniform density (a size field), step 0 is a Delaunay refinement driven by the
    /// density and the run is Algorithm 1 from it: Algorithm 2's single ε cannot fit a boundary
    /// layer whose spacing varies along ∂Ω, and a uniform lattice would have to be carried
    /// across the region. No effect for ρ ≡ 1.
    pub graded_start: bool,
    /// From this many generators on, Algorithm 2 with a uniform density (from the lattice, ε
    /// starting at 0) starts instead from an outer row of generators just inside ∂Ω_ε at the
    /// boundary spacing a converged CCVT settles at, with the lattice, dilated to Ω_ε, inside
    /// it, and ε from 0.686 of the spacing. The lattice path spends most of its evaluations
    /// on the CVT of Ω and its slow dilation into Ω_ε, which is what thins the outer row to
    /// that spacing; the row start skips both. Over the ten built-in regions at K = 30 000
    /// (two seeds) it took 0.61 of the time, with a lower energy in 18 of 20 runs and 11 of the
    /// 12 measures lower on average; at K = 3000 and 5000, 0.43 and 0.42 of the time with 9
    /// and 11 of the 12 lower on average (λ 2–4 % higher: `docs/design-notes.md`). 3000 by
    /// default: below it the lattice's own structure (the rings of Table 1's disc) matters
    /// more, and the study's K stay below it; the paper's methods ([`Ccvt::algorithm1`],
    /// [`Ccvt::algorithm2`]) never take it.
    pub row_from: usize,
    /// Where each generator moves before the labels and projections: its centroid (CCVT, the
    /// default) or VTM's optimal-Delaunay target ([`Update::Odt`], with Algorithm 1 and Lloyd
    /// iteration only; [`Ccvt::validate`] refuses other combinations).
    pub update: Update,
}

impl Default for Ccvt {
    /// Algorithm 2 with Newton's method and the settings listed on [`Ccvt`].
    fn default() -> Self {
        Ccvt {
            algorithm: Algorithm::Two,
            solver: Solver::Newton,
            init: Init::Lattice,
            polygon_tol: 1e-4,
            eps_tol: 1e-2,
            max_eps_updates: 30,
            eps_phase_tol: 1e-3,
            active_from: 3_000,
            eps_start: 0.0,
            multilevel_from: usize::MAX,
            graded_multilevel_from: 20_000,
            levels_max_boundary_share: 0.03,
            graded_start: true,
            row_from: 3_000,
            update: Update::Centroid,
        }
    }
}

/// Coarse levels stop at this largest move (relative to the local spacing), or at the
/// request's tolerance if looser: the prolongation's own error is larger.
const COARSE_TOL: f64 = 1e-3;

/// The ε-phases from the boundary row start stop at this multiple of
/// [`Ccvt::eps_phase_tol`]: that start is the lattice's CVT inside a row already, and its
/// ε-phase relaxes the seam between the two; the constrained phase that follows relaxes the
/// same layer again after projecting the row onto ∂Ω.
// `solve`-like probes, 10⁵, seeds 1–12, 3 against 1 (solve seconds in all): circle 16.4 →
// 15.4 s, lake 24.3 → 22.8 s; circle 10⁶, seeds 1–2: 13.3 / 12.6 → 10.7 / 12.3 s. Whole command
// at 10⁵, seeds 1–6 interleaved: circle 8.62 → 8.05 s, lake 11.89 → 11.57 s, the means of λ,
// γ, β, q and p within 1.7 % (λ within 0.1 %). 10 gave 0.91 of the time on the circle (seeds
// 1–4) where 3 gave 0.86.
const ROW_EPS_PHASE_FACTOR: f64 = 3.0;

/// Where every cell of the CVT of Ω_ε reaches ∂Ω_ε, Algorithm 2's ε is followed only while
/// each of its steps is at most this share of the one before (a contraction toward a fixed
/// point). Steps measured in spacings: a ring 0.65 spacings wide (the robustness sweep's thin
/// annulus at K = 3000) 0.75, 0.52, 0.35, 0.07, 0.02, settling at 1.70 (ratios 0.69, 0.67,
/// 0.19, 0.27), and the small triangle of a two-part region at K = 16 0.83, 0.41, 0.21, 0.09,
/// 0.04 (about 0.5 each); three generators on a 1 × 12 sliver 1.58, 0.91, 0.86, 0.85, 0.86, …
/// (0.58, then 0.95 and above, to 14.6 spacings in 30 updates), and on such a sliver under a
/// coarse size field 1.64, 0.90, 1.94, 3.5, 6.4, … (to 5 230 spacings).
const EPS_HOLD_RATIO: f64 = 0.8;

impl Ccvt {
    /// Check the settings: `polygon_tol` and `eps_tol` positive and finite, `eps_phase_tol`,
    /// `eps_start` and `levels_max_boundary_share` finite and non-negative
    /// ([`MeshError::InvalidSetting`] otherwise). The meshing calls check them first.
    ///
    /// ```
    /// use cvtmesh::ccvt::Ccvt;
    /// use cvtmesh::MeshError;
    ///
    /// assert!(Ccvt::default().validate().is_ok());
    /// let bad = Ccvt { polygon_tol: 0.0, ..Ccvt::default() };
    /// assert!(matches!(
    ///     bad.validate(),
    ///     Err(MeshError::InvalidSetting { setting: "polygon_tol", .. })
    /// ));
    /// ```
    pub fn validate(&self) -> Result<(), MeshError> {
        let name = self.name();
        MeshError::check_positive(name, "polygon_tol", self.polygon_tol)?;
        MeshError::check_positive(name, "eps_tol", self.eps_tol)?;
        MeshError::check_non_negative(name, "eps_phase_tol", self.eps_phase_tol)?;
        MeshError::check_non_negative(name, "eps_start", self.eps_start)?;
        MeshError::check_non_negative(
            name,
            "levels_max_boundary_share",
            self.levels_max_boundary_share,
        )?;
        if self.update == Update::Odt
            && (self.algorithm != Algorithm::One || self.solver != Solver::Lloyd)
        {
            return Err(MeshError::invalid_setting(
                name,
                "update",
                f64::NAN,
                "Update::Centroid unless the algorithm is One and the solver Lloyd",
            ));
        }
        Ok(())
    }

    /// The paper's Algorithm 1: constrained Lloyd iteration on Ω (`Algorithm::One`,
    /// `Solver::Lloyd`) from the lattice, without levels or a graded start; every other
    /// setting as in [`Ccvt::default`]. Mesher name `ccvt1`.
    pub fn algorithm1() -> Self {
        Ccvt {
            algorithm: Algorithm::One,
            solver: Solver::Lloyd,
            multilevel_from: usize::MAX,
            graded_multilevel_from: usize::MAX,
            graded_start: false,
            row_from: usize::MAX,
            ..Ccvt::default()
        }
    }
    /// The paper's Algorithm 2: adaptive ε-expansion, then constrained Lloyd iteration
    /// (`Algorithm::Two`, `Solver::Lloyd`) from the lattice, without levels or a graded start;
    /// every other setting as in [`Ccvt::default`]. Mesher name `ccvt2`.
    pub fn algorithm2() -> Self {
        Ccvt {
            algorithm: Algorithm::Two,
            solver: Solver::Lloyd,
            multilevel_from: usize::MAX,
            graded_multilevel_from: usize::MAX,
            graded_start: false,
            row_from: usize::MAX,
            ..Ccvt::default()
        }
    }
    /// Algorithm 2 with Newton's method on the energy (`Algorithm::Two`, `Solver::Newton`):
    /// the same as [`Ccvt::default`]. It reaches the energy Lloyd iteration reaches with far
    /// fewer evaluations of the Voronoi cells, since Lloyd's slow tail is an elastic mode that
    /// a Newton step removes at once. Mesher name `ccvt`.
    pub fn fast() -> Self {
        Ccvt::default()
    }
    /// Algorithm 2 with Anderson acceleration of depth 5 (`Algorithm::Two`,
    /// `Solver::Anderson { depth: 5 }`) from the lattice, without levels or a graded start;
    /// every other setting as in [`Ccvt::default`]. Mesher name `ccvt-anderson`.
    pub fn anderson() -> Self {
        Ccvt {
            algorithm: Algorithm::Two,
            solver: Solver::Anderson { depth: 5 },
            multilevel_from: usize::MAX,
            graded_multilevel_from: usize::MAX,
            graded_start: false,
            row_from: usize::MAX,
            ..Ccvt::default()
        }
    }
}

/// Converged (or capped) generators with their boundary markers, before triangulation.
#[derive(Clone, Debug)]
pub struct Generators {
    /// The generators z_k.
    pub points: Vec<geometry::DVec2>,
    /// Interior / boundary piece / corner of each generator (from the last iteration's labels).
    pub markers: Vec<VertexMarker>,
    /// Lloyd iterations over all phases.
    pub iterations: usize,
    /// Every phase met its tolerance (and ε settled, for Algorithm 2).
    pub converged: bool,
    /// A phase stopped unconverged because its largest move made no new low in
    /// `STALL_EVALUATIONS` evaluations (the iterate cycles).
    pub stalled: bool,
    /// CVT energy (4) per iteration.
    pub energy_history: Vec<f64>,
    /// Largest move / mean spacing per iteration.
    pub move_history: Vec<f64>,
    /// What the user should know (ε, reductions).
    pub notes: Vec<String>,
    /// Where the time went.
    pub profile: Profile,
}

/// From this many generators the mesh is read off the last iterate's own triangulation,
/// repaired by flips ([`tessellation::conforming_mesh_from`]: circle 10⁵ 0.13 → 0.05 s, lake
/// 10⁵ 0.17 → 0.05 s, circle 10⁶ 1.6 → 0.8 s), instead of a constrained triangulation built
/// afresh: the same triangles, listed in another order. Below it (the study's sizes) the
/// triangles keep the constrained triangulation's order.
const MESH_FROM_SOLVE: usize = 10_000;

impl Ccvt {
    /// Run the algorithm and return the generators (no triangulation). The settings
    /// ([`Ccvt::validate`]) and the request ([`MeshRequest::validate`]) are checked first.
    pub fn generators(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<Generators, MeshError> {
        Ok(self.solved(region, request, progress)?.0)
    }

    /// The coarser level's size and request for a run of `k` generators, or None when the run
    /// takes no levels: below its threshold ([`Ccvt::multilevel_from`] or
    /// [`Ccvt::graded_multilevel_from`]), where more than [`Ccvt::levels_max_boundary_share`]
    /// of the generators would lie on ∂Ω, or where the coarser level would not be a valid
    /// request of its own (a region with more corners than the coarse count).
    fn coarser(
        &self,
        region: &Region,
        request: &MeshRequest,
        scale: &LocalScale,
        k: usize,
    ) -> Option<(usize, MeshRequest)> {
        let levels_from = if request.density.is_uniform() {
            self.multilevel_from
        } else {
            self.graded_multilevel_from
        };
        if k < levels_from {
            return None;
        }
        let boundary = start::boundary_count(region, scale);
        if boundary > self.levels_max_boundary_share * k as f64 {
            return None;
        }
        let coarse_k = start::coarse_count(boundary, k);
        let coarse = MeshRequest {
            size: mesh::Size::Points(coarse_k),
            tol: request.tol.max(COARSE_TOL),
            ..request.clone()
        };
        coarse.validate(region).ok().map(|_| (coarse_k, coarse))
    }

    /// [`Ccvt::generators`] with the triangulation of the last iterate.
    fn solved(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<(Generators, Delaunay), MeshError> {
        self.validate()?;
        let k = request.validate(region)?;
        let spacing = request.spacing(region);
        let scale = LocalScale::new(region, &request.density, spacing);
        if let Some((coarse_k, coarse_request)) = self.coarser(region, request, &scale, k) {
            let coarse = self.generators(region, &coarse_request, progress)?;
            let mesh = tessellation::conforming_mesh(&coarse.points, &coarse.markers, region)?;
            let seeds = start::prolongate_resampled(region, &scale, &mesh);
            let z = start::along_hilbert(start::fit_count(region, &scale, seeds, k, request.seed));
            let (fine, del) = self.solve_on_pool(region, request, z, Run::Relax, progress)?;
            let levels = coarse.then(fine, coarse_k);
            if !levels.stalled || request.cancelled() || request.out_of_time() {
                return Ok((levels, del));
            }
            // The relaxation from the prolongated start cycled; the single level's path is
            // another one, and on the regions where this was seen it converged.
            let single = Ccvt {
                multilevel_from: usize::MAX,
                graded_multilevel_from: usize::MAX,
                ..self.clone()
            };
            let (again, del) = single.solved(region, request, progress)?;
            return Ok((levels.then_again(again), del));
        }
        if self.graded_start && !request.density.is_uniform() {
            let z = start::along_hilbert(start::graded(region, request, &scale, k)?);
            return self.solve_on_pool(region, request, z, Run::Relax, progress);
        }
        if k >= self.row_from
            && self.algorithm == Algorithm::Two
            && self.init == Init::Lattice
            && self.eps_start == 0.0
            && request.density.is_uniform()
        {
            // Ω_ε must keep every hole at the row's ε (else Algorithm 2 reduces ε, and the
            // row would lie outside the domain): then the lattice path below.
            if let Some(z) = start::boundary_row(
                region,
                k,
                request.spacing(region),
                start::ROW_EPS,
                request.seed,
            ) {
                let from_row = Ccvt {
                    eps_start: start::ROW_EPS,
                    ..self.clone()
                };
                return from_row.solve_on_pool(
                    region,
                    request,
                    start::along_hilbert(z),
                    Run::FromRow,
                    progress,
                );
            }
        }
        let z = start::along_hilbert(initial_points(region, k, self.init, request.seed));
        self.solve_on_pool(region, request, z, Run::Paper(self.algorithm), progress)
    }

    /// Run the algorithm from the given initial generators (step 0 done by the caller, e.g. a
    /// restart or a refined coarser solution): K is their number and `request.size` is ignored.
    /// They should lie in Ω. The settings and the request (with K = `z.len()`) are checked
    /// first, as in [`Ccvt::generators`].
    pub fn generators_from(
        &self,
        region: &Region,
        request: &MeshRequest,
        z: Vec<geometry::DVec2>,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<Generators, MeshError> {
        self.validate()?;
        MeshRequest {
            size: mesh::Size::Points(z.len()),
            ..request.clone()
        }
        .validate(region)?;
        Ok(self
            .solve_on_pool(region, request, z, Run::Paper(self.algorithm), progress)?
            .0)
    }

    /// [`Ccvt::generators_from`] for a validated request, on rayon's pool.
    fn solve_on_pool(
        &self,
        region: &Region,
        request: &MeshRequest,
        z: Vec<geometry::DVec2>,
        run: Run,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<(Generators, Delaunay), MeshError> {
        if rayon::current_thread_index().is_some() {
            return self.solve(region, request, z, run, progress);
        }
        // The solve runs on rayon's pool, not on the calling thread: from outside the pool each
        // of its many parallel passes would hand its work over and put the caller to sleep until
        // it is done. `progress` stays on the caller's thread, fed through a channel.
        let (tx, rx) = std::sync::mpsc::channel();
        let mut out = None;
        rayon::in_place_scope(|s| {
            let out = &mut out;
            s.spawn(move |_| {
                *out = Some(self.solve(region, request, z, run, &mut |p| {
                    // The receiver outlives the solve (it drains until this sender drops).
                    let _ = tx.send(p);
                }));
            });
            for p in rx {
                progress(p);
            }
        });
        out.expect("the scope waits for the solve")
    }

    /// [`Ccvt::generators_from`] on the current thread, for a validated request, with the
    /// triangulation of the last iterate.
    fn solve(
        &self,
        region: &Region,
        request: &MeshRequest,
        mut z: Vec<geometry::DVec2>,
        run: Run,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<(Generators, Delaunay), MeshError> {
        let request = &MeshRequest {
            size: mesh::Size::Points(z.len()),
            ..request.clone()
        };
        let spacing = request.spacing(region);
        let tol_poly = self.polygon_tol * spacing;
        let omega = region.polygonize(tol_poly);
        let mut notes = Vec::new();
        let mut tally = Tally {
            method: self.name(),
            request,
            iterations: 0,
            converged: true,
            stalled: false,
        };
        let mut trace = Trace {
            energies: Vec::new(),
            moves: Vec::new(),
            progress,
            prof: Profile::default(),
        };
        let solver = self.solver;
        // One triangulation, repaired from phase to phase.
        let mut work = Work::new(&omega);
        // Squares of about three spacings: most generators are answered by the grid.
        let in_region = Sublevel::new(region, 0.0, 3.0 * spacing);
        // A point of Ω_ε's polygon (chord error ≤ tol_poly) if closer than ε − 2·tol_poly.
        let in_domain = |eps: f64| Sublevel::new(region, eps - 2.0 * tol_poly, 3.0 * spacing);
        let scale = LocalScale::new(region, &request.density, spacing);
        let common = (region, request, solver, scale, self.active_from);
        let (eps_share, eps_phase_tol) = if matches!(run, Run::FromRow) {
            (
                active::ACTIVE_SHARE_FROM_ROW,
                ROW_EPS_PHASE_FACTOR * self.eps_phase_tol,
            )
        } else {
            (active::ACTIVE_SHARE, self.eps_phase_tol)
        };
        fn phase<'a>(
            (region, request, solver, scale, active_from): (
                &'a Region,
                &'a MeshRequest,
                Solver,
                LocalScale<'a>,
                usize,
            ),
            domain: &'a geometry::Polygon,
            inside: &'a Sublevel<'a>,
            constrained: bool,
            tol: f64,
        ) -> Phase<'a> {
            Phase {
                region,
                domain,
                inside,
                density: &request.density,
                constrained,
                update: Update::Centroid,
                solver,
                tol,
                max_iter: request.max_iter,
                spacing: scale.mean(),
                scale,
                active_from,
                active_share: active::ACTIVE_SHARE,
                project_first: false,
                cancel: request.cancel.as_deref(),
                deadline: request.deadline,
            }
        }
        let final_domain = match run {
            Run::Relax => omega,
            Run::Paper(Algorithm::One) => {
                if self.init == Init::Cvt {
                    let r = tally.run(
                        &phase(common, &omega, &in_domain(0.0), false, request.tol),
                        z,
                        &mut work,
                        &mut trace,
                    )?;
                    z = r.z;
                }
                omega
            }
            Run::Paper(Algorithm::Two) | Run::FromRow => {
                // Steps 1–3: ordinary CVTs of Ω_ε with ε updated until it settles.
                let (mut eps, mut domain) = (self.eps_start * spacing, omega);
                let mut holes = HoleLimit::new(region, tol_poly);
                if eps > 0.0 {
                    domain = holes.expand(region, &mut eps, tol_poly);
                }
                let (mut settled, mut held) = (false, false);
                // The size of ε's last step.
                let mut last_change: Option<f64> = None;
                // The estimate ε settled below, where a larger ε closes a hole.
                let mut capped: Option<f64> = None;
                for _ in 0..self.max_eps_updates {
                    work.retarget(&domain);
                    let r = tally.run(
                        &Phase {
                            active_share: eps_share,
                            ..phase(
                                common,
                                &domain,
                                &in_domain(eps),
                                false,
                                request.tol.max(eps_phase_tol),
                            )
                        },
                        z,
                        &mut work,
                        &mut trace,
                    )?;
                    z = r.z;
                    let boundary: Vec<f64> = work
                        .cells
                        .cells
                        .iter()
                        .filter(|c| c.on_boundary())
                        .map(|c| c.h)
                        .collect();
                    let eps_new = boundary.iter().sum::<f64>() / boundary.len().max(1) as f64;
                    if (eps_new - eps).abs() < self.eps_tol * spacing {
                        settled = true;
                        break;
                    }
                    // Every cell reaches ∂Ω_ε: the mean farthest distance grows with ε
                    // itself, and may have no fixed point (a part that gets little more than
                    // its corners' generators). Followed then, Ω_ε grows without end, each
                    // ε-phase costs more than the last, and a size field's values far outside
                    // Ω (an extension, not the field) draw the generators away
                    // (docs/design-notes.md, "Algorithm 2's edge cases"). A ring thinner than
                    // the spacing has one all the same, reached by steps that shrink. So ε is
                    // followed while its steps shrink, and stays where it is once they do not.
                    let change = (eps_new - eps).abs();
                    if boundary.len() == work.cells.cells.len()
                        && last_change.is_some_and(|last| change > EPS_HOLD_RATIO * last)
                    {
                        held = true;
                        break;
                    }
                    // The first estimate, from Ω itself, is where the iteration starts, not
                    // one of its steps.
                    if eps > 0.0 {
                        last_change = Some(change);
                    }
                    if request.out_of_time() {
                        break;
                    }
                    let mut next = eps_new;
                    let next_domain = holes.expand(region, &mut next, tol_poly);
                    // A larger ε would close a hole, and the reduced one is the ε just used:
                    // the estimate has no fixed point Ω_ε can reach, and followed it would
                    // come back to this ε in every update (each one expanding Ω_ε several
                    // times). ε settles at the largest value that keeps every hole.
                    if next < eps_new && (next - eps).abs() < self.eps_tol * spacing {
                        settled = true;
                        capped = Some(eps_new);
                        break;
                    }
                    eps = next;
                    domain = next_domain;
                }
                tally.converged &= settled;
                if let Some(widest) = holes.closing.iter().copied().reduce(f64::max) {
                    notes.push(format!(
                        "epsilon reduced by a fifth {} where Omega_epsilon closed a hole \
                         (the largest that did: {widest:.4e})",
                        match holes.closing.len() {
                            1 => "once".to_string(),
                            n => format!("{n} times"),
                        }
                    ));
                }
                notes.push(format!(
                    "epsilon = {eps:.6e} ({:.4} of the spacing){}",
                    eps / spacing,
                    if let Some(estimate) = capped {
                        format!(
                            ", held below its estimate {estimate:.4e}, which would close a hole"
                        )
                    } else if settled {
                        String::new()
                    } else if held {
                        ", not settled: held where every cell reaches the boundary and its \
                         estimate does not converge (too few generators for Algorithm 2's \
                         estimate)"
                            .to_string()
                    } else {
                        ", not settled".to_string()
                    }
                ));
                domain
            }
        };
        // Step 4 / Algorithm 1: constrained iteration, boundary centroids projected onto ∂Ω.
        work.retarget(&final_domain);
        let r = tally.run(
            &Phase {
                update: self.update,
                project_first: matches!(run, Run::FromRow),
                ..phase(common, &final_domain, &in_region, true, request.tol)
            },
            z,
            &mut work,
            &mut trace,
        )?;
        let markers: Vec<VertexMarker> =
            r.z.iter()
                .zip(&r.roles)
                .map(|(p, role)| match *role {
                    Role::Interior | Role::Embedded(_) => VertexMarker::Interior,
                    Role::Corner(c) => VertexMarker::at_corner(region, c),
                    Role::Boundary(j) => VertexMarker::on_piece(region, *p, j),
                })
                .collect();
        if tally.stalled {
            notes.push(format!(
                "stopped unconverged: the largest move made no new low in the work of {} \
                 evaluations (the iterate cycles); more points, or a corner angle keeping \
                 fewer corners (corner_angle, --corner-angle), give the generators room",
                crate::newton::STALL_EVALUATIONS
            ));
        }
        let generators = Generators {
            points: r.z,
            markers,
            iterations: tally.iterations,
            converged: tally.converged,
            stalled: tally.stalled,
            energy_history: trace.energies,
            move_history: trace.moves,
            notes,
            profile: trace.prof,
        };
        Ok((generators, work.del))
    }
}

impl Generators {
    /// This coarse level's record followed by the finer level `fine` solved from its
    /// prolongation: iterations, histories and profiles add up; convergence is the fine
    /// level's (a coarse level only provides the start).
    fn then(mut self, mut fine: Generators, coarse_k: usize) -> Generators {
        let mut notes = std::mem::take(&mut self.notes);
        notes.push(format!(
            "started from a CCVT of {coarse_k} generators, every edge of its mesh split"
        ));
        notes.append(&mut fine.notes);
        self.followed_by(fine, notes)
    }

    /// A stalled run from a coarser level (`self`) followed by the run `again` without
    /// levels: `again`'s generators and convergence, the evaluations and histories of both.
    fn then_again(self, mut again: Generators) -> Generators {
        let mut notes = vec![format!(
            "the run from a coarser level stopped unconverged after {} evaluations (the \
             iterate cycled); solved again without levels",
            self.iterations
        )];
        notes.append(&mut again.notes);
        self.followed_by(again, notes)
    }

    /// `next`'s generators and convergence with `notes`, after `self`'s evaluations, histories
    /// and profile.
    fn followed_by(self, next: Generators, notes: Vec<String>) -> Generators {
        let mut energy_history = self.energy_history;
        energy_history.extend(next.energy_history);
        let mut move_history = self.move_history;
        move_history.extend(next.move_history);
        let mut profile = self.profile;
        profile.add(&next.profile);
        Generators {
            points: next.points,
            markers: next.markers,
            iterations: self.iterations + next.iterations,
            converged: next.converged,
            stalled: next.stalled,
            energy_history,
            move_history,
            notes,
            profile,
        }
    }
}

/// What a solve runs from its start.
#[derive(Clone, Copy)]
enum Run {
    /// The algorithm as the paper states it (with the `Init::Cvt` phase of Algorithm 1).
    Paper(Algorithm),
    /// Algorithm 1's constrained iteration alone, from a start that already has the target
    /// spacing (a graded start, a prolongated coarse level).
    Relax,
    /// Algorithm 2 from the boundary row start (`start::boundary_row`): its ε-phase starts
    /// from the lattice's CVT inside a row, where only the seam between the two has far to
    /// move, and takes active-set steps with a larger share of its generators moving; its
    /// constrained phase takes the projection onto ∂Ω before any Newton step
    /// (`Phase::project_first`).
    FromRow,
}

/// Iterations and convergence summed over the phases of one solve.
struct Tally<'a> {
    method: &'static str,
    request: &'a MeshRequest,
    iterations: usize,
    converged: bool,
    /// A phase stopped because its largest move stopped falling.
    stalled: bool,
}

impl Tally<'_> {
    /// Run one phase from `z` and add it to the totals; a cancelled request stops the solve
    /// here.
    fn run(
        &mut self,
        phase: &Phase,
        z: Vec<geometry::DVec2>,
        work: &mut Work,
        trace: &mut Trace,
    ) -> Result<PhaseResult, MeshError> {
        let r = run(phase, z, work, trace);
        self.iterations += r.iterations;
        self.request.check_cancel(self.method, self.iterations)?;
        self.converged &= r.converged;
        self.stalled |= r.stalled;
        Ok(r)
    }
}

impl Mesher for Ccvt {
    // Only the graded start spaces the points as the density asks before the iteration.
    fn follows_size_fields(&self) -> bool {
        self.graded_start
    }

    fn name(&self) -> &'static str {
        if self.update == Update::Odt {
            return "ccvt1-odt";
        }
        match (self.algorithm, self.solver) {
            (Algorithm::One, Solver::Lloyd) => "ccvt1",
            (Algorithm::Two, Solver::Lloyd) => "ccvt2",
            (Algorithm::One, Solver::Anderson { .. }) => "ccvt1-anderson",
            (Algorithm::Two, Solver::Anderson { .. }) => "ccvt-anderson",
            (Algorithm::One, Solver::Newton) => "ccvt1-fast",
            (Algorithm::Two, Solver::Newton) => "ccvt",
        }
    }

    fn mesh(
        &self,
        region: &Region,
        request: &MeshRequest,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<MeshResult, MeshError> {
        let (g, mut del) = self.solved(region, request, progress)?;
        let mesh = if g.points.len() >= MESH_FROM_SOLVE {
            tessellation::conforming_mesh_from(&mut del, &g.points, &g.markers, region)?
        } else {
            tessellation::conforming_mesh(&g.points, &g.markers, region)?
        };
        let mut notes = g.notes;
        if mesh.num_vertices() < g.points.len() {
            notes.push(format!(
                "{} generators outside the boundary polygon were dropped from the mesh",
                g.points.len() - mesh.num_vertices()
            ));
        }
        Ok(MeshResult {
            mesh,
            iterations: g.iterations,
            converged: g.converged,
            energy_history: g.energy_history,
            move_history: g.move_history,
            notes,
        })
    }
}

/// What Algorithm 2's ε loop knows of the limit the holes set on ε: every ε that closed a hole
/// (for a note), the largest that kept them all, and an ε above which one surely closes.
struct HoleLimit {
    closing: Vec<f64>,
    keeps: f64,
    /// The smallest hole's radius of equal area, plus the polygon's tolerance: no disc wider
    /// than that fits in the hole, so Ω_ε covers it for any larger ε. Expanding there is
    /// wasted, and dearest just past a round hole's radius, where the offsets of all its
    /// edges cross one another.
    surely_closes: f64,
}

impl HoleLimit {
    fn new(region: &Region, tol: f64) -> HoleLimit {
        let smallest = region
            .loops()
            .iter()
            .filter(|l| l.role == geometry::LoopRole::Hole)
            .map(|l| {
                let area: f64 = l
                    .pieces
                    .iter()
                    .map(|&p| region.pieces()[p].area_integral())
                    .sum();
                (area.abs() / std::f64::consts::PI).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        HoleLimit {
            closing: Vec::new(),
            keeps: 0.0,
            surely_closes: smallest + tol,
        }
    }

    /// Ω_ε, with ε reduced by fifths until no hole vanishes (a hole without boundary generators
    /// could not be meshed), but never below the largest ε that kept every hole; an ε at or
    /// above the smallest that closed one starts a fifth below that one. Once the limit is
    /// bracketed, every estimate past it comes to the same ε, which is how the ε loop sees ε
    /// settle there instead of alternating between an estimate that keeps the holes and one
    /// that does not.
    fn expand(&mut self, region: &Region, eps: &mut f64, tol: f64) -> geometry::Polygon {
        if let Some(closes) = self.closing.iter().copied().reduce(f64::min) {
            if *eps >= closes {
                *eps = (0.8 * closes).max(self.keeps);
            }
        }
        loop {
            if *eps <= self.surely_closes {
                let poly = region.expand(*eps, tol);
                if poly.rings.len() == region.loops().len() {
                    self.keeps = self.keeps.max(*eps);
                    return poly;
                }
            }
            self.closing.push(*eps);
            *eps = (0.8 * *eps).max(self.keeps);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::{DVec2, SizeField, Threshold, Toward};

    /// Levels are taken from the threshold on, by the threshold of the run's own kind, and
    /// never where the coarser level would be refused: a coastline with 1597 corners at
    /// K = 3000 has a coarse count of about a thousand.
    #[test]
    fn a_coarser_level_is_taken_only_where_it_is_a_valid_request() {
        let ccvt = Ccvt {
            graded_multilevel_from: 2000,
            ..Ccvt::default()
        };
        let graded = |region: &Region| {
            let field = SizeField::from_expr("0.02 + 0.05 * x * x").unwrap();
            MeshRequest::size_field(&field, region, Some(3000)).unwrap()
        };
        let coarser = |region: &Region, request: &MeshRequest| {
            let k = request.validate(region).unwrap();
            let scale = LocalScale::new(region, &request.density, request.spacing(region));
            ccvt.coarser(region, request, &scale, k)
        };
        let circle = Region::builtin("circle").unwrap();
        let many = |region: &Region, k: usize| {
            let field = SizeField::from_expr("0.02 + 0.05 * x * x").unwrap();
            MeshRequest::size_field(&field, region, Some(k)).unwrap()
        };
        let (coarse_k, coarse) = coarser(&circle, &many(&circle, 40_000)).unwrap();
        assert!((9_900..10_300).contains(&coarse_k), "{coarse_k}");
        assert_eq!(coarse.validate(&circle).unwrap(), coarse_k);
        assert!(coarser(&circle, &MeshRequest::points(40_000)).is_none());
        // At 3000 generators about 5 % of them lie on the circle: no levels.
        assert!(coarser(&circle, &graded(&circle)).is_none());
        // The lake refined toward its shores puts 5.5 % of 10⁵ generators on them: no levels;
        // toward one point inside, 0.4 %: levels.
        let lake = Region::builtin("lake").unwrap();
        let toward = |targets: &[Toward], t| {
            let field = SizeField::threshold(&lake, targets, t).unwrap();
            MeshRequest::size_field(&field, &lake, Some(100_000)).unwrap()
        };
        let t = Threshold {
            size_min: 1.0,
            size_max: 5.0,
            dist_min: 0.0,
            dist_max: 35.0,
        };
        assert!(coarser(&lake, &toward(&[Toward::Loop(0), Toward::Loop(1)], t)).is_none());
        // The point deepest inside on a 40 × 40 grid of the lake's box.
        let (lo, hi) = lake.bbox();
        let inside = (0..1600)
            .map(|i| {
                lo + (hi - lo) * DVec2::new((i % 40) as f64 + 0.5, (i / 40) as f64 + 0.5) / 40.0
            })
            .min_by(|a, b| {
                lake.signed_distance(*a)
                    .total_cmp(&lake.signed_distance(*b))
            })
            .unwrap();
        assert!(coarser(&lake, &toward(&[Toward::Point(inside)], t)).is_some());
        let text = include_str!("../tests/data/coast5000.txt");
        let coast = geometry::formats::loops_from_str(text, "coast5000", "coast5000")
            .unwrap()
            .with_default_corners();
        assert!(coast.corners().len() > 1500);
        let request = graded(&coast);
        assert_eq!(request.validate(&coast).unwrap(), 3000);
        assert!(coarser(&coast, &request).is_none());
    }
}
