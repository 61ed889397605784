//! Spatial index for exact nearest-boundary queries: the boundary is cut into *elements*
//! (one per straight segment of a line or chain, one per arc/circle/super-ellipse), kept in
//! loop order with their neighbours and end tangents, and searched with a bounding-volume
//! hierarchy (branch and bound on box distances).
use crate::numeric::box_dist2;
use crate::piece::{Foot, FootAt, Piece};
use crate::predicates::closest_on_segment;
use crate::se::{Samples, SuperEllipse};
use glam::DVec2;

/// One boundary element.
#[derive(Clone, Debug)]
pub(crate) struct Elem {
    /// Straight segment `a → b` (a whole `Line` or one segment of a `Chain`); `None` for a
    /// curved piece handled exactly by `Piece::foot`.
    pub seg: Option<(DVec2, DVec2)>,
    /// Piece it belongs to.
    pub piece: u32,
    /// For a chain segment: its index in the chain (the piece parameter is `index + t`).
    pub sub: u32,
    /// Previous and next element along the loop.
    pub prev: u32,
    pub next: u32,
    /// Unit tangents at the element's start and end.
    pub t_start: DVec2,
    pub t_end: DVec2,
}

/// Nearest point found by a query.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hit {
    pub elem: u32,
    pub point: DVec2,
    pub d2: f64,
    /// Parameter on the piece, as `Piece::foot` reports it.
    pub aux: f64,
    /// Whether the point is the start or end of the *element*.
    pub end: FootAt,
}

impl Hit {
    /// Nothing found yet: infinitely far, so that any element's point is nearer.
    const NONE: Hit = Hit {
        elem: 0,
        point: DVec2::NAN,
        d2: f64::INFINITY,
        aux: 0.0,
        end: FootAt::Interior,
    };
}

#[derive(Clone, Debug)]
struct Node {
    lo: DVec2,
    hi: DVec2,
    /// Leaf: items[a..b]. Internal: children a and b.
    a: u32,
    b: u32,
    leaf: bool,
}

/// A bounding-volume hierarchy over items with boxes.
#[derive(Clone, Debug)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    items: Vec<u32>,
    boxes: Vec<(DVec2, DVec2)>,
}

const LEAF: usize = 4;

impl Bvh {
    /// Builds over `ids`, whose boxes are `boxes[id]`.
    pub fn build(boxes: &[(DVec2, DVec2)], ids: Vec<u32>) -> Bvh {
        let mut entries: Vec<Entry> = ids.into_iter().map(|i| (i, boxes[i as usize])).collect();
        let mut nodes = Vec::new();
        if !entries.is_empty() {
            nodes.push(Node {
                lo: DVec2::ZERO,
                hi: DVec2::ZERO,
                a: 0,
                b: 0,
                leaf: true,
            });
            split(&mut nodes, 0, &mut entries, 0);
        }
        Bvh {
            nodes,
            items: entries.iter().map(|e| e.0).collect(),
            boxes: entries.iter().map(|e| e.1).collect(),
        }
    }

