//! Region files: the JSON schema of the built-in regions in `regions/` (see
//! `regions/SOURCES.md` in this crate).
//!
//! Only `loops` is required. Each loop is an object with `segments` (required, non-empty),
//! `role` (`"outer"` | `"hole"`; default: nesting decides, a loop inside no loop or inside a
//! hole is outer, a loop inside an outer loop is a hole of it; several outer loops make a
//! region of several parts) and
//! `orientation` (`"ccw"` | `"cw"`; only gives circles and super-ellipses their direction,
//! and orientation is normalised anyway). Segment kinds:
//! - `polyline`: `points` (≥ 2), each straight edge a `Piece::Line`;
//! - `arc`: `center`, `radius`, `from_deg`, `to_deg` (CCW when to > from); optional `start`
//!   and `end` must agree with the computed end points (to 1e-9·radius);
//! - `circle`: `center`, `radius`;
//! - `superellipse`: `center`, `a`, `b`, `exponent` (≥ 2);
//! - `parametric`: `points` (≥ 2), a dense sampling used as one `Piece::Chain`
//!   (`formula`/`t_range` are documentation only).
//!
//! Any segment may carry `marker` (an integer, as a `.poly`'s segment markers number walls for
//! boundary conditions): its pieces get that marker ([`Region::piece_markers`]; 0 for a
//! segment without one, where some have one), and a junction where the marker changes is a
//! corner, so a mesh has a vertex there even where the boundary runs smoothly on.
//!
//! `lines` (optional) lists polylines to keep in every mesh as edges (a material interface, a
//! crack, an inclusion's outline), each `{"points": [[x, y], ...], "marker": m}` (`marker`
//! optional; closed when the last point is the first): see [`Region::with_embedded_lines`].
//!
//! A segment or a line may carry `name` as well (`"inlet"`, `"fault"`): the name of its marker
//! ([`Region::marker_names`]), which a `.msh` file gives its physical curve, as Gmsh's physical
//! names do. A name without a marker gets the next number past every marker the file gives,
//! one per name (two lines named `"fault"` share it); one marker with two names is refused.
//!
//! `subdomains` (optional) numbers the parts the lines cut the region into, each
//! `{"point": [x, y], "id": n}` (the part holding the point gets `n`), with an optional
//! `"name"` for the `.msh` files' physical surface: see
//! [`Region::with_subdomain_points`].
//!
//! `corners` (optional) lists every tangent discontinuity; an empty list means none, and
//! without the field corners are computed. `name` (optional) names the region; otherwise
//! the file stem. Every other field (`area`, `bbox`, `length`, ...) is ignored: all derived
//! quantities are recomputed.
use crate::error::GeometryError;
use crate::piece::Piece;
use crate::region::Region;
use crate::types::LoopRole;
use glam::DVec2;
use serde_json::{Map, Value};
use std::sync::OnceLock;

/// Built-in regions in the paper's table order.
pub const BUILTIN_NAMES: &[&str] = &{
    let mut names = [""; BUILTIN_FILES.len()];
    let mut i = 0;
    while i < names.len() {
        names[i] = BUILTIN_FILES[i].0;
        i += 1;
    }
    names
};

/// The built-in region files, embedded at compile time, in the paper's table order.
const BUILTIN_FILES: &[(&str, &str)] = &[
    ("circle", include_str!("../regions/circle.json")),
    ("annulus", include_str!("../regions/annulus.json")),
    ("square_hole", include_str!("../regions/square_hole.json")),
    ("hex_hole", include_str!("../regions/hex_hole.json")),
    ("horn", include_str!("../regions/horn.json")),
    ("superellipse", include_str!("../regions/superellipse.json")),
    ("bike_seat", include_str!("../regions/bike_seat.json")),
    ("pie_hole", include_str!("../regions/pie_hole.json")),
    (
        "square_two_hex",
        include_str!("../regions/square_two_hex.json"),
    ),
    ("lake", include_str!("../regions/lake.json")),
];

