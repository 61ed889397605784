//! What `cvtmesh mesh FILE` meshes again: the region a mesh's triangles cover, with the walls
//! and points its file numbers; shared by the mesh readers' targets.

/// The region of `m` and `walls`, if it is one, checked: it has loops, and each point the file
/// marks on its own is a vertex of the mesh and a corner of the region.
pub fn checked(m: &mesh::Mesh, walls: &mesh::io::Walls) -> Option<geometry::Region> {
    let r = geometry::Region::from_triangles_pinned(
        "fuzz",
        &m.points,
        &m.triangles,
        &walls.edges,
        &walls.points,
    )
    .ok()?;
    assert!(!r.loops().is_empty());
    let c = r.with_default_corners();
    for (p, _) in r.vertex_markers() {
        assert!(m.points.contains(p) && c.corners().iter().any(|k| k.pos == *p));
    }
    Some(r)
}