    /// Branch-and-bound nearest search: `eval(item, best_d2)` returns the item's squared
    /// distance (or ∞ when it cannot beat `best_d2`). Returns the best item and distance².
    pub fn nearest(&self, p: DVec2, mut eval: impl FnMut(u32, f64) -> f64) -> Option<(u32, f64)> {
        if self.nodes.is_empty() {
            return None;
        }
        let mut best: Option<(u32, f64)> = None;
        let mut best_d2 = f64::INFINITY;
        // A fixed stack: the tree depth is below 64 for any realistic size (median splits).
        let mut stack = [(0u32, 0.0f64); 128];
        let mut top = 1;
        stack[0] = (0, box_dist2(self.nodes[0].lo, self.nodes[0].hi, p));
        while top > 0 {
            top -= 1;
            let (n, lb) = stack[top];
            if lb >= best_d2 {
                continue;
            }
            let node = &self.nodes[n as usize];
            if node.leaf {
                for k in node.a..node.b {
                    let (lo, hi) = self.boxes[k as usize];
                    if box_dist2(lo, hi, p) >= best_d2 {
                        continue;
                    }
                    let item = self.items[k as usize];
                    let d2 = eval(item, best_d2);
                    if d2 < best_d2 {
                        best_d2 = d2;
                        best = Some((item, d2));
                    }
                }
            } else {
                let (a, b) = (&self.nodes[node.a as usize], &self.nodes[node.b as usize]);
                let (da, db) = (box_dist2(a.lo, a.hi, p), box_dist2(b.lo, b.hi, p));
                // Push the farther child first so the nearer one is searched first.
                let (near, far) = if da <= db {
                    ((node.a, da), (node.b, db))
                } else {
                    ((node.b, db), (node.a, da))
                };
                if far.1 < best_d2 && top < stack.len() {
                    stack[top] = far;
                    top += 1;
                }
                if near.1 < best_d2 && top < stack.len() {
                    stack[top] = near;
                    top += 1;
                }
            }
        }
        best
    }
}

type Entry = (u32, (DVec2, DVec2));

/// Fills `nodes[node]` for `entries` (which start at `offset` in leaf order), splitting at
/// the median of box centres along the longer axis.
fn split(nodes: &mut Vec<Node>, node: usize, entries: &mut [Entry], offset: usize) {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for (_, (l, h)) in entries.iter() {
        lo = lo.min(*l);
        hi = hi.max(*h);
    }
    nodes[node].lo = lo;
    nodes[node].hi = hi;
    if entries.len() <= LEAF {
        nodes[node].a = offset as u32;
        nodes[node].b = (offset + entries.len()) as u32;
        nodes[node].leaf = true;
        return;
    }
    let x_axis = hi.x - lo.x >= hi.y - lo.y;
    let key = |e: &Entry| {
        let (l, h) = e.1;
        if x_axis {
            l.x + h.x
        } else {
            l.y + h.y
        }
    };
    let mid = entries.len() / 2;
    entries.select_nth_unstable_by(mid, |x, y| key(x).total_cmp(&key(y)));
    let left = nodes.len();
    // Two placeholders for the children, filled in by the recursive calls below.
    let placeholder = Node {
        lo,
        hi,
        a: 0,
        b: 0,
        leaf: true,
    };
    nodes.extend([placeholder.clone(), placeholder]);
    nodes[node].a = left as u32;
    nodes[node].b = left as u32 + 1;
    nodes[node].leaf = false;
    let (l, r) = entries.split_at_mut(mid);
    split(nodes, left, l, offset);
    split(nodes, left + 1, r, offset + mid);
}

/// Elements of a region's boundary and the hierarchies over them.
#[derive(Clone, Debug)]
pub(crate) struct Index {
    pub elems: Vec<Elem>,
    bvh: Bvh,
    /// Element range of each piece.
    pub piece_elems: Vec<(u32, u32)>,
    /// A hierarchy per chain piece with many segments (for `project_onto_piece`).
    piece_bvh: Vec<Option<Bvh>>,
    /// Cumulative arc length at the start of each chain segment element (0 otherwise).
    pub s0: Vec<f64>,
    /// What each super-ellipse piece's queries share, made once.
    curves: Vec<Option<CurveQueries>>,
}

/// A super-ellipse piece with what every query on it would otherwise remake: its
/// closest-point samples, its octant lengths (arc-length parameters) and the outer radius of
/// the annulus holding it (the nearest-element search's lower bound).
#[derive(Clone, Debug)]
struct CurveQueries {
    curve: SuperEllipse,
    samples: Samples,
    lengths: (f64, f64),
    outer: f64,
}