impl Region {
    /// Parse region JSON in the project's schema (see the module documentation of
    /// `file.rs` and `regions/SOURCES.md`); `label` names the source in errors and is the
    /// region's name unless the JSON has a `name`.
    ///
    /// ```
    /// use cvtmesh::geometry::Region;
    /// // A half disc of radius 1: an arc from 0° to 180° closed by a straight diameter.
    /// let json = r#"{"name": "half_disc", "loops": [{"segments": [
    ///     {"kind": "arc", "center": [0, 0], "radius": 1, "from_deg": 0, "to_deg": 180},
    ///     {"kind": "polyline", "points": [[-1, 0], [1, 0]]}
    /// ]}]}"#;
    /// let r = Region::from_json_str(json, "example")?;
    /// assert_eq!(r.name(), "half_disc");
    /// assert!((r.area() - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    /// assert_eq!(r.corners().len(), 2); // where the arc meets the diameter
    /// # Ok::<(), cvtmesh::geometry::GeometryError>(())
    /// ```
    pub fn from_json_str(text: &str, label: &str) -> Result<Region, GeometryError> {
        parse(text, label, label)
    }
    /// One of the paper's ten regions by name (`circle`, `lake`, ...).
    pub fn builtin(name: &str) -> Result<Region, GeometryError> {
        match BUILTIN_FILES.iter().find(|(n, _)| *n == name) {
            Some((n, text)) => parse(text, &format!("built-in region '{n}'"), n),
            None => Err(GeometryError::UnknownBuiltin(
                name.to_string(),
                BUILTIN_NAMES.join(", "),
            )),
        }
    }
    /// Names of the built-in regions, in the paper's table order.
    pub fn builtin_names() -> &'static [&'static str] {
        BUILTIN_NAMES
    }

    /// The K values of the paper's tables for the built-in region `name` (the `paper.K` field
    /// of its file), in table order; empty for any other name.
    ///
    /// ```
    /// use cvtmesh::geometry::Region;
    /// assert_eq!(Region::paper_k("circle"), [19, 88, 362]);
    /// assert!(Region::paper_k("nowhere").is_empty());
    /// ```
    pub fn paper_k(name: &str) -> &'static [usize] {
        static PAPER_K: OnceLock<Vec<Vec<usize>>> = OnceLock::new();
        let all = PAPER_K.get_or_init(|| {
            BUILTIN_FILES
                .iter()
                .map(|(n, text)| {
                    paper_k_of(text)
                        .unwrap_or_else(|| panic!("built-in region '{n}' has no list paper.K"))
                })
                .collect()
        });
        match BUILTIN_FILES.iter().position(|(n, _)| *n == name) {
            Some(i) => &all[i],
            None => &[],
        }
    }

    /// The title of the built-in region `name` (the `title` field of its file, what it is and
    /// where it comes from); None for any other name.
    ///
    /// ```
    /// use cvtmesh::geometry::Region;
    /// assert_eq!(Region::builtin_title("circle"), Some("Unit circle"));
    /// assert_eq!(Region::builtin_title("nowhere"), None);
    /// ```
    pub fn builtin_title(name: &str) -> Option<&'static str> {
        static TITLES: OnceLock<Vec<String>> = OnceLock::new();
        let all = TITLES.get_or_init(|| {
            BUILTIN_FILES
                .iter()
                .map(|(_, text)| {
                    serde_json::from_str::<Value>(text)
                        .ok()
                        .and_then(|v| v.get("title")?.as_str().map(str::to_string))
                        .unwrap_or_default()
                })
                .collect()
        });
        let i = BUILTIN_FILES.iter().position(|(n, _)| *n == name)?;
        Some(all[i].as_str())
    }

    /// Every (built-in region, K) of the paper's Tables 1–12, in table order.
    pub fn paper_cases() -> impl Iterator<Item = (&'static str, usize)> {
        BUILTIN_NAMES
            .iter()
            .flat_map(|&name| Region::paper_k(name).iter().map(move |&k| (name, k)))
    }
}

/// The `paper.K` list of a region file, if it has one of counts.
fn paper_k_of(text: &str) -> Option<Vec<usize>> {
    let v: Value = serde_json::from_str(text).ok()?;
    v.get("paper")?
        .get("K")?
        .as_array()?
        .iter()
        .map(|k| k.as_u64().and_then(|k| usize::try_from(k).ok()))
        .collect()
}

