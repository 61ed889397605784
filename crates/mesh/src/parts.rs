//! Regions of several parts: each part meshed on its own with its share of K, the meshes
//! merged into one whose markers speak of the whole region.
use crate::{
    check_conforming, thin_feature, Mesh, MeshError, MeshRequest, MeshResult, Mesher, Progress,
    Size, VertexMarker,
};
use geometry::{DVec2, Density, Part, Piece, Region, SpacingCorners};

/// Implements [`Mesher::mesh_parts`].
pub(crate) fn mesh_parts<M: Mesher + ?Sized>(
    mesher: &M,
    region: &Region,
    request: &MeshRequest,
    progress: &mut dyn FnMut(Progress),
) -> Result<MeshResult, MeshError> {
    // An embedded line's vertices, placed at the local spacing, are points every mesh keeps,
    // unless the method keeps the lines as it meshes.
    let with_points;
    let lined = (!region.embedded_lines().is_empty()).then_some(region);
    let (region, pieces) = if lined.is_none() || mesher.meshes_embedded_lines() {
        (region, None)
    } else {
        with_points = crate::lines::with_line_points(region, request)?;
        (&with_points.0, Some(&with_points.1))
    };
    let (bent, unfitted) = match with_spacing_corners(region, request) {
        Fit::Added(b) => (Some(*b), None),
        Fit::TooMany { needed } => (None, Some(needed)),
        Fit::None => (None, None),
    };
    let work = bent.as_ref().map_or(region, |b| &b.region);
    // Where the corners did not fit, a failure says how many points would have given them room.
    let unfitted_hint = |needed: usize| {
        format!(
            "at this spacing the boundary's bends and gaps need {needed} boundary vertices, more \
             than K = {}: a larger K would follow them, or a boundary simplified to the mesh's \
             scale (simplify \"auto\", --simplify auto) would need fewer",
            request.size.points(region)
        )
    };
    let run = if work.num_parts() <= 1 {
        mesher.mesh(work, request, progress)
    } else {
        mesh_each_part(mesher, work, request, progress)
    };
    let mut result = match (run, unfitted) {
        (Ok(r), _) => r,
        (Err(MeshError::BadRequest(m)), Some(needed)) => {
            return Err(MeshError::BadRequest(format!(
                "{m}; {}",
                unfitted_hint(needed)
            )))
        }
        (Err(e), _) => return Err(e),
    };
    // A triangulation of points spaced along a line has the edges between them unless a point
    // off the line crowds one; flips restore those before the polish, which holds the line's
    // vertices.
    let missing = |mesh: &Mesh| crate::lines::line_edges(mesh, region).is_err();
    if pieces.is_some_and(|pieces| {
        missing(&result.mesh) && !crate::lines::restore_line_edges(&mut result.mesh, pieces)
    }) {
        return Err(MeshError::Failed {
            method: mesher.name().to_string(),
            message: "an embedded line has a piece between two of its vertices that no flip of \
                      the mesh's edges could make an edge (lines nearly meeting there, closer \
                      than the spacing); ask for more points, or use the refine method \
                      (--method refine, method=\"refine\"), which splits lines where they \
                      nearly meet as Triangle does"
                .into(),
        });
    }
    if !request.density.is_uniform() && !mesher.follows_size_fields() {
        result.notes.push(format!(
            "{} starts from a uniform lattice that the density only reshapes, and follows a \
             size field loosely (edges within √2 of their size: 79–97 % for MESHGEN, VTM, \
             CCVT(1) and CCVT(2) in the graded study, against 99.5–100 % for ccvt and distmesh)",
            mesher.name()
        ));
    }
    if !result.converged && request.out_of_time() {
        result
            .notes
            .push("stopped at the time limit before converging".into());
    }
    // Whether the mesh as it stands has passed the conformity check against `region` (the
    // polish checks what it moved; with corners added at bends the check was of `work`).
    let mut checked = false;
    // Polished in the terms of the region the method meshed, so that corners added at bends
    // stay put; undone if the polished mesh leaves the region (a boundary edge moved across a
    // narrow gap), which the check below would refuse.
    if request.polish_below_deg > 0.0 {
        // Undone, the method's own mesh meets the check below as it would have.
        // A graded mesh's largest and smallest elements are its size field's: sizes are held for
        // a uniform density only, shapes always.
        let uniform = request.density.is_uniform();
        let report = crate::polish::within(
            &mut result.mesh,
            work,
            request.polish_below_deg,
            uniform,
            &[],
        );
        checked = report.checked && bent.is_none();
        if report.polished.moved > 0 {
            result.notes.push(report.to_string());
        }
    }
    if let Some(bent) = &bent {
        unbend(&mut result.mesh, bent, region);
        result.notes.push(format!(
            "corners: {} added where a boundary edge of the local spacing would stray more than \
             {} of its length from a bend, {} along gaps narrower than {} spacings",
            bent.bends,
            geometry::BEND_TOLERANCE,
            bent.gaps,
            geometry::GAP_SPACINGS
        ));
    }
    // A method may hand back a mesh that leaves the region where the region is far thinner
    // than the spacing; the caller gets an error naming the place instead.
    if !checked && result.mesh.num_vertices() <= CONFORMITY_CHECK_LIMIT {
        if let Err(cause) = check_conforming(&result.mesh, region) {
            let hint = match (thin_feature(region, request), unfitted) {
                (Some(thin), _) => thin.to_string(),
                (None, Some(needed)) => unfitted_hint(needed),
                (None, None) => {
                    "try a larger K, or keep every corner (corner_angle 0, --corner-angle 0)".into()
                }
            };
            return Err(MeshError::NotConforming {
                method: mesher.name().to_string(),
                cause,
                hint,
            });
        }
    }
    // A mesh over less than half the region whose boundary vertices bunch on part of a loop
    // is not a mesh of it, whatever the method's own test of convergence said (MESHGEN and
    // VTM at K = 6 on the disc can end with every boundary vertex on one arc, 1.8 % of the
    // disc covered). Spread vertices too few for a curve (a triangle in the disc) are a
    // coarse mesh, which `short_coverage` names.
    let share = result.mesh.area() / region.area();
    if share < MIN_SHARE {
        if let Some((l, span)) = widest_boundary_edge(&result.mesh, region).filter(|w| w.1 > 0.5) {
            return Err(MeshError::Failed {
                method: mesher.name().to_string(),
                message: format!(
                    "the mesh covers {:.1} % of the region's area, its boundary vertices \
                     bunched on part of loop {l} (one boundary edge cuts across {:.0} % of \
                     it): at K = {} this method gives no mesh of the region; ask for more \
                     points or use another method",
                    100.0 * share,
                    100.0 * span,
                    result.mesh.num_vertices()
                ),
            });
        }
    }
    // Every point the region embeds is a vertex, or the caller hears which is not: one closer
    // to a curved boundary than its chords at this spacing cannot be a vertex of the mesh.
    if !region.embedded_points().is_empty() {
        let vertices: std::collections::HashSet<(u64, u64)> = result
            .mesh
            .points
            .iter()
            .map(|p| (p.x.to_bits(), p.y.to_bits()))
            .collect();
        if let Some(&(p, _)) = region
            .embedded_points()
            .iter()
            .find(|(p, _)| !vertices.contains(&(p.x.to_bits(), p.y.to_bits())))
        {
            return Err(MeshError::Failed {
                method: mesher.name().to_string(),
                message: format!(
                    "the embedded point ({}, {}) is not a vertex of the mesh: it lies closer to \
                     the boundary than the mesh's boundary edges follow it; move it inward or \
                     ask for more points",
                    p.x, p.y
                ),
            });
        }
    }
    // The line's pieces are edges still (the polish moves no vertex of a line): checked, as a
    // method's own triangulation could have lost one no flip restored.
    if let Some(lines) = lined {
        crate::lines::line_edges(&result.mesh, lines).map_err(|e| match e {
            MeshError::Failed { message, .. } => MeshError::Failed {
                method: mesher.name().to_string(),
                message,
            },
            e => e,
        })?;
    }
    Ok(result)
}