impl Index {
    /// Builds the elements of `loops` (each a list of piece ids in order).
    pub fn build(pieces: &[Piece], loops: &[Vec<usize>]) -> Index {
        let mut elems = Vec::new();
        let mut s0 = Vec::new();
        let mut piece_elems = vec![(0u32, 0u32); pieces.len()];
        for lp in loops {
            let first = elems.len();
            for &pid in lp {
                let start = elems.len() as u32;
                let piece = &pieces[pid];
                match piece {
                    Piece::Line { a, b } => {
                        let d = (*b - *a).normalize_or_zero();
                        elems.push(Elem {
                            seg: Some((*a, *b)),
                            piece: pid as u32,
                            sub: 0,
                            prev: 0,
                            next: 0,
                            t_start: d,
                            t_end: d,
                        });
                        s0.push(0.0);
                    }
                    Piece::Chain(p) => {
                        let mut s = 0.0;
                        for (k, w) in p.windows(2).enumerate() {
                            let d = (w[1] - w[0]).normalize_or_zero();
                            elems.push(Elem {
                                seg: Some((w[0], w[1])),
                                piece: pid as u32,
                                sub: k as u32,
                                prev: 0,
                                next: 0,
                                t_start: d,
                                t_end: d,
                            });
                            s0.push(s);
                            s += w[0].distance(w[1]);
                        }
                    }
                    _ => {
                        let (ts, te) = piece.end_tangents();
                        elems.push(Elem {
                            seg: None,
                            piece: pid as u32,
                            sub: 0,
                            prev: 0,
                            next: 0,
                            t_start: ts,
                            t_end: te,
                        });
                        s0.push(0.0);
                    }
                }
                piece_elems[pid] = (start, elems.len() as u32);
            }
            let n = elems.len() - first;
            for k in 0..n {
                elems[first + k].prev = (first + (k + n - 1) % n) as u32;
                elems[first + k].next = (first + (k + 1) % n) as u32;
            }
        }
        let boxes: Vec<(DVec2, DVec2)> = elems
            .iter()
            .map(|e| match e.seg {
                Some((a, b)) => (a.min(b), a.max(b)),
                None => pieces[e.piece as usize].bbox(),
            })
            .collect();
        let bvh = Bvh::build(&boxes, (0..elems.len() as u32).collect());
        let piece_bvh = piece_elems
            .iter()
            .map(|&(a, b)| (b - a > 16).then(|| Bvh::build(&boxes, (a..b).collect())))
            .collect();
        let curves = pieces
            .iter()
            .map(|p| {
                p.superellipse().map(|curve| CurveQueries {
                    curve,
                    samples: curve.samples(),
                    lengths: curve.octant_lengths(),
                    // The curve lies within max(a,b)·2^{1/2−1/n} of its centre.
                    outer: curve.a.max(curve.b) * 2f64.powf(0.5 - 1.0 / curve.n),
                })
            })
            .collect();
        Index {
            elems,
            bvh,
            piece_elems,
            piece_bvh,
            s0,
            curves,
        }
    }

    /// Exact squared distance from p to element e (∞ when it cannot beat `best`).
    fn eval(&self, pieces: &[Piece], e: u32, p: DVec2, best: f64, out: &mut Hit) -> f64 {
        let el = &self.elems[e as usize];
        match el.seg {
            Some((a, b)) => {
                let (q, t, d2) = closest_on_segment(a, b, p);
                if d2 < best {
                    let end = if t <= 0.0 {
                        FootAt::Start
                    } else if t >= 1.0 {
                        FootAt::End
                    } else {
                        FootAt::Interior
                    };
                    *out = Hit {
                        elem: e,
                        point: q,
                        d2,
                        aux: el.sub as f64 + t,
                        end,
                    };
                }
                d2
            }
            None => {
                let piece = &pieces[el.piece as usize];
                let f = match &self.curves[el.piece as usize] {
                    Some(c) => {
                        // The curve lies in the annulus min(a,b) ≤ |x − c| ≤ outer.
                        let r = p.distance(c.curve.c);
                        let lb = (r - c.outer).max(c.curve.a.min(c.curve.b) - r).max(0.0);
                        if lb * lb >= best {
                            return f64::INFINITY;
                        }
                        let (point, d2, t) = c.curve.closest_sampled(p, &c.samples);
                        Foot {
                            point,
                            d2,
                            aux: t,
                            end: FootAt::Interior,
                        }
                    }
                    None => piece.foot(p),
                };
                if f.d2 < best {
                    *out = Hit {
                        elem: e,
                        point: f.point,
                        d2: f.d2,
                        aux: f.aux,
                        end: f.end,
                    };
                }
                f.d2
            }
        }
    }