/// Parses region JSON; `label` names the source in errors, `default_name` is the region's
/// name when the file has no `name`.
pub(crate) fn parse(text: &str, label: &str, default_name: &str) -> Result<Region, GeometryError> {
    let perr = |message: String| GeometryError::Parse {
        path: label.to_string(),
        message,
    };
    let v: Value = serde_json::from_str(text).map_err(|e| perr(format!("invalid JSON: {e}")))?;
    let top = v
        .as_object()
        .ok_or_else(|| perr("the top level must be a JSON object".into()))?;
    let name = match top.get("name") {
        None | Some(Value::Null) => default_name.to_string(),
        Some(Value::String(s)) => s.clone(),
        Some(_) => return Err(perr("'name' must be a string".into())),
    };
    let loops_v = top
        .get("loops")
        .ok_or_else(|| perr("missing field 'loops' (a list of boundary loops)".into()))?
        .as_array()
        .ok_or_else(|| perr("'loops' must be a list".into()))?;
    if loops_v.is_empty() {
        return Err(perr(
            "'loops' is empty; a region needs an outer loop".into(),
        ));
    }
    let mut loops = Vec::with_capacity(loops_v.len());
    let mut marks: Vec<Option<i64>> = Vec::new();
    let mut piece_names: Vec<(Option<String>, String)> = Vec::new();
    for (i, lv) in loops_v.iter().enumerate() {
        let ctx = format!("loops[{i}]");
        let (role, pieces, m, names) = parse_loop(lv, &ctx).map_err(perr)?;
        loops.push((role, pieces));
        marks.extend(m);
        piece_names.extend(names.into_iter().map(|n| (n, ctx.clone())));
    }
    if loops.iter().all(|l| l.0 == Some(LoopRole::Hole)) {
        return Err(perr("no loop has role 'outer'".into()));
    }
    let corners = match top.get("corners") {
        None | Some(Value::Null) => None,
        Some(c) => Some(points(c, "corners", 0).map_err(perr)?),
    };
    let located = |e| match e {
        GeometryError::Invalid { region, message } => GeometryError::Invalid {
            region: format!("{region} (from {label})"),
            message,
        },
        other => other,
    };
    let lines = match top.get("lines") {
        None | Some(Value::Null) => Vec::new(),
        Some(v) => embedded_lines(v).map_err(perr)?,
    };
    // Names give markers to the pieces and lines that have none.
    let named: Vec<(Option<i64>, String, String)> = piece_names
        .iter()
        .zip(&marks)
        .filter_map(|((n, at), m)| Some((*m, n.clone()?, at.clone())))
        .chain(lines.iter().enumerate().filter_map(|(i, (l, has, n))| {
            Some((has.then_some(l.marker), n.clone()?, format!("lines[{i}]")))
        }))
        .collect();
    let given = marks
        .iter()
        .flatten()
        .copied()
        .chain(lines.iter().filter(|l| l.1).map(|l| l.0.marker));
    let marker_names = name_markers(&named, given).map_err(perr)?;
    let marker_of_name = |n: &str| marker_names.iter().find(|(_, m)| m == n).map(|(k, _)| *k);
    for (m, (n, _)) in marks.iter_mut().zip(&piece_names) {
        if m.is_none() {
            *m = n.as_deref().and_then(marker_of_name);
        }
    }
    let lines: Vec<crate::EmbeddedLine> = lines
        .into_iter()
        .map(|(mut l, has, n)| {
            if !has {
                if let Some(m) = n.as_deref().and_then(marker_of_name) {
                    l.marker = m;
                }
            }
            l
        })
        .collect();
    let subdomains = match top.get("subdomains") {
        None | Some(Value::Null) => Vec::new(),
        Some(v) => subdomain_points(v).map_err(perr)?,
    };
    let subdomain_names: Vec<(i64, String)> = subdomains
        .iter()
        .filter_map(|(_, id, name)| Some((*id, name.clone()?)))
        .collect();
    let subdomains: Vec<(DVec2, i64)> = subdomains.iter().map(|&(p, id, _)| (p, id)).collect();
    if marks.iter().all(Option::is_none) {
        return crate::build::new_region(&name, loops, corners)
            .and_then(|r| r.with_embedded_lines(lines))
            .and_then(|r| r.with_subdomain_points(subdomains))
            .map(|r| {
                r.with_subdomain_names(subdomain_names)
                    .with_marker_names(marker_names)
            })
            .map_err(located);
    }
    // Each piece's marker by its end points (either way round: loops are reoriented).
    let key = |p: &Piece| {
        let (a, b) = (
            p.start().to_array().map(f64::to_bits),
            p.end().to_array().map(f64::to_bits),
        );
        (a.min(b), a.max(b))
    };
    let by_ends: std::collections::HashMap<_, i64> = loops
        .iter()
        .flat_map(|(_, pieces)| pieces.iter())
        .zip(&marks)
        .map(|(p, m)| (key(p), m.unwrap_or(0)))
        .collect();
    let region =
        crate::build::new_region(&name, loops.clone(), corners.clone()).map_err(located)?;
    let marker_of = |r: &Region| -> Vec<i64> {
        r.pieces
            .iter()
            .map(|p| by_ends.get(&key(p)).copied().unwrap_or(0))
            .collect()
    };
    let markers = marker_of(&region);
    // Where the marker changes along a loop, the junction is a corner.
    let markers = &markers;
    let changes: Vec<DVec2> = region
        .loops
        .iter()
        .flat_map(|lp| {
            let n = lp.pieces.len();
            (0..n).filter_map(move |k| {
                let (prev, cur) = (lp.pieces[(k + n - 1) % n], lp.pieces[k]);
                (n > 1 && markers[prev] != markers[cur]).then_some(cur)
            })
        })
        .map(|cur| region.pieces[cur].start())
        .filter(|p| region.corners.iter().all(|c| c.pos != *p))
        .collect();
    let mut region = if changes.is_empty() {
        region
    } else {
        let mut listed: Vec<DVec2> = region.corners.iter().map(|c| c.pos).collect();
        listed.extend(changes);
        let mut again = crate::build::new_region(&name, loops, Some(listed)).map_err(located)?;
        again.corners_computed = region.corners_computed;
        again
    };
    region.markers = marker_of(&region);
    region
        .with_embedded_lines(lines)
        .and_then(|r| r.with_subdomain_points(subdomains))
        .map(|r| {
            r.with_subdomain_names(subdomain_names)
                .with_marker_names(marker_names)
        })
        .map_err(located)
}

