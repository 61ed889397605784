//! The ε-expansion Ω_ε of Algorithm 2.
use crate::{Polygon, Region};

pub fn expand(region: &Region, eps: f64, tol: f64) -> Polygon {
    let _ = (region, eps, tol);
    todo!()
}