    /// Nearest boundary point over all elements.
    pub fn nearest(&self, pieces: &[Piece], p: DVec2) -> Hit {
        let mut hit = Hit::NONE;
        self.bvh
            .nearest(p, |e, best| self.eval(pieces, e, p, best, &mut hit));
        hit
    }

    /// Nearest boundary point over the elements of the pieces `keep` accepts.
    pub fn nearest_where(&self, pieces: &[Piece], p: DVec2, keep: impl Fn(usize) -> bool) -> Hit {
        let mut hit = Hit::NONE;
        self.bvh.nearest(p, |e, best| {
            if keep(self.elems[e as usize].piece as usize) {
                self.eval(pieces, e, p, best, &mut hit)
            } else {
                f64::INFINITY
            }
        });
        hit
    }

    /// Nearest point on one piece.
    pub fn nearest_on_piece(&self, pieces: &[Piece], p: DVec2, piece: usize) -> Hit {
        let mut hit = Hit::NONE;
        let (a, b) = self.piece_elems[piece];
        match &self.piece_bvh[piece] {
            Some(bvh) => {
                bvh.nearest(p, |e, best| self.eval(pieces, e, p, best, &mut hit));
            }
            None => {
                let mut best = f64::INFINITY;
                for e in a..b {
                    best = best.min(self.eval(pieces, e, p, best, &mut hit));
                }
            }
        }
        hit
    }

    /// Arc length from the start of the hit's piece to the hit point.
    pub fn piece_param(&self, pieces: &[Piece], hit: &Hit) -> f64 {
        let el = &self.elems[hit.elem as usize];
        match el.seg {
            Some((a, b)) => self.s0[hit.elem as usize] + (hit.aux - el.sub as f64) * a.distance(b),
            None => match &self.curves[el.piece as usize] {
                Some(c) => c.curve.arc_length_with(hit.aux, c.lengths),
                None => pieces[el.piece as usize].arc_length_at(hit.aux),
            },
        }
    }

    /// Whether p (not on the boundary) is inside, judged from its nearest point: on the
    /// inner side of the nearest element, or — when the nearest point is a vertex where two
    /// elements meet — inside the wedge of the two tangents (both sides at a convex vertex,
    /// either side at a reflex one). Exact whenever `hit` is the true nearest point.
    pub fn inside(&self, pieces: &[Piece], p: DVec2, hit: &Hit) -> bool {
        let el = &self.elems[hit.elem as usize];
        let (t_in, t_out) = match hit.end {
            FootAt::Interior => {
                let side = match el.seg {
                    Some((a, b)) => crate::predicates::orient(a, b, p),
                    None => pieces[el.piece as usize].side(p),
                };
                return side > 0.0;
            }
            FootAt::Start => (self.elems[el.prev as usize].t_end, el.t_start),
            FootAt::End => (el.t_end, self.elems[el.next as usize].t_start),
        };
        let d = p - hit.point;
        let (c1, c2) = (t_in.perp_dot(d), t_out.perp_dot(d));
        if t_in.perp_dot(t_out) >= 0.0 {
            c1 > 0.0 && c2 > 0.0
        } else {
            c1 > 0.0 || c2 > 0.0
        }
    }
}