/// The `subdomains` field: each an object with `point`, an integer `id` and optionally a
/// `name`.
fn subdomain_points(v: &Value) -> Result<Vec<(DVec2, i64, Option<String>)>, String> {
    let list = v.as_array().ok_or_else(|| {
        "'subdomains' must be a list of {\"point\": [x, y], \"id\": n}".to_string()
    })?;
    list.iter()
        .enumerate()
        .map(|(i, sv)| {
            let ctx = format!("subdomains[{i}]");
            let field = |f: &str| {
                sv.get(f)
                    .ok_or_else(|| format!("{ctx}: missing field '{f}'"))
            };
            let point = point(field("point")?, &format!("{ctx}.point"))?;
            let id = field("id")?;
            // A whole number written as a float (3.0, as a .poly's attributes are) is that
            // number.
            let id = id
                .as_i64()
                .or_else(|| {
                    id.as_f64()
                        .filter(|v| v.fract() == 0.0 && v.abs() < 9e15)
                        .map(|v| v as i64)
                })
                .ok_or_else(|| format!("{ctx}.id is {id}; expected an integer"))?;
            Ok((point, id, optional_name(sv, &ctx)?))
        })
        .collect()
}

/// The `lines` field: each line an object with `points` (at least two), an optional integer
/// `marker` and an optional `name`; each line with whether it gave a marker, and its name.
fn embedded_lines(v: &Value) -> Result<Vec<(crate::EmbeddedLine, bool, Option<String>)>, String> {
    let list = v.as_array().ok_or_else(|| {
        "'lines' must be a list of {\"points\": [...], \"marker\": m}".to_string()
    })?;
    list.iter()
        .enumerate()
        .map(|(i, lv)| {
            let ctx = format!("lines[{i}]");
            let points = points(
                lv.get("points")
                    .ok_or_else(|| format!("{ctx}: missing field 'points'"))?,
                &format!("{ctx}.points"),
                2,
            )?;
            let marker = match lv.get("marker") {
                None | Some(Value::Null) => None,
                Some(m) => Some(
                    m.as_i64()
                        .ok_or_else(|| format!("{ctx}.marker is {m}; expected an integer"))?,
                ),
            };
            Ok((
                crate::EmbeddedLine {
                    points,
                    marker: marker.unwrap_or(0),
                },
                marker.is_some(),
                optional_name(lv, &ctx)?,
            ))
        })
        .collect()
}