/// Below this share of the region's area covered, [`Mesher::mesh_parts`] refuses a mesh whose
/// boundary vertices bunch on part of a loop. The coarsest mesh of a disc with its boundary
/// vertices spread, a triangle, covers 41 %; a square 64 %.
const MIN_SHARE: f64 = 0.5;

/// The boundary edge that spans the largest share of its loop's length, measured along the
/// loop from its start to its end (the mesh on the edge's left, the region on the loop's):
/// the loop and that share. An edge that follows its loop spans less than half of it, as a
/// chord is no longer than the rest of the loop. None where the vertices know no positions.
fn widest_boundary_edge(mesh: &Mesh, region: &Region) -> Option<(usize, f64)> {
    let param = |v: u32| {
        mesh.markers[v as usize]
            .loop_param()
            .filter(|s| s.is_finite())
    };
    mesh.boundary_edges()
        .iter()
        .filter_map(|e| {
            let length = region.loops().get(e.loop_index)?.length;
            let span = (param(e.b)? - param(e.a)?).rem_euclid(length) / length;
            // A step back by rounding (an end a hair behind the start) is no span.
            (span < 1.0 - 1e-9).then_some((e.loop_index, span))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

/// What [`with_spacing_corners`] found.
enum Fit {
    /// Corners added.
    Added(Box<SpacingCorners>),
    /// Corners needed, but with them the boundary would need `needed` vertices, more than K.
    TooMany { needed: usize },
    /// No corner needed (or no polyline piece to add one to).
    None,
}

/// `region` with the corners the spacing `request` asks for needs
/// ([`Region::with_spacing_corners`]), unless there are none or K could not give each a
/// vertex.
fn with_spacing_corners(region: &Region, request: &MeshRequest) -> Fit {
    if !region
        .pieces()
        .iter()
        .any(|p| matches!(p, Piece::Chain(_) | Piece::Line { .. }))
    {
        return Fit::None;
    }
    let k = request.size.points(region);
    let bent = region.with_spacing_corners(&request.spacing_at(region));
    let needed = crate::boundary_points_needed(&bent.region);
    if bent.added() == 0 {
        Fit::None
    } else if needed > k {
        Fit::TooMany { needed }
    } else {
        Fit::Added(Box::new(bent))
    }
}

/// Markers of a mesh of `bent.region` renumbered to speak of `region`: an added corner
/// becomes a boundary vertex of the piece it lies on. Arc-length positions are the same in
/// both.
fn unbend(mesh: &mut Mesh, bent: &SpacingCorners, region: &Region) {
    debug_assert_eq!(bent.pieces.len(), bent.region.pieces().len());
    debug_assert!(region.pieces().len() <= bent.pieces.len());
    for m in &mut mesh.markers {
        *m = match *m {
            VertexMarker::Interior => VertexMarker::Interior,
            VertexMarker::Boundary {
                loop_index,
                piece,
                loop_param,
            } => VertexMarker::Boundary {
                loop_index,
                piece: bent.pieces[piece],
                loop_param,
            },
            VertexMarker::Corner {
                loop_index,
                corner,
                loop_param,
            } => match bent.corners[corner] {
                Some(c) => VertexMarker::Corner {
                    loop_index,
                    corner: c,
                    loop_param,
                },
                None => VertexMarker::Boundary {
                    loop_index,
                    piece: bent.pieces[bent.region.corners()[corner].piece_out],
                    loop_param,
                },
            },
        };
    }
}

/// The largest mesh [`Mesher::mesh_parts`] checks for conformity before returning it (the
/// check takes about a quarter of a second at 10⁶ vertices on two cores: `cargo bench -p
/// cvtmesh-mesh --bench check`).
pub const CONFORMITY_CHECK_LIMIT: usize = 2_000_000;

/// Each part meshed with its share of K, the meshes merged.
fn mesh_each_part<M: Mesher + ?Sized>(
    mesher: &M,
    region: &Region,
    request: &MeshRequest,
    progress: &mut dyn FnMut(Progress),
) -> Result<MeshResult, MeshError> {
    let k = request.validate_whole(region)?;
    let parts = region.parts();
    // Each part's boundary, and a vertex for each point it embeds.
    let needs: Vec<usize> = parts
        .iter()
        .map(|p| mesher.min_boundary_points(&p.region) + p.region.embedded_points().len())
        .collect();
    let needed: usize = needs.iter().sum();
    if needed > k {
        return Err(MeshError::BadRequest(format!(
            "K = {k} is too small for region '{}' with {}: its {} parts' boundaries need {needed} \
             vertices ({})",
            region.name(),
            mesher.name(),
            parts.len(),
            needs
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(" + ")
        )));
    }
    let shares = shares(k, &parts, &request.density, &needs);
    let mut merged = MeshResult {
        mesh: Mesh::default(),
        iterations: 0,
        converged: true,
        energy_history: Vec::new(),
        move_history: Vec::new(),
        notes: Vec::new(),
    };
    // The energy is a sum over cells: while part i runs, the region's energy is that of the
    // parts before it, as they ended, plus part i's own.
    let mut finished = 0.0;
    for (i, (part, &ki)) in parts.iter().zip(&shares).enumerate() {
        let mut r = request.clone();
        r.size = Size::Points(ki);
        let result = mesher.mesh(&part.region, &r, progress)?;
        merged.notes.push(format!(
            "part {i}: K = {} on area {:.6e} ({:.1} % of the region){}",
            result.mesh.num_vertices(),
            part.region.area(),
            100.0 * part.region.area() / region.area(),
            if result.converged {
                ""
            } else {
                ", NOT CONVERGED"
            }
        ));
        merged
            .notes
            .extend(result.notes.iter().map(|n| format!("part {i}: {n}")));
        merge(&mut merged.mesh, result.mesh, part)?;
        merged.iterations += result.iterations;
        merged.converged &= result.converged;
        merged
            .energy_history
            .extend(result.energy_history.iter().map(|e| finished + e));
        finished += result.energy_history.last().copied().unwrap_or(0.0);
        merged.move_history.extend(result.move_history);
    }
    Ok(merged)
}

/// Appends a part's mesh, its vertex numbers offset and its markers renumbered from the
/// part's loops, pieces and corners to the whole region's.
fn merge(into: &mut Mesh, mesh: Mesh, part: &Part) -> Result<(), MeshError> {
    let offset = u32::try_from(into.points.len())
        .ok()
        .filter(|o| u32::try_from(mesh.points.len()).is_ok_and(|n| o.checked_add(n).is_some()))
        .ok_or_else(|| MeshError::BadRequest("more vertices than a mesh can number".into()))?;
    into.points.extend(mesh.points);
    into.triangles
        .extend(mesh.triangles.iter().map(|t| t.map(|v| v + offset)));
    into.markers
        .extend(mesh.markers.into_iter().map(|m| match m {
            VertexMarker::Interior => VertexMarker::Interior,
            VertexMarker::Boundary {
                loop_index,
                piece,
                loop_param,
            } => VertexMarker::Boundary {
                loop_index: part.loops[loop_index],
                piece: part.pieces[piece],
                loop_param,
            },
            VertexMarker::Corner {
                loop_index,
                corner,
                loop_param,
            } => VertexMarker::Corner {
                loop_index: part.loops[loop_index],
                corner: part.corners[corner],
                loop_param,
            },
        }));
    Ok(())
}

/// Each part's share of `k` vertices: in proportion to the count the density asks for there,
/// ∫ ρ^(1/2) (spacing ∝ ρ^(-1/4), so vertices per area ∝ ρ^(1/2); its area for ρ ≡ 1), but at
/// least what its boundary needs (`needs`, from [`Mesher::min_boundary_points`](crate::Mesher::min_boundary_points)). The shares
/// add up to `k`, which must be at least the parts' needs together (checked by the caller).
pub(crate) fn shares(k: usize, parts: &[Part], density: &Density, needs: &[usize]) -> Vec<usize> {
    let weights: Vec<f64> = parts.iter().map(|p| weight(&p.region, density)).collect();
    allocate(k, &weights, needs)
}

/// Largest-remainder apportionment of `k` by `weights`, each share at least its `need`.
/// Parts whose proportional share falls below their need get their need, and the rest is
/// shared among the others in proportion; if every part is short, each gets its need and the
/// surplus goes to the heaviest. Weights that are not positive numbers count as zero (all
/// zero: equal shares).
pub(crate) fn allocate(k: usize, weights: &[f64], needs: &[usize]) -> Vec<usize> {
    let n = weights.len();
    let w: Vec<f64> = weights
        .iter()
        .map(|&x| if x.is_finite() && x > 0.0 { x } else { 0.0 })
        .collect();
    let mut fixed = vec![false; n];
    loop {
        let free: Vec<usize> = (0..n).filter(|&i| !fixed[i]).collect();
        let rest = k.saturating_sub((0..n).filter(|&i| fixed[i]).map(|i| needs[i]).sum());
        let total: f64 = free.iter().map(|&i| w[i]).sum();
        let weight = |i: usize| if total > 0.0 { w[i] } else { 1.0 };
        let total = if total > 0.0 {
            total
        } else {
            free.len() as f64
        };
        let ideal = |i: usize| rest as f64 * weight(i) / total;
        let short: Vec<usize> = free
            .iter()
            .copied()
            .filter(|&i| ideal(i) < needs[i] as f64)
            .collect();
        if short.len() == free.len() {
            let mut out = needs.to_vec();
            let used: usize = out.iter().sum();
            if let Some(big) = (0..n).max_by(|&a, &b| w[a].total_cmp(&w[b]).then(b.cmp(&a))) {
                out[big] += k.saturating_sub(used);
            }
            return out;
        }
        if short.is_empty() {
            let mut out: Vec<usize> = (0..n)
                .map(|i| {
                    if fixed[i] {
                        needs[i]
                    } else {
                        ideal(i).floor() as usize
                    }
                })
                .collect();
            let mut left = rest.saturating_sub(free.iter().map(|&i| out[i]).sum());
            let mut order = free.clone();
            let frac = |i: usize| ideal(i) - ideal(i).floor();
            order.sort_by(|&a, &b| frac(b).total_cmp(&frac(a)).then(a.cmp(&b)));
            for i in order {
                if left == 0 {
                    break;
                }
                out[i] += 1;
                left -= 1;
            }
            return out;
        }
        for i in short {
            fixed[i] = true;
        }
    }
}

/// ∫ ρ^(1/2) over a part (its area for a uniform density), estimated on a 128 × 128 grid of
/// cell centres over its bounding box; a part too small for the grid takes ρ at the centre
/// of its bounding box times its area.
pub(crate) fn weight(region: &Region, density: &Density) -> f64 {
    if density.is_uniform() {
        return region.area();
    }
    const N: usize = 128;
    let (lo, hi) = region.bbox();
    let (mut sum, mut inside) = (0.0, 0usize);
    for i in 0..N {
        for j in 0..N {
            let p = lo
                + (hi - lo) * DVec2::new((i as f64 + 0.5) / N as f64, (j as f64 + 0.5) / N as f64);
            if region.contains(p) {
                sum += density.at(p).max(0.0).sqrt();
                inside += 1;
            }
        }
    }
    let mean = if inside > 0 {
        sum / inside as f64
    } else {
        density.at((lo + hi) / 2.0).max(0.0).sqrt()
    };
    mean * region.area()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_follow_the_weights_and_add_up() {
        assert_eq!(allocate(100, &[1.0, 1.0, 2.0], &[3, 3, 3]), [25, 25, 50]);
        assert_eq!(allocate(10, &[1.0, 1.0, 1.0], &[3, 3, 3]), [4, 3, 3]);
        // A tiny part gets its need, the rest is shared by the others.
        assert_eq!(allocate(100, &[1e-6, 1.0, 1.0], &[6, 3, 3]), [6, 47, 47]);
        // Every part at its need, the surplus to the largest.
        assert_eq!(allocate(13, &[1.0, 2.0], &[6, 6]), [6, 7]);
        for k in [15, 16, 50, 333, 1001] {
            let s = allocate(k, &[0.3, 0.01, 5.0, 1.2], &[3, 3, 3, 6]);
            assert_eq!(s.iter().sum::<usize>(), k, "{s:?}");
            assert!(s.iter().zip([3, 3, 3, 6]).all(|(a, b)| *a >= b), "{s:?}");
        }
    }
}
