//! What one robot sees, as CSV: `monoculus look` prints it, the Python package's
//! `Simulation.look` reads it.

use monoculus_core::algorithms::Model;
use monoculus_core::observe::inspect;
use monoculus_core::vision::VisionParams;
use monoculus_engine::{IndexPoint, IndexedSight};

use crate::results::num;

/// One row per point robot `robot` sees among `points`: `index` (the lowest index of
/// co-located robots), then `far` (LD: farther than `locality`) or `side_x,side_y[,side_z]`
/// (OLA: -1, 0 or 1 beyond the tolerance) or nothing (directions, positions), then the
/// unit direction `dx,dy[,dz]` in the global frame; the header first.
///
/// ```
/// use glam::DVec2;
/// use monoculus_core::algorithms::Model;
///
/// let pts = vec![DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(3.0, 0.0)];
/// let csv = monoculus_experiments::look::look_csv(pts, 0, Model::Ld, 2.0);
/// assert_eq!(csv, "index,far,dx,dy\n1,false,1,0\n");
/// ```
pub fn look_csv<P: IndexPoint>(
    points: Vec<P>,
    robot: usize,
    model: Model,
    locality: f64,
) -> String {
    let axes = &["x", "y", "z"][..P::DIM];
    let sight = IndexedSight::new(points, VisionParams::default());
    let mut header = vec!["index".to_string()];
    match model {
        Model::Ld => header.push("far".into()),
        Model::Ola => header.extend(axes.iter().map(|a| format!("side_{a}"))),
        Model::Directions | Model::Positions => {}
    }
    header.extend(axes.iter().map(|a| format!("d{a}")));
    let mut out = header.join(",");
    out.push('\n');
    for seen in inspect(&sight, robot, locality) {
        let mut row = vec![seen.index.to_string()];
        match model {
            Model::Ld => row.push(seen.far.to_string()),
            Model::Ola => row.extend(seen.sides.iter().map(i8::to_string)),
            Model::Directions | Model::Positions => {}
        }
        row.extend((0..P::DIM).map(|k| num(seen.direction.axis(k))));
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}