/// A loop's role, its pieces, and each piece's marker and name (its segment's `marker` and
/// `name`, if any).
type ParsedLoop = (
    Option<LoopRole>,
    Vec<Piece>,
    Vec<Option<i64>>,
    Vec<Option<String>>,
);

fn parse_loop(lv: &Value, ctx: &str) -> Result<ParsedLoop, String> {
    let obj = lv
        .as_object()
        .ok_or_else(|| format!("{ctx} must be an object with 'segments'"))?;
    let role = match obj.get("role") {
        None | Some(Value::Null) => None,
        Some(Value::String(s)) if s.eq_ignore_ascii_case("outer") => Some(LoopRole::Outer),
        Some(Value::String(s)) if s.eq_ignore_ascii_case("hole") => Some(LoopRole::Hole),
        Some(other) => {
            return Err(format!(
                "{ctx}.role is {other}; expected \"outer\" or \"hole\""
            ))
        }
    };
    let ccw = match obj.get("orientation") {
        None | Some(Value::Null) => role != Some(LoopRole::Hole),
        Some(Value::String(s)) if s.eq_ignore_ascii_case("ccw") => true,
        Some(Value::String(s)) if s.eq_ignore_ascii_case("cw") => false,
        Some(other) => {
            return Err(format!(
                "{ctx}.orientation is {other}; expected \"ccw\" or \"cw\""
            ))
        }
    };
    let segs = obj
        .get("segments")
        .ok_or_else(|| format!("{ctx}: missing field 'segments'"))?
        .as_array()
        .ok_or_else(|| format!("{ctx}.segments must be a list"))?;
    if segs.is_empty() {
        return Err(format!("{ctx}.segments is empty"));
    }
    let (mut pieces, mut marks, mut names) = (Vec::new(), Vec::new(), Vec::new());
    for (k, sv) in segs.iter().enumerate() {
        let sctx = format!("{ctx}.segments[{k}]");
        parse_segment(sv, ccw, &sctx, &mut pieces)?;
        let marker = match sv.get("marker") {
            None | Some(Value::Null) => None,
            Some(m) => Some(
                m.as_i64()
                    .filter(|m| i32::try_from(*m).is_ok())
                    .ok_or_else(|| {
                        format!(
                            "{sctx}.marker is {m}; expected an integer within Triangle's and \
                             Gmsh's 32-bit range"
                        )
                    })?,
            ),
        };
        marks.resize(pieces.len(), marker);
        names.resize(pieces.len(), optional_name(sv, &sctx)?);
    }
    Ok((role, pieces, marks, names))
}

/// The optional `name` field of a segment, a line or a subdomain.
fn optional_name(v: &Value, ctx: &str) -> Result<Option<String>, String> {
    match v.get("name") {
        None | Some(Value::Null) => Ok(None),
        Some(n) => Ok(Some(
            n.as_str()
                .ok_or_else(|| format!("{ctx}.name is {n}; expected a string"))?
                .to_string(),
        )),
    }
}

/// Each name's marker, given or assigned: a name without a marker takes the next number past
/// every marker given (`given`), one per name; a marker given two names is refused.
/// `items` are (marker, name, where) of every named segment or line, in the file's order.
fn name_markers(
    items: &[(Option<i64>, String, String)],
    given: impl Iterator<Item = i64>,
) -> Result<Vec<(i64, String)>, String> {
    let mut named: std::collections::BTreeMap<i64, (String, &str)> = Default::default();
    for (marker, name, at) in items {
        if let Some(m) = marker {
            if let Some((other, there)) = named.get(m).filter(|(n, _)| n != name) {
                return Err(format!(
                    "{at} names marker {m} \"{name}\", which {there} names \"{other}\"; one \
                     marker has one name"
                ));
            }
            named.insert(*m, (name.clone(), at));
        }
    }
    let mut next = given.chain(named.keys().copied()).max().unwrap_or(0).max(0) + 1;
    let mut out: Vec<(i64, String)> = named.into_iter().map(|(m, (n, _))| (m, n)).collect();
    for (marker, name, _) in items {
        if marker.is_none() && !out.iter().any(|(_, n)| n == name) {
            out.push((next, name.clone()));
            next += 1;
        }
    }
    Ok(out)
}

const KINDS: &str = "polyline, arc, circle, superellipse, parametric";

fn parse_segment(sv: &Value, ccw: bool, ctx: &str, out: &mut Vec<Piece>) -> Result<(), String> {
    let obj = sv
        .as_object()
        .ok_or_else(|| format!("{ctx} must be an object with a 'kind'"))?;
    let kind = match obj.get("kind") {
        Some(Value::String(s)) => s.as_str(),
        Some(other) => return Err(format!("{ctx}.kind is {other}; expected one of: {KINDS}")),
        None => return Err(format!("{ctx}: missing field 'kind' (one of: {KINDS})")),
    };
    let ctx = format!("{ctx} ({kind})");
    match kind {
        "polyline" => {
            let pts = points(field(obj, "points", &ctx)?, &format!("{ctx}.points"), 2)?;
            out.extend(pts.windows(2).map(|w| Piece::Line { a: w[0], b: w[1] }));
        }
        "parametric" => {
            let pts = points(field(obj, "points", &ctx)?, &format!("{ctx}.points"), 2)?;
            out.push(Piece::Chain(pts));
        }
        "circle" => {
            let center = point(field(obj, "center", &ctx)?, &format!("{ctx}.center"))?;
            let radius = number(obj, "radius", &ctx)?;
            out.push(Piece::Circle {
                center,
                radius,
                ccw,
            });
        }
        "superellipse" => {
            let center = point(field(obj, "center", &ctx)?, &format!("{ctx}.center"))?;
            let (a, b, n) = (
                number(obj, "a", &ctx)?,
                number(obj, "b", &ctx)?,
                number(obj, "exponent", &ctx)?,
            );
            out.push(Piece::SuperEllipse {
                center,
                a,
                b,
                n,
                ccw,
            });
        }
        "arc" => {
            let center = point(field(obj, "center", &ctx)?, &format!("{ctx}.center"))?;
            let radius = number(obj, "radius", &ctx)?;
            let from = number(obj, "from_deg", &ctx)?.to_radians();
            let to = number(obj, "to_deg", &ctx)?.to_radians();
            let arc = Piece::Arc {
                center,
                radius,
                from,
                to,
            };
            for (key, computed) in [("start", arc.start()), ("end", arc.end())] {
                if let Some(v) = obj.get(key).filter(|v| !v.is_null()) {
                    let given = point(v, &format!("{ctx}.{key}"))?;
                    if given.distance(computed) > 1e-9 * radius.abs().max(f64::MIN_POSITIVE) {
                        return Err(format!(
                            "{ctx}.{key} ({}, {}) is not the arc's {key} point ({}, {}) computed from center, radius and angles",
                            given.x, given.y, computed.x, computed.y
                        ));
                    }
                }
            }
            out.push(arc);
        }
        other => {
            return Err(format!(
                "{ctx}: unknown segment kind '{other}'; expected one of: {KINDS}"
            ))
        }
    }
    Ok(())
}

fn field<'a>(obj: &'a Map<String, Value>, key: &str, ctx: &str) -> Result<&'a Value, String> {
    obj.get(key)
        .ok_or_else(|| format!("{ctx}: missing field '{key}'"))
}

fn number(obj: &Map<String, Value>, key: &str, ctx: &str) -> Result<f64, String> {
    let v = field(obj, key, ctx)?;
    v.as_f64()
        .ok_or_else(|| format!("{ctx}.{key} must be a number, found {v}"))
}

fn point(v: &Value, ctx: &str) -> Result<DVec2, String> {
    match v.as_array().map(|a| a.as_slice()) {
        Some([x, y]) => match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => Ok(DVec2::new(x, y)),
            _ => Err(format!(
                "{ctx} must be a point [x, y] of numbers, found {v}"
            )),
        },
        _ => Err(format!("{ctx} must be a point [x, y], found {v}")),
    }
}

fn points(v: &Value, ctx: &str, min: usize) -> Result<Vec<DVec2>, String> {
    let arr = v
        .as_array()
        .ok_or_else(|| format!("{ctx} must be a list of points [x, y]"))?;
    if arr.len() < min {
        return Err(format!(
            "{ctx} has {} point(s); at least {min} are needed",
            arr.len()
        ));
    }
    arr.iter()
        .enumerate()
        .map(|(i, p)| point(p, &format!("{ctx}[{i}]")))
        .collect()
}
